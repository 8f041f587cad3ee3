//! The 3D domain stage: each facet triangulated in its plane by the 2D
//! domain stage, and simplices of different facets checked exactly to meet
//! only in a common face.

use crate::backend::Backend;
use crate::complex::Complex3;
use crate::error::{Error, Result};
use crate::geom::Simplices;

/// The simplicial complex of a validated PLC: each facet triangulated in
/// its plane (constrained Delaunay, no new points; regions outside its
/// polygons or around its hole points left out), the segments on no such
/// triangle, the points on no triangle or segment; each with its facet
/// (index into `Complex3::facets`).
#[derive(Debug, Clone, Default)]
pub struct Simplices3 {
    /// Facet triangles.
    pub triangles: Vec<[u32; 3]>,
    /// Per triangle, its facet.
    pub triangle_facet: Vec<u32>,
    /// Segments on no triangle.
    pub segments: Vec<[u32; 2]>,
    /// Per segment, its facet.
    pub segment_facet: Vec<u32>,
    /// Points on no triangle or segment.
    pub points: Vec<u32>,
    /// Per point, its facet.
    pub point_facet: Vec<u32>,
}

/// A facet's triangles, segments and points.
type Piece = (Vec<[u32; 3]>, Vec<[u32; 2]>, Vec<u32>);

impl Complex3 {
    /// Validates, triangulates the facets, and checks that simplices of
    /// different facets meet only in a common face (exactly): else an
    /// error naming the facets.
    pub fn triangulate<B: Backend + ?Sized>(&self, backend: &B) -> Result<Simplices3> {
        self.validate_in_space()?;
        // (facets in parallel: each is its own 2D domain; gathered in
        // facet order, the first error in that order reported)
        use rayon::prelude::*;
        let pieces: Vec<Result<Piece>> = (0..self.facets.len())
            .into_par_iter()
            .map(|f| self.facet_simplices(backend, f))
            .collect();
        let mut out = Simplices3::default();
        for (f, piece) in pieces.into_iter().enumerate() {
            let (triangles, segments, points) = piece?;
            let f = f as u32;
            out.triangle_facet.extend(triangles.iter().map(|_| f));
            out.triangles.extend(triangles);
            out.segment_facet.extend(segments.iter().map(|_| f));
            out.segments.extend(segments);
            out.point_facet.extend(points.iter().map(|_| f));
            out.points.extend(points);
        }
        let pairs = self.crossing_facets(&out);
        if pairs.is_empty() {
            Ok(out)
        } else {
            Err(Error::CrossingFacets { pairs })
        }
    }

    /// One facet's triangles, segments on no triangle, and points on
    /// neither (see `Simplices3`).
    fn facet_simplices<B: Backend + ?Sized>(&self, backend: &B, f: usize) -> Result<Piece> {
        let facet = &self.facets[f];
        let mut piece: Piece = Default::default();
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
                    piece.0.push(g);
                }
            }
        }
        for poly in &facet.polygons {
            if poly.len() == 2 {
                let (a, b) = (poly[0].min(poly[1]), poly[0].max(poly[1]));
                if on_edge.insert((a, b)) {
                    piece.1.push([a, b]);
                    on_triangle.extend([a, b]);
                }
            }
        }
        for poly in &facet.polygons {
            if poly.len() == 1 && on_triangle.insert(poly[0]) {
                piece.2.push(poly[0]);
            }
        }
        Ok(piece)
    }

    /// Pairs of facets (ids from 1) with simplices that meet other than in
    /// a common face: an R-tree of bounding boxes (boundaries included),
    /// then exact tests. (A sweep along one axis was quadratic in a layer
    /// of a layered field: 4 s of 22 on `generate field3` 16 x 16 x 8.)
    fn crossing_facets(&self, sc: &Simplices3) -> Vec<(i64, i64)> {
        use rstar::primitives::{GeomWithData, Rectangle};
        let mut items: Vec<(&[u32], u32)> = vec![];
        items.extend(
            sc.triangles
                .iter()
                .zip(&sc.triangle_facet)
                .map(|(t, &f)| (&t[..], f)),
        );
        items.extend(
            sc.segments
                .iter()
                .zip(&sc.segment_facet)
                .map(|(s, &f)| (&s[..], f)),
        );
        items.extend(
            sc.points
                .iter()
                .zip(&sc.point_facet)
                .map(|(p, &f)| (std::slice::from_ref(p), f)),
        );
        let boxes: Vec<rstar::AABB<[f64; 3]>> = items
            .iter()
            .map(|(vs, _)| {
                let pts: Vec<[f64; 3]> = vs.iter().map(|&v| self.points[v as usize]).collect();
                let (lo, hi) = crate::geom::bbox(&pts);
                rstar::AABB::from_corners(lo, hi)
            })
            .collect();
        let tree = rstar::RTree::bulk_load(
            boxes
                .iter()
                .enumerate()
                .map(|(i, b)| GeomWithData::new(Rectangle::from_aabb(*b), i))
                .collect(),
        );
        // (in parallel: each query is independent, and the exact tests are
        // most of this stage)
        use rayon::prelude::*;
        let pairs: std::collections::BTreeSet<(u32, u32)> = (0..items.len())
            .into_par_iter()
            .flat_map_iter(|i| {
                let (si, fi) = items[i];
                let (items, points) = (&items, &self.points);
                tree.locate_in_envelope_intersecting(&boxes[i])
                    .filter_map(move |j| {
                        let (sj, fj) = items[j.data];
                        (j.data > i && fi != fj && Simplices(points).improper(si, sj))
                            .then(|| (fi.min(fj) + 1, fi.max(fj) + 1))
                    })
                    .collect::<Vec<_>>()
            })
            .collect();
        pairs
            .into_iter()
            .map(|(a, b)| (a as i64, b as i64))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::complex::{tests::cube, Facet};

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
}
