//! A block of cells whose layer boundaries are parallel planes (a dipping
//! layer cake, such as SPE9): the frame of its layers (two axes in them,
//! their normal), each boundary's height along the normal, and how far the
//! data's corners lie off those planes.

use super::super::cpg::{Cpg, Ijk};
use crate::geom::{cross_f, dot_f};
use nalgebra::{Matrix3, SymmetricEigen};

/// Corners may lie this far (relative to the block's size) off their
/// boundary's plane, and a column's wall off its plane, and points this
/// close are one: the decimals of corner-point files round planes. SPE9's
/// GRDECL (six decimals) by about 1e-9 of the field.
pub(crate) const PLANAR: f64 = 1e-7;

/// Corners of data rounded coarser may lie up to this far (relative to the
/// block's size) off their planes: the SPE9 benchmark deck's depths,
/// written by MRST to the hundredth of a foot (three decimals in places),
/// lie 4.1e-3 ft off, 5.3e-7 of its 7,700 ft block. The block's
/// tolerance is then twice that (`Frame::tol`), and its layered cells
/// fill it to 2e-9 of its volume (`assemble::FILLED` checks it).
pub(crate) const ROUNDED: f64 = 1e-6;

/// Cut points of twisted layers within this (relative to the block's
/// size) are one: 20 nanometres in a block of 200 m.
pub(crate) const TWISTED: f64 = 1e-10;

/// The layers' frame: `n` up across them, `a` and `b` in them (right
/// handed), heights along `n` from `o`.
#[derive(Debug, Clone)]
pub(crate) struct Frame {
    pub(crate) o: [f64; 3],
    pub(crate) a: [f64; 3],
    pub(crate) b: [f64; 3],
    pub(crate) n: [f64; 3],
    /// The first layer; per boundary from its top down, the height.
    pub(crate) k0: usize,
    pub(crate) h: Vec<f64>,
    /// The largest distance of a corner off its boundary's or wall's plane.
    pub(crate) off: f64,
    /// The block's size (its bounding box's diagonal).
    pub(crate) size: f64,
    /// Whether the boundaries are the grid's own faces, not planes
    /// (`Frame::twisted`); `h` is then each one's mean height.
    pub(crate) twisted: bool,
    /// The highest corner of the top boundary and the lowest of the bottom.
    extremes: [f64; 2],
}

impl Frame {
    /// Distances below this are the data's rounding: `PLANAR` of the
    /// block, or twice its corners' distance off their planes where the
    /// data round coarser (`ROUNDED`).
    pub(crate) fn tol(&self) -> f64 {
        match self.twisted {
            true => PLANAR * self.size,
            false => (PLANAR * self.size).max(2.0 * self.off),
        }
    }

    /// A point in frame coordinates (along a, b, n from o).
    pub(crate) fn to(&self, p: [f64; 3]) -> [f64; 3] {
        let d: [f64; 3] = std::array::from_fn(|k| p[k] - self.o[k]);
        [dot_f(d, self.a), dot_f(d, self.b), dot_f(d, self.n)]
    }

    /// A point from frame coordinates.
    pub(crate) fn from(&self, q: [f64; 3]) -> [f64; 3] {
        std::array::from_fn(|k| self.o[k] + q[0] * self.a[k] + q[1] * self.b[k] + q[2] * self.n[k])
    }

    /// Where the layers are twisted, the distance within which cut points
    /// are one and lie on a plane or an edge (`geom::Cutter`, `on_edges`):
    /// `TWISTED` of the block, not `PLANAR`, since pieces of a thin cell
    /// cut by planes at shallow angles (a pyramid's side from inside a
    /// 2.5 m cell to its 150 m edge) are thinner than that in places,
    /// and welding them leaves holes. None (rounding) where planar.
    pub(crate) fn weld(&self) -> f64 {
        match self.twisted {
            true => TWISTED * self.size,
            false => 0.0,
        }
    }

    /// The heights of the block's top and bottom: its boundaries' planes,
    /// or where they are twisted, their highest and lowest corners.
    pub(crate) fn ends(&self) -> [f64; 2] {
        match self.twisted {
            true => self.extremes,
            false => [self.h[0], self.h[self.h.len() - 1]],
        }
    }

    /// Where a pillar (COORD's top and bottom, depths down) crosses the
    /// plane at height h: its coordinates along a and b.
    pub(crate) fn crossing(&self, c: [f64; 6], h: f64) -> [f64; 2] {
        let (q0, q1) = (self.to([c[0], c[1], -c[2]]), self.to([c[3], c[4], -c[5]]));
        let t = (h - q0[2]) / (q1[2] - q0[2]);
        [q0[0] + t * (q1[0] - q0[0]), q0[1] + t * (q1[1] - q0[1])]
    }

    /// The frame of the live cells of columns `cols` over layers k0..=k1,
    /// or why they have none: an inactive or pinched cell, a boundary or a
    /// wall that is not a plane, boundaries that are not parallel.
    pub(crate) fn fit(
        cpg: &Cpg,
        cols: &[[usize; 2]],
        k0: usize,
        k1: usize,
    ) -> Result<Frame, String> {
        let mut f = Frame::measure(cpg, cols, k0, k1)?;
        let tol = ROUNDED * f.size;
        if f.off > tol {
            return Err(format!(
                "its layers' boundaries are not parallel planes (a corner {:.3e} off, above {tol:.3e})",
                f.off
            ));
        }
        // walls: each column side's corners over the layers on one plane
        for &c in cols {
            for side in 0..4 {
                let mut pts = vec![];
                for k in k0..=k1 {
                    pts.extend_from_slice(&cpg.face([c[0], c[1], k], side));
                }
                let (o, m) = plane_fit(&pts);
                let w = pts
                    .iter()
                    .map(|p| (dot_f(*p, m) - dot_f(o, m)).abs())
                    .fold(0.0, f64::max);
                if w > tol {
                    return Err(format!(
                        "the walls of column ({}, {}) are not planes ({w:.3e} off)",
                        c[0] + 1,
                        c[1] + 1
                    ));
                }
                f.off = f.off.max(w);
            }
        }
        Ok(f)
    }

    /// The frame of columns whose layers' boundaries and walls are not
    /// planes (leaning pillars, twisted tops: emerald): the normal and
    /// heights as `fit` has them, the cells then cut by the grid's own
    /// faces (`cones`); `off` says how far the boundaries stray from
    /// their planes. Errors only on an inactive or pinched cell.
    pub(crate) fn twisted(cpg: &Cpg, cols: &[[usize; 2]], k: [usize; 2]) -> Result<Frame, String> {
        let f = Frame::measure(cpg, cols, k[0], k[1])?;
        Ok(Frame { twisted: true, ..f })
    }

    /// The boundaries' common normal (their planes' normals averaged) and
    /// heights, and how far their corners lie off those planes.
    fn measure(cpg: &Cpg, cols: &[[usize; 2]], k0: usize, k1: usize) -> Result<Frame, String> {
        let cell = |[i, j]: [usize; 2], k: usize| -> Ijk { [i, j, k] };
        if let Some(c) = cols
            .iter()
            .flat_map(|&c| (k0..=k1).map(move |k| cell(c, k)))
            .find(|&c| !cpg.live(c))
        {
            return Err(format!(
                "cell {} is inactive or pinched out",
                super::super::cpg::one_based(c)
            ));
        }
        // each boundary's corners: tops of layer k, and the bottoms above
        let mut bounds: Vec<Vec<[f64; 3]>> = vec![vec![]; k1 - k0 + 2];
        for &c in cols {
            for k in k0..=k1 {
                let p = cpg.corners(cell(c, k));
                bounds[k - k0].extend_from_slice(&p[..4]);
                bounds[k - k0 + 1].extend_from_slice(&p[4..]);
            }
        }
        let all: Vec<[f64; 3]> = bounds.iter().flatten().copied().collect();
        let (lo, hi) = crate::geom::bbox(&all);
        let size = crate::geom::dist_f(lo, hi);
        let fits: Vec<([f64; 3], [f64; 3])> = bounds.iter().map(|b| plane_fit(b)).collect();
        // the common normal: the boundaries' normals, averaged
        let mut n = [0.0; 3];
        for (_, m) in &fits {
            for k in 0..3 {
                n[k] += m[k];
            }
        }
        let len = dot_f(n, n).sqrt();
        let n = n.map(|x| x / len);
        let mut off: f64 = 0.0;
        for (b, (c, _)) in bounds.iter().zip(&fits) {
            let h = dot_f(*c, n);
            for p in b {
                off = off.max((dot_f(*p, n) - h).abs());
            }
        }
        // a along x as far as the layers allow, b = n x a
        let x = [1.0, 0.0, 0.0];
        let t = dot_f(x, n);
        let a: [f64; 3] = std::array::from_fn(|k| x[k] - t * n[k]);
        let la = dot_f(a, a).sqrt();
        let a = a.map(|v| v / la);
        let b = cross_f(n, a);
        let o = fits[0].0;
        let height = |p: &[f64; 3]| dot_f(std::array::from_fn(|k| p[k] - o[k]), n);
        let h = fits.iter().map(|(c, _)| height(c)).collect();
        let top = bounds[0]
            .iter()
            .map(height)
            .fold(f64::NEG_INFINITY, f64::max);
        let bottom = bounds[k1 - k0 + 1]
            .iter()
            .map(height)
            .fold(f64::INFINITY, f64::min);
        Ok(Frame {
            o,
            a,
            b,
            n,
            k0,
            h,
            off,
            size,
            twisted: false,
            extremes: [top, bottom],
        })
    }
}

/// A least-squares plane through points: their centroid, and the unit
/// normal (pointing up, z > 0) of least spread.
pub(super) fn plane_fit(pts: &[[f64; 3]]) -> ([f64; 3], [f64; 3]) {
    let k = pts.len() as f64;
    let c: [f64; 3] = std::array::from_fn(|a| pts.iter().map(|p| p[a]).sum::<f64>() / k);
    let mut m = Matrix3::<f64>::zeros();
    for p in pts {
        for r in 0..3 {
            for s in 0..3 {
                m[(r, s)] += (p[r] - c[r]) * (p[s] - c[s]);
            }
        }
    }
    let e = SymmetricEigen::new(m);
    let i = e.eigenvalues.imin();
    let v = e.eigenvectors.column(i);
    let mut n = [v[0], v[1], v[2]];
    // up, else along +x then +y, for one orientation
    let key = if n[2] != 0.0 {
        n[2]
    } else if n[0] != 0.0 {
        n[0]
    } else {
        n[1]
    };
    if key < 0.0 {
        n = n.map(|x| -x);
    }
    (c, n)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reservoir::CornerPointGrid;

    #[test]
    fn a_dipping_layer_cake_has_a_frame_and_a_twisted_one_none() {
        // 4 x 3 x 3 columns of 10 m, layers 2 m, 1 m and 3 m thick, dipping
        // 1 in 5 along x
        let mut g = CornerPointGrid::layered([4, 3], [10.0, 10.0], &[100.0, 102.0, 103.0, 106.0]);
        for (p, c) in g.coord.iter_mut().enumerate() {
            let x = (p % 5) as f64 * 10.0;
            c[2] += 0.2 * x;
            c[5] += 0.2 * x;
        }
        let nx = 4;
        for (n, z) in g.zcorn.iter_mut().enumerate() {
            // zcorn: per layer, top then bottom rows of 2 nx per j half
            let i2 = n % (2 * nx);
            let x = ((i2 + 1) / 2) as f64 * 10.0;
            *z += 0.2 * x;
        }
        let cpg = Cpg::new(&g);
        let cols: Vec<[usize; 2]> = (0..3).flat_map(|j| (0..4).map(move |i| [i, j])).collect();
        let f = Frame::fit(&cpg, &cols, 0, 2).unwrap();
        assert!(f.off < 1e-9, "{}", f.off);
        let slope = -f.n[0] / f.n[2];
        assert!((slope.abs() - 0.2).abs() < 1e-12, "{:?}", f.n);
        let th: Vec<f64> = f.h.windows(2).map(|w| w[0] - w[1]).collect();
        let cos = f.n[2];
        for (t, want) in th.iter().zip([2.0, 1.0, 3.0]) {
            assert!((t - want * cos).abs() < 1e-9, "{th:?}");
        }
        // a corner and back
        let p = cpg.corner([1, 1, 1], 5);
        let q = f.from(f.to(p));
        assert!(crate::geom::dist_f(p, q) < 1e-9);
        // one corner raised 1 m: not parallel planes
        g.zcorn[8 * nx * 3 + 9] -= 1.0;
        let cpg = Cpg::new(&g);
        assert!(Frame::fit(&cpg, &cols, 0, 2).is_err());
    }
}
