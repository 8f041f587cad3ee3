//! A double carried with a bound on its distance from the exact value it
//! stands for (running error analysis): the first filter of the site
//! predicates, before intervals. Per operation a few multiplications and no
//! branch, where an interval operation takes four products, their minimum
//! and maximum and two outward steps. Decides only what the bound allows;
//! the rest goes on to intervals and exact arithmetic.

use super::Filter;
use std::cmp::Ordering;
use std::ops::{Add, Mul, Sub};

/// Unit roundoff of doubles.
const U: f64 = f64::EPSILON / 2.0;
/// Added to every bound: the absolute rounding error of a result in the
/// subnormal range, which `|v| U` does not cover.
const TINY: f64 = 4.0 * f64::MIN_POSITIVE * f64::EPSILON;

/// A double `v` with `|exact - v| <= e`.
#[derive(Debug, Clone, Copy)]
pub struct Ev {
    v: f64,
    e: f64,
}

impl Ev {
    /// A double inside an enclosure, with r its distance to the farther
    /// end, computed in doubles (rounded up here: that subtraction may round
    /// down by a relative U, the product too).
    pub fn off_by(v: f64, r: f64) -> Ev {
        Ev {
            v,
            e: r * (1.0 + 4.0 * U) + TINY,
        }
    }
}

impl Filter for Ev {
    fn of(x: f64) -> Ev {
        Ev { v: x, e: 0.0 }
    }

    fn sqr(self) -> Ev {
        let v = self.v * self.v;
        let a = self.v.abs();
        Ev {
            v,
            e: 2.0 * a * self.e + self.e * self.e + v.abs() * U + TINY,
        }
    }

    /// The sign of every value within the bound, or None. Each bound above
    /// was itself rounded (down by at most a relative U per operation, over
    /// fewer than 60 operations in any predicate here), hence the margin.
    fn sign(self) -> Option<Ordering> {
        let bound = self.e * (1.0 + 128.0 * U);
        if !(bound.is_finite() && self.v.is_finite()) || self.v.abs() <= bound {
            return None;
        }
        Some(if self.v > 0.0 {
            Ordering::Greater
        } else {
            Ordering::Less
        })
    }
}

impl Add for Ev {
    type Output = Ev;
    fn add(self, o: Ev) -> Ev {
        let v = self.v + o.v;
        Ev {
            v,
            e: self.e + o.e + v.abs() * U + TINY,
        }
    }
}

impl Sub for Ev {
    type Output = Ev;
    fn sub(self, o: Ev) -> Ev {
        let v = self.v - o.v;
        Ev {
            v,
            e: self.e + o.e + v.abs() * U + TINY,
        }
    }
}

impl Mul for Ev {
    type Output = Ev;
    fn mul(self, o: Ev) -> Ev {
        let v = self.v * o.v;
        Ev {
            v,
            e: self.v.abs() * o.e + o.v.abs() * self.e + self.e * o.e + v.abs() * U + TINY,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::{det3, det3_q, q, Iv, Q};

    /// Rows near singular at every scale: whatever the filter decides, the
    /// rationals agree.
    #[test]
    fn decided_signs_are_exact() {
        let mut u = crate::geom::uniform(3);
        let (mut decided, mut undecided) = (0, 0);
        for k in 0..20_000 {
            let scale = [1.0, 1e-150, 1e150, 3e-300, 1e-5][k % 5];
            let mut r: [[f64; 3]; 3] = std::array::from_fn(|_| std::array::from_fn(|_| u() - 0.5));
            // Three in four: a third row close to a combination of the
            // first two, within a few ulps or as near as rounding allows.
            let (a, b) = (u(), u());
            for j in (0..3).filter(|_| k % 4 != 0) {
                let x = a * r[0][j] + b * r[1][j];
                let ulps = (u() * 8.0) as i64 - 4;
                r[2][j] = f64::from_bits((x.to_bits() as i64 + ulps * (k as i64 % 3)) as u64);
            }
            let r = r.map(|row| row.map(|x| x * scale));
            let filtered = det3(r.map(|row| row.map(Ev::of))).sign();
            let exact = {
                let qr = r.map(|row| row.map(q));
                let rows = [&qr[0], &qr[1], &qr[2]].map(|row| [&row[0], &row[1], &row[2]]);
                det3_q(rows).cmp(&Q::from(0))
            };
            match filtered {
                Some(s) => {
                    assert_eq!(s, exact, "{r:?}");
                    decided += 1;
                }
                None => undecided += 1,
            }
        }
        // The filter must also decide: a quarter are random rows, and at
        // three of the five scales their products stay in range.
        assert!(decided > 3_000 && undecided > 100, "{decided} {undecided}");
    }

    #[test]
    fn enclosures_bound_their_values() {
        let i = Iv::of(1.0) / Iv::of(3.0);
        let m = i.mid();
        let e = Ev::off_by(m, (i.hi - m).max(m - i.lo));
        let third = Q::from(1) / Q::from(3);
        let d = q(e.v) - third;
        assert!(d.clone() * d <= q(e.e) * q(e.e));
        assert_eq!((e - Ev::of(i.mid())).sign(), None);
        assert_eq!((Ev::of(1.0) - Ev::of(1.0)).sign(), None);
        assert_eq!((Ev::of(1e300) * Ev::of(1e300)).sign(), None);
        assert_eq!((Ev::of(2.0) * Ev::of(3.0)).sign(), Some(Ordering::Greater));
    }
}
