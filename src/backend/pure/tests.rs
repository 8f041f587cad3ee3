//! The pure engine against CGAL and against known answers.
use super::*;

fn rng_points(n: usize, seed: u64, weight: f64) -> (Vec<[f64; 2]>, Vec<f64>) {
    let mut r = Rng(seed);
    let mut u = move || (r.next() >> 11) as f64 / (1u64 << 53) as f64;
    let p: Vec<[f64; 2]> = (0..n).map(|_| [u(), u()]).collect();
    let w: Vec<f64> = (0..n).map(|_| weight * u() / n as f64).collect();
    (p, w)
}

/// Every interior edge locally regular, every hull edge convex, every
/// hidden point in no conflict: the regular triangulation.
fn check<P: Weighted>(p: &P, t: &Triangulation) {
    let hull: Vec<(u32, u32)> = t
        .edges()
        .filter(|&(a, b)| t.left_of(a, b).is_none() || t.left_of(b, a).is_none())
        .collect();
    for (a, b) in t.edges() {
        if let (Some(l), Some(r)) = (t.left_of(a, b), t.left_of(b, a)) {
            let c = t.apex(l, a, b);
            let e = t.apex(r, b, a);
            assert_ne!(p.power(a, b, c, e), Ordering::Greater, "edge {a}-{b}");
        }
    }
    for &(a, b) in &hull {
        // directed with the triangle on its left: no vertex right of it
        let (a, b) = if t.left_of(a, b).is_some() {
            (a, b)
        } else {
            (b, a)
        };
        for v in 0..p.len() as u32 {
            if !t.hidden.contains(&v) {
                assert_ne!(
                    p.orient(a, b, v),
                    Ordering::Less,
                    "hull edge {a}-{b}, vertex {v}"
                );
            }
        }
    }
    for (tri, tr) in t.triangles.iter().enumerate() {
        assert_eq!(
            p.orient(tr[0], tr[1], tr[2]),
            Ordering::Greater,
            "triangle {tri}"
        );
    }
}

fn sorted(t: &Triangulation) -> Vec<[u32; 3]> {
    let mut v: Vec<[u32; 3]> = t
        .triangles
        .iter()
        .map(|tr| {
            let k = (0..3).min_by_key(|&k| tr[k]).unwrap();
            [tr[k], tr[(k + 1) % 3], tr[(k + 2) % 3]]
        })
        .collect();
    v.sort_unstable();
    v
}

#[test]
fn random_weighted_points_give_a_regular_triangulation() {
    for (n, weight) in [(10, 0.0), (1000, 0.0), (3000, 1.0), (3000, 30.0)] {
        let (p, w) = rng_points(n, 7 + n as u64, weight);
        let pts = F64Points { p: &p, w: &w };
        let t = regular(&pts);
        check(&pts, &t);
        // Euler: 2n - 2 - hull triangles for the vertices kept
        let kept = n - t.hidden.len();
        assert!(t.triangles.len() <= 2 * kept - 5, "{n}");
        if weight > 1.0 {
            assert!(!t.hidden.is_empty(), "large weights hide points");
        }
    }
}

#[test]
fn duplicates_lattices_and_collinear_points() {
    // a 20 x 20 lattice: cocircular everywhere, with every point twice
    // (the second copy heavier for odd ids, equal otherwise)
    let mut p = vec![];
    let mut w = vec![];
    for i in 0..20 {
        for j in 0..20 {
            p.push([i as f64, j as f64]);
            w.push(0.0);
        }
    }
    for k in 0..400 {
        p.push(p[k]);
        w.push(if k % 2 == 1 { 0.5 } else { 0.0 });
    }
    let pts = F64Points { p: &p, w: &w };
    let t = regular(&pts);
    check(&pts, &t);
    assert_eq!(t.hidden.len(), 400);
    for k in 0..400u32 {
        if k % 2 == 1 {
            assert!(t.hidden.contains(&k), "{k}: the lighter copy");
        } else {
            // equal weights: one copy, either
            assert!(
                t.hidden.contains(&k) != t.hidden.contains(&(k + 400)),
                "{k}"
            );
        }
    }
    assert_eq!(t.triangles.len(), 2 * 19 * 19);
    // all on a line: no triangles, the lower hull's points kept
    let p: Vec<[f64; 2]> = (0..5).map(|i| [i as f64, 2.0 * i as f64]).collect();
    let w = vec![0.0, 0.0, -10.0, 0.0, 0.0];
    let t = regular(&F64Points { p: &p, w: &w });
    assert!(t.triangles.is_empty());
    assert_eq!(t.hidden, vec![2]);
}

#[test]
fn rational_input_gives_the_same_triangulation() {
    let (p, w) = rng_points(500, 3, 5.0);
    let t = regular(&F64Points { p: &p, w: &w });
    let pq: Vec<[Q; 2]> = p.iter().map(|x| x.map(q)).collect();
    let wq: Vec<Q> = w.iter().map(|&x| q(x)).collect();
    let tq = regular(&QPoints { p: &pq, w: &wq });
    assert_eq!(sorted(&t), sorted(&tq));
    assert_eq!(t.hidden, tq.hidden);
}

/// Every segment an edge, every other interior edge locally Delaunay,
/// triangles ccw, Euler's count: the constrained Delaunay triangulation.
fn check_cdt(p: &[[f64; 2]], segs: &[[u32; 2]], t: &Triangulation) {
    let w = vec![0.0; p.len()];
    let pts = F64Points { p, w: &w };
    let constrained: crate::FastSet<(u32, u32)> = segs
        .iter()
        .map(|s| (s[0].min(s[1]), s[0].max(s[1])))
        .collect();
    for s in segs {
        assert!(t.has_edge(s[0], s[1]), "{s:?}");
    }
    for (a, b) in t.edges() {
        if constrained.contains(&(a.min(b), a.max(b))) {
            continue;
        }
        if let (Some(l), Some(r)) = (t.left_of(a, b), t.left_of(b, a)) {
            let (c, e) = (t.apex(l, a, b), t.apex(r, b, a));
            assert_ne!(pts.power(a, b, c, e), Ordering::Greater, "edge {a}-{b}");
        }
    }
    for tr in &t.triangles {
        assert_eq!(pts.orient(tr[0], tr[1], tr[2]), Ordering::Greater);
    }
    assert_eq!(t.triangles.len(), 2 * p.len() - 2 - hull_size(t));
}

#[test]
fn constrained_delaunay_holds_every_segment() {
    for cx in [
        crate::generate::cavities(3, 2, 24.5),
        crate::generate::staggered_chains(6, 30, 0.1),
    ] {
        cx.validate().unwrap();
        let t = constrained_delaunay(&cx.points, &cx.segments).unwrap();
        check_cdt(&cx.points, &cx.segments, &t);
    }
    // a segment through a vertex is refused, not mis-triangulated
    let p = [[0.0, 0.0], [2.0, 0.0], [1.0, 0.0], [1.0, 1.0]];
    assert!(constrained_delaunay(&p, &[[0, 1]]).is_err());
}

fn hull_size(t: &Triangulation) -> usize {
    t.edges()
        .filter(|&(a, b)| t.left_of(a, b).is_none() || t.left_of(b, a).is_none())
        .count()
}

/// Near-degenerate inputs through both engines: both regular (checked
/// exactly), the same points hidden, the same number of triangles.
#[cfg(feature = "cgal")]
#[test]
fn same_certificates_as_cgal_on_degenerate_input() {
    use crate::backend::Backend;
    type Case = (&'static str, Vec<[f64; 2]>, Vec<f64>);
    let mut cases: Vec<Case> = vec![];
    // a cocircular lattice
    let lattice: Vec<[f64; 2]> = (0..400)
        .map(|k| [(k % 20) as f64, (k / 20) as f64])
        .collect();
    cases.push(("lattice", lattice.clone(), vec![0.0; 400]));
    // the lattice nudged by one ulp here and there
    let nudged: Vec<[f64; 2]> = lattice
        .iter()
        .enumerate()
        .map(|(k, p)| match k % 3 {
            0 => [p[0].next_up(), p[1]],
            1 => [p[0], p[1].next_down()],
            _ => *p,
        })
        .collect();
    cases.push(("nudged lattice", nudged, vec![0.0; 400]));
    // points on the lattice's vertices and edge midpoints with weights
    // that hide them, leave them on the lifted plane, or keep them
    let mut p = lattice.clone();
    let mut w = vec![0.0; 400];
    for k in 0..60 {
        let (i, j) = ((k % 19) as f64, (k / 19) as f64 + 1.0);
        p.push([i + 0.5, j]); // an edge midpoint: lifted plane at w = -0.25
        w.push([-1.0, -0.25, 0.5][k % 3]);
        p.push([i, j + 0.1]); // near a vertex, heavier or lighter
        w.push([-0.5, 0.5][k % 2]);
    }
    // a vertex again, heavier
    p.push([5.0, 5.0]);
    w.push(1.0);
    cases.push(("hidden on vertices and edges", p, w));
    // many points on one circle, and its centre heavier
    let mut p: Vec<[f64; 2]> = (0..64)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / 64.0;
            [a.cos(), a.sin()]
        })
        .collect();
    p.push([0.0, 0.0]);
    cases.push(("circle", p, vec![0.0; 65]));
    for (name, p, w) in cases {
        let ours = regular(&F64Points { p: &p, w: &w });
        let theirs = crate::backend::Cgal.regular(&p, &w).unwrap();
        let pts = F64Points { p: &p, w: &w };
        check(&pts, &ours);
        check(&pts, &theirs);
        assert_eq!(ours.hidden, theirs.hidden, "{name}");
        assert_eq!(ours.triangles.len(), theirs.triangles.len(), "{name}");
    }
}

/// Rational points that doubles cannot hold (thirds, sevenths) with
/// rational weights: the same exact triangulation as CGAL's Epeck.
#[cfg(feature = "cgal")]
#[test]
fn same_as_cgal_on_rational_input() {
    use crate::backend::Backend;
    let (p, w) = rng_points(300, 13, 2.0);
    let third = Q::from_signeds(1, 3);
    let seventh = Q::from_signeds(1, 7);
    let pq: Vec<[Q; 2]> = p
        .iter()
        .map(|x| [q(x[0]) + &third, q(x[1]) - &seventh])
        .collect();
    let wq: Vec<Q> = w.iter().map(|&x| q(x) * &third).collect();
    let ours = Pure.regular_exact(&pq, &wq).unwrap();
    let theirs = crate::backend::Cgal.regular_exact(&pq, &wq).unwrap();
    assert_eq!(sorted(&ours), sorted(&theirs));
    assert_eq!(ours.hidden, theirs.hidden);
    check(&QPoints { p: &pq, w: &wq }, &ours);
}

#[cfg(feature = "cgal")]
#[test]
fn same_as_cgal_on_generic_input() {
    use crate::backend::Backend;
    for (n, weight) in [(2000, 0.0), (2000, 3.0)] {
        let (p, w) = rng_points(n, 11, weight);
        let ours = regular(&F64Points { p: &p, w: &w });
        let theirs = crate::backend::Cgal.regular(&p, &w).unwrap();
        assert_eq!(sorted(&ours), sorted(&theirs), "{n} {weight}");
        assert_eq!(ours.hidden, theirs.hidden);
    }
}
