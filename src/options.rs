//! What the caller chooses, for both dimensions.

use crate::progress::Progress;
use crate::weights::Keep;

/// Choices of the caller. Fields marked 2D or 3D are ignored in the other
/// dimension.
#[derive(Debug, Clone, Default)]
pub struct Options {
    /// Write the conforming mesh even when some sites lie outside their cells.
    pub allow_sites_outside: bool,
    /// 2D: also time the backend's raw regular triangulation of the input
    /// vertices, for the report's speed ratio (outside the pipeline's time).
    pub compare_with_raw: bool,
    /// Called as stages end and (2D) as the LP's pieces are solved:
    /// (what, done, of).
    pub progress: Option<Progress>,
    /// 2D: at a convex corner of the domain between two segments, one site
    /// at the power centre of their triangle in RT(w) serves both (its cell
    /// owns the corner) where that centre lies inside the domain.
    pub corner_sites: bool,
    /// 2D: where system 3 is infeasible, split the segments that miss their
    /// duals at Steiner points and mesh again (`split`).
    pub split_segments: bool,
    /// 3D: how polygons kept whole keep their lifts coplanar (`Keep::Auto`
    /// unless the caller asks for shared weights or coplanar lifts).
    pub whole_polygons: Keep,
    /// 3D: where faces miss their duals (system 3 infeasible), add Steiner
    /// points inside them to their facets, round by round, until none
    /// misses or no point can be added.
    pub split_facets: bool,
    /// 3D: facets (0-based) that bound the domain with nothing beyond them
    /// (each on the hull of the points): the cells are cut at their planes
    /// by mirrored sites instead of meeting them as single faces, so
    /// their triangles need not cross their duals.
    pub clip: Vec<u32>,
}
