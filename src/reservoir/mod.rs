//! Reservoir meshes (paper section 5, docs/reservoir.md): the corner-point
//! grid model (`grid`), hybrid meshes of one layer in map view (`hybrid`:
//! wells, cavities, faults, the certified transition mesh), mapped onto
//! every layer (`layers`, 2.5D) or built in true 3D (`hybrid3`), the
//! two-point flux check against Thiem's solution (`flow`), and the grid's
//! own transmissibilities as OPM Flow computes them (`trans`).

pub mod deck;
pub mod flow;
mod grid;
pub mod hybrid;
pub mod hybrid3;
pub mod layers;
pub mod synthetic;
pub mod trans;

pub use grid::{CornerPointGrid, Fault, FaultFace};
pub use hybrid::{
    build, demo, Hybrid, HybridOptions, HybridReport, Region, WellAt, WellInput, WellMesh,
};
pub use hybrid3::{Hybrid3, Hybrid3Options, Hybrid3Report, Section, Well3};
pub use layers::{extrude, Layered};
