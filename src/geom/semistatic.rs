//! Semi-static filters: a determinant of rounded entries, evaluated in
//! doubles, and a bound on how far rounding the entries and the arithmetic
//! can move it. Its sign is final beyond the bound; within it the caller
//! falls back to intervals and exact arithmetic.

use std::cmp::Ordering;

/// The sign of a determinant in doubles when it is beyond what rounding
/// the entries (permanents p0 of the magnitudes, p1 with the entries'
/// bounds added) and the arithmetic (`k` eps of p1) can change; None near
/// underflow, where rounding is not relative.
#[inline]
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

/// `sign_beyond`'s permanents bounded by columns, n! times the product of each
/// column's largest magnitude (x; with its largest error y added for p1):
/// each of the n! products is at most that, and the change of a product
/// when its entries move, prod(|a| + eta) - prod(|a|), grows with every
/// entry. At most n! times the permanents, for a fraction of their cost.
#[inline]
pub(crate) fn by_columns<const N: usize>(x: [f64; N], y: [f64; N], terms: f64) -> (f64, f64) {
    let p0: f64 = x.iter().product();
    let p1: f64 = x.iter().zip(&y).map(|(a, b)| a + b).product();
    (terms * p0, terms * p1)
}

/// Differences x - o of rounded coordinates (each point's doubles `mid`
/// and how far its exact values may be, `rad`), with bounds on how far the
/// exact differences may be: both points' rounding and the subtraction's.
#[inline]
pub(crate) fn diff<const D: usize>(
    (mx, rx): (&[f64], &[f64]),
    (mo, ro): (&[f64], &[f64]),
) -> ([f64; D], [f64; D]) {
    let d: [f64; D] = std::array::from_fn(|k| mx[k] - mo[k]);
    (
        d,
        std::array::from_fn(|k| rx[k] + ro[k] + f64::EPSILON * d[k].abs()),
    )
}

/// A power test's lifted entry |d|^2 - (w_x - w_o) for the row d = x - o
/// (within eta, `diff`) and the weights (w, rad) of x and o: the entry, a
/// bound on its magnitude, and how far the exact entry may be (d's error
/// moves |d|^2 by at most sum (2 |d_k| + eta_k) eta_k; the weights'
/// rounding; its own, 4 eps of its magnitude).
#[inline]
pub(crate) fn lifted<const D: usize>(
    (d, eta): ([f64; D], [f64; D]),
    (wx, rx): (f64, f64),
    (wo, ro): (f64, f64),
) -> (f64, f64, f64) {
    let sq: f64 = d.iter().map(|x| x * x).sum();
    let wz = wx - wo;
    let moved: f64 = (0..D).map(|k| (2.0 * d[k].abs() + eta[k]) * eta[k]).sum();
    let err = moved + rx + ro + 4.0 * f64::EPSILON * (sq + wx.abs() + wo.abs());
    (sq - wz, sq + wz.abs(), err)
}

/// Each column's largest entry.
#[inline]
pub(crate) fn column_max<const N: usize>(rows: &[[f64; N]]) -> [f64; N] {
    std::array::from_fn(|k| rows.iter().fold(0.0f64, |m, r| m.max(r[k])))
}
