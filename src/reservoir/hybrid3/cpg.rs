//! Corner-point cells as polyhedra in the mesh's frame (x, y, z up =
//! minus depth): their faces, each planar and convex kept whole, else two
//! triangles along a diagonal both cells across choose alike; the
//! neighbour across each face, past pinched-out cells; and which cell
//! holds a point.

use crate::error::{Error, Result};
use crate::geom::{in_solid, newell, orient, orient3};
use crate::reservoir::grid::FACES;
use crate::reservoir::CornerPointGrid;
use std::cmp::Ordering;

/// A cell (i, j, k), 0-based.
pub(super) type Ijk = [usize; 3];

/// The corner across face f that matches corner c of this cell.
fn across(f: usize, c: usize) -> usize {
    match f {
        0 | 1 => c ^ 1,
        2 | 3 => c ^ 2,
        _ => c ^ 4,
    }
}

/// The grid's cells as polyhedra.
pub(super) struct Cpg<'g> {
    pub(super) g: &'g CornerPointGrid,
    /// Per pillar (j (nx + 1) + i), the depths of every cell's corners on
    /// it, sorted and distinct.
    pub(super) pillars: Vec<Vec<f64>>,
    /// Per column face, whether the cells on its two sides differ in a
    /// corner there (a throw): the I faces (j (nx + 1) + i, between columns
    /// i - 1 and i), then the J faces (nx (ny + 1) of them, j nx + i).
    thrown: Vec<bool>,
    /// The faces FAULTS names, (cell, face), from both sides.
    faults: std::collections::BTreeSet<(Ijk, usize)>,
    /// Per column (j nx + i), whether its tops and bottoms are split along
    /// the diagonal between its pillars (i + 1, j) and (i, j + 1) rather
    /// than (i, j) and (i + 1, j + 1) (`diagonals`).
    other_diagonal: Vec<bool>,
}

impl<'g> Cpg<'g> {
    /// The grid's cells, with its pillars' depths and its throws.
    pub(super) fn new(g: &'g CornerPointGrid) -> Cpg<'g> {
        let (nx, ny, nz) = (g.nx, g.ny, g.nz);
        let mut pillars = vec![vec![]; (nx + 1) * (ny + 1)];
        for k in 0..nz {
            for j in 0..ny {
                for i in 0..nx {
                    for c in 0..8 {
                        let (di, dj) = (c & 1, (c >> 1) & 1);
                        pillars[(j + dj) * (nx + 1) + i + di].push(g.depth(i, j, k, c));
                    }
                }
            }
        }
        for p in &mut pillars {
            p.sort_by(f64::total_cmp);
            p.dedup();
        }
        // the corners of the cells on either side of a column face that
        // must agree: (this side's, that side's)
        let differ = |a: [usize; 2], b: [usize; 2], mine: [usize; 4], theirs: [usize; 4]| {
            (0..nz).any(|k| {
                (0..4).any(|n| g.depth(a[0], a[1], k, mine[n]) != g.depth(b[0], b[1], k, theirs[n]))
            })
        };
        let mut thrown = vec![false; (nx + 1) * ny + nx * (ny + 1)];
        for j in 0..ny {
            for i in 1..nx {
                thrown[j * (nx + 1) + i] = differ([i - 1, j], [i, j], [1, 3, 5, 7], [0, 2, 4, 6]);
            }
        }
        for j in 1..ny {
            for i in 0..nx {
                thrown[(nx + 1) * ny + j * nx + i] =
                    differ([i, j - 1], [i, j], [2, 3, 6, 7], [0, 1, 4, 5]);
            }
        }
        let mut faults = std::collections::BTreeSet::new();
        for face in g.faults.iter().flat_map(|f| &f.faces) {
            let f = face.side();
            for k in face.k[0]..=face.k[1].min(nz.saturating_sub(1)) {
                for j in face.j[0]..=face.j[1].min(ny.saturating_sub(1)) {
                    for i in face.i[0]..=face.i[1].min(nx.saturating_sub(1)) {
                        faults.insert(([i, j, k], f));
                        if let Some(n) = next(g, [i, j, k], f) {
                            faults.insert((n, f ^ 1));
                        }
                    }
                }
            }
        }
        Cpg {
            g,
            pillars,
            thrown,
            faults,
            other_diagonal: diagonals(g),
        }
    }

    /// Whether FAULTS names face f of cell c (from either side).
    pub(super) fn on_fault(&self, c: Ijk, f: usize) -> bool {
        self.faults.contains(&(c, f))
    }

    /// Whether column face f (0..4) of column (i, j) lies on a throw.
    pub(super) fn is_thrown(&self, [i, j]: [usize; 2], f: usize) -> bool {
        let nx = self.g.nx;
        match f {
            0 => self.thrown[j * (nx + 1) + i],
            1 => self.thrown[j * (nx + 1) + i + 1],
            2 => self.thrown[(nx + 1) * self.g.ny + j * nx + i],
            _ => self.thrown[(nx + 1) * self.g.ny + (j + 1) * nx + i],
        }
    }

    /// Corner c of cell (i, j, k) in the mesh's frame.
    pub(super) fn corner(&self, [i, j, k]: Ijk, c: usize) -> [f64; 3] {
        let [x, y, depth] = self.g.corner(i, j, k, c);
        [x, y, -depth]
    }

    /// The cell's eight corners.
    pub(super) fn corners(&self, c: Ijk) -> [[f64; 3]; 8] {
        std::array::from_fn(|n| self.corner(c, n))
    }

    /// Whether the cell has no thickness: each top corner on its bottom one.
    pub(super) fn pinched(&self, c: Ijk) -> bool {
        (0..4).all(|n| self.corner(c, n) == self.corner(c, n + 4))
    }

    /// Whether the cell is meshed: active and not pinched out.
    pub(super) fn live(&self, c: Ijk) -> bool {
        self.g.active(c[0], c[1], c[2]) && !self.pinched(c)
    }

    /// Face f's corners, outward.
    pub(super) fn face(&self, c: Ijk, f: usize) -> [[f64; 3]; 4] {
        let p = self.corners(c);
        let mut q = FACES[f].map(|n| p[n]);
        if self.left_handed() {
            q.reverse();
        }
        q
    }

    /// Whether the grid's cells are left-handed (their FACES turn inward),
    /// decided on the first pillars' layout.
    pub(super) fn left_handed(&self) -> bool {
        let g = self.g;
        let p = |i: usize, j: usize| {
            let c = g.coord[j * (g.nx + 1) + i];
            [c[0], c[1]]
        };
        orient(p(0, 0), p(1, 0), p(0, 1)) == Ordering::Less
    }

    /// The live cell across face f, when the faces match exactly (past
    /// pinched-out cells across the top and bottom); None on the grid's
    /// boundary or beside an inactive cell; an error where the faces do not
    /// match (a fault's throw, a gap between layers).
    pub(super) fn neighbour(&self, c: Ijk, f: usize) -> Result<Option<Ijk>> {
        let step = |n: Ijk| next(self.g, n, f);
        let mut n = c;
        loop {
            let Some(next) = step(n) else { return Ok(None) };
            n = next;
            if f < 4 || !self.pinched(n) {
                break;
            }
        }
        let matches = FACES[f]
            .iter()
            .all(|&m| self.corner(c, m) == self.corner(n, across(f, m)));
        if !matches {
            // Between columns, a throw (`parts` cuts the face there);
            // across layers, a gap or an overlap.
            return Err(Error::Usage(format!(
                "cells {} and {} do not share their face: {}",
                one_based(c),
                one_based(n),
                match f {
                    0..4 => "a throw",
                    _ => "a gap or an overlap between layers, which the 3D hybrid needs to meet around its cavities",
                }
            )));
        }
        Ok(self.g.active(n[0], n[1], n[2]).then_some(n))
    }

    /// The shorter side of a cell's top, in map view.
    pub(super) fn side(&self, c: Ijk) -> f64 {
        let top = self.face(c, 4);
        (0..4)
            .map(|k| {
                let (a, b) = (top[k], top[(k + 1) % 4]);
                (a[0] - b[0]).hypot(a[1] - b[1])
            })
            .fold(f64::INFINITY, f64::min)
    }

    /// The cell's site: the mean of its corners.
    pub(super) fn centre(&self, c: Ijk) -> [f64; 3] {
        let p = self.corners(c);
        std::array::from_fn(|a| p.iter().map(|q| q[a]).sum::<f64>() / 8.0)
    }

    /// Face f's corners, outward, and its pieces (`pieces`): a top or
    /// bottom that is split is split along its column's diagonal
    /// (`diagonals`), so that a cell's top and bottom, and the cells above
    /// and below, take the same diagonal and a thin cell's two surfaces
    /// cannot cross where its top twists; unless the face itself is
    /// concave, then through its reflex corner.
    pub(super) fn face_pieces(&self, c: Ijk, f: usize) -> ([[f64; 3]; 4], Vec<Vec<usize>>) {
        let q = self.face(c, f);
        // corner 0 (top) or 4 (bottom) is first in FACES, last reversed;
        // the other diagonal is through the next
        let first = if self.left_handed() { 3 } else { 0 };
        let other = usize::from(self.other_diagonal[c[1] * self.g.nx + c[0]]);
        let through = (f >= 4).then_some((first + other) % 4);
        let p = pieces(&q, through);
        (q, p)
    }

    /// The corners of the diagonal its column's tops are split along
    /// (`diagonals`); the bottoms' are these plus 4.
    pub(super) fn diagonal(&self, c: Ijk) -> [usize; 2] {
        match self.other_diagonal[c[1] * self.g.nx + c[0]] {
            true => [1, 2],
            false => [0, 3],
        }
    }

    /// The triangles of the pieces of the cell's faces, outward.
    fn triangles_of(&self, c: Ijk) -> Vec<[[f64; 3]; 3]> {
        let mut out = vec![];
        for f in 0..6 {
            let (q, p) = self.face_pieces(c, f);
            for t in p {
                out.extend(triangles(&t).into_iter().map(|w| w.map(|n| q[n])));
            }
        }
        out
    }

    /// Where the cell is inverted: the first of its four pillars (as
    /// corner 0..4) at which its top lies below its bottom. Eclipse's
    /// cells are valid where the top is at or above the bottom at every
    /// pillar, however thin, wide, sheared or twisted they are.
    pub(super) fn inverted(&self, c: Ijk) -> Option<usize> {
        (0..4).find(|&n| self.g.depth(c[0], c[1], c[2], n) > self.g.depth(c[0], c[1], c[2], n + 4))
    }

    /// The pillar (i, j) of the cell's corner n, 1-based for messages.
    pub(super) fn pillar_name(&self, [i, j, _]: Ijk, n: usize) -> String {
        format!("({}, {})", i + 1 + (n & 1), j + 1 + ((n >> 1) & 1))
    }

    /// The cell holding p among the given live cells, if any: exactly, by
    /// the parity of a ray's crossings of its faces' pieces (no assumption
    /// on the cell's shape; a point on a face is in).
    pub(super) fn locate(&self, p: [f64; 3], cells: impl IntoIterator<Item = Ijk>) -> Option<Ijk> {
        cells.into_iter().find(|&c| {
            // outside the box of its corners is outside (a cheap first test:
            // walks along wells try every cell of their layers)
            let k = self.corners(c);
            let off = |a: usize| {
                let (lo, hi) = k
                    .iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), q| {
                        (lo.min(q[a]), hi.max(q[a]))
                    });
                p[a] < lo || p[a] > hi
            };
            !(0..3).any(off) && in_solid(&self.triangles_of(c), p)
        })
    }
}

/// The cell across face f of cell c, if the grid has one there.
pub(super) fn next(g: &CornerPointGrid, [i, j, k]: Ijk, f: usize) -> Option<Ijk> {
    match f {
        0 => i.checked_sub(1).map(|i| [i, j, k]),
        1 => (i + 1 < g.nx).then_some([i + 1, j, k]),
        2 => j.checked_sub(1).map(|j| [i, j, k]),
        3 => (j + 1 < g.ny).then_some([i, j + 1, k]),
        4 => k.checked_sub(1).map(|k| [i, j, k]),
        _ => (k + 1 < g.nz).then_some([i, j, k + 1]),
    }
}

/// Lexicographic order of points.
pub(super) fn lex(a: &[f64; 3], b: &[f64; 3]) -> Ordering {
    a.iter()
        .zip(b)
        .map(|(x, y)| x.total_cmp(y))
        .find(|o| o.is_ne())
        .unwrap_or(Ordering::Equal)
}

/// (i, j, k) 1-based for messages.
pub(super) fn one_based([i, j, k]: Ijk) -> String {
    format!("({}, {}, {})", i + 1, j + 1, k + 1)
}

/// A face's pieces, as indices of its corners: none where it has no area;
/// the face whole where it is planar and strictly convex (after merging
/// coincident corners); else two triangles along the diagonal through
/// corner `through`, or where it is None through the smallest corner (by
/// coordinates): either way the cell across picks the same.
pub(super) fn pieces(q: &[[f64; 3]; 4], through: Option<usize>) -> Vec<Vec<usize>> {
    // the corners left after merging coincident neighbours
    let mut v: Vec<usize> = vec![];
    for n in 0..4 {
        if v.last().is_none_or(|&l| q[l] != q[n]) {
            v.push(n);
        }
    }
    while v.len() > 1 && q[v[0]] == q[*v.last().unwrap_or(&0)] {
        v.pop();
    }
    match v.len() {
        0..=2 => vec![],
        3 => {
            let n = newell(&[q[v[0]], q[v[1]], q[v[2]]]);
            if n == [0.0; 3] {
                vec![]
            } else {
                vec![v]
            }
        }
        _ => {
            let planar = orient3(q[0], q[1], q[2], q[3]) == Ordering::Equal;
            if planar && strictly_convex(q) {
                return vec![vec![0, 1, 2, 3]];
            }
            // (a quad concave in its view along its normal folds when split
            // along the other diagonal: emerald's cells at its edge)
            let least = reflex(q)
                .or(through)
                .unwrap_or_else(|| (0..4).min_by(|&a, &b| lex(&q[a], &q[b])).unwrap_or(0));
            let (a, b, c, d) = (least, (least + 1) % 4, (least + 2) % 4, (least + 3) % 4);
            vec![vec![a, b, c], vec![a, c, d]]
                .into_iter()
                .filter(|t| newell(&[q[t[0]], q[t[1]], q[t[2]]]) != [0.0; 3])
                .collect()
        }
    }
}

/// Per column, whether its tops and bottoms take the diagonal between
/// its pillars (i + 1, j) and (i, j + 1): where its outline halfway down
/// its pillars, seen from above, is concave or straight at one of them, or
/// convex with
/// that diagonal Delaunay and the other not (exactly). Else (0, 0) to
/// (1, 1), ties included: a rectangle's keeps it. (A diagonal across a
/// nearly straight corner makes a sliver triangle, under which the side
/// faces at that corner cross the top: emerald's edge columns.)
fn diagonals(g: &CornerPointGrid) -> Vec<bool> {
    let (nx, ny) = (g.nx, g.ny);
    let mid = |i: usize, j: usize| {
        let c = g.coord[j * (nx + 1) + i];
        [(c[0] + c[3]) / 2.0, (c[1] + c[4]) / 2.0]
    };
    let mut out = Vec::with_capacity(nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            // around the outline: corners 0, 1, 3, 2 (pillars (i, j),
            // (i + 1, j), (i + 1, j + 1), (i, j + 1))
            let p = [mid(i, j), mid(i + 1, j), mid(i + 1, j + 1), mid(i, j + 1)];
            let turns = turns(p);
            let left = turns.iter().filter(|&&t| t == Ordering::Greater).count();
            let right = turns.iter().filter(|&&t| t == Ordering::Less).count();
            let other = match (left, right) {
                (4, 0) | (0, 4) => in_circle(p[0], p[1], p[2], p[3]),
                (3, 1) => turns[1] == Ordering::Less || turns[3] == Ordering::Less,
                (1, 3) => turns[1] == Ordering::Greater || turns[3] == Ordering::Greater,
                // a straight corner: the diagonal through it
                (l, r) if l + r == 3 => turns[1] == Ordering::Equal || turns[3] == Ordering::Equal,
                _ => false,
            };
            out.push(other);
        }
    }
    out
}

/// Whether d lies strictly inside the circle through a, b, c (exactly).
fn in_circle(a: [f64; 2], b: [f64; 2], c: [f64; 2], d: [f64; 2]) -> bool {
    use crate::geom::{det3_q, q};
    let row = |p: [f64; 2]| {
        let (x, y) = (q(p[0]) - q(d[0]), q(p[1]) - q(d[1]));
        let r = &x * &x + &y * &y;
        [x, y, r]
    };
    let (ra, rb, rc) = (row(a), row(b), row(c));
    let det = det3_q([
        [&ra[0], &ra[1], &ra[2]],
        [&rb[0], &rb[1], &rb[2]],
        [&rc[0], &rc[1], &rc[2]],
    ]);
    match orient(a, b, c) {
        Ordering::Greater => crate::geom::is_pos(&det),
        Ordering::Less => crate::geom::is_pos(&-det),
        Ordering::Equal => false,
    }
}

/// The one corner where a quadrilateral, seen along its Newell normal,
/// turns against the other three (exactly): only the diagonal through it
/// lies inside. None where it turns one way (convex), or two and two (a
/// bow tie), or straight somewhere.
fn reflex(q: &[[f64; 3]; 4]) -> Option<usize> {
    let turns = turns(flat(q));
    if turns.contains(&Ordering::Equal) {
        return None;
    }
    let left = turns.iter().filter(|&&t| t == Ordering::Greater).count();
    let odd = match left {
        1 => Ordering::Greater,
        3 => Ordering::Less,
        _ => return None,
    };
    turns.iter().position(|&t| t == odd)
}

/// Whether a planar quadrilateral turns one way at every corner.
fn strictly_convex(q: &[[f64; 3]; 4]) -> bool {
    let turns = turns(flat(q));
    turns[0] != Ordering::Equal && turns.iter().all(|&t| t == turns[0])
}

/// A quadrilateral seen along its Newell normal (its largest axis dropped).
fn flat(q: &[[f64; 3]; 4]) -> [[f64; 2]; 4] {
    let n = newell(q);
    let axis = (0..3)
        .max_by(|&a, &b| n[a].abs().total_cmp(&n[b].abs()))
        .unwrap_or(2);
    q.map(|p| crate::geom::drop_axis(axis, p))
}

/// The way a quadrilateral turns at each corner (exactly).
fn turns(p: [[f64; 2]; 4]) -> [Ordering; 4] {
    std::array::from_fn(|k| orient(p[(k + 3) % 4], p[k], p[(k + 1) % 4]))
}

/// A piece's fan of triangles.
fn triangles(t: &[usize]) -> Vec<[usize; 3]> {
    (1..t.len() - 1).map(|k| [t[0], t[k], t[k + 1]]).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_box_has_six_whole_faces_and_matching_neighbours() {
        let g = CornerPointGrid::cartesian([2, 2, 2], [10.0, 10.0, 4.0]);
        let cpg = Cpg::new(&g);
        for f in 0..6 {
            let q = cpg.face([0, 0, 0], f);
            assert_eq!(cpg.face_pieces([0, 0, 0], f).1, vec![vec![0, 1, 2, 3]]);
            // outward: the Newell normal points away from the centre
            let n = newell(&q);
            let o = cpg.centre([0, 0, 0]);
            let out: f64 = (0..3).map(|a| n[a] * (q[0][a] - o[a])).sum();
            assert!(out > 0.0, "face {f}");
        }
        assert_eq!(cpg.neighbour([0, 0, 0], 1).unwrap(), Some([1, 0, 0]));
        assert_eq!(cpg.neighbour([0, 0, 0], 0).unwrap(), None);
        assert_eq!(cpg.neighbour([0, 0, 0], 5).unwrap(), Some([0, 0, 1]));
        assert_eq!(
            cpg.locate([5.0, 5.0, -6.0], [[0, 0, 0], [0, 0, 1]]),
            Some([0, 0, 1])
        );
        assert_eq!(cpg.locate([15.0, 5.0, -6.0], [[0, 0, 0], [0, 0, 1]]), None);
        assert_eq!(cpg.inverted([1, 1, 1]), None);
    }

    /// A cell whose top corner sinks below its bottom is inverted there,
    /// named by its pillar.
    #[test]
    fn an_inverted_cell_is_found_with_its_pillar() {
        let mut g = CornerPointGrid::cartesian([1, 1, 1], [10.0, 10.0, 4.0]);
        let cpg = Cpg::new(&g);
        assert_eq!(cpg.inverted([0, 0, 0]), None);
        g.zcorn[1] = 9.0; // top corner 1, 5 below the bottom
        let cpg = Cpg::new(&g);
        assert_eq!(cpg.inverted([0, 0, 0]), Some(1));
        assert_eq!(cpg.pillar_name([0, 0, 0], 1), "(2, 1)");
    }

    /// A thin wide cell whose top twists by more than its thickness (as
    /// on real fields' leaning pillars) is valid: its top and bottom are
    /// split along the same diagonal, so they never cross, and points in
    /// it are found although it is not star-shaped from its centre.
    #[test]
    fn a_thin_twisted_cell_is_located() {
        let mut g = CornerPointGrid::cartesian([1, 1, 1], [150.0, 150.0, 3.0]);
        // corners 0 and 3 (one diagonal) 10 m deeper than 1 and 2, top and bottom
        for (n, d) in [(0, 10.0), (3, 10.0), (1, 0.0), (2, 0.0)] {
            g.zcorn[n] += d;
            g.zcorn[4 + n] += d;
        }
        let cpg = Cpg::new(&g);
        assert_eq!(cpg.inverted([0, 0, 0]), None);
        let tris = cpg.triangles_of([0, 0, 0]);
        // a closed surface: every oriented edge has its opposite
        let key = |p: [f64; 3]| p.map(f64::to_bits);
        let mut edges: Vec<([u64; 3], [u64; 3])> = vec![];
        for t in &tris {
            for k in 0..3 {
                edges.push((key(t[k]), key(t[(k + 1) % 3])));
            }
        }
        for &(a, b) in &edges {
            assert!(edges.contains(&(b, a)));
        }
        // under the column's middle, on the split diagonal 0-3, the cell
        // spans depths 10 to 13; its centre (mean of the corners, depth
        // 6.5) is outside it
        let at = |d: f64| [75.0, 75.0, -d];
        assert_eq!(cpg.locate(at(11.5), [[0, 0, 0]]), Some([0, 0, 0]));
        assert_eq!(cpg.locate(at(6.5), [[0, 0, 0]]), None);
        assert_eq!(cpg.locate(at(13.5), [[0, 0, 0]]), None);
    }

    #[test]
    fn tops_split_along_the_diagonal_inside_the_column() {
        // the column's outline: corners 0 (0, 0), 1, 3 (150, 150), 2 (0, 150)
        let top_pieces = |x: f64, y: f64| {
            let mut g = CornerPointGrid::cartesian([1, 1, 1], [150.0, 150.0, 3.0]);
            g.coord[1] = [x, y, 0.0, x, y, 3.0];
            // (corner 0 a metre down: a twisted top, split)
            g.zcorn[0] += 1.0;
            Cpg::new(&g).face_pieces([0, 0, 0], 4).1
        };
        // (face 4's corners in order are the cell's 0, 1, 3, 2)
        let other = vec![vec![1, 2, 3], vec![1, 3, 0]];
        let first = vec![vec![0, 1, 2], vec![0, 2, 3]];
        // concave at corner 1: only the diagonal 1-2 lies inside
        assert_eq!(top_pieces(50.0, 70.0), other);
        // convex but nearly straight at corner 1: the Delaunay diagonal,
        // not a sliver under which the sides at that corner cross the top
        assert_eq!(top_pieces(75.0, 74.9), other);
        // a square's tie, and a convex outline Delaunay either way, keep
        // the diagonal 0-3 (a twisted top, so that it is split)
        let mut g = CornerPointGrid::cartesian([1, 1, 1], [150.0, 150.0, 3.0]);
        g.zcorn[0] += 1.0;
        assert_eq!(Cpg::new(&g).face_pieces([0, 0, 0], 4).1, first);
        // the bottoms alike
        assert_eq!(Cpg::new(&g).diagonal([0, 0, 0]), [0, 3]);
    }

    #[test]
    fn pinched_out_cells_are_skipped_across() {
        // layer 2 of 3 has no thickness: layers 1 and 3 meet across it
        let g = CornerPointGrid::layered([1, 1], [10.0, 10.0], &[0.0, 4.0, 4.0, 9.0]);
        let cpg = Cpg::new(&g);
        assert!(cpg.pinched([0, 0, 1]) && !cpg.live([0, 0, 1]));
        assert_eq!(cpg.neighbour([0, 0, 0], 5).unwrap(), Some([0, 0, 2]));
        assert_eq!(cpg.neighbour([0, 0, 2], 4).unwrap(), Some([0, 0, 0]));
        // a gap between layers is no shared face: an error naming both cells
        let mut gap = g.clone();
        for r in 0..4 {
            gap.zcorn[4 * 4 + r] = 5.0; // layer 3's top 1 m below layer 1's bottom
            gap.zcorn[2 * 4 + r] = 5.0; // (and layer 2 pinched there)
            gap.zcorn[3 * 4 + r] = 5.0;
        }
        let e = Cpg::new(&gap)
            .neighbour([0, 0, 0], 5)
            .unwrap_err()
            .to_string();
        assert!(e.contains("(1, 1, 1) and (1, 1, 3)"), "{e}");
    }

    #[test]
    fn a_twisted_face_splits_alike_from_both_sides() {
        let q = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.3],
            [0.0, 1.0, 0.0],
        ];
        let mine: Vec<Vec<[f64; 3]>> = pieces(&q, None)
            .iter()
            .map(|t| t.iter().map(|&n| q[n]).collect())
            .collect();
        // the cell across sees the corners the other way round
        let r = [q[2], q[1], q[0], q[3]];
        let theirs: Vec<Vec<[f64; 3]>> = pieces(&r, None)
            .iter()
            .map(|t| t.iter().map(|&n| r[n]).collect())
            .collect();
        assert_eq!(mine.len(), 2);
        let key = |t: &Vec<[f64; 3]>| {
            let mut k: Vec<[u64; 3]> = t.iter().map(|p| p.map(f64::to_bits)).collect();
            k.sort_unstable();
            k
        };
        let mut a: Vec<_> = mine.iter().map(key).collect();
        let mut b: Vec<_> = theirs.iter().map(key).collect();
        a.sort();
        b.sort();
        assert_eq!(a, b);
        // a pinched face: two corners coincide, one triangle
        let p = [q[0], q[1], q[1], q[3]];
        assert_eq!(pieces(&p, None).len(), 1);
        assert!(pieces(&[q[0], q[0], q[1], q[1]], None).is_empty());
    }
}
