//! The one error type. Variants carry the offending items by the ids the
//! input file gave them, so messages point back into the user's file.

use std::fmt;
use std::path::PathBuf;

/// Result with the crate's error.
pub type Result<T> = std::result::Result<T, Error>;

/// Everything that can stop orthomesh.
#[derive(Debug)]
pub enum Error {
    /// A file could not be read or written.
    Io {
        /// The file.
        path: PathBuf,
        /// What the system said.
        message: String,
    },
    /// A file does not parse; `line` is 1-based.
    Parse {
        /// The file.
        path: PathBuf,
        /// The line (1-based).
        line: usize,
        /// What is wrong there.
        message: String,
    },
    /// Vertices with NaN or infinite coordinates.
    NonFinite {
        /// Their ids.
        vertices: Vec<i64>,
    },
    /// Pairs of vertices at the same position.
    DuplicateVertices {
        /// Their ids.
        pairs: Vec<(i64, i64)>,
    },
    /// Segments whose two ends are the same vertex.
    ZeroLengthSegments {
        /// Their ids.
        segments: Vec<i64>,
    },
    /// Pairs of segments joining the same two vertices.
    RepeatedSegments {
        /// Their ids.
        pairs: Vec<(i64, i64)>,
    },
    /// Pairs of segments that cross, overlap or touch other than at a shared endpoint.
    CrossingSegments {
        /// Their ids.
        pairs: Vec<(i64, i64)>,
    },
    /// (vertex, segment): a vertex inside a segment.
    VertexOnSegment {
        /// Their ids.
        pairs: Vec<(i64, i64)>,
    },
    /// Coordinates whose squares do not fit in a double (weights are squared lengths).
    OutOfRange(String),
    /// The input has no area to mesh (fewer than 3 points, all collinear, empty domain).
    Degenerate(String),
    /// System 1 infeasible: no regular constrained triangulation exists.
    NoRegularConstrainedTriangulation {
        /// The segments (ids) the LP could not make faces.
        segments: Vec<i64>,
        /// Rows of the exact certificate (`lp::Proof`) that proves it;
        /// None when only the LP's floating-point margin says so.
        proof_rows: Option<usize>,
    },
    /// 3D system 1 infeasible: no regular triangulation contains the
    /// facets' triangles (facet ids) and the isolated points (vertex ids).
    NoRegularConstrainedTetrahedralisation {
        /// Facet ids.
        facets: Vec<i64>,
        /// Vertex ids.
        vertices: Vec<i64>,
        /// Rows of the exact certificate (`lp::Proof`) that proves it;
        /// None when only the LP's floating-point margin says so.
        proof_rows: Option<usize>,
    },
    /// System 3 infeasible: these segments cannot cross their dual edges, so
    /// some sites must lie outside their cells.
    /// `lp_error`: None when the LP proved it; else why the LP gave no answer
    /// (zero weights were then used).
    SegmentsMissTheirDuals {
        /// Their ids.
        segments: Vec<i64>,
        /// Why the LP gave no answer, if it did not.
        lp_error: Option<String>,
        /// Segments (ids) that an exact certificate proves cannot all
        /// cross their duals; empty when the verdict is the LP's alone.
        proved: Vec<i64>,
    },
    /// Sites that could not be brought into their own cells; `crowding`:
    /// the segments whose sites they lie beyond (or their own).
    SitesOutsideCells {
        /// Each site, with why.
        sites: Vec<String>,
        /// The segments (ids) in the way.
        crowding: Vec<i64>,
    },
    /// The LP stopped short of a verdict: a solver failure, the time
    /// budget, the rows it may grow to, or a precision it cannot resolve;
    /// the message names the limit and what was tried. Not a proof.
    SolverLimit(String),
    /// A defect of orthomesh (a state the code holds impossible): please
    /// report it with the input.
    Internal(String),
    /// A backend (CGAL) reported an error or threw.
    Backend(String),
    /// The exact certificate of the final mesh does not hold.
    Certificate(String),
    /// Command-line usage error.
    Usage(String),
    /// 3D input: pairs of facets (ids from 1) that meet other than in shared
    /// edges and vertices.
    CrossingFacets {
        /// Facet ids.
        pairs: Vec<(i64, i64)>,
    },
    /// 3D input: facets that are not planar polygons (named in the message).
    BadFacets(String),
    /// 3D input: what is wrong inside one facet (numbered from 1 in file
    /// order), its edges numbered from 1 in file order.
    InFacet {
        /// The facet (id from 1).
        facet: i64,
        /// What is wrong in its plane.
        error: Box<Error>,
    },
    /// Each way a build was tried (how, and why it failed).
    Tried(Vec<(String, Error)>),
    /// An error in one part of a larger build (which part, and the error).
    Within {
        /// The part, e.g. the cavity of some wells.
        part: String,
        /// What went wrong there.
        error: Box<Error>,
    },
}

/// How a system 1 verdict is known.
fn proved(rows: &Option<usize>) -> String {
    match rows {
        Some(n) => format!(", proved exactly by a certificate combining {n} LP rows"),
        None => ": the LP's margin is not positive, not proved exactly".into(),
    }
}

/// Shows at most 20 items, then how many more.
pub(crate) fn list<T: fmt::Display>(items: &[T]) -> String {
    let shown: Vec<String> = items.iter().take(20).map(|x| x.to_string()).collect();
    let more = items.len().saturating_sub(20);
    if more > 0 {
        format!("{} and {more} more", shown.join(", "))
    } else {
        shown.join(", ")
    }
}

fn pairs(items: &[(i64, i64)], join: &str) -> String {
    let v: Vec<String> = items.iter().map(|(a, b)| format!("{a}{join}{b}")).collect();
    list(&v)
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::Io { path, message } => write!(f, "{}: {message}", path.display()),
            Error::Parse { path, line, message } => write!(f, "{}:{line}: {message}", path.display()),
            Error::NonFinite { vertices } => {
                write!(f, "vertices with a NaN or infinite coordinate: {}", list(vertices))
            }
            Error::DuplicateVertices { pairs: p } => {
                write!(f, "duplicate vertices (same position): {}", pairs(p, " = "))
            }
            Error::ZeroLengthSegments { segments } => {
                write!(f, "zero-length segments (both ends the same vertex): {}", list(segments))
            }
            Error::RepeatedSegments { pairs: p } => {
                write!(f, "repeated segments (same two vertices): {}", pairs(p, " = "))
            }
            Error::CrossingSegments { pairs: p } => write!(
                f,
                "segments that cross, overlap or touch other than at a shared endpoint: {}",
                pairs(p, " x ")
            ),
            Error::VertexOnSegment { pairs: p } => {
                write!(f, "vertices lying inside a segment (vertex on segment): {}", pairs(p, " on "))
            }
            Error::OutOfRange(m) => write!(f, "coordinates out of range: {m}"),
            Error::Degenerate(m) => write!(f, "nothing to mesh: {m}"),
            Error::NoRegularConstrainedTriangulation {
                segments,
                proof_rows,
            } => write!(
                f,
                "no regular constrained triangulation exists (system 1 is infeasible{}), so no conforming \
                 power diagram can be built without extra points; constraints involved (segment ids): {}",
                proved(proof_rows),
                list(segments)
            ),
            Error::NoRegularConstrainedTetrahedralisation {
                facets,
                vertices,
                proof_rows,
            } => write!(
                f,
                "no regular triangulation contains the 3D constraints (system 1 is infeasible{}), so no \
                 conforming power diagram can be built without extra points; facets involved (ids): {}{}",
                proved(proof_rows),
                list(facets),
                if vertices.is_empty() {
                    String::new()
                } else {
                    format!("; isolated vertices: {}", list(vertices))
                }
            ),
            Error::SegmentsMissTheirDuals {
                segments,
                lp_error,
                proved,
            } => write!(
                f,
                "a conforming mesh exists but these segments {}, so sites cannot all lie inside \
                 their cells; segment ids: {}. Rerun with --allow-sites-outside to write the \
                 conforming mesh anyway",
                match lp_error {
                    None if proved.is_empty() => "do not cross their dual edges (the LP finds no \
                        weights for system 3; not proved exactly)"
                        .to_string(),
                    None => format!(
                        "do not cross their dual edges (system 3 is infeasible, proved exactly: \
                         segments {} cannot all cross theirs)",
                        list(proved)
                    ),
                    Some(m) => format!(
                        "do not cross their dual edges with zero weights (not proven infeasible: the LP \
                         gave no answer: {m})"
                    ),
                },
                list(segments)
            ),
            Error::SitesOutsideCells { sites, .. } => write!(
                f,
                "sites that could not be brought strictly inside their own cells: {}. Rerun with \
                 --allow-sites-outside to write the conforming mesh anyway",
                list(sites)
            ),
            Error::SolverLimit(m) => write!(f, "solver limit: {m}"),
            Error::Internal(m) => write!(
                f,
                "internal error (a defect of orthomesh; please report it with the input): {m}"
            ),
            Error::Backend(m) => write!(f, "triangulation backend: {m}"),
            Error::Certificate(m) => write!(f, "certificate failed: {m}"),
            Error::Usage(m) => write!(f, "{m}"),
            Error::BadFacets(m) => write!(f, "invalid facets: {m}"),
            Error::CrossingFacets { pairs: p } => write!(
                f,
                "facets that cross, overlap or touch other than in shared edges and vertices \
                 (facets numbered from 1 in file order): {}",
                pairs(p, " x ")
            ),
            Error::InFacet { facet, error } => write!(
                f,
                "in facet {facet} (its edges numbered from 1 in file order): {error}"
            ),
            Error::Tried(ways) => {
                let v: Vec<String> = ways.iter().map(|(how, e)| format!("{how}: {e}")).collect();
                write!(f, "every way failed: {}", v.join("; "))
            }
            Error::Within { part, error } => write!(f, "{part}: {error}"),
        }
    }
}

impl std::error::Error for Error {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn long_lists_are_cut() {
        let e = Error::ZeroLengthSegments {
            segments: (1..=25).collect(),
        };
        let s = e.to_string();
        assert!(s.contains("20 and 5 more"), "{s}");
        assert!(!s.contains("21"));
    }

    #[test]
    fn every_way_tried_is_named() {
        let e = Error::Tried(vec![
            ("cut".into(), Error::Degenerate("flat".into())),
            ("faces".into(), Error::SolverLimit("no solution".into())),
        ]);
        let s = e.to_string();
        assert!(s.contains("cut: nothing to mesh: flat; faces: "), "{s}");
        assert!(s.ends_with("no solution"), "{s}");
    }
}
