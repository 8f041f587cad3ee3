//! The 3D constraint complex of a piecewise linear complex (TetGen's PLC):
//! points and facets, each facet a planar straight-line graph (polygons,
//! segments and points in one plane, with hole points), plus volume hole
//! points. Validation comes before any geometry and decides exactly.
//! Inside a facet, crossings and incidences are decided as in 2D, on the
//! facet projected to a coordinate plane; between facets, on their
//! triangulations (`Complex3::triangulate`): simplices of different facets
//! meet only in a common face.

use super::{distinct_with_extent, finite_in_range, Complex};
use crate::error::{Error, Result};
use crate::geom::{collinear, drop_axis, orient, orient3, plane_axis};
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
    /// The vertices.
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
    pub(crate) fn validate_in_space(&self) -> Result<()> {
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
        // A 3D mesh needs volume: four points not in one plane (exactly).
        let all: Vec<u32> = (0..self.points.len() as u32).collect();
        let p = |v: u32| self.points[v as usize];
        let volume = self.spanning(&all).is_some_and(|[a, b, c]| {
            all.iter()
                .any(|&v| orient3(p(a), p(b), p(c), p(v)) != Ordering::Equal)
        });
        if !volume {
            return Err(Error::Degenerate(format!(
                "the {} points lie in one plane: a 3D mesh needs volume",
                self.points.len()
            )));
        }
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
    pub(crate) fn checked_facet_2d(&self, f: usize) -> Result<Option<(Complex, Vec<u32>)>> {
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

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// The unit cube, its six squares as facets.
    pub(crate) fn cube() -> Complex3 {
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
