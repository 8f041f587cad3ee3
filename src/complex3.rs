//! The 3D constraint complex of a piecewise linear complex (TetGen's PLC):
//! points and facets, each facet a planar straight-line graph (polygons,
//! segments and points in one plane, with hole points), plus volume hole
//! points. Validation comes before any geometry and decides exactly.
//! Not checked yet (issue 6): that facets meet only in shared edges and
//! vertices.

use crate::complex::MAX_COORD;
use crate::error::{Error, Result};
use crate::exact::{orient3, q};
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
    /// range, distinct points, cycles without a repeated vertex, and
    /// facets that are planar and not all on one line (exactly).
    pub fn validate(&self) -> Result<()> {
        let bad: Vec<i64> = (0..self.points.len())
            .filter(|&i| self.points[i].iter().any(|c| !c.is_finite()))
            .map(|i| self.vertex_ids[i])
            .collect();
        if !bad.is_empty() {
            return Err(Error::NonFinite { vertices: bad });
        }
        if let Some(i) =
            (0..self.points.len()).find(|&i| self.points[i].iter().any(|c| c.abs() > MAX_COORD))
        {
            return Err(Error::OutOfRange(format!(
                "vertex {} has a coordinate beyond {MAX_COORD:e} (its square would overflow)",
                self.vertex_ids[i]
            )));
        }
        self.distinct()?;
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
            return Err(Error::Degenerate(format!(
                "a polygon visits a vertex twice: {}",
                list.join(", ")
            )));
        }
        if !flat.is_empty() {
            return Err(Error::Degenerate(format!(
                "facets whose polygons lie on one line (no area): {flat:?}"
            )));
        }
        if !non_planar.is_empty() {
            let list: Vec<String> = non_planar
                .iter()
                .map(|(f, v)| format!("facet {f} (vertex {v} is off its plane)"))
                .collect();
            return Err(Error::Degenerate(format!(
                "facets that are not planar: {}",
                list.join(", ")
            )));
        }
        Ok(())
    }

    /// Pairs of points at the same position (exactly: doubles compare
    /// exactly), as an error naming them.
    fn distinct(&self) -> Result<()> {
        let mut order: Vec<usize> = (0..self.points.len()).collect();
        let key = |i: usize| self.points[i];
        order.sort_unstable_by(|&a, &b| {
            (0..3).fold(Ordering::Equal, |o, k| {
                o.then(key(a)[k].total_cmp(&key(b)[k]))
            })
        });
        let pairs: Vec<(i64, i64)> = order
            .windows(2)
            .filter(|w| key(w[0]) == key(w[1]))
            .map(|w| (self.vertex_ids[w[0]], self.vertex_ids[w[1]]))
            .collect();
        if pairs.is_empty() {
            Ok(())
        } else {
            Err(Error::DuplicateVertices { pairs })
        }
    }

    /// Whether a facet's vertices span a plane, lie on a line, or leave
    /// the plane of its first non-collinear triple (which vertex).
    fn plane(&self, facet: &Facet) -> Plane {
        let vs: Vec<u32> = facet.polygons.iter().flatten().copied().collect();
        let p = |v: u32| self.points[v as usize];
        let Some(&a) = vs.first() else {
            return Plane::Line;
        };
        let Some(&b) = vs.iter().find(|&&v| p(v) != p(a)) else {
            return Plane::Line;
        };
        let Some(&c) = vs.iter().find(|&&v| !collinear(p(a), p(b), p(v))) else {
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
    }
}
