//! What the 3D hybrid gives: the mesh with its regions, hosts and well
//! links, and the report of what the build did.

use crate::conform::{Report, D3};
use crate::mesh::{CellArray, CellMesh, Cells, Mesh3};
use crate::reservoir::deck::WellLinks;
use crate::reservoir::hybrid::Region;
use crate::reservoir::CornerPointGrid;
use serde::Serialize;
use std::collections::BTreeMap;

/// The 3D hybrid mesh: reservoir cells, transition polyhedra, well cells,
/// all as polyhedra with one point numbering.
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
    /// Per well, the cells facing its wellbore, each with the geometric
    /// part of its connection factor (m; `reservoir::deck`).
    pub wellbore: Vec<WellLinks>,
    /// What the build did.
    pub report: Hybrid3Report,
}

/// A cavity's part of the report.
#[derive(Debug, Clone, Serialize)]
pub struct CavityReport {
    /// The wells in it.
    pub wells: Vec<String>,
    /// Its grid cells.
    pub grid_cells: usize,
    /// Its wells' outer radii.
    pub outer_radii: Vec<f64>,
    /// The transition mesh's own report, with its certificate.
    pub transition: Report<D3>,
}

/// Connections between two regions.
#[derive(Debug, Clone, Serialize, Default, PartialEq)]
pub struct Connections {
    /// How many.
    pub connections: usize,
    /// Those whose face is not orthogonal to the link (|cos| above 1e-6).
    pub non_orthogonal: usize,
    /// The angle (degrees) between a face's normal and the line joining
    /// its two sites: median, 99th percentile, largest.
    pub angle: [f64; 3],
    /// Those whose two sites lie on one side of their face (a site outside
    /// its cell): a two-point transmissibility negative or infinite.
    pub one_sided: usize,
}

/// What the build did.
#[derive(Debug, Clone, Serialize, Default)]
pub struct Hybrid3Report {
    /// Cells per region: reservoir, transition, well.
    pub cells: [usize; 3],
    /// Per cavity, its wells and its transition's report.
    pub cavities: Vec<CavityReport>,
    /// Connections between cells.
    pub connections: usize,
    /// Transition faces on a side between two cavities that match no face
    /// of the other (0: the cavities meet face to face).
    pub unpaired_faces: usize,
    /// Faces between reservoir cells left unconnected: across a gap
    /// between layers, or a throw whose cells across do not overlap them.
    pub unmatched_faces: usize,
    /// Connections between reservoir cells across a fault's throw, by the
    /// overlap of their faces.
    pub across_throws: usize,
    /// Connections whose face is not orthogonal to the link.
    pub non_orthogonal: usize,
    /// The same per pair of regions ("reservoir-transition", ...).
    pub by_regions: BTreeMap<String, Connections>,
    /// Transition sites outside their cells, over all cavities.
    pub sites_outside: usize,
    /// Transition cells under a thousandth of their cavity's median
    /// transition cell's volume.
    pub slivers: usize,
    /// The smallest transition cell's share of its cavity's median.
    pub smallest_volume_share: f64,
    /// What was left out of the wells' completions, and why.
    pub notes: Vec<String>,
}

impl Hybrid3Report {
    /// Whether every cavity's transition is certified conforming.
    pub fn conforms(&self) -> bool {
        self.cavities
            .iter()
            .all(|c| c.transition.certificate.conforms())
    }
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
