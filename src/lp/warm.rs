//! Warm starts from a similar piece. The local form's pieces repeat where
//! the input does: the cavities of a grid around wells of one pattern,
//! the cells of a lattice. Pieces whose rows have the same pattern (the
//! same free weights in each row, in the same families) are alike: the
//! first of them is solved as any piece, its basis kept after each solve
//! of its ladder; each of the others starts the same solve
//! from that basis, its rows matched by pattern. HiGHS still solves every
//! piece from there, and the exact check of RT(w) still judges the
//! weights: only the start changes. Measured on `generate mixed 20` (400
//! pieces, 75 patterns): 41,388 simplex iterations -> 12,892.
//! Deterministic: a piece's start depends on its pattern's first piece
//! alone, which is solved before the others.
//! Where the first piece's weights already meet every row of another at
//! the margin its own LP guaranteed (translates of one cavity, equal but
//! for rounding), that piece takes them and no LP runs (`serves`).

use super::highs::{Basis, Lp};
use super::proof::RowRef;
use super::{Family, Row, System, WeightsReport};
use crate::error::Result;
use crate::FastMap;
use std::hash::{Hash, Hasher};
use std::sync::{Arc, Mutex};

/// Which solve of a ladder: a margin rung (the bits of its k; None:
/// unbounded), phase 2, or another (never warm-started).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Stage {
    Margin(Option<u64>),
    Phase2,
    Other,
}

/// A solve's end: its stage, the key of each model row, the basis.
#[derive(Debug)]
pub(crate) struct Step {
    stage: Stage,
    rows: Vec<u64>,
    basis: Basis,
}

/// A system's part in warm starts.
#[derive(Debug, Default)]
pub(crate) struct Warm {
    /// One key per row (rows, then eqs): its pattern and its rank among
    /// the rows of that pattern (ordered by their coefficients).
    keys: Vec<u64>,
    /// The steps of a similar system, to start from.
    from: Option<Arc<Vec<Step>>>,
    /// Where this system's steps go, when others start from them.
    record: Option<Mutex<Vec<Step>>>,
}

fn hash(x: impl Hash) -> u64 {
    let mut h = rustc_hash::FxHasher::default();
    x.hash(&mut h);
    h.finish()
}

/// A row's pattern: its columns, its family, whether a model leaves it
/// lazy, whether it carries the margin.
fn pattern(r: &Row, eq: bool) -> u64 {
    let mut cols: Vec<usize> = r.terms.iter().map(|t| t.0).collect();
    cols.sort_unstable();
    let family = match r.family {
        Family::Sys1 => 0u8,
        Family::Sys3(_) => 1,
        Family::Anchor => 2,
    };
    hash((cols, family, eq, r.share > 0.0))
}

/// Orders rows of one pattern by their coefficients, then right-hand side.
fn by_values(a: &Row, b: &Row) -> std::cmp::Ordering {
    let va = a.terms.iter().map(|t| t.1).chain([a.rhs]);
    let vb = b.terms.iter().map(|t| t.1).chain([b.rhs]);
    va.zip(vb)
        .map(|(x, y)| x.total_cmp(&y))
        .find(|o| o.is_ne())
        .unwrap_or(a.terms.len().cmp(&b.terms.len()))
}

/// The system's pattern (equal for similar systems) and its rows' keys.
pub(crate) fn keys(sys: &System) -> (u64, Vec<u64>) {
    let all: Vec<(&Row, bool)> = (sys.rows.iter().map(|r| (r, false)))
        .chain(sys.eqs.iter().map(|r| (r, true)))
        .collect();
    let shape: Vec<u64> = all.iter().map(|&(r, eq)| pattern(r, eq)).collect();
    let mut order: Vec<usize> = (0..all.len()).collect();
    order.sort_by(|&a, &b| {
        shape[a]
            .cmp(&shape[b])
            .then_with(|| by_values(all[a].0, all[b].0))
    });
    let mut keys = vec![0; all.len()];
    let mut rank = 0u64;
    for (j, &i) in order.iter().enumerate() {
        rank = match j {
            0 => 0,
            _ if shape[order[j - 1]] == shape[i] => rank + 1,
            _ => 0,
        };
        keys[i] = hash((shape[i], rank));
    }
    let sorted: Vec<u64> = order.iter().map(|&i| shape[i]).collect();
    (hash((sys.n, sys.rows.len(), sorted)), keys)
}

/// How much of the first piece's phase-2 margin a piece that takes its
/// weights may lose to rounding (relative): translates of one cavity
/// measured 1e-12.
const SERVES_SLACK: f64 = 1e-9;

/// Whether the weights `w` of a similar system, answered with the report
/// `by`, serve `sys` as they are: every row of it (finite, as models take
/// them) holds with half the margin `by` found, as phase 2 makes its own
/// rows hold, and within its rung's bound. Systems with equalities,
/// anchors or auxiliary columns are always solved.
pub(crate) fn serves(sys: &System, w: &[f64], by: &WeightsReport) -> bool {
    let Some(margin) = by.margin.filter(|&m| m > super::TRUST) else {
        return false;
    };
    let plain = sys.eqs.is_empty() && sys.aux == 0 && w.len() == sys.n;
    if !plain || sys.rows.iter().any(|r| r.family == Family::Anchor) {
        return false;
    }
    // Weights come back in the input's units (`System::unit2`).
    let w: Vec<f64> = w.iter().map(|x| x / sys.unit2).collect();
    let bounded = |(i, x): (usize, &f64)| match by.bound_k {
        _ if !sys.free[i] => *x == 0.0,
        Some(k) => x.abs() <= k * sys.l2[i],
        None => true,
    };
    let delta = margin / 2.0 * (1.0 - SERVES_SLACK);
    let holds = |r: &Row| r.lhs(&w) - r.share * delta >= r.rhs;
    w.iter().enumerate().all(bounded) && sys.rows.iter().filter(super::finite).all(holds)
}

impl WeightsReport {
    /// The report of a piece that took the weights of the similar piece
    /// that answered with `by` (`serves`): its margin, bound and status.
    pub(crate) fn served_by(by: &WeightsReport) -> WeightsReport {
        WeightsReport {
            lp_status: by.lp_status.clone(),
            margin: by.margin,
            bound_k: by.bound_k,
            lp_served: 1,
            ..Default::default()
        }
    }
}

impl Warm {
    /// The part of the first of its pattern, whose steps `others` use
    /// (none: nothing kept).
    pub(crate) fn leader(keys: Vec<u64>, others: bool) -> Warm {
        Warm {
            keys,
            from: None,
            record: others.then(|| Mutex::new(vec![])),
        }
    }

    /// The steps this leader kept (taken: once its solves are done).
    pub(crate) fn steps(&self) -> Option<Arc<Vec<Step>>> {
        let record = self.record.as_ref()?;
        let steps = std::mem::take(&mut *record.lock().unwrap_or_else(|e| e.into_inner()));
        Some(Arc::new(steps))
    }

    /// The part of a system that starts from a leader's `steps`.
    pub(crate) fn follower(keys: Vec<u64>, steps: Option<Arc<Vec<Step>>>) -> Warm {
        Warm {
            keys,
            from: steps,
            record: None,
        }
    }
}

impl Lp {
    /// The keys of the model's rows, in order (phase 2's anchor rows by
    /// their order).
    fn row_keys(&self, sys: &System, warm: &Warm) -> Vec<u64> {
        let mut other = 0u64;
        let n = sys.rows.len();
        (self.refs.iter())
            .map(|r| match *r {
                RowRef::Row(at) => warm.keys[at],
                RowRef::Eq(at) => warm.keys[n + at],
                RowRef::Other => {
                    other += 1;
                    hash(("other", other))
                }
            })
            .collect()
    }

    /// Before a solve: where a similar system's next step is this stage,
    /// the lazy rows it had in its model enter this one, and its basis is
    /// this model's start, row by row where keys match (other rows
    /// basic). Where the statuses do not make a basis by count, the
    /// model's own stays. A ladder that goes another way stops here.
    pub(crate) fn warm_start(&mut self, sys: &System) -> Result<()> {
        let Some(warm) = sys.warm.as_deref() else {
            return Ok(());
        };
        let Some(from) = warm.from.as_deref() else {
            return Ok(());
        };
        let Some(step) = from.get(self.hinted).filter(|s| s.stage == self.stage) else {
            self.hinted = usize::MAX;
            return Ok(());
        };
        self.hinted += 1;
        let status: FastMap<u64, highs_sys::HighsInt> = step
            .rows
            .iter()
            .copied()
            .zip(step.basis.1.iter().copied())
            .collect();
        let (enter, keep): (Vec<usize>, Vec<usize>) =
            (self.lazy.iter()).partition(|&&at| status.contains_key(&warm.keys[at]));
        self.add_rows(sys, &enter)?;
        self.lazy = keep;
        let basic = highs_sys::kHighsBasisStatusBasic as highs_sys::HighsInt;
        let rows: Vec<highs_sys::HighsInt> = (self.row_keys(sys, warm).iter())
            .map(|k| status.get(k).copied().unwrap_or(basic))
            .collect();
        let cols = &step.basis.0;
        let model = self.model.as_mut().expect("model");
        let basics = cols.iter().chain(&rows).filter(|&&s| s == basic).count();
        if cols.len() == model.num_cols() && basics == rows.len() {
            self.set_basis((cols.clone(), rows));
        }
        Ok(())
    }

    /// After a solve: its step, where others start from this system's.
    pub(crate) fn record(&mut self, sys: &System) {
        let Some(warm) = sys.warm.as_deref() else {
            return;
        };
        let Some(record) = &warm.record else {
            return;
        };
        let step = Step {
            stage: self.stage,
            rows: self.row_keys(sys, warm),
            basis: self.basis(),
        };
        record.lock().unwrap_or_else(|e| e.into_inner()).push(step);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lp::{jittered_lattice, solve_rows, Answer, WeightsReport};

    fn solve(sys: &System) -> (Vec<f64>, usize) {
        let mut report = WeightsReport::started("test");
        match solve_rows(sys, false, &mut report).unwrap() {
            Answer::Weights(w, ..) => (w, report.lp_iterations),
            _ => panic!("no weights"),
        }
    }

    /// A copy of a system with its rows in another order and its
    /// coefficients rounded otherwise (a translated piece) has the same
    /// pattern, its rows the keys of the rows they copy; started from the
    /// first one's steps, it reaches the same weights in few iterations.
    #[test]
    fn a_similar_system_starts_from_the_first_ones_bases() {
        let mut first = jittered_lattice();
        first.verdict = false;
        let mut copy = first.clone();
        copy.rows.reverse();
        for r in &mut copy.rows {
            r.terms.iter_mut().for_each(|t| t.1 *= 1.0 + 1e-13);
            r.rhs *= 1.0 - 1e-13;
        }
        let ((s1, k1), (s2, k2)) = (keys(&first), keys(&copy));
        assert_eq!(s1, s2);
        let n = k1.len();
        assert!((0..n).all(|i| k1[i] == k2[n - 1 - i]));
        let mut distinct = k1.clone();
        distinct.sort_unstable();
        distinct.dedup();
        assert_eq!(distinct.len(), n);

        let alone = solve(&copy).1;
        first.warm = Some(Arc::new(Warm::leader(k1, true)));
        let (w1, it1) = solve(&first);
        let steps = first.warm.as_ref().and_then(|w| w.steps());
        assert!(steps.as_ref().is_some_and(|s| s.len() >= 2));
        copy.warm = Some(Arc::new(Warm::follower(k2, steps)));
        let (w2, it2) = solve(&copy);
        eprintln!("iterations: {alone} alone, {it1} first, {it2} from its steps");
        assert!(alone > 20 && it1 == alone, "{alone} {it1}");
        assert!(4 * it2 <= alone, "{it2} from the steps, {alone} alone");
        let far = (w1.iter().zip(&w2)).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        assert!(far <= 1e-9, "{far}");
    }

    /// A re-rounded copy of a system takes the first one's weights as they
    /// are; a copy one of whose rows they no longer meet at half the
    /// margin is solved.
    #[test]
    fn weights_serve_a_copy_only_where_every_row_holds() {
        let mut first = jittered_lattice();
        first.verdict = false;
        let mut report = WeightsReport::started("test");
        let Answer::Weights(w, ..) = solve_rows(&first, false, &mut report).unwrap() else {
            panic!("no weights")
        };
        let margin = report.margin.unwrap();
        assert!(margin > 1e-3, "{margin}");
        let mut copy = first.clone();
        for r in &mut copy.rows {
            r.terms.iter_mut().for_each(|t| t.1 *= 1.0 + 1e-13);
        }
        assert!(serves(&first, &w, &report) && serves(&copy, &w, &report));
        // The tightest row asked for a quarter of the margin more.
        let value = |r: &Row| r.lhs(&w) - r.rhs;
        let tight = (0..copy.rows.len())
            .min_by(|&a, &b| value(&copy.rows[a]).total_cmp(&value(&copy.rows[b])))
            .unwrap();
        copy.rows[tight].rhs += margin / 4.0;
        assert!(!serves(&copy, &w, &report));
        // Nor where the system has an equality, or a weight beyond its bound.
        let mut eq = first.clone();
        eq.eqs.push(first.rows[0].clone());
        assert!(!serves(&eq, &w, &report));
        let bounded = WeightsReport {
            bound_k: Some(1e-9),
            ..report.clone()
        };
        assert!(w.iter().any(|x| x.abs() > 1e-9) && !serves(&first, &w, &bounded));
    }
}
