//! Faults inside a cavity refined to about the wells' outer radius. A
//! radial mesh clears a fault by a fraction of its cells' size (3.3 m of
//! 10 m columns beside a fault 5 m from the axis), so a whole fault face,
//! or its two triangles, has diametral balls that take in the well's outer
//! surface. The LP then finds no weights that keep the cavity's sides
//! whole (their links to the reservoir orthogonal), and drops them all.
//! Transition cells lie on both sides of such a face, so nothing needs it
//! whole: it is cut into triangles of about that radius, its edges on the
//! cavity's sides kept whole (the reservoir cells across have them). So
//! are the sides facing nothing (a throw's step). `complex::mesh` keeps
//! the cut complex only where it keeps more polygons whole.

use super::cavity::Side;
use crate::backend::Backend;
use crate::error::Result;
use crate::geom::{cross_f, dist_f, dot_f, newell};
use std::collections::BTreeSet;

/// A cut polygon's triangles.
pub(super) type Triangles = Vec<[[f64; 3]; 3]>;

/// An edge by its ends' bits, the lesser first.
pub(super) type Edge = [[u64; 3]; 2];

/// Edge p-q's key, whichever way it is walked.
fn key(p: [f64; 3], q: [f64; 3]) -> Edge {
    let (a, b) = (p.map(f64::to_bits), q.map(f64::to_bits));
    if q < p {
        [b, a]
    } else {
        [a, b]
    }
}

/// Per side, its triangles when it is cut to about h (`refine`): a fault
/// inside the cavity or a side facing nothing, near a well (`near`); and
/// the edges that stay whole: those of the sides not cut, those that
/// cannot be (not convex) included, so that the sides beside them keep
/// their points there too.
pub(super) fn faults<B: Backend + ?Sized>(
    backend: &B,
    sides: &[Side],
    h: f64,
    near: &dyn Fn(&[[f64; 3]]) -> bool,
) -> Result<(Vec<Option<Triangles>>, BTreeSet<Edge>)> {
    let edges = |s: &Side| {
        let n = s.points.len();
        (0..n)
            .map(|k| key(s.points[k], s.points[(k + 1) % n]))
            .collect::<Vec<_>>()
    };
    // faults inside the cavity and sides facing nothing (beside a throw's
    // step), whose balls reach a well
    let free = |s: &Side| s.open.is_none() && (s.inner || s.across.is_none()) && near(&s.points);
    let mut whole: BTreeSet<Edge> = sides
        .iter()
        .filter(|s| s.open.is_none() && !free(s))
        .flat_map(edges)
        .collect();
    loop {
        let mut cuts = vec![];
        for s in sides {
            let cut = match free(s) && h.is_finite() {
                true => {
                    let keep: Vec<bool> = edges(s).iter().map(|e| whole.contains(e)).collect();
                    refine(backend, &s.points, &keep, h)?
                }
                false => None,
            };
            cuts.push(cut);
        }
        let before = whole.len();
        for (s, cut) in sides.iter().zip(&cuts) {
            if free(s) && cut.is_none() {
                whole.extend(edges(s));
            }
        }
        if whole.len() == before {
            return Ok((cuts, whole));
        }
    }
}

/// Edge p-q's points, ends included: in pieces of about h unless it is in
/// `whole`, as the cut facet beside it has them.
pub(super) fn split(p: [f64; 3], q: [f64; 3], h: f64, whole: &BTreeSet<Edge>) -> Vec<[f64; 3]> {
    let m = match whole.contains(&key(p, q)) {
        true => 1,
        false => pieces(p, q, h),
    };
    edge_points(p, q, m)
}

/// How many pieces edge p-q takes at spacing h (at least one).
fn pieces(p: [f64; 3], q: [f64; 3], h: f64) -> usize {
    ((dist_f(p, q) / h).ceil() as usize).max(1)
}

/// The points of edge p-q in n pieces, ends included, computed from its
/// lesser end: the facets on either side of the edge get the same bits.
fn edge_points(p: [f64; 3], q: [f64; 3], n: usize) -> Vec<[f64; 3]> {
    let flip = q.partial_cmp(&p) == Some(std::cmp::Ordering::Less);
    let (a, b) = if flip { (q, p) } else { (p, q) };
    let mut out: Vec<[f64; 3]> = (0..=n)
        .map(|k| match k {
            0 => a,
            k if k == n => b,
            k => {
                let t = k as f64 / n as f64;
                std::array::from_fn(|c| a[c] + t * (b[c] - a[c]))
            }
        })
        .collect();
    if flip {
        out.reverse();
    }
    out
}

/// A planar convex polygon as triangles of about h: its edges split by
/// `edge_points` except those in `keep`, points of a triangular lattice
/// of spacing h inside it (at least 0.4 h from its edges), and the Delaunay
/// triangulation of them all in its plane. None when it is not convex
/// (it is then kept as it is).
pub(super) fn refine<B: Backend + ?Sized>(
    backend: &B,
    poly: &[[f64; 3]],
    keep: &[bool],
    h: f64,
) -> Result<Option<Triangles>> {
    let n = poly.len();
    let normal = newell(poly);
    let len = dot_f(normal, normal).sqrt();
    let first: [f64; 3] = std::array::from_fn(|c| poly[1][c] - poly[0][c]);
    let l1 = dot_f(first, first).sqrt();
    if n < 3 || !(len > 0.0 && l1 > 0.0 && h > 0.0) {
        return Ok(None);
    }
    let nz = normal.map(|x| x / len);
    let e1 = first.map(|x| x / l1);
    let e2 = cross_f(nz, e1);
    let o = poly[0];
    let flat = |p: [f64; 3]| -> [f64; 2] {
        let d: [f64; 3] = std::array::from_fn(|c| p[c] - o[c]);
        [dot_f(d, e1), dot_f(d, e2)]
    };
    let f: Vec<[f64; 2]> = poly.iter().map(|&p| flat(p)).collect();
    // strictly convex, counter-clockwise in (e1, e2) as Newell's normal
    // says: a corner on a side could give a flat triangle along it
    let turn = |k: usize| {
        let (a, b, c) = (f[k], f[(k + 1) % n], f[(k + 2) % n]);
        let (u, v) = ([b[0] - a[0], b[1] - a[1]], [c[0] - b[0], c[1] - b[1]]);
        let cross = u[0] * v[1] - u[1] * v[0];
        cross / ((u[0] * u[0] + u[1] * u[1]) * (v[0] * v[0] + v[1] * v[1])).sqrt()
    };
    if (0..n).any(|k| turn(k).is_nan() || turn(k) < 1e-6) {
        return Ok(None);
    }
    // the boundary's points, and the edge each lies on (corners: the next)
    let mut xyz: Vec<[f64; 3]> = vec![];
    let mut on: Vec<usize> = vec![];
    for k in 0..n {
        let (p, q) = (poly[k], poly[(k + 1) % n]);
        let m = if keep[k] { 1 } else { pieces(p, q, h) };
        xyz.extend(&edge_points(p, q, m)[..m]);
        on.extend((0..m).map(|_| k));
    }
    let boundary = xyz.len();
    // inside by 0.4 h: to the left of every edge by that distance
    let inside = |x: [f64; 2]| {
        (0..n).all(|k| {
            let (a, b) = (f[k], f[(k + 1) % n]);
            let e = [b[0] - a[0], b[1] - a[1]];
            let cross = e[0] * (x[1] - a[1]) - e[1] * (x[0] - a[0]);
            cross >= 0.4 * h * (e[0] * e[0] + e[1] * e[1]).sqrt()
        })
    };
    let (lo, hi) = f.iter().fold(
        ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]),
        |(lo, hi), p| {
            (
                [lo[0].min(p[0]), lo[1].min(p[1])],
                [hi[0].max(p[0]), hi[1].max(p[1])],
            )
        },
    );
    // a triangular lattice: no four of its points on a circle, unlike a
    // square grid's, whose ties the conforming mesh around would break
    // into nearly flat corners
    let row = h * 3f64.sqrt() / 2.0;
    for j in 1..=((hi[1] - lo[1]) / row).floor() as usize {
        let shift = if j % 2 == 1 { h / 2.0 } else { 0.0 };
        for i in 0..=((hi[0] - lo[0]) / h).floor() as usize {
            let x = [lo[0] + shift + i as f64 * h, lo[1] + j as f64 * row];
            if inside(x) {
                xyz.push(std::array::from_fn(|c| o[c] + x[0] * e1[c] + x[1] * e2[c]));
            }
        }
    }
    let plane: Vec<[f64; 2]> = xyz.iter().map(|&p| flat(p)).collect();
    let dt = backend.regular(&plane, &vec![0.0; plane.len()])?;
    // a triangle of three points of one edge (its points, rounded, need
    // not be on one line in the plane's frame) is flat: not cut then
    let along = |v: u32, k: usize| {
        let v = v as usize;
        v < boundary && (on[v] == k || (on[v] + n - 1) % n == k && v == first_of(&on, on[v]))
    };
    let flat_one = dt
        .triangles
        .iter()
        .any(|t| (0..n).any(|k| t.iter().all(|&v| along(v, k))));
    if !dt.hidden.is_empty() || flat_one {
        return Ok(None);
    }
    Ok(Some(
        dt.triangles
            .iter()
            .map(|t| t.map(|v| xyz[v as usize]))
            .collect(),
    ))
}

/// The index of the first boundary point on edge k (its corner).
fn first_of(on: &[usize], k: usize) -> usize {
    on.iter().position(|&e| e == k).unwrap_or(usize::MAX)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 10 x 4 rectangle at spacing 3, its left edge kept: its triangles
    /// tile it (areas add up), the right edge is in 2 pieces, the bottom
    /// in 4, and the kept edge has no point inside it.
    #[test]
    fn a_rectangle_is_cut_with_one_edge_kept() {
        let b = crate::backend::default_backend();
        let r = [
            [0.0, 0.0, 0.0],
            [10.0, 0.0, 0.0],
            [10.0, 4.0, 0.0],
            [0.0, 4.0, 0.0],
        ];
        let tris = refine(&b, &r, &[false, false, false, true], 3.0)
            .unwrap()
            .unwrap();
        let area: f64 = tris
            .iter()
            .map(|t| newell(t).iter().map(|x| x * x).sum::<f64>().sqrt() / 2.0)
            .sum();
        assert!((area - 40.0).abs() < 1e-9, "{area}");
        let pts: std::collections::BTreeSet<[u64; 3]> =
            tris.iter().flatten().map(|p| p.map(f64::to_bits)).collect();
        let on =
            |f: &dyn Fn([f64; 3]) -> bool| pts.iter().filter(|p| f(p.map(f64::from_bits))).count();
        assert_eq!(on(&|p| p[0] == 10.0), 3);
        assert_eq!(on(&|p| p[1] == 0.0), 5);
        assert_eq!(on(&|p| p[0] == 0.0), 2);
    }

    /// An edge's points are the same bits whichever way it is walked.
    #[test]
    fn edge_points_do_not_depend_on_direction() {
        let (p, q) = ([0.1, 0.7, 3.3], [9.9, -2.2, 1.0 / 3.0]);
        let mut back = edge_points(q, p, 7);
        back.reverse();
        assert_eq!(edge_points(p, q, 7), back);
    }

    /// A polygon that turns the other way somewhere is left as it is.
    #[test]
    fn a_nonconvex_polygon_is_left_whole() {
        let b = crate::backend::default_backend();
        let l = [
            [0.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [2.0, 1.0, 0.0],
            [1.0, 1.0, 0.0],
            [1.0, 2.0, 0.0],
            [0.0, 2.0, 0.0],
        ];
        assert!(refine(&b, &l, &[false; 6], 0.5).unwrap().is_none());
    }
}
