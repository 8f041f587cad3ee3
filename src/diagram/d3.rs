//! The power diagram of the 3D sites and its exact certificate (issue 6;
//! docs/method.md section 7). The sites' regular triangulation is checked
//! exactly (`regular3`), and "this power vertex is input vertex p" and
//! "this face has exactly these vertices" are decided without rounding.
//! Positions are rounded only for output, and input vertices are written
//! as the input's own doubles.

use super::faces3::{Faces, Side};
use super::regular3::{regular3, PowerVertices, Regular3, CHUNK};
use crate::backend::{Backend, Tetrahedralisation};
use crate::complex::Complex3;
use crate::error::{Error, Result};
use crate::geom::{det3_f, dot_f, f, newell, norm2, q, sub, Weighted3, Q};
use crate::sites::Sites3;
use crate::weights::Weights3;
use crate::{FastMap as HashMap, FastSet as HashSet};
use rayon::prelude::*;
use serde::Serialize;

/// A cell: its faces (`Faces::side` reads each as a cycle of power
/// vertices counter-clockwise seen from outside), with the site across.
pub type Cell = Vec<Side>;

/// Power diagram of the sites.
#[derive(Debug, Clone, Default)]
pub struct Diagram3 {
    /// Regular triangulation of the sites (exact).
    pub rt: Tetrahedralisation,
    /// Per site tetrahedron: its power vertex.
    pub vertex_of: Vec<u32>,
    /// Power vertices: input vertices exactly, the others rounded.
    pub points: Vec<[f64; 3]>,
    /// The input vertex a power vertex is, if any (decided exactly).
    pub input_vertex: Vec<Option<u32>>,
    /// Per site: whether its cell lies in the domain.
    pub in_domain: Vec<bool>,
    /// Per site in the domain: its cell's faces, with the site across.
    pub cells: Vec<Option<Cell>>,
    /// Per edge of `rt`: its dual face, the cycle of power vertices around
    /// it with repeats merged (None: unbounded).
    pub faces: Faces,
    /// Per site, whether it lies strictly inside its own cell (exact).
    pub site_inside: Vec<bool>,
    /// The sites and weights as doubles.
    pub approx: Vec<[f64; 4]>,
    /// Whether the backend's triangulation of the rounded sites failed
    /// its exact check, so that the exact sites were triangulated.
    pub rebuilt: bool,
    /// Whether the crate's engine triangulated the exact sites (the
    /// backend's triangulation of the rounded ones failed its check and
    /// flips did not mend it, or was not tried).
    pub engine: bool,
}

/// What the finished 3D mesh proves about itself.
#[derive(Debug, Clone, Serialize, Default)]
pub struct Certificate3 {
    /// Triangles and whole polygons that are exactly one face of the
    /// diagram (with exactly their vertices), of all.
    pub faces_exact: usize,
    /// Faces of the complex (triangles and whole polygons) in the domain.
    pub faces: usize,
    /// Dangling segments that are exactly one edge.
    pub segments_exact: usize,
    /// Constraint segments.
    pub segments: usize,
    /// Input vertices that are power vertices.
    pub vertices_exact: usize,
    /// Input vertices.
    pub vertices: usize,
    /// Sites of domain cells strictly inside their own cell (exact), of all.
    pub sites_inside: usize,
    /// Sites whose cells are in the domain.
    pub domain_sites: usize,
    /// Sum of the domain cells' volumes and the volume the domain's
    /// boundary faces enclose (doubles).
    pub cells_volume: f64,
    /// The domain's volume.
    pub domain_volume: f64,
    /// Largest |cos| between a face's in-plane directions and the segment
    /// joining its two sites, on the output as written (`conform3` fills it).
    pub orthogonality_defect: f64,
}

impl Certificate3 {
    /// Conformity holds (faces, segments, vertices exact; volumes agree).
    pub fn conforms(&self) -> bool {
        self.faces_exact == self.faces
            && self.segments_exact == self.segments
            && self.vertices_exact == self.vertices
            && (self.cells_volume - self.domain_volume).abs()
                <= 1e-9 * self.domain_volume.abs().max(1e-300)
    }
}

/// Whether hidden site h is a tie: its lifted point (p, |p|^2 - w) lies
/// exactly on the lower hull of the others' (the tetrahedron of `rt` that
/// holds p interpolates its height), so that a regular triangulation may
/// keep it with a cell of no volume or hide it, as backends' tie-breaks
/// choose (measured: CGAL keeps, the pure backend hides).
fn on_lower_hull(s: &Sites3, rt: &Tetrahedralisation, h: usize) -> bool {
    let x = &s.p[h];
    let det = |a: &[Q; 3], b: &[Q; 3], c: &[Q; 3]| {
        crate::geom::det3_q([
            [&a[0], &a[1], &a[2]],
            [&b[0], &b[1], &b[2]],
            [&c[0], &c[1], &c[2]],
        ])
    };
    let height = |v: usize| norm2(&s.p[v]) - &s.w[v];
    rt.tets.iter().any(|t| {
        let v = t.map(|k| k as usize);
        let d = |a: usize, b: usize, c: usize, o: &[Q; 3]| {
            det(&sub(&s.p[a], o), &sub(&s.p[b], o), &sub(&s.p[c], o))
        };
        let whole = d(v[1], v[2], v[3], &s.p[v[0]]);
        // barycentric coordinates of x, each a signed volume over the whole
        let parts = [
            d(v[1], v[2], v[3], x),
            -d(v[0], v[2], v[3], x),
            d(v[0], v[1], v[3], x),
            -d(v[0], v[1], v[2], x),
        ];
        let zero = Q::from(0);
        if whole == zero
            || parts
                .iter()
                .any(|l| (l < &zero) != (whole < zero) && l != &zero)
        {
            return false;
        }
        let interpolated: Q = (0..4).map(|k| &parts[k] * height(v[k])).sum::<Q>() / &whole;
        interpolated == height(h)
    })
}

impl Diagram3 {
    /// Builds the site diagram and its domain (cells not separated by a
    /// face from an unbounded cell or a hole point). `engine_first` skips
    /// the backend's triangulation of the rounded sites: when it failed
    /// for earlier sites of the same input, it will most likely fail again
    /// (measured on `generate field3` 4 x 4 x 4: 205 ms of CGAL, slowed by
    /// near-ties, and 150 ms of flips before the engine's 380 ms).
    pub fn build<B: Backend + ?Sized>(
        backend: &B,
        cx: &Complex3,
        s: &Sites3,
        engine_first: bool,
    ) -> Result<Diagram3> {
        let k = Weighted3::new(&s.p, &s.w);
        let Regular3 {
            rt,
            mut pv,
            rebuilt,
            engine,
        } = regular3(backend, cx, s, &k, engine_first)?;
        // (mirrors across two planes may hide each other beyond both: no
        // cell there is in the domain)
        let hidden = rt
            .hidden
            .iter()
            .filter(|&&x| !s.is_mirror(x as usize))
            .count();
        if hidden > 0 {
            let ties: Vec<u32> = rt
                .hidden
                .iter()
                .copied()
                .filter(|&x| !s.is_mirror(x as usize) && on_lower_hull(s, &rt, x as usize))
                .collect();
            if ties.len() == hidden {
                return Err(Error::Degenerate(format!(
                    "sites {ties:?} have no cell of positive volume: each lies exactly where \
                     other sites' cells meet (the facets are degenerate there)"
                )));
            }
            return Err(Error::Certificate(format!(
                "{hidden} sites are hidden in their own diagram"
            )));
        }
        let faces = edge_faces(&rt, &pv.vertex_of, s.p.len());
        let in_domain = domain(cx, s, &k, &rt, &faces)?;
        // the power vertices of the domain's cells well rounded
        let mut used = vec![false; pv.points.len()];
        for ([a, b], face) in faces.iter() {
            if in_domain[a as usize] || in_domain[b as usize] {
                face.iter()
                    .copied()
                    .flatten()
                    .for_each(|&v| used[v as usize] = true);
            }
        }
        pv.refine(&k, &rt, |v| used[v as usize]);
        let PowerVertices {
            vertex_of,
            points,
            input_vertex,
            ..
        } = pv;
        let sp = s.approx();
        // in edge order: the same input gives the same cells' face order
        let keys: Vec<[u32; 2]> = faces.edges().collect();
        let site_inside = sites_inside(&k, s.p.len(), &keys);
        // each side's face oriented outward (its normal towards the other
        // site), in parallel a chunk at a time; None for an unbounded
        // domain cell
        let mut cells: Vec<Option<Cell>> = vec![None; s.p.len()];
        for chunk in keys.chunks(CHUNK) {
            let (sp, points) = (&sp, &points);
            let sides: Vec<(u32, Option<Side>)> = chunk
                .par_iter()
                .flat_map_iter(|&[a, b]| {
                    let (k, face) = faces.numbered(&[a, b]).expect("an edge's face");
                    [(a, b), (b, a)]
                        .into_iter()
                        .filter(|&(me, _)| in_domain[me as usize])
                        .filter(move |_| face.is_none_or(|f| f.len() >= 3))
                        .map(move |(me, other)| {
                            let side = face.map(|face| {
                                let d: [f64; 3] = std::array::from_fn(|k| {
                                    sp[other as usize][k] - sp[me as usize][k]
                                });
                                let pts: Vec<[f64; 3]> =
                                    face.iter().map(|&v| points[v as usize]).collect();
                                Side {
                                    face: k,
                                    reversed: dot_f(newell(&pts), d) < 0.0,
                                    other,
                                }
                            });
                            (me, side)
                        })
                })
                .collect();
            for (me, side) in sides {
                let Some(side) = side else {
                    return Err(Error::Certificate(format!(
                        "a domain cell (site {me}) is unbounded"
                    )));
                };
                cells[me as usize].get_or_insert_with(Vec::new).push(side);
            }
        }
        // A site whose cell has no face of positive area (a vertex of the
        // site triangulation whose cell is a point or a segment) has no
        // volume: no mesh cell.
        let mut in_domain = in_domain;
        for (x, inside) in in_domain.iter_mut().enumerate() {
            *inside &= cells[x].is_some();
        }
        Ok(Diagram3 {
            rt,
            vertex_of,
            points,
            input_vertex,
            in_domain,
            cells,
            faces,
            site_inside,
            approx: sp,
            rebuilt,
            engine,
        })
    }

    /// The exact certificate (see `Certificate3`).
    pub fn certify(&self, cx: &Complex3, wt: &Weights3, s: &Sites3) -> Certificate3 {
        let mut c = Certificate3::default();
        let vertex_set = |a: u32, b: u32| -> Option<HashSet<u32>> {
            let face = self.faces.get(&[a.min(b), a.max(b)])??;
            Some(face.iter().copied().collect())
        };
        // power vertex of each input vertex
        let mut of_input: HashMap<u32, u32> = HashMap::default();
        for (v, iv) in self.input_vertex.iter().enumerate() {
            if let Some(i) = iv {
                of_input.insert(*i, v as u32);
            }
        }
        let mut edges: HashSet<[u32; 2]> = HashSet::default();
        for (t, _, u, _) in self.rt.inner_faces() {
            let (a, b) = (self.vertex_of[t as usize], self.vertex_of[u as usize]);
            if a != b {
                edges.insert([a.min(b), a.max(b)]);
            }
        }
        let mut vertices: Vec<u32> = vec![];
        for (fi, face) in wt.faces.iter().enumerate() {
            vertices.extend(&face.vertices);
            if crate::sites::clip_of(&s.clips, face.facet).is_some() {
                // cut by mirrors: the domain's cells share them out
                continue;
            }
            match face.dim() {
                2 => {
                    c.faces += 1;
                    let Some([s1, s2]) = s.of_face[fi] else {
                        continue;
                    };
                    let want: Option<HashSet<u32>> = face
                        .vertices
                        .iter()
                        .map(|v| of_input.get(v).copied())
                        .collect();
                    if want.is_some() && vertex_set(s1, s2) == want {
                        c.faces_exact += 1;
                    }
                }
                1 => {
                    c.segments += 1;
                    let ends = [0, 1].map(|k| of_input.get(&face.vertices[k]).copied());
                    if let [Some(a), Some(b)] = ends {
                        if edges.contains(&[a.min(b), a.max(b)]) {
                            c.segments_exact += 1;
                        }
                    }
                }
                _ => {}
            }
        }
        vertices.sort_unstable();
        vertices.dedup();
        c.vertices = vertices.len();
        c.vertices_exact = vertices.iter().filter(|v| of_input.contains_key(v)).count();
        let domain: Vec<usize> = (0..s.p.len()).filter(|&x| self.in_domain[x]).collect();
        c.domain_sites = domain.len();
        c.sites_inside = domain.iter().filter(|&&x| self.site_inside[x]).count();
        c.cells_volume = domain.iter().map(|&x| self.volume(x)).sum();
        c.domain_volume = boundary_volume(cx, wt, s, self);
        c
    }

    /// A cell's volume from its faces (divergence theorem, doubles).
    pub fn volume(&self, site: usize) -> f64 {
        let Some(faces) = &self.cells[site] else {
            return 0.0;
        };
        let first = self
            .faces
            .side(&faces[0])
            .next()
            .expect("a face of 3 vertices");
        let o = self.points[first as usize];
        faces
            .iter()
            .map(|side| {
                let face = self.faces.polygon(side.face);
                let n = face.len();
                let p = |k: usize| -> [f64; 3] {
                    let k = if side.reversed { n - 1 - k } else { k };
                    let x = self.points[face[k] as usize];
                    std::array::from_fn(|i| x[i] - o[i])
                };
                (1..n - 1)
                    .map(|k| det3_f(p(0), p(k), p(k + 1)) / 6.0)
                    .sum::<f64>()
            })
            .sum()
    }
}

/// Each edge's face: the power vertices of the tetrahedra around it,
/// repeats merged (None: unbounded), from its first tetrahedron (the
/// lowest numbered). Edges are found site by site from each site's
/// tetrahedra, so that the rings are walked where the memory was just
/// read. (The faces in parallel, a chunk at a time: whole intermediate
/// vectors raised the peak by a KB a facet triangle.)
fn edge_faces(rt: &Tetrahedralisation, vertex_of: &[u32], n: usize) -> Faces {
    let mut start = vec![0u32; n + 1];
    for tet in &rt.tets {
        tet.iter().for_each(|&v| start[v as usize + 1] += 1);
    }
    for i in 0..n {
        start[i + 1] += start[i];
    }
    let mut fill = start.clone();
    let mut star = vec![0u32; start[n] as usize];
    for (t, tet) in rt.tets.iter().enumerate() {
        for &v in tet {
            star[fill[v as usize] as usize] = t as u32;
            fill[v as usize] += 1;
        }
    }
    // per site a, its neighbours b > a, each with its first tetrahedron
    let above: Vec<Vec<(u32, u32)>> = (0..n)
        .into_par_iter()
        .map(|a| {
            let tets = &star[start[a] as usize..start[a + 1] as usize];
            let mut out: Vec<(u32, u32)> = tets
                .iter()
                .flat_map(|&t| {
                    let tet = rt.tets[t as usize];
                    tet.into_iter()
                        .filter(|&b| b > a as u32)
                        .map(move |b| (b, t))
                })
                .collect();
            out.sort_unstable();
            out.dedup_by_key(|x| x.0);
            out.shrink_to_fit();
            out
        })
        .collect();
    drop((start, fill, star));
    let first: Vec<u32> = above.iter().flatten().map(|&(_, t)| t).collect();
    let mut faces = Faces::with_edges(
        above
            .into_iter()
            .map(|list| list.into_iter().map(|(b, _)| b).collect())
            .collect(),
    );
    let first: Vec<([u32; 2], u32)> = faces.edges().zip(first).collect();
    for chunk in first.chunks(CHUNK) {
        let made: Vec<Option<Vec<u32>>> = chunk
            .par_iter()
            .map(|&(e, t)| {
                rt.ring(t, e[0], e[1]).map(|ring| {
                    let mut face: Vec<u32> = ring.iter().map(|&t| vertex_of[t as usize]).collect();
                    face.dedup();
                    while face.len() > 1 && face.first() == face.last() {
                        face.pop();
                    }
                    face
                })
            })
            .collect();
        made.iter().for_each(|face| faces.push(face.as_deref()));
    }
    faces
}

/// Per site, whether it lies strictly inside its own cell, exactly:
/// |p_s - p_t|^2 - w_t + w_s > 0 for every neighbour t (`edges`: the
/// edges of the sites' regular triangulation).
fn sites_inside(k: &Weighted3, n: usize, edges: &[[u32; 2]]) -> Vec<bool> {
    let apart: Vec<[bool; 2]> = edges.par_iter().map(|&[a, b]| k.apart(a, b)).collect();
    let mut inside = vec![true; n];
    for (&[a, b], [in_a, in_b]) in edges.iter().zip(apart) {
        inside[a as usize] &= in_a;
        inside[b as usize] &= in_b;
    }
    inside
}

/// Per site, whether its cell is in the domain: sites are joined across
/// every diagram face of positive area except the constraint faces; a group with an
/// unbounded cell (a site on the hull of the sites) or with the cell
/// holding a volume hole point is outside.
fn domain(
    cx: &Complex3,
    s: &Sites3,
    k: &Weighted3,
    rt: &Tetrahedralisation,
    faces: &Faces,
) -> Result<Vec<bool>> {
    let n = s.p.len();
    let mut cut: HashSet<[u32; 2]> = HashSet::default();
    for [a, b] in s.of_face.iter().flatten() {
        cut.insert([*a.min(b), *a.max(b)]);
    }
    // mirrors are outside, and the faces they share with sites are on the
    // clip planes
    for e in faces.edges() {
        if s.is_mirror(e[0] as usize) != s.is_mirror(e[1] as usize) {
            cut.insert(e);
        }
    }
    let mut parent: Vec<u32> = (0..n as u32).collect();
    fn find(p: &mut [u32], mut x: u32) -> u32 {
        while p[x as usize] != x {
            p[x as usize] = p[p[x as usize] as usize];
            x = p[x as usize];
        }
        x
    }
    // Faces of no area (sites meeting at a power vertex or edge only) join
    // nothing: they may cross a constraint face's boundary.
    for (e, face) in faces.iter() {
        if !cut.contains(&e) && face.is_none_or(|f| f.len() >= 3) {
            let (a, b) = (find(&mut parent, e[0]), find(&mut parent, e[1]));
            parent[a.max(b) as usize] = a.min(b);
        }
    }
    let mut outside = HashSet::default();
    for x in (0..n).filter(|&x| s.is_mirror(x)) {
        outside.insert(find(&mut parent, x as u32));
    }
    for f in rt.hull_faces() {
        for v in f {
            outside.insert(find(&mut parent, v));
        }
    }
    for h in &cx.holes {
        // the least power at h: intervals, then rationals among the sites
        // whose interval may hold it
        let iv: Vec<_> = (0..n as u32).map(|x| k.power_at(x, *h)).collect();
        let least = iv.iter().fold(f64::INFINITY, |m, p| m.min(p.hi));
        let hq = h.map(q);
        let best = (0..n as u32)
            .filter(|&x| iv[x as usize].lo <= least)
            .map(|x| (k.power_at_q(x, &hq), x))
            .min_by(|a, b| a.0.cmp(&b.0).then(a.1.cmp(&b.1)))
            .map_or(0, |(_, x)| x);
        outside.insert(find(&mut parent, best));
    }
    let inside: Vec<bool> = (0..n as u32)
        .map(|x| !outside.contains(&find(&mut parent, x)))
        .collect();
    if !inside.iter().any(|&b| b) {
        return Err(Error::Degenerate(
            "the facets enclose no volume (every cell is unbounded or around a hole)".into(),
        ));
    }
    Ok(inside)
}

/// The volume the constraint faces between domain and non-domain cells
/// enclose: each such face oriented away from its domain site.
fn boundary_volume(cx: &Complex3, wt: &Weights3, s: &Sites3, d: &Diagram3) -> f64 {
    let (sp, in_domain) = (&d.approx, &d.in_domain);
    let o = cx.points[0];
    let mut vol = 0.0;
    for (fi, face) in wt.faces.iter().enumerate() {
        // away from the domain: towards the outer site, or the clip's normal
        let d: [f64; 3] = if let Some(c) = crate::sites::clip_of(&s.clips, face.facet) {
            c.n.clone().map(|x| f(&x))
        } else {
            let Some([a, b]) = s.of_face[fi] else {
                continue;
            };
            let (ia, ib) = (in_domain[a as usize], in_domain[b as usize]);
            if ia == ib {
                continue;
            }
            let (inner, outer) = if ia { (a, b) } else { (b, a) };
            std::array::from_fn(|k| sp[outer as usize][k] - sp[inner as usize][k])
        };
        let p = |v: u32| -> [f64; 3] {
            let x = cx.points[v as usize];
            std::array::from_fn(|i| x[i] - o[i])
        };
        let vs = &face.vertices;
        if vs.len() < 3 {
            continue;
        }
        let mut face_vol: f64 = (1..vs.len() - 1)
            .map(|k| det3_f(p(vs[0]), p(vs[k]), p(vs[k + 1])) / 6.0)
            .sum();
        let pts: Vec<[f64; 3]> = vs.iter().map(|&v| cx.points[v as usize]).collect();
        if dot_f(newell(&pts), d) < 0.0 {
            face_vol = -face_vol;
        }
        vol += face_vol;
    }
    vol
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::backend::compiled;

    fn pipeline(cx: &Complex3) -> (Weights3, Sites3, Diagram3, Certificate3) {
        let b = &compiled()[0];
        let sc = cx.triangulate(b.as_ref()).unwrap();
        let wt = crate::weights::solve3(b.as_ref(), cx, &sc, Default::default(), &[]).unwrap();
        let s = crate::sites::place3(cx, &wt).unwrap();
        let d = Diagram3::build(b.as_ref(), cx, &s, false).unwrap();
        let c = d.certify(cx, &wt, &s);
        (wt, s, d, c)
    }

    /// (TetGen's example runs through the pipeline in tests/conform3.rs.)
    #[test]
    fn stacked_boxes_certify() {
        let cx = crate::generate::stacked_boxes(2);
        let (wt, s, d, c) = pipeline(&cx);
        eprintln!(
            "faces {} sites {} cells {} {:?}",
            wt.faces.len(),
            s.p.len(),
            d.cells.iter().flatten().count(),
            c
        );
        assert!(c.conforms());
    }
}
