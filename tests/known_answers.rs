//! Hand-built cases with known answers.

mod common;
use common::*;
use orthomesh::backend::default_backend;
use orthomesh::{Complex, Error};

/// The "mother of all examples": an outer triangle, a shrunken inner copy,
/// and all twelve edges of its cyclically twisted triangulation, which is
/// not regular. With every edge a constraint no regular constrained
/// triangulation exists: system 1 is infeasible.
#[test]
fn mother_of_all_examples_has_no_regular_constrained_triangulation() {
    let outer = [[0.0, 0.0], [4.0, 0.0], [2.0, 3.5]];
    let c = [2.0, 3.5 / 3.0];
    let inner: Vec<[f64; 2]> = outer
        .iter()
        .map(|p| [c[0] + 0.3 * (p[0] - c[0]), c[1] + 0.3 * (p[1] - c[1])])
        .collect();
    let points: Vec<[f64; 2]> = outer.iter().copied().chain(inner).collect();
    let mut segs = vec![];
    for i in 0..3u32 {
        let j = (i + 1) % 3;
        segs.push([i, j]); // outer
        segs.push([3 + i, 3 + j]); // inner
        segs.push([i, 3 + i]); // spoke
        segs.push([i, 3 + j]); // twisted diagonal
    }
    let cx = Complex::new(points, segs);
    cx.validate().unwrap();
    match run(&default_backend(), &cx, "mother", true) {
        Err(Error::NoRegularConstrainedTriangulation {
            segments,
            proof_rows,
        }) => {
            assert!(!segments.is_empty());
            // proved exactly (a certificate), not read off the LP's margin
            assert!(proof_rows.is_some_and(|n| n > 0), "{proof_rows:?}");
        }
        other => panic!(
            "expected no regular constrained triangulation, got {:?}",
            other.map(|o| o.report.weights)
        ),
    }
    // The dense LP of tests/common/dense.rs agrees: no margin.
    let m1 = dense::dense_margin(&cx.points, &cx.segments, false);
    assert!(m1.is_some_and(|m| m < 1e-5), "{m1:?}");
    // Untwisting one diagonal makes it regular again.
    let mut cx2 = cx.clone();
    cx2.segments[11] = [0, 5]; // P0-Q2 instead of P2-Q0
    let out = run(&default_backend(), &cx2, "mother-untwisted", true).unwrap();
    assert_certified(&out, "mother-untwisted");
    let m1 = dense::dense_margin(&cx2.points, &cx2.segments, false);
    assert!(m1.is_some_and(|m| m > 1e-3), "{m1:?}");
}

/// A segment that is not a Delaunay edge: the long diagonal of a flat
/// rhombus. Zero weights cannot work; the LP finds weights and every site
/// ends in its cell.
#[test]
fn a_non_delaunay_segment_needs_the_lp() {
    let cx = Complex::new(
        vec![[0.0, 0.0], [4.0, 0.0], [2.0, 1.0], [2.0, -1.0]],
        vec![[0, 1]],
    );
    let out = run(&default_backend(), &cx, "rhombus", false).unwrap();
    assert_certified(&out, "rhombus");
    assert_ne!(out.report.weights.method, "zero");
    assert!(out.report.weights.max_abs_weight > 0.0);
    assert_eq!(out.report.certificate.sites_outside, 0);
    assert_eq!(out.report.input.hull_edges_added, 4);
}

/// A free end (case 2) and an isolated vertex (case 3) inside a square.
#[test]
fn free_ends_and_isolated_vertices_get_extra_sites() {
    let cx = Complex::new(
        vec![
            [0.0, 0.0],
            [10.0, 0.0],
            [10.0, 10.0],
            [0.0, 10.0],
            [3.0, 3.0],
            [5.0, 4.0],
            [7.0, 7.0],
        ],
        vec![[0, 1], [1, 2], [2, 3], [3, 0], [4, 5]],
    );
    let out = run(&default_backend(), &cx, "free-ends", true).unwrap();
    assert_certified(&out, "free-ends");
    // two free ends (one site each, possibly shared) and one isolated vertex (three)
    assert!(
        out.report.sites.vertex_sites >= 4,
        "{}",
        out.report.sites.vertex_sites
    );
}

#[test]
fn bad_inputs_get_errors_naming_items() {
    let b = default_backend();
    let square = vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
    let e = run(
        &b,
        &Complex::new(square.clone(), vec![[0, 2], [1, 3]]),
        "x",
        true,
    )
    .err()
    .unwrap();
    assert_eq!(
        e.to_string(),
        "segments that cross, overlap or touch other than at a shared endpoint: 0 x 1"
    );
    let e = run(
        &b,
        &Complex::new(vec![[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]], vec![[0, 1]]),
        "x",
        true,
    )
    .err()
    .unwrap();
    assert!(matches!(e, Error::Degenerate(_)), "{e}");
}

/// The field of issue 21 (cavities of 16 unit sides, a well off centre, a
/// fault with two free ends): 31 segments a cavity, strictly Gabriel, so
/// zero weights; every site inside its cell, two extra sites per fault.
#[test]
fn a_field_of_cavities_needs_zero_weights_and_two_extra_sites_each() {
    let cx = orthomesh::generate::field(3, 2, 0, 7);
    assert_eq!((cx.segments.len(), cx.holes.len()), (6 * 31, 6));
    let out = run(&default_backend(), &cx, "field", false).expect("meshes");
    assert_certified(&out, "field");
    assert_eq!(out.report.weights.method, "zero");
    assert_eq!(out.report.sites.vertex_sites, 6 * 2);
    let with_points = orthomesh::generate::field(3, 2, 2, 7);
    assert_eq!(with_points.points.len(), cx.points.len() + 6 * 2);
}

/// Two isolated points a cavity, near its side: their extra sites crowd
/// each other. A vertex site outside its cell moves to the sampled place
/// of its dual edge farthest inside its faces (was: five fixed fractions,
/// which left 19 of field 6x6's sites outside; 4 since).
#[test]
fn crowded_extra_sites_mostly_find_their_cells() {
    let cx = orthomesh::generate::field(6, 6, 2, 7);
    let out = run(&default_backend(), &cx, "field-points", true).expect("meshes");
    assert_certified(&out, "field with points");
    let outside = out.report.certificate.sites_outside;
    eprintln!(
        "field 6x6, 2 points a cavity: {outside} of {} sites outside",
        out.report.sites.placed
    );
    assert!(outside <= 8, "{outside} sites outside");
}

/// A square whose sides are cut 2 from each corner: with corner sites, the
/// power centre of each corner's triangle, (1, 1) from the corner, is one
/// site serving both sides there, and its cell is the only one at the
/// corner (two cells meet there without). Certified on every backend.
#[test]
fn a_corner_site_owns_each_convex_corner() {
    use orthomesh::backend::compiled;
    use orthomesh::{Mesher, Options};
    let mut points = vec![];
    for k in 0..4 {
        let rot = |[x, y]: [f64; 2]| match k {
            0 => [x, y],
            1 => [10.0 - y, x],
            2 => [10.0 - x, 10.0 - y],
            _ => [y, 10.0 - x],
        };
        points.extend([[0.0, 0.0], [2.0, 0.0], [8.0, 0.0]].map(rot));
    }
    let segments = (0..12u32).map(|k| [k, (k + 1) % 12]).collect();
    let cx = Complex::new(points, segments);
    for b in compiled() {
        let owners = |corner_sites: bool| {
            let out = Mesher::new(&*b)
                .options(Options {
                    corner_sites,
                    ..Default::default()
                })
                .conform(&cx)
                .unwrap();
            assert_certified(&out, "square corners");
            assert_eq!(out.report.certificate.sites_outside, 0);
            let m = &out.mesh;
            let at = |p: [f64; 2]| {
                let cells = m
                    .cells
                    .iter()
                    .enumerate()
                    .filter(|(_, c)| c.iter().any(|&v| m.points[v as usize] == p));
                cells.map(|(k, _)| m.sites[k]).collect::<Vec<_>>()
            };
            (at([0.0, 0.0]), at([10.0, 10.0]), m.cells.len())
        };
        let (origin, far, n) = owners(true);
        assert_eq!(origin, vec![[1.0, 1.0]], "{}", b.name());
        assert_eq!(far, vec![[9.0, 9.0]], "{}", b.name());
        let (origin, _, n0) = owners(false);
        assert_eq!(origin.len(), 2, "{}", b.name());
        // one site for two at each of the four corners
        assert_eq!(n0 - n, 4, "{}", b.name());
    }
}
