//! Hybrid reservoir meshes on the shared SPE9 grid and deck: every well
//! gets a radial mesh, every cavity a certified transition mesh, the whole
//! conforms, and the interfaces are orthogonal.

use orthomesh::backend::default_backend;
use orthomesh::io::eclipse::{read_grid, read_wells};
use orthomesh::reservoir::hybrid::{build, HybridOptions, Region, WellAt, WellInput};
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

fn write(tag: &str, h: &orthomesh::reservoir::hybrid::Hybrid) {
    write_files(
        &format!("hybrid-{tag}"),
        &orthomesh::io::vtu::to_string(&h.cells()),
        &orthomesh::io::tough::to_string(&h.network()).unwrap(),
    );
}

/// 2.5D meshes go to `layers-*` files: tests/readers.py validates them as
/// polyhedra.
fn write_layers(
    tag: &str,
    h: &orthomesh::reservoir::hybrid::Hybrid,
    l: &orthomesh::reservoir::layers::Layered,
) {
    write_files(
        &format!("layers-{tag}"),
        &orthomesh::io::vtu::to_string(&l.cells(h)),
        &orthomesh::io::tough::to_string(&l.network(h)).unwrap(),
    );
}

fn write_files(stem: &str, vtu: &str, tough: &str) {
    if let Ok(dir) = std::env::var("ORTHOMESH_TEST_OUT") {
        let path = Path::new(&dir).join(format!("{stem}.vtu"));
        orthomesh::io::write_atomic(&path, vtu.as_bytes()).unwrap();
        let mesh = Path::new(&dir).join(format!("{stem}.tough"));
        orthomesh::io::write_atomic(&mesh, tough.as_bytes()).unwrap();
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
    assert!(r.non_orthogonal_interfaces.is_empty());
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
    // On the dipping layer, transition and well cells take the depth of
    // the column that holds their site: across their connections depth
    // steps no more than between diagonal reservoir columns (it was 599 ft
    // with the layer's mean depth).
    let net = h.network();
    let step = |of_reservoir: bool| {
        net.connections
            .iter()
            .filter(|c| c.elements.iter().all(|&e| h.ijk[e].is_some()) == of_reservoir)
            .map(|c| {
                (net.elements[c.elements[0]].node[2] - net.elements[c.elements[1]].node[2]).abs()
            })
            .fold(0.0, f64::max)
    };
    let (others, reservoir) = (step(false), step(true));
    println!("SPE9 top layer: depth steps across connections: {others:.2} ft with transition or well cells, {reservoir:.2} ft between columns");
    assert!(others <= 2.0 * reservoir, "{others} > 2 x {reservoir}");
    write("spe9", &h);
}

/// SPE9's hybrid mesh is the same on every backend compiled in.
#[test]
fn spe9_on_every_backend() {
    let g = read_grid(&data("SPE9.GRDECL")).unwrap();
    let opts = HybridOptions::default();
    let key = |h: &orthomesh::reservoir::hybrid::Hybrid| {
        let r = &h.report;
        (
            r.cells,
            r.transmissibility.connections,
            r.transmissibility.non_orthogonal,
            r.transition.weights.anchors_met,
            r.transition.certificate.conforms(),
        )
    };
    let keys: Vec<_> = orthomesh::backend::compiled()
        .iter()
        .map(|b| key(&build(&**b, &g, &spe9_wells(), &opts).unwrap()))
        .collect();
    assert!(keys.windows(2).all(|w| w[0] == w[1]), "{keys:?}");
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

#[test]
fn spe9_in_2_5d() {
    let g = read_grid(&data("SPE9.GRDECL")).unwrap();
    let opts = HybridOptions::default();
    let h = build(&default_backend(), &g, &spe9_wells(), &opts).unwrap();
    let l = orthomesh::reservoir::layers::extrude(&h, &g).unwrap();
    write_layers("spe9", &h, &l);
    assert_eq!(l.cells.len(), 15 * h.mesh.cells.len());
    // COMPDAT's layers: each well linked to its wellbore there only (the
    // injector in layers 11-15, the producers in 2-4), else in every layer.
    let (found, _) = orthomesh::io::eclipse::read_wells(&data("SPE9_CP.DATA")).unwrap();
    let completed: Vec<(String, [usize; 2])> =
        found.into_iter().map(|w| (w.name, w.k.unwrap())).collect();
    let open = l.well_links(&h, &[]);
    let links = l.well_links(&h, &completed);
    for ((a, b), (name, [k1, k2])) in open.iter().zip(&links).zip(&completed) {
        assert_eq!(&b.name, name);
        assert_eq!(a.links.len(), 15 * b.links.len() / (k2 - k1 + 1), "{name}");
        assert!(b
            .links
            .iter()
            .all(|&(e, _)| (*k1..=*k2).contains(&l.origin[e].1)));
    }
    // Volumes add up to the grid's (less the wellbores), to the precision
    // of mean thicknesses over cells that straddle columns.
    let grid_volume: f64 = (0..15)
        .flat_map(|k| (0..25).flat_map(move |j| (0..24).map(move |i| (i, j, k))))
        .map(|(i, j, k)| {
            let z: Vec<f64> = (0..8).map(|c| g.corner(i, j, k, c)[2]).collect();
            300.0 * 300.0 * (4..8).map(|c| z[c] - z[c - 4]).sum::<f64>() / 4.0
        })
        .sum();
    let total: f64 = l.volume.iter().sum();
    assert!(
        (total - grid_volume).abs() < 1e-3 * grid_volume,
        "{total} vs {grid_volume}"
    );
    // Every polyhedron is closed: each edge in two of its faces, once each way.
    for faces in &l.cells {
        let mut edges = std::collections::HashMap::new();
        for f in faces {
            for e in 0..f.len() {
                *edges.entry((f[e], f[(e + 1) % f.len()])).or_insert(0) += 1;
            }
        }
        assert!(edges
            .iter()
            .all(|(&(a, b), &n)| n == 1 && edges.get(&(b, a)) == Some(&1)));
    }
    let tough = orthomesh::io::tough::to_string(&l.network(&h)).unwrap();
    let conne = tough
        .lines()
        .skip_while(|l| *l != "CONNE")
        .filter(|l| l.len() > 30)
        .count();
    let vertical = tough
        .lines()
        .filter(|l| l.len() > 30 && &l[25..30] == "    3")
        .count();
    assert_eq!(vertical, 14 * h.mesh.cells.len());
    assert!(conne > vertical);
}

/// A 11 x 11 Cartesian grid of 10 m cells written as GRDECL with a fault
/// that ends next to the well: along the east sides of column I = 6 for
/// J = 3..5, and a part far away along the north sides of row J = 9.
fn faulted_grid() -> std::path::PathBuf {
    let g = orthomesh::reservoir::CornerPointGrid::cartesian([11, 11, 2], [10.0, 10.0, 5.0]);
    grdecl_file(
        "faulted",
        &g,
        "FAULTS\n 'F1' 6 6 3 5 1 2 X /\n 'F1' 7 9 9 9 1 2 Y /\n/\n",
    )
}

/// Every anchor (reservoir centre, ring site across an interface) on its
/// segment's dual line, every interface face orthogonal.
fn assert_interfaces_orthogonal(r: &orthomesh::reservoir::hybrid::HybridReport) {
    let w = &r.transition.weights;
    assert!(w.anchors > 0 && w.anchors_met == w.anchors, "{w:?}");
    assert!(
        r.non_orthogonal_interfaces.is_empty(),
        "{:?}",
        r.non_orthogonal_interfaces
    );
    for (pair, d) in &r.orthogonality_defect {
        if pair != "reservoir-reservoir" {
            assert!(*d < 1e-6, "{pair}: {d}");
        }
    }
}

/// Writes grid g (and `extra` keywords) as GRDECL in a temporary folder.
fn grdecl_file(
    name: &str,
    g: &orthomesh::reservoir::CornerPointGrid,
    extra: &str,
) -> std::path::PathBuf {
    use std::fmt::Write;
    let mut s = format!("SPECGRID\n {} {} {} 1 F /\nCOORD\n", g.nx, g.ny, g.nz);
    for p in &g.coord {
        let _ = writeln!(s, "{} {} {} {} {} {}", p[0], p[1], p[2], p[3], p[4], p[5]);
    }
    s += "/\nZCORN\n";
    for z in &g.zcorn {
        let _ = writeln!(s, "{z}");
    }
    s += "/\n";
    s += extra;
    let dir = std::env::temp_dir().join(format!("orthomesh-hybrid-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(format!("{name}.grdecl"));
    std::fs::write(&path, s).unwrap();
    path
}

#[test]
fn a_fault_through_a_cavity_is_a_chain_of_mesh_edges() {
    let g = read_grid(&faulted_grid()).unwrap();
    assert_eq!(g.faults.len(), 1);
    assert_eq!(g.faults[0].faces.len(), 2);
    let well = WellInput::column("W", 5, 4, 0.1);
    let h = build(&default_backend(), &g, &[well], &HybridOptions::default()).unwrap();
    let r = &h.report;
    // The cavity is columns I = 5..7, J = 4..6 (1-based): the fault's two
    // sides between J = 4 and 5 are inside it (split where the well is
    // near), ending at a free end.
    assert!(r.fault_segments >= 2, "{}", r.fault_segments);
    let degree = h.constraints.degrees();
    assert_eq!(
        degree.iter().filter(|&&d| d == 1).count(),
        1,
        "one free end"
    );
    let c = &r.transition.certificate;
    assert!(c.conforms() && c.sites_inside_cells, "{:?}", c.problems);
    assert_eq!(r.unmatched_faces, 0);
    assert_eq!(
        (
            r.transmissibility.negative,
            r.transmissibility.non_orthogonal
        ),
        (0, 0)
    );
    // Each fault segment in the cavity is an edge of the hybrid mesh.
    let edges: std::collections::HashSet<(u32, u32)> = h
        .mesh
        .cells
        .iter()
        .flat_map(|cell| (0..cell.len()).map(move |e| (cell[e], cell[(e + 1) % cell.len()])))
        .collect();
    // The fault line x = 60 from y = 30 to 50 is covered by mesh edges.
    let on_fault: f64 = edges
        .iter()
        .filter(|&&(a, b)| a < b || !edges.contains(&(b, a)))
        .map(|&(a, b)| (h.mesh.points[a as usize], h.mesh.points[b as usize]))
        .filter(|(p, q)| {
            p[0] == 60.0 && q[0] == 60.0 && p[1].min(q[1]) >= 30.0 && p[1].max(q[1]) <= 50.0
        })
        .map(|(p, q)| (p[1] - q[1]).abs())
        .sum();
    assert!((on_fault - 20.0).abs() < 1e-9, "{on_fault}");
    write("faulted", &h);
    let l = orthomesh::reservoir::layers::extrude(&h, &g).unwrap();
    assert_eq!(l.cells.len(), 2 * h.mesh.cells.len());
    write_layers("faulted", &h, &l);
}

#[test]
fn distorted_corner_point_cells_get_orthogonal_interfaces_from_the_lp() {
    // emerald: rotated, left-handed, distorted columns.
    let g = read_grid(&data("emerald.grdecl")).unwrap();
    let well = WellInput::column("W", 1, 1, 0.1);
    let h = build(&default_backend(), &g, &[well], &HybridOptions::default()).unwrap();
    let r = &h.report;
    let c = &r.transition.certificate;
    assert!(c.conforms() && c.sites_inside_cells, "{:?}", c.problems);
    assert_eq!(r.unmatched_faces, 0);
    assert_eq!(r.transmissibility.negative, 0);
    // The weights put every reservoir centre and radial site across an
    // interface on its dual line: every interface is orthogonal, though
    // zero weights leave emerald's centres off.
    assert!(r.transition.weights.method != "zero");
    assert_interfaces_orthogonal(r);
    write("emerald", &h);
}

#[test]
fn sheared_cells_get_orthogonal_interfaces_from_the_lp() {
    // Parallelogram cells: a centre is off the perpendicular bisectors of
    // its sides, so zero weights leave every cavity side non-orthogonal.
    let mut g = orthomesh::reservoir::CornerPointGrid::cartesian([11, 11, 1], [10.0, 10.0, 5.0]);
    for p in &mut g.coord {
        p[0] += 0.25 * p[1];
        p[3] += 0.25 * p[4];
    }
    let g = read_grid(&grdecl_file("sheared", &g, "")).unwrap();
    let well = WellInput::column("W", 6, 6, 0.1);
    let h = build(&default_backend(), &g, &[well], &HybridOptions::default()).unwrap();
    let r = &h.report;
    let c = &r.transition.certificate;
    assert!(c.conforms() && c.sites_inside_cells, "{:?}", c.problems);
    assert_interfaces_orthogonal(r);
    assert_eq!(r.transmissibility.negative, 0);
    write("sheared", &h);
}

#[test]
fn a_fault_polyline_is_clipped_to_the_cavity_with_free_ends() {
    let g = orthomesh::reservoir::CornerPointGrid::cartesian([12, 12, 1], [10.0, 10.0, 5.0]);
    let well = WellInput::column("W", 5, 5, 0.1);
    // The middle vertex (70, 75) lies on a cavity side: the chain stops
    // short of it as it does where the line leaves the cavity.
    let opts = HybridOptions {
        margin: 1,
        fault_lines: vec![vec![[20.0, 30.0], [70.0, 75.0], [110.0, 60.0]]],
        ..Default::default()
    };
    let h = build(&default_backend(), &g, &[well], &opts).unwrap();
    let r = &h.report;
    assert!(r.fault_segments > 0);
    let c = &r.transition.certificate;
    assert!(c.conforms() && c.sites_inside_cells, "{:?}", c.problems);
    assert_eq!(r.unmatched_faces, 0);
    // Free ends: the chain's ends have one segment each, away from the cavity sides.
    let free = h.constraints.degrees().iter().filter(|&&d| d == 1).count();
    assert_eq!(free, 2);
    write("fault-line", &h);
}

#[test]
fn a_cavity_that_cannot_grow_is_an_error_unless_allowed() {
    // concave.grdecl is a single column: nowhere to grow.
    let g = read_grid(&data("concave.grdecl")).unwrap();
    let well = WellInput::column("W", 0, 0, 0.1);
    let e = build(
        &default_backend(),
        &g,
        std::slice::from_ref(&well),
        &HybridOptions::default(),
    )
    .unwrap_err();
    assert!(e.to_string().contains("cannot grow"), "{e}");
    let opts = HybridOptions {
        allow_sites_outside: true,
        ..Default::default()
    };
    let h = build(&default_backend(), &g, &[well], &opts).unwrap();
    assert!(h.report.transition.certificate.conforms());
    assert!(h.report.transition.certificate.sites_outside > 0);
    assert!(h.report.notes.iter().any(|n| n.contains("cannot grow")));
}

#[test]
fn a_well_on_a_grid_line_and_one_inside_a_column() {
    // The first well sits exactly on a pillar (it touches four columns);
    // every well must keep its own column.
    let g = orthomesh::reservoir::CornerPointGrid::cartesian([14, 14, 1], [10.0, 10.0, 5.0]);
    let wells = [
        WellInput {
            name: "ON".into(),
            at: WellAt::Xy([40.0, 40.0]),
            radius: 0.1,
        },
        WellInput::column("IN", 10, 10, 0.1),
    ];
    let h = build(&default_backend(), &g, &wells, &HybridOptions::default()).unwrap();
    let r = &h.report;
    assert_eq!(r.cavities, 2);
    assert_eq!(r.unmatched_faces, 0);
    assert!(r.transition.certificate.conforms() && r.transition.certificate.sites_inside_cells);
}
