//! The 3D hybrid mesh (issues 6 and 24): a corner-point grid, wells
//! (vertical or deviated, each along its completed layers) with radial
//! meshes of rings x sectors x layers, a cavity of the live cells within
//! one cell of each well's completed cells (cavities that touch merge),
//! and a conforming orthogonal transition mesh (`conform3`) between the
//! cavity's sides and the wells' outer surfaces. The sides are the grid
//! cells' faces, each kept whole where it is planar and convex, else two
//! triangles along a diagonal that the reservoir cell across carries too
//! (no hanging faces); at a fault's throw, cut into the overlaps with the
//! cells across (`sheet`), which are constraint facets in a cavity, inside
//! it where the fault crosses it. A radial mesh ends open where it meets
//! its column's flat top or bottom (its outline a window in the face
//! there, the transition cut at it), else closed by a plug inside the
//! cavity. A vertical well's layers are horizontal, at its axis' crossings
//! of the grid's layers; a deviated well's are slabs across its axis,
//! exact rectangles on a lattice (`lattice`); a trajectory that bends is
//! meshed as its straight legs joined by mitred knees (`bend`). Built in stages: the corner-point
//! cells (`cpg`, `sheet`), each well's completed interval (`path`), the
//! cavities and the radial meshes in them (`cavity`, `radial`), each
//! cavity's complex and certified transition (`complex`, in parallel), the
//! assembly (`assembly`).

mod assembly;
mod bend;
mod cavity;
mod complex;
mod cpg;
mod lattice;
mod path;
mod radial;
mod refine;
mod sheet;
mod stats;

use crate::backend::Backend;
use crate::conform::{Report, D3};
use crate::error::{Error, Result};
use crate::mesh::{CellArray, CellMesh, Cells, Mesh3};
use crate::progress::Progress;
use crate::reservoir::deck::WellLinks;
use crate::reservoir::hybrid::Region;
use crate::reservoir::CornerPointGrid;
use rayon::prelude::*;
use serde::Serialize;
use std::collections::BTreeMap;

/// A well: its head column (0-based), completed layers, wellbore radius,
/// and its deviation from vertical (degrees) towards the azimuth (degrees
/// clockwise from +y). A deviated well's axis is rounded onto a lattice
/// (its slopes to multiples of 2^-16 or finer) for exact rectangles on
/// its outer surface.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Well3 {
    /// Its name.
    pub name: String,
    /// Its column I (0-based).
    pub i: usize,
    /// Its column J (0-based).
    pub j: usize,
    /// Its completed layers (first, last; 0-based): COMPDAT's K range.
    /// None: every layer.
    pub k: Option<[usize; 2]>,
    /// Wellbore radius.
    pub radius: f64,
    /// Dip from vertical (degrees).
    pub dip: f64,
    /// Azimuth clockwise from +y (degrees).
    pub azimuth: f64,
    /// Its completed cells in the deck's order (0-based; COMPDAT's),
    /// which may change column; empty: column (i, j)'s layers `k`. The
    /// well runs through their centres, as the simulator connects it:
    /// where those are not on one vertical, it is meshed as a trajectory
    /// through them (following leaning columns), unless `straight`.
    pub cells: Vec<[usize; 3]>,
    /// A straight axis from the head (vertical, or at `dip` and
    /// `azimuth`) wherever its completed cells' centres lie.
    pub straight: bool,
    /// A trajectory (x, y, depth as the grid has them), first point to
    /// last, completed over its whole length: instead of the column,
    /// layers, dip and azimuth. Horizontal wells come this way; where it
    /// bends, its straight legs are meshed, joined by mitred knees (`bend`).
    pub path: Option<Vec<[f64; 3]>>,
}

/// Choices of the radial mesh.
#[derive(Debug, Clone)]
pub struct Hybrid3Options {
    /// Rings of the radial mesh.
    pub rings: usize,
    /// Sectors of the radial mesh.
    pub sectors: usize,
    /// Outer radius of the radial mesh, in the well's head cell's shorter
    /// sides: up to 0.4 (also where the mesh shrinks to that to clear its
    /// cavity), the cavity is the well's own column(s); above, the columns
    /// around too, which the mesh may reach into. At most 0.3 of
    /// the way to another well's axis, and shrunk by steps of 0.8 until the
    /// mesh is clear of the cavity's sides. Measured with the flow check
    /// (tests/hybrid3.rs, 16 sectors, 10 m cells, the annuli as faces): 0.4
    /// gives 9.4% off Thiem's pressure drop, 1.0 gives 0.16%, 1.3 gives
    /// 3.9%; as in 2D, the well polygon belongs near the cavity's sides but
    /// not at them.
    pub outer: f64,
    /// Write the mesh even when some transition sites stay outside their cells.
    pub allow_sites_outside: bool,
    /// Steiner points in the top and bottom annuli where their triangles
    /// miss their duals (`Options3::split_facets`).
    pub split_facets: bool,
    /// Cut the transition cells at the grid's flat top and bottom with
    /// mirrored sites (`Options3::clip`) where wells end open there,
    /// instead of keeping the faces there (whose triangles may miss their
    /// duals and leave sites outside); falls back to the faces when
    /// clipping fails.
    pub clip: bool,
    /// Told of each cavity meshed: ("cavities", done, of).
    pub progress: Option<Progress>,
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
            progress: None,
        }
    }
}

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

/// Builds the 3D hybrid mesh around the wells: their cavities meshed in
/// parallel, then assembled.
pub fn build<B: Backend + ?Sized>(
    backend: &B,
    g: &CornerPointGrid,
    wells: &[Well3],
    opts: &Hybrid3Options,
) -> Result<Hybrid3> {
    let cpg = cpg::Cpg::new(g);
    if wells.is_empty() {
        return Err(Error::Usage("the 3D hybrid needs a well".into()));
    }
    // what the completions leave out (inactive, pinched-out cells), said
    let mut notes = vec![];
    for w in wells.iter().filter(|w| w.path.is_none()) {
        notes.extend(path::completed(&cpg, w)?.1);
    }
    // one path per well, or per straight leg of a trajectory that bends
    let mut owner = vec![];
    let mut legs = vec![];
    let mut paths = vec![];
    for (n, w) in wells.iter().enumerate() {
        for (leg, path) in bend::paths(&cpg, w, n, opts.outer)? {
            owner.push(n);
            legs.push(leg);
            paths.push(path);
        }
    }
    let wells = &legs;
    let reach: Vec<usize> = wells
        .par_iter()
        .zip(&paths)
        .map(|(w, p)| cavity::reach(&cpg, w, p, opts))
        .collect();
    let groups = cavity::cavities(&cpg, &paths, &reach);
    let done = std::sync::atomic::AtomicUsize::new(0);
    let of = groups.len();
    let built = groups
        .into_par_iter()
        .map(|cells| {
            let ws: Vec<&Well3> = cells.wells.iter().map(|&w| &wells[w]).collect();
            let ps: Vec<&path::Path> = cells.wells.iter().map(|&w| &paths[w]).collect();
            let open: Vec<(usize, f64)> = ps.iter().flat_map(|p| p.open_faces()).collect();
            if let Some((c, n)) = cells
                .cells
                .iter()
                .find_map(|&c| cpg.inverted(c).map(|n| (c, n)))
            {
                return Err(Error::Usage(format!(
                    "{}: cell {} of the cavity is inverted: at pillar {} its top lies below its \
                     bottom",
                    well_names(&ws),
                    cpg::one_based(c),
                    cpg.pillar_name(c, n)
                )));
            }
            let sides = cavity::sides(&cpg, &cells.cells, &open)?;
            let (mut radials, full) =
                cavity::radials(&cpg, &ws, &ps, &cells.cells, &sides, opts, 1.0)?;
            let (mut transition, mut outcome) = complex::mesh(backend, &sides, &radials, opts)?;
            // Radial meshes as wide as asked come within half a cell of the
            // sides, whose facets' balls may then take them in: the sites
            // of those facets cannot all be inside (a horizontal well in a
            // box of 10 m cells: 48 of 582 outside at 10 m, none at 9 or 8).
            // Once smaller, kept if fewer are outside.
            // (an attempt that fails leaves the first)
            if full && outside(&outcome) > 0 {
                let again =
                    cavity::radials(&cpg, &ws, &ps, &cells.cells, &sides, opts, RETRY_SCALE)
                        .and_then(|(smaller, _)| {
                            complex::mesh(backend, &sides, &smaller, opts).map(|m| (smaller, m))
                        });
                if let Ok((smaller, (t, o))) = again {
                    if outside(&o) < outside(&outcome) {
                        (radials, transition, outcome) = (smaller, t, o);
                    }
                }
            }
            let outcome = outcome.map_err(|e| Error::Within {
                part: format!("the cavity of {}", well_names(&ws)),
                error: Box::new(e),
            })?;
            let n = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
            if let Some(p) = opts.progress {
                p("cavities", n, of);
            }
            Ok(assembly::Built {
                cells,
                transition,
                radials,
                outcome,
            })
        })
        .collect::<Result<Vec<_>>>()?;
    let mut h = assembly::assemble(&cpg, wells, &owner, built)?;
    h.report.notes = notes;
    Ok(h)
}

/// The radii a cavity's wells try again at when some transition sites
/// are outside their cells (`build`).
const RETRY_SCALE: f64 = 0.8;

/// A transition's sites outside their cells (an error: all of them).
fn outside(o: &Result<crate::conform::Outcome<D3>>) -> usize {
    o.as_ref()
        .map_or(usize::MAX, |o| o.report.sites.sites_outside)
}

/// "well W" or "wells A, B": a cavity's wells, each once (a bent well's
/// legs are wells of their own there).
fn well_names(ws: &[&Well3]) -> String {
    let mut names: Vec<&str> = vec![];
    for w in ws {
        if !names.contains(&w.name.as_str()) {
            names.push(&w.name);
        }
    }
    let wells = if names.len() == 1 { "well" } else { "wells" };
    format!("{wells} {}", names.join(", "))
}
