//! Exact certificates that a row system has no solution (Farkas). When the
//! LP's margin is not positive, HiGHS' duals name a few rows; they are
//! rebuilt in rationals from the points and a combination of them with
//! non-negative multipliers on the inequalities is solved for exactly, in
//! which every column cancels and the right-hand sides sum to zero or
//! more. No weights then satisfy those rows strictly, so none satisfy the
//! whole system: the verdict is proved, not read off floating point
//! (docs/method.md section 3).

use super::rows::{Family, Origin, Row, System};
use crate::geom::{cross, dot, norm2, q, sub, Q};
use serde::Serialize;
use std::collections::BTreeMap;
#[cfg(test)]
use std::collections::BTreeSet;

/// A verified certificate, by the faces (indices of the caller's) whose
/// rows it combines.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Certificate {
    /// Faces whose system 1 rows it uses: each must be a face of the
    /// regular triangulation.
    pub faces: Vec<u32>,
    /// Faces whose system 3 rows it uses: each must cross its dual.
    pub crossing: Vec<u32>,
    /// Rows combined.
    pub rows: usize,
}

/// A certificate for the report: faces named by their input vertex ids (a
/// segment's two, a triangle's three).
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct Proof {
    /// Faces that must be faces of the regular triangulation.
    pub faces: Vec<Vec<i64>>,
    /// Faces that must cross their duals.
    pub crossing: Vec<Vec<i64>>,
    /// LP rows the certificate combines.
    pub rows: usize,
    /// What the rows assume beyond the input (how facets were cut into
    /// faces, weights tied together); empty when nothing.
    #[serde(skip_serializing_if = "String::is_empty")]
    pub premise: String,
}

impl Certificate {
    /// The certificate with each face named by `name`, under `premise`.
    pub(crate) fn named(&self, name: impl Fn(u32) -> Vec<i64>, premise: &str) -> Proof {
        Proof {
            faces: self.faces.iter().map(|&f| name(f)).collect(),
            crossing: self.crossing.iter().map(|&f| name(f)).collect(),
            rows: self.rows,
            premise: premise.into(),
        }
    }
}

/// Which row of a system a model row is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum RowRef {
    Eq(usize),
    Row(usize),
    /// Rows of phase 2 (anchors): never part of a certificate.
    Other,
}

/// A row's multiplier in an LP's dual solution.
pub(crate) type Duals = Vec<(RowRef, f64)>;

/// Exact terms (column, coefficient) of a row.
pub(crate) type Terms = Vec<(usize, Q)>;

/// Largest number of rows a certificate may combine (an exact dense
/// elimination over them).
const MAX_ROWS: usize = 400;

/// Duals below this fraction of the largest are taken as zero.
const SUPPORT: f64 = 1e-9;

/// One exact row: sum(terms) >= rhs (strictly), or == rhs.
struct Exact {
    terms: BTreeMap<usize, Q>,
    rhs: Q,
    eq: bool,
    share: Q,
    hint: f64,
    row: usize,
}

/// The certificate, when `duals` (of a solve of `sys` whose margin was
/// not positive) lead to one that checks exactly. `points` are the LP's
/// points (exact), `substitute` rewrites weights that depend on others
/// (identity where none do).
pub(crate) fn prove<const D: usize>(
    sys: &System,
    duals: &Duals,
    points: &[[Q; D]],
    substitute: &dyn Fn(Terms) -> Terms,
) -> Option<Certificate> {
    let top = duals.iter().fold(0.0f64, |m, d| m.max(d.1.abs()));
    // Multipliers of inequalities share one sign; make it positive.
    let sign = duals
        .iter()
        .filter(|d| matches!(d.0, RowRef::Row(_)))
        .map(|d| d.1)
        .sum::<f64>()
        .signum();
    let mut rows = vec![];
    for &(at, y) in duals.iter().filter(|d| d.1.abs() > SUPPORT * top) {
        let (r, eq, row) = match at {
            RowRef::Eq(e) => (&sys.eqs[e], true, e),
            RowRef::Row(k) => (&sys.rows[k], false, k),
            RowRef::Other => return None,
        };
        let (terms, rhs) = rebuild(&r.origin, points)?;
        let terms: BTreeMap<usize, Q> = merge(substitute(terms), sys);
        let scale = scale(r, &terms)?;
        rows.push(Exact {
            terms,
            rhs,
            eq,
            share: q(r.share),
            hint: sign * y * scale,
            row,
        });
    }
    if rows.is_empty() || rows.len() > MAX_ROWS || rows.iter().all(|r| r.eq) {
        return None;
    }
    let x = solve(&rows)?;
    let value: Q = rows.iter().zip(&x).map(|(r, x)| &r.rhs * x).sum();
    let signs_ok = rows.iter().zip(&x).all(|(r, x)| r.eq || *x >= 0);
    (signs_ok && value >= 0).then(|| named(sys, &rows, &x))
}

/// Terms merged by column, zeros and fixed weights (zero, not in the LP)
/// dropped.
fn merge(terms: Vec<(usize, Q)>, sys: &System) -> BTreeMap<usize, Q> {
    let mut out: BTreeMap<usize, Q> = BTreeMap::new();
    for (c, v) in terms {
        if c >= sys.n || sys.free[c] {
            *out.entry(c).or_default() += v;
        }
    }
    out.retain(|_, v| *v != 0);
    out
}

/// The positive factor from an exact row to the LP's (which may be
/// scaled by norms the exact row leaves out): multipliers of the LP's row
/// times it are the exact row's.
fn scale(r: &Row, exact: &BTreeMap<usize, Q>) -> Option<f64> {
    let lp: f64 = r.terms.iter().map(|t| t.1.abs()).sum();
    let ex: f64 = exact.values().map(|v| crate::geom::f(v).abs()).sum();
    (ex > 0.0 && lp > 0.0)
        .then_some(lp / ex)
        .filter(|s| s.is_finite())
}

/// The faces a certificate's rows belong to.
fn named(sys: &System, rows: &[Exact], x: &[Q]) -> Certificate {
    let (mut faces, mut crossing) = (vec![], vec![]);
    for (r, x) in rows.iter().zip(x) {
        if *x == 0 {
            continue;
        }
        let row = if r.eq {
            &sys.eqs[r.row]
        } else {
            &sys.rows[r.row]
        };
        match (row.family, row.origin) {
            (Family::Sys3(f), _) => crossing.push(f),
            (_, Origin::PlaneAbove { face, .. }) => faces.push(face),
            _ => {}
        }
    }
    for v in [&mut faces, &mut crossing] {
        v.sort_unstable();
        v.dedup();
    }
    Certificate {
        faces,
        crossing,
        rows: x.iter().filter(|x| **x != 0).count(),
    }
}

/// Multipliers x with sum x_r a_r = 0 in every column and sum over the
/// inequalities of share_r x_r = 1, by exact Gauss-Jordan elimination;
/// unknowns left free take the LP's (rounded) values.
fn solve(rows: &[Exact]) -> Option<Vec<Q>> {
    let cols: Vec<usize> = {
        let mut c: Vec<usize> = rows.iter().flat_map(|r| r.terms.keys().copied()).collect();
        c.sort_unstable();
        c.dedup();
        c
    };
    let k = rows.len();
    // One equation per column, then the normalisation; k unknowns and the
    // right-hand side.
    let mut m: Vec<Vec<Q>> = cols
        .iter()
        .map(|c| {
            let mut e: Vec<Q> = rows
                .iter()
                .map(|r| r.terms.get(c).cloned().unwrap_or_default())
                .collect();
            e.push(Q::default());
            e
        })
        .collect();
    let mut norm: Vec<Q> = rows
        .iter()
        .map(|r| if r.eq { Q::default() } else { r.share.clone() })
        .collect();
    norm.push(Q::from(1));
    m.push(norm);
    let mut pivots = vec![];
    let mut top = 0;
    for col in 0..k {
        let Some(p) = (top..m.len()).find(|&r| m[r][col] != 0) else {
            continue;
        };
        m.swap(top, p);
        let inv = Q::from(1) / &m[top][col];
        for v in m[top].iter_mut() {
            *v *= &inv;
        }
        let pivot_row = m[top].clone();
        for (r, row) in m.iter_mut().enumerate() {
            if r != top && row[col] != 0 {
                let f = row[col].clone();
                for (v, p) in row.iter_mut().zip(&pivot_row) {
                    *v -= &f * p;
                }
            }
        }
        pivots.push(col);
        top += 1;
        if top == m.len() {
            break;
        }
    }
    // An equation 0 = nonzero left: no combination.
    if m[top..].iter().any(|row| row[k] != 0) {
        return None;
    }
    let mut x: Vec<Q> = rows.iter().map(|r| q(r.hint)).collect();
    for (r, &col) in pivots.iter().enumerate() {
        let others: Q = (0..k)
            .filter(|c| !pivots.contains(c))
            .map(|c| &m[r][c] * &x[c])
            .sum();
        x[col] = &m[r][k] - others;
    }
    Some(x)
}

/// A row rebuilt exactly from its origin: terms (weights, then the face's
/// slope columns) and right-hand side; None for rows without one.
pub(crate) fn rebuild<const D: usize>(o: &Origin, p: &[[Q; D]]) -> Option<(Terms, Q)> {
    let pt = |v: u32| &p[v as usize];
    let rel = |a: u32, b: u32| sub(pt(b), pt(a));
    let one = || Q::from(1);
    Some(match *o {
        Origin::Other => return None,
        Origin::PlaneAbove { i, on, m, aux, .. } => {
            let on: Vec<u32> = on.into_iter().filter(|&j| j != u32::MAX).collect();
            let us: Vec<[Q; D]> = on.iter().map(|&j| rel(i, j)).collect();
            let r = rel(i, m);
            let g = gram_solve(&us, &r)?;
            let gb: Q = g.iter().zip(&us).map(|(g, u)| g * norm2(u)).sum();
            let mut t = vec![
                (m as usize, -one()),
                (i as usize, one() - g.iter().sum::<Q>()),
            ];
            t.extend(on.iter().zip(&g).map(|(&j, g)| (j as usize, g.clone())));
            let normals = complement(&us);
            t.extend(
                normals
                    .iter()
                    .enumerate()
                    .map(|(k, n)| (aux + k, -dot(n, &r))),
            );
            (t, gb - norm2(&r))
        }
        Origin::Apart { i, j, up } => {
            let s = if up { one() } else { -one() };
            let t = vec![(i as usize, -s.clone()), (j as usize, s)];
            (t, -norm2(&rel(i, j)))
        }
        Origin::Radical { i, j, m } => {
            // power(m) - power(i) at the radical point, times |u|^2
            let (u, r) = (rel(i, j), rel(i, m));
            let (l, ur) = (norm2(&u), dot(&u, &r));
            let t = vec![
                (i as usize, &l - &ur),
                (j as usize, ur.clone()),
                (m as usize, -l.clone()),
            ];
            (t, -(norm2(&r) - ur) * l)
        }
        Origin::CentreInside { t, a, b } => {
            // Triangles and polygons as faces are 3D only.
            let c = Centre::new(p, t)?;
            let d3 = |x: [Q; D]| -> Option<[Q; 3]> {
                (D == 3).then(|| std::array::from_fn(|k| x[k].clone()))
            };
            // inward in the face's plane (its cycle turns about u x v)
            let normal = cross(&d3(rel(t[0], t[1]))?, &d3(rel(t[0], t[2]))?);
            let n3 = cross(&normal, &d3(rel(a, b))?);
            let n: [Q; D] = std::array::from_fn(|k| n3[k.min(2)].clone());
            let base = dot(&sub(&c.x0, &rel(t[0], a)), &n);
            c.row(base, c.mt(&n), &[])
        }
        Origin::CentreNearer { t, o } => {
            let c = Centre::new(p, t)?;
            let r = rel(t[0], o);
            let base = norm2(&r) - Q::from(2) * dot(&c.x0, &r);
            let g = c.mt(&r);
            let coef = [Q::from(-2) * &g[0], Q::from(-2) * &g[1]];
            c.row(base, coef, &[(o, -one()), (t[0], one())])
        }
    })
}

/// g = G^-1 U^T r exactly, as `rows::plane_rows` computes it in doubles;
/// None where G is singular.
fn gram_solve<const D: usize>(us: &[[Q; D]], r: &[Q; D]) -> Option<Vec<Q>> {
    match us {
        [] => Some(vec![]),
        [u] => {
            let uu = norm2(u);
            (uu != 0).then(|| vec![dot(u, r) / uu])
        }
        [u, v] => {
            let (uu, uv, vv) = (norm2(u), dot(u, v), norm2(v));
            let (ur, vr) = (dot(u, r), dot(v, r));
            let det = &uu * &vv - &uv * &uv;
            (det != 0).then(|| {
                vec![
                    (&vv * &ur - &uv * &vr) / &det,
                    (&uu * &vr - &uv * &ur) / &det,
                ]
            })
        }
        _ => None,
    }
}

/// The directions of `rows::complement`, exactly.
fn complement<const D: usize>(us: &[[Q; D]]) -> Vec<[Q; D]> {
    let from3 = |x: [Q; 3]| -> [Q; D] { std::array::from_fn(|k| x[k].clone()) };
    let to3 = |x: &[Q; D]| -> [Q; 3] { std::array::from_fn(|k| x[k].clone()) };
    let axis = |k: usize| -> [Q; D] { std::array::from_fn(|c| Q::from(u8::from(c == k))) };
    match (D, us) {
        (_, []) => (0..D).map(axis).collect(),
        (2, [u]) => vec![std::array::from_fn(|k| {
            if k == 0 {
                -u[1].clone()
            } else {
                u[0].clone()
            }
        })],
        (3, [u]) => (0..3)
            .map(|k| from3(cross(&to3(u), &to3(&axis(k)))))
            .collect(),
        (3, [u, v]) => vec![from3(cross(&to3(u), &to3(v)))],
        _ => vec![],
    }
}

/// The power centre of a triangle t = (i, j, k) in its plane:
/// p_i + x0 + M (w_i - w_j, w_i - w_k), with M = [u v] G^-1 / 2 for
/// u = p_j - p_i, v = p_k - p_i and their Gram matrix G.
struct Centre<const D: usize> {
    t: [u32; 3],
    /// Columns of M.
    m: [[Q; D]; 2],
    x0: [Q; D],
}

impl<const D: usize> Centre<D> {
    fn new(p: &[[Q; D]], t: [u32; 3]) -> Option<Centre<D>> {
        let (u, v) = (
            sub(&p[t[1] as usize], &p[t[0] as usize]),
            sub(&p[t[2] as usize], &p[t[0] as usize]),
        );
        let (uu, uv, vv) = (norm2(&u), dot(&u, &v), norm2(&v));
        let det = &uu * &vv - &uv * &uv;
        if det == 0 {
            return None;
        }
        let half = Q::from(2) * det;
        // G^-1 / 2 = [vv -uv; -uv uu] / (2 det)
        let col =
            |a: &Q, b: &Q| -> [Q; D] { std::array::from_fn(|k| (&u[k] * a + &v[k] * b) / &half) };
        let m = [col(&vv, &-uv.clone()), col(&-uv.clone(), &uu)];
        let x0 = std::array::from_fn(|k| &m[0][k] * &uu + &m[1][k] * &vv);
        Some(Centre { t, m, x0 })
    }

    /// M^T y.
    fn mt(&self, y: &[Q; D]) -> [Q; 2] {
        [dot(&self.m[0], y), dot(&self.m[1], y)]
    }

    /// base + c . (w_i - w_j, w_i - w_k) + extra >= 0 as terms and rhs.
    fn row(&self, base: Q, c: [Q; 2], extra: &[(u32, Q)]) -> (Terms, Q) {
        let [i, j, k] = self.t.map(|v| v as usize);
        let mut t = vec![(i, &c[0] + &c[1]), (j, -c[0].clone()), (k, -c[1].clone())];
        t.extend(extra.iter().map(|(v, x)| (*v as usize, x.clone())));
        (t, -base)
    }
}

/// Whether an LP row is its exact rebuild times one positive factor, to
/// rounding (tests: the exact rows must say what the LP's say).
#[cfg(test)]
pub(crate) fn agrees<const D: usize>(r: &Row, p: &[[Q; D]]) -> bool {
    let Some((terms, rhs)) = rebuild(&r.origin, p) else {
        return false;
    };
    let mut exact: BTreeMap<usize, f64> = BTreeMap::new();
    for (c, v) in terms {
        *exact.entry(c).or_default() += crate::geom::f(&v);
    }
    let mut lp: BTreeMap<usize, f64> = BTreeMap::new();
    for &(c, v) in &r.terms {
        *lp.entry(c).or_default() += v;
    }
    let (c, v) = exact
        .iter()
        .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
        .map(|(c, v)| (*c, *v))
        .expect("a row has terms");
    let k = lp.get(&c).copied().unwrap_or(0.0) / v;
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * (1.0 + a.abs().max(b.abs()));
    let cols: BTreeSet<usize> = exact.keys().chain(lp.keys()).copied().collect();
    k > 0.0
        && cols.iter().all(|c| {
            close(
                lp.get(c).copied().unwrap_or(0.0),
                k * exact.get(c).copied().unwrap_or(0.0),
            )
        })
        && close(r.rhs, k * crate::geom::f(&rhs))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lp::rows::{plane_rows, sys3_rows};
    use crate::lp::{margin, WeightsReport};

    fn exact<const D: usize>(p: &[[f64; D]]) -> Vec<[Q; D]> {
        p.iter().map(|x| x.map(q)).collect()
    }

    /// A verdict's system over n free weights, no rows yet.
    fn verdict(n: usize) -> System {
        System {
            n,
            free: vec![true; n],
            verdict: true,
            unit2: 1.0,
            l2: vec![1.0; n],
            ..Default::default()
        }
    }

    #[test]
    fn exact_rows_say_what_the_lp_rows_say() {
        let p = [
            [0.1, 0.2, 0.0],
            [0.9, 0.3, 0.1],
            [0.4, 0.8, 0.2],
            [0.5, 0.4, 0.9],
            [-0.3, 0.6, -0.7],
        ];
        let mut sys = System {
            n: 5,
            free: vec![true; 5],
            l2: vec![1.0; 5],
            ..Default::default()
        };
        // a triangle, a segment and a point in 3D: one, three and three
        // slope columns
        plane_rows(&mut sys, &p, 0, 0, &[1, 2], &[3, 4], 0.7);
        plane_rows(&mut sys, &p, 1, 3, &[1], &[0, 2, 4], 0.3);
        plane_rows(&mut sys, &p, 2, 4, &[], &[0, 1], 0.5);
        assert_eq!(sys.aux, 1 + 3 + 3);
        sys.rows.extend(sys3_rows(&p, 1, 0, 1, &[2, 3, 4]));
        let pq = exact(&p);
        assert_eq!((sys.eqs.len(), sys.rows.len()), (0, 2 + 3 + 2 + 5));
        for r in &sys.rows {
            assert!(agrees(r, &pq), "{r:?}");
        }
        // and a segment in 2D: one slope column
        let flat = [[0.1, 0.2], [0.9, 0.3], [0.4, 0.8]];
        let mut sys2 = System {
            n: 3,
            ..Default::default()
        };
        plane_rows(&mut sys2, &flat, 0, 0, &[1], &[2], 0.9);
        assert_eq!(sys2.aux, 1);
        assert!(agrees(&sys2.rows[0], &exact(&flat)));
        // A row whose right-hand side is off is caught.
        let mut off = sys.rows[0].clone();
        off.rhs += 1e-3;
        assert!(!agrees(&off, &pq));
    }

    /// A segment (0, 1) and points off it: system 1 and 3 hold (a
    /// positive margin), so no duals whatever may prove otherwise.
    #[test]
    fn nothing_proves_a_feasible_system_infeasible() {
        let p = [[0.0, 0.0], [1.0, 0.0], [0.5, 0.9], [0.4, -0.8], [2.0, 0.1]];
        let mut sys = verdict(5);
        plane_rows(&mut sys, &p, 0, 0, &[1], &[2, 3, 4], 1.0);
        sys.rows.extend(sys3_rows(&p, 0, 0, 1, &[2, 3, 4]));
        let mut report = WeightsReport::started("test");
        let (m, _, mut lp) = margin(&sys, true, false, &mut report).unwrap();
        assert!(m > 1e-3, "{m}");
        let same = |t: Terms| t;
        let pq = exact(&p);
        assert_eq!(
            prove(&sys, &lp.duals(&sys, &mut report).unwrap(), &pq, &same),
            None
        );
        let every: Duals = (0..sys.rows.len()).map(|k| (RowRef::Row(k), 1.0)).collect();
        assert_eq!(prove(&sys, &every, &pq, &same), None);
    }

    /// Two crossing segments cannot both be edges: at the crossing, each
    /// chord of lifts must lie above the other's. The certificate names
    /// both, exactly.
    #[test]
    fn proves_crossing_segments_are_not_both_edges() {
        let p = [[-1.0, 0.0], [1.0, 0.25], [0.1, -1.0], [-0.2, 1.0]];
        let mut sys = verdict(4);
        plane_rows(&mut sys, &p, 0, 0, &[1], &[2, 3], 1.0);
        plane_rows(&mut sys, &p, 1, 2, &[3], &[0, 1], 1.0);
        let mut report = WeightsReport::started("test");
        let (m, _, mut lp) = margin(&sys, false, false, &mut report).unwrap();
        assert!(m <= crate::lp::TRUST, "{m}");
        let duals = lp.duals(&sys, &mut report).unwrap();
        let proof = prove(&sys, &duals, &exact(&p), &|t| t).expect("a certificate");
        assert_eq!((proof.faces, proof.crossing), (vec![0, 1], vec![]));
        assert!(proof.rows >= 4, "{}", proof.rows);
    }
}
