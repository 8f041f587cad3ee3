//! Sites of the conforming power diagram (paper section 4, Theorem 1;
//! method.md section 4). Each site moves on a line `base + t n` inside the
//! dual edge it was chosen on; its weight makes it have power w_i at each
//! vertex p_i of the simplex it serves, exactly:
//! omega_s = |s - p_i|^2 - w_i.

use crate::backend::Triangulation;
use crate::complex::Complex;
use crate::exact::{
    add, cross, dot, is_pos, norm2, one, power_centre, q, qi, qp, ratio, round, scale, sub, zero,
    QPoint, Q,
};
use rayon::prelude::*;
use std::cmp::Ordering;
use std::collections::HashMap;

/// What a site is for.
#[derive(Debug, Clone, PartialEq)]
pub enum Role {
    /// One of the two sites of a segment, left or right of it (i -> j).
    Segment { seg: u32, left: bool },
    /// An extra site on the dual of the non-constraint edge (i, k), for the
    /// free ends and isolated vertices among `serves`.
    Vertex { edge: (u32, u32), serves: Vec<u32> },
}

/// The line a site moves on, t in the open interval (ta, tb) or towards tb.
#[derive(Debug, Clone)]
struct Track {
    base: QPoint,
    dir: QPoint,
    ta: Q,
    tb: Q,
    /// A vertex of the simplex served, for the weight.
    anchor: u32,
}

/// All sites, exact.
#[derive(Debug, Clone, Default)]
pub struct Sites {
    pub pos: Vec<QPoint>,
    pub weight: Vec<Q>,
    pub role: Vec<Role>,
    /// Nearest doubles of (x, y, weight), for filters and reports.
    pub approx: Vec<[f64; 3]>,
    track: Vec<Track>,
    /// Position on the track as the fraction (t - ta) / (tb - ta).
    frac: Vec<Q>,
    /// Whether relocation may move the site.
    pub movable: Vec<bool>,
    points: Vec<QPoint>,
    weights: Vec<Q>,
    /// Power centres of the triangles of RT(w), computed in parallel.
    centres: Vec<QPoint>,
}

/// Shortest dual edge, relative to its primal edge, that carries a vertex site.
const MIN_DUAL: f64 = 1e-3;

/// Fractions tried in turn for a vertex site that is outside its cell.
const VERTEX_FRACS: [(i64, i64); 5] = [(1, 2), (1, 4), (3, 4), (1, 8), (7, 8)];

impl Sites {
    /// Places the sites: two per segment on opposite sides when the segment
    /// crosses its dual, then extra sites for free ends and isolated vertices.
    pub fn place(cx: &Complex, w: &[f64], rt: &Triangulation, sys3_failed: &[u32]) -> Sites {
        let points: Vec<QPoint> = cx.points.iter().map(|&p| qp(p)).collect();
        let weights: Vec<Q> = w.iter().map(|&x| q(x)).collect();
        let centres = rt
            .triangles
            .par_iter()
            .map(|tri| {
                let [a, b, c] = tri.map(|v| v as usize);
                power_centre(
                    [&points[a], &points[b], &points[c]],
                    [&weights[a], &weights[b], &weights[c]],
                )
                .expect("triangles of a regular triangulation are not flat")
            })
            .collect();
        let mut s = Sites {
            points,
            weights,
            centres,
            ..Default::default()
        };
        let failed: std::collections::HashSet<u32> = sys3_failed.iter().copied().collect();
        for (k, &[i, j]) in cx.segments.iter().enumerate() {
            let (base, dir, tl, tr) = s.dual_line(rt, i, j);
            // (left, ta, tb, fraction, movable) of the two sites
            let placements = if failed.contains(&(k as u32)) {
                // The dual edge misses the segment: both sites on it, fixed.
                let ta = tr.unwrap_or_else(|| {
                    tl.clone()
                        .expect("a segment of RT(w) has a triangle beside it")
                        - qi(2)
                });
                let tb = tl.unwrap_or_else(|| ta.clone() + qi(2));
                [
                    (true, ta.clone(), tb.clone(), ratio(2, 3), false),
                    (false, ta, tb, ratio(1, 3), false),
                ]
            } else {
                // Left site in (0, tl), right in (tr, 0); a ray is cut at |e|.
                [
                    (true, zero(), tl.unwrap_or_else(one), ratio(1, 2), true),
                    (
                        false,
                        zero(),
                        tr.unwrap_or_else(|| -one()),
                        ratio(1, 2),
                        true,
                    ),
                ]
            };
            for (left, ta, tb, frac, movable) in placements {
                let tk = Track {
                    base: base.clone(),
                    dir: dir.clone(),
                    ta,
                    tb,
                    anchor: i,
                };
                s.push(
                    Role::Segment {
                        seg: k as u32,
                        left,
                    },
                    tk,
                    frac,
                    movable,
                );
            }
        }
        s.place_vertex_sites(cx, rt);
        s
    }

    fn push(&mut self, role: Role, track: Track, frac: Q, movable: bool) {
        let (pos, weight) = self.at(&track, &frac);
        self.approx.push([
            crate::exact::f(&pos[0]),
            crate::exact::f(&pos[1]),
            crate::exact::f(&weight),
        ]);
        self.pos.push(pos);
        self.weight.push(weight);
        self.role.push(role);
        self.track.push(track);
        self.frac.push(frac);
        self.movable.push(movable);
    }

    /// Position and weight at a fraction of the track. The parameter t is
    /// rounded to a double when that keeps it strictly inside the track, so
    /// that positions stay short rationals.
    fn at(&self, tk: &Track, frac: &Q) -> (QPoint, Q) {
        let exact_t = &tk.ta + (&tk.tb - &tk.ta) * frac;
        let short = round(&exact_t);
        let inside = |t: &Q| {
            let (lo, hi) = if tk.ta < tk.tb {
                (&tk.ta, &tk.tb)
            } else {
                (&tk.tb, &tk.ta)
            };
            t > lo && t < hi
        };
        let t = if inside(&short) { short } else { exact_t };
        let pos = add(&tk.base, &scale(&tk.dir, &t));
        let a = tk.anchor as usize;
        let weight = norm2(&sub(&pos, &self.points[a])) - &self.weights[a];
        (pos, weight)
    }

    /// The radical line of (i, j) as base + t n, with n the left normal of
    /// i -> j, and the parameters of the power centres of the triangles left
    /// and right of i -> j (None: that side is a ray).
    fn dual_line(
        &self,
        rt: &Triangulation,
        i: u32,
        j: u32,
    ) -> (QPoint, QPoint, Option<Q>, Option<Q>) {
        let (pi, pj) = (&self.points[i as usize], &self.points[j as usize]);
        let (wi, wj) = (&self.weights[i as usize], &self.weights[j as usize]);
        let u = sub(pj, pi);
        let l = norm2(&u);
        // lambda = (L + w_i - w_j) / (2 L)
        let lambda = (&l + wi - wj) / (&l * qi(2));
        let base = add(pi, &scale(&u, &lambda));
        let dir = [-u[1].clone(), u[0].clone()];
        let param = |a: u32, b: u32| {
            rt.left_of(a, b).map(|t| {
                let c = self.centre(t);
                dot(&sub(&c, &base), &dir) / &l
            })
        };
        (base.clone(), dir.clone(), param(i, j), param(j, i))
    }

    fn centre(&self, t: u32) -> QPoint {
        self.centres[t as usize].clone()
    }

    /// Extra sites: one for a free end, three for an isolated vertex, on
    /// duals of non-constraint edges of positive length (method.md section 4).
    fn place_vertex_sites(&mut self, cx: &Complex, rt: &Triangulation) {
        let degree = cx.degrees();
        let n = cx.points.len();
        let nb = rt.neighbours(n);
        let segs: std::collections::HashSet<(u32, u32)> = cx
            .segments
            .iter()
            .map(|s| (s[0].min(s[1]), s[0].max(s[1])))
            .collect();
        let mut other_end = vec![u32::MAX; n];
        for &[a, b] in &cx.segments {
            other_end[a as usize] = b;
            other_end[b as usize] = a;
        }
        let mut on_edge: HashMap<(u32, u32), usize> = HashMap::new();
        for i in 0..n as u32 {
            let want = match degree[i as usize] {
                0 => 3,
                1 => 1,
                _ => continue,
            };
            // Candidate edges with a dual of positive length.
            let pi = &self.points[i as usize];
            let mut cands: Vec<(u32, Track)> = vec![];
            for &k in &nb[i as usize] {
                if segs.contains(&(i.min(k), i.max(k))) {
                    continue;
                }
                let (base, dir, tl, tr) = self.dual_line(rt, i, k);
                let (ta, tb) = match (tr, tl) {
                    // t is in units of |p_k - p_i|: a dual edge far shorter
                    // than the edge itself gives a sliver cell.
                    (Some(a), Some(b)) if crate::exact::f(&(&b - &a)) > MIN_DUAL => (a, b),
                    (Some(_), Some(_)) => continue, // (nearly) zero-length dual
                    (Some(a), None) => (a.clone(), a + one()),
                    (None, Some(b)) => (b.clone() - one(), b),
                    (None, None) => continue,
                };
                cands.push((
                    k,
                    Track {
                        base,
                        dir,
                        ta,
                        tb,
                        anchor: i,
                    },
                ));
            }
            let dirs: Vec<QPoint> = cands
                .iter()
                .map(|(k, _)| sub(&self.points[*k as usize], pi))
                .collect();
            let chosen: Vec<usize> = if want == 1 {
                // The edge pointing most away from the segment.
                let away = sub(&self.points[other_end[i as usize] as usize], pi);
                let score = |d: &QPoint| {
                    let c = crate::exact::f(&dot(d, &away));
                    c / (crate::exact::f(&norm2(d)).sqrt() + f64::MIN_POSITIVE)
                };
                (0..cands.len())
                    .min_by(|&a, &b| score(&dirs[a]).total_cmp(&score(&dirs[b])))
                    .into_iter()
                    .collect()
            } else {
                spanning_triple(&dirs)
                    .map(|t| t.to_vec())
                    .unwrap_or_default()
            };
            if chosen.is_empty() {
                // No usable dual edges (a vertex where diagonals cross, or all
                // its edges are constraints): points inside its power cell
                // serve it just as well (Theorem 1 only needs them in the cell).
                for tk in self.in_cell_tracks(rt, i, want) {
                    self.push(
                        Role::Vertex {
                            edge: (i, i),
                            serves: vec![i],
                        },
                        tk,
                        ratio(1, 2),
                        true,
                    );
                }
                continue;
            }
            for c in chosen {
                let (k, tk) = cands[c].clone();
                let key = (i.min(k), i.max(k));
                if let Some(&s) = on_edge.get(&key) {
                    if let Role::Vertex { serves, .. } = &mut self.role[s] {
                        serves.push(i);
                    }
                    continue;
                }
                on_edge.insert(key, self.pos.len());
                self.push(
                    Role::Vertex {
                        edge: key,
                        serves: vec![i],
                    },
                    tk,
                    ratio(1, 2),
                    true,
                );
            }
        }
    }

    /// Tracks from the centroid of the power cell of vertex i towards `count`
    /// of its corners, chosen not collinear: sites on them lie strictly
    /// inside the cell.
    fn in_cell_tracks(&self, rt: &Triangulation, i: u32, count: usize) -> Vec<Track> {
        let mut corners: Vec<QPoint> = vec![];
        for (t, tri) in rt.triangles.iter().enumerate() {
            if tri.contains(&i) {
                let c = self.centre(t as u32);
                if !corners.contains(&c) {
                    corners.push(c);
                }
            }
        }
        if corners.len() < 3 {
            return vec![];
        }
        let k = qi(corners.len() as i64);
        let g = [
            corners.iter().map(|c| &c[0]).sum::<Q>() / &k,
            corners.iter().map(|c| &c[1]).sum::<Q>() / &k,
        ];
        // the first corner, the farthest from it, and the farthest from their line
        let far = |from: &QPoint| {
            (0..corners.len())
                .max_by_key(|&c| norm2(&sub(&corners[c], from)))
                .unwrap()
        };
        let a = 0;
        let b = far(&corners[a]);
        let c = (0..corners.len())
            .max_by_key(|&c| {
                crate::exact::abs(&cross(
                    &sub(&corners[b], &corners[a]),
                    &sub(&corners[c], &corners[a]),
                ))
            })
            .unwrap();
        [a, b, c]
            .iter()
            .take(count)
            .map(|&k| Track {
                base: g.clone(),
                dir: sub(&corners[k], &g),
                ta: zero(),
                tb: one(),
                anchor: i,
            })
            .collect()
    }

    /// Moves a site that is outside its cell because of the sites in
    /// `against`: a segment site moves towards its segment, at least halfway
    /// and, when the power difference with those sites (a quadratic in its
    /// position, solved in doubles) says so, to half the position where it
    /// turns positive (of the fractions tried, the one with the largest
    /// smallest margin on the shared inputs); a vertex site tries the next fraction of its
    /// dual edge. Returns false when the site cannot move further. Whether
    /// the new position is inside is decided exactly afterwards.
    pub fn step(&mut self, s: usize, against: &[usize]) -> bool {
        if !self.movable[s] {
            return false;
        }
        let next = match &self.role[s] {
            Role::Segment { .. } => {
                let cur = crate::exact::f(&self.frac[s]);
                let target = against
                    .iter()
                    .fold(cur / 2.0, |t, &b| t.min(0.5 * self.inside_below(s, b, cur)));
                if target < 1.0 / (1u64 << 40) as f64 {
                    return false;
                }
                q(target)
            }
            Role::Vertex { .. } => {
                let at = VERTEX_FRACS
                    .iter()
                    .position(|&(a, b)| ratio(a, b) == self.frac[s]);
                match at.map(|k| k + 1).filter(|&k| k < VERTEX_FRACS.len()) {
                    Some(k) => ratio(VERTEX_FRACS[k].0, VERTEX_FRACS[k].1),
                    None => return false,
                }
            }
        };
        let (pos, weight) = self.at(&self.track[s], &next);
        self.approx[s] = [
            crate::exact::f(&pos[0]),
            crate::exact::f(&pos[1]),
            crate::exact::f(&weight),
        ];
        self.pos[s] = pos;
        self.weight[s] = weight;
        self.frac[s] = next;
        true
    }

    /// For segment site a on its track a(f) = base + f (tb - ta) dir (ta = 0),
    /// the smallest positive root of g(f) = |a(f) - b|^2 + omega_a(f) - omega_b
    /// below `cur` (a is inside with respect to b where g > 0), or `cur`
    /// when g has none there or is not positive at the segment itself.
    fn inside_below(&self, a: usize, b: usize, cur: f64) -> f64 {
        let tk = &self.track[a];
        let fv =
            |p: &QPoint| nalgebra::Vector2::new(crate::exact::f(&p[0]), crate::exact::f(&p[1]));
        let d = fv(&tk.dir) * crate::exact::f(&(&tk.tb - &tk.ta));
        let base = fv(&tk.base);
        let anchor = fv(&self.points[tk.anchor as usize]);
        let sb = nalgebra::Vector2::new(self.approx[b][0], self.approx[b][1]);
        let (wa, wb) = (
            crate::exact::f(&self.weights[tk.anchor as usize]),
            self.approx[b][2],
        );
        // g(f) = 2|d|^2 f^2 + 2 f d.(2 base - b - p) + |base - b|^2 + |base - p|^2 - w - omega_b
        let qa = 2.0 * d.norm_squared();
        let qb = 2.0 * d.dot(&(2.0 * base - sb - anchor));
        let qc = (base - sb).norm_squared() + (base - anchor).norm_squared() - wa - wb;
        let disc = qb * qb - 4.0 * qa * qc;
        if !(qc > 0.0 && qa > 0.0 && disc > 0.0) {
            return cur;
        }
        let r1 = (-qb - disc.sqrt()) / (2.0 * qa);
        if r1 > 0.0 && r1 < cur {
            r1
        } else {
            cur
        }
    }

    /// The input vertices at which this site has the power of that vertex's
    /// weight by construction (both ends of its segment, or of its edge).
    pub fn served(&self, s: usize, cx: &Complex) -> [u32; 2] {
        match &self.role[s] {
            Role::Segment { seg, .. } => cx.segments[*seg as usize],
            Role::Vertex { edge, .. } => [edge.0, edge.1],
        }
    }

    /// Human-readable name of a site, with the input's ids.
    pub fn describe(&self, s: usize, cx: &Complex) -> String {
        match &self.role[s] {
            Role::Segment { seg, left } => format!(
                "site {s} ({} side of segment {})",
                if *left { "left" } else { "right" },
                cx.segment_ids[*seg as usize]
            ),
            Role::Vertex { serves, .. } => {
                let ids: Vec<String> = serves
                    .iter()
                    .map(|&v| cx.vertex_ids[v as usize].to_string())
                    .collect();
                format!("site {s} (extra site of vertex {})", ids.join(", "))
            }
        }
    }

    /// The pairs of sites of each segment: (left, right).
    pub fn segment_pairs(&self, nseg: usize) -> Vec<[u32; 2]> {
        let mut pairs = vec![[u32::MAX; 2]; nseg];
        for (s, r) in self.role.iter().enumerate() {
            if let Role::Segment { seg, left } = r {
                pairs[*seg as usize][usize::from(!*left)] = s as u32;
            }
        }
        pairs
    }

    pub fn len(&self) -> usize {
        self.pos.len()
    }

    pub fn is_empty(&self) -> bool {
        self.pos.is_empty()
    }
}

/// Three directions that positively span the plane, as spread as possible.
fn spanning_triple(dirs: &[QPoint]) -> Option<[usize; 3]> {
    let ang: Vec<f64> = dirs
        .iter()
        .map(|d| crate::exact::f(&d[1]).atan2(crate::exact::f(&d[0])))
        .collect();
    let mut best: Option<([usize; 3], f64)> = None;
    for a in 0..dirs.len() {
        for b in a + 1..dirs.len() {
            for c in b + 1..dirs.len() {
                // Positively spanning iff the origin is strictly inside the
                // triangle of the three directions (exact).
                let o = [zero(), zero()];
                let sides = [(a, b), (b, c), (c, a)]
                    .map(|(x, y)| cross(&sub(&dirs[y], &dirs[x]), &sub(&o, &dirs[x])).cmp(&zero()));
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

/// Whether site a lies strictly inside its cell with respect to neighbour b:
/// |a - b|^2 + omega_a - omega_b > 0. Decided in doubles when a bound on
/// their error allows it, exactly otherwise.
pub fn inside_wrt(sites: &Sites, a: usize, b: usize) -> bool {
    let ([xa, ya, wa], [xb, yb, wb]) = (sites.approx[a], sites.approx[b]);
    let v = (xa - xb) * (xa - xb) + (ya - yb) * (ya - yb) + wa - wb;
    // Each input is within a relative 2^-53 of its exact value; 16 ulps of
    // the magnitudes involved bound the error of v generously.
    let bound = 16.0
        * f64::EPSILON
        * ((xa.abs() + xb.abs()).powi(2) + (ya.abs() + yb.abs()).powi(2) + wa.abs() + wb.abs());
    // (Tiny magnitudes could be subnormal, where that bound fails: exact.)
    if v.is_finite() && bound.is_finite() && bound > 1e-280 && v.abs() > bound {
        return v > 0.0;
    }
    let d = norm2(&sub(&sites.pos[a], &sites.pos[b]));
    is_pos(&(d + &sites.weight[a] - &sites.weight[b]))
}
