//! The 2D pipeline: validate, domain, weights, sites, relocation, diagram,
//! certificate, mesh.

use super::{peak_mib_since_last, Outcome, Stage, Timing, D2};
use crate::backend::Backend;
use crate::certify::{certify, Certificate};
use crate::complex::Complex;
use crate::domain;
use crate::error::{Error, Result};
use crate::mesh::Mesh;
use crate::options::Options;
use crate::progress::Progress;
use crate::relocate::relocate;
use crate::sites::{Role, Sites};
use crate::weights::{self, WeightsReport};
use serde::Serialize;
use std::time::Instant;

/// The report written next to the mesh.
#[derive(Debug, Clone, Serialize, Default)]
pub struct Report {
    /// The backend's name.
    pub backend: String,
    /// Input vertices.
    pub vertices: usize,
    /// Input segments.
    pub segments: usize,
    /// Input hole points.
    pub holes: usize,
    /// What the reader or the domain changed and the user should know.
    pub notes: Vec<String>,
    /// The domain's area.
    pub domain_area: f64,
    /// Convex hull edges added where the segments enclose nothing.
    pub hull_edges_added: usize,
    /// Input vertices outside the domain, dropped.
    pub dropped_vertices: usize,
    /// Input segments outside the domain, dropped.
    pub dropped_segments: usize,
    /// What the weights step did.
    pub weights: WeightsReport,
    /// Segments (input ids) that do not cross their dual edge.
    pub segments_missing_dual: Vec<i64>,
    /// Sites placed.
    pub sites: usize,
    /// Extra sites of free ends and isolated vertices.
    pub vertex_sites: usize,
    /// Rounds of relocation.
    pub relocation_rounds: usize,
    /// Rounds whose site triangulation had to be built in exact rationals
    /// (the one from rounded sites failed its exact check).
    pub exact_site_triangulations: usize,
    /// Smallest distance from a domain site to its cell's boundary, divided
    /// by the square root of the cell's area (0 when some site is outside).
    pub min_site_margin: f64,
    /// Sites outside their cells, each with why.
    pub sites_outside: Vec<String>,
    /// Cells in the mesh.
    pub cells: usize,
    /// Vertices in the mesh.
    pub mesh_vertices: usize,
    /// Vertices merged with a neighbour closer than the output precision.
    pub collapsed_vertices: usize,
    /// The exact certificate.
    pub certificate: Certificate,
    /// Time and memory: they differ from run to run, everything else in
    /// the report does not (the CLI's `--reproducible` leaves this out).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub timing: Option<Timing>,
    /// Segments meshed as chains (`Options::split_segments`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub split: Option<SplitReport>,
}

struct Clock {
    last: Instant,
    stages: Vec<Stage>,
    progress: Option<Progress>,
}

impl Clock {
    fn start(progress: Option<Progress>) -> Clock {
        peak_mib_since_last();
        Clock {
            last: Instant::now(),
            stages: vec![],
            progress,
        }
    }

    fn lap(&mut self, stage: &str) {
        let now = Instant::now();
        self.stages.push(Stage {
            stage: stage.into(),
            ms: (now - self.last).as_secs_f64() * 1e3,
            peak_mib: peak_mib_since_last(),
        });
        self.last = now;
        if let Some(f) = self.progress {
            f(stage, self.stages.len(), STAGES);
        }
    }
}

/// Stages `conform` reports (the clock's laps).
const STAGES: usize = 7;

/// Builds the certified conforming orthogonal mesh of a 2D complex, once
/// (no Steiner points: `split` adds those).
pub fn conform2<B: Backend + ?Sized>(
    backend: &B,
    input: &Complex,
    opts: &Options,
) -> Result<Outcome<D2>> {
    let start = Instant::now();
    let mut clock = Clock::start(opts.progress);
    input.validate()?;
    clock.lap("validate");
    let dom = domain::build(backend, input)?;
    clock.lap("domain");
    let cx = &dom.complex;
    let wts = weights::solve(backend, &dom, opts.progress)?;
    clock.lap("weights");
    let missing_dual: Vec<i64> = wts
        .sys3_failed
        .iter()
        .map(|&s| cx.segment_ids[s as usize])
        .collect();
    if !missing_dual.is_empty() && !opts.allow_sites_outside {
        return Err(Error::SegmentsMissTheirDuals {
            segments: missing_dual,
            lp_error: wts.report.lp_error.clone(),
        });
    }
    let inside = |t: Option<u32>| t.is_some_and(|t| dom.inside[t as usize]);
    let domain_side: Vec<[bool; 2]> = cx
        .segments
        .iter()
        .map(|&[i, j]| [inside(dom.cdt.left_of(i, j)), inside(dom.cdt.left_of(j, i))])
        .collect();
    let mut sites = Sites::place(cx, &wts.w, &wts.rt, &wts.sys3_failed, &domain_side);
    if let Some(s) = sites.unrepresentable() {
        return Err(Error::Certificate(format!(
            "{} lies beyond the range of doubles: cells this thin cannot be written in double precision",
            sites.describe(s, cx)
        )));
    }
    clock.lap("sites");
    let rel = relocate(backend, &dom, &mut sites)?;
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
        return Err(Error::Certificate(cert.problems.join("; ")));
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
    let report = Report {
        backend: backend.name().into(),
        vertices: input.points.len(),
        segments: input.segments.len(),
        holes: input.holes.len(),
        notes: cx.notes.clone(),
        domain_area: dom.area(),
        hull_edges_added: dom.hull_edges_added,
        dropped_vertices: dom.dropped_vertices,
        dropped_segments: dom.dropped_segments,
        weights: wts.report.clone(),
        segments_missing_dual: wts
            .sys3_failed
            .iter()
            .map(|&s| cx.segment_ids[s as usize])
            .collect(),
        sites: sites.len(),
        vertex_sites: sites
            .role
            .iter()
            .filter(|r| matches!(r, Role::Vertex { .. }))
            .count(),
        relocation_rounds: rel.rounds,
        exact_site_triangulations: rel.exact_rounds,
        min_site_margin,
        sites_outside: outside_names,
        cells: mesh.cells.len(),
        mesh_vertices: mesh.points.len(),
        collapsed_vertices: mesh.collapsed,
        certificate: cert,
        timing: Some(Timing {
            peak_mib: clock
                .stages
                .iter()
                .filter_map(|s| s.peak_mib)
                .reduce(f64::max),
            stages: clock.stages,
            total_ms,
            raw_triangulation_ms,
            ratio_to_raw: raw_triangulation_ms.map(|raw| total_ms / raw),
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

/// What splitting did, for the report.
#[derive(Debug, Clone, Serialize, Default)]
pub struct SplitReport {
    /// Rounds of splitting.
    pub rounds: usize,
    /// Steiner points added in all.
    pub steiner_points: usize,
    /// Input segments meshed as chains.
    pub segments: Vec<SplitSegment>,
}

/// One input segment meshed as a chain.
#[derive(Debug, Clone, Serialize)]
pub struct SplitSegment {
    /// The segment's id in the input.
    pub id: i64,
    /// Edges of its chain.
    pub pieces: usize,
    /// Largest distance of its Steiner points from the segment, over its
    /// length: 0 when they lie on it exactly; else each is the double
    /// nearest its midpoint (no double lies on the segment near there).
    pub off_line: f64,
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
    let mut nearest = vec![f64::INFINITY; sites.len()];
    for (a, b) in rt.edges() {
        for (x, y) in [(a as usize, b as usize), (b as usize, a as usize)] {
            let [xa, ya, wa] = sites.approx[x];
            let [xb, yb, wb] = sites.approx[y];
            let d2 = (xa - xb).powi(2) + (ya - yb).powi(2);
            nearest[x] = nearest[x].min((d2 + wa - wb) / (2.0 * d2.sqrt()));
        }
    }
    domain_sites
        .iter()
        .zip(&mesh.cells)
        .map(|(&a, cell)| nearest[a] / mesh.area(cell).abs().sqrt())
        .fold(f64::INFINITY, f64::min)
}
