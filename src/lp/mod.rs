//! The LP engine behind the weights (docs/method.md sections 2 and 3), the
//! only code that talks to HiGHS: rows of systems 1 and 3 (`rows`), the
//! HiGHS model kept across the phases (`highs`), the split of a local
//! system into independent pieces (`pieces`), and the ladder of solves
//! that gives a trusted margin or a verdict (`solve_rows`). Generic over
//! the dimension: rows are written over weights and coordinates in any D.
//! The LP looks for weights whose regular triangulation holds every
//! constraint (system 1) and, where it can, under which every constraint
//! crosses its dual (section 5.1, system 3).
//!
//! Order of attack: zero weights when every segment is strictly Gabriel;
//! else the local form (one power-test row per interior edge of the
//! constrained Delaunay triangulation); else the lazy global form (a
//! supporting plane per segment, rows added where the regular triangulation
//! of the current weights disagrees). The LP output is floating point and
//! is never trusted: the regular triangulation of the returned weights is
//! built with exact predicates and checked segment by segment.
//!
//! Objective (docs/method.md section 2): phase 1 maximises a common margin `delta`
//! over rows scaled to be dimensionless: first with free weights (only that
//! try may declare infeasibility), then with |w_i| <= k l_i^2 for k raised
//! stepwise (1, 16) until the margin is trusted; phase 2 keeps delta >= delta*/2
//! and minimises sum |w_i| / l_i^2, so weights stay small and sites stay near the segments'
//! midpoints. Phase 1's ladder and phase 2 share one HiGHS model, each
//! solve warm-started from the last basis (`Lp`). When system 3 cannot hold, an elastic phase keeps system 1 and
//! minimises the total violation of system 3, so that as few segments as
//! possible miss their duals.

mod cancel;
mod highs;
mod instance;
mod pieces;
mod proof;
mod rows;
mod warm;

#[cfg(test)]
pub(crate) use cancel::cancellable;
pub(crate) use cancel::{carried, flags};
pub(crate) use highs::destroy_finished;
use highs::{Basis, Lp, Mode, Solution};
pub(crate) use pieces::solve_pieces;
#[cfg(test)]
pub(crate) use proof::agrees as proof_agrees;
pub use proof::Proof;
pub(crate) use proof::{prove, Certificate, Duals};
#[cfg(test)]
pub(crate) use rows::jittered_lattice;
pub(crate) use rows::{plane_rows, rel, sys3_rows, Family, Origin, Row, System, Units};

use crate::error::{Error, Result};
use serde::Serialize;
use std::collections::HashMap;
use std::sync::atomic::{AtomicBool, Ordering};

/// Margins below this are inside HiGHS' tolerances: not trusted.
pub(crate) const TRUST: f64 = 1e-6;

/// Bounds |w_i| <= k l_i^2 tried in turn after the unbounded try.
pub(crate) const K_LADDER: [f64; 2] = [1.0, 16.0];

/// Time all LP solves of one run may take together.
pub(crate) const LP_BUDGET: std::time::Duration = std::time::Duration::from_secs(1800);

/// Largest number of point rows the lazy global form may grow to.
pub(crate) const MAX_GLOBAL_ROWS: usize = 5_000_000;

/// System 1 margin tried first by the elastic phase.
pub(crate) const ELASTIC_MARGIN: f64 = 1e-3;

/// The margin an elastic system 3 row asks for beyond its violation
/// (rows are dimensionless).
pub(crate) const ELASTIC_ROW_MARGIN: f64 = 1e-3;

/// Reweightings of the elastic phase. Measured with the LP's slopes in
/// closed form: one left the staggered chains (tests/corpus) 8 segments
/// missing their duals, two leave 6, and TetGen's example 7 facets instead
/// of 8, la.poly 35 segments instead of 36; a third changed nothing.
pub(crate) const REWEIGHTS: usize = 2;

/// How far `settle` lets a segment's system 3 violation exceed the elastic
/// optimum's (a multiple). Measured on three inputs whose elastic weights
/// left sliver cells or thin cells: 1 to 4 all mesh them; dropping the
/// violated rows altogether gave zero weights to a triangle 1e-8 thin,
/// whose far power centre then collapsed a cell in doubles.
pub(crate) const ELASTIC_ALLOWANCE: f64 = 2.0;

/// Rounds of the lazy global form before giving up on adding rows locally.
pub(crate) const GLOBAL_ROUNDS: usize = 40;

/// Phase 2 cost of an anchor's violation (dimensionless, like the weights'
/// cost sum |w_i| / l_i^2, which it outweighs).
pub(crate) const ANCHOR_COST: f64 = 1e3;

/// A margin row of a simplex model whose slack at zero weights (and zero
/// auxiliary columns) exceeds this enters the model only once a solution
/// violates it (measured on the
/// local form's pieces: 80% of the rows, of which 1 in 200 ever enters;
/// HiGHS' cost per iteration grows with the rows). The optimum is the same:
/// a solution of fewer rows that meets all rows is optimal for all. In the
/// 3D global form's elastic models system 3's rows are lazy too, their
/// slack columns there from the start (SPE9's transitions in 3D: 10,065
/// rows -> 5,600 in a cavity's first elastic solve, 26 cavities 8.9 s ->
/// 7.5 s).
pub(crate) const LAZY_SLACK: f64 = 0.2;

/// Violated lazy rows above which a model's first round of entering
/// enters only the most violated row of each face or segment
/// (`rows::most_violated`); every later round enters all violated rows.
/// A face's rows (one per vertex near it) are mostly violated together
/// after a cold solve and mostly met once one is in: SPE9's transitions in
/// 3D (two wells, callgrind) 5.55G -> 4.78G instructions. Grouping every
/// round was slower on emerald's well beside the hole (tests/fields3.rs:
/// rounds of 15,000 iterations, over 10 minutes against 46 s); grouping
/// the first only takes it to 38 s. The local form's pieces (at most 9
/// rows a round on `generate mixed`) are unchanged.
pub(crate) const ENTER_ALL: usize = 256;

/// Rows of a model above which interior point replaces the simplex.
pub(crate) const BIG_MODEL: usize = 5_000;

/// The same for the 3D global form (`System::lazy_aux`), whose models are
/// tall: SPE9's transitions in 3D have 11,608 rows for 717 columns, and
/// there interior point spent 60% of the time forming its normal
/// equations. The simplex, with its lazy rows, took a cavity's weights
/// from 2.3 s to 0.86 s at the same margin (SPE9's 26 cavities: 32 s to
/// 13.5 s). Where the simplex fails on one, interior point solves it
/// (`solve_tall`).
pub(crate) const BIG_MODEL_3D: usize = 50_000;

/// Whether interior point solves `sys`'s models (`BIG_MODEL`).
pub(crate) fn is_big(sys: &System) -> bool {
    let limit = if sys.lazy_aux {
        BIG_MODEL_3D
    } else {
        BIG_MODEL
    };
    sys.eqs.len() + sys.rows.len() > limit
}

/// What the weights step did, for the report.
#[derive(Debug, Clone, Serialize, Default)]
pub struct WeightsReport {
    /// When the LP work must stop (never a hang).
    #[serde(skip)]
    pub(crate) deadline: Option<std::time::Instant>,
    /// "zero", "local", or "global".
    pub method: String,
    /// LP solves in all.
    pub lp_solves: usize,
    /// Simplex iterations of those solves, together.
    pub lp_iterations: usize,
    /// Independent LPs the local form split into (solved in parallel).
    pub lp_pieces: usize,
    /// Of those, pieces that took the weights of an earlier piece like
    /// them, which meet all their rows: no LP ran for them.
    pub lp_served: usize,
    /// Largest LP solved (rows, columns).
    pub lp_rows: usize,
    /// Largest LP's columns.
    pub lp_cols: usize,
    /// HiGHS' status of the last solve.
    pub lp_status: String,
    /// Phase-1 margin (dimensionless), when an LP ran.
    pub margin: Option<f64>,
    /// The k of |w_i| <= k l_i^2 that gave a positive margin (None: unbounded).
    pub bound_k: Option<f64>,
    /// Rounds of the lazy global form.
    pub global_rounds: usize,
    /// How many weights were LP unknowns (the others stayed zero).
    pub free_weights: usize,
    /// Largest |weight|.
    pub max_abs_weight: f64,
    /// Whether every constraint crosses its dual (checked exactly).
    pub system3_feasible: bool,
    /// Why the LP gave no answer, when zero weights had to do.
    pub lp_error: Option<String>,
    /// Segments with an anchor, and those whose anchor is on the dual line.
    pub anchors: usize,
    /// Anchors on their segments' dual lines.
    pub anchors_met: usize,
    /// Where system 3 could not hold: an exact certificate that no weights
    /// make every face one of the regular triangulation with the faces of
    /// `crossing` crossing their duals (absent when none was found).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub system3_proof: Option<Proof>,
}

impl WeightsReport {
    /// A report whose LP work has the whole budget from now.
    pub(crate) fn started(method: &str) -> WeightsReport {
        WeightsReport {
            method: method.into(),
            deadline: Some(std::time::Instant::now() + LP_BUDGET),
            ..Default::default()
        }
    }

    /// Adds what one piece's LPs did: counts add up, sizes take the
    /// largest, the margin the smallest, the bound the loosest.
    pub(crate) fn absorb(&mut self, piece: &WeightsReport) {
        self.lp_solves += piece.lp_solves;
        self.lp_served += piece.lp_served;
        self.lp_iterations += piece.lp_iterations;
        self.lp_rows = self.lp_rows.max(piece.lp_rows);
        self.lp_cols = self.lp_cols.max(piece.lp_cols);
        if self.lp_status.is_empty() || piece.lp_status != "Optimal" {
            self.lp_status = piece.lp_status.clone();
        }
        if let Some(m) = piece.margin {
            self.bound_k = match (self.margin, self.bound_k, piece.bound_k) {
                (None, _, k) => k,
                (Some(_), Some(a), Some(b)) => Some(a.max(b)),
                _ => None,
            };
            self.margin = Some(self.margin.map_or(m, |x| x.min(m)));
        }
    }
}

/// A row from a triangle too thin for doubles may hold infinities: it is
/// left out (the exact verification of the result still covers it).
pub(crate) fn finite(r: &&Row) -> bool {
    r.rhs.is_finite() && r.terms.iter().all(|t| t.1.is_finite())
}

/// One model, one solve.
pub(crate) fn run(
    sys: &System,
    with3: bool,
    k: Option<f64>,
    mode: &Mode,
    report: &mut WeightsReport,
) -> Result<Solution> {
    Lp::build(sys, with3, k, mode)?.solve(sys, report, f64::NEG_INFINITY)
}

/// Phase 1 up the k ladder, in one warm model: the best margin, the k that
/// reached it, and the model at that k (for phase 2).
/// Where a failure is a verdict (the global form), the unbounded try comes
/// first: only it may declare infeasibility, and an infeasible system then
/// costs one solve. The local form's failures are no verdict: its ladder
/// starts small and the unbounded try comes last. The smallest k with a
/// trusted margin keeps the weights small.
/// With `restart` (settling), each bounded rung after the first starts
/// from the free rung's optimum (the verdict order).
pub(crate) fn margin(
    sys: &System,
    with3: bool,
    restart: bool,
    report: &mut WeightsReport,
) -> Result<(f64, Option<f64>, Lp)> {
    margin_on(None, sys, with3, restart, report)
}

/// `margin` on `built` where given: a model of this system's first rung,
/// not solved yet.
fn margin_on(
    built: Option<Lp>,
    sys: &System,
    with3: bool,
    restart: bool,
    report: &mut WeightsReport,
) -> Result<(f64, Option<f64>, Lp)> {
    let ladder: Vec<Option<f64>> = K_LADDER.iter().map(|&k| Some(k)).collect();
    let order: Vec<Option<f64>> = if sys.verdict {
        [None].into_iter().chain(ladder).collect()
    } else {
        ladder.into_iter().chain([None]).collect()
    };
    let mut lp = match built {
        Some(lp) => lp,
        None => Lp::build(sys, with3, order[0], &Mode::Margin)?,
    };
    let mut best = (f64::NEG_INFINITY, None);
    let mut free: Option<(Basis, Vec<f64>, f64)> = None;
    let mut skip = None;
    for (step, &k) in order.iter().enumerate() {
        if step > 0 {
            lp.bound(sys, k)?;
        }
        if let Some((b, cols, delta)) = &free {
            // From the free rung's optimum, not the failed rung's last
            // basis: where the free weights meet the bound it is this
            // rung's optimum too (measured on TetGen's example: settling's
            // k = 16 rung took 0 iterations instead of 55), and its solve
            // is skipped.
            if step > 1 {
                lp.set_basis(b.clone());
            }
            if lp.fits(sys, cols, k) {
                return Ok((*delta, k, lp));
            }
        }
        if skip == Some(step) {
            continue;
        }
        // A rung whose margin is not returned fails as soon as its rows so
        // far leave none (lazy rows cannot raise it).
        let returned = step + 1 == order.len() || (sys.verdict && step == 0);
        let enough = if returned { f64::NEG_INFINITY } else { TRUST };
        // A verdict's free rung that is not trusted on some of its rows is
        // not on all of them, and its duals there prove as much: the other
        // rows need not enter (measured on SPE9's transitions in 3D: 1,300
        // of the verdict's 1,700 iterations a cavity went to rows entered
        // after the margin was already negative).
        let stop = if sys.verdict && step == 0 {
            TRUST
        } else {
            enough
        };
        let delta = if restart && step == 0 && k.is_none() && order.len() > 2 {
            // The next rung is solved beside this one, from scratch on a
            // model of its own, and skipped where it fails (measured on
            // TetGen's example: 1.5 ms off the critical path). Skipped or
            // solved, the rung after it restarts from this one's optimum.
            let deadline = report.deadline;
            let (solved, fails) = cancel::beside_here(
                || lp.solve_until(sys, report, enough, stop),
                || fails(sys, with3, order[1], deadline),
            );
            report.lp_solves += 1;
            skip = (fails == Some(true)).then_some(1);
            let delta = solved?.delta;
            let cols = highs::columns(lp.model.as_mut().expect("model"));
            free = Some((lp.basis(), cols, delta));
            delta
        } else {
            lp.solve_until(sys, report, enough, stop)?.delta
        };
        if sys.verdict && step == 0 {
            if delta <= TRUST {
                return Ok((delta, None, lp));
            }
            best = (delta, None);
        } else if delta > TRUST || k.is_none() {
            return Ok((delta, k, lp));
        }
    }
    // The verdict order: no bound gave a trusted margin, the free one did.
    // Back at the free rung's optimum where it was kept: rows entered
    // since were violated by bounded weights only (measured on SPE9's
    // transitions in 3D: 1,900 to 3,000 iterations from the last rung's
    // basis).
    lp.bound(sys, None)?;
    if let Some((b, ..)) = free {
        lp.set_basis(b);
    }
    lp.solve(sys, report, f64::NEG_INFINITY)?;
    Ok((best.0, best.1, lp))
}

/// Whether the margin rung at `k` fails (no trusted margin), solved from
/// scratch on a model of its own; None where it could not be told.
fn fails(
    sys: &System,
    with3: bool,
    k: Option<f64>,
    deadline: Option<std::time::Instant>,
) -> Option<bool> {
    let mut report = WeightsReport {
        deadline,
        ..Default::default()
    };
    let mut lp = Lp::build(sys, with3, k, &Mode::Margin).ok()?;
    let delta = lp.solve(sys, &mut report, TRUST).ok()?.delta;
    Some(delta <= TRUST)
}

/// The weights of an elastic optimum made regular. The elastic optimum
/// leaves the weights at a vertex of its polytope, often where power cells
/// are slivers (measured: weights of -44 on a domain of size 10, cells too
/// thin for a double point). With each segment's violation allowed up to
/// `ELASTIC_ALLOWANCE` times the optimum's, the system is solved as on the
/// feasible path (largest margin, then smallest weights); `best`'s own
/// weights where that finds no trusted margin.
/// `built`, where given, is an unsolved free Margin model of `sys`.
fn settle(
    sys: &System,
    best: &Solution,
    built: Option<Lp>,
    report: &mut WeightsReport,
) -> Result<Vec<f64>> {
    let mut rest = sys.clone();
    for r in &mut rest.rows {
        if let Family::Sys3(s) = r.family {
            let v = best.slack.get(&s).copied().unwrap_or(0.0).max(0.0);
            if v > 1e-9 {
                r.rhs += ELASTIC_ROW_MARGIN - ELASTIC_ALLOWANCE * v;
            }
        }
    }
    // The bound ladder, though the elastic optimum's weights were free:
    // with free weights at once (two solves fewer on TetGen's example) a
    // fuzzed input's vertex cell became a sliver no extra site fits in
    // (tests/zigzag/fuzz-starved-vertex.poly).
    let built = match built {
        Some(mut lp) => lp.restate(sys, &rest, true)?.then_some(lp),
        None => None,
    };
    let (m, _, mut lp) = margin_on(built, &rest, true, true, report)?;
    if m <= TRUST {
        return Ok(best.w.clone());
    }
    report.margin = Some(m);
    lp.regularise(&rest, m / 2.0)?;
    let w = lp.solve(&rest, report, f64::NEG_INFINITY)?.w;
    Ok(if w.is_empty() { best.w.clone() } else { w })
}

/// What the LP says about one row system (no verification yet).
pub(crate) enum Answer {
    /// Weights (for the system's columns), and whether system 3 held on
    /// the rows (false: elastic, with the duals of systems 1 and 3
    /// together for `prove` when the system is a verdict's).
    Weights(Vec<f64>, bool, Duals),
    /// System 1 has no trusted margin on these rows (the duals, for
    /// `prove`, when the system is a verdict's).
    Sys1Infeasible(Duals),
    /// Systems 1 and 3 together have none (asked not to go elastic).
    Sys3Infeasible,
}

/// What the verdict's ladder found: phase 2's weights where systems 1 and
/// 3 have a trusted margin, else the duals of its free rung (a verdict's,
/// for `prove`, when asked for).
struct Verdict {
    margin: f64,
    k: Option<f64>,
    w: Option<Vec<f64>>,
    duals: Duals,
    /// Where the margin is not trusted: a fresh model of the first rung
    /// for settling (built here, beside the elastic solves).
    next: Option<cancel::Moved>,
}

/// Systems 1 and 3 together: their margin up the ladder, then phase 2
/// where it is trusted (`found` raised as soon as it is).
fn verdict(
    sys: &System,
    with_duals: bool,
    found: &AtomicBool,
    report: &mut WeightsReport,
) -> Result<Verdict> {
    let (margin, k, mut lp) = self::margin(sys, true, false, report)?;
    if margin > TRUST {
        found.store(true, Ordering::Relaxed);
        lp.regularise(sys, margin / 2.0)?;
        let w = Some(lp.solve(sys, report, f64::NEG_INFINITY)?.w);
        return Ok(Verdict {
            margin,
            k,
            w,
            duals: vec![],
            next: None,
        });
    }
    // A verdict's first rung is free: its duals may prove the margin's sign.
    let (duals, next) = if with_duals && sys.verdict {
        let duals = lp.duals(sys, report)?;
        let next = cancel::Moved(Lp::build(sys, true, None, &Mode::Margin)?);
        (duals, Some(next))
    } else {
        (vec![], None)
    };
    Ok(Verdict {
        margin,
        k,
        w: None,
        duals,
        next,
    })
}

/// The elastic solve at a fixed system 1 margin, reweighted: its best
/// solution, None where system 1 has no margin `ELASTIC_MARGIN`.
fn elastic(sys: &System, report: &mut WeightsReport) -> Result<Option<Solution>> {
    let mode = |costs| Mode::Elastic {
        delta_min: ELASTIC_MARGIN,
        costs,
    };
    let mut lp = Lp::build(sys, true, None, &mode(HashMap::new()))?;
    let quick = lp.solve(sys, report, f64::NEG_INFINITY)?;
    if quick.delta < ELASTIC_MARGIN {
        return Ok(None);
    }
    // Reweighted (cost 1 / (violation + eps)), `REWEIGHTS` times: the total
    // violation is spread over fewer segments, so fewer miss their duals
    // and fewer sites end outside. Warm: only the slack columns' costs
    // change, so the last optimum stays primal feasible and the primal
    // simplex goes on from it (measured on TetGen's example: 23 and 9
    // iterations, against 158 for one reweighting from scratch).
    let mut sparse = quick.clone();
    for _ in 0..REWEIGHTS {
        if sparse.delta < ELASTIC_MARGIN {
            break;
        }
        let costs: HashMap<u32, f64> = sparse
            .slack
            .iter()
            .map(|(&s, &v)| (s, 1.0 / (v.max(0.0) + 1e-3)))
            .collect();
        lp.recost(&costs)?;
        sparse = lp.solve(sys, report, f64::NEG_INFINITY)?;
    }
    Ok(Some(if sparse.delta >= ELASTIC_MARGIN {
        sparse
    } else {
        quick
    }))
}

/// What the elastic side of `solve_rows` found.
enum Elastic {
    /// The elastic optimum (system 1 at margin `ELASTIC_MARGIN`).
    Best(Solution),
    /// System 1 has no margin `ELASTIC_MARGIN`, but a trusted one (and k).
    Sys1(f64, Option<f64>),
    /// Nor a trusted one: its margin, k and the duals of its free rung
    /// (a verdict's, for `prove`).
    NoSys1(f64, Option<f64>, Duals),
}

/// The elastic solves; where system 1 has no margin `ELASTIC_MARGIN`, its
/// own ladder, whose failure makes the verdict of systems 1 and 3 moot
/// (theirs is no larger).
fn elastic_side(sys: &System, moot: &AtomicBool, report: &mut WeightsReport) -> Result<Elastic> {
    if let Some(best) = elastic(sys, report)? {
        return Ok(Elastic::Best(best));
    }
    let (m1, k1, mut lp1) = margin(sys, false, false, report)?;
    if m1 > TRUST {
        return Ok(Elastic::Sys1(m1, k1));
    }
    let duals = if sys.verdict {
        lp1.duals(sys, report)?
    } else {
        vec![]
    };
    moot.store(true, Ordering::Relaxed);
    Ok(Elastic::NoSys1(m1, k1, duals))
}

/// Adds what another part's solves did to `report` (counts, sizes, the
/// last status).
fn merge(report: &mut WeightsReport, part: &WeightsReport) {
    report.lp_solves += part.lp_solves;
    report.lp_iterations += part.lp_iterations;
    report.lp_rows = report.lp_rows.max(part.lp_rows);
    report.lp_cols = report.lp_cols.max(part.lp_cols);
    if part.lp_solves > 0 {
        report.lp_status = part.lp_status.clone();
    }
}

/// `solve_rows` (elastic) for the 3D global form; where the simplex fails
/// on a tall model (`BIG_MODEL_3D`; a well at 85 degrees' dip in SPE9),
/// again by interior point on all its rows.
pub(crate) fn solve_tall(sys: &System, report: &mut WeightsReport) -> Result<Answer> {
    let answer = solve_rows(sys, true, report);
    if !matches!(answer, Err(Error::SolverLimit(_))) || sys.rows.len() <= BIG_MODEL {
        return answer;
    }
    let all = System {
        lazy_aux: false,
        ..sys.clone()
    };
    solve_rows(&all, true, report)
}

/// The LP on one row system: system 1 + 3; else system 1 with system 3
/// elastic (as few segments as possible missing their duals).
/// Where it may go elastic, the elastic solves run beside the verdict
/// (each cancels the other where it decides alone): same results, and
/// where the verdict has no margin (TetGen's example) its time is saved.
/// Each side counts its solves apart, so the report does not depend on
/// how far a cancelled side got.
pub(crate) fn solve_rows(
    sys: &System,
    elastic: bool,
    report: &mut WeightsReport,
) -> Result<Answer> {
    if !elastic {
        let found = AtomicBool::new(false);
        let v = verdict(sys, false, &found, report)?;
        report.margin = Some(v.margin);
        report.bound_k = v.k;
        return Ok(match v.w {
            Some(w) => Answer::Weights(w, true, v.duals),
            None => Answer::Sys3Infeasible,
        });
    }
    let part = || WeightsReport {
        lp_solves: 0,
        lp_iterations: 0,
        ..report.clone()
    };
    let (mut by_elastic, mut by_verdict) = (part(), part());
    let (side, v) = cancel::beside(
        |moot| elastic_side(sys, moot, &mut by_elastic),
        |found| verdict(sys, true, found, &mut by_verdict),
    );
    if let Some(Ok(Elastic::NoSys1(m1, k1, duals))) = side {
        merge(report, &by_elastic);
        report.margin = Some(m1);
        report.bound_k = k1;
        return Ok(Answer::Sys1Infeasible(duals));
    }
    let v = v.expect("the verdict is moot only where system 1 fails")?;
    merge(report, &by_verdict);
    report.margin = Some(v.margin);
    report.bound_k = v.k;
    if let Some(w) = v.w {
        return Ok(Answer::Weights(w, true, v.duals));
    }
    merge(report, &by_elastic);
    let w = match side.expect("the elastic side runs unless the verdict succeeds")? {
        Elastic::Best(best) => {
            report.margin = Some(best.delta);
            report.bound_k = None;
            settle(sys, &best, v.next.map(|m| m.0), report)?
        }
        Elastic::Sys1(m1, k1) => {
            report.margin = Some(m1);
            report.bound_k = k1;
            let mode = Mode::Elastic {
                delta_min: m1 / 2.0,
                costs: HashMap::new(),
            };
            run(sys, true, k1, &mode, report)?.w
        }
        Elastic::NoSys1(..) => unreachable!("answered above"),
    };
    Ok(Answer::Weights(w, false, v.duals))
}
