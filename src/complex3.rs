//! The 3D constraint complex of a piecewise linear complex (TetGen's PLC):
//! points and facets, each facet a planar straight-line graph (polygons,
//! segments and points in one plane, with hole points), plus volume hole
//! points. Validation comes before any geometry and decides exactly.
//! Inside a facet, crossings and incidences are decided as in 2D, on the
//! facet projected to a coordinate plane; between facets, on their
//! triangulations (`Complex3::triangulate`): simplices of different facets
//! meet only in a common face.

use crate::backend::Backend;
use crate::complex::{distinct_with_extent, finite_in_range, Complex};
use crate::error::{Error, Result};
use crate::geom::{is_pos, orient, orient3, q, Q};
use std::cmp::Ordering;

/// One facet: everything in it lies in one plane.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Facet {
    /// Vertex cycles: polygons (3 or more vertices), segments (2), points (1).
    pub polygons: Vec<Vec<u32>>,
    /// Hole points in the facet's plane: the region around each is not part
    /// of the facet.
    pub holes: Vec<[f64; 3]>,
    /// The facet's boundary marker (0 when the file gives none).
    pub marker: i64,
}

/// A 3D complex of constraints, with the ids its file gave.
#[derive(Debug, Clone, Default)]
pub struct Complex3 {
    pub points: Vec<[f64; 3]>,
    /// The id of each point in the input file.
    pub vertex_ids: Vec<i64>,
    /// Facets, numbered from 1 in file order (as TetGen reports them).
    pub facets: Vec<Facet>,
    /// Volume hole points: the region around each is not meshed.
    pub holes: Vec<[f64; 3]>,
}

impl Complex3 {
    /// Checks what can be decided facet by facet: finite coordinates in
    /// range, distinct points, cycles without a repeated vertex, facets
    /// that are planar and not all on one line, and each facet valid as a
    /// 2D complex in its plane (exactly).
    pub fn validate(&self) -> Result<()> {
        self.validate_in_space()?;
        for f in 0..self.facets.len() {
            self.checked_facet_2d(f)?;
        }
        Ok(())
    }

    /// `validate` less the checks in each facet's plane.
    fn validate_in_space(&self) -> Result<()> {
        finite_in_range(&self.points, &self.vertex_ids)?;
        let holes = self
            .holes
            .iter()
            .chain(self.facets.iter().flat_map(|f| &f.holes));
        if holes.clone().any(|h| h.iter().any(|c| !c.is_finite())) {
            return Err(Error::BadFacets(
                "a hole point has a NaN or infinite coordinate".into(),
            ));
        }
        distinct_with_extent(&self.points, &self.vertex_ids)?;
        let mut repeated = vec![];
        let mut flat = vec![];
        let mut non_planar = vec![];
        for (f, facet) in self.facets.iter().enumerate() {
            let id = f as i64 + 1;
            for poly in &facet.polygons {
                let mut v = poly.clone();
                v.sort_unstable();
                if let Some(w) = v.windows(2).find(|w| w[0] == w[1]) {
                    repeated.push((id, self.vertex_ids[w[0] as usize]));
                }
            }
            match self.plane(facet) {
                Plane::Spans => {}
                Plane::Line if facet.polygons.iter().any(|p| p.len() >= 3) => flat.push(id),
                Plane::Line => {}
                Plane::Beyond(v) => non_planar.push((id, self.vertex_ids[v as usize])),
            }
        }
        if !repeated.is_empty() {
            let list: Vec<String> = repeated
                .iter()
                .map(|(f, v)| format!("facet {f} (vertex {v})"))
                .collect();
            return Err(Error::BadFacets(format!(
                "a polygon visits a vertex twice: {}",
                list.join(", ")
            )));
        }
        if !flat.is_empty() {
            return Err(Error::BadFacets(format!(
                "facets whose polygons lie on one line (no area): {flat:?}"
            )));
        }
        if !non_planar.is_empty() {
            let list: Vec<String> = non_planar
                .iter()
                .map(|(f, v)| format!("facet {f} (vertex {v} is off its plane)"))
                .collect();
            return Err(Error::BadFacets(format!(
                "facets that are not planar: {}",
                list.join(", ")
            )));
        }
        Ok(())
    }

    /// `facet_2d`, validated as a 2D complex (errors name the facet).
    fn checked_facet_2d(&self, f: usize) -> Result<Option<(Complex, Vec<u32>)>> {
        let flat = self.facet_2d(f);
        if let Some((cx, _)) = &flat {
            cx.validate().map_err(|e| Error::InFacet {
                facet: f as i64 + 1,
                error: Box::new(e),
            })?;
        }
        Ok(flat)
    }

    /// Facet f as a 2D complex in a coordinate plane, with the index here
    /// of each of its points: the facet's vertices with the coordinate
    /// dropped along which its plane is steepest (among those whose drop
    /// keeps it a plane). That is an affine bijection of the facet's plane,
    /// so orientations, crossings and incidences in it are decided exactly
    /// as in the plane. Segments: the polygons' edges (a two-vertex cycle
    /// is one segment, an edge shared by two polygons one segment),
    /// numbered from 1 in file order; one-vertex cycles are points. None
    /// for a facet without area (validated planar first).
    pub fn facet_2d(&self, f: usize) -> Option<(Complex, Vec<u32>)> {
        let facet = &self.facets[f];
        let mut global: Vec<u32> = facet.polygons.iter().flatten().copied().collect();
        global.sort_unstable();
        global.dedup();
        let [a, b, c] = self.spanning(&global)?;
        let p = |v: u32| self.points[v as usize];
        let axis = plane_axis(p(a), p(b), p(c))?;
        let flat = |x: [f64; 3]| drop_axis(axis, x);
        let local = |v: u32| global.binary_search(&v).expect("a facet vertex") as u32;
        let (mut segments, mut seen) = (vec![], std::collections::HashSet::new());
        for poly in &facet.polygons {
            let n = poly.len();
            let edges = if n >= 3 { n } else { n - 1 };
            for k in 0..edges {
                let (a, b) = (local(poly[k]), local(poly[(k + 1) % n]));
                if seen.insert((a.min(b), a.max(b))) {
                    segments.push([a, b]);
                }
            }
        }
        let mut cx = Complex::new(global.iter().map(|&v| flat(p(v))).collect(), segments);
        cx.vertex_ids = global
            .iter()
            .map(|&v| self.vertex_ids[v as usize])
            .collect();
        cx.segment_ids = (1..=cx.segments.len() as i64).collect();
        cx.holes = facet.holes.iter().map(|&h| flat(h)).collect();
        Some((cx, global))
    }

    /// The first non-collinear triple of these vertices.
    pub fn spanning(&self, vs: &[u32]) -> Option<[u32; 3]> {
        let p = |v: u32| self.points[v as usize];
        let &a = vs.first()?;
        let &b = vs.iter().find(|&&v| p(v) != p(a))?;
        let &c = vs.iter().find(|&&v| !collinear(p(a), p(b), p(v)))?;
        Some([a, b, c])
    }

    /// Whether a facet's vertices span a plane, lie on a line, or leave
    /// the plane of its first non-collinear triple (which vertex).
    fn plane(&self, facet: &Facet) -> Plane {
        let vs: Vec<u32> = facet.polygons.iter().flatten().copied().collect();
        let p = |v: u32| self.points[v as usize];
        let Some([a, b, c]) = self.spanning(&vs) else {
            return Plane::Line;
        };
        match vs
            .iter()
            .find(|&&v| orient3(p(a), p(b), p(c), p(v)) != Ordering::Equal)
        {
            Some(&v) => Plane::Beyond(v),
            None => Plane::Spans,
        }
    }
}

enum Plane {
    Spans,
    Line,
    Beyond(u32),
}

impl Complex3 {
    /// The point `near` moved onto the plane of triangle `t` of facet `f`
    /// (its coordinate along the plane's main axis recomputed from the
    /// plane), when it then lies strictly inside `t`, exactly in the facet's
    /// plane, and on no point of the complex; None otherwise.
    pub fn steiner_in(&self, f: usize, t: [u32; 3], near: [f64; 3]) -> Option<[f64; 3]> {
        let [a, b, c] = t.map(|v| self.points[v as usize]);
        let axis = plane_axis(a, b, c)?;
        let mut x = near;
        // the plane n.(x - a) = 0 solved for x[axis]
        let (u, w) = (
            [0, 1, 2].map(|k| b[k] - a[k]),
            [0, 1, 2].map(|k| c[k] - a[k]),
        );
        let n: [f64; 3] = std::array::from_fn(|k| {
            let (i, j) = ((k + 1) % 3, (k + 2) % 3);
            u[i] * w[j] - u[j] * w[i]
        });
        let off: f64 = (0..3)
            .filter(|&k| k != axis)
            .map(|k| n[k] * (x[k] - a[k]))
            .sum();
        x[axis] = a[axis] - off / n[axis];
        let flat = |p: [f64; 3]| drop_axis(axis, p);
        let side = orient(flat(a), flat(b), flat(c));
        let inside = [(a, b), (b, c), (c, a)]
            .iter()
            .all(|&(p, r)| orient(flat(p), flat(r), flat(x)) == side);
        if !inside {
            return None;
        }
        let spans = self.spanning(&self.facets[f].polygons.concat())?;
        let [p, r, s] = spans.map(|v| self.points[v as usize]);
        (orient3(p, r, s, x) == Ordering::Equal && !self.points.contains(&x)).then_some(x)
    }
}

/// Whether three double points lie on one line (exactly: the cross
/// product of b - a and c - a in rationals is zero).
fn collinear(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> bool {
    let d = |u: [f64; 3], k: usize| q(u[k]) - q(a[k]);
    let (u, v) = ([0, 1, 2].map(|k| d(b, k)), [0, 1, 2].map(|k| d(c, k)));
    (0..3).all(|k| {
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        &u[i] * &v[j] == &u[j] * &v[i]
    })
}

/// The simplicial complex of a validated PLC: each facet triangulated in
/// its plane (constrained Delaunay, no new points; regions outside its
/// polygons or around its hole points left out), the segments on no such
/// triangle, the points on no triangle or segment; each with its facet
/// (index into `Complex3::facets`).
#[derive(Debug, Clone, Default)]
pub struct Simplices3 {
    pub triangles: Vec<[u32; 3]>,
    pub triangle_facet: Vec<u32>,
    pub segments: Vec<[u32; 2]>,
    pub segment_facet: Vec<u32>,
    pub points: Vec<u32>,
    pub point_facet: Vec<u32>,
}

impl Complex3 {
    /// Validates, triangulates the facets, and checks that simplices of
    /// different facets meet only in a common face (exactly): else an
    /// error naming the facets.
    pub fn triangulate<B: Backend + ?Sized>(&self, backend: &B) -> Result<Simplices3> {
        self.validate_in_space()?;
        let mut out = Simplices3::default();
        for (f, facet) in self.facets.iter().enumerate() {
            let mut on_triangle = std::collections::HashSet::new();
            let mut on_edge = std::collections::HashSet::new();
            let area = facet.polygons.iter().any(|p| p.len() >= 3);
            if let Some((cx, global)) = self.checked_facet_2d(f)?.filter(|_| area) {
                let dom = crate::domain::build(backend, &cx).map_err(|e| Error::InFacet {
                    facet: f as i64 + 1,
                    error: Box::new(e),
                })?;
                for (t, tri) in dom.cdt.triangles.iter().enumerate() {
                    if dom.inside[t] {
                        let g = tri.map(|v| global[v as usize]);
                        for k in 0..3 {
                            on_triangle.insert(g[k]);
                            let (a, b) = (g[k], g[(k + 1) % 3]);
                            on_edge.insert((a.min(b), a.max(b)));
                        }
                        out.triangles.push(g);
                        out.triangle_facet.push(f as u32);
                    }
                }
            }
            for poly in &facet.polygons {
                if poly.len() == 2 {
                    let (a, b) = (poly[0].min(poly[1]), poly[0].max(poly[1]));
                    if on_edge.insert((a, b)) {
                        out.segments.push([a, b]);
                        out.segment_facet.push(f as u32);
                        on_triangle.extend([a, b]);
                    }
                }
            }
            for poly in &facet.polygons {
                if poly.len() == 1 && on_triangle.insert(poly[0]) {
                    out.points.push(poly[0]);
                    out.point_facet.push(f as u32);
                }
            }
        }
        let pairs = self.crossing_facets(&out);
        if pairs.is_empty() {
            Ok(out)
        } else {
            Err(Error::CrossingFacets { pairs })
        }
    }

    /// Pairs of facets (ids from 1) with simplices that meet other than in
    /// a common face: a sweep along x over bounding boxes, then exact tests.
    fn crossing_facets(&self, sc: &Simplices3) -> Vec<(i64, i64)> {
        let mut items: Vec<(Vec<u32>, u32)> = vec![];
        items.extend(
            sc.triangles
                .iter()
                .zip(&sc.triangle_facet)
                .map(|(t, &f)| (t.to_vec(), f)),
        );
        items.extend(
            sc.segments
                .iter()
                .zip(&sc.segment_facet)
                .map(|(s, &f)| (s.to_vec(), f)),
        );
        items.extend(
            sc.points
                .iter()
                .zip(&sc.point_facet)
                .map(|(&p, &f)| (vec![p], f)),
        );
        let bbox = |vs: &[u32]| {
            let pts: Vec<[f64; 3]> = vs.iter().map(|&v| self.points[v as usize]).collect();
            let (lo, hi) = crate::geom::bbox(&pts);
            [lo, hi]
        };
        let boxes: Vec<[[f64; 3]; 2]> = items.iter().map(|(vs, _)| bbox(vs)).collect();
        let mut order: Vec<usize> = (0..items.len()).collect();
        order.sort_unstable_by(|&i, &j| boxes[i][0][0].total_cmp(&boxes[j][0][0]));
        let mut active: Vec<usize> = vec![];
        let mut pairs = std::collections::BTreeSet::new();
        for &i in &order {
            active.retain(|&j| boxes[j][1][0] >= boxes[i][0][0]);
            for &j in &active {
                let (fi, fj) = (items[i].1, items[j].1);
                let overlap = (1..3)
                    .all(|k| boxes[i][0][k] <= boxes[j][1][k] && boxes[j][0][k] <= boxes[i][1][k]);
                if fi != fj && overlap && self.improper(&items[i].0, &items[j].0) {
                    pairs.insert((fi.min(fj) as i64 + 1, fi.max(fj) as i64 + 1));
                }
            }
            active.push(i);
        }
        pairs.into_iter().collect()
    }

    /// Whether two simplices (1 to 3 vertices) meet in more than the face
    /// their shared vertices span (exactly).
    fn improper(&self, s: &[u32], t: &[u32]) -> bool {
        let shared: Vec<u32> = s.iter().copied().filter(|v| t.contains(v)).collect();
        let rest =
            |x: &[u32]| -> Vec<u32> { x.iter().copied().filter(|v| !shared.contains(v)).collect() };
        let (s1, t1) = (rest(s), rest(t));
        if s1.is_empty() || t1.is_empty() {
            return false; // one is a face of the other
        }
        let g = Geometry(&self.points);
        match shared.len() {
            0 => g.meet(s, t),
            1 => {
                let v = shared[0];
                // The faces away from v, then the edges from v (a point of
                // such an edge other than v lies in the other simplex only
                // in its plane, inside its cone at v).
                g.meet(&s1, t)
                    || g.meet(&t1, s)
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

/// Exact predicates on simplices of double points, by index.
struct Geometry<'a>(&'a [[f64; 3]]);

impl Geometry<'_> {
    fn p(&self, v: u32) -> [f64; 3] {
        self.0[v as usize]
    }

    fn o3(&self, a: u32, b: u32, c: u32, d: u32) -> Ordering {
        orient3(self.p(a), self.p(b), self.p(c), self.p(d))
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
        let others: Vec<u32> = t.iter().copied().filter(|&x| x != v).collect();
        match others[..] {
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

    /// For collinear v, a, b: whether a and b lie on the same side of v.
    fn same_direction(&self, v: u32, a: u32, b: u32) -> bool {
        let (v, a, b) = (self.p(v), self.p(a), self.p(b));
        let d = (0..3)
            .map(|k| (q(a[k]) - q(v[k])) * (q(b[k]) - q(v[k])))
            .fold(Q::from(0), |s, x| s + x);
        is_pos(&d)
    }

    /// For a, b coplanar with the line vw: whether they lie on one side of it.
    fn same_side(&self, v: u32, w: u32, a: u32, b: u32) -> bool {
        let k = self.axis(v, w, a);
        self.o2(k, v, w, a) == self.o2(k, v, w, b)
    }
}

/// The coordinate (0, 1, 2) whose drop keeps the triangle abc
/// non-degenerate, the one along which its plane is steepest; None for
/// collinear points.
pub(crate) fn plane_axis(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> Option<usize> {
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
pub(crate) fn drop_axis(axis: usize, x: [f64; 3]) -> [f64; 2] {
    [x[(axis + 1) % 3], x[(axis + 2) % 3]]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube() -> Complex3 {
        let points: Vec<[f64; 3]> = (0..8)
            .map(|i| [(i & 1) as f64, (i >> 1 & 1) as f64, (i >> 2) as f64])
            .collect();
        let quads = [
            [0, 1, 3, 2],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 3, 7, 6],
            [0, 2, 6, 4],
            [1, 3, 7, 5],
        ];
        Complex3 {
            vertex_ids: (1..=8).collect(),
            points,
            facets: quads
                .iter()
                .map(|q| Facet {
                    polygons: vec![q.to_vec()],
                    ..Default::default()
                })
                .collect(),
            holes: vec![],
        }
    }

    #[test]
    fn a_cube_is_valid() {
        cube().validate().unwrap();
    }

    #[test]
    fn bad_complexes_name_what_is_wrong() {
        let mut c = cube();
        c.points[6][2] = 1.0 + f64::EPSILON;
        let e = c.validate().unwrap_err().to_string();
        assert!(e.contains("not planar") && e.contains("vertex 7"), "{e}");

        let mut c = cube();
        c.points[3] = c.points[0];
        let e = c.validate().unwrap_err();
        assert!(
            matches!(e, Error::DuplicateVertices { ref pairs } if pairs == &[(1, 4)]),
            "{e}"
        );

        // -0.0 is 0.0, with other points sorted between them.
        let mut c = cube();
        c.points[7] = [-0.0, 0.0, 0.0];
        let e = c.validate().unwrap_err();
        assert!(
            matches!(e, Error::DuplicateVertices { ref pairs } if pairs == &[(1, 8)]),
            "{e}"
        );

        let mut c = cube();
        c.points[2][1] = f64::NAN;
        assert!(matches!(c.validate(), Err(Error::NonFinite { vertices }) if vertices == [3]));

        let mut c = cube();
        c.facets[1].polygons[0] = vec![4, 5, 4];
        let e = c.validate().unwrap_err().to_string();
        assert!(e.contains("twice") && e.contains("facet 2"), "{e}");

        let mut c = cube();
        c.points.push([2.0, 0.0, 0.0]);
        c.vertex_ids.push(9);
        c.facets.push(Facet {
            polygons: vec![vec![0, 1, 8]],
            ..Default::default()
        });
        let e = c.validate().unwrap_err().to_string();
        assert!(e.contains("one line") && e.contains('7'), "{e}");

        // Inside a facet: a segment across the top face's square from
        // corner to corner and another one crossing it.
        let mut c = cube();
        c.facets[1].polygons.extend([vec![4, 7], vec![5, 6]]);
        let e = c.validate().unwrap_err().to_string();
        assert!(e.contains("facet 2") && e.contains("5 x 6"), "{e}");
        // A point in a slanted facet (x = y + z), then on its edge.
        let mut c = cube();
        c.points.push([0.75, 0.25, 0.5]);
        c.vertex_ids.push(9);
        c.facets.push(Facet {
            polygons: vec![vec![0, 5, 3], vec![8]],
            ..Default::default()
        });
        c.validate().unwrap();
        c.points[8] = [1.0, 0.5, 0.5];
        let e = c.validate().unwrap_err().to_string();
        assert!(e.contains("facet 7") && e.contains("9 on"), "{e}");
    }

    #[test]
    fn facets_triangulate_and_must_not_cross() {
        let b = crate::backend::default_backend();
        let sc = cube().triangulate(&b).unwrap();
        assert_eq!(sc.triangles.len(), 12);
        assert!(sc.segments.is_empty() && sc.points.is_empty());
        // A square through the cube's middle, its corners outside.
        let mut c = cube();
        let n = c.points.len() as u32;
        c.points.extend([
            [-1.0, -1.0, 0.5],
            [2.0, -1.0, 0.5],
            [2.0, 2.0, 0.5],
            [-1.0, 2.0, 0.5],
        ]);
        c.vertex_ids.extend(9..=12);
        c.facets.push(Facet {
            polygons: vec![vec![n, n + 1, n + 2, n + 3]],
            ..Default::default()
        });
        let e = c.triangulate(&b).unwrap_err();
        assert!(
            matches!(e, Error::CrossingFacets { ref pairs } if pairs.len() == 4 && pairs.iter().all(|p| p.1 == 7)),
            "{e}"
        );
        // A dangling segment from a corner into the cube: fine; through
        // the top face's interior: not.
        let mut c = cube();
        c.points.extend([[0.5, 0.5, 0.5], [0.5, 0.5, 2.0]]);
        c.vertex_ids.extend([9, 10]);
        c.facets.push(Facet {
            polygons: vec![vec![0, 8]],
            ..Default::default()
        });
        let sc = c.triangulate(&b).unwrap();
        assert_eq!(sc.segments, vec![[0, 8]]);
        c.facets.push(Facet {
            polygons: vec![vec![8, 9]],
            ..Default::default()
        });
        let e = c.triangulate(&b).unwrap_err().to_string();
        assert!(e.contains("2 x 8"), "{e}");
        // A triangle folded back onto the bottom face along its edge, and
        // one touching it at a corner from inside its plane.
        let mut c = cube();
        c.points.extend([[0.5, 0.5, 0.0], [-1.0, -0.5, 0.0]]);
        c.vertex_ids.extend([9, 10]);
        c.facets.push(Facet {
            polygons: vec![vec![0, 1, 8]],
            ..Default::default()
        });
        let e = c.triangulate(&b).unwrap_err().to_string();
        assert!(e.contains("1 x 7"), "{e}");
        c.facets[6].polygons = vec![vec![0, 9, 2]];
        assert!(
            c.triangulate(&b).is_ok(),
            "outside the square, sharing a corner"
        );
        c.points[9] = [0.25, 0.5, 0.0];
        let e = c.triangulate(&b).unwrap_err().to_string();
        assert!(e.contains("1 x 7"), "{e}");
    }

    #[test]
    fn facets_project_to_a_plane_that_keeps_them() {
        let c = cube();
        let (top, global) = c.facet_2d(1).unwrap();
        assert_eq!(global, vec![4, 5, 6, 7]);
        assert_eq!(
            top.points,
            vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]]
        );
        assert_eq!(top.segments, vec![[0, 1], [1, 3], [3, 2], [2, 0]]);
        assert_eq!(top.vertex_ids, vec![5, 6, 7, 8]);
    }
}
