//! Sites into their own cells (paper section 5.2, method.md section 5).
//! A site lies strictly inside its cell iff for every neighbour b in the
//! regular triangulation of the sites |a - b|^2 + omega_a - omega_b > 0,
//! decided exactly. A segment site outside its cell moves halfway towards its
//! segment (its cell then tends to a fixed half-region around the segment,
//! so close enough is inside); a vertex site tries other points of its dual
//! edge. Bounded in rounds.

use crate::backend::{Backend, Triangulation};
use crate::diagram::{CentreCache, Diagram};
use crate::domain::Domain;
use crate::error::Result;
use crate::sites::{inside_wrt, Sites};

/// Rounds of relocation before giving up.
pub const MAX_ROUNDS: usize = 48;

/// The final site diagram.
pub struct Relocated {
    pub rt: Triangulation,
    pub diagram: Diagram,
    pub rounds: usize,
    /// Domain sites not strictly inside their cell (or hidden).
    pub outside: Vec<usize>,
}

/// Domain sites that are hidden or not strictly inside their cell.
pub fn outside(sites: &Sites, rt: &Triangulation, diagram: &Diagram) -> Vec<usize> {
    let nb = rt.neighbours(sites.len());
    let hidden: std::collections::HashSet<u32> = rt.hidden.iter().copied().collect();
    (0..sites.len())
        .filter(|&a| diagram.in_domain[a] || hidden.contains(&(a as u32)))
        .filter(|&a| {
            hidden.contains(&(a as u32)) || nb[a].iter().any(|&b| !inside_wrt(sites, a, b as usize))
        })
        .collect()
}

/// Why a site is outside its cell, for messages.
pub fn why(sites: &Sites, rt: &Triangulation, s: usize, cx: &crate::complex::Complex) -> String {
    if rt.hidden.contains(&(s as u32)) {
        return "hidden: other sites' power is lower everywhere, it has no cell".into();
    }
    if !sites.movable[s] {
        return "its segment misses its dual edge, so it cannot be on the segment's side".into();
    }
    let nb = rt.neighbours(sites.len());
    match nb[s].iter().find(|&&b| !inside_wrt(sites, s, b as usize)) {
        Some(&b) => format!(
            "no position tried on its dual edge puts it inside; it lies beyond its face with {}",
            sites.describe(b as usize, cx)
        ),
        None => "outside".into(),
    }
}

/// Builds the site diagram, moving sites until all domain sites are inside
/// their cells or no site can move.
pub fn relocate<B: Backend + ?Sized>(
    backend: &B,
    dom: &Domain,
    sites: &mut Sites,
) -> Result<Relocated> {
    let mut round = 0;
    let mut cache = CentreCache::default();
    loop {
        let rt = backend.regular_exact(&sites.pos, &sites.weight)?;
        let diagram = Diagram::build(dom, sites, &rt, &mut cache);
        let out = outside(sites, &rt, &diagram);
        let mut moved = std::collections::HashSet::new();
        if round < MAX_ROUNDS {
            let nb = rt.neighbours(sites.len());
            for &s in &out {
                let against: Vec<usize> = nb[s]
                    .iter()
                    .map(|&b| b as usize)
                    .filter(|&b| !inside_wrt(sites, s, b))
                    .collect();
                if sites.step(s, &against) {
                    moved.insert(s as u32);
                }
            }
        }
        cache.forget(&moved);
        if out.is_empty() || moved.is_empty() {
            return Ok(Relocated {
                rt,
                diagram,
                rounds: round,
                outside: out,
            });
        }
        round += 1;
    }
}
