//! Semi-static filters: a determinant of rounded entries, evaluated in
//! doubles, and a bound on how far rounding the entries and the arithmetic
//! can move it. Its sign is final beyond the bound; within it the caller
//! falls back to intervals and exact arithmetic.

use std::cmp::Ordering;

/// The sign of a determinant in doubles when it is beyond what rounding
/// the entries (permanents p0 of the magnitudes, p1 with the entries'
/// bounds added) and the arithmetic (`k` eps of p1) can change; None near
/// underflow, where rounding is not relative.
pub(crate) fn sign_beyond(det: f64, p0: f64, p1: f64, k: f64) -> Option<Ordering> {
    let bound = (p1 - p0) + k * f64::EPSILON * p1;
    if !(bound.is_finite() && det.is_finite()) || p1 < 1e-200 {
        return None;
    }
    if det > bound {
        Some(Ordering::Greater)
    } else if det < -bound {
        Some(Ordering::Less)
    } else {
        None
    }
}

/// `decide`'s permanents bounded by columns, n! times the product of each
/// column's largest magnitude (x; with its largest error y added for p1):
/// each of the n! products is at most that, and the change of a product
/// when its entries move, prod(|a| + eta) - prod(|a|), grows with every
/// entry. At most n! times the permanents, for a fraction of their cost.
pub(crate) fn by_columns<const N: usize>(x: [f64; N], y: [f64; N], terms: f64) -> (f64, f64) {
    let p0: f64 = x.iter().product();
    let p1: f64 = x.iter().zip(&y).map(|(a, b)| a + b).product();
    (terms * p0, terms * p1)
}
