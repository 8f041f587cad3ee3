//! The geometric kernel: every exact predicate and construction (filters,
//! intervals, rationals) and the measures in doubles. The one place where
//! a geometric decision is made.

mod cut;
mod dyadic;
mod exact;
mod grid;
mod measure;
mod polygon;
mod power3;
mod running;
mod semistatic;
mod simplices;
mod solid;

pub use cut::{CutFace, Cutter, Halfspace};
pub use dyadic::*;
pub use exact::*;
pub use grid::Grid;
pub use measure::*;
pub use polygon::ear_clip;
pub use power3::Weighted3;
pub use running::*;
pub(crate) use semistatic::{by_columns, column_max, diff, lifted, sign_beyond};
pub use simplices::*;
pub use solid::in_solid;

/// Reproducible pseudo-random doubles in [0, 1) (xorshift): the kernel's
/// tests and `generate` (which re-exports it) draw from it.
pub fn uniform(seed: u64) -> impl FnMut() -> f64 {
    let mut state = seed.max(1);
    move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Hilbert index of (x, y) on a 2^16 grid: an order of points that
/// keeps neighbours near (the pure backend's insertion order, the
/// simulator decks' cell order).
pub fn hilbert(mut x: u32, mut y: u32) -> u64 {
    let mut d = 0u64;
    let mut s = 1u32 << 15;
    while s > 0 {
        let rx = u32::from(x & s > 0);
        let ry = u32::from(y & s > 0);
        d += u64::from(s) * u64::from(s) * u64::from((3 * rx) ^ ry);
        if ry == 0 {
            if rx == 1 {
                x = s.wrapping_mul(2).wrapping_sub(1).wrapping_sub(x) & 0xffff;
                y = s.wrapping_mul(2).wrapping_sub(1).wrapping_sub(y) & 0xffff;
            }
            std::mem::swap(&mut x, &mut y);
        }
        s >>= 1;
    }
    d
}

/// Hilbert keys of points, on a 2^16 grid over their bounding box per axis
/// (an axis of zero or infinite span keys 0).
pub fn hilbert_keys(points: &[[f64; 2]]) -> Vec<u64> {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for a in points {
        for k in 0..2 {
            lo[k] = lo[k].min(a[k]);
            hi[k] = hi[k].max(a[k]);
        }
    }
    let cell = |k: usize, v: f64| {
        let span = hi[k] - lo[k];
        if span > 0.0 && span.is_finite() {
            (((v - lo[k]) / span) * 65535.0).clamp(0.0, 65535.0) as u32
        } else {
            0
        }
    };
    points
        .iter()
        .map(|a| hilbert(cell(0, a[0]), cell(1, a[1])))
        .collect()
}

/// Hilbert index of a point of a 2^21 grid in 3D (Skilling's transpose
/// form: the coordinates' bits untwisted, Gray-coded, then interleaved).
/// Only the pure engine's 3D side orders points by it.
#[cfg_attr(not(feature = "pure-rust"), allow(dead_code))]
pub fn hilbert3(mut x: [u32; 3]) -> u64 {
    const BITS: u32 = 21;
    let top = 1u32 << (BITS - 1);
    let mut q = top;
    while q > 1 {
        let p = q - 1;
        for i in 0..3 {
            if x[i] & q != 0 {
                x[0] ^= p;
            } else {
                let t = (x[0] ^ x[i]) & p;
                x[0] ^= t;
                x[i] ^= t;
            }
        }
        q >>= 1;
    }
    x[1] ^= x[0];
    x[2] ^= x[1];
    let (mut t, mut q) = (0, top);
    while q > 1 {
        if x[2] & q != 0 {
            t ^= q - 1;
        }
        q >>= 1;
    }
    let x = x.map(|v| v ^ t);
    (0..BITS)
        .rev()
        .flat_map(|b| x.map(|v| u64::from((v >> b) & 1)))
        .fold(0, |key, bit| key << 1 | bit)
}

/// 3D Hilbert keys of points, on a 2^21 grid over their bounding box per
/// axis (an axis of zero or infinite span keys 0).
#[cfg_attr(not(feature = "pure-rust"), allow(dead_code))]
pub fn hilbert_keys3(points: &[[f64; 3]]) -> Vec<u64> {
    let (lo, hi) = bbox(points);
    let max = ((1u32 << 21) - 1) as f64;
    let cell = |k: usize, v: f64| {
        let span = hi[k] - lo[k];
        if span > 0.0 && span.is_finite() {
            (((v - lo[k]) / span) * max).clamp(0.0, max) as u32
        } else {
            0
        }
    };
    points
        .iter()
        .map(|a| hilbert3(std::array::from_fn(|k| cell(k, a[k]))))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_3d_curve_steps_to_a_neighbour_each_time() {
        // Every cell of an 8^3 corner of the grid, at the grid's scale:
        // sorted by key, consecutive cells share a face.
        let shift = 21 - 3;
        let mut cells: Vec<(u64, [u32; 3])> = (0..512u32)
            .map(|i| {
                let c = [i % 8, i / 8 % 8, i / 64];
                (hilbert3(c.map(|v| v << shift)), c)
            })
            .collect();
        cells.sort_unstable();
        for w in cells.windows(2) {
            let d: u32 = (0..3).map(|k| w[0].1[k].abs_diff(w[1].1[k])).sum();
            assert_eq!(d, 1, "{:?} -> {:?}", w[0].1, w[1].1);
        }
    }
}
