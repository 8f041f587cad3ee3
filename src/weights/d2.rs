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
use crate::domain::Domain;
use crate::error::{Error, Result};
use crate::geom::{abs, dot, in_diametral_disc, is_pos, norm2, orient, q, qp, sub, Q};
use crate::lp::{
    destroy_finished, plane_rows, prove, rel, solve_pieces, solve_rows, sys3_rows, Answer,
    Certificate, Duals, Family, Origin, Row, System, Units, WeightsReport, GLOBAL_ROUNDS,
    MAX_GLOBAL_ROWS,
};
use crate::progress::Progress;
use nalgebra::Vector2;
use rayon::prelude::*;
use std::collections::BTreeSet;

/// An anchor within this fraction of its segment's length of the dual line
/// is met (the hybrid report's orthogonality threshold is 1e-6).
const ANCHOR_MET: f64 = 1e-9;
/// Largest local system solved as one LP when its pieces give no answer
/// (measured: 13,600 free weights take 95 s as one LP, 0.7 s as pieces).
const MAX_JOINT_WEIGHTS: usize = 20_000;

/// Verified weights and their regular triangulation.
#[derive(Debug, Clone)]
pub struct Weights {
    pub w: Vec<f64>,
    /// RT(w): contains every segment, hides no vertex (checked exactly).
    pub rt: Triangulation,
    pub report: WeightsReport,
    /// Segments that do not cross their dual edge (exact check).
    pub sys3_failed: Vec<u32>,
    /// Segments that an exact certificate proves cannot all cross their
    /// dual edges (`lp::prove`; empty without one).
    pub sys3_proved: Vec<u32>,
}

/// Finds weights for the domain's complex.
pub fn solve<B: Backend + ?Sized>(
    backend: &B,
    dom: &Domain,
    progress: Option<Progress>,
) -> Result<Weights> {
    // (nothing cancels weights from outside: see weights::d3::solve)
    let out = crate::lp::carried(&[], || solve_unanchored_first(backend, dom, progress));
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
            .par_iter()
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
        sys3_proved: vec![],
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
            z.report.lp_iterations = w.report.lp_iterations;
            z.report.lp_rows = w.report.lp_rows;
            z.report.lp_cols = w.report.lp_cols;
            Ok(z)
        }
        // The LP gave no answer (slivers beyond its precision, a solver
        // error, the time budget). Zero weights are still a regular
        // constrained triangulation when the Delaunay triangulation contains
        // every segment (checked exactly): use them, and check system 3 for
        // them exactly (its failure is then no proof).
        (zero_rt, Err(Error::SolverLimit(m)))
            if zero_rt.is_some() || conforms(cx, &rt0).is_ok() =>
        {
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
                sys3_proved: vec![],
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
            if let Attempt::Found(found) = verify(backend, dom, w, (true, vec![]))? {
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

/// A candidate from one LP attempt, verified to conform.
struct Found {
    w: Vec<f64>,
    rt: Triangulation,
    sys3_failed: Vec<u32>,
    /// Whether the LP found system 3 feasible on its rows (false: elastic).
    lp_sys3: bool,
    /// The duals of systems 1 and 3 together when they did not hold (for
    /// `prove`).
    duals: Duals,
}

fn finish(found: Found, mut report: WeightsReport) -> Result<Weights> {
    report.max_abs_weight = found.w.iter().fold(0.0, |m, w| m.max(w.abs()));
    report.system3_feasible = found.sys3_failed.is_empty();
    Ok(Weights {
        w: found.w,
        rt: found.rt,
        report,
        sys3_failed: found.sys3_failed,
        sys3_proved: vec![],
    })
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
    sys.rows = t
        .par_edge_triangles()
        .filter_map(|(a, b, tl, tr)| {
            let tr = tr?;
            let (c, d) = (t.apex(tl, a, b), t.apex(tr, b, a));
            any_free(&[a, b, c, d]).then(|| {
                let mut row = convexity_row(p, a, b, c, d);
                row.outside = !inside[tl as usize] || !inside[tr as usize];
                row.weak = row.outside && !segments.contains(&[a.min(b), a.max(b)]);
                row
            })
        })
        .collect();
    let per_segment = cx
        .segments
        .par_iter()
        .enumerate()
        .flat_map_iter(|(s, &[i, j])| {
            let (mut apexes, mut outside) = (vec![], vec![]);
            for (tri, (x, y)) in t.beside(i, j).into_iter().zip([(i, j), (j, i)]) {
                if let Some(tri) = tri {
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
        });
    sys.rows.par_extend(per_segment);
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
            origin: Origin::Other,
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
        origin: Origin::Other,
    }
}

/// The outcome of one LP attempt on a row system.
enum Attempt {
    /// Weights whose RT contains every segment (system 3 checked exactly).
    Found(Found),
    /// Weights whose RT (given) misses segments or hides vertices: rows
    /// are missing.
    NotConforming(Vec<f64>, Triangulation),
    /// System 1 has no trusted margin on these rows (the LP's duals).
    Sys1Infeasible(Duals),
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
        Answer::Weights(w, lp_sys3, duals) => verify(backend, dom, w, (lp_sys3, duals)),
        Answer::Sys1Infeasible(duals) => Ok(Attempt::Sys1Infeasible(duals)),
        Answer::Sys3Infeasible => Ok(Attempt::Sys3Infeasible),
    }
}

/// Builds RT(w) with exact predicates and checks it segment by segment.
fn verify<B: Backend + ?Sized>(
    backend: &B,
    dom: &Domain,
    w: Vec<f64>,
    (lp_sys3, duals): (bool, Duals),
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
        duals,
    }))
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
    cx.segments.par_iter().all(|&[a, b]| {
        let [Some(t1), Some(t2)] = t.beside(a, b) else {
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
    dt.beside(i, j)
        .into_iter()
        .zip([(i, j), (j, i)])
        .all(|(t, (a, b))| match t {
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
    let p = &cx.points;
    // Filtered: the same expressions in intervals, exact rationals only
    // where an interval holds zero.
    let holds = |s: usize| -> bool {
        let [i, j] = cx.segments[s];
        let apexes: Vec<u32> = rt
            .beside(i, j)
            .into_iter()
            .zip([(i, j), (j, i)])
            .filter_map(|(t, (a, b))| t.map(|t| rt.apex(t, a, b)))
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

/// For each hidden vertex, the vertices of the triangles of `rt` that
/// contain its point (closed; decided exactly). One sweep over the
/// triangles, the hidden points sorted by x.
fn covering(p: &[[f64; 2]], rt: &Triangulation, hidden: &[u32]) -> crate::FastMap<u32, Vec<u32>> {
    use std::cmp::Ordering::Less;
    let mut out: crate::FastMap<u32, Vec<u32>> = crate::FastMap::default();
    if hidden.is_empty() {
        return out;
    }
    let mut by_x: Vec<u32> = hidden.to_vec();
    by_x.sort_by(|&a, &b| p[a as usize][0].total_cmp(&p[b as usize][0]));
    for tri in &rt.triangles {
        let c = tri.map(|v| p[v as usize]);
        let lo = c.iter().map(|q| q[0]).fold(f64::INFINITY, f64::min);
        let hi = c.iter().map(|q| q[0]).fold(f64::NEG_INFINITY, f64::max);
        let first = by_x.partition_point(|&h| p[h as usize][0] < lo);
        for &h in by_x[first..]
            .iter()
            .take_while(|&&h| p[h as usize][0] <= hi)
        {
            let x = p[h as usize];
            let inside = (0..3).all(|k| orient(c[k], c[(k + 1) % 3], x) != Less);
            if inside {
                out.entry(h).or_default().extend(tri);
            }
        }
    }
    out
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

/// The lazy global form: a supporting plane per segment and per isolated
/// vertex, with rows for the points near it; rows are added where RT(w)
/// disagrees. A restricted LP that is infeasible proves the full one so.
/// What the LP's infeasibility of system 1 means: no regular constrained
/// triangulation (the segments last missing, or all), unless triangles far
/// thinner than its tolerances make it no verdict at all.
fn sys1_verdict(dom: &Domain, last_missing: Vec<u32>, proof: Option<Certificate>) -> Error {
    let cx = &dom.complex;
    if let Some(c) = proof {
        // Faces beyond the segments are isolated vertices' (`global`).
        let of = |f: &u32| cx.segment_ids.get(*f as usize).copied();
        return Error::NoRegularConstrainedTriangulation {
            segments: c.faces.iter().filter_map(of).collect(),
            proof_rows: Some(c.rows),
        };
    }
    let thin = slivers(&cx.points, &dom.cdt);
    if !thin.is_empty() {
        let ids: Vec<i64> = thin.iter().map(|&v| cx.vertex_ids[v as usize]).collect();
        return Error::SolverLimit(format!(
            "cannot decide whether a regular constrained triangulation exists: the LP finds none, \
             but triangles of nearly collinear vertices are beyond its precision (vertices {ids:?})"
        ));
    }
    // Infeasible on a subset of the rows: infeasible outright.
    let ids = if last_missing.is_empty() {
        (0..cx.segments.len() as u32).collect()
    } else {
        last_missing
    };
    Error::NoRegularConstrainedTriangulation {
        segments: ids.iter().map(|&s| cx.segment_ids[s as usize]).collect(),
        proof_rows: None,
    }
}

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
    let lp_points: Vec<[Q; 2]> = p.iter().map(|x| x.map(q)).collect();
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
            plane_rows(&mut sys, p, o as u32, i, j.as_slice(), &others, scale2);
            if let Some(j) = j {
                sys.rows.extend(sys3_rows(p, o as u32, i, j, &others));
            }
        }
        if anchored {
            anchor_rows(&mut sys, cx, units);
        }
        let (found, w, rt) = match attempt(backend, dom, &sys, true, &mut report)? {
            Attempt::Sys1Infeasible(duals) => {
                let proof = prove(&sys, &duals, &lp_points, &|t| t);
                return Err(sys1_verdict(dom, last_missing, proof));
            }
            // Elastic: system 3 is infeasible on a subset of its rows, hence
            // outright; keep these weights.
            Attempt::Found(f) if f.sys3_failed.is_empty() || !f.lp_sys3 => {
                let name = |o: u32| {
                    let (i, j) = owners[o as usize];
                    let ends = std::iter::once(i).chain(j);
                    ends.map(|v| cx.vertex_ids[v as usize]).collect()
                };
                let proof = prove(&sys, &f.duals, &lp_points, &|t| t);
                report.system3_proof = proof.as_ref().map(|c| c.named(name, ""));
                let mut out = finish(f, report)?;
                out.sys3_proved = proof.map(|c| c.crossing).unwrap_or_default();
                return Ok(out);
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
        let bad = Violations {
            missing: &missing,
            sys3_bad: &sys3_bad,
            hidden: &hidden,
        };
        let grew = grow(
            cx,
            &rt,
            &cdt_nb,
            &owners,
            &mut sets,
            &bad,
            round > GLOBAL_ROUNDS / 2,
        );
        let rows: usize = sets.iter().map(BTreeSet::len).sum();
        if rows > MAX_GLOBAL_ROWS {
            // Dense rows for many owners would not fit; better a clear stop.
            return Err(Error::SolverLimit(format!(
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
            // Every violated owner has its dense rows (every vertex), the LP
            // meets them, yet RT(w) disagrees: the LP's margin is below what
            // doubles resolve.
            if let Some(f) = found {
                return finish(f, report);
            }
            let ids = |v: &[u32], of: &[i64]| v.iter().map(|&s| of[s as usize]).collect::<Vec<_>>();
            return Err(Error::SolverLimit(format!(
                "the lazy global form gave every violated segment and vertex its rows against \
                 all {n} vertices ({} rounds), yet the exact check of its weights finds segments \
                 {:?} missing and vertices {:?} hidden: the LP's margin is below what doubles resolve",
                round,
                ids(&missing, &cx.segment_ids),
                ids(&hidden, &cx.vertex_ids)
            )));
        }
    }
    Err(Error::SolverLimit(format!(
        "the lazy global form did not converge in {} rounds",
        GLOBAL_ROUNDS + 2
    )))
}

/// What the exact check found wrong with the global form's weights.
struct Violations<'a> {
    missing: &'a [u32],
    sys3_bad: &'a [u32],
    hidden: &'a [u32],
}

/// The lazy global form's new rows: each violated owner (segment or
/// isolated vertex) gets the two rings around its ends in RT(w) and in the
/// CDT (and around the triangles covering a hidden end), or every vertex
/// when `widen`; when no set grows so, the violated owners get their
/// dense rows, so that the loop ends in weights, a proof or a named limit,
/// never with rows left unwritten. Whether any set grew.
fn grow(
    cx: &Complex,
    rt: &Triangulation,
    cdt_nb: &[Vec<u32>],
    owners: &[(u32, Option<u32>)],
    sets: &mut [BTreeSet<u32>],
    bad: &Violations,
    widen: bool,
) -> bool {
    let n = cx.points.len();
    let rt_nb = rt.neighbours(n);
    let mut grew = false;
    let mut bad_owners: BTreeSet<usize> = bad
        .missing
        .iter()
        .chain(bad.sys3_bad)
        .map(|&s| s as usize)
        .collect();
    for h in bad.hidden {
        if let Some(o) = owners.iter().position(|&(i, j)| i == *h || j == Some(*h)) {
            bad_owners.insert(o);
        }
    }
    // A hidden vertex has no neighbours in RT(w): the vertices of the
    // triangles that cover it are the ones its rows lack.
    let covers = covering(&cx.points, rt, bad.hidden);
    for o in bad_owners.iter().copied() {
        let (i, j) = owners[o];
        let before = sets[o].len();
        let ends: Vec<u32> = std::iter::once(i).chain(j).collect();
        // two rings around both ends, in RT(w) and in the CDT, and
        // around the triangles covering them when they are hidden
        let mut ring: BTreeSet<u32> = BTreeSet::new();
        let cover = ends.iter().flat_map(|e| covers.get(e)).flatten();
        for &a in ends
            .iter()
            .flat_map(|&e| rt_nb[e as usize].iter().chain(&cdt_nb[e as usize]))
            .chain(cover)
        {
            ring.insert(a);
            ring.extend(rt_nb[a as usize].iter().copied());
            ring.extend(cdt_nb[a as usize].iter().copied());
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
    if !grew {
        for &o in &bad_owners {
            let (i, j) = owners[o];
            let before = sets[o].len();
            sets[o].extend((0..n as u32).filter(|&v| v != i && Some(v) != j));
            grew |= sets[o].len() > before;
        }
    }
    grew
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
    fn flips_from_the_constrained_triangulation_give_the_regular_one() {
        use crate::generate::scatter;
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
