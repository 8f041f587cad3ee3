//! Slivers merged away: a 3D transition cell under `stats::SLIVER` of its
//! cavity's median volume (near-degenerate power vertices leave some, a few
//! rounding to a negative volume) is joined to the transition cell in the
//! same grid cell (never across a fault or a layer) it shares most area
//! with. A simulator's time steps would shrink to it, and
//! TOUGH readers refuse a volume that is not positive. The union keeps the
//! larger cell's site; the sliver's other faces become its faces, their
//! distances taken from that site. It is often not convex: the VTU marks
//! such cells (`merged`).

use super::stats::SLIVER;
use crate::mesh::Mesh3;
use crate::reservoir::deck::WellLinks;
use crate::reservoir::hybrid::Region;
use std::collections::{BTreeMap, HashSet};

/// A sliver under this share of its cavity's median volume has no rock to
/// keep (measured: emerald's leaning column (19, 18) on the pure backend
/// left one at -1e-13 of the median, flat on a layer's boundary, its
/// neighbours all in the layers above and below).
const NO_ROCK: f64 = 1e-9;

/// The cells and what is kept per cell beside the mesh.
pub(super) struct Cells<'a> {
    pub(super) mesh: &'a mut Mesh3,
    pub(super) region: &'a mut Vec<Region>,
    pub(super) ijk: &'a mut Vec<Option<[usize; 3]>>,
    /// Per cell, the grid cell whose rock it takes.
    pub(super) host: &'a mut Vec<[usize; 3]>,
    /// The grid cell of a cavity (given by index) that holds a point.
    pub(super) locate: &'a dyn Fn([f64; 3], usize) -> Option<[usize; 3]>,
    /// Whether a grid cell's side faces are clear of faults and throws (a
    /// sliver alone in such a cell may join a cell beside it in its layer).
    pub(super) clear: &'a dyn Fn([usize; 3]) -> bool,
    /// Per cell from `first`, its cavity.
    pub(super) cavity_of: &'a mut Vec<usize>,
    pub(super) first: usize,
    pub(super) wellbore: &'a mut [WellLinks],
}

/// Per transition cell under SLIVER of its cavity's median, the transition
/// cell it joins (the one across its largest face; smallest first, so that
/// a sliver beside a sliver joins the one that absorbed it).
fn targets(c: &Cells) -> BTreeMap<usize, usize> {
    let m = &*c.mesh;
    let t: Vec<usize> = (c.first..m.volumes.len())
        .filter(|&k| c.region[k] == Region::Transition)
        .collect();
    let cavity: Vec<usize> = t.iter().map(|&k| c.cavity_of[k - c.first]).collect();
    let volumes: Vec<f64> = t.iter().map(|&k| m.volumes[k]).collect();
    let median = super::stats::medians(&volumes, &cavity);
    let mut small: Vec<usize> = t
        .into_iter()
        .filter(|&k| m.volumes[k] < SLIVER * median[&c.cavity_of[k - c.first]])
        .collect();
    small.sort_by(|&a, &b| m.volumes[a].total_cmp(&m.volumes[b]));
    // the grid cell that holds the mean of a cell's points (a sliver's
    // site may lie far outside it)
    let home = |k: usize| {
        let pts: Vec<[f64; 3]> = m.cells[k]
            .iter()
            .flatten()
            .map(|&v| m.points[v as usize])
            .collect();
        let n = pts.len().max(1) as f64;
        let x: [f64; 3] = std::array::from_fn(|a| pts.iter().map(|p| p[a]).sum::<f64>() / n);
        (c.locate)(x, c.cavity_of[k - c.first]).unwrap_or(c.host[k])
    };
    let mut into: BTreeMap<usize, usize> = BTreeMap::new();
    let root = |into: &BTreeMap<usize, usize>, mut k: usize| {
        while let Some(&n) = into.get(&k) {
            k = n;
        }
        k
    };
    // a sliver alone in its grid cell (at a reflex corner of a cavity's
    // outline) joins a cell of a column beside it, in its layer, where no
    // fault or throw runs between them: its rock hardly counts, and a pore
    // volume of a barrel would set a simulator's steps
    let beside = |a: [usize; 3], b: [usize; 3]| {
        a[2] == b[2]
            && a[0].abs_diff(b[0]) <= 1
            && a[1].abs_diff(b[1]) <= 1
            && (c.clear)(a)
            && (c.clear)(b)
    };
    for a in small {
        let at = home(a);
        // a cell without rock (flat on a layer's boundary, its volume
        // rounding to zero or below) may join one in the next layer
        let flat = m.volumes[a] < NO_ROCK * median[&c.cavity_of[a - c.first]];
        let mut best: [Option<(f64, usize)>; 3] = [None, None, None];
        for l in m.links.iter().filter(|l| l.cells.contains(&a)) {
            let b = root(&into, l.cells[usize::from(l.cells[0] == a)]);
            if b == a || c.region[b] != Region::Transition {
                continue;
            }
            let hb = home(b);
            let slot = match (hb == at, beside(at, hb)) {
                (true, _) => 0,
                (false, true) => 1,
                (false, false) if flat => 2,
                (false, false) => continue,
            };
            if best[slot].is_none_or(|(area, _)| l.area > area) {
                best[slot] = Some((l.area, b));
            }
        }
        if let Some((_, b)) = best[0].or(best[1]).or(best[2]) {
            into.insert(a, b);
        }
    }
    into.keys().map(|&a| (a, root(&into, a))).collect()
}

/// A face's points as a key that its reverse (the same face seen from the
/// other cell) shares: rotated to start at its smallest id, turned to go
/// on to the smaller neighbour.
fn key(f: &[u32]) -> Vec<u32> {
    let n = f.len();
    let s = (0..n).min_by_key(|&k| f[k]).unwrap_or(0);
    let fwd: Vec<u32> = (0..n).map(|k| f[(s + k) % n]).collect();
    let back: Vec<u32> = (0..n).map(|k| f[(s + n - k) % n]).collect();
    fwd.min(back)
}

/// Drops the entries of the merged cells from a per-cell list (whose
/// entry k is cell first + k).
fn drop<T>(v: &mut Vec<T>, first: usize, merged: &BTreeMap<usize, usize>) {
    let mut k = first;
    v.retain(|_| {
        k += 1;
        !merged.contains_key(&(k - 1))
    });
}

/// Merges the slivers; returns how many, and the cells they joined (new
/// ids).
pub(super) fn merge(c: Cells) -> (usize, Vec<usize>) {
    let into = targets(&c);
    if into.is_empty() {
        return (0, vec![]);
    }
    let m = c.mesh;
    // the kept cells' new ids, a merged cell's its target's
    let mut id = vec![0usize; m.volumes.len()];
    let mut next = 0;
    for (k, slot) in id.iter_mut().enumerate() {
        if !into.contains_key(&k) {
            *slot = next;
            next += 1;
        }
    }
    for (&a, &b) in &into {
        id[a] = id[b];
    }
    for (&a, &b) in &into {
        let faces = std::mem::take(&mut m.cells[a]);
        m.cells[b].extend(faces);
    }
    // faces now inside a cell appear in it twice (once each way)
    for &b in into.values().collect::<HashSet<_>>() {
        let mut count: BTreeMap<Vec<u32>, usize> = BTreeMap::new();
        for f in &m.cells[b] {
            *count.entry(key(f)).or_default() += 1;
        }
        m.cells[b].retain(|f| count[&key(f)] == 1);
        // from the union's faces: a sliver's own volume is its points'
        // rounding
        m.volumes[b] = crate::geom::volume(&m.cells[b], &m.points);
    }
    drop(&mut m.cells, 0, &into);
    drop(&mut m.sites, 0, &into);
    drop(&mut m.weights, 0, &into);
    drop(&mut m.volumes, 0, &into);
    drop(&mut m.site_inside, 0, &into);
    drop(c.region, 0, &into);
    drop(c.ijk, 0, &into);
    drop(c.host, 0, &into);
    drop(c.cavity_of, c.first, &into);
    for f in &mut m.facet_faces {
        f.cell = id[f.cell];
    }
    for w in c.wellbore.iter_mut() {
        for l in &mut w.links {
            l.0 = id[l.0];
        }
    }
    // links: the merged cell's side measured from its new site
    let links = std::mem::take(&mut m.links);
    for mut l in links {
        let moved = l.cells.map(|k| into.contains_key(&k));
        l.cells = l.cells.map(|k| id[k]);
        if l.cells[0] == l.cells[1] {
            continue;
        }
        for s in 0..2 {
            if moved[s] {
                let o = m.points[l.face[0] as usize];
                let x = m.sites[l.cells[s]];
                let r: [f64; 3] = std::array::from_fn(|a| x[a] - o[a]);
                l.d[s] = crate::geom::dot_f(r, l.normal).abs();
            }
        }
        m.links.push(l);
    }
    m.links = super::assembly::one_per_pair(std::mem::take(&mut m.links));
    let joined: std::collections::BTreeSet<usize> = into.values().map(|&b| id[b]).collect();
    (into.len(), joined.into_iter().collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_face_and_its_reverse_share_a_key() {
        assert_eq!(key(&[4, 2, 7, 9]), key(&[9, 7, 2, 4]));
        assert_eq!(key(&[2, 7, 9, 4]), key(&[4, 9, 7, 2]));
        assert_ne!(key(&[2, 7, 9, 4]), key(&[2, 9, 7, 4, 5]));
    }
}
