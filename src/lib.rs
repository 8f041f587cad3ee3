//! # orthomesh
//!
//! Conforming orthogonal meshes: power diagrams (PEBI grids) whose edges
//! contain given constraint segments exactly, with no extra points on them,
//! and whose sites lie inside their own cells. An implementation of
//! Balaven, Bennis, Boissonnat and Yvinec, "Conforming orthogonal meshes"
//! (IMR 2002), with exact predicates and an exact certificate.
//!
//! ```
//! use orthomesh::{default_backend, generate, Mesher};
//! // A square cavity around a well polygon (its interior a hole).
//! let input = generate::cavities(1, 1, 14.0);
//! let backend = default_backend();
//! let out = Mesher::new(&backend).conform(&input).unwrap();
//! assert!(out.report.certificate.conforms());
//! assert_eq!(out.report.certificate.sites_outside, 0);
//! let vtu = orthomesh::io::vtu::to_string(&out.mesh.cells(&out.site_inside));
//! assert!(vtu.contains("UnstructuredGrid"));
//! ```
//!
//! | feature | default | what |
//! |---|---|---|
//! | `cgal` | yes | CGAL backend (`Regular_triangulation_2`, exact kernels) via a C++ shim |
//!
//! Inputs come from files ([`io::read_input`]: Triangle `.poly`, CGAL `.edg`,
//! TetGen `.poly`/`.smesh`) or are built in code ([`Complex::new`],
//! [`generate`]). A [`Mesher`] on a [`Backend`] runs the pipeline (domain,
//! weights, sites, relocation, diagram, certificate, mesh: docs/method.md)
//! in either dimension and returns an [`Outcome`]: the mesh, its report and
//! certificate. Reservoir meshes (corner-point grids, wells, faults; 2D,
//! 2.5D and 3D) are in [`reservoir`]; readers and writers in [`io`].

#![deny(unsafe_code)]
#![warn(missing_docs)]

pub mod backend;
mod certify;
mod complex;
mod conform;
mod diagram;
mod domain;
mod error;
pub mod generate;
mod geom;
pub mod io;
mod lp;
mod mesh;
mod mesher;
mod options;
mod progress;
mod relocate;
pub mod reservoir;
mod sites;
mod split;
mod weights;

pub use backend::{by_name, compiled, default_backend, Backend};
pub use certify::{Certificate, Certificate3};
pub use complex::{Complex, Complex3, Facet};
pub use conform::{
    hull_facets, Dimension, InputReport2, InputReport3, Outcome, Report, SitesReport2,
    SitesReport3, SplitReport, SplitSegment, Stage, Timing, D2, D3,
};
pub use domain::Simplices3;
pub use error::{Error, Result};
pub use geom::{q, Q};
pub use mesh::{
    CellArray, CellMesh, Cells, Connection, Element, FacetFace, Link3, Mesh, Mesh3, Network, Values,
};
pub use mesher::{Input, Mesher};
pub use options::Options;
pub use progress::Progress;
pub use weights::{Keep, WeightsReport};

/// Hash maps keyed by indices, which are not chosen by an adversary: Fx
/// hashing instead of SipHash, which dominated the adjacency lookups.
pub(crate) type FastMap<K, V> = rustc_hash::FxHashMap<K, V>;
pub(crate) type FastSet<K> = rustc_hash::FxHashSet<K>;
