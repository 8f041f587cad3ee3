//! Every shared constraint set, through the whole pipeline, with the answers
//! known for each (issue 2, item 10).

mod common;
use common::*;
use orthomesh::backend::{default_backend, Backend};
use orthomesh::Error;

/// Inputs where every site ends strictly inside its cell.
const SITES_INSIDE: [&str; 8] = [
    "box.poly",
    "butterfly.edg",
    "double_hex.poly",
    "double_hex2.poly",
    "double_hex3.poly",
    "fish.edg",
    "fish-and-rectangle.poly",
    "square_circle_hole.poly",
];

/// System 3 infeasible: long segments next to other features.
const SYS3_INFEASIBLE: [&str; 4] = ["A.poly", "face.poly", "la.poly", "lettre_A.edg"];

fn sites_inside<B: Backend>(b: &B) {
    for name in SITES_INSIDE {
        let out = run(b, &read(name), name, false).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_certified(&out, name);
        let c = &out.report.certificate;
        assert!(
            c.sites_inside_cells && c.sites_outside == 0,
            "{name}: {c:?}"
        );
        assert!(
            out.report.sites.min_site_margin > 0.0,
            "{name}: margin {}",
            out.report.sites.min_site_margin
        );
        eprintln!(
            "{name}: {} cells, weights {}, margin {:.3e}",
            out.mesh.cells.len(),
            out.report.weights.method,
            out.report.sites.min_site_margin
        );
    }
}

fn sys3_infeasible<B: Backend>(b: &B) {
    for name in SYS3_INFEASIBLE {
        let cx = read(name);
        match run(b, &cx, name, false) {
            Err(Error::SegmentsMissTheirDuals {
                segments,
                lp_error,
                proved,
            }) => {
                assert!(!segments.is_empty() && lp_error.is_none());
                // the verdict is proved exactly (a certificate), not the LP's
                assert!(!proved.is_empty(), "{name}");
                let msg = Error::SegmentsMissTheirDuals {
                    segments: segments.clone(),
                    lp_error,
                    proved,
                }
                .to_string();
                assert!(msg.contains("--allow-sites-outside"), "{msg}");
                assert!(msg.contains("proved exactly"), "{msg}");
            }
            other => panic!(
                "{name}: expected the sites-in-cells error, got {:?}",
                other.map(|o| o.report.certificate)
            ),
        }
        let out = run(b, &cx, name, true)
            .unwrap_or_else(|e| panic!("{name} with --allow-sites-outside: {e}"));
        assert_certified(&out, name);
        assert!(out.report.certificate.sites_outside > 0, "{name}");
        assert!(!out.report.sites.segments_missing_dual.is_empty(), "{name}");
    }
}

#[test]
fn shared_inputs_with_sites_inside_default_backend() {
    sites_inside(&default_backend());
}

#[test]
fn shared_inputs_where_system_3_is_infeasible_default_backend() {
    sys3_infeasible(&default_backend());
}

#[cfg(feature = "pure-rust")]
#[test]
fn shared_inputs_with_sites_inside_pure() {
    sites_inside(&orthomesh::backend::pure::Pure);
}

#[cfg(feature = "pure-rust")]
#[test]
fn shared_inputs_where_system_3_is_infeasible_pure() {
    sys3_infeasible(&orthomesh::backend::pure::Pure);
}

/// Every backend compiled in gives the same mesh size, weights method and
/// certificate on every shared input.
#[test]
fn backends_agree_on_the_shared_inputs() {
    let backends = orthomesh::backend::compiled();
    for name in SITES_INSIDE.iter().chain(&SYS3_INFEASIBLE) {
        let cx = read(name);
        let outs: Vec<_> = backends
            .iter()
            .map(|b| {
                run(&**b, &cx, name, true).unwrap_or_else(|e| panic!("{name} on {}: {e}", b.name()))
            })
            .collect();
        let key = |o: &orthomesh::Outcome<orthomesh::D2>| {
            let c = &o.report.certificate;
            (
                o.mesh.cells.len(),
                o.report.weights.method.clone(),
                c.conforms(),
                c.sites_inside_cells,
                c.sites_outside,
            )
        };
        for (b, o) in backends.iter().zip(&outs).skip(1) {
            assert_eq!(
                key(o),
                key(&outs[0]),
                "{name}: {} against {}",
                b.name(),
                backends[0].name()
            );
        }
    }
}

/// The double hexagons are closed polygons only (every vertex on two
/// segments): the paper's setting, where every site can be brought inside.
#[test]
fn closed_polygons_end_with_every_site_inside() {
    for name in ["double_hex.poly", "double_hex2.poly", "double_hex3.poly"] {
        let cx = read(name);
        assert!(cx.degrees().iter().all(|&d| d >= 2), "{name}");
        let out = run(&default_backend(), &cx, name, false).unwrap();
        assert_eq!(out.report.certificate.sites_outside, 0);
    }
}

/// fish-and-rectangle.poly has constraints inside a hole. They play no role
/// (issue 2, item 6): without them system 3 is feasible and every site ends
/// inside. (With them, a dense solver finds system 3 infeasible.)
#[test]
fn constraints_inside_holes_play_no_role() {
    let out = run(
        &default_backend(),
        &read("fish-and-rectangle.poly"),
        "fish-holes",
        false,
    )
    .unwrap();
    assert_eq!(
        (
            out.report.input.dropped_vertices,
            out.report.input.dropped_segments
        ),
        (2, 4)
    );
    assert!(out
        .report
        .input
        .notes
        .iter()
        .any(|n| n.contains("outside the domain")));
}

/// clusters.edg: eight segments meeting at one point, enclosing nothing, so
/// the convex hull is meshed; next to the hull edges system 3 fails, which
/// is said clearly, and the conforming mesh is certified when allowed.
#[test]
fn clusters_gets_a_clear_answer() {
    let cx = read("clusters.edg");
    let e =
        run(&default_backend(), &cx, "clusters", false).expect_err("system 3 is infeasible here");
    assert!(matches!(e, Error::SegmentsMissTheirDuals { .. }), "{e}");
    let out = run(&default_backend(), &cx, "clusters", true).unwrap();
    assert_certified(&out, "clusters");
    assert!(out.report.input.hull_edges_added > 0);
}

#[test]
fn demo_data_is_certified_with_zero_weights() {
    let cx = orthomesh::io::poly::parse(
        include_str!("../data/demo.poly"),
        std::path::Path::new("demo.poly"),
    )
    .unwrap();
    let out = run(&default_backend(), &cx, "demo", false).unwrap();
    assert_certified(&out, "demo");
    assert_eq!(out.report.weights.method, "zero");
    assert_eq!(out.mesh.cells.len(), 36);
    assert_eq!(out.report.certificate.sites_outside, 0);
}

/// The copies in tests/data equal the shared originals (when those are here).
#[test]
fn test_data_copies_are_unmodified() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    for folder in ["pslg", "grids", "plc3d", "decks/spe9"] {
        let original = root.join("../shared/data").join(folder);
        let Ok(entries) = std::fs::read_dir(&original) else {
            eprintln!("no shared data next to the repository: nothing to compare");
            return;
        };
        for e in entries {
            let path = e.unwrap().path();
            let name = path.file_name().unwrap().to_str().unwrap().to_string();
            assert_eq!(
                std::fs::read(&path).unwrap(),
                std::fs::read(root.join("tests/data").join(folder).join(&name)).unwrap(),
                "{folder}/{name} differs from the shared original"
            );
        }
    }
}

/// `--split-segments` on the letter A (Triangle's A.poly and CGAL's
/// lettre_A.edg): a few Steiner points on the segments that miss their
/// duals, then every site inside its cell; each split segment is a chain
/// of mesh edges whose inner vertices lie on it (or within rounding, as
/// the report says).
#[test]
fn split_segments_puts_every_site_inside_the_letter_a() {
    let b = default_backend();
    for name in ["A.poly", "lettre_A.edg"] {
        let input = read(name);
        let opts = orthomesh::Options {
            split_segments: true,
            ..Default::default()
        };
        let out = orthomesh::Mesher::new(&b)
            .options(opts)
            .conform(&input)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_certified(&out, name);
        assert_eq!(out.report.certificate.sites_outside, 0, "{name}");
        let split = out.report.split.as_ref().expect("split report");
        eprintln!("{name}: {split:?}");
        assert!(
            split.steiner_points > 0 && split.steiner_points <= 8,
            "{split:?}"
        );
        let vertices = out.constraints.points.len();
        assert_eq!(
            vertices,
            input.points.len() + split.steiner_points,
            "{name}"
        );
        for s in &split.segments {
            assert!(s.pieces >= 2 && s.off_line < 1e-15, "{s:?}");
            // Every Steiner point lies within its rounding of the input segment.
            let k = input.segment_ids.iter().position(|&id| id == s.id).unwrap();
            let [i, j] = input.segments[k].map(|v| input.points[v as usize]);
            let on = out.constraints.points[input.points.len()..]
                .iter()
                .filter(|p| {
                    let cross = (j[0] - i[0]) * (p[1] - i[1]) - (j[1] - i[1]) * (p[0] - i[0]);
                    let l2 = (j[0] - i[0]).powi(2) + (j[1] - i[1]).powi(2);
                    cross.abs() / l2 <= 1e-15
                        && (p[0] - i[0]) * (j[0] - i[0]) + (p[1] - i[1]) * (j[1] - i[1]) > 0.0
                        && (p[0] - j[0]) * (i[0] - j[0]) + (p[1] - j[1]) * (i[1] - j[1]) > 0.0
                })
                .count();
            assert!(
                on >= s.pieces - 1,
                "{name}: segment {} has {on} Steiner points on it",
                s.id
            );
        }
    }
}

/// TetGen's example PLC: read and validated as a 3D complex (the 3D
/// pipeline that would mesh it comes next, issue 6).
#[test]
fn tetgen_example_plc_reads_and_validates() {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/plc3d/example.poly");
    let cx = orthomesh::io::read_complex3(&path).unwrap();
    assert_eq!(cx.points.len(), 28);
    assert_eq!(cx.facets.len(), 23);
    // Facet 3: the front side with a window (a second polygon) and a
    // hole point in it.
    assert_eq!(cx.facets[2].polygons.len(), 2);
    assert_eq!(cx.facets[2].holes, vec![[1.0, 0.0, 2.25]]);
    assert_eq!(cx.facets[2].marker, 3);
    assert_eq!(cx.holes, vec![[1.0, 0.4, 2.25], [1.0, 0.4, 0.75]]);
    cx.validate().unwrap();
    // Its facets triangulated by every backend's 2D side, and found to
    // meet only in shared edges and vertices. Facet 3 (a square with a
    // square window) is an annulus of 8 triangles; every facet point is
    // on a triangle.
    for b in orthomesh::backend::compiled() {
        let sc = cx.triangulate(&*b).unwrap();
        let of = |f: u32| sc.triangle_facet.iter().filter(|&&g| g == f).count();
        assert_eq!(of(2), 8, "{}", b.name());
        assert!((0..23).all(|f| of(f) >= 2), "{}", b.name());
        assert!(sc.segments.is_empty() && sc.points.is_empty());
        // Facet 3: the 2 x 4 side less its 1.5 x 0.5 window.
        let area: f64 = (0..sc.triangles.len())
            .filter(|&t| sc.triangle_facet[t] == 2)
            .map(|t| {
                let [a, b, c] = sc.triangles[t].map(|v| cx.points[v as usize]);
                let u = [0, 1, 2].map(|k| b[k] - a[k]);
                let w = [0, 1, 2].map(|k| c[k] - a[k]);
                let n = [0, 1, 2]
                    .map(|k| u[(k + 1) % 3] * w[(k + 2) % 3] - u[(k + 2) % 3] * w[(k + 1) % 3]);
                (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt() / 2.0
            })
            .sum();
        assert!((area - 7.25).abs() < 1e-12, "{}: {area}", b.name());
    }
    // The 2D reader says what the file is.
    let e = orthomesh::io::read_complex(&path).unwrap_err().to_string();
    assert!(e.contains("dimension 3") && e.contains("TetGen"), "{e}");
}
