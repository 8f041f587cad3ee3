//! The triangulation backends. This trait is the only boundary behind which
//! CGAL (or, later, a pure-Rust engine) lives; everything above it is generic.

#[cfg(feature = "cgal")]
mod cgal;
#[cfg(feature = "pure-rust")]
pub mod pure;
// (the 3D engine also triangulates exact sites for the site diagram)
mod brio;
mod pure3;
#[cfg(feature = "cgal")]
pub use cgal::Cgal;
mod flips3;
mod halves;
pub(crate) mod points;
mod tetrahedra;
pub use halves::regular_in_halves;
pub(crate) use pure3::{regular3 as regular3_with, Predicates3};
pub use tetrahedra::{Adjacency, Tetrahedralisation};

use crate::error::Result;
use crate::geom::Q;
#[cfg(test)]
use crate::FastMap;
use std::cmp::Ordering;

/// What every backend computes, in batch.
pub trait Backend: Sync {
    /// Short name used in reports and benchmark ids.
    fn name(&self) -> &'static str;
    /// Regular triangulation of weighted double points, exact predicates.
    fn regular(&self, points: &[[f64; 2]], weights: &[f64]) -> Result<Triangulation>;
    /// Constrained Delaunay triangulation of a validated complex.
    fn constrained_delaunay(
        &self,
        points: &[[f64; 2]],
        segments: &[[u32; 2]],
    ) -> Result<Triangulation>;
    /// Regular triangulation of exact rational weighted points.
    fn regular_exact(&self, points: &[[Q; 2]], weights: &[Q]) -> Result<Triangulation>;
    /// Regular triangulation of weighted double points in 3D, exact
    /// predicates. Err when the points are coplanar (no tetrahedron).
    fn regular3(&self, points: &[[f64; 3]], weights: &[f64]) -> Result<Tetrahedralisation>;
    /// Regular triangulation of exact rational weighted points in 3D.
    fn regular3_exact(&self, points: &[[Q; 3]], weights: &[Q]) -> Result<Tetrahedralisation>;
}

/// The backend compiled in by default.
#[cfg(feature = "cgal")]
pub fn default_backend() -> Cgal {
    Cgal
}

/// The backend compiled in by default.
#[cfg(not(feature = "cgal"))]
pub fn default_backend() -> pure::Pure {
    pure::Pure
}

/// Every backend compiled in, by name: "cgal" (feature cgal), "pure"
/// (feature pure-rust).
pub fn compiled() -> Vec<Box<dyn Backend>> {
    vec![
        #[cfg(feature = "cgal")]
        Box::new(Cgal),
        #[cfg(feature = "pure-rust")]
        Box::new(pure::Pure),
    ]
}

/// The compiled-in backend of that name.
pub fn by_name(name: &str) -> Result<Box<dyn Backend>> {
    let all = compiled();
    let names: Vec<&str> = all.iter().map(|b| b.name()).collect();
    let list = names.join(", ");
    all.into_iter().find(|b| b.name() == name).ok_or_else(|| {
        crate::error::Error::Usage(format!(
            "backend {name:?} is not compiled in (this build has: {list})"
        ))
    })
}

/// A finite 2D triangulation as index triples, with its edge adjacency.
#[derive(Debug, Clone, Default)]
pub struct Triangulation {
    /// Counter-clockwise triangles (input indices).
    pub triangles: Vec<[u32; 3]>,
    /// Input indices that are not vertices (hidden or merged).
    pub hidden: Vec<u32>,
    /// Per triangle, the triangle across its edge k = (tri[k], tri[k+1]),
    /// or NONE on the hull.
    adj: Vec<[u32; 3]>,
    /// Per vertex, one triangle holding it (NONE: not a vertex).
    corner: Vec<u32>,
}

/// No triangle (tetrahedron).
const NONE: u32 = u32::MAX;

/// The exact tests Lawson flips decide with, by vertex index.
pub trait FlipTests {
    /// Greater when (a, b, c) is counter-clockwise.
    fn orient(&self, a: u32, b: u32, c: u32) -> Ordering;
    /// Greater when d conflicts with the counter-clockwise triangle abc
    /// (its lifted point lies below their plane).
    fn power(&self, a: u32, b: u32, c: u32, d: u32) -> Ordering;
}

impl Triangulation {
    /// From triangles and their adjacency (as the backends give them).
    pub(crate) fn from_parts(flat: &[u32], neighbours: &[u32], hidden: Vec<u32>) -> Self {
        let triples = |v: &[u32]| v.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
        Self::from_arrays(triples(flat), triples(neighbours), hidden)
    }

    /// From triangles and their neighbours (NONE: none).
    pub(crate) fn from_arrays(
        triangles: Vec<[u32; 3]>,
        adj: Vec<[u32; 3]>,
        hidden: Vec<u32>,
    ) -> Self {
        let n = triangles
            .iter()
            .flatten()
            .max()
            .map_or(0, |&m| m as usize + 1);
        let mut corner = vec![NONE; n];
        for (t, tri) in triangles.iter().enumerate() {
            for &v in tri {
                corner[v as usize] = t as u32;
            }
        }
        Triangulation {
            triangles,
            hidden,
            adj,
            corner,
        }
    }

    /// From triangles alone: the adjacency is found by matching edges.
    #[cfg(test)]
    pub(crate) fn from_flat(flat: &[u32], hidden: Vec<u32>) -> Self {
        let mut left: FastMap<(u32, u32), u32> = FastMap::default();
        for (t, tri) in flat.chunks_exact(3).enumerate() {
            for k in 0..3 {
                left.insert((tri[k], tri[(k + 1) % 3]), t as u32);
            }
        }
        let neighbours: Vec<u32> = flat
            .chunks_exact(3)
            .flat_map(|tri| {
                (0..3).map(|k| {
                    left.get(&(tri[(k + 1) % 3], tri[k]))
                        .copied()
                        .unwrap_or(NONE)
                })
            })
            .collect();
        Self::from_parts(flat, &neighbours, hidden)
    }

    /// The triangle on the left of the directed edge a->b, if any: a walk
    /// around a, counter-clockwise, then clockwise from the hull.
    pub fn left_of(&self, a: u32, b: u32) -> Option<u32> {
        let start = self
            .corner
            .get(a as usize)
            .copied()
            .filter(|&t| t != NONE)?;
        let at = |t: u32| {
            let tri = self.triangles[t as usize];
            let k = tri
                .iter()
                .position(|&v| v == a)
                .expect("corner holds its vertex");
            (tri, k)
        };
        let mut t = start;
        loop {
            let (tri, k) = at(t);
            if tri[(k + 1) % 3] == b {
                return Some(t);
            }
            t = self.adj[t as usize][(k + 2) % 3];
            if t == NONE {
                break;
            }
            if t == start {
                return None;
            }
        }
        let mut t = start;
        loop {
            let (_, k) = at(t);
            t = self.adj[t as usize][k];
            if t == NONE {
                return None;
            }
            let (tri, k) = at(t);
            if tri[(k + 1) % 3] == b {
                return Some(t);
            }
        }
    }

    /// The triangles on the left of a->b and of b->a: one walk around a
    /// where a->b has a triangle (the other is across its edge).
    pub fn beside(&self, a: u32, b: u32) -> [Option<u32>; 2] {
        match self.left_of(a, b) {
            Some(t) => [Some(t), self.across(t, self.edge_index(t, a, b))],
            None => [None, self.left_of(b, a)],
        }
    }

    /// The vertex of triangle `t` opposite its edge a->b (which must be in it).
    pub fn apex(&self, t: u32, a: u32, b: u32) -> u32 {
        let tri = self.triangles[t as usize];
        *tri.iter()
            .find(|&&v| v != a && v != b)
            .expect("edge belongs to triangle")
    }

    /// Replaces the diagonal a-b of the two triangles beside it by the other
    /// diagonal (the caller checks that their union is strictly convex).
    /// Returns the new triangles, or None when a-b is not an inner edge.
    pub fn flip(&mut self, a: u32, b: u32) -> Option<[u32; 2]> {
        let [t1, t2] = self.beside(a, b);
        let (t1, t2) = (t1?, t2?);
        let c = self.apex(t1, a, b);
        let d = self.apex(t2, b, a);
        let edge = |s: &Self, t: u32, x: u32, y: u32| s.edge_index(t, x, y);
        let n_bc = self.adj[t1 as usize][edge(self, t1, b, c)];
        let n_ca = self.adj[t1 as usize][edge(self, t1, c, a)];
        let n_ad = self.adj[t2 as usize][edge(self, t2, a, d)];
        let n_db = self.adj[t2 as usize][edge(self, t2, d, b)];
        self.triangles[t1 as usize] = [c, a, d];
        self.triangles[t2 as usize] = [c, d, b];
        self.adj[t1 as usize] = [n_ca, n_ad, t2];
        self.adj[t2 as usize] = [t1, n_db, n_bc];
        // The outer triangles that changed sides: across a-d now t1, across b-c now t2.
        for (n, x, y, t) in [(n_ad, d, a, t1), (n_bc, c, b, t2)] {
            if n != NONE {
                let k = edge(self, n, x, y);
                self.adj[n as usize][k] = t;
            }
        }
        self.corner[a as usize] = t1;
        self.corner[b as usize] = t2;
        Some([t1, t2])
    }

    /// The k of triangle t's directed edge x -> y (tri[k], tri[k + 1]).
    pub fn edge_index(&self, t: u32, x: u32, y: u32) -> usize {
        let tri = self.triangles[t as usize];
        (0..3)
            .find(|&k| (tri[k], tri[(k + 1) % 3]) == (x, y))
            .expect("edge of triangle")
    }

    /// Splits triangle t = (a, b, c) at a hidden input index h strictly
    /// inside it into (a, b, h), (b, c, h), (c, a, h); h is a vertex then.
    pub fn split(&mut self, t: u32, h: u32) {
        let [a, b, c] = self.triangles[t as usize];
        let [_, n_bc, n_ca] = self.adj[t as usize];
        let (t1, t2) = (self.triangles.len() as u32, self.triangles.len() as u32 + 1);
        self.triangles[t as usize] = [a, b, h];
        self.triangles.push([b, c, h]);
        self.triangles.push([c, a, h]);
        self.adj[t as usize] = [self.adj[t as usize][0], t1, t2];
        self.adj.push([n_bc, t2, t]);
        self.adj.push([n_ca, t, t1]);
        for (n, x, y, new) in [(n_bc, c, b, t1), (n_ca, a, c, t2)] {
            if n != NONE {
                let k = self.edge_index(n, x, y);
                self.adj[n as usize][k] = new;
            }
        }
        if self.corner.len() <= h as usize {
            self.corner.resize(h as usize + 1, NONE);
        }
        self.corner[c as usize] = t1;
        self.corner[h as usize] = t;
        self.hidden.retain(|&x| x != h);
    }

    /// The two triangles beside a-b fail the power test: their apexes.
    pub fn non_regular<T: FlipTests + ?Sized>(
        &self,
        tests: &T,
        a: u32,
        b: u32,
    ) -> Option<(u32, u32)> {
        let [t1, t2] = self.beside(a, b);
        let (t1, t2) = (t1?, t2?);
        let (c, d) = (self.apex(t1, a, b), self.apex(t2, b, a));
        (tests.power(a, b, c, d) == Ordering::Greater).then_some((c, d))
    }

    /// Lawson flips from the edges on `stack` until every edge they reach
    /// is locally regular: the vertices of the flipped quadrilaterals, or
    /// None when an edge cannot be flipped (its quadrilateral is not
    /// strictly convex) or the flips do not settle.
    pub fn flip_to_regular<T: FlipTests + ?Sized>(
        &mut self,
        tests: &T,
        mut stack: Vec<(u32, u32)>,
    ) -> Option<Vec<u32>> {
        let mut touched = vec![];
        let mut budget = 10 * stack.len() + 1000;
        while let Some((a, b)) = stack.pop() {
            let Some((c, d)) = self.non_regular(tests, a, b) else {
                continue;
            };
            if budget == 0
                || tests.orient(c, a, d) != Ordering::Greater
                || tests.orient(c, d, b) != Ordering::Greater
            {
                return None;
            }
            budget -= 1;
            self.flip(a, b);
            stack.extend([(a, d), (d, b), (b, c), (c, a)]);
            touched.extend([a, b, c, d]);
        }
        Some(touched)
    }

    /// Whether input index v is a vertex.
    pub fn is_vertex(&self, v: u32) -> bool {
        self.corner.get(v as usize).is_some_and(|&t| t != NONE)
    }

    /// Whether {a, b} is an edge.
    pub fn has_edge(&self, a: u32, b: u32) -> bool {
        self.left_of(a, b).is_some() || self.left_of(b, a).is_some()
    }

    /// Every undirected edge once, as (a, b) with a triangle on the left of
    /// a->b, in triangle order (deterministic: LP rows follow this order).
    pub fn edges(&self) -> impl Iterator<Item = (u32, u32)> + '_ {
        self.triangles.iter().zip(&self.adj).flat_map(|(t, adj)| {
            (0..3)
                .filter(move |&k| t[k] < t[(k + 1) % 3] || adj[k] == NONE)
                .map(move |k| (t[k], t[(k + 1) % 3]))
        })
    }

    /// Every undirected edge once as (a, b, t, u): t the triangle on the
    /// left of a->b, u the one across (None on the hull).
    pub fn edge_triangles(&self) -> impl Iterator<Item = (u32, u32, u32, Option<u32>)> + '_ {
        self.triangles.iter().enumerate().flat_map(move |(t, tri)| {
            (0..3).filter_map(move |k| {
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                let u = self.across(t as u32, k);
                (a < b || u.is_none()).then_some((a, b, t as u32, u))
            })
        })
    }

    /// `edge_triangles` in parallel, in the same order when collected.
    pub fn par_edge_triangles(
        &self,
    ) -> impl rayon::iter::ParallelIterator<Item = (u32, u32, u32, Option<u32>)> + '_ {
        use rayon::prelude::*;
        (0..self.triangles.len() as u32)
            .into_par_iter()
            .flat_map_iter(move |t| {
                let tri = self.triangles[t as usize];
                (0..3).filter_map(move |k| {
                    let (a, b) = (tri[k], tri[(k + 1) % 3]);
                    let u = self.across(t, k);
                    (a < b || u.is_none()).then_some((a, b, t, u))
                })
            })
    }

    /// The triangle across edge k of triangle t (edge k joins its vertices
    /// k and k + 1), if any.
    pub fn across(&self, t: u32, k: usize) -> Option<u32> {
        Some(self.adj[t as usize][k]).filter(|&n| n != NONE)
    }

    /// The triangles around an interior vertex, counter-clockwise; None
    /// when v is on the hull or not a vertex.
    pub fn star(&self, v: u32) -> Option<Vec<u32>> {
        let start = self
            .corner
            .get(v as usize)
            .copied()
            .filter(|&t| t != NONE)?;
        let mut out = vec![];
        let mut t = start;
        loop {
            out.push(t);
            let tri = self.triangles[t as usize];
            let k = tri.iter().position(|&x| x == v)?;
            t = self.across(t, (k + 2) % 3)?;
            if t == start {
                return Some(out);
            }
        }
    }

    /// Neighbours of each vertex (n = number of input points).
    pub fn neighbours(&self, n: usize) -> Vec<Vec<u32>> {
        let mut nb = vec![Vec::new(); n];
        for (a, b) in self.edges() {
            nb[a as usize].push(b);
            nb[b as usize].push(a);
        }
        nb
    }

    /// The triangles around vertex v, interior or on the hull: a walk each
    /// way from its corner (empty when v is no vertex).
    pub fn fan(&self, v: u32) -> Vec<u32> {
        let Some(start) = self.corner.get(v as usize).copied().filter(|&t| t != NONE) else {
            return vec![];
        };
        let at = |t: u32| {
            self.triangles[t as usize]
                .iter()
                .position(|&x| x == v)
                .expect("the fan's triangles hold its vertex")
        };
        let mut out = vec![start];
        let mut t = start;
        while let Some(n) = self.across(t, (at(t) + 2) % 3) {
            if n == start {
                return out;
            }
            out.push(n);
            t = n;
        }
        t = start;
        while let Some(n) = self.across(t, at(t)) {
            out.push(n);
            t = n;
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn adjacency_of_two_triangles() {
        let t = Triangulation::from_flat(&[0, 1, 2, 2, 1, 3], vec![]);
        assert_eq!(t.left_of(0, 1), Some(0));
        assert_eq!(t.left_of(1, 2), Some(0));
        assert_eq!(t.left_of(2, 1), Some(1));
        assert_eq!(t.apex(1, 2, 1), 3);
        assert!(t.has_edge(3, 2));
        assert!(!t.has_edge(0, 3));
        assert_eq!(t.edges().count(), 5);
        assert_eq!(t.beside(1, 2), [Some(0), Some(1)]);
        assert_eq!(t.beside(0, 1), [Some(0), None]);
        assert_eq!(t.beside(1, 0), [None, Some(0)]);
        assert_eq!(t.beside(0, 3), [None, None]);
    }

    #[test]
    fn fans_hold_every_triangle_of_their_vertex() {
        // A hexagon around vertex 0, less one triangle: 0 is on the hull.
        let mut flat = vec![];
        for k in 1..6 {
            flat.extend([0, k, k % 6 + 1]);
        }
        for (whole, flat) in [
            (false, flat.clone()),
            (true, [flat, vec![0, 6, 1]].concat()),
        ] {
            let t = Triangulation::from_flat(&flat, vec![]);
            for v in 0..7 {
                let mut fan = t.fan(v);
                fan.sort();
                let holding: Vec<u32> = (0..t.triangles.len() as u32)
                    .filter(|&k| t.triangles[k as usize].contains(&v))
                    .collect();
                assert_eq!(fan, holding, "vertex {v}, closed {whole}");
            }
        }
    }

    #[test]
    fn flip_swaps_the_diagonal() {
        let mut t = Triangulation::from_flat(&[0, 1, 2, 2, 1, 3], vec![]);
        assert!(t.flip(1, 2).is_some());
        assert!(!t.has_edge(1, 2));
        assert!(t.has_edge(0, 3));
        assert_eq!(t.left_of(0, 1), t.left_of(1, 3));
        assert_eq!(t.left_of(3, 2), t.left_of(2, 0));
        assert!(t.flip(0, 1).is_none());
        assert_eq!(t.edges().count(), 5);
        // adjacency after the flip is what a fresh build gives
        let flat: Vec<u32> = t.triangles.iter().flatten().copied().collect();
        assert_eq!(t.adj, Triangulation::from_flat(&flat, vec![]).adj);
    }
}
