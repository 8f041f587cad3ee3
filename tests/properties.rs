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

fn check<B: Backend>(b: &B, cx: &Complex) -> Result<(), TestCaseError> {
    match run(b, cx, "proptest", true) {
        Ok(out) => {
            assert_certified(&out, "random complex");
            Ok(())
        }
        // Collinear point sets have no area; every other failure is a bug:
        // subsets of a Delaunay triangulation always admit zero weights.
        Err(Error::Degenerate(_)) => Ok(()),
        Err(e) => Err(TestCaseError::fail(format!("{e}"))),
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

    #[test]
    fn random_delaunay_subcomplexes_are_certified_cgal(
        pts in prop::collection::vec((-6i8..6, -6i8..6), 3..28),
        keep in prop::collection::vec(any::<bool>(), 1..16),
    ) {
        let b = default_backend();
        if let Some(cx) = complex(&b, pts, keep) {
            check(&b, &cx)?;
        }
    }
}
