//! Sites of one vertex in 3D (docs/method.md sections 4 and 5). A vertex
//! still short of four affinely independent sites, and strictly inside its
//! own power cell (of RT(w)), gets sites of its own near it, each serving
//! it alone. Anywhere strictly inside that cell such a site has power w_v
//! at v and more at every other vertex, so it may go anywhere there. Sites
//! of v all have power w_v at v, so their walls with one another pass
//! through v: near v they split the cell into cones, one site in each.
//! Another site y beats a site of v at v + d only when y's power at v is
//! within 2 d.(y - v) - 2 |d|^2 of w_v, so they start close to v, in
//! directions away from the sites already serving it.

use super::d3::{spans, Sites3};
use super::track3::{depth, Roam};
use crate::complex::Complex3;
use crate::geom::{cross_f, dot_f, f, power_nearer, q, Q};
use crate::weights::Weights3;
use std::sync::Arc;

/// Directions a moving site tries around its vertex (a spiral on the sphere).
const DIRECTIONS: usize = 64;

/// Radii it tries, in units of its spot's radius.
const RADII: [f64; 3] = [0.5, 1.0, 2.0];

/// Places it tests exactly, best first, before it gives up a move.
const TRIES: usize = 8;

/// The corners of a regular tetrahedron around the origin.
const TETRAHEDRON: [[f64; 3]; 4] = [
    [1.0, 1.0, 1.0],
    [1.0, -1.0, -1.0],
    [-1.0, 1.0, -1.0],
    [-1.0, -1.0, 1.0],
];

/// Where a site serving vertex v alone may lie: strictly inside v's power
/// cell.
#[derive(Debug, Clone)]
pub struct Spot {
    v: u32,
    /// Where its places centre: v, or a point inside v's cell.
    o: [f64; 3],
    /// v's neighbours in RT(w): the walls of its cell.
    walls: Arc<[u32]>,
    /// Sites serving v, this one included: their span must stay a volume.
    peers: Arc<[u32]>,
    /// A power of two about a quarter of o's distance to v's walls.
    r: f64,
    /// Moves made so far (`wander` stops at its limit).
    pub(super) moves: u8,
}

impl Spot {
    /// The same spot with its peers renumbered by `id`, dropped ones
    /// (u32::MAX) left out.
    pub(super) fn renumbered(&self, id: &[u32]) -> Spot {
        let peers: Vec<u32> = self
            .peers
            .iter()
            .map(|&x| id[x as usize])
            .filter(|&x| x != u32::MAX)
            .collect();
        Spot {
            peers: peers.into(),
            ..self.clone()
        }
    }
}

/// Whether p is strictly inside the power cell of v, exactly.
fn inside_cell(cx: &Complex3, w: &[Q], v: u32, walls: &[u32], p: &[Q; 3]) -> bool {
    let at = |u: u32| cx.points[u as usize].map(q);
    let pv = at(v);
    walls.iter().all(|&u| {
        let pu = at(u);
        power_nearer(p, (&pv, &w[v as usize]), (&pu, &w[u as usize]))
    })
}

fn unit(d: [f64; 3]) -> [f64; 3] {
    let n = d.iter().map(|x| x * x).sum::<f64>().sqrt();
    if n > 0.0 {
        d.map(|x| x / n)
    } else {
        d
    }
}

/// `n` directions spread evenly on the unit sphere (Fibonacci's spiral).
fn sphere(n: usize) -> impl Iterator<Item = [f64; 3]> {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    (0..n).map(move |k| {
        let z = 1.0 - (2.0 * k as f64 + 1.0) / n as f64;
        let rho = (1.0 - z * z).sqrt();
        let a = golden * k as f64;
        [rho * a.cos(), rho * a.sin(), z]
    })
}

/// The smallest distance from o to a wall of v's power cell (negative
/// beyond one), in doubles.
fn gap(cx: &Complex3, w: &[Q], v: u32, walls: &[u32], o: [f64; 3]) -> f64 {
    let pv = cx.points[v as usize];
    let power = |x: u32, p: [f64; 3]| -> f64 {
        let px = cx.points[x as usize];
        (0..3).map(|k| (p[k] - px[k]).powi(2)).sum::<f64>() - f(&w[x as usize])
    };
    walls
        .iter()
        .map(|&u| {
            let pu = cx.points[u as usize];
            let d = crate::geom::dist_f(pu, pv);
            (power(u, o) - power(v, o)) / (2.0 * d)
        })
        .fold(f64::INFINITY, f64::min)
}

/// The corners of v's bounded power cell (the orthocentres of the
/// tetrahedra `star` around v), in doubles.
fn corners(cx: &Complex3, w: &[Q], v: u32, star: &[[u32; 4]]) -> Option<Vec<[f64; 3]>> {
    let pv = cx.points[v as usize];
    let lift = |x: u32| {
        let p = cx.points[x as usize];
        (0..3).map(|k| p[k] * p[k]).sum::<f64>() - f(&w[x as usize])
    };
    let row = |x: u32| {
        let p = cx.points[x as usize];
        [0, 1, 2].map(|k| 2.0 * (p[k] - pv[k]))
    };
    star.iter()
        .map(|t| {
            let others: Vec<u32> = t.iter().copied().filter(|&x| x != v).collect();
            let [a, b, c] = [row(others[0]), row(others[1]), row(others[2])];
            let m = nalgebra::Matrix3::new(a[0], a[1], a[2], b[0], b[1], b[2], c[0], c[1], c[2]);
            let rhs = nalgebra::Vector3::from_iterator(others.iter().map(|&x| lift(x) - lift(v)));
            let o = m.lu().solve(&rhs)?;
            let o = [o[0], o[1], o[2]];
            o.iter().all(|x| x.is_finite()).then_some(o)
        })
        .collect()
}

/// Four places for sites of v around o within about r / 2 of it: the
/// corners of a tetrahedron when o is v, else on the sphere about v
/// through o (sites of v at one distance from v never beat one another):
/// o and three around it. Ordered by `worst` (ascending).
fn four(pv: [f64; 3], o: [f64; 3], r: f64, worst: &dyn Fn(&[f64; 3]) -> f64) -> Vec<[f64; 3]> {
    let e: [f64; 3] = std::array::from_fn(|k| o[k] - pv[k]);
    let dist = e.iter().map(|x| x * x).sum::<f64>().sqrt();
    let mut places: Vec<[f64; 3]> = if dist == 0.0 {
        TETRAHEDRON
            .iter()
            .map(|d| std::array::from_fn(|k| pv[k] + r / 2.0 * d[k]))
            .collect()
    } else {
        let e = e.map(|x| x / dist);
        // a and b across e
        let m = (0..3)
            .min_by(|&i, &j| e[i].abs().total_cmp(&e[j].abs()))
            .unwrap_or(0);
        let mut axis = [0.0; 3];
        axis[m] = 1.0;
        let a = unit(cross_f(e, axis));
        let b = cross_f(e, a);
        let theta = (r / 2.0 / dist).min(0.5).asin();
        let mut out = vec![o];
        for k in 0..3 {
            let phi = 2.0 * std::f64::consts::PI * k as f64 / 3.0;
            let (c, s) = (theta.cos(), theta.sin());
            out.push(std::array::from_fn(|i| {
                pv[i] + dist * (c * e[i] + s * (phi.cos() * a[i] + phi.sin() * b[i]))
            }));
        }
        out
    };
    places.sort_by(|a, b| {
        let d = |p: &[f64; 3]| -> [f64; 3] { std::array::from_fn(|k| p[k] - pv[k]) };
        worst(&d(a)).total_cmp(&worst(&d(b)))
    });
    places
}

impl Sites3 {
    /// Gives vertex v sites of its own until the sites serving it span a
    /// volume: near v when v is strictly inside its own power cell (RT
    /// neighbours `walls`), else near the centre of its cell when that is
    /// bounded (the tetrahedra `star` around v), in directions away from
    /// the sites `have` that serve it already. None, and no site added,
    /// when neither is found in doubles or no places pass the exact test.
    pub(super) fn own_sites(
        &mut self,
        cx: &Complex3,
        wt: &Weights3,
        v: u32,
        have: &[u32],
        (walls, stars): &(Vec<Vec<u32>>, Vec<Option<Vec<u32>>>),
    ) -> Option<Vec<u32>> {
        let star: Option<Vec<[u32; 4]>> = stars[v as usize]
            .as_ref()
            .map(|st| st.iter().map(|&t| wt.rt.tets[t as usize]).collect());
        let cell = (&walls[v as usize][..], star.as_deref());
        self.own_sites_in(cx, &wt.w, v, have, cell)
    }

    /// `own_sites` in the cell of v with these walls and tetrahedra.
    fn own_sites_in(
        &mut self,
        cx: &Complex3,
        w: &[Q],
        v: u32,
        have: &[u32],
        (walls, star): (&[u32], Option<&[[u32; 4]]>),
    ) -> Option<Vec<u32>> {
        let pv = cx.points[v as usize];
        let corners: Vec<[f64; 3]> = star
            .and_then(|st| corners(cx, w, v, st))
            .unwrap_or_default();
        let (o, room) = match gap(cx, w, v, walls, pv) {
            h if h > 0.0 => (pv, h),
            _ if corners.is_empty() => return None,
            _ => {
                let n = corners.len() as f64;
                let c = [0, 1, 2].map(|k| corners.iter().map(|p| p[k]).sum::<f64>() / n);
                (c, gap(cx, w, v, walls, c))
            }
        };
        if !(room.is_finite() && room > 0.0) {
            return None;
        }
        let towards: Vec<[f64; 3]> = have
            .iter()
            .map(|&y| unit(std::array::from_fn(|k| f(&self.p[y as usize][k]) - pv[k])))
            .collect();
        // the direction's largest cosine with a site serving v
        let worst = |d: &[f64; 3]| {
            let d = unit(*d);
            towards.iter().map(|t| dot_f(d, *t)).fold(-1.0, f64::max)
        };
        let walls: Arc<[u32]> = walls.into();
        let mut r = 2f64.powi((room / 4.0).log2().floor() as i32);
        for _ in 0..16 {
            let places: Vec<[Q; 3]> = four(pv, o, r, &worst)
                .into_iter()
                .map(|p| p.map(q))
                .collect();
            if places.iter().all(|p| inside_cell(cx, w, v, &walls, p)) {
                return Some(self.add_own(
                    cx,
                    w,
                    v,
                    have,
                    places,
                    Spot {
                        v,
                        o,
                        walls,
                        peers: Arc::new([]),
                        r,
                        moves: 0,
                    },
                ));
            }
            r /= 2.0;
        }
        None
    }

    /// Adds sites of v at `places`, in order, until v's sites span a volume.
    fn add_own(
        &mut self,
        cx: &Complex3,
        w: &[Q],
        v: u32,
        have: &[u32],
        places: Vec<[Q; 3]>,
        spot: Spot,
    ) -> Vec<u32> {
        let mut peers = have.to_vec();
        let first = self.p.len() as u32;
        for p in places {
            if spans(self, &peers, 3) {
                break;
            }
            let x = self.p.len();
            self.p.push(p);
            self.w.push(Q::from(0));
            self.serves.push(vec![v]);
            self.line.push(None);
            self.track.push(None);
            self.reweigh(x, cx, w);
            peers.push(x as u32);
        }
        let peers: Arc<[u32]> = peers.into();
        let added: Vec<u32> = (first..self.p.len() as u32).collect();
        for &x in &added {
            self.track[x as usize] = Some(Box::new(Roam::Cell(Spot {
                peers: peers.clone(),
                ..spot.clone()
            })));
        }
        added
    }

    /// Moves site x (serving one vertex, outside its cell) to the place
    /// around its vertex farthest inside its faces with `others` (the
    /// neighbours' doubles and weights) that is farther than where it is,
    /// strictly inside the vertex's cell (exact) and keeps the vertex's
    /// sites spanning a volume; false, and it stays, when none is.
    pub(super) fn wander_cell(
        &mut self,
        x: usize,
        cx: &Complex3,
        w: &[Q],
        spot: &Spot,
        others: &[[f64; 4]],
    ) -> bool {
        let pv = cx.points[spot.v as usize];
        let at = |p: [f64; 3]| depth(p, (pv, f(&w[spot.v as usize])), others);
        let now = at(self.p[x].each_ref().map(f));
        // (around o; on the sphere about v through o when o is not v)
        let dist = (0..3)
            .map(|k| (spot.o[k] - pv[k]).powi(2))
            .sum::<f64>()
            .sqrt();
        let onto = |p: [f64; 3]| -> [f64; 3] {
            if dist == 0.0 {
                return p;
            }
            let d = unit(std::array::from_fn(|k| p[k] - pv[k]));
            std::array::from_fn(|k| pv[k] + dist * d[k])
        };
        let mut places: Vec<(f64, [f64; 3])> = sphere(DIRECTIONS)
            .flat_map(|d| {
                RADII.map(|k| onto(std::array::from_fn(|i| spot.o[i] + k * spot.r * d[i])))
            })
            .map(|p| (at(p), p))
            .filter(|&(d, _)| d > now)
            .collect();
        places.sort_by(|a, b| b.0.total_cmp(&a.0));
        for (_, p) in places.into_iter().take(TRIES) {
            let p = p.map(q);
            if !inside_cell(cx, w, spot.v, &spot.walls, &p) {
                continue;
            }
            let was = std::mem::replace(&mut self.p[x], p);
            if spans(self, &spot.peers, 3) {
                self.reweigh(x, cx, w);
                if let Some(Roam::Cell(s)) = self.track[x].as_deref_mut() {
                    s.moves += 1;
                }
                return true;
            }
            self.p[x] = was;
        }
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::{norm2, sub};

    /// A vertex at the centre of a tetrahedron of vertices, zero weights:
    /// four sites of its own, strictly inside its cell, spanning a volume,
    /// serving it alone with power 0 there, and none beating another at
    /// its place. A heavy site next to one of them beats it; it moves to a
    /// place where it beats that site.
    #[test]
    fn a_vertex_gets_four_sites_of_its_own_that_move_in_its_cell() {
        let corners = [
            [1.0, 1.0, 1.0],
            [1.0, -1.0, -1.0],
            [-1.0, 1.0, -1.0],
            [-1.0, -1.0, 1.0],
        ];
        let mut points: Vec<[f64; 3]> = corners.map(|p| p.map(|x| 3.0 * x)).to_vec();
        points.push([0.0, 0.0, 0.0]);
        let cx = Complex3 {
            points,
            vertex_ids: (1..=5).collect(),
            facets: vec![],
            holes: vec![],
        };
        let w = vec![Q::from(0); 5];
        let mut s = Sites3::default();
        let walls = [0, 1, 2, 3];
        let added = s
            .own_sites_in(&cx, &w, 4, &[], (&walls, None))
            .expect("room");
        assert_eq!(added, vec![0, 1, 2, 3]);
        assert!(spans(&s, &added, 3));
        let centre = [0, 0, 0].map(Q::from);
        for &x in &added {
            let x = x as usize;
            assert_eq!(s.serves[x], vec![4]);
            assert!(inside_cell(&cx, &w, 4, &walls, &s.p[x]));
            assert_eq!(norm2(&sub(&s.p[x], &centre)) - &s.w[x], 0, "power 0 at v");
            for y in (0..4).filter(|&y| y != x) {
                let beats = norm2(&sub(&s.p[x], &s.p[y])) - &s.w[y] + &s.w[x];
                assert!(beats > 0, "{y} beats {x}");
            }
        }
        // a heavy site beside site 0 beats it there
        let p0 = s.p[0].each_ref().map(f);
        s.p.push(p0.map(|x| q(x * 1.1)));
        s.w.push(Q::from(1));
        s.serves.push(vec![0]);
        s.line.push(None);
        s.track.push(None);
        let beaten = |s: &Sites3| norm2(&sub(&s.p[0], &s.p[4])) - &s.w[4] + &s.w[0] < 0;
        assert!(beaten(&s));
        assert!(s.wander(0, &cx, &w, &[1, 2, 3, 4]));
        assert!(!beaten(&s), "{:?}", s.p[0]);
        assert!(inside_cell(&cx, &w, 4, &walls, &s.p[0]));
        assert!(spans(&s, &added, 3));
    }
}
