//! The CGAL shim across the FFI: whole batches in, flat arrays out, C++
//! exceptions as errors. `scripts/valgrind.sh` runs this file under
//! valgrind (memcheck), so it exercises every entry point and every throw.
#![cfg(feature = "cgal")]

use orthomesh::backend::{Backend, Cgal, Triangulation};
use orthomesh::Error;
use orthomesh::Q;

fn random(n: usize, seed: u64) -> Vec<f64> {
    let mut u = orthomesh::generate::uniform(seed);
    (0..n).map(|_| u()).collect()
}

/// Every index a vertex or hidden, once; triangles counter-clockwise;
/// adjacency symmetric (via left_of).
fn assert_sound(t: &Triangulation, points: &[[f64; 2]]) {
    let mut seen = vec![false; points.len()];
    for tri in &t.triangles {
        let [a, b, c] = tri.map(|v| points[v as usize]);
        let o = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        assert!(o > 0.0, "triangle {tri:?} is not counter-clockwise");
        for k in 0..3 {
            seen[tri[k] as usize] = true;
            let (x, y) = (tri[k], tri[(k + 1) % 3]);
            assert!(t.left_of(x, y).is_some());
        }
    }
    for &h in &t.hidden {
        assert!(!seen[h as usize], "hidden {h} is a vertex");
        seen[h as usize] = true;
    }
    assert!(
        seen.iter().all(|&s| s),
        "an index is neither vertex nor hidden"
    );
}

#[test]
fn regular_triangulation_of_a_large_batch_with_hidden_points() {
    let n = 20_000;
    let r = random(3 * n, 7);
    let mut points: Vec<[f64; 2]> = (0..n).map(|i| [r[3 * i], r[3 * i + 1]]).collect();
    let mut weights: Vec<f64> = (0..n).map(|i| 1e-5 * r[3 * i + 2]).collect();
    // a duplicate point and a point with a very negative weight: both hidden
    points.push(points[0]);
    weights.push(weights[0] - 1.0);
    points.push([0.5, 0.5]);
    weights.push(-1.0);
    let t = Cgal.regular(&points, &weights).unwrap();
    assert_sound(&t, &points);
    assert!(t.hidden.contains(&(n as u32)) && t.hidden.contains(&(n as u32 + 1)));
}

#[test]
fn degenerate_batches() {
    // empty, one point, collinear points: no triangle, nothing lost
    for pts in [
        vec![],
        vec![[1.0, 2.0]],
        vec![[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]],
    ] {
        let t = Cgal.regular(&pts, &vec![0.0; pts.len()]).unwrap();
        assert!(t.triangles.is_empty());
        assert!(t.hidden.is_empty());
    }
}

#[test]
fn constrained_delaunay_keeps_its_segments() {
    let points = vec![[0.0, 0.0], [4.0, 0.0], [2.0, 1.0], [2.0, -1.0], [2.0, 3.0]];
    let t = Cgal.constrained_delaunay(&points, &[[0, 1]]).unwrap();
    assert_sound(&t, &points);
    assert!(t.has_edge(0, 1) && !t.has_edge(2, 3));
}

#[test]
fn exact_rational_input() {
    let q = |s: &str| s.parse::<Q>().unwrap();
    let points = [
        [q("0"), q("0")],
        [q("1"), q("0")],
        [q("0"), q("1")],
        [q("1/3"), q("1/3")],
    ];
    let weights = [q("0"), q("0"), q("0"), q("-1/1000")];
    let t = Cgal.regular_exact(&points, &weights).unwrap();
    assert_eq!(t.triangles.len(), 3);
    assert!(t.hidden.is_empty());
}

#[test]
fn every_throw_in_the_shim_is_an_error() {
    let backend_error = |r: orthomesh::Result<Triangulation>, what: &str| match r {
        Err(Error::Backend(m)) => assert!(m.contains(what), "{m}"),
        other => panic!("expected a backend error with '{what}', got {other:?}"),
    };
    let square = vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
    let mut bad = square.clone();
    bad[2][0] = f64::NAN;
    backend_error(Cgal.regular(&bad, &[0.0; 4]), "is not finite");
    backend_error(
        Cgal.regular(&square, &[0.0, f64::INFINITY, 0.0, 0.0]),
        "is not finite",
    );
    backend_error(Cgal.constrained_delaunay(&bad, &[[0, 1]]), "is not finite");
    // crossing diagonals: CGAL would add their intersection point
    backend_error(
        Cgal.constrained_delaunay(&square, &[[0, 2], [1, 3]]),
        "the segments intersect",
    );
    backend_error(
        Cgal.constrained_delaunay(&square, &[[0, 9]]),
        "out of range",
    );
    let mut dup = square.clone();
    dup.push(square[0]);
    backend_error(
        Cgal.constrained_delaunay(&dup, &[[4, 1]]),
        "duplicate point",
    );
}

#[test]
fn regular_triangulation_3_batch_and_throws() {
    use orthomesh::backend::Backend;
    let n = 5_000;
    let r = random(4 * n, 11);
    let mut points: Vec<[f64; 3]> = (0..n)
        .map(|i| [r[4 * i], r[4 * i + 1], r[4 * i + 2]])
        .collect();
    let mut weights: Vec<f64> = (0..n).map(|i| 1e-4 * r[4 * i + 3]).collect();
    // Hidden by its weight. (Not a duplicate point, as the unit tests
    // have: under valgrind, which ignores the rounding modes CGAL's
    // interval filters set, CGAL 3D then keeps both copies.)
    points.push([0.5, 0.5, 0.5]);
    weights.push(-1.0);
    let t = Cgal.regular3(&points, &weights).unwrap();
    assert_eq!(t.hidden, vec![n as u32]);
    let mut seen = vec![false; n + 1];
    for tet in &t.tets {
        for &v in tet {
            seen[v as usize] = true;
        }
    }
    assert!(seen[..n].iter().all(|&s| s));
    let flat: Vec<[f64; 3]> = (0..6).map(|i| [i as f64, (i * i) as f64, 0.0]).collect();
    match Cgal.regular3(&flat, &[0.0; 6]) {
        Err(Error::Backend(m)) => assert!(m.contains("coplanar"), "{m}"),
        other => panic!("expected a backend error, got {other:?}"),
    }
    let mut bad = flat.clone();
    bad[1][1] = f64::INFINITY;
    match Cgal.regular3(&bad, &[0.0; 6]) {
        Err(Error::Backend(m)) => assert!(m.contains("is not finite"), "{m}"),
        other => panic!("expected a backend error, got {other:?}"),
    }
}

#[test]
fn regular_triangulation_3_of_exact_rationals() {
    use orthomesh::backend::Backend;
    use orthomesh::{q, Q};
    // A unit cube's corners and its centre at weight 1/3: 6 pyramids, 12
    // tetrahedra. Halfway from the centre to the bottom face the lower hull
    // of the lifts is at (3/4 - 1/3 + 1) / 2 = 17/24; a point there with
    // weight -1/5 is lifted to 9/16 + 1/5 above it: hidden.
    let mut points: Vec<[Q; 3]> = (0..8)
        .map(|k| [k & 1, (k >> 1) & 1, (k >> 2) & 1].map(|c| Q::from(c as i64)))
        .collect();
    let mut weights: Vec<Q> = vec![Q::from(0); 8];
    points.push([q(0.5), q(0.5), q(0.5)]);
    weights.push(Q::from(1) / Q::from(3));
    points.push([q(0.5), q(0.5), q(0.25)]);
    weights.push(-Q::from(1) / Q::from(5));
    let t = Cgal.regular3_exact(&points, &weights).unwrap();
    assert_eq!(t.hidden, vec![9]);
    assert_eq!(t.tets.len(), 12);
}
