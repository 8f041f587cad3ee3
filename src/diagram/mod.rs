//! The site diagram stage: the sites' regular triangulation, checked
//! exactly and repaired by exact flips (`d2`), or built exactly with its
//! certificate (`d3`), and the power diagram read off it.

mod d2;
mod d3;
mod faces3;
mod regular3;

pub use d2::{repair_around, star_ccw, Diagram, EdgeTests};
pub use d3::{Certificate3, Diagram3};
