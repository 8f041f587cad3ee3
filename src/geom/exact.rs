//! Exact arithmetic and predicates. Every geometric decision goes through
//! here: doubles are converted exactly to rationals (or fed to Shewchuk's
//! adaptive predicates); nothing else in the crate looks at a raw sign.

use malachite_base::num::arithmetic::traits::{Abs, Sign};
use malachite_q::Rational;
use std::cmp::Ordering;

/// An exact rational number (malachite: subquadratic gcd, which dominates
/// the cost of exact constructions).
pub type Q = Rational;
/// An exact point.
pub type QPoint = [Q; 2];

/// The exact value of a finite double.
pub fn q(x: f64) -> Q {
    Rational::try_from(x).expect("finite coordinates are validated before any geometry")
}

/// The exact value of a double point.
pub fn qp(p: [f64; 2]) -> QPoint {
    [q(p[0]), q(p[1])]
}

/// Nearest double (ties to even); out of range gives an infinity.
pub fn f(x: &Q) -> f64 {
    use malachite_base::num::conversion::traits::RoundingFrom;
    if let Some(v) = small_quotient(x) {
        return v;
    }
    f64::rounding_from(x, malachite_base::rounding_modes::RoundingMode::Nearest).0
}

/// `f` without big-number arithmetic where numerator and denominator are
/// both doubles exactly: IEEE division then rounds the quotient once, to
/// nearest with ties to even, as `f` does.
fn small_quotient(x: &Q) -> Option<f64> {
    const EXACT: u64 = 1 << 53;
    let n = u64::try_from(x.numerator_ref()).ok()?;
    let d = u64::try_from(x.denominator_ref()).ok()?;
    if n > EXACT || !(d <= EXACT || d.is_power_of_two()) {
        return None;
    }
    let v = n as f64 / d as f64;
    Some(if x.sign() == Ordering::Less { -v } else { v })
}

/// Whether x > 0.
pub fn is_pos(x: &Q) -> bool {
    x.sign() == Ordering::Greater
}

pub fn abs(x: &Q) -> Q {
    x.abs()
}

pub fn sub<const N: usize>(a: &[Q; N], b: &[Q; N]) -> [Q; N] {
    std::array::from_fn(|k| &a[k] - &b[k])
}

pub fn dot<const N: usize>(a: &[Q; N], b: &[Q; N]) -> Q {
    (0..N).map(|k| &a[k] * &b[k]).sum()
}

pub fn norm2<const N: usize>(a: &[Q; N]) -> Q {
    dot(a, a)
}

pub fn cross(a: &[Q; 3], b: &[Q; 3]) -> [Q; 3] {
    std::array::from_fn(|k| {
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        &a[i] * &b[j] - &a[j] * &b[i]
    })
}

/// a + t d.
pub fn along<const N: usize>(a: &[Q; N], t: &Q, d: &[Q; N]) -> [Q; N] {
    std::array::from_fn(|k| &a[k] + t * &d[k])
}

/// Whether x lies strictly nearer, in power, to weighted point (a, wa) than
/// to (b, wb): |x - a|^2 - wa < |x - b|^2 - wb, exactly (as 2 x.(b - a) <
/// |b|^2 - |a|^2 - wb + wa, one product per coordinate).
pub fn power_nearer(x: &[Q; 3], (a, wa): (&[Q; 3], &Q), (b, wb): (&[Q; 3], &Q)) -> bool {
    let lhs = Q::from(2) * dot(x, &sub(b, a));
    lhs < norm2(b) - norm2(a) - wb + wa
}

/// Exact orientation of double points (Shewchuk's adaptive predicate).
pub fn orient(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> Ordering {
    let d = robust::orient2d(
        robust::Coord { x: a[0], y: a[1] },
        robust::Coord { x: b[0], y: b[1] },
        robust::Coord { x: c[0], y: c[1] },
    );
    d.partial_cmp(&0.0).unwrap_or(Ordering::Equal)
}

/// Exact orientation of four double points: Greater when d sees (a, b, c)
/// counter-clockwise, the sign of det[b - a; c - a; d - a] (CGAL's
/// orientation; Shewchuk's orient3d, which decides it, has the other sign).
pub fn orient3(a: [f64; 3], b: [f64; 3], c: [f64; 3], d: [f64; 3]) -> Ordering {
    let co = |p: [f64; 3]| robust::Coord3D {
        x: p[0],
        y: p[1],
        z: p[2],
    };
    let s = robust::orient3d(co(a), co(b), co(c), co(d));
    0.0.partial_cmp(&s).unwrap_or(Ordering::Equal)
}

/// Whether the closed segments ab and cd share a point (exactly).
pub fn segments_meet(a: [f64; 2], b: [f64; 2], c: [f64; 2], d: [f64; 2]) -> bool {
    let o = [
        orient(a, b, c),
        orient(a, b, d),
        orient(c, d, a),
        orient(c, d, b),
    ];
    let touch = [(a, b, c), (a, b, d), (c, d, a), (c, d, b)];
    if (0..4).any(|k| o[k] == Ordering::Equal && in_box(touch[k].0, touch[k].1, touch[k].2)) {
        return true;
    }
    !o.contains(&Ordering::Equal) && o[0] != o[1] && o[2] != o[3]
}

/// Whether p lies in the closed axis-aligned box of segment ab.
pub fn in_box(a: [f64; 2], b: [f64; 2], p: [f64; 2]) -> bool {
    (0..2).all(|k| p[k] >= a[k].min(b[k]) && p[k] <= a[k].max(b[k]))
}

/// Whether p lies in the closed diametral disc of segment ab: (a-p).(b-p) <= 0.
pub fn in_diametral_disc(a: [f64; 2], b: [f64; 2], p: [f64; 2]) -> bool {
    let d = |u: [f64; 2], k: usize| Iv::of(u[k]) - Iv::of(p[k]);
    let v = d(a, 0) * d(b, 0) + d(a, 1) * d(b, 1);
    match v.sign() {
        Some(o) => o != Ordering::Greater,
        None => {
            let (a, b, p) = (qp(a), qp(b), qp(p));
            !is_pos(&dot(&sub(&a, &p), &sub(&b, &p)))
        }
    }
}

/// A closed interval that holds an exact value: every operation rounds
/// outwards by one ulp, so the exact result of the same expression on the
/// enclosed values stays inside. Filters predicates before exact fallbacks.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Iv {
    pub lo: f64,
    pub hi: f64,
}

impl Iv {
    /// The exact double x.
    pub fn of(x: f64) -> Iv {
        Iv { lo: x, hi: x }
    }

    /// An enclosure of a rational: its nearest double, widened by an ulp
    /// each way.
    pub fn of_q(x: &Q) -> Iv {
        let m = f(x);
        Iv::out(m.next_down(), m.next_up())
    }

    fn out(lo: f64, hi: f64) -> Iv {
        if lo.is_nan() || hi.is_nan() {
            return Iv {
                lo: f64::NEG_INFINITY,
                hi: f64::INFINITY,
            };
        }
        Iv {
            lo: lo.next_down(),
            hi: hi.next_up(),
        }
    }

    fn times(self, o: Iv) -> Iv {
        let p = [
            self.lo * o.lo,
            self.lo * o.hi,
            self.hi * o.lo,
            self.hi * o.hi,
        ];
        if p.iter().any(|x| x.is_nan()) {
            return Iv::out(f64::NAN, f64::NAN);
        }
        Iv::out(
            p.iter().copied().fold(f64::INFINITY, f64::min),
            p.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        )
    }

    pub fn sqr(self) -> Iv {
        let (a, b) = (self.lo.abs(), self.hi.abs());
        let hi = a.max(b);
        let lo = if self.lo <= 0.0 && self.hi >= 0.0 {
            0.0
        } else {
            a.min(b)
        };
        let r = Iv::out(lo * lo, hi * hi);
        Iv {
            lo: r.lo.max(0.0),
            hi: r.hi,
        }
    }

    fn over(self, o: Iv) -> Iv {
        if o.lo <= 0.0 && o.hi >= 0.0 {
            return Iv::out(f64::NAN, f64::NAN);
        }
        let q = [
            self.lo / o.lo,
            self.lo / o.hi,
            self.hi / o.lo,
            self.hi / o.hi,
        ];
        if q.iter().any(|x| x.is_nan()) {
            return Iv::out(f64::NAN, f64::NAN);
        }
        Iv::out(
            q.iter().copied().fold(f64::INFINITY, f64::min),
            q.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        )
    }

    /// The sign of every value inside, or None when the interval holds 0.
    pub fn sign(self) -> Option<Ordering> {
        if self.lo > 0.0 {
            Some(Ordering::Greater)
        } else if self.hi < 0.0 {
            Some(Ordering::Less)
        } else {
            None
        }
    }

    /// A double inside (the midpoint).
    pub fn mid(self) -> f64 {
        let m = 0.5 * self.lo + 0.5 * self.hi;
        if m.is_finite() {
            m
        } else {
            self.lo.clamp(f64::MIN, f64::MAX)
        }
    }
}

impl std::ops::Add for Iv {
    type Output = Iv;
    fn add(self, o: Iv) -> Iv {
        Iv::out(self.lo + o.lo, self.hi + o.hi)
    }
}

impl std::ops::Sub for Iv {
    type Output = Iv;
    fn sub(self, o: Iv) -> Iv {
        Iv::out(self.lo - o.hi, self.hi - o.lo)
    }
}

impl std::ops::Mul for Iv {
    type Output = Iv;
    fn mul(self, o: Iv) -> Iv {
        self.times(o)
    }
}

impl std::ops::Div for Iv {
    type Output = Iv;
    fn div(self, o: Iv) -> Iv {
        self.over(o)
    }
}

impl std::ops::Neg for Iv {
    type Output = Iv;
    fn neg(self) -> Iv {
        Iv {
            lo: -self.hi,
            hi: -self.lo,
        }
    }
}

/// The arithmetic a filter evaluates a predicate in (intervals, or doubles
/// with running error bounds): each predicate's expression is written once,
/// generic over it, and evaluated in each filter in turn.
pub trait Filter:
    Copy + std::ops::Add<Output = Self> + std::ops::Sub<Output = Self> + std::ops::Mul<Output = Self>
{
    /// The exact double x.
    fn of(x: f64) -> Self;
    fn sqr(self) -> Self;
    /// The sign of every value the result stands for, or None.
    fn sign(self) -> Option<Ordering>;
}

impl Filter for Iv {
    fn of(x: f64) -> Iv {
        Iv::of(x)
    }
    fn sqr(self) -> Iv {
        Iv::sqr(self)
    }
    fn sign(self) -> Option<Ordering> {
        Iv::sign(self)
    }
}

/// 3x3 determinant of filtered rows.
pub fn det3<T: Filter>(r: [[T; 3]; 3]) -> T {
    let m = |a: T, b: T, c: T, d: T| a * b - c * d;
    r[0][0] * (m(r[1][1], r[2][2], r[1][2], r[2][1]))
        - r[0][1] * (m(r[1][0], r[2][2], r[1][2], r[2][0]))
        + r[0][2] * (m(r[1][0], r[2][1], r[1][1], r[2][0]))
}

/// The same determinant exactly.
pub fn det3_q(r: [[&Q; 3]; 3]) -> Q {
    let m = |a: &Q, b: &Q, c: &Q, d: &Q| a * b - c * d;
    r[0][0] * m(r[1][1], r[2][2], r[1][2], r[2][1])
        - r[0][1] * m(r[1][0], r[2][2], r[1][2], r[2][0])
        + r[0][2] * m(r[1][0], r[2][1], r[1][1], r[2][0])
}

/// The rows other than `skip` of a 4x4 matrix, in order.
pub(crate) const OTHER_ROWS: [[usize; 3]; 4] = [[1, 2, 3], [0, 2, 3], [0, 1, 3], [0, 1, 2]];

/// 4x4 determinant of filtered rows (expanded along the last column).
pub fn det4<T: Filter>(r: [[T; 4]; 4]) -> T {
    let minor = |skip: usize| det3(OTHER_ROWS[skip].map(|i| [r[i][0], r[i][1], r[i][2]]));
    r[1][3] * minor(1) - r[0][3] * minor(0) - r[2][3] * minor(2) + r[3][3] * minor(3)
}

/// A 4x4 determinant in doubles, expanded as `geom::det4`, and the same
/// expansion of the magnitudes `m` with every sign + (its permanent).
pub(crate) fn det4_f64(r: [[f64; 4]; 4], m: [[f64; 4]; 4]) -> (f64, f64) {
    (det4_f(r), per4_f64(m))
}

/// A 4x4 determinant in doubles, expanded as `geom::det4`.
pub(crate) fn det4_f(r: [[f64; 4]; 4]) -> f64 {
    let three =
        |x: &[[f64; 4]; 4], skip: usize| OTHER_ROWS[skip].map(|i| [x[i][0], x[i][1], x[i][2]]);
    let det3 = |a: [[f64; 3]; 3]| super::det3_f(a[0], a[1], a[2]);
    r[1][3] * det3(three(&r, 1)) - r[0][3] * det3(three(&r, 0)) - r[2][3] * det3(three(&r, 2))
        + r[3][3] * det3(three(&r, 3))
}

/// The permanent of a 3x3 matrix of magnitudes, in doubles.
pub(crate) fn per3_f64(a: [[f64; 3]; 3]) -> f64 {
    a[0][0] * (a[1][1] * a[2][2] + a[1][2] * a[2][1])
        + a[0][1] * (a[1][0] * a[2][2] + a[1][2] * a[2][0])
        + a[0][2] * (a[1][0] * a[2][1] + a[1][1] * a[2][0])
}

/// The permanent of a 4x4 matrix of magnitudes, in doubles.
pub(crate) fn per4_f64(m: [[f64; 4]; 4]) -> f64 {
    (0..4)
        .map(|i| m[i][3] * per3_f64(OTHER_ROWS[i].map(|r| [m[r][0], m[r][1], m[r][2]])))
        .sum()
}

/// The same determinant exactly.
pub fn det4_q(r: &[[Q; 4]; 4]) -> Q {
    let minor = |skip: usize| {
        let m: Vec<[&Q; 3]> = (0..4)
            .filter(|&i| i != skip)
            .map(|i| [&r[i][0], &r[i][1], &r[i][2]])
            .collect();
        det3_q([m[0], m[1], m[2]])
    };
    &r[1][3] * minor(1) - &r[0][3] * minor(0) - &r[2][3] * minor(2) + &r[3][3] * minor(3)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn by_malachite(x: &Q) -> f64 {
        use malachite_base::num::conversion::traits::RoundingFrom;
        f64::rounding_from(x, malachite_base::rounding_modes::RoundingMode::Nearest).0
    }

    proptest! {
        /// The quotient of two doubles rounds as the rational does, ties
        /// to even included (odd numerators over powers of two beyond the
        /// mantissa make ties).
        #[test]
        fn small_quotients_round_to_nearest(
            n in 0u64..(1 << 54),
            d in 1u64..(1 << 54),
            k in 0u32..64,
            neg in any::<bool>(),
        ) {
            for den in [d, 1u64 << k, (d >> 10).max(1)] {
                let x = Q::from_integers(n.into(), den.into());
                let x = if neg { -x } else { x };
                let expected = by_malachite(&x);
                prop_assert_eq!(f(&x).to_bits(), expected.to_bits(), "{}/{}", n, den);
                if let Some(v) = small_quotient(&x) {
                    prop_assert_eq!(v.to_bits(), expected.to_bits());
                }
            }
        }
    }

    #[test]
    fn intervals_hold_the_exact_value() {
        let third = Iv::of(1.0) / Iv::of(3.0);
        let exact_third = Q::from(1) / Q::from(3);
        assert!(q(third.lo) < exact_third && q(third.hi) > exact_third);
        // the exact sum of the three doubles is inside
        let x = Iv::of(0.1) + Iv::of(0.2) - Iv::of(0.3);
        let exact = q(0.1) + q(0.2) - q(0.3);
        assert!(q(x.lo) <= exact && exact <= q(x.hi));
        assert_eq!(
            (Iv::of(1e300) * Iv::of(1e300)).sign(),
            Some(Ordering::Greater)
        );
        assert_eq!(Iv::of(-2.0).sqr().lo, 4.0f64.next_down());
        assert_eq!((Iv::of(1.0) - Iv::of(1.0)).sign(), None);
        let r = [
            [Iv::of(1.0), Iv::of(2.0), Iv::of(3.0)],
            [Iv::of(4.0), Iv::of(5.0), Iv::of(6.0)],
            [Iv::of(7.0), Iv::of(8.0), Iv::of(10.0)],
        ];
        assert_eq!(det3(r).sign(), Some(Ordering::Less)); // det = -3
    }

    #[test]
    fn doubles_convert_exactly() {
        assert_ne!(q(0.1) * Q::from(3), q(0.3));
        assert_eq!(q(0.5) * Q::from(2), Q::from(1));
    }

    #[test]
    fn orientation_is_exact_near_degeneracy() {
        let a = [0.0, 0.0];
        let b = [1.0, 1.0];
        let c = [0.5, 0.5];
        assert_eq!(orient(a, b, c), Ordering::Equal);
        let c2 = [0.5, f64::from_bits(0.5f64.to_bits() + 1)];
        assert_eq!(orient(a, b, c2), Ordering::Greater);
    }

    #[test]
    fn diametral_disc_is_closed() {
        assert!(in_diametral_disc([-1.0, 0.0], [1.0, 0.0], [0.0, 1.0]));
        assert!(!in_diametral_disc(
            [-1.0, 0.0],
            [1.0, 0.0],
            [0.0, 1.0 + 1e-15]
        ));
    }
}
