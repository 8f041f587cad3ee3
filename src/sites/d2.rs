//! Sites of the conforming power diagram (paper section 4, Theorem 1;
//! docs/method.md section 4). A site is defined exactly by doubles: a parameter t
//! on the radical line of two input vertices i, j (base + t n, n the left
//! normal of i -> j), or a double point serving one vertex. Its weight gives
//! it power w_i at each vertex p_i it serves, exactly:
//! omega_s = |s - p_i|^2 - w_i. Predicates on sites are filtered with
//! intervals and fall back to exact rationals; four sites serving a common
//! vertex are co-orthogonal by construction, which decides the degenerate
//! power tests at input vertices without arithmetic.

use crate::backend::Triangulation;
use crate::complex::Complex;
use crate::generate::scatter;
use crate::geom::{
    by_columns, centre_f64, column_max, det3, det3_f, det3_sign, det4_sign, diff, lifted, q, qp,
    sign_beyond, Dyadic, Ev, Filter, Iv, QPoint, Q,
};
use rayon::prelude::*;
use std::cmp::Ordering;
use std::sync::atomic::{AtomicUsize, Ordering::Relaxed};

mod corner;
mod extra;

/// How far along its dual edge (in lengths of its segment) a segment's
/// site is looked for.
const DUAL_REACH: f64 = 1e4;

/// What a site is for.
#[derive(Debug, Clone, PartialEq)]
pub enum Role {
    /// One of the two sites of a segment, left or right of it (i -> j).
    Segment { seg: u32, left: bool },
    /// An extra site on the dual of the non-constraint edge (i, k), for the
    /// free ends and isolated vertices among `serves`; (i, i) for a site
    /// inside the power cell of i.
    Vertex { edge: (u32, u32), serves: Vec<u32> },
    /// The one domain-side site of the two segments (seg, left) at a
    /// convex corner of the domain (`corner.rs`).
    Corner { segs: [(u32, bool); 2] },
}

/// A site, exactly.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Def {
    /// p_i + lambda u + t J u with u = p_j - p_i, J u its left normal and
    /// lambda = (|u|^2 + w_i - w_j) / (2 |u|^2): on the radical line of i, j.
    Line { i: u32, j: u32, t: f64 },
    /// A double point serving `anchor`.
    Free { p: [f64; 2], anchor: u32 },
    /// The power centre of a triangle of RT(w), serving its three vertices.
    Centre { tri: [u32; 3] },
}

/// Where a site may move: t in (ta, tb) on a line, or base + t dir.
#[derive(Debug, Clone)]
struct Track {
    ta: f64,
    tb: f64,
    kind: Def,
    dir: [f64; 2],
}

/// All sites.
#[derive(Debug, Default)]
pub struct Sites {
    pub def: Vec<Def>,
    pub role: Vec<Role>,
    /// Enclosures of (x, y, weight).
    pub iv: Vec<[Iv; 3]>,
    /// Doubles inside them (`approx`) and what else the filters read.
    hot: Vec<Hot>,
    track: Vec<Track>,
    /// Position on the track as the fraction (t - ta) / (tb - ta).
    frac: Vec<f64>,
    /// Whether relocation may move the site.
    pub movable: Vec<bool>,
    points: Vec<[f64; 2]>,
    weights: Vec<f64>,
    /// Power centres of the triangles of RT(w), approximately (placement only).
    centres: Vec<[f64; 2]>,
    /// Neighbours in RT(w) of the vertices that vertex sites serve (empty
    /// for the others): their half-planes bound the power cells in which
    /// those sites must stay.
    cell_walls: Vec<Vec<u32>>,
    /// Free ends and isolated vertices that got fewer extra sites than
    /// they need: their power cells have no room for them in doubles.
    pub starved: Vec<u32>,
    /// Predicates the intervals could not decide.
    pub exact_evaluations: AtomicUsize,
}

/// A site's doubles (inside its enclosures), their distances from the exact
/// values, and the input vertices it serves: what the filtered predicates
/// read, in one cache line (three arrays cost three misses a site on large
/// inputs).
#[derive(Debug, Clone, Copy)]
#[repr(align(64))]
struct Hot {
    m: [f64; 3],
    r: [f64; 3],
    served: [u32; 3],
}

impl Hot {
    fn of(def: &Def, iv: &[Iv; 3]) -> Hot {
        let m = iv.map(Iv::mid);
        Hot {
            m,
            r: std::array::from_fn(|k| (iv[k].hi - m[k]).max(m[k] - iv[k].lo)),
            served: match *def {
                Def::Line { i, j, .. } => [i, j, j],
                Def::Free { anchor, .. } => [anchor; 3],
                Def::Centre { tri } => tri,
            },
        }
    }
}

/// Shortest dual edge, relative to its primal edge, that carries a vertex site.
const MIN_DUAL: f64 = 1e-3;

/// Fractions tried in turn for a vertex site placed outside the cells it
/// serves.
const VERTEX_FRACS: [f64; 5] = [0.5, 0.25, 0.75, 0.125, 0.875];

/// Positions sampled on its track when a vertex site outside its own cell
/// moves (measured on `generate field 6` with two points a cavity: the
/// five fractions above left 19 sites outside, 17 fractions 5).
const VERTEX_SAMPLES: usize = 64;

impl Sites {
    /// Places the sites: two per segment on opposite sides when the segment
    /// crosses its dual, then extra sites for free ends and isolated vertices.
    /// `domain_side[k]` says whether the left and right of segment k are in
    /// the domain: a site outside never meets a domain cell except at its
    /// segment (the radical line of its pair is the segment's line wherever
    /// it is), so it goes at a scattered fraction of its dual edge, which
    /// keeps symmetric holes (a regular well polygon) from being nearly
    /// co-orthogonal, a case only exact arithmetic could decide. With
    /// `corners`, one site serves both segments at a convex corner of the
    /// domain where it can (`corner.rs`).
    pub fn place(
        cx: &Complex,
        w: &[f64],
        rt: &Triangulation,
        sys3_failed: &[u32],
        domain_side: &[[bool; 2]],
        corners: bool,
    ) -> Sites {
        let p = &cx.points;
        let centres = rt
            .triangles
            .par_iter()
            .map(|tri| {
                let [a, b, c] = tri.map(|v| v as usize);
                centre_f64([p[a], p[b], p[c]], [w[a], w[b], w[c]])
            })
            .collect();
        let mut s = Sites {
            points: cx.points.clone(),
            weights: w.to_vec(),
            centres,
            ..Default::default()
        };
        let mut failed = vec![false; cx.segments.len()];
        for &k in sys3_failed {
            failed[k as usize] = true;
        }
        // Segment sites are independent of one another: placed in parallel.
        let placed: Vec<[corner::Placed; 2]> = cx
            .segments
            .par_iter()
            .enumerate()
            .map(|(k, &[i, j])| {
                // a site may lie anywhere on its dual edge: its far end
                // kept within reach (a sliver on the hull, split points of
                // a side rounded a hair inward, puts it beyond doubles)
                let (tl, tr) = s.dual_params(rt, i, j);
                let (tl, tr) = (
                    tl.map(|t| t.min(DUAL_REACH)),
                    tr.map(|t| t.max(-DUAL_REACH)),
                );
                // (left, ta, tb, fraction, movable) of the two sites
                let placements = if failed[k] {
                    // The dual edge misses the segment: both sites on it, fixed.
                    let ta = tr.unwrap_or_else(|| {
                        tl.expect("a segment of RT(w) has a triangle beside it") - 2.0
                    });
                    let tb = tl.unwrap_or(ta + 2.0);
                    [
                        (true, ta, tb, 2.0 / 3.0, false),
                        (false, ta, tb, 1.0 / 3.0, false),
                    ]
                } else {
                    // Left site in (0, tl), right in (tr, 0); a ray is cut at |e|.
                    let frac = |side: usize| {
                        if domain_side[k][side] {
                            0.5
                        } else {
                            0.3 + 0.4 * scatter(2 * k as u64 + side as u64)
                        }
                    };
                    [
                        (true, 0.0, tl.unwrap_or(1.0), frac(0), true),
                        (false, 0.0, tr.unwrap_or(-1.0), frac(1), true),
                    ]
                };
                placements.map(|(left, ta, tb, frac, movable)| {
                    let kind = Def::Line { i, j, t: 0.0 };
                    let tk = Track {
                        ta,
                        tb,
                        kind,
                        dir: [0.0; 2],
                    };
                    let role = Role::Segment {
                        seg: k as u32,
                        left,
                    };
                    (role, tk, frac, movable)
                })
            })
            .collect();
        // Room for all sites at once: the extra sites of free ends and
        // isolated vertices would otherwise copy the arrays again.
        let extra: usize = cx
            .degrees()
            .iter()
            .map(|&d| [3, 1, 0][d.min(2) as usize])
            .sum();
        s.reserve(2 * cx.segments.len() + extra);
        match corners {
            true => {
                let found = s.corners(cx, rt, domain_side);
                s.extend(corner::with_corners(placed, &found));
            }
            false => s.extend(placed),
        }
        s.place_vertex_sites(cx, rt);
        s
    }

    /// Pushes many sites whose tracks and fractions are given: their
    /// definitions and enclosures are computed in parallel.
    fn extend<const K: usize>(&mut self, sites: Vec<[(Role, Track, f64, bool); K]>) {
        // Written in place, in parallel: the pages of these arrays are
        // first touched here (a sequential push of 10^5 sites costs more
        // than their enclosures).
        let mut out = (
            std::mem::take(&mut self.def),
            (
                std::mem::take(&mut self.iv),
                (
                    std::mem::take(&mut self.hot),
                    (
                        std::mem::take(&mut self.role),
                        (
                            std::mem::take(&mut self.track),
                            (
                                std::mem::take(&mut self.frac),
                                std::mem::take(&mut self.movable),
                            ),
                        ),
                    ),
                ),
            ),
        );
        let item = |k: usize| {
            let (role, track, frac, movable) = &sites[k / K][k % K];
            let def = Self::at(track, *frac);
            let iv = self.enclose(&def);
            let rest = (role.clone(), (track.clone(), (*frac, *movable)));
            (def, (iv, (Hot::of(&def, &iv), rest)))
        };
        out.par_extend((0..K * sites.len()).into_par_iter().map(item));
        let (def, (iv, (hot, (role, (track, (frac, movable)))))) = out;
        (self.def, self.iv, self.hot) = (def, iv, hot);
        (self.role, self.track, self.frac, self.movable) = (role, track, frac, movable);
    }

    fn reserve(&mut self, n: usize) {
        self.def.reserve(n);
        self.iv.reserve(n);
        self.hot.reserve(n);
        self.role.reserve(n);
        self.track.reserve(n);
        self.frac.reserve(n);
        self.movable.reserve(n);
    }

    #[cfg(test)]
    fn push(&mut self, role: Role, track: Track, frac: f64, movable: bool) {
        self.extend(vec![[(role, track, frac, movable)]]);
    }

    fn set(&mut self, s: usize, def: Def) {
        self.def[s] = def;
        self.iv[s] = self.enclose(&def);
        self.hot[s] = Hot::of(&def, &self.iv[s]);
    }

    /// The site at a fraction of its track.
    fn at(tk: &Track, frac: f64) -> Def {
        let t = tk.ta + (tk.tb - tk.ta) * frac;
        match tk.kind {
            Def::Line { i, j, .. } => Def::Line { i, j, t },
            Def::Free { p, anchor } => Def::Free {
                p: [p[0] + t * tk.dir[0], p[1] + t * tk.dir[1]],
                anchor,
            },
            Def::Centre { .. } => tk.kind,
        }
    }

    /// Intervals around the exact position and weight.
    fn enclose(&self, d: &Def) -> [Iv; 3] {
        let pt = |v: u32| self.points[v as usize].map(Iv::of);
        match *d {
            Def::Line { i, j, t } => {
                let (pi, pj) = (pt(i), pt(j));
                let (wi, wj) = (self.weights[i as usize], self.weights[j as usize]);
                let u = [pj[0] - pi[0], pj[1] - pi[1]];
                let l = u[0].sqr() + u[1].sqr();
                let lambda = if wi == wj {
                    Iv::of(0.5)
                } else {
                    (l + Iv::of(wi) - Iv::of(wj)) / (l * Iv::of(2.0))
                };
                let t = Iv::of(t);
                [
                    pi[0] + lambda * u[0] - t * u[1],
                    pi[1] + lambda * u[1] + t * u[0],
                    l * (lambda.sqr() + t.sqr()) - Iv::of(wi),
                ]
            }
            Def::Free { p, anchor } => {
                let a = pt(anchor);
                let (x, y) = (Iv::of(p[0]), Iv::of(p[1]));
                [
                    x,
                    y,
                    (x - a[0]).sqr() + (y - a[1]).sqr() - Iv::of(self.weights[anchor as usize]),
                ]
            }
            Def::Centre { tri } => {
                let (p, w) = self.centre_q(tri);
                [Iv::of_q(&p[0]), Iv::of_q(&p[1]), Iv::of_q(&w)]
            }
        }
    }

    /// The exact position and weight (rationals, made when a filter cannot
    /// decide: rarely, so not kept).
    pub fn exact(&self, s: usize) -> (QPoint, Q) {
        {
            let pt = |v: u32| qp(self.points[v as usize]);
            match self.def[s] {
                Def::Line { i, j, t } => {
                    let (pi, pj) = (pt(i), pt(j));
                    let (wi, wj) = (q(self.weights[i as usize]), q(self.weights[j as usize]));
                    let u = [&pj[0] - &pi[0], &pj[1] - &pi[1]];
                    let l = &u[0] * &u[0] + &u[1] * &u[1];
                    let lambda = (&l + &wi - wj) / (&l * Q::from(2));
                    let t = q(t);
                    let pos = [
                        &pi[0] + &lambda * &u[0] - &t * &u[1],
                        &pi[1] + &lambda * &u[1] + &t * &u[0],
                    ];
                    let w = l * (&lambda * &lambda + &t * &t) - wi;
                    (pos, w)
                }
                Def::Free { p, anchor } => {
                    let a = pt(anchor);
                    let pos = qp(p);
                    let d = [&pos[0] - &a[0], &pos[1] - &a[1]];
                    let w = &d[0] * &d[0] + &d[1] * &d[1] - q(self.weights[anchor as usize]);
                    (pos, w)
                }
                Def::Centre { tri } => self.centre_q(tri),
            }
        }
    }

    /// Site s's (x, y, weight) in doubles, inside its enclosures.
    pub fn approx(&self, s: usize) -> [f64; 3] {
        self.hot[s].m
    }

    /// The input vertices at which this site has that vertex's weight as its
    /// power, by construction (repeated to fill three).
    pub fn served_by(&self, s: usize) -> [u32; 3] {
        self.hot[s].served
    }

    /// An input vertex served by all the given sites, if any.
    pub fn common_vertex(&self, sites: &[usize]) -> Option<u32> {
        let first = self.served_by(sites[0]);
        first
            .into_iter()
            .find(|v| sites[1..].iter().all(|&s| self.served_by(s).contains(v)))
    }

    /// A predicate's sign: its expression in doubles with running error
    /// bounds (`quick`), else in intervals (`filtered`), else `exact`.
    fn decide(
        &self,
        quick: Ev,
        filtered: impl FnOnce() -> Iv,
        exact: impl FnOnce() -> Ordering,
    ) -> Ordering {
        quick
            .sign()
            .or_else(|| filtered().sign())
            .unwrap_or_else(|| {
                self.exact_evaluations.fetch_add(1, Relaxed);
                exact()
            })
    }

    /// Site s's position and weight in each filter's arithmetic.
    fn ev(&self, s: usize) -> [Ev; 3] {
        let h = &self.hot[s];
        [0, 1, 2].map(|k| Ev::off_by(h.m[k], h.r[k]))
    }

    fn iv(&self, s: usize) -> [Iv; 3] {
        self.iv[s]
    }

    /// Site s exactly and homogeneously, [X, Y, W, H]: its position is
    /// (X, Y) / H and its weight W / H^2, with H > 0. Polynomials in the
    /// defining doubles, so predicates on them need no division (`exact`
    /// gives the rationals).
    pub(crate) fn homogeneous(&self, s: usize) -> [Dyadic; 4] {
        let d = |x: f64| Dyadic::of(x);
        let pt = |v: u32| self.points[v as usize].map(d);
        let wt = |v: u32| d(self.weights[v as usize]);
        match self.def[s] {
            Def::Line { i, j, t } => {
                let (pi, pj) = (pt(i), pt(j));
                let u = [&pj[0] - &pi[0], &pj[1] - &pi[1]];
                let l = &u[0].sqr() + &u[1].sqr();
                // lambda = a / h with h = 2 l.
                let a = &(&l + &wt(i)) - &wt(j);
                let h = &l * &Dyadic::int(2);
                let ht = &h * &d(t);
                let x = &(&(&h * &pi[0]) + &(&a * &u[0])) - &(&ht * &u[1]);
                let y = &(&(&h * &pi[1]) + &(&a * &u[1])) + &(&ht * &u[0]);
                // H^2 (l (lambda^2 + t^2) - w_i) = l a^2 + l h^2 t^2 - h^2 w_i.
                let h2 = h.sqr();
                let w = &(&(&l * &a.sqr()) + &(&(&l * &h2) * &d(t).sqr())) - &(&h2 * &wt(i));
                [x, y, w, h]
            }
            Def::Free { p, anchor } => {
                let (p, a) = (p.map(d), pt(anchor));
                let w = &(&(&p[0] - &a[0]).sqr() + &(&p[1] - &a[1]).sqr()) - &wt(anchor);
                let [x, y] = p;
                [x, y, w, Dyadic::int(1)]
            }
            Def::Centre { tri } => self.centre_homogeneous(tri),
        }
    }

    /// Site x's doubles and how far its exact values may be from them.
    fn near(&self, x: usize) -> ([f64; 3], [f64; 3]) {
        (self.hot[x].m, self.hot[x].r)
    }

    /// Differences of positions x - o in doubles, with their bounds
    /// (`geom::diff`).
    fn diff(&self, x: usize, o: usize) -> ([f64; 2], [f64; 2]) {
        let ((mx, rx), (mo, ro)) = (self.near(x), self.near(o));
        diff((&mx, &rx), (&mo, &ro))
    }

    /// The semi-static filter of `orient`: det [b - a; c - a] in doubles,
    /// beyond what the sites' rounding and the arithmetic can change.
    fn orient_f64(&self, [a, b, c]: [usize; 3]) -> Option<Ordering> {
        let ((u, eu), (v, ev)) = (self.diff(b, a), self.diff(c, a));
        let det = u[0] * v[1] - u[1] * v[0];
        let x = column_max(&[u.map(f64::abs), v.map(f64::abs)]);
        let (p0, p1) = by_columns(x, column_max(&[eu, ev]), 2.0);
        sign_beyond(det, p0, p1, 16.0)
    }

    /// The semi-static filter of `power_test`: `power_expr` in doubles
    /// (rows relative to d), as `geom::Weighted3::power_f64` in 3D.
    fn power_f64(&self, [a, b, c, d]: [usize; 4]) -> Option<Ordering> {
        let weight = |s: usize| {
            let (m, r) = self.near(s);
            (m[2], r[2])
        };
        // the entries, and per column the largest magnitude and error
        let (mut rows, mut x, mut y) = ([[0.0; 3]; 3], [0.0f64; 3], [0.0f64; 3]);
        for (i, s) in [a, b, c].into_iter().enumerate() {
            let (dd, eta) = self.diff(s, d);
            let (z, mag, err) = lifted((dd, eta), weight(s), weight(d));
            rows[i] = [dd[0], dd[1], z];
            for k in 0..2 {
                (x[k], y[k]) = (x[k].max(dd[k].abs()), y[k].max(eta[k]));
            }
            (x[2], y[2]) = (x[2].max(mag), y[2].max(err));
        }
        let (p0, p1) = by_columns(x, y, 6.0);
        let det = det3_f(rows[0], rows[1], rows[2]);
        sign_beyond(det, p0, p1, 64.0)
    }

    /// Orientation of three sites (Greater: counter-clockwise).
    pub fn orient(&self, a: usize, b: usize, c: usize) -> Ordering {
        let t = [a, b, c];
        if let Some(s) = self.orient_f64(t) {
            return s;
        }
        // det [x y 1] of the three, each row times its H > 0.
        self.decide(
            orient_expr(t.map(|s| self.ev(s))),
            || orient_expr(t.map(|s| self.iv(s))),
            || {
                let h = t.map(|s| self.homogeneous(s));
                det3_sign(h.each_ref().map(|[x, y, _, w]| [x, y, w]))
            },
        )
    }

    /// Power test: Greater when d has less power than the orthogonal circle of
    /// the counter-clockwise triangle (a, b, c) requires (their edge is not
    /// regular), Equal when the four are co-orthogonal.
    pub fn power_test(&self, a: usize, b: usize, c: usize, d: usize) -> Ordering {
        if self.common_vertex(&[a, b, c, d]).is_some() {
            return Ordering::Equal;
        }
        let t = [a, b, c, d];
        if let Some(s) = self.power_f64(t) {
            return s;
        }
        // The same determinant is det [x y (x^2 + y^2 - w) 1] of a, b, c, d;
        // each row times H^2 > 0.
        self.decide(
            power_expr(t.map(|s| self.ev(s))),
            || power_expr(t.map(|s| self.iv(s))),
            || {
                let rows = t.map(|s| {
                    let [x, y, w, h] = self.homogeneous(s);
                    let z = &(&x.sqr() + &y.sqr()) - &w;
                    [&x * &h, &y * &h, z, h.sqr()]
                });
                det4_sign(&rows)
            },
        )
    }

    /// Whether site a lies strictly inside its cell with respect to site b:
    /// |a - b|^2 + omega_a - omega_b > 0.
    pub fn inside_wrt(&self, a: usize, b: usize) -> bool {
        // Times H_a^2 H_b^2 > 0.
        let t = [a, b];
        self.decide(
            inside_expr(t.map(|s| self.ev(s))),
            || inside_expr(t.map(|s| self.iv(s))),
            || {
                let [[xa, ya, wa, ha], [xb, yb, wb, hb]] = t.map(|s| self.homogeneous(s));
                let dx = &(&xa * &hb) - &(&xb * &ha);
                let dy = &(&ya * &hb) - &(&yb * &ha);
                let lhs = &(&dx.sqr() + &dy.sqr()) + &(&wa * &hb.sqr());
                (&lhs - &(&wb * &ha.sqr())).sign()
            },
        ) == Ordering::Greater
    }

    /// The parameters of the power centres of the triangles left and right
    /// of i -> j on its radical line base + t J(p_j - p_i) (None: a ray).
    fn dual_params(&self, rt: &Triangulation, i: u32, j: u32) -> (Option<f64>, Option<f64>) {
        let (pi, pj) = (self.points[i as usize], self.points[j as usize]);
        let (wi, wj) = (self.weights[i as usize], self.weights[j as usize]);
        let u = [pj[0] - pi[0], pj[1] - pi[1]];
        let l = u[0] * u[0] + u[1] * u[1];
        let lambda = (l + wi - wj) / (2.0 * l);
        let base = [pi[0] + lambda * u[0], pi[1] + lambda * u[1]];
        let param = |t: Option<u32>| {
            t.map(|t| {
                let c = self.centres[t as usize];
                ((c[0] - base[0]) * -u[1] + (c[1] - base[1]) * u[0]) / l
            })
        };
        let [left, right] = rt.beside(i, j);
        (param(left), param(right))
    }

    /// Moves a site that is outside its cell because of the sites in
    /// `against`: a segment site moves towards its segment, at least halfway
    /// and, when the power difference with those sites (a quadratic in its
    /// position, solved in doubles) says so, to half the position where it
    /// turns positive (of the fractions tried, the one with the largest
    /// smallest margin on the shared inputs); a vertex site tries the next
    /// fraction of its track. Returns false when the site cannot move
    /// further. Whether the new position is inside is decided exactly afterwards.
    pub fn step(&mut self, s: usize, against: &[usize]) -> bool {
        if !self.movable[s] {
            return false;
        }
        let cur = self.frac[s];
        let next = match &self.role[s] {
            Role::Segment { .. } => {
                let target = against
                    .iter()
                    .fold(cur / 2.0, |t, &b| t.min(0.5 * self.inside_below(s, b, cur)));
                if target < 1.0 / (1u64 << 40) as f64 {
                    return false;
                }
                target
            }
            Role::Corner { .. } => return false,
            Role::Vertex { .. } => {
                // The sampled fraction farthest inside the faces with
                // `against` (its neighbours), among those better than now
                // and inside the cells it serves (decided exactly).
                // A hidden site has no neighbours to weigh: it walks the
                // fixed fractions from where it is in them (or from the first).
                let better: Vec<f64> = if against.is_empty() {
                    let from = VERTEX_FRACS
                        .iter()
                        .position(|&f| f == cur)
                        .map_or(0, |k| k + 1);
                    VERTEX_FRACS[from..].to_vec()
                } else {
                    let now = self.depth(s, cur, against);
                    let mut better: Vec<(f64, f64)> = (1..VERTEX_SAMPLES)
                        .map(|k| k as f64 / VERTEX_SAMPLES as f64)
                        .map(|f| (self.depth(s, f, against), f))
                        .filter(|&(d, _)| d > now)
                        .collect();
                    better.sort_by(|a, b| b.0.total_cmp(&a.0));
                    better.into_iter().map(|(_, f)| f).collect()
                };
                let next = better.into_iter().find(|&f| {
                    self.move_to(s, f);
                    self.in_served_cells(s)
                });
                match next {
                    Some(f) => f,
                    None => {
                        self.move_to(s, cur);
                        return false;
                    }
                }
            }
        };
        self.move_to(s, next);
        true
    }

    /// How far site s at fraction f of its track would be inside its faces
    /// with the sites `against` (the smallest distance to their radical
    /// lines, negative beyond one), in doubles: a heuristic for choosing
    /// where to move, never a decision.
    fn depth(&self, s: usize, f: f64, against: &[usize]) -> f64 {
        let [x, y, w] = self.enclose(&Self::at(&self.track[s], f)).map(Iv::mid);
        against
            .iter()
            .map(|&b| {
                let [bx, by, bw] = self.approx(b);
                let d2 = (x - bx).powi(2) + (y - by).powi(2);
                (d2 + w - bw) / (2.0 * d2.sqrt())
            })
            .fold(f64::INFINITY, f64::min)
    }

    /// Where site s is on its track.
    pub fn frac(&self, s: usize) -> f64 {
        self.frac[s]
    }

    /// Puts site s at a fraction of its track.
    pub fn move_to(&mut self, s: usize, frac: f64) {
        let def = Self::at(&self.track[s], frac);
        self.set(s, def);
        self.frac[s] = frac;
    }

    /// Whether s is a segment site (it moves continuously along its track;
    /// a vertex site jumps between fixed fractions).
    pub fn on_segment(&self, s: usize) -> bool {
        matches!(self.role[s], Role::Segment { .. })
    }

    /// For segment site a on its track a(f) = base + f (tb - ta) n (ta = 0),
    /// the smallest positive root of g(f) = |a(f) - b|^2 + omega_a(f) - omega_b
    /// below `cur` (a is inside with respect to b where g > 0), or `cur`
    /// when g has none there or is not positive at the segment itself.
    fn inside_below(&self, a: usize, b: usize, cur: f64) -> f64 {
        let tk = &self.track[a];
        let Def::Line { i, j, .. } = tk.kind else {
            return cur;
        };
        let v = |p: [f64; 2]| nalgebra::Vector2::new(p[0], p[1]);
        let (pi, pj) = (v(self.points[i as usize]), v(self.points[j as usize]));
        let (wi, wj) = (self.weights[i as usize], self.weights[j as usize]);
        let u = pj - pi;
        let lambda = (u.norm_squared() + wi - wj) / (2.0 * u.norm_squared());
        let base = pi + lambda * u;
        let d = nalgebra::Vector2::new(-u[1], u[0]) * (tk.tb - tk.ta);
        let [bx, by, wb] = self.approx(b);
        let sb = nalgebra::Vector2::new(bx, by);
        // g(f) = 2|d|^2 f^2 + 2 f d.(2 base - b - p) + |base - b|^2 + |base - p|^2 - w - omega_b
        let qa = 2.0 * d.norm_squared();
        let qb = 2.0 * d.dot(&(2.0 * base - sb - pi));
        let qc = (base - sb).norm_squared() + (base - pi).norm_squared() - wi - wb;
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

    /// Weights for a triangulation of the rounded sites, each shifted by a
    /// fixed pseudo-random 1e-9 of itself: the sites around an input vertex
    /// are co-orthogonal, which a floating-point filter cannot decide, so a
    /// backend would fall back to exact arithmetic at every vertex. Nudged,
    /// they are triangulated in some order, which is as good (the check
    /// accepts any triangulation of a co-orthogonal group); a real decision
    /// below 1e-9 that the nudge gets wrong is caught by the exact check and
    /// flipped.
    pub fn nudged_weights(&self) -> Vec<f64> {
        self.hot
            .iter()
            .enumerate()
            .map(|(s, h)| h.m[2] * (1.0 + 1e-9 * (scatter(s as u64) - 0.5)))
            .collect()
    }

    /// The power centre of three sites in doubles, with an estimate of its
    /// error: the inputs are off by their enclosures' widths, and far sites
    /// with large weights cancel.
    pub fn centre_estimate(&self, t: [u32; 3]) -> ([f64; 2], f64) {
        let [a, b, c] = t.map(|s| self.approx(s as usize));
        let u = [b[0] - a[0], b[1] - a[1]];
        let v = [c[0] - a[0], c[1] - a[1]];
        let det = (u[0] * v[1] - u[1] * v[0]).abs();
        let width = |k: usize| {
            t.iter()
                .map(|&s| self.iv[s as usize][k])
                .map(|x| x.hi - x.lo)
                .fold(0.0, f64::max)
        };
        let big = a
            .iter()
            .chain(&b)
            .chain(&c)
            .fold(0.0f64, |m, x| m.max(x.abs()));
        let e = width(0).max(width(1)) + 4.0 * f64::EPSILON * big; // of a coordinate
        let ew = width(2) + 4.0 * f64::EPSILON * big * big; // of a weight
        let (lu, lv) = (u[0].hypot(u[1]), v[0].hypot(v[1]));
        let mu = lu * lu + a[2].abs() + b[2].abs();
        let mv = lv * lv + a[2].abs() + c[2].abs();
        let dmu = 2.0 * lu * e + 2.0 * ew + 4.0 * f64::EPSILON * mu;
        let dmv = 2.0 * lv * e + 2.0 * ew + 4.0 * f64::EPSILON * mv;
        let ddet = 4.0 * f64::EPSILON * lu * lv + 2.0 * e * (lu + lv);
        let centre = centre_f64(
            [[a[0], a[1]], [b[0], b[1]], [c[0], c[1]]],
            [a[2], b[2], c[2]],
        );
        let off = (centre[0] - a[0]).abs().max((centre[1] - a[1]).abs());
        let err = e + (dmu * lv + dmv * lu + (mu + mv) * 2.0 * e) / (2.0 * det) + off * ddet / det;
        (centre, if err.is_finite() { err } else { f64::INFINITY })
    }

    /// The power centre of three sites in interval arithmetic from their
    /// enclosures: a rigorous enclosure of each coordinate.
    pub fn centre_interval(&self, t: [u32; 3]) -> [Iv; 2] {
        let [a, b, c] = t.map(|s| self.iv[s as usize]);
        let u = [b[0] - a[0], b[1] - a[1]];
        let v = [c[0] - a[0], c[1] - a[1]];
        let two_det = (u[0] * v[1] - u[1] * v[0]) * Iv::of(2.0);
        let ru = u[0].sqr() + u[1].sqr() - (b[2] - a[2]);
        let rv = v[0].sqr() + v[1].sqr() - (c[2] - a[2]);
        [
            a[0] + (ru * v[1] - rv * u[1]) / two_det,
            a[1] + (rv * u[0] - ru * v[0]) / two_det,
        ]
    }

    /// The power centre of three sites exactly, rounded to doubles: from
    /// their homogeneous coordinates in dyadic integers, with one rational
    /// division per coordinate at the end.
    pub fn centre_exact(&self, t: [u32; 3]) -> [f64; 2] {
        self.exact_evaluations.fetch_add(1, Relaxed);
        let [[x0, y0, w0, h0], [x1, y1, w1, h1], [x2, y2, w2, h2]] =
            t.map(|s| self.homogeneous(s as usize));
        // u = p1 - p0 and v = p2 - p0 times h0 h1 and h0 h2.
        let u = [&(&x1 * &h0) - &(&x0 * &h1), &(&y1 * &h0) - &(&y0 * &h1)];
        let v = [&(&x2 * &h0) - &(&x0 * &h2), &(&y2 * &h0) - &(&y0 * &h2)];
        let det = &(&u[0] * &v[1]) - &(&u[1] * &v[0]);
        if det.sign() == Ordering::Equal {
            return self.centre_estimate(t).0;
        }
        // y = c - p0 solves 2 y.u = |u|^2 - w1 + w0, 2 y.v = |v|^2 - w2 + w0,
        // whose right sides are ru / (h0 h1)^2 and rv / (h0 h2)^2.
        let h0s = h0.sqr();
        let ru = &(&(&u[0].sqr() + &u[1].sqr()) - &(&w1 * &h0s)) + &(&w0 * &h1.sqr());
        let rv = &(&(&v[0].sqr() + &v[1].sqr()) - &(&w2 * &h0s)) + &(&w0 * &h2.sqr());
        let (ru, rv) = (&ru * &h2, &rv * &h1);
        // c = (2 det h1 h2 p0 h0 + n) / (2 det h0 h1 h2).
        let two_det_h12 = &(&det * &Dyadic::int(2)) * &(&h1 * &h2);
        let den = (&two_det_h12 * &h0).exact();
        let nx = &(&ru * &v[1]) - &(&rv * &u[1]);
        let ny = &(&rv * &u[0]) - &(&ru * &v[0]);
        let coord =
            |p: &Dyadic, n: &Dyadic| crate::geom::f(&((&(&two_det_h12 * p) + n).exact() / &den));
        [coord(&x0, &nx), coord(&y0, &ny)]
    }

    /// A site whose position or weight is beyond the range of doubles, or
    /// that doubles cannot tell from the other site of its segment.
    pub fn unrepresentable(&self) -> Option<usize> {
        // The other site of each segment site's pair (a vector, not a map:
        // two million sites at 10^6 segments).
        let mut partner = vec![u32::MAX; self.len()];
        for [l, r] in self.segment_pairs(self.len()) {
            if l != u32::MAX && r != u32::MAX {
                (partner[l as usize], partner[r as usize]) = (r, l);
            }
        }
        (0..self.len()).into_par_iter().position_first(|s| {
            self.iv[s]
                .iter()
                .any(|x| !(x.lo.is_finite() && x.hi.is_finite()))
                || (partner[s] != u32::MAX && self.def[partner[s] as usize] == self.def[s])
        })
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
            Role::Corner { segs } => format!(
                "site {s} (corner site of segments {} and {})",
                cx.segment_ids[segs[0].0 as usize], cx.segment_ids[segs[1].0 as usize]
            ),
        }
    }

    /// The pairs of sites of each segment: (left, right).
    pub fn segment_pairs(&self, nseg: usize) -> Vec<[u32; 2]> {
        let mut pairs = vec![[u32::MAX; 2]; nseg];
        for (s, r) in self.role.iter().enumerate() {
            match r {
                Role::Segment { seg, left } => pairs[*seg as usize][usize::from(!*left)] = s as u32,
                Role::Corner { segs } => {
                    for (seg, left) in segs {
                        pairs[*seg as usize][usize::from(!*left)] = s as u32;
                    }
                }
                Role::Vertex { .. } => {}
            }
        }
        pairs
    }

    pub fn len(&self) -> usize {
        self.def.len()
    }

    pub fn is_empty(&self) -> bool {
        self.def.is_empty()
    }
}

/// det [b - a, c - a] of three sites' positions, in a filter's arithmetic.
fn orient_expr<T: Filter>([a, b, c]: [[T; 3]; 3]) -> T {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// The power test of sites a, b, c, d (rows relative to d).
fn power_expr<T: Filter>([a, b, c, d]: [[T; 3]; 4]) -> T {
    let row = |p: [T; 3]| {
        let (dx, dy) = (p[0] - d[0], p[1] - d[1]);
        [dx, dy, dx.sqr() + dy.sqr() - p[2] + d[2]]
    };
    det3([row(a), row(b), row(c)])
}

/// |a - b|^2 + omega_a - omega_b.
fn inside_expr<T: Filter>([a, b]: [[T; 3]; 2]) -> T {
    (a[0] - b[0]).sqr() + (a[1] - b[1]).sqr() + a[2] - b[2]
}

impl crate::backend::FlipTests for Sites {
    fn orient(&self, a: u32, b: u32, c: u32) -> Ordering {
        Sites::orient(self, a as usize, b as usize, c as usize)
    }

    fn power(&self, a: u32, b: u32, c: u32, d: u32) -> Ordering {
        self.power_test(a as usize, b as usize, c as usize, d as usize)
    }
}

#[cfg(test)]
mod exact_tests;

#[cfg(test)]
pub(crate) mod tests;
