//! The weights stage: weights under which the regular triangulation
//! contains every constraint and every constraint crosses its dual
//! (docs/method.md sections 2 and 3), by the LP of `lp`, checked exactly.
//! 2D: zero weights, the local form, the lazy global form (`d2`); 3D: the
//! lazy global form over the maximal faces, polygons kept whole (`d3`).

mod d2;
mod d3;

pub use crate::lp::WeightsReport;
pub use d2::{anchor_offset, solve, sys3_failures, Weights};
pub use d3::{face_centre, solve as solve3, Face, Keep, Weights3};
pub(crate) use d3::{fan, sorted3};
