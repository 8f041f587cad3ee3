//! Property tests: random valid complexes are certified on every backend;
//! arbitrary segment soups (crossings, vertices on segments, duplicates,
//! near-degeneracies) give a certified mesh or a clean error of a kind the
//! input explains; never a panic. `PROPTEST_CASES=2000 cargo test --test
//! properties` explores further than CI does.

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
fn check(b: &dyn Backend, cx: &Complex) -> Result<Option<(usize, usize)>, TestCaseError> {
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

    /// Arbitrary segments between random points (a quarter of them a hair
    /// off a lattice): most soups are invalid, and each must get its error.
    #[test]
    fn arbitrary_segment_soups_give_a_certified_mesh_or_an_input_error(
        pts in prop::collection::vec((-40i16..40, -40i16..40, 0u8..4), 3..20),
        segs in prop::collection::vec((0usize..20, 0usize..20), 0..10),
    ) {
        let points: Vec<[f64; 2]> = pts
            .iter()
            .map(|&(x, y, nudge)| {
                let hair = if nudge == 0 { 1e-13 } else { 0.0 };
                [x as f64 * 0.25 + hair, y as f64 * 0.25]
            })
            .collect();
        let n = points.len();
        let segments = segs.iter().map(|&(a, b)| [(a % n) as u32, (b % n) as u32]).collect();
        let cx = Complex::new(points, segments);
        for b in orthomesh::backend::compiled() {
            match run(&*b, &cx, "soup", true) {
                Ok(out) => assert_certified(&out, "segment soup"),
                Err(
                    Error::DuplicateVertices { .. }
                    | Error::ZeroLengthSegments { .. }
                    | Error::RepeatedSegments { .. }
                    | Error::CrossingSegments { .. }
                    | Error::VertexOnSegment { .. }
                    | Error::Degenerate(_)
                    | Error::NoRegularConstrainedTriangulation { .. }
                    | Error::SolverLimit(_),
                ) => {}
                Err(Error::Certificate(m)) if m.contains("double precision") => {}
                Err(e) => return Err(TestCaseError::fail(format!("{} backend: {e}", b.name()))),
            }
        }
    }
}
