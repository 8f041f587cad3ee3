//! Property tests on random valid complexes: every output is certified, or a
//! clean error of an expected kind; never a panic.

mod common;
use common::*;
use orthomesh::backend::{default_backend, Backend};
use orthomesh::{Complex, Error};
use proptest::prelude::*;

/// Random points on a small integer lattice (so cocircular and collinear
/// degeneracies are common) and a random subset of their Delaunay edges
/// (which never cross and never pass through a vertex).
fn complex<B: Backend>(b: &B, pts: Vec<(i8, i8)>, keep: Vec<bool>) -> Option<Complex> {
    let mut points: Vec<[f64; 2]> = pts
        .iter()
        .map(|&(x, y)| [x as f64, y as f64 * 0.75])
        .collect();
    points.sort_by(|a, b| a.partial_cmp(b).unwrap());
    points.dedup();
    let dt = b.regular(&points, &vec![0.0; points.len()]).ok()?;
    let mut edges: Vec<(u32, u32)> = dt.edges().map(|(a, b)| (a.min(b), a.max(b))).collect();
    edges.sort();
    let segments = edges
        .iter()
        .zip(keep.iter().cycle())
        .filter(|(_, &k)| k)
        .map(|(&(a, b), _)| [a, b])
        .collect();
    Some(Complex::new(points, segments))
}

/// The mesh's cell count and sites outside, or None for no area.
fn check<B: Backend + ?Sized>(
    b: &B,
    cx: &Complex,
) -> Result<Option<(usize, usize)>, TestCaseError> {
    match run(b, cx, "proptest", true) {
        Ok(out) => {
            assert_certified(&out, "random complex");
            Ok(Some((
                out.mesh.cells.len(),
                out.report.certificate.sites_outside,
            )))
        }
        // Collinear point sets have no area; every other failure is a bug:
        // subsets of a Delaunay triangulation always admit zero weights.
        Err(Error::Degenerate(_)) => Ok(None),
        Err(e) => Err(TestCaseError::fail(format!("{} backend: {e}", b.name()))),
    }
}

proptest! {
    // A fixed seed keeps CI reproducible; raise the cases (and change the
    // seed) locally to explore: 1000 cases passed when this was written.
    #![proptest_config(ProptestConfig {
        cases: 64,
        rng_seed: proptest::test_runner::RngSeed::Fixed(2026),
        ..ProptestConfig::default()
    })]

    /// Through every backend compiled in, each certified.
    #[test]
    fn random_delaunay_subcomplexes_are_certified_on_every_backend(
        pts in prop::collection::vec((-6i8..6, -6i8..6), 3..28),
        keep in prop::collection::vec(any::<bool>(), 1..16),
    ) {
        if let Some(cx) = complex(&default_backend(), pts, keep) {
            let answers = orthomesh::backend::compiled()
                .iter()
                .map(|b| check(&**b, &cx))
                .collect::<Result<Vec<_>, _>>()?;
            // Lattices are cocircular: the triangulations, hence the
            // meshes, may differ between backends; the verdict may not.
            prop_assert!(
                answers.windows(2).all(|w| w[0].is_some() == w[1].is_some()),
                "{:?}",
                answers
            );
        }
    }
}
