//! Trajectories that bend: split into straight legs (runs of points
//! within 1% of their chord's length of it, or within `STRAY` of the
//! radial mesh's outer radius: a sampled curve becomes a few legs at the
//! radial mesh's scale), each meshed as a straight path. At a bend the
//! legs meet in a knee (`chain`): mitred, each leg's layer there the
//! other's mirror image, the wellbore whole. The legs' links to the
//! wellbore are one well's (`merge_legs`).

use super::cpg::Cpg;
use super::path::{off_line, Path};
use super::radial::{frame, After, End, Knee, Radial};
use super::well::{Hybrid3Options, Well3};
use crate::error::{Error, Result};
use crate::geom::{dist_f, dot_f};
use crate::reservoir::deck::WellLinks;

/// How far off its leg's line a point of a trajectory may lie, in outer
/// radii of the leg's radial mesh (as its start cell's sides give it): a
/// build section sampled every few metres is then legs of a cell or so,
/// not one per sample, each too short to mesh.
const STRAY: f64 = 0.1;

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

/// A well's paths: one, or for a trajectory that bends one per leg, from
/// bend to bend, each marked as leg `(n, leg)` of well n with the half
/// turn at each of its knees and the outer radius at which they fit it.
/// Radial meshes reach at most `outer` head-cell sides from their axis.
pub(super) fn paths(cpg: &Cpg, well: &Well3, n: usize, outer: f64) -> Result<Vec<(Well3, Path)>> {
    // a well whose completed cells' centres are not on one vertical is the
    // trajectory through them
    let centred;
    let well = match super::path::through_centres(cpg, well)? {
        Some(w) => {
            centred = w;
            &centred
        }
        None => well,
    };
    let one = || Ok(vec![(well.clone(), Path::new(cpg, well)?)]);
    let Some(points) = &well.path else {
        return one();
    };
    let (pts, ranges) = legs(points, |p| STRAY * outer * side_at(cpg, p));
    // each leg its chord: the points between may stray from it
    let leg = |r: [usize; 2]| Well3 {
        path: Some(vec![pts[r[0]], pts[r[1]]]),
        ..well.clone()
    };
    match ranges[..] {
        [] => return one(),
        [r] => return Ok(vec![(leg(r), Path::new(cpg, &leg(r))?)]),
        _ => {}
    }
    let mut out = ranges
        .iter()
        .map(|&r| Ok((leg(r), Path::new(cpg, &leg(r))?)))
        .collect::<Result<Vec<_>>>()?;
    for a in 0..ranges.len() - 1 {
        let (p, q) = (&out[a].1, &out[a + 1].1);
        let cos = dot_f(p.u, q.u);
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
        out[a].1.bends[1] = Some(half);
        out[a + 1].1.bends[0] = Some(half);
    }
    for (a, (_, path)) in out.iter_mut().enumerate() {
        // the radius at which the knees at its ends take `ROOM` of it
        let per_r: f64 = path.bends.iter().flatten().map(|&h| depth(1.0, h)).sum();
        path.max_outer = ROOM * path.length / per_r;
        let [s, e] = ranges[a];
        if path.max_outer <= 2.5 * well.radius {
            return Err(Error::Usage(format!(
                "well {}: its leg from point {} to {} is {:.3} long, too short for the knees \
                 at its ends (a radial mesh of radius {:.3} at most, around a wellbore of \
                 radius {})",
                well.name,
                s + 1,
                e + 1,
                path.length,
                path.max_outer,
                well.radius
            )));
        }
        path.leg = Some((n, a));
    }
    Ok(out)
}

/// How much of a leg its knees may take: the rest is its own layers.
const ROOM: f64 = 0.9;

/// How far along its axis a leg's layer at a knee reaches from the knee's
/// point, for outer radius r and half turn `half`: twice the mitre's
/// slant on the outer surface and a quarter radius, so that the layer's
/// sites (halfway) lie inside it, mirrored across the mitre.
pub(super) fn depth(r: f64, half: f64) -> f64 {
    2.0 * r * half.tan() + 0.25 * r
}

/// A chain of legs' radial meshes (a well's consecutive legs in one
/// cavity, in order, with their ends) at one outer radius: the mitre
/// plane at each knee halves the turn between the legs' rounded axes,
/// through the end of the leg before's, where the leg after starts, its
/// sectors turned to mirror the leg before's and its first level's points
/// taken from it. Both layers at the knee are then mirror images: their
/// links across it orthogonal, and the wellbore has no gap.
pub(super) fn chain(
    legs: &[(&Well3, &Path, [End; 2])],
    opts: &Hybrid3Options,
    outer: f64,
) -> Result<Vec<Radial>> {
    let axes: Vec<[f64; 3]> = legs
        .iter()
        .map(|&(_, p, ends)| Radial::lattice(p, outer, ends).map_or(p.u, |l| l.axis()))
        .collect();
    let mut out: Vec<Radial> = vec![];
    let mut after: Option<After> = None;
    let mut before: Option<Knee> = None;
    for (a, &(well, path, mut ends)) in legs.iter().enumerate() {
        if let (Some(k), End::Knee(_)) = (before, ends[0]) {
            ends[0] = End::Knee(k);
        }
        let head = after.as_ref().map_or(path.head, |x| x.head);
        let knee = (a + 1 < legs.len() && matches!(ends[1], End::Knee(_))).then(|| {
            let (u, v) = (axes[a], axes[a + 1]);
            let sum: [f64; 3] = std::array::from_fn(|k| u[k] + v[k]);
            let cos = dot_f(u, v);
            Knee {
                point: std::array::from_fn(|k| head[k] + path.length * u[k]),
                normal: sum.map(|x| x / dist_f(sum, [0.0; 3])),
                depth: depth(outer, cos.clamp(-1.0, 1.0).acos() / 2.0),
            }
        });
        if let Some(k) = knee {
            ends[1] = End::Knee(k);
        }
        let r = Radial::new(well, path, opts, outer, ends, after.as_ref())?;
        after = knee.map(|k| {
            // the leg before's sector 0, mirrored, in the leg after's frame
            let [e1, e2] = r.across();
            let (c, s) = (r.angle(0).cos(), r.angle(0).sin());
            let d: [f64; 3] = std::array::from_fn(|i| c * e1[i] + s * e2[i]);
            let dn = dot_f(d, k.normal);
            let m: [f64; 3] = std::array::from_fn(|i| d[i] - 2.0 * dn * k.normal[i]);
            let [f1, f2] = frame(axes[a + 1]);
            let last = r.levels.len() - 1;
            After {
                head: k.point,
                phase: dot_f(m, f2).atan2(dot_f(m, f1)),
                points: (0..=r.rings)
                    .flat_map(|q| (0..r.m).map(move |s| (q, s)))
                    .map(|(q, s)| r.point(q, s, last))
                    .collect(),
            }
        });
        before = knee;
        out.push(r);
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
        .map_or(0.0, |c| cpg.side(c))
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
