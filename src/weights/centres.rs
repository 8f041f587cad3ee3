//! Each face's exact centre on its dual (the radical point of a segment,
//! the power centre in a triangle's or polygon's plane), made once for
//! the final weights: system 3's check, the sites' duals and the mesh's
//! repairs all read it (a rational construction per face, the larger part
//! of both stages on lattices of boxes).

use super::face::{fan, sorted3, Face};
use crate::backend::Adjacency;
use crate::complex::Complex3;
use crate::geom::{along, dot, drop_axis, is_pos, norm2, plane_axis, q, sub, Iv, Q};
use std::sync::OnceLock;

/// Whether a quantity is positive: its enclosure, else exactly.
fn positive(iv: Iv, exact: impl FnOnce() -> Q) -> bool {
    iv.sign()
        .map_or_else(|| is_pos(&exact()), |s| s == std::cmp::Ordering::Greater)
}

/// A face's centre and its power to the face's vertices.
pub type Centre = ([Q; 3], Q);

/// The faces' centres under one set of weights, each made when first read.
#[derive(Debug, Clone, Default)]
pub struct Centres(Vec<OnceLock<Option<Centre>>>);

impl Centres {
    /// An empty cache for `n` faces.
    pub fn new(n: usize) -> Centres {
        Centres((0..n).map(|_| OnceLock::new()).collect())
    }

    /// Face `fi`'s centre under weights `w` (those the cache was made for).
    pub fn of<'a>(
        &'a self,
        cx: &Complex3,
        w: &[Q],
        faces: &[Face],
        fi: usize,
    ) -> Option<&'a Centre> {
        self.0[fi]
            .get_or_init(|| face_centre(cx, w, &faces[fi].vertices))
            .as_ref()
    }
}

/// The exact point of a face of dimension 1 or 2 (its vertices) on its
/// dual (the radical point on a segment; the power centre in a triangle's
/// or polygon's plane), and its power to the face's vertices.
pub fn face_centre(cx: &Complex3, w: &[Q], vs: &[u32]) -> Option<Centre> {
    let p = |v: u32| cx.points[v as usize].map(q);
    let (pi, wi) = (p(vs[0]), w[vs[0] as usize].clone());
    let d = |v: u32| sub(&p(v), &pi);
    // c - p_i = alpha u + beta v with 2 (c - p_i).u = |u|^2 + w_i - w_j ...
    let half = |v: u32, u: &[Q; 3]| (norm2(u) + &wi - &w[v as usize]) / Q::from(2);
    let x: [Q; 3] = match vs.len() {
        2 => {
            let u = d(vs[1]);
            let lambda = half(vs[1], &u) / norm2(&u);
            u.map(|c| c * &lambda)
        }
        3.. => {
            let (u, v) = (d(vs[1]), d(vs[2]));
            let (uu, uv, vv) = (norm2(&u), dot(&u, &v), norm2(&v));
            let det = &uu * &vv - &uv * &uv;
            if det == 0 {
                return None;
            }
            let (r1, r2) = (half(vs[1], &u), half(vs[2], &v));
            let alpha = (&vv * &r1 - &uv * &r2) / &det;
            let beta = (&uu * &r2 - &uv * &r1) / &det;
            along(
                &along(&[Q::from(0), Q::from(0), Q::from(0)], &alpha, &u),
                &beta,
                &v,
            )
        }
        _ => return None,
    };
    let power = norm2(&x) - &wi;
    Some((std::array::from_fn(|k| &pi[k] + &x[k]), power))
}

/// Faces of dimension 1 or 2 whose dual they do not cross, exactly: the
/// centre must lie strictly inside the face and have a smaller power to
/// the face's vertices than to every vertex of RT next to the face (those
/// across its triangles; around a segment, its link).
pub fn sys3_failures(
    cx: &Complex3,
    faces: &[Face],
    (w, centres): (&[Q], &Centres),
    Adjacency { tris, links }: &Adjacency,
) -> Vec<u32> {
    let p = |v: u32| cx.points[v as usize].map(q);
    let crosses = |fi: usize, face: &Face| -> bool {
        let Some((c, power)) = centres.of(cx, w, faces, fi) else {
            return false;
        };
        let vs = &face.vertices;
        let (ci, power_i) = (c.each_ref().map(Iv::of_q), Iv::of_q(power));
        // pi(c; m) - pi(c; face) > 0, in intervals unless they hold 0
        let beyond = |m: usize| {
            let pm = cx.points[m];
            let d = (0..3).fold(Iv::of(0.0), |s, k| s + (ci[k] - Iv::of(pm[k])).sqr());
            positive(d - Iv::of_q(&w[m]) - power_i, || {
                let pm = p(m as u32);
                let d: Q = (0..3).map(|k| (&c[k] - &pm[k]) * (&c[k] - &pm[k])).sum();
                d - &w[m] - power
            })
        };
        let near: Vec<u32> = if vs.len() == 2 {
            let pi = p(vs[0]);
            let u: [Q; 3] = {
                let pj = p(vs[1]);
                [0, 1, 2].map(|k| &pj[k] - &pi[k])
            };
            let t: Q = (0..3).map(|k| (&c[k] - &pi[k]) * &u[k]).sum();
            let uu: Q = (0..3).map(|k| &u[k] * &u[k]).sum();
            if !(is_pos(&t) && is_pos(&(uu - t))) {
                return false;
            }
            links
                .get(&[vs[0].min(vs[1]), vs[0].max(vs[1])])
                .cloned()
                .unwrap_or_default()
        } else {
            let axis = plane_axis(
                cx.points[vs[0] as usize],
                cx.points[vs[1] as usize],
                cx.points[vs[2] as usize],
            )
            .expect("faces span a plane");
            // c strictly inside the polygon (in its plane, projected along
            // `axis`): on the side of every edge its turn is
            let flat = |v: u32| drop_axis(axis, cx.points[v as usize]).map(q);
            let side = |a: &[Q; 2], b: &[Q; 2], x: &[Q; 2]| {
                (&b[0] - &a[0]) * (&x[1] - &a[1]) - (&b[1] - &a[1]) * (&x[0] - &a[0])
            };
            let flat_i = |v: u32| drop_axis(axis, cx.points[v as usize]).map(Iv::of);
            let side_i = |a: [Iv; 2], b: [Iv; 2], x: [Iv; 2]| {
                (b[0] - a[0]) * (x[1] - a[1]) - (b[1] - a[1]) * (x[0] - a[0])
            };
            let turn_i = side_i(flat_i(vs[0]), flat_i(vs[1]), flat_i(vs[2]));
            let cfi = [1, 2].map(|k| ci[(axis + k) % 3]);
            let m = vs.len();
            let inside = (0..m).all(|k| {
                let (a, b) = (vs[k], vs[(k + 1) % m]);
                positive(side_i(flat_i(a), flat_i(b), cfi) * turn_i, || {
                    let cf = [1, 2].map(|k| c[(axis + k) % 3].clone());
                    side(&flat(a), &flat(b), &cf) * side(&flat(vs[0]), &flat(vs[1]), &flat(vs[2]))
                })
            });
            if !inside {
                return false;
            }
            let fan_tris = if m == 3 {
                vec![sorted3(vs)]
            } else {
                fan(&face.vertices, &tris)
            };
            fan_tris
                .iter()
                .flat_map(|t| tris.get(t).cloned().unwrap_or_default())
                .filter(|a| !vs.contains(a))
                .collect()
        };
        near.iter().all(|&m| beyond(m as usize))
    };
    // (in parallel: exact and independent per face)
    use rayon::prelude::*;
    faces
        .par_iter()
        .enumerate()
        .filter(|&(i, f)| f.dim() > 0 && !f.cut && !crosses(i, f))
        .map(|(i, _)| i as u32)
        .collect()
}
