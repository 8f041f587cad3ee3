//! Hybrid reservoir meshes in map view (paper section 5, docs/method.md section 6):
//! a layer of a corner-point grid, radial meshes around vertical wells, and
//! between them, in cavities cut out of the grid, transition meshes from the
//! 2D core. The result is one conforming polygon mesh: active reservoir cells
//! outside the cavities, transition cells, radial cells. Built in stages:
//! wells (`wells`), cavities (`cavities`), the transition mesh
//! (`transition`), assembly (`assembly`), on the layer's map view (`map`).

mod assembly;
mod cavities;
mod map;
mod transition;
mod wells;

pub(crate) use map::map_view;
pub(crate) use wells::{first_ring_radii, ring_radii, site_radii};
pub use wells::{MAX_RINGS, MAX_SECTORS};

use crate::backend::Backend;
use crate::complex::Complex;
use crate::conform::{Report, D2};
use crate::error::{Error, Result};
use crate::mesh::{CellArray, CellMesh, Mesh, Network};
use crate::reservoir::CornerPointGrid;
use map::MapView;
use serde::Serialize;

/// Where a well is: a grid column (0-based) or a map position.
#[derive(Debug, Clone, PartialEq)]
pub enum WellAt {
    /// Column (i, j).
    Column(usize, usize),
    /// Map position.
    Xy([f64; 2]),
}

/// A vertical well.
#[derive(Debug, Clone, PartialEq)]
pub struct WellInput {
    /// Its name.
    pub name: String,
    /// Where it is.
    pub at: WellAt,
    /// Wellbore radius.
    pub radius: f64,
}

impl WellInput {
    /// A well in column (i, j), 0-based.
    pub fn column(name: &str, i: usize, j: usize, radius: f64) -> WellInput {
        WellInput {
            name: name.into(),
            at: WellAt::Column(i, j),
            radius,
        }
    }
}

/// Choices for the hybrid mesh.
#[derive(Debug, Clone)]
pub struct HybridOptions {
    /// The layer (0-based) whose map view is meshed.
    pub layer: usize,
    /// Rings and sectors of each radial mesh.
    pub rings: usize,
    /// Sectors of each radial mesh.
    pub sectors: usize,
    /// Outer radius of the radial meshes, as a multiple of the shortest side
    /// of the well's cell.
    pub outer: f64,
    /// Layers of cells added around the cells the radial mesh reaches.
    pub margin: usize,
    /// Called as stages advance: (stage, done, of).
    pub progress: Option<fn(&str, usize, usize)>,
    /// Write the mesh even when some transition sites cannot be inside their
    /// cells (after the cavities have grown as far as they can).
    pub allow_sites_outside: bool,
    /// Faults given as map polylines: their parts inside cavities become
    /// constraint chains, ending a quarter cell short of the cavity sides.
    pub fault_lines: Vec<Vec<[f64; 2]>>,
    /// A section of the 3D hybrid's layered cavities: column sides inside
    /// cavities become constraints too, but for those within 1.25 outer
    /// radii of a well (each cell then lies in one column, under one cell
    /// above), and the cavities' sides are not anchored at the reservoir
    /// cells across (those are not kept: the cells beside a side have
    /// their sites on its perpendicular bisector where weights are zero).
    pub layered_section: bool,
    /// Every cavity side split into pieces no longer than its distance to
    /// the nearest well polygon, nor than two outer radii of the smallest
    /// radial mesh, not only those on the mesh's outer boundary (a layered
    /// section keeps no reservoir cells to anchor them at): a well near a
    /// side then does not make system 3 infeasible.
    pub split_sides: bool,
    /// The cavities' columns (a flag per column, `j * nx + i`) where the
    /// caller has chosen them; still grown where the transition needs
    /// room.
    pub cavity: Option<Vec<bool>>,
    /// Each radial mesh kept inside its well's column, clear of the
    /// column's sides by a quarter of its outer radius (so that every
    /// column side inside a cavity can be a constraint), however far
    /// `outer` would reach.
    pub in_column: bool,
    /// Column sides inside cavities are split into pieces no longer than
    /// this share of their distance to the nearest well polygon: the
    /// transition's cells near the wells are that much finer.
    pub piece_share: f64,
    /// Each convex corner of the cavities cut off by a short piece of both
    /// sides and owned by one cell (`Options::corner_sites`): a layered
    /// section's prisms lean off its walls, and the cell beside a corner
    /// then reaches the two walls without crossing the pillar.
    pub corner_cells: bool,
    /// A layered section's pillars moved in at reflex corners of its
    /// cavities (`layered::section::inset`), with the points where they
    /// were: the column sides inside that start at such a pillar start
    /// there instead, on the outline's side through it, so that they keep
    /// the grid's own lines.
    pub inner_pillars: Vec<(usize, [f64; 2])>,
    /// The innermost ring's outer radius as a share of the outer radius,
    /// the rings beyond it geometric (`wells::first_ring_radii`); None:
    /// geometric from the wellbore.
    pub first_ring: Option<f64>,
}

impl Default for HybridOptions {
    fn default() -> Self {
        // The flow check (tests/flow.rs) against Thiem's solution: 0.02% off
        // with these (5 x 5-cell cavity, well polygon 0.6 cells from its
        // sides, docs/method.md section 6); 0.5-1% with an outer radius of 0.9
        // cells; 3% with 4 rings. Crowded wells get smaller radial meshes.
        HybridOptions {
            layer: 0,
            rings: 12,
            sectors: 32,
            outer: 1.9,
            margin: 0,
            progress: None,
            allow_sites_outside: false,
            fault_lines: vec![],
            layered_section: false,
            split_sides: false,
            cavity: None,
            in_column: false,
            piece_share: 1.0,
            corner_cells: false,
            inner_pillars: vec![],
            first_ring: None,
        }
    }
}

/// Which part of the hybrid mesh a cell belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Region {
    /// A corner-point cell outside the cavities.
    Reservoir = 0,
    /// A cell of the transition mesh.
    Transition = 1,
    /// A cell of a radial well mesh.
    Well = 2,
}

/// The hybrid mesh and how it was made.
#[derive(Debug, Clone)]
pub struct Hybrid {
    /// Cells, sites, weights; faces between cells.
    pub mesh: Mesh,
    /// Per cell, its region.
    pub region: Vec<Region>,
    /// The reservoir cell (i, j, k), 0-based, for reservoir cells.
    pub ijk: Vec<Option<[usize; 3]>>,
    /// The transition meshes' constraints: cavity boundaries, well polygons.
    pub constraints: Complex,
    /// Per cell: thickness and mid-depth (the reservoir cell's own; the
    /// layer's mean for transition and well cells).
    pub thickness: Vec<f64>,
    /// Per cell, its mid-depth.
    pub depth: Vec<f64>,
    /// Per cell, the grid cell (i, j, k; 0-based) whose rock it takes: its
    /// own for reservoir cells, the one holding its site for the others.
    pub host: Vec<[usize; 3]>,
    /// The radial mesh of each well.
    pub wells: Vec<WellMesh>,
    /// What the build did.
    pub report: HybridReport,
}

/// A well's radial mesh, as a simulator connects to it.
#[derive(Debug, Clone, PartialEq)]
pub struct WellMesh {
    /// The well's name.
    pub name: String,
    /// Its axis in map view.
    pub centre: [f64; 2],
    /// The wellbore's radius.
    pub radius: f64,
    /// The radius of the innermost ring's sites.
    pub site_radius: f64,
    /// The innermost ring's cells, one per sector (of equal angles).
    pub inner: Vec<u32>,
}

impl WellMesh {
    /// Per inner cell, the geometric part of its connection to the
    /// wellbore: radial flow from the wellbore to the site's radius within
    /// the sector is exact, theta h / ln(rho / r_w), times k and Darcy's
    /// constant for a connection factor (thickness h of each cell).
    pub fn links(&self, thickness: impl Fn(u32) -> f64) -> Vec<(u32, f64)> {
        let theta = std::f64::consts::TAU / self.inner.len() as f64;
        let log = (self.site_radius / self.radius).ln();
        self.inner
            .iter()
            .map(|&c| (c, theta * thickness(c) / log))
            .collect()
    }
}

impl Hybrid {
    /// Each well's links to its innermost ring, by cell (for
    /// `reservoir::deck`).
    pub fn well_links(&self) -> Vec<crate::reservoir::deck::WellLinks> {
        self.wells
            .iter()
            .map(|w| crate::reservoir::deck::WellLinks {
                name: w.name.clone(),
                radius: w.radius,
                links: w
                    .links(|c| self.thickness[c as usize])
                    .into_iter()
                    .map(|(c, g)| (c as usize, g))
                    .collect(),
                log: (w.site_radius / w.radius).ln(),
            })
            .collect()
    }

    /// The cells on the mesh's outer boundary, wellbores left out: what an
    /// open boundary holds (`reservoir::deck::DeckChoices::aquifer`).
    pub fn outer_cells(&self) -> Vec<usize> {
        let inner: crate::FastSet<u32> = self.wells.iter().flat_map(|w| w.inner.clone()).collect();
        let mut cells: Vec<usize> = crate::reservoir::flow::boundary_faces(&self.mesh)
            .into_iter()
            .filter(|f| !inner.contains(&f.cell))
            .map(|f| f.cell as usize)
            .collect();
        cells.dedup();
        cells
    }

    /// The two-point flux network (`reservoir::flow::network`), each cell
    /// with its thickness and mid-depth.
    pub fn network(&self) -> Network {
        crate::reservoir::flow::network(&self.mesh, &self.thickness, &self.depth)
    }

    /// Polygons with cell data site, weight, region (0 reservoir, 1
    /// transition, 2 well) and ijk (1-based; -1 elsewhere).
    pub fn cells(&self) -> CellMesh {
        let region = CellArray::int("region", 1, self.region.iter().map(|&r| r as i64).collect());
        let ijk = CellArray::ijk(self.ijk.iter().copied());
        self.mesh.cells_with(vec![region, ijk])
    }
}

/// Built-in example: a 15 x 15-cell Cartesian layer of 10 m cells, one well
/// of radius 0.1 m in column (7, 8) (1-based), and a fault along the east
/// sides of column I = 8 for J = 6..8 that ends inside the well's cavity.
pub fn demo() -> (CornerPointGrid, Vec<WellInput>, HybridOptions) {
    let mut grid = CornerPointGrid::cartesian([15, 15, 1], [10.0, 10.0, 5.0]);
    grid.faults.push(crate::reservoir::Fault {
        name: "F1".into(),
        faces: vec![crate::reservoir::FaultFace {
            i: [7, 7],
            j: [5, 7],
            k: [0, 0],
            axis: 'X',
            sign: 1,
        }],
    });
    let opts = HybridOptions {
        margin: 1,
        ..Default::default()
    };
    (grid, vec![WellInput::column("W1", 6, 7, 0.1)], opts)
}

/// What the report says about the hybrid mesh.
#[derive(Debug, Clone, Serialize)]
pub struct HybridReport {
    /// The layer meshed (0-based).
    pub layer: usize,
    /// The wells' names.
    pub wells: Vec<String>,
    /// Cavities (connected).
    pub cavities: usize,
    /// Columns in cavities.
    pub cavity_cells: usize,
    /// Cells per region: reservoir, transition, well.
    pub cells: [usize; 3],
    /// Largest |cos| between a face and its two sites' segment, per pair
    /// of regions: reservoir-reservoir, reservoir-transition,
    /// transition-transition, transition-well, well-well.
    pub orthogonality_defect: Vec<(String, f64)>,
    /// Interface faces (between regions) whose defect exceeds 1e-6: the
    /// reservoir cell's ijk (1-based) when one side is a reservoir cell, the
    /// pair of regions, the defect. The first 100.
    pub non_orthogonal_interfaces: Vec<(Option<[usize; 3]>, String, f64)>,
    /// Two-point transmissibilities (unit permeability): all connections,
    /// and those touching the transition or well regions (where none may be
    /// negative or non-orthogonal).
    pub transmissibility: crate::reservoir::flow::TransmissibilityStats,
    /// The same over the connections near the wells.
    pub transmissibility_near_wells: crate::reservoir::flow::TransmissibilityStats,
    /// Faces that are not shared by two cells nor on the outer boundary: 0
    /// for a conforming mesh (no hanging nodes).
    pub unmatched_faces: usize,
    /// Fault segments inside cavities (chains with free ends there).
    pub fault_segments: usize,
    /// Cavities grown because system 3 was infeasible.
    pub notes: Vec<String>,
    /// The transition meshes' own report (certificate, weights, sites).
    pub transition: Report<D2>,
}

/// One layer of the grid in map view: what every stage works on.
pub(super) struct Layer<'a> {
    grid: &'a CornerPointGrid,
    /// The layer (0-based).
    k: usize,
    view: MapView,
    nx: usize,
    ny: usize,
}

impl Layer<'_> {
    /// The corners of column (i, j) in the map, counter-clockwise.
    fn quad_points(&self, i: usize, j: usize) -> [[f64; 2]; 4] {
        self.view.quad(i, j).map(|p| self.view.pillar[p as usize])
    }
}

/// Checks what the stages take for granted: the layer, the radial meshes'
/// sizes, some well, and active columns of positive area.
fn check<'a>(
    grid: &'a CornerPointGrid,
    wells: &[WellInput],
    opts: &HybridOptions,
) -> Result<Layer<'a>> {
    let k = opts.layer;
    if k >= grid.nz {
        return Err(Error::Usage(format!(
            "layer {} outside 1..{}",
            k + 1,
            grid.nz
        )));
    }
    if !(1..=MAX_RINGS).contains(&opts.rings) || !(3..=MAX_SECTORS).contains(&opts.sectors) {
        return Err(Error::Usage(format!(
            "radial meshes need 1 to {MAX_RINGS} rings and 3 to {MAX_SECTORS} sectors"
        )));
    }
    if wells.is_empty() {
        return Err(Error::Usage("a hybrid mesh needs at least one well".into()));
    }
    let (nx, ny) = (grid.nx, grid.ny);
    if opts.cavity.as_ref().is_some_and(|c| c.len() != nx * ny) {
        return Err(Error::Usage(format!(
            "the cavities' columns need a flag for each of the grid's {nx} x {ny} columns"
        )));
    }
    let layer = Layer {
        grid,
        k,
        view: MapView::new(grid, k),
        nx,
        ny,
    };
    let quad_points = |i: usize, j: usize| layer.quad_points(i, j);
    let flat: Vec<String> = (0..ny)
        .flat_map(|j| (0..nx).map(move |i| (i, j)))
        .filter(|&(i, j)| {
            let q = quad_points(i, j);
            // NaN area (unreadable corners) counts as none
            grid.active(i, j, k)
                && crate::geom::shoelace(4, |c| q[c]).abs().partial_cmp(&0.0)
                    != Some(std::cmp::Ordering::Greater)
        })
        .map(|(i, j)| format!("({}, {}, {})", i + 1, j + 1, k + 1))
        .collect();
    if !flat.is_empty() {
        return Err(Error::Degenerate(format!(
            "active cells with no area in map view (collapsed pillars): {}{}",
            flat[..flat.len().min(20)].join(", "),
            if flat.len() > 20 {
                format!(" and {} more", flat.len() - 20)
            } else {
                String::new()
            }
        )));
    }
    Ok(layer)
}

/// The cavities' columns `build` starts from (a flag per column, `j * nx +
/// i`): those its wells' radial meshes reach, with `opts.margin` rings
/// more. `build` grows them where the transition needs room.
pub fn cavity_columns(
    grid: &CornerPointGrid,
    wells: &[WellInput],
    opts: &HybridOptions,
) -> Result<Vec<bool>> {
    let layer = check(grid, wells, opts)?;
    let placed = wells::place(&layer, wells, opts, &|_, _, _| {})?;
    Ok(layer.cavities(&placed, opts.margin))
}

/// Builds the hybrid mesh of one layer with the given wells.
pub fn build<B: Backend + ?Sized>(
    backend: &B,
    grid: &CornerPointGrid,
    wells: &[WellInput],
    opts: &HybridOptions,
) -> Result<Hybrid> {
    let layer = check(grid, wells, opts)?;
    let tell = |stage: &str, done: usize, of: usize| {
        if let Some(f) = opts.progress {
            f(stage, done, of);
        }
    };
    let placed = wells::place(&layer, wells, opts, &tell)?;
    let mut cavity = match &opts.cavity {
        Some(c) => c.clone(),
        None => layer.cavities(&placed, opts.margin),
    };
    let t = transition::solve(backend, &layer, &placed, &mut cavity, opts, &tell)?;
    tell("assembling", 1, 1);
    assembly::assemble(&layer, &placed, &cavity, t, opts)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::backend::compiled;

    /// Given cavities' columns are the ones meshed (here the demo's with
    /// a column more); a flag list of the wrong length is a usage error.
    #[test]
    fn given_cavity_columns_are_meshed() {
        let (grid, wells, mut opts) = demo();
        let mut flags = cavity_columns(&grid, &wells, &opts).unwrap();
        let extra = (0..flags.len())
            .find(|&c| !flags[c] && flags[c + 1])
            .unwrap();
        flags[extra] = true;
        opts.cavity = Some(flags.clone());
        for b in compiled() {
            let h = build(&*b, &grid, &wells, &opts).unwrap();
            assert_eq!(h.report.cavity_cells, flags.iter().filter(|&&f| f).count());
            let reservoir: Vec<usize> = h.ijk.iter().flatten().map(|c| c[1] * 15 + c[0]).collect();
            assert!(!reservoir.contains(&extra) && reservoir.len() + h.report.cavity_cells == 225);
        }
        opts.cavity = Some(vec![true; 3]);
        let e = build(&*compiled()[0], &grid, &wells, &opts).unwrap_err();
        assert!(e.to_string().contains("15 x 15 columns"), "{e}");
    }

    /// Radial meshes kept in their columns: the demo's well (column 7, 8,
    /// 1-based; 10 m columns) has its rings within 0.75 of its 5 m to the
    /// column's sides, however far `outer` reaches, and the cavity is the
    /// one `outer` gives.
    #[test]
    fn radial_meshes_kept_in_their_columns() {
        let (grid, wells, mut opts) = demo();
        let flags = cavity_columns(&grid, &wells, &opts).unwrap();
        opts.cavity = Some(flags.clone());
        opts.in_column = true;
        opts.layered_section = true;
        let h = build(&*compiled()[0], &grid, &wells, &opts).unwrap();
        assert_eq!(h.report.cavity_cells, flags.iter().filter(|&&f| f).count());
        let well = (0..h.region.len()).filter(|&c| h.region[c] == Region::Well);
        for c in well {
            assert_eq!(&h.host[c][..2], &[6, 7], "cell {c}");
        }
        let reach = h
            .mesh
            .sites
            .iter()
            .zip(&h.region)
            .filter(|p| *p.1 == Region::Well);
        let [x, y] = h.wells[0].centre;
        let far = reach
            .map(|(p, _)| (p[0] - x).hypot(p[1] - y))
            .fold(0.0, f64::max);
        assert!(far > 1.0 && far < 0.75 * 5.0, "{far}");
    }
}
