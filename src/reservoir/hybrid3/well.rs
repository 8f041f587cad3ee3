//! What the 3D hybrid is asked for: its wells and the choices of their
//! radial meshes.

use crate::progress::Progress;

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
    /// The innermost ring's outer radius as a share of the outer radius,
    /// the rings beyond it geometric (`Section::first_ring` for layered
    /// sections); None: geometric from the wellbore.
    pub first_ring: Option<f64>,
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
    /// Where the cells around the wells lie between parallel planes (a
    /// dipping layer cake), mesh a 2D section across the layers with these
    /// radial meshes and take it through each layer (`layered`): every
    /// link in the cavity orthogonal, every cell in one layer. Else, and
    /// when None, the transition is meshed in 3D with the radial meshes
    /// above. `Section::default()` by default (as the CLI's `hybrid --3d`
    /// but with `--transition-3d`).
    pub layered: Option<Section>,
    /// Told of each cavity meshed: ("cavities", done, of).
    pub progress: Option<Progress>,
}

/// The radial meshes of layered cavities (the 2D hybrid's: measured
/// against Thiem in a block of three layers, tests/hybrid3.rs, 0.07% with
/// these; 1.3-1.9% with outer radii of 0.35-0.6, radial meshes inside
/// their column).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Section {
    /// Rings.
    pub rings: usize,
    /// Sectors.
    pub sectors: usize,
    /// Outer radius, in the well's cell's shorter sides.
    pub outer: f64,
    /// On planes, each radial mesh kept inside its well's column, in a
    /// cavity as wide as `outer` would make it (every link to the radial
    /// cells across the cavity's ends orthogonal); else the rings reach
    /// `outer` over several columns (Thiem's check closer).
    pub in_column: bool,
    /// The innermost ring's outer radius as a share of the outer radius
    /// (`HybridOptions::first_ring`); None: rings geometric from the
    /// wellbore.
    pub first_ring: Option<f64>,
}

impl Default for Section {
    fn default() -> Self {
        Section {
            rings: 12,
            sectors: 32,
            outer: 1.9,
            in_column: true,
            first_ring: None,
        }
    }
}

impl Default for Hybrid3Options {
    fn default() -> Self {
        Hybrid3Options {
            rings: 6,
            sectors: 16,
            outer: 1.0,
            first_ring: None,
            allow_sites_outside: false,
            split_facets: false,
            clip: true,
            layered: Some(Section::default()),
            progress: None,
        }
    }
}
