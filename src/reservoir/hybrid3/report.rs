//! What the 3D hybrid gives: the mesh with its regions, hosts and well
//! links, and the report of what the build did.

use crate::conform::{Report, D2, D3};
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
    /// Cells that took in slivers of the 3D transition: unions of power
    /// cells, often not convex (the VTU's `merged` array).
    pub merged: Vec<usize>,
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

/// A section of layered cavities (`layered`): wells meshed on one 2D
/// section across their layers, taken through each layer.
#[derive(Debug, Clone, Serialize)]
pub struct SectionReport {
    /// Its wells.
    pub wells: Vec<String>,
    /// The layers' normal (up).
    pub normal: [f64; 3],
    /// Its angle off vertical (degrees): the wells' radial meshes run
    /// along it.
    pub dip: f64,
    /// The largest distance of a corner of the cells it spans from its
    /// layer boundary's or wall's plane (the data's rounding).
    pub off_plane: f64,
    /// Per cavity: its columns, its layers (first, last; 1-based), its
    /// cells and their sites inside.
    pub cavities: Vec<LayeredCavity>,
    /// The section's 2D transition, with its exact certificate.
    pub transition: Report<D2>,
}

/// A layered cavity.
#[derive(Debug, Clone, Serialize)]
pub struct LayeredCavity {
    /// Its grid columns.
    pub columns: usize,
    /// Its layers, first and last (1-based).
    pub layers: [usize; 2],
    /// Its cells (transition and radial).
    pub cells: usize,
    /// Those whose site lies inside them.
    pub sites_inside: usize,
    /// The cells' volumes added up against the grid cells' they replace,
    /// less the wellbores: |difference| / the grid cells' (0 up to
    /// rounding and the data's planes: the cells fill the cavity once).
    pub volume_gap: f64,
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
    /// Between a reservoir cell and another: those whose other site's foot
    /// on the face's plane lies inside the face, so that with the reservoir
    /// cell's node mirrored across the face (its distance to the plane,
    /// which the transmissibility takes) the link is orthogonal and
    /// crosses its face.
    pub mirrored: usize,
    /// The share of those links' area that `mirrored` links carry.
    pub mirrored_area: f64,
}

/// What the build did.
#[derive(Debug, Clone, Serialize, Default)]
pub struct Hybrid3Report {
    /// Cells per region: reservoir, transition, well.
    pub cells: [usize; 3],
    /// Per cavity, its wells and its transition's report.
    pub cavities: Vec<CavityReport>,
    /// Layered cavities, per section (then `cavities` is empty).
    pub sections: Vec<SectionReport>,
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
    /// transition cell's volume (after merging).
    pub slivers: usize,
    /// 3D transition slivers merged into the transition cell across their
    /// largest face (`Hybrid3::merged`).
    pub slivers_merged: usize,
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
            && self
                .sections
                .iter()
                .all(|s| s.transition.certificate.conforms())
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
    /// (1-based, -1 outside the grid), and where slivers were merged,
    /// merged (1 for the cells that took them in).
    pub fn cells(&self) -> CellMesh {
        let m = &self.mesh;
        let mut data = vec![
            CellArray::float("site", 3, m.sites.iter().flatten().copied().collect()),
            CellArray::float("weight", 1, m.weights.clone()),
            CellArray::float("volume", 1, m.volumes.clone()),
            CellArray::int("region", 1, self.region.iter().map(|&r| r as i64).collect()),
            CellArray::ijk(self.ijk.iter().copied()),
        ];
        if !self.merged.is_empty() {
            let mut flag = vec![0; m.cells.len()];
            for &c in &self.merged {
                flag[c] = 1;
            }
            data.push(CellArray::int("merged", 1, flag));
        }
        CellMesh {
            points: m.points.clone(),
            cells: Cells::Polyhedra(m.cells.clone()),
            data,
            scalars: "region",
        }
    }
}
