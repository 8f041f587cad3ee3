//! Exact predicates on points and simplices in space (points, segments,
//! triangles of double points, by index): whether they meet, and the
//! coordinate plane a facet projects onto.

use super::exact::{orient, orient3};
use std::cmp::Ordering;

/// Whether three double points lie on one line (exactly: the cross
/// product of b - a and c - a is zero, each of its coordinates an exact 2D
/// orientation of the points projected along an axis).
pub fn collinear(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> bool {
    (0..3).all(|k| orient(drop_axis(k, a), drop_axis(k, b), drop_axis(k, c)) == Ordering::Equal)
}

/// Exact predicates on simplices of double points, by index.
pub struct Simplices<'a>(pub &'a [[f64; 3]]);

impl Simplices<'_> {
    fn p(&self, v: u32) -> [f64; 3] {
        self.0[v as usize]
    }

    fn o3(&self, a: u32, b: u32, c: u32, d: u32) -> Ordering {
        let p = [a, b, c, d].map(|v| self.p(v));
        // four points on one plane x, y or z = const: the usual tie between
        // neighbouring facets, which the adaptive test is slowest on
        if (0..3).any(|k| p[1..].iter().all(|x| x[k] == p[0][k])) {
            return Ordering::Equal;
        }
        orient3(p[0], p[1], p[2], p[3])
    }

    fn coplanar(&self, a: u32, b: u32, c: u32, d: u32) -> bool {
        self.o3(a, b, c, d) == Ordering::Equal
    }

    /// The coordinate plane a non-degenerate triangle projects onto
    /// without degenerating (the steepest such).
    fn axis(&self, a: u32, b: u32, c: u32) -> usize {
        plane_axis(self.p(a), self.p(b), self.p(c)).expect("a triangle of a validated facet")
    }

    /// 2D orientation of three points projected along `axis`.
    fn o2(&self, axis: usize, a: u32, b: u32, c: u32) -> Ordering {
        let f = |v: u32| drop_axis(axis, self.p(v));
        orient(f(a), f(b), f(c))
    }

    /// Whether closed simplices (1 to 3 vertices) intersect.
    fn meet(&self, s: &[u32], t: &[u32]) -> bool {
        let (s, t) = if s.len() <= t.len() { (s, t) } else { (t, s) };
        match (s, t) {
            ([x], [y]) => x == y,
            ([x], [p, q]) => self.on_segment(*x, *p, *q),
            ([x], [a, b, c]) => self.coplanar(*a, *b, *c, *x) && self.in_triangle(*x, [*a, *b, *c]),
            ([p, q], [r, u]) => self.segments_meet(*p, *q, *r, *u),
            ([p, q], [a, b, c]) => self.segment_meets_triangle(*p, *q, [*a, *b, *c]),
            ([a, b, c], [_, _, _]) => {
                let tt = [t[0], t[1], t[2]];
                let ss = [*a, *b, *c];
                (0..3).any(|k| self.segment_meets_triangle(ss[k], ss[(k + 1) % 3], tt))
                    || (0..3).any(|k| self.segment_meets_triangle(tt[k], tt[(k + 1) % 3], ss))
            }
            _ => unreachable!("simplices have 1 to 3 vertices"),
        }
    }

    fn on_segment(&self, x: u32, p: u32, q: u32) -> bool {
        let (x, p, q) = (self.p(x), self.p(p), self.p(q));
        collinear(p, q, x) && (0..3).all(|k| x[k] >= p[k].min(q[k]) && x[k] <= p[k].max(q[k]))
    }

    /// x (in the triangle's plane) in the closed triangle.
    fn in_triangle(&self, x: u32, [a, b, c]: [u32; 3]) -> bool {
        let k = self.axis(a, b, c);
        let o = [
            self.o2(k, a, b, x),
            self.o2(k, b, c, x),
            self.o2(k, c, a, x),
        ];
        !(o.contains(&Ordering::Greater) && o.contains(&Ordering::Less))
    }

    fn segments_meet(&self, p: u32, q: u32, r: u32, s: u32) -> bool {
        if !self.coplanar(p, q, r, s) {
            return false;
        }
        let (pp, pq) = (self.p(p), self.p(q));
        let Some(k) = [r, s].iter().find_map(|&x| plane_axis(pp, pq, self.p(x))) else {
            // all four on one line
            return self.on_segment(r, p, q)
                || self.on_segment(s, p, q)
                || self.on_segment(p, r, s)
                || self.on_segment(q, r, s);
        };
        let f = |v: u32| drop_axis(k, self.p(v));
        crate::geom::segments_meet(f(p), f(q), f(r), f(s))
    }

    fn segment_meets_triangle(&self, p: u32, q: u32, [a, b, c]: [u32; 3]) -> bool {
        let (op, oq) = (self.o3(a, b, c, p), self.o3(a, b, c, q));
        if op == Ordering::Equal && oq == Ordering::Equal {
            return self.in_triangle(p, [a, b, c])
                || self.in_triangle(q, [a, b, c])
                || (0..3).any(|k| {
                    let t = [a, b, c];
                    self.segments_meet(p, q, t[k], t[(k + 1) % 3])
                });
        }
        if op == oq {
            return false;
        }
        let o = [
            self.o3(p, q, a, b),
            self.o3(p, q, b, c),
            self.o3(p, q, c, a),
        ];
        !(o.contains(&Ordering::Greater) && o.contains(&Ordering::Less))
    }

    /// Whether the segment from v (a vertex of t) to a has points other
    /// than v in the closed simplex t.
    fn beyond_vertex(&self, v: u32, a: u32, t: &[u32]) -> bool {
        let mut others = [0u32; 2];
        let mut n = 0;
        for &x in t.iter().filter(|&&x| x != v).take(2) {
            others[n] = x;
            n += 1;
        }
        match others[..n] {
            // t a segment (v, b): overlap along one line, on b's side.
            [b] => collinear(self.p(v), self.p(b), self.p(a)) && self.same_direction(v, a, b),
            // t a triangle (v, b, c): a in its plane, within its cone at v.
            [b, c] => {
                if !self.coplanar(v, b, c, a) {
                    return false;
                }
                let k = self.axis(v, b, c);
                let (b, c) = if self.o2(k, v, b, c) == Ordering::Greater {
                    (b, c)
                } else {
                    (c, b)
                };
                self.o2(k, v, b, a) != Ordering::Less && self.o2(k, v, a, c) != Ordering::Less
            }
            _ => false,
        }
    }

    /// For collinear v, a, b (a not v): whether a and b lie on the same
    /// side of v, read off an axis along which a and v differ (comparing
    /// doubles is exact).
    fn same_direction(&self, v: u32, a: u32, b: u32) -> bool {
        let (v, a, b) = (self.p(v), self.p(a), self.p(b));
        (0..3)
            .find(|&k| a[k] != v[k])
            .is_some_and(|k| (a[k] > v[k]) == (b[k] > v[k]) && b[k] != v[k])
    }

    /// For a, b coplanar with the line vw: whether they lie on one side of it.
    fn same_side(&self, v: u32, w: u32, a: u32, b: u32) -> bool {
        let k = self.axis(v, w, a);
        self.o2(k, v, w, a) == self.o2(k, v, w, b)
    }

    /// For two coplanar triangles sharing at most one vertex: whether the
    /// line of an edge of one (through the shared vertex, if any) has the
    /// other's vertices, shared one aside, strictly beyond it, and its own
    /// third vertex strictly before it. They then meet in the shared vertex
    /// at most. A cheap exact sufficient test: grids of coplanar facets
    /// give many such pairs, and the general test is slow on them.
    fn separated_in_plane(&self, s: &[u32], t: &[u32], shared: &[u32]) -> bool {
        let ([a, b, c], [d, e, f]) = (s, t) else {
            return false;
        };
        let (s, t) = ([*a, *b, *c], [*d, *e, *f]);
        if t.iter()
            .any(|&x| !s.contains(&x) && !self.coplanar(*a, *b, *c, x))
        {
            return false;
        }
        let k = self.axis(s[0], s[1], s[2]);
        let splits = |p: [u32; 3], q: [u32; 3]| {
            (0..3).any(|i| {
                let (x, y, z) = (p[i], p[(i + 1) % 3], p[(i + 2) % 3]);
                if shared.iter().any(|v| *v != x && *v != y) {
                    return false; // the line must pass through the shared vertex
                }
                let own = self.o2(k, x, y, z);
                own != Ordering::Equal
                    && q.iter()
                        .filter(|v| !shared.contains(v))
                        .all(|&v| self.o2(k, x, y, v) == own.reverse())
            })
        };
        splits(s, t) || splits(t, s)
    }

    /// Whether two simplices (1 to 3 vertices) meet in more than the face
    /// their shared vertices span (exactly).
    pub fn improper(&self, s: &[u32], t: &[u32]) -> bool {
        // (fixed arrays: this runs for every nearby pair of facet simplices)
        let pick = |x: &[u32], keep: &dyn Fn(u32) -> bool| {
            let mut out = ([0u32; 3], 0);
            for &v in x.iter().filter(|&&v| keep(v)) {
                out.0[out.1] = v;
                out.1 += 1;
            }
            out
        };
        let (sh, n) = pick(s, &|v| t.contains(&v));
        let shared = &sh[..n];
        let (s1, ns) = pick(s, &|v| !shared.contains(&v));
        let (t1, nt) = pick(t, &|v| !shared.contains(&v));
        let (s1, t1) = (&s1[..ns], &t1[..nt]);
        if s1.is_empty() || t1.is_empty() {
            return false; // one is a face of the other
        }
        let g = self;
        // The vertices not shared strictly on one side of the other
        // triangle's plane: the simplices meet in the shared face only.
        let off = |a: &[u32], t: &[u32]| {
            let [x, y, z] = t[..] else {
                return false;
            };
            let first = g.o3(x, y, z, a[0]);
            first != Ordering::Equal && a[1..].iter().all(|&v| g.o3(x, y, z, v) == first)
        };
        if off(s1, t) || off(t1, s) {
            return false;
        }
        if shared.len() < 2 && self.separated_in_plane(s, t, shared) {
            return false;
        }
        match shared.len() {
            0 => g.meet(s, t),
            1 => {
                let v = shared[0];
                // The faces away from v, then the edges from v (a point of
                // such an edge other than v lies in the other simplex only
                // in its plane, inside its cone at v).
                g.meet(s1, t)
                    || g.meet(t1, s)
                    || s1.iter().any(|&a| g.beyond_vertex(v, a, t))
                    || t1.iter().any(|&a| g.beyond_vertex(v, a, s))
            }
            _ => {
                // A shared edge (v, w): two triangles fold onto each other
                // when coplanar with their third vertices on one side.
                let [v, w] = [shared[0], shared[1]];
                let (a, b) = (s1[0], t1[0]);
                g.coplanar(v, w, a, b) && g.same_side(v, w, a, b)
            }
        }
    }
}

/// The coordinate (0, 1, 2) whose drop keeps the triangle abc
/// non-degenerate, the one along which its plane is steepest; None for
/// collinear points.
pub fn plane_axis(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> Option<usize> {
    let u = [0, 1, 2].map(|k| b[k] - a[k]);
    let w = [0, 1, 2].map(|k| c[k] - a[k]);
    let normal = [0, 1, 2].map(|k| {
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        (u[i] * w[j] - u[j] * w[i]).abs()
    });
    (0..3)
        .filter(|&k| orient(drop_axis(k, a), drop_axis(k, b), drop_axis(k, c)) != Ordering::Equal)
        .max_by(|&i, &j| normal[i].total_cmp(&normal[j]))
}

/// A point with coordinate `axis` dropped (the others in cyclic order).
pub fn drop_axis(axis: usize, x: [f64; 3]) -> [f64; 2] {
    [x[(axis + 1) % 3], x[(axis + 2) % 3]]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn improper_meetings_of_triangles() {
        let p: Vec<[f64; 3]> = vec![
            [0.0, 0.0, 0.0],   // 0: a corner of the base triangle in z = 0
            [4.0, 0.0, 0.0],   // 1
            [0.0, 4.0, 0.0],   // 2
            [1.0, 1.0, 2.0],   // 3: above the base
            [2.0, 1.0, 3.0],   // 4: above the base
            [1.0, 1.0, -2.0],  // 5: below the base
            [1.0, 2.0, 0.0],   // 6: inside the base, in its plane
            [-1.0, -1.0, 0.0], // 7: outside the base, in its plane
            [0.0, -4.0, 0.0],  // 8: beyond edge 0-1, in the plane
            [5.0, 5.0, 5.0],   // 9: far above
            [6.0, 5.0, 5.0],   // 10
            [5.0, 6.0, 5.0],   // 11
            [8.0, 0.0, 0.0],   // 12: on the line of edge 0-1, beyond 1
            [-3.0, 0.0, 0.0],  // 13: on that line, behind 0
        ];
        let s = Simplices(&p);
        let base = [0, 1, 2];
        // one shared vertex, the rest strictly on one side: only the vertex
        assert!(!s.improper(&base, &[0, 3, 4]));
        // one shared vertex, piercing the base through its inside
        assert!(s.improper(&base, &[0, 3, 5]));
        // one shared vertex, lying in the base's plane over it
        assert!(s.improper(&base, &[0, 6, 1]));
        // one shared vertex, in the plane but outside it
        assert!(!s.improper(&base, &[0, 7, 8]));
        // no shared vertex: far apart, or piercing
        assert!(!s.improper(&base, &[9, 10, 11]));
        assert!(s.improper(&base, &[3, 5, 4]));
        // a shared edge: folded onto the base in its plane, or bent away
        assert!(s.improper(&base, &[0, 1, 6]));
        assert!(!s.improper(&base, &[0, 1, 8]));
        assert!(!s.improper(&base, &[0, 1, 3]));
        // segments from a shared vertex along one line: overlapping when
        // they leave it on the same side
        assert!(s.improper(&[0, 1], &[0, 12]));
        assert!(!s.improper(&[0, 1], &[0, 13]));
        assert!(s.improper(&base, &[0, 12]));
        assert!(!s.improper(&base, &[0, 13]));
        assert!(collinear(p[13], p[0], p[12]) && !collinear(p[0], p[1], p[6]));
        // the answers do not depend on the order
        for t in [[0, 3, 4], [0, 3, 5], [0, 6, 1], [3, 5, 4], [0, 1, 6]] {
            assert_eq!(s.improper(&base, &t), s.improper(&t, &base));
        }
    }

    #[test]
    fn coplanar_separation_never_hides_a_meeting() {
        // triangles on a small grid (many collinear and shared points), in
        // an axis plane and in a tilted one; sharing no vertex or one
        let mut u = crate::geom::uniform(7);
        let mut next = |m: u64| (u() * m as f64) as u64;
        let (mut separated, mut checked) = (0, 0);
        for tilted in [false, true] {
            let p: Vec<[f64; 3]> = (0..25)
                .map(|i| {
                    let (x, y) = ((i % 5) as f64, (i / 5) as f64);
                    [x, y, if tilted { 6.0 - x - y } else { 0.0 }]
                })
                .collect();
            let g = Simplices(&p);
            for _ in 0..4000 {
                let tri = |next: &mut dyn FnMut(u64) -> u64| loop {
                    let t = [0; 3].map(|_| next(25) as u32);
                    if g.o2(2, t[0], t[1], t[2]) != Ordering::Equal {
                        return t;
                    }
                };
                let (s, mut t) = (tri(&mut next), tri(&mut next));
                if next(2) == 0 {
                    t[0] = s[next(3) as usize]; // share a vertex (maybe)
                }
                if g.o2(2, t[0], t[1], t[2]) == Ordering::Equal {
                    continue;
                }
                let shared: Vec<u32> = s.iter().copied().filter(|v| t.contains(v)).collect();
                if shared.len() > 1 {
                    continue;
                }
                checked += 1;
                if !g.separated_in_plane(&s, &t, &shared) {
                    continue;
                }
                separated += 1;
                let meets = match shared[..] {
                    [] => g.meet(&s, &t),
                    [v] => {
                        let s1: Vec<u32> = s.iter().copied().filter(|&x| x != v).collect();
                        let t1: Vec<u32> = t.iter().copied().filter(|&x| x != v).collect();
                        g.meet(&s1, &t)
                            || g.meet(&t1, &s)
                            || s1.iter().any(|&a| g.beyond_vertex(v, a, &t))
                            || t1.iter().any(|&a| g.beyond_vertex(v, a, &s))
                    }
                    _ => unreachable!(),
                };
                assert!(
                    !meets,
                    "{s:?} and {t:?} (tilted {tilted}) meet beyond {shared:?}"
                );
            }
        }
        assert!(
            separated > 1000 && separated < checked,
            "{separated} of {checked}"
        );
    }
}
