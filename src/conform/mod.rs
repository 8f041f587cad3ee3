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

use crate::complex::{Complex, Complex3};
use crate::mesh::Mesh3;
use crate::progress::Progress;
use serde::Serialize;
use std::time::Instant;

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

/// Laps of the pipeline's stages, told to the progress callback as they end.
pub(crate) struct Clock {
    last: Instant,
    stages: Vec<Stage>,
    progress: Option<Progress>,
    /// Stages the run reports, for the progress callback.
    of: usize,
}

impl Clock {
    /// A clock from now (the peak of memory reset).
    pub(crate) fn start(progress: Option<Progress>, of: usize) -> Clock {
        peak_mib_since_last();
        Clock {
            last: Instant::now(),
            stages: vec![],
            progress,
            of,
        }
    }

    /// Ends a stage.
    pub(crate) fn lap(&mut self, stage: &str) {
        let now = Instant::now();
        self.stages.push(Stage {
            stage: stage.into(),
            ms: (now - self.last).as_secs_f64() * 1e3,
            peak_mib: peak_mib_since_last(),
        });
        self.last = now;
        if let Some(f) = self.progress {
            f(stage, self.stages.len(), self.of);
        }
    }

    /// The stages and their peak, for a run of `total_ms`.
    pub(crate) fn timing(self, total_ms: f64) -> Timing {
        Timing {
            peak_mib: self
                .stages
                .iter()
                .filter_map(|s| s.peak_mib)
                .reduce(f64::max),
            stages: self.stages,
            total_ms,
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
/// (Linux: getrusage's maximum resident set, which follows the reset
/// through /proc/self/clear_refs; measured equal to /proc/self/status'
/// VmHWM at every stage of field3 16 x 16 x 8. The kernel also keeps the
/// peak of threads that exit, and the pipeline's threads do not). None
/// where the system does not tell.
#[allow(unsafe_code)]
pub fn peak_mib_since_last() -> Option<f64> {
    // SAFETY: getrusage fills the struct it is given, all integers.
    let usage = unsafe {
        let mut usage: libc::rusage = std::mem::zeroed();
        (libc::getrusage(libc::RUSAGE_SELF, &mut usage) == 0).then_some(usage)
    }?;
    // Best effort: without the reset, peaks only grow.
    let _ = std::fs::write("/proc/self/clear_refs", "5");
    // (kilobytes on Linux)
    Some(usage.ru_maxrss as f64 / 1024.0)
}
