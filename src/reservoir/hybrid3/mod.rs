//! The 3D hybrid mesh (issue 6, part 6): a Cartesian block grid, a well
//! (vertical or deviated, straight through the grid's whole thickness)
//! with a radial mesh of rings x sectors x layers (a vertical well's are
//! the grid's; a deviated well's are slabs across its axis, the first and
//! last cut by the grid's top and bottom, so that its own links are
//! orthogonal), a cavity of
//! the 3 x 3 columns around the well's head, and a conforming orthogonal
//! transition mesh (`conform3`) between the cavity's walls and the well
//! mesh's outer surface. The walls are rectangles kept whole, so the
//! reservoir cells beyond stay hexahedra; the well's outer faces are
//! rectangles too (a deviated well's exact on a lattice, `Lattice`),
//! except in a deviated well's first and last layers, where they are
//! split in two triangles and their links to the transition need not be
//! orthogonal. Built in stages: the radial mesh's geometry (`radial`, on
//! a `lattice` when deviated), the cavity's complex and its certified
//! transition mesh (`cavity`), the assembly (`assembly`).

mod assembly;
mod cavity;
mod lattice;
mod radial;

use crate::backend::Backend;
use crate::conform::{Report, D3};
use crate::error::{Error, Result};
use crate::mesh::{CellArray, CellMesh, Cells, Mesh3};
use crate::reservoir::hybrid::Region;
use crate::reservoir::CornerPointGrid;
use serde::Serialize;

/// A well: its column (0-based), wellbore radius, and its deviation from
/// vertical (degrees) towards the azimuth (degrees clockwise from +y). A
/// deviated well's axis is rounded onto a lattice (its slopes to multiples
/// of 2^-16 or finer) for exact rectangles on its outer surface.
#[derive(Debug, Clone, PartialEq)]
pub struct Well3 {
    /// Its name.
    pub name: String,
    /// Its column I (0-based).
    pub i: usize,
    /// Its column J (0-based).
    pub j: usize,
    /// Wellbore radius.
    pub radius: f64,
    /// Dip from vertical (degrees).
    pub dip: f64,
    /// Azimuth clockwise from +y (degrees).
    pub azimuth: f64,
}

/// Choices of the radial mesh.
#[derive(Debug, Clone)]
pub struct Hybrid3Options {
    /// Rings of the radial mesh.
    pub rings: usize,
    /// Sectors of the radial mesh.
    pub sectors: usize,
    /// Outer radius of the radial mesh, in the well cell's shorter sides
    /// (as in 2D; it may reach into the cavity's other columns). Measured
    /// with the flow check (tests/hybrid3.rs, 16 sectors, 10 m cells, the
    /// annuli as faces): 0.4 gives 9.4% off Thiem's pressure drop, 1.0
    /// gives 0.16%, 1.3 gives 3.9%; as in 2D, the well polygon belongs near the cavity's sides but
    /// not at them.
    pub outer: f64,
    /// Write the mesh even when some transition sites stay outside their cells.
    pub allow_sites_outside: bool,
    /// Steiner points in the top and bottom annuli where their triangles
    /// miss their duals (`Options3::split_facets`).
    pub split_facets: bool,
    /// Cut the transition cells at the grid's top and bottom with mirrored
    /// sites (`Options3::clip`) instead of making the annuli there faces
    /// (whose triangles may miss their duals and leave sites outside);
    /// falls back to the annuli as faces when clipping fails.
    pub clip: bool,
}

impl Default for Hybrid3Options {
    fn default() -> Self {
        Hybrid3Options {
            rings: 6,
            sectors: 16,
            outer: 1.0,
            allow_sites_outside: false,
            split_facets: false,
            clip: true,
        }
    }
}

/// The 3D hybrid mesh: reservoir hexahedra, transition polyhedra, well
/// cells, all as polyhedra with one point numbering.
#[derive(Debug, Clone)]
pub struct Hybrid3 {
    /// Cells, sites, weights; faces between cells.
    pub mesh: Mesh3,
    /// Per cell, its region.
    pub region: Vec<Region>,
    /// Per cell, its grid cell (reservoir cells).
    pub ijk: Vec<Option<[usize; 3]>>,
    /// Per cell, the grid cell whose rock it takes: its own, or for
    /// transition and well cells the cavity's cell that holds the site.
    pub host: Vec<[usize; 3]>,
    /// The cells facing the wellbore, each with the geometric part of its
    /// connection factor (m; `reservoir::deck`).
    pub wellbore: Vec<(usize, f64)>,
    /// What the build did.
    pub report: Hybrid3Report,
}

/// What the build did.
#[derive(Debug, Clone, Serialize, Default)]
pub struct Hybrid3Report {
    /// Cells per region: reservoir, transition, well.
    pub cells: [usize; 3],
    /// The transition mesh's own report.
    pub transition: Report<D3>,
    /// Connections between cells, and those whose two sites are not on the
    /// normal of their face (|cos| above 1e-6).
    pub connections: usize,
    /// Connections whose face is not orthogonal to the link.
    pub non_orthogonal: usize,
}

/// Checks that the grid is a Cartesian block grid (vertical pillars, flat
/// horizons, axis-aligned cells) and returns its node coordinates per axis
/// (x, y, and z up = -depth).
fn axes(g: &CornerPointGrid) -> Result<[Vec<f64>; 3]> {
    let x: Vec<f64> = (0..=g.nx)
        .map(|i| g.corner(i.min(g.nx - 1), 0, 0, (i == g.nx) as usize)[0])
        .collect();
    let y: Vec<f64> = (0..=g.ny)
        .map(|j| g.corner(0, j.min(g.ny - 1), 0, 2 * (j == g.ny) as usize)[1])
        .collect();
    let z: Vec<f64> = (0..=g.nz)
        .map(|k| -g.corner(0, 0, k.min(g.nz - 1), 4 * (k == g.nz) as usize)[2])
        .collect();
    for k in 0..g.nz {
        for j in 0..g.ny {
            for i in 0..g.nx {
                for c in 0..8 {
                    let (di, dj, b) = (c & 1, (c >> 1) & 1, c >> 2);
                    let p = g.corner(i, j, k, c);
                    if p != [x[i + di], y[j + dj], -z[k + b]] {
                        return Err(Error::Usage(format!(
                            "the 3D hybrid mesh needs a Cartesian block grid (vertical pillars, flat \
                             horizons): cell ({}, {}, {}) is not a box",
                            i + 1,
                            j + 1,
                            k + 1
                        )));
                    }
                }
            }
        }
    }
    let increasing = |v: &[f64]| v.windows(2).all(|w| w[0] < w[1]);
    let decreasing = |v: &[f64]| v.windows(2).all(|w| w[0] > w[1]);
    if !(increasing(&x) && increasing(&y) && decreasing(&z)) {
        return Err(Error::Usage(
            "the grid's cells have no volume or are not ordered".into(),
        ));
    }
    Ok([x, y, z])
}

impl Hybrid3 {
    /// The reservoir cells in the grid's outermost columns: what an open
    /// boundary holds (`reservoir::deck::DeckChoices::aquifer`).
    pub fn outer_cells(&self, g: &CornerPointGrid) -> Vec<usize> {
        let (nx, ny) = (g.nx, g.ny);
        (0..self.ijk.len())
            .filter(|&k| {
                self.ijk[k].is_some_and(|[i, j, _]| i == 0 || j == 0 || i + 1 == nx || j + 1 == ny)
            })
            .collect()
    }

    /// Polyhedra with cell data site, weight, volume, region, ijk
    /// (1-based, -1 outside the grid).
    pub fn cells(&self) -> CellMesh {
        let m = &self.mesh;
        CellMesh {
            points: m.points.clone(),
            cells: Cells::Polyhedra(m.cells.clone()),
            data: vec![
                CellArray::float("site", 3, m.sites.iter().flatten().copied().collect()),
                CellArray::float("weight", 1, m.weights.clone()),
                CellArray::float("volume", 1, m.volumes.clone()),
                CellArray::int("region", 1, self.region.iter().map(|&r| r as i64).collect()),
                CellArray::ijk(self.ijk.iter().copied()),
            ],
            scalars: "region",
        }
    }
}

/// Builds the 3D hybrid mesh around one well.
pub fn build<B: Backend + ?Sized>(
    backend: &B,
    g: &CornerPointGrid,
    well: &Well3,
    opts: &Hybrid3Options,
) -> Result<Hybrid3> {
    let w = radial::Radial::new(g, well, opts)?;
    let cavity = cavity::Cavity::new(g, &w);
    let t = cavity.mesh(backend, opts)?;
    Ok(assembly::assemble(g, &w, &cavity, t))
}
