//! Zero weights in 3D, when they serve: the Delaunay triangulation of the
//! vertices (exact predicates on the input doubles) has every face, and
//! every face of dimension 1 or 2 crosses its dual. Boxes, stacks of boxes
//! and fields of well-shaped facets need no LP.
//!
//! Two exact tests make that a proof. `check` finds each face among the
//! triangles of the Delaunay triangulation, and `sys3_failures` puts each
//! face's centre strictly closer to its vertices than to the apexes across
//! it. A face is then a face of the Delaunay subdivision, not only of the
//! triangulation a symbolic perturbation chose, unless another vertex lies
//! on its circle. The sphere through that circle centred in its plane is
//! then empty: on either side it lies inside the empty sphere of the
//! tetrahedron across. So that is the third test, `on_circles`.

use super::centres::{sys3_failures, Centres};
use super::d3::{check, finish, Weights3};
use super::face::Face;
use super::Keep;
use crate::backend::Tetrahedralisation;
use crate::complex::Complex3;
use crate::geom::{cross_f, dot_f, orient3, plane_axis, Grid, Q};
use crate::lp::WeightsReport;

/// Zero weights with `dt`, the Delaunay triangulation of the vertices,
/// when they serve (see the module's doc); None otherwise.
pub(super) fn zero(
    cx: &Complex3,
    faces: &[Face],
    dt: &Tetrahedralisation,
    keep: Keep,
) -> Option<Weights3> {
    let adj = dt.adjacency();
    let misses = check(cx, faces, dt, &adj);
    if !misses.faces.is_empty() || !misses.hidden.is_empty() {
        return None;
    }
    let w = vec![Q::from(0); cx.points.len()];
    let centres = Centres::new(faces.len());
    if !sys3_failures(cx, faces, (&w, &centres), &adj).is_empty() || on_circles(cx, faces) {
        return None;
    }
    let whole = faces.iter().filter(|f| f.vertices.len() > 3).count();
    let report = WeightsReport {
        method: "zero".into(),
        ..Default::default()
    };
    Some(finish(
        w,
        (dt.clone(), adj),
        faces.to_vec(),
        report,
        (whole, keep),
        (vec![], centres),
    ))
}

/// Whether a vertex other than a face's own lies exactly on the circle of
/// a triangle or polygon face (in its plane).
fn on_circles(cx: &Complex3, faces: &[Face]) -> bool {
    let grid = Grid::new(&cx.points);
    faces.iter().filter(|f| f.vertices.len() >= 3).any(|f| {
        let vs = &f.vertices;
        let p = |k: usize| cx.points[vs[k] as usize];
        let (a, b, c) = (p(0), p(1), p(2));
        let Some(axis) = plane_axis(a, b, c) else {
            return false;
        };
        let (lo, hi) = circle_box(a, b, c);
        grid.within(lo, hi).any(|m| {
            !vs.contains(&m)
                && orient3(a, b, c, cx.points[m as usize]).is_eq()
                && super::d3::cocircular(cx, axis, vs[0], vs[1], vs[2], m)
        })
    })
}

/// A box around the circle through a, b, c, widened by a relative margin
/// far above rounding (the tests inside it are exact).
fn circle_box(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    let d = |x: [f64; 3], y: [f64; 3]| [x[0] - y[0], x[1] - y[1], x[2] - y[2]];
    let (u, v) = (d(b, a), d(c, a));
    let n = cross_f(u, v);
    let nn = dot_f(n, n);
    // circumcentre - a = (|u|^2 (v x n) + |v|^2 (n x u)) / (2 |n|^2)
    let (vn, nu) = (cross_f(v, n), cross_f(n, u));
    let (uu, vv) = (dot_f(u, u), dot_f(v, v));
    let o: [f64; 3] = std::array::from_fn(|k| a[k] + (uu * vn[k] + vv * nu[k]) / (2.0 * nn));
    let r2 = dot_f(d(a, o), d(a, o));
    let pad = 1e-9 * (r2.sqrt() + o.iter().fold(0.0f64, |m, x| m.max(x.abs())));
    let half = |k: usize| (r2 * (1.0 - n[k] * n[k] / nn)).max(0.0).sqrt() + pad;
    (
        std::array::from_fn(|k| o[k] - half(k)),
        std::array::from_fn(|k| o[k] + half(k)),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_circle_box_holds_the_circle() {
        let (a, b, c) = ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]);
        let (lo, hi) = circle_box(a, b, c);
        // the unit circle in z = 0: a box of side 2, flat in z
        for k in 0..2 {
            assert!((lo[k] + 1.0).abs() < 1e-6 && (hi[k] - 1.0).abs() < 1e-6);
        }
        assert!(hi[2] - lo[2] < 1e-6);
        let tilted = circle_box([0.0, 0.0, 0.0], [2.0, 0.0, 2.0], [0.0, 2.0, 0.0]);
        assert!(tilted.0.iter().zip(&tilted.1).all(|(l, h)| h > l));
    }

    #[test]
    fn a_point_on_a_faces_circle_is_found() {
        // the rectangle [0,2]x[0,1] in z = 0: centre (1, 0.5), radius^2
        // 1.25 = 0.5^2 + 1^2, so (1.5, 1.5, 0) is on its circle
        let cx = |extra: [f64; 3]| Complex3 {
            points: vec![
                [0.0, 0.0, 0.0],
                [2.0, 0.0, 0.0],
                [2.0, 1.0, 0.0],
                [0.0, 1.0, 0.0],
                extra,
            ],
            vertex_ids: (1..=5).collect(),
            facets: vec![],
            holes: vec![],
        };
        let rectangle = [Face {
            vertices: vec![0, 1, 2, 3],
            facet: Some(0),
            cut: false,
        }];
        let triangle = [Face {
            vertices: vec![0, 1, 2],
            facet: Some(0),
            cut: false,
        }];
        assert!(on_circles(&cx([1.5, 1.5, 0.0]), &rectangle));
        assert!(on_circles(&cx([1.5, 1.5, 0.0]), &triangle));
        // the triangle's own circle holds the rectangle's fourth corner
        assert!(on_circles(&cx([9.0, 9.0, 9.0]), &triangle));
        assert!(!on_circles(&cx([9.0, 9.0, 9.0]), &rectangle));
        assert!(!on_circles(&cx([1.5, 1.5, 1e-300]), &rectangle));
        assert!(!on_circles(&cx([1.5, 1.5 + 1e-15, 0.0]), &rectangle));
    }
}
