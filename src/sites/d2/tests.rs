//! Unit tests of the 2D sites: exact predicates, served vertices.

use super::*;

/// Unweighted sites at the given points (each a vertex serving itself).
pub(crate) fn points_as_sites(points: &[[f64; 2]]) -> Sites {
    weighted_sites(points, &vec![0.0; points.len()])
}

/// Unweighted sites at the given points, site s free to move to
/// points[s] + f dirs[s] (f = 0 now).
pub(crate) fn sites_on_tracks(points: &[[f64; 2]], dirs: &[[f64; 2]]) -> Sites {
    let mut s = points_as_sites(points);
    for (k, &d) in dirs.iter().enumerate() {
        s.track[k].tb = 1.0;
        s.track[k].dir = d;
    }
    s
}

/// Sites at the given points with weights -w (each serves itself, a
/// vertex of weight w).
pub(crate) fn weighted_sites(points: &[[f64; 2]], w: &[f64]) -> Sites {
    let mut s = Sites {
        points: points.to_vec(),
        weights: w.to_vec(),
        ..Default::default()
    };
    for (i, &p) in points.iter().enumerate() {
        let track = Track {
            ta: 0.0,
            tb: 0.0,
            kind: Def::Free {
                p,
                anchor: i as u32,
            },
            dir: [0.0; 2],
        };
        let role = Role::Vertex {
            edge: (i as u32, i as u32),
            serves: vec![i as u32],
        };
        s.push(role, track, 0.0, false);
    }
    s
}

#[test]
fn power_test_is_the_incircle_test_for_zero_weights() {
    // d inside the circle through a, b, c (ccw): the edge is not regular.
    let s = points_as_sites(&[[0.0, 0.0], [2.0, 0.0], [0.0, 2.0], [1.5, 1.5], [3.0, 3.0]]);
    assert_eq!(s.power_test(0, 1, 2, 3), Ordering::Greater);
    assert_eq!(s.power_test(0, 1, 2, 4), Ordering::Less);
    assert_eq!(s.orient(0, 1, 2), Ordering::Greater);
    assert_eq!(s.exact_evaluations.load(Relaxed), 0);
}

#[test]
fn cocircular_sites_are_decided_exactly() {
    // Exactly cocircular: the intervals hold zero, the rationals say so.
    let s = points_as_sites(&[[0.0, 0.0], [0.1, 0.0], [0.1, 0.1], [0.0, 0.1]]);
    assert_eq!(s.power_test(0, 1, 2, 3), Ordering::Equal);
    assert!(s.exact_evaluations.load(Relaxed) > 0);
    // 0.1 is not 1/10: the site one ulp off the circle is decided too.
    let off = f64::from_bits(0.1f64.to_bits() + 1);
    let t = points_as_sites(&[[0.0, 0.0], [0.1, 0.0], [0.1, 0.1], [0.0, off]]);
    assert_eq!(t.power_test(0, 1, 2, 3), Ordering::Less);
}

#[test]
fn sites_on_a_radical_line_serve_both_ends_exactly() {
    let mut s = points_as_sites(&[[0.0, 0.0], [3.0, 1.0]]);
    s.weights = vec![0.5, -0.25];
    let track = Track {
        ta: 0.0,
        tb: 1.0,
        kind: Def::Line { i: 0, j: 1, t: 0.0 },
        dir: [0.0; 2],
    };
    let role = Role::Segment { seg: 0, left: true };
    s.push(role, track, 0.3, true);
    let (p, w) = s.exact(2);
    for v in 0..2 {
        let d = [&p[0] - q(s.points[v][0]), &p[1] - q(s.points[v][1])];
        let power = &d[0] * &d[0] + &d[1] * &d[1] - &w;
        assert_eq!(power, q(s.weights[v]), "vertex {v}");
    }
    // and the enclosures hold the exact values
    for (x, i) in p.iter().zip(&s.iv[2]) {
        assert!(q(i.lo) <= *x && *x <= q(i.hi));
    }
    assert!(q(s.iv[2][2].lo) <= w && w <= q(s.iv[2][2].hi));
}

#[test]
fn a_vertex_site_is_held_to_the_cell_it_serves_exactly() {
    // Vertex 0 at the origin, neighbours 1 at (1, 0) and 2 at (-1, 0):
    // its cell is the strip |x| <= 1/2 (zero weights); site 3 serves 0.
    let mut s = points_as_sites(&[[0.0, 0.0], [1.0, 0.0], [-1.0, 0.0]]);
    s.cell_walls = vec![vec![1, 2], vec![], vec![]];
    let track = Track {
        ta: 0.0,
        tb: 1.0,
        kind: Def::Free {
            p: [0.0, 5.0],
            anchor: 0,
        },
        dir: [1.0, 0.0],
    };
    let role = Role::Vertex {
        edge: (0, 0),
        serves: vec![0],
    };
    s.push(role, track, 0.25, true);
    assert!(s.in_served_cells(3));
    // on the wall x = 1/2 exactly: closed cell, still serves
    s.move_to(3, 0.5);
    assert!(s.in_served_cells(3));
    // one ulp beyond it: decided exactly, outside
    s.move_to(3, f64::from_bits(0.5f64.to_bits() + 1));
    assert!(!s.in_served_cells(3));
}

#[test]
fn inside_with_respect_to_a_neighbour() {
    let s = points_as_sites(&[[0.0, 0.0], [1.0, 0.0]]);
    assert!(s.inside_wrt(0, 1) && s.inside_wrt(1, 0));
}

#[test]
fn a_corner_site_serves_its_triangles_three_vertices_exactly() {
    // clockwise on purpose: the homogeneous form keeps H > 0 either way
    let mut s = points_as_sites(&[[0.0, 0.0], [1.0, 4.0], [3.0, 1.0]]);
    s.weights = vec![0.5, -0.25, 0.1];
    let kind = Def::Centre { tri: [0, 1, 2] };
    let track = Track {
        ta: 0.0,
        tb: 0.0,
        kind,
        dir: [0.0; 2],
    };
    let role = Role::Corner {
        segs: [(0, true), (1, true)],
    };
    s.push(role, track, 0.0, false);
    let (p, w) = s.exact(3);
    for v in 0..3 {
        let d = [&p[0] - q(s.points[v][0]), &p[1] - q(s.points[v][1])];
        let power = &d[0] * &d[0] + &d[1] * &d[1] - &w;
        assert_eq!(power, q(s.weights[v]), "vertex {v}");
    }
    for (x, i) in p.iter().zip(&s.iv[3]) {
        assert!(q(i.lo) <= *x && *x <= q(i.hi));
    }
    assert!(s.homogeneous(3)[3].sign() == Ordering::Greater);
    assert_eq!(s.served_by(3), [0, 1, 2]);
    // it stays where it is
    assert!(!s.step(3, &[]));
}
