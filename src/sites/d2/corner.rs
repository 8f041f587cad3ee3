//! Corner sites: at a convex corner v of the domain, between segments
//! (v, a) and (v, b) whose domain-side triangle in RT(w) is (a, v, b), one
//! site at that triangle's power centre o serves both segments' domain
//! sides. Its circle is orthogonal to the three vertices and to no other
//! closer (a triangle of RT(w)), so its power on each segment's line is
//! that of every site on the segment's radical line, and no site's is
//! lower there (docs/method.md section 4): each segment stays one edge
//! between o and its outer site. Its cell owns the corner, which the
//! layered 3D cavities need: a prism leaning off the walls then reaches
//! the two walls only from the one cell that owns their corner.

use super::{Def, Role, Sites, Track};
use crate::backend::Triangulation;
use crate::complex::Complex;
use crate::geom::{Dyadic, QPoint, Q};
use crate::FastMap;
use std::cmp::Ordering;

/// A site placed for a segment side: its role, track, fraction, and
/// whether relocation may move it.
pub(super) type Placed = (Role, Track, f64, bool);

/// How far from each segment's line a corner's power centre may lie, in
/// lengths of that segment: a centre nearer is a sliver cell, one farther a
/// cell reaching deep into the domain (a corner nearly flat).
const DEPTH: std::ops::RangeInclusive<f64> = 1e-3..=1.0;

/// A corner: its two segment sides (segment, domain on its left) and the
/// triangle of RT(w) whose power centre serves them.
pub(super) type Corner = ([(u32, bool); 2], [u32; 3]);

impl Sites {
    /// The convex corners of the domain that one site can serve: a vertex
    /// with exactly two segments, each with the domain on one side only and
    /// not anchored, whose domain-side triangles in RT(w) are one, its power
    /// centre at a `DEPTH` from both. A segment side serves one corner.
    pub(super) fn corners(
        &self,
        cx: &Complex,
        rt: &Triangulation,
        domain_side: &[[bool; 2]],
    ) -> Vec<Corner> {
        let mut at: Vec<Vec<u32>> = vec![vec![]; cx.points.len()];
        for (k, s) in cx.segments.iter().enumerate() {
            for v in s {
                at[*v as usize].push(k as u32);
            }
        }
        let mut taken = vec![false; cx.segments.len()];
        let mut out = vec![];
        for segs in &at {
            let &[k1, k2] = &segs[..] else {
                continue;
            };
            let side = |k: u32| -> Option<(bool, u32)> {
                let [i, j] = cx.segments[k as usize];
                let left = match domain_side[k as usize] {
                    [true, false] => true,
                    [false, true] => false,
                    _ => return None,
                };
                if taken[k as usize] || cx.anchor(k as usize).is_some() {
                    return None;
                }
                let t = if left {
                    rt.left_of(i, j)
                } else {
                    rt.left_of(j, i)
                }?;
                let (tl, tr) = self.dual_params(rt, i, j);
                let depth = if left { tl? } else { -tr? };
                DEPTH.contains(&depth).then_some((left, t))
            };
            let (Some((l1, t1)), Some((l2, t2))) = (side(k1), side(k2)) else {
                continue;
            };
            if t1 == t2 {
                taken[k1 as usize] = true;
                taken[k2 as usize] = true;
                out.push(([(k1, l1), (k2, l2)], rt.triangles[t1 as usize]));
            }
        }
        out
    }

    /// The power centre of triangle `tri` of input vertices, homogeneous
    /// ([X, Y, W, H], H > 0, as `homogeneous`): with u, v its edges from a
    /// and D = 2 u x v, the centre is a + (ru v_y - rv u_y, rv u_x - ru v_x)
    /// / D, ru = |u|^2 - w_b + w_a (rv likewise), its weight its power at a.
    pub(super) fn centre_homogeneous(&self, tri: [u32; 3]) -> [Dyadic; 4] {
        let d = Dyadic::of;
        let pt = |v: u32| self.points[v as usize].map(d);
        let wt = |v: u32| d(self.weights[v as usize]);
        let [a, b, c] = tri;
        let (p0, p1, p2) = (pt(a), pt(b), pt(c));
        let u = [&p1[0] - &p0[0], &p1[1] - &p0[1]];
        let v = [&p2[0] - &p0[0], &p2[1] - &p0[1]];
        let h = &(&(&u[0] * &v[1]) - &(&u[1] * &v[0])) * &Dyadic::int(2);
        let ru = &(&u[0].sqr() + &u[1].sqr()) - &(&wt(b) - &wt(a));
        let rv = &(&v[0].sqr() + &v[1].sqr()) - &(&wt(c) - &wt(a));
        let nx = &(&ru * &v[1]) - &(&rv * &u[1]);
        let ny = &(&rv * &u[0]) - &(&ru * &v[0]);
        let [h, nx, ny] = match h.sign() {
            Ordering::Less => [h, nx, ny].map(|x| &Dyadic::int(0) - &x),
            _ => [h, nx, ny],
        };
        let x = &(&p0[0] * &h) + &nx;
        let y = &(&p0[1] * &h) + &ny;
        let w = &(&nx.sqr() + &ny.sqr()) - &(&wt(a) * &h.sqr());
        [x, y, w, h]
    }

    /// The power centre of `tri` and its weight, as rationals.
    pub(super) fn centre_q(&self, tri: [u32; 3]) -> (QPoint, Q) {
        let [x, y, w, h] = self.centre_homogeneous(tri).map(|x| x.exact());
        let h2 = &h * &h;
        ([x / &h, y / &h], w / h2)
    }
}

/// The sites of each segment side, with corners: the first side of each
/// corner gets its site, the second none.
pub(super) fn with_corners(placed: Vec<[Placed; 2]>, corners: &[Corner]) -> Vec<[Placed; 1]> {
    let mut claim: FastMap<(u32, bool), Option<usize>> = FastMap::default();
    for (c, (segs, _)) in corners.iter().enumerate() {
        claim.insert(segs[0], Some(c));
        claim.insert(segs[1], None);
    }
    let mut out = Vec::with_capacity(2 * placed.len());
    for site in placed.into_iter().flatten() {
        let key = match site.0 {
            Role::Segment { seg, left } => (seg, left),
            _ => (u32::MAX, false),
        };
        match claim.get(&key) {
            None => out.push([site]),
            Some(Some(c)) => {
                let (segs, tri) = corners[*c];
                let kind = Def::Centre { tri };
                let track = Track {
                    ta: 0.0,
                    tb: 0.0,
                    kind,
                    dir: [0.0; 2],
                };
                out.push([(Role::Corner { segs }, track, 0.0, false)]);
            }
            Some(None) => {}
        }
    }
    out
}
