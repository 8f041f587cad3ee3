//! The 3D sites' regular triangulation and its power vertices (issue 23).
//! The backend triangulates the sites' rounded doubles; the result is then
//! checked against the exact sites: every tetrahedron positive, every
//! interior face locally regular, the hull locally convex, every site a
//! vertex (or a mirror hidden under the others). Such a triangulation is
//! the regular triangulation of the exact sites (docs/method.md section 7,
//! as in 2D). Where the check fails, exact flips repair it
//! (`Tetrahedralisation::flip_to_regular3`); where they get stuck (rounding
//! lifts a plane of co-orthogonal sites into flat tetrahedra), the crate's
//! own engine triangulates the exact sites with these predicates; the
//! backend's exact triangulation (CGAL's Epeck) is the last resort.
//!
//! Power vertices are decided without computing most of them exactly:
//! two tetrahedra across a face share their power vertex exactly when the
//! five sites lie on one orthosphere (an exact power test), and four sites
//! that serve a common input vertex have that vertex as their orthocentre
//! (each has power w_v there by construction). Other power vertices are
//! computed in intervals, and exactly only where an interval might hold an
//! input vertex or is too wide to round.

use crate::backend::{regular3_with, Backend, Predicates3, Tetrahedralisation};
use crate::complex::Complex3;
use crate::error::{Error, Result};
use crate::geom::{dot, q, sub, Weighted3, Q};
use crate::sites::Sites3;
use std::cmp::Ordering;
use std::collections::HashMap;

/// Items per parallel batch where results are gathered (bounds the
/// intermediate memory).
pub(super) const CHUNK: usize = 1 << 15;

/// The sites' regular triangulation with its power vertices.
pub(super) struct Regular3 {
    pub rt: Tetrahedralisation,
    pub pv: PowerVertices,
    /// Whether the backend's triangulation of the rounded sites failed the
    /// check and was rebuilt from the exact sites.
    pub rebuilt: bool,
    /// Whether the crate's engine triangulated the exact sites.
    pub engine: bool,
}

/// The power vertices of a regular triangulation.
pub(super) struct PowerVertices {
    /// Per tetrahedron: its power vertex.
    pub vertex_of: Vec<u32>,
    /// Power vertices: input vertices exactly, the others rounded.
    pub points: Vec<[f64; 3]>,
    /// The input vertex a power vertex is, if any (decided exactly).
    pub input_vertex: Vec<Option<u32>>,
    /// Power vertices whose interval was too wide to round well (near
    /// flat tetrahedra, mostly far from the domain), with a tetrahedron:
    /// `refine` computes those the mesh uses exactly.
    rough: Vec<(u32, u32)>,
}

impl PowerVertices {
    /// Rounds the rough power vertices `used` picks from their exact value.
    /// (In parallel: exact, independent per vertex.)
    pub fn refine(
        &mut self,
        k: &Weighted3,
        rt: &Tetrahedralisation,
        used: impl Fn(u32) -> bool + Sync,
    ) {
        use rayon::prelude::*;
        let exact: Vec<(u32, [f64; 3])> = self
            .rough
            .par_iter()
            .filter(|&&(v, _)| used(v))
            .filter_map(|&(v, t)| Some((v, Weighted3::round(&k.orthocentre(rt.tets[t as usize])?))))
            .collect();
        for (v, c) in exact {
            self.points[v as usize] = c;
        }
    }
}

/// Builds and checks the triangulation (see the module's doc).
pub(super) fn regular3<B: Backend + ?Sized>(
    backend: &B,
    cx: &Complex3,
    s: &Sites3,
    k: &Weighted3,
    engine_first: bool,
) -> Result<Regular3> {
    let tests = Tests::new(cx, s, k);
    let (mut fast, mut checked) = if engine_first || rounding_breaks_planes(cx, s) {
        (Tetrahedralisation::default(), Err("not tried".into()))
    } else {
        let approx = s.approx();
        let p: Vec<[f64; 3]> = approx.iter().map(|a| [a[0], a[1], a[2]]).collect();
        let w: Vec<f64> = approx.iter().map(|a| a[3]).collect();
        let fast = backend.regular3(&p, &w)?;
        let checked = check(&tests, &fast);
        (fast, checked)
    };
    if checked.is_err() && !fast.tets.is_empty() {
        let limit = fast.tets.len() / 8 + 64;
        if fast.flip_to_regular3(&tests, limit) {
            checked = check(&tests, &fast);
        }
    }
    let mut engine = false;
    if checked.is_err() {
        // the Rust engine on the exact sites; ties it breaks by hiding a
        // site are left to the backend (CGAL keeps such sites)
        if let Ok(exact) = regular3_with(&tests) {
            if exact.hidden.iter().all(|&x| s.is_mirror(x as usize)) {
                checked = check(&tests, &exact);
                fast = exact;
                engine = true;
            }
        }
    }
    let (rt, ties, rebuilt) = match checked {
        Ok(ties) => (fast, ties, false),
        Err(_) => {
            let rt = backend.regular3_exact(&s.p, &s.w)?;
            if rt.hidden.iter().any(|&x| !s.is_mirror(x as usize)) {
                // the caller names them (`Diagram3::build`)
                return Ok(Regular3 {
                    rt,
                    pv: PowerVertices {
                        vertex_of: vec![],
                        points: vec![],
                        input_vertex: vec![],
                        rough: vec![],
                    },
                    rebuilt: true,
                    engine,
                });
            }
            let ties = check(&tests, &rt).map_err(|why| {
                Error::Certificate(format!(
                    "the exact regular triangulation of the sites fails its check: {why}"
                ))
            })?;
            (rt, ties, true)
        }
    };
    let pv = power_vertices(cx, &tests, &rt, &ties);
    Ok(Regular3 {
        rt,
        pv,
        rebuilt,
        engine,
    })
}

/// Whether rounding the sites to doubles moves some of them off a plane
/// that four or more lie on exactly: the radical plane of two input
/// vertices they all serve, when it is not an axis plane (there every
/// site's coordinate along the axis is the same rational, so it rounds
/// the same) and some site on it is not a double. The backend's
/// triangulation of the rounded sites then has flat tetrahedra that fail
/// the check (every field3 and TetGen run measured), and building it is
/// wasted, so the engine goes first. Sites serving more than 16 vertices
/// (large whole polygons) are not counted: the answer may then be a
/// wrong guess, which costs time, never exactness.
fn rounding_breaks_planes(cx: &Complex3, s: &Sites3) -> bool {
    let double = |x: usize| s.p[x].iter().all(|c| q(crate::geom::f(c)) == *c);
    let mut planes: crate::FastMap<[u32; 2], (u32, bool)> = Default::default();
    for (x, sv) in s.serves.iter().enumerate().filter(|(_, v)| v.len() <= 16) {
        let off = !double(x);
        for (i, &a) in sv.iter().enumerate() {
            for &b in &sv[i + 1..] {
                let (pa, pb) = (cx.points[a as usize], cx.points[b as usize]);
                if (0..3).filter(|&k| pa[k] != pb[k]).count() > 1 {
                    let e = planes.entry([a, b]).or_default();
                    e.0 += 1;
                    e.1 |= off;
                }
            }
        }
    }
    planes.values().any(|&(n, off)| n >= 4 && off)
}

/// The exact tests on the sites. Sites with power w_v at the same point
/// (an input vertex v, or v's mirror image across a clip plane) are
/// co-orthogonal, with that point as their orthocentre: decided without
/// arithmetic.
struct Tests<'a> {
    s: &'a Sites3,
    k: &'a Weighted3<'a>,
    /// Per site, sorted, the points where its power is w_v (numbered
    /// v * clips + 0 for v itself, + c + 1 for its mirror image across clip
    /// c): the vertices it serves, and for the mirror of a site across
    /// clip c the images of that site's vertices (a vertex on the plane
    /// being its own image).
    at: Vec<Vec<u64>>,
    /// One more than the number of clip planes.
    clips: u64,
}

impl<'a> Tests<'a> {
    fn new(cx: &Complex3, s: &'a Sites3, k: &'a Weighted3<'a>) -> Self {
        let clips = s.clips.len() as u64 + 1;
        let witness = |v: u32, c: Option<u32>| v as u64 * clips + c.map_or(0, |c| c as u64 + 1);
        let at = (0..s.p.len())
            .map(|x| {
                let mut at: Vec<u64> = match s.mirror_of.get(x).copied().flatten() {
                    None => s.serves[x].iter().map(|&v| witness(v, None)).collect(),
                    Some((y, c)) => {
                        let plane = &s.clips[c as usize];
                        let on = |v: u32| {
                            dot(&sub(&cx.points[v as usize].map(q), &plane.o), &plane.n) == 0
                        };
                        // (a vertex on the plane is its own image: one
                        // point, one witness, or four sites serving it
                        // alone would look coplanar)
                        s.serves[y as usize]
                            .iter()
                            .map(|&v| witness(v, (!on(v)).then_some(c)))
                            .collect()
                    }
                };
                at.sort_unstable();
                at
            })
            .collect();
        Tests { s, k, at, clips }
    }

    /// How many points (up to 2) every one of these sites has power w_v
    /// at (witnesses, see `at`).
    fn witnesses(&self, xs: &[u32]) -> usize {
        let Some((first, rest)) = xs.split_first() else {
            return 0;
        };
        self.at[*first as usize]
            .iter()
            .filter(|v| {
                rest.iter()
                    .all(|&x| self.at[x as usize].binary_search(v).is_ok())
            })
            .take(2)
            .count()
    }

    /// An input vertex where every one of these sites has power w_v.
    fn common_vertex(&self, xs: &[u32]) -> Option<u32> {
        let (first, rest) = xs.split_first()?;
        self.at[*first as usize]
            .iter()
            .copied()
            .filter(|v| v % self.clips == 0)
            .find(|v| {
                rest.iter()
                    .all(|&x| self.at[x as usize].binary_search(v).is_ok())
            })
            .map(|v| (v / self.clips) as u32)
    }
}

impl Predicates3 for Tests<'_> {
    fn len(&self) -> usize {
        self.s.p.len()
    }
    fn orient(&self, a: u32, b: u32, c: u32, d: u32) -> Ordering {
        // four sites with power w_v at two points lie on a plane (normal
        // to the segment joining the points)
        // (ties seen without arithmetic before the intervals: most that
        // the doubles leave are such, and intervals cannot decide them)
        let t = [a, b, c, d];
        self.k.orient_f64(t).unwrap_or_else(|| {
            if self.k.axis_flat(t) || self.witnesses(&t) == 2 {
                return Ordering::Equal;
            }
            self.k
                .orient_interval(t)
                .unwrap_or_else(|| self.k.orient_exact(t))
        })
    }
    fn power(&self, t: [u32; 4], e: u32) -> Ordering {
        let five = [t[0], t[1], t[2], t[3], e];
        self.k
            .power_f64(t, e)
            .unwrap_or_else(|| match self.witnesses(&five) {
                0 => self
                    .k
                    .power_interval(t, e)
                    .unwrap_or_else(|| self.k.power_exact(t, e)),
                _ => Ordering::Equal,
            })
    }
    fn exact(&self, v: u32) -> ([Q; 3], Q) {
        (self.s.p[v as usize].clone(), self.s.w[v as usize].clone())
    }
    fn in_plane_filtered(&self, face: [u32; 3], p: u32) -> Option<Ordering> {
        self.k.in_plane_interval(face, p)
    }
}

/// Why `rt` is not the regular triangulation of the exact sites, or the
/// pairs of tetrahedra across faces whose five sites lie on one
/// orthosphere.
fn check(t: &Tests, rt: &Tetrahedralisation) -> std::result::Result<Vec<[u32; 2]>, String> {
    if rt.tets.is_empty() {
        return Err("no tetrahedra".into());
    }
    // (the exact tests in parallel: independent, and as many as the
    // triangulation's faces)
    use rayon::prelude::*;
    let flat = rt
        .tets
        .par_iter()
        .enumerate()
        .find_first(|(_, tet)| t.orient(tet[0], tet[1], tet[2], tet[3]) != Ordering::Greater);
    if let Some((i, tet)) = flat {
        return Err(format!("tetrahedron {i} {tet:?} is not positive"));
    }
    let mut vertex = vec![false; t.s.p.len()];
    for tet in &rt.tets {
        tet.iter().for_each(|&v| vertex[v as usize] = true);
    }
    // Only mirrors may be hidden (a site's own tie is the caller's to
    // name), and only under the lifted hull of the others.
    for &h in &rt.hidden {
        if !t.s.is_mirror(h as usize) || vertex[h as usize] {
            return Err(format!("site {h} is hidden"));
        }
        let home = rt
            .locate(t, h)
            .ok_or_else(|| format!("hidden site {h} is outside"))?;
        if t.power(rt.tets[home as usize], h) == Ordering::Greater {
            return Err(format!("hidden site {h} has a cell"));
        }
        vertex[h as usize] = true;
    }
    if let Some(x) = vertex.iter().position(|&v| !v) {
        return Err(format!("site {x} is not a vertex"));
    }
    let mut ties = vec![];
    let mut faces = rt.inner_faces().map(|(a, _, b, l)| (a, b, l));
    loop {
        // (a chunk at a time: all faces at once held 16 bytes each)
        let chunk: Vec<(u32, u32, usize)> = faces.by_ref().take(CHUNK).collect();
        if chunk.is_empty() {
            break;
        }
        let power: Vec<Ordering> = chunk
            .par_iter()
            .map(|&(t1, t2, l)| t.power(rt.tets[t1 as usize], rt.tets[t2 as usize][l]))
            .collect();
        for (&(t1, t2, _), o) in chunk.iter().zip(power) {
            match o {
                Ordering::Greater => {
                    return Err(format!("the face of {t1} and {t2} is not regular"))
                }
                Ordering::Equal => ties.push([t1, t2]),
                Ordering::Less => {}
            }
        }
    }
    // The hull bends inwards at every edge: the third vertex of the hull
    // face across the edge is not beyond this face's plane.
    let hull: Vec<[u32; 3]> = rt.hull_faces().collect();
    let mut by_edge: HashMap<[u32; 2], u32> = HashMap::with_capacity(3 * hull.len());
    for f in &hull {
        for e in 0..3 {
            by_edge.insert([f[e], f[(e + 1) % 3]], f[(e + 2) % 3]);
        }
    }
    for f in &hull {
        for e in 0..3 {
            let Some(&c) = by_edge.get(&[f[(e + 1) % 3], f[e]]) else {
                return Err(format!("hull edge of {f:?} has no face across"));
            };
            if t.orient(f[0], f[1], f[2], c) == Ordering::Less {
                return Err(format!("the hull is not convex at {f:?}"));
            }
        }
    }
    Ok(ties)
}

/// Per tetrahedron its power vertex, the power vertices' positions and
/// the input vertex each is (see the module's doc).
fn power_vertices(
    cx: &Complex3,
    tests: &Tests,
    rt: &Tetrahedralisation,
    ties: &[[u32; 2]],
) -> PowerVertices {
    let n = rt.tets.len();
    let mut parent: Vec<u32> = (0..n as u32).collect();
    fn find(p: &mut [u32], mut x: u32) -> u32 {
        while p[x as usize] != x {
            p[x as usize] = p[p[x as usize] as usize];
            x = p[x as usize];
        }
        x
    }
    for &[a, b] in ties {
        let (a, b) = (find(&mut parent, a), find(&mut parent, b));
        parent[a.max(b) as usize] = a.min(b);
    }
    // classes numbered in order of their first tetrahedron
    let mut id_of_root = vec![u32::MAX; n];
    let mut vertex_of = Vec::with_capacity(n);
    let mut first: Vec<u32> = vec![];
    let mut input: Vec<Option<u32>> = vec![];
    for t in 0..n as u32 {
        let r = find(&mut parent, t) as usize;
        if id_of_root[r] == u32::MAX {
            id_of_root[r] = first.len() as u32;
            first.push(t);
            input.push(None);
        }
        let id = id_of_root[r];
        vertex_of.push(id);
        if input[id as usize].is_none() {
            input[id as usize] = tests.common_vertex(&rt.tets[t as usize]);
        }
    }
    // input points by x, for the intervals' candidates
    let mut by_x: Vec<u32> = (0..cx.points.len() as u32).collect();
    by_x.sort_by(|&a, &b| cx.points[a as usize][0].total_cmp(&cx.points[b as usize][0]));
    let scale = cx
        .points
        .iter()
        .flatten()
        .fold(1e-300f64, |m, x| m.max(x.abs()));
    // (each class apart, in parallel: the exact orthocentres are costly)
    use rayon::prelude::*;
    let placed: Vec<([f64; 3], Option<u32>, bool)> = first
        .par_iter()
        .zip(&input)
        .map(|(&t, &known)| {
            if let Some(v) = known {
                return (cx.points[v as usize], Some(v), false);
            }
            let tet = rt.tets[t as usize];
            let iv = tests.k.orthocentre_iv(tet);
            let lo = by_x.partition_point(|&v| cx.points[v as usize][0] < iv[0].lo);
            let mut candidates = by_x[lo..]
                .iter()
                .take_while(|&&v| cx.points[v as usize][0] <= iv[0].hi)
                .filter(|&&v| {
                    (1..3).all(|c| {
                        iv[c].lo <= cx.points[v as usize][c] && cx.points[v as usize][c] <= iv[c].hi
                    })
                })
                .peekable();
            let narrow = iv.iter().all(|x| x.hi - x.lo <= 1e-12 * scale);
            if candidates.peek().is_none() {
                return (iv.map(|x| x.mid()), None, !narrow);
            }
            let Some(c) = tests.k.orthocentre(tet) else {
                // (a positive tetrahedron is not flat)
                return (iv.map(|x| x.mid()), None, false);
            };
            match candidates.find(|&&v| cx.points[v as usize].map(q) == c) {
                Some(&v) => (cx.points[v as usize], Some(v), false),
                None => (Weighted3::round(&c), None, false),
            }
        })
        .collect();
    let points = placed.iter().map(|x| x.0).collect();
    let input = placed.iter().map(|x| x.1).collect();
    let rough: Vec<u32> = (0..placed.len() as u32)
        .filter(|&i| placed[i as usize].2)
        .collect();
    PowerVertices {
        vertex_of,
        points,
        input_vertex: input,
        rough: rough.into_iter().map(|v| (v, first[v as usize])).collect(),
    }
}
