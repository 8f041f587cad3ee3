//! # orthomesh
//!
//! Conforming orthogonal meshes: power diagrams (PEBI grids) whose edges
//! contain given constraint segments exactly, with no extra points on them,
//! and whose sites lie inside their own cells. An implementation of
//! Balaven, Bennis, Boissonnat and Yvinec, "Conforming orthogonal meshes"
//! (IMR 2002), with exact predicates and an exact certificate.
//!
//! ```
//! use orthomesh::{backend::default_backend, conform, generate};
//! // A square cavity around a well polygon (its interior a hole).
//! let input = generate::cavities(1, 1, 14.0);
//! let out = conform::conform(&default_backend(), &input, &Default::default()).unwrap();
//! assert!(out.report.certificate.conforms());
//! assert_eq!(out.report.certificate.sites_outside, 0);
//! let vtu = orthomesh::io::vtu::to_string(&out.mesh, &out.site_inside);
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
pub mod complex3;
pub mod conform;
pub mod conform3;
pub mod diagram;
pub mod diagram3;
pub mod domain;
pub mod error;
pub mod exact;
pub mod flow;
pub mod generate;
pub mod hybrid;
pub mod hybrid3;
pub mod io;
pub mod layers;
pub mod mesh;
pub mod relocate;
pub mod sites;
pub mod sites3;
pub mod split;
pub mod weights;
pub mod weights3;

pub use complex::Complex;
pub use error::{Error, Result};

/// Hash maps keyed by indices, which are not chosen by an adversary: a
/// multiplicative hash (as in rustc's FxHash) instead of SipHash, which
/// dominated the adjacency lookups.
pub(crate) type FastMap<K, V> = std::collections::HashMap<K, V, std::hash::BuildHasherDefault<Fx>>;
pub(crate) type FastSet<K> = std::collections::HashSet<K, std::hash::BuildHasherDefault<Fx>>;

#[derive(Default, Clone, Copy)]
pub(crate) struct Fx(u64);

impl std::hash::Hasher for Fx {
    fn write(&mut self, bytes: &[u8]) {
        for chunk in bytes.chunks(8) {
            let mut b = [0u8; 8];
            b[..chunk.len()].copy_from_slice(chunk);
            self.write_u64(u64::from_le_bytes(b));
        }
    }
    fn write_u32(&mut self, x: u32) {
        self.write_u64(u64::from(x));
    }
    fn write_u64(&mut self, x: u64) {
        self.0 = (self.0.rotate_left(5) ^ x).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }
    fn write_usize(&mut self, x: usize) {
        self.write_u64(x as u64);
    }
    fn finish(&self) -> u64 {
        self.0
    }
}
