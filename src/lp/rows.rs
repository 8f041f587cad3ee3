//! Rows of the weights LP: power tests (system 1), supporting planes,
//! system 3 and anchors, over weights and coordinates in any dimension, in
//! units that scale back exactly.

use nalgebra::SVector;

/// Which rows a row belongs to.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Family {
    Sys1,
    Sys3(u32),
    /// An anchor on a segment's dual line: in `rows`, an elastic equality
    /// in phase 2 only.
    Anchor,
}

/// Where a row comes from, so that `proof` can rebuild it exactly. Points
/// are the LP's (`Units`), p_x is point x, and `aux` the first of a face's
/// D slope columns.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Origin {
    /// Not rebuilt: a certificate that needs it is not attempted.
    Other,
    /// The lift of j on face's plane through the lift of i.
    PlaneOn {
        face: u32,
        i: u32,
        j: u32,
        aux: usize,
    },
    /// The lift of m above face's plane through the lift of i.
    PlaneAbove {
        face: u32,
        i: u32,
        m: u32,
        aux: usize,
    },
    /// |w_i - w_j| < |p_j - p_i|^2, one side (`up`: w_j - w_i).
    Apart { i: u32, j: u32, up: bool },
    /// The radical point of i and j on their segment nearer (in power) to
    /// i than to m.
    Radical { i: u32, j: u32, m: u32 },
    /// The power centre of triangle t inside beyond its edge (a, b).
    CentreInside { t: [u32; 3], a: u32, b: u32 },
    /// The power centre of triangle t nearer (in power) to t[0] than to o.
    CentreNearer { t: [u32; 3], o: u32 },
}

/// sum(terms) - share * delta >= rhs  (or == rhs for equalities, without
/// delta).
#[derive(Debug, Clone)]
pub(crate) struct Row {
    pub(crate) terms: Vec<(usize, f64)>,
    pub(crate) rhs: f64,
    pub(crate) family: Family,
    /// This row's part of a row split between pieces (1 when whole).
    pub(crate) share: f64,
    /// A row about a triangle outside the domain (the gap between two
    /// cavities): `pieces` may split it between the pieces it joins.
    pub(crate) outside: bool,
    /// An outside row at an edge that is not a segment: between pieces,
    /// `pieces` leaves it out. Outside the domain only segments need be
    /// strict edges, and a gap between cavities on a lattice is
    /// cocircular: splitting its rows would tie the pieces' weights.
    pub(crate) weak: bool,
    pub(crate) origin: Origin,
}

/// An LP over the weights (columns 0..n) and auxiliary free columns.
#[derive(Debug, Clone, Default)]
pub(crate) struct System {
    pub(crate) n: usize,
    /// Which weights are unknowns; the others stay zero.
    pub(crate) free: Vec<bool>,
    /// Whether infeasibility of these rows proves infeasibility (global form).
    pub(crate) verdict: bool,
    /// Rows are written for points divided by a power of two near the
    /// input's extent (so HiGHS' absolute tolerances mean the same at any
    /// scale); weights come back multiplied by its square, exactly.
    pub(crate) unit2: f64,
    pub(crate) aux: usize,
    pub(crate) l2: Vec<f64>,
    pub(crate) rows: Vec<Row>,
    pub(crate) eqs: Vec<Row>,
}

impl Row {
    /// A whole system 1 row inside the domain.
    pub(crate) fn sys1(terms: Vec<(usize, f64)>, rhs: f64) -> Row {
        Row {
            terms,
            rhs,
            family: Family::Sys1,
            share: 1.0,
            outside: false,
            weak: false,
            origin: Origin::Other,
        }
    }
}

/// p_to - p_from.
pub(crate) fn rel<const D: usize>(p: &[[f64; D]], from: u32, to: u32) -> SVector<f64, D> {
    SVector::from(p[to as usize]) - SVector::from(p[from as usize])
}

/// System 3 for segment s = (i, j): |w_i - w_j| < L and, for each m, the
/// radical point q of i, j on the segment has smaller power for i than for m.
pub(crate) fn sys3_rows<const D: usize>(
    p: &[[f64; D]],
    s: u32,
    i: u32,
    j: u32,
    others: &[u32],
) -> Vec<Row> {
    let u = rel(p, i, j);
    let l = u.norm_squared();
    let fam = Family::Sys3(s);
    let (i, j) = (i as usize, j as usize);
    let mut rows = vec![
        Row {
            terms: vec![(i, -1.0 / l), (j, 1.0 / l)],
            rhs: -1.0,
            family: fam,
            share: 1.0,
            outside: false,
            weak: false,
            origin: Origin::Apart {
                i: i as u32,
                j: j as u32,
                up: true,
            },
        },
        Row {
            terms: vec![(i, 1.0 / l), (j, -1.0 / l)],
            rhs: -1.0,
            family: fam,
            share: 1.0,
            outside: false,
            weak: false,
            origin: Origin::Apart {
                i: i as u32,
                j: j as u32,
                up: false,
            },
        },
    ];
    for &m in others {
        let r = rel(p, i as u32, m);
        let (ur, rr) = (u.dot(&r), r.norm_squared());
        rows.push(Row {
            terms: vec![
                (i, (1.0 - ur / l) / l),
                (j, ur / l / l),
                (m as usize, -1.0 / l),
            ],
            rhs: -(rr - ur) / l,
            family: fam,
            share: 1.0,
            outside: false,
            weak: false,
            origin: Origin::Radical {
                i: i as u32,
                j: j as u32,
                m,
            },
        });
    }
    rows
}

/// The supporting-plane rows of a face with first vertex i and the
/// vertices `on` (none for an isolated vertex): the plane through their
/// lifts, relative to p_i, has free slopes in D auxiliary columns; every m
/// lies above it.
pub(crate) fn plane_rows<const D: usize>(
    sys: &mut System,
    p: &[[f64; D]],
    face: u32,
    i: u32,
    on: &[u32],
    others: &[u32],
    scale2: f64,
) -> usize {
    let a0 = sys.n + sys.aux;
    sys.aux += D;
    let slopes =
        |r: SVector<f64, D>, sign: f64| (0..D).map(move |k| (a0 + k, sign * r[k] / scale2));
    for &j in on {
        // a.u + w_j - w_i = |u|^2, scaled by 1/L.
        let u = rel(p, i, j);
        let mut terms: Vec<(usize, f64)> = slopes(u, 1.0).collect();
        terms.extend([(j as usize, 1.0 / scale2), (i as usize, -1.0 / scale2)]);
        let mut row = Row::sys1(terms, u.norm_squared() / scale2);
        row.origin = Origin::PlaneOn {
            face,
            i,
            j,
            aux: a0,
        };
        sys.eqs.push(row);
    }
    for &m in others {
        let r = rel(p, i, m);
        // |r|^2 - w_m + w_i - a.r >= delta * scale2
        let mut terms = vec![(m as usize, -1.0 / scale2), (i as usize, 1.0 / scale2)];
        terms.extend(slopes(r, -1.0));
        let mut row = Row::sys1(terms, -r.norm_squared() / scale2);
        row.origin = Origin::PlaneAbove {
            face,
            i,
            m,
            aux: a0,
        };
        sys.rows.push(row);
    }
    a0
}

/// The input in LP units.
pub(crate) struct Units<const D: usize> {
    /// Points divided by the power of two nearest the input's extent.
    pub points: Vec<[f64; D]>,
    /// That power of two, squared: the unit of weights.
    pub unit2: f64,
    /// Squared length of the shortest given edge at each vertex, in LP units.
    pub l2: Vec<f64>,
}

impl<const D: usize> Units<D> {
    pub fn new(input: &[[f64; D]], edges: impl Iterator<Item = (u32, u32)>) -> Units<D> {
        let (mut lo, mut hi) = ([f64::INFINITY; D], [f64::NEG_INFINITY; D]);
        for p in input {
            for k in 0..D {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let extent = (0..D).map(|k| hi[k] - lo[k]).fold(0.0, f64::max);
        let scale = 2f64.powi(extent.log2().round() as i32);
        let points: Vec<[f64; D]> = input.iter().map(|p| p.map(|x| x / scale)).collect();
        let mut l2 = vec![f64::INFINITY; points.len()];
        for (a, b) in edges {
            let d = rel(&points, a, b).norm_squared();
            for v in [a, b] {
                l2[v as usize] = l2[v as usize].min(d);
            }
        }
        let l2 = l2
            .iter()
            .map(|&d| if d.is_finite() && d > 0.0 { d } else { 1.0 })
            .collect();
        Units {
            points,
            unit2: scale * scale,
            l2,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sys3_rows_by_hand() {
        // Segment (0,0)-(2,0), apex (1,1): q = (1,0) with zero weights;
        // pi(q; m) - pi(q; i) = 1 - 1 = 0, scaled by L = 4 -> row value 0.
        let p = [[0.0, 0.0], [2.0, 0.0], [1.0, 1.0]];
        let mut sys = System {
            n: 3,
            l2: vec![1.0; 3],
            ..Default::default()
        };
        sys.rows.extend(sys3_rows(&p, 0, 0, 1, &[2]));
        assert_eq!(sys.rows.len(), 3);
        let apex = &sys.rows[2];
        assert_eq!(apex.rhs, -(2.0 - 2.0) / 4.0);
        // raising w_i by 1 moves q towards j: lambda = (1 + 1/4)/2, value
        // |r|^2 - 2 lambda u.r - w_m + w_i = 2 - 2.5 + 1 = 0.5 -> 0.125 scaled
        let v: f64 = apex
            .terms
            .iter()
            .map(|&(c, k)| k * if c == 0 { 1.0 } else { 0.0 })
            .sum::<f64>()
            - apex.rhs;
        assert!((v - 0.125).abs() < 1e-15, "{v}");
    }

    #[test]
    fn plane_rows_by_hand() {
        // Segment (0,0)-(2,0) and a point (1,1): the plane through the lifts
        // of the segment's ends has slopes a (two auxiliary columns).
        let p = [[0.0, 0.0], [2.0, 0.0], [1.0, 1.0]];
        let mut sys = System {
            n: 3,
            l2: vec![1.0; 3],
            ..Default::default()
        };
        let a0 = plane_rows(&mut sys, &p, 0, 0, &[1], &[2], 4.0);
        assert_eq!((a0, sys.aux), (3, 2));
        // a.u + w_1 - w_0 = |u|^2, over L = 4
        let eq = &sys.eqs[0];
        assert_eq!(eq.terms, vec![(3, 0.5), (4, 0.0), (1, 0.25), (0, -0.25)]);
        assert_eq!(eq.rhs, 1.0);
        // |r|^2 - w_2 + w_0 - a.r >= delta L: with zero weights and
        // a = (2, -1) the row value is (2 - (2 - 1)) / 4 = 1/4.
        let row = &sys.rows[0];
        assert_eq!(row.rhs, -0.5);
        let x = [0.0, 0.0, 0.0, 2.0, -1.0];
        let value: f64 = row.terms.iter().map(|&(c, k)| k * x[c]).sum::<f64>() - row.rhs;
        assert_eq!(value, 0.25);
        // and the equality holds for those slopes
        let lhs: f64 = eq.terms.iter().map(|&(c, k)| k * x[c]).sum();
        assert_eq!(lhs, eq.rhs);
    }
}
