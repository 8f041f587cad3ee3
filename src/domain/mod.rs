//! The domain stage: in 2D the constrained Delaunay triangulation of the
//! complex eaten from the hull and the holes (`Domain`); in 3D each facet
//! triangulated in its plane (`Simplices3`).

mod d2;
mod d3;

pub use d2::{build, Domain};
pub use d3::Simplices3;
