//! The 2D pipeline: validate, domain, weights, sites, relocation, diagram,
//! certificate, mesh.

use super::{Clock, InputReport2, Outcome, Report, SitesReport2, Timing, D2};
use crate::backend::Backend;
use crate::certify::certify;
use crate::complex::Complex;
use crate::domain;
use crate::error::{Error, Result};
use crate::mesh::Mesh;
use crate::options::Options;
use crate::relocate::relocate;
use crate::sites::{Role, Sites};
use crate::weights;
use rayon::prelude::*;
use std::time::Instant;

/// Stages the 2D pipeline reports (the clock's laps).
const STAGES: usize = 8;

/// Builds the certified conforming orthogonal mesh of a 2D complex, once
/// (no Steiner points: `split` adds those).
pub fn conform2<B: Backend + ?Sized>(
    backend: &B,
    input: &Complex,
    opts: &Options,
) -> Result<Outcome<D2>> {
    let start = Instant::now();
    let mut clock = Clock::start(opts.progress, STAGES);
    input.validate()?;
    clock.lap("validate");
    let dom = domain::build(backend, input)?;
    clock.lap("domain");
    let wts = weights::solve(backend, &dom, opts.progress)?;
    clock.lap("weights");
    with_weights(backend, input, dom, wts, opts, (start, clock))
}

/// The pipeline from the weights on: sites, relocation, diagram,
/// certificate, mesh and report.
fn with_weights<B: Backend + ?Sized>(
    backend: &B,
    input: &Complex,
    dom: domain::Domain,
    wts: weights::Weights,
    opts: &Options,
    (start, mut clock): (Instant, Clock),
) -> Result<Outcome<D2>> {
    let cx = &dom.complex;
    let ids = |v: &[u32]| -> Vec<i64> { v.iter().map(|&s| cx.segment_ids[s as usize]).collect() };
    if !wts.sys3_failed.is_empty() && !opts.allow_sites_outside {
        return Err(Error::SegmentsMissTheirDuals {
            segments: ids(&wts.sys3_failed),
            lp_error: wts.report.lp_error.clone(),
            proved: ids(&wts.sys3_proved),
        });
    }
    let corners = opts.corner_sites;
    let mut sites = Sites::place(cx, &wts.w, &wts.rt, &wts.sys3_failed, &dom.sides, corners);
    if let Some(s) = sites.unrepresentable() {
        return Err(Error::Certificate(format!(
            "{} lies beyond the range of doubles: cells this thin cannot be written in double precision",
            sites.describe(s, cx)
        )));
    }
    if !sites.starved.is_empty() {
        let ids: Vec<i64> = sites
            .starved
            .iter()
            .map(|&v| cx.vertex_ids[v as usize])
            .collect();
        return Err(Error::SolverLimit(format!(
            "the weights leave the power cells of vertices {ids:?} (free ends or isolated) too small for their extra sites: no dual edge of theirs is long enough, and their cells' corners coincide in double precision"
        )));
    }
    let stray: Vec<String> = (0..sites.len())
        .filter(|&s| !sites.in_served_cells(s))
        .map(|s| sites.describe(s, cx))
        .collect();
    if !stray.is_empty() {
        return Err(Error::SolverLimit(format!(
            "no position in double precision puts {} inside the power cell it serves: the weights leave that cell a sliver",
            stray.join(", ")
        )));
    }
    clock.lap("sites");
    let first = crate::relocate::first_diagram(backend, &dom, &sites)?;
    clock.lap("site diagram");
    let rel = relocate(backend, &dom, &mut sites, first)?;
    clock.lap("relocate");
    let (why, crowding) = crate::relocate::why(&sites, &rel.rt, &rel.outside, cx);
    let outside_names: Vec<String> = why
        .into_iter()
        .zip(&rel.outside)
        .map(|(why, &s)| format!("{}: {why}", sites.describe(s, cx)))
        .collect();
    if !rel.outside.is_empty() && !opts.allow_sites_outside {
        return Err(Error::SitesOutsideCells {
            sites: outside_names,
            crowding,
        });
    }
    let mesh = Mesh::from_diagram(&rel.diagram, &sites, &rel.rt)?;
    let cert = certify(&dom, &sites, &rel.rt, &rel.diagram, &rel.outside, &mesh);
    clock.lap("certify");
    if !cert.conforms() {
        return Err(hidden_extra_sites(&sites, &rel.rt, cx)
            .map(|names| {
                Error::SolverLimit(format!(
                    "hidden at every place tried on its track ({names}): the weights leave the power cell it serves too small for sites that each keep a cell, so that vertex is no mesh vertex ({})",
                    cert.problems.join("; ")
                ))
            })
            .unwrap_or_else(|| Error::Certificate(cert.problems.join("; "))));
    }
    let domain_sites: Vec<usize> = (0..sites.len())
        .filter(|&s| rel.diagram.in_domain[s])
        .collect();
    let outside: std::collections::HashSet<usize> = rel.outside.iter().copied().collect();
    let site_inside: Vec<bool> = domain_sites.iter().map(|s| !outside.contains(s)).collect();
    let min_site_margin = if rel.outside.is_empty() {
        site_margin(&sites, &rel.rt, &mesh, &domain_sites)
    } else {
        0.0
    };

    clock.lap("report");
    let total_ms = start.elapsed().as_secs_f64() * 1e3;
    let raw_triangulation_ms = if opts.compare_with_raw {
        let t0 = Instant::now();
        backend.regular(&input.points, &vec![0.0; input.points.len()])?;
        Some(t0.elapsed().as_secs_f64() * 1e3)
    } else {
        None
    };
    let report = Report::<D2> {
        backend: backend.name().into(),
        input: InputReport2 {
            vertices: input.points.len(),
            segments: input.segments.len(),
            holes: input.holes.len(),
            notes: cx.notes.clone(),
            domain_area: dom.area(),
            hull_edges_added: dom.hull_edges_added,
            dropped_vertices: dom.dropped_vertices,
            dropped_segments: dom.dropped_segments,
        },
        weights: wts.report.clone(),
        sites: SitesReport2 {
            segments_missing_dual: ids(&wts.sys3_failed),
            placed: sites.len(),
            vertex_sites: sites
                .role
                .iter()
                .filter(|r| matches!(r, Role::Vertex { .. }))
                .count(),
            relocation_rounds: rel.rounds,
            exact_site_triangulations: rel.exact_rounds,
            min_site_margin,
            sites_outside: outside_names,
        },
        cells: mesh.cells.len(),
        mesh_vertices: mesh.points.len(),
        collapsed_vertices: mesh.collapsed,
        certificate: cert,
        timing: Some(Timing {
            raw_triangulation_ms,
            ratio_to_raw: raw_triangulation_ms.map(|raw| total_ms / raw),
            ..clock.timing(total_ms)
        }),
        split: None,
    };
    Ok(Outcome {
        mesh,
        report,
        constraints: dom.complex,
        site_inside,
    })
}

/// The hidden extra sites, named, if any: in a tiny power cell an extra
/// site can stay hidden at every place its track offers (a fuzzed input's
/// weights made four such cells meet within 1e-3 of one point), and its
/// vertex then lacks a site. A limit of those weights, not a wrong mesh.
fn hidden_extra_sites(
    sites: &Sites,
    rt: &crate::backend::Triangulation,
    cx: &Complex,
) -> Option<String> {
    let names: Vec<String> = rt
        .hidden
        .iter()
        .map(|&s| s as usize)
        .filter(|&s| matches!(sites.role[s], Role::Vertex { .. }))
        .map(|s| sites.describe(s, cx))
        .collect();
    (!names.is_empty()).then(|| names.join(", "))
}

/// Smallest (distance from site to a face of its cell) / sqrt(cell area)
/// over the domain sites; the distance to the radical line of a and b is
/// (|a - b|^2 + omega_a - omega_b) / (2 |a - b|).
fn site_margin(
    sites: &Sites,
    rt: &crate::backend::Triangulation,
    mesh: &Mesh,
    domain_sites: &[usize],
) -> f64 {
    // Per site, its power distance to the nearest dual line: each thread
    // takes a block of triangles (both ways along their edges), then the
    // minima of the blocks (a minimum is the same in any order).
    let block = rt
        .triangles
        .len()
        .div_ceil(rayon::current_num_threads())
        .max(1);
    let nearest = rt
        .triangles
        .par_chunks(block)
        .map(|tris| {
            let mut near = vec![f64::INFINITY; sites.len()];
            for tri in tris {
                for k in 0..3 {
                    let (a, b) = (tri[k] as usize, tri[(k + 1) % 3] as usize);
                    let ([xa, ya, wa], [xb, yb, wb]) = (sites.approx(a), sites.approx(b));
                    let d2 = (xa - xb).powi(2) + (ya - yb).powi(2);
                    let twice_len = 2.0 * d2.sqrt();
                    near[a] = near[a].min((d2 + wa - wb) / twice_len);
                    near[b] = near[b].min((d2 + wb - wa) / twice_len);
                }
            }
            near
        })
        .reduce_with(|mut a, b| {
            a.par_iter_mut().zip(&b).for_each(|(x, y)| *x = x.min(*y));
            a
        })
        .unwrap_or_default();
    domain_sites
        .iter()
        .zip(&mesh.cells)
        .map(|(&a, cell)| nearest[a] / mesh.area(cell).abs().sqrt())
        .fold(f64::INFINITY, f64::min)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Fourteen points on a 1/16 lattice, three of them collinear on the
    /// hull at x = 0 (the pipeline fuzz target's seed
    /// `collinear-hull-vertex`), with the weights another HiGHS release
    /// returned for them. Vertex 12's neighbour 8 lies level with it, and an
    /// extra site of 8 placed on their wall x = 3.125 ties with vertex 12's
    /// sites at vertex 12: the site triangulation put it in every triangle
    /// there, and the diagram lost that input vertex.
    #[test]
    fn an_extra_site_on_a_wall_keeps_the_vertex_beyond_it() {
        let lattice = [
            (80, 255),
            (154, 2),
            (52, 228),
            (145, 39),
            (26, 223),
            (32, 255),
            (255, 255),
            (44, 111),
            (100, 2),
            (38, 1),
            (101, 31),
            (0, 0),
            (0, 2),
            (0, 4),
        ];
        let points = lattice
            .map(|(x, y)| [x as f64 / 16.0, y as f64 / 16.0])
            .to_vec();
        let input = Complex::new(points, vec![]);
        let w = [
            0.0,
            32.484374999999964,
            0.0,
            0.0,
            0.0,
            0.0,
            0.0,
            -43.72621859455694,
            0.0,
            -9.201918036269594,
            0.0,
            0.009782645190775742,
            0.0,
            0.0,
        ];
        let opts = Options {
            allow_sites_outside: true,
            ..Default::default()
        };
        for backend in crate::backend::compiled() {
            let dom = domain::build(&*backend, &input).unwrap();
            let mut wts = weights::solve(&*backend, &dom, None).unwrap();
            wts.rt = backend.regular(&dom.complex.points, &w).unwrap();
            wts.w = w.to_vec();
            let clock = (Instant::now(), Clock::start(None, STAGES));
            let out = with_weights(&*backend, &input, dom, wts, &opts, clock);
            let cert = out.map(|o| o.report.certificate);
            assert!(
                cert.as_ref().is_ok_and(|c| c.conforms()),
                "{}: {cert:?}",
                backend.name()
            );
        }
    }
}
