//! Trajectories that bend: split into straight legs (runs of points
//! within 1% of their chord's length of it, or within `STRAY` of the
//! radial mesh's outer radius: a sampled curve becomes a few legs at the
//! radial mesh's scale), each meshed as a straight path. At a bend both legs stop short, each by what keeps its radial
//! mesh on its side of the bend's bisector plane, a margin and a plug;
//! the wellbore there has no radial cells. The legs' links to the
//! wellbore are one well's (`merge_legs`).

use super::cavity::{cell_side, head_side};
use super::cpg::Cpg;
use super::path::Path;
use super::Well3;
use crate::error::{Error, Result};
use crate::reservoir::deck::WellLinks;

/// How far off its leg's line a point of a trajectory may lie, in outer
/// radii of the leg's radial mesh (as its start cell's sides give it): a
/// build section sampled every few metres is then legs of a cell or so,
/// not one per sample, each too short to mesh.
const STRAY: f64 = 0.1;

/// The first point farther off the line from the first point to the last
/// than 1% of their distance and than `floor`: its index and how far.
pub(super) fn off_line(points: &[[f64; 3]], floor: f64) -> Option<(usize, f64)> {
    let (first, last) = (points.first()?, points.last()?);
    let d: [f64; 3] = std::array::from_fn(|a| last[a] - first[a]);
    let length = d.iter().map(|x| x * x).sum::<f64>().sqrt();
    let u = d.map(|x| x / length);
    points.iter().enumerate().find_map(|(n, q)| {
        let v: [f64; 3] = std::array::from_fn(|a| q[a] - first[a]);
        let t: f64 = (0..3).map(|a| v[a] * u[a]).sum();
        let off = (0..3)
            .map(|a| (v[a] - t * u[a]).powi(2))
            .sum::<f64>()
            .sqrt();
        (off > floor.max(0.01 * length)).then_some((n, off))
    })
}

/// A trajectory's straight legs, as ranges of its points (repeated points
/// dropped first): from the first point, each leg takes as many points as
/// stay on its line (`off_line`), within `stray` of it (given its first
/// point).
fn legs(points: &[[f64; 3]], stray: impl Fn([f64; 3]) -> f64) -> (Vec<[f64; 3]>, Vec<[usize; 2]>) {
    let mut pts = points.to_vec();
    pts.dedup();
    let mut out = vec![];
    let mut s = 0;
    while s + 1 < pts.len() {
        let floor = stray(pts[s]);
        let mut e = s + 1;
        while e + 1 < pts.len() && off_line(&pts[s..=e + 1], floor).is_none() {
            e += 1;
        }
        out.push([s, e]);
        s = e;
    }
    (pts, out)
}

/// A well's paths: one, or for a trajectory that bends one per leg, each
/// shortened at its bends and marked as leg `(n, leg)` of well n. Radial
/// meshes reach at most `outer` head-cell sides from their axis.
pub(super) fn paths(cpg: &Cpg, well: &Well3, n: usize, outer: f64) -> Result<Vec<(Well3, Path)>> {
    let one = || Ok(vec![(well.clone(), Path::new(cpg, well)?)]);
    let Some(points) = &well.path else {
        return one();
    };
    let (pts, ranges) = legs(points, |p| STRAY * outer * side_at(cpg, p));
    if ranges.len() < 2 {
        return one();
    }
    // each leg its chord: the points between may stray from it
    let leg = |r: [usize; 2]| Well3 {
        path: Some(vec![pts[r[0]], pts[r[1]]]),
        ..well.clone()
    };
    let whole = ranges
        .iter()
        .map(|&r| Path::new(cpg, &leg(r)))
        .collect::<Result<Vec<_>>>()?;
    // per leg and end: how far it stops short of the bend, its plug's length
    let mut short = vec![[(0.0, None); 2]; ranges.len()];
    for a in 0..ranges.len() - 1 {
        let (p, q) = (&whole[a], &whole[a + 1]);
        let cos: f64 = (0..3).map(|k| p.u[k] * q.u[k]).sum();
        let half = cos.clamp(-1.0, 1.0).acos() / 2.0;
        if half > 60f64.to_radians() {
            return Err(Error::Usage(format!(
                "well {}: its path turns by {:.1} degrees at point {} (the 3D hybrid takes \
                 bends up to 120 degrees)",
                well.name,
                2.0 * half.to_degrees(),
                ranges[a][1] + 1
            )));
        }
        let r = outer * head_side(cpg, p).max(head_side(cpg, q));
        let plug = 0.125 * r;
        // beyond the bisector plane by a quarter radius, then the plug
        let t = r * half.tan() + 0.25 * r + plug;
        short[a][1] = (t, Some(plug));
        short[a + 1][0] = (t, Some(plug));
    }
    let mut out = vec![];
    for (a, &[s, e]) in ranges.iter().enumerate() {
        let (first, last) = (pts[s], pts[e]);
        let d: [f64; 3] = std::array::from_fn(|k| last[k] - first[k]);
        let length = d.iter().map(|x| x * x).sum::<f64>().sqrt();
        let [(t0, p0), (t1, p1)] = short[a];
        let plugs = p0.unwrap_or(0.0) + p1.unwrap_or(0.0);
        if length - t0 - t1 <= plugs {
            return Err(Error::Usage(format!(
                "well {}: its leg from point {} to {} is {length:.3} long, too short for the \
                 bends at its ends ({:.3}, with the radial meshes' plugs)",
                well.name,
                s + 1,
                e + 1,
                t0 + t1 + plugs
            )));
        }
        let at = |t: f64| -> [f64; 3] { std::array::from_fn(|k| first[k] + t / length * d[k]) };
        let w = Well3 {
            path: Some(vec![at(t0), at(length - t1)]),
            ..well.clone()
        };
        let mut path = Path::new(cpg, &w)?;
        path.leg = Some((n, a));
        path.bends = [p0, p1];
        out.push((w, path));
    }
    Ok(out)
}

/// The shorter side of the top of the live cell that holds a point of a
/// trajectory (x, y, depth); 0 outside the live cells.
fn side_at(cpg: &Cpg, p: [f64; 3]) -> f64 {
    let g = cpg.g;
    let cells = (0..g.nz)
        .flat_map(|k| (0..g.ny).flat_map(move |j| (0..g.nx).map(move |i| [i, j, k])))
        .filter(|&c| cpg.live(c));
    cpg.locate([p[0], p[1], -p[2]], cells)
        .map_or(0.0, |c| cell_side(cpg, c))
}

/// Whether two paths are adjacent legs of one well: their radial meshes
/// lie on either side of their bend by construction.
pub(super) fn adjacent(a: &Path, b: &Path) -> bool {
    matches!((a.leg, b.leg), (Some((w, x)), Some((v, y))) if w == v && x.abs_diff(y) == 1)
}

/// The wells' links to their wellbores, the legs of one well as one (in
/// the order their first legs come), given each entry's well.
pub(super) fn merge_legs(links: Vec<WellLinks>, owner: &[usize]) -> Vec<WellLinks> {
    let mut out: Vec<WellLinks> = vec![];
    let mut at: std::collections::BTreeMap<usize, usize> = Default::default();
    for (l, &w) in links.into_iter().zip(owner) {
        match at.get(&w) {
            Some(&k) => out[k].links.extend(l.links),
            None => {
                at.insert(w, out.len());
                out.push(l);
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::legs;

    /// A quarter circle of radius 45 sampled every 5 (or so): at 1% of
    /// each chord, a leg per two points; within 1 of their lines, legs
    /// about 17 long; repeated points are dropped.
    #[test]
    fn sampled_arcs_become_legs_at_the_given_scale() {
        let mut arc: Vec<[f64; 3]> = (0..=14)
            .map(|k| {
                let a = k as f64 / 14.0 * std::f64::consts::FRAC_PI_2;
                [45.0 * (1.0 - a.cos()), 0.0, 45.0 * a.sin()]
            })
            .collect();
        arc.insert(3, arc[3]);
        let (pts, fine) = legs(&arc, |_| 0.0);
        assert_eq!(pts.len(), 15);
        assert_eq!(fine.len(), 14);
        let (_, coarse) = legs(&arc, |_| 1.0);
        assert_eq!(coarse.len(), 5);
        assert!(coarse.windows(2).all(|w| w[0][1] == w[1][0]));
        assert_eq!((coarse[0][0], coarse[4][1]), (0, 14));
    }
}
