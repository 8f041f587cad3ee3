//! Sites into their own cells (paper section 5.2, docs/method.md section 5).
//! A site lies strictly inside its cell iff for every neighbour b in the
//! regular triangulation of the sites |a - b|^2 + omega_a - omega_b > 0,
//! decided exactly. The site triangulation is built once from the sites
//! rounded to doubles and checked exactly (diagram.rs; when the check
//! fails, the backend's exact-rational triangulation is used instead), then
//! kept regular by exact flips as sites move, and checked whole again at
//! the end. A segment site outside its cell moves towards its segment (its
//! cell then tends to a fixed half-region around the segment, so close
//! enough is inside); a vertex site tries other points of its dual edge.
//! Bounded in rounds.

use crate::backend::{Backend, Triangulation};
use crate::diagram::{Diagram, EdgeTests};
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
    let mut crowding = std::collections::BTreeSet::new();
    let mut segment_of = |s: usize| match sites.role[s] {
        crate::sites::Role::Segment { seg, .. } => {
            crowding.insert(cx.segment_ids[seg as usize]);
        }
        crate::sites::Role::Corner { segs } => {
            crowding.extend(segs.map(|(seg, _)| cx.segment_ids[seg as usize]));
        }
        crate::sites::Role::Vertex { .. } => {}
    };
    let mut messages = vec![];
    for &s in outside {
        messages.push(if rt.hidden.contains(&(s as u32)) {
            "hidden: other sites' power is lower everywhere, it has no cell".into()
        } else if matches!(sites.role[s], crate::sites::Role::Corner { .. }) {
            segment_of(s);
            "a corner's site stays at its triangle's power centre, beyond a face with a neighbour"
                .into()
        } else if !sites.movable[s] {
            segment_of(s);
            "its segment misses its dual edge, so it cannot be on the segment's side".into()
        } else if let Some(&b) = beaten_by(sites, rt, s).first() {
            segment_of(b);
            format!(
                "no position tried on its dual edge puts it inside; it lies beyond its face with {}",
                sites.describe(b, cx)
            )
        } else {
            "outside".into()
        });
    }
    (messages, crowding.into_iter().collect())
}

/// The regular triangulation of the sites: from the rounded sites when it
/// passes the exact check (`Diagram::check_or_repair`, after flips where
/// it does not), with its edges' power tests; else from exact rationals
/// (None).
fn site_triangulation<B: Backend + ?Sized>(
    backend: &B,
    sites: &Sites,
) -> Result<(Triangulation, Option<EdgeTests>)> {
    let pos: Vec<[f64; 2]> = (0..sites.len())
        .map(|s| {
            let [x, y, _] = sites.approx(s);
            [x, y]
        })
        .collect();
    let w = sites.nudged_weights();
    if let Some(mut rt) = crate::backend::regular_in_halves(backend, &pos, &w) {
        let checked = Diagram::check_or_repair(sites, &mut rt);
        if checked.is_some() {
            return Ok((rt, checked));
        }
    }
    let mut rt = backend.regular(&pos, &w)?;
    let checked = Diagram::check_or_repair(sites, &mut rt);
    if checked.is_some() {
        return Ok((rt, checked));
    }
    let (pos, w): (Vec<_>, Vec<_>) = (0..sites.len()).map(|s| sites.exact(s).clone()).unzip();
    Ok((backend.regular_exact(&pos, &w)?, None))
}

/// The diagram of a triangulation of the sites that is known regular:
/// checked (its power tests given), or exact (it may hide sites).
fn diagram_of(
    dom: &Domain,
    sites: &Sites,
    rt: &Triangulation,
    checked: Option<EdgeTests>,
) -> Result<Diagram> {
    Diagram::build(dom, sites, rt, checked)
        .map_err(|why| Error::Backend(format!("the regular triangulation of the sites: {why}")))
}

/// The neighbours of site s in rt (from its star; a hull site by a scan).
fn neighbours_of(rt: &Triangulation, s: usize) -> Vec<usize> {
    match rt.star(s as u32) {
        Some(star) => star
            .iter()
            .map(|&t| {
                let tri = rt.triangles[t as usize];
                let k = tri.iter().position(|&x| x as usize == s).expect("star");
                tri[(k + 1) % 3] as usize
            })
            .collect(),
        None => rt
            .edges()
            .filter_map(|(a, b)| match (a as usize, b as usize) {
                (a, b) if a == s => Some(b),
                (a, b) if b == s => Some(a),
                _ => None,
            })
            .collect(),
    }
}

/// The neighbours whose power at site s is not above its own (exact): s is
/// outside its cell when there is one.
fn beaten_by(sites: &Sites, rt: &Triangulation, s: usize) -> Vec<usize> {
    neighbours_of(rt, s)
        .into_iter()
        .filter(|&b| !sites.inside_wrt(s, b))
        .collect()
}

/// Halvings tried to keep a moved site's triangles counter-clockwise.
const PULL_BACKS: usize = 24;

/// Moves each site of `out` (`Sites::step`) against the neighbours that
/// beat it, one after the other, keeping `rt` a triangulation of the sites
/// (every triangle around a moved site counter-clockwise, with the sites
/// moved before it): the sites that moved, and the moves that would fold a
/// triangle, undone (site, fraction). A segment site whose full step would
/// fold one steps back towards where it was, in halves, first. (A vertex
/// site that skipped to its next position instead was measured to stay
/// outside: its folding jump is the one that brings it in.)
fn step_all(
    sites: &mut Sites,
    rt: &Triangulation,
    out: &[usize],
) -> (Vec<usize>, Vec<(usize, f64)>) {
    let ccw = |sites: &Sites, s: usize| crate::diagram::star_ccw(sites, rt, s);
    let (mut moved, mut folding) = (vec![], vec![]);
    for &s in out {
        let from = sites.frac(s);
        // a vertex site weighs its whole cell when it chooses where to go
        let against = if sites.on_segment(s) {
            beaten_by(sites, rt, s)
        } else {
            neighbours_of(rt, s)
        };
        if !sites.step(s, &against) {
            continue;
        }
        let to = sites.frac(s);
        let mut h = 1.0;
        let fits = (0..PULL_BACKS).any(|_| {
            sites.move_to(s, from + h * (to - from));
            h /= 2.0;
            ccw(sites, s) || !sites.on_segment(s)
        }) && ccw(sites, s);
        if fits {
            moved.push(s);
        } else {
            sites.move_to(s, from);
            folding.push((s, to));
        }
    }
    (moved, folding)
}

/// Increments of a walk (`walk`).
const WALK: usize = 16;

/// Moves site s to fraction `to` of its track in small increments, making
/// the triangulation regular by flips after each, as a kinetic
/// triangulation would: moving a site across others changes a regular
/// triangulation by flips before any triangle folds (unless the site is
/// hidden on the way). The sites whose neighbourhood changed, or None when
/// an increment folds a triangle or a flip is stuck (then the site has
/// moved part of the way and the triangulation must be built anew).
fn walk(sites: &mut Sites, rt: &mut Triangulation, s: usize, to: f64) -> Option<Vec<u32>> {
    let from = sites.frac(s);
    let mut touched = vec![];
    for k in 1..=WALK {
        sites.move_to(s, from + (to - from) * k as f64 / WALK as f64);
        if k == WALK {
            sites.move_to(s, to);
        }
        // repair_around refuses a folded triangle around s.
        touched.extend(crate::diagram::repair_around(sites, rt, &[s])?);
    }
    Some(touched)
}

/// The first site diagram, before any site moves.
pub struct First {
    rt: Triangulation,
    diagram: Diagram,
    /// Domain sites not strictly inside their cell (or hidden).
    out: Vec<usize>,
    /// Whether the triangulation had to be built from exact rationals.
    exact: bool,
}

/// The triangulation and diagram of the sites as placed (the pipeline's
/// "site diagram" stage; relocation starts from it).
pub fn first_diagram<B: Backend + ?Sized>(
    backend: &B,
    dom: &Domain,
    sites: &Sites,
) -> Result<First> {
    let (rt, checked) = site_triangulation(backend, sites)?;
    let exact = checked.is_none();
    let diagram = diagram_of(dom, sites, &rt, checked)?;
    let out = outside(sites, &rt, &diagram);
    Ok(First {
        rt,
        diagram,
        out,
        exact,
    })
}

/// Moves sites from the `first` diagram until all domain sites are inside
/// their cells or no site can move. The first triangulation is built whole;
/// after a round of moves it is repaired by exact flips around the moved
/// sites (a round then costs what the moves touch, not a rebuild of all
/// sites), and built anew only where that fails or a move would fold a
/// triangle. When no site moves any more, a repaired triangulation gets
/// the full exact check of `Diagram::check`, and relocation goes on from
/// there if sites are still outside. Between full diagrams, which sites are
/// in the domain is taken from the last one (sites move only along their
/// dual edges); the final diagram decides it afresh.
pub fn relocate<B: Backend + ?Sized>(
    backend: &B,
    dom: &Domain,
    sites: &mut Sites,
    first: First,
) -> Result<Relocated> {
    let mut round = 0;
    let First {
        mut rt,
        mut diagram,
        mut out,
        exact,
    } = first;
    let mut exact_rounds = usize::from(exact);
    let mut checked = None;
    // Whether `diagram` and `out` are of the current sites and `rt`, and
    // whether `rt` is known regular (built by `site_triangulation`: checked
    // whole, its power tests in `checked`, or exact).
    let (mut fresh, mut trusted) = (true, true);
    loop {
        let (moved, folding) = if round < MAX_ROUNDS {
            step_all(sites, &rt, &out)
        } else {
            (vec![], vec![])
        };
        if moved.is_empty() && folding.is_empty() {
            if fresh {
                diagram.exact_corners(sites, &rt);
                return Ok(Relocated {
                    rt,
                    diagram,
                    rounds: round,
                    outside: out,
                    exact_rounds,
                });
            }
            if !trusted {
                match Diagram::check(sites, &rt) {
                    Ok(c) => checked = Some(c),
                    Err(_) => {
                        (rt, checked) = site_triangulation(backend, sites)?;
                        exact_rounds += usize::from(checked.is_none());
                    }
                }
            }
            diagram = diagram_of(dom, sites, &rt, checked.take())?;
            out = outside(sites, &rt, &diagram);
            (fresh, trusted) = (true, true);
            continue;
        }
        round += 1;
        // Moves that fold a triangle wait until the others are done, then
        // walk; where a walk fails, the triangulation is built anew.
        let repaired = if moved.is_empty() {
            let mut touched = Some(vec![]);
            for &(s, to) in &folding {
                match touched.as_mut() {
                    Some(all) => match walk(sites, &mut rt, s, to) {
                        Some(t) => all.extend(t),
                        None => {
                            sites.move_to(s, to);
                            touched = None;
                        }
                    },
                    None => sites.move_to(s, to),
                }
            }
            touched.map(|mut t| {
                t.sort_unstable();
                t.dedup();
                t
            })
        } else {
            crate::diagram::repair_around(sites, &mut rt, &moved)
        };
        if let Some(touched) = repaired {
            let mut flag = vec![false; sites.len()];
            for &s in &out {
                flag[s] = true;
            }
            // (each touched site's test in parallel, applied in order)
            let beaten: Vec<bool> = touched
                .par_iter()
                .map(|&s| {
                    let s = s as usize;
                    diagram.in_domain[s] && !beaten_by(sites, &rt, s).is_empty()
                })
                .collect();
            for (&s, beaten) in touched.iter().zip(beaten) {
                flag[s as usize] = beaten;
            }
            out = (0..sites.len()).filter(|&s| flag[s]).collect();
            (trusted, checked) = (false, None);
        } else {
            (rt, checked) = site_triangulation(backend, sites)?;
            exact_rounds += usize::from(checked.is_none());
            out = outside(sites, &rt, &diagram);
            trusted = true;
        }
        fresh = false;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::scatter;
    use crate::sites::tests::sites_on_tracks;

    #[test]
    fn a_walk_across_other_sites_ends_in_the_regular_triangulation() {
        let backend = crate::backend::default_backend();
        let n = 300;
        let pts: Vec<[f64; 2]> = (0..n as u64)
            .map(|i| [scatter(2 * i) * 100.0, scatter(2 * i + 1) * 100.0])
            .collect();
        let edges = |t: &Triangulation| {
            let mut e: Vec<(u32, u32)> = t.edges().map(|(a, b)| (a.min(b), a.max(b))).collect();
            e.sort_unstable();
            e
        };
        let (mut walked, mut changed) = (0, 0);
        for trial in 0..30u64 {
            // One site walks most of a neighbour spacing away; as a vertex
            // site its weight grows with the distance from its vertex (its
            // power there stays zero), so it may hide others: then the
            // walk says so.
            let s = (scatter(50_000 + trial) * n as f64) as usize;
            let angle = scatter(60_000 + trial) * std::f64::consts::TAU;
            let mut dirs = vec![[0.0; 2]; n];
            dirs[s] = [4.0 * angle.cos(), 4.0 * angle.sin()];
            let end = [pts[s][0] + dirs[s][0], pts[s][1] + dirs[s][1]];
            if !(5.0..95.0).contains(&end[0]) || !(5.0..95.0).contains(&end[1]) {
                continue;
            }
            let mut sites = sites_on_tracks(&pts, &dirs);
            let mut rt = backend.regular(&pts, &vec![0.0; n]).unwrap();
            if rt.star(s as u32).is_none() {
                continue;
            }
            let before = edges(&rt);
            if let Some(touched) = walk(&mut sites, &mut rt, s, 1.0) {
                walked += 1;
                let pos: Vec<[f64; 2]> = (0..sites.len())
                    .map(|s| {
                        let [x, y, _] = sites.approx(s);
                        [x, y]
                    })
                    .collect();
                let w: Vec<f64> = (0..sites.len()).map(|s| sites.approx(s)[2]).collect();
                assert_eq!(pos[s], end);
                let fresh = backend.regular(&pos, &w).unwrap();
                assert_eq!(edges(&rt), edges(&fresh), "trial {trial}");
                assert!(touched.contains(&(s as u32)));
                changed += usize::from(edges(&rt) != before);
            }
        }
        assert!(
            walked >= 10 && changed >= 5,
            "{walked} walked, {changed} changed"
        );
    }
}
