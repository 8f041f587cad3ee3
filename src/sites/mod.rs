//! The sites stage (docs/method.md section 4): two sites per constraint on
//! its dual, extra sites for free ends and isolated vertices; in 2D defined
//! exactly by doubles (`d2`), in 3D exact rationals with clipping by
//! mirrored sites (`d3`).

mod cell3;
mod d2;
mod d3;
mod track3;

#[cfg(test)]
pub(crate) use d2::tests;
pub use d2::{Role, Sites};
pub use d3::{clip_of, place as place3, Clip, Sites3};
