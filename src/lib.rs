//! # orthomesh
//!
//! Conforming orthogonal meshes: power diagrams (PEBI grids) whose edges
//! contain given constraint segments exactly, with no extra points on them,
//! and whose sites lie inside their own cells. An implementation of
//! Balaven, Bennis, Boissonnat and Yvinec, "Conforming orthogonal meshes"
//! (IMR 2002), with exact predicates and an exact certificate.
//!
//! ```no_run
//! use orthomesh::{backend::default_backend, conform, io};
//! let input = io::read_complex(std::path::Path::new("A.poly")).unwrap();
//! let out = conform::conform(&default_backend(), &input, &Default::default()).unwrap();
//! assert!(out.report.certificate.conforms());
//! ```
//!
//! | feature | default | what |
//! |---|---|---|
//! | `cgal` | yes | CGAL backend (`Regular_triangulation_2`, exact kernels) via a C++ shim |
//!
//! Pipeline stages, one module each: [`complex`] (input and validation),
//! [`domain`], [`weights`] (LP), [`sites`], [`relocate`], [`diagram`],
//! [`mesh`], [`certify`]; [`conform`] runs them in order.

#![deny(unsafe_code)]

pub mod backend;
pub mod certify;
pub mod complex;
pub mod conform;
pub mod diagram;
pub mod domain;
pub mod error;
pub mod exact;
pub mod generate;
pub mod io;
pub mod mesh;
pub mod relocate;
pub mod sites;
pub mod weights;

pub use complex::Complex;
pub use error::{Error, Result};
