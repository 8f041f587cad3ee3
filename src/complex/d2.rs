//! The 2D constraint complex (points and segments, plus hole points), and
//! its validation.

use super::{distinct_with_extent, finite_in_range};
use crate::error::{Error, Result};
use crate::geom::{in_box, orient};
use std::cmp::Ordering;

/// Two segments (indices) that cross.
type SegmentPair = (usize, usize);
/// A vertex (index) inside a segment (index).
type VertexOnSegment = (u32, usize);

/// A 2D simplicial complex of constraints, with the ids its file gave.
#[derive(Debug, Clone, Default)]
pub struct Complex {
    /// The vertices.
    pub points: Vec<[f64; 2]>,
    /// Segments as vertex index pairs.
    pub segments: Vec<[u32; 2]>,
    /// Triangle-style hole points: the region around each is not meshed.
    pub holes: Vec<[f64; 2]>,
    /// The id of each point in the input file.
    pub vertex_ids: Vec<i64>,
    /// The id of each segment in the input file.
    pub segment_ids: Vec<i64>,
    /// Things the reader changed and the user should know.
    pub notes: Vec<String>,
    /// Per segment (or empty: none), a point that should lie on the
    /// segment's dual line: the site of the cell across an interface, so
    /// that the face is orthogonal to the link between the two sites. Met
    /// where the weights LP can meet it (docs/method.md section 6).
    pub anchors: Vec<Option<[f64; 2]>>,
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
            anchors: vec![],
        }
    }

    /// The anchor of segment s, if it has one.
    pub fn anchor(&self, s: usize) -> Option<[f64; 2]> {
        self.anchors.get(s).copied().flatten()
    }

    /// Checks that this is a simplicial complex: finite coordinates, distinct
    /// vertices, proper segments, no crossings, no vertex inside a segment.
    pub fn validate(&self) -> Result<()> {
        let vid = |i: u32| self.vertex_ids[i as usize];
        let sid = |s: usize| self.segment_ids[s];

        finite_in_range(&self.points, &self.vertex_ids)?;
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

        if !self.anchors.is_empty() && self.anchors.len() != self.segments.len() {
            return Err(Error::Usage(format!(
                "{} anchors for {} segments",
                self.anchors.len(),
                self.segments.len()
            )));
        }
        let bad: Vec<i64> = (0..self.anchors.len())
            .filter(|&s| self.anchors[s].is_some_and(|a| !a.iter().all(|c| c.is_finite())))
            .map(sid)
            .collect();
        if !bad.is_empty() {
            return Err(Error::Degenerate(format!(
                "segments {bad:?} have an anchor with a NaN or infinite coordinate"
            )));
        }

        distinct_with_extent(&self.points, &self.vertex_ids)?;

        let zero: Vec<i64> = (0..self.segments.len())
            .filter(|&s| self.segments[s][0] == self.segments[s][1])
            .map(sid)
            .collect();
        if !zero.is_empty() {
            return Err(Error::ZeroLengthSegments { segments: zero });
        }

        let mut seen: crate::FastMap<(u32, u32), usize> = crate::FastMap::default();
        seen.reserve(self.segments.len());
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

    /// Proper crossings (segment pairs) and vertices inside segments, with
    /// exact orientation tests. Candidates come from a uniform grid: each
    /// segment is listed in the cells its bounding box covers, and a pair is
    /// tested only in the cell holding the lower-left corner of their boxes'
    /// overlap, so once. Segments whose boxes cover too many cells are tested
    /// against everything instead. Touching, T-junctions and collinear
    /// overlaps all put a vertex inside a segment.
    fn intersections(&self) -> (Vec<SegmentPair>, Vec<VertexOnSegment>) {
        let p = &self.points;
        let (crossings, on_segment) = (vec![], vec![]);
        if self.segments.is_empty() {
            return (crossings, on_segment);
        }
        let seg = |s: usize| {
            (
                p[self.segments[s][0] as usize],
                p[self.segments[s][1] as usize],
            )
        };
        let bbox = |s: usize| {
            let (a, b) = seg(s);
            [
                a[0].min(b[0]),
                a[1].min(b[1]),
                a[0].max(b[0]),
                a[1].max(b[1]),
            ]
        };
        let boxes: Vec<[f64; 4]> = (0..self.segments.len()).map(bbox).collect();
        let (lo, hi) = crate::geom::bbox(p);
        // About one cell per item, but no smaller than a typical segment.
        let mut sizes: Vec<f64> = boxes
            .iter()
            .map(|b| (b[2] - b[0]).max(b[3] - b[1]))
            .collect();
        let mid = sizes.len() / 2;
        let typical = *sizes.select_nth_unstable_by(mid, f64::total_cmp).1;
        let area = ((hi[0] - lo[0]) * (hi[1] - lo[1])).max(0.0);
        let items = (self.segments.len() + p.len()) as f64;
        let mut side = (area / items).sqrt().max(typical);
        if !(side.is_finite() && side > 0.0) {
            side = (hi[0] - lo[0]).max(hi[1] - lo[1]).max(f64::MIN_POSITIVE);
        }
        let dims =
            [0, 1].map(|k| (((hi[k] - lo[k]) / side).floor() as usize).clamp(0, 1 << 20) + 1);
        let cell =
            |x: f64, k: usize| (((x - lo[k]) / side).floor().max(0.0) as usize).min(dims[k] - 1);
        const MAX_CELLS: usize = 64;
        let covers = |b: &[f64; 4]| [cell(b[0], 0), cell(b[1], 1), cell(b[2], 0), cell(b[3], 1)];
        let mut grid: Vec<Vec<u32>> = vec![vec![]; dims[0] * dims[1]];
        let mut big: Vec<usize> = vec![];
        for (s, b) in boxes.iter().enumerate() {
            let [c0, r0, c1, r1] = covers(b);
            if (c1 - c0 + 1) * (r1 - r0 + 1) > MAX_CELLS {
                big.push(s);
                continue;
            }
            for r in r0..=r1 {
                for c in c0..=c1 {
                    grid[r * dims[0] + c].push(s as u32);
                }
            }
        }
        let mut pts: Vec<Vec<u32>> = vec![vec![]; dims[0] * dims[1]];
        for (v, q) in p.iter().enumerate() {
            pts[cell(q[1], 1) * dims[0] + cell(q[0], 0)].push(v as u32);
        }
        let (mut crossings, mut on_segment) = (crossings, on_segment);
        let overlap = |a: &[f64; 4], b: &[f64; 4]| {
            a[0] <= b[2] && b[0] <= a[2] && a[1] <= b[3] && b[1] <= a[3]
        };
        let mut test_pair = |s: usize, t: usize| {
            let [ia, ib] = self.segments[s];
            let [ic, id] = self.segments[t];
            if ia == ic || ia == id || ib == ic || ib == id {
                return; // shared endpoint: overlaps show up as vertex-on-segment
            }
            let ((a, b), (c, d)) = (seg(s), seg(t));
            let strict =
                |x: Ordering, y: Ordering| x != Ordering::Equal && y != Ordering::Equal && x != y;
            if strict(orient(a, b, c), orient(a, b, d)) && strict(orient(c, d, a), orient(c, d, b))
            {
                crossings.push((s.min(t), s.max(t)));
            }
        };
        for (k, list) in grid.iter().enumerate() {
            let (c, r) = (k % dims[0], k / dims[0]);
            for (x, &s) in list.iter().enumerate() {
                for &t in &list[x + 1..] {
                    let (bs, bt) = (&boxes[s as usize], &boxes[t as usize]);
                    if overlap(bs, bt)
                        && cell(bs[0].max(bt[0]), 0) == c
                        && cell(bs[1].max(bt[1]), 1) == r
                    {
                        test_pair(s as usize, t as usize);
                    }
                }
            }
        }
        let mut is_big = vec![false; self.segments.len()];
        for &s in &big {
            is_big[s] = true;
        }
        for &s in &big {
            for t in 0..self.segments.len() {
                if (!is_big[t] || t > s) && overlap(&boxes[s], &boxes[t]) {
                    test_pair(s, t);
                }
            }
        }
        let mut test_point = |v: u32, s: usize| {
            let [a, b] = self.segments[s];
            if a == v || b == v {
                return;
            }
            let (pa, pb) = seg(s);
            let q = p[v as usize];
            if in_box(pa, pb, q) && orient(pa, pb, q) == Ordering::Equal {
                on_segment.push((v, s));
            }
        };
        for (s, b) in boxes.iter().enumerate() {
            let [c0, r0, c1, r1] = covers(b);
            if is_big[s] {
                (0..p.len() as u32).for_each(|v| test_point(v, s));
                continue;
            }
            for r in r0..=r1 {
                for c in c0..=c1 {
                    for &v in &pts[r * dims[0] + c] {
                        test_point(v, s);
                    }
                }
            }
        }
        crossings.sort();
        crossings.dedup();
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
