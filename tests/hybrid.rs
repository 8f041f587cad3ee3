//! Hybrid reservoir meshes on the shared SPE9 grid and deck: every well
//! gets a radial mesh, every cavity a certified transition mesh, the whole
//! conforms, and the interfaces are orthogonal.

use orthomesh::backend::default_backend;
use orthomesh::hybrid::{build, HybridOptions, Region, WellAt, WellInput};
use orthomesh::io::eclipse::{read_grid, read_wells};
use std::path::Path;

fn data(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/grids")
        .join(name)
}

fn spe9_wells() -> Vec<WellInput> {
    let (wells, _) = read_wells(&data("SPE9_CP.DATA")).unwrap();
    wells
        .into_iter()
        .map(|w| WellInput {
            name: w.name,
            at: WellAt::Column(w.i, w.j),
            radius: w.radius.unwrap(),
        })
        .collect()
}

fn write(tag: &str, h: &orthomesh::hybrid::Hybrid) {
    if let Ok(dir) = std::env::var("ORTHOMESH_TEST_OUT") {
        let path = Path::new(&dir).join(format!("hybrid-{tag}.vtu"));
        orthomesh::io::write_atomic(&path, h.vtu().as_bytes()).unwrap();
        let mesh = Path::new(&dir).join(format!("hybrid-{tag}.tough"));
        orthomesh::io::write_atomic(&mesh, h.tough().unwrap().as_bytes()).unwrap();
    }
}

#[test]
fn spe9_top_layer_with_all_26_wells() {
    let g = read_grid(&data("SPE9.GRDECL")).unwrap();
    let opts = HybridOptions::default();
    let h = build(&default_backend(), &g, &spe9_wells(), &opts).unwrap();
    let r = &h.report;
    assert_eq!(r.wells.len(), 26);
    assert_eq!(r.unmatched_faces, 0, "hanging nodes or overlaps");
    let c = &r.transition.certificate;
    assert!(c.conforms() && c.sites_inside_cells, "{:?}", c.problems);
    // Every column is a reservoir cell or part of a cavity.
    assert_eq!(r.cells[0] + r.cavity_cells, 24 * 25);
    assert_eq!(r.cells[2], 26 * opts.rings * opts.sectors);
    let t = &r.transmissibility;
    assert_eq!((t.negative, t.non_orthogonal), (0, 0));
    assert!(t.connections > h.mesh.cells.len());
    for (pair, d) in &r.orthogonality_defect {
        assert!(*d < 1e-9, "{pair}: {d}");
    }
    // Cell areas add up to the grid's.
    let area: f64 = h.mesh.cells.iter().map(|c| h.mesh.area(c)).sum();
    let wellbores: f64 = 26.0 * 0.5 * 32.0 * (std::f64::consts::TAU / 32.0).sin() * 0.25;
    assert!(
        (area + wellbores - 7200.0 * 7500.0).abs() < 1e-6 * area,
        "{area}"
    );
    assert!(h
        .region
        .iter()
        .zip(&h.ijk)
        .all(|(r, c)| (*r == Region::Reservoir) == c.is_some()));
    write("spe9", &h);
}

#[test]
fn bad_wells_are_errors() {
    let g = read_grid(&data("SPE9.GRDECL")).unwrap();
    let opts = HybridOptions::default();
    let well = |at, radius| WellInput {
        name: "W".into(),
        at,
        radius,
    };
    for (w, text) in [
        (well(WellAt::Column(24, 0), 0.5), "outside the grid"),
        (well(WellAt::Xy([-10.0, 5.0]), 0.5), "outside the grid"),
        (well(WellAt::Column(3, 3), 500.0), "radius"),
        (well(WellAt::Column(3, 3), -1.0), "radius"),
    ] {
        let e = build(&default_backend(), &g, &[w], &opts)
            .unwrap_err()
            .to_string();
        assert!(e.contains(text), "{e}");
    }
    let e = build(&default_backend(), &g, &[], &opts)
        .unwrap_err()
        .to_string();
    assert!(e.contains("at least one well"), "{e}");
}
