//! The entry point of the library: a `Mesher` on a backend, with options,
//! meshes a 2D `Complex` or a 3D `Complex3` into a certified conforming
//! orthogonal mesh.

use crate::backend::Backend;
use crate::complex::{Complex, Complex3};
use crate::conform::{conform2, conform3, Dimension, Outcome, D2, D3};
use crate::error::Result;
use crate::options::Options;

/// Meshes constraint complexes on one backend with one set of options.
///
/// ```
/// use orthomesh::{default_backend, generate, Mesher};
/// // A square cavity around a well polygon (its interior a hole).
/// let input = generate::cavities(1, 1, 14.0);
/// let backend = default_backend();
/// let out = Mesher::new(&backend).conform(&input).unwrap();
/// assert!(out.report.certificate.conforms());
/// assert_eq!(out.report.certificate.sites_outside, 0);
/// ```
pub struct Mesher<'a> {
    backend: &'a dyn Backend,
    options: Options,
}

impl<'a> Mesher<'a> {
    /// A mesher on this backend with the default options.
    pub fn new(backend: &'a dyn Backend) -> Mesher<'a> {
        Mesher {
            backend,
            options: Options::default(),
        }
    }

    /// The same mesher with these options.
    pub fn options(mut self, options: Options) -> Mesher<'a> {
        self.options = options;
        self
    }

    /// The certified mesh of a 2D or 3D complex.
    pub fn conform<I: Input>(&self, input: &I) -> Result<Outcome<I::Dim>> {
        input.mesh(self.backend, &self.options)
    }
}

/// A constraint complex the mesher takes: `Complex` (2D) or `Complex3`.
pub trait Input {
    /// Its dimension.
    type Dim: Dimension;
    /// Its certified mesh.
    fn mesh(&self, backend: &dyn Backend, options: &Options) -> Result<Outcome<Self::Dim>>;
}

impl Input for Complex {
    type Dim = D2;
    fn mesh(&self, backend: &dyn Backend, options: &Options) -> Result<Outcome<D2>> {
        if options.split_segments {
            let once = Options {
                split_segments: false,
                ..options.clone()
            };
            crate::split::conform_splitting(backend, self, &once)
        } else {
            conform2(backend, self, options)
        }
    }
}

impl Input for Complex3 {
    type Dim = D3;
    fn mesh(&self, backend: &dyn Backend, options: &Options) -> Result<Outcome<D3>> {
        conform3(backend, self, options)
    }
}
