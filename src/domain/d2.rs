//! The domain, as Triangle's `p` switch sees it: the region enclosed by the
//! segments minus the regions of the hole points; with no enclosing segments,
//! the convex hull (its edges join the constraints). Vertices and segments
//! outside the domain are dropped: they play no role in the mesh.

use crate::backend::{Backend, Triangulation};
use crate::complex::Complex;
use crate::error::{Error, Result};
use crate::geom::orient;
use crate::FastSet;
use rayon::prelude::*;
use std::cmp::Ordering;
use std::collections::VecDeque;

/// The complex restricted to the domain, with its constrained Delaunay
/// triangulation and which of its triangles lie in the domain.
#[derive(Debug, Clone)]
pub struct Domain {
    pub complex: Complex,
    pub cdt: Triangulation,
    pub inside: Vec<bool>,
    /// Per segment, whether the triangles on its left and on its right are
    /// in the domain.
    pub sides: Vec<[bool; 2]>,
    /// Convex-hull edges added as constraints.
    pub hull_edges_added: usize,
    /// Input vertices and segments dropped as outside the domain.
    pub dropped_vertices: usize,
    pub dropped_segments: usize,
}

impl Domain {
    /// Domain boundary as directed segments (a, b) with the domain on the left.
    pub fn boundary(&self) -> Vec<(u32, u32)> {
        self.complex
            .segments
            .iter()
            .zip(&self.sides)
            .filter_map(|(&[a, b], side)| match side {
                [true, false] => Some((a, b)),
                [false, true] => Some((b, a)),
                _ => None,
            })
            .collect()
    }

    /// Area of the domain (floating point, for reports).
    pub fn area(&self) -> f64 {
        let p = &self.complex.points;
        // Terms in parallel, summed in order (the same sum on any threads).
        let terms: Vec<f64> = self
            .cdt
            .triangles
            .par_iter()
            .zip(&self.inside)
            .filter(|(_, &i)| i)
            .map(|(t, _)| {
                let [a, b, c] = t.map(|v| p[v as usize]);
                0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
            })
            .collect();
        terms.iter().sum()
    }
}

/// Builds the domain of a validated complex.
pub fn build<B: Backend + ?Sized>(backend: &B, input: &Complex) -> Result<Domain> {
    let mut cx = input.clone();
    let mut cdt = backend.constrained_delaunay(&cx.points, &cx.segments)?;
    if cdt.triangles.is_empty() {
        return Err(Error::Degenerate(
            "fewer than three vertices, or all vertices collinear".into(),
        ));
    }
    let (mut inside, mut sides) = classify(&cx, &cdt);
    let mut hull_edges_added = 0;
    if !inside.iter().any(|&i| i) {
        // Nothing enclosed: mesh the convex hull, its edges become constraints.
        let segs: FastSet<(u32, u32)> = cx
            .segments
            .iter()
            .map(|s| (s[0].min(s[1]), s[0].max(s[1])))
            .collect();
        let mut next_id = cx.segment_ids.iter().copied().max().unwrap_or(0) + 1;
        for (a, b, _) in hull_edges(&cdt) {
            if !segs.contains(&(a.min(b), a.max(b))) {
                cx.segments.push([a, b]);
                cx.segment_ids.push(next_id);
                if !cx.anchors.is_empty() {
                    cx.anchors.push(None);
                }
                next_id += 1;
                hull_edges_added += 1;
            }
        }
        cx.notes.push(format!(
            "no segments enclose a region: meshing the convex hull ({hull_edges_added} hull edges added as segments, ids from {})",
            next_id - hull_edges_added as i64
        ));
        cdt = backend.constrained_delaunay(&cx.points, &cx.segments)?;
        (inside, sides) = classify(&cx, &cdt);
        if !inside.iter().any(|&i| i) {
            return Err(Error::Degenerate(
                "the hole points remove the whole convex hull".into(),
            ));
        }
    }

    // Keep what touches the domain.
    let n = cx.points.len();
    let mut keep_v = vec![false; n];
    for (t, tri) in cdt.triangles.iter().enumerate() {
        if inside[t] {
            for &v in tri {
                keep_v[v as usize] = true;
            }
        }
    }
    let keep_s: Vec<bool> = sides.iter().map(|&[l, r]| l || r).collect();
    let dropped_vertices = keep_v.iter().filter(|&&k| !k).count();
    let dropped_segments = keep_s.iter().filter(|&&k| !k).count();
    if dropped_vertices == 0 && dropped_segments == 0 {
        return Ok(Domain {
            complex: cx,
            cdt,
            inside,
            sides,
            hull_edges_added,
            dropped_vertices,
            dropped_segments,
        });
    }
    let mut map = vec![u32::MAX; n];
    let mut rc = Complex {
        holes: cx.holes.clone(),
        notes: cx.notes.clone(),
        ..Default::default()
    };
    for v in 0..n {
        if keep_v[v] {
            map[v] = rc.points.len() as u32;
            rc.points.push(cx.points[v]);
            rc.vertex_ids.push(cx.vertex_ids[v]);
        }
    }
    for (s, &[a, b]) in cx.segments.iter().enumerate() {
        if keep_s[s] {
            rc.segments.push([map[a as usize], map[b as usize]]);
            rc.segment_ids.push(cx.segment_ids[s]);
            if !cx.anchors.is_empty() {
                rc.anchors.push(cx.anchors[s]);
            }
        }
    }
    rc.notes.push(format!(
        "{dropped_vertices} vertices and {dropped_segments} segments lie outside the domain (or in holes) and are ignored"
    ));
    let cdt = backend.constrained_delaunay(&rc.points, &rc.segments)?;
    let (inside, sides) = classify(&rc, &cdt);
    Ok(Domain {
        complex: rc,
        cdt,
        inside,
        sides,
        hull_edges_added,
        dropped_vertices,
        dropped_segments,
    })
}

/// Directed convex-hull edges (interior on the left) and their triangles.
fn hull_edges(t: &Triangulation) -> Vec<(u32, u32, u32)> {
    t.edge_triangles()
        .filter(|e| e.3.is_none())
        .map(|(a, b, k, _)| (a, b, k))
        .collect()
}

/// Whether triangle k holds h (closed).
fn contains(t: &Triangulation, p: &[[f64; 2]], k: u32, h: [f64; 2]) -> bool {
    let [a, b, c] = t.triangles[k as usize].map(|v| p[v as usize]);
    [orient(a, b, h), orient(b, c, h), orient(c, a, h)]
        .iter()
        .all(|&o| o != Ordering::Less)
}

/// A triangle holding h (closed), or None outside the hull: a walk across
/// the edges h is beyond, in a scrambled order (a fixed order can cycle in
/// a triangulation that is not Delaunay), with a scan as the last resort.
fn locate(t: &Triangulation, p: &[[f64; 2]], h: [f64; 2], start: u32) -> Option<u32> {
    let mut cur = start;
    let mut state = 0x2545_F491_4F6C_DD1Du64;
    'walk: for _ in 0..t.triangles.len() {
        let tri = t.triangles[cur as usize];
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        for e in 0..3 {
            let k = (state as usize + e) % 3;
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            if orient(p[a as usize], p[b as usize], h) == Ordering::Less {
                cur = t.across(cur, k)?;
                continue 'walk;
            }
        }
        return Some(cur);
    }
    (0..t.triangles.len() as u32).find(|&k| contains(t, p, k, h))
}

/// Triangle's eating: from the hull and from the hole points, across every
/// edge that is not a segment. What is not eaten is the domain. Also, per
/// segment, whether the triangles on its left and right are in it.
fn classify(cx: &Complex, t: &Triangulation) -> (Vec<bool>, Vec<[bool; 2]>) {
    let (is_seg, around_seg) = segment_edges(cx, t);
    let mut eaten = vec![false; t.triangles.len()];
    let mut queue: VecDeque<u32> = (0..t.triangles.len() as u32)
        .filter(|&k| (0..3).any(|e| t.across(k, e).is_none() && is_seg[k as usize] & 1 << e == 0))
        .collect();
    let p = &cx.points;
    let mut start = 0;
    for &h in &cx.holes {
        // Each walk starts where the last ended: nearby holes are cheap.
        let Some(k) = locate(t, p, h, start) else {
            continue;
        };
        start = k;
        // h may be on an edge or a vertex of k: every triangle holding it.
        let tri = t.triangles[k as usize];
        if tri.iter().any(|&v| p[v as usize] == h)
            || (0..3).any(|e| {
                orient(p[tri[e] as usize], p[tri[(e + 1) % 3] as usize], h) == Ordering::Equal
            })
        {
            queue.extend(
                tri.iter()
                    .flat_map(|&v| t.fan(v))
                    .filter(|&k| contains(t, p, k, h)),
            );
        } else {
            queue.push_back(k);
        }
    }
    while let Some(k) = queue.pop_front() {
        if std::mem::replace(&mut eaten[k as usize], true) {
            continue;
        }
        for e in 0..3 {
            if is_seg[k as usize] & 1 << e == 0 {
                if let Some(n) = t.across(k, e) {
                    if !eaten[n as usize] {
                        queue.push_back(n);
                    }
                }
            }
        }
    }
    let inside: Vec<bool> = eaten.into_iter().map(|e| !e).collect();
    let sides = around_seg
        .iter()
        .map(|lr| lr.map(|t| t.is_some_and(|t| inside[t as usize])))
        .collect();
    (inside, sides)
}

/// Per triangle, a bit per edge k (vertex k to k + 1) that is a segment;
/// per segment, the triangles on its left and on its right.
fn segment_edges(cx: &Complex, t: &Triangulation) -> (Vec<u8>, Vec<[Option<u32>; 2]>) {
    let around: Vec<[Option<u32>; 2]> = cx
        .segments
        .par_iter()
        .map(|&[a, b]| t.beside(a, b))
        .collect();
    let mut is_seg = vec![0u8; t.triangles.len()];
    for (&[a, b], lr) in cx.segments.iter().zip(&around) {
        for (k, (x, y)) in lr.iter().zip([(a, b), (b, a)]) {
            if let Some(k) = *k {
                is_seg[k as usize] |= 1 << t.edge_index(k, x, y);
            }
        }
    }
    (is_seg, around)
}
