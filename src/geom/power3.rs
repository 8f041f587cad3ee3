//! Exact predicates on weighted points in 3D given as rationals (the 3D
//! sites), filtered: each is evaluated first in doubles against a bound
//! that covers the points' rounding and the arithmetic (a semi-static
//! filter), then in outward-rounded intervals around the rationals, and in
//! integers only where the interval holds 0.

use super::semistatic::{by_columns, column_max, diff, lifted, sign_beyond};
use super::{det3, det3_f, det4, det4_f, f, norm2, sub, Iv, Q};
use malachite_base::num::arithmetic::traits::{DivExact, Lcm, Sign};
use malachite_nz::integer::Integer;
use malachite_nz::natural::Natural;
use rayon::prelude::*;
use std::cmp::Ordering;
use std::sync::atomic::{AtomicUsize, Ordering::Relaxed};
use std::sync::OnceLock;

/// A point's doubles and their error bounds, in one cache line (the
/// filters read both for five random points per test).
#[derive(Clone, Copy)]
#[repr(align(64))]
struct Near {
    mid: [f64; 4],
    rad: [f64; 4],
}

/// Weighted points (p, w), exactly, with enclosures of (x, y, z, w).
pub struct Weighted3<'a> {
    p: &'a [[Q; 3]],
    w: &'a [Q],
    iv: Vec<[Iv; 4]>,
    /// The nearest doubles to (x, y, z, w), and how far the exact values
    /// may be from them (from the enclosures).
    near: Vec<Near>,
    /// Per point, made when an exact test first needs it: (p, 1) and
    /// (p, |p|^2 - w, 1), each scaled by a positive integer to integers
    /// (a determinant's sign in integers needs no gcd).
    rows: Vec<OnceLock<([Integer; 4], [Integer; 5])>>,
    /// Predicates the intervals could not decide.
    pub exact_evaluations: AtomicUsize,
}

/// The sign of a rational.
fn sign(x: &Q) -> Ordering {
    x.partial_cmp(&Q::from(0)).unwrap_or(Ordering::Equal)
}

impl<'a> Weighted3<'a> {
    pub fn new(p: &'a [[Q; 3]], w: &'a [Q]) -> Self {
        // (in parallel: rounding rationals is slow)
        let iv: Vec<[Iv; 4]> = p
            .par_iter()
            .zip(w)
            .map(|(p, w)| {
                [
                    Iv::of_q(&p[0]),
                    Iv::of_q(&p[1]),
                    Iv::of_q(&p[2]),
                    Iv::of_q(w),
                ]
            })
            .collect();
        let near = iv
            .par_iter()
            .zip(p.par_iter().zip(w))
            .map(|(i, (p, w))| {
                let mid = [f(&p[0]), f(&p[1]), f(&p[2]), f(w)];
                let rad = std::array::from_fn(|k| (i[k].hi - mid[k]).max(mid[k] - i[k].lo));
                Near { mid, rad }
            })
            .collect();
        Weighted3 {
            p,
            w,
            iv,
            near,
            rows: (0..p.len()).map(|_| OnceLock::new()).collect(),
            exact_evaluations: AtomicUsize::new(0),
        }
    }

    fn exact(&self) {
        self.exact_evaluations.fetch_add(1, Relaxed);
    }

    /// How many points.
    pub fn count(&self) -> usize {
        self.p.len()
    }

    /// Point x and its weight, exactly.
    pub fn point(&self, x: u32) -> (&[Q; 3], &Q) {
        (&self.p[x as usize], &self.w[x as usize])
    }

    /// Point x's integer rows (see `rows`).
    fn rows(&self, x: usize) -> &([Integer; 4], [Integer; 5]) {
        self.rows[x].get_or_init(|| {
            let p = &self.p[x];
            let lift = norm2(p) - &self.w[x];
            let scaled = |xs: &[&Q]| -> Vec<Integer> {
                let m = xs
                    .iter()
                    .fold(Natural::from(1u32), |m, v| m.lcm(v.denominator_ref()));
                let m = Q::from(m);
                xs.iter()
                    .map(|v| Integer::try_from(&(*v * &m)).expect("scaled to an integer"))
                    .chain([Integer::try_from(&m).expect("an integer")])
                    .collect()
            };
            let a = scaled(&[&p[0], &p[1], &p[2]]);
            let b = scaled(&[&p[0], &p[1], &p[2], &lift]);
            (
                std::array::from_fn(|k| a[k].clone()),
                std::array::from_fn(|k| b[k].clone()),
            )
        })
    }

    /// In intervals, when they decide it: Greater when d sees (a, b, c)
    /// counter-clockwise, the sign of det[b - a; c - a; d - a] (as
    /// `orient3` on doubles).
    pub fn orient_iv(&self, t: [u32; 4]) -> Option<Ordering> {
        self.orient_f64(t).or_else(|| self.orient_interval(t))
    }

    /// `orient_iv`'s second step alone: in intervals around the rationals.
    pub fn orient_interval(&self, t: [u32; 4]) -> Option<Ordering> {
        let [a, b, c, d] = t.map(|x| x as usize);
        let v = |x: usize| [0, 1, 2].map(|k| self.iv[x][k] - self.iv[a][k]);
        det3([v(b), v(c), v(d)]).sign()
    }

    /// Differences p_x - p_o in doubles, each with a bound on how far the
    /// exact difference may be: both points' rounding and the subtraction's.
    fn diff(&self, x: u32, o: u32) -> ([f64; 3], [f64; 3]) {
        let near = |v: u32| {
            let n = &self.near[v as usize];
            (&n.mid[..], &n.rad[..])
        };
        diff(near(x), near(o))
    }

    /// The semi-static filter of `orient_iv`: a determinant's change when
    /// its entries move by at most eta is at most perm(|a| + eta) -
    /// perm(|a|) (expand both products), bounded by columns
    /// (`by_columns`); its rounding, 64 eps of the permanent, is generous.
    pub fn orient_f64(&self, t: [u32; 4]) -> Option<Ordering> {
        let rows = [t[1], t[2], t[3]].map(|x| self.diff(x, t[0]));
        let det = det3_f(rows[0].0, rows[1].0, rows[2].0);
        let x = column_max(&rows.map(|r| r.0.map(f64::abs)));
        let y = column_max(&rows.map(|r| r.1));
        let (p0, p1) = by_columns(x, y, 6.0);
        sign_beyond(det, p0, p1, 64.0)
    }

    /// The semi-static filter of `power_iv`, as `orient_f64`; the lifted
    /// entry |d|^2 - (w_x - w_e) moves by at most sum (2 |d_k| + eta_k)
    /// eta_k, the weights' rounding and its own (4 eps of its magnitude).
    pub fn power_f64(&self, t: [u32; 4], e: u32) -> Option<Ordering> {
        let weight = |v: u32| (self.near[v as usize].mid[3], self.near[v as usize].rad[3]);
        // the entries, and per column the largest magnitude and error
        let (mut rows, mut x, mut y) = ([[0.0; 4]; 4], [0.0f64; 4], [0.0f64; 4]);
        for (i, &v) in t.iter().enumerate() {
            let (d, eta) = self.diff(v, e);
            let (z, mag, err) = lifted((d, eta), weight(v), weight(e));
            rows[i] = [d[0], d[1], d[2], z];
            for k in 0..3 {
                (x[k], y[k]) = (x[k].max(d[k].abs()), y[k].max(eta[k]));
            }
            (x[3], y[3]) = (x[3].max(mag), y[3].max(err));
        }
        let (p0, p1) = by_columns(x, y, 24.0);
        sign_beyond(det4_f(rows), p0, p1, 128.0).map(Ordering::reverse)
    }

    /// The same orientation in integers.
    pub fn orient_exact(&self, t: [u32; 4]) -> Ordering {
        if self.axis_flat(t) {
            return Ordering::Equal;
        }
        self.exact();
        // det[b - a; c - a; d - a] = -det[(p, 1) rows]
        let m = t.map(|x| self.rows(x as usize).0.to_vec());
        bareiss(m.to_vec()).reverse()
    }

    /// Whether four points are flat for a reason seen without arithmetic:
    /// all on one plane x, y or z = const, or three on one line parallel
    /// to an axis (the usual ties of boxes and prisms). The doubles are
    /// compared first: equal rationals round alike.
    pub fn axis_flat(&self, t: [u32; 4]) -> bool {
        let same = |x: u32, y: u32, k: usize| {
            let (x, y) = (x as usize, y as usize);
            self.near[x].mid[k] == self.near[y].mid[k] && self.p[x][k] == self.p[y][k]
        };
        let [a, b, c, d] = t;
        if (0..3).any(|k| [b, c, d].iter().all(|&x| same(a, x, k))) {
            return true;
        }
        let on_line = |x: u32, y: u32, z: u32| {
            (0..3).any(|k| {
                let (i, j) = ((k + 1) % 3, (k + 2) % 3);
                [y, z].iter().all(|&v| same(x, v, i) && same(x, v, j))
            })
        };
        on_line(a, b, c) || on_line(a, b, d) || on_line(a, c, d) || on_line(b, c, d)
    }

    /// In intervals, when they decide it: Greater when e conflicts with
    /// the positively oriented tetrahedron t, its lifted point strictly
    /// below the hyperplane through theirs (as
    /// `backend::points::F64Points3::power` on doubles); Equal when the
    /// five lie on one orthosphere.
    pub fn power_iv(&self, t: [u32; 4], e: u32) -> Option<Ordering> {
        self.power_f64(t, e).or_else(|| self.power_interval(t, e))
    }

    /// For p coplanar with the triangle (a, b, c): the sign of E, where p
    /// conflicts with the triangle's power circle iff E > 0 (see
    /// `pure3::conflict_in_plane`), in intervals; None when they cannot
    /// decide. With u = b - a, v = c - a, r = p - a and heights
    /// z_x = |x - a|^2 - w_x + w_a, E times the positive Gram determinant
    /// is (vv ur - uv vr) z_b + (uu vr - uv ur) z_c - (uu vv - uv^2) z_p.
    pub fn in_plane_interval(&self, [a, b, c]: [u32; 3], p: u32) -> Option<Ordering> {
        let ia = self.iv[a as usize];
        let rel = |x: u32| {
            let ix = self.iv[x as usize];
            let d = [0, 1, 2].map(|k| ix[k] - ia[k]);
            let z = d[0].sqr() + d[1].sqr() + d[2].sqr() - ix[3] + ia[3];
            (d, z)
        };
        let dot = |x: &[Iv; 3], y: &[Iv; 3]| x[0] * y[0] + x[1] * y[1] + x[2] * y[2];
        let ((u, zb), (v, zc), (r, zp)) = (rel(b), rel(c), rel(p));
        let (uu, uv, vv, ur, vr) = (
            u[0].sqr() + u[1].sqr() + u[2].sqr(),
            dot(&u, &v),
            v[0].sqr() + v[1].sqr() + v[2].sqr(),
            dot(&u, &r),
            dot(&v, &r),
        );
        let gram = uu * vv - uv.sqr();
        if gram.sign() != Some(Ordering::Greater) {
            return None;
        }
        ((vv * ur - uv * vr) * zb + (uu * vr - uv * ur) * zc - gram * zp).sign()
    }

    /// `power_iv`'s second step alone: in intervals around the rationals.
    pub fn power_interval(&self, t: [u32; 4], e: u32) -> Option<Ordering> {
        let ie = self.iv[e as usize];
        let rows = t.map(|x| {
            let ix = self.iv[x as usize];
            let d = [0, 1, 2].map(|k| ix[k] - ie[k]);
            let z = d[0].sqr() + d[1].sqr() + d[2].sqr() - (ix[3] - ie[3]);
            [d[0], d[1], d[2], z]
        });
        det4(rows).sign().map(Ordering::reverse)
    }

    /// The same power test in integers.
    pub fn power_exact(&self, t: [u32; 4], e: u32) -> Ordering {
        self.exact();
        // the 4x4 determinant of differences is the 5x5 one of
        // (p, |p|^2 - w, 1) rows
        let m: Vec<Vec<Integer>> = [t[0], t[1], t[2], t[3], e]
            .iter()
            .map(|&x| self.rows(x as usize).1.to_vec())
            .collect();
        bareiss(m).reverse()
    }

    /// Whether p_a lies strictly on a's side of the bisector of a and b,
    /// and p_b strictly on b's: pi(p_a; b) > pi(p_a; a) = -w_a, i.e.
    /// |p_a - p_b|^2 - w_b + w_a > 0, and the same with a and b swapped.
    pub fn apart(&self, a: u32, b: u32) -> [bool; 2] {
        let (a, b) = (a as usize, b as usize);
        let (ia, ib) = (self.iv[a], self.iv[b]);
        let d = [0, 1, 2].map(|k| ia[k] - ib[k]);
        let dd = d[0].sqr() + d[1].sqr() + d[2].sqr();
        let dw = ia[3] - ib[3];
        let fast = [(dd + dw).sign(), (dd - dw).sign()];
        if fast.iter().all(Option::is_some) {
            return fast.map(|s| s == Some(Ordering::Greater));
        }
        self.exact();
        let dd = norm2(&sub(&self.p[a], &self.p[b]));
        let dw = &self.w[a] - &self.w[b];
        [sign(&(&dd + &dw)), sign(&(&dd - &dw))].map(|s| s == Ordering::Greater)
    }

    /// An enclosure of pi(x; a) = |x - p_a|^2 - w_a for an exact double x.
    pub fn power_at(&self, a: u32, x: [f64; 3]) -> Iv {
        let ia = self.iv[a as usize];
        let d = [0, 1, 2].map(|k| Iv::of(x[k]) - ia[k]);
        d[0].sqr() + d[1].sqr() + d[2].sqr() - ia[3]
    }

    /// The same power exactly, for a rational x.
    pub fn power_at_q(&self, a: u32, x: &[Q; 3]) -> Q {
        norm2(&sub(x, &self.p[a as usize])) - &self.w[a as usize]
    }

    /// An enclosure of the orthocentre of tetrahedron t (the point of equal
    /// power to its four points); unbounded when t is nearly flat.
    pub fn orthocentre_iv(&self, t: [u32; 4]) -> [Iv; 3] {
        let [a, b, c, d] = t.map(|x| self.iv[x as usize]);
        // 2 y.(p_x - p_a) = |p_x - p_a|^2 - w_x + w_a, y = x - p_a
        let row = |x: [Iv; 4]| {
            let e = [0, 1, 2].map(|k| x[k] - a[k]);
            let r = e[0].sqr() + e[1].sqr() + e[2].sqr() - (x[3] - a[3]);
            (e.map(|v| v + v), r)
        };
        let rows = [row(b), row(c), row(d)];
        let m = rows.map(|r| r.0);
        let det = det3(m);
        std::array::from_fn(|k| {
            let col = std::array::from_fn(|i| {
                let mut r = m[i];
                r[k] = rows[i].1;
                r
            });
            a[k] + det3(col) / det
        })
    }

    /// The orthocentre of tetrahedron t, exactly (None when it is flat).
    /// From each point's integer row (p = P / M, |p|^2 - w = L / M): for x
    /// in b, c, d, 2 y.(M_a P_x - M_x P_a) = M_a L_x - M_x L_a, solved by
    /// Cramer's rule in integers (rationals cost a gcd at every step:
    /// measured 3x slower on TetGen's example's rough power vertices).
    pub fn orthocentre(&self, t: [u32; 4]) -> Option<[Q; 3]> {
        let [a, rest @ ..] = t.map(|x| &self.rows(x as usize).1);
        let rows: [([Integer; 3], Integer); 3] = rest.map(|x| {
            let e = std::array::from_fn(|k| Integer::from(2) * (&a[4] * &x[k] - &x[4] * &a[k]));
            (e, &a[4] * &x[3] - &x[4] * &a[3])
        });
        let det = |col: Option<usize>| {
            let m: [[&Integer; 3]; 3] = std::array::from_fn(|i| {
                std::array::from_fn(|c| {
                    if Some(c) == col {
                        &rows[i].1
                    } else {
                        &rows[i].0[c]
                    }
                })
            });
            let two = |p: &Integer, q: &Integer, r: &Integer, s: &Integer| p * q - r * s;
            m[0][0] * two(m[1][1], m[2][2], m[1][2], m[2][1])
                - m[0][1] * two(m[1][0], m[2][2], m[1][2], m[2][0])
                + m[0][2] * two(m[1][0], m[2][1], m[1][1], m[2][0])
        };
        let d = det(None);
        if d == 0 {
            return None;
        }
        Some(std::array::from_fn(|k| {
            Q::from_integers(det(Some(k)), d.clone())
        }))
    }

    /// A double near each coordinate of x (for output).
    pub fn round(x: &[Q; 3]) -> [f64; 3] {
        x.clone().map(|v| f(&v))
    }
}

/// The sign of a square integer matrix's determinant (Bareiss'
/// fraction-free elimination: every division is exact).
fn bareiss(mut m: Vec<Vec<Integer>>) -> Ordering {
    let n = m.len();
    let mut flip = false;
    let mut prev = Integer::from(1);
    for k in 0..n - 1 {
        if m[k][k] == 0 {
            let Some(r) = (k + 1..n).find(|&r| m[r][k] != 0) else {
                return Ordering::Equal;
            };
            m.swap(k, r);
            flip = !flip;
        }
        for i in k + 1..n {
            for j in k + 1..n {
                let v = &m[i][j] * &m[k][k] - &m[i][k] * &m[k][j];
                m[i][j] = v.div_exact(&prev);
            }
        }
        prev = m[k][k].clone();
    }
    let s = m[n - 1][n - 1].sign();
    if flip {
        s.reverse()
    } else {
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::{dot, per4_f64, q};
    use proptest::prelude::*;

    proptest! {
        /// The column bounds hold the permanents' (what `sign_beyond` needs:
        /// p1 - p0 and p1 no smaller).
        #[test]
        fn column_bounds_hold_the_permanents(
            a in prop::array::uniform4(prop::array::uniform4(0.0f64..1e3)),
            eta in prop::array::uniform4(prop::array::uniform4(0.0f64..1.0)),
        ) {
            let plus: [[f64; 4]; 4] = std::array::from_fn(|i| std::array::from_fn(|k| a[i][k] + eta[i][k]));
            let (q0, q1) = (per4_f64(a), per4_f64(plus));
            let (p0, p1) = by_columns(column_max(&a), column_max(&eta), 24.0);
            prop_assert!(p1 >= q1 * (1.0 - 1e-12));
            prop_assert!(p1 - p0 >= (q1 - q0) * (1.0 - 1e-9) - 1e-9 * q1);
        }
    }

    fn points(p: &[[f64; 4]]) -> (Vec<[Q; 3]>, Vec<Q>) {
        (
            p.iter().map(|x| [q(x[0]), q(x[1]), q(x[2])]).collect(),
            p.iter().map(|x| q(x[3])).collect(),
        )
    }

    /// The orthocentre has one power to the four points, exactly, on
    /// points whose rationals have unlike denominators; None when flat.
    #[test]
    fn the_orthocentre_has_equal_powers() {
        let mut next = crate::geom::uniform(17);
        for _ in 0..50 {
            let p: Vec<[Q; 3]> = (0..4)
                .map(|_| [0; 3].map(|_| q(next()) / Q::from(1 + (next() * 7.0) as u32)))
                .collect();
            let w: Vec<Q> = (0..4).map(|_| q(next() * 0.1) / Q::from(3)).collect();
            let s = Weighted3::new(&p, &w);
            let y = s.orthocentre([0, 1, 2, 3]).expect("not flat");
            let power = |x: usize| norm2(&sub(&y, &p[x])) - &w[x];
            assert!((1..4).all(|x| power(x) == power(0)));
        }
        let (p, w) = points(&[
            [0.0, 0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0, 0.3],
        ]);
        assert!(Weighted3::new(&p, &w).orthocentre([0, 1, 2, 3]).is_none());
    }

    #[test]
    fn exact_on_cospherical_and_filtered_elsewhere() {
        // the unit cube's corners: any five lie on one sphere
        let (p, w) = points(&[
            [0.0, 0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
            [1.0, 1.0, 1.0, 0.0],
            [1.0, 1.0, 1.0, 0.5],
            [0.2, 0.2, 0.2, 0.0],
            [0.0, 0.0, 0.5, 0.0],
        ]);
        let s = Weighted3::new(&p, &w);
        let orient = |t: [u32; 4]| s.orient_iv(t).unwrap_or_else(|| s.orient_exact(t));
        let power = |t: [u32; 4], e: u32| s.power_iv(t, e).unwrap_or_else(|| s.power_exact(t, e));
        let t = [0, 1, 2, 3];
        assert_eq!(orient(t), Ordering::Greater);
        assert_eq!(orient([0, 2, 1, 3]), Ordering::Less);
        assert_eq!(s.exact_evaluations.load(Relaxed), 0);
        assert_eq!(power(t, 4), Ordering::Equal);
        assert_eq!(s.exact_evaluations.load(Relaxed), 1);
        // a heavier copy of the far corner conflicts; a point inside does
        assert_eq!(power(t, 5), Ordering::Greater);
        assert_eq!(power(t, 6), Ordering::Greater);
        let c = s.orthocentre(t).unwrap();
        assert_eq!(c, [q(0.5), q(0.5), q(0.5)]);
        let iv = s.orthocentre_iv(t);
        assert!((0..3).all(|k| iv[k].lo <= 0.5 && 0.5 <= iv[k].hi));
        assert_eq!(s.apart(0, 1), [true, true]);
        // flat without arithmetic: three points on the line x = y = 0 ...
        assert!(s.axis_flat([0, 3, 7, 6]));
        // ... all four on the plane z = 0 (with a repeat), or neither
        assert!(s.axis_flat([0, 1, 2, 0]));
        assert!(!s.axis_flat(t));
        assert!(!s.axis_flat([0, 1, 2, 6]));
        assert_eq!(s.apart(4, 5), [false, true]);
    }

    #[test]
    fn the_double_filter_agrees_with_integers_near_ties() {
        // grid points (many ties) moved by rationals of 2^-40 to 2^-64,
        // often below the doubles' resolution: the filter must allow for
        // the rounding, and decide only what the integers confirm
        let mut u = crate::geom::uniform(5);
        let mut tiny = |k: i32| {
            let m = (u() * 2000.0) as i64 - 1000;
            Q::from(m) / Q::from(3) * q(2f64.powi(-k))
        };
        let mut u2 = crate::geom::uniform(6);
        let mut grid = |n: f64| (u2() * n).floor();
        let (mut p, mut w) = (vec![], vec![]);
        for i in 0..40 {
            let k = 40 + (i % 25);
            let base = [grid(3.0), grid(3.0), grid(3.0)];
            p.push(base.map(|b| q(b) + tiny(k)));
            w.push(match i % 3 {
                0 => Q::from(0),
                1 => q(grid(4.0) / 4.0),
                _ => q(grid(4.0) / 4.0) + tiny(k),
            });
        }
        let s = Weighted3::new(&p, &w);
        let mut pick = crate::geom::uniform(7);
        let mut next = || (pick() * 40.0) as u32;
        let (mut orients, mut powers) = (0, 0);
        for _ in 0..6000 {
            let t = [next(), next(), next(), next()];
            if let Some(o) = s.orient_f64(t) {
                assert_eq!(o, s.orient_exact(t), "{t:?}");
                orients += 1;
            }
            if s.orient_exact(t) != Ordering::Greater {
                continue;
            }
            let e = next();
            if let Some(o) = s.power_f64(t, e) {
                assert_eq!(o, s.power_exact(t, e), "{t:?} {e}");
                powers += 1;
            }
        }
        assert!(orients > 1000 && powers > 300, "{orients} {powers}");
    }

    #[test]
    fn in_plane_filter_agrees_with_rationals() {
        // points on the tilted plane x + 2y + 3z = 1 (thirds: not doubles),
        // some on a common circle, weights small
        let mut u = crate::geom::uniform(11);
        let mut next = |m: i64| (u() * m as f64) as i64;
        let third = Q::from(1) / Q::from(3);
        let (mut p, mut w) = (vec![], vec![]);
        for _ in 0..40 {
            let (x, y) = (Q::from(next(7) - 3), Q::from(next(7) - 3));
            let z = (Q::from(1) - &x - Q::from(2) * &y) * &third;
            p.push([x, y, z]);
            w.push(Q::from(next(3)) / Q::from(4));
        }
        let s = Weighted3::new(&p, &w);
        let exact = |[a, b, c]: [u32; 3], e: u32| {
            let rel = |x: u32| {
                let d = sub(&p[x as usize], &p[a as usize]);
                let z = norm2(&d) - &w[x as usize] + &w[a as usize];
                (d, z)
            };
            let ((u, zb), (v, zc), (r, zp)) = (rel(b), rel(c), rel(e));
            let (uu, uv, vv) = (norm2(&u), dot(&u, &v), norm2(&v));
            let (ur, vr) = (dot(&u, &r), dot(&v, &r));
            let gram = &uu * &vv - &uv * &uv;
            (gram != 0).then(|| {
                sign(&((&vv * &ur - &uv * &vr) * zb + (&uu * &vr - &uv * &ur) * zc - gram * zp))
            })
        };
        let (mut decided, mut ties) = (0, 0);
        for _ in 0..3000 {
            let f = [0; 3].map(|_| next(40) as u32);
            let e = next(40) as u32;
            let Some(want) = exact(f, e) else { continue };
            ties += usize::from(want == Ordering::Equal);
            if let Some(got) = s.in_plane_interval(f, e) {
                assert_eq!(got, want, "{f:?} {e}");
                decided += 1;
            }
        }
        assert!(
            decided > 1000 && ties > 10,
            "{decided} decided, {ties} ties"
        );
    }
}
