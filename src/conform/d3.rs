//! The whole 3D pipeline (issue 6): validate and triangulate the facets,
//! weights, sites, relocation, site diagram, certificate, mesh. Generic
//! over the backend's 3D side.

use super::{Clock, InputReport3, Outcome, Report, SitesReport3, D3};
use crate::backend::Backend;
use crate::diagram::Diagram3;
use crate::error::{Error, Result};
use crate::geom::Plane;
use crate::geom::{cross, dot, q, sub, Q};
use crate::mesh::{FacetFace, Link3, Mesh3};
use crate::options::Options;
use crate::sites::{self, Clip, Sites3};
use crate::weights;
use crate::{complex::Complex3, domain::Simplices3};
use std::cmp::Ordering::{Greater, Less};
use std::time::Instant;

/// Stages the 3D pipeline reports (the clock's laps).
const STAGES: usize = 7;

/// Rounds of relocation (each builds the exact site diagram once).
const RELOCATION_ROUNDS: usize = 24;

/// Rounds of moving sites that others beat, before the first diagram
/// (`Sites3::settle`: cheap, in doubles).
const SETTLE_ROUNDS: usize = 8;

/// Steiner points `split_facets` may add in all.
const MAX_STEINER: usize = 10_000;

/// Rounds of `split_facets` (each solves the LP again).
const SPLIT_ROUNDS: usize = 4;

/// When a round's whole batch of Steiner points is rejected, its first
/// points are tried one at a time (each a whole pipeline run).
const SINGLE_TRIES: usize = 4;

/// Meshes a 3D complex.
pub fn conform3<B: Backend + ?Sized>(
    backend: &B,
    cx: &Complex3,
    opts: &Options,
) -> Result<Outcome<D3>> {
    let start = Instant::now();
    let mut clock = Clock::start(opts.progress, STAGES);
    let clips = clips(cx, &opts.clip)?;
    let mut best = Attempt::run(
        backend,
        cx.clone(),
        opts.whole_polygons,
        &clips,
        Some(&mut clock),
    )?;
    // Refinement rounds, each kept only when it leaves fewer sites
    // outside (measured: a round that does not tends to start a cascade of
    // new failing faces); when the whole batch does not, a single point
    // may (TetGen's example: 17 -> 13 with one point, 17 -> 18 with all),
    // and a round where nothing helps ends the refinement.
    for _ in 0..SPLIT_ROUNDS {
        if !opts.split_facets || best.outside == 0 {
            break;
        }
        let add = steiner_points(&best.cx, &best.sc, &best.wt, &clips);
        if add.is_empty() || best.cx.points.len() + add.len() > cx.points.len() + MAX_STEINER {
            break;
        }
        let batches = std::iter::once(&add[..]).chain(
            (add.len() > 1)
                .then(|| add.chunks(1).take(SINGLE_TRIES))
                .into_iter()
                .flatten(),
        );
        let better = batches
            .map(|b| best.split(backend, b, opts.whole_polygons, &clips))
            .find_map(|next| next.ok().filter(|next| next.outside < best.outside));
        match better {
            Some(next) => best = next,
            None => break,
        }
    }
    clock.lap("split facets");
    let Attempt {
        cx: split,
        mut wt,
        mut s,
        mut d,
        settled,
        rounds,
        exact,
        ..
    } = best;
    let steiner = split.points[cx.points.len()..].to_vec();
    let cx = &split;
    let mut certificate = d.certify(cx, &wt, &s);
    clock.lap("certify");
    if !certificate.conforms() {
        return Err(Error::Certificate(format!(
            "the 3D mesh does not conform: {certificate:?}"
        )));
    }
    let outside = certificate.domain_sites - certificate.sites_inside;
    if outside > 0 && !opts.allow_sites_outside {
        return Err(sites_outside(cx, &wt, &s, &d));
    }
    // what the mesh does not need goes first (peak memory: the field
    // 16 x 16 x 4 peaked here, 251 MiB, now 231 in relocation)
    // (the faces' numbers go; their cycles stay for the cells)
    (d.rt, d.vertex_of, wt.rt) = Default::default();
    d.faces.drop_edges();
    // (and the sites' rationals: the mesh reads their doubles; field3 16 x
    // 16 x 8's peak went from 419 to 390 MiB without the relocation lines)
    let placed = s.p.len();
    let extra_sites =
        (0..placed).filter(|&x| !s.is_mirror(x)).count() - 2 * s.of_face.iter().flatten().count();
    (s.p, s.w, s.serves, s.line, s.track) = Default::default();
    let mesh = mesh(&d, &s, &wt);
    certificate.orthogonality_defect = mesh.orthogonality_defect();
    clock.lap("mesh");
    let count = |k: usize| wt.faces.iter().filter(|f| f.vertices.len() == k).count();
    let report = Report::<D3> {
        backend: backend.name().into(),
        input: InputReport3 {
            dimension: 3,
            vertices: cx.points.len(),
            facets: cx.facets.len(),
            triangles: count(3),
            whole_polygons: wt.whole_polygons,
            whole_polygons_kept: wt.keep,
            steiner_points: steiner,
            clip_facets: clips.iter().map(|c| c.facet as i64 + 1).collect(),
            segments: count(2),
            points: count(1),
        },
        weights: wt.report.clone(),
        sites: SitesReport3 {
            // (a clip facet's faces need not cross their duals)
            facets_missing_dual: facet_ids(&wt, &wt.sys3_failed)
                .into_iter()
                .filter(|&f| !clips.iter().any(|c| c.facet as i64 + 1 == f))
                .collect(),
            placed,
            extra_sites,
            settle_moves: settled,
            relocation_rounds: rounds,
            exact_triangulations: exact,
            sites_outside: outside,
        },
        cells: mesh.cells.len(),
        mesh_vertices: mesh.points.len(),
        collapsed_vertices: mesh.collapsed,
        certificate,
        timing: Some(clock.timing(start.elapsed().as_secs_f64() * 1e3)),
        split: None,
    };
    Ok(Outcome {
        site_inside: mesh.site_inside.clone(),
        mesh,
        report,
        constraints: split,
    })
}

/// The pipeline from a complex to its relocated site diagram.
#[derive(Clone)]
struct Attempt {
    cx: Complex3,
    sc: Simplices3,
    wt: weights::Weights3,
    s: Sites3,
    d: Diagram3,
    /// Moves before the first diagram (`Sites3::settle`).
    settled: usize,
    /// Relocation rounds, and the domain's sites left outside their cells.
    rounds: usize,
    /// Site diagrams built from the exact sites (`Diagram3::rebuilt`).
    exact: usize,
    outside: usize,
}

impl Attempt {
    /// The pipeline again with Steiner points `add` (facet, point) added.
    fn split<B: Backend + ?Sized>(
        &self,
        backend: &B,
        add: &[(usize, [f64; 3])],
        keep: weights::Keep,
        clips: &[Clip],
    ) -> Result<Attempt> {
        let mut next = self.cx.clone();
        let mut id = next.vertex_ids.iter().max().copied().unwrap_or(0);
        for &(f, p) in add {
            next.facets[f].polygons.push(vec![next.points.len() as u32]);
            next.points.push(p);
            id += 1;
            next.vertex_ids.push(id);
        }
        Attempt::run(backend, next, keep, clips, None)
    }

    /// The pipeline on `cx`, its stages timed on `clock` when given.
    fn run<B: Backend + ?Sized>(
        backend: &B,
        cx: Complex3,
        keep: weights::Keep,
        clips: &[Clip],
        mut clock: Option<&mut Clock>,
    ) -> Result<Attempt> {
        let mut lap = |stage: &str| {
            if let Some(c) = clock.as_deref_mut() {
                c.lap(stage)
            }
        };
        let sc = cx.triangulate(backend)?;
        lap("facets");
        let cut: Vec<u32> = clips.iter().map(|c| c.facet).collect();
        let wt = weights::solve3(backend, &cx, &sc, keep, &cut)?;
        lap("weights");
        let mut s = sites::place3(&cx, &wt)?;
        if !clips.is_empty() {
            s = s.clipped(&cx, &wt, clips.to_vec());
            if !s.span_volume() {
                return Err(Error::Degenerate(format!(
                    "cut at facets {}, the sites left span no volume (cut at fewer facets)",
                    crate::error::list(&clips.iter().map(|c| c.facet + 1).collect::<Vec<_>>())
                )));
            }
        }
        let settled = s.settle(&cx, &wt.w, SETTLE_ROUNDS);
        lap("sites");
        let mut d = Diagram3::build(backend, &cx, &s, false)?;
        let mut exact = d.rebuilt as usize;
        let mut rounds = 0;
        while rounds < RELOCATION_ROUNDS {
            // Sites of faces that cross their duals move towards the face,
            // past the neighbours that beat them (`Sites3::jump`): near it,
            // a site's cell is its half of a region around the face. Extra
            // sites try other places on their dual edges (`Sites3::wander`).
            if !(0..s.p.len()).any(|x| d.in_domain[x] && !d.site_inside[x]) {
                break;
            }
            let neighbours = d.rt.neighbours(s.p.len());
            let mut moved = false;
            for (x, around) in neighbours.iter().enumerate() {
                if d.in_domain[x] && !d.site_inside[x] {
                    moved |= s.jump(x, &cx, &wt.w, around) || s.wander(x, &cx, &wt.w, around);
                }
            }
            if !moved {
                break;
            }
            s.remirror();
            rounds += 1;
            // the old diagram goes before the new one is built (peak memory)
            drop(neighbours);
            let engine = d.engine;
            drop(std::mem::take(&mut d));
            d = Diagram3::build(backend, &cx, &s, engine)?;
            exact += d.rebuilt as usize;
        }
        let outside = (0..s.p.len())
            .filter(|&x| d.in_domain[x] && !d.site_inside[x])
            .count();
        lap("relocate");
        Ok(Attempt {
            cx,
            sc,
            wt,
            s,
            d,
            settled,
            rounds,
            exact,
            outside,
        })
    }
}

/// Chew's refinement with weights: the power centre of each triangle
/// that misses its dual, as a new point of its facet inside the facet's
/// triangle that holds it (exactly in the plane; none when doubles have
/// no such point).
fn steiner_points(
    cx: &Complex3,
    sc: &Simplices3,
    wt: &weights::Weights3,
    clips: &[Clip],
) -> Vec<(usize, [f64; 3])> {
    let mut add: Vec<(usize, [f64; 3])> = vec![];
    for (fi, face) in wt
        .sys3_failed
        .iter()
        .map(|&f| (f as usize, &wt.faces[f as usize]))
    {
        let (Some(f), 3) = (face.facet, face.vertices.len()) else {
            continue;
        };
        if sites::clip_of(clips, face.facet).is_some() {
            continue;
        }
        let Some((c, _)) = wt.centres.of(cx, &wt.w, &wt.faces, fi) else {
            continue;
        };
        let c = c.each_ref().map(crate::geom::f);
        let g: [f64; 3] = std::array::from_fn(|k| {
            face.vertices
                .iter()
                .map(|&v| cx.points[v as usize][k])
                .sum::<f64>()
                / 3.0
        });
        // the power centre, or the first point towards it from the
        // centroid that stays in the facet (outside it, e.g. in a hole)
        let found = [1.0, 0.5, 0.25, 0.125].iter().find_map(|&t| {
            let x: [f64; 3] = std::array::from_fn(|k| g[k] + t * (c[k] - g[k]));
            sc.triangles
                .iter()
                .zip(&sc.triangle_facet)
                .filter(|(_, &h)| h == f)
                .find_map(|(tri, _)| cx.steiner_in(f as usize, *tri, x))
        });
        if let Some(x) = found.filter(|x| !add.iter().any(|(_, y)| y == x)) {
            add.push((f as usize, x));
        }
    }
    add
}

/// A facet's plane (a point on it and a normal, None: no plane) and
/// whether input points lie beyond it (along the normal) and before it.
fn plane_sides(cx: &Complex3, f: usize) -> Option<([Q; 3], [Q; 3], bool, bool)> {
    let p = |v: u32| cx.points[v as usize].map(q);
    let [a, b, c] = cx.spanning(&cx.facets[f].polygons.concat())?;
    let o = p(a);
    let n = cross(&sub(&p(b), &o), &sub(&p(c), &o));
    let sides: Vec<std::cmp::Ordering> = cx
        .points
        .iter()
        .map(|x| dot(&sub(&x.map(q), &o), &n).cmp(&Q::from(0)))
        .collect();
    Some((o, n, sides.contains(&Greater), sides.contains(&Less)))
}

/// Whether every point is finite (exact geometry needs it; validation
/// names the others).
fn finite(cx: &Complex3) -> bool {
    cx.points.iter().flatten().all(|x| x.is_finite())
}

/// The facets with every input point on one side of their plane (on the
/// hull), to be clipped at (`Options::clip`). None where a point is not
/// finite: the pipeline's validation then names it.
pub fn hull_facets(cx: &Complex3) -> Vec<u32> {
    if !finite(cx) {
        return vec![];
    }
    (0..cx.facets.len())
        .filter(|&f| plane_sides(cx, f).is_some_and(|(_, _, above, below)| !(above && below)))
        .map(|f| f as u32)
        .collect()
}

/// The clip planes of these facets, their normals away from the points.
fn clips(cx: &Complex3, facets: &[u32]) -> Result<Vec<Clip>> {
    if !finite(cx) {
        // (the facets' validation names the point first)
        return Ok(vec![]);
    }
    facets
        .iter()
        .map(|&f| {
            if f as usize >= cx.facets.len() {
                return Err(Error::Usage(format!(
                    "clip facet {} of {}",
                    f + 1,
                    cx.facets.len()
                )));
            }
            let (o, n, above, below) = plane_sides(cx, f as usize)
                .ok_or_else(|| Error::BadFacets(format!("facet {} spans no plane", f + 1)))?;
            if above && below {
                return Err(Error::BadFacets(format!(
                    "facet {} cannot bound the mesh: points lie on both sides of its plane",
                    f + 1
                )));
            }
            let n = if above { n.map(|x| -x) } else { n };
            Ok(Clip { facet: f, o, n })
        })
        .collect()
}

fn facet_ids(wt: &weights::Weights3, faces: &[u32]) -> Vec<i64> {
    let mut ids: Vec<i64> = faces
        .iter()
        .filter_map(|&f| wt.faces[f as usize].facet)
        .map(|f| f as i64 + 1)
        .collect();
    ids.sort_unstable();
    ids.dedup();
    ids
}

/// The error naming the sites left outside their cells.
fn sites_outside(cx: &Complex3, wt: &weights::Weights3, s: &Sites3, d: &Diagram3) -> Error {
    let id = |v: u32| cx.vertex_ids[v as usize];
    let mut centres: Option<Vec<Centre>> = None;
    let mut own: std::collections::BTreeMap<u32, Vec<usize>> = Default::default();
    let mut sites = vec![];
    let mut faces = vec![];
    for x in (0..s.p.len()).filter(|&x| d.in_domain[x] && !d.site_inside[x]) {
        let face = s
            .of_face
            .iter()
            .position(|p| p.is_some_and(|p| p.contains(&(x as u32))));
        let ids: Vec<i64> = s.serves[x]
            .iter()
            .map(|&v| cx.vertex_ids[v as usize])
            .collect();
        sites.push(match face {
            Some(f) => {
                faces.push(f as u32);
                let why = if wt.sys3_failed.contains(&(f as u32)) {
                    ", whose face misses its dual"
                } else {
                    ""
                };
                format!(
                    "site {x} of a face of facet {} (vertices {ids:?}){why}",
                    wt.faces[f].facet.map_or(0, |f| f + 1)
                )
            }
            None => match s.serves[x][..] {
                [v] => {
                    own.entry(v).or_default().push(x);
                    continue;
                }
                _ => format!("extra site {x} (vertices {ids:?})"),
            },
        });
    }
    for (k, (&v, xs)) in own.iter().enumerate() {
        let why = (k < 20)
            .then(|| obtuse(cx, wt, &mut centres, v))
            .flatten()
            .map(|(f, a)| {
                let face: Vec<i64> = wt.faces[f].vertices.iter().map(|&u| id(u)).collect();
                format!(
                    ": it lies in the ball on the segment from the power centre of face {face:?} \
                     to its corner {}, so no sites close to it fit in their cells",
                    id(a)
                )
            })
            .unwrap_or_default();
        sites.push(format!("extra sites {xs:?} of vertex {}{why}", id(v)));
    }
    let hull = hull_facets(cx);
    if s.clips.is_empty() && !hull.is_empty() {
        sites.insert(
            0,
            format!(
                "facets {} lie on the hull: where nothing lies beyond them, --clip-hull cuts the \
                 cells at their planes, and their faces need not cross their duals",
                crate::error::list(&hull.iter().map(|f| f + 1).collect::<Vec<_>>())
            ),
        );
    }
    if let Some(p) = &wt.report.system3_proof {
        // First: `list` shows only the first sites.
        sites.insert(
            0,
            format!(
                "with {}, no weights make every face cross its dual (an exact certificate of {} LP \
                 rows proves that faces {:?}, by vertex ids, cannot all cross theirs)",
                p.premise, p.rows, p.crossing
            ),
        );
    }
    Error::SitesOutsideCells {
        sites,
        crowding: facet_ids(wt, &faces),
    }
}

/// A face's power centre, exact and rounded (None: a segment, a point, or
/// a face that is cut).
type Centre = Option<([Q; 3], [f64; 3])>;

/// A face (of dimension 2, not cut) and a corner a of it such that vertex
/// v lies in the closed ball on the segment from the face's power centre c
/// to a, (c - v).(a - v) <= 0, exactly. Sites close to v then cannot all be
/// inside their cells: they share a power p at v, which the face's site on
/// v's side must exceed there (at most |v - c|^2 - |a - c|^2 + w_a, its
/// value as it nears c), while their power at a must exceed w_a (about
/// |v - a|^2 + p): both need |v - c|^2 + |v - a|^2 > |a - c|^2.
/// `centres` holds the faces' power centres once computed.
fn obtuse(
    cx: &Complex3,
    wt: &weights::Weights3,
    centres: &mut Option<Vec<Centre>>,
    v: u32,
) -> Option<(usize, u32)> {
    use rayon::prelude::*;
    let centres = centres.get_or_insert_with(|| {
        wt.faces
            .par_iter()
            .enumerate()
            .map(|(fi, f)| {
                let (c, _) = (f.dim() == 2 && !f.cut)
                    .then(|| wt.centres.of(cx, &wt.w, &wt.faces, fi))??
                    .clone();
                let rounded = c.each_ref().map(crate::geom::f);
                Some((c, rounded))
            })
            .collect()
    });
    let pv = cx.points[v as usize];
    centres.iter().enumerate().find_map(|(f, c)| {
        let (c, rounded) = c.as_ref()?;
        let at = |x: [f64; 3]| [0, 1, 2].map(|k| x[k] - pv[k]);
        let cv = at(*rounded);
        wt.faces[f]
            .vertices
            .iter()
            .find(|&&a| {
                // doubles first, far from a tie; exact near one
                let av = at(cx.points[a as usize]);
                let d = crate::geom::dot_f(cv, av);
                let tie = 1e-9 * crate::geom::dot_f(cv, cv).max(crate::geom::dot_f(av, av));
                d < -tie
                    || (d <= tie && {
                        let pq = pv.map(q);
                        dot(&sub(c, &pq), &sub(&cx.points[a as usize].map(q), &pq)) <= 0
                    })
            })
            .map(|&a| (f, a))
    })
}

/// The domain's cells as a mesh, with the faces between them.
fn mesh(d: &Diagram3, s: &Sites3, wt: &weights::Weights3) -> Mesh3 {
    let approx = &d.approx;
    let domain: Vec<usize> = (0..d.in_domain.len()).filter(|&x| d.in_domain[x]).collect();
    let mut cell_of = vec![usize::MAX; d.in_domain.len()];
    for (c, &x) in domain.iter().enumerate() {
        cell_of[x] = c;
    }
    // Power vertices of the domain's cells, those closer than the output
    // precision merged (docs/method.md section 4).
    let mut used: Vec<u32> = domain
        .iter()
        .flat_map(|&x| {
            d.cells[x]
                .iter()
                .flatten()
                .flat_map(|side| d.faces.side(side))
        })
        .collect();
    used.sort_unstable();
    used.dedup();
    let pts: Vec<[f64; 3]> = used.iter().map(|&v| d.points[v as usize]).collect();
    let fixed: Vec<bool> = used
        .iter()
        .map(|&v| d.input_vertex[v as usize].is_some())
        .collect();
    let merged = crate::mesh::Collapsed::of(&pts, &fixed);
    let mut id = vec![u32::MAX; d.points.len()];
    for (k, &v) in used.iter().enumerate() {
        id[v as usize] = merged.map[k];
    }
    // per domain cell, its faces (merged ids), and the site across each
    let sides = |x: usize| d.cells[x].iter().flatten();
    let shapes: Vec<Vec<Vec<u32>>> = domain
        .iter()
        .map(|&x| {
            sides(x)
                .map(|side| d.faces.side(side).map(|v| id[v as usize]).collect())
                .collect()
        })
        .collect();
    let welded = crate::mesh::weld(&merged.points, &merged.fixed, &shapes);
    for v in id.iter_mut().filter(|v| **v != u32::MAX) {
        *v = welded.map[*v as usize];
    }
    let points = welded.points;
    let mut cells = vec![];
    let mut links = vec![];
    for (&x, faces) in domain.iter().zip(&shapes) {
        let mut out = vec![];
        for (f, side) in faces.iter().zip(sides(x)) {
            let o = side.other as usize;
            let mut f: Vec<u32> = f.iter().map(|&v| welded.map[v as usize]).collect();
            f.dedup();
            while f.len() > 1 && f.first() == f.last() {
                f.pop();
            }
            if f.len() < 3 {
                continue;
            }
            if d.in_domain[o] && x < o {
                let pts: Vec<[f64; 3]> = f.iter().map(|&v| points[v as usize]).collect();
                let plane = Plane::of(&pts);
                let dist = |site: usize| plane.distance(xyz(approx[site]));
                links.push(Link3 {
                    cells: [cell_of[x], cell_of[o]],
                    face: f.clone(),
                    area: plane.area,
                    d: [dist(x), dist(o)],
                    normal: plane.unit,
                });
            }
            out.push(f);
        }
        cells.push(out);
    }
    let mut of_input = std::collections::HashMap::new();
    for (v, iv) in d.input_vertex.iter().enumerate() {
        if let Some(i) = iv {
            of_input.insert(*i, id[v]);
        }
    }
    let mut facet_faces = vec![];
    for (fi, face) in wt.faces.iter().enumerate() {
        let (Some([a, b]), Some(facet)) = (s.of_face[fi], face.facet) else {
            continue;
        };
        let (a, b) = (a as usize, b as usize);
        if d.in_domain[a] == d.in_domain[b] {
            continue;
        }
        let x = if d.in_domain[a] { a } else { b };
        let ids: Option<Vec<u32>> = face
            .vertices
            .iter()
            .map(|v| of_input.get(v).copied())
            .collect();
        let Some(ids) = ids.filter(|ids| ids.iter().all(|&i| i != u32::MAX)) else {
            continue;
        };
        let pts: Vec<[f64; 3]> = ids.iter().map(|&v| points[v as usize]).collect();
        let plane = Plane::of(&pts);
        facet_faces.push(FacetFace {
            facet,
            points: ids,
            cell: cell_of[x],
            area: plane.area,
            d: plane.distance(xyz(approx[x])),
        });
    }
    // welded cells' volumes as written (their points moved by a few 1e-5
    // of an edge beside at most), the others' from the diagram
    let mut shared = vec![0u32; points.len()];
    for &v in &welded.map {
        shared[v as usize] += 1;
    }
    let volumes = domain
        .iter()
        .zip(&cells)
        .map(|(&x, c)| {
            let moved = c.iter().flatten().any(|&v| shared[v as usize] > 1);
            if moved {
                crate::geom::volume(c, &points)
            } else {
                d.volume(x)
            }
        })
        .collect();
    Mesh3 {
        points,
        volumes,
        facet_faces,
        collapsed: merged.collapsed + welded.welded,
        cells,
        sites: domain.iter().map(|&x| xyz(approx[x])).collect(),
        weights: domain.iter().map(|&x| approx[x][3]).collect(),
        site_inside: domain.iter().map(|&x| d.site_inside[x]).collect(),
        links,
    }
}

/// A site's position.
fn xyz(p: [f64; 4]) -> [f64; 3] {
    [p[0], p[1], p[2]]
}
