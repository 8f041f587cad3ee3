//! A layered cavity's cells: each cell of the 2D section (a transition or
//! radial cell) times each layer of the cavity, a prism across the layers
//! (so every link inside the cavity is orthogonal: the section's faces
//! stand across the layers, the layers' planes lie across the prisms), cut
//! by the walls of the cavity's columns. A section cell on the cavity's
//! side reaches on to the walls (which lean off the prisms' axis where the
//! layers dip), bounded there as the section's power diagram would bound
//! it: along its faces with its neighbours, and by its power bisectors
//! with the other cells on the side, so that the cells fill the cavity
//! once and every link between them stays orthogonal.

use super::super::cpg::{Cpg, Ijk};
use super::cones::{self, Cones};
use super::frame::Frame;
use super::join;
use super::reflex::{self, left_of};
use crate::geom::{CutFace, Cutter, Halfspace};
use crate::mesh::Mesh;
use crate::reservoir::hybrid::Region;
use crate::FastMap;
use std::collections::{BTreeMap, BTreeSet, HashMap};

/// What lies across a cell's face.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) enum Across {
    /// The cell of section cell c in layer k.
    Cell(usize, usize),
    /// A grid cell outside the cavity (or none: the grid's side, an
    /// inactive cell).
    Grid(Option<Ijk>),
    /// The wellbore (a radial cell's inner face).
    Wellbore,
}

/// A cell: section cell `c` in layer `k`, its faces (points in frame
/// coordinates, `Cutter::points`) with what is across each, its site.
#[derive(Debug, Clone)]
pub(crate) struct Cell {
    pub(crate) c: usize,
    pub(crate) k: usize,
    pub(crate) faces: Vec<(Across, Vec<u32>)>,
    pub(crate) site: [f64; 3],
    /// The cell's length along the normal through its site.
    pub(crate) span: f64,
    /// Whether the site lies inside the cell (within the walls of a
    /// column of the cavity; inside its section cell by the section's
    /// certificate).
    pub(crate) inside: bool,
}

/// What lies across a section cell's edge: a cavity cell, the wellbore
/// (a radial cell's inner edge), the cavity's side (the edge left open,
/// the cell reaching on to the walls), or the box an open cell is cut to.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Edge {
    Cell(usize),
    Wellbore,
    Open,
    Box,
    /// A cavity cell across the line of a reflex corner (`reflex`): that
    /// cell where the column across the face is the cavity's, else the
    /// grid's cell there.
    Line(usize),
}

/// The plane through section points x and y across the layers, its normal
/// to the right of x -> y.
fn side_plane(x: [f64; 2], y: [f64; 2]) -> Halfspace {
    let n = [y[1] - x[1], x[0] - y[0], 0.0];
    Halfspace {
        n,
        c: n[0] * x[0] + n[1] * x[1],
    }
}

/// Whether two planes are one: their unit normals parallel to within
/// `angle` (1 - |cos|) and their offsets within `tol`.
fn coplanar(a: Halfspace, b: Halfspace, angle: f64, tol: f64) -> bool {
    let unit = |h: Halfspace| {
        let l = crate::geom::dot_f(h.n, h.n).sqrt();
        (h.n.map(|x| x / l), h.c / l)
    };
    let ((n, c), (m, d)) = (unit(a), unit(b));
    let dot = crate::geom::dot_f(n, m);
    dot.abs() >= 1.0 - angle && (c - dot.signum() * d).abs() <= tol
}

/// A layered cavity: its columns, layers k0..=k1, and section cells.
pub(crate) struct Cavity {
    pub(crate) cols: BTreeSet<[usize; 2]>,
    pub(crate) k: [usize; 2],
    pub(crate) cells: Vec<usize>,
    /// The section's reflex pillars that `section::inset` moved: each
    /// one's moved point and its own point (on the outline's side through
    /// the moved one).
    pub(crate) reflex: Vec<[[f64; 2]; 2]>,
}

/// A box in the section: its lowest and highest corners.
type Bounds = ([f64; 2], [f64; 2]);

/// The walls between columns: ('I', i, j) between (i - 1, j) and (i, j),
/// ('J', i, j) between (i, j - 1) and (i, j).
type Wall = (char, usize, usize);

/// Column (i, j)'s walls, in the order of cpg's faces I-, I+, J-, J+, and
/// the column across each.
fn walls([i, j]: [usize; 2]) -> [(Wall, Option<[usize; 2]>); 4] {
    [
        (('I', i, j), i.checked_sub(1).map(|i| [i, j])),
        (('I', i + 1, j), Some([i + 1, j])),
        (('J', i, j), j.checked_sub(1).map(|j| [i, j])),
        (('J', i, j + 1), Some([i, j + 1])),
    ]
}

struct Build<'a> {
    cpg: &'a Cpg<'a>,
    f: &'a Frame,
    m: &'a Mesh,
    cut: Cutter,
    lines: HashMap<u32, u32>,
    edges: HashMap<(u32, u32), u32>,
    walls: HashMap<Wall, u32>,
    /// Per column, its walls' planes and whether each normal points out.
    sides: HashMap<[usize; 2], [(u32, bool); 4]>,
    slabs: Vec<u32>,
    /// Per world (`Worlds`), the section cells with an edge on the cavity's
    /// side, with their bounding boxes.
    open: Vec<BTreeMap<usize, Bounds>>,
    /// Twisted layers: the grid cells' pyramids.
    cones: Cones,
    /// Whether the walls lean off the prisms (the cavity's sides then
    /// moved in, `section::inset`).
    leans: bool,
    /// Per world, section edges on the lines of reflex corners with the
    /// cell across; and the world the outlines are built in.
    over: Vec<HashMap<(u32, u32), Edge>>,
    world: usize,
}

impl Build<'_> {
    /// The vertical line through section point p.
    fn line(&mut self, p: u32) -> u32 {
        if let Some(&l) = self.lines.get(&p) {
            return l;
        }
        let q = self.m.points[p as usize];
        let l = self.cut.line([q[0], q[1], 0.0], [0.0, 0.0, 1.0]);
        self.lines.insert(p, l);
        l
    }

    /// The plane of section edge p - q, one for both cells beside it.
    fn edge(&mut self, p: u32, q: u32) -> u32 {
        let (a, b) = (p.min(q), p.max(q));
        if let Some(&id) = self.edges.get(&(a, b)) {
            return id;
        }
        let (x, y) = (self.m.points[a as usize], self.m.points[b as usize]);
        let id = self.cut.plane(side_plane(x, y));
        self.edges.insert((a, b), id);
        id
    }

    /// Column col's walls (`walls`' order): each one's plane, and whether
    /// its normal points out of the column (its inside then the plane's).
    fn column(&mut self, col: [usize; 2]) -> [(u32, bool); 4] {
        if let Some(&s) = self.sides.get(&col) {
            return s;
        }
        let ws = walls(col);
        let s = std::array::from_fn(|f| self.wall(ws[f].0, col, f));
        self.sides.insert(col, s);
        s
    }

    /// The plane of a wall, and whether its normal points out of column
    /// `col` (its inside is then the plane's inside).
    fn wall(&mut self, w: Wall, col: [usize; 2], f: usize) -> (u32, bool) {
        let id = match self.walls.get(&w) {
            Some(&id) => id,
            None => {
                let [k0, k1] = [self.f.k0, self.f.k0 + self.f.h.len() - 2];
                let mut pts = self.cpg.face([col[0], col[1], k0], f).to_vec();
                pts.extend(self.cpg.face([col[0], col[1], k1], f));
                let q: Vec<[f64; 3]> = pts.iter().map(|&p| self.f.to(p)).collect();
                let (o, n) = super::frame::plane_fit(&q);
                let c = crate::geom::dot_f(n, o);
                // walls in one plane (columns along the grid's side) are one
                // plane, so that a cell's faces there join
                let tol = self.f.tol();
                let same = self.walls.values().copied().find(|&id| {
                    coplanar(self.cut.planes[id as usize], Halfspace { n, c }, 1e-12, tol)
                });
                let id = same.unwrap_or_else(|| self.cut.plane(Halfspace { n, c }));
                self.walls.insert(w, id);
                id
            }
        };
        // outward for this column: its centre inside
        let centre = self.f.to(self.cpg.centre([col[0], col[1], self.f.k0]));
        (id, self.cut.planes[id as usize].eval(centre) < 0.0)
    }
}

/// The section cell's polygon as lines and side planes, reaching past the
/// cavity's side (its edges there, with no section neighbour, left out)
/// within a box: (lines, sides with their flips, what is across each).
fn outline(
    b: &mut Build,
    c: usize,
    inside: &dyn Fn(u32) -> bool,
    owner: Owners,
    region: Region,
    reach: f64,
) -> Option<(Vec<u32>, Vec<u32>, Vec<Edge>)> {
    let poly = b.m.cells[c].clone();
    let n = poly.len();
    let mut kinds = vec![];
    for k in 0..n {
        let (p, q) = (poly[k], poly[(k + 1) % n]);
        kinds.push(match owner.get(&(q, p)) {
            _ if b.over[b.world].contains_key(&(p, q)) => b.over[b.world][&(p, q)],
            Some(&d) if inside(d) => Edge::Cell(d as usize),
            _ if region == Region::Well => Edge::Wellbore,
            _ => Edge::Open,
        });
    }
    if !kinds.contains(&Edge::Open) {
        let lines = poly.iter().map(|&p| b.line(p)).collect();
        let sides = (0..n).map(|k| b.edge(poly[k], poly[(k + 1) % n])).collect();
        return Some((lines, sides, kinds));
    }
    // open: its closed edges' half-planes, and its open edges' moved out
    // by `reach` (as far as the walls lean off the section), in 2D; where
    // they lean, by its size more: beside a reflex corner of the outline
    // a cell on one side reaches that far along the strip between the
    // other side's moved line and its wall (SPE9 (11, 3) with its sides
    // cut short left a hole there)
    let pts: Vec<[f64; 2]> = poly.iter().map(|&p| b.m.points[p as usize]).collect();
    let (lo, hi) = crate::geom::bbox(&pts);
    let grow = margin(b.leans, reach, (lo, hi), (lo, hi));
    let out = if b.leans { grow } else { reach };
    let (lo, hi) = (lo.map(|x| x - grow), hi.map(|x| x + grow));
    let shift = |k: usize| -> ([f64; 2], [f64; 2]) {
        let (a, z) = (pts[k], pts[(k + 1) % n]);
        if kinds[k] != Edge::Open {
            return (a, z);
        }
        let (dx, dy) = (z[0] - a[0], z[1] - a[1]);
        let len = dx.hypot(dy);
        let o = [out * dy / len, -out * dx / len];
        ([a[0] + o[0], a[1] + o[1]], [z[0] + o[0], z[1] + o[1]])
    };
    // vertices as (point, the edge before it, the edge after it): edges
    // by index into the polygon, box sides as n..n+4
    let corners = [
        [lo[0], lo[1]],
        [hi[0], lo[1]],
        [hi[0], hi[1]],
        [lo[0], hi[1]],
    ];
    let mut ring: Vec<([f64; 2], usize, usize)> = (0..4)
        .map(|k| (corners[k], n + (k + 3) % 4, n + k))
        .collect();
    // and the power bisectors with other open cells nearby, as n+4..
    let extra = bisectors(b, c, &poly, &kinds, reach);
    let plane = |k: usize| match k < n {
        true => shift(k),
        false => (extra[k - n - 4].0, extra[k - n - 4].1),
    };
    for k in (0..n).chain(n + 4..n + 4 + extra.len()) {
        let (a, z) = plane(k);
        let side = |x: [f64; 2]| left_of(a, z, x);
        let mut next = vec![];
        for e in 0..ring.len() {
            let (x, y) = (ring[e], ring[(e + 1) % ring.len()]);
            let (sx, sy) = (side(x.0), side(y.0));
            if sx >= 0.0 {
                next.push(x);
            }
            if (sx >= 0.0) != (sy >= 0.0) {
                let t = sx / (sx - sy);
                let p = [
                    x.0[0] + t * (y.0[0] - x.0[0]),
                    x.0[1] + t * (y.0[1] - x.0[1]),
                ];
                // entering: along edge k before it, the ring's edge after;
                // leaving: the ring's edge before, edge k after
                if sx < 0.0 {
                    next.push((p, k, x.2));
                } else {
                    next.push((p, x.2, k));
                }
            }
        }
        ring = next;
        if ring.len() < 3 {
            return None;
        }
    }
    let mut lines = vec![];
    let mut sides = vec![];
    let mut across = vec![];
    for (v, (p, _, after)) in ring.iter().enumerate() {
        let before = ring[(v + ring.len() - 1) % ring.len()].2;
        // a vertex between consecutive closed edges is the polygon's point
        let closed = |e: usize| e < n && kinds[e] != Edge::Open;
        let l = if closed(before) && closed(*after) && *after == (before + 1) % n {
            b.line(poly[*after])
        } else {
            b.cut.line([p[0], p[1], 0.0], [0.0, 0.0, 1.0])
        };
        lines.push(l);
        if closed(*after) {
            sides.push(b.edge(poly[*after], poly[(*after + 1) % n]));
            across.push(kinds[*after]);
        } else if *after < n {
            let (x, y) = shift(*after);
            sides.push(b.cut.plane(side_plane(x, y)));
            across.push(Edge::Open);
        } else if *after >= n + 4 {
            let (x, y, kind) = extra[*after - n - 4];
            sides.push(b.cut.plane(side_plane(x, y)));
            across.push(kind);
        } else {
            let k = *after - n;
            sides.push(b.cut.plane(side_plane(corners[k], corners[(k + 1) % 4])));
            across.push(Edge::Box);
        }
    }
    Some((lines, sides, across))
}

/// How far past two open cells' bounding boxes their reaches past the
/// cavity's side may go: twice the walls' lean, and where they lean, the
/// larger cell's size.
fn margin(leans: bool, reach: f64, a: ([f64; 2], [f64; 2]), b: ([f64; 2], [f64; 2])) -> f64 {
    let size = |(l, h): ([f64; 2], [f64; 2])| (h[0] - l[0]).hypot(h[1] - l[1]);
    2.0 * reach + f64::from(u8::from(leans)) * size(a).max(size(b))
}

/// Where cell c's reach past the cavity's side may meet another open
/// cell's, the power bisector of their section sites as a half-plane (a,
/// z: kept on the left of a -> z) with that cell across: the section's
/// diagram carried on past the outline, so that open cells share what the
/// leaning walls add without overlapping, and their faces there stay
/// orthogonal to their links. Through the point the two cells share, if
/// any (exactly); left out where either polygon lies across it (rounding).
fn bisectors(
    b: &Build,
    c: usize,
    poly: &[u32],
    kinds: &[Edge],
    reach: f64,
) -> Vec<([f64; 2], [f64; 2], Edge)> {
    let at = |p: u32| b.m.points[p as usize];
    let Some(&(lo, hi)) = b.open[b.world].get(&c) else {
        return vec![];
    };
    let near = |(l, h): ([f64; 2], [f64; 2])| {
        let m = margin(b.leans, reach, (lo, hi), (l, h));
        (0..2).all(|a| l[a] <= hi[a] + m && h[a] >= lo[a] - m)
    };
    let size = (hi[0] - lo[0]).hypot(hi[1] - lo[1]);
    let (sc, wc) = (b.m.sites[c], b.m.weights[c]);
    let mut out = vec![];
    for (&d, &bounds) in &b.open[b.world] {
        let across = kinds.contains(&Edge::Cell(d)) || kinds.contains(&Edge::Line(d));
        if d == c || across || !near(bounds) {
            continue;
        }
        // power_c(y) <= power_d(y) where n . y <= k
        let (sd, wd) = (b.m.sites[d], b.m.weights[d]);
        let n = [2.0 * (sd[0] - sc[0]), 2.0 * (sd[1] - sc[1])];
        let k = sd[0] * sd[0] + sd[1] * sd[1] - sc[0] * sc[0] - sc[1] * sc[1] - wd + wc;
        let nn = n[0] * n[0] + n[1] * n[1];
        if nn == 0.0 {
            continue;
        }
        let a = match poly.iter().find(|p| b.m.cells[d].contains(p)) {
            Some(&p) => at(p),
            None => [n[0] * k / nn, n[1] * k / nn],
        };
        // c's side (n . y <= k) on the left
        let z = [a[0] - n[1], a[1] + n[0]];
        let tol = 1e-9 * nn.sqrt() * size;
        let mine_ok = poly.iter().all(|&y| left_of(a, z, at(y)) >= -tol);
        let theirs_ok = b.m.cells[d].iter().all(|&y| left_of(a, z, at(y)) <= tol);
        if mine_ok && theirs_ok {
            out.push((a, z, Edge::Cell(d)));
        }
    }
    out
}

/// A cell being labelled: section cell c in layer k (the cavity's t-th of
/// nl), its sides' planes and what is across each.
struct At<'s> {
    c: usize,
    k: usize,
    t: usize,
    nl: usize,
    sides: &'s [u32],
    kinds: &'s [Edge],
}

impl At<'_> {
    /// What is across the section side on `plane`, if it is one.
    fn kind(&self, plane: u32) -> Option<Edge> {
        let s = self.sides.iter().position(|&s| s == plane)?;
        Some(self.kinds[s])
    }

    /// The cell across a side on a reflex corner's line, if it is one.
    fn line(&self, plane: u32) -> Option<usize> {
        match self.kind(plane)? {
            Edge::Line(d) => Some(d),
            _ => None,
        }
    }

    /// What lies across the cell's face on one of its section sides: a
    /// cell in its layer, the wellbore, or (the cavity's side) none.
    fn across(&self, plane: u32) -> Across {
        match self.kind(plane) {
            Some(Edge::Wellbore) => Across::Wellbore,
            Some(Edge::Cell(d) | Edge::Line(d)) => Across::Cell(d, self.k),
            _ => Across::Grid(None),
        }
    }
}

impl Build<'_> {
    /// Whether a point lies within column col's walls.
    fn within(&mut self, col: [usize; 2], x: [f64; 3]) -> bool {
        self.column(col).iter().all(|&(id, out)| {
            let e = self.cut.planes[id as usize].eval(x);
            if out {
                e <= 0.0
            } else {
                e >= 0.0
            }
        })
    }

    /// The column across the wall of column `col` that lies in `plane`
    /// (within the welding tolerance), if any.
    fn across_plane(&mut self, col: [usize; 2], plane: u32) -> Option<[usize; 2]> {
        let h = self.cut.planes[plane as usize];
        let sides = self.column(col);
        let tol = self.f.tol();
        walls(col)
            .into_iter()
            .zip(sides)
            .find_map(|((_, other), (id, _))| {
                coplanar(h, self.cut.planes[id as usize], 1e-9, tol)
                    .then_some(other)
                    .flatten()
            })
    }

    /// A polyhedron's box in the section.
    fn footprint(&self, faces: &[CutFace]) -> ([f64; 2], [f64; 2]) {
        let flat: Vec<[f64; 2]> = faces
            .iter()
            .flat_map(|f| f.points.iter())
            .map(|&p| {
                let q = self.cut.points[p as usize];
                [q[0], q[1]]
            })
            .collect();
        crate::geom::bbox(&flat)
    }

    /// A prism's pieces in the cavity's columns (whose outlines' boxes
    /// meet its own): cut by each column's walls.
    fn pieces(
        &mut self,
        faces: &[CutFace],
        boxes: &BTreeMap<[usize; 2], ([f64; 2], [f64; 2])>,
    ) -> Vec<([usize; 2], Vec<CutFace>)> {
        let (lo, hi) = self.footprint(faces);
        let mut pieces = vec![];
        for (&col, &(clo, chi)) in boxes {
            if clo[0] > hi[0] || chi[0] < lo[0] || clo[1] > hi[1] || chi[1] < lo[1] {
                continue;
            }
            let mut piece = faces.to_vec();
            for (id, out) in self.column(col) {
                piece = self.cut.cut(&piece, id, !out);
                if piece.is_empty() {
                    break;
                }
            }
            if !piece.is_empty() {
                pieces.push((col, piece));
            }
        }
        pieces
    }

    /// A piece's faces with what is across each (faces on walls between
    /// the cavity's columns left out); returns whether the site lies
    /// within the column's walls.
    fn label(
        &mut self,
        cav: &Cavity,
        at: &At,
        col: [usize; 2],
        piece: &[CutFace],
        site: [f64; 3],
        out: &mut Vec<(Across, u32, Vec<u32>)>,
    ) -> bool {
        let (cpg, k) = (self.cpg, at.k);
        let sides = self.column(col);
        let wall_ids: Vec<(u32, bool, Option<[usize; 2]>)> = walls(col)
            .into_iter()
            .zip(sides)
            .map(|((_, across), (id, out))| (id, out, across))
            .collect();
        let within = self.within(col, site);
        let grid = |c: Option<Ijk>| {
            Across::Grid(
                c.filter(|x| x[0] < cpg.g.nx && x[1] < cpg.g.ny && x[2] < cpg.g.nz && cpg.live(*x)),
            )
        };
        for face in piece {
            let across = if let Some(&(_, _, other)) = wall_ids.iter().find(|w| w.0 == face.plane) {
                match other {
                    Some(o) if cav.cols.contains(&o) => continue,
                    o => grid(o.map(|[i, j]| [i, j, k])),
                }
            } else if face.plane == self.slabs[at.t] {
                match at.t {
                    0 => grid(k.checked_sub(1).map(|k| [col[0], col[1], k])),
                    _ => Across::Cell(at.c, k - 1),
                }
            } else if face.plane == self.slabs[at.t + 1] {
                match at.t + 1 == at.nl {
                    true => grid(Some([col[0], col[1], k + 1])),
                    false => Across::Cell(at.c, k + 1),
                }
            } else if let Some(d) = at.line(face.plane) {
                // the cell across where the column across is the cavity's
                match self.across_plane(col, face.plane) {
                    Some(o) if !cav.cols.contains(&o) => grid(Some([o[0], o[1], k])),
                    _ => Across::Cell(d, k),
                }
            } else {
                at.across(face.plane)
            };
            out.push((across, face.plane, face.points.clone()));
        }
        within
    }
}

impl Build<'_> {
    /// Twisted layers: a prism's pieces in grid cells (col, k) of the
    /// cavity, cut by each of their pyramids.
    fn cone_pieces(
        &mut self,
        faces: &[CutFace],
        cav: &Cavity,
        k: usize,
    ) -> Result<Vec<([usize; 2], Vec<CutFace>)>, String> {
        let (lo, hi) = self.footprint(faces);
        let mut out = vec![];
        for &col in &cav.cols {
            let cell = [col[0], col[1], k];
            self.cones.of(self.cpg, self.f, &mut self.cut, cell)?;
            for pyr in &self.cones.cells[&cell] {
                if pyr.lo[0] > hi[0] || pyr.hi[0] < lo[0] || pyr.lo[1] > hi[1] || pyr.hi[1] < lo[1]
                {
                    continue;
                }
                let piece = cones::cut_by(&mut self.cut, faces, pyr);
                if !piece.is_empty() {
                    out.push((col, piece));
                }
            }
        }
        Ok(out)
    }

    /// Twisted layers: a piece's faces with what is across each (faces
    /// inside the cell left out); returns whether the site lies in it.
    fn label_cone(
        &mut self,
        cav: &Cavity,
        at: &At,
        col: [usize; 2],
        piece: &[CutFace],
        site: [f64; 3],
        out: &mut Vec<(Across, u32, Vec<u32>)>,
    ) -> bool {
        let cell = [col[0], col[1], at.k];
        for face in piece {
            if self.cones.inner.contains(&face.plane) {
                continue;
            }
            // what lies across this piece of the cell's face: a cell of
            // the cavity (across a throw, in another layer), or the grid
            let across = self
                .cones
                .faces
                .get(&face.plane)
                .and_then(|v| v.iter().find(|x| x.0 == cell).map(|x| x.1));
            let in_cavity =
                |o: &Ijk| cav.cols.contains(&[o[0], o[1]]) && cav.k[0] <= o[2] && o[2] <= cav.k[1];
            let across = match across {
                Some(Some(o)) if in_cavity(&o) && o[2] == at.k => continue,
                Some(Some(o)) if in_cavity(&o) => Across::Cell(at.c, o[2]),
                Some(o) => Across::Grid(o),
                None => at.across(face.plane),
            };
            out.push((across, face.plane, face.points.clone()));
        }
        cones::contains(&self.cut, piece, site)
    }

    /// Twisted layers: the site of section cell c in layer k, halfway
    /// between the layer's top and bottom along the normal through the
    /// section's site, and that length; None where no column of the
    /// cavity lies there.
    fn twisted_site(&self, cav: &Cavity, uv: [f64; 2], k: usize) -> Option<([f64; 3], f64)> {
        let at = |face: usize| {
            cav.cols
                .iter()
                .find_map(|&[i, j]| cones::height(self.cpg, self.f, [i, j, k], face, uv))
        };
        let (top, bottom) = (at(4)?, at(5)?);
        Some(([uv[0], uv[1], 0.5 * (top + bottom)], top - bottom))
    }
}

/// A section cell's outline: its lines, sides, and what is across each.
type Outline = (Vec<u32>, Vec<u32>, Vec<Edge>);

/// What a section's cavities share, made once (per cavity it made a field
/// of 100 wells quadratic: 11% of its time in `edge_owners`).
pub(crate) struct Shared {
    /// Each section edge's cell (`Mesh::edge_owners`).
    pub(super) owner: FastMap<(u32, u32), u32>,
    /// The wells' sites (`Cones::avoid`).
    wells: std::sync::Arc<rstar::RTree<[f64; 2]>>,
}

impl Shared {
    pub(crate) fn new(m: &Mesh, region: &[Region]) -> Shared {
        let wells = (0..m.sites.len())
            .filter(|&c| region.get(c) == Some(&Region::Well))
            .map(|c| m.sites[c])
            .collect();
        Shared {
            owner: m.edge_owners(),
            wells: std::sync::Arc::new(rstar::RTree::bulk_load(wells)),
        }
    }
}

/// Each edge's cell: the section's, under the mirror cells' edges.
#[derive(Clone, Copy)]
struct Owners<'a> {
    base: &'a FastMap<(u32, u32), u32>,
    over: &'a FastMap<(u32, u32), u32>,
}

impl Owners<'_> {
    fn get(&self, e: &(u32, u32)) -> Option<&u32> {
        self.over.get(e).or_else(|| self.base.get(e))
    }
}

/// The cells of a layered cavity, and the cutter holding their points.
pub(crate) fn cells(
    cpg: &Cpg,
    f: &Frame,
    (m, region): (&Mesh, &[Region]),
    shared: &Shared,
    cav: &Cavity,
) -> Result<(Cutter, Vec<Cell>), String> {
    let leans = lean(cpg, f, cav) > f.tol();
    let corners = match leans && !f.twisted {
        true => reflex::corners(m, region, &cav.cells, &shared.owner, &cav.reflex),
        false => vec![],
    };
    // the corners' mirror cells, cells n0.. of the section
    let n0 = m.cells.len();
    let with_mirrors;
    let m = match corners.is_empty() {
        true => m,
        false => {
            with_mirrors = reflex::mirrored(m, &corners);
            &with_mirrors
        }
    };
    let region_of = |c: usize| region.get(c).copied().unwrap_or(Region::Transition);
    let mut b = Build {
        cpg,
        f,
        m,
        cut: Cutter::new(if f.twisted { f.weld() } else { f.tol() }),
        lines: HashMap::new(),
        edges: HashMap::new(),
        walls: HashMap::new(),
        sides: HashMap::new(),
        slabs: vec![],
        open: vec![],
        cones: Cones {
            avoid: shared.wells.clone(),
            ..Cones::default()
        },
        leans,
        over: vec![],
        world: 0,
    };
    b.slabs = slabs(&mut b, cav);
    // the mirror cells' edges over the section's (as `edge_owners` of the
    // mesh with them would give)
    let mirrors = m.edge_owners_from(n0);
    let owner = Owners {
        base: &shared.owner,
        over: &mirrors,
    };
    // from a side moved in by up to the lean (`section::inset`; further at
    // a corner, moved in along both its sides) out to the wall, leaning out
    // as far; twisted layers' corners move along their bisectors (twice)
    let times = if f.twisted { 10.0 } else { 3.0 };
    let reach = times * lean(cpg, f, cav) + 10.0 * f.tol();
    let nl = cav.k[1] - cav.k[0] + 1;
    // the columns' outlines at the cavity's top and bottom, for quick tests
    let boxes: BTreeMap<[usize; 2], ([f64; 2], [f64; 2])> = cav
        .cols
        .iter()
        .map(|&[i, j]| {
            let mut q: Vec<[f64; 2]> = vec![];
            for k in [cav.k[0], cav.k[1]] {
                for p in cpg.corners([i, j, k]) {
                    let t = f.to(p);
                    q.push([t[0], t[1]]);
                }
            }
            ([i, j], crate::geom::bbox(&q))
        })
        .collect();
    let worlds = Worlds::new(&mut b, cav, &corners, n0, &boxes, owner, &region_of);
    let mut cache: HashMap<(usize, usize), Option<Outline>> = HashMap::new();
    let mut out = vec![];
    for c in cav.cells.iter().copied().chain(n0..n0 + corners.len()) {
        for t in 0..nl {
            let w = worlds.of[t];
            if c >= n0 && !worlds.sets[w].contains(&(c - n0)) {
                continue;
            }
            let o = cache.entry((w, c)).or_insert_with(|| {
                b.world = w;
                let inside = |d: u32| worlds.members[w].contains(&(d as usize));
                outline(&mut b, c, &inside, owner, region_of(c), reach)
            });
            let Some(o) = o else {
                continue;
            };
            if let Some(cell) = layer_cell(&mut b, cav, o, c, t, &boxes)? {
                out.push(cell);
            }
        }
    }
    Ok((b.cut, out))
}

/// The planes between a cavity's layers (frame heights); twisted layers:
/// one prism through the whole cavity (cut by the grid cells' pyramids).
fn slabs(b: &mut Build, cav: &Cavity) -> Vec<u32> {
    let (f, cpg) = (b.f, b.cpg);
    let heights = match f.twisted {
        true => {
            // over every cell of the cavity (beside a throw the frame's own
            // columns are not the highest or lowest)
            let [mut top, mut bottom] = f.ends();
            for &[i, j] in &cav.cols {
                for k in cav.k[0]..=cav.k[1] {
                    for p in cpg.corners([i, j, k]) {
                        let h = f.to(p)[2];
                        (top, bottom) = (top.max(h), bottom.min(h));
                    }
                }
            }
            vec![top + 0.1 * f.size, bottom - 0.1 * f.size]
        }
        false => f.h.clone(),
    };
    heights
        .iter()
        .map(|&h| {
            b.cut.plane(Halfspace {
                n: [0.0, 0.0, 1.0],
                c: h,
            })
        })
        .collect()
}

/// The cavity's cells in each layer with reflex corners' mirror cells
/// (`reflex`): a mirror cell is in a layer where its site is within the
/// cavity's columns (the strip it fills narrows to nothing at one end of
/// the cavity); each set of corners with mirrors is a world, with its own
/// open cells and outlines.
struct Worlds {
    /// Per layer, its world.
    of: Vec<usize>,
    /// Per world, the corners with mirrors and the section cells.
    sets: Vec<BTreeSet<usize>>,
    members: Vec<BTreeSet<usize>>,
}

impl Worlds {
    fn new(
        b: &mut Build,
        cav: &Cavity,
        corners: &[reflex::Corner],
        n0: usize,
        boxes: &BTreeMap<[usize; 2], ([f64; 2], [f64; 2])>,
        owner: Owners,
        region: &dyn Fn(usize) -> Region,
    ) -> Worlds {
        let (f, m) = (b.f, b.m);
        let nl = cav.k[1] - cav.k[0] + 1;
        let mut w = Worlds {
            of: vec![],
            sets: vec![],
            members: vec![],
        };
        for t in 0..nl {
            let h = 0.5 * (f.h[t] + f.h[t + 1]);
            let set: BTreeSet<usize> = (0..corners.len())
                .filter(|&i| {
                    let s = m.sites[n0 + i];
                    let x = [s[0], s[1], h];
                    boxes
                        .iter()
                        .filter(|(_, (lo, hi))| (0..2).all(|a| lo[a] <= x[a] && x[a] <= hi[a]))
                        .any(|(&c, _)| b.within(c, x))
                })
                .collect();
            let at = w.sets.iter().position(|s| *s == set).unwrap_or_else(|| {
                w.sets.push(set);
                w.sets.len() - 1
            });
            w.of.push(at);
        }
        for set in &w.sets {
            let mut members: BTreeSet<usize> = cav.cells.iter().copied().collect();
            members.extend(set.iter().map(|&i| n0 + i));
            let mut over = HashMap::new();
            for &i in set {
                let k = &corners[i];
                for (c, other) in [(k.g, n0 + i), (n0 + i, k.g)] {
                    let poly = &m.cells[c];
                    for e in 0..poly.len() {
                        let (u, v) = (poly[e], poly[(e + 1) % poly.len()]);
                        if [u, v] == [k.p, k.x] || [u, v] == [k.x, k.p] {
                            over.insert((u, v), Edge::Line(other));
                        }
                    }
                }
            }
            let mut open = BTreeMap::new();
            for &c in &members {
                let poly = &m.cells[c];
                let n = poly.len();
                let closed = |k: usize| {
                    let (p, q) = (poly[k], poly[(k + 1) % n]);
                    let d = owner.get(&(q, p)).map(|&d| d as usize);
                    over.contains_key(&(p, q)) || d.is_some_and(|d| members.contains(&d))
                };
                if region(c) != Region::Well && !(0..n).all(closed) {
                    let pts: Vec<[f64; 2]> = poly.iter().map(|&p| m.points[p as usize]).collect();
                    open.insert(c, crate::geom::bbox(&pts));
                }
            }
            b.over.push(over);
            b.open.push(open);
            w.members.push(members);
        }
        w
    }
}

/// Section cell c's prism in layer t of the cavity (its outline `o`), cut
/// by the walls of the cavity's columns (or the grid cells' pyramids), its
/// faces labelled; None where the prism is empty.
fn layer_cell(
    b: &mut Build,
    cav: &Cavity,
    o: &Outline,
    c: usize,
    t: usize,
    boxes: &BTreeMap<[usize; 2], ([f64; 2], [f64; 2])>,
) -> Result<Option<Cell>, String> {
    let (f, m) = (b.f, b.m);
    let (lines, sides, kinds) = o;
    let nl = cav.k[1] - cav.k[0] + 1;
    let k = cav.k[0] + t;
    let slab = if f.twisted { 0 } else { t };
    let Some(faces) = b.cut.prism(lines, sides, b.slabs[slab + 1], b.slabs[slab]) else {
        return Ok(None);
    };
    let site2 = m.sites[c];
    // at the layer's mean height, so that links within a layer are
    // orthogonal; where twisted layers leave that outside the cell,
    // halfway between its top and bottom there
    let flat = [site2[0], site2[1], 0.5 * (f.h[t] + f.h[t + 1])];
    let local = f.twisted.then(|| b.twisted_site(cav, site2, k)).flatten();
    let span = local.map_or(f.h[t] - f.h[t + 1], |l| l.1);
    let mut inside_site = false;
    let mut labelled: Vec<(Across, u32, Vec<u32>)> = vec![];
    let at = At {
        c,
        k,
        t,
        nl,
        sides,
        kinds,
    };
    let mut site = flat;
    if f.twisted {
        let pieces = b.cone_pieces(&faces, cav, k)?;
        let holds = |x: [f64; 3]| pieces.iter().any(|(_, p)| cones::contains(&b.cut, p, x));
        if let Some((mid, _)) = local.filter(|_| !holds(flat)) {
            site = mid;
        }
        for (col, piece) in &pieces {
            inside_site |= b.label_cone(cav, &at, *col, piece, site, &mut labelled);
        }
    } else {
        for (col, piece) in &b.pieces(&faces, boxes) {
            inside_site |= b.label(cav, &at, *col, piece, site, &mut labelled);
        }
    }
    let merged = join::merge(labelled, &b.cut.points, f.weld());
    Ok(Some(Cell {
        c,
        k,
        faces: merged,
        site,
        span,
        inside: inside_site,
    }))
}

/// How far the cavity's walls stray from the section's outline within its
/// layers: the largest distance, across the layers, between a pillar's
/// crossing of the section and of the cavity's top or bottom.
fn lean(cpg: &Cpg, f: &Frame, cav: &Cavity) -> f64 {
    let g = cpg.g;
    let [top, bottom] = f.ends();
    let at = 0.5 * (top + bottom);
    let mut most: f64 = 0.0;
    for &[i, j] in &cav.cols {
        for (n, (di, dj)) in [(0, 0), (1, 0), (0, 1), (1, 1)].into_iter().enumerate() {
            let c = g.coord[(j + dj) * (g.nx + 1) + i + di];
            let m = f.crossing(c, at);
            // twisted layers: to the cavity's own corners on the pillar
            let ends = match f.twisted {
                true => [
                    f.to(cpg.corner([i, j, cav.k[0]], n)),
                    f.to(cpg.corner([i, j, cav.k[1]], n + 4)),
                ]
                .map(|q| [q[0], q[1]]),
                false => [top, bottom].map(|h| f.crossing(c, h)),
            };
            for x in ends {
                most = most.max((x[0] - m[0]).hypot(x[1] - m[1]));
            }
        }
    }
    most
}
