//! Sites into their own cells (paper section 5.2, method.md section 5).
//! A site lies strictly inside its cell iff for every neighbour b in the
//! regular triangulation of the sites |a - b|^2 + omega_a - omega_b > 0,
//! decided exactly. The site triangulation is built from the sites rounded
//! to doubles and checked exactly (diagram.rs); when the check fails, the
//! backend's exact-rational triangulation is used instead. A segment site outside its cell moves halfway towards its
//! segment (its cell then tends to a fixed half-region around the segment,
//! so close enough is inside); a vertex site tries other points of its dual
//! edge. Bounded in rounds.

use crate::backend::{Backend, Triangulation};
use crate::diagram::Diagram;
use crate::domain::Domain;
use crate::error::{Error, Result};
use crate::sites::Sites;
use rayon::prelude::*;

/// Rounds of relocation before giving up.
pub const MAX_ROUNDS: usize = 48;

/// The final site diagram.
pub struct Relocated {
    pub rt: Triangulation,
    pub diagram: Diagram,
    pub rounds: usize,
    /// Domain sites not strictly inside their cell (or hidden).
    pub outside: Vec<usize>,
    /// Rounds whose rounded-site triangulation failed its exact check and
    /// were redone with exact rationals.
    pub exact_rounds: usize,
}

/// Domain sites that are hidden or not strictly inside their cell.
pub fn outside(sites: &Sites, rt: &Triangulation, diagram: &Diagram) -> Vec<usize> {
    let mut out = vec![false; sites.len()];
    for &h in &rt.hidden {
        out[h as usize] = true;
    }
    // Every directed edge a -> b once: in the triangle on its left, or on
    // the hull for the reverse of a hull edge.
    let bad: Vec<usize> = (0..rt.triangles.len() as u32)
        .into_par_iter()
        .flat_map_iter(|t| {
            let tri = rt.triangles[t as usize];
            (0..3).flat_map(move |k| {
                let (a, b) = (tri[k] as usize, tri[(k + 1) % 3] as usize);
                let hull = rt.across(t, k).is_none();
                let test = |x: usize, y: usize| diagram.in_domain[x] && !sites.inside_wrt(x, y);
                [(test(a, b)).then_some(a), (hull && test(b, a)).then_some(b)]
                    .into_iter()
                    .flatten()
            })
        })
        .collect();
    for s in bad {
        out[s] = true;
    }
    (0..sites.len()).filter(|&s| out[s]).collect()
}

/// Why each of the sites `outside` is outside its cell, for messages; and
/// the segments (input ids) whose sites crowd them out, or whose own sites
/// they are: splitting those is what `--split-segments` can do.
pub fn why(
    sites: &Sites,
    rt: &Triangulation,
    outside: &[usize],
    cx: &crate::complex::Complex,
) -> (Vec<String>, Vec<i64>) {
    if outside.is_empty() {
        return (vec![], vec![]);
    }
    let nb = rt.neighbours(sites.len());
    let mut crowding = std::collections::BTreeSet::new();
    let mut segment_of = |s: usize| {
        if let crate::sites::Role::Segment { seg, .. } = sites.role[s] {
            crowding.insert(cx.segment_ids[seg as usize]);
        }
    };
    let mut messages = vec![];
    for &s in outside {
        let blocking = nb[s].iter().find(|&&b| !sites.inside_wrt(s, b as usize));
        messages.push(if rt.hidden.contains(&(s as u32)) {
            "hidden: other sites' power is lower everywhere, it has no cell".into()
        } else if !sites.movable[s] {
            segment_of(s);
            "its segment misses its dual edge, so it cannot be on the segment's side".into()
        } else if let Some(&b) = blocking {
            segment_of(b as usize);
            format!(
                "no position tried on its dual edge puts it inside; it lies beyond its face with {}",
                sites.describe(b as usize, cx)
            )
        } else {
            "outside".into()
        });
    }
    (messages, crowding.into_iter().collect())
}

/// The regular triangulation of the sites and its diagram: from the rounded
/// sites when that passes the exact check, else from exact rationals.
fn site_diagram<B: Backend + ?Sized>(
    backend: &B,
    dom: &Domain,
    sites: &Sites,
) -> Result<(Triangulation, Diagram, bool)> {
    let pos: Vec<[f64; 2]> = sites.approx.iter().map(|a| [a[0], a[1]]).collect();
    let w = sites.nudged_weights();
    let mut rt = backend.regular(&pos, &w)?;
    if let Ok(d) = Diagram::build(dom, sites, &rt, true) {
        return Ok((rt, d, false));
    }
    if crate::diagram::repair(sites, &mut rt) {
        if let Ok(d) = Diagram::build(dom, sites, &rt, true) {
            return Ok((rt, d, false));
        }
    }
    let (pos, w): (Vec<_>, Vec<_>) = (0..sites.len()).map(|s| sites.exact(s).clone()).unzip();
    let rt = backend.regular_exact(&pos, &w)?;
    let d = Diagram::build(dom, sites, &rt, false).map_err(|why| {
        Error::Backend(format!(
            "the exact regular triangulation of the sites: {why}"
        ))
    })?;
    Ok((rt, d, true))
}

/// Builds the site diagram, moving sites until all domain sites are inside
/// their cells or no site can move.
pub fn relocate<B: Backend + ?Sized>(
    backend: &B,
    dom: &Domain,
    sites: &mut Sites,
) -> Result<Relocated> {
    let mut round = 0;
    let mut exact_rounds = 0;
    loop {
        let (rt, diagram, exact) = site_diagram(backend, dom, sites)?;
        exact_rounds += usize::from(exact);
        let out = outside(sites, &rt, &diagram);
        let mut moved = false;
        if round < MAX_ROUNDS {
            let nb = rt.neighbours(sites.len());
            for &s in &out {
                let against: Vec<usize> = nb[s]
                    .iter()
                    .map(|&b| b as usize)
                    .filter(|&b| !sites.inside_wrt(s, b))
                    .collect();
                moved |= sites.step(s, &against);
            }
        }
        if out.is_empty() || !moved {
            return Ok(Relocated {
                rt,
                diagram,
                rounds: round,
                outside: out,
                exact_rounds,
            });
        }
        round += 1;
    }
}
