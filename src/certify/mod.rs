//! The certificate stage (docs/method.md section 7): what a finished mesh
//! proves about itself, decided exactly. The 3D certificate is computed on
//! the exact site diagram (`diagram::Diagram3::certify`).

mod d2;

pub use crate::diagram::Certificate3;
pub use d2::{certify, Certificate};
