//! A finite 3D triangulation as index quadruples, with its face adjacency:
//! what the backends' 3D side returns.

use super::NONE;
use crate::FastMap as HashMap;

/// A triangulation's triangles (sorted) with the vertices across them, and
/// its edges (sorted) with their links (`triangle_apexes`, `edge_links`).
#[derive(Debug, Clone, Default)]
pub struct Adjacency {
    /// Per triangle, the vertices across it.
    pub tris: HashMap<[u32; 3], Vec<u32>>,
    /// Per edge, its link.
    pub links: HashMap<[u32; 2], Vec<u32>>,
}

/// Positively oriented tetrahedra (input indices; each vertex sees the
/// other three counter-clockwise, see `points::F64Points3::orient`), and
/// per tetrahedron the one across the face opposite each vertex.
#[derive(Debug, Clone, Default)]
pub struct Tetrahedralisation {
    /// Positively oriented tetrahedra (input indices).
    pub tets: Vec<[u32; 4]>,
    /// Input indices that are not vertices (hidden by their weights).
    pub hidden: Vec<u32>,
    /// Per tetrahedron, the one across the face opposite vertex k, or NONE
    /// on the hull.
    pub(super) adj: Vec<[u32; 4]>,
}

impl Tetrahedralisation {
    /// From tetrahedra and their adjacency (as the backends give them).
    #[cfg_attr(not(feature = "cgal"), allow(dead_code))]
    pub(crate) fn from_parts(flat: &[u32], neighbours: &[u32], hidden: Vec<u32>) -> Self {
        let quad = |c: &[u32]| [c[0], c[1], c[2], c[3]];
        Tetrahedralisation {
            tets: flat.chunks_exact(4).map(quad).collect(),
            hidden,
            adj: neighbours.chunks_exact(4).map(quad).collect(),
        }
    }

    /// The tetrahedron across the face of t opposite its vertex k.
    pub fn across(&self, t: u32, k: usize) -> Option<u32> {
        Some(self.adj[t as usize][k]).filter(|&u| u != NONE)
    }

    /// The face of t opposite its vertex k, oriented so that the vertex
    /// sees it counter-clockwise (from outside t it is clockwise).
    pub fn face(&self, t: u32, k: usize) -> [u32; 3] {
        let v = self.tets[t as usize];
        // Even permutations of (k, a, b, c) keep the orientation.
        const FACES: [[usize; 3]; 4] = [[1, 3, 2], [0, 2, 3], [0, 3, 1], [0, 1, 2]];
        FACES[k].map(|i| v[i])
    }

    /// Interior faces once each: (t, k, u, l) with u across the face of t
    /// opposite its vertex k, and l the vertex of u opposite the same face.
    pub fn inner_faces(&self) -> impl Iterator<Item = (u32, usize, u32, usize)> + '_ {
        (0..self.tets.len() as u32).flat_map(move |t| {
            (0..4).filter_map(move |k| {
                let u = self.across(t, k).filter(|&u| t < u)?;
                let l = (0..4).find(|&l| self.adj[u as usize][l] == t)?;
                Some((t, k, u, l))
            })
        })
    }

    /// Per point of n, the tetrahedra around it; None for a point on the
    /// hull (its power cell is unbounded) or hidden.
    pub fn bounded_stars(&self, n: usize) -> Vec<Option<Vec<u32>>> {
        let mut star: Vec<Option<Vec<u32>>> = vec![Some(vec![]); n];
        for (t, tet) in self.tets.iter().enumerate() {
            for &v in tet {
                if let Some(s) = &mut star[v as usize] {
                    s.push(t as u32);
                }
            }
        }
        for face in self.hull_faces() {
            for v in face {
                star[v as usize] = None;
            }
        }
        for s in &mut star {
            if s.as_ref().is_some_and(|s| s.is_empty()) {
                *s = None;
            }
        }
        star
    }

    /// Each of n points' neighbours along edges (empty for hidden points).
    pub fn neighbours(&self, n: usize) -> Vec<Vec<u32>> {
        // (per vertex, every tetrahedron's three, then sorted and deduped:
        // hashing each edge cost 5% of a 10^5-triangle run)
        let mut nb = vec![vec![]; n];
        for t in &self.tets {
            for a in 0..4 {
                let others = (0..4).filter(|&b| b != a).map(|b| t[b]);
                nb[t[a] as usize].extend(others);
            }
        }
        for v in &mut nb {
            v.sort_unstable();
            v.dedup();
        }
        nb
    }

    /// Its triangles' apexes and its edges' links at once (the weights'
    /// checks and the sites read both of the same triangulation).
    pub fn adjacency(&self) -> Adjacency {
        let (tris, links) = rayon::join(|| self.triangle_apexes(), || self.edge_links());
        Adjacency { tris, links }
    }

    /// Every triangle (vertices sorted) with the vertices across it: two
    /// inside, one on the hull.
    pub fn triangle_apexes(&self) -> HashMap<[u32; 3], Vec<u32>> {
        let mut out: HashMap<[u32; 3], Vec<u32>> = HashMap::default();
        for t in &self.tets {
            for k in 0..4 {
                let mut f = [0, 1, 2].map(|i| t[(k + 1 + i) % 4]);
                f.sort_unstable();
                out.entry(f).or_default().push(t[k]);
            }
        }
        out
    }

    /// Every edge (vertices sorted) with the other vertices of the
    /// tetrahedra around it (its link), sorted.
    pub fn edge_links(&self) -> HashMap<[u32; 2], Vec<u32>> {
        let mut out: HashMap<[u32; 2], Vec<u32>> = HashMap::default();
        for t in &self.tets {
            for a in 0..4 {
                for b in a + 1..4 {
                    let e = [t[a].min(t[b]), t[a].max(t[b])];
                    let link = out.entry(e).or_default();
                    link.extend((0..4).filter(|&c| c != a && c != b).map(|c| t[c]));
                }
            }
        }
        for link in out.values_mut() {
            link.sort_unstable();
            link.dedup();
        }
        out
    }

    /// The tetrahedra around the edge (a, b) of tetrahedron t, in cyclic
    /// order starting at t; None when the edge is on the hull.
    pub fn ring(&self, t: u32, a: u32, b: u32) -> Option<Vec<u32>> {
        let mut out = vec![t];
        let v = self.tets[t as usize];
        // leave t across the face opposite one of its other two vertices
        let mut back = *v.iter().find(|&&x| x != a && x != b)?;
        let mut cur = t;
        loop {
            let k = self.tets[cur as usize].iter().position(|&x| x == back)?;
            let next = self.across(cur, k)?;
            if next == t {
                return Some(out);
            }
            let shared = self.tets[cur as usize];
            back = *self.tets[next as usize]
                .iter()
                .find(|&&x| x != a && x != b && shared.contains(&x))?;
            // the shared vertex other than a, b is the one we cross next from
            // the far side: leave `next` across the face opposite it
            out.push(next);
            cur = next;
            if out.len() > self.tets.len() {
                return None;
            }
        }
    }

    /// Hull faces, each seen counter-clockwise from inside.
    pub fn hull_faces(&self) -> impl Iterator<Item = [u32; 3]> + '_ {
        (0..self.tets.len() as u32).flat_map(move |t| {
            (0..4)
                .filter(move |&k| self.across(t, k).is_none())
                .map(move |k| self.face(t, k))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::backend::compiled;
    use crate::backend::points::F64Points3;
    use std::cmp::Ordering;

    fn rng(n: usize, seed: u64) -> Vec<f64> {
        let mut u = crate::generate::uniform(seed);
        (0..n).map(|_| u()).collect()
    }

    fn volume(p: &[[f64; 3]], t: [u32; 4]) -> f64 {
        let [a, b, c, d] = t.map(|v| p[v as usize]);
        let u = [0, 1, 2].map(|k| b[k] - a[k]);
        let v = [0, 1, 2].map(|k| c[k] - a[k]);
        let w = [0, 1, 2].map(|k| d[k] - a[k]);
        (u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
            + u[2] * (v[0] * w[1] - v[1] * w[0]))
            / 6.0
    }

    /// A regular triangulation of the points, checked exactly: positive
    /// tetrahedra, symmetric adjacency, every interior face locally
    /// regular, a convex hull that no point lies beyond, every index a
    /// vertex or hidden (and a hidden point in conflict with no tetrahedron
    /// holding it), and tetrahedra that tile the hull (volumes).
    fn check(p: &[[f64; 3]], w: &[f64], t: &Tetrahedralisation) {
        let x = F64Points3 { p, w };
        let mut vertex = vec![false; p.len()];
        for (i, &tet) in t.tets.iter().enumerate() {
            let [a, b, c, d] = tet;
            assert_eq!(
                x.orient(a, b, c, d),
                Ordering::Greater,
                "tetrahedron {tet:?}"
            );
            for k in 0..4 {
                vertex[tet[k] as usize] = true;
                assert_eq!(
                    x.orient(
                        t.face(i as u32, k)[0],
                        t.face(i as u32, k)[1],
                        t.face(i as u32, k)[2],
                        tet[k]
                    ),
                    Ordering::Greater
                );
            }
        }
        for (t1, k, t2, l) in t.inner_faces() {
            let mut f1 = t.face(t1, k);
            let mut f2 = t.face(t2, l);
            f1.sort_unstable();
            f2.sort_unstable();
            assert_eq!(f1, f2, "adjacent tetrahedra share the face");
            let apex = t.tets[t2 as usize][l];
            assert_ne!(
                x.power(t.tets[t1 as usize], apex),
                Ordering::Greater,
                "face of {t1} and {t2}"
            );
        }
        let hull: Vec<[u32; 3]> = t.hull_faces().collect();
        for f in &hull {
            for v in (0..p.len() as u32).filter(|&v| vertex[v as usize]) {
                assert_ne!(
                    x.orient(f[0], f[1], f[2], v),
                    Ordering::Less,
                    "vertex {v} beyond hull face {f:?}"
                );
            }
        }
        for &h in &t.hidden {
            assert!(!vertex[h as usize], "hidden {h} is a vertex");
            vertex[h as usize] = true;
            let holds = |tet: &[u32; 4]| {
                let [a, b, c, d] = *tet;
                [[a, b, c, h], [a, c, d, h], [a, d, b, h], [b, d, c, h]]
                    .iter()
                    .all(|f| x.orient(f[0], f[1], f[2], f[3]) != Ordering::Less)
            };
            let home = t.tets.iter().filter(|tet| holds(tet));
            for tet in home {
                assert_ne!(
                    x.power(*tet, h),
                    Ordering::Greater,
                    "hidden {h} conflicts with {tet:?}"
                );
            }
        }
        assert!(
            vertex.iter().all(|&v| v),
            "an index is neither vertex nor hidden"
        );
        // The hull's volume from its faces (seen counter-clockwise from
        // inside): tetrahedra to an inner point.
        let o = t.tets[0][0];
        let total: f64 = t.tets.iter().map(|&tet| volume(p, tet)).sum();
        let hull_volume: f64 = hull.iter().map(|f| volume(p, [f[0], f[1], f[2], o])).sum();
        assert!(
            (total - hull_volume).abs() <= 1e-9 * hull_volume.abs(),
            "{total} vs {hull_volume}"
        );
    }

    #[test]
    fn faces_are_seen_counter_clockwise_from_their_vertex() {
        let p = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ];
        let t = Tetrahedralisation::from_parts(&[0, 1, 2, 3], &[NONE; 4], vec![]);
        let x = F64Points3 {
            p: &p,
            w: &[0.0; 4],
        };
        assert_eq!(x.orient(0, 1, 2, 3), Ordering::Greater);
        for k in 0..4 {
            let f = t.face(0, k);
            assert_eq!(x.orient(f[0], f[1], f[2], k as u32), Ordering::Greater);
        }
        assert_eq!(t.hull_faces().count(), 4);
        assert_eq!(t.inner_faces().count(), 0);
    }

    #[test]
    fn power_test_by_hand() {
        // The unit corner tetrahedron's circumsphere (centre (0.5, 0.5,
        // 0.5)) holds (0.1, 0.1, 0.1), not (2, 2, 2), and passes through
        // (1, 1, 0): there a tiny weight decides.
        let mut p = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ];
        p.extend([[0.1, 0.1, 0.1], [2.0, 2.0, 2.0], [1.0, 1.0, 0.0]]);
        let mut w = vec![0.0; 7];
        let x = F64Points3 { p: &p, w: &w };
        assert_eq!(x.power([0, 1, 2, 3], 4), Ordering::Greater);
        assert_eq!(x.power([0, 1, 2, 3], 5), Ordering::Less);
        assert_eq!(x.power([0, 1, 2, 3], 6), Ordering::Equal);
        w[6] = 1e-300;
        let x = F64Points3 { p: &p, w: &w };
        assert_eq!(x.power([0, 1, 2, 3], 6), Ordering::Greater);
        w[6] = -1e-300;
        let x = F64Points3 { p: &p, w: &w };
        assert_eq!(x.power([0, 1, 2, 3], 6), Ordering::Less);
    }

    #[test]
    fn random_weighted_points_give_a_regular_triangulation() {
        for b in compiled() {
            let n = 1500;
            let r = rng(4 * n, 3);
            let mut p: Vec<[f64; 3]> = (0..n)
                .map(|i| [r[4 * i], r[4 * i + 1], r[4 * i + 2]])
                .collect();
            let mut w: Vec<f64> = (0..n).map(|i| 1e-3 * r[4 * i + 3]).collect();
            // A duplicate with a smaller weight, and a heavy point that
            // hides its neighbours.
            p.push(p[0]);
            w.push(w[0] - 1.0);
            p.push([0.5, 0.5, 0.5]);
            w.push(0.02);
            let t = b.regular3(&p, &w).unwrap();
            check(&p, &w, &t);
            assert!(
                t.hidden.contains(&(n as u32)),
                "{}: the lighter duplicate is hidden",
                b.name()
            );
            assert!(
                t.hidden.len() > 1,
                "{}: the heavy point hides others",
                b.name()
            );
        }
    }

    /// Every backend's 3D side gives the same tetrahedra on points in
    /// general position, from doubles and from their exact rationals.
    #[test]
    fn backends_agree() {
        let n = 400;
        let r = rng(4 * n, 11);
        let p: Vec<[f64; 3]> = (0..n)
            .map(|i| [r[4 * i], r[4 * i + 1], r[4 * i + 2]])
            .collect();
        let w: Vec<f64> = (0..n).map(|i| 2e-3 * r[4 * i + 3]).collect();
        let sorted = |t: &Tetrahedralisation| {
            let mut v: Vec<[u32; 4]> = t
                .tets
                .iter()
                .map(|x| {
                    let mut y = *x;
                    y.sort_unstable();
                    y
                })
                .collect();
            v.sort_unstable();
            (v, t.hidden.clone())
        };
        let qp: Vec<[crate::geom::Q; 3]> = p.iter().map(|x| x.map(crate::geom::q)).collect();
        let qw: Vec<crate::geom::Q> = w.iter().map(|&x| crate::geom::q(x)).collect();
        let all: Vec<_> = compiled()
            .iter()
            .flat_map(|b| {
                let from_f64 = sorted(&b.regular3(&p, &w).unwrap());
                let from_q = sorted(&b.regular3_exact(&qp, &qw).unwrap());
                assert_eq!(from_f64, from_q, "{}", b.name());
                [from_f64]
            })
            .collect();
        assert!(all.windows(2).all(|x| x[0] == x[1]), "the backends differ");
        assert!(!all[0].1.is_empty(), "some points hidden");
    }

    #[test]
    fn a_cospherical_lattice() {
        for b in compiled() {
            let p: Vec<[f64; 3]> = (0..125)
                .map(|i| [(i % 5) as f64, (i / 5 % 5) as f64, (i / 25) as f64])
                .collect();
            let w = vec![0.0; p.len()];
            let t = b.regular3(&p, &w).unwrap();
            check(&p, &w, &t);
            assert!(t.hidden.is_empty());
            let total: f64 = t.tets.iter().map(|&tet| volume(&p, tet)).sum();
            assert!((total - 64.0).abs() < 1e-9, "{}: volume {total}", b.name());
        }
    }

    #[test]
    fn coplanar_or_not_finite_points_are_errors() {
        for b in compiled() {
            let flat: Vec<[f64; 3]> = (0..10).map(|i| [i as f64, (i * i) as f64, 0.0]).collect();
            assert!(
                b.regular3(&flat, &[0.0; 10]).is_err(),
                "{}: coplanar",
                b.name()
            );
            let mut nan = flat.clone();
            nan[3][2] = f64::NAN;
            let e = b.regular3(&nan, &[0.0; 10]).unwrap_err().to_string();
            assert!(e.contains("not finite"), "{}: {e}", b.name());
        }
    }
}
