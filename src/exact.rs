//! Exact arithmetic and predicates. Every geometric decision goes through
//! here: doubles are converted exactly to rationals (or fed to Shewchuk's
//! adaptive predicates); nothing else in the crate looks at a raw sign.

use malachite_base::num::arithmetic::traits::{Abs, Sign};
use malachite_base::num::basic::traits::{One, Zero};
use malachite_base::num::conversion::traits::RoundingFrom;
use malachite_base::rounding_modes::RoundingMode;
use malachite_nz::integer::Integer;
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

/// Small integer as a rational.
pub fn qi(n: i64) -> Q {
    Rational::from(n)
}

/// n / d exactly.
pub fn ratio(n: i64, d: i64) -> Q {
    Rational::from_signeds(n, d)
}

pub fn zero() -> Q {
    Rational::ZERO
}

pub fn one() -> Q {
    Rational::ONE
}

/// Whether x > 0.
pub fn is_pos(x: &Q) -> bool {
    x.sign() == Ordering::Greater
}

pub fn abs(x: &Q) -> Q {
    x.abs()
}

/// Nearest double (ties to even); out of range gives an infinity.
pub fn f(x: &Q) -> f64 {
    f64::rounding_from(x, RoundingMode::Nearest).0
}

/// Nearest double point.
pub fn fp(p: &QPoint) -> [f64; 2] {
    [f(&p[0]), f(&p[1])]
}

pub fn sub(a: &QPoint, b: &QPoint) -> QPoint {
    [&a[0] - &b[0], &a[1] - &b[1]]
}

pub fn add(a: &QPoint, b: &QPoint) -> QPoint {
    [&a[0] + &b[0], &a[1] + &b[1]]
}

pub fn scale(a: &QPoint, t: &Q) -> QPoint {
    [&a[0] * t, &a[1] * t]
}

pub fn dot(a: &QPoint, b: &QPoint) -> Q {
    &a[0] * &b[0] + &a[1] * &b[1]
}

pub fn cross(a: &QPoint, b: &QPoint) -> Q {
    &a[0] * &b[1] - &a[1] * &b[0]
}

pub fn norm2(a: &QPoint) -> Q {
    dot(a, a)
}

/// Sign of the turn a -> b -> c: Greater = counter-clockwise.
pub fn orient_q(a: &QPoint, b: &QPoint, c: &QPoint) -> Ordering {
    cross(&sub(b, a), &sub(c, a)).sign()
}

/// Orientation of exact points given with their nearest doubles: decided in
/// doubles when an error bound allows it, exactly otherwise.
pub fn orient_filtered(p: [&QPoint; 3], a: [[f64; 2]; 3]) -> Ordering {
    let [x, y, z] = a;
    let det = (y[0] - x[0]) * (z[1] - x[1]) - (y[1] - x[1]) * (z[0] - x[0]);
    // Inputs within a relative 2^-53; 16 ulps of the magnitudes bound the
    // error generously (subnormal magnitudes go to the exact path).
    let bound = 16.0
        * f64::EPSILON
        * ((x[0].abs() + y[0].abs()) * (x[1].abs() + z[1].abs())
            + (x[1].abs() + y[1].abs()) * (x[0].abs() + z[0].abs()));
    if det.is_finite() && bound.is_finite() && bound > 1e-280 && det.abs() > bound {
        return det.partial_cmp(&0.0).unwrap_or(Ordering::Equal);
    }
    orient_q(p[0], p[1], p[2])
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

/// Whether p lies in the closed axis-aligned box of segment ab.
pub fn in_box(a: [f64; 2], b: [f64; 2], p: [f64; 2]) -> bool {
    (0..2).all(|k| p[k] >= a[k].min(b[k]) && p[k] <= a[k].max(b[k]))
}

/// Whether p lies in the closed diametral disc of segment ab: (a-p).(b-p) <= 0.
pub fn in_diametral_disc(a: [f64; 2], b: [f64; 2], p: [f64; 2]) -> bool {
    let (a, b, p) = (qp(a), qp(b), qp(p));
    !is_pos(&dot(&sub(&a, &p), &sub(&b, &p)))
}

/// Power of x with respect to the weighted point (p, w): |x - p|^2 - w.
pub fn power(x: &QPoint, p: &QPoint, w: &Q) -> Q {
    norm2(&sub(x, p)) - w
}

/// A fraction kept unreduced: sums and products without gcds, which
/// dominate rational arithmetic; reduced once when turned back into a `Q`.
#[derive(Clone)]
struct Fr {
    n: Integer,
    d: Integer,
}

impl Fr {
    fn of(x: &Q) -> Fr {
        let n = Integer::from_sign_and_abs(x.sign() != Ordering::Less, x.numerator_ref().clone());
        Fr {
            n,
            d: Integer::from(x.denominator_ref().clone()),
        }
    }

    fn add(&self, o: &Fr, sign: bool) -> Fr {
        let (a, b) = if self.d == o.d {
            (self.n.clone(), o.n.clone())
        } else {
            (&self.n * &o.d, &o.n * &self.d)
        };
        let n = if sign { a + b } else { a - b };
        let d = if self.d == o.d {
            self.d.clone()
        } else {
            &self.d * &o.d
        };
        Fr { n, d }
    }

    fn plus(&self, o: &Fr) -> Fr {
        self.add(o, true)
    }

    fn minus(&self, o: &Fr) -> Fr {
        self.add(o, false)
    }

    fn times(&self, o: &Fr) -> Fr {
        Fr {
            n: &self.n * &o.n,
            d: &self.d * &o.d,
        }
    }

    fn over(&self, o: &Fr) -> Fr {
        Fr {
            n: &self.n * &o.d,
            d: &self.d * &o.n,
        }
    }

    fn q(self) -> Q {
        Rational::from_integers(self.n, self.d)
    }
}

/// The power centre of three weighted points (equal power to all three), or
/// None when they are collinear.
pub fn power_centre(p: [&QPoint; 3], w: [&Q; 3]) -> Option<QPoint> {
    // x = p0 + y with 2 y.(pk - p0) = |pk - p0|^2 - wk + w0 for k = 1, 2,
    // in unreduced fractions: two gcds per centre instead of dozens.
    let f = |x: &Q| Fr::of(x);
    let (x0, y0) = (f(&p[0][0]), f(&p[0][1]));
    let u = [f(&p[1][0]).minus(&x0), f(&p[1][1]).minus(&y0)];
    let v = [f(&p[2][0]).minus(&x0), f(&p[2][1]).minus(&y0)];
    let det = u[0].times(&v[1]).minus(&u[1].times(&v[0]));
    if det.n == 0 {
        return None;
    }
    let w0 = f(w[0]);
    let ru = u[0]
        .times(&u[0])
        .plus(&u[1].times(&u[1]))
        .minus(&f(w[1]))
        .plus(&w0);
    let rv = v[0]
        .times(&v[0])
        .plus(&v[1].times(&v[1]))
        .minus(&f(w[2]))
        .plus(&w0);
    let two_det = Fr {
        n: det.n * Integer::from(2),
        d: det.d,
    };
    let c0 = ru.times(&v[1]).minus(&rv.times(&u[1])).over(&two_det);
    let c1 = rv.times(&u[0]).minus(&ru.times(&v[0])).over(&two_det);
    Some([x0.plus(&c0).q(), y0.plus(&c1).q()])
}

/// The double nearest to x, back as an exact value: a short rational.
/// (x itself when it is beyond the range of doubles).
pub fn round(x: &Q) -> Q {
    let d = f(x);
    if d.is_finite() {
        q(d)
    } else {
        x.clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn doubles_convert_exactly() {
        assert_eq!(q(0.1) * qi(10), q(0.1) * qi(10));
        assert_ne!(q(0.1) * qi(3), q(0.3));
        assert_eq!(f(&q(0.1)), 0.1);
    }

    #[test]
    fn orientation_is_exact_near_degeneracy() {
        let a = [0.0, 0.0];
        let b = [1.0, 1.0];
        let c = [0.5, 0.5];
        assert_eq!(orient(a, b, c), Ordering::Equal);
        let c2 = [0.5, f64::from_bits(0.5f64.to_bits() + 1)];
        assert_eq!(orient(a, b, c2), Ordering::Greater);
        assert_eq!(orient_q(&qp(a), &qp(b), &qp(c2)), Ordering::Greater);
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

    #[test]
    fn power_centre_of_unweighted_triangle_is_circumcentre() {
        let p = [qp([0.0, 0.0]), qp([2.0, 0.0]), qp([0.0, 2.0])];
        let z = zero();
        let c = power_centre([&p[0], &p[1], &p[2]], [&z, &z, &z]).unwrap();
        assert_eq!(c, qp([1.0, 1.0]));
        // Weights shift it: equal power to all three.
        let w = [qi(1), qi(0), qi(3)];
        let c = power_centre([&p[0], &p[1], &p[2]], [&w[0], &w[1], &w[2]]).unwrap();
        let pw: Vec<Q> = (0..3).map(|k| power(&c, &p[k], &w[k])).collect();
        assert_eq!(pw[0], pw[1]);
        assert_eq!(pw[1], pw[2]);
    }
}
