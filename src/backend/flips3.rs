//! Exact flips on a tetrahedralisation (issue 23): a triangulation of
//! rounded points is made the regular triangulation of the exact ones
//! where rounding chose otherwise. Faces that are not locally regular are
//! flipped 2-3 (when the two tetrahedra's union is convex across the face)
//! or 3-2 (when an edge of the face has three tetrahedra around it); flat
//! tetrahedra (four sites on one plane, which rounding lifted off it) are
//! flipped away 3-2 around an edge (2-3 flips around it first bring it
//! down to three tetrahedra), or dropped from the hull. A flip is made only
//! when its new tetrahedra all have one strict orientation, exactly: then
//! they tile the region of the old ones. Flips in 3D may get stuck; then
//! the caller triangulates the exact points.

use super::pure3::Predicates3;
use super::{Tetrahedralisation, NONE};
use std::cmp::Ordering;
use std::collections::HashMap;

/// The orientation of tetrahedron t (Greater: positive).
fn orient<T: Predicates3 + ?Sized>(tests: &T, t: [u32; 4]) -> Ordering {
    tests.orient(t[0], t[1], t[2], t[3])
}

/// The face opposite vertex k, sorted (a key).
fn key(t: [u32; 4], k: usize) -> [u32; 3] {
    let mut f = [0, 1, 2].map(|i| t[(k + 1 + i) % 4]);
    f.sort_unstable();
    f
}

/// The tetrahedra, all turned positive, when they all have one strict
/// orientation: then they tile the region they are to fill (a segment
/// crosses a triangle's interior), else None.
fn all_one_way<T: Predicates3 + ?Sized, const N: usize>(
    tests: &T,
    tets: [[u32; 4]; N],
) -> Option<[[u32; 4]; N]> {
    let o = orient(tests, tets[0]);
    if o == Ordering::Equal || tets[1..].iter().any(|&t| orient(tests, t) != o) {
        return None;
    }
    Some(tets.map(|t| match o {
        Ordering::Less => [t[1], t[0], t[2], t[3]],
        _ => t,
    }))
}

/// Flips in progress: dead slots to reuse, and tetrahedra to look at.
struct Flipper<'a, T: Predicates3 + ?Sized> {
    tri: &'a mut Tetrahedralisation,
    tests: &'a T,
    free: Vec<u32>,
    todo: Vec<u32>,
}

impl<T: Predicates3 + ?Sized> Flipper<'_, T> {
    fn alive(&self, t: u32) -> bool {
        self.tri.tets[t as usize][0] != NONE
    }

    /// Replaces the tetrahedra `old` by `new` (positive, filling the same
    /// region, or less of it only on the hull), mending the adjacency.
    fn replace(&mut self, old: &[u32], new: &[[u32; 4]]) {
        let tri = &mut *self.tri;
        // the faces of the region's boundary, with the tetrahedron outside
        let mut outer: HashMap<[u32; 3], u32> = HashMap::new();
        for &t in old {
            for k in 0..4 {
                let u = tri.adj[t as usize][k];
                if !old.contains(&u) {
                    outer.insert(key(tri.tets[t as usize], k), u);
                }
            }
        }
        for &t in old {
            tri.tets[t as usize] = [NONE; 4];
            tri.adj[t as usize] = [NONE; 4];
            self.free.push(t);
        }
        let mut inner: HashMap<[u32; 3], (u32, usize)> = HashMap::new();
        for &t in new {
            let s = match self.free.pop() {
                Some(s) => s,
                None => {
                    tri.tets.push([NONE; 4]);
                    tri.adj.push([NONE; 4]);
                    tri.tets.len() as u32 - 1
                }
            };
            tri.tets[s as usize] = t;
            self.todo.push(s);
            for k in 0..4 {
                let f = key(t, k);
                if let Some(u) = outer.remove(&f) {
                    tri.adj[s as usize][k] = u;
                    if u != NONE {
                        let l = (0..4).find(|&l| !f.contains(&tri.tets[u as usize][l]));
                        tri.adj[u as usize][l.expect("a neighbour has a vertex off the face")] = s;
                    }
                } else if let Some((o, l)) = inner.remove(&f) {
                    tri.adj[s as usize][k] = o;
                    tri.adj[o as usize][l] = s;
                } else {
                    inner.insert(f, (s, k));
                }
            }
        }
        // faces left uncovered become hull faces
        for (f, u) in outer {
            if u != NONE {
                let l = (0..4).find(|&l| !f.contains(&self.tri.tets[u as usize][l]));
                self.tri.adj[u as usize][l.expect("a neighbour has a vertex off the face")] = NONE;
            }
        }
    }

    /// The 2-3 flip of t and the tetrahedron across its face opposite k,
    /// when the segment joining their apexes crosses the face's interior.
    fn flip23(&mut self, t: u32, k: usize) -> bool {
        let Some(u) = self.tri.across(t, k) else {
            return false;
        };
        let (tt, tu) = (self.tri.tets[t as usize], self.tri.tets[u as usize]);
        let p = tt[k];
        let Some(&q) = tu.iter().find(|v| !tt.contains(v)) else {
            return false;
        };
        // p q must cross the face's interior
        let f = key(tt, k);
        let Some(new) = all_one_way(self.tests, [0, 1, 2].map(|i| [f[i], f[(i + 1) % 3], p, q]))
        else {
            return false;
        };
        self.replace(&[t, u], &new);
        true
    }

    /// The 3-2 flip around edge (a, b) of t, when three tetrahedra are
    /// around it and the edge crosses the triangle of the other three
    /// vertices.
    fn flip32(&mut self, t: u32, a: u32, b: u32) -> bool {
        let Some(ring) = self.tri.ring(t, a, b).filter(|r| r.len() == 3) else {
            return false;
        };
        let mut link: Vec<u32> = ring
            .iter()
            .flat_map(|&r| self.tri.tets[r as usize])
            .filter(|&v| v != a && v != b)
            .collect();
        link.sort_unstable();
        link.dedup();
        let [c, d, e] = link[..] else {
            return false;
        };
        // a b must cross the triangle c d e's interior
        let Some(new) = all_one_way(self.tests, [[c, d, e, a], [d, c, e, b]]) else {
            return false;
        };
        self.replace(&ring, &new);
        true
    }

    /// Brings the tetrahedra around edge (a, b) of t down to three by 2-3
    /// flips of the faces around it (not t's own), then flips it 3-2.
    fn shrink_ring(&mut self, t: u32, a: u32, b: u32) -> bool {
        for _ in 0..16 {
            let Some(ring) = self.tri.ring(t, a, b) else {
                return false;
            };
            if ring.len() <= 3 {
                return self.flip32(t, a, b);
            }
            let shrunk = ring[1..].windows(2).any(|w| {
                let (tr, ts) = (self.tri.tets[w[0] as usize], self.tri.tets[w[1] as usize]);
                let k = (0..4).find(|&k| !ts.contains(&tr[k]));
                k.is_some_and(|k| self.flip23(w[0], k))
            });
            if !shrunk {
                return false;
            }
        }
        false
    }

    /// Looks at tetrahedron t: a flat one is flipped away or dropped from
    /// the hull; otherwise its first face that is not locally regular is
    /// flipped. False when something needed flipping and could not be.
    fn visit(&mut self, t: u32) -> bool {
        if !self.alive(t) {
            return true;
        }
        let tt = self.tri.tets[t as usize];
        let edges = [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)];
        if orient(self.tests, tt) != Ordering::Greater {
            if (0..4).any(|k| self.tri.across(t, k).is_none()) {
                self.replace(&[t], &[]);
                return true;
            }
            return edges.iter().any(|&(i, j)| self.flip32(t, tt[i], tt[j]))
                || (0..4).any(|k| self.flip23(t, k))
                || edges
                    .iter()
                    .any(|&(i, j)| self.shrink_ring(t, tt[i], tt[j]));
        }
        for k in 0..4 {
            let Some(u) = self.tri.across(t, k) else {
                continue;
            };
            let tu = self.tri.tets[u as usize];
            let Some(&e) = tu.iter().find(|v| !tt.contains(v)) else {
                continue;
            };
            if self.tests.power(tt, e) != Ordering::Greater {
                continue;
            }
            let f = key(tt, k);
            let done = self.flip23(t, k)
                || [(0, 1), (1, 2), (0, 2)]
                    .iter()
                    .any(|&(i, j)| self.flip32(t, f[i], f[j]));
            if !done {
                return false;
            }
            return true;
        }
        true
    }
}

impl Tetrahedralisation {
    /// A tetrahedron holding point h (closed), found by a visibility walk
    /// from tetrahedron 0 with exact orientations; None when h lies
    /// outside the hull (or the walk does not end, which exact tests on a
    /// valid triangulation should not allow).
    pub(crate) fn locate<T: Predicates3 + ?Sized>(&self, tests: &T, h: u32) -> Option<u32> {
        let mut t = 0u32;
        let mut turn = 0usize;
        'walk: for _ in 0..4 * self.tets.len() + 16 {
            turn += 1;
            for i in 0..4 {
                let k = (i + turn) % 4;
                let f = self.face(t, k);
                if tests.orient(f[0], f[1], f[2], h) == Ordering::Less {
                    t = self.across(t, k)?;
                    continue 'walk;
                }
            }
            return Some(t);
        }
        None
    }

    /// Flips until no tetrahedron is flat and every face is locally
    /// regular, at most `limit` flips; false when a needed flip is not
    /// possible (the triangulation is then valid but not regular). Dead
    /// slots are removed at the end.
    pub(crate) fn flip_to_regular3<T: Predicates3 + ?Sized>(
        &mut self,
        tests: &T,
        limit: usize,
    ) -> bool {
        let mut f = Flipper {
            todo: (0..self.tets.len() as u32).rev().collect(),
            tri: self,
            tests,
            free: vec![],
        };
        let mut stuck = vec![];
        let mut flips = 0;
        while let Some(t) = f.todo.pop() {
            let before = f.todo.len();
            if !f.visit(t) {
                stuck.push(t);
            } else if f.todo.len() > before {
                flips += 1;
                if flips > limit {
                    break;
                }
                // a flip may unstick earlier tetrahedra
                f.todo.append(&mut stuck);
            }
        }
        let ok = f.todo.is_empty() && stuck.iter().all(|&t| !f.alive(t));
        self.compact();
        ok
    }

    /// Removes dead slots (`NONE` tetrahedra), renumbering the rest.
    fn compact(&mut self) {
        if self.tets.iter().all(|t| t[0] != NONE) {
            return;
        }
        let mut id = vec![NONE; self.tets.len()];
        let mut next = 0u32;
        for (t, tet) in self.tets.iter().enumerate() {
            if tet[0] != NONE {
                id[t] = next;
                next += 1;
            }
        }
        let keep = |t: &usize| id[*t] != NONE;
        let tets: Vec<[u32; 4]> = (0..self.tets.len())
            .filter(keep)
            .map(|t| self.tets[t])
            .collect();
        let adj: Vec<[u32; 4]> = (0..self.adj.len())
            .filter(keep)
            .map(|t| self.adj[t].map(|u| if u == NONE { NONE } else { id[u as usize] }))
            .collect();
        self.tets = tets;
        self.adj = adj;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::backend::compiled;
    use crate::backend::points::F64Points3;

    /// Tetrahedra glued along their shared faces.
    fn with_adjacency(tets: Vec<[u32; 4]>) -> Tetrahedralisation {
        let mut adj = vec![[NONE; 4]; tets.len()];
        let mut open: HashMap<[u32; 3], (usize, usize)> = HashMap::new();
        for (t, &q) in tets.iter().enumerate() {
            for k in 0..4 {
                if let Some((u, l)) = open.remove(&key(q, k)) {
                    adj[t][k] = u as u32;
                    adj[u][l] = t as u32;
                } else {
                    open.insert(key(q, k), (t, k));
                }
            }
        }
        Tetrahedralisation {
            tets,
            hidden: vec![],
            adj,
        }
    }

    fn sorted(t: &Tetrahedralisation) -> Vec<[u32; 4]> {
        let mut v: Vec<[u32; 4]> = t
            .tets
            .iter()
            .map(|t| {
                let mut t = *t;
                t.sort_unstable();
                t
            })
            .collect();
        v.sort_unstable();
        v
    }

    #[test]
    fn flips_undo_flips_away_from_regular() {
        let mut u = crate::generate::uniform(7);
        let p: Vec<[f64; 3]> = (0..150).map(|_| [u(), u(), u()]).collect();
        let w: Vec<f64> = (0..150).map(|_| 0.01 * u()).collect();
        let x = F64Points3 { p: &p, w: &w };
        for b in compiled() {
            let regular = b.regular3(&p, &w).unwrap();
            let mut t = regular.clone();
            // 2-3 flips wherever they keep the tetrahedra positive: no
            // longer regular
            let mut f = Flipper {
                tri: &mut t,
                tests: &x,
                free: vec![],
                todo: vec![],
            };
            let mut flipped = 0;
            for s in (0..f.tri.tets.len() as u32).step_by(7) {
                if f.alive(s) && (0..4).any(|k| f.flip23(s, k)) {
                    flipped += 1;
                }
            }
            t.compact();
            assert!(flipped >= 10, "{flipped}");
            assert_ne!(sorted(&t), sorted(&regular));
            assert!(t.flip_to_regular3(&x, 10_000));
            assert_eq!(sorted(&t), sorted(&regular), "{}", b.name());
            // the adjacency is mended: every interior face once, each way
            let inner = t.inner_faces().count();
            assert_eq!(4 * t.tets.len(), 2 * inner + t.hull_faces().count());
            for (t1, k, t2, l) in t.inner_faces() {
                assert_eq!(t.across(t2, l), Some(t1));
                assert_eq!(t.across(t1, k), Some(t2));
            }
        }
    }

    #[test]
    fn a_flat_tetrahedron_is_flipped_away() {
        // a square (0..3) in z = 0 with apexes above and below: rounding
        // could have put a flat tetrahedron on the square between the two
        // diagonals; built here by hand with diagonal 0-2 above, 1-3
        // below
        let p = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.5, 0.5, 1.0],
            [0.5, 0.5, -1.0],
        ];
        let w = [0.0; 6];
        let x = F64Points3 { p: &p, w: &w };
        let tets: Vec<[u32; 4]> = [
            [0, 1, 2, 4],
            [0, 2, 3, 4],
            [0, 1, 3, 5],
            [1, 2, 3, 5],
            [0, 1, 2, 3],
        ]
        .iter()
        .map(|t| match x.orient(t[0], t[1], t[2], t[3]) {
            Ordering::Less => [t[1], t[0], t[2], t[3]],
            _ => *t,
        })
        .collect();
        let mut t = with_adjacency(tets);
        assert!(t.flip_to_regular3(&x, 100));
        assert_eq!(t.tets.len(), 4);
        assert!(t
            .tets
            .iter()
            .all(|&q| x.orient(q[0], q[1], q[2], q[3]) == Ordering::Greater));
        for (t1, k, t2, l) in t.inner_faces() {
            let apex = t.tets[t2 as usize][l];
            assert_ne!(x.power(t.tets[t1 as usize], apex), Ordering::Greater, "{k}");
        }
    }
}
