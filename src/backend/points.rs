//! Double weighted points with exact predicates by index: what Lawson
//! flips above the backends decide with, and the pure-Rust engine's input.

use super::FlipTests;
use crate::geom::{det3, det3_q, det4, det4_f64, det4_q, q, Iv, Q};
use std::cmp::Ordering;

/// Double points and weights.
pub(crate) struct F64Points<'a> {
    pub p: &'a [[f64; 2]],
    pub w: &'a [f64],
}

/// The power test exactly: the lifted determinant relative to d.
pub(crate) fn power_q(p: [&[Q; 2]; 4], w: [&Q; 4]) -> Ordering {
    let d = p[3];
    let row = |x: &[Q; 2], wx: &Q| {
        let dx = &x[0] - &d[0];
        let dy = &x[1] - &d[1];
        let z = &dx * &dx + &dy * &dy - wx + w[3];
        [dx, dy, z]
    };
    let r = [row(p[0], w[0]), row(p[1], w[1]), row(p[2], w[2])];
    sign_q(&det3_q([
        [&r[0][0], &r[0][1], &r[0][2]],
        [&r[1][0], &r[1][1], &r[1][2]],
        [&r[2][0], &r[2][1], &r[2][2]],
    ]))
}

pub(crate) fn sign_q(x: &Q) -> Ordering {
    x.partial_cmp(&Q::from(0)).expect("rationals are ordered")
}

impl FlipTests for F64Points<'_> {
    fn orient(&self, a: u32, b: u32, c: u32) -> Ordering {
        crate::geom::orient(self.p[a as usize], self.p[b as usize], self.p[c as usize])
    }

    fn power(&self, a: u32, b: u32, c: u32, d: u32) -> Ordering {
        let pd = self.p[d as usize];
        let wd = self.w[d as usize];
        // Semi-static filter: the determinant in doubles against a bound on
        // its rounding error (each entry within 5 eps of its magnitude, the
        // products and sums adding a few more: 64 eps of the permanent is
        // generous); then intervals; then rationals.
        let fast = |x: u32| {
            let (px, wx) = (self.p[x as usize], self.w[x as usize]);
            let (dx, dy) = (px[0] - pd[0], px[1] - pd[1]);
            let sq = dx * dx + dy * dy;
            let wz = wx - wd;
            (dx, dy, sq - wz, sq + wz.abs())
        };
        let (ax, ay, az, am) = fast(a);
        let (bx, by, bz, bm) = fast(b);
        let (cx, cy, cz, cm) = fast(c);
        let det = ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx);
        let perm = ax.abs() * (by.abs() * cm + bm * cy.abs())
            + ay.abs() * (bx.abs() * cm + bm * cx.abs())
            + am * (bx.abs() * cy.abs() + by.abs() * cx.abs());
        let bound = 64.0 * f64::EPSILON * perm;
        if det > bound {
            return Ordering::Greater;
        }
        if det < -bound {
            return Ordering::Less;
        }
        let row = |x: u32| {
            let (px, wx) = (self.p[x as usize], self.w[x as usize]);
            let dx = Iv::of(px[0]) - Iv::of(pd[0]);
            let dy = Iv::of(px[1]) - Iv::of(pd[1]);
            [dx, dy, dx.sqr() + dy.sqr() - (Iv::of(wx) - Iv::of(wd))]
        };
        if let Some(s) = det3([row(a), row(b), row(c)]).sign() {
            return s;
        }
        let pt = [a, b, c, d].map(|x| self.p[x as usize].map(q));
        let wt = [a, b, c, d].map(|x| q(self.w[x as usize]));
        power_q(pt.each_ref(), wt.each_ref())
    }
}

/// Double points in 3D and weights. (So far only the tests of the 3D
/// backends use them; the 3D pipeline stages are next, issue 6.)
#[allow(dead_code)]
pub(crate) struct F64Points3<'a> {
    pub p: &'a [[f64; 3]],
    pub w: &'a [f64],
}

#[allow(dead_code)]
impl F64Points3<'_> {
    /// Greater when d sees (a, b, c) counter-clockwise (`exact::orient3`).
    pub fn orient(&self, a: u32, b: u32, c: u32, d: u32) -> Ordering {
        let p = |x: u32| self.p[x as usize];
        crate::geom::orient3(p(a), p(b), p(c), p(d))
    }

    /// Greater when e conflicts with the positively oriented tetrahedron
    /// abcd: its lifted point lies strictly below the hyperplane through
    /// theirs (inside their orthosphere). The sign of the lifted 4x4
    /// determinant relative to e, negated: in intervals, then rationals.
    pub fn power(&self, t: [u32; 4], e: u32) -> Ordering {
        let (pe, we) = (self.p[e as usize], self.w[e as usize]);
        // Semi-static filter, as in 2D: the determinant in doubles against
        // a bound on its rounding error (each entry within 6 eps of its
        // magnitude, products of four and 24 terms adding some more: 128
        // eps of the permanent is generous); then intervals; then rationals.
        let fast = t.map(|x| {
            let (px, wx) = (self.p[x as usize], self.w[x as usize]);
            let d = [0, 1, 2].map(|k| px[k] - pe[k]);
            let sq = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
            let wz = wx - we;
            (
                [d[0], d[1], d[2], sq - wz],
                [d[0].abs(), d[1].abs(), d[2].abs(), sq + wz.abs()],
            )
        });
        let (det, perm) = det4_f64(fast.map(|r| r.0), fast.map(|r| r.1));
        let bound = 128.0 * f64::EPSILON * perm;
        if det > bound {
            return Ordering::Less;
        }
        if det < -bound {
            return Ordering::Greater;
        }
        let rows_iv = t.map(|x| {
            let (px, wx) = (self.p[x as usize], self.w[x as usize]);
            let d = [0, 1, 2].map(|k| Iv::of(px[k]) - Iv::of(pe[k]));
            let z = d[0].sqr() + d[1].sqr() + d[2].sqr() - (Iv::of(wx) - Iv::of(we));
            [d[0], d[1], d[2], z]
        });
        if let Some(s) = det4(rows_iv).sign() {
            return s.reverse();
        }
        let qe = pe.map(q);
        let rows_q = t.map(|x| {
            let (px, wx) = (self.p[x as usize], self.w[x as usize]);
            let d = [0, 1, 2].map(|k| q(px[k]) - &qe[k]);
            let z = &d[0] * &d[0] + &d[1] * &d[1] + &d[2] * &d[2] - q(wx) + q(we);
            [d[0].clone(), d[1].clone(), d[2].clone(), z]
        });
        sign_q(&det4_q(&rows_q)).reverse()
    }
}
