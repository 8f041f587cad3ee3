//! The weights stage: weights under which the regular triangulation
//! contains every constraint and every constraint crosses its dual
//! (docs/method.md sections 2 and 3), by the LP of `lp`, checked exactly.
//! 2D: zero weights, the local form, the lazy global form (`d2`); 3D: zero
//! weights (`zero3`), else the lazy global form over the maximal faces,
//! polygons kept whole (`d3`).

mod centres;
mod coplanar;
mod d2;
mod d3;
mod face;
mod rows3;
mod zero3;

pub use crate::lp::WeightsReport;
pub use centres::{face_centre, Centre};
pub use d2::{solve, Weights};
pub use d3::{kept_whole, solve as solve3, Weights3};
pub use face::Face;
pub(crate) use face::{fan, sorted3};

/// How whole polygons keep their lifts coplanar.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum Keep {
    /// Shared weights, and coplanar lifts where shared weights leave no
    /// solution even with every facet triangulated, or HiGHS fails on them
    /// (measured on TetGen's example: shared weights bring more sites
    /// inside, see docs/limitations.md).
    #[default]
    Auto,
    /// Each polygon's vertices beyond its first three get the weights that
    /// put their lifts on the plane through the first three lifts (the
    /// equality rows of docs/method.md section 6, made exact): the most freedom.
    Coplanar,
    /// The vertices of whole polygons joined through common vertices share
    /// one weight: every polygon's power centre is its circumcentre, which
    /// an orthogonal interface with a neighbour cell centred on it needs
    /// (the hybrid's walls).
    Shared,
}

impl Keep {
    /// The ways tried in turn (shared weights are a special case of
    /// coplanar lifts, so coplanar lifts after them can only add
    /// solutions; shared weights after coplanar lifts are there for HiGHS
    /// failures).
    fn ways(self) -> &'static [Keep] {
        match self {
            Keep::Auto => &[Keep::Shared, Keep::Coplanar],
            Keep::Coplanar => &[Keep::Coplanar, Keep::Shared],
            Keep::Shared => &[Keep::Shared],
        }
    }
}

impl std::fmt::Display for Keep {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str(match self {
            Keep::Auto => "auto",
            Keep::Coplanar => "coplanar",
            Keep::Shared => "shared-weight",
        })
    }
}
