//! The pipeline run once, in either dimension: its stages in order (`d2`,
//! `d3`), what it returns (`Outcome`, generic over the `Dimension`) and
//! what each stage cost (`Timing`).

mod d2;
mod d3;
mod report;

pub use d2::conform2;
pub use d3::{conform3, hull_facets};
pub use report::{
    InputReport2, InputReport3, Report, SitesReport2, SitesReport3, SplitReport, SplitSegment,
};

use crate::mesh::Mesh3;
use crate::complex::{Complex, Complex3};
use serde::Serialize;

/// A dimension the pipeline runs in: what it takes and what it gives.
pub trait Dimension {
    /// The constraint complex.
    type Complex: Clone + std::fmt::Debug;
    /// The mesh as written.
    type Mesh: Clone + std::fmt::Debug;
    /// The report's section on the input.
    type InputReport: Clone + std::fmt::Debug + Default + Serialize;
    /// The report's section on the sites.
    type SitesReport: Clone + std::fmt::Debug + Default + Serialize;
    /// What the finished mesh proves about itself.
    type Certificate: Clone + std::fmt::Debug + Default + Serialize;
}

/// The plane: polygons around segments.
#[derive(Debug, Clone, Copy, Default)]
pub struct D2;

/// Space: polyhedra around facets.
#[derive(Debug, Clone, Copy, Default)]
pub struct D3;

impl Dimension for D2 {
    type Complex = Complex;
    type Mesh = crate::mesh::Mesh;
    type InputReport = InputReport2;
    type SitesReport = SitesReport2;
    type Certificate = crate::certify::Certificate;
}

impl Dimension for D3 {
    type Complex = Complex3;
    type Mesh = Mesh3;
    type InputReport = InputReport3;
    type SitesReport = SitesReport3;
    type Certificate = crate::certify::Certificate3;
}

/// A certified mesh and how it was made.
#[derive(Debug, Clone)]
pub struct Outcome<D: Dimension> {
    /// The mesh as written.
    pub mesh: D::Mesh,
    /// What was done and what the certificate found.
    pub report: Report<D>,
    /// The constraints as meshed: the input with the convex hull's edges
    /// where the segments enclose nothing (2D) and any Steiner points.
    pub constraints: D::Complex,
    /// Which mesh cells have their site strictly inside.
    pub site_inside: Vec<bool>,
}

/// What each stage cost.
#[derive(Debug, Clone, Serialize, Default)]
pub struct Timing {
    /// In order.
    pub stages: Vec<Stage>,
    /// The whole run.
    pub total_ms: f64,
    /// Largest resident memory of the process over the run (MiB; Linux).
    pub peak_mib: Option<f64>,
    /// The backend's raw regular triangulation of the same vertices, when
    /// asked for (`Options::compare_with_raw`).
    pub raw_triangulation_ms: Option<f64>,
    /// total_ms / raw_triangulation_ms (the speed measure).
    pub ratio_to_raw: Option<f64>,
}

impl Timing {
    /// The whole run's time since `start`, without stages.
    pub(crate) fn total(start: std::time::Instant) -> Timing {
        Timing {
            total_ms: start.elapsed().as_secs_f64() * 1e3,
            peak_mib: peak_mib_since_last(),
            ..Timing::default()
        }
    }
}

/// One stage's time and the peak of resident memory while it ran.
#[derive(Debug, Clone, Serialize)]
pub struct Stage {
    /// Its name.
    pub stage: String,
    /// Its time.
    pub ms: f64,
    /// The peak of resident memory while it ran (MiB).
    pub peak_mib: Option<f64>,
}

/// Peak resident memory since the last call (MiB), then the peak is reset
/// (Linux: VmHWM in /proc/self/status, reset through /proc/self/clear_refs).
/// None where the system does not tell.
pub fn peak_mib_since_last() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let kib: f64 = status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))?
        .trim()
        .trim_end_matches("kB")
        .trim()
        .parse()
        .ok()?;
    // Best effort: without the reset, peaks only grow.
    let _ = std::fs::write("/proc/self/clear_refs", "5");
    Some(kib / 1024.0)
}
