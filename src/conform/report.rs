//! The report written next to the mesh, one type for both dimensions: the
//! parts every run has, and two sections whose fields differ with the
//! dimension (what came in, and how the sites were placed). The sections
//! are flattened, so the JSON is one flat object as before.

use super::{Dimension, Timing};
use crate::weights::{Keep, WeightsReport};
use serde::Serialize;

/// The report written next to the mesh.
#[derive(Debug, Clone, Default, Serialize)]
#[serde(bound = "")]
pub struct Report<D: Dimension> {
    /// The backend's name.
    pub backend: String,
    /// What came in, and what the domain changed.
    #[serde(flatten)]
    pub input: D::InputReport,
    /// What the weights step did.
    pub weights: WeightsReport,
    /// Where the sites went.
    #[serde(flatten)]
    pub sites: D::SitesReport,
    /// Cells in the mesh.
    pub cells: usize,
    /// Vertices in the mesh.
    pub mesh_vertices: usize,
    /// Vertices merged with a neighbour closer than the output precision.
    pub collapsed_vertices: usize,
    /// The exact certificate.
    pub certificate: D::Certificate,
    /// Time and memory: they differ from run to run, everything else in
    /// the report does not (the CLI's `--reproducible` leaves this out).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub timing: Option<Timing>,
    /// 2D: segments meshed as chains (`Options::split_segments`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub split: Option<SplitReport>,
}

/// 2D: the input and what the domain changed.
#[derive(Debug, Clone, Serialize, Default)]
pub struct InputReport2 {
    /// Input vertices.
    pub vertices: usize,
    /// Input segments.
    pub segments: usize,
    /// Input hole points.
    pub holes: usize,
    /// What the reader or the domain changed and the user should know.
    pub notes: Vec<String>,
    /// The domain's area.
    pub domain_area: f64,
    /// Convex hull edges added where the segments enclose nothing.
    pub hull_edges_added: usize,
    /// Input vertices outside the domain, dropped.
    pub dropped_vertices: usize,
    /// Input segments outside the domain, dropped.
    pub dropped_segments: usize,
}

/// 3D: the input and the faces it became.
#[derive(Debug, Clone, Serialize, Default)]
pub struct InputReport3 {
    /// Always 3.
    pub dimension: usize,
    /// Input vertices.
    pub vertices: usize,
    /// Input facets.
    pub facets: usize,
    /// Faces of the complex: triangles (facets split in their planes),
    /// polygons kept whole, dangling segments, isolated points.
    pub triangles: usize,
    /// Polygons kept whole (one face each).
    pub whole_polygons: usize,
    /// How they were kept: coplanar lifts, or shared weights.
    pub whole_polygons_kept: Keep,
    /// Points added inside faces that missed their duals (`split_facets`).
    pub steiner_points: Vec<[f64; 3]>,
    /// Facets (ids from 1) the cells were cut at (`Options::clip`).
    pub clip_facets: Vec<i64>,
    /// Dangling segments.
    pub segments: usize,
    /// Isolated points.
    pub points: usize,
}

/// 2D: the sites, their relocation and their margins.
#[derive(Debug, Clone, Serialize, Default)]
pub struct SitesReport2 {
    /// Segments (input ids) that do not cross their dual edge.
    pub segments_missing_dual: Vec<i64>,
    /// Sites placed.
    #[serde(rename = "sites")]
    pub placed: usize,
    /// Extra sites of free ends and isolated vertices.
    pub vertex_sites: usize,
    /// Rounds of relocation.
    pub relocation_rounds: usize,
    /// Rounds whose site triangulation had to be built in exact rationals
    /// (the one from rounded sites failed its exact check).
    pub exact_site_triangulations: usize,
    /// Smallest distance from a domain site to its cell's boundary, divided
    /// by the square root of the cell's area (0 when some site is outside).
    pub min_site_margin: f64,
    /// Sites outside their cells, each with why.
    pub sites_outside: Vec<String>,
}

/// 3D: the sites and their relocation.
#[derive(Debug, Clone, Serialize, Default)]
pub struct SitesReport3 {
    /// Faces (facet ids) that do not cross their dual edge: their sites
    /// cannot be brought near them.
    pub facets_missing_dual: Vec<i64>,
    /// Sites placed.
    #[serde(rename = "sites")]
    pub placed: usize,
    /// Sites beyond two per face (edges and vertices that need more).
    pub extra_sites: usize,
    /// Moves of sites that others beat, made before the first diagram
    /// (in doubles, `Sites3::settle`).
    pub settle_moves: usize,
    /// Rounds of relocation.
    pub relocation_rounds: usize,
    /// Site diagrams (one per round, and one before) whose triangulation
    /// of the rounded sites failed its exact check even after flips, so
    /// that the exact sites were triangulated.
    pub exact_triangulations: usize,
    /// Domain sites outside their cells.
    pub sites_outside: usize,
}

/// What splitting did, for the report.
#[derive(Debug, Clone, Serialize, Default)]
pub struct SplitReport {
    /// Rounds of splitting.
    pub rounds: usize,
    /// Steiner points added in all.
    pub steiner_points: usize,
    /// Input segments meshed as chains.
    pub segments: Vec<SplitSegment>,
}

/// One input segment meshed as a chain.
#[derive(Debug, Clone, Serialize)]
pub struct SplitSegment {
    /// The segment's id in the input.
    pub id: i64,
    /// Edges of its chain.
    pub pieces: usize,
    /// Largest distance of its Steiner points from the segment, over its
    /// length: 0 when they lie on it exactly; else each is the double
    /// nearest its midpoint (no double lies on the segment near there).
    pub off_line: f64,
}
