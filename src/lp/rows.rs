//! Rows of the weights LP: power tests (system 1), supporting planes,
//! system 3 and anchors, over weights and coordinates in any dimension, in
//! units that scale back exactly.

use nalgebra::SVector;
use std::collections::HashMap;

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
/// free slope columns.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Origin {
    /// Not rebuilt: a certificate that needs it is not attempted.
    Other,
    /// The lift of m above face's hyperplane through the lifts of i and
    /// `on` (u32::MAX where absent), its slopes relative to p_i written
    /// with the free columns from `aux` on (`plane_rows`).
    PlaneAbove {
        face: u32,
        i: u32,
        on: [u32; 2],
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
    /// Whether rows may be lazy (`LAZY_SLACK`) though they have auxiliary
    /// columns, in elastic models too (system 1 rows only there): the 3D
    /// global form. Measured on TetGen's example: 0.5-1 ms of its 16 ms,
    /// the same sites outside and faces missing their duals on both
    /// backends. The 2D global form keeps them all: lazy elastic rows there
    /// made five of the fuzzed inputs in tests/zigzag fail.
    pub(crate) lazy_aux: bool,
    pub(crate) l2: Vec<f64>,
    pub(crate) rows: Vec<Row>,
    pub(crate) eqs: Vec<Row>,
    /// Where this system is one of many alike (the local form's pieces),
    /// what its solves start from or leave for the others (`warm`).
    pub(crate) warm: Option<std::sync::Arc<super::warm::Warm>>,
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

    /// sum(terms) at the columns' values `x`.
    pub(crate) fn lhs(&self, x: &[f64]) -> f64 {
        self.terms.iter().map(|&(c, v)| v * x[c]).sum()
    }

    /// The face or segment whose rows this row is one of (None: its own).
    fn group(&self) -> Option<(bool, u32)> {
        match (self.family, self.origin) {
            (Family::Sys3(s), _) => Some((true, s)),
            (_, Origin::PlaneAbove { face, .. }) => Some((false, face)),
            _ => None,
        }
    }
}

/// Of the violated rows `enter` (indices into `rows`, with their values,
/// negative), the most violated of each face or segment (by value over
/// the norm of its terms; the first such on ties) and every row of no
/// group, in their order; then the rest, in their order.
pub(crate) fn most_violated(rows: &[Row], enter: &[(usize, f64)]) -> (Vec<usize>, Vec<usize>) {
    let mut best: HashMap<(bool, u32), (f64, usize)> = HashMap::new();
    for &(at, v) in enter {
        let r = &rows[at];
        let Some(g) = r.group() else { continue };
        let norm = r.terms.iter().map(|t| t.1 * t.1).sum::<f64>().sqrt();
        let v = if norm > 0.0 { v / norm } else { v };
        let e = best.entry(g).or_insert((v, at));
        if v < e.0 {
            *e = (v, at);
        }
    }
    enter.iter().map(|e| e.0).partition(|&at| {
        rows[at]
            .group()
            .is_none_or(|g| best.get(&g).is_some_and(|b| b.1 == at))
    })
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
/// vertices `on` (at most two; none for an isolated vertex): every m lies
/// above a hyperplane through their lifts. Its slopes a (relative to p_i)
/// meet a.u_j + w_j - w_i = |u_j|^2 for u_j = p_j - p_i, so a = U G^-1 (b -
/// dw) + N t with G = U^T U, b_j = |u_j|^2, dw_j = w_j - w_i and N spanning
/// the directions normal to every u_j (`complement`): only t is left to
/// the LP, in auxiliary columns, and the equalities are met by
/// construction (measured on TetGen's example: equality rows with free
/// slopes took half of the simplex's iterations).
pub(crate) fn plane_rows<const D: usize>(
    sys: &mut System,
    p: &[[f64; D]],
    face: u32,
    i: u32,
    on: &[u32],
    others: &[u32],
    scale2: f64,
) -> usize {
    let us: Vec<SVector<f64, D>> = on.iter().map(|&j| rel(p, i, j)).collect();
    let normals = complement(&us);
    let a0 = sys.n + sys.aux;
    sys.aux += normals.len();
    let mut at = [u32::MAX; 2];
    at[..on.len()].copy_from_slice(on);
    for &m in others {
        let r = rel(p, i, m);
        let g = gram_solve(&us, &r);
        // |r|^2 - g.b - w_m + w_i + sum_j g_j (w_j - w_i) - (N^T r).t >= delta L
        let gb: f64 = g.iter().zip(&us).map(|(g, u)| g * u.norm_squared()).sum();
        let mut terms = vec![
            (m as usize, -1.0 / scale2),
            (i as usize, (1.0 - g.iter().sum::<f64>()) / scale2),
        ];
        terms.extend(on.iter().zip(&g).map(|(&j, g)| (j as usize, g / scale2)));
        terms.extend(
            normals
                .iter()
                .enumerate()
                .map(|(k, n)| (a0 + k, -n.dot(&r) / scale2)),
        );
        let mut row = Row::sys1(terms, -(r.norm_squared() - gb) / scale2);
        row.origin = Origin::PlaneAbove {
            face,
            i,
            on: at,
            m,
            aux: a0,
        };
        sys.rows.push(row);
    }
    a0
}

/// g = G^-1 U^T r for the Gram matrix G of `us` (at most two vectors); NaN
/// where G is singular (the rows are then left out as not finite).
fn gram_solve<const D: usize>(us: &[SVector<f64, D>], r: &SVector<f64, D>) -> Vec<f64> {
    match us {
        [] => vec![],
        [u] => vec![u.dot(r) / u.norm_squared()],
        [u, v] => {
            let (uu, uv, vv) = (u.dot(u), u.dot(v), v.dot(v));
            let (ur, vr) = (u.dot(r), v.dot(r));
            let det = uu * vv - uv * uv;
            let det = if det == 0.0 { f64::NAN } else { det };
            vec![(vv * ur - uv * vr) / det, (uu * vr - uv * ur) / det]
        }
        _ => unreachable!("a face has at most three vertices on its plane"),
    }
}

/// Directions normal to every vector of `us`, spanning all of them: the
/// axes for none, the normal of a segment in 2D or of a triangle in 3D,
/// and u x e_k for a segment in 3D (three, of rank two: no axis to choose,
/// and the exact rebuild repeats it).
fn complement<const D: usize>(us: &[SVector<f64, D>]) -> Vec<SVector<f64, D>> {
    let from3 = |x: [f64; 3]| SVector::<f64, D>::from_fn(|k, _| x[k]);
    let to3 = |x: &SVector<f64, D>| std::array::from_fn(|k| x[k]);
    match (D, us) {
        (_, []) => (0..D)
            .map(|k| SVector::<f64, D>::from_fn(|c, _| f64::from(u8::from(c == k))))
            .collect(),
        (2, [u]) => vec![SVector::<f64, D>::from_fn(|k, _| {
            if k == 0 {
                -u[1]
            } else {
                u[0]
            }
        })],
        (3, [u]) => (0..3)
            .map(|k| {
                let mut e = [0.0; 3];
                e[k] = 1.0;
                from3(crate::geom::cross_f(to3(u), e))
            })
            .collect(),
        (3, [u, v]) => vec![from3(crate::geom::cross_f(to3(u), to3(v)))],
        _ => unreachable!("a face spans fewer dimensions than its space"),
    }
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

/// A test system: a jittered 8 x 5 lattice, segments between horizontal
/// neighbours, each with system 3 rows for every other point.
#[cfg(test)]
pub(crate) fn jittered_lattice() -> System {
    let p: Vec<[f64; 2]> = (0..40)
        .map(|k| {
            let t = k as f64;
            let (x, y) = ((k % 8) as f64, (k / 8) as f64);
            [x + 0.3 * (t * 1.7).sin(), y + 0.3 * (t * 2.3).cos()]
        })
        .collect();
    let mut sys = System {
        n: p.len(),
        free: vec![true; p.len()],
        verdict: true,
        unit2: 1.0,
        l2: vec![1.0; p.len()],
        ..Default::default()
    };
    for s in 0..10u32 {
        let others: Vec<u32> = (0..p.len() as u32).filter(|&m| m / 2 != s).collect();
        sys.rows.extend(sys3_rows(&p, s, 2 * s, 2 * s + 1, &others));
    }
    sys
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
    fn most_violated_rows_by_face_and_segment() {
        let row = |family, origin, terms: Vec<(usize, f64)>| Row {
            terms,
            rhs: 0.0,
            family,
            share: 1.0,
            outside: false,
            weak: false,
            origin,
        };
        let plane = |face| Origin::PlaneAbove {
            face,
            i: 0,
            on: [1, u32::MAX],
            m: 2,
            aux: 3,
        };
        let rows = vec![
            row(Family::Sys1, plane(0), vec![(0, 1.0)]),
            // more violated by value, less by value over its norm
            row(Family::Sys1, plane(0), vec![(0, 4.0)]),
            row(Family::Sys3(7), Origin::Other, vec![(1, 1.0)]),
            row(Family::Sys3(7), Origin::Other, vec![(1, 1.0)]),
            row(Family::Sys1, Origin::Other, vec![(2, 1.0)]),
            row(Family::Sys1, plane(1), vec![(2, 1.0)]),
        ];
        let enter = [
            (0, -1.0),
            (1, -2.0),
            (2, -0.5),
            (3, -0.5),
            (4, -0.1),
            (5, -0.2),
        ];
        let (now, later) = most_violated(&rows, &enter);
        assert_eq!(now, vec![0, 2, 4, 5]);
        assert_eq!(later, vec![1, 3]);
    }

    #[test]
    fn plane_rows_by_hand() {
        // Segment (0,0)-(2,0) and a point (1,1): the planes through the
        // lifts of the segment's ends have slopes a = (2 - dw/2, t) with
        // dw = w_1 - w_0, written with one slope column t (along (0, 2), the
        // segment's normal, so a_y = 2 t).
        let p = [[0.0, 0.0], [2.0, 0.0], [1.0, 1.0]];
        let mut sys = System {
            n: 3,
            l2: vec![1.0; 3],
            ..Default::default()
        };
        let a0 = plane_rows(&mut sys, &p, 0, 0, &[1], &[2], 4.0);
        assert_eq!((a0, sys.aux, sys.eqs.len()), (3, 1, 0));
        // |r|^2 - w_2 + w_0 - a.r >= delta L with r = (1, 1):
        // 2 - 2 + dw/2 - 2t - w_2 + w_0, over L = 4
        let row = &sys.rows[0];
        assert_eq!(
            row.terms,
            vec![(2, -0.25), (0, 0.125), (1, 0.125), (3, -0.5)]
        );
        assert_eq!(row.rhs, 0.0);
        // a = (2, -1), zero weights: t = -1/2, row value (2 - 1) / 4
        let x = [0.0, 0.0, 0.0, -0.5];
        let value: f64 = row.terms.iter().map(|&(c, k)| k * x[c]).sum::<f64>() - row.rhs;
        assert_eq!(value, 0.25);
    }
}
