//! Sites of the conforming power diagram in 3D (paper section 4, Theorem 1;
//! issue 6): two sites on the dual edge of each triangle or whole polygon,
//! one on each side; three affinely independent sites in the dual polygon
//! of each constraint edge and four in the power cell of each vertex,
//! counting the sites already placed on faces that contain it and adding
//! sites on the duals of other triangles of the regular triangulation
//! where they fall short. A site s on the dual of an RT face F gets the
//! weight pi(s; p_i, w_i), the same for every vertex i of F; everything is
//! exact rationals, so each site lies exactly on its dual and its weight
//! is exactly that power.

use super::track3::{Roam, Track};
use crate::complex::Complex3;
use crate::error::{Error, Result};
use crate::geom::{
    along, cross, cross_f, det3, det3_f, dot, dot_f, f, is_pos, norm2, q, sub, Iv, Q,
};
use crate::weights::{face_centre, fan, sorted3, Centre, Weights3};
use crate::FastMap;
use rayon::prelude::*;
use std::cmp::Ordering;
use std::collections::{BTreeMap, HashMap};
use std::sync::Arc;

/// All sites, exactly.
#[derive(Debug, Clone, Default)]
pub struct Sites3 {
    pub p: Vec<[Q; 3]>,
    pub w: Vec<Q>,
    /// Per site: the vertices of the RT face on whose dual it lies (sorted):
    /// it lies in their power cells, with power w_i to each.
    pub serves: Vec<Vec<u32>>,
    /// Per face (`Weights3::faces`) of dimension 2: its two sites, behind
    /// and in front of it along the normal of its first three vertices.
    pub of_face: Vec<Option<[u32; 2]>>,
    /// Per site of a face that crosses its dual: the line it may move on
    /// towards the face (relocation).
    pub line: Vec<Option<Line>>,
    /// Per extra site: where it may move (`wander`); boxed, as
    /// most sites have none (unboxed, field3 16 x 16 x 8's peak grew by 0.7
    /// KB a triangle).
    pub track: Vec<Option<Box<Roam>>>,
    /// The planes the diagram is cut at (`clipped`), and per site the
    /// site and plane it mirrors (empty: no mirrors).
    pub clips: Vec<Clip>,
    pub mirror_of: Vec<Option<(u32, u32)>>,
}

/// A plane that bounds the domain where no mesh lies beyond (a facet on
/// the hull, e.g. a reservoir's top): `o` on it, `n` pointing away from
/// the domain.
#[derive(Debug, Clone)]
pub struct Clip {
    pub facet: u32,
    pub o: [Q; 3],
    pub n: [Q; 3],
}

/// The clip plane of the facet a face lies in, if it is one.
pub fn clip_of(clips: &[Clip], facet: Option<u32>) -> Option<&Clip> {
    clips.iter().find(|c| facet == Some(c.facet))
}

impl Clip {
    /// The mirror image of x.
    fn mirror(&self, x: &[Q; 3]) -> [Q; 3] {
        let t = Q::from(-2) * dot(&sub(x, &self.o), &self.n) / dot(&self.n, &self.n);
        along(x, &t, &self.n)
    }

    /// Whether x is strictly on the domain's side.
    fn below(&self, x: &[Q; 3]) -> bool {
        is_pos(&-dot(&sub(x, &self.o), &self.n))
    }
}

/// A site at c + t n on the dual line of a face that crosses it at c.
#[derive(Debug, Clone)]
pub struct Line {
    /// Shared by the face's two sites: exact centres and normals are large
    /// rationals (field3 16 x 16 x 8: about 10% of the peak memory).
    pub c: Arc<[Q; 3]>,
    pub n: Arc<[Q; 3]>,
    pub t: Q,
}

/// The dual line of a planar set of vertices with coplanar lifts: the
/// centre c, the normal n, and the range (lo, hi) of t for which c + t n
/// is in the power cells of these vertices only (None: unbounded).
struct Dual {
    c: Arc<[Q; 3]>,
    n: Arc<[Q; 3]>,
    lo: Option<Q>,
    hi: Option<Q>,
}

impl Dual {
    /// The dual of face `vs` (3 or more coplanar vertices) with the RT
    /// vertices across its triangles, from the face's centre.
    fn of(cx: &Complex3, w: &[Q], (vs, centre): (&[u32], &Centre), apexes: &[u32]) -> Option<Dual> {
        let (c, power) = centre.clone();
        let p = |v: u32| cx.points[v as usize].map(q);
        let p0 = p(vs[0]);
        let n = cross(&sub(&p(vs[1]), &p0), &sub(&p(vs[2]), &p0));
        let (mut lo, mut hi): (Option<Q>, Option<Q>) = (None, None);
        for &m in apexes {
            let pm = p(m);
            let denom = Q::from(2) * dot(&n, &sub(&pm, &p0));
            if denom == 0 {
                return None;
            }
            // pi(c + t n; m) = pi(c + t n; v0)
            let t = (norm2(&sub(&c, &pm)) - &w[m as usize] - &power) / &denom;
            if is_pos(&denom) {
                hi = Some(hi.map_or(t.clone(), |h| if t < h { t.clone() } else { h }));
            } else {
                lo = Some(lo.map_or(t.clone(), |l| if t > l { t.clone() } else { l }));
            }
        }
        match (&lo, &hi) {
            (Some(l), Some(h)) if l >= h => None,
            _ => Some(Dual {
                c: Arc::new(c),
                n: Arc::new(n),
                lo,
                hi,
            }),
        }
    }

    /// A step of t that moves about half the face's size: sqrt(L) / 2 / |n|.
    /// For a face in an axis plane, the power of two at or below sqrt(L) / 2
    /// over n's one component, exactly: the sites beyond hull faces in one
    /// axis plane then share their height, exact ties the tests see without
    /// arithmetic instead of near-ties that cost them integers (field3 8 x 8
    /// x 4: site diagram 1.5 -> 1.1 s).
    fn scale(&self, cx: &Complex3, vs: &[u32]) -> Q {
        let p = |v: u32| cx.points[v as usize];
        let l = (0..vs.len())
            .map(|k| {
                let (a, b) = (p(vs[k]), p(vs[(k + 1) % vs.len()]));
                (0..3).map(|i| (b[i] - a[i]).powi(2)).sum::<f64>()
            })
            .fold(0.0, f64::max);
        let zero = Q::from(0);
        let axes: Vec<usize> = (0..3).filter(|&k| self.n[k] != zero).collect();
        if let [k] = axes[..] {
            let h = 2f64.powi((l.sqrt() / 2.0).log2().floor() as i32);
            let nk = if is_pos(&self.n[k]) {
                self.n[k].clone()
            } else {
                -self.n[k].clone()
            };
            return q(h) / nk;
        }
        let n = self.n.iter().map(|x| f(x).powi(2)).sum::<f64>().sqrt();
        q(l.sqrt() / 2.0 / n)
    }

    /// Whether the face crosses its dual: t = 0 is strictly inside (lo, hi).
    fn crosses(&self) -> bool {
        let zero = Q::from(0);
        self.lo.as_ref().is_none_or(|l| l < &zero) && self.hi.as_ref().is_none_or(|h| h > &zero)
    }

    /// Two values of t strictly inside (lo, hi): on both sides of the face
    /// when the face crosses its dual (halfway to the ends), else at its
    /// thirds; a step of `scale` stands in for a missing end.
    fn two(&self, scale: &Q) -> [Q; 2] {
        let (lo, hi) = (self.lo.clone(), self.hi.clone());
        if self.crosses() {
            // (a step stands unrounded: `scale`)
            let below = lo.map_or(-scale.clone(), |l| self.snap(l / Q::from(2)));
            let above = hi.map_or(scale.clone(), |h| self.snap(h / Q::from(2)));
            return [below, above];
        }
        let pick = {
            let (l, h) = match (lo, hi) {
                (Some(l), Some(h)) => (l, h),
                (Some(l), None) => (l.clone(), l + Q::from(3) * scale),
                (None, Some(h)) => (h.clone() - Q::from(3) * scale, h),
                (None, None) => unreachable!("crosses"),
            };
            let third = (&h - &l) / Q::from(3);
            [&l + &third, &h - &third]
        };
        pick.map(|t| self.snap(t))
    }

    /// One value of t inside (lo, hi): the middle, or a step beyond the
    /// one end.
    fn one(&self, scale: &Q) -> Q {
        let t = match (&self.lo, &self.hi) {
            (Some(l), Some(h)) => (l + h) / Q::from(2),
            (Some(l), None) => l + scale,
            (None, Some(h)) => h - scale,
            (None, None) => Q::from(0),
        };
        self.snap(t)
    }

    /// The nearest double to t when it is still strictly inside (short
    /// rationals keep the exact site diagram cheap), else t.
    fn snap(&self, t: Q) -> Q {
        let d = q(f(&t));
        let inside =
            self.lo.as_ref().is_none_or(|l| &d > l) && self.hi.as_ref().is_none_or(|h| &d < h);
        if inside {
            d
        } else {
            t
        }
    }
}

/// Places the sites (see the module's doc).
pub fn place(cx: &Complex3, wt: &Weights3) -> Result<Sites3> {
    let w = &wt.w;
    let (tris, links) = (&wt.adjacency.tris, &wt.adjacency.links);
    let mut s = Sites3 {
        of_face: vec![None; wt.faces.len()],
        ..Default::default()
    };
    // The RT triangles inside whole polygons share the polygon's dual.
    let mut in_polygon: HashMap<[u32; 3], u32> = HashMap::new();
    for (fi, face) in wt
        .faces
        .iter()
        .enumerate()
        .filter(|(_, f)| f.vertices.len() > 3)
    {
        for t in fan(&face.vertices, &tris) {
            in_polygon.insert(t, fi as u32);
        }
    }
    let add = |s: &mut Sites3, dual: &Dual, t: &Q, serves: &[u32]| -> u32 {
        let mut sv = serves.to_vec();
        sv.sort_unstable();
        s.p.push(along(&dual.c, t, &dual.n));
        s.w.push(Q::from(0));
        s.serves.push(sv);
        let x = s.p.len() - 1;
        s.reweigh(x, cx, w);
        s.line.push(dual.crosses().then(|| Line {
            c: dual.c.clone(),
            n: dual.n.clone(),
            t: t.clone(),
        }));
        s.track.push(None);
        x as u32
    };
    let faces: Vec<_> = wt
        .faces
        .iter()
        .enumerate()
        .filter(|(_, f)| f.dim() == 2)
        .collect();
    let duals = face_duals(cx, wt, &tris, &faces)?;
    for ((fi, face), (dual, [a, b])) in faces.into_iter().zip(duals) {
        let vs = &face.vertices;
        s.of_face[fi] = Some([add(&mut s, &dual, &a, vs), add(&mut s, &dual, &b, vs)]);
    }
    // Extra sites, at most one per RT triangle (shared by its vertices).
    let mut extra: BTreeMap<[u32; 3], Option<u32>> = BTreeMap::new();
    let mut extra_site = |s: &mut Sites3, t: [u32; 3]| -> Option<u32> {
        if in_polygon.contains_key(&t) {
            return None;
        }
        *extra.entry(t).or_insert_with(|| {
            let dual = Dual::of(cx, w, (&t, &face_centre(cx, w, &t)?), &tris[&t])?;
            let scale = dual.scale(cx, &t);
            let tt = dual.one(&scale);
            let x = add(s, &dual, &tt, &t);
            // It moves anywhere on its dual edge, not towards a face.
            s.line[x as usize] = None;
            let ends = (&dual.lo, &dual.hi);
            let track = Track::new((&dual.c, &dual.n), ends, &scale, &tt);
            s.track[x as usize] = Some(Box::new(Roam::Edge(track)));
            Some(x)
        })
    };
    // Constraint edges: those of triangles and polygons, and segments.
    let mut edges: Vec<[u32; 2]> = vec![];
    for face in wt.faces.iter().filter(|f| f.dim() > 0) {
        let vs = &face.vertices;
        let m = vs.len();
        for k in 0..if m == 2 { 1 } else { m } {
            let (a, b) = (vs[k], vs[(k + 1) % m]);
            edges.push([a.min(b), a.max(b)]);
        }
    }
    edges.sort_unstable();
    edges.dedup();
    let mut index = by_vertex(&s);
    // Most edges and vertices have enough sites from their faces: checked
    // in parallel first (more sites only keep a span).
    let spanned: Vec<bool> = edges.par_iter().map(|e| enough(&s, &index, e, 2)).collect();
    let edges: Vec<[u32; 2]> = edges
        .into_iter()
        .zip(spanned)
        .filter_map(|(e, ok)| (!ok).then_some(e))
        .collect();
    for e in &edges {
        let have = |s: &Sites3, index: &HashMap<u32, Vec<u32>>| -> Vec<u32> {
            index
                .get(&e[0])
                .into_iter()
                .flatten()
                .copied()
                .filter(|&x| s.serves[x as usize].contains(&e[1]))
                .collect()
        };
        let link = links.get(e).cloned().unwrap_or_default();
        let mut candidates = link.iter().map(|&m| sorted3(&[e[0], e[1], m]));
        while !spans(&s, &have(&s, &index), 2) {
            let Some(t) = candidates.next() else {
                return Err(short(cx, "edge", e));
            };
            if let Some(x) = extra_site(&mut s, t) {
                register(&mut index, t, x);
            }
        }
    }
    let mut vertices: Vec<u32> = wt
        .faces
        .iter()
        .flat_map(|f| f.vertices.iter().copied())
        .collect();
    vertices.sort_unstable();
    vertices.dedup();
    let spanned: Vec<bool> = vertices
        .par_iter()
        .map(|&v| enough(&s, &index, &[v], 3))
        .collect();
    // the candidates ordered by the sites placed so far, when first needed
    let served = served(&s);
    let (mut around, mut cells) = (None, None);
    for (v, _) in vertices.into_iter().zip(spanned).filter(|(_, ok)| !ok) {
        // sites of its own first: they move anywhere in its cell (the loop
        // below checks their span: rounding may collapse them)
        let n = cx.points.len();
        let cells = cells.get_or_insert_with(|| (wt.rt.neighbours(n), wt.rt.bounded_stars(n)));
        let have = index.get(&v).cloned().unwrap_or_default();
        if let Some(added) = s.own_sites(cx, wt, v, &have, cells) {
            index.entry(v).or_default().extend(added);
        }
        let around = around.get_or_insert_with(|| candidates(&tris, &served));
        let mut candidates = around.get(&v).cloned().unwrap_or_default().into_iter();
        loop {
            let have = index.get(&v).cloned().unwrap_or_default();
            if spans(&s, &have, 3) {
                break;
            }
            let Some(t) = candidates.next() else {
                return Err(short(cx, "vertex", &[v]));
            };
            if let Some(x) = extra_site(&mut s, t) {
                register(&mut index, t, x);
            }
        }
    }
    Ok(s)
}

/// Each face's dual with the two sites' parameters on it, in parallel
/// (exact and independent, most of the sites stage on a large input; the
/// sites are then added in face order).
fn face_duals(
    cx: &Complex3,
    wt: &Weights3,
    tris: &FastMap<[u32; 3], Vec<u32>>,
    faces: &[(usize, &crate::weights::Face)],
) -> Result<Vec<(Dual, [Q; 2])>> {
    faces
        .par_iter()
        .map(|&(fi, face)| {
            let (w, vs) = (&wt.w[..], &face.vertices);
            let apexes: Vec<u32> = if vs.len() == 3 {
                tris.get(&sorted3(vs)).cloned().unwrap_or_default()
            } else {
                fan(vs, tris)
                    .iter()
                    .flat_map(|t| tris[t].iter().copied())
                    .filter(|a| !vs.contains(a))
                    .collect()
            };
            let centre = wt.centres.of(cx, w, &wt.faces, fi);
            let dual = centre
                .and_then(|c| Dual::of(cx, w, (vs, c), &apexes))
                .ok_or_else(|| {
                    Error::Certificate(format!(
                        "the dual edge of a face of facet {} is empty",
                        face.facet.map_or(0, |f| f as i64 + 1)
                    ))
                })?;
            let two = dual.two(&dual.scale(cx, vs));
            Ok((dual, two))
        })
        .collect()
}

/// Per vertex, the RT triangles around it that may carry its extra sites,
/// those with more vertices that no site serves yet first (one extra site
/// then serves several that need it), in a fixed order: `tris` is a hash
/// map, whose order changes from run to run (it chose different extra
/// sites each run).
fn candidates(tris: &FastMap<[u32; 3], Vec<u32>>, served: &[bool]) -> HashMap<u32, Vec<[u32; 3]>> {
    let mut around: HashMap<u32, Vec<[u32; 3]>> = HashMap::new();
    for t in tris.keys() {
        for &v in t {
            around.entry(v).or_default().push(*t);
        }
    }
    let served = |v: &u32| served.get(*v as usize).copied().unwrap_or(false);
    for list in around.values_mut() {
        list.sort_by_cached_key(|t| (t.iter().filter(|v| served(v)).count(), *t));
    }
    around
}

/// Whether the sites serving all of `vs` span dimension r (`spans`).
fn enough(s: &Sites3, index: &HashMap<u32, Vec<u32>>, vs: &[u32], r: usize) -> bool {
    let have: Vec<u32> = index
        .get(&vs[0])
        .into_iter()
        .flatten()
        .copied()
        .filter(|&x| vs[1..].iter().all(|v| s.serves[x as usize].contains(v)))
        .collect();
    spans(s, &have, r)
}

/// Per input vertex, whether some site serves it.
fn served(s: &Sites3) -> Vec<bool> {
    let mut out = vec![];
    for &v in s.serves.iter().flatten() {
        if out.len() <= v as usize {
            out.resize(v as usize + 1, false);
        }
        out[v as usize] = true;
    }
    out
}

fn short(cx: &Complex3, what: &str, vs: &[u32]) -> Error {
    let ids: Vec<i64> = vs.iter().map(|&v| cx.vertex_ids[v as usize]).collect();
    Error::Certificate(format!(
        "the power cells around {what} {ids:?} have too few places for sites (Theorem 1)"
    ))
}

/// Adds site x to the sites serving each vertex of t.
fn register(index: &mut HashMap<u32, Vec<u32>>, t: [u32; 3], x: u32) {
    for v in t {
        let list = index.entry(v).or_default();
        if !list.contains(&x) {
            list.push(x);
        }
    }
}

/// Per input vertex, the sites serving it.
fn by_vertex(s: &Sites3) -> HashMap<u32, Vec<u32>> {
    let mut out: HashMap<u32, Vec<u32>> = HashMap::new();
    for (x, sv) in s.serves.iter().enumerate() {
        for &v in sv {
            out.entry(v).or_default().push(x as u32);
        }
    }
    out
}

/// Whether these sites' affine hull has dimension at least r (2 or 3),
/// exactly: r + 1 of them chosen in doubles (each farthest from the span
/// of those before) and their cross product or volume proved nonzero in
/// intervals, else the rank in rationals.
pub(super) fn spans(s: &Sites3, ids: &[u32], r: usize) -> bool {
    if ids.len() <= r {
        return false;
    }
    let m: Vec<[f64; 3]> = ids
        .iter()
        .map(|&x| s.p[x as usize].each_ref().map(f))
        .collect();
    let d: Vec<[f64; 3]> = m
        .iter()
        .map(|a| [0, 1, 2].map(|k| a[k] - m[0][k]))
        .collect();
    let widest = |size: &dyn Fn(usize) -> f64| {
        (1..ids.len())
            .max_by(|&a, &b| size(a).total_cmp(&size(b)))
            .expect("more than r sites")
    };
    let b = widest(&|x| dot_f(d[x], d[x]));
    let c = widest(&|x| {
        let n = cross_f(d[b], d[x]);
        dot_f(n, n)
    });
    let e = widest(&|x| det3_f(d[b], d[c], d[x]).abs());
    let [b, c, e] = [b, c, e].map(|i| ids[i]);
    let iv = |x: u32| {
        let (p, o) = (&s.p[x as usize], &s.p[ids[0] as usize]);
        [0, 1, 2].map(|k| Iv::of_q(&p[k]) - Iv::of_q(&o[k]))
    };
    let (vb, vc) = (iv(b), iv(c));
    let proved = if r == 2 {
        (0..3).any(|k| {
            let (i, j) = ((k + 1) % 3, (k + 2) % 3);
            (vb[i] * vc[j] - vb[j] * vc[i])
                .sign()
                .is_some_and(|o| o != Ordering::Equal)
        })
    } else {
        det3([vb, vc, iv(e)])
            .sign()
            .is_some_and(|o| o != Ordering::Equal)
    };
    proved || affine_rank(s, ids) >= r as i32
}

/// The dimension of the affine hull of these sites (-1 for none), exactly.
fn affine_rank(s: &Sites3, ids: &[u32]) -> i32 {
    let Some((&first, rest)) = ids.split_first() else {
        return -1;
    };
    let mut rows: Vec<[Q; 3]> = rest
        .iter()
        .map(|&x| sub(&s.p[x as usize], &s.p[first as usize]))
        .collect();
    let mut rank = 0;
    for col in 0..3 {
        let Some(piv) = (rank..rows.len()).find(|&r| rows[r][col] != 0) else {
            continue;
        };
        rows.swap(rank, piv);
        for r in rank + 1..rows.len() {
            if rows[r][col] != 0 {
                let factor = &rows[r][col] / &rows[rank][col];
                let pivot = rows[rank].clone();
                for k in col..3 {
                    rows[r][k] -= &factor * &pivot[k];
                }
            }
        }
        rank += 1;
    }
    rank as i32
}

impl Sites3 {
    /// Whether site x is a mirror image (`clipped`).
    pub fn is_mirror(&self, x: usize) -> bool {
        self.mirror_of.get(x).is_some_and(|m| m.is_some())
    }

    /// The sites of a diagram cut at `clips` (mirrors clip exactly: where
    /// every site lies on one side of a plane, a site's mirror image with
    /// the same weight has a greater power than the site itself at every
    /// point on that side, so it changes nothing there, and the mirrors of
    /// all sites own everything beyond). The sites of the clip facets'
    /// faces are dropped (those faces need not be single cell faces); a
    /// site beyond a plane moves towards its face (in the domain's
    /// closure) until it is strictly on the domain's side, and one that
    /// cannot is dropped (its face then fails the certificate).
    pub fn clipped(&self, cx: &Complex3, wt: &Weights3, clips: Vec<Clip>) -> Sites3 {
        let mut this = self.clone();
        for x in 0..this.p.len() {
            for _ in 0..64 {
                if clips.iter().all(|c| c.below(&this.p[x])) || !this.halve(x, cx, &wt.w) {
                    break;
                }
            }
        }
        let mut keep = vec![true; this.p.len()];
        for (fi, face) in wt.faces.iter().enumerate() {
            if clip_of(&clips, face.facet).is_some() {
                for x in this.of_face[fi].into_iter().flatten() {
                    keep[x as usize] = false;
                }
            }
        }
        for (x, k) in keep.iter_mut().enumerate() {
            *k &= clips.iter().all(|c| c.below(&this.p[x]));
        }
        let mut id = vec![u32::MAX; this.p.len()];
        let mut out = Sites3::default();
        for x in (0..this.p.len()).filter(|&x| keep[x]) {
            id[x] = out.p.len() as u32;
            out.p.push(this.p[x].clone());
            out.w.push(this.w[x].clone());
            out.serves.push(this.serves[x].clone());
            out.line.push(this.line[x].clone());
            out.mirror_of.push(None);
        }
        // (a site of one vertex names the others serving it: renumbered)
        out.track = (0..this.p.len())
            .filter(|&x| keep[x])
            .map(|x| this.track[x].as_ref().map(|r| Box::new(r.renumbered(&id))))
            .collect();
        out.of_face = self
            .of_face
            .iter()
            .map(|f| {
                let [a, b] = f.map(|p| p.map(|x| id[x as usize]))?;
                (a != u32::MAX && b != u32::MAX).then_some([a, b])
            })
            .collect();
        let n = out.p.len() as u32;
        for c in 0..clips.len() as u32 {
            for x in 0..n {
                out.p.push(std::array::from_fn(|_| Q::from(0)));
                out.w.push(Q::from(0));
                out.serves.push(vec![]);
                out.line.push(None);
                out.track.push(None);
                out.mirror_of.push(Some((x, c)));
            }
        }
        out.clips = clips;
        out.remirror();
        out
    }

    /// Whether the sites that are not mirrors span a volume (clipping at
    /// every facet may leave them on a plane, or none).
    pub fn span_volume(&self) -> bool {
        let own: Vec<&[Q; 3]> = (0..self.p.len())
            .filter(|&x| self.mirror_of[x].is_none())
            .map(|x| &self.p[x])
            .collect();
        let Some(&a) = own.first() else {
            return false;
        };
        let zero = Q::from(0);
        let Some(&b) = own.iter().find(|b| **b != a) else {
            return false;
        };
        let Some(n) = own
            .iter()
            .map(|c| cross(&sub(b, a), &sub(c, a)))
            .find(|n| n.iter().any(|x| *x != zero))
        else {
            return false;
        };
        own.iter().any(|d| dot(&sub(d, a), &n) != zero)
    }

    /// Puts the mirrors where their sites are now (after relocation).
    pub fn remirror(&mut self) {
        for m in 0..self.mirror_of.len() {
            if let Some((x, c)) = self.mirror_of[m] {
                self.p[m] = self.clips[c as usize].mirror(&self.p[x as usize]);
                self.w[m] = self.w[x as usize].clone();
            }
        }
    }

    /// Gives site x the power w_v at the vertices v it serves.
    pub(super) fn reweigh(&mut self, x: usize, cx: &Complex3, w: &[Q]) {
        let v0 = self.serves[x][0] as usize;
        self.w[x] = norm2(&sub(&self.p[x], &cx.points[v0].map(q))) - &w[v0];
    }

    /// Moves a site on a line halfway to its face (rounded to a double
    /// parameter when that stays strictly between); false when it has no
    /// line.
    pub fn halve(&mut self, x: usize, cx: &Complex3, w: &[Q]) -> bool {
        let Some(line) = &self.line[x] else {
            return false;
        };
        let half = f(&line.t) / 2.0;
        self.move_to(x, cx, w, half)
    }

    /// Moves a site on a line towards its face, past the neighbours that
    /// beat it: along the line c + t n its power difference with a
    /// neighbour y, g(t) = |p(t) - p_y|^2 - w_y + w(t), is the quadratic
    /// 2 |n|^2 t^2 + 2 n.(c - p_y) t + pi_y(c) + P (P the face centre's
    /// power, n.(c - p_v) = 0), positive at t = 0 when pi_y(c) + P > 0: the
    /// site goes to half the root nearest the face over the neighbours
    /// negative at the present t (doubles; the diagram decides exactly), or
    /// halfway when none has such a root. False, and the site stays, when it
    /// has no line or a neighbour beats it even on the face.
    pub fn jump(&mut self, x: usize, cx: &Complex3, w: &[Q], neighbours: &[u32]) -> bool {
        let Some(line) = &self.line[x] else {
            return false;
        };
        let (c, n, t) = (
            line.c.each_ref().map(f),
            line.n.each_ref().map(f),
            f(&line.t),
        );
        let v0 = self.serves[x][0] as usize;
        let power_c = (0..3)
            .map(|k| (c[k] - cx.points[v0][k]).powi(2))
            .sum::<f64>()
            - f(&w[v0]);
        let a = 2.0 * (0..3).map(|k| n[k] * n[k]).sum::<f64>();
        let mut target = t / 2.0;
        for &y in neighbours {
            let py = self.p[y as usize].each_ref().map(f);
            let wy = f(&self.w[y as usize]);
            let d: [f64; 3] = std::array::from_fn(|k| c[k] - py[k]);
            let b = 2.0 * (0..3).map(|k| n[k] * d[k]).sum::<f64>();
            let k0 = (0..3).map(|k| d[k] * d[k]).sum::<f64>() - wy + power_c;
            let g = |s: f64| a * s * s + b * s + k0;
            let disc = b * b - 4.0 * a * k0;
            if g(t) > 0.0 {
                continue;
            }
            let size = (0..3).map(|k| d[k] * d[k]).sum::<f64>() + wy.abs() + power_c.abs();
            if k0 < -1e-9 * size {
                // g is convex and negative at 0 and t: no place on the
                // line beats y (until y moves)
                return false;
            }
            if disc < 0.0 {
                continue;
            }
            // the root between 0 and t (g > 0 at 0, <= 0 at t)
            let r = [
                (-b - disc.sqrt()) / (2.0 * a),
                (-b + disc.sqrt()) / (2.0 * a),
            ]
            .into_iter()
            .filter(|r| r * t > 0.0 && r.abs() < t.abs() && r.abs() > 1e-9 * t.abs())
            .fold(t, |m, r| if r.abs() < m.abs() { r } else { m });
            if (r / 2.0).abs() < target.abs() {
                target = r / 2.0;
            }
        }
        self.move_to(x, cx, w, target)
    }

    /// Moves the sites on lines that another site beats at their own
    /// place (in doubles), as the first relocation round would, but
    /// without a site diagram. Site y can beat site x only if |x - y|^2 <=
    /// w_y - w_x, so x's candidates are the sites whose ball of radius
    /// sqrt(w_y - min w) holds it (`Reach`). The diagram still decides
    /// inside or outside exactly; this only spares it rounds. Stops after
    /// `rounds` rounds, or when the balls would fill more than 64 grid
    /// cells a site (weights of very different sizes). Returns how many
    /// moves it made.
    pub fn settle(&mut self, cx: &Complex3, w: &[Q], rounds: usize) -> usize {
        let mut moves = 0;
        for _ in 0..rounds {
            let a = self.approx();
            let Some(reach) = Reach::new(&a, 64 * a.len()) else {
                break;
            };
            let beaten: Vec<(usize, Vec<u32>)> = (0..a.len())
                .into_par_iter()
                .filter(|&x| self.line[x].is_some())
                .filter_map(|x| {
                    let by: Vec<u32> = reach
                        .at(a[x])
                        .filter(|&y| {
                            let b = a[y as usize];
                            let d2: f64 = (0..3).map(|k| (a[x][k] - b[k]).powi(2)).sum();
                            y as usize != x && d2 - b[3] + a[x][3] <= 0.0
                        })
                        .collect();
                    (!by.is_empty()).then_some((x, by))
                })
                .collect();
            if beaten.is_empty() {
                break;
            }
            let before = moves;
            for (x, by) in beaten {
                moves += usize::from(self.jump(x, cx, w, &by));
            }
            self.remirror();
            if moves == before {
                break;
            }
        }
        moves
    }

    /// Moves a site on a line to parameter `to` when that double lies
    /// strictly between the face and the site, else exactly halfway.
    fn move_to(&mut self, x: usize, cx: &Complex3, w: &[Q], to: f64) -> bool {
        let Some(line) = &mut self.line[x] else {
            return false;
        };
        let zero = Q::from(0);
        let between = |v: &Q| {
            if line.t > zero {
                v > &zero && v < &line.t
            } else {
                v < &zero && v > &line.t
            }
        };
        let d = to.is_finite().then(|| q(to)).filter(|d| between(d));
        line.t = d.unwrap_or_else(|| &line.t / Q::from(2));
        self.p[x] = along(&line.c, &line.t, &line.n);
        self.reweigh(x, cx, w);
        true
    }

    /// Doubles nearest the sites and weights.
    pub fn approx(&self) -> Vec<[f64; 4]> {
        // (in parallel: rounding rationals is slow, and this runs per round)
        self.p
            .par_iter()
            .zip(&self.w)
            .map(|(p, w)| [f(&p[0]), f(&p[1]), f(&p[2]), f(w)])
            .collect()
    }
}

/// Weighted points' power balls (radius sqrt(w - min w)) bucketed in a
/// uniform grid: the points whose ball may hold a given point.
struct Reach {
    lo: [f64; 3],
    h: f64,
    cells: FastMap<[i64; 3], Vec<u32>>,
}

impl Reach {
    /// None when the balls would fill more than `budget` cells.
    fn new(a: &[[f64; 4]], budget: usize) -> Option<Reach> {
        let points: Vec<[f64; 3]> = a.iter().map(|x| [x[0], x[1], x[2]]).collect();
        let (lo, hi) = crate::geom::bbox(&points);
        let low = a.iter().map(|x| x[3]).fold(f64::INFINITY, f64::min);
        let radius: Vec<f64> = a
            .iter()
            .map(|x| (x[3] - low).sqrt() * (1.0 + 1e-9))
            .collect();
        let extent = (0..3).fold(0.0f64, |m, k| m.max(hi[k] - lo[k]));
        let mut sorted = radius.clone();
        sorted.sort_unstable_by(f64::total_cmp);
        let median = sorted.get(sorted.len() / 2).copied().unwrap_or(0.0);
        let h = (extent / (a.len() as f64).cbrt())
            .max(median)
            .max(f64::MIN_POSITIVE);
        let mut reach = Reach {
            lo,
            h,
            cells: FastMap::default(),
        };
        let mut filled = 0usize;
        for (y, (p, r)) in points.iter().zip(&radius).enumerate() {
            let (u, v) = (reach.key(p.map(|c| c - r)), reach.key(p.map(|c| c + r)));
            // (saturating: a huge ball among small ones is over budget, not
            // an overflow)
            let cells = (0..3).fold(1usize, |m, k| {
                m.saturating_mul(v[k].saturating_sub(u[k]).saturating_add(1) as usize)
            });
            filled = filled.saturating_add(cells);
            if !r.is_finite() || filled > budget {
                return None;
            }
            for i in u[0]..=v[0] {
                for j in u[1]..=v[1] {
                    for k in u[2]..=v[2] {
                        reach.cells.entry([i, j, k]).or_default().push(y as u32);
                    }
                }
            }
        }
        Some(reach)
    }

    fn key(&self, p: [f64; 3]) -> [i64; 3] {
        std::array::from_fn(|k| ((p[k] - self.lo[k]) / self.h).floor() as i64)
    }

    /// The points whose ball may hold p.
    fn at(&self, p: [f64; 4]) -> impl Iterator<Item = u32> + '_ {
        self.cells
            .get(&self.key([p[0], p[1], p[2]]))
            .into_iter()
            .flatten()
            .copied()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spans_agrees_with_the_exact_rank() {
        // points on a line, a plane (tilted: rounding makes them look off
        // it), and in space
        let third = Q::from(1) / Q::from(3);
        let on_line = |t: i64| [0, 1, 2].map(|k| Q::from(t * (k as i64 + 1)) * &third);
        let on_plane = |u: i64, v: i64| {
            let (u, v) = (Q::from(u) * &third, Q::from(v) / Q::from(7));
            [u.clone(), v.clone(), -(u + v)]
        };
        let line: Vec<[Q; 3]> = (0..5).map(on_line).collect();
        let plane: Vec<[Q; 3]> = (0..6).map(|i| on_plane(i % 3, i / 3 + i)).collect();
        let mut space = plane.clone();
        space.push([third.clone(), third.clone(), -Q::from(1) / Q::from(1000)]);
        for (p, rank) in [(line, 1), (plane, 2), (space, 3)] {
            let s = Sites3 {
                p,
                ..Default::default()
            };
            let ids: Vec<u32> = (0..s.p.len() as u32).collect();
            assert_eq!(affine_rank(&s, &ids), rank);
            for r in [2, 3] {
                assert_eq!(spans(&s, &ids, r), rank >= r as i32, "rank {rank}, r {r}");
            }
            assert!(!spans(&s, &ids[..2], 2));
        }
    }

    #[test]
    fn reach_offers_every_site_whose_ball_holds_the_point() {
        let mut r = crate::geom::uniform(7);
        let a: Vec<[f64; 4]> = (0..400)
            .map(|_| [r() * 10.0, r() * 10.0, r() * 3.0, r() * r() * 4.0])
            .collect();
        let reach = Reach::new(&a, 64 * a.len()).expect("within budget");
        let low = a.iter().map(|x| x[3]).fold(f64::INFINITY, f64::min);
        for x in &a {
            let offered: Vec<u32> = reach.at(*x).collect();
            for (y, b) in a.iter().enumerate() {
                let d2: f64 = (0..3).map(|k| (x[k] - b[k]).powi(2)).sum();
                if d2 <= b[3] - low {
                    assert!(offered.contains(&(y as u32)), "{x:?} misses {b:?}");
                }
            }
        }
        // one huge ball over many small ones: over budget
        let mut big = a.clone();
        big[0][3] = 1e6;
        assert!(Reach::new(&big, 64 * big.len()).is_none());
        // (cells beyond what a usize counts)
        big[0][3] = 1e300;
        assert!(Reach::new(&big, 64 * big.len()).is_none());
    }
}
