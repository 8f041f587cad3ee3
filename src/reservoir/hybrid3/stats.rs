//! What a simulator will make of the mesh, measured: per pair of regions,
//! the links, how far off orthogonal (the angle between a face's normal
//! and the line joining its two sites), and those whose sites lie on one
//! side of their face (a two-point transmissibility that is negative or
//! infinite); transition cells much smaller than their cavity's others.

use super::report::Connections;
use crate::mesh::Mesh3;
use crate::reservoir::hybrid::Region;
use std::collections::BTreeMap;

/// A transition cell under this share of its cavity's median transition
/// cell's volume is a sliver: a simulator's time steps shrink to it.
pub(super) const SLIVER: f64 = 1e-3;

/// A link's angle off orthogonal (degrees): between its face's normal and
/// the line joining its sites.
pub(super) fn angle(m: &Mesh3, l: &crate::mesh::Link3) -> f64 {
    let (a, b) = (m.sites[l.cells[0]], m.sites[l.cells[1]]);
    let d: [f64; 3] = std::array::from_fn(|k| b[k] - a[k]);
    let len = crate::geom::dist_f(d, [0.0; 3]);
    let cos = crate::geom::dot_f(d, l.normal).abs() / len;
    match cos.is_finite() {
        true => cos.min(1.0).acos().to_degrees(),
        false => 90.0,
    }
}

/// Whether a link's two sites lie on one side of its face's plane (or on
/// it): its distances, taken unsigned, hide that.
fn one_sided(m: &Mesh3, l: &crate::mesh::Link3) -> bool {
    let Some(&o) = l.face.first() else {
        return false;
    };
    let o = m.points[o as usize];
    let side = |c: usize| {
        let s = m.sites[c];
        crate::geom::dot_f(std::array::from_fn(|k| s[k] - o[k]), l.normal)
    };
    side(l.cells[0]) * side(l.cells[1]) >= 0.0
}

/// Whether x's foot on a link's face's plane lies inside the face (within
/// 1e-9 of its size; a convex polygon).
fn foot_inside(m: &Mesh3, l: &crate::mesh::Link3, x: [f64; 3]) -> bool {
    let pts: Vec<[f64; 3]> = l.face.iter().map(|&v| m.points[v as usize]).collect();
    let n = crate::geom::newell(&pts);
    let size = pts
        .iter()
        .map(|p| crate::geom::dist_f(*p, pts[0]))
        .fold(0.0, f64::max);
    let len = crate::geom::dot_f(n, n).sqrt();
    if pts.len() < 3 || len == 0.0 {
        return false;
    }
    (0..pts.len()).all(|k| {
        let (a, b) = (pts[k], pts[(k + 1) % pts.len()]);
        let e: [f64; 3] = std::array::from_fn(|i| b[i] - a[i]);
        let r: [f64; 3] = std::array::from_fn(|i| x[i] - a[i]);
        // x left of edge a -> b seen from the normal's tip
        crate::geom::dot_f(crate::geom::cross_f(e, r), n) / len >= -1e-9 * size * size
    })
}

/// The connections per pair of regions ("reservoir-transition", ...).
pub(super) fn by_regions(m: &Mesh3, region: &[Region]) -> BTreeMap<String, Connections> {
    let name = |r: Region| match r {
        Region::Reservoir => "reservoir",
        Region::Transition => "transition",
        Region::Well => "well",
    };
    let mut angles: BTreeMap<String, Vec<f64>> = BTreeMap::new();
    let mut out: BTreeMap<String, Connections> = BTreeMap::new();
    let mut areas: BTreeMap<String, [f64; 2]> = BTreeMap::new();
    for l in &m.links {
        let mut pair = l.cells.map(|c| region[c]);
        pair.sort_by_key(|&r| r as u8);
        let key = format!("{}-{}", name(pair[0]), name(pair[1]));
        let e = out.entry(key.clone()).or_default();
        e.connections += 1;
        e.non_orthogonal += usize::from(m.link_defect(l) > 1e-6);
        e.one_sided += usize::from(one_sided(m, l));
        if let Some(x) = match pair.map(|r| r == Region::Reservoir) {
            [true, false] => Some(l.cells[usize::from(region[l.cells[0]] == Region::Reservoir)]),
            _ => None,
        } {
            let ok = !one_sided(m, l) && foot_inside(m, l, m.sites[x]);
            e.mirrored += usize::from(ok);
            let a = areas.entry(key.clone()).or_default();
            a[0] += l.area * f64::from(u8::from(ok));
            a[1] += l.area;
        }
        angles.entry(key).or_default().push(angle(m, l));
    }
    for (key, [ok, all]) in areas {
        if let Some(e) = out.get_mut(&key) {
            e.mirrored_area = ok / all;
        }
    }
    for (key, mut a) in angles {
        a.sort_by(f64::total_cmp);
        let at = |q: f64| a[((a.len() - 1) as f64 * q).round() as usize];
        if let Some(e) = out.get_mut(&key) {
            e.angle = [at(0.5), at(0.99), at(1.0)];
        }
    }
    out
}

/// Per cavity, the median of its cells' volumes (given each cell's
/// cavity).
pub(super) fn medians(volumes: &[f64], cavity_of: &[usize]) -> BTreeMap<usize, f64> {
    let mut per: BTreeMap<usize, Vec<f64>> = BTreeMap::new();
    for (&v, &c) in volumes.iter().zip(cavity_of) {
        per.entry(c).or_default().push(v);
    }
    per.into_iter()
        .map(|(c, mut v)| {
            v.sort_by(f64::total_cmp);
            (c, v[v.len() / 2])
        })
        .collect()
}

/// The transition cells under `SLIVER` of their cavity's median (given
/// each transition cell's cavity), and the smallest such share.
pub(super) fn slivers(volumes: &[f64], cavity_of: &[usize]) -> (usize, f64) {
    let median = medians(volumes, cavity_of);
    let shares = volumes
        .iter()
        .zip(cavity_of)
        .map(|(&v, c)| v / median.get(c).copied().unwrap_or(f64::NAN));
    shares.fold((0, f64::INFINITY), |(n, least), s| {
        (n + usize::from(s < SLIVER), least.min(s))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slivers_are_counted_per_cavity() {
        // cavity 0: median 1, one cell of 1e-4; cavity 1: median 1e-4
        let v = [1.0, 1.0, 1e-4, 1e-4, 1e-4, 2e-4];
        let (n, least) = slivers(&v, &[0, 0, 0, 1, 1, 1]);
        assert_eq!(n, 1);
        assert_eq!(least, 1e-4);
    }
}
