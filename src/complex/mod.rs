//! The input stage: constraint complexes in 2D (`Complex`: points,
//! segments, holes) and 3D (`Complex3`: points and planar facets), and
//! their validation, which comes before any geometry and decides exactly.

mod d2;
mod d3;

pub use d2::Complex;
#[cfg(test)]
pub(crate) use d3::tests;
pub use d3::{Complex3, Facet};

use crate::error::{Error, Result};
use rayon::prelude::*;

/// Largest coordinate magnitude: squared lengths stay far below f64::MAX.
pub const MAX_COORD: f64 = 1e150;
/// Smallest extent: squared lengths stay normal doubles.
pub const MIN_EXTENT: f64 = 1e-150;

/// Points with a NaN or infinite coordinate, then points beyond
/// MAX_COORD, as errors naming their ids (weights are squared lengths in
/// doubles: squares must neither overflow nor vanish).
pub(crate) fn finite_in_range<const D: usize>(points: &[[f64; D]], ids: &[i64]) -> Result<()> {
    let bad: Vec<i64> = (0..points.len())
        .filter(|&i| !points[i].iter().all(|c| c.is_finite()))
        .map(|i| ids[i])
        .collect();
    if !bad.is_empty() {
        return Err(Error::NonFinite { vertices: bad });
    }
    let big: Vec<i64> = (0..points.len())
        .filter(|&i| points[i].iter().any(|c| c.abs() > MAX_COORD))
        .map(|i| ids[i])
        .collect();
    if !big.is_empty() {
        return Err(Error::OutOfRange(format!(
            "vertices beyond +-{MAX_COORD:e} (rescale the input): {big:?}"
        )));
    }
    Ok(())
}

/// Exact duplicates (-0.0 and 0.0 are the same position), then an extent
/// below MIN_EXTENT, as errors naming them.
pub(crate) fn distinct_with_extent<const D: usize>(points: &[[f64; D]], ids: &[i64]) -> Result<()> {
    let key = |i: u32| points[i as usize].map(|c| (c + 0.0).to_bits());
    // Sorted by position, then index: each run of one position starts at
    // its first occurrence.
    let mut order: Vec<u32> = (0..points.len() as u32).collect();
    order.par_sort_unstable_by_key(|&i| (key(i), i));
    let mut dups: Vec<(usize, usize)> = order
        .chunk_by(|&a, &b| key(a) == key(b))
        .flat_map(|run| run[1..].iter().map(|&i| (run[0] as usize, i as usize)))
        .collect();
    dups.sort_unstable_by_key(|&(_, i)| i);
    let dups: Vec<(i64, i64)> = dups.into_iter().map(|(j, i)| (ids[j], ids[i])).collect();
    if !dups.is_empty() {
        return Err(Error::DuplicateVertices { pairs: dups });
    }
    let extent = (0..D)
        .map(|k| {
            let it = points.iter().map(|p| p[k]);
            it.clone().fold(f64::NEG_INFINITY, f64::max) - it.fold(f64::INFINITY, f64::min)
        })
        .fold(0.0, f64::max);
    if points.len() > 1 && extent < MIN_EXTENT {
        return Err(Error::OutOfRange(format!(
            "the input spans {extent:e}, below {MIN_EXTENT:e} (rescale the input)"
        )));
    }
    Ok(())
}
