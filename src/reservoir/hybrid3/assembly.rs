//! The assembly of the 3D hybrid: reservoir cells outside the cavities
//! (corner-point cells as polyhedra), the transitions' cells, the wells'
//! radial cells, one point numbering over all, and the connections.

use super::cavity::CavityCells;
use super::complex::{Across, Transition};
use super::cpg::{Cpg, Ijk};
use super::lattice::{find_face, orient_faces};
use super::radial::{End, Radial};
use crate::conform::{Outcome, D3};
use crate::error::Result;
use crate::geom::{dot_f, newell, volume, Plane};
use crate::mesh::{Link3, Mesh3};
use crate::reservoir::deck::WellLinks;
use crate::reservoir::hybrid::{site_radii, Region};
use std::collections::{BTreeMap, HashMap};
use std::f64::consts::TAU;

/// A cavity and what was built in it.
pub(super) struct Built {
    pub(super) cells: CavityCells,
    pub(super) transition: Transition,
    pub(super) radials: Vec<Radial>,
    pub(super) outcome: Outcome<D3>,
}

/// The mesh being assembled, with per cell its region and grid cell.
#[derive(Default)]
pub(super) struct Assembly {
    pub(super) out: Mesh3,
    pub(super) region: Vec<Region>,
    pub(super) ijk: Vec<Option<Ijk>>,
    ids: HashMap<[u64; 3], u32>,
    /// Per reservoir grid cell, its cell.
    pub(super) res_cell: BTreeMap<Ijk, usize>,
    /// Transition faces on sides between two cavities, by the side's
    /// points: (cell, face, area, distance from the site).
    between: BTreeMap<Vec<u32>, Vec<Half>>,
}

/// A transition face on a side between cavities: its cell, points, area,
/// and its site's distance.
type Half = (usize, Vec<u32>, f64, f64);

/// The plane of a face through its points' centroid (Newell's normal: the
/// mean plane of a face that is not planar).
fn mean_plane(pts: &[[f64; 3]]) -> Plane {
    let n = newell(pts);
    let len = n.iter().map(|x| x * x).sum::<f64>().sqrt();
    let k = pts.len() as f64;
    Plane {
        origin: std::array::from_fn(|a| pts.iter().map(|p| p[a]).sum::<f64>() / k),
        unit: n.map(|c| c / len),
        area: len / 2.0,
    }
}

/// The plane of a face in pieces: their normals' sum, their areas', and
/// the mean of their centroids by area.
fn plane_of_pieces(pieces: &[Vec<[f64; 3]>]) -> Plane {
    let (mut n, mut area, mut o) = ([0.0; 3], 0.0, [0.0; 3]);
    for p in pieces {
        // each piece's area and centroid as mean_plane has them, from one
        // Newell vector
        let m = newell(p);
        let a = m.iter().map(|x| x * x).sum::<f64>().sqrt() / 2.0;
        for k in 0..3 {
            n[k] += m[k];
            o[k] += a * (p.iter().map(|q| q[k]).sum::<f64>() / p.len() as f64);
        }
        area += a;
    }
    let len = n.iter().map(|x| x * x).sum::<f64>().sqrt();
    Plane {
        origin: o.map(|x| x / area),
        unit: n.map(|x| x / len),
        area,
    }
}

impl Assembly {
    /// The id of point p: points are shared by exact coordinates.
    pub(super) fn point(&mut self, p: [f64; 3]) -> u32 {
        let out = &mut self.out;
        *self.ids.entry(p.map(f64::to_bits)).or_insert_with(|| {
            out.points.push(p);
            out.points.len() as u32 - 1
        })
    }

    pub(super) fn push_cell(
        &mut self,
        faces: Vec<Vec<u32>>,
        site: [f64; 3],
        region: Region,
        ijk: Option<Ijk>,
    ) {
        self.out.volumes.push(volume(&faces, &self.out.points));
        self.out.cells.push(faces);
        self.out.sites.push(site);
        self.out.weights.push(0.0);
        self.out.site_inside.push(true);
        self.region.push(region);
        self.ijk.push(ijk);
    }

    /// Reservoir cells outside the cavities, in grid order: each face's
    /// pieces (`pieces`), also at throws: vtk accepts no face cut there
    /// (corners on a side make its edges meet, coplanar pieces make the
    /// cell nonconvex for it), so the cells across a throw, and the
    /// transition's faces on one, meet there without matching corners.
    pub(super) fn reservoir(&mut self, cpg: &Cpg, in_cavity: &dyn Fn(Ijk) -> bool) {
        let g = cpg.g;
        for k in 0..g.nz {
            for j in 0..g.ny {
                for i in 0..g.nx {
                    let c = [i, j, k];
                    if in_cavity(c) || !cpg.live(c) {
                        continue;
                    }
                    let mut faces = vec![];
                    for f in 0..6 {
                        let (q, ps) = cpg.face_pieces(c, f);
                        for p in ps {
                            faces.push(p.iter().map(|&n| self.point(q[n])).collect());
                        }
                    }
                    self.res_cell.insert(c, self.out.cells.len());
                    self.push_cell(faces, cpg.centre(c), Region::Reservoir, Some(c));
                }
            }
        }
    }

    /// Connections between reservoir cells across their I+, J+ and bottom
    /// faces, in grid order; across a throw, to each cell across by the
    /// pieces of the face they share (as corner-point simulators connect
    /// cells across faults). Returns the faces left unconnected (a throw
    /// with nothing across, a gap between layers) and the links across
    /// throws.
    pub(super) fn reservoir_links(&mut self, cpg: &Cpg) -> Result<[usize; 2]> {
        let cells: Vec<(Ijk, usize)> = self.res_cell.iter().map(|(&c, &a)| (c, a)).collect();
        let (mut unmatched, mut thrown) = (0, 0);
        for (c, a) in cells {
            for f in [1, 3, 5] {
                let n = match cpg.neighbour(c, f) {
                    Ok(Some(n)) => n,
                    Ok(None) => continue,
                    Err(_) if f < 4 => {
                        let [links, none] = self.across_throw(cpg, c, a, f)?;
                        unmatched += none;
                        thrown += links;
                        continue;
                    }
                    Err(_) => {
                        unmatched += 1;
                        continue;
                    }
                };
                let Some(&b) = self.res_cell.get(&n) else {
                    continue;
                };
                let q = cpg.face(c, f);
                let mut pts: Vec<[f64; 3]> = vec![];
                for p in q {
                    if pts.last() != Some(&p) && pts.first() != Some(&p) {
                        pts.push(p);
                    }
                }
                if pts.len() < 3 {
                    continue;
                }
                let face: Vec<u32> = pts.iter().map(|&p| self.point(p)).collect();
                self.link(a, b, face, mean_plane(&pts));
            }
        }
        Ok([unmatched, thrown])
    }

    /// Links from reservoir cell c (mesh cell a) across its face f on a
    /// throw: one to each reservoir cell across, by the pieces they share.
    /// Returns the links made, and 1 where no live cell is across.
    fn across_throw(&mut self, cpg: &Cpg, c: Ijk, a: usize, f: usize) -> Result<[usize; 2]> {
        let mut by_cell: BTreeMap<Ijk, Vec<Vec<[f64; 3]>>> = BTreeMap::new();
        for p in cpg.parts(c, f)? {
            if let Some(n) = p.across {
                by_cell.entry(n).or_default().push(p.points);
            }
        }
        let none = usize::from(by_cell.is_empty());
        let mut made = 0;
        for (n, pieces) in by_cell {
            let Some(&b) = self.res_cell.get(&n) else {
                continue;
            };
            let pl = plane_of_pieces(&pieces);
            if pl.area > 0.0 && pl.area.is_finite() {
                let face = pieces[0].iter().map(|&p| self.point(p)).collect();
                self.link(a, b, face, pl);
                made += 1;
            }
        }
        Ok([made, none])
    }

    /// A link across a face between cells a and b.
    pub(super) fn link(&mut self, a: usize, b: usize, face: Vec<u32>, pl: Plane) {
        if pl.area <= 0.0 || !pl.area.is_finite() {
            return;
        }
        let d = [
            pl.distance(self.out.sites[a]),
            pl.distance(self.out.sites[b]),
        ];
        self.out.links.push(Link3 {
            cells: [a, b],
            face,
            area: pl.area,
            d,
            normal: pl.unit,
        });
    }

    /// A transition's cells and links; returns the first's index.
    pub(super) fn transition(&mut self, t: &Outcome<D3>) -> usize {
        let first_t = self.out.cells.len();
        for (c, faces) in t.mesh.cells.iter().enumerate() {
            let faces: Vec<Vec<u32>> = faces
                .iter()
                .map(|f| {
                    f.iter()
                        .map(|&v| self.point(t.mesh.points[v as usize]))
                        .collect()
                })
                .collect();
            self.out.cells.push(faces);
            self.out.sites.push(t.mesh.sites[c]);
            self.out.weights.push(t.mesh.weights[c]);
            self.out.volumes.push(t.mesh.volumes[c]);
            self.out.site_inside.push(t.mesh.site_inside[c]);
            self.region.push(Region::Transition);
            self.ijk.push(None);
        }
        for l in &t.mesh.links {
            let face = l
                .face
                .iter()
                .map(|&v| self.point(t.mesh.points[v as usize]))
                .collect();
            self.out.links.push(Link3 {
                cells: l.cells.map(|c| c + first_t),
                face,
                ..l.clone()
            });
        }
        first_t
    }

    /// A well's cells (ring q, sector s, layer k; a plug's wedges) and its
    /// own links; returns the first's index.
    pub(super) fn well(&mut self, w: &Radial) -> usize {
        let m = w.m;
        let first_w = self.out.cells.len();
        let rho = site_radii(&w.r, m);
        for (k, &mid_k) in w.mid.iter().enumerate() {
            if w.is_plug(k) {
                self.wedges(w, k);
                continue;
            }
            for (q, &rho_q) in rho.iter().enumerate() {
                for s in 0..m {
                    let v: Vec<u32> = [
                        (q, s, k),
                        (q + 1, s, k),
                        (q + 1, s + 1, k),
                        (q, s + 1, k),
                        (q, s, k + 1),
                        (q + 1, s, k + 1),
                        (q + 1, s + 1, k + 1),
                        (q, s + 1, k + 1),
                    ]
                    .map(|(q, s, k)| self.point(w.point(q, s, k)))
                    .to_vec();
                    // the outer face whole, also where the transition has it as
                    // two triangles (vtk's convexity test fails coplanar faces)
                    let faces = vec![
                        vec![v[0], v[3], v[2], v[1]],
                        vec![v[4], v[5], v[6], v[7]],
                        vec![v[0], v[1], v[5], v[4]],
                        vec![v[2], v[3], v[7], v[6]],
                        vec![v[3], v[0], v[4], v[7]],
                        vec![v[1], v[2], v[6], v[5]],
                    ];
                    // on the sector's mid-angle ray at the layer's mid-level
                    let site = w.at(rho_q, w.mid_angle(s), mid_k);
                    let faces = orient_faces(faces, &self.out.points, site);
                    self.push_cell(faces, site, Region::Well, None);
                }
            }
        }
        self.well_links(w, first_w);
        first_w
    }

    /// A plug's wedges in layer k: triangular prisms from the axis to the
    /// outer surface. Toward the rings, a wedge's face is one triangle that
    /// the rings' faces and the wellbore's end tile: a polyhedron carrying
    /// the ring points on its own edges is not valid for vtk (its
    /// convexity test), so faces meet there without matching corners (as
    /// reservoir cells do at throws, `reservoir`).
    fn wedges(&mut self, w: &Radial, k: usize) {
        let rings = w.rings;
        let (far, near) = if k == 0 { (0, 1) } else { (k + 1, k) };
        let half = std::f64::consts::PI / w.m as f64;
        let rho = 2.0 / 3.0 * w.outer * half.cos();
        for s in 0..w.m {
            let (cf, cn) = (self.point(w.centre(far)), self.point(w.centre(near)));
            let [of, of1, on, on1] = [(s, far), (s + 1, far), (s, near), (s + 1, near)]
                .map(|(s, l)| self.point(w.point(rings, s, l)));
            let faces = vec![
                vec![cf, of, of1],
                vec![cn, on, on1],
                vec![of, of1, on1, on],
                vec![cf, of, on, cn],
                vec![cf, of1, on1, cn],
            ];
            let site = w.at(rho, w.mid_angle(s), w.mid[k]);
            let faces = orient_faces(faces, &self.out.points, site);
            self.push_cell(faces, site, Region::Well, None);
        }
    }

    /// A well's own links: across sectors, rings and layers (a plug's
    /// wedge to each ring cell of its sector beside it).
    fn well_links(&mut self, w: &Radial, first_w: usize) {
        let (m, rings) = (w.m, w.rings);
        let cell = |k: usize, q: usize, s: usize| first_w + w.cell(k, q, s);
        for k in 0..w.nl {
            let qs = if w.is_plug(k) { 1 } else { rings };
            for q in 0..qs {
                for s in 0..m {
                    let a = cell(k, q, s);
                    let mut next = vec![cell(k, q, (s + 1) % m)];
                    if q + 1 < qs {
                        next.push(cell(k, q + 1, s));
                    }
                    if k + 1 < w.nl {
                        match (w.is_plug(k), w.is_plug(k + 1)) {
                            (false, false) | (true, true) => next.push(cell(k + 1, q, s)),
                            (false, true) => next.push(cell(k + 1, 0, s)),
                            (true, false) => next.extend((0..rings).map(|q| cell(k + 1, q, s))),
                        }
                    }
                    for b in next {
                        let mut face = find_face(&self.out.cells[a], &self.out.cells[b]);
                        if face.is_empty() {
                            // a plug's wedge and a ring cell: the ring cell's face
                            let (ring, wedge) = if w.is_plug(k) { (b, a) } else { (a, b) };
                            face = self.ring_face(ring, wedge);
                        }
                        let pts: Vec<[f64; 3]> =
                            face.iter().map(|&v| self.out.points[v as usize]).collect();
                        if pts.len() >= 3 {
                            let pl = Plane::of(&pts);
                            self.link(a, b, face, pl);
                        }
                    }
                }
            }
        }
    }

    /// Links across the knees between a cavity's legs (`bend::chain`):
    /// each ring cell of a leg's last layer to its mirror image, the leg
    /// after's in its first layer, across the face they share.
    fn knees(&mut self, radials: &[Radial], first_w: &[usize]) {
        for (a, w) in radials.iter().enumerate() {
            let Some((well, leg)) = w.leg else { continue };
            let Some(b) = radials.iter().position(|v| v.leg == Some((well, leg + 1))) else {
                continue;
            };
            if !matches!(w.ends[1], End::Knee(_)) {
                continue;
            }
            let (v, last) = (&radials[b], w.nl - 1);
            for q in 0..w.rings {
                for s in 0..w.m {
                    let (x, y) = (
                        first_w[a] + w.cell(last, q, s),
                        first_w[b] + v.cell(0, q, s),
                    );
                    let face = find_face(&self.out.cells[x], &self.out.cells[y]);
                    let pts: Vec<[f64; 3]> =
                        face.iter().map(|&p| self.out.points[p as usize]).collect();
                    if pts.len() >= 3 {
                        self.link(x, y, face, Plane::of(&pts));
                    }
                }
            }
        }
    }

    /// The face of a ring cell toward the plug's wedge beside it: the one
    /// whose points all lie on the wedge's face (the level between them).
    fn ring_face(&self, ring: usize, wedge: usize) -> Vec<u32> {
        let theirs = &self.out.cells[wedge];
        let on_level = |f: &Vec<u32>| {
            theirs.iter().any(|g| {
                g.len() == 3 && {
                    let pts: Vec<[f64; 3]> =
                        g.iter().map(|&v| self.out.points[v as usize]).collect();
                    let pl = Plane::of(&pts);
                    let scale = pl.area.sqrt();
                    f.iter()
                        .all(|&v| pl.distance(self.out.points[v as usize]) <= 1e-9 * scale)
                }
            })
        };
        self.out.cells[ring]
            .iter()
            .find(|f| on_level(f))
            .cloned()
            .unwrap_or_default()
    }

    /// Interfaces: a transition's faces on the cavity's sides and on its
    /// wells' surfaces. Returns the links of the plugs' wedges to anchor:
    /// each to the one transition cell across its cap triangle
    /// (`anchor_wedges`).
    pub(super) fn interfaces(
        &mut self,
        b: &Built,
        first_t: usize,
        first_w: &[usize],
    ) -> Vec<usize> {
        let t = &b.outcome;
        let mut faces_of: HashMap<u32, usize> = HashMap::new();
        for f in &t.mesh.facet_faces {
            *faces_of.entry(f.facet).or_default() += 1;
        }
        let mut anchors = vec![];
        for f in &t.mesh.facet_faces {
            let a = first_t + f.cell;
            let mut anchor = false;
            let other = match b.transition.across[f.facet as usize] {
                Across::Cell(c) if !self.res_cell.contains_key(&c) => {
                    // a side shared with another cavity: paired later
                    let mut key: Vec<u32> = b.transition.cx.facets[f.facet as usize].polygons[0]
                        .iter()
                        .map(|&v| self.point(b.transition.cx.points[v as usize]))
                        .collect();
                    key.sort_unstable();
                    let face = f
                        .points
                        .iter()
                        .map(|&v| self.point(t.mesh.points[v as usize]));
                    let e = (a, face.collect(), f.area, f.d);
                    self.between.entry(key).or_default().push(e);
                    None
                }
                Across::Cell(c) => self.res_cell.get(&c).copied(),
                Across::Well(n, [k, q, s]) => {
                    let r = &b.radials[n];
                    let w = first_w[n] + r.cell(k, q, s);
                    // a cap's triangle (around the axis' point at the
                    // plug's far level), not the plug's outer face
                    let far = r.centre(if k == 0 { 0 } else { r.nl });
                    let cap = r.is_plug(k)
                        && b.transition.cx.facets[f.facet as usize].polygons[0]
                            .iter()
                            .any(|&v| b.transition.cx.points[v as usize] == far);
                    anchor = cap && faces_of[&f.facet] == 1;
                    Some(w)
                }
                Across::Outside | Across::Inner => None,
            };
            let Some(other) = other else { continue };
            let face: Vec<u32> = f
                .points
                .iter()
                .map(|&v| self.point(t.mesh.points[v as usize]))
                .collect();
            let pts: Vec<[f64; 3]> = face.iter().map(|&v| self.out.points[v as usize]).collect();
            let pl = Plane::of(&pts);
            self.out.links.push(Link3 {
                cells: [a, other],
                face,
                area: f.area,
                d: [f.d, pl.distance(self.out.sites[other])],
                normal: pl.unit,
            });
            if anchor {
                anchors.push(self.out.links.len() - 1);
            }
        }
        anchors
    }

    /// Each plug's wedge whose cap triangle is one face of one transition
    /// cell: its site moved, across the cap, onto the normal through that
    /// cell's site (the foot of the triangle's power centre, about), so
    /// that their link is orthogonal; kept where that would leave the
    /// wedge. The distances of its links (among the cavity's, from
    /// `first_link` on) are measured again.
    pub(super) fn anchor_wedges(&mut self, anchors: &[usize], first_link: usize) {
        let mut moved = std::collections::BTreeSet::new();
        for &a in anchors {
            let l = &self.out.links[a];
            let [t, w] = l.cells;
            let (n, old, ts) = (l.normal, self.out.sites[w], self.out.sites[t]);
            let off = dot_f(std::array::from_fn(|k| ts[k] - old[k]), n);
            let site: [f64; 3] = std::array::from_fn(|k| ts[k] - off * n[k]);
            // strictly inside the wedge (convex): behind each face's plane
            let inside = self.out.cells[w].iter().all(|f| {
                let pts: Vec<[f64; 3]> = f.iter().map(|&v| self.out.points[v as usize]).collect();
                let v = newell(&pts);
                dot_f(std::array::from_fn(|k| site[k] - pts[0][k]), v) < 0.0
            });
            if inside {
                self.out.sites[w] = site;
                moved.insert(w);
            }
        }
        for l in &mut self.out.links[first_link..] {
            for (i, &c) in l.cells.iter().enumerate() {
                if moved.contains(&c) && !l.face.is_empty() {
                    let pts: Vec<[f64; 3]> = l
                        .face
                        .iter()
                        .map(|&v| self.out.points[v as usize])
                        .collect();
                    l.d[i] = mean_plane(&pts).distance(self.out.sites[c]);
                }
            }
        }
    }
}

impl Assembly {
    /// Links across the sides between cavities: faces with the same
    /// points, else a side kept whole on one side against each of the
    /// other side's pieces of it. Returns the faces left unpaired.
    pub(super) fn between_cavities(&mut self, cavity_of: &[usize], first_t: usize) -> usize {
        let mut unpaired = 0;
        for (side, faces) in std::mem::take(&mut self.between) {
            let key = |f: &Vec<u32>| {
                let mut k = f.clone();
                k.sort_unstable();
                k
            };
            let cav = |c: usize| cavity_of[c - first_t];
            let Some(&(a0, ..)) = faces.first() else {
                continue;
            };
            let (mine, theirs): (Vec<_>, Vec<_>) = faces.iter().partition(|f| cav(f.0) == cav(a0));
            let mut used = vec![false; theirs.len()];
            for x in &mine {
                let same = theirs.iter().position(|y| key(&y.1) == key(&x.1));
                let whole = |f: &Vec<u32>| key(f) == side;
                let pairs: Vec<usize> = match same {
                    Some(n) => vec![n],
                    None if whole(&x.1) => (0..theirs.len()).collect(),
                    None if theirs.len() == 1 && whole(&theirs[0].1) => vec![0],
                    None => vec![],
                };
                unpaired += usize::from(pairs.is_empty());
                for n in pairs {
                    used[n] = true;
                    let y = theirs[n];
                    // the smaller face is the shared one
                    let (face, area) = if y.2 < x.2 { (&y.1, y.2) } else { (&x.1, x.2) };
                    let pts: Vec<[f64; 3]> =
                        face.iter().map(|&v| self.out.points[v as usize]).collect();
                    let pl = Plane::of(&pts);
                    self.out.links.push(Link3 {
                        cells: [x.0, y.0],
                        face: face.clone(),
                        area,
                        d: [x.3, y.3],
                        normal: pl.unit,
                    });
                }
            }
            unpaired += used.iter().filter(|u| !**u).count();
        }
        unpaired
    }
}

/// The innermost ring's cells and the geometric part of their connection
/// to the wellbore: radial flow from the wellbore to the sites' radius
/// within a sector is exact, theta L / ln(rho / r_w), L the cell's length
/// along the axis. Plugs have none.
pub(super) fn wellbore(w: &Radial, first_w: usize) -> Vec<(usize, f64)> {
    let m = w.m;
    let rho = site_radii(&w.r, m);
    let log = (rho[0] / w.r[0]).ln();
    let theta = TAU / m as f64;
    (0..w.nl)
        .filter(|&k| !w.is_plug(k))
        .flat_map(|k| {
            let (a, b) = (w.axis_at(k), w.axis_at(k + 1));
            let length = crate::geom::dist_f(b, a);
            (0..m).map(move |s| (first_w + w.cell(k, 0, s), theta * length / log))
        })
        .collect()
}

/// The wells' links to their wellbores: per well its name and radius.
pub(super) fn well_links(
    names: &[(String, f64)],
    radials: &[&Radial],
    first_w: &[usize],
) -> Vec<WellLinks> {
    names
        .iter()
        .zip(radials)
        .zip(first_w)
        .map(|(((name, radius), w), &first)| WellLinks {
            name: name.clone(),
            radius: *radius,
            links: wellbore(w, first),
            log: (site_radii(&w.r, w.m)[0] / w.r[0]).ln(),
        })
        .collect()
}

/// The 3D hybrid from its parts, with its report.
/// `wells` are the paths' (a bent trajectory's legs apart), `well_of`
/// per path its well.
pub(super) fn assemble(
    cpg: &Cpg,
    wells: &[super::well::Well3],
    well_of: &[usize],
    built: Vec<Built>,
) -> Result<super::report::Hybrid3> {
    let mut a = Assembly::default();
    let owner: BTreeMap<Ijk, usize> = built
        .iter()
        .enumerate()
        .flat_map(|(n, b)| b.cells.cells.iter().map(move |&c| (c, n)))
        .collect();
    a.reservoir(cpg, &|c| owner.contains_key(&c));
    let [unmatched, thrown] = a.reservoir_links(cpg)?;
    let mut names = vec![];
    let mut owners = vec![];
    let mut radials: Vec<&Radial> = vec![];
    let mut firsts = vec![];
    let mut cavity_of = vec![];
    for (n, b) in built.iter().enumerate() {
        let first_link = a.out.links.len();
        let first_t = a.transition(&b.outcome);
        let first_w: Vec<usize> = b.radials.iter().map(|w| a.well(w)).collect();
        a.knees(&b.radials, &first_w);
        let anchors = a.interfaces(b, first_t, &first_w);
        a.anchor_wedges(&anchors, first_link);
        for (&w, r) in b.cells.wells.iter().zip(&b.radials) {
            names.push((wells[w].name.clone(), wells[w].radius));
            owners.push(well_of[w]);
            radials.push(r);
        }
        firsts.extend(first_w);
        cavity_of.extend(std::iter::repeat_n(n, a.out.cells.len() - first_t));
    }
    let first_t = a.res_cell.len();
    let unpaired = a.between_cavities(&cavity_of, first_t);
    let mut wellbore = super::bend::merge_legs(well_links(&names, &radials, &firsts), &owners);
    let (mut out, mut region, mut ijk) = a.finish();
    let first_t = region
        .iter()
        .take_while(|r| **r == Region::Reservoir)
        .count();
    let mut host = hosts(cpg, &built, &ijk, &out.sites, first_t, &cavity_of);
    let locate = |p: [f64; 3], cav: usize| cpg.locate(p, built[cav].cells.cells.iter().copied());
    let (slivers_merged, merged) = super::slivers::merge(super::slivers::Cells {
        locate: &locate,
        // 3D transitions' cells cross no column sides: slivers stay in theirs
        clear: &|_| false,
        mesh: &mut out,
        region: &mut region,
        ijk: &mut ijk,
        host: &mut host,
        cavity_of: &mut cavity_of,
        first: first_t,
        wellbore: &mut wellbore,
    });
    let by_regions = super::stats::by_regions(&out, &region);
    let count = |r: Region| region.iter().filter(|&&x| x == r).count();
    let cavities: Vec<super::report::CavityReport> = built
        .into_iter()
        .map(|b| super::report::CavityReport {
            wells: {
                let mut names: Vec<String> = vec![];
                for &w in &b.cells.wells {
                    if !names.contains(&wells[w].name) {
                        names.push(wells[w].name.clone());
                    }
                }
                names
            },
            grid_cells: b.cells.cells.len(),
            outer_radii: b.radials.iter().map(|r| r.outer).collect(),
            transition: b.outcome.report,
        })
        .collect();
    let t_cells: Vec<usize> = (0..region.len())
        .filter(|&c| region[c] == Region::Transition)
        .collect();
    let (slivers, smallest_volume_share) = super::stats::slivers(
        &t_cells.iter().map(|&c| out.volumes[c]).collect::<Vec<_>>(),
        &t_cells
            .iter()
            .map(|&c| cavity_of[c - first_t])
            .collect::<Vec<_>>(),
    );
    let report = super::report::Hybrid3Report {
        cells: [
            count(Region::Reservoir),
            count(Region::Transition),
            count(Region::Well),
        ],
        sites_outside: cavities
            .iter()
            .map(|c| {
                let k = &c.transition.certificate;
                k.domain_sites - k.sites_inside
            })
            .sum(),
        cavities,
        connections: out.links.len(),
        unpaired_faces: unpaired,
        unmatched_faces: unmatched,
        across_throws: thrown,
        non_orthogonal: by_regions.values().map(|c| c.non_orthogonal).sum(),
        by_regions,
        sections: vec![],
        slivers,
        slivers_merged,
        smallest_volume_share,
        notes: vec![],
    };
    Ok(super::report::Hybrid3 {
        mesh: out,
        region,
        ijk,
        host,
        wellbore,
        merged,
        report,
    })
}

impl Assembly {
    /// The mesh with one connection per pair of cells, each cell's region
    /// and grid cell.
    pub(super) fn finish(self) -> (Mesh3, Vec<Region>, Vec<Option<Ijk>>) {
        let mut out = self.out;
        out.links = one_per_pair(std::mem::take(&mut out.links));
        (out, self.region, self.ijk)
    }
}

/// One connection per pair of cells: a face split in two triangles on one
/// side is two transition faces (their areas added), and a cell beside a
/// cavity's side may touch a grid cell across two walls (a corner of it
/// past a pillar). The connection then takes its largest face (plane,
/// distances), its area scaled so that area / (d0 + d1) adds up the
/// faces' (exact where the two cells' permeabilities are equal).
pub(super) fn one_per_pair(links: Vec<Link3>) -> Vec<Link3> {
    let mut seen: HashMap<[usize; 2], usize> = HashMap::new();
    let mut merged: Vec<Link3> = vec![];
    for l in links {
        let Some(&i) = seen.get(&l.cells) else {
            seen.insert(l.cells, merged.len());
            merged.push(l);
            continue;
        };
        let m = &mut merged[i];
        let (dm, dl) = (m.d[0] + m.d[1], l.d[0] + l.d[1]);
        let coplanar = crate::geom::dot_f(m.normal, l.normal).abs() >= 1.0 - 1e-12
            && (dm - dl).abs() <= 1e-9 * dm.max(dl);
        if coplanar || dm <= 0.0 || dl <= 0.0 {
            m.area += l.area;
            continue;
        }
        let t = m.area / dm + l.area / dl;
        if l.area > m.area {
            *m = Link3 { area: 0.0, ..l };
        }
        m.area = t * (m.d[0] + m.d[1]);
    }
    merged
}

/// Per cell, the grid cell whose rock it takes: a reservoir cell its own;
/// a transition or well cell the cavity's cell that holds its site (the
/// cavity's cell with the nearest centre for a site outside them all).
fn hosts(
    cpg: &Cpg,
    built: &[Built],
    ijk: &[Option<Ijk>],
    sites: &[[f64; 3]],
    first_t: usize,
    cavity_of: &[usize],
) -> Vec<Ijk> {
    (0..ijk.len())
        .map(|c| {
            ijk[c].unwrap_or_else(|| {
                let cells = &built[cavity_of[c - first_t]].cells.cells;
                let p = sites[c];
                cpg.locate(p, cells.iter().copied()).unwrap_or_else(|| {
                    let d = |q: [f64; 3]| (0..3).map(|k| (p[k] - q[k]).powi(2)).sum::<f64>();
                    cells
                        .iter()
                        .copied()
                        .min_by(|&x, &y| d(cpg.centre(x)).total_cmp(&d(cpg.centre(y))))
                        .unwrap_or([0; 3])
                })
            })
        })
        .collect()
}
