//! Which polygons are kept whole in 3D: those that can be (strictly
//! convex, exactly cocircular), and the smaller sets tried when they
//! leave the weights no solution (`d3::solve_kept`).

use super::d3::{faces, ties};
use crate::complex::Complex3;
use crate::domain::Simplices3;
use crate::geom::{drop_axis, plane_axis, q, Q};

/// Polygons with more vertices than this are triangulated (the exact check
/// of a whole polygon looks at every triple of its vertices).
const MAX_WHOLE: usize = 12;

/// The whole polygons with no vertex on a triangle or segment.
pub(super) fn direct(cx: &Complex3, sc: &Simplices3, whole: &[bool]) -> Vec<bool> {
    let fs = faces(cx, sc, whole, &[]);
    let mut touched = vec![false; cx.points.len()];
    for f in fs.iter().filter(|f| (2..=3).contains(&f.vertices.len())) {
        f.vertices.iter().for_each(|&v| touched[v as usize] = true);
    }
    let mut out = whole.to_vec();
    for f in fs.iter().filter(|f| f.vertices.len() > 3) {
        if f.vertices.iter().any(|&v| touched[v as usize]) {
            out[f.facet.expect("polygons have a facet") as usize] = false;
        }
    }
    out
}

/// The whole polygons whose shared-weight class (polygons joined through
/// common vertices) has no vertex on a triangle or segment.
pub(super) fn untouched(cx: &Complex3, sc: &Simplices3, whole: &[bool]) -> Vec<bool> {
    let fs = faces(cx, sc, whole, &[]);
    let tie = ties(cx.points.len(), &fs);
    let mut touched = vec![false; cx.points.len()];
    for f in fs.iter().filter(|f| (2..=3).contains(&f.vertices.len())) {
        f.vertices
            .iter()
            .for_each(|&v| touched[tie[v as usize] as usize] = true);
    }
    let mut out = whole.to_vec();
    for f in fs.iter().filter(|f| f.vertices.len() > 3) {
        if touched[tie[f.vertices[0] as usize] as usize] {
            out[f.facet.expect("polygons have a facet") as usize] = false;
        }
    }
    out
}

/// Per facet, whether it is kept whole: one strictly convex polygon of 4
/// to `MAX_WHOLE` vertices, no holes, its vertices exactly cocircular.
pub fn kept_whole(cx: &Complex3) -> Vec<bool> {
    let p = |v: u32| cx.points[v as usize];
    cx.facets
        .iter()
        .map(|f| {
            let [poly] = f.polygons.as_slice() else {
                return false;
            };
            if poly.len() < 4 || poly.len() > MAX_WHOLE || !f.holes.is_empty() {
                return false;
            }
            let Some(axis) = plane_axis(p(poly[0]), p(poly[1]), p(poly[2])) else {
                return false;
            };
            let flat = |v: u32| drop_axis(axis, p(v));
            let m = poly.len();
            let turn = |k: usize| {
                crate::geom::orient(
                    flat(poly[k]),
                    flat(poly[(k + 1) % m]),
                    flat(poly[(k + 2) % m]),
                )
            };
            // A simple polygon (validated) turning one way at every vertex
            // is strictly convex.
            let first = turn(0);
            first != std::cmp::Ordering::Equal
                && (1..m).all(|k| turn(k) == first)
                && poly[3..]
                    .iter()
                    .all(|&d| cocircular(cx, axis, poly[0], poly[1], poly[2], d))
        })
        .collect()
}

/// Whether d, coplanar with a, b, c, lies on their circle: with one
/// weight for all four, whether their lifts are coplanar. In affine
/// coordinates d = a + s (b - a) + t (c - a) (a coordinate projection
/// keeps them), the lift must be the same combination:
/// D (|d|^2 - |a|^2) = S (|b|^2 - |a|^2) + T (|c|^2 - |a|^2), s = S / D.
pub(super) fn cocircular(cx: &Complex3, axis: usize, a: u32, b: u32, c: u32, d: u32) -> bool {
    let p = |v: u32| cx.points[v as usize];
    let f = |v: u32| drop_axis(axis, p(v)).map(q);
    let (fa, fb, fc, fd) = (f(a), f(b), f(c), f(d));
    let det = |x: &[Q; 2], y: &[Q; 2], o: &[Q; 2]| {
        (&x[0] - &o[0]) * (&y[1] - &o[1]) - (&x[1] - &o[1]) * (&y[0] - &o[0])
    };
    let big_d = det(&fb, &fc, &fa);
    let s = det(&fd, &fc, &fa);
    let t = det(&fb, &fd, &fa);
    let n2 = |v: u32| {
        p(v).iter()
            .map(|&x| q(x) * q(x))
            .fold(Q::from(0), |acc, x| acc + x)
    };
    let na = n2(a);
    big_d * (n2(d) - &na) == s * (n2(b) - &na) + t * (n2(c) - &na)
}
