//! The power diagram of the sites, read off a regular triangulation of the
//! sites that is checked exactly: every triangle counter-clockwise, the hull
//! convex, every edge locally regular (docs/method.md section 7). Such a
//! triangulation is the regular triangulation of the exact sites, whatever
//! arithmetic built it. Triangles whose power centres coincide exactly (edges
//! with a zero power test) share one power vertex; a vertex is an input
//! vertex exactly when three sites serving that vertex meet there.

use crate::backend::Triangulation;
use crate::domain::Domain;
use crate::sites::Sites;
use rayon::prelude::*;
use std::cmp::Ordering;

/// Power diagram of the sites.
#[derive(Debug, Clone)]
pub struct Diagram {
    /// Power vertices: input vertices exactly, the others rounded.
    pub points: Vec<[f64; 2]>,
    /// The input vertex a power vertex is, if any (decided exactly).
    pub input_vertex: Vec<Option<u32>>,
    /// Per site: its cell as ccw vertex ids (distinct consecutive), or None
    /// when the cell is unbounded or the site hidden.
    pub cells: Vec<Option<Vec<u32>>>,
    /// Per site: whether its cell lies in the domain.
    pub in_domain: Vec<bool>,
    /// Per triangle of the site triangulation: its power vertex.
    pub vertex_of: Vec<u32>,
    /// Components of cells (connected without crossing a segment) whose
    /// segments disagree about which side is the domain.
    pub leaking_components: usize,
    /// Edges of the triangulation whose regularity was checked.
    pub checked_edges: usize,
    /// Per power vertex: a bound on the error of its rounded position (0
    /// when exact), and one triangle of its class (`exact_corners`).
    error: Vec<f64>,
    first: Vec<u32>,
}

/// Interior edges once: (left triangle, right triangle, apex of the right
/// one), and the power test of each (the apex against the left triangle).
pub struct EdgeTests {
    inner: Vec<(u32, u32, u32)>,
    tests: Vec<Ordering>,
}

/// Interior edges once, in triangle order: (left, right, apex of right).
fn interior_edges(rt: &Triangulation) -> Vec<(u32, u32, u32)> {
    let tris = &rt.triangles;
    // (rayon's collect keeps the sequential order)
    (0..tris.len() as u32)
        .into_par_iter()
        .flat_map_iter(|t1| {
            (0..3).filter_map(move |k| {
                let tri = tris[t1 as usize];
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                let t2 = rt.across(t1, k).filter(|_| a < b)?;
                Some((t1, t2, rt.apex(t2, b, a)))
            })
        })
        .collect()
}

/// The power test of interior edge (t1, _, d).
fn power_test(sites: &Sites, rt: &Triangulation, (t1, _, d): (u32, u32, u32)) -> Ordering {
    let [a, b, c] = rt.triangles[t1 as usize].map(|v| v as usize);
    sites.power_test(a, b, c, d as usize)
}

fn power_tests(sites: &Sites, rt: &Triangulation) -> EdgeTests {
    let inner = interior_edges(rt);
    let tests = inner
        .par_iter()
        .map(|&e| power_test(sites, rt, e))
        .collect();
    EdgeTests { inner, tests }
}

/// The power tests of `rt` after flips (and splits) changed some of the
/// triangles `before` had: edges beside a changed triangle are tested
/// afresh, the others keep `old`'s test (an unchanged triangle keeps its
/// interior edges in the same order).
fn retest(sites: &Sites, rt: &Triangulation, before: &[[u32; 3]], old: EdgeTests) -> EdgeTests {
    let changed = |t: u32| before.get(t as usize) != Some(&rt.triangles[t as usize]);
    let mut first = vec![0usize; before.len() + 1];
    for &(t1, _, _) in &old.inner {
        first[t1 as usize + 1] += 1;
    }
    for t in 0..before.len() {
        first[t + 1] += first[t];
    }
    let inner = interior_edges(rt);
    let (mut tests, mut rank, mut last) = (Vec::with_capacity(inner.len()), 0, u32::MAX);
    for &e in &inner {
        (rank, last) = if e.0 == last {
            (rank + 1, last)
        } else {
            (0, e.0)
        };
        tests.push(if changed(e.0) || changed(e.1) {
            power_test(sites, rt, e)
        } else {
            old.tests[first[e.0 as usize] + rank]
        });
    }
    EdgeTests { inner, tests }
}

fn find(parent: &mut [u32], mut x: u32) -> u32 {
    while parent[x as usize] != x {
        parent[x as usize] = parent[parent[x as usize] as usize];
        x = parent[x as usize];
    }
    x
}

impl Diagram {
    /// Whether a triangulation built from rounded sites is the regular
    /// triangulation of the exact sites: no site hidden, every triangle
    /// counter-clockwise, the hull convex and winding once, every interior
    /// edge locally regular (exact). Ok gives its interior edges and their
    /// power tests (for `build`); Err says what fails.
    pub fn check(sites: &Sites, rt: &Triangulation) -> std::result::Result<EdgeTests, String> {
        if !rt.hidden.is_empty() {
            return Err(format!("{} sites hidden", rt.hidden.len()));
        }
        check_shape(sites, rt)?;
        let checked = power_tests(sites, rt);
        if let Some(k) = checked.tests.iter().position(|&o| o == Ordering::Greater) {
            let (t1, _, d) = checked.inner[k];
            return Err(format!(
                "edge of {:?} is not regular (site {d})",
                rt.triangles[t1 as usize]
            ));
        }
        Ok(checked)
    }

    /// `check`, and where only edges fail (or a few sites are hidden by
    /// rounding), `repair` from those edges, re-testing only the edges
    /// beside triangles the repair changed: the triangulation is then the
    /// regular one of the exact sites (flips keep every triangle
    /// counter-clockwise and the hull, and Lawson's flips end with every
    /// edge locally regular). None when it cannot be made so.
    pub fn check_or_repair(sites: &Sites, rt: &mut Triangulation) -> Option<EdgeTests> {
        if rt.hidden.len() > MAX_REINSERTED {
            return None;
        }
        check_shape(sites, rt).ok()?;
        let tests = power_tests(sites, rt);
        let bad: Vec<(u32, u32)> = tests
            .inner
            .iter()
            .zip(&tests.tests)
            .filter(|(_, &o)| o == Ordering::Greater)
            .map(|(&(t1, t2, _), _)| {
                let tri = rt.triangles[t1 as usize];
                let k = (0..3)
                    .find(|&k| rt.across(t1, k) == Some(t2))
                    .expect("adjacent");
                (tri[k], tri[(k + 1) % 3])
            })
            .collect();
        if bad.is_empty() && rt.hidden.is_empty() {
            return Some(tests);
        }
        let before = rt.triangles.clone();
        if !repair_from(sites, rt, bad) {
            return None;
        }
        let tests = retest(sites, rt, &before, tests);
        tests
            .tests
            .iter()
            .all(|&o| o != Ordering::Greater)
            .then_some(tests)
    }

    /// Builds the diagram of a triangulation known regular: one that passed
    /// `check` (its power tests given), or an exact backend's (None: the
    /// tests are made here; it may hide sites). Err when the triangulation
    /// makes one power vertex two input vertices.
    pub fn build(
        dom: &Domain,
        sites: &Sites,
        rt: &Triangulation,
        checked: Option<EdgeTests>,
    ) -> std::result::Result<Diagram, String> {
        let n = sites.len();
        let tris = &rt.triangles;
        let EdgeTests { inner, tests } = checked.unwrap_or_else(|| power_tests(sites, rt));
        // Power vertices: classes of triangles joined by zero-length duals.
        let mut parent: Vec<u32> = (0..tris.len() as u32).collect();
        for (&(t1, t2, _), &o) in inner.iter().zip(&tests) {
            if o == Ordering::Equal {
                let (r1, r2) = (find(&mut parent, t1), find(&mut parent, t2));
                parent[r1.max(r2) as usize] = r1.min(r2);
            }
        }
        let mut class = vec![u32::MAX; tris.len()];
        let mut first: Vec<u32> = vec![]; // a triangle of each class
        for t in 0..tris.len() {
            let r = find(&mut parent, t as u32) as usize;
            if class[r] == u32::MAX {
                class[r] = first.len() as u32;
                first.push(r as u32);
            }
            class[t] = class[r];
        }
        let (mut points, mut error): (Vec<[f64; 2]>, Vec<f64>) = first
            .par_iter()
            .map(|&t| sites.centre_estimate(tris[t as usize]))
            .unzip();
        let cx = &dom.complex;
        let input_vertex = input_vertices(sites, tris, &class, points.len()).map_err(|[u, v]| {
            format!(
                "one power vertex is two input vertices ({} and {})",
                cx.vertex_ids[u as usize], cx.vertex_ids[v as usize]
            )
        })?;
        for (id, v) in input_vertex.iter().enumerate() {
            if let Some(v) = v {
                points[id] = cx.points[*v as usize];
                error[id] = 0.0;
            }
        }
        // One triangle at each site, then the ring of triangles around it.
        let mut corner = vec![u32::MAX; n];
        for (t, tri) in tris.iter().enumerate() {
            for &v in tri {
                corner[v as usize] = t as u32;
            }
        }
        let cells: Vec<Option<Vec<u32>>> = (0..n)
            .into_par_iter()
            .map(|v| {
                let start = Some(corner[v]).filter(|&t| t != u32::MAX)?;
                let mut ring = Vec::with_capacity(8);
                let mut t = start;
                loop {
                    ring.push(class[t as usize]);
                    let tri = tris[t as usize];
                    let k = tri.iter().position(|&x| x as usize == v).unwrap();
                    t = rt.across(t, (k + 2) % 3)?; // None: unbounded cell
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
        let mut d = Diagram {
            points,
            input_vertex,
            cells,
            in_domain: vec![],
            vertex_of: class,
            leaking_components: 0,
            checked_edges: inner.len(),
            error,
            first,
        };
        d.classify(dom, sites, rt);
        Ok(d)
    }

    /// Corners whose error may be a noticeable part of an edge of theirs
    /// (thin cells, far sites with large weights) are made again in interval
    /// arithmetic, which bounds their error rigorously (and mostly far below
    /// the estimate); those still in doubt are made exactly (then rounded).
    /// Only the mesh needs them: relocation reads the diagram's topology, so
    /// this waits for the final diagram.
    pub fn exact_corners(&mut self, sites: &Sites, rt: &Triangulation) {
        let redo = self.doubtful_corners();
        let tighter: Vec<(usize, [f64; 2], f64)> = redo
            .par_iter()
            .filter_map(|&i| {
                let c = sites.centre_interval(rt.triangles[self.first[i] as usize]);
                let radius = c.iter().map(|x| (x.hi - x.lo) / 2.0).fold(0.0, f64::max);
                // The midpoint is within the width of either end.
                let err = 2.0 * radius;
                (err < self.error[i]).then(|| (i, [c[0].mid(), c[1].mid()], err))
            })
            .collect();
        for (i, p, e) in tighter {
            self.points[i] = p;
            self.error[i] = e;
        }
        let exact: Vec<(usize, [f64; 2])> = self
            .doubtful_corners()
            .into_par_iter()
            .map(|i| (i, sites.centre_exact(rt.triangles[self.first[i] as usize])))
            .collect();
        for (i, p) in exact {
            self.points[i] = p;
            self.error[i] = 0.0;
        }
    }

    /// Corners of an edge whose ends' errors add up to more than 1e-6 of
    /// its length (corners without error excepted).
    fn doubtful_corners(&self) -> Vec<usize> {
        let (points, error) = (&self.points, &self.error);
        let flagged: Vec<u32> = self
            .cells
            .par_iter()
            .flatten()
            .flat_map_iter(|ring| {
                (0..ring.len()).flat_map(move |k| {
                    let (p, q) = (ring[k], ring[(k + 1) % ring.len()]);
                    let (ep, eq) = (error[p as usize], error[q as usize]);
                    let (a, b) = (points[p as usize], points[q as usize]);
                    let doubt = ep + eq > 0.0 && ep + eq > 1e-6 * length(a, b);
                    [(p, ep), (q, eq)]
                        .into_iter()
                        .filter(move |&(_, e)| doubt && e > 0.0)
                        .map(|(v, _)| v)
                })
            })
            .collect();
        let mut redo = vec![false; points.len()];
        for v in flagged {
            redo[v as usize] = true;
        }
        (0..points.len()).filter(|&i| redo[i]).collect()
    }

    /// Cells reachable from each other without crossing a segment form
    /// components. The cell of a segment's left site lies left of it (the
    /// side where its power is below the right site's), so each segment says
    /// whether the components beside it are in the domain; unbounded
    /// components are not.
    fn classify(&mut self, dom: &Domain, sites: &Sites, rt: &Triangulation) {
        let class = &self.vertex_of;
        let n = sites.len();
        let cx = &dom.complex;
        let pairs = sites.segment_pairs(cx.segments.len());
        // a corner's site has two partners, one per segment
        let mut partner = vec![[u32::MAX; 2]; n];
        let mut pair = |a: u32, b: u32| {
            let slots = &mut partner[a as usize];
            slots[usize::from(slots[0] != u32::MAX)] = b;
        };
        let mut label: Vec<Option<bool>> = vec![None; n];
        for (&[l, r], &[in_l, in_r]) in pairs.iter().zip(&dom.sides) {
            pair(l, r);
            pair(r, l);
            label[l as usize] = Some(in_l);
            label[r as usize] = Some(in_r);
        }
        // Cells are neighbours across dual edges of positive length only: at a
        // vertex where four cells meet, the diagonal's dual is a point.
        let mut parent: Vec<u32> = (0..n as u32).collect();
        for (t, tri) in rt.triangles.iter().enumerate() {
            for k in 0..3 {
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                let other = rt.across(t as u32, k);
                if other.is_some_and(|o| class[o as usize] == class[t])
                    || partner[a as usize].contains(&b)
                {
                    continue;
                }
                let (ra, rb) = (find(&mut parent, a), find(&mut parent, b));
                parent[ra.max(rb) as usize] = ra.min(rb);
            }
        }
        // Per component: [says inside, says outside, unbounded].
        let mut seen = vec![[false; 3]; n];
        let cells = &self.cells;
        let root: Vec<usize> = (0..n as u32)
            .map(|v| find(&mut parent, v) as usize)
            .collect();
        for v in 0..n {
            let r = &mut seen[root[v]];
            match label[v] {
                Some(true) => r[0] = true,
                Some(false) => r[1] = true,
                None => {}
            }
            r[2] |= cells[v].is_none();
        }
        self.leaking_components = (0..n)
            .filter(|&v| root[v] == v && seen[v][0] && (seen[v][1] || seen[v][2]))
            .count();
        self.in_domain = (0..n)
            .map(|v| {
                let [inside, _, unbounded] = seen[root[v]];
                inside && !unbounded
            })
            .collect();
    }
}

/// |a - b| (hypot's care for overflow only where it is needed: hypot is
/// several times slower than a square root).
fn length(a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dy) = (a[0] - b[0], a[1] - b[1]);
    let d2 = dx * dx + dy * dy;
    if d2.is_normal() {
        d2.sqrt()
    } else {
        dx.hypot(dy)
    }
}

/// Sites hidden by rounding that `repair` puts back (each costs a scan).
const MAX_REINSERTED: usize = 16;

/// Lawson flips decided exactly, for a triangulation of rounded sites that
/// failed its check: sites that are co-orthogonal up to rounding (around a
/// regular polygon, say) may be triangulated otherwise by the exact sites.
/// Sites hidden by rounding are inserted first when their exact weights
/// give them a cell. False when a non-regular edge cannot be flipped (its
/// quadrilateral is not strictly convex), the flips do not settle, or a
/// hidden site is not strictly inside a triangle.
/// The input vertex at each power vertex (a class of triangles, `class`),
/// or the two a class would be. Three sites serving one input vertex have
/// their power centre there. Usually one triangle's sites do; but a site
/// on a wall of the cell it serves has the vertex beyond that wall's power
/// there too, ties with that vertex's sites, and the triangulation may then
/// mix it into every triangle at that vertex (a fuzzed input did): so the
/// sites of a class of several triangles, which share one power centre,
/// are counted together.
fn input_vertices(
    sites: &Sites,
    tris: &[[u32; 3]],
    class: &[u32],
    classes: usize,
) -> std::result::Result<Vec<Option<u32>>, [u32; 2]> {
    let mut input_vertex: Vec<Option<u32>> = vec![None; classes];
    let mut size = vec![0u32; classes];
    fn set(at: &mut Option<u32>, v: u32) -> std::result::Result<(), [u32; 2]> {
        match *at {
            Some(u) if u != v => Err([u, v]),
            _ => {
                *at = Some(v);
                Ok(())
            }
        }
    }
    // (the tests in parallel, in triangle order)
    let common: Vec<Option<u32>> = tris
        .par_iter()
        .map(|tri| sites.common_vertex(&tri.map(|s| s as usize)))
        .collect();
    for (t, v) in common.into_iter().enumerate() {
        size[class[t] as usize] += 1;
        if let Some(v) = v {
            set(&mut input_vertex[class[t] as usize], v)?;
        }
    }
    let mut pooled: std::collections::BTreeMap<u32, Vec<u32>> = Default::default();
    for (t, tri) in tris.iter().enumerate() {
        let id = class[t];
        if size[id as usize] > 1 && input_vertex[id as usize].is_none() {
            pooled.entry(id).or_default().extend(tri);
        }
    }
    for (id, mut members) in pooled {
        members.sort_unstable();
        members.dedup();
        // (vertex, site) for each vertex a member serves, by vertex
        let mut served: Vec<(u32, u32)> = members
            .iter()
            .flat_map(|&s| {
                let mut vs = sites.served_by(s as usize).to_vec();
                vs.dedup();
                vs.into_iter().map(move |v| (v, s))
            })
            .collect();
        served.sort_unstable();
        for run in served.chunk_by(|a, b| a.0 == b.0) {
            // Three of its sites not on one line: their power centre is the
            // vertex (collinear ones only share a line through it).
            let on: Vec<usize> = run.iter().map(|&(_, s)| s as usize).collect();
            let spans = (1..on.len()).any(|b| {
                on[b + 1..]
                    .iter()
                    .any(|&c| sites.orient(on[0], on[b], c) != std::cmp::Ordering::Equal)
            });
            if spans {
                set(&mut input_vertex[id as usize], run[0].0)?;
            }
        }
    }
    Ok(input_vertex)
}

#[cfg(test)]
fn repair(sites: &Sites, rt: &mut Triangulation) -> bool {
    let stack: Vec<(u32, u32)> = rt
        .edges()
        .filter(|&(a, b)| rt.non_regular(sites, a, b).is_some())
        .collect();
    repair_from(sites, rt, stack)
}

/// `repair` given every edge that is not locally regular.
fn repair_from(sites: &Sites, rt: &mut Triangulation, mut stack: Vec<(u32, u32)>) -> bool {
    // A few sites hidden by rounding but not by their exact weights: each
    // goes into the triangle holding it strictly, then the flips below.
    if rt.hidden.len() > MAX_REINSERTED {
        return false;
    }
    for h in rt.hidden.clone() {
        let hu = h as usize;
        let holder = rt.triangles.iter().position(|t| {
            let [a, b, c] = t.map(|v| v as usize);
            sites.orient(a, b, hu) == Ordering::Greater
                && sites.orient(b, c, hu) == Ordering::Greater
                && sites.orient(c, a, hu) == Ordering::Greater
        });
        let Some(t) = holder else { return false };
        let [a, b, c] = rt.triangles[t];
        if sites.power_test(a as usize, b as usize, c as usize, hu) != Ordering::Greater {
            return false; // hidden indeed (or on the orthocircle)
        }
        rt.split(t as u32, h);
        stack.extend([(a, b), (b, c), (c, a)]);
    }
    rt.flip_to_regular(sites, stack).is_some()
}

/// Whether site v is an interior vertex of rt whose triangles are all
/// counter-clockwise (exact).
pub fn star_ccw(sites: &Sites, rt: &Triangulation, v: usize) -> bool {
    rt.star(v as u32).is_some_and(|star| {
        star.iter().all(|&t| {
            let [a, b, c] = rt.triangles[t as usize].map(|x| x as usize);
            sites.orient(a, b, c) == Ordering::Greater
        })
    })
}

/// After the sites `moved` changed (position and weight), makes the
/// triangulation regular again by flips around them, when it can: every
/// triangle around a moved site must still be counter-clockwise and no
/// moved site on the hull. Only the edges whose power test involves a moved
/// site can have changed. Returns the sites whose neighbourhood changed
/// (moved, their neighbours, the flipped quadrilaterals), or None: then
/// the triangulation must be built anew. Not a certificate: the final
/// triangulation is checked whole (`Diagram::check`).
pub fn repair_around(sites: &Sites, rt: &mut Triangulation, moved: &[usize]) -> Option<Vec<u32>> {
    let mut stack = vec![];
    for &v in moved {
        if !star_ccw(sites, rt, v) {
            return None;
        }
        for t in rt.star(v as u32)? {
            let tri = rt.triangles[t as usize];
            stack.extend([(tri[0], tri[1]), (tri[1], tri[2]), (tri[2], tri[0])]);
        }
    }
    let mut touched = rt.flip_to_regular(sites, stack)?;
    for &v in moved {
        touched.push(v as u32);
        for t in rt.star(v as u32)? {
            touched.extend(rt.triangles[t as usize]);
        }
    }
    touched.sort_unstable();
    touched.dedup();
    Some(touched)
}

/// Every triangle counter-clockwise and the hull convex, winding once
/// (exact): what flips keep, so a repair need not check it again.
fn check_shape(sites: &Sites, rt: &Triangulation) -> std::result::Result<(), String> {
    let tris = &rt.triangles;
    let flat = tris.par_iter().position_any(|t| {
        sites.orient(t[0] as usize, t[1] as usize, t[2] as usize) != Ordering::Greater
    });
    if let Some(t) = flat {
        return Err(format!("triangle {:?} is not counter-clockwise", tris[t]));
    }
    check_hull(sites, rt)
}

/// The boundary of the triangulation, walked with the triangles on its left,
/// turns left or goes straight at every vertex and winds once: the
/// triangles cover the convex hull of the sites.
fn check_hull(sites: &Sites, rt: &Triangulation) -> std::result::Result<(), String> {
    let hull: Vec<(u32, u32)> = rt
        .par_edge_triangles()
        .filter_map(|(a, b, _, u)| u.is_none().then_some((a, b)))
        .collect();
    let mut next = crate::FastMap::default();
    for (a, b) in hull {
        if next.insert(a, b).is_some() {
            return Err(format!("site {a} is twice on the hull"));
        }
    }
    let mut turning = 0.0;
    for (&a, &b) in &next {
        let c = *next.get(&b).ok_or("the hull is not closed")?;
        if sites.orient(a as usize, b as usize, c as usize) == Ordering::Less {
            return Err(format!("the hull turns right at site {b}"));
        }
        let p = |s: u32| sites.approx(s as usize);
        let (pa, pb, pc) = (p(a), p(b), p(c));
        let u = [pb[0] - pa[0], pb[1] - pa[1]];
        let v = [pc[0] - pb[0], pc[1] - pb[1]];
        turning += (u[0] * v[1] - u[1] * v[0]).atan2(u[0] * v[0] + u[1] * v[1]);
    }
    // Left turns only: the total is 2 pi k; k = 1 up to rounding.
    if turning > 3.0 * std::f64::consts::PI {
        return Err("the hull winds more than once".into());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sites::tests::{points_as_sites, weighted_sites};

    #[test]
    fn repair_flips_to_the_regular_diagonal() {
        // A convex quadrilateral triangulated by its non-Delaunay diagonal 0-2.
        let sites = points_as_sites(&[[0.0, 0.0], [4.0, -1.0], [8.0, 0.0], [4.0, 1.0]]);
        let mut t = Triangulation::from_flat(&[0, 1, 2, 0, 2, 3], vec![]);
        assert!(repair(&sites, &mut t));
        assert!(t.has_edge(1, 3) && !t.has_edge(0, 2));
        assert!(check_hull(&sites, &t).is_ok());
    }

    #[test]
    fn a_repair_retests_exactly_the_edges_it_changed() {
        // Delaunay triangulation of scattered points, then some edges
        // flipped away from it: repaired, with the tests a fresh pass gives.
        let pts: Vec<[f64; 2]> = (0..200u64)
            .map(|i| {
                let s = crate::generate::scatter;
                [s(2 * i) * 50.0, s(2 * i + 1) * 50.0]
            })
            .collect();
        use crate::backend::Backend;
        let sites = points_as_sites(&pts);
        let backend = crate::backend::default_backend();
        let mut rt = backend.regular(&pts, &vec![0.0; pts.len()]).unwrap();
        let mut flipped = 0;
        for (a, b) in rt.edges().collect::<Vec<_>>().into_iter().step_by(37) {
            let convex = rt
                .left_of(a, b)
                .zip(rt.left_of(b, a))
                .is_some_and(|(t1, t2)| {
                    let (c, d) = (rt.apex(t1, a, b), rt.apex(t2, b, a));
                    let o =
                        |x: u32, y: u32, z: u32| sites.orient(x as usize, y as usize, z as usize);
                    o(c, a, d) == Ordering::Greater && o(c, d, b) == Ordering::Greater
                });
            if convex && rt.flip(a, b).is_some() {
                flipped += 1;
            }
        }
        assert!(flipped >= 5, "{flipped}");
        assert!(Diagram::check(&sites, &rt).is_err());
        let tests = Diagram::check_or_repair(&sites, &mut rt).expect("repaired");
        let fresh = power_tests(&sites, &rt);
        assert_eq!(tests.inner, fresh.inner);
        assert_eq!(tests.tests, fresh.tests);
        assert!(Diagram::check(&sites, &rt).is_ok());
    }

    #[test]
    fn a_site_hidden_by_rounding_is_put_back() {
        // Site 3 inside triangle 0 1 2 with a weight that gives it a cell,
        // reported hidden: split in, then flipped to the regular triangulation.
        let sites = weighted_sites(
            &[[0.0, 0.0], [8.0, 0.0], [4.0, 6.0], [4.0, 2.0]],
            &[0.0, 0.0, 0.0, -1.0],
        );
        let mut t = Triangulation::from_flat(&[0, 1, 2], vec![3]);
        assert!(repair(&sites, &mut t));
        assert!(t.hidden.is_empty());
        assert_eq!(t.triangles.len(), 3);
        for v in 0..3 {
            assert!(t.has_edge(v, 3));
        }
        assert!(check_hull(&sites, &t).is_ok());
        // With a weight that hides it, it stays out and repair says so.
        let hiding = weighted_sites(
            &[[0.0, 0.0], [8.0, 0.0], [4.0, 6.0], [4.0, 2.0]],
            &[0.0, 0.0, 0.0, 100.0],
        );
        let mut t = Triangulation::from_flat(&[0, 1, 2], vec![3]);
        assert!(!repair(&hiding, &mut t));
    }

    #[test]
    fn a_hidden_site_cannot_be_flipped_away() {
        // Site 3 inside triangle 0 1 2 with so small a weight that it has no
        // cell: its edges are not regular, and every quadrilateral around it
        // is reflex, so no flip helps.
        let sites = weighted_sites(
            &[[0.0, 0.0], [8.0, 0.0], [4.0, 6.0], [4.0, 2.0]],
            &[0.0, 0.0, 0.0, 100.0],
        );
        let mut t = Triangulation::from_flat(&[0, 1, 3, 1, 2, 3, 2, 0, 3], vec![]);
        assert!(!repair(&sites, &mut t));
    }

    #[test]
    fn flips_around_moved_sites_give_the_regular_triangulation() {
        use crate::backend::Backend;
        let backend = crate::backend::default_backend();
        let r = crate::generate::scatter;
        let mut pts: Vec<[f64; 2]> = (0..300)
            .map(|i| [r(2 * i) * 100.0, r(2 * i + 1) * 100.0])
            .collect();
        let edges = |t: &Triangulation| {
            let mut e: Vec<(u32, u32)> = t.edges().map(|(a, b)| (a.min(b), a.max(b))).collect();
            e.sort_unstable();
            e
        };
        let mut rt = backend.regular(&pts, &vec![0.0; pts.len()]).unwrap();
        let (mut repaired, mut flipped) = (0, 0);
        for round in 0..40u64 {
            let mut moved: Vec<usize> = (0..6)
                .map(|k| (r(10_000 + 10 * round + k) * 300.0) as usize)
                .filter(|&v| rt.star(v as u32).is_some())
                .collect();
            moved.sort_unstable();
            moved.dedup();
            for (k, &v) in moved.iter().enumerate() {
                let key = 20_000 + 100 * round + 2 * k as u64;
                pts[v][0] += (r(key) - 0.5) * 2.0;
                pts[v][1] += (r(key + 1) - 0.5) * 2.0;
            }
            let sites = points_as_sites(&pts);
            let before = edges(&rt);
            let fresh = backend.regular(&pts, &vec![0.0; pts.len()]).unwrap();
            match repair_around(&sites, &mut rt, &moved) {
                Some(touched) => {
                    repaired += 1;
                    assert_eq!(edges(&rt), edges(&fresh), "round {round}");
                    assert!(moved.iter().all(|&v| touched.contains(&(v as u32))));
                    flipped += usize::from(edges(&rt) != before);
                }
                None => rt = fresh,
            }
        }
        assert!(
            repaired > 10 && flipped > 5,
            "{repaired} repaired, {flipped} flipped"
        );
    }

    #[test]
    fn the_hull_must_turn_left() {
        let sites = points_as_sites(&[[0.0, 0.0], [4.0, 1.0], [8.0, 0.0], [4.0, 3.0]]);
        let t = Triangulation::from_flat(&[0, 1, 3, 1, 2, 3], vec![]);
        assert!(check_hull(&sites, &t).is_err());
    }
}
