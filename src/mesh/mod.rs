//! The mesh stage: the mesh as written in doubles (`Mesh` in 2D, `Mesh3`
//! in 3D), and the two views every writer takes: cells with named arrays
//! (`CellMesh`) and a two-point flux network (`Network`).

mod cells;
mod d2;
mod d3;
mod network;
mod weld;

pub use cells::{join, CellArray, CellMesh, Cells, Values};
pub use d2::{Collapsed, Mesh};
pub use d3::{FacetFace, Link3, Mesh3};
pub use network::{Connection, Element, Network};
pub use weld::weld;
