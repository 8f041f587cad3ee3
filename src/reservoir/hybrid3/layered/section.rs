//! The cross-section of a layer cake: the grid's pillars where they cross
//! a plane across its layers, as a one-layer grid in the layers' frame, and
//! the 2D hybrid mesh of its wells on it (`reservoir::hybrid`).

use super::frame::Frame;
use crate::backend::Backend;
use crate::error::Result;
use crate::reservoir::hybrid::{self, Hybrid, HybridOptions, WellAt, WellInput};
use crate::reservoir::CornerPointGrid;

/// The one-layer grid of the pillars' crossings of the plane at height
/// `at` (frame coordinates; pillars vertical in it), its columns active
/// where `live`.
pub(super) fn grid(
    g: &CornerPointGrid,
    f: &Frame,
    at: f64,
    live: impl Fn([usize; 2]) -> bool,
) -> CornerPointGrid {
    let (nx, ny) = (g.nx, g.ny);
    let mut s = CornerPointGrid::layered([nx, ny], [1.0, 1.0], &[0.0, 1.0]);
    for (p, c) in g.coord.iter().enumerate() {
        let [u, v] = f.crossing(*c, at);
        s.coord[p] = [u, v, 0.0, u, v, 1.0];
    }
    for j in 0..ny {
        for i in 0..nx {
            s.actnum[i + nx * j] = live([i, j]);
        }
    }
    s
}

/// The 2D hybrid mesh of wells at map points `at` (frame coordinates) on
/// the section grid, with the 3D hybrid's rings, sectors and outer radius.
pub(super) fn mesh<B: Backend + ?Sized>(
    backend: &B,
    s: &CornerPointGrid,
    wells: &[(String, [f64; 2], f64)],
    rings: usize,
    sectors: usize,
    outer: f64,
) -> Result<Hybrid> {
    let input: Vec<WellInput> = wells
        .iter()
        .map(|(name, at, radius)| WellInput {
            name: name.clone(),
            at: WellAt::Xy(*at),
            radius: *radius,
        })
        .collect();
    let opts = HybridOptions {
        layer: 0,
        rings,
        sectors,
        outer,
        allow_sites_outside: true,
        column_sides: true,
        ..Default::default()
    };
    hybrid::build(backend, s, &input, &opts)
}
