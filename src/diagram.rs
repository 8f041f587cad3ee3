//! The power diagram of the sites: cells as exact polygons, and which cells
//! lie in the domain.

use crate::backend::Triangulation;
use crate::domain::Domain;
use crate::exact::{orient_q, power_centre, qi, qp, zero, QPoint};
use crate::sites::Sites;
use rayon::prelude::*;
use std::cmp::Ordering;
use std::collections::{HashMap, VecDeque};

/// Power centres by sorted site triple.
#[derive(Debug, Default)]
pub struct CentreCache(HashMap<[u32; 3], QPoint>);

impl CentreCache {
    /// Forgets the centres of triangles with a moved site.
    pub fn forget(&mut self, moved: &std::collections::HashSet<u32>) {
        self.0.retain(|k, _| !k.iter().any(|v| moved.contains(v)));
    }
}

/// Power diagram of the sites, exact.
#[derive(Debug, Clone)]
pub struct Diagram {
    /// Distinct power vertices.
    pub points: Vec<QPoint>,
    /// Their nearest doubles.
    pub approx: Vec<[f64; 2]>,
    /// Per site: its cell as ccw vertex ids (distinct consecutive), or None
    /// when the cell is unbounded or the site hidden.
    pub cells: Vec<Option<Vec<u32>>>,
    /// Per site: whether its cell lies in the domain.
    pub in_domain: Vec<bool>,
}

impl Diagram {
    /// Builds the cells from the regular triangulation of the sites, reusing
    /// the power centres of triangles whose sites have not moved since the
    /// cache was filled (relocation rounds).
    pub fn build(
        dom: &Domain,
        sites: &Sites,
        rt: &Triangulation,
        cache: &mut CentreCache,
    ) -> Diagram {
        let mut index: HashMap<QPoint, u32> = HashMap::new();
        let mut points = vec![];
        let served: Vec<[u32; 2]> = (0..sites.len())
            .map(|s| sites.served(s, &dom.complex))
            .collect();
        let mut vertex_id: Vec<Option<u32>> = vec![None; dom.complex.points.len()];
        let mut id_of = |c: &QPoint, points: &mut Vec<QPoint>| match index.get(c) {
            Some(&id) => id,
            None => {
                points.push(c.clone());
                index.insert(c.clone(), points.len() as u32 - 1);
                points.len() as u32 - 1
            }
        };
        // Three sites serving one input vertex have equal power there by
        // construction: their centre is that vertex.
        let vertex_of = |tri: &[u32; 3]| {
            let [a, b, c] = tri.map(|v| served[v as usize]);
            a.into_iter().find(|v| b.contains(v) && c.contains(v))
        };
        let key = |tri: &[u32; 3]| {
            let mut k = *tri;
            k.sort_unstable();
            k
        };
        // The other centres not cached yet, constructed in parallel.
        let todo: Vec<[u32; 3]> = rt
            .triangles
            .iter()
            .filter(|tri| vertex_of(tri).is_none() && !cache.0.contains_key(&key(tri)))
            .copied()
            .collect();
        let fresh: Vec<QPoint> = todo
            .par_iter()
            .map(|tri| {
                let [a, b, c] = tri.map(|v| v as usize);
                power_centre(
                    [&sites.pos[a], &sites.pos[b], &sites.pos[c]],
                    [&sites.weight[a], &sites.weight[b], &sites.weight[c]],
                )
                .expect("triangles of a regular triangulation are not flat")
            })
            .collect();
        for (tri, c) in todo.iter().zip(fresh) {
            cache.0.insert(key(tri), c);
        }
        let centre_id: Vec<u32> = rt
            .triangles
            .iter()
            .map(|tri| match vertex_of(tri) {
                Some(v) => *vertex_id[v as usize]
                    .get_or_insert_with(|| id_of(&qp(dom.complex.points[v as usize]), &mut points)),
                None => id_of(&cache.0[&key(tri)], &mut points),
            })
            .collect();
        let around = rt.vertex_triangles(sites.len());
        let cells: Vec<Option<Vec<u32>>> = (0..sites.len())
            .map(|v| {
                let start = *around[v].first()?;
                let mut ring = vec![];
                let mut t = start;
                loop {
                    ring.push(centre_id[t as usize]);
                    let tri = rt.triangles[t as usize];
                    let k = tri.iter().position(|&x| x as usize == v).unwrap();
                    let prev = tri[(k + 2) % 3];
                    t = rt.left_of(v as u32, prev)?; // None: hull site, unbounded cell
                    if t == start {
                        break;
                    }
                }
                ring.dedup();
                if ring.len() > 1 && ring.first() == ring.last() {
                    ring.pop();
                }
                Some(ring)
            })
            .collect();
        let approx = points.iter().map(crate::exact::fp).collect();
        let mut d = Diagram {
            points,
            approx,
            cells,
            in_domain: vec![],
        };
        d.in_domain = d.classify(dom, sites, rt, &centre_id);
        d
    }

    /// Cells reachable from each other without crossing a segment form
    /// components; a component is in the domain when it has no unbounded
    /// cell and an interior point of one of its cells is in the domain.
    fn classify(
        &self,
        dom: &Domain,
        sites: &Sites,
        rt: &Triangulation,
        centre_id: &[u32],
    ) -> Vec<bool> {
        let n = sites.len();
        let pairs = sites.segment_pairs(dom.complex.segments.len());
        let mut partner = vec![u32::MAX; n];
        for [a, b] in pairs {
            partner[a as usize] = b;
            partner[b as usize] = a;
        }
        // Cells are neighbours across dual edges of positive length only: at a
        // vertex where four cells meet, the diagonal's dual is a point.
        let mut nb = vec![Vec::new(); n];
        for (a, b) in rt.edges() {
            let c = |x, y| rt.left_of(x, y).map(|t| centre_id[t as usize]);
            if c(a, b).is_none() || c(a, b) != c(b, a) {
                nb[a as usize].push(b);
                nb[b as usize].push(a);
            }
        }
        let mut comp = vec![u32::MAX; n];
        let mut result = vec![false; n];
        for seed in 0..n {
            if comp[seed] != u32::MAX {
                continue;
            }
            let mut members = vec![];
            let mut queue = VecDeque::from([seed]);
            comp[seed] = seed as u32;
            while let Some(v) = queue.pop_front() {
                members.push(v);
                for &u in &nb[v] {
                    if comp[u as usize] == u32::MAX && partner[v] != u {
                        comp[u as usize] = seed as u32;
                        queue.push_back(u as usize);
                    }
                }
            }
            let bounded = members.iter().all(|&v| self.cells[v].is_some());
            let inside = bounded
                && members
                    .iter()
                    .find_map(|&v| self.interior_point(v))
                    .is_some_and(|x| in_domain(dom, &x));
            for v in members {
                result[v] = inside;
            }
        }
        result
    }

    /// A point strictly inside a cell with at least three vertices.
    fn interior_point(&self, v: usize) -> Option<QPoint> {
        let cell = self.cells[v].as_ref()?;
        if cell.len() < 3 {
            return None;
        }
        let k = qi(cell.len() as i64);
        let mut x = [zero(), zero()];
        for &c in cell {
            x[0] += &self.points[c as usize][0];
            x[1] += &self.points[c as usize][1];
        }
        Some([&x[0] / &k, &x[1] / &k])
    }
}

/// Whether x lies in a domain triangle (closed; x never lies on a segment).
fn in_domain(dom: &Domain, x: &QPoint) -> bool {
    let xf = crate::exact::fp(x);
    let p = &dom.complex.points;
    dom.cdt
        .triangles
        .iter()
        .zip(&dom.inside)
        .any(|(tri, &inside)| {
            let [a, b, c] = tri.map(|v| p[v as usize]);
            let lo = |k: usize| a[k].min(b[k]).min(c[k]);
            let hi = |k: usize| a[k].max(b[k]).max(c[k]);
            // cheap reject with a margin for the rounding of x, then exact
            let slack = |k: usize| (hi(k) - lo(k)) * 1e-9 + xf[k].abs() * 1e-15;
            if (0..2).any(|k| xf[k] < lo(k) - slack(k) || xf[k] > hi(k) + slack(k)) {
                return false;
            }
            let (qa, qb, qc) = (qp(a), qp(b), qp(c));
            let o = [
                orient_q(&qa, &qb, x),
                orient_q(&qb, &qc, x),
                orient_q(&qc, &qa, x),
            ];
            inside && o.iter().all(|&s| s != Ordering::Less)
        })
}
