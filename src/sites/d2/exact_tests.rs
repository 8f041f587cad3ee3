//! The exact fallbacks of the site predicates and constructions (dyadic
//! integers on homogeneous coordinates) against the rationals.

use super::tests::weighted_sites;
use super::{Def, Role, Sites, Track};
use crate::geom::Q;
use std::cmp::Ordering;
use std::sync::atomic::Ordering::Relaxed;

/// A cavity side (0, 3)-(0, 2)-(0, 1) and a well's vertex (1, 2) with its
/// neighbours, mirror images about y = 2 (generate field's cavities), as
/// weighted points, and five line sites: the first four (sites 6 to 9)
/// exactly co-orthogonal when the weights are symmetric about y = 2.
fn symmetric(w: &[f64]) -> Sites {
    let pts = [
        [0.0, 3.0],
        [0.0, 2.0],
        [0.0, 1.0],
        [1.0803847577293368, 2.3],
        [1.0, 2.0],
        [1.0803847577293368, 1.7000000000000002],
    ];
    let (t1, t2) = (-0.9003206314411143, 0.22150239020997187);
    let lines = [(3, 4, t1), (0, 1, t2), (4, 5, t1), (1, 2, t2), (0, 4, 0.1)];
    let mut s = weighted_sites(&pts, w);
    for (k, &(i, j, t)) in lines.iter().enumerate() {
        let kind = Def::Line { i, j, t };
        let track = Track {
            ta: t,
            tb: t,
            kind,
            dir: [0.0; 2],
        };
        let role = Role::Segment {
            seg: k as u32,
            left: true,
        };
        s.push(role, track, 0.0, false);
    }
    s
}

#[test]
fn exact_fallbacks_agree_with_the_rationals() {
    // A cavity side (0, 3)-(0, 2)-(0, 1) and a well's vertex (1, 2) with
    // its neighbours, mirror images about y = 2 (generate field's
    // cavities): the four segment sites are exactly co-orthogonal.
    // Unweighted, and under weights symmetric about y = 2, which keep
    // the four co-orthogonal.
    for sites in [
        symmetric(&[0.0; 6]),
        symmetric(&[0.3, -0.2, 0.3, 0.05, 0.01, 0.05]),
    ] {
        let n = sites.len();
        for (k, h) in (0..n).map(|k| (k, sites.homogeneous(k))) {
            let (p, wt) = sites.exact(k);
            let hq = h[3].exact();
            assert_eq!(h[0].exact(), &p[0] * &hq, "site {k}");
            assert_eq!(h[1].exact(), &p[1] * &hq, "site {k}");
            assert_eq!(h[2].exact(), &wt * &hq * &hq, "site {k}");
        }
        let reference = |a: usize, b: usize, c: usize, d: usize| {
            let (qd, wd) = sites.exact(d);
            let rows: Vec<[Q; 3]> = [a, b, c]
                .map(|s| {
                    let (p, w) = sites.exact(s);
                    let (dx, dy) = (&p[0] - &qd[0], &p[1] - &qd[1]);
                    let z = &dx * &dx + &dy * &dy - w + &wd;
                    [dx, dy, z]
                })
                .into();
            let r = |k: usize| [&rows[k][0], &rows[k][1], &rows[k][2]];
            crate::geom::det3_q([r(0), r(1), r(2)]).cmp(&Q::from(0))
        };
        let first = 6;
        let quads = [[0, 1, 2, 3], [1, 0, 2, 3], [0, 1, 2, 4], [4, 3, 1, 0]];
        for q4 in quads.map(|q| q.map(|k| first + k)) {
            let [a, b, c, d] = q4;
            assert_eq!(
                sites.power_test(a, b, c, d),
                reference(a, b, c, d),
                "{q4:?}"
            );
        }
        assert_eq!(
            sites.power_test(first, first + 1, first + 2, first + 3),
            Ordering::Equal
        );
        assert!(sites.exact_evaluations.load(Relaxed) > 0);
    }
}

#[test]
fn exact_centres_are_the_rationals_rounded() {
    // Weighted points and the line sites, under weights that are not
    // symmetric: the centre of every triple, against the power centre
    // solved in rationals.
    let s = symmetric(&[0.3, -0.2, 0.1, 0.05, 0.01, -0.05]);
    let reference = |t: [u32; 3]| {
        let [(p0, w0), (p1, w1), (p2, w2)] = t.map(|k| s.exact(k as usize));
        let u = [&p1[0] - &p0[0], &p1[1] - &p0[1]];
        let v = [&p2[0] - &p0[0], &p2[1] - &p0[1]];
        let det = &u[0] * &v[1] - &u[1] * &v[0];
        let ru = &u[0] * &u[0] + &u[1] * &u[1] - w1 + &w0;
        let rv = &v[0] * &v[0] + &v[1] * &v[1] - w2 + &w0;
        let two_det = det * Q::from(2);
        let x = &p0[0] + (&ru * &v[1] - &rv * &u[1]) / &two_det;
        let y = &p0[1] + (&rv * &u[0] - &ru * &v[0]) / &two_det;
        [crate::geom::f(&x), crate::geom::f(&y)]
    };
    let n = s.len() as u32;
    let mut checked = 0;
    for a in 0..n {
        for b in a + 1..n {
            for c in b + 1..n {
                if s.orient(a as usize, b as usize, c as usize) == Ordering::Equal {
                    continue;
                }
                assert_eq!(
                    s.centre_exact([a, b, c]),
                    reference([a, b, c]),
                    "{a} {b} {c}"
                );
                checked += 1;
            }
        }
    }
    assert!(checked > 150, "{checked}");
}

/// Line sites of random segments and weights: the semi-static filters,
/// the running-error filter and the fallbacks all agree with the rationals.
#[test]
fn filters_agree_with_the_rationals_on_random_sites() {
    use proptest::prelude::*;
    let pt = (-50.0f64..50.0, -50.0f64..50.0).prop_map(|(x, y)| [x, y]);
    let case = (
        prop::collection::vec(pt, 5),
        prop::collection::vec(-1.0f64..1.0, 5),
        prop::collection::vec(-2.0f64..2.0, 5),
    );
    proptest!(ProptestConfig::with_cases(24), |((pts, w, ts) in case)| {
        let mut s = weighted_sites(&pts, &w);
        let pairs = [(0, 1), (1, 2), (2, 3), (3, 4), (4, 0)];
        for (k, (&(i, j), &t)) in pairs.iter().zip(&ts).enumerate() {
            let kind = Def::Line { i, j, t };
            let track = Track { ta: t, tb: t, kind, dir: [0.0; 2] };
            let role = Role::Segment { seg: k as u32, left: true };
            s.push(role, track, 0.0, false);
        }
        let zero = Q::from(0);
        let first = pts.len();
        let ex: Vec<_> = (first..s.len()).map(|k| s.exact(k)).collect();
        let idx = |k: usize| k - first;
        for a in first..s.len() {
            for b in first..s.len() {
                for c in first..s.len() {
                    let (pa, pb, pc) = (&ex[idx(a)].0, &ex[idx(b)].0, &ex[idx(c)].0);
                    let o = (&pb[0] - &pa[0]) * (&pc[1] - &pa[1]) - (&pb[1] - &pa[1]) * (&pc[0] - &pa[0]);
                    prop_assert_eq!(s.orient(a, b, c), o.cmp(&zero));
                    for d in first..s.len() {
                        if [a, b, c].contains(&d) || s.common_vertex(&[a, b, c, d]).is_some() {
                            continue;
                        }
                        let (qd, wd) = &ex[idx(d)];
                        let rows: Vec<[Q; 3]> = [a, b, c]
                            .iter()
                            .map(|&x| {
                                let (p, wx) = &ex[idx(x)];
                                let (dx, dy) = (&p[0] - &qd[0], &p[1] - &qd[1]);
                                let z = &dx * &dx + &dy * &dy - wx + wd;
                                [dx, dy, z]
                            })
                            .collect();
                        let r = |k: usize| [&rows[k][0], &rows[k][1], &rows[k][2]];
                        let det = crate::geom::det3_q([r(0), r(1), r(2)]);
                        prop_assert_eq!(s.power_test(a, b, c, d), det.cmp(&zero));
                    }
                }
            }
        }
    });
}
