//! Exact dyadic numbers `m 2^e`: what doubles, their sums, differences and
//! products are. Predicates whose inputs are doubles and whose values are
//! polynomials in them (after clearing positive denominators) are decided
//! here without a gcd: rationals normalise after every operation, which
//! made an exact power test of four sites cost 60-110 us (measured), where
//! these take a few.

use malachite_base::num::arithmetic::traits::Sign;
use malachite_nz::integer::Integer;
use std::cmp::Ordering;
use std::ops::{Add, Mul, Sub};

/// The exact value `m 2^e`.
#[derive(Debug, Clone, PartialEq)]
pub struct Dyadic {
    m: Integer,
    e: i64,
}

impl Dyadic {
    /// The exact value of a finite double.
    pub fn of(x: f64) -> Dyadic {
        debug_assert!(
            x.is_finite(),
            "finite values are validated before any geometry"
        );
        let bits = x.to_bits();
        let (biased, frac) = (((bits >> 52) & 0x7ff) as i64, bits & ((1u64 << 52) - 1));
        let (mantissa, e) = if biased == 0 {
            (frac, -1074)
        } else {
            (frac | (1u64 << 52), biased - 1075)
        };
        if mantissa == 0 {
            return Dyadic::int(0);
        }
        // Odd mantissas keep the numbers short (1.0 is 1, not 2^52 2^-52).
        let tz = mantissa.trailing_zeros();
        let (mantissa, e) = (mantissa >> tz, e + i64::from(tz));
        let m = Integer::from(mantissa);
        Dyadic {
            m: if bits >> 63 == 1 { -m } else { m },
            e,
        }
    }

    /// The integer n.
    pub fn int(n: i64) -> Dyadic {
        Dyadic {
            m: Integer::from(n),
            e: 0,
        }
    }

    /// Its sign.
    pub fn sign(&self) -> Ordering {
        self.m.sign()
    }

    /// Its value as a rational.
    pub fn exact(&self) -> crate::geom::Q {
        use malachite_base::num::arithmetic::traits::PowerOf2;
        crate::geom::Q::from(self.m.clone()) * crate::geom::Q::power_of_2(self.e)
    }

    /// Its square.
    pub fn sqr(&self) -> Dyadic {
        self * self
    }

    /// self + sign o, at the smaller exponent: only the mantissa with the
    /// larger exponent is shifted (a new integer), the other is added to
    /// it by reference. A zero takes the other's exponent, so that it never
    /// lengthens the other.
    fn plus(&self, o: &Dyadic, negate: bool) -> Dyadic {
        let signed = |m: Integer| if negate { -m } else { m };
        if o.m == 0 {
            return self.clone();
        }
        if self.m == 0 {
            return Dyadic {
                m: signed(o.m.clone()),
                e: o.e,
            };
        }
        let shifted = |x: &Dyadic, e: i64| &x.m << ((x.e - e) as u64);
        match self.e.cmp(&o.e) {
            Ordering::Greater => Dyadic {
                m: if negate {
                    shifted(self, o.e) - &o.m
                } else {
                    shifted(self, o.e) + &o.m
                },
                e: o.e,
            },
            Ordering::Less => Dyadic {
                m: signed(shifted(o, self.e)) + &self.m,
                e: self.e,
            },
            Ordering::Equal => Dyadic {
                m: if negate {
                    &self.m - &o.m
                } else {
                    &self.m + &o.m
                },
                e: self.e,
            },
        }
    }
}

impl Add for &Dyadic {
    type Output = Dyadic;
    fn add(self, o: &Dyadic) -> Dyadic {
        self.plus(o, false)
    }
}

impl Sub for &Dyadic {
    type Output = Dyadic;
    fn sub(self, o: &Dyadic) -> Dyadic {
        self.plus(o, true)
    }
}

impl Mul for &Dyadic {
    type Output = Dyadic;
    fn mul(self, o: &Dyadic) -> Dyadic {
        Dyadic {
            m: &self.m * &o.m,
            e: self.e + o.e,
        }
    }
}

/// a d - b c.
fn minor(a: &Dyadic, b: &Dyadic, c: &Dyadic, d: &Dyadic) -> Dyadic {
    &(a * d) - &(b * c)
}

/// The sign of a 3x3 determinant of dyadic rows.
pub fn det3_sign(r: [[&Dyadic; 3]; 3]) -> Ordering {
    let t0 = r[0][0] * &minor(r[1][1], r[1][2], r[2][1], r[2][2]);
    let t1 = r[0][1] * &minor(r[1][0], r[1][2], r[2][0], r[2][2]);
    let t2 = r[0][2] * &minor(r[1][0], r[1][1], r[2][0], r[2][1]);
    (&(&t0 - &t1) + &t2).sign()
}

/// The sign of a 4x4 determinant of dyadic rows (Laplace expansion by the
/// 2x2 minors of the first two rows and the last two).
pub fn det4_sign(r: &[[Dyadic; 4]; 4]) -> Ordering {
    let top = |i: usize, j: usize| minor(&r[0][i], &r[0][j], &r[1][i], &r[1][j]);
    let bottom = |i: usize, j: usize| minor(&r[2][i], &r[2][j], &r[3][i], &r[3][j]);
    let plus = [(0, 1, 2, 3), (0, 3, 1, 2), (1, 2, 0, 3), (2, 3, 0, 1)];
    let minus = [(0, 2, 1, 3), (1, 3, 0, 2)];
    let sum = |terms: &[(usize, usize, usize, usize)]| {
        terms.iter().fold(Dyadic::int(0), |acc, &(a, b, c, d)| {
            &acc + &(&top(a, b) * &bottom(c, d))
        })
    };
    (&sum(&plus) - &sum(&minus)).sign()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::{det3_q, det4_q, q, Q};

    fn same(x: f64) {
        assert_eq!(Dyadic::of(x).exact(), q(x), "{x}");
    }

    #[test]
    fn doubles_are_dyadic_exactly() {
        for x in [
            0.0,
            -0.0,
            1.0,
            -0.1,
            1e300,
            -1e-300,
            5e-324,
            f64::MAX,
            3.0f64.sqrt(),
        ] {
            same(x);
        }
        let (a, b) = (Dyadic::of(0.1), Dyadic::of(0.2));
        assert_eq!((&a + &b).exact(), q(0.1) + q(0.2));
        assert_eq!((&(&a * &b) - &(&b * &a)).sign(), Ordering::Equal);
        assert_eq!(
            (&Dyadic::of(1e-300) - &Dyadic::of(1e300)).sign(),
            Ordering::Less
        );
    }

    #[test]
    fn determinant_signs_match_the_rationals() {
        // Pseudo-random rows, some made exactly singular.
        let mut u = crate::geom::uniform(7);
        for k in 0..200 {
            let mut r4: [[f64; 4]; 4] = std::array::from_fn(|_| std::array::from_fn(|_| u() - 0.5));
            if k % 3 == 0 {
                // Row 3 = row 0 + row 1 (exactly, in halves).
                r4[0] = r4[0].map(|x| (x * 1024.0).round() / 1024.0);
                r4[1] = r4[1].map(|x| (x * 1024.0).round() / 1024.0);
                r4[3] = std::array::from_fn(|j| r4[0][j] + r4[1][j]);
            }
            let d4: [[Dyadic; 4]; 4] = r4.map(|row| row.map(Dyadic::of));
            let q4: [[Q; 4]; 4] = r4.map(|row| row.map(q));
            assert_eq!(det4_sign(&d4), det4_q(&q4).cmp(&Q::from(0)), "{r4:?}");
            let r3 = [&d4[0], &d4[1], &d4[3]].map(|row| [&row[0], &row[1], &row[2]]);
            let q3 = [&q4[0], &q4[1], &q4[3]].map(|row| [&row[0], &row[1], &row[2]]);
            assert_eq!(det3_sign(r3), det3_q(q3).cmp(&Q::from(0)), "{r4:?}");
        }
    }
}
