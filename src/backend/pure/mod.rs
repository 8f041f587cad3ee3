//! The pure-Rust engine: regular triangulations of weighted points by
//! incremental insertion (Bowyer-Watson conflict regions, an infinite
//! vertex for the hull), points in BRIO order with a Hilbert sort per round,
//! a walking locate from the last insertion. Predicates are exact: for
//! doubles a semi-static filter, then intervals, then rationals; rationals
//! throughout for rational input.
//!
//! Constrained Delaunay triangulations insert each segment into the
//! Delaunay triangulation by retriangulating the polygons beside it.

use super::brio::{brio_order, Rng};
use super::points::{power_q, sign_q, F64Points};
use super::{Backend, FlipTests, Tetrahedralisation, Triangulation};
use crate::error::{Error, Result};
use crate::geom::{hilbert_keys, q, Q};
use std::cmp::Ordering;

/// Weighted points as the engine sees them: exact predicates by index.
/// Orientation and power tests come from `FlipTests`.
pub(crate) trait Weighted: FlipTests {
    fn len(&self) -> usize;
    /// For d on the line ab: Greater when d's lifted point lies strictly
    /// below the lifted line through a and b (at a or b: when d is heavier).
    fn power_1d(&self, a: u32, b: u32, d: u32) -> Ordering;
    /// Compares positions along x, then y.
    fn lex(&self, a: u32, b: u32) -> Ordering;
    /// Compares weights.
    fn weight_cmp(&self, a: u32, b: u32) -> Ordering;
    /// An approximate position, for the spatial sort only.
    fn approx(&self, a: u32) -> [f64; 2];
}

/// L^2 z'(d) against s z'(b), relative to a (see `power_1d`).
fn power_1d_q(a: &[Q; 2], b: &[Q; 2], d: &[Q; 2], wa: &Q, wb: &Q, wd: &Q) -> Ordering {
    let (ux, uy) = (&b[0] - &a[0], &b[1] - &a[1]);
    let (vx, vy) = (&d[0] - &a[0], &d[1] - &a[1]);
    let l2 = &ux * &ux + &uy * &uy;
    let s = &ux * &vx + &uy * &vy;
    let zb = &l2 - wb + wa;
    let zd = &vx * &vx + &vy * &vy - wd + wa;
    // below: L^2 z'(d) < s z'(b)
    sign_q(&(s * zb - l2 * zd))
}

impl Weighted for F64Points<'_> {
    fn len(&self) -> usize {
        self.p.len()
    }

    fn power_1d(&self, a: u32, b: u32, d: u32) -> Ordering {
        let pt = |x: u32| self.p[x as usize].map(q);
        let wt = |x: u32| q(self.w[x as usize]);
        power_1d_q(&pt(a), &pt(b), &pt(d), &wt(a), &wt(b), &wt(d))
    }

    fn lex(&self, a: u32, b: u32) -> Ordering {
        let (p, r) = (self.p[a as usize], self.p[b as usize]);
        p[0].total_cmp(&r[0]).then(p[1].total_cmp(&r[1]))
    }

    fn weight_cmp(&self, a: u32, b: u32) -> Ordering {
        self.w[a as usize].total_cmp(&self.w[b as usize])
    }

    fn approx(&self, a: u32) -> [f64; 2] {
        self.p[a as usize]
    }
}

/// Rational points and weights.
pub(crate) struct QPoints<'a> {
    pub p: &'a [[Q; 2]],
    pub w: &'a [Q],
}

impl FlipTests for QPoints<'_> {
    fn orient(&self, a: u32, b: u32, c: u32) -> Ordering {
        let [a, b, c] = [a, b, c].map(|x| &self.p[x as usize]);
        let d = (&b[0] - &a[0]) * (&c[1] - &a[1]) - (&b[1] - &a[1]) * (&c[0] - &a[0]);
        sign_q(&d)
    }

    fn power(&self, a: u32, b: u32, c: u32, d: u32) -> Ordering {
        power_q(
            [a, b, c, d].map(|x| &self.p[x as usize]),
            [a, b, c, d].map(|x| &self.w[x as usize]),
        )
    }
}

impl Weighted for QPoints<'_> {
    fn len(&self) -> usize {
        self.p.len()
    }

    fn power_1d(&self, a: u32, b: u32, d: u32) -> Ordering {
        let (p, w) = (self.p, self.w);
        let (a, b, d) = (a as usize, b as usize, d as usize);
        power_1d_q(&p[a], &p[b], &p[d], &w[a], &w[b], &w[d])
    }

    fn lex(&self, a: u32, b: u32) -> Ordering {
        let (p, r) = (&self.p[a as usize], &self.p[b as usize]);
        p[0].partial_cmp(&r[0])
            .expect("ordered")
            .then(p[1].partial_cmp(&r[1]).expect("ordered"))
    }

    fn weight_cmp(&self, a: u32, b: u32) -> Ordering {
        self.w[a as usize]
            .partial_cmp(&self.w[b as usize])
            .expect("ordered")
    }

    fn approx(&self, a: u32) -> [f64; 2] {
        self.p[a as usize].each_ref().map(crate::geom::f)
    }
}

/// The infinite vertex.
const INF: u32 = u32::MAX - 1;
/// No triangle.
const NONE: u32 = u32::MAX;

/// Biased randomised insertion order: rounds of doubling size, each sorted
/// along a Hilbert curve.
fn brio<P: Weighted>(p: &P) -> Vec<u32> {
    let points: Vec<[f64; 2]> = (0..p.len() as u32).map(|i| p.approx(i)).collect();
    brio_order(&hilbert_keys(&points), &[])
}

struct Engine<'a, P: Weighted> {
    p: &'a P,
    tri: Vec<[u32; 3]>,
    /// Across edge k = (tri[k], tri[k + 1]).
    nbr: Vec<[u32; 3]>,
    alive: Vec<bool>,
    free: Vec<u32>,
    /// Per vertex, a live triangle holding it (NONE: not a vertex).
    at: Vec<u32>,
    stamp: Vec<u32>,
    round: u32,
    rng: Rng,
    last: u32,
    /// Per vertex (the infinite one last): the round it was last on a
    /// cavity's rim, and the new triangle starting there.
    on_rim: Vec<u32>,
    starting_at: Vec<u32>,
}

impl<'a, P: Weighted> Engine<'a, P> {
    fn new_tri(&mut self, t: [u32; 3]) -> u32 {
        let id = if let Some(id) = self.free.pop() {
            self.tri[id as usize] = t;
            self.nbr[id as usize] = [NONE; 3];
            self.alive[id as usize] = true;
            self.stamp[id as usize] = 0;
            id
        } else {
            self.tri.push(t);
            self.nbr.push([NONE; 3]);
            self.alive.push(true);
            self.stamp.push(0);
            self.tri.len() as u32 - 1
        };
        for v in t {
            if v != INF {
                self.at[v as usize] = id;
            }
        }
        id
    }

    /// Whether d conflicts with triangle t.
    fn conflict(&self, t: u32, d: u32) -> bool {
        let [a, b, c] = self.tri[t as usize];
        let inf = [a, b, c].iter().position(|&v| v == INF);
        match inf {
            None => self.p.power(a, b, c, d) == Ordering::Greater,
            Some(k) => {
                // the finite edge, with the outside on its left
                let (u, v) = (
                    self.tri[t as usize][(k + 1) % 3],
                    self.tri[t as usize][(k + 2) % 3],
                );
                match self.p.orient(u, v, d) {
                    Ordering::Greater => true,
                    Ordering::Less => false,
                    // on the hull's line: below the lifted line through u, v
                    // (beyond an end, the end between is then hidden)
                    Ordering::Equal => self.p.power_1d(u, v, d) == Ordering::Greater,
                }
            }
        }
    }

    /// d on the closed segment ab (all three collinear).
    fn within(&self, a: u32, b: u32, d: u32) -> bool {
        let (x, y) = (self.p.lex(a, d), self.p.lex(d, b));
        x == Ordering::Equal || y == Ordering::Equal || x == y
    }

    /// A triangle that d conflicts with, or None when d is hidden.
    fn locate(&mut self, d: u32) -> Option<u32> {
        let mut t = self.last;
        let cap = 4 * self.tri.len() + 64;
        for _ in 0..cap {
            let tr = self.tri[t as usize];
            if let Some(k) = tr.iter().position(|&v| v == INF) {
                let (u, v) = (tr[(k + 1) % 3], tr[(k + 2) % 3]);
                match self.p.orient(u, v, d) {
                    Ordering::Greater => return Some(t),
                    // inside the hull: the finite triangle across (u, v)
                    Ordering::Less => t = self.nbr[t as usize][(k + 1) % 3],
                    Ordering::Equal if self.within(u, v, d) => {
                        t = self.nbr[t as usize][(k + 1) % 3]
                    }
                    Ordering::Equal if self.conflict(t, d) => return Some(t),
                    Ordering::Equal => {
                        // on the hull's line beyond u or v: the infinite
                        // neighbour on that side
                        let beyond_v = self.p.lex(u, v) == self.p.lex(v, d);
                        t = if beyond_v {
                            self.nbr[t as usize][(k + 2) % 3]
                        } else {
                            self.nbr[t as usize][k]
                        };
                    }
                }
                continue;
            }
            let start = (self.rng.next() % 3) as usize;
            let step = (0..3)
                .map(|i| (start + i) % 3)
                .find(|&k| self.p.orient(tr[k], tr[(k + 1) % 3], d) == Ordering::Less);
            match step {
                Some(k) => t = self.nbr[t as usize][k],
                None => return self.conflict(t, d).then_some(t),
            }
        }
        // The walk did not settle (it cannot cycle but for bad luck): scan.
        (0..self.tri.len() as u32).find(|&t| self.alive[t as usize] && self.conflict(t, d))
    }

    fn insert(&mut self, d: u32) {
        let Some(start) = self.locate(d) else {
            return; // hidden
        };
        self.round += 1;
        let round = self.round;
        let mut cavity = vec![start];
        self.stamp[start as usize] = round;
        let mut boundary = vec![]; // (triangle, edge) on the cavity's rim
        let mut i = 0;
        loop {
            while i < cavity.len() {
                let t = cavity[i];
                i += 1;
                for k in 0..3 {
                    let u = self.nbr[t as usize][k];
                    if self.stamp[u as usize] == round {
                        continue;
                    }
                    if self.conflict(u, d) {
                        self.stamp[u as usize] = round;
                        cavity.push(u);
                    } else {
                        boundary.push((t, k));
                    }
                }
            }
            // A rim edge that d does not see strictly (d on its line, a
            // tie of the power test beyond it) would make a flat triangle:
            // the triangle across joins the cavity (its lifted plane holds
            // d's lifted point, so the result stays regular).
            let flat: Vec<u32> = boundary
                .iter()
                .filter(|&&(t, k)| {
                    let tr = self.tri[t as usize];
                    let (u, v) = (tr[k], tr[(k + 1) % 3]);
                    u != INF && v != INF && self.p.orient(u, v, d) != Ordering::Greater
                })
                .map(|&(t, k)| self.nbr[t as usize][k])
                .filter(|&u| self.stamp[u as usize] != round)
                .collect();
            if flat.is_empty() {
                boundary.retain(|&(t, k)| self.stamp[self.nbr[t as usize][k] as usize] != round);
                break;
            }
            for u in flat {
                if self.stamp[u as usize] != round {
                    self.stamp[u as usize] = round;
                    cavity.push(u);
                }
            }
            boundary.retain(|&(t, k)| self.stamp[self.nbr[t as usize][k] as usize] != round);
        }
        // Vertices of the cavity not on its rim are hidden now.
        let slot = |v: u32| if v == INF { self.at.len() } else { v as usize };
        for &(t, k) in &boundary {
            let v = self.tri[t as usize][k];
            self.on_rim[slot(v)] = round;
        }
        for &t in &cavity {
            for v in self.tri[t as usize] {
                if v != INF && self.on_rim[v as usize] != round {
                    self.at[v as usize] = NONE;
                }
            }
        }
        let rim: Vec<(u32, u32, u32)> = boundary
            .iter()
            .map(|&(t, k)| {
                let tr = self.tri[t as usize];
                (tr[k], tr[(k + 1) % 3], self.nbr[t as usize][k])
            })
            .collect();
        for &t in &cavity {
            self.alive[t as usize] = false;
            self.free.push(t);
        }
        let mut made = Vec::with_capacity(rim.len());
        for &(u, v, out) in &rim {
            let n = self.new_tri([u, v, d]);
            self.nbr[n as usize][0] = out;
            let back = self.tri[out as usize]
                .iter()
                .position(|&x| x == v)
                .expect("the outside triangle holds the rim edge");
            self.nbr[out as usize][back] = n;
            let su = if u == INF { self.at.len() } else { u as usize };
            self.starting_at[su] = n;
            made.push((n, v));
        }
        for &(n, v) in &made {
            let m = self.starting_at[if v == INF { self.at.len() } else { v as usize }];
            self.nbr[n as usize][1] = m;
            self.nbr[m as usize][2] = n;
        }
        self.last = made[0].0;
    }
}

/// The pure-Rust backend.
#[derive(Debug, Clone, Copy, Default)]
pub struct Pure;

impl Backend for Pure {
    fn name(&self) -> &'static str {
        "pure"
    }

    fn regular(&self, points: &[[f64; 2]], weights: &[f64]) -> Result<Triangulation> {
        Ok(regular_f64(points, weights))
    }

    fn constrained_delaunay(
        &self,
        points: &[[f64; 2]],
        segments: &[[u32; 2]],
    ) -> Result<Triangulation> {
        constrained_delaunay(points, segments)
    }

    fn regular_exact(&self, points: &[[Q; 2]], weights: &[Q]) -> Result<Triangulation> {
        Ok(regular(&QPoints {
            p: points,
            w: weights,
        }))
    }

    fn regular3(&self, points: &[[f64; 3]], weights: &[f64]) -> Result<Tetrahedralisation> {
        self.regular3_f64(points, weights)
    }

    fn regular3_exact(&self, points: &[[Q; 3]], weights: &[Q]) -> Result<Tetrahedralisation> {
        self.regular3_q(points, weights)
    }
}

/// The regular triangulation of double points with double weights, exact
/// predicates (what `Backend::regular` computes, without CGAL).
pub fn regular_f64(points: &[[f64; 2]], weights: &[f64]) -> Triangulation {
    regular(&F64Points {
        p: points,
        w: weights,
    })
}

/// The regular triangulation of the weighted points, exact predicates.
pub(crate) fn regular<P: Weighted>(p: &P) -> Triangulation {
    match build(p) {
        Some(e) => export(&e),
        None => collinear(p, &brio(p)),
    }
}

/// The engine after inserting every point, or None when they are all on
/// one line (or fewer than three).
fn build<P: Weighted>(p: &P) -> Option<Engine<'_, P>> {
    let n = p.len();
    let order = brio(p);
    // A first proper triangle: two positions, then one off their line.
    let first = |pred: &dyn Fn(u32) -> bool| order.iter().copied().find(|&i| pred(i));
    let a = *order.first()?;
    let b = first(&|i| p.lex(i, a) != Ordering::Equal)?;
    let c = first(&|i| p.orient(a, b, i) != Ordering::Equal)?;
    let (b, c) = if p.orient(a, b, c) == Ordering::Greater {
        (b, c)
    } else {
        (c, b)
    };
    let mut e = Engine {
        p,
        tri: vec![],
        nbr: vec![],
        alive: vec![],
        free: vec![],
        at: vec![NONE; n],
        stamp: vec![],
        round: 0,
        rng: Rng(0x2545_f491_4f6c_dd1d),
        last: 0,
        on_rim: vec![0; n + 1],
        starting_at: vec![NONE; n + 1],
    };
    let t0 = e.new_tri([a, b, c]);
    // Across edge (u, v) of t0: the infinite triangle (v, u, INF).
    let outs: Vec<u32> = [(a, b), (b, c), (c, a)]
        .iter()
        .map(|&(u, v)| e.new_tri([v, u, INF]))
        .collect();
    for k in 0..3 {
        e.nbr[t0 as usize][k] = outs[k];
        e.nbr[outs[k] as usize][0] = t0;
        // (v, u, INF): edge 1 = (u, INF) meets the previous outer triangle's
        // edge 2 = (INF, u).
        e.nbr[outs[k] as usize][1] = outs[(k + 2) % 3];
        e.nbr[outs[(k + 2) % 3] as usize][2] = outs[k];
    }
    e.last = t0;
    for &d in &order {
        if d != a && d != b && d != c {
            e.insert(d);
        }
    }
    Some(e)
}

/// The constrained Delaunay triangulation of a validated complex (distinct
/// points, no crossings, no vertex inside a segment): the Delaunay
/// triangulation, then each missing segment by removing the triangles it
/// crosses and triangulating the two pseudo-polygons beside it (Anglada).
pub fn constrained_delaunay(points: &[[f64; 2]], segments: &[[u32; 2]]) -> Result<Triangulation> {
    let w = vec![0.0; points.len()];
    let p = F64Points { p: points, w: &w };
    let Some(mut e) = build(&p) else {
        return Ok(collinear(&p, &brio(&p)));
    };
    if let Some(v) = e.at.iter().position(|&t| t == NONE) {
        return Err(Error::Backend(format!(
            "vertex {v} repeats another position"
        )));
    }
    for &[a, b] in segments {
        e.insert_segment(a, b)?;
    }
    Ok(export(&e))
}

impl<P: Weighted> Engine<'_, P> {
    /// Triangles around vertex v (finite and infinite), counter-clockwise.
    fn star(&self, v: u32) -> Vec<u32> {
        let first = self.at[v as usize];
        let mut out = vec![];
        let mut t = first;
        loop {
            out.push(t);
            let k = self.tri[t as usize]
                .iter()
                .position(|&x| x == v)
                .expect("star");
            // across edge (k + 2) = (prev, v): the next triangle around v
            t = self.nbr[t as usize][(k + 2) % 3];
            if t == first || out.len() > self.tri.len() {
                return out;
            }
        }
    }

    fn insert_segment(&mut self, a: u32, b: u32) -> Result<()> {
        let bad = |m: &str| Err(Error::Backend(format!("segment {a}-{b}: {m}")));
        // the finite triangle at a whose opposite edge the segment crosses
        let mut start = None;
        for t in self.star(a) {
            let tr = self.tri[t as usize];
            if tr.contains(&INF) {
                continue;
            }
            let k = tr.iter().position(|&x| x == a).expect("in star");
            let (x, y) = (tr[(k + 1) % 3], tr[(k + 2) % 3]);
            if x == b || y == b {
                return Ok(()); // already an edge
            }
            if self.p.orient(a, b, x) == Ordering::Less
                && self.p.orient(a, b, y) == Ordering::Greater
            {
                start = Some((t, (k + 1) % 3));
            }
        }
        let Some((mut t, mut k)) = start else {
            return bad("no triangle at its first vertex points along it");
        };
        // Walk across the crossed edges; left and right chains of vertices.
        let mut crossed = vec![t];
        let (mut left, mut right) = (vec![], vec![]);
        loop {
            let tr = self.tri[t as usize];
            let (r, l) = (tr[k], tr[(k + 1) % 3]); // crossed edge, r right of ab
            let u = self.nbr[t as usize][k];
            let ut = self.tri[u as usize];
            let j = ut.iter().position(|&x| x == l).expect("shared edge");
            let v = ut[(j + 2) % 3];
            crossed.push(u);
            if v == b {
                push_once(&mut left, l);
                push_once(&mut right, r);
                break;
            }
            if v == INF {
                return bad("leaves the convex hull");
            }
            push_once(&mut left, l);
            push_once(&mut right, r);
            match self.p.orient(a, b, v) {
                Ordering::Greater => {
                    // v left: next crossed edge (r, v)
                    t = u;
                    k = (j + 1) % 3;
                }
                Ordering::Less => {
                    // v right: next crossed edge (v, l)
                    t = u;
                    k = (j + 2) % 3;
                }
                Ordering::Equal => return bad("passes through a vertex"),
            }
        }
        // The rim of the crossed triangles: directed edges to the outside.
        let mut inside = crate::FastSet::default();
        inside.extend(crossed.iter().copied());
        let mut rim: crate::FastMap<(u32, u32), u32> = crate::FastMap::default();
        for &c in &crossed {
            for k in 0..3 {
                let out = self.nbr[c as usize][k];
                if !inside.contains(&out) {
                    let tr = self.tri[c as usize];
                    rim.insert((tr[k], tr[(k + 1) % 3]), out);
                }
            }
        }
        for &c in &crossed {
            self.alive[c as usize] = false;
            self.free.push(c);
        }
        let mut made = vec![];
        self.pseudo_polygon(a, b, &left, &mut made);
        right.reverse();
        self.pseudo_polygon(b, a, &right, &mut made);
        // Link the new triangles with each other and with the rim.
        let mut by_edge: crate::FastMap<(u32, u32), (u32, usize)> = crate::FastMap::default();
        for &n in &made {
            let tr = self.tri[n as usize];
            for k in 0..3 {
                by_edge.insert((tr[k], tr[(k + 1) % 3]), (n, k));
            }
        }
        for &n in &made {
            let tr = self.tri[n as usize];
            for k in 0..3 {
                let (x, y) = (tr[k], tr[(k + 1) % 3]);
                if let Some(&(m, _)) = by_edge.get(&(y, x)) {
                    self.nbr[n as usize][k] = m;
                } else if let Some(&out) = rim.get(&(x, y)) {
                    self.nbr[n as usize][k] = out;
                    let back = self.tri[out as usize]
                        .iter()
                        .position(|&z| z == y)
                        .expect("rim");
                    self.nbr[out as usize][back] = n;
                } else {
                    return bad("the new triangles do not close up");
                }
            }
        }
        self.last = made[0];
        Ok(())
    }

    /// Triangulates the polygon a, chain..., b (chain left of a->b) with
    /// Delaunay triangles: the chain vertex whose circle through a, b holds
    /// no other chain vertex, then both sides.
    fn pseudo_polygon(&mut self, a: u32, b: u32, chain: &[u32], made: &mut Vec<u32>) {
        if chain.is_empty() {
            return;
        }
        let mut c = 0;
        for i in 1..chain.len() {
            if self.p.power(a, b, chain[c], chain[i]) == Ordering::Greater {
                c = i;
            }
        }
        made.push(self.new_tri([a, b, chain[c]]));
        self.pseudo_polygon(a, chain[c], &chain[..c], made);
        self.pseudo_polygon(chain[c], b, &chain[c + 1..], made);
    }
}

fn push_once(v: &mut Vec<u32>, x: u32) {
    if v.last() != Some(&x) {
        v.push(x);
    }
}

fn export<P: Weighted>(e: &Engine<P>) -> Triangulation {
    let mut id = vec![NONE; e.tri.len()];
    let mut flat = vec![];
    for (t, tr) in e.tri.iter().enumerate() {
        if e.alive[t] && !tr.contains(&INF) {
            id[t] = (flat.len() / 3) as u32;
            flat.extend_from_slice(tr);
        }
    }
    let mut neighbours = Vec::with_capacity(flat.len());
    for (t, tr) in e.tri.iter().enumerate() {
        if e.alive[t] && !tr.contains(&INF) {
            neighbours.extend(e.nbr[t].iter().map(|&u| id[u as usize]));
        }
    }
    let hidden = (0..e.at.len() as u32)
        .filter(|&v| e.at[v as usize] == NONE)
        .collect();
    Triangulation::from_parts(&flat, &neighbours, hidden)
}

/// All points on one line: no triangles; the vertices are the lower hull of
/// the lifted points along the line, the others hidden.
fn collinear<P: Weighted>(p: &P, order: &[u32]) -> Triangulation {
    let mut along = order.to_vec();
    along.sort_by(|&a, &b| p.lex(a, b));
    let mut hull: Vec<u32> = vec![];
    for &d in &along {
        if let Some(&top) = hull.last() {
            if p.lex(top, d) == Ordering::Equal {
                // same position: the larger weight stays
                if p.weight_cmp(d, top) == Ordering::Greater {
                    hull.pop();
                } else {
                    continue;
                }
            }
        }
        while hull.len() >= 2 {
            let (u, m) = (hull[hull.len() - 2], hull[hull.len() - 1]);
            if p.power_1d(u, d, m) == Ordering::Greater {
                break;
            }
            hull.pop();
        }
        hull.push(d);
    }
    let mut vertex = vec![false; p.len()];
    for &v in &hull {
        vertex[v as usize] = true;
    }
    let hidden = (0..p.len() as u32)
        .filter(|&v| !vertex[v as usize])
        .collect();
    Triangulation::from_parts(&[], &[], hidden)
}

#[cfg(test)]
mod tests;
