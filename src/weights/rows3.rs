//! The rows of the 3D global form (`d3`): a supporting plane per maximal
//! face with rows for the points near it (system 1), and system 3: a
//! dangling segment's radical point and a triangle's or polygon's power
//! centre inside it and nearest, in power, to its own vertices.

use super::face::Face;
use crate::lp::{plane_rows, rel, sys3_rows, Family, Origin, Row, System, Units};
use nalgebra::{Matrix2, Matrix3x2, Vector2};
use std::collections::BTreeSet;

/// The rows of every face with the points of its set (`sets`, by face).
pub(super) fn system(
    p: &[[f64; 3]],
    faces: &[Face],
    sets: &[BTreeSet<u32>],
    units: &Units<3>,
    free: Vec<bool>,
) -> System {
    let mut sys = System {
        n: p.len(),
        free,
        verdict: true,
        unit2: units.unit2,
        lazy_aux: true,
        l2: units.l2.clone(),
        ..Default::default()
    };
    for (fi, face) in faces.iter().enumerate() {
        let others: Vec<u32> = sets[fi].iter().copied().collect();
        let vs = &face.vertices;
        let on = &vs[1..vs.len().min(3)];
        let scale2 = on
            .iter()
            .map(|&j| rel(p, vs[0], j).norm_squared())
            .fold(units.l2[vs[0] as usize], f64::max);
        plane_rows(&mut sys, p, fi as u32, vs[0], on, &others, scale2);
        match if face.cut { 0 } else { face.dim() } {
            1 => sys
                .rows
                .extend(sys3_rows(p, fi as u32, vs[0], vs[1], &others)),
            2 => sys.rows.extend(centre_rows(p, fi as u32, vs, &others)),
            _ => {}
        }
    }
    sys
}

/// System 3 for a triangle or polygon face f: its power centre c (in its
/// plane, equal power to all its vertices) lies strictly inside it, at
/// least delta times its longest edge from every edge, and every point m
/// has a larger power at c than the face's vertices (over the squared
/// longest edge). With u = p_j - p_i, v = p_k - p_i and G their Gram
/// matrix, c - p_i = M (|u|^2 + w_i - w_j, |v|^2 + w_i - w_k), M = [u v] G^-1 / 2.
fn centre_rows(p: &[[f64; 3]], f: u32, verts: &[u32], others: &[u32]) -> Vec<Row> {
    let (i, j, k) = (verts[0], verts[1], verts[2]);
    let (u, v) = (rel(p, i, j), rel(p, i, k));
    let g = Matrix2::new(u.dot(&u), u.dot(&v), u.dot(&v), v.dot(&v));
    let Some(gi) = g.try_inverse() else {
        return vec![];
    };
    let m = Matrix3x2::from_columns(&[u, v]) * gi * 0.5;
    let x0 = m * Vector2::new(u.norm_squared(), v.norm_squared());
    let cycle = || verts.iter().zip(verts.iter().cycle().skip(1));
    let l = cycle()
        .map(|(&a, &b)| rel(p, a, b).norm_squared())
        .fold(0.0, f64::max);
    // base + c . (w_i - w_j, w_i - w_k) + extra >= delta * scale
    let row = |base: f64, c: Vector2<f64>, extra: &[(u32, f64)], scale: f64, origin| {
        let mut terms = vec![
            (i as usize, (c[0] + c[1]) / scale),
            (j as usize, -c[0] / scale),
            (k as usize, -c[1] / scale),
        ];
        terms.extend(extra.iter().map(|&(v, x)| (v as usize, x / scale)));
        let mut r = Row::sys1(terms, -base / scale);
        r.family = Family::Sys3(f);
        r.origin = origin;
        r
    };
    let t = [i, j, k];
    let normal = u.cross(&v);
    let mut rows: Vec<Row> = cycle()
        .map(|(&a, &b)| {
            // inward in the face's plane (the cycle turns about `normal`)
            let n = normal.cross(&rel(p, a, b)).normalize();
            let base = (rel(p, a, i) + x0).dot(&n);
            let origin = Origin::CentreInside { t, a, b };
            row(base, m.transpose() * n, &[], l.sqrt(), origin)
        })
        .collect();
    for &o in others {
        let r = rel(p, i, o);
        let base = r.norm_squared() - 2.0 * x0.dot(&r);
        rows.push(row(
            base,
            -2.0 * m.transpose() * r,
            &[(o, -1.0), (i, 1.0)],
            l,
            Origin::CentreNearer { t, o },
        ));
    }
    rows
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::q;
    use crate::lp::proof_agrees;

    /// The exact rows of a certificate say what the LP's centre rows say,
    /// for a triangle and a convex quad (edges beyond the first three
    /// vertices included).
    #[test]
    fn centre_rows_rebuild_exactly() {
        let p = [
            [0.0, 0.0, 0.1],
            [1.0, 0.1, 0.0],
            [1.2, 0.9, 0.3],
            [0.1, 1.0, 0.4],
            [0.5, 0.4, 1.1],
            [0.3, -0.6, -0.5],
        ];
        let pq: Vec<[crate::geom::Q; 3]> = p.iter().map(|x| x.map(q)).collect();
        // the quad's fourth vertex on the plane of its first three
        let mut quad = p;
        quad[3] = [-0.2, 0.8, 0.39];
        let quad_q: Vec<[crate::geom::Q; 3]> = quad.iter().map(|x| x.map(q)).collect();
        for (pts, exact, verts) in [
            (&p, &pq, vec![0u32, 1, 2]),
            (&quad, &quad_q, vec![0u32, 1, 2, 3]),
        ] {
            let rows = centre_rows(pts, 7, &verts, &[4, 5]);
            assert_eq!(rows.len(), verts.len() + 2);
            for r in &rows {
                assert_eq!(r.family, Family::Sys3(7));
                assert!(proof_agrees(r, exact), "{r:?}");
            }
        }
    }
}
