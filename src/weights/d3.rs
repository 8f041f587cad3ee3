//! Weights in 3D (issue 6): system 1 (a regular triangulation that has
//! every face of the complex as a face) and system 3 (every face crosses
//! its dual) in the lazy global form. There is no constrained Delaunay
//! tetrahedralisation to lean on (some complexes admit none), so there is
//! no local form: each maximal face gets a supporting hyperplane through
//! its lifted vertices with rows for the points near it, and rows are added
//! where the regular triangulation of the LP's weights, built with exact
//! predicates, disagrees. A restricted LP that is infeasible proves the
//! whole one so. The LP, its objective and its trust threshold are the 2D
//! ones (`weights`).
//!
//! Planar convex polygons whose vertices are exactly cocircular
//! (rectangles, regular polygons) are kept whole: their lifts are made
//! exactly coplanar, so the polygon is one face of the regular subdivision
//! and one face of the power diagram. By default (`Keep::Coplanar`) that is
//! docs/method.md section 6's equality rows, solved exactly: each polygon
//! vertex beyond the first three has its weight fixed by the others
//! (`Relations`), the LP sees only the free weights, and the dependent ones
//! are recomputed as rationals from the LP's (the equalities hold
//! exactly, not within HiGHS' tolerances). `Keep::Shared` gives all
//! vertices of polygons joined at vertices one weight, which puts each
//! polygon's power centre at its circumcentre (orthogonal links to cells
//! centred on it, as the hybrid's walls need). When whole polygons leave no
//! solution, fewer are kept and the LP tried again.

use super::centres::{sys3_failures, Centres};
use super::coplanar::Relations;
use super::face::{fan, sorted3, Face};
use super::Keep;
use crate::backend::{Adjacency, Backend, Tetrahedralisation};
use crate::error::{Error, Result};
use crate::geom::{is_pos, q, Q};
use crate::lp::{
    carried, destroy_finished, prove, solve_tall, Answer, Certificate, Duals, Units, WeightsReport,
    GLOBAL_ROUNDS, MAX_GLOBAL_ROWS,
};
use crate::{
    complex::Complex3,
    domain::Simplices3,
    geom::{drop_axis, plane_axis},
};
use std::collections::{BTreeSet, HashSet};
use std::sync::Arc;

/// Polygons with more vertices than this are triangulated (the exact check
/// of a whole polygon looks at every triple of its vertices).
const MAX_WHOLE: usize = 12;

/// Verified weights, their regular triangulation and the faces it has.
#[derive(Debug, Clone)]
pub struct Weights3 {
    pub w: Vec<Q>,
    /// RT(w): has every face (polygons as unions of its triangles), hides
    /// no vertex (checked exactly).
    pub rt: Tetrahedralisation,
    pub faces: Vec<Face>,
    pub report: WeightsReport,
    /// Polygons kept whole, and how (shared weights after a fallback).
    pub whole_polygons: usize,
    pub keep: Keep,
    /// Faces (indices into `faces`) of dimension 1 or 2 that do not cross
    /// their dual (exact check).
    pub sys3_failed: Vec<u32>,
    /// The faces' centres under `w` (`Centres::of`).
    pub centres: Centres,
    /// RT(w)'s triangles and edges with what is around them.
    pub adjacency: Arc<Adjacency>,
}

/// Finds weights for a validated, triangulated 3D complex, whole polygons
/// kept as `keep` asks: each way in turn (`Keep::ways`) while the LP finds
/// no solution or fails. Nothing cancels them from outside: a thread that
/// steals this work from within cancellable work does not pass its flags.
pub fn solve<B: Backend + ?Sized>(
    backend: &B,
    cx: &Complex3,
    sc: &Simplices3,
    keep: Keep,
    cut: &[u32],
) -> Result<Weights3> {
    carried(&[], || solve_any(backend, cx, sc, keep, cut))
}

/// `solve`, with this thread's cancellation flags.
fn solve_any<B: Backend + ?Sized>(
    backend: &B,
    cx: &Complex3,
    sc: &Simplices3,
    keep: Keep,
    cut: &[u32],
) -> Result<Weights3> {
    let n = cx.points.len();
    let dt = backend.regular3(&cx.points, &vec![0.0; n])?;
    let all = kept_whole(cx);
    // Zero weights are shared weights, and make every lift coplanar.
    if let Some(w) = super::zero3::zero(cx, &faces(cx, sc, &all, cut), &dt, keep.ways()[0]) {
        return Ok(w);
    }
    let mut out = Err(Error::Internal("the 3D weights made no attempt".into()));
    for &way in keep.ways() {
        out = solve_kept(backend, cx, sc, &dt, (&all, cut), way);
        if !no_solution(&out) {
            break;
        }
    }
    destroy_finished();
    out
}

/// Whole polygons fix the shape of the regular triangulation in every
/// plane where their vertices lie (they are Delaunay there), which the
/// triangles of other facets may contradict: then only the whole polygons
/// whose vertices are on no triangle or segment are kept whole, then none.
fn solve_kept<B: Backend + ?Sized>(
    backend: &B,
    cx: &Complex3,
    sc: &Simplices3,
    dt: &Tetrahedralisation,
    (all, cut): (&[bool], &[u32]),
    way: Keep,
) -> Result<Weights3> {
    let first = untouched(cx, sc, all);
    // (one after the other: see lp::cancel::beside)
    let mut whole = all.to_vec();
    let mut out = global(backend, cx, dt, faces(cx, sc, all, cut), way);
    for retry in [first, vec![false; all.len()]] {
        if !mended(&out) {
            break;
        }
        if retry != whole {
            whole = retry;
            out = global(backend, cx, dt, faces(cx, sc, &whole, cut), way);
        }
    }
    out
}

/// Whether an attempt with fewer polygons whole may mend this one.
fn mended(out: &Result<Weights3>) -> bool {
    matches!(
        out,
        Err(Error::NoRegularConstrainedTetrahedralisation { .. })
    )
}

/// Whether an attempt ended without weights in a way another may mend.
fn no_solution(out: &Result<Weights3>) -> bool {
    matches!(
        out,
        Err(Error::NoRegularConstrainedTetrahedralisation { .. } | Error::SolverLimit(_))
    )
}

/// The whole polygons whose shared-weight class (polygons joined through
/// common vertices) has no vertex on a triangle or segment.
fn untouched(cx: &Complex3, sc: &Simplices3, whole: &[bool]) -> Vec<bool> {
    let fs = faces(cx, sc, whole, &[]);
    let tie = ties(cx.points.len(), &fs);
    let mut touched = vec![false; cx.points.len()];
    for f in fs.iter().filter(|f| (2..=3).contains(&f.vertices.len())) {
        f.vertices
            .iter()
            .for_each(|&v| touched[tie[v as usize] as usize] = true);
    }
    let mut out = whole.to_vec();
    for f in fs.iter().filter(|f| f.vertices.len() > 3) {
        if touched[tie[f.vertices[0] as usize] as usize] {
            out[f.facet.expect("polygons have a facet") as usize] = false;
        }
    }
    out
}

/// Per facet, whether it is kept whole: one strictly convex polygon of 4
/// to `MAX_WHOLE` vertices, no holes, its vertices exactly cocircular.
pub fn kept_whole(cx: &Complex3) -> Vec<bool> {
    let p = |v: u32| cx.points[v as usize];
    cx.facets
        .iter()
        .map(|f| {
            let [poly] = f.polygons.as_slice() else {
                return false;
            };
            if poly.len() < 4 || poly.len() > MAX_WHOLE || !f.holes.is_empty() {
                return false;
            }
            let Some(axis) = plane_axis(p(poly[0]), p(poly[1]), p(poly[2])) else {
                return false;
            };
            let flat = |v: u32| drop_axis(axis, p(v));
            let m = poly.len();
            let turn = |k: usize| {
                crate::geom::orient(
                    flat(poly[k]),
                    flat(poly[(k + 1) % m]),
                    flat(poly[(k + 2) % m]),
                )
            };
            // A simple polygon (validated) turning one way at every vertex
            // is strictly convex.
            let first = turn(0);
            first != std::cmp::Ordering::Equal
                && (1..m).all(|k| turn(k) == first)
                && poly[3..]
                    .iter()
                    .all(|&d| cocircular(cx, axis, poly[0], poly[1], poly[2], d))
        })
        .collect()
}

/// Whether d, coplanar with a, b, c, lies on their circle: with one
/// weight for all four, whether their lifts are coplanar. In affine
/// coordinates d = a + s (b - a) + t (c - a) (a coordinate projection
/// keeps them), the lift must be the same combination:
/// D (|d|^2 - |a|^2) = S (|b|^2 - |a|^2) + T (|c|^2 - |a|^2), s = S / D.
pub(super) fn cocircular(cx: &Complex3, axis: usize, a: u32, b: u32, c: u32, d: u32) -> bool {
    let p = |v: u32| cx.points[v as usize];
    let f = |v: u32| drop_axis(axis, p(v)).map(q);
    let (fa, fb, fc, fd) = (f(a), f(b), f(c), f(d));
    let det = |x: &[Q; 2], y: &[Q; 2], o: &[Q; 2]| {
        (&x[0] - &o[0]) * (&y[1] - &o[1]) - (&x[1] - &o[1]) * (&y[0] - &o[0])
    };
    let big_d = det(&fb, &fc, &fa);
    let s = det(&fd, &fc, &fa);
    let t = det(&fb, &fd, &fa);
    let n2 = |v: u32| {
        p(v).iter()
            .map(|&x| q(x) * q(x))
            .fold(Q::from(0), |acc, x| acc + x)
    };
    let na = n2(a);
    big_d * (n2(d) - &na) == s * (n2(b) - &na) + t * (n2(c) - &na)
}

/// The maximal faces: whole polygons, the triangles of the other facets,
/// dangling segments, then points on no triangle or segment.
/// The maximal faces: polygons kept whole (`whole`, by facet), triangles,
/// segments and points; those of the facets `cut` need not cross their duals.
fn faces(cx: &Complex3, sc: &Simplices3, whole: &[bool], cut: &[u32]) -> Vec<Face> {
    let mut out: Vec<Face> = vec![];
    for (f, _) in whole.iter().enumerate().filter(|w| *w.1) {
        out.push(Face {
            vertices: cx.facets[f].polygons[0].clone(),
            facet: Some(f as u32),
            cut: false,
        });
    }
    for (t, &f) in sc.triangles.iter().zip(&sc.triangle_facet) {
        if !whole[f as usize] {
            out.push(Face {
                vertices: t.to_vec(),
                facet: Some(f),
                cut: false,
            });
        }
    }
    for (s, &f) in sc.segments.iter().zip(&sc.segment_facet) {
        out.push(Face {
            vertices: s.to_vec(),
            facet: Some(f),
            cut: false,
        });
    }
    let mut used = vec![false; cx.points.len()];
    for face in &out {
        face.vertices.iter().for_each(|&v| used[v as usize] = true);
    }
    for (&v, &f) in sc.points.iter().zip(&sc.point_facet) {
        if !std::mem::replace(&mut used[v as usize], true) {
            out.push(Face {
                vertices: vec![v],
                facet: Some(f),
                cut: false,
            });
        }
    }
    for v in 0..cx.points.len() as u32 {
        if !used[v as usize] {
            out.push(Face {
                vertices: vec![v],
                facet: None,
                cut: false,
            });
        }
    }
    for face in &mut out {
        face.cut = face.facet.is_some_and(|f| cut.contains(&f));
    }
    out
}

/// Per vertex, the vertex whose weight it shares (the smallest of the
/// whole polygons joined to it; itself when on none).
pub(super) fn ties(n: usize, faces: &[Face]) -> Vec<u32> {
    let mut rep: Vec<u32> = (0..n as u32).collect();
    fn root(rep: &mut [u32], mut v: u32) -> u32 {
        while rep[v as usize] != v {
            rep[v as usize] = rep[rep[v as usize] as usize];
            v = rep[v as usize];
        }
        v
    }
    for face in faces.iter().filter(|f| f.vertices.len() > 3) {
        for &v in &face.vertices[1..] {
            let (a, b) = (root(&mut rep, face.vertices[0]), root(&mut rep, v));
            let (lo, hi) = (a.min(b), a.max(b));
            rep[hi as usize] = lo;
        }
    }
    (0..n as u32).map(|v| root(&mut rep, v)).collect()
}

/// What the exact check of RT(w) finds wrong.
#[derive(Default)]
pub(super) struct Misses {
    /// Faces that are not faces of RT(w).
    pub faces: Vec<u32>,
    /// Vertices RT(w) hides.
    pub hidden: Vec<u32>,
}

/// The vertices next to any of `vs` in any of the neighbour lists `nbs`.
fn ring(vs: &[u32], nbs: &[&Vec<Vec<u32>>]) -> BTreeSet<u32> {
    vs.iter()
        .flat_map(|&v| {
            nbs.iter()
                .flat_map(move |nb| nb[v as usize].iter().copied())
        })
        .collect()
}

/// The lazy global form (see the module's doc).
fn global<B: Backend + ?Sized>(
    backend: &B,
    cx: &Complex3,
    dt: &Tetrahedralisation,
    faces: Vec<Face>,
    keep: Keep,
) -> Result<Weights3> {
    let n = cx.points.len();
    let dt_nb = dt.neighbours(n);
    let units = Units::new(&cx.points, dt.edge_links().into_keys().map(|[a, b]| (a, b)));
    let p = &units.points;
    let pts_q: Vec<[Q; 3]> = cx.points.iter().map(|p| p.map(q)).collect();
    let lp_points: Vec<[Q; 3]> = p.iter().map(|p| p.map(q)).collect();
    let relations = match keep {
        Keep::Shared => Relations::shared(n, &faces),
        _ => Relations::coplanar(cx, &faces),
    };
    let whole_polygons = faces.iter().filter(|f| f.vertices.len() > 3).count();
    let free = relations.free();
    let mut report = WeightsReport::started("global");
    report.free_weights = n - relations.dependent.len();
    let mut sets: Vec<BTreeSet<u32>> = faces
        .iter()
        .map(|f| {
            let mut s = ring(&f.vertices, &[&dt_nb]);
            for v in &f.vertices {
                s.remove(v);
            }
            s
        })
        .collect();
    let mut last = Misses::default();
    let mut found: Option<Weights3> = None;
    for round in 1..=GLOBAL_ROUNDS + 2 {
        report.global_rounds = round;
        let mut sys = super::rows3::system(p, &faces, &sets, &units, free.clone());
        relations.substitute(&mut sys.rows);
        relations.substitute(&mut sys.eqs);
        let answer = solve_tall(&sys, &mut report);
        let exact = |duals: &Duals| {
            let sub = |t| relations.substitute_exact(t);
            prove(&sys, duals, &lp_points, &sub)
        };
        let (w, lp_sys3) = match answer? {
            Answer::Weights(w, lp_sys3, duals) => {
                let name = |f: u32| {
                    faces[f as usize]
                        .vertices
                        .iter()
                        .map(|&v| cx.vertex_ids[v as usize])
                        .collect()
                };
                let premise = match (whole_polygons, keep) {
                    (0, _) => "the facets as triangulated".to_string(),
                    (k, Keep::Shared) => format!(
                        "the facets as triangulated, {k} polygons kept whole, and the vertices of \
                         whole polygons joined at vertices sharing one weight"
                    ),
                    (k, _) => format!("the facets as triangulated and {k} polygons kept whole"),
                };
                report.system3_proof = exact(&duals).map(|c| c.named(name, &premise));
                (w, lp_sys3)
            }
            Answer::Sys1Infeasible(duals) => {
                // Shared weights are a choice, not a necessity: no proof.
                let proof = (keep != Keep::Shared || whole_polygons == 0)
                    .then(|| exact(&duals))
                    .flatten();
                return Err(infeasible(cx, &faces, &last, proof));
            }
            Answer::Sys3Infeasible => unreachable!("the global form goes elastic"),
        };
        let w = relations.exact(&w);
        let rt = backend.regular3_exact(&pts_q, &w)?;
        let adj = rt.adjacency();
        let misses = check(cx, &faces, &rt, &adj);
        let mut bad: BTreeSet<usize> = misses.faces.iter().map(|&f| f as usize).collect();
        for h in &misses.hidden {
            bad.extend(faces.iter().position(|f| f.vertices.contains(h)));
        }
        if bad.is_empty() {
            let centres = Centres::new(faces.len());
            let sys3_failed = sys3_failures(cx, &faces, (&w, &centres), &adj);
            if sys3_failed.is_empty() || !lp_sys3 {
                return Ok(finish(
                    w,
                    (rt, adj),
                    faces,
                    report,
                    (whole_polygons, keep),
                    (sys3_failed, centres),
                ));
            }
            bad.extend(sys3_failed.iter().map(|&f| f as usize));
            found = Some(finish(
                w,
                (rt.clone(), adj),
                faces.clone(),
                report.clone(),
                (whole_polygons, keep),
                (sys3_failed, centres),
            ));
        }
        let rt_nb = rt.neighbours(n);
        let widen = round > GLOBAL_ROUNDS / 2;
        let mut grew = false;
        for f in bad {
            let vs = &faces[f].vertices;
            let first = ring(vs, &[&rt_nb, &dt_nb]);
            let mut add = first.clone();
            for a in first {
                add.extend(rt_nb[a as usize].iter().chain(&dt_nb[a as usize]).copied());
            }
            if widen {
                add.extend(0..n as u32); // the dense rows for this face only
            }
            for v in vs {
                add.remove(v);
            }
            let before = sets[f].len();
            sets[f].extend(add);
            grew |= sets[f].len() > before;
        }
        last = misses;
        if sets.iter().map(BTreeSet::len).sum::<usize>() > MAX_GLOBAL_ROWS {
            return Err(Error::SolverLimit(format!(
                "the 3D lazy global form needs more than {MAX_GLOBAL_ROWS} rows without converging"
            )));
        }
        if !grew {
            // Every violated face has all its rows, yet RT(w) disagrees:
            // the LP's margin is below what the exact check confirms.
            return found.ok_or_else(|| {
                Error::SolverLimit("3D weights from the LP do not give a conforming triangulation and no rows are left to add".into())
            });
        }
    }
    Err(Error::SolverLimit(
        "the 3D lazy global form did not converge".into(),
    ))
}

pub(super) fn finish(
    w: Vec<Q>,
    (rt, adjacency): (Tetrahedralisation, Adjacency),
    faces: Vec<Face>,
    mut report: WeightsReport,
    (whole_polygons, keep): (usize, Keep),
    (sys3_failed, centres): (Vec<u32>, Centres),
) -> Weights3 {
    report.max_abs_weight = w.iter().fold(0.0, |m, x| m.max(crate::geom::f(x).abs()));
    report.system3_feasible = sys3_failed.is_empty();
    Weights3 {
        w,
        rt,
        faces,
        report,
        whole_polygons,
        keep,
        sys3_failed,
        centres,
        adjacency: Arc::new(adjacency),
    }
}

/// The verdict of an infeasible restricted LP, naming the faces of its
/// exact certificate, else those the last RT(w) missed (all, when none
/// was built yet).
fn infeasible(cx: &Complex3, faces: &[Face], last: &Misses, proof: Option<Certificate>) -> Error {
    let named: Vec<&Face> = if let Some(p) = &proof {
        let mut v: Vec<u32> = p.faces.iter().chain(&p.crossing).copied().collect();
        v.sort_unstable();
        v.dedup();
        v.iter().map(|&f| &faces[f as usize]).collect()
    } else if last.faces.is_empty() && last.hidden.is_empty() {
        faces.iter().collect()
    } else {
        let mut v: Vec<&Face> = last.faces.iter().map(|&f| &faces[f as usize]).collect();
        v.extend(
            faces
                .iter()
                .filter(|f| f.vertices.iter().any(|x| last.hidden.contains(x))),
        );
        v
    };
    let facets: BTreeSet<i64> = named
        .iter()
        .filter_map(|f| f.facet)
        .map(|f| f as i64 + 1)
        .collect();
    let vertices: BTreeSet<i64> = named
        .iter()
        .filter(|f| f.facet.is_none())
        .map(|f| cx.vertex_ids[f.vertices[0] as usize])
        .collect();
    Error::NoRegularConstrainedTetrahedralisation {
        facets: facets.into_iter().collect(),
        vertices: vertices.into_iter().collect(),
        proof_rows: proof.map(|p| p.rows),
    }
}

/// Twice the area of a triangle projected along `axis`, exactly.
fn area2(cx: &Complex3, axis: usize, [a, b, c]: [u32; 3]) -> Q {
    let f = |v: u32| drop_axis(axis, cx.points[v as usize]).map(q);
    let (a, b, c) = (f(a), f(b), f(c));
    (&b[0] - &a[0]) * (&c[1] - &a[1]) - (&b[1] - &a[1]) * (&c[0] - &a[0])
}

/// Exactly: the faces RT(w) lacks and the vertices it hides. A polygon is
/// there when RT's triangles among its vertices (all in its plane) have
/// its area: they then tile it.
pub(super) fn check(
    cx: &Complex3,
    faces: &[Face],
    rt: &Tetrahedralisation,
    Adjacency { tris, links: edges }: &Adjacency,
) -> Misses {
    let hidden: HashSet<u32> = rt.hidden.iter().copied().collect();
    let present = |(fi, face): (usize, &Face)| -> Option<u32> {
        let vs = &face.vertices;
        let ok = match vs.len() {
            1 => !hidden.contains(&vs[0]),
            2 => edges.contains_key(&[vs[0].min(vs[1]), vs[0].max(vs[1])]),
            3 => tris.contains_key(&sorted3(vs)),
            _ => {
                let axis = plane_axis(
                    cx.points[vs[0] as usize],
                    cx.points[vs[1] as usize],
                    cx.points[vs[2] as usize],
                )
                .expect("whole polygons are strictly convex");
                let abs = |x: Q| if is_pos(&x) { x } else { -x };
                let polygon: Q = (1..vs.len() - 1)
                    .map(|k| abs(area2(cx, axis, [vs[0], vs[k], vs[k + 1]])))
                    .sum();
                let covered: Q = fan(&face.vertices, &tris)
                    .into_iter()
                    .map(|t| abs(area2(cx, axis, t)))
                    .sum();
                covered == polygon
            }
        };
        (!ok).then_some(fi as u32)
    };
    let mut hidden: Vec<u32> = rt.hidden.clone();
    hidden.sort_unstable();
    use rayon::prelude::*;
    Misses {
        faces: faces.par_iter().enumerate().filter_map(present).collect(),
        hidden,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::backend::compiled;
    use crate::complex::Facet;
    use crate::geom::norm2;

    fn facet(polygons: Vec<Vec<u32>>) -> Facet {
        Facet {
            polygons,
            ..Default::default()
        }
    }

    /// A box [0,2]x[0,1]x[0,1] with its six rectangles, and more points.
    fn boxed(extra: Vec<[f64; 3]>) -> Complex3 {
        let mut points = vec![];
        for k in 0..8 {
            points.push([
                (2 * (k & 1)) as f64,
                ((k >> 1) & 1) as f64,
                ((k >> 2) & 1) as f64,
            ]);
        }
        points.extend(extra);
        let n = points.len();
        Complex3 {
            points,
            vertex_ids: (1..=n as i64).collect(),
            facets: vec![
                facet(vec![vec![0, 1, 3, 2]]),
                facet(vec![vec![4, 5, 7, 6]]),
                facet(vec![vec![0, 1, 5, 4]]),
                facet(vec![vec![2, 3, 7, 6]]),
                facet(vec![vec![0, 2, 6, 4]]),
                facet(vec![vec![1, 3, 7, 5]]),
            ],
            holes: vec![],
        }
    }

    fn run_kept(cx: &Complex3, keep: Keep) -> Result<Weights3> {
        let b = &compiled()[0];
        let sc = cx.triangulate(b.as_ref())?;
        solve(b.as_ref(), cx, &sc, keep, &[])
    }

    fn run(cx: &Complex3) -> Result<Weights3> {
        run_kept(cx, Keep::Auto)
    }

    use std::sync::{atomic::AtomicBool, Arc};

    /// A thread waiting in cancellable work may steal another cavity's
    /// weights (rayon): raised flags there must not cancel them (they did,
    /// as "an LP run was cancelled but its result was used").
    #[test]
    fn weights_stolen_into_cancelled_work_are_not_cancelled() {
        let raised = Arc::new(AtomicBool::new(true));
        // (a point inside a box: the LP runs)
        let cx = boxed(vec![[1.0, 0.5, 0.5]]);
        let alone = run(&cx).unwrap();
        assert!(alone.report.lp_solves > 0);
        let stolen = crate::lp::cancellable(&raised, || run(&cx)).unwrap();
        assert_eq!(stolen.w, alone.w);
    }

    /// Whether the lifts (p, |p|^2 - w) of a whole polygon's vertices lie
    /// exactly on one plane.
    fn lifts_coplanar(cx: &Complex3, w: &[Q], vs: &[u32]) -> bool {
        let lift = |v: u32| {
            let p = cx.points[v as usize].map(q);
            let h = norm2(&p) - &w[v as usize];
            [p[0].clone(), p[1].clone(), p[2].clone(), h]
        };
        let l0 = lift(vs[0]);
        let rel = |v: u32| -> Vec<Q> { (0..4).map(|k| &lift(v)[k] - &l0[k]).collect() };
        let (a, b) = (rel(vs[1]), rel(vs[2]));
        // the 3x3 minors of [a; b; d] all vanish for every other vertex d
        vs[3..].iter().all(|&d| {
            let d = rel(d);
            let m = |i: usize, j: usize, k: usize| {
                let det2 = |x: usize, y: usize| Q::from(&b[x] * &d[y]) - Q::from(&b[y] * &d[x]);
                Q::from(&a[i] * &det2(j, k)) - Q::from(&a[j] * &det2(i, k))
                    + Q::from(&a[k] * &det2(i, j))
            };
            [(0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3)]
                .iter()
                .all(|&(i, j, k)| m(i, j, k) == 0)
        })
    }

    #[test]
    fn a_box_keeps_its_rectangles_whole() {
        let cx = boxed(vec![[3.0, 0.2, 0.3], [-1.0, 0.6, 0.4], [1.0, 0.5, 1.2]]);
        for keep in [Keep::Coplanar, Keep::Shared] {
            let out = run_kept(&cx, keep).unwrap();
            assert_eq!((out.whole_polygons, out.keep), (6, keep));
            assert!(check(&cx, &out.faces, &out.rt, &out.adjacency)
                .faces
                .is_empty());
            for f in out.faces.iter().filter(|f| f.vertices.len() > 3) {
                assert!(lifts_coplanar(&cx, &out.w, &f.vertices), "{keep:?} {f:?}");
            }
            // shared: the eight corners have one weight; coplanar: the
            // 6 x 1 relations leave 4 of the 8 corners free
            let free = out.report.free_weights;
            match keep {
                Keep::Shared => {
                    assert!(out.w[..8].iter().all(|x| *x == out.w[0]));
                    assert_eq!(free, 1 + 3);
                }
                _ => assert_eq!(free, 4 + 3),
            }
            assert!(out.sys3_failed.is_empty(), "{:?}", out.sys3_failed);
            assert_eq!(out.faces.len(), 6 + 3);
        }
    }

    #[test]
    fn a_bare_box_has_zero_weights() {
        let cx = boxed(vec![]);
        let out = run(&cx).unwrap();
        assert_eq!(
            (out.report.method.as_str(), out.whole_polygons),
            ("zero", 6)
        );
        assert!(out.w.iter().all(|x| *x == 0));
    }

    #[test]
    fn a_point_inside_a_box_of_whole_rectangles() {
        // The faces' supporting hyperplanes tilt about their lifted
        // rectangles; the point's weight lowers it below them all.
        let cx = boxed(vec![[1.0, 0.5, 0.5]]);
        let out = run(&cx).unwrap();
        assert_eq!(out.whole_polygons, 6);
        assert!(check(&cx, &out.faces, &out.rt, &out.adjacency)
            .faces
            .is_empty());
        assert!(out.rt.hidden.is_empty());
        assert!(out.w[8] < out.w[0]);
    }

    #[test]
    fn shared_weights_without_a_solution_fall_back_to_triangles() {
        // Rectangle A in z = 0 on the circle of radius 5; rectangle B shares
        // a corner with A (so all eight share one weight) and has a corner
        // (5, 0, 0) on A's circle: its lift is on A's lifted plane, which no
        // hyperplane then separates. Triangulated, A and B have weights.
        let points = vec![
            [-3.0, -4.0, 0.0],
            [3.0, -4.0, 0.0],
            [3.0, 4.0, 0.0],
            [-3.0, 4.0, 0.0],
            [5.0, 0.0, 0.0],
            [5.0, 0.0, 1.0],
            [3.0, 4.0, 1.0],
        ];
        let cx = Complex3 {
            points,
            vertex_ids: (1..=7).collect(),
            facets: vec![facet(vec![vec![0, 1, 2, 3]]), facet(vec![vec![2, 4, 5, 6]])],
            holes: vec![],
        };
        assert_eq!(kept_whole(&cx), vec![true, true]);
        let out = run_kept(&cx, Keep::Shared).unwrap();
        // Zero weights have both rectangles in the Delaunay triangulation
        // and cross their duals; only the point on A's circle refuses them.
        assert_eq!(out.report.method, "global");
        assert_eq!(out.whole_polygons, 0);
        assert!(check(&cx, &out.faces, &out.rt, &out.adjacency)
            .faces
            .is_empty());
        // Coplanar lifts give B its own plane: both stay whole.
        let out = run_kept(&cx, Keep::Coplanar).unwrap();
        assert_eq!((out.whole_polygons, out.keep), (2, Keep::Coplanar));
        assert!(check(&cx, &out.faces, &out.rt, &out.adjacency)
            .faces
            .is_empty());
    }

    #[test]
    fn a_skewed_quad_is_triangulated() {
        // not cocircular: a trapezoid that is not isosceles
        let mut cx = boxed(vec![[3.0, 0.0, 0.0], [2.5, 1.0, 0.0]]);
        cx.facets.push(facet(vec![vec![1, 8, 9, 3]]));
        let out = run(&cx).unwrap();
        assert_eq!(out.whole_polygons, 6);
        assert_eq!(
            out.faces.iter().filter(|f| f.vertices.len() == 3).count(),
            2
        );
        assert!(check(&cx, &out.faces, &out.rt, &out.adjacency)
            .faces
            .is_empty());
    }

    #[test]
    fn a_tilted_triangle_needs_weights() {
        // a long thin triangle whose diametral spheres hold other points:
        // Delaunay alone would not have it
        let mut points = vec![[0.0, 0.0, 0.0], [4.0, 0.0, 0.0], [2.0, 0.3, 0.1]];
        points.extend([
            [2.0, -0.2, 0.6],
            [2.0, 0.5, -0.5],
            [1.0, 1.0, 1.0],
            [3.0, -1.0, -1.0],
        ]);
        let n = points.len();
        let cx = Complex3 {
            points,
            vertex_ids: (0..n as i64).collect(),
            facets: vec![facet(vec![vec![0, 1, 2]])],
            holes: vec![],
        };
        let b = &compiled()[0];
        let dt = b.regular3(&cx.points, &vec![0.0; n]).unwrap();
        assert!(!dt.triangle_apexes().contains_key(&[0, 1, 2]));
        let out = run(&cx).unwrap();
        assert!(out.rt.triangle_apexes().contains_key(&[0, 1, 2]));
        assert!(out.rt.hidden.is_empty());
        assert!(out.report.margin.unwrap() > 1e-6);
    }

    #[test]
    fn schoenhardt_has_no_regular_triangulation() {
        // Schoenhardt's twisted prism: no triangulation of its six vertices
        // has its eight boundary triangles (its interior has none).
        let t = 0.5f64; // twist (radians)
        let mut points = vec![];
        for (z, a0) in [(0.0, 0.0), (2.0, t)] {
            for k in 0..3 {
                let a = a0 + k as f64 * 2.0 * std::f64::consts::PI / 3.0;
                points.push([a.cos(), a.sin(), z]);
            }
        }
        // Each side quad (b_k, b_k+1, t_k+1, t_k) folded along the
        // diagonal that is not a hull edge.
        let b = &compiled()[0];
        let hull = b.regular3(&points, &[0.0; 6]).unwrap();
        let on_hull = |a: u32, b: u32| {
            hull.hull_faces().any(|f| {
                (0..3).any(|k| [f[k], f[(k + 1) % 3]] == [a, b] || [f[k], f[(k + 1) % 3]] == [b, a])
            })
        };
        let twisted = !on_hull(0, 4);
        assert_ne!(
            twisted,
            !on_hull(1, 3),
            "one diagonal of each side is a hull edge"
        );
        let mut tris = vec![[0, 2, 1], [3, 4, 5]];
        for k in 0..3u32 {
            let (b0, b1, t0, t1) = (k, (k + 1) % 3, k + 3, (k + 1) % 3 + 3);
            tris.extend(if twisted {
                [[b0, b1, t1], [b0, t1, t0]]
            } else {
                [[b0, b1, t0], [b1, t1, t0]]
            });
        }
        let cx = Complex3 {
            points,
            vertex_ids: (1..=6).collect(),
            facets: tris.iter().map(|t| facet(vec![t.to_vec()])).collect(),
            holes: vec![],
        };
        match run(&cx) {
            Err(Error::NoRegularConstrainedTetrahedralisation {
                facets, proof_rows, ..
            }) => {
                assert!(!facets.is_empty());
                // proved exactly, not only by the LP's margin
                assert!(proof_rows.is_some_and(|n| n > 0), "{proof_rows:?}");
            }
            other => panic!("expected infeasible, got {:?}", other.map(|w| w.w)),
        }
    }
}
