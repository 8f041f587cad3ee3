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
//! Inputs come from files ([`io::read_complex`]: Triangle `.poly`, CGAL `.edg`) or are
//! built in code ([`Complex::new`], [`generate`]).
//!
//! Pipeline stages, one module each: [`complex`] (input and validation),
//! [`domain`], [`weights`] (LP), [`sites`], [`relocate`], [`diagram`],
//! [`mesh`], [`certify`]; [`conform`] runs them in order. Reservoir meshes:
//! [`hybrid`] (corner-point layer, radial wells, cavities, faults),
//! [`layers`] (2.5D), [`flow`] (two-point flux check); readers and writers
//! in [`io`] (Triangle, CGAL, Eclipse, VTU, SVG, TOUGH2).

#![deny(unsafe_code)]

pub mod backend;
pub mod certify;
pub mod complex;
pub mod conform;

pub mod diagram;
pub mod domain;
pub mod error;
pub mod generate;
pub mod geom;
pub mod io;
pub mod lp;
pub mod mesh;
pub mod mesher;
pub mod options;
pub mod progress;
pub mod relocate;
pub mod reservoir;
pub mod sites;
pub mod split;
pub mod weights;

pub use backend::{by_name, compiled, default_backend, Backend};
pub use complex::{Complex, Complex3, Facet};
pub use conform::{Dimension, Outcome, D2, D3};
pub use error::{Error, Result};
pub use mesher::{Input, Mesher};
pub use options::Options;

/// Hash maps keyed by indices, which are not chosen by an adversary: Fx
/// hashing instead of SipHash, which dominated the adjacency lookups.
pub(crate) type FastMap<K, V> = rustc_hash::FxHashMap<K, V>;
pub(crate) type FastSet<K> = rustc_hash::FxHashSet<K>;
