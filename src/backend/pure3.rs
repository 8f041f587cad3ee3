//! The pure-Rust backend's 3D side: the regular triangulation of weighted
//! points by Bowyer-Watson insertion (conflict region, star from the new
//! point) over an infinite vertex, with exact predicates (intervals, then
//! rationals) and ties broken by a symbolic perturbation of the weights
//! (w_i + eps_i, eps_0 >> eps_1 >> ...: earlier points win), which makes
//! every decision consistent with one regular triangulation.

use super::points::{sign_q, F64Points3};
use super::{Tetrahedralisation, NONE};
use crate::error::{Error, Result};
use crate::geom::{dot, norm2, q, sub, Weighted3, Q};
use crate::FastMap;
use std::cmp::Ordering;

/// The infinite vertex.
const INF: u32 = u32::MAX - 1;

/// Exact predicates on weighted points in 3D.
pub(crate) trait Predicates3 {
    fn len(&self) -> usize;
    /// Greater when d sees (a, b, c) counter-clockwise (`exact::orient3`).
    fn orient(&self, a: u32, b: u32, c: u32, d: u32) -> Ordering;
    /// Greater when e conflicts with the positive tetrahedron t, Equal on
    /// a tie (unperturbed).
    fn power(&self, t: [u32; 4], e: u32) -> Ordering;
    /// The exact point and weight.
    fn exact(&self, v: u32) -> ([Q; 3], Q);
    /// `conflict_in_plane`'s sign before its tie-break, when a filter
    /// decides it.
    fn in_plane_filtered(&self, _face: [u32; 3], _p: u32) -> Option<Ordering> {
        None
    }
}

impl Predicates3 for F64Points3<'_> {
    fn len(&self) -> usize {
        self.p.len()
    }
    fn orient(&self, a: u32, b: u32, c: u32, d: u32) -> Ordering {
        F64Points3::orient(self, a, b, c, d)
    }
    fn power(&self, t: [u32; 4], e: u32) -> Ordering {
        F64Points3::power(self, t, e)
    }
    fn exact(&self, v: u32) -> ([Q; 3], Q) {
        (self.p[v as usize].map(q), q(self.w[v as usize]))
    }
}

/// The pure engine's 3D entry points (`Backend::regular3`, `regular3_exact`).
#[cfg(feature = "pure-rust")]
impl super::pure::Pure {
    pub(super) fn regular3_f64(
        &self,
        points: &[[f64; 3]],
        weights: &[f64],
    ) -> Result<Tetrahedralisation> {
        if let Some(i) = points
            .iter()
            .flatten()
            .chain(weights)
            .position(|x| !x.is_finite())
        {
            return Err(Error::Backend(format!(
                "regular triangulation input: value {i} is not finite"
            )));
        }
        regular3(&F64Points3 {
            p: points,
            w: weights,
        })
    }

    pub(super) fn regular3_q(
        &self,
        points: &[[Q; 3]],
        weights: &[Q],
    ) -> Result<Tetrahedralisation> {
        regular3(&Weighted3::new(points, weights))
    }
}

/// Rational weighted points (`geom::Weighted3`: intervals, then integer
/// determinants), for the exact sites and `regular3_exact`.
impl Predicates3 for Weighted3<'_> {
    fn len(&self) -> usize {
        self.count()
    }
    fn orient(&self, a: u32, b: u32, c: u32, d: u32) -> Ordering {
        let t = [a, b, c, d];
        self.orient_iv(t).unwrap_or_else(|| self.orient_exact(t))
    }
    fn power(&self, t: [u32; 4], e: u32) -> Ordering {
        self.power_iv(t, e)
            .unwrap_or_else(|| self.power_exact(t, e))
    }
    fn exact(&self, v: u32) -> ([Q; 3], Q) {
        let (p, w) = self.point(v);
        (p.clone(), w.clone())
    }
    fn in_plane_filtered(&self, face: [u32; 3], p: u32) -> Option<Ordering> {
        self.in_plane_interval(face, p)
    }
}

/// Whether e conflicts with the positive tetrahedron t, ties broken by
/// the perturbation: with weights w_x + eps_x, the 5x5 determinant of the
/// rows (p_x, |p_x|^2 - w_x, 1) (that of the power test, conflict iff
/// D < 0) gains -eps_x C_x, C_x the cofactor of row x's lift. That
/// cofactor is, up to the sign (-1)^(r + 3) of its place r, minus the
/// orientation of the other four points; so the first point in index
/// order whose coefficient (-1)^(r + 3) orient(others) is not zero
/// decides, by orientations alone.
fn conflict<P: Predicates3 + ?Sized>(pts: &P, t: [u32; 4], e: u32) -> bool {
    match pts.power(t, e) {
        Ordering::Greater => return true,
        Ordering::Less => return false,
        Ordering::Equal => {}
    }
    let five = [t[0], t[1], t[2], t[3], e];
    // places in index order, each orientation computed only when all
    // earlier ones vanish (usually the first decides)
    let mut places = [0usize, 1, 2, 3, 4];
    places.sort_unstable_by_key(|&r| five[r]);
    places
        .iter()
        .map(|&r| {
            let mut o = [0u32; 4];
            let mut n = 0;
            for (i, &x) in five.iter().enumerate() {
                if i != r {
                    o[n] = x;
                    n += 1;
                }
            }
            let s = pts.orient(o[0], o[1], o[2], o[3]);
            if r % 2 == 0 {
                s.reverse()
            } else {
                s
            }
        })
        .find(|s| *s != Ordering::Equal)
        == Some(Ordering::Less)
}

/// The sign of a perturbed quantity whose coefficients of eps_i are
/// given: that of the point earliest in index order with a non-zero one.
fn perturbed_sign(mut order: Vec<(u32, Q)>) -> Ordering {
    order.sort_by_key(|x| x.0);
    order
        .into_iter()
        .map(|(_, coef)| sign_q(&coef))
        .find(|s| *s != Ordering::Equal)
        .unwrap_or(Ordering::Equal)
}

/// For p coplanar with the hull face (a, b, c): whether p is inside its
/// power circle, perturbed alike. With p = a + s (b - a) + t (c - a) and
/// heights z_x = |x - a|^2 - w_x + w_a, p conflicts iff E = s z_b + t z_c -
/// z_p > 0; perturbed, E gains (s + t - 1) eps_a - s eps_b - t eps_c + eps_p.
fn conflict_in_plane<P: Predicates3 + ?Sized>(pts: &P, [a, b, c]: [u32; 3], p: u32) -> bool {
    match pts.in_plane_filtered([a, b, c], p) {
        Some(Ordering::Greater) => return true,
        Some(Ordering::Less) => return false,
        _ => {}
    }
    let (pa, wa) = pts.exact(a);
    let rel = |x: u32| {
        let (px, wx) = pts.exact(x);
        let d = sub(&px, &pa);
        let z = norm2(&d) - wx + &wa;
        (d, z)
    };
    let ((u, zb), (v, zc), (r, zp)) = (rel(b), rel(c), rel(p));
    let (uu, uv, vv) = (norm2(&u), dot(&u, &v), norm2(&v));
    let (ur, vr) = (dot(&u, &r), dot(&v, &r));
    let det = &uu * &vv - &uv * &uv;
    let s = (&vv * &ur - &uv * &vr) / &det;
    let t = (&uu * &vr - &uv * &ur) / &det;
    let e = &s * zb + &t * zc - zp;
    match sign_q(&e) {
        Ordering::Greater => return true,
        Ordering::Less => return false,
        Ordering::Equal => {}
    }
    let order = vec![(a, &s + &t - Q::from(1)), (b, -s), (c, -t), (p, Q::from(1))];
    perturbed_sign(order) == Ordering::Greater
}

/// Even permutations of (k, a, b, c): vertex k sees face k
/// counter-clockwise (as `Tetrahedralisation::face`).
const FACES: [[usize; 3]; 4] = [[1, 3, 2], [0, 2, 3], [0, 3, 1], [0, 1, 2]];

struct Builder<'a, P: Predicates3 + ?Sized> {
    pts: &'a P,
    tets: Vec<[u32; 4]>,
    adj: Vec<[u32; 4]>,
    alive: Vec<bool>,
    /// Dead tetrahedra's slots, for the next stars.
    free: Vec<u32>,
    /// Per tetrahedron, 2 r when insertion r found it in conflict, 2 r + 1
    /// when it found it not (r counts insertions from 1).
    stamp: Vec<u32>,
    round: u32,
    /// The star's faces through the new point still waiting for their
    /// twin, by their other two vertices.
    open: FastMap<[u32; 2], (u32, usize)>,
    /// A live tetrahedron to start walks from.
    last: u32,
    seed: u64,
}

impl<P: Predicates3 + ?Sized> Builder<'_, P> {
    fn face(&self, t: u32, k: usize) -> [u32; 3] {
        FACES[k].map(|i| self.tets[t as usize][i])
    }

    fn infinite(&self, t: u32) -> Option<usize> {
        self.tets[t as usize].iter().position(|&v| v == INF)
    }

    /// Whether p conflicts with t (finite or infinite).
    fn in_conflict(&self, t: u32, p: u32) -> bool {
        match self.infinite(t) {
            None => conflict(self.pts, self.tets[t as usize], p),
            Some(k) => {
                let f = self.face(t, k);
                match self.pts.orient(f[0], f[1], f[2], p) {
                    Ordering::Greater => true,
                    Ordering::Less => false,
                    Ordering::Equal => conflict_in_plane(self.pts, f, p),
                }
            }
        }
    }

    fn random(&mut self) -> u64 {
        self.seed ^= self.seed << 13;
        self.seed ^= self.seed >> 7;
        self.seed ^= self.seed << 17;
        self.seed
    }

    /// A tetrahedron whose closure holds p (finite), or an infinite one
    /// whose face p lies strictly beyond.
    fn locate(&mut self, p: u32) -> u32 {
        let mut t = self.last;
        if let Some(k) = self.infinite(t) {
            t = self.adj[t as usize][k];
        }
        let mut steps = 0usize;
        'walk: loop {
            steps += 1;
            if steps > 4 * self.tets.len() + 16 {
                // a visibility walk can cycle only in degenerate ways; a
                // scan then finds the answer
                return self.scan(p);
            }
            let start = (self.random() % 4) as usize;
            for i in 0..4 {
                let k = (start + i) % 4;
                let f = self.face(t, k);
                if self.pts.orient(f[0], f[1], f[2], p) == Ordering::Less {
                    let u = self.adj[t as usize][k];
                    if self.infinite(u).is_some() {
                        return u;
                    }
                    t = u;
                    continue 'walk;
                }
            }
            return t;
        }
    }

    /// A new live tetrahedron, in a dead one's slot where there is one.
    fn slot(&mut self, tet: [u32; 4], adj: [u32; 4]) -> u32 {
        match self.free.pop() {
            Some(n) => {
                self.tets[n as usize] = tet;
                self.adj[n as usize] = adj;
                self.alive[n as usize] = true;
                n
            }
            None => {
                self.tets.push(tet);
                self.adj.push(adj);
                self.alive.push(true);
                self.stamp.push(0);
                self.tets.len() as u32 - 1
            }
        }
    }

    fn scan(&self, p: u32) -> u32 {
        (0..self.tets.len() as u32)
            .filter(|&t| self.alive[t as usize])
            .find(|&t| match self.infinite(t) {
                None => (0..4).all(|k| {
                    let f = self.face(t, k);
                    self.pts.orient(f[0], f[1], f[2], p) != Ordering::Less
                }),
                Some(k) => {
                    let f = self.face(t, k);
                    self.pts.orient(f[0], f[1], f[2], p) == Ordering::Greater
                }
            })
            .expect("a live tetrahedron holds every point")
    }

    /// Inserts p; false when p is hidden.
    fn insert(&mut self, p: u32) -> bool {
        let mut start = self.locate(p);
        if !self.in_conflict(start, p) {
            // p on a face of the tetrahedron found: the one across may be
            // the one in conflict
            let across = (0..4).filter_map(|k| {
                let f = self.face(start, k);
                (self.infinite(start).is_none()
                    && self.pts.orient(f[0], f[1], f[2], p) == Ordering::Equal)
                    .then(|| self.adj[start as usize][k])
            });
            match across
                .collect::<Vec<_>>()
                .into_iter()
                .find(|&u| self.in_conflict(u, p))
            {
                Some(u) => start = u,
                None => return false,
            }
        }
        self.round += 1;
        let (yes, no) = (2 * self.round, 2 * self.round + 1);
        self.stamp[start as usize] = yes;
        let mut region = vec![start];
        let mut i = 0;
        while i < region.len() {
            let t = region[i];
            i += 1;
            for k in 0..4 {
                let u = self.adj[t as usize][k];
                let seen = self.stamp[u as usize];
                if seen != yes && seen != no {
                    let hit = self.in_conflict(u, p);
                    self.stamp[u as usize] = if hit { yes } else { no };
                    if hit {
                        region.push(u);
                    }
                }
            }
        }
        // Star the region's boundary from p, in the slots of earlier stars'
        // dead tetrahedra first.
        let mut created = vec![];
        for &t in &region {
            for k in 0..4 {
                let u = self.adj[t as usize][k];
                if self.stamp[u as usize] == yes {
                    continue;
                }
                let f = self.face(t, k);
                let n = self.slot([f[0], f[1], f[2], p], [NONE, NONE, NONE, u]);
                // u's face towards t now faces n
                let back = (0..4)
                    .find(|&l| self.adj[u as usize][l] == t)
                    .expect("adjacency is symmetric");
                self.adj[u as usize][back] = n;
                created.push(n);
                for l in 0..3 {
                    // the face opposite f[l]: p and the other two
                    let (a, b) = (f[(l + 1) % 3], f[(l + 2) % 3]);
                    let key = [a.min(b), a.max(b)];
                    match self.open.remove(&key) {
                        Some((m, ml)) => {
                            self.adj[n as usize][l] = m;
                            self.adj[m as usize][ml] = n;
                        }
                        None => {
                            self.open.insert(key, (n, l));
                        }
                    }
                }
            }
        }
        debug_assert!(self.open.is_empty(), "the star closes up");
        for &t in &region {
            self.alive[t as usize] = false;
        }
        self.free.extend_from_slice(&region);
        self.last = created
            .iter()
            .copied()
            .find(|&t| self.infinite(t).is_none())
            .unwrap_or(created[0]);
        true
    }
}

/// The regular triangulation of the points (see the module's doc).
pub(crate) fn regular3<P: Predicates3 + ?Sized>(pts: &P) -> Result<Tetrahedralisation> {
    let n = pts.len() as u32;
    let coplanar = || {
        Error::Backend(
            "the points are coplanar: their regular triangulation has no tetrahedron".into(),
        )
    };
    // Four affinely independent points, the first of each kind in order.
    let a = 0;
    let same = |x: u32, y: u32| pts.exact(x).0 == pts.exact(y).0;
    let b = (1..n).find(|&x| !same(a, x)).ok_or_else(coplanar)?;
    let collinear = |x: u32| {
        let (pa, pb, px) = (pts.exact(a).0, pts.exact(b).0, pts.exact(x).0);
        let (u, v) = (sub(&pb, &pa), sub(&px, &pa));
        crate::geom::cross(&u, &v).iter().all(|c| *c == 0)
    };
    let c = (1..n)
        .find(|&x| x != b && !collinear(x))
        .ok_or_else(coplanar)?;
    let d = (1..n)
        .find(|&x| x != b && x != c && pts.orient(a, b, c, x) != Ordering::Equal)
        .ok_or_else(coplanar)?;
    let first = if pts.orient(a, b, c, d) == Ordering::Greater {
        [a, b, c, d]
    } else {
        [b, a, c, d]
    };
    let mut bld = Builder {
        pts,
        tets: vec![first],
        adj: vec![[1, 2, 3, 4]],
        alive: vec![true; 5],
        free: vec![],
        stamp: vec![0; 5],
        round: 0,
        open: FastMap::default(),
        last: 0,
        seed: 0x9e37_79b9_7f4a_7c15,
    };
    for k in 0..4 {
        let f = bld.face(0, k);
        // seen from outside: reversed; the infinite vertex last
        bld.tets.push([f[0], f[2], f[1], INF]);
        bld.adj.push([NONE, NONE, NONE, 0]);
    }
    // the infinite tetrahedra meet across faces through INF
    let mut faces: FastMap<[u32; 3], (u32, usize)> = FastMap::default();
    for t in 1..5u32 {
        for l in 0..3 {
            let mut key = bld.face(t, l);
            key.sort_unstable();
            if let Some((m, ml)) = faces.remove(&key) {
                bld.adj[t as usize][l] = m;
                bld.adj[m as usize][ml] = t;
            } else {
                faces.insert(key, (t, l));
            }
        }
    }
    // The rest in BRIO order: shuffled, in rounds of doubling size, each
    // along a Hilbert curve (short walks, and no bad order to fall into).
    let approx: Vec<[f64; 3]> = (0..n)
        .map(|v| pts.exact(v).0.map(|x| crate::geom::f(&x)))
        .collect();
    let rest = super::brio::brio_order(&crate::geom::hilbert_keys3(&approx), &first);
    for p in rest {
        bld.insert(p);
    }
    // Output: live finite tetrahedra renumbered, infinite neighbours NONE.
    let mut id = vec![NONE; bld.tets.len()];
    let mut flat = vec![];
    for (t, tet) in bld.tets.iter().enumerate() {
        if bld.alive[t] && !tet.contains(&INF) {
            id[t] = (flat.len() / 4) as u32;
            flat.extend_from_slice(tet);
        }
    }
    let mut neighbours = vec![];
    for t in 0..bld.tets.len() {
        if id[t] != NONE {
            neighbours.extend(bld.adj[t].map(|u| id[u as usize]));
        }
    }
    let mut present = vec![false; n as usize];
    for &v in &flat {
        present[v as usize] = true;
    }
    let hidden = (0..n).filter(|&v| !present[v as usize]).collect();
    Ok(Tetrahedralisation::from_parts(&flat, &neighbours, hidden))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::{det3_q, norm2, sub};

    /// Rows (p_i - p_e, |p_i - p_e|^2 - w_i + w_e) of the power test.
    fn lifted_rows<P: Predicates3 + ?Sized>(pts: &P, t: [u32; 4], e: u32) -> [[Q; 4]; 4] {
        let (pe, we) = pts.exact(e);
        t.map(|x| {
            let (px, wx) = pts.exact(x);
            let d = sub(&px, &pe);
            let z = norm2(&d) - wx + &we;
            [d[0].clone(), d[1].clone(), d[2].clone(), z]
        })
    }

    /// The rationals' cofactors, as the perturbation was first written.
    fn conflict_q<P: Predicates3 + ?Sized>(pts: &P, t: [u32; 4], e: u32) -> bool {
        match pts.power(t, e) {
            Ordering::Greater => return true,
            Ordering::Less => return false,
            Ordering::Equal => {}
        }
        let r = lifted_rows(pts, t, e);
        let cof = |i: usize| {
            let m: Vec<[&Q; 3]> = (0..4)
                .filter(|&k| k != i)
                .map(|k| [&r[k][0], &r[k][1], &r[k][2]])
                .collect();
            let d = det3_q([m[0], m[1], m[2]]);
            if (i + 3) % 2 == 0 {
                d
            } else {
                -d
            }
        };
        let c: Vec<Q> = (0..4).map(cof).collect();
        let mut order: Vec<(u32, Q)> = (0..4).map(|i| (t[i], -c[i].clone())).collect();
        order.push((e, c.iter().sum()));
        perturbed_sign(order) == Ordering::Less
    }

    #[test]
    fn ties_broken_by_orientations_as_by_cofactors() {
        // a 3 x 3 x 3 grid: many cospherical fives; some weights tie too
        let p: Vec<[f64; 3]> = (0..27)
            .map(|i| [(i % 3) as f64, (i / 3 % 3) as f64, (i / 9) as f64])
            .collect();
        let w: Vec<f64> = (0..27)
            .map(|i| if i % 5 == 0 { 0.5 } else { 0.0 })
            .collect();
        let x = F64Points3 { p: &p, w: &w };
        let mut u = crate::generate::uniform(3);
        let mut pick = || (u() * 27.0) as u32;
        let mut ties = 0;
        for _ in 0..20_000 {
            let mut t = [pick(), pick(), pick(), pick()];
            let e = pick();
            match x.orient(t[0], t[1], t[2], t[3]) {
                Ordering::Equal => continue,
                Ordering::Less => t.swap(0, 1),
                Ordering::Greater => {}
            }
            if t.contains(&e) || x.power(t, e) != Ordering::Equal {
                continue;
            }
            ties += 1;
            assert_eq!(conflict(&x, t, e), conflict_q(&x, t, e), "{t:?} {e}");
        }
        assert!(ties > 100, "{ties}");
    }
}
