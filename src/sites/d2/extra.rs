//! Extra sites (paper section 4, Theorem 1): one for a free end, three for
//! an isolated vertex, and the exact check that each stays in the power
//! cells of the vertices it serves.

use super::{Def, Role, Sites, Track, MIN_DUAL, VERTEX_FRACS};
use crate::backend::Triangulation;
use crate::complex::Complex;
use crate::geom::{orient, Dyadic, Filter};
use crate::{FastMap, FastSet};
use rayon::prelude::*;
use std::cmp::Ordering;

impl Sites {
    /// Extra sites: one for a free end, three for an isolated vertex, on
    /// duals of non-constraint edges of positive length (docs/method.md section 4).
    pub(super) fn place_vertex_sites(&mut self, cx: &Complex, rt: &Triangulation) {
        let degree = cx.degrees();
        let n = cx.points.len();
        // Neighbours (in the order of rt.edges()) of the vertices served.
        let mut nb = vec![Vec::new(); n];
        for (a, b) in rt.edges() {
            for (x, y) in [(a, b), (b, a)] {
                if degree[x as usize] < 2 {
                    nb[x as usize].push(y);
                }
            }
        }
        let segs: FastSet<(u32, u32)> = cx
            .segments
            .iter()
            .map(|s| (s[0].min(s[1]), s[0].max(s[1])))
            .collect();
        let mut other_end = vec![u32::MAX; n];
        for &[a, b] in &cx.segments {
            other_end[a as usize] = b;
            other_end[b as usize] = a;
        }
        let mut on_edge: FastMap<(u32, u32), usize> = FastMap::default();
        // New sites, pushed together at the end (their enclosures are made
        // in parallel there); site `first + k` is pending[k].
        let (first, mut pending) = (self.def.len(), vec![]);
        self.cell_walls = vec![vec![]; n];
        for i in 0..n as u32 {
            let want = match degree[i as usize] {
                0 => 3,
                1 => 1,
                _ => continue,
            };
            self.cell_walls[i as usize] = nb[i as usize].clone();
            // Candidate edges with a dual of positive length.
            let pi = self.points[i as usize];
            let mut cands: Vec<(u32, Track)> = vec![];
            for &k in &nb[i as usize] {
                if segs.contains(&(i.min(k), i.max(k))) {
                    continue;
                }
                let (ta, tb) = match self.dual_params(rt, i, k) {
                    // t is in units of |p_k - p_i|: a dual edge far shorter
                    // than the edge itself gives a sliver cell.
                    (Some(b), Some(a)) if b - a > MIN_DUAL => (a, b),
                    (Some(_), Some(_)) => continue, // (nearly) zero-length dual
                    (None, Some(a)) => (a, a + 1.0),
                    (Some(b), None) => (b - 1.0, b),
                    (None, None) => continue,
                };
                let kind = Def::Line { i, j: k, t: 0.0 };
                cands.push((
                    k,
                    Track {
                        ta,
                        tb,
                        kind,
                        dir: [0.0; 2],
                    },
                ));
            }
            let chosen: Vec<usize> = if want == 1 {
                // The edge pointing most away from the segment.
                let o = self.points[other_end[i as usize] as usize];
                let away = [o[0] - pi[0], o[1] - pi[1]];
                let score = |k: u32| {
                    let p = self.points[k as usize];
                    let d = [p[0] - pi[0], p[1] - pi[1]];
                    (d[0] * away[0] + d[1] * away[1]) / (d[0].hypot(d[1]) + f64::MIN_POSITIVE)
                };
                (0..cands.len())
                    .min_by(|&a, &b| score(cands[a].0).total_cmp(&score(cands[b].0)))
                    .into_iter()
                    .collect()
            } else {
                let others: Vec<[f64; 2]> = cands
                    .iter()
                    .map(|(k, _)| self.points[*k as usize])
                    .collect();
                spanning_triple(pi, &others)
                    .map(|t| t.to_vec())
                    .unwrap_or_default()
            };
            if chosen.is_empty() {
                // No usable dual edges (a vertex where diagonals cross, or all
                // its edges are constraints): points inside its power cell
                // serve it just as well (Theorem 1 only needs them in the cell).
                let tracks = self.in_cell_tracks(rt, i, want);
                if tracks.len() < want {
                    self.starved.push(i);
                }
                for tk in tracks {
                    let role = Role::Vertex {
                        edge: (i, i),
                        serves: vec![i],
                    };
                    pending.push([(role, tk, 0.5, true)]);
                }
                continue;
            }
            for c in chosen {
                let (k, tk) = cands[c].clone();
                let key = (i.min(k), i.max(k));
                if let Some(&s) = on_edge.get(&key) {
                    if let Role::Vertex { serves, .. } = &mut pending[s - first][0].0 {
                        serves.push(i);
                    }
                    continue;
                }
                on_edge.insert(key, first + pending.len());
                let role = Role::Vertex {
                    edge: key,
                    serves: vec![i],
                };
                pending.push([(role, tk, 0.5, true)]);
            }
        }
        self.extend(pending);
        // The tracks' ends are power centres in doubles: in a sliver cell
        // the middle may lie outside it, so the first fraction inside is
        // taken (decided exactly).
        let off: Vec<usize> = (first..self.def.len())
            .into_par_iter()
            .filter(|&v| matches!(self.role[v], Role::Vertex { .. }) && !self.in_served_cells(v))
            .collect();
        for v in off {
            let inside = VERTEX_FRACS.iter().find(|&&f| {
                self.move_to(v, f);
                self.in_served_cells(v)
            });
            self.move_to(v, inside.copied().unwrap_or(VERTEX_FRACS[0]));
        }
    }

    /// Tracks from the centroid of the power cell of vertex i towards `count`
    /// of its corners, chosen not collinear: sites on them lie inside the cell.
    fn in_cell_tracks(&self, rt: &Triangulation, i: u32, count: usize) -> Vec<Track> {
        // Its triangles in index order (from its star; a hull vertex's by a scan).
        let mut star = rt.star(i).unwrap_or_else(|| {
            (0..rt.triangles.len() as u32)
                .filter(|&t| rt.triangles[t as usize].contains(&i))
                .collect()
        });
        star.sort_unstable();
        let mut corners: Vec<[f64; 2]> = vec![];
        for t in star {
            if !corners.contains(&self.centres[t as usize]) {
                corners.push(self.centres[t as usize]);
            }
        }
        if corners.len() < 3 {
            return vec![];
        }
        let k = corners.len() as f64;
        let g = [
            corners.iter().map(|c| c[0]).sum::<f64>() / k,
            corners.iter().map(|c| c[1]).sum::<f64>() / k,
        ];
        // the first corner, the farthest from it, and the farthest from their line
        let d2 = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2);
        let a = 0;
        let b = (0..corners.len())
            .max_by(|&x, &y| d2(corners[x], corners[a]).total_cmp(&d2(corners[y], corners[a])))
            .unwrap();
        let area = |c: usize| {
            let (pa, pb, pc) = (corners[a], corners[b], corners[c]);
            ((pb[0] - pa[0]) * (pc[1] - pa[1]) - (pb[1] - pa[1]) * (pc[0] - pa[0])).abs()
        };
        // Not a or b again, even where the corners look collinear in doubles.
        let c = (0..corners.len())
            .filter(|&x| x != a && x != b)
            .max_by(|&x, &y| area(x).total_cmp(&area(y)))
            .unwrap_or(b);
        [a, b, c]
            .iter()
            .take(count)
            .map(|&k| Track {
                ta: 0.0,
                tb: 1.0,
                kind: Def::Free { p: g, anchor: i },
                dir: [corners[k][0] - g[0], corners[k][1] - g[1]],
            })
            .collect()
    }

    /// Whether vertex site s lies in the closed power cells (of RT(w)) of
    /// the vertices it serves, exactly: Theorem 1 needs it there, and
    /// positions computed in doubles may miss a sliver cell.
    pub fn in_served_cells(&self, s: usize) -> bool {
        let Role::Vertex { serves, .. } = &self.role[s] else {
            return true;
        };
        let [i, j, _] = self.served_by(s);
        serves.iter().all(|&v| {
            let walls = self.cell_walls.get(v as usize).map_or(&[][..], |w| &w[..]);
            walls
                .iter()
                .filter(|&&k| !(k == i && v == j || k == j && v == i))
                .all(|&k| self.nearer(s, v, k) != Ordering::Less)
        })
    }

    /// The sign of pow_k(x) - pow_v(x) at site s's position x, where
    /// pow_v(x) = |x - p_v|^2 - w_v: linear in x.
    fn nearer(&self, s: usize, v: u32, k: u32) -> Ordering {
        let (pv, pk) = (self.points[v as usize], self.points[k as usize]);
        let (wv, wk) = (self.weights[v as usize], self.weights[k as usize]);
        // pow_k - pow_v at x, in a filter's arithmetic.
        fn expr<T: Filter>(x: [T; 3], (pv, wv): ([f64; 2], f64), (pk, wk): ([f64; 2], f64)) -> T {
            let d = |a: [f64; 2]| (x[0] - T::of(a[0])).sqr() + (x[1] - T::of(a[1])).sqr();
            d(pk) - T::of(wk) - d(pv) + T::of(wv)
        }
        let (v, k) = ((pv, wv), (pk, wk));
        // Times H^2 > 0 at the homogeneous position (X, Y) / H.
        self.decide(
            expr(self.ev(s), v, k),
            || expr(self.iv(s), v, k),
            || {
                let [x, y, _, h] = self.homogeneous(s);
                let h2 = h.sqr();
                let power = |p: [f64; 2], w: f64| {
                    let dx = &x - &(&h * &Dyadic::of(p[0]));
                    let dy = &y - &(&h * &Dyadic::of(p[1]));
                    &(&dx.sqr() + &dy.sqr()) - &(&h2 * &Dyadic::of(w))
                };
                (&power(pk, wk) - &power(pv, wv)).sign()
            },
        )
    }
}

/// Three of the points around p whose directions from p positively span the
/// plane (p strictly inside their triangle, exact), as spread as possible.
fn spanning_triple(p: [f64; 2], around: &[[f64; 2]]) -> Option<[usize; 3]> {
    let ang: Vec<f64> = around
        .iter()
        .map(|d| (d[1] - p[1]).atan2(d[0] - p[0]))
        .collect();
    let mut best: Option<([usize; 3], f64)> = None;
    for a in 0..around.len() {
        for b in a + 1..around.len() {
            for c in b + 1..around.len() {
                let sides = [(a, b), (b, c), (c, a)].map(|(x, y)| orient(around[x], around[y], p));
                if !(sides.iter().all(|&s| s == Ordering::Greater)
                    || sides.iter().all(|&s| s == Ordering::Less))
                {
                    continue;
                }
                let mut t = [ang[a], ang[b], ang[c]];
                t.sort_by(f64::total_cmp);
                let gap = (t[1] - t[0])
                    .max(t[2] - t[1])
                    .max(t[0] + std::f64::consts::TAU - t[2]);
                if best.as_ref().is_none_or(|(_, g)| gap < *g) {
                    best = Some(([a, b, c], gap));
                }
            }
        }
    }
    best.map(|(t, _)| t)
}
