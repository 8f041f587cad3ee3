//! Polygons kept whole by exact relations (docs/method.md section 6): the
//! weights of each polygon's vertices beyond three fixed by the others, so
//! that their lifts are exactly coplanar; the LP sees only free weights.

use super::d3::ties;
use super::face::Face;
use crate::complex::Complex3;
use crate::geom::{drop_axis, plane_axis, q, Q};
use crate::lp::Row;

/// Exact linear relations between weights, solved for some of them (the
/// dependent ones) in terms of the others (free): the LP sees only the
/// free weights, and the dependent ones are recomputed exactly from the
/// LP's, so that every whole polygon's lift is exactly planar.
pub(super) struct Relations {
    /// (dependent weight, its combination of free weights).
    pub(super) dependent: Vec<(usize, Vec<(usize, Q)>)>,
    /// Per weight, its index in `dependent`.
    pub(super) of: Vec<Option<usize>>,
}

impl Relations {
    pub(super) fn new(n: usize, dependent: Vec<(usize, Vec<(usize, Q)>)>) -> Relations {
        let mut of = vec![None; n];
        for (k, (d, _)) in dependent.iter().enumerate() {
            of[*d] = Some(k);
        }
        Relations { dependent, of }
    }

    pub(super) fn shared(n: usize, faces: &[Face]) -> Relations {
        let tie = ties(n, faces);
        let dependent = (0..n)
            .filter(|&v| tie[v] as usize != v)
            .map(|v| (v, vec![(tie[v] as usize, Q::from(1))]))
            .collect();
        Relations::new(n, dependent)
    }

    /// Polygon vertex d with affine coordinates (r, s, t) over the first
    /// three a, b, c lifts onto their plane when w_d = r w_a + s w_b + t w_c
    /// (the squared norms agree because the vertices are cocircular). The
    /// relations of all polygons, reduced by exact Gauss-Jordan elimination.
    pub(super) fn coplanar(cx: &Complex3, faces: &[Face]) -> Relations {
        type Sparse = std::collections::BTreeMap<usize, Q>;
        // a += x b, zeros dropped
        let axpy = |a: &mut Sparse, x: &Q, b: &Sparse| {
            for (c, y) in b {
                *a.entry(*c).or_insert_with(|| Q::from(0)) += x * y;
            }
            a.retain(|_, v| *v != 0);
        };
        let mut pivots: Vec<(usize, Sparse)> = vec![];
        for f in faces.iter().filter(|f| f.vertices.len() > 3) {
            let vs = &f.vertices;
            let p = |v: u32| cx.points[v as usize];
            let axis = plane_axis(p(vs[0]), p(vs[1]), p(vs[2])).expect("polygons span a plane");
            let fl = |v: u32| drop_axis(axis, p(v)).map(q);
            let det = |x: &[Q; 2], y: &[Q; 2], o: &[Q; 2]| {
                (&x[0] - &o[0]) * (&y[1] - &o[1]) - (&x[1] - &o[1]) * (&y[0] - &o[0])
            };
            let (a, b, c) = (fl(vs[0]), fl(vs[1]), fl(vs[2]));
            let big = det(&b, &c, &a);
            for &d in &vs[3..] {
                let fd = fl(d);
                let s = det(&fd, &c, &a) / &big;
                let t = det(&b, &fd, &a) / &big;
                let r = Q::from(1) - &s - &t;
                let mut row = Sparse::new();
                for (v, x) in [(d, Q::from(1)), (vs[0], -r), (vs[1], -s), (vs[2], -t)] {
                    axpy(&mut row, &x, &Sparse::from([(v as usize, Q::from(1))]));
                }
                for (pc, prow) in &pivots {
                    if let Some(x) = row.get(pc).cloned() {
                        axpy(&mut row, &-x, prow);
                    }
                }
                // pivot on the last weight of the row
                let Some((&pc, pv)) = row.iter().next_back() else {
                    continue; // implied by the others
                };
                let pv = pv.clone();
                row.values_mut().for_each(|x| *x /= &pv);
                for (_, prow) in pivots.iter_mut() {
                    if let Some(x) = prow.get(&pc).cloned() {
                        axpy(prow, &-x, &row);
                    }
                }
                pivots.push((pc, row));
            }
        }
        let dependent = pivots
            .into_iter()
            .map(|(pc, row)| {
                let combo = row
                    .into_iter()
                    .filter(|(c, _)| *c != pc)
                    .map(|(c, x)| (c, -x))
                    .collect();
                (pc, combo)
            })
            .collect();
        Relations::new(cx.points.len(), dependent)
    }

    pub(super) fn free(&self) -> Vec<bool> {
        self.of.iter().map(Option::is_none).collect()
    }

    /// Rows over free weights only (dependent ones replaced by their
    /// combinations, in doubles: the LP's answer is checked exactly).
    pub(super) fn substitute(&self, rows: &mut [Row]) {
        for r in rows {
            let mut merged: Vec<(usize, f64)> = vec![];
            let mut add = |c: usize, x: f64| match merged.iter_mut().find(|t| t.0 == c) {
                Some(t) => t.1 += x,
                None => merged.push((c, x)),
            };
            for &(c, x) in &r.terms {
                match self.of.get(c).copied().flatten() {
                    Some(k) => {
                        for (f, y) in &self.dependent[k].1 {
                            add(*f, x * crate::geom::f(y));
                        }
                    }
                    None => add(c, x),
                }
            }
            r.terms = merged;
        }
    }

    /// Exact terms over free weights only (dependent ones replaced by
    /// their combinations), for `lp::prove`.
    pub(super) fn substitute_exact(&self, terms: Vec<(usize, Q)>) -> Vec<(usize, Q)> {
        let mut out = vec![];
        for (c, x) in terms {
            match self.of.get(c).copied().flatten() {
                Some(k) => out.extend(self.dependent[k].1.iter().map(|(f, y)| (*f, &x * y))),
                None => out.push((c, x)),
            }
        }
        out
    }

    /// The LP's weights as exact rationals, the dependent ones recomputed.
    pub(super) fn exact(&self, w: &[f64]) -> Vec<Q> {
        let mut out: Vec<Q> = w.iter().map(|&x| q(x)).collect();
        for (d, combo) in &self.dependent {
            out[*d] = combo.iter().map(|(c, x)| x * &out[*c]).sum();
        }
        out
    }
}
