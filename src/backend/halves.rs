//! A large 2D regular triangulation built as two overlapping halves, one
//! per thread, and stitched at the median. A frame of points of weight
//! zero around the input makes every input point interior, so that no half
//! has the long flat triangles of a nearly straight hull, whose presence
//! depends on the far side. A triangle of a half (without frame points) is
//! one of the whole when no point outside that half is in conflict with it;
//! the overlap is widened until every kept triangle is so, else the caller
//! triangulates the whole. The triangles the frame displaced, between the
//! kept ones and the hull, have all their vertices on the kept region's
//! boundary, and are taken from the regular triangulation of those points.
//! Whatever arithmetic decided this, the caller's exact check proves the
//! result: the stitch pairs every edge with its reverse or leaves it on the
//! boundary, so ccw triangles whose boundary is one convex loop winding
//! once tile the hull exactly once, and local regularity then makes the
//! tiling the regular triangulation.

use super::{Backend, Triangulation, NONE};
use crate::error::Result;
use crate::geom::{bbox, centre_f64};
use crate::FastMap;
use rayon::prelude::*;

/// Fewer points are triangulated whole (the seam and a second thread cost
/// more than they save).
pub const MIN_POINTS: usize = 8_000;
/// Share of the points on each side of the median in the first overlap.
const FIRST_SHARE: f64 = 0.02;
/// Widest share tried before giving up.
const LAST_SHARE: f64 = 0.2;
/// Frame points a side.
const FRAME: usize = 32;
/// Most kept triangles of a half tested point by point.
const MAX_FAR: usize = 64;

/// Points of weight zero on a box around the extent `x`, `y`, FRAME a
/// side, spaced as far from each other as from the box's content.
fn frame(x: (f64, f64), y: (f64, f64)) -> Vec<[f64; 2]> {
    let gap = (x.1 - x.0).max(y.1 - y.0).max(f64::MIN_POSITIVE) / FRAME as f64;
    let (x0, x1, y0, y1) = (x.0 - gap, x.1 + gap, y.0 - gap, y.1 + gap);
    let along = |a: f64, b: f64, k: usize| a + (b - a) * k as f64 / FRAME as f64;
    (0..FRAME)
        .flat_map(|k| {
            [
                [along(x0, x1, k), y0],
                [x1, along(y0, y1, k)],
                [along(x1, x0, k), y1],
                [x0, along(y1, y0, k)],
            ]
        })
        .collect()
}

/// One half: its points' indices (the frame's follow the input's) and their
/// triangulation.
struct Half {
    ids: Vec<u32>,
    rt: Triangulation,
}

/// The regular triangulation of the weighted points from two halves, or
/// None when the input is small or the halves do not stitch or fail (then
/// the caller triangulates the whole). Deterministic: the same halves
/// whatever the number of threads.
pub fn regular_in_halves<B: Backend + ?Sized>(
    backend: &B,
    points: &[[f64; 2]],
    weights: &[f64],
) -> Option<Triangulation> {
    let n = points.len();
    if n < MIN_POINTS {
        return None;
    }
    let (lo, hi) = bbox(points);
    let (x, y) = ((lo[0], hi[0]), (lo[1], hi[1]));
    let (axis, across) = if x.1 - x.0 >= y.1 - y.0 {
        (0, y)
    } else {
        (1, x)
    };
    let frame = frame(x, y);
    if !frame.iter().flatten().all(|c| c.is_finite()) {
        return None;
    }
    let m = frame.len() as u32;
    let all: Vec<[f64; 2]> = points.iter().copied().chain(frame).collect();
    let all_w: Vec<f64> = weights.iter().copied().chain((0..m).map(|_| 0.0)).collect();
    let mut sorted: Vec<f64> = points.iter().map(|p| p[axis]).collect();
    sorted.par_sort_unstable_by(f64::total_cmp);
    let median = sorted[n / 2];
    let seam = Seam {
        points: &all,
        weights: &all_w,
        n,
        axis,
        across,
        median,
    };
    let mut share = FIRST_SHARE;
    while share <= LAST_SHARE {
        let at = |q: f64| sorted[((q * n as f64) as usize).min(n - 1)];
        let (lo, hi) = (at(0.5 - share).min(median), at(0.5 + share).max(median));
        let pick = |keep: &dyn Fn(f64) -> bool| -> Result<Half> {
            let ids: Vec<u32> = (0..n as u32)
                .filter(|&i| keep(points[i as usize][axis]))
                .chain(n as u32..n as u32 + m)
                .collect();
            let p: Vec<[f64; 2]> = ids.iter().map(|&i| all[i as usize]).collect();
            let w: Vec<f64> = ids.iter().map(|&i| all_w[i as usize]).collect();
            Ok(Half {
                rt: backend.regular(&p, &w)?,
                ids,
            })
        };
        let (left, right) = rayon::join(|| pick(&|k| k < hi), || pick(&|k| k >= lo));
        // A half the backend refuses (a frame beyond doubles, say) leaves
        // the whole to the caller, which reports what is wrong with it.
        let (Ok(left), Ok(right)) = (left, right) else {
            return None;
        };
        let keep_l = seam.kept(&left, hi, true);
        let keep_r = seam.kept(&right, lo, false);
        if let (Some(kl), Some(kr)) = (keep_l, keep_r) {
            let core = stitch([(&left, &kl), (&right, &kr)])?;
            return fill(backend, &seam, core).ok().flatten();
        }
        share *= 2.0;
    }
    None
}

/// Where the halves meet.
struct Seam<'a> {
    /// The points, then the frame's.
    points: &'a [[f64; 2]],
    weights: &'a [f64],
    /// The number of input points.
    n: usize,
    axis: usize,
    /// The points' extent across the axis.
    across: (f64, f64),
    median: f64,
}

impl Seam<'_> {
    /// The half's triangles on its side of the median (by centroid), or
    /// None when one of them may be in conflict with a point beyond `edge`,
    /// the half's far end (`left`: the half lies below it). A triangle
    /// whose orthogonal circle cannot reach past `edge` (within the points'
    /// extent across the axis) is safe; the few that can (long flat ones at
    /// the hull) are tested against each point beyond.
    fn kept(&self, half: &Half, edge: f64, left: bool) -> Option<Vec<bool>> {
        let key = |i: u32| self.points[half.ids[i as usize] as usize][self.axis];
        let beyond: Vec<usize> = (0..self.n)
            .filter(|&i| (self.points[i][self.axis] >= edge) == left)
            .collect();
        let w_out = beyond.iter().map(|&i| self.weights[i]).fold(0.0, f64::max);
        let kept: Vec<bool> = half
            .rt
            .triangles
            .par_iter()
            .map(|t| {
                let real = t.iter().all(|&v| (half.ids[v as usize] as usize) < self.n);
                real && ((key(t[0]) + key(t[1]) + key(t[2])) / 3.0 < self.median) == left
            })
            .collect();
        let far: Vec<Option<([f64; 2], f64)>> = half
            .rt
            .triangles
            .par_iter()
            .zip(&kept)
            .filter(|(_, &k)| k)
            .filter_map(|(t, _)| {
                let circle = self.orthocircle(t.map(|v| half.ids[v as usize]));
                let Some((c, rho)) = circle else {
                    return Some(None);
                };
                // The farthest a point of weight w_out in conflict can lie.
                let across = c[1 - self.axis];
                let off = across.clamp(self.across.0, self.across.1) - across;
                let r2 = rho + w_out - off * off;
                let reach = r2.max(0.0).sqrt() * (1.0 + 1e-9) + 1e-12 * edge.abs();
                let safe = r2 < 0.0
                    || if left {
                        c[self.axis] + reach < edge
                    } else {
                        c[self.axis] - reach >= edge
                    };
                (!safe).then_some(circle)
            })
            .collect();
        if far.len() > MAX_FAR {
            return None;
        }
        let clear = |(c, rho): ([f64; 2], f64)| {
            beyond.par_iter().all(|&i| {
                let p = self.points[i];
                let d2 = (p[0] - c[0]).powi(2) + (p[1] - c[1]).powi(2);
                d2 - rho - self.weights[i] > 1e-9 * (d2 + rho.abs())
            })
        };
        far.into_iter()
            .all(|circle| circle.is_some_and(clear))
            .then_some(kept)
    }

    /// The orthogonal circle (centre, squared radius) of three weighted
    /// points, in doubles; None when they are nearly collinear.
    fn orthocircle(&self, t: [u32; 3]) -> Option<([f64; 2], f64)> {
        let [a, b, c] = t.map(|v| self.points[v as usize]);
        let (u, v) = ([b[0] - a[0], b[1] - a[1]], [c[0] - a[0], c[1] - a[1]]);
        let size = u[0].abs() + u[1].abs() + v[0].abs() + v[1].abs();
        if (u[0] * v[1] - u[1] * v[0]).abs() <= 0.5e-12 * size * size {
            return None;
        }
        let o = centre_f64([a, b, c], t.map(|v| self.weights[v as usize]));
        let rho = (o[0] - a[0]).powi(2) + (o[1] - a[1]).powi(2) - self.weights[t[0] as usize];
        Some((o, rho))
    }
}

/// Directed edges (a, b) without a neighbour yet -> their slot.
type Open = FastMap<(u32, u32), usize>;

/// Triangles with their adjacency (NONE: none yet or the boundary) and
/// the hidden points.
struct Parts {
    tris: Vec<[u32; 3]>,
    adj: Vec<[u32; 3]>,
    hidden: Vec<u32>,
}

impl Parts {
    /// Adds triangles with their neighbours among them (`adj`: indices into
    /// `tris`, NONE for none); the edges without one go to `open` as
    /// (a, b) -> slot 3 t + k. False when a directed edge is open twice.
    fn add(&mut self, tris: Vec<[u32; 3]>, adj: Vec<[u32; 3]>, open: &mut Open) -> bool {
        let first = self.tris.len();
        let unpaired: Vec<((u32, u32), usize)> = tris
            .par_iter()
            .zip(&adj)
            .enumerate()
            .flat_map_iter(|(t, (tri, a))| {
                (0..3)
                    .filter(move |&k| a[k] == NONE)
                    .map(move |k| ((tri[k], tri[(k + 1) % 3]), 3 * (first + t) + k))
            })
            .collect();
        for (edge, slot) in unpaired {
            if open.insert(edge, slot).is_some() {
                return false;
            }
        }
        let shift = |u: u32| if u == NONE { NONE } else { first as u32 + u };
        self.adj
            .par_extend(adj.into_par_iter().map(|a| a.map(shift)));
        self.tris.extend(tris);
        true
    }

    /// Pairs open edges with open reverses; the rest stay open.
    fn pair(&mut self, open: &Open) {
        for (&(a, b), &slot) in open {
            if let Some(&twin) = open.get(&(b, a)) {
                self.adj[slot / 3][slot % 3] = (twin / 3) as u32;
            }
        }
    }
}

/// The triangles of `rt` that `keep` marks, with `map` applied to their
/// vertices, and their neighbours among them (renumbered; NONE for none).
fn kept_part(
    rt: &Triangulation,
    keep: &[bool],
    map: impl Fn(u32) -> u32 + Sync,
) -> (Vec<[u32; 3]>, Vec<[u32; 3]>) {
    let ids: Vec<u32> = (0..keep.len() as u32)
        .into_par_iter()
        .filter(|&t| keep[t as usize])
        .collect();
    let mut new_id = vec![NONE; keep.len()];
    for (i, &t) in ids.iter().enumerate() {
        new_id[t as usize] = i as u32;
    }
    let tris = ids
        .par_iter()
        .map(|&t| rt.triangles[t as usize].map(&map))
        .collect();
    let adj = ids
        .par_iter()
        .map(|&t| {
            rt.adj[t as usize].map(|u| {
                if u != NONE && keep[u as usize] {
                    new_id[u as usize]
                } else {
                    NONE
                }
            })
        })
        .collect();
    (tris, adj)
}

/// The kept triangles of both halves in global indices, paired with their
/// neighbours; the edges left open bound the kept region. None when a
/// directed edge is kept twice.
fn stitch(halves: [(&Half, &Vec<bool>); 2]) -> Option<(Parts, Open)> {
    let part = |(half, kept): (&Half, &Vec<bool>)| {
        kept_part(&half.rt, kept, |v: u32| half.ids[v as usize])
    };
    let both = rayon::join(|| part(halves[0]), || part(halves[1]));
    let mut parts = Parts {
        tris: vec![],
        adj: vec![],
        hidden: vec![],
    };
    let mut open = FastMap::default();
    for ((half, _), (tris, adj)) in halves.into_iter().zip([both.0, both.1]) {
        parts
            .hidden
            .extend(half.rt.hidden.iter().map(|&v| half.ids[v as usize]));
        if !parts.add(tris, adj, &mut open) {
            return None;
        }
    }
    parts.pair(&open);
    open.retain(|_, slot| parts.adj[*slot / 3][*slot % 3] == NONE);
    Some((parts, open))
}

/// Adds the triangles between the kept region and the hull: those of the
/// regular triangulation of the region's boundary points outside it
/// (reached from the open edges without crossing one). None when an open
/// edge is no edge there, or a point is in no triangle and not hidden.
fn fill<B: Backend + ?Sized>(
    backend: &B,
    seam: &Seam,
    (mut parts, open): (Parts, Open),
) -> Result<Option<Triangulation>> {
    let mut ring: Vec<u32> = open.keys().flat_map(|&(a, b)| [a, b]).collect();
    ring.sort_unstable();
    ring.dedup();
    let local: FastMap<u32, u32> = ring
        .iter()
        .enumerate()
        .map(|(i, &v)| (v, i as u32))
        .collect();
    let p: Vec<[f64; 2]> = ring.iter().map(|&v| seam.points[v as usize]).collect();
    let w: Vec<f64> = ring.iter().map(|&v| seam.weights[v as usize]).collect();
    let rt = backend.regular(&p, &w)?;
    // Pocket triangles: flood from the reverse of each open edge.
    let mut pocket = vec![false; rt.triangles.len()];
    let mut stack = vec![];
    for &(a, b) in open.keys() {
        let (la, lb) = (local[&a], local[&b]);
        if !rt.has_edge(la, lb) {
            return Ok(None);
        }
        stack.extend(rt.left_of(lb, la));
    }
    let closed = |t: &[u32; 3], k: usize| {
        open.contains_key(&(ring[t[(k + 1) % 3] as usize], ring[t[k] as usize]))
    };
    while let Some(t) = stack.pop() {
        if std::mem::replace(&mut pocket[t as usize], true) {
            continue;
        }
        let tri = rt.triangles[t as usize];
        for k in 0..3 {
            let u = rt.adj[t as usize][k];
            if u != NONE && !closed(&tri, k) && !pocket[u as usize] {
                stack.push(u);
            }
        }
    }
    let (tris, adj) = kept_part(&rt, &pocket, |v: u32| ring[v as usize]);
    let mut open2 = open.clone();
    if !parts.add(tris, adj, &mut open2) {
        return Ok(None);
    }
    parts.pair(&open2);
    let Parts {
        tris,
        adj,
        mut hidden,
    } = parts;
    // (hidden frame points are no concern)
    hidden.retain(|&v| (v as usize) < seam.n);
    hidden.sort_unstable();
    hidden.dedup();
    let mut seen = vec![false; seam.n];
    for &v in tris.iter().flatten().chain(&hidden) {
        seen[v as usize] = true;
    }
    if seen.contains(&false) {
        return Ok(None);
    }
    Ok(Some(Triangulation::from_arrays(tris, adj, hidden)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::scatter;

    fn cloud(n: u64) -> (Vec<[f64; 2]>, Vec<f64>) {
        (0..n)
            .map(|i| {
                let p = [scatter(2 * i) * 300.0, scatter(2 * i + 1) * 100.0];
                (p, scatter(7 * i + 3) * 0.5)
            })
            .unzip()
    }

    fn canon(t: &Triangulation) -> Vec<[u32; 3]> {
        let mut v: Vec<[u32; 3]> = t
            .triangles
            .iter()
            .map(|&t| {
                let r = (0..3).min_by_key(|&k| t[k]).unwrap();
                [t[r], t[(r + 1) % 3], t[(r + 2) % 3]]
            })
            .collect();
        v.sort_unstable();
        v
    }

    /// On every backend: the halves give the whole's triangles, hidden
    /// points and edge pairing, or nothing.
    fn same_as_whole(p: &[[f64; 2]], w: &[f64]) -> usize {
        let mut stitched = 0;
        for b in crate::backend::compiled() {
            let whole = b.regular(p, w).unwrap();
            let Some(split) = regular_in_halves(&*b, p, w) else {
                continue;
            };
            stitched += 1;
            assert_eq!(canon(&split), canon(&whole), "{}", b.name());
            assert_eq!(split.hidden, whole.hidden);
            for (a, b, t, u) in split.edge_triangles() {
                assert!(split.triangles[t as usize].contains(&a));
                assert_eq!(u, split.left_of(b, a));
            }
        }
        stitched
    }

    #[test]
    fn halves_give_the_whole_triangulation() {
        let (p, w) = cloud(MIN_POINTS as u64 + 2_000);
        assert_eq!(same_as_whole(&p, &w), crate::backend::compiled().len());
        // A lattice (many cocircular points) along a straight hull, with
        // weights nudged apart as the site diagram does.
        let (p, w): (Vec<[f64; 2]>, Vec<f64>) = (0..MIN_POINTS as u64 + 1_000)
            .map(|i| {
                let p = [(i % 150) as f64, (i / 150) as f64];
                (p, 1e-9 * (scatter(i) - 0.5))
            })
            .unzip();
        assert_eq!(same_as_whole(&p, &w), crate::backend::compiled().len());
    }

    #[test]
    fn a_wide_gap_at_the_median_is_stitched_or_left_whole() {
        // Two clusters with nothing between them: the seam's triangles are
        // long; whichever way it goes, never a wrong triangulation.
        let (mut p, w) = cloud(MIN_POINTS as u64 + 2_000);
        for q in p.iter_mut() {
            if q[0] > 150.0 {
                q[0] += 5_000.0;
            }
        }
        same_as_whole(&p, &w);
    }

    #[test]
    fn a_frame_beyond_doubles_leaves_the_whole_to_the_caller() {
        // Points spread over the whole range of doubles: the frame around
        // them is not finite; the halves give up (a backend may refuse or
        // panic on such points) and leave the whole to the caller.
        let (p, w) = cloud(MIN_POINTS as u64 + 10);
        let p: Vec<[f64; 2]> = p.iter().map(|q| [q[0] * 1e306 - 1.5e308, q[1]]).collect();
        for b in crate::backend::compiled() {
            assert!(regular_in_halves(&*b, &p, &w).is_none(), "{}", b.name());
        }
    }

    #[test]
    fn small_inputs_are_left_whole() {
        let b = crate::backend::default_backend();
        let (p, w) = cloud(100);
        assert!(regular_in_halves(&b, &p, &w).is_none());
    }
}
