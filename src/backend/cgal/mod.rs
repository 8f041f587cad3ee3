//! CGAL backend: `Regular_triangulation_2` over Epick (double input, exact
//! predicates) and Epeck (rational input), `Constrained_Delaunay_triangulation_2`,
//! `Regular_triangulation_3` over Epick.

#[allow(unsafe_code)]
mod ffi;

use super::{Backend, Tetrahedralisation, Triangulation};
use crate::error::{Error, Result};
use crate::geom::Q;
use std::fmt::Write;

/// The CGAL backend (feature `cgal`).
#[derive(Debug, Default, Clone, Copy)]
pub struct Cgal;

/// A C++ exception from the shim as our error.
fn thrown<T>(r: std::result::Result<T, cxx::Exception>) -> Result<T> {
    r.map_err(|e| Error::Backend(format!("CGAL: {}", e.what())))
}

fn convert(
    r: std::result::Result<ffi::bridge::TriangulationOut, cxx::Exception>,
) -> Result<Triangulation> {
    let out = thrown(r)?;
    Ok(Triangulation::from_parts(
        slice(&out.triangles),
        slice(&out.neighbours),
        out.hidden,
    ))
}

/// A C++ vector's elements (none when the shim left it null).
fn slice(v: &cxx::UniquePtr<cxx::CxxVector<u32>>) -> &[u32] {
    v.as_ref().map_or(&[], |v| v.as_slice())
}

impl Backend for Cgal {
    fn name(&self) -> &'static str {
        "cgal"
    }

    fn regular(&self, points: &[[f64; 2]], weights: &[f64]) -> Result<Triangulation> {
        let xyw: Vec<f64> = points
            .iter()
            .zip(weights)
            .flat_map(|(p, w)| [p[0], p[1], *w])
            .collect();
        convert(ffi::bridge::regular_triangulation_2(&xyw))
    }

    fn constrained_delaunay(
        &self,
        points: &[[f64; 2]],
        segments: &[[u32; 2]],
    ) -> Result<Triangulation> {
        let xy: Vec<f64> = points.iter().flatten().copied().collect();
        let segs: Vec<u32> = segments.iter().flatten().copied().collect();
        convert(ffi::bridge::constrained_delaunay_2(&xy, &segs))
    }

    fn regular_exact(&self, points: &[[Q; 2]], weights: &[Q]) -> Result<Triangulation> {
        let mut text = String::with_capacity(points.len() * 96);
        for (p, w) in points.iter().zip(weights) {
            // malachite prints "n/d" or "n", which GMP's mpq parser reads.
            let _ = writeln!(text, "{} {} {}", p[0], p[1], w);
        }
        convert(ffi::bridge::regular_triangulation_2_exact(&text))
    }

    fn regular3(&self, points: &[[f64; 3]], weights: &[f64]) -> Result<Tetrahedralisation> {
        let xyzw: Vec<f64> = points
            .iter()
            .zip(weights)
            .flat_map(|(p, w)| [p[0], p[1], p[2], *w])
            .collect();
        convert3(ffi::bridge::regular_triangulation_3(&xyzw))
    }

    fn regular3_exact(&self, points: &[[Q; 3]], weights: &[Q]) -> Result<Tetrahedralisation> {
        let mut text = String::with_capacity(points.len() * 128);
        for (p, w) in points.iter().zip(weights) {
            let _ = writeln!(text, "{} {} {} {}", p[0], p[1], p[2], w);
        }
        convert3(ffi::bridge::regular_triangulation_3_exact(&text))
    }
}

fn convert3(
    out: std::result::Result<ffi::bridge::TetrahedralisationOut, cxx::Exception>,
) -> Result<Tetrahedralisation> {
    let out = thrown(out)?;
    Ok(Tetrahedralisation::from_parts(
        slice(&out.tets),
        slice(&out.neighbours),
        out.hidden,
    ))
}
