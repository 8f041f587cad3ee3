//! Shared helpers for the integration tests.
#![allow(dead_code)]

pub mod dense;
pub mod hybrid3;

use orthomesh::backend::Backend;
use orthomesh::{io, Complex, Complex3, Facet, Result};
use orthomesh::{Mesher, Options, Outcome, D2};
use std::path::{Path, PathBuf};

/// A constraint set from the copy of the shared data in tests/data/pslg.
pub fn shared(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/pslg")
        .join(name)
}

pub fn read(name: &str) -> Complex {
    io::read_complex(&shared(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// Runs the pipeline; on success writes the mesh where the reader checks
/// (scripts/test.sh) will find it.
pub fn run(b: &dyn Backend, cx: &Complex, tag: &str, allow: bool) -> Result<Outcome<D2>> {
    let out = Mesher::new(b)
        .options(Options {
            allow_sites_outside: allow,
            ..Default::default()
        })
        .conform(cx)?;
    if let Ok(dir) = std::env::var("ORTHOMESH_TEST_OUT") {
        let name = format!("{tag}-{}.vtu", b.name());
        io::write_atomic(
            &Path::new(&dir).join(name),
            orthomesh::io::vtu::to_string(&out.mesh.cells(&out.site_inside)).as_bytes(),
        )?;
    }
    Ok(out)
}

/// The invariants every returned mesh satisfies.
pub fn assert_certified(out: &Outcome<D2>, tag: &str) {
    assert_certified_to(out, tag, 1e-6);
}

/// As `assert_certified`, with the largest orthogonality defect allowed on
/// the mesh as written (coordinates far from the origin resolve less).
pub fn assert_certified_to(out: &Outcome<D2>, tag: &str, orthogonality: f64) {
    let c = &out.report.certificate;
    assert!(c.conforms(), "{tag}: certificate {c:?}");
    assert!(
        c.area_relative_error < 1e-9,
        "{tag}: area error {}",
        c.area_relative_error
    );
    assert!(
        c.max_orthogonality_defect < orthogonality,
        "{tag}: orthogonality defect {}",
        c.max_orthogonality_defect
    );
    assert_eq!(out.mesh.cells.len(), out.site_inside.len());
    // hidden sites count as outside and have no cell
    let hidden = out
        .report
        .sites
        .sites_outside
        .iter()
        .filter(|m| m.contains(": hidden:"))
        .count();
    assert_eq!(
        c.sites_outside,
        out.site_inside.iter().filter(|&&i| !i).count() + hidden,
        "{tag}"
    );
}

/// A complex of one facet per polygon (1-based vertex lists, as in files).
pub fn complex(points: Vec<[f64; 3]>, polygons: &[&[u32]]) -> Complex3 {
    Complex3 {
        vertex_ids: (1..=points.len() as i64).collect(),
        points,
        facets: polygons
            .iter()
            .map(|p| Facet {
                polygons: vec![p.iter().map(|v| v - 1).collect()],
                ..Default::default()
            })
            .collect(),
        holes: vec![],
    }
}

/// The unit cube's corners (1-8: z = 0 then z = 1, counter-clockwise) and
/// its six faces.
pub fn cube() -> (Vec<[f64; 3]>, Vec<Vec<u32>>) {
    let mut points = vec![];
    for z in [0.0, 1.0] {
        points.extend([[0.0, 0.0, z], [1.0, 0.0, z], [1.0, 1.0, z], [0.0, 1.0, z]]);
    }
    let faces = [
        [1, 4, 3, 2],
        [5, 6, 7, 8],
        [1, 2, 6, 5],
        [2, 3, 7, 6],
        [3, 4, 8, 7],
        [4, 1, 5, 8],
    ];
    (points, faces.iter().map(|f| f.to_vec()).collect())
}

pub fn with(points: Vec<[f64; 3]>, faces: &[Vec<u32>]) -> Complex3 {
    let polys: Vec<&[u32]> = faces.iter().map(|f| f.as_slice()).collect();
    complex(points, &polys)
}
