//! One HiGHS model of a row system, kept across phase 1's k ladder and
//! phase 2, warm-started from its basis.

use super::instance::{self, Col, Problem};
use super::proof::{Duals, RowRef};
use super::warm::Stage;
use super::{
    finite, Family, Row, System, WeightsReport, ANCHOR_COST, ELASTIC_ROW_MARGIN, LAZY_SLACK,
    LP_BUDGET,
};
use crate::error::{Error, Result};
use highs::{HighsModelStatus, Sense};
use std::collections::HashMap;
use std::ops::Bound;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

pub(crate) enum Mode {
    /// Maximise delta (as minimise -delta).
    Margin,
    /// System 1 with delta >= min; system 3 rows elastic, minimise the
    /// violation, segment s weighted by costs[s] (1 where absent).
    Elastic {
        delta_min: f64,
        costs: HashMap<u32, f64>,
    },
}

/// A basis: column statuses, row statuses (HiGHS' constants).
pub(crate) type Basis = (Vec<highs_sys::HighsInt>, Vec<highs_sys::HighsInt>);

#[derive(Clone)]
pub(crate) struct Solution {
    pub(crate) delta: f64,
    pub(crate) w: Vec<f64>,
    /// Elastic mode: the violation of system 3 per segment.
    pub(crate) slack: HashMap<u32, f64>,
}

/// HiGHS runs (shared) and instance drops (exclusive), see `Lp::solve`.
pub(crate) static HIGHS: std::sync::RwLock<()> = std::sync::RwLock::new(());

/// One HiGHS model of a row system, kept across phase 1's k ladder and
/// phase 2. Each free weight is the difference of two non-negative columns,
/// w_i = p_i - q_i, so that phase 2's objective sum (p_i + q_i) / l_i^2
/// (which is sum |w_i| / l_i^2 at the optimum) needs no rows: going from
/// phase 1 to phase 2 changes only costs and delta's bounds, phase 1's
/// optimal basis stays feasible, and the primal simplex goes on from it
/// (measured on the local form's pieces: phase 2 had cost more than phase
/// 1, from scratch or with |w_i| as rows).
pub(crate) struct Lp {
    pub(crate) model: Option<highs::Model>,
    /// Per weight, its columns (p, q); None for fixed weights, which are
    /// zero and left out of the rows.
    pub(crate) w: Vec<Option<(Col, Col)>>,
    /// The auxiliary columns (supporting planes' free slopes).
    pub(crate) aux: Vec<Col>,
    pub(crate) delta: Col,
    /// Elastic mode: the violation column of each segment.
    pub(crate) slack: HashMap<u32, Col>,
    /// Rows of `sys.rows` not in the model yet (see `LAZY_SLACK`).
    pub(crate) lazy: Vec<usize>,
    /// Whether the next solve is the dual simplex (see `Lp::simplex`).
    pub(crate) dual: bool,
    /// The system's row behind each model row, in order.
    pub(crate) refs: Vec<RowRef>,
    /// Whether delta starts bounded below (`margin_floor`).
    pub(crate) floor: bool,
    /// Violated lazy rows above which not all enter at once (`ENTER_ALL`;
    /// none once rows have entered).
    pub(crate) enter_all: usize,
    /// Which solve of the ladder comes next (`warm`).
    pub(crate) stage: Stage,
    /// The next of a similar piece's steps to start from (`warm`; past
    /// the end once this model's ladder went another way).
    pub(crate) hinted: usize,
}

thread_local! {
    /// This thread's finished models, destroyed together (`Drop for Lp`).
    static FINISHED: std::cell::RefCell<Vec<highs::Model>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// Models destroyed at once. Destroying a HiGHS instance resets its global
/// scheduler, which must not happen while another thread is inside HiGHS
/// (ERGO-Code/HiGHS#3141): drops take the lock exclusively and so wait for
/// the other threads' running solves. One at a time, that serialised the
/// local form's parallel pieces.
pub(crate) const DROP_BATCH: usize = 64;

impl Drop for Lp {
    fn drop(&mut self) {
        let Some(model) = self.model.take() else {
            return;
        };
        // Kept for this thread's next model where it keeps few.
        let Some(model) = instance::keep(model) else {
            return;
        };
        let batch = FINISHED.with_borrow_mut(|f| {
            f.push(model);
            (f.len() >= DROP_BATCH).then(|| std::mem::take(f))
        });
        if let Some(batch) = batch {
            let _alone = HIGHS.write().unwrap_or_else(|e| e.into_inner());
            drop(batch);
        }
    }
}

/// Destroys the finished models that wait, on this thread and on every
/// thread of rayon's pool (at the end of a weights step); the pool's as
/// soon as its threads are free, off the caller's path (measured: 0.2 ms
/// of TetGen's example).
pub(crate) fn destroy_finished() {
    fn flush() {
        let mut batch = FINISHED.with_borrow_mut(std::mem::take);
        batch.extend(instance::kept());
        if !batch.is_empty() {
            let _alone = HIGHS.write().unwrap_or_else(|e| e.into_inner());
            drop(batch);
        }
    }
    flush();
    rayon::spawn(|| {
        rayon::broadcast(|_| flush());
    });
}

/// A row as model terms: weights (columns below `n`) as p - q (v w_c is
/// v p_c - v q_c, nothing for a fixed weight), auxiliary columns as they
/// are. Without allocations: a model has thousands of rows.
fn model_terms<'a>(
    r: &'a Row,
    n: usize,
    w: &'a [Option<(Col, Col)>],
    aux: &'a [Col],
) -> impl Iterator<Item = (Col, f64)> + 'a {
    r.terms.iter().flat_map(move |&(c, v)| {
        let pair = match (c.checked_sub(n), w.get(c).copied().flatten()) {
            (Some(a), _) => [Some((aux[a], v)), None],
            (None, Some((p, q))) => [Some((p, v)), Some((q, -v))],
            (None, None) => [None, None],
        };
        pair.into_iter().flatten()
    })
}

/// A row over weights alone (no auxiliary columns) as model terms.
pub(crate) fn weight_row(w: &[Option<(Col, Col)>], r: &Row) -> Vec<(Col, f64)> {
    model_terms(r, w.len(), w, &[]).collect()
}

/// New values for columns: bounds (lower, upper) or costs, one per column.
pub(crate) enum Change<'a> {
    Bounds(&'a [f64], &'a [f64]),
    Costs(&'a [f64]),
}

/// Changes many columns in one HiGHS call: the crate changes one at a
/// time, and HiGHS invalidates its solution and info at every call
/// (measured: 6% of the pieces' instructions).
#[allow(unsafe_code)]
pub(crate) fn change_columns(model: &mut highs::Model, cols: &[Col], change: Change) -> Result<()> {
    let set: Vec<highs_sys::HighsInt> = cols.iter().map(|c| c.index() as _).collect();
    let n = set.len() as highs_sys::HighsInt;
    let ptr = model.as_mut_ptr();
    // SAFETY: `ptr` is the model's live HiGHS instance, `set` holds its
    // columns, and every array given has set.len() entries (asserted).
    let status = match change {
        Change::Bounds(lower, upper) => {
            assert!(lower.len() == set.len() && upper.len() == set.len());
            unsafe {
                highs_sys::Highs_changeColsBoundsBySet(
                    ptr,
                    n,
                    set.as_ptr(),
                    lower.as_ptr(),
                    upper.as_ptr(),
                )
            }
        }
        Change::Costs(cost) => {
            assert_eq!(cost.len(), set.len());
            unsafe { highs_sys::Highs_changeColsCostBySet(ptr, n, set.as_ptr(), cost.as_ptr()) }
        }
    };
    if status == highs_sys::STATUS_ERROR {
        return Err(Error::SolverLimit(
            "HiGHS refused to change the LP's columns".into(),
        ));
    }
    Ok(())
}

/// The error of a cancelled run (never shown: the caller discards it).
fn cancelled() -> Error {
    Error::Internal("an LP run was cancelled but its result was used".into())
}

/// HiGHS' simplex interrupt: asks to stop once the flag is raised.
#[allow(unsafe_code)]
unsafe extern "C" fn interrupt(
    _kind: std::os::raw::c_int,
    _message: *const std::os::raw::c_char,
    _out: *const highs_sys::HighsCallbackDataOut,
    data_in: *mut highs_sys::HighsCallbackDataIn,
    flag: *mut std::os::raw::c_void,
) {
    // SAFETY: `flag` is the flags that `run_model` registered, alive and
    // unchanged for the run; `data_in` is HiGHS' own, non-null for
    // interrupt callbacks.
    unsafe {
        let flags = &*(flag as *const Vec<Arc<AtomicBool>>);
        if flags.iter().any(|f| f.load(Ordering::Relaxed)) && !data_in.is_null() {
            (*data_in).user_interrupt = 1;
        }
    }
}

/// Runs HiGHS on the model in place: its status, and its columns when
/// optimal. Where HiGHS fails (a singular basis in a badly scaled warm
/// start, say), it runs from scratch closer to its defaults (the dual
/// simplex, its refactorisation checks), with presolve and then without;
/// a third failure is an error that says so. A simplex run past `stall`
/// iterations is stalled: it runs again from scratch with presolve.
#[allow(unsafe_code)]
fn run_model(model: &mut highs::Model, stall: i32) -> Result<(HighsModelStatus, Option<Vec<f64>>)> {
    let ptr = model.as_mut_ptr();
    let stop = super::cancel::flags();
    let raised = || stop.iter().any(|s| s.load(Ordering::Relaxed));
    if !stop.is_empty() {
        if raised() {
            return Err(cancelled());
        }
        // SAFETY: `ptr` is live; the flags outlive the run (`stop` holds
        // them and is not touched until the run ends).
        unsafe {
            let data = &stop as *const Vec<Arc<AtomicBool>> as *mut std::os::raw::c_void;
            highs_sys::Highs_setCallback(ptr, Some(interrupt), data);
            highs_sys::Highs_startCallback(ptr, highs_sys::kHighsCallbackSimplexInterrupt);
        }
    }
    model.set_option("simplex_iteration_limit", stall);
    // SAFETY: `ptr` is the model's live HiGHS instance.
    let mut ran = unsafe { highs_sys::Highs_run(ptr) };
    model.set_option("simplex_iteration_limit", i32::MAX);
    if ran != highs_sys::STATUS_ERROR
        && status_of(model)? == HighsModelStatus::ReachedIterationLimit
    {
        // Stalled: from scratch, with presolve (measured: a warm dual solve
        // of 12,121 rows on the pure backend's SPE9 well at 85 degrees ran
        // over 5 minutes; it stops after 25 s, and presolved takes 2.3 s).
        // SAFETY: as above; clearing the solver keeps the model.
        unsafe { highs_sys::Highs_clearSolver(ptr) };
        model.set_option("presolve", "on");
        // SAFETY: as above.
        ran = unsafe { highs_sys::Highs_run(ptr) };
        model.set_option("presolve", "off");
    }
    if !stop.is_empty() {
        // SAFETY: as above; the callback's data dies with this frame.
        unsafe {
            highs_sys::Highs_stopCallback(ptr, highs_sys::kHighsCallbackSimplexInterrupt);
        }
    }
    if raised() {
        return Err(cancelled());
    }
    // Where it fails, from scratch: with presolve, then without (measured,
    // two fuzzed wells: a cavity whose widened rows span 1e-9 to 2e5 is
    // solved only with presolve, another only without, where the primal
    // simplex failed on postsolve's basis).
    for presolve in ["on", "off"] {
        if ran != highs_sys::STATUS_ERROR {
            break;
        }
        // SAFETY: as above; clearing the solver keeps the model.
        unsafe { highs_sys::Highs_clearSolver(ptr) };
        model.set_option("presolve", presolve);
        model.set_option("solver", "simplex");
        model.set_option("simplex_strategy", 1);
        model.set_option("rebuild_refactor_solution_error_tolerance", 1e-8);
        // Entries below this are rounding noise in rows whose largest terms
        // are 1 to 1e5 (rows scaled by their face's size); the first case
        // above is not solved with them.
        model.set_option("small_matrix_value", 1e-7);
        // SAFETY: as above.
        ran = unsafe { highs_sys::Highs_run(model.as_mut_ptr()) };
    }
    if ran == highs_sys::STATUS_ERROR {
        return Err(Error::SolverLimit(format!(
            "HiGHS failed on an LP of {} rows and {} columns, warm-started, and from scratch with and without presolve",
            model.num_rows(),
            model.num_cols()
        )));
    }
    let status = status_of(model)?;
    if status != HighsModelStatus::Optimal {
        return Ok((status, None));
    }
    Ok((status, Some(columns(model))))
}

/// A simplex run stalls after this many iterations plus so many per row
/// (measured: at most 1.8 per row on the 3D global forms of tests/fields3,
/// hybrid3 and layered3, 18,381 on 10,090 rows).
const STALL: [i32; 2] = [5_000, 2];

#[allow(unsafe_code)]
fn status_of(model: &mut highs::Model) -> Result<HighsModelStatus> {
    // SAFETY: `model` is a live HiGHS instance.
    let code = unsafe { highs_sys::Highs_getModelStatus(model.as_mut_ptr()) };
    HighsModelStatus::try_from(code as std::os::raw::c_int)
        .map_err(|_| Error::SolverLimit(format!("HiGHS returned an unknown model status {code}")))
}

/// The simplex iterations of a model's last run.
#[allow(unsafe_code)]
fn iterations(model: &mut highs::Model) -> usize {
    let mut count: highs_sys::HighsInt = 0;
    // SAFETY: a live instance, a name HiGHS knows, an int it writes.
    unsafe {
        highs_sys::Highs_getIntInfoValue(
            model.as_mut_ptr(),
            c"simplex_iteration_count".as_ptr(),
            &mut count,
        )
    };
    usize::try_from(count).unwrap_or(0)
}

/// The column values of a model's last solution.
#[allow(unsafe_code)]
pub(crate) fn columns(model: &mut highs::Model) -> Vec<f64> {
    let mut cols = vec![0.0; model.num_cols()];
    let none = std::ptr::null_mut();
    // SAFETY: the model's live instance; `cols` has its column count, which
    // HiGHS fills; it skips the arrays given as null (duals and row values).
    unsafe {
        highs_sys::Highs_getSolution(model.as_mut_ptr(), cols.as_mut_ptr(), none, none, none)
    };
    cols
}

/// A lower bound of a simplex model's margin: the margin that zero
/// weights reach, where that is nearer zero than delta's upper bound 1.
/// HiGHS starts a boxed column at its bound nearer zero, so delta starts
/// here and the slack basis meets every margin row (measured: 2% fewer
/// instructions). The optimum is the same: zero weights reach this margin.
pub(crate) fn margin_floor(sys: &System, with3: bool, big: bool) -> Bound<f64> {
    let floor = sys
        .rows
        .iter()
        .filter(finite)
        .filter(|r| r.share > 0.0 && margin_row(r, with3))
        .map(|r| -r.rhs / r.share)
        .fold(f64::INFINITY, f64::min);
    if big || floor.is_nan() || floor.abs() >= 1.0 {
        Bound::Unbounded
    } else {
        Bound::Included(floor)
    }
}

/// A lower bound as a number (unbounded: minus infinity).
fn lowest(b: Bound<f64>) -> f64 {
    match b {
        Bound::Included(x) | Bound::Excluded(x) => x,
        Bound::Unbounded => f64::NEG_INFINITY,
    }
}

/// Whether a row is one of the model's margin rows: system 1's, and
/// system 3's when asked for (anchors are elastic rows of phase 2).
pub(crate) fn margin_row(r: &Row, with3: bool) -> bool {
    match r.family {
        Family::Anchor => false,
        Family::Sys3(_) => with3,
        Family::Sys1 => true,
    }
}

/// Upper bound of p_i and q_i (>= 0) for |w_i| <= k l_i^2 (k None:
/// unbounded).
pub(crate) fn part_upper(sys: &System, i: usize, k: Option<f64>) -> f64 {
    k.map_or(f64::INFINITY, |k| k * sys.l2[i])
}

impl Lp {
    /// The model of `sys` in `mode` (Margin or Elastic; phase 2 comes from
    /// a Margin model through `regularise`).
    pub(crate) fn build(sys: &System, with3: bool, k: Option<f64>, mode: &Mode) -> Result<Lp> {
        let mut pb = Problem::default();
        let free = (f64::NEG_INFINITY, f64::INFINITY);
        let w: Vec<_> = (0..sys.n)
            .map(|i| {
                sys.free[i].then(|| {
                    let b = (0.0, part_upper(sys, i, k));
                    (pb.add_column(0.0, b), pb.add_column(0.0, b))
                })
            })
            .collect();
        let aux: Vec<_> = (0..sys.aux).map(|_| pb.add_column(0.0, free)).collect();
        let big = super::is_big(sys);
        let floor = match mode {
            Mode::Margin => margin_floor(sys, with3, big),
            Mode::Elastic { .. } => Bound::Unbounded,
        };
        let (delta, sense) = match mode {
            // Minimise -delta: HiGHS' dual simplex stops at an objective
            // bound on minimisations only (`solve_once`).
            Mode::Margin => (pb.add_column(-1.0, (lowest(floor), 1.0)), Sense::Minimise),
            Mode::Elastic { delta_min, .. } => (
                pb.add_column(0.0, (*delta_min, 1.0f64.max(*delta_min))),
                Sense::Minimise,
            ),
        };
        let terms = |r| model_terms(r, sys.n, &w, &aux);
        let mut slack = HashMap::new();
        let mut refs = vec![];
        for (at, r) in sys.eqs.iter().enumerate().filter(|(_, r)| finite(r)) {
            pb.add_row((r.rhs, r.rhs), terms(r));
            refs.push(RowRef::Eq(at));
        }
        let lazy_ok = !big && ((matches!(mode, Mode::Margin) && sys.aux == 0) || sys.lazy_aux);
        let mut lazy = vec![];
        for (at, r) in sys.rows.iter().enumerate().filter(|(_, r)| finite(r)) {
            match (r.family, mode) {
                // Anchors (elastic in phase 2 only, `regularise`), and
                // system 3 unless asked for.
                _ if !margin_row(r, with3) => continue,
                // A margin row; its slack at zero weights and margin is -rhs.
                // (an elastic model's system 3 rows have their slacks)
                (Family::Sys3(s), Mode::Elastic { costs, .. }) => {
                    // sum(terms) + slack_s >= rhs + small positive margin
                    // (the slack column exists even while its rows are lazy)
                    let cost = costs.get(&s).copied().unwrap_or(1.0);
                    let sl = *slack
                        .entry(s)
                        .or_insert_with(|| pb.add_column(cost, (0.0, f64::INFINITY)));
                    if lazy_ok && -r.rhs > LAZY_SLACK {
                        lazy.push(at);
                        continue;
                    }
                    let low = r.rhs + ELASTIC_ROW_MARGIN;
                    pb.add_row((low, f64::INFINITY), terms(r).chain([(sl, 1.0)]));
                    refs.push(RowRef::Row(at));
                }
                _ if lazy_ok && -r.rhs > LAZY_SLACK => lazy.push(at),
                _ => {
                    pb.add_row((r.rhs, f64::INFINITY), terms(r).chain([(delta, -r.share)]));
                    refs.push(RowRef::Row(at));
                }
            }
        }
        let mut model = pb.pass()?;
        model.set_sense(sense);
        // HiGHS' own threads are unused here (the simplex runs serially,
        // the pieces in parallel); with the default (0) every run asked
        // the system for its core count (measured: 3% of the CPU time of
        // `generate mixed 20`).
        model.set_option("threads", 1);
        // Measured: dual simplex stalls on large sparse systems of this shape
        // where interior point finishes in seconds (docs/method.md section 2).
        model.set_option("solver", if big { "ipm" } else { "simplex" });
        // An elastic model minimises non-negative costs: its slack basis is
        // dual feasible, so the dual simplex starts in its phase 2.
        // Measured on TetGen's example: 6.5 ms a solve against the
        // primal's 14.5; on the shared inputs no more sites outside or
        // constraints missing their duals, and on face.poly 8 sites
        // outside instead of 18.
        let dual = !big && matches!(mode, Mode::Elastic { .. });
        if !big {
            // Measured: the primal simplex is 20% faster than the dual
            // (steepest edge) on the pieces' phase 1, and goes on from phase
            // 1's basis in phase 2. The dual goes on after rows enter or
            // bounds loosen (`Lp::simplex`); devex pricing, as the primal's:
            // steepest edge weights cost more than the few iterations need.
            model.set_option("simplex_strategy", if dual { 1 } else { 4 });
            model.set_option("simplex_dual_edge_weight_strategy", 1);
            // Measured: on the local form's small pieces presolve costs as
            // much as the solve (and it would discard the warm start); on
            // the 3D global form's cold margin solves it saved nothing once
            // their elastic rows were lazy, and made emerald's wells
            // (tests/fields3.rs) 4x slower. Where the simplex stalls
            // without it, `run_model` falls back to it.
            model.set_option("presolve", "off");
            // Measured: HiGHS' accuracy test before a rebuild (a solve with
            // fresh work vectors each time) was 7% of the pieces' time; their
            // few updates keep the factors accurate, and the weights are
            // checked exactly anyway.
            model.set_option("rebuild_refactor_solution_error_tolerance", 0.0);
        }
        Ok(Lp {
            model: Some(model),
            w,
            aux,
            delta,
            slack,
            lazy,
            dual,
            refs,
            floor: floor != Bound::Unbounded,
            enter_all: super::ENTER_ALL,
            stage: match mode {
                Mode::Margin => Stage::Margin(k.map(f64::to_bits)),
                Mode::Elastic { .. } => Stage::Other,
            },
            hinted: 0,
        })
    }

    /// This unsolved Margin model of `was` made the model `build` would
    /// give for `sys`, which differs from it only in margin rows'
    /// right-hand sides (settling's): those rows' bounds and delta's floor
    /// set again (lazy rows keep the partition `was` gave them: they still
    /// enter where violated). False, the model unchanged, where that cannot
    /// be told so (no auxiliary columns, interior point, rows no longer
    /// finite).
    #[allow(unsafe_code)]
    pub(crate) fn restate(&mut self, was: &System, sys: &System, with3: bool) -> Result<bool> {
        let big = super::is_big(sys);
        if sys.aux == 0 || big || !self.slack.is_empty() || was.rows.len() != sys.rows.len() {
            return Ok(false);
        }
        let (mut set, mut lower) = (vec![], vec![]);
        for (i, rf) in self.refs.iter().enumerate() {
            if let RowRef::Row(at) = *rf {
                let r = &sys.rows[at];
                if !finite(&r) {
                    return Ok(false);
                }
                if r.rhs != was.rows[at].rhs {
                    set.push(i as highs_sys::HighsInt);
                    lower.push(r.rhs);
                }
            }
        }
        let upper = vec![f64::INFINITY; set.len()];
        let model = self.model.as_mut().expect("model");
        // SAFETY: live instance; `set` holds its rows, and the bounds have
        // one entry each.
        let status = unsafe {
            highs_sys::Highs_changeRowsBoundsBySet(
                model.as_mut_ptr(),
                set.len() as _,
                set.as_ptr(),
                lower.as_ptr(),
                upper.as_ptr(),
            )
        };
        if status == highs_sys::STATUS_ERROR {
            return Err(Error::SolverLimit(
                "HiGHS refused to change the LP's rows".into(),
            ));
        }
        let floor = margin_floor(sys, with3, false);
        instance::column_bounds(model, self.delta, (lowest(floor), 1.0));
        self.floor = floor != Bound::Unbounded;
        Ok(true)
    }

    /// The lazy rows that the solution `cols` violates, now in the model.
    pub(crate) fn enter_violated(&mut self, sys: &System, cols: &[f64]) -> Result<bool> {
        let n = self.w.len();
        // An elastic model's system 3 row has its segment's slack instead
        // of the margin, and its small margin.
        let elastic = |r: &Row| match r.family {
            Family::Sys3(s) => self.slack.get(&s).copied(),
            _ => None,
        };
        let value = |r: &Row| {
            let terms = r
                .terms
                .iter()
                .filter_map(|&(c, v)| match c.checked_sub(n) {
                    Some(a) => Some(v * cols[self.aux[a].index()]),
                    None => self.w[c].map(|(p, q)| v * (cols[p.index()] - cols[q.index()])),
                })
                .sum::<f64>();
            match elastic(r) {
                Some(sl) => terms + cols[sl.index()] - r.rhs - ELASTIC_ROW_MARGIN,
                None => terms - r.share * cols[self.delta.index()] - r.rhs,
            }
        };
        let (mut keep, mut violated) = (vec![], vec![]);
        for &at in &self.lazy {
            match value(&sys.rows[at]) {
                v if v < 0.0 => violated.push((at, v)),
                _ => keep.push(at),
            }
        }
        let enter = if violated.len() > self.enter_all {
            let (enter, later) = super::rows::most_violated(&sys.rows, &violated);
            keep.extend(later);
            enter
        } else {
            violated.into_iter().map(|v| v.0).collect()
        };
        if !enter.is_empty() {
            // Only a model's first round is grouped (`ENTER_ALL`).
            self.enter_all = usize::MAX;
        }
        self.add_rows(sys, &enter)?;
        self.lazy = keep;
        if !enter.is_empty() {
            self.simplex(true);
        }
        Ok(!enter.is_empty())
    }

    /// The lazy rows `enter` (indices into `sys.rows`) in the model, in
    /// one HiGHS call (one at a time, each rebuilt the row-wise copy of
    /// the matrix). The caller takes them out of `lazy`.
    #[allow(unsafe_code)]
    pub(crate) fn add_rows(&mut self, sys: &System, enter: &[usize]) -> Result<()> {
        if enter.is_empty() {
            return Ok(());
        }
        let n = self.w.len();
        let (mut lower, mut starts, mut index, mut values) = (vec![], vec![], vec![], vec![]);
        for &at in enter {
            let r = &sys.rows[at];
            starts.push(index.len() as highs_sys::HighsInt);
            // An elastic model's system 3 row has its segment's slack
            // instead of the margin, and its small margin.
            let (extra, low) = match r.family {
                Family::Sys3(s) if self.slack.contains_key(&s) => {
                    ((self.slack[&s], 1.0), r.rhs + ELASTIC_ROW_MARGIN)
                }
                _ => ((self.delta, -r.share), r.rhs),
            };
            for (c, v) in model_terms(r, n, &self.w, &self.aux).chain([extra]) {
                index.push(c.index() as highs_sys::HighsInt);
                values.push(v);
            }
            lower.push(low);
            self.refs.push(RowRef::Row(at));
        }
        let upper = vec![f64::INFINITY; enter.len()];
        let model = self.model.as_mut().expect("model");
        // SAFETY: live instance; one bound pair and one start per row,
        // `index` and `values` of one length, columns of this model.
        let status = unsafe {
            highs_sys::Highs_addRows(
                model.as_mut_ptr(),
                enter.len() as _,
                lower.as_ptr(),
                upper.as_ptr(),
                index.len() as _,
                starts.as_ptr(),
                index.as_ptr(),
                values.as_ptr(),
            )
        };
        if status == highs_sys::STATUS_ERROR {
            return Err(instance::refused("rows added"));
        }
        Ok(())
    }

    /// Whether the columns `cols` of this model meet |w_i| <= k l_i^2.
    pub(crate) fn fits(&self, sys: &System, cols: &[f64], k: Option<f64>) -> bool {
        self.w.iter().enumerate().all(|(i, pq)| {
            pq.is_none_or(|(p, q)| {
                let up = part_upper(sys, i, k);
                cols[p.index()] <= up && cols[q.index()] <= up
            })
        })
    }

    /// The model's basis (column and row statuses).
    #[allow(unsafe_code)]
    pub(crate) fn basis(&mut self) -> Basis {
        let model = self.model.as_mut().expect("model");
        let mut cols = vec![0; model.num_cols()];
        let mut rows = vec![0; model.num_rows()];
        // SAFETY: live instance; arrays of its column and row counts.
        unsafe {
            highs_sys::Highs_getBasis(model.as_mut_ptr(), cols.as_mut_ptr(), rows.as_mut_ptr())
        };
        (cols, rows)
    }

    /// Goes back to `basis`: columns added since are nonbasic at their
    /// lower bound, rows added since basic. Where HiGHS refuses it, the
    /// current basis stays (only the speed of the next solve depends on it).
    /// The solver starts afresh from it: what runs since that basis left in
    /// HiGHS (its factors, perturbations, edge weights) would steer the
    /// next solve to another optimal vertex (measured: phase 2 after a
    /// failed rung and phase 2 with that rung skipped ended at different
    /// weights on TetGen's example).
    #[allow(unsafe_code)]
    pub(crate) fn set_basis(&mut self, (mut cols, mut rows): Basis) {
        let model = self.model.as_mut().expect("model");
        cols.resize(model.num_cols(), highs_sys::kHighsBasisStatusLower as _);
        rows.resize(model.num_rows(), highs_sys::kHighsBasisStatusBasic as _);
        // SAFETY: live instance; clearing its solver keeps the model, and
        // the arrays have its column and row counts.
        unsafe {
            highs_sys::Highs_clearSolver(model.as_mut_ptr());
            highs_sys::Highs_setBasis(model.as_mut_ptr(), cols.as_ptr(), rows.as_ptr())
        };
    }

    /// Which simplex goes on from the current basis: the dual after rows
    /// enter or bounds loosen (the basis stays dual feasible), the primal
    /// after costs change (it stays primal feasible). Simplex models only.
    /// Measured (callgrind, the pieces' solves at 13,200 segments): 15%
    /// fewer instructions than the primal throughout.
    pub(crate) fn simplex(&mut self, dual: bool) {
        if self.dual != dual {
            let model = self.model.as_mut().expect("model");
            model.set_option("simplex_strategy", if dual { 1 } else { 4 });
            self.dual = dual;
        }
    }

    /// Phase 1 again with |w_i| <= k l_i^2 (free: None).
    pub(crate) fn bound(&mut self, sys: &System, k: Option<f64>) -> Result<()> {
        self.simplex(true);
        if let Stage::Margin(_) = self.stage {
            self.stage = Stage::Margin(k.map(f64::to_bits));
        }
        let (mut cols, mut upper) = (vec![], vec![]);
        for (i, pq) in self.w.iter().enumerate() {
            if let Some((p, q)) = *pq {
                cols.extend([p, q]);
                upper.extend([part_upper(sys, i, k); 2]);
            }
        }
        let lower = vec![0.0; cols.len()];
        let model = self.model.as_mut().expect("model");
        change_columns(model, &cols, Change::Bounds(&lower, &upper))
    }

    /// New costs of an elastic model's slack columns (by segment, 1 where
    /// absent); the primal simplex goes on from the basis.
    pub(crate) fn recost(&mut self, costs: &HashMap<u32, f64>) -> Result<()> {
        self.simplex(false);
        let mut by_col: Vec<(Col, f64)> = self
            .slack
            .iter()
            .map(|(s, &c)| (c, costs.get(s).copied().unwrap_or(1.0)))
            .collect();
        by_col.sort_unstable_by_key(|c| c.0.index());
        let (cols, cost): (Vec<Col>, Vec<f64>) = by_col.into_iter().unzip();
        let model = self.model.as_mut().expect("model");
        change_columns(model, &cols, Change::Costs(&cost))
    }

    /// Turns a solved Margin model into phase 2: delta >= delta_min,
    /// minimise sum |w_i| / l_i^2 plus the anchors' violations.
    pub(crate) fn regularise(&mut self, sys: &System, delta_min: f64) -> Result<()> {
        self.simplex(false);
        self.stage = Stage::Phase2;
        let model = self.model.as_mut().expect("model");
        model.set_sense(Sense::Minimise);
        instance::column_bounds(model, self.delta, (delta_min, 1.0f64.max(delta_min)));
        let (mut cols, mut cost) = (vec![self.delta], vec![0.0]);
        for (i, pq) in self.w.iter().enumerate() {
            if let Some((p, q)) = *pq {
                cols.extend([p, q]);
                cost.extend([1.0 / sys.l2[i]; 2]);
            }
        }
        change_columns(model, &cols, Change::Costs(&cost))?;
        for r in sys.rows.iter().filter(finite) {
            if r.family == Family::Anchor {
                // sum(terms) + s+ - s- == rhs, |violation| costed
                let up = instance::add_column(model, ANCHOR_COST, (0.0, f64::INFINITY))?;
                let down = instance::add_column(model, ANCHOR_COST, (0.0, f64::INFINITY))?;
                let mut terms = weight_row(&self.w, r);
                terms.extend([(up, 1.0), (down, -1.0)]);
                instance::add_row(model, (r.rhs, r.rhs), &terms)?;
                self.refs.push(RowRef::Other);
            }
        }
        Ok(())
    }

    /// The row duals of a Margin model's optimum, by system row (nonzero
    /// ones only). Delta is freed from its floor first: at that bound the
    /// duals need not sum to one, and say nothing.
    #[allow(unsafe_code)]
    pub(crate) fn duals(&mut self, sys: &System, report: &mut WeightsReport) -> Result<Duals> {
        if self.floor {
            self.floor = false;
            self.simplex(false);
            let model = self.model.as_mut().expect("model");
            instance::column_bounds(model, self.delta, (f64::NEG_INFINITY, 1.0));
            // Without its floor the margin is no larger: where it is not
            // trusted, no row needs to enter for the duals to prove that.
            self.solve_until(sys, report, f64::NEG_INFINITY, super::TRUST)?;
        }
        let model = self.model.as_mut().expect("model");
        let mut dual = vec![0.0; model.num_rows()];
        let none = std::ptr::null_mut();
        // SAFETY: `model` is a live HiGHS instance and `dual` has its row
        // count, which HiGHS fills; it skips the arrays given as null.
        unsafe {
            highs_sys::Highs_getSolution(model.as_mut_ptr(), none, none, none, dual.as_mut_ptr())
        };
        Ok(self
            .refs
            .iter()
            .zip(dual)
            .filter(|d| d.1 != 0.0 && d.1.is_finite())
            .map(|(&r, y)| (r, y))
            .collect())
    }

    /// Solves, and again while the solution violates lazy rows (which
    /// then enter the model; the basis goes on). Rows only lower the
    /// margin: a margin at or below `enough` is returned as it is, an upper
    /// bound of the whole system's. Where the system is like one solved
    /// before, each solve starts from that one's basis (`warm`).
    pub(crate) fn solve(
        &mut self,
        sys: &System,
        report: &mut WeightsReport,
        enough: f64,
    ) -> Result<Solution> {
        self.solve_until(sys, report, enough, enough)
    }

    /// `solve`, with rows no longer entering once an optimum's margin is at
    /// or below `stop`: each model is still solved to its optimum (below
    /// `enough`), so its duals bound the whole system's margin too.
    pub(crate) fn solve_until(
        &mut self,
        sys: &System,
        report: &mut WeightsReport,
        enough: f64,
        stop: f64,
    ) -> Result<Solution> {
        self.warm_start(sys)?;
        let solution = loop {
            let (solution, cols) = self.solve_once(sys, report, enough)?;
            if solution.delta <= enough.max(stop) {
                break solution;
            }
            match cols {
                Some(cols) if self.enter_violated(sys, &cols)? => continue,
                _ => break solution,
            }
        };
        self.record(sys);
        Ok(solution)
    }

    /// One HiGHS run: the solution, and the columns when optimal.
    pub(crate) fn solve_once(
        &mut self,
        sys: &System,
        report: &mut WeightsReport,
        enough: f64,
    ) -> Result<(Solution, Option<Vec<f64>>)> {
        let left = report.deadline.map_or(LP_BUDGET, |d| {
            d.saturating_duration_since(std::time::Instant::now())
        });
        if left.is_zero() {
            return Err(Error::SolverLimit(format!(
                "the LP time budget of {} s ran out",
                LP_BUDGET.as_secs()
            )));
        }
        let model = self.model.as_mut().expect("model");
        report.lp_rows = report.lp_rows.max(model.num_rows());
        report.lp_cols = report.lp_cols.max(model.num_cols());
        report.lp_solves += 1;
        model.set_option("time_limit", left.as_secs_f64());
        // A rung whose margin only matters above `enough` stops once the
        // dual simplex proves it cannot get there (its dual objective passes
        // -enough). Measured on TetGen's example: the failing k = 1 rung of
        // settling takes 54 iterations instead of 160; on the shared inputs
        // the counts of sites outside move by one or two either way, and
        // lattice-sliver.poly now meshes on the pure backend.
        let bound = if enough.is_finite() {
            -enough
        } else {
            f64::INFINITY
        };
        model.set_option("objective_bound", bound);
        let ran = {
            let _running = HIGHS.read().unwrap_or_else(|e| e.into_inner());
            let rows = i32::try_from(model.num_rows()).unwrap_or(i32::MAX);
            run_model(
                model,
                STALL[0].saturating_add(STALL[1].saturating_mul(rows)),
            )
        };
        let (status, cols) = ran?;
        report.lp_iterations += iterations(model);
        report.lp_status = format!("{status:?}");
        match status {
            HighsModelStatus::Optimal => {
                let cols = cols.expect("optimal");
                let w: Vec<f64> = self
                    .w
                    .iter()
                    .map(|pq| {
                        pq.map_or(0.0, |(p, q)| cols[p.index()] - cols[q.index()]) * sys.unit2
                    })
                    .collect();
                if cols.iter().chain(&w).any(|c| !c.is_finite()) {
                    return Err(Error::SolverLimit(
                        "the LP returned weights that are not finite doubles".into(),
                    ));
                }
                let solution = Solution {
                    slack: self
                        .slack
                        .iter()
                        .map(|(&s, c)| (s, cols[c.index()]))
                        .collect(),
                    delta: cols[self.delta.index()],
                    w,
                };
                Ok((solution, Some(cols)))
            }
            HighsModelStatus::Infeasible | HighsModelStatus::ObjectiveBound => Ok((
                Solution {
                    delta: f64::NEG_INFINITY,
                    w: vec![],
                    slack: HashMap::new(),
                },
                None,
            )),
            HighsModelStatus::ReachedTimeLimit => Err(Error::SolverLimit(format!(
                "the LP time budget of {} s ran out ({} solves of up to {} rows)",
                LP_BUDGET.as_secs(),
                report.lp_solves,
                report.lp_rows
            ))),
            s => Err(Error::SolverLimit(format!("HiGHS ended with status {s:?}"))),
        }
    }
}

#[cfg(test)]
mod tests;
