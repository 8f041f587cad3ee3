//! Weights of a regular constrained triangulation (paper section 3, system 1)
//! under which every segment crosses its dual (section 5.1, system 3).
//! The only module that talks to HiGHS.
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

use crate::backend::{Backend, Triangulation};
use crate::complex::Complex;
use crate::conform::Progress;
use crate::domain::Domain;
use crate::error::{Error, Result};
use crate::geom::{abs, dot, in_diametral_disc, is_pos, norm2, q, qp, sub, Q};
use highs::{HighsModelStatus, RowProblem, Sense};
use nalgebra::{SVector, Vector2};
use serde::Serialize;
use std::collections::{BTreeSet, HashMap};
use std::ops::Bound;

/// Margins below this are inside HiGHS' tolerances: not trusted.
pub(crate) const TRUST: f64 = 1e-6;
/// Bounds |w_i| <= k l_i^2 tried in turn after the unbounded try.
const K_LADDER: [f64; 2] = [1.0, 16.0];
/// Time all LP solves of one run may take together.
const LP_BUDGET: std::time::Duration = std::time::Duration::from_secs(1800);
/// Largest number of point rows the lazy global form may grow to.
pub(crate) const MAX_GLOBAL_ROWS: usize = 5_000_000;
/// System 1 margin tried first by the elastic phase.
const ELASTIC_MARGIN: f64 = 1e-3;
/// Rounds of the lazy global form before giving up on adding rows locally.
pub(crate) const GLOBAL_ROUNDS: usize = 40;
/// An anchor within this fraction of its segment's length of the dual line
/// is met (the hybrid report's orthogonality threshold is 1e-6).
const ANCHOR_MET: f64 = 1e-9;
/// Phase 2 cost of an anchor's violation (dimensionless, like the weights'
/// cost sum |w_i| / l_i^2, which it outweighs).
const ANCHOR_COST: f64 = 1e3;
/// Largest local system solved as one LP when its pieces give no answer
/// (measured: 13,600 free weights take 95 s as one LP, 0.7 s as pieces).
const MAX_JOINT_WEIGHTS: usize = 20_000;
/// A margin row of a simplex model whose slack at zero weights exceeds
/// this enters the model only once a solution violates it (measured on the
/// local form's pieces: 80% of the rows, of which 1 in 200 ever enters;
/// HiGHS' cost per iteration grows with the rows). The optimum is the same:
/// a solution of fewer rows that meets all rows is optimal for all.
const LAZY_SLACK: f64 = 0.2;
/// Rows of a model above which interior point replaces the simplex.
const BIG_MODEL: usize = 5_000;

/// Verified weights and their regular triangulation.
#[derive(Debug, Clone)]
pub struct Weights {
    pub w: Vec<f64>,
    /// RT(w): contains every segment, hides no vertex (checked exactly).
    pub rt: Triangulation,
    pub report: WeightsReport,
    /// Segments that do not cross their dual edge (exact check).
    pub sys3_failed: Vec<u32>,
}

/// What the weights step did, for the report.
#[derive(Debug, Clone, Serialize, Default)]
pub struct WeightsReport {
    /// When the LP work must stop (never a hang).
    #[serde(skip)]
    deadline: Option<std::time::Instant>,
    /// "zero", "local", or "global".
    pub method: String,
    pub lp_solves: usize,
    /// Independent LPs the local form split into (solved in parallel).
    pub lp_pieces: usize,
    /// Largest LP solved (rows, columns).
    pub lp_rows: usize,
    pub lp_cols: usize,
    pub lp_status: String,
    /// Phase-1 margin (dimensionless), when an LP ran.
    pub margin: Option<f64>,
    /// The k of |w_i| <= k l_i^2 that gave a positive margin (None: unbounded).
    pub bound_k: Option<f64>,
    pub global_rounds: usize,
    /// How many weights were LP unknowns (the others stayed zero).
    pub free_weights: usize,
    pub max_abs_weight: f64,
    pub system3_feasible: bool,
    /// Why the LP gave no answer, when zero weights had to do.
    pub lp_error: Option<String>,
    /// Segments with an anchor, and those whose anchor is on the dual line.
    pub anchors: usize,
    pub anchors_met: usize,
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
    fn absorb(&mut self, piece: &WeightsReport) {
        self.lp_solves += piece.lp_solves;
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

/// Finds weights for the domain's complex.
pub fn solve<B: Backend + ?Sized>(
    backend: &B,
    dom: &Domain,
    progress: Option<Progress>,
) -> Result<Weights> {
    let out = solve_unanchored_first(backend, dom, progress);
    destroy_finished();
    let mut out = out?;
    let cx = &dom.complex;
    out.report.anchors = (0..cx.segments.len())
        .filter(|&s| cx.anchor(s).is_some())
        .count();
    out.report.anchors_met = out.report.anchors - unmet_anchors(cx, &out.w).len();
    Ok(out)
}

/// How far anchor c of segment s lies from the segment's dual line under
/// weights w, as a fraction of the segment's length (the power difference
/// of c to the segment's ends over 2 L^2).
pub fn anchor_offset(cx: &Complex, w: &[f64], s: usize) -> Option<f64> {
    let c = cx.anchor(s)?;
    let [i, j] = cx.segments[s].map(|v| v as usize);
    let (pi, pj) = (cx.points[i], cx.points[j]);
    let d2 = |p: [f64; 2]| (c[0] - p[0]).powi(2) + (c[1] - p[1]).powi(2);
    let l2 = (pj[0] - pi[0]).powi(2) + (pj[1] - pi[1]).powi(2);
    Some(((d2(pi) - w[i]) - (d2(pj) - w[j])) / (2.0 * l2))
}

/// Anchored segments whose anchor is off the dual line under w.
fn unmet_anchors(cx: &Complex, w: &[f64]) -> Vec<u32> {
    (0..cx.segments.len())
        .filter(|&s| anchor_offset(cx, w, s).is_some_and(|o| o.abs() > ANCHOR_MET))
        .map(|s| s as u32)
        .collect()
}

/// Zero weights when they serve (anchors included), else the LP.
fn solve_unanchored_first<B: Backend + ?Sized>(
    backend: &B,
    dom: &Domain,
    progress: Option<Progress>,
) -> Result<Weights> {
    let cx = &dom.complex;
    let n = cx.points.len();
    let zero = vec![0.0; n];
    let unmet_at_zero = unmet_anchors(cx, &zero).len();
    let gabriel = |t: &Triangulation| {
        cx.segments
            .iter()
            .all(|s| strictly_gabriel(cx, t, s[0], s[1]))
    };
    let zero_weights = |rt: Triangulation, method: &str| Weights {
        w: vec![0.0; n],
        rt,
        report: WeightsReport {
            method: method.into(),
            system3_feasible: true,
            ..Default::default()
        },
        sys3_failed: vec![],
    };
    // A constrained Delaunay triangulation that is Delaunay at every edge
    // is a Delaunay triangulation holding every segment: no second build.
    // (Its other edges are Delaunay by construction, with exact predicates.)
    let zero_rt = if delaunay(cx, &dom.cdt) && gabriel(&dom.cdt) {
        Some(dom.cdt.clone())
    } else {
        None
    };
    if let (Some(rt), 0) = (&zero_rt, unmet_at_zero) {
        return Ok(zero_weights(rt.clone(), "zero"));
    }
    // Only segments may fail the Delaunay test in a constrained Delaunay
    // triangulation: flips there give the Delaunay triangulation.
    let segments = cx.segments.iter().map(|s| (s[0], s[1])).collect();
    let rt0 = regular_from(backend, &cx.points, &zero, &dom.cdt, segments)?;
    let zero_rt =
        zero_rt.or_else(|| (conforms(cx, &rt0).is_ok() && gabriel(&rt0)).then(|| rt0.clone()));
    // Anchors that zero weights meet are kept as equalities; should they
    // leave no weights at all, the LP runs again without anchors.
    let has_anchors = !cx.anchors.is_empty();
    let lpres = match lp(backend, dom, &rt0, has_anchors, progress) {
        Ok(w) if w.sys3_failed.is_empty() || !has_anchors => Ok(w),
        Err(e) if !has_anchors => Err(e),
        _ => lp(backend, dom, &rt0, false, progress),
    };
    match (zero_rt, lpres) {
        (Some(rt), Ok(w)) if unmet_anchors(cx, &w.w).len() >= unmet_at_zero => {
            // Zero weights serve but for anchors, and the LP meets no more
            // of them (keeping the margin it needs): zero weights.
            let mut z = zero_weights(rt, "zero (the LP met no more anchors)");
            z.report.lp_solves = w.report.lp_solves;
            z.report.lp_rows = w.report.lp_rows;
            z.report.lp_cols = w.report.lp_cols;
            Ok(z)
        }
        // The LP gave no answer (slivers beyond its precision, a solver
        // error, the time budget). Zero weights are still a regular
        // constrained triangulation when the Delaunay triangulation contains
        // every segment (checked exactly): use them, and check system 3 for
        // them exactly (its failure is then no proof).
        (zero_rt, Err(Error::Lp(m))) if zero_rt.is_some() || conforms(cx, &rt0).is_ok() => {
            let rt = zero_rt.unwrap_or(rt0);
            let sys3_failed = sys3_failures(cx, &zero, &rt);
            let report = WeightsReport {
                method: "zero (the LP gave no answer)".into(),
                system3_feasible: sys3_failed.is_empty(),
                lp_error: Some(m),
                ..Default::default()
            };
            Ok(Weights {
                w: zero,
                rt,
                report,
                sys3_failed,
            })
        }
        (_, other) => other,
    }
}

/// The local form, then the lazy global form.
fn lp<B: Backend + ?Sized>(
    backend: &B,
    dom: &Domain,
    rt0: &Triangulation,
    anchored: bool,
    progress: Option<Progress>,
) -> Result<Weights> {
    let cx = &dom.complex;
    let n = cx.points.len();
    let units = Units::new(&cx.points, dom.cdt.edges());
    let mut report = WeightsReport::started("local");
    // The local form fixes the triangulation, so its failures are no
    // verdict. First with weights free only near the segments that need
    // them (docs/method.md section 2), then with all free.
    let unmet = if anchored {
        unmet_anchors(cx, &vec![0.0; n])
    } else {
        vec![]
    };
    let near = near_failures(cx, rt0, &dom.cdt, &unmet);
    let all = vec![true; n];
    let tries = if near.iter().all(|&f| f) {
        vec![all]
    } else {
        vec![near, all]
    };
    for free in tries {
        let free_weights = free.iter().filter(|&&f| f).count();
        report.free_weights = free_weights;
        let system = || {
            let mut local = local_system(cx, &dom.cdt, &dom.inside, &units, free.clone());
            if anchored {
                anchor_rows(&mut local, cx, &units);
            }
            local
        };
        if let Some(w) = solve_pieces(system(), &mut report, progress)? {
            if let Attempt::Found(found) = verify(backend, dom, w, true)? {
                if found.sys3_failed.is_empty() {
                    return finish(found, report);
                }
            }
        }
        // The split restricts the rows between pieces and leaves out weak
        // ones: the whole system may still have weights (when it is small
        // enough for one LP).
        if report.lp_pieces > 1 && free_weights <= MAX_JOINT_WEIGHTS {
            if let Attempt::Found(found) = attempt(backend, dom, &system(), false, &mut report)? {
                if found.sys3_failed.is_empty() {
                    return finish(found, report);
                }
            }
        }
    }
    report.free_weights = n;
    report.method = "global".into();
    global(backend, dom, &units, report, anchored)
}

/// A part of a local system whose rows share no free weight with the
/// rest: its LP is independent. Columns are the part's free weights only
/// (the others are zero, so their terms vanish exactly).
struct Piece {
    sys: System,
    /// Column k of `sys` is weight `cols[k]`.
    cols: Vec<usize>,
}

/// Splits a local system (no auxiliary columns) into independent pieces:
/// weights joined by a row inside the domain (union-find) form a piece,
/// numbered by its smallest weight, so the split does not depend on row
/// order. A row outside the domain that joins m pieces (the gap between
/// two cavities) is split: each piece gets its own terms, and rhs / m and
/// delta / m when zero weights meet the row with slack (the parts' sum is
/// the row with the mean of the pieces' margins); otherwise the piece of
/// its first weight gets all of rhs and delta, the others 0. Weak rows
/// between pieces are left out. The weights of all pieces are then checked
/// exactly together (RT(w)), as every LP answer is.
fn pieces(mut sys: System) -> Vec<Piece> {
    debug_assert_eq!(sys.aux, 0);
    let mut parent: Vec<usize> = (0..sys.n).collect();
    fn root(parent: &mut [usize], mut v: usize) -> usize {
        while parent[v] != v {
            parent[v] = parent[parent[v]];
            v = parent[v];
        }
        v
    }
    // Rows move into their pieces one by one: one copy in memory at a time.
    let (rows, eqs) = (std::mem::take(&mut sys.rows), std::mem::take(&mut sys.eqs));
    // A row's free weights, into a buffer reused row after row.
    let free_terms = |r: &Row, f: &mut Vec<usize>| {
        f.clear();
        f.extend(r.terms.iter().map(|t| t.0).filter(|&c| sys.free[c]));
    };
    let (mut f, mut joined) = (vec![], vec![]);
    for r in rows.iter().chain(&eqs) {
        if r.outside {
            continue;
        }
        free_terms(r, &mut f);
        for w in f.windows(2) {
            let (a, b) = (root(&mut parent, w[0]), root(&mut parent, w[1]));
            // The smaller index is the root: pieces come out in weight order.
            parent[a.max(b)] = a.min(b);
        }
    }
    let mut piece_of = vec![usize::MAX; sys.n];
    let mut local = vec![usize::MAX; sys.n];
    let mut out: Vec<Piece> = vec![];
    for v in (0..sys.n).filter(|&v| sys.free[v]) {
        let r = root(&mut parent, v);
        if piece_of[r] == usize::MAX {
            piece_of[r] = out.len();
            out.push(Piece {
                sys: System {
                    verdict: sys.verdict,
                    unit2: sys.unit2,
                    ..Default::default()
                },
                cols: vec![],
            });
        }
        piece_of[v] = piece_of[r];
        local[v] = out[piece_of[r]].cols.len();
        out[piece_of[r]].cols.push(v);
        out[piece_of[r]].sys.l2.push(sys.l2[v]);
    }
    for (row, eq) in rows
        .into_iter()
        .map(|r| (r, false))
        .chain(eqs.into_iter().map(|r| (r, true)))
    {
        let r = &row;
        free_terms(r, &mut f);
        let owner = f.first().map(|&c| piece_of[c]);
        joined.clear();
        joined.extend(f.iter().map(|&c| piece_of[c]));
        joined.sort_unstable();
        joined.dedup();
        let m = joined.len() as f64;
        if let [k] = joined[..] {
            // Whole in one piece (most rows): moved, its terms renumbered.
            let mut r = row;
            r.terms.retain(|t| sys.free[t.0]);
            r.terms.iter_mut().for_each(|t| t.0 = local[t.0]);
            let piece = &mut out[k].sys;
            if eq {
                piece.eqs.push(r);
            } else {
                piece.rows.push(r);
            }
            continue;
        }
        for &k in &joined {
            if m > 1.0 && r.weak {
                // Left to the exact check of RT(w).
                continue;
            }
            // Slack at zero weights is shared out; a row that zero weights
            // do not meet is the burden of the piece of its first weight
            // (the segment's or the edge's end), the others must not
            // worsen it.
            let (rhs, share) = if m == 1.0 {
                (r.rhs, r.share)
            } else if r.rhs < 0.0 {
                (r.rhs / m, r.share / m)
            } else if Some(k) == owner {
                (r.rhs, r.share)
            } else {
                (0.0, 0.0)
            };
            let row = Row {
                terms: r
                    .terms
                    .iter()
                    .filter(|t| sys.free[t.0] && piece_of[t.0] == k)
                    .map(|&(c, v)| (local[c], v))
                    .collect(),
                rhs,
                family: r.family,
                share,
                outside: r.outside,
                weak: r.weak,
            };
            let piece = &mut out[k].sys;
            if eq {
                piece.eqs.push(row);
            } else {
                piece.rows.push(row);
            }
        }
    }
    for p in &mut out {
        p.sys.n = p.cols.len();
        p.sys.free = vec![true; p.sys.n];
    }
    out
}

/// The local form's LP, piece by piece (in parallel): weights when every
/// piece has systems 1 and 3 with a trusted margin, else None.
fn solve_pieces(
    sys: System,
    report: &mut WeightsReport,
    progress: Option<Progress>,
) -> Result<Option<Vec<f64>>> {
    use rayon::prelude::*;
    use std::sync::atomic::{AtomicUsize, Ordering};
    let n = sys.n;
    let parts = pieces(sys);
    let done = AtomicUsize::new(0);
    let answers: Vec<(Result<Answer>, WeightsReport)> = parts
        .par_iter()
        .map(|p| {
            let mut r = WeightsReport {
                deadline: report.deadline,
                ..Default::default()
            };
            let answer = solve_rows(&p.sys, false, &mut r);
            let k = done.fetch_add(1, Ordering::Relaxed) + 1;
            if let Some(f) = progress.filter(|_| k % 64 == 0 || k == parts.len()) {
                f("weights: LP pieces", k, parts.len());
            }
            (answer, r)
        })
        .collect();
    report.lp_pieces = parts.len();
    let mut w = vec![0.0; n];
    let mut all = true;
    for ((answer, r), part) in answers.into_iter().zip(&parts) {
        report.absorb(&r);
        match answer? {
            Answer::Weights(pw, _) => {
                for (k, &v) in part.cols.iter().enumerate() {
                    w[v] = pw[k];
                }
            }
            _ => all = false,
        }
    }
    Ok(all.then_some(w))
}

/// A candidate from one LP attempt, verified to conform.
struct Found {
    w: Vec<f64>,
    rt: Triangulation,
    sys3_failed: Vec<u32>,
    /// Whether the LP found system 3 feasible on its rows (false: elastic).
    lp_sys3: bool,
}

fn finish(found: Found, mut report: WeightsReport) -> Result<Weights> {
    report.max_abs_weight = found.w.iter().fold(0.0, |m, w| m.max(w.abs()));
    report.system3_feasible = found.sys3_failed.is_empty();
    Ok(Weights {
        w: found.w,
        rt: found.rt,
        report,
        sys3_failed: found.sys3_failed,
    })
}

/// Which rows a row belongs to.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Family {
    Sys1,
    Sys3(u32),
    /// An anchor on a segment's dual line: in `rows`, an elastic equality
    /// in phase 2 only.
    Anchor,
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

/// Power-test rows for every interior edge of `t`, and system 3 rows for
/// every segment against the apexes of `t` beside it.
/// Only rows with a free weight are written: a row over zero weights alone
/// is a fixed Delaunay property that the exact verification checks anyway.
fn local_system(
    cx: &Complex,
    t: &Triangulation,
    inside: &[bool],
    units: &Units<2>,
    free: Vec<bool>,
) -> System {
    let p = &units.points;
    let any_free = |vs: &[u32]| vs.iter().any(|&v| free[v as usize]);
    let mut sys = System {
        n: p.len(),
        l2: units.l2.clone(),
        unit2: units.unit2,
        ..Default::default()
    };
    let segments: std::collections::HashSet<[u32; 2]> = cx
        .segments
        .iter()
        .map(|&[i, j]| [i.min(j), i.max(j)])
        .collect();
    use rayon::prelude::*;
    // In parallel, in edge order then segment order (rows stay deterministic).
    let inner: Vec<(u32, u32, u32, u32)> = t
        .edge_triangles()
        .filter_map(|(a, b, tl, tr)| Some((a, b, tl, tr?)))
        .collect();
    sys.rows = inner
        .par_iter()
        .filter_map(|&(a, b, tl, tr)| {
            let (c, d) = (t.apex(tl, a, b), t.apex(tr, b, a));
            any_free(&[a, b, c, d]).then(|| {
                let mut row = convexity_row(p, a, b, c, d);
                row.outside = !inside[tl as usize] || !inside[tr as usize];
                row.weak = row.outside && !segments.contains(&[a.min(b), a.max(b)]);
                row
            })
        })
        .collect();
    let per_segment: Vec<Vec<Row>> = cx
        .segments
        .par_iter()
        .enumerate()
        .map(|(s, &[i, j])| {
            let (mut apexes, mut outside) = (vec![], vec![]);
            for (x, y) in [(i, j), (j, i)] {
                if let Some(tri) = t.left_of(x, y) {
                    apexes.push(t.apex(tri, x, y));
                    outside.push(!inside[tri as usize]);
                }
            }
            if !(any_free(&[i, j]) || any_free(&apexes)) {
                return vec![];
            }
            let mut rows = sys3_rows(p, s as u32, i, j, &apexes);
            // Its last rows are the apexes', in order.
            let first = rows.len() - apexes.len();
            for (row, out) in rows[first..].iter_mut().zip(outside) {
                row.outside = out;
            }
            rows
        })
        .collect();
    sys.rows.extend(per_segment.into_iter().flatten());
    sys.free = free;
    sys
}

/// For each anchored segment (i, j) with anchor c: the power difference of
/// c to i and j is zero, w_i - w_j = |c - p_i|^2 - |c - p_j|^2, over L^2.
/// An equality where zero weights meet it (orthogonality already there is
/// not traded for orthogonality elsewhere), else elastic in phase 2.
fn anchor_rows(sys: &mut System, cx: &Complex, units: &Units<2>) {
    let p = &units.points;
    let scale = units.unit2.sqrt();
    let zero = vec![0.0; cx.points.len()];
    for (s, &[i, j]) in cx.segments.iter().enumerate() {
        let Some(c) = cx.anchor(s) else { continue };
        let c = Vector2::new(c[0] / scale, c[1] / scale);
        let d2 = |v: u32| (c - Vector2::from(p[v as usize])).norm_squared();
        let l = rel(p, i, j).norm_squared();
        let row = Row {
            terms: vec![(i as usize, 1.0 / l), (j as usize, -1.0 / l)],
            rhs: (d2(i) - d2(j)) / l,
            family: Family::Anchor,
            share: 1.0,
            outside: false,
            weak: false,
        };
        if anchor_offset(cx, &zero, s).is_some_and(|o| o.abs() <= ANCHOR_MET) {
            sys.eqs.push(row);
        } else {
            sys.rows.push(row);
        }
    }
}

/// Endpoints of the segments that zero weights do not serve (not strictly
/// Gabriel edges of the Delaunay triangulation, or an anchor missed), and
/// two rings of constrained-Delaunay neighbours around them: the weights
/// that may move.
fn near_failures(
    cx: &Complex,
    dt: &Triangulation,
    cdt: &Triangulation,
    unmet: &[u32],
) -> Vec<bool> {
    let nb = cdt.neighbours(cx.points.len());
    let mut free = vec![false; cx.points.len()];
    let mut ring: Vec<u32> = cx
        .segments
        .iter()
        .filter(|s| !(dt.has_edge(s[0], s[1]) && strictly_gabriel(cx, dt, s[0], s[1])))
        .chain(unmet.iter().map(|&s| &cx.segments[s as usize]))
        .flat_map(|s| [s[0], s[1]])
        .collect();
    for _ in 0..3 {
        let mut next = vec![];
        for v in ring {
            if !std::mem::replace(&mut free[v as usize], true) {
                next.extend(nb[v as usize].iter().copied());
            }
        }
        ring = next;
    }
    free
}

/// p_to - p_from.
pub(crate) fn rel<const D: usize>(p: &[[f64; D]], from: u32, to: u32) -> SVector<f64, D> {
    SVector::from(p[to as usize]) - SVector::from(p[from as usize])
}

/// Lifted edge (a, b) of ccw triangle (a, b, c), apex d across: locally
/// convex iff det[[b-a, Zb], [c-a, Zc], [d-a, Zd]] > 0, Z relative to a.
fn convexity_row(p: &[[f64; 2]], a: u32, b: u32, c: u32, d: u32) -> Row {
    let (u, v, r) = (rel(p, a, b), rel(p, a, c), rel(p, a, d));
    let (ca, cb, cc) = (v.perp(&r), u.perp(&r), u.perp(&v));
    let c0 = u.norm_squared() * ca - v.norm_squared() * cb + r.norm_squared() * cc;
    let norm = u.norm_squared() * (cc.abs() + cb.abs()) / 2.0;
    Row {
        terms: vec![
            (a as usize, (ca - cb + cc) / norm),
            (b as usize, -ca / norm),
            (c as usize, cb / norm),
            (d as usize, -cc / norm),
        ],
        rhs: -c0 / norm,
        family: Family::Sys1,
        share: 1.0,
        outside: false,
        weak: false,
    }
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
        },
        Row {
            terms: vec![(i, 1.0 / l), (j, -1.0 / l)],
            rhs: -1.0,
            family: fam,
            share: 1.0,
            outside: false,
            weak: false,
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
        sys.eqs.push(Row::sys1(terms, u.norm_squared() / scale2));
    }
    for &m in others {
        let r = rel(p, i, m);
        // |r|^2 - w_m + w_i - a.r >= delta * scale2
        let mut terms = vec![(m as usize, -1.0 / scale2), (i as usize, 1.0 / scale2)];
        terms.extend(slopes(r, -1.0));
        sys.rows.push(Row::sys1(terms, -r.norm_squared() / scale2));
    }
    a0
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
        }
    }
}

enum Mode {
    /// Maximise delta.
    Margin,
    /// System 1 with delta >= min; system 3 rows elastic, minimise the
    /// violation, segment s weighted by costs[s] (1 where absent).
    Elastic {
        delta_min: f64,
        costs: HashMap<u32, f64>,
    },
}

struct Solution {
    delta: f64,
    w: Vec<f64>,
    /// Elastic mode: the violation of system 3 per segment.
    slack: HashMap<u32, f64>,
}

/// HiGHS runs (shared) and instance drops (exclusive), see `Lp::solve`.
static HIGHS: std::sync::RwLock<()> = std::sync::RwLock::new(());

/// One HiGHS model of a row system, kept across phase 1's k ladder and
/// phase 2. Each free weight is the difference of two non-negative columns,
/// w_i = p_i - q_i, so that phase 2's objective sum (p_i + q_i) / l_i^2
/// (which is sum |w_i| / l_i^2 at the optimum) needs no rows: going from
/// phase 1 to phase 2 changes only costs and delta's bounds, phase 1's
/// optimal basis stays feasible, and the primal simplex goes on from it
/// (measured on the local form's pieces: phase 2 had cost more than phase
/// 1, from scratch or with |w_i| as rows).
struct Lp {
    model: Option<highs::Model>,
    /// Per weight, its columns (p, q); None for fixed weights, which are
    /// zero and left out of the rows.
    w: Vec<Option<(highs::Col, highs::Col)>>,
    delta: highs::Col,
    /// Elastic mode: the violation column of each segment.
    slack: HashMap<u32, highs::Col>,
    /// Rows of `sys.rows` not in the model yet (see `LAZY_SLACK`).
    lazy: Vec<usize>,
    /// Whether the next solve is the dual simplex (see `Lp::simplex`).
    dual: bool,
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
const DROP_BATCH: usize = 64;

impl Drop for Lp {
    fn drop(&mut self) {
        let Some(model) = self.model.take() else {
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
/// thread of rayon's pool (at the end of a weights step).
pub(crate) fn destroy_finished() {
    let flush = || {
        let batch = FINISHED.with_borrow_mut(std::mem::take);
        let _alone = HIGHS.write().unwrap_or_else(|e| e.into_inner());
        drop(batch);
    };
    flush();
    rayon::broadcast(|_| flush());
}

/// v w_c as terms of the model: v p_c - v q_c, nothing for a fixed weight.
fn weight_terms(
    w: &[Option<(highs::Col, highs::Col)>],
    c: usize,
    v: f64,
) -> Vec<(highs::Col, f64)> {
    w[c].map_or(vec![], |(p, q)| vec![(p, v), (q, -v)])
}

/// A row over weights alone (no auxiliary columns) as model terms.
fn weight_row(w: &[Option<(highs::Col, highs::Col)>], r: &Row) -> Vec<(highs::Col, f64)> {
    r.terms
        .iter()
        .flat_map(|&(c, v)| weight_terms(w, c, v))
        .collect()
}

/// New values for columns: bounds (lower, upper) or costs, one per column.
enum Change<'a> {
    Bounds(&'a [f64], &'a [f64]),
    Costs(&'a [f64]),
}

/// Changes many columns in one HiGHS call: the crate changes one at a
/// time, and HiGHS invalidates its solution and info at every call
/// (measured: 6% of the pieces' instructions).
#[allow(unsafe_code)]
fn change_columns(model: &mut highs::Model, cols: &[highs::Col], change: Change) -> Result<()> {
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
        return Err(Error::Lp("HiGHS refused to change the LP's columns".into()));
    }
    Ok(())
}

/// HiGHS refused a row or the model.
fn rejected(e: highs::HighsStatus) -> Error {
    Error::Lp(format!(
        "HiGHS rejects the LP as built ({e:?}): its coefficients are beyond its range \
         (nearly coincident or collinear vertices?)"
    ))
}

/// A lower bound of a simplex model's margin: the margin that zero
/// weights reach, where that is nearer zero than delta's upper bound 1.
/// HiGHS starts a boxed column at its bound nearer zero, so delta starts
/// here and the slack basis meets every margin row (measured: 2% fewer
/// instructions). The optimum is the same: zero weights reach this margin.
fn margin_floor(sys: &System, with3: bool, big: bool) -> Bound<f64> {
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

/// Whether a row is one of the model's margin rows: system 1's, and
/// system 3's when asked for (anchors are elastic rows of phase 2).
fn margin_row(r: &Row, with3: bool) -> bool {
    match r.family {
        Family::Anchor => false,
        Family::Sys3(_) => with3,
        Family::Sys1 => true,
    }
}

/// Upper bound of p_i and q_i (>= 0) for |w_i| <= k l_i^2 (k None:
/// unbounded).
fn part_upper(sys: &System, i: usize, k: Option<f64>) -> f64 {
    k.map_or(f64::INFINITY, |k| k * sys.l2[i])
}

impl Lp {
    /// The model of `sys` in `mode` (Margin or Elastic; phase 2 comes from
    /// a Margin model through `regularise`).
    fn build(sys: &System, with3: bool, k: Option<f64>, mode: &Mode) -> Result<Lp> {
        let mut pb = RowProblem::default();
        let free = (Bound::<f64>::Unbounded, Bound::<f64>::Unbounded);
        let w: Vec<_> = (0..sys.n)
            .map(|i| {
                sys.free[i].then(|| {
                    let b = 0.0..=part_upper(sys, i, k);
                    (pb.add_column(0.0, b.clone()), pb.add_column(0.0, b))
                })
            })
            .collect();
        let aux: Vec<_> = (0..sys.aux).map(|_| pb.add_column(0.0, free)).collect();
        let big = sys.eqs.len() + sys.rows.len() > BIG_MODEL;
        let (delta, sense) = match mode {
            Mode::Margin => (
                pb.add_column(1.0, (margin_floor(sys, with3, big), Bound::Included(1.0))),
                Sense::Maximise,
            ),
            Mode::Elastic { delta_min, .. } => (
                pb.add_column(0.0, *delta_min..=1.0f64.max(*delta_min)),
                Sense::Minimise,
            ),
        };
        let terms = |r: &Row| -> Vec<(highs::Col, f64)> {
            r.terms
                .iter()
                .flat_map(|&(c, v)| match c.checked_sub(sys.n) {
                    Some(a) => vec![(aux[a], v)],
                    None => weight_terms(&w, c, v),
                })
                .collect()
        };
        let mut slack = HashMap::new();
        for r in sys.eqs.iter().filter(finite) {
            pb.add_row(r.rhs..=r.rhs, terms(r));
        }
        let lazy_ok = matches!(mode, Mode::Margin) && sys.aux == 0 && !big;
        let mut lazy = vec![];
        for (at, r) in sys.rows.iter().enumerate().filter(|(_, r)| finite(r)) {
            match (r.family, mode) {
                // Anchors (elastic in phase 2 only, `regularise`), and
                // system 3 unless asked for.
                _ if !margin_row(r, with3) => continue,
                // A margin row; its slack at zero weights and margin is -rhs.
                _ if lazy_ok && -r.rhs > LAZY_SLACK => lazy.push(at),
                (Family::Sys3(s), Mode::Elastic { costs, .. }) => {
                    // sum(terms) + slack_s >= rhs + small positive margin
                    let cost = costs.get(&s).copied().unwrap_or(1.0);
                    let sl = *slack.entry(s).or_insert_with(|| pb.add_column(cost, 0.0..));
                    let mut terms = terms(r);
                    terms.push((sl, 1.0));
                    pb.add_row((r.rhs + 1e-3).., terms);
                }
                _ => {
                    let mut terms = terms(r);
                    terms.push((delta, -r.share));
                    pb.add_row(r.rhs.., terms);
                }
            }
        }
        let mut model = pb.try_optimise(sense).map_err(rejected)?;
        model.make_quiet();
        // Measured: dual simplex stalls on large sparse systems of this shape
        // where interior point finishes in seconds (docs/method.md section 2).
        model.set_option("solver", if big { "ipm" } else { "simplex" });
        if !big {
            // Measured: the primal simplex is 20% faster than the dual
            // (steepest edge) on the pieces' phase 1, and goes on from phase
            // 1's basis in phase 2. The dual goes on after rows enter or
            // bounds loosen (`Lp::simplex`); devex pricing, as the primal's:
            // steepest edge weights cost more than the few iterations need.
            model.set_option("simplex_strategy", 4);
            model.set_option("simplex_dual_edge_weight_strategy", 1);
            // Measured: on the local form's small pieces presolve costs as
            // much as the solve (and it would discard the warm start).
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
            delta,
            slack,
            lazy,
            dual: false,
        })
    }

    /// The lazy rows that the solution `cols` violates, now in the model.
    fn enter_violated(&mut self, sys: &System, cols: &[f64]) -> Result<bool> {
        let value = |r: &Row| {
            r.terms
                .iter()
                .filter_map(|&(c, v)| {
                    self.w[c].map(|(p, q)| v * (cols[p.index()] - cols[q.index()]))
                })
                .sum::<f64>()
                - r.share * cols[self.delta.index()]
                - r.rhs
        };
        let (enter, keep): (Vec<usize>, Vec<usize>) = self
            .lazy
            .iter()
            .partition(|&&at| value(&sys.rows[at]) < 0.0);
        for &at in &enter {
            let r = &sys.rows[at];
            let mut terms = weight_row(&self.w, r);
            terms.push((self.delta, -r.share));
            let model = self.model.as_mut().expect("model");
            model.try_add_row(r.rhs.., terms).map_err(rejected)?;
        }
        self.lazy = keep;
        if !enter.is_empty() {
            self.simplex(true);
        }
        Ok(!enter.is_empty())
    }

    /// Which simplex goes on from the current basis: the dual after rows
    /// enter or bounds loosen (the basis stays dual feasible), the primal
    /// after costs change (it stays primal feasible). Simplex models only.
    /// Measured (callgrind, the pieces' solves at 13,200 segments): 15%
    /// fewer instructions than the primal throughout.
    fn simplex(&mut self, dual: bool) {
        if self.dual != dual {
            let model = self.model.as_mut().expect("model");
            model.set_option("simplex_strategy", if dual { 1 } else { 4 });
            self.dual = dual;
        }
    }

    /// Phase 1 again with |w_i| <= k l_i^2 (free: None).
    fn bound(&mut self, sys: &System, k: Option<f64>) -> Result<()> {
        self.simplex(true);
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

    /// Turns a solved Margin model into phase 2: delta >= delta_min,
    /// minimise sum |w_i| / l_i^2 plus the anchors' violations.
    fn regularise(&mut self, sys: &System, delta_min: f64) -> Result<()> {
        self.simplex(false);
        let model = self.model.as_mut().expect("model");
        model.set_sense(Sense::Minimise);
        model.change_column_bounds(self.delta, delta_min..=1.0f64.max(delta_min));
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
                let up = model
                    .try_add_column(ANCHOR_COST, 0.0.., [])
                    .map_err(rejected)?;
                let down = model
                    .try_add_column(ANCHOR_COST, 0.0.., [])
                    .map_err(rejected)?;
                let mut terms = weight_row(&self.w, r);
                terms.extend([(up, 1.0), (down, -1.0)]);
                model.try_add_row(r.rhs..=r.rhs, terms).map_err(rejected)?;
            }
        }
        Ok(())
    }

    /// Solves, and again while the solution violates lazy rows (which
    /// then enter the model; the basis goes on). Rows only lower the
    /// margin: a margin at or below `enough` is returned as it is, an upper
    /// bound of the whole system's.
    fn solve(&mut self, sys: &System, report: &mut WeightsReport, enough: f64) -> Result<Solution> {
        loop {
            let (solution, cols) = self.solve_once(sys, report)?;
            if solution.delta <= enough {
                return Ok(solution);
            }
            match cols {
                Some(cols) if self.enter_violated(sys, &cols)? => continue,
                _ => return Ok(solution),
            }
        }
    }

    /// One HiGHS run: the solution, and the columns when optimal.
    fn solve_once(
        &mut self,
        sys: &System,
        report: &mut WeightsReport,
    ) -> Result<(Solution, Option<Vec<f64>>)> {
        let left = report.deadline.map_or(LP_BUDGET, |d| {
            d.saturating_duration_since(std::time::Instant::now())
        });
        if left.is_zero() {
            return Err(Error::Lp(format!(
                "the LP time budget of {} s ran out",
                LP_BUDGET.as_secs()
            )));
        }
        // Taken out (a solve consumes it) only now: on the early return the
        // model stays for `Drop`, which destroys it under the lock.
        let mut model = self.model.take().expect("model");
        report.lp_rows = report.lp_rows.max(model.num_rows());
        report.lp_cols = report.lp_cols.max(model.num_cols());
        report.lp_solves += 1;
        model.set_option("time_limit", left.as_secs_f64());
        let solved = {
            let _running = HIGHS.read().unwrap_or_else(|e| e.into_inner());
            model
                .try_solve()
                .map_err(|e| Error::Lp(format!("HiGHS: {e:?}")))?
        };
        let status = solved.status();
        let cols =
            (status == HighsModelStatus::Optimal).then(|| solved.get_solution().columns().to_vec());
        self.model = Some(solved.into());
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
                    return Err(Error::Lp(
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
            HighsModelStatus::Infeasible => Ok((
                Solution {
                    delta: f64::NEG_INFINITY,
                    w: vec![],
                    slack: HashMap::new(),
                },
                None,
            )),
            HighsModelStatus::ReachedTimeLimit => Err(Error::Lp(format!(
                "the LP time budget of {} s ran out ({} solves of up to {} rows)",
                LP_BUDGET.as_secs(),
                report.lp_solves,
                report.lp_rows
            ))),
            s => Err(Error::Lp(format!("HiGHS ended with status {s:?}"))),
        }
    }
}

/// A row from a triangle too thin for doubles may hold infinities: it is
/// left out (the exact verification of the result still covers it).
fn finite(r: &&Row) -> bool {
    r.rhs.is_finite() && r.terms.iter().all(|t| t.1.is_finite())
}

/// One model, one solve.
fn run(
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
fn margin(sys: &System, with3: bool, report: &mut WeightsReport) -> Result<(f64, Option<f64>, Lp)> {
    let ladder: Vec<Option<f64>> = K_LADDER.iter().map(|&k| Some(k)).collect();
    let order: Vec<Option<f64>> = if sys.verdict {
        [None].into_iter().chain(ladder).collect()
    } else {
        ladder.into_iter().chain([None]).collect()
    };
    let mut lp = Lp::build(sys, with3, order[0], &Mode::Margin)?;
    let mut best = (f64::NEG_INFINITY, None);
    for (step, &k) in order.iter().enumerate() {
        if step > 0 {
            lp.bound(sys, k)?;
        }
        // A rung whose margin is not returned fails as soon as its rows so
        // far leave none (lazy rows cannot raise it).
        let returned = step + 1 == order.len() || (sys.verdict && step == 0);
        let enough = if returned { f64::NEG_INFINITY } else { TRUST };
        let delta = lp.solve(sys, report, enough)?.delta;
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
    lp.bound(sys, None)?;
    lp.solve(sys, report, f64::NEG_INFINITY)?;
    Ok((best.0, best.1, lp))
}

/// The outcome of one LP attempt on a row system.
enum Attempt {
    /// Weights whose RT contains every segment (system 3 checked exactly).
    Found(Found),
    /// Weights whose RT (given) misses segments or hides vertices: rows
    /// are missing.
    NotConforming(Vec<f64>, Triangulation),
    /// System 1 has no trusted margin on these rows.
    Sys1Infeasible,
    /// Systems 1 and 3 together have none (asked not to go elastic).
    Sys3Infeasible,
}

/// What the LP says about one row system (no verification yet).
pub(crate) enum Answer {
    /// Weights (for the system's columns), and whether system 3 held on
    /// the rows (false: elastic).
    Weights(Vec<f64>, bool),
    /// System 1 has no trusted margin on these rows.
    Sys1Infeasible,
    /// Systems 1 and 3 together have none (asked not to go elastic).
    Sys3Infeasible,
}

/// One attempt on a row system: the LP, then the exact check.
fn attempt<B: Backend + ?Sized>(
    backend: &B,
    dom: &Domain,
    sys: &System,
    elastic: bool,
    report: &mut WeightsReport,
) -> Result<Attempt> {
    match solve_rows(sys, elastic, report)? {
        Answer::Weights(w, lp_sys3) => verify(backend, dom, w, lp_sys3),
        Answer::Sys1Infeasible => Ok(Attempt::Sys1Infeasible),
        Answer::Sys3Infeasible => Ok(Attempt::Sys3Infeasible),
    }
}

/// Builds RT(w) with exact predicates and checks it segment by segment.
fn verify<B: Backend + ?Sized>(
    backend: &B,
    dom: &Domain,
    w: Vec<f64>,
    lp_sys3: bool,
) -> Result<Attempt> {
    let cx = &dom.complex;
    let rt = regular_from(backend, &cx.points, &w, &dom.cdt, dom.cdt.edges().collect())?;
    if conforms(cx, &rt).is_err() {
        return Ok(Attempt::NotConforming(w, rt));
    }
    let sys3_failed = sys3_failures(cx, &w, &rt);
    Ok(Attempt::Found(Found {
        w,
        rt,
        sys3_failed,
        lp_sys3,
    }))
}

/// The LP on one row system: system 1 + 3; else system 1 with system 3
/// elastic (as few segments as possible missing their duals).
pub(crate) fn solve_rows(
    sys: &System,
    elastic: bool,
    report: &mut WeightsReport,
) -> Result<Answer> {
    let (m3, k3, mut lp) = margin(sys, true, report)?;
    if m3 <= TRUST && !elastic {
        return Ok(Answer::Sys3Infeasible);
    }
    let (w, lp_sys3) = if m3 > TRUST {
        report.margin = Some(m3);
        report.bound_k = k3;
        lp.regularise(sys, m3 / 2.0)?;
        (lp.solve(sys, report, f64::NEG_INFINITY)?.w, true)
    } else {
        drop(lp);
        // Usually system 1 alone has a comfortable margin: one elastic solve
        // at a fixed margin settles it; only when that fails is the margin of
        // system 1 searched (and its absence a verdict).
        let elastic = |costs| Mode::Elastic {
            delta_min: ELASTIC_MARGIN,
            costs,
        };
        let quick = run(sys, true, None, &elastic(HashMap::new()), report)?;
        if quick.delta >= ELASTIC_MARGIN {
            // Reweighted once (cost 1 / (violation + eps)): the total
            // violation is spread over fewer segments, so fewer miss their
            // duals and fewer sites end outside.
            let costs = quick
                .slack
                .iter()
                .map(|(&s, &v)| (s, 1.0 / (v.max(0.0) + 1e-3)))
                .collect();
            let sparse = run(sys, true, None, &elastic(costs), report)?;
            let w = if sparse.delta >= ELASTIC_MARGIN {
                sparse.w
            } else {
                quick.w
            };
            report.margin = Some(quick.delta);
            report.bound_k = None;
            (w, false)
        } else {
            let (m1, k1, _) = margin(sys, false, report)?;
            report.margin = Some(m1);
            report.bound_k = k1;
            if m1 <= TRUST {
                return Ok(Answer::Sys1Infeasible);
            }
            (
                run(
                    sys,
                    true,
                    k1,
                    &Mode::Elastic {
                        delta_min: m1 / 2.0,
                        costs: HashMap::new(),
                    },
                    report,
                )?
                .w,
                false,
            )
        }
    };
    Ok(Answer::Weights(w, lp_sys3))
}

/// The regular triangulation of weighted points from a triangulation of
/// the same points (`start`, all of them vertices) by Lawson flips from
/// `edges`, which must hold every edge of `start` that may fail the power
/// test: every edge is then locally regular, so the triangulation is
/// regular (decided exactly). From the backend when a flip is stuck (a
/// vertex that the weights hide, say). Near the start, flips cost a
/// fraction of a build (measured: ... at 10^5 segments).
fn regular_from<B: Backend + ?Sized>(
    backend: &B,
    points: &[[f64; 2]],
    w: &[f64],
    start: &Triangulation,
    edges: Vec<(u32, u32)>,
) -> Result<Triangulation> {
    let mut t = start.clone();
    let tests = crate::backend::points::F64Points { p: points, w };
    if (0..points.len() as u32).all(|v| t.is_vertex(v))
        && t.flip_to_regular(&tests, edges).is_some()
    {
        return Ok(t);
    }
    backend.regular(points, w)
}

/// Ok, or the segments missing from `rt` (and hidden vertices as Err too).
fn conforms(cx: &Complex, rt: &Triangulation) -> std::result::Result<(), (Vec<u32>, Vec<u32>)> {
    let missing: Vec<u32> = (0..cx.segments.len() as u32)
        .filter(|&s| !rt.has_edge(cx.segments[s as usize][0], cx.segments[s as usize][1]))
        .collect();
    if missing.is_empty() && rt.hidden.is_empty() {
        Ok(())
    } else {
        Err((missing, rt.hidden.clone()))
    }
}

/// Whether every segment is a locally Delaunay edge of the constrained
/// Delaunay triangulation t (exact incircle).
fn delaunay(cx: &Complex, t: &Triangulation) -> bool {
    let p = &cx.points;
    let c = |v: u32| robust::Coord {
        x: p[v as usize][0],
        y: p[v as usize][1],
    };
    cx.segments.iter().all(|&[a, b]| {
        let (Some(t1), Some(t2)) = (t.left_of(a, b), t.left_of(b, a)) else {
            return true;
        };
        let (x, y) = (t.apex(t1, a, b), t.apex(t2, b, a));
        robust::incircle(c(a), c(b), c(x), c(y)) <= 0.0
    })
}

/// Strictly Gabriel, for a segment that is an edge of the Delaunay
/// triangulation: both apexes outside the closed diametral disc.
fn strictly_gabriel(cx: &Complex, dt: &Triangulation, i: u32, j: u32) -> bool {
    let p = &cx.points;
    [(i, j), (j, i)]
        .iter()
        .all(|&(a, b)| match dt.left_of(a, b) {
            Some(t) => {
                !in_diametral_disc(p[i as usize], p[j as usize], p[dt.apex(t, a, b) as usize])
            }
            None => true,
        })
}

/// Segments of `rt` that do not cross their dual edge, decided exactly:
/// |w_i - w_j| < L and the radical point of i, j on the segment has smaller
/// power for i than for each apex beside the segment.
pub fn sys3_failures(cx: &Complex, w: &[f64], rt: &Triangulation) -> Vec<u32> {
    use crate::geom::Iv;
    use rayon::prelude::*;
    let p = &cx.points;
    // Filtered: the same expressions in intervals, exact rationals only
    // where an interval holds zero.
    let holds = |s: usize| -> bool {
        let [i, j] = cx.segments[s];
        let apexes: Vec<u32> = [(i, j), (j, i)]
            .into_iter()
            .filter_map(|(a, b)| rt.left_of(a, b).map(|t| rt.apex(t, a, b)))
            .collect();
        let iv = |v: u32| p[v as usize].map(Iv::of);
        let ivsub = |a: [Iv; 2], b: [Iv; 2]| [a[0] - b[0], a[1] - b[1]];
        let ivdot = |a: [Iv; 2], b: [Iv; 2]| a[0] * b[0] + a[1] * b[1];
        let (pi, pj) = (iv(i), iv(j));
        let u = ivsub(pj, pi);
        let l = ivdot(u, u);
        let d = Iv::of(w[i as usize]) - Iv::of(w[j as usize]);
        let mut signs = vec![(l - d).sign(), (l + d).sign()];
        for &m in &apexes {
            let r = ivsub(iv(m), pi);
            let v = l * ivdot(r, r) - (l + d) * ivdot(u, r)
                + l * (Iv::of(w[i as usize]) - Iv::of(w[m as usize]));
            signs.push(v.sign());
        }
        if signs.iter().all(Option::is_some) {
            return signs
                .iter()
                .all(|&o| o == Some(std::cmp::Ordering::Greater));
        }
        let (pi, pj) = (qp(p[i as usize]), qp(p[j as usize]));
        let u = sub(&pj, &pi);
        let l = norm2(&u);
        let d = q(w[i as usize]) - q(w[j as usize]);
        let mut ok = abs(&d) < l;
        for m in apexes {
            let r = sub(&qp(p[m as usize]), &pi);
            // L * (pi(q; m) - pi(q; i)) > 0
            let v: Q = &l * norm2(&r) - (&l + &d) * dot(&u, &r)
                + &l * (q(w[i as usize]) - q(w[m as usize]));
            ok &= is_pos(&v);
        }
        ok
    };
    (0..cx.segments.len())
        .into_par_iter()
        .filter(|&s| !holds(s))
        .map(|s| s as u32)
        .collect()
}

/// Vertices of triangles of `t` whose height is below 1e-9 of their longest
/// edge: the LP's tolerances cannot resolve their lifts.
fn slivers(p: &[[f64; 2]], t: &Triangulation) -> Vec<u32> {
    let mut out: Vec<u32> = vec![];
    for tri in &t.triangles {
        let [a, b, c] = *tri;
        let (u, v) = (rel(p, a, b), rel(p, a, c));
        let longest2 = u
            .norm_squared()
            .max(v.norm_squared())
            .max((v - u).norm_squared());
        if u.perp(&v).abs() < 1e-9 * longest2 {
            out.extend(tri);
        }
    }
    out.sort_unstable();
    out.dedup();
    out
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

/// The lazy global form: a supporting plane per segment and per isolated
/// vertex, with rows for the points near it; rows are added where RT(w)
/// disagrees. A restricted LP that is infeasible proves the full one so.
fn global<B: Backend + ?Sized>(
    backend: &B,
    dom: &Domain,
    units: &Units<2>,
    mut report: WeightsReport,
    anchored: bool,
) -> Result<Weights> {
    let cx = &dom.complex;
    let p = &units.points;
    let l2 = &units.l2;
    let n = p.len();
    let cdt_nb = dom.cdt.neighbours(n);
    let degree = cx.degrees();
    // Row sets: segments first, then isolated vertices.
    let owners: Vec<(u32, Option<u32>)> = cx
        .segments
        .iter()
        .map(|s| (s[0], Some(s[1])))
        .chain(
            (0..n as u32)
                .filter(|&v| degree[v as usize] == 0)
                .map(|v| (v, None)),
        )
        .collect();
    let mut sets: Vec<BTreeSet<u32>> = owners
        .iter()
        .map(|&(i, j)| {
            let mut s: BTreeSet<u32> = cdt_nb[i as usize].iter().copied().collect();
            if let Some(j) = j {
                s.extend(cdt_nb[j as usize].iter().copied());
                s.remove(&j);
            }
            s.remove(&i);
            s
        })
        .collect();
    let mut last_missing: Vec<u32> = vec![];
    for round in 1..=GLOBAL_ROUNDS + 2 {
        report.global_rounds = round;
        let mut sys = System {
            n,
            free: vec![true; n],
            verdict: true,
            unit2: units.unit2,
            l2: l2.to_vec(),
            ..Default::default()
        };
        for (o, &(i, j)) in owners.iter().enumerate() {
            let others: Vec<u32> = sets[o].iter().copied().collect();
            let scale2 = j.map_or(l2[i as usize], |j| rel(p, i, j).norm_squared());
            plane_rows(&mut sys, p, i, j.as_slice(), &others, scale2);
            if let Some(j) = j {
                sys.rows.extend(sys3_rows(p, o as u32, i, j, &others));
            }
        }
        if anchored {
            anchor_rows(&mut sys, cx, units);
        }
        let (found, w, rt) = match attempt(backend, dom, &sys, true, &mut report)? {
            Attempt::Sys1Infeasible => {
                // The verdict is the LP's, in floating point: triangles far
                // thinner than its tolerances make it no verdict at all.
                let thin = slivers(&cx.points, &dom.cdt);
                if !thin.is_empty() {
                    let ids: Vec<i64> = thin.iter().map(|&v| cx.vertex_ids[v as usize]).collect();
                    return Err(Error::Lp(format!(
                        "cannot decide whether a regular constrained triangulation exists: the LP finds none, \
                         but triangles of nearly collinear vertices are beyond its precision (vertices {ids:?})"
                    )));
                }
                // Infeasible on a subset of the rows: infeasible outright.
                let ids = if last_missing.is_empty() {
                    (0..cx.segments.len() as u32).collect()
                } else {
                    last_missing
                };
                return Err(Error::NoRegularConstrainedTriangulation {
                    segments: ids.iter().map(|&s| cx.segment_ids[s as usize]).collect(),
                });
            }
            // Elastic: system 3 is infeasible on a subset of its rows, hence
            // outright; keep these weights.
            Attempt::Found(f) if f.sys3_failed.is_empty() || !f.lp_sys3 => {
                return finish(f, report)
            }
            Attempt::Found(f) => {
                let (w, rt) = (f.w.clone(), f.rt.clone());
                (Some(f), w, rt)
            }
            Attempt::NotConforming(w, rt) => (None, w, rt),
            Attempt::Sys3Infeasible => unreachable!("the global form goes elastic"),
        };
        let (missing, hidden) = conforms(cx, &rt).err().unwrap_or_default();
        let sys3_bad = if missing.is_empty() && hidden.is_empty() {
            sys3_failures(cx, &w, &rt)
        } else {
            vec![]
        };
        last_missing = missing.clone();
        let rt_nb = rt.neighbours(n);
        let widen = round > GLOBAL_ROUNDS / 2;
        let mut grew = false;
        let mut bad_owners: BTreeSet<usize> = missing
            .iter()
            .chain(&sys3_bad)
            .map(|&s| s as usize)
            .collect();
        for h in &hidden {
            if let Some(o) = owners.iter().position(|&(i, j)| i == *h || j == Some(*h)) {
                bad_owners.insert(o);
            }
        }
        for o in bad_owners {
            let (i, j) = owners[o];
            let before = sets[o].len();
            let ends: Vec<u32> = std::iter::once(i).chain(j).collect();
            // two rings around both ends, in RT(w) and in the CDT
            let mut ring: BTreeSet<u32> = BTreeSet::new();
            for &e in &ends {
                for &a in rt_nb[e as usize].iter().chain(&cdt_nb[e as usize]) {
                    ring.insert(a);
                    ring.extend(rt_nb[a as usize].iter().copied());
                    ring.extend(cdt_nb[a as usize].iter().copied());
                }
            }
            if widen {
                ring.extend(0..n as u32); // the dense rows for this owner only
            }
            for e in &ends {
                ring.remove(e);
            }
            sets[o].extend(ring);
            grew |= sets[o].len() > before;
        }
        let rows: usize = sets.iter().map(BTreeSet::len).sum();
        if rows > MAX_GLOBAL_ROWS {
            // Dense rows for many owners would not fit; better a clear stop.
            return Err(Error::Lp(format!(
                "the lazy global form needs more than {MAX_GLOBAL_ROWS} rows without converging \
                 (segments still missing: {:?})",
                missing
                    .iter()
                    .take(20)
                    .map(|&s| cx.segment_ids[s as usize])
                    .collect::<Vec<_>>()
            )));
        }
        if !grew {
            // Every violated owner has all its rows, yet RT(w) disagrees:
            // the LP's margin is below what the exact check can confirm.
            if let Some(f) = found {
                return finish(f, report);
            }
            return Err(Error::Lp(format!(
                "weights from the global form do not give a conforming triangulation (segments {:?} missing) and no rows are left to add",
                missing.iter().map(|&s| cx.segment_ids[s as usize]).collect::<Vec<_>>()
            )));
        }
    }
    Err(Error::Lp("the lazy global form did not converge".into()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn anchor_offsets_by_hand() {
        let mut cx = Complex::new(
            vec![[0.0, 0.0], [2.0, 0.0], [1.0, 3.0]],
            vec![[0, 1], [1, 2]],
        );
        cx.anchors = vec![Some([1.5, 1.0]), None];
        // power difference (3.25 - 1.25) over 2 L^2 = 8
        assert_eq!(anchor_offset(&cx, &[0.0; 3], 0), Some(0.25));
        assert_eq!(unmet_anchors(&cx, &[0.0; 3]), vec![0]);
        // w_0 - w_1 = 2 puts the anchor on the radical line
        assert_eq!(anchor_offset(&cx, &[2.0, 0.0, 0.0], 0), Some(0.0));
        assert_eq!(anchor_offset(&cx, &[0.0; 3], 1), None);
        assert!(cx.validate().is_ok());
        cx.anchors = vec![Some([f64::NAN, 0.0]), None];
        assert!(cx.validate().is_err());
        cx.anchors = vec![None];
        assert!(cx.validate().is_err());
    }

    #[test]
    fn convexity_row_matches_the_incircle_sign() {
        // Unit square split by the diagonal (0,2): the other two corners are
        // cocircular, so zero weights give a zero row value.
        let p = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        // edge 0->2, left triangle (0, 2, 3), right apex 1
        let r = convexity_row(&p, 0, 2, 3, 1);
        assert!((-r.rhs).abs() < 1e-12, "cocircular: {}", r.rhs);
        // Raising the weight of the apex lowers its lift: the edge becomes reflex.
        let coef_d = r.terms.iter().find(|t| t.0 == 1).unwrap().1;
        assert!(coef_d < 0.0);
        // Pushing d outwards makes the edge convex with zero weights.
        let p2 = [[0.0, 0.0], [1.5, -0.5], [1.0, 1.0], [0.0, 1.0]];
        let r2 = convexity_row(&p2, 0, 2, 3, 1);
        assert!(-r2.rhs > 0.0);
    }

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
        let a0 = plane_rows(&mut sys, &p, 0, &[1], &[2], 4.0);
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

    #[test]
    fn pieces_split_rows_between_them() {
        let row = |terms: Vec<(usize, f64)>, rhs: f64, outside: bool, weak: bool| Row {
            terms,
            rhs,
            family: Family::Sys1,
            share: 1.0,
            outside,
            weak,
        };
        let sys = System {
            n: 5,
            free: vec![true, true, true, true, false],
            unit2: 1.0,
            l2: vec![1.0, 2.0, 3.0, 4.0, 5.0],
            rows: vec![
                row(vec![(0, 1.0), (1, 1.0), (4, 7.0)], -1.0, false, false),
                row(vec![(2, 1.0), (3, 1.0)], -1.0, false, false),
                // outside with slack: halved between the two pieces
                row(vec![(1, 2.0), (2, 3.0)], -2.0, true, false),
                // outside, violated at zero: the first weight's piece's
                row(vec![(3, 1.0), (0, 1.0)], 0.5, true, false),
                // outside and weak between pieces: left out
                row(vec![(0, 1.0), (3, -1.0)], 0.0, true, true),
            ],
            ..Default::default()
        };
        let p = pieces(sys);
        assert_eq!(p.len(), 2);
        assert_eq!(p[0].cols, vec![0, 1]);
        assert_eq!(p[1].cols, vec![2, 3]);
        assert_eq!(p[0].sys.l2, vec![1.0, 2.0]);
        // (terms, rhs, share) of each row of a piece
        type Summary = Vec<(Vec<(usize, f64)>, f64, f64)>;
        let summary = |s: &System| -> Summary {
            s.rows
                .iter()
                .map(|r| (r.terms.clone(), r.rhs, r.share))
                .collect()
        };
        let expected: [Summary; 2] = [
            // The fixed weight 4 drops out of the first row.
            vec![
                (vec![(0, 1.0), (1, 1.0)], -1.0, 1.0),
                (vec![(1, 2.0)], -1.0, 0.5),
                (vec![(0, 1.0)], 0.0, 0.0),
            ],
            vec![
                (vec![(0, 1.0), (1, 1.0)], -1.0, 1.0),
                (vec![(0, 3.0)], -1.0, 0.5),
                (vec![(1, 1.0)], 0.5, 1.0),
            ],
        ];
        for (piece, want) in p.iter().zip(expected) {
            assert_eq!(summary(&piece.sys), want);
        }
    }

    #[test]
    fn flips_from_the_constrained_triangulation_give_the_regular_one() {
        use crate::sites::scatter;
        let n = 400;
        let p: Vec<[f64; 2]> = (0..n as u64)
            .map(|i| [scatter(2 * i) * 100.0, scatter(2 * i + 1) * 100.0])
            .collect();
        // Segments between near neighbours (by index order in x), not
        // crossing: a chain through the points sorted by x.
        let mut by_x: Vec<u32> = (0..n as u32).collect();
        by_x.sort_by(|&a, &b| p[a as usize][0].total_cmp(&p[b as usize][0]));
        let segments: Vec<[u32; 2]> = by_x.windows(2).step_by(7).map(|w| [w[0], w[1]]).collect();
        let edges = |t: &Triangulation| {
            let mut e: Vec<(u32, u32)> = t.edges().map(|(a, b)| (a.min(b), a.max(b))).collect();
            e.sort_unstable();
            e
        };
        for backend in crate::backend::compiled() {
            let cdt = backend.constrained_delaunay(&p, &segments).unwrap();
            let zero = vec![0.0; n];
            let from = segments.iter().map(|s| (s[0], s[1])).collect();
            let dt = regular_from(&*backend, &p, &zero, &cdt, from).unwrap();
            let fresh = backend.regular(&p, &zero).unwrap();
            assert_eq!(edges(&dt), edges(&fresh), "{}", backend.name());
            assert_ne!(edges(&cdt), edges(&fresh), "some segment is not Delaunay");
            // Weights small enough to hide no vertex, large enough to flip.
            let w: Vec<f64> = (0..n as u64)
                .map(|i| (scatter(9_000 + i) - 0.5) * 0.2)
                .collect();
            let rt = regular_from(&*backend, &p, &w, &cdt, cdt.edges().collect()).unwrap();
            let fresh = backend.regular(&p, &w).unwrap();
            assert!(fresh.hidden.is_empty());
            assert_ne!(edges(&fresh), edges(&dt), "the weights change some edge");
            assert_eq!(edges(&rt), edges(&fresh), "{}", backend.name());
        }
    }
}
