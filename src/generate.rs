//! Synthetic constraint complexes of any size, for benchmarks and tests.

use crate::complex::Complex;

/// `nx` x `ny` square cavities of side 50 (10 m cells), each with a 16-gon
/// well boundary of the given radius and a hole inside it: the paper's
/// setting. At radius 14 zero weights suffice; at radius 24.5 the well
/// polygon nearly touches the cavity sides and the weights need the LP.
/// Adjacent cavities share their sides.
pub fn cavities(nx: usize, ny: usize, radius: f64) -> Complex {
    let mut cx = Complex::default();
    let side = 50.0;
    let per = 5; // points per cavity side
    let step = side / per as f64;
    let grid = |i: usize, j: usize| -> u32 { (j * (nx * per + 1) + i) as u32 };
    // Lattice points on the cavity sides only.
    let mut index = std::collections::HashMap::new();
    for j in 0..=ny * per {
        for i in 0..=nx * per {
            if i % per == 0 || j % per == 0 {
                index.insert(grid(i, j), cx.points.len() as u32);
                cx.points.push([i as f64 * step, j as f64 * step]);
            }
        }
    }
    for j in 0..=ny * per {
        for i in 0..=nx * per {
            if j % per == 0 && i < nx * per {
                cx.segments
                    .push([index[&grid(i, j)], index[&grid(i + 1, j)]]);
            }
            if i % per == 0 && j < ny * per {
                cx.segments
                    .push([index[&grid(i, j)], index[&grid(i, j + 1)]]);
            }
        }
    }
    let n = 16;
    for cy in 0..ny {
        for cxi in 0..nx {
            let c = [(cxi as f64 + 0.5) * side, (cy as f64 + 0.5) * side];
            let first = cx.points.len() as u32;
            for k in 0..n {
                let a = std::f64::consts::TAU * (k as f64 + 0.5) / n as f64;
                cx.points
                    .push([c[0] + radius * a.cos(), c[1] + radius * a.sin()]);
                cx.segments
                    .push([first + k as u32, first + ((k + 1) % n) as u32]);
            }
            cx.holes.push(c);
        }
    }
    cx.vertex_ids = (0..cx.points.len() as i64).collect();
    cx.segment_ids = (0..cx.segments.len() as i64).collect();
    cx
}

/// `rows` horizontal chains of `cols - 1` unit segments, rows `h` apart and
/// staggered by half a segment: for h < 0.5 the segments are not Gabriel
/// (and for small h not Delaunay), so the weights need the LP.
pub fn staggered_chains(rows: usize, cols: usize, h: f64) -> Complex {
    let mut points = vec![];
    let mut segments = vec![];
    for j in 0..rows {
        let off = 0.5 * (j % 2) as f64;
        for i in 0..cols {
            points.push([i as f64 + off, j as f64 * h]);
            if i > 0 {
                let v = (j * cols + i) as u32;
                segments.push([v - 1, v]);
            }
        }
    }
    Complex::new(points, segments)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn generated_complexes_are_valid() {
        let c = cavities(2, 3, 14.0);
        c.validate().unwrap();
        assert_eq!(c.holes.len(), 6);
        assert_eq!(c.segments.len(), 2 * 5 * 4 + 3 * 5 * 3 + 6 * 16);
        let s = staggered_chains(4, 10, 0.3);
        s.validate().unwrap();
        assert_eq!(s.segments.len(), 36);
    }
}
