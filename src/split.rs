//! `--split-segments`: where system 3 is infeasible (long segments close to
//! other features), split the segments that miss their duals at Steiner
//! points and mesh again, round by round, until every site can lie in its
//! cell; where sites of free ends or isolated vertices are crowded out by
//! a segment's sites, split that segment too (its sites come closer). The mesh then conforms to each split segment as a chain of edges,
//! no longer as one edge; the report lists them. Each round splits only
//! the segments the elastic LP left missing their duals (it spreads the
//! violation over as few segments as it can), each at one point.

use crate::backend::Backend;
use crate::complex::Complex;
use crate::conform::{conform2, Outcome, SplitReport, SplitSegment, D2};
use crate::error::{Error, Result};
use crate::geom::orient;
use crate::options::Options;
use std::cmp::Ordering;
use std::collections::BTreeMap;

/// Rounds of splitting before giving up.
pub const MAX_ROUNDS: usize = 12;
/// Pieces a segment is halved into before its pieces follow its
/// surroundings.
const REFINE_AFTER: usize = 4;

/// The points dividing segment a-b into `pieces` (a power of two) equal
/// parts, in order from a: each exactly on the segment when the double
/// computed for it is (checked exactly), else that double, with its
/// distance from the segment's line over the segment's length.
pub fn steiner_points(a: [f64; 2], b: [f64; 2], pieces: usize) -> Vec<([f64; 2], f64)> {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let l2 = dx * dx + dy * dy;
    (1..pieces)
        .map(|k| {
            let t = k as f64 / pieces as f64;
            // Two roundings of the same point: a + t (b - a), and the
            // weighted mean (exact for the midpoint of nearby doubles).
            let candidates = [
                [a[0] + t * dx, a[1] + t * dy],
                [a[0] * (1.0 - t) + b[0] * t, a[1] * (1.0 - t) + b[1] * t],
            ];
            match candidates
                .iter()
                .find(|&&p| orient(a, b, p) == Ordering::Equal)
            {
                Some(&p) => (p, 0.0),
                None => {
                    let p = candidates[0];
                    (p, ((p[0] - a[0]) * dy - (p[1] - a[1]) * dx).abs() / l2)
                }
            }
        })
        .collect()
}

/// Pieces for a segment that misses its dual: about its length over twice
/// its distance to the nearest vertex off it (a chain of pieces that short
/// is Gabriel there), a power of two from 2 to 64.
fn pieces_for(cx: &Complex, s: usize) -> usize {
    let [i, j] = cx.segments[s].map(|v| v as usize);
    let (a, b) = (cx.points[i], cx.points[j]);
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let l2 = dx * dx + dy * dy;
    let near = (0..cx.points.len())
        .filter(|&v| v != i && v != j)
        .map(|v| {
            let p = cx.points[v];
            let t = (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l2).clamp(0.0, 1.0);
            (p[0] - a[0] - t * dx).hypot(p[1] - a[1] - t * dy)
        })
        .fold(f64::INFINITY, f64::min);
    let want = (l2.sqrt() / (2.0 * near)).ceil();
    if want.is_finite() {
        (want as usize).clamp(2, 64).next_power_of_two()
    } else {
        2
    }
}

/// `conform`, splitting the segments that miss their duals (or crowd
/// sites out) until none does, at most `MAX_ROUNDS` rounds: in halves
/// first, then, for a segment still in the way, into pieces about twice
/// as short as the distance to the nearest vertex off it.
pub fn conform_splitting<B: Backend + ?Sized>(
    backend: &B,
    input: &Complex,
    opts: &Options,
) -> Result<Outcome<D2>> {
    let mut cx = input.clone();
    // Per segment of `cx`, the input segment it is part of.
    let mut origin: Vec<i64> = cx.segment_ids.clone();
    let mut next_vertex = cx.vertex_ids.iter().max().map_or(0, |m| m + 1);
    let mut next_segment = cx.segment_ids.iter().max().map_or(0, |m| m + 1);
    let mut split: BTreeMap<i64, (usize, f64)> = BTreeMap::new();
    let inner = Options {
        allow_sites_outside: false,
        ..opts.clone()
    };
    for round in 0..=MAX_ROUNDS {
        let missing = match conform2(backend, &cx, &inner) {
            Ok(mut out) => {
                out.report.split = Some(report(round, &split));
                return Ok(out);
            }
            Err(Error::SegmentsMissTheirDuals { segments, .. }) if round < MAX_ROUNDS => segments,
            Err(Error::SitesOutsideCells { crowding, .. })
                if round < MAX_ROUNDS && !crowding.is_empty() =>
            {
                crowding
            }
            Err(e) if opts.allow_sites_outside && round > 0 => {
                // Still sites outside after the splits: the caller allows it.
                let mut out = conform2(backend, &cx, opts).map_err(|_| e)?;
                out.report.split = Some(report(round, &split));
                return Ok(out);
            }
            Err(_) if opts.allow_sites_outside => return conform2(backend, &cx, opts),
            Err(e) => return Err(e),
        };
        let mut done_any = false;
        for id in missing {
            // Segments the domain added (hull edges) are not in `cx`.
            let Some(s) = cx.segment_ids.iter().position(|&x| x == id) else {
                continue;
            };
            let [i, j] = cx.segments[s];
            // Halves first; a segment already in REFINE_AFTER pieces and
            // still in the way gets pieces as short as its surroundings ask
            // (measured on A.poly: 6 Steiner points this way, 15 when
            // refining after one halving).
            let pieces = if split.get(&origin[s]).is_some_and(|e| e.0 >= REFINE_AFTER) {
                pieces_for(&cx, s)
            } else {
                2
            };
            let points = steiner_points(cx.points[i as usize], cx.points[j as usize], pieces);
            let mut from = i;
            for (k, &(p, off)) in points.iter().enumerate() {
                let v = cx.points.len() as u32;
                cx.points.push(p);
                cx.vertex_ids.push(next_vertex);
                next_vertex += 1;
                if k == 0 {
                    cx.segments[s] = [i, v];
                } else {
                    cx.segments.push([from, v]);
                    cx.segment_ids.push(next_segment);
                    next_segment += 1;
                    origin.push(origin[s]);
                }
                from = v;
                let e = split.entry(origin[s]).or_insert((1, 0.0));
                e.0 += 1;
                e.1 = e.1.max(off);
            }
            cx.segments.push([from, j]);
            cx.segment_ids.push(next_segment);
            next_segment += 1;
            origin.push(origin[s]);
            if !cx.anchors.is_empty() {
                let anchor = cx.anchors[s];
                cx.anchors.resize(cx.segments.len(), anchor);
            }
            done_any = true;
        }
        if !done_any {
            return Err(Error::Usage(
                "--split-segments: the segments that miss their duals are hull edges the domain added; \
                 add them to the input to let them be split"
                    .into(),
            ));
        }
    }
    unreachable!("the last round returns")
}

fn report(rounds: usize, split: &BTreeMap<i64, (usize, f64)>) -> SplitReport {
    SplitReport {
        rounds,
        steiner_points: split.values().map(|(n, _)| n - 1).sum(),
        segments: split
            .iter()
            .map(|(&id, &(pieces, off_line))| SplitSegment {
                id,
                pieces,
                off_line,
            })
            .collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn steiner_points_are_on_the_segment_when_a_double_is() {
        assert_eq!(
            steiner_points([0.0, 0.0], [4.0, 2.0], 4),
            vec![([1.0, 0.5], 0.0), ([2.0, 1.0], 0.0), ([3.0, 1.5], 0.0)]
        );
        // Decimal input: whichever points come back are in order inside
        // the segment, on it or within rounding of it.
        let (a, b) = ([0.1, 0.2], [0.7, 0.3]);
        let pts = steiner_points(a, b, 2);
        let (p, off) = pts[0];
        assert!(p[0] > a[0] && p[0] < b[0] && p[1] > a[1] && p[1] < b[1]);
        assert!(off < 1e-15, "{off}");
        if off == 0.0 {
            assert_eq!(orient(a, b, p), Ordering::Equal);
        }
    }

    #[test]
    fn pieces_follow_the_nearest_vertex_off_the_segment() {
        // A segment of length 8 with a vertex 0.5 from it: 8 pieces.
        let cx = Complex::new(vec![[0.0, 0.0], [8.0, 0.0], [3.0, 0.5]], vec![[0, 1]]);
        assert_eq!(pieces_for(&cx, 0), 8);
        let far = Complex::new(vec![[0.0, 0.0], [8.0, 0.0], [3.0, 40.0]], vec![[0, 1]]);
        assert_eq!(pieces_for(&far, 0), 2);
    }
}
