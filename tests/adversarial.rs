//! Inputs at the edges of what doubles and the LP can carry: each gets a
//! certified mesh or a clear error, never a panic.

mod common;
use common::*;
use orthomesh::backend::default_backend;
use orthomesh::{Complex, Error};

fn square_with_inner_segment(scale: f64, offset: f64) -> Complex {
    let pts = [
        [0.0, 0.0],
        [1.0, 0.0],
        [1.0, 1.0],
        [0.0, 1.0],
        [0.3, 0.4],
        [0.6, 0.5],
    ];
    let points = pts
        .iter()
        .map(|p| [p[0] * scale + offset, p[1] * scale + offset])
        .collect();
    Complex::new(points, vec![[0, 1], [1, 2], [2, 3], [3, 0], [4, 5]])
}

#[test]
fn any_scale_that_doubles_carry_is_meshed_the_same_way() {
    let b = default_backend();
    let reference = run(&b, &square_with_inner_segment(1.0, 0.0), "scale-1", true).unwrap();
    for (scale, offset) in [(1e150, 0.0), (1e-150, 0.0), (1e3, 6e6), (1e-3, 6e6)] {
        let tag = format!("scale-{scale:e}-{offset:e}");
        let out = run(&b, &square_with_inner_segment(scale, offset), &tag, true)
            .unwrap_or_else(|e| panic!("{tag}: {e}"));
        // As written: a 1 mm mesh at 6e6 m has coordinates good to 1e-9 m,
        // so face directions are good to about 1e-5.
        let tolerance = if offset == 0.0 { 1e-9 } else { 1e-4 };
        assert_certified_to(&out, &tag, tolerance);
        assert_eq!(out.mesh.cells.len(), reference.mesh.cells.len(), "{tag}");
        assert_eq!(out.report.certificate.sites_outside, 0, "{tag}");
    }
}

#[test]
fn out_of_range_and_degenerate_inputs_are_errors() {
    let b = default_backend();
    for (scale, offset) in [(1e300, 0.0), (1e-300, 0.0), (1e-310, 0.0)] {
        let e = run(&b, &square_with_inner_segment(scale, offset), "x", true)
            .err()
            .unwrap();
        assert!(matches!(e, Error::OutOfRange(_)), "{scale:e}: {e}");
    }
    let e = run(
        &b,
        &Complex::new(vec![[0.0, 0.0], [1.0, 0.0]], vec![[0, 1]]),
        "x",
        true,
    )
    .err()
    .unwrap();
    assert!(matches!(e, Error::Degenerate(_)), "{e}");
    // A triangle of height 1e-300: the LP gives no answer, zero weights
    // (exact) conform, but cells that thin cannot be written in doubles.
    let sliver = Complex::new(vec![[0.0, 0.0], [1.0, 0.0], [0.5, 1e-300]], vec![[0, 1]]);
    let e = run(&b, &sliver, "x", true).err().unwrap();
    assert!(
        matches!(e, Error::Certificate(ref m) if m.contains("double precision")),
        "{e}"
    );
    // A triangle 1e-8 thin is meshed: its cells are thin but far above
    // what doubles resolve.
    let thin = Complex::new(vec![[0.0, 0.0], [1.0, 0.0], [0.5, 1e-8]], vec![[0, 1]]);
    let out = run(&b, &thin, "thin", true).unwrap();
    assert!(
        out.report.certificate.conforms(),
        "{:?}",
        out.report.certificate
    );
}

/// A side split by a point a hair inside the domain (as split points of a
/// slanted side round): the hull then has a sliver beyond the side, whose
/// power centre lies beyond doubles. The sites outside the side are taken
/// nearer along their dual edges: meshed and certified.
#[test]
fn a_side_split_a_hair_inward_is_meshed() {
    let b = default_backend();
    for eps in [1e-300, 1e-17] {
        let cx = Complex::new(
            vec![[0.0, 0.0], [1.0, eps], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]],
            vec![[0, 1], [1, 2], [2, 3], [3, 4], [4, 0]],
        );
        let tag = format!("hair-{eps:e}");
        let out = run(&b, &cx, &tag, true).unwrap_or_else(|e| panic!("{tag}: {e}"));
        assert!(
            out.report.certificate.conforms(),
            "{tag}: {:?}",
            out.report.certificate
        );
    }
}
