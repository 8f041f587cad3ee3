//! The flow check: single-phase incompressible two-point flux on the hybrid
//! mesh of a homogeneous Cartesian reservoir with one vertical well, fixed
//! rate at the well and fixed pressure on the outer boundary, against
//! Thiem's radial solution. Prints what it measures.

use orthomesh::backend::default_backend;
use orthomesh::reservoir::flow::{boundary_faces, connections, pressures, stats, BoundaryFace};
use orthomesh::reservoir::hybrid::{build, HybridOptions, Region, WellAt, WellInput};
use orthomesh::reservoir::CornerPointGrid;
use std::f64::consts::TAU;

/// Relative error of the pressure drop between the well's cells and
/// r = L/4, and the transmissibility statistics of the transition and well
/// regions.
fn thiem(cells: usize, h: f64, opts: &HybridOptions) -> (f64, usize, usize) {
    let grid = CornerPointGrid::cartesian([cells, cells, 1], [h, h, 1.0]);
    let rw = 0.1;
    let mid = cells / 2;
    let well = WellInput {
        name: "W".into(),
        at: WellAt::Column(mid, mid),
        radius: rw,
    };
    let hy = build(&default_backend(), &grid, &[well], opts).unwrap();
    let m = &hy.mesh;
    let c = [(mid as f64 + 0.5) * h, (mid as f64 + 0.5) * h];
    let dist = |x: [f64; 2]| (x[0] - c[0]).hypot(x[1] - c[1]);
    let q = 1.0;
    let exact = |x: [f64; 2]| -q / TAU * dist(x).ln();
    let conns = connections(m);
    let mut source = vec![0.0; m.cells.len()];
    let mut fixed: Vec<(BoundaryFace, f64)> = vec![];
    let faces = boundary_faces(m);
    let wellbore: f64 = faces
        .iter()
        .filter(|f| dist(m.points[f.points[0] as usize]) < 2.0 * rw)
        .map(|f| f.area)
        .sum();
    for f in faces {
        let (a, b) = (
            m.points[f.points[0] as usize],
            m.points[f.points[1] as usize],
        );
        if dist(a) < 2.0 * rw {
            source[f.cell as usize] += q * f.area / wellbore; // the well's rate
        } else {
            let x = [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0];
            fixed.push((f, exact(x)));
        }
    }
    let p = pressures(m.cells.len(), &conns, &fixed, &source).unwrap();
    let inner: Vec<usize> = (0..m.cells.len()).filter(|&k| source[k] > 0.0).collect();
    let quarter = cells as f64 * h / 4.0;
    let band: Vec<usize> = (0..m.cells.len())
        .filter(|&k| {
            hy.region[k] == Region::Reservoir && (dist(m.sites[k]) - quarter).abs() <= h / 2.0
        })
        .collect();
    assert!(!band.is_empty() && inner.len() == opts.sectors);
    let mean = |f: &dyn Fn(usize) -> f64, set: &[usize]| {
        set.iter().map(|&k| f(k)).sum::<f64>() / set.len() as f64
    };
    let num = mean(&|k| p[k], &inner) - mean(&|k| p[k], &band);
    let ana = mean(&|k| exact(m.sites[k]), &inner) - mean(&|k| exact(m.sites[k]), &band);
    let near_well = |cc: [u32; 2]| {
        cc.iter()
            .all(|&k| hy.region[k as usize] != Region::Reservoir)
    };
    let s = stats(m, &conns, near_well);
    ((num - ana).abs() / ana, s.negative, s.non_orthogonal)
}

#[test]
fn thiem_within_half_a_percent() {
    for (label, opts) in [
        (
            "defaults (12 rings, 32 sectors, outer radius 1.9 cells)",
            HybridOptions::default(),
        ),
        (
            "64 sectors",
            HybridOptions {
                sectors: 64,
                ..Default::default()
            },
        ),
        (
            "outer radius 0.9 cells",
            HybridOptions {
                outer: 0.9,
                ..Default::default()
            },
        ),
        (
            "4 rings",
            HybridOptions {
                rings: 4,
                ..Default::default()
            },
        ),
    ] {
        let (err, negative, non_orthogonal) = thiem(31, 10.0, &opts);
        eprintln!(
            "Thiem check, 31 x 31 cells of 10 m, rw = 0.1 m, {label}: pressure drop off by {:.3}%, \
             {negative} negative transmissibilities, {non_orthogonal} non-orthogonal connections near the well",
            100.0 * err
        );
        assert_eq!((negative, non_orthogonal), (0, 0), "{label}");
        if label.starts_with("defaults") {
            assert!(err < 0.005, "{label}: {err}");
        }
    }
}
