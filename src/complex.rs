//! The constraint complex (points and segments, plus hole points), and its
//! validation. Validation comes before any geometry and decides exactly.

use crate::error::{Error, Result};
use crate::exact::{in_box, orient};
use std::cmp::Ordering;
use std::collections::HashMap;

/// Two segments (indices) that cross.
type SegmentPair = (usize, usize);
/// A vertex (index) inside a segment (index).
type VertexOnSegment = (u32, usize);

/// Largest coordinate magnitude: squared lengths stay far below f64::MAX.
pub const MAX_COORD: f64 = 1e150;
/// Smallest extent: squared lengths stay normal doubles.
pub const MIN_EXTENT: f64 = 1e-150;

/// A 2D simplicial complex of constraints, with the ids its file gave.
#[derive(Debug, Clone, Default)]
pub struct Complex {
    pub points: Vec<[f64; 2]>,
    pub segments: Vec<[u32; 2]>,
    /// Triangle-style hole points: the region around each is not meshed.
    pub holes: Vec<[f64; 2]>,
    /// The id of each point in the input file.
    pub vertex_ids: Vec<i64>,
    /// The id of each segment in the input file.
    pub segment_ids: Vec<i64>,
    /// Things the reader changed and the user should know.
    pub notes: Vec<String>,
}

impl Complex {
    /// A complex with ids 0.. for points and segments.
    pub fn new(points: Vec<[f64; 2]>, segments: Vec<[u32; 2]>) -> Self {
        let vertex_ids = (0..points.len() as i64).collect();
        let segment_ids = (0..segments.len() as i64).collect();
        Complex {
            points,
            segments,
            holes: vec![],
            vertex_ids,
            segment_ids,
            notes: vec![],
        }
    }

    /// Checks that this is a simplicial complex: finite coordinates, distinct
    /// vertices, proper segments, no crossings, no vertex inside a segment.
    pub fn validate(&self) -> Result<()> {
        let vid = |i: u32| self.vertex_ids[i as usize];
        let sid = |s: usize| self.segment_ids[s];

        let bad: Vec<i64> = (0..self.points.len())
            .filter(|&i| !self.points[i].iter().all(|c| c.is_finite()))
            .map(|i| self.vertex_ids[i])
            .collect();
        if !bad.is_empty() {
            return Err(Error::NonFinite { vertices: bad });
        }
        // Weights are squared lengths in doubles: squares must neither
        // overflow nor vanish.
        let big: Vec<i64> = (0..self.points.len())
            .filter(|&i| self.points[i].iter().any(|c| c.abs() > MAX_COORD))
            .map(|i| self.vertex_ids[i])
            .collect();
        if !big.is_empty() {
            return Err(Error::OutOfRange(format!(
                "vertices beyond +-{MAX_COORD:e} (rescale the input): {big:?}"
            )));
        }
        if let Some(h) = self
            .holes
            .iter()
            .position(|h| !h.iter().all(|c| c.is_finite()))
        {
            return Err(Error::Degenerate(format!(
                "hole {} has a NaN or infinite coordinate",
                h + 1
            )));
        }

        // Exact duplicates: -0.0 and 0.0 are the same position.
        let key = |p: [f64; 2]| [(p[0] + 0.0).to_bits(), (p[1] + 0.0).to_bits()];
        let mut seen: HashMap<[u64; 2], u32> = HashMap::with_capacity(self.points.len());
        let mut dups = vec![];
        for (i, &p) in self.points.iter().enumerate() {
            if let Some(&j) = seen.get(&key(p)) {
                dups.push((vid(j), vid(i as u32)));
            } else {
                seen.insert(key(p), i as u32);
            }
        }
        if !dups.is_empty() {
            return Err(Error::DuplicateVertices { pairs: dups });
        }
        let extent = (0..2)
            .map(|k| {
                let it = self.points.iter().map(|p| p[k]);
                it.clone().fold(f64::NEG_INFINITY, f64::max) - it.fold(f64::INFINITY, f64::min)
            })
            .fold(0.0, f64::max);
        if self.points.len() > 1 && extent < MIN_EXTENT {
            return Err(Error::OutOfRange(format!(
                "the input spans {extent:e}, below {MIN_EXTENT:e} (rescale the input)"
            )));
        }

        let zero: Vec<i64> = (0..self.segments.len())
            .filter(|&s| self.segments[s][0] == self.segments[s][1])
            .map(sid)
            .collect();
        if !zero.is_empty() {
            return Err(Error::ZeroLengthSegments { segments: zero });
        }

        let mut seen: HashMap<(u32, u32), usize> = HashMap::with_capacity(self.segments.len());
        let mut rep = vec![];
        for (s, &[a, b]) in self.segments.iter().enumerate() {
            let k = (a.min(b), a.max(b));
            if let Some(&t) = seen.get(&k) {
                rep.push((sid(t), sid(s)));
            } else {
                seen.insert(k, s);
            }
        }
        if !rep.is_empty() {
            return Err(Error::RepeatedSegments { pairs: rep });
        }

        let (crossings, on_segment) = self.intersections();
        if !crossings.is_empty() {
            let pairs = crossings
                .into_iter()
                .map(|(s, t)| (sid(s), sid(t)))
                .collect();
            return Err(Error::CrossingSegments { pairs });
        }
        if !on_segment.is_empty() {
            let pairs = on_segment
                .into_iter()
                .map(|(v, s)| (vid(v), sid(s)))
                .collect();
            return Err(Error::VertexOnSegment { pairs });
        }
        Ok(())
    }

    /// Proper crossings (segment pairs) and vertices inside segments, found by
    /// a sweep over x with exact orientation tests. Touching, T-junctions and
    /// collinear overlaps all put a vertex inside a segment.
    fn intersections(&self) -> (Vec<SegmentPair>, Vec<VertexOnSegment>) {
        let p = &self.points;
        let seg = |s: usize| {
            (
                p[self.segments[s][0] as usize],
                p[self.segments[s][1] as usize],
            )
        };
        // Events by min x; at equal x segments come before points.
        let mut events: Vec<(f64, u8, usize)> = (0..self.segments.len())
            .map(|s| {
                let (a, b) = seg(s);
                (a[0].min(b[0]), 0, s)
            })
            .chain((0..p.len()).map(|v| (p[v][0], 1, v)))
            .collect();
        events.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
        let mut active: Vec<usize> = vec![];
        let (mut crossings, mut on_segment) = (vec![], vec![]);
        for (x, kind, i) in events {
            active.retain(|&s| {
                let (a, b) = seg(s);
                a[0].max(b[0]) >= x
            });
            if kind == 1 {
                let v = p[i];
                for &s in &active {
                    let [a, b] = self.segments[s];
                    if a as usize == i || b as usize == i {
                        continue;
                    }
                    let (pa, pb) = seg(s);
                    if in_box(pa, pb, v) && orient(pa, pb, v) == Ordering::Equal {
                        on_segment.push((i as u32, s));
                    }
                }
                continue;
            }
            let (a, b) = seg(i);
            let (ylo, yhi) = (a[1].min(b[1]), a[1].max(b[1]));
            for &t in &active {
                let (c, d) = seg(t);
                if c[1].max(d[1]) < ylo || c[1].min(d[1]) > yhi {
                    continue;
                }
                let [ia, ib] = self.segments[i];
                let [ic, id] = self.segments[t];
                if ia == ic || ia == id || ib == ic || ib == id {
                    continue; // shared endpoint: overlaps show up as vertex-on-segment
                }
                let o1 = orient(a, b, c);
                let o2 = orient(a, b, d);
                let o3 = orient(c, d, a);
                let o4 = orient(c, d, b);
                let strict = |x: Ordering, y: Ordering| {
                    x != Ordering::Equal && y != Ordering::Equal && x != y
                };
                if strict(o1, o2) && strict(o3, o4) {
                    crossings.push((t.min(i), t.max(i)));
                }
            }
            active.push(i);
        }
        crossings.sort();
        on_segment.sort();
        (crossings, on_segment)
    }

    /// Number of segments at each vertex.
    pub fn degrees(&self) -> Vec<u32> {
        let mut d = vec![0; self.points.len()];
        for s in &self.segments {
            d[s[0] as usize] += 1;
            d[s[1] as usize] += 1;
        }
        d
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cx(points: &[[f64; 2]], segs: &[[u32; 2]]) -> Complex {
        Complex::new(points.to_vec(), segs.to_vec())
    }

    #[test]
    fn a_square_is_valid() {
        let c = cx(
            &[[0., 0.], [1., 0.], [1., 1.], [0., 1.]],
            &[[0, 1], [1, 2], [2, 3], [3, 0]],
        );
        c.validate().unwrap();
    }

    #[test]
    fn each_defect_is_named() {
        let e = cx(&[[0., 0.], [f64::NAN, 0.]], &[]).validate().unwrap_err();
        assert!(matches!(e, Error::NonFinite { ref vertices } if vertices == &[1]));
        let e = cx(&[[0., 0.], [-0.0, 0.]], &[]).validate().unwrap_err();
        assert!(matches!(e, Error::DuplicateVertices { ref pairs } if pairs == &[(0, 1)]));
        let e = cx(&[[0., 0.], [1., 0.]], &[[1, 1]]).validate().unwrap_err();
        assert!(matches!(e, Error::ZeroLengthSegments { ref segments } if segments == &[0]));
        let e = cx(&[[0., 0.], [1., 0.]], &[[0, 1], [1, 0]])
            .validate()
            .unwrap_err();
        assert!(matches!(e, Error::RepeatedSegments { ref pairs } if pairs == &[(0, 1)]));
        let e = cx(&[[0., 0.], [1., 1.], [0., 1.], [1., 0.]], &[[0, 1], [2, 3]])
            .validate()
            .unwrap_err();
        assert!(matches!(e, Error::CrossingSegments { ref pairs } if pairs == &[(0, 1)]));
        // T-junction: vertex 2 inside segment 0.
        let e = cx(&[[0., 0.], [2., 0.], [1., 0.], [1., 1.]], &[[0, 1], [2, 3]])
            .validate()
            .unwrap_err();
        assert!(matches!(e, Error::VertexOnSegment { ref pairs } if pairs == &[(2, 0)]));
        // Collinear overlap sharing an endpoint.
        let e = cx(&[[0., 0.], [2., 0.], [1., 0.]], &[[0, 1], [0, 2]])
            .validate()
            .unwrap_err();
        assert!(matches!(e, Error::VertexOnSegment { .. }));
        // Vertical segment with a vertex at its min x.
        let e = cx(&[[0., 0.], [0., 2.], [0., 1.]], &[[0, 1]])
            .validate()
            .unwrap_err();
        assert!(matches!(e, Error::VertexOnSegment { ref pairs } if pairs == &[(2, 0)]));
    }

    #[test]
    fn squares_must_fit_in_doubles() {
        let e = cx(&[[0., 0.], [1e200, 0.], [0., 1.]], &[])
            .validate()
            .unwrap_err();
        assert!(
            matches!(e, Error::OutOfRange(ref m) if m.contains("[1]")),
            "{e}"
        );
        let e = cx(&[[0., 0.], [1e-200, 0.], [0., 1e-200]], &[])
            .validate()
            .unwrap_err();
        assert!(matches!(e, Error::OutOfRange(_)), "{e}");
        cx(&[[6e6, 6e6], [6e6 + 1e-3, 6e6], [6e6, 6e6 + 1e-3]], &[])
            .validate()
            .unwrap();
    }

    #[test]
    fn one_ulp_off_the_segment_is_fine() {
        let y = f64::from_bits(1.0f64.to_bits() + 1);
        cx(&[[0., 0.], [2., 2.], [1., y]], &[[0, 1]])
            .validate()
            .unwrap();
    }
}
