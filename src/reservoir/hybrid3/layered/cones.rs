//! Twisted layers (emerald: leaning pillars, tops off their planes by up
//! to a metre): a grid cell is the union of convex pyramids, one per
//! planar piece of its faces (`Cpg::parts`: cut where cells across a throw meet them), their apex halfway
//! between the diagonals its top and bottom are split along (inside
//! however thin and twisted the cell is), away from the wells. Cutting a prism of the section
//! by each pyramid cuts it along the grid's own faces into convex pieces
//! (`cells`); the heights of a cell's top and bottom at a point of the
//! section place its site.

use super::super::cpg::{Cpg, Ijk};
use super::frame::Frame;
use crate::geom::{cross_f, dot_f, CutFace, Cutter, Halfspace};
use std::collections::{HashMap, HashSet};

/// A pyramid: its planes, each with whether its outside is kept (the
/// apex or the base on the plane's outside), and its box in the section.
pub(super) struct Pyramid {
    pub(super) planes: Vec<(u32, bool)>,
    pub(super) lo: [f64; 2],
    pub(super) hi: [f64; 2],
}

/// The pyramids of the cavity's cells, planes in a cutter.
#[derive(Default)]
pub(super) struct Cones {
    /// Face pieces' planes, by their corners (bits, sorted): one plane for
    /// the two cells a piece lies between.
    pub(super) by_corners: HashMap<Vec<[u64; 3]>, u32>,
    /// Per face piece's plane, the cells it bounds and the live cell across.
    pub(super) faces: HashMap<u32, Vec<(Ijk, Option<Ijk>)>>,
    /// The pyramids' sides (inside their cells).
    pub(super) inner: HashSet<u32>,
    pub(super) cells: HashMap<Ijk, Vec<Pyramid>>,
    /// Section points the apexes keep away from (the wells: where every
    /// pyramid's sides meet, a ring cell would be cut to slivers), one tree
    /// for the section's cavities.
    pub(super) avoid: std::sync::Arc<rstar::RTree<[f64; 2]>>,
}

/// The plane through a, b, c (normal (b - a) x (c - a)).
fn through(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> Halfspace {
    let d = |p: [f64; 3], q: [f64; 3]| std::array::from_fn(|k| p[k] - q[k]);
    let n = cross_f(d(b, a), d(c, a));
    Halfspace { n, c: dot_f(n, a) }
}

/// The plane of a planar polygon (Newell's normal), through its mean.
fn plane_of(pts: &[[f64; 3]]) -> Halfspace {
    let n = crate::geom::newell(pts);
    let m: [f64; 3] =
        std::array::from_fn(|k| pts.iter().map(|p| p[k]).sum::<f64>() / pts.len() as f64);
    Halfspace { n, c: dot_f(n, m) }
}

impl Cones {
    /// Cell c's pyramids (frame coordinates), made once; an error where
    /// the apex does not lie strictly inside a face piece's plane.
    pub(super) fn of(
        &mut self,
        cpg: &Cpg,
        f: &Frame,
        cut: &mut Cutter,
        c: Ijk,
    ) -> Result<&[Pyramid], String> {
        if !self.cells.contains_key(&c) {
            let made = self.make(cpg, f, cut, c)?;
            self.cells.insert(c, made);
        }
        Ok(&self.cells[&c])
    }

    fn make(
        &mut self,
        cpg: &Cpg,
        f: &Frame,
        cut: &mut Cutter,
        c: Ijk,
    ) -> Result<Vec<Pyramid>, String> {
        let [a, b] = cpg.diagonal(c);
        let p = cpg.corners(c).map(|q| f.to(q));
        // on the diagonal's vertical halfway between top and bottom, a
        // quarter of the way from either end, the farther from the wells
        let at = |s: f64| -> [f64; 3] {
            std::array::from_fn(|k| {
                0.5 * ((1.0 - s) * (p[a][k] + p[a + 4][k]) + s * (p[b][k] + p[b + 4][k]))
            })
        };
        let clear = |x: [f64; 3]| {
            self.avoid
                .nearest_neighbor(&[x[0], x[1]])
                .map_or(f64::INFINITY, |w| (x[0] - w[0]).hypot(x[1] - w[1]))
        };
        let size = f.size;
        // the face's parts: whole or two triangles, or cut where the cells
        // across a throw meet them (both sides cut them alike); pieces
        // without area (a pillar where the cell has no thickness) bound
        // nothing
        let mut pieces = vec![];
        for face in 0..6 {
            for part in cpg.parts(c, face).map_err(|e| e.to_string())? {
                let pts: Vec<[f64; 3]> = part.points.iter().map(|&x| f.to(x)).collect();
                let h = plane_of(&pts);
                let len = dot_f(h.n, h.n).sqrt();
                if len > 1e-12 * size * size {
                    pieces.push((pts, h, len, part.across));
                }
            }
        }
        // the pieces face out of the cell: an apex behind every one (else
        // pyramids overlap: emerald (14, 41, 7), beside a throw to cells 7
        // layers down, at 0.25 and 0.75), the farther from the wells of
        // those a quarter of the way along, else of the others
        let behind = |x: &[f64; 3]| {
            pieces
                .iter()
                .all(|(_, h, len, _)| (dot_f(h.n, *x) - h.c) / len < -1e-9 * size)
        };
        let pick = |ss: &[f64]| {
            ss.iter()
                .map(|&s| at(s))
                .filter(behind)
                .max_by(|x, y| clear(*x).total_cmp(&clear(*y)))
        };
        let apex = pick(&[0.25, 0.75])
            .or_else(|| pick(&[0.5, 0.1, 0.9]))
            .ok_or_else(|| {
                format!(
                    "cell {} is not star-shaped from a point between its diagonals",
                    super::super::cpg::one_based(c)
                )
            })?;
        let mut sides: HashMap<[[u64; 3]; 2], u32> = HashMap::new();
        let mut out = vec![];
        for (pts, h, len, across) in pieces {
            let mut key: Vec<[u64; 3]> = pts.iter().map(|x| x.map(f64::to_bits)).collect();
            key.sort_unstable();
            let id = *self.by_corners.entry(key).or_insert_with(|| cut.plane(h));
            self.faces.entry(id).or_default().push((c, across));
            let e = cut.planes[id as usize].eval(apex) / len;
            for poly in convex(&pts, h.n) {
                let mut planes = vec![(id, e > 0.0)];
                let mid: [f64; 3] = std::array::from_fn(|k| {
                    poly.iter().map(|x| x[k]).sum::<f64>() / poly.len() as f64
                });
                for k in 0..poly.len() {
                    let (u, v) = (poly[k], poly[(k + 1) % poly.len()]);
                    let mut key = [u.map(f64::to_bits), v.map(f64::to_bits)];
                    key.sort_unstable();
                    let id = *sides
                        .entry(key)
                        .or_insert_with(|| cut.plane(through(apex, u, v)));
                    self.inner.insert(id);
                    planes.push((id, cut.planes[id as usize].eval(mid) > 0.0));
                }
                let flat: Vec<[f64; 2]> =
                    poly.iter().chain([&apex]).map(|x| [x[0], x[1]]).collect();
                let (lo, hi) = crate::geom::bbox(&flat);
                out.push(Pyramid { planes, lo, hi });
            }
        }
        Ok(out)
    }
}

/// A planar polygon (normal n) as convex pieces for pyramids' bases: its
/// corners but those on a straight side (a throw's points on a face's
/// edge), whole where that is convex, else its ears.
fn convex(pts: &[[f64; 3]], n: [f64; 3]) -> Vec<Vec<[f64; 3]>> {
    let m = pts.len();
    let turn = |k: usize| {
        let (a, b, c) = (pts[(k + m - 1) % m], pts[k], pts[(k + 1) % m]);
        let d = |p: [f64; 3], q: [f64; 3]| -> [f64; 3] { std::array::from_fn(|i| p[i] - q[i]) };
        let (u, v) = (d(b, a), d(c, b));
        dot_f(cross_f(u, v), n) / (dot_f(u, u) * dot_f(v, v)).sqrt().max(f64::MIN_POSITIVE)
    };
    let nn = dot_f(n, n).sqrt();
    let turns: Vec<f64> = (0..m).map(|k| turn(k) / nn).collect();
    let kept: Vec<[f64; 3]> = (0..m)
        .filter(|&k| turns[k].abs() > 1e-9)
        .map(|k| pts[k])
        .collect();
    if kept.len() < 3 || (0..m).all(|k| turns[k] >= -1e-9) {
        return vec![if kept.len() >= 3 { kept } else { pts.to_vec() }];
    }
    // drop the normal's largest axis: the polygon seen along it
    let a = (0..3)
        .max_by(|&x, &y| n[x].abs().total_cmp(&n[y].abs()))
        .expect("three");
    let (x, y) = ((a + 1) % 3, (a + 2) % 3);
    let flat: Vec<[f64; 2]> = kept
        .iter()
        .map(|p| match n[a] > 0.0 {
            true => [p[x], p[y]],
            false => [p[y], p[x]],
        })
        .collect();
    match crate::geom::ear_clip(&flat) {
        Some(ears) if !ears.is_empty() => ears
            .iter()
            .map(|t| t.iter().map(|&k| kept[k]).collect())
            .collect(),
        _ => vec![kept],
    }
}

/// A convex polyhedron cut by a pyramid (empty where they do not meet).
pub(super) fn cut_by(cut: &mut Cutter, faces: &[CutFace], pyr: &Pyramid) -> Vec<CutFace> {
    let mut piece = faces.to_vec();
    for &(id, flip) in &pyr.planes {
        piece = cut.cut(&piece, id, flip);
        if piece.is_empty() {
            break;
        }
    }
    piece
}

/// Whether x lies in the convex polyhedron (on its faces' inner sides,
/// as its points' mean is).
pub(super) fn contains(cut: &Cutter, faces: &[CutFace], x: [f64; 3]) -> bool {
    let pts: Vec<u32> = faces
        .iter()
        .flat_map(|f| f.points.iter().copied())
        .collect();
    if pts.is_empty() {
        return false;
    }
    let m: [f64; 3] = std::array::from_fn(|k| {
        pts.iter().map(|&p| cut.points[p as usize][k]).sum::<f64>() / pts.len() as f64
    });
    faces.iter().all(|f| {
        let h = cut.planes[f.plane as usize];
        let (a, b) = (h.eval(m), h.eval(x));
        a * b >= 0.0 || b == 0.0
    })
}

/// The height along the frame's normal of face `face` (4 top, 5 bottom)
/// of cell c at section point uv, where its pieces lie over it.
pub(super) fn height(cpg: &Cpg, f: &Frame, c: Ijk, face: usize, uv: [f64; 2]) -> Option<f64> {
    let (q, pieces) = cpg.face_pieces(c, face);
    let q = q.map(|x| f.to(x));
    for piece in pieces {
        for k in 1..piece.len() - 1 {
            let [a, b, d] = [q[piece[0]], q[piece[k]], q[piece[k + 1]]];
            let det = (b[0] - a[0]) * (d[1] - a[1]) - (d[0] - a[0]) * (b[1] - a[1]);
            if det == 0.0 {
                continue;
            }
            let s = ((uv[0] - a[0]) * (d[1] - a[1]) - (d[0] - a[0]) * (uv[1] - a[1])) / det;
            let t = ((b[0] - a[0]) * (uv[1] - a[1]) - (uv[0] - a[0]) * (b[1] - a[1])) / det;
            let tol = -1e-12;
            if s >= tol && t >= tol && s + t <= 1.0 - tol {
                return Some(a[2] + s * (b[2] - a[2]) + t * (d[2] - a[2]));
            }
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reservoir::CornerPointGrid;

    /// A thin wide cell whose top twists by more than its thickness (one
    /// corner raised 3 m on a 2 m cell 100 m wide) is its pyramids' union:
    /// their volumes add up to its own, every piece positive.
    #[test]
    fn a_twisted_thin_cell_is_its_pyramids() {
        let mut g = CornerPointGrid::layered([1, 1], [100.0, 100.0], &[1000.0, 1002.0]);
        // corner 3 (i + 1, j + 1) of the top and of the bottom raised (one
        // cell: ZCORN in corner order)
        for n in [3, 7] {
            g.zcorn[n] -= 3.0;
        }
        let cpg = Cpg::new(&g);
        let f = Frame::twisted(&cpg, &[[0, 0]], [0, 0]).unwrap();
        assert!(f.off > 0.5);
        let mut cut = Cutter::new(1e-10 * f.size);
        let mut cones = Cones::default();
        let pyramids = cones.of(&cpg, &f, &mut cut, [0, 0, 0]).unwrap().len();
        assert!(pyramids >= 8, "{pyramids}");
        // a box around the cell, cut by each pyramid
        let lines: Vec<u32> = [[-1e3, -1e3], [1e3, -1e3], [1e3, 1e3], [-1e3, 1e3]]
            .map(|[u, v]| cut.line([u, v, 0.0], [0.0, 0.0, 1.0]))
            .to_vec();
        let sides: Vec<u32> = (0..4)
            .map(|k| {
                let n = [[0.0, -1.0], [1.0, 0.0], [0.0, 1.0], [-1.0, 0.0]][k];
                cut.plane(Halfspace {
                    n: [n[0], n[1], 0.0],
                    c: 1e3,
                })
            })
            .collect();
        let low = cut.plane(Halfspace {
            n: [0.0, 0.0, -1.0],
            c: 1e3,
        });
        let high = cut.plane(Halfspace {
            n: [0.0, 0.0, 1.0],
            c: 1e3,
        });
        let prism = cut.prism(&lines, &sides, low, high).unwrap();
        let mut total = 0.0;
        for k in 0..pyramids {
            let pyr = &cones.cells[&[0, 0, 0]][k];
            let piece = cut_by(&mut cut, &prism, pyr);
            let faces: Vec<Vec<u32>> = piece.iter().map(|f| f.points.clone()).collect();
            let v = crate::geom::volume(&faces, &cut.points);
            assert!(v > 0.0, "{v}");
            total += v;
        }
        // the cell's own: its faces' pieces
        let mut points = vec![];
        let mut faces = vec![];
        for face in 0..6 {
            let (q, pieces) = cpg.face_pieces([0, 0, 0], face);
            let at = points.len() as u32;
            points.extend(q);
            faces.extend(
                pieces
                    .iter()
                    .map(|p| p.iter().map(|&k| at + k as u32).collect::<Vec<_>>()),
            );
        }
        let own = crate::geom::volume(&faces, &points);
        assert!((total - own).abs() <= 1e-9 * own, "{total} {own}");
    }
}
