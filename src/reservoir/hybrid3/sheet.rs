//! Cells' faces where the cells across do not match them: a fault's
//! throw, or other cells' corners on a pillar between a face's corners.
//! There a face is cut into its overlaps with the cells across, on the
//! sheet between its two pillars, and every face meeting the cut carries
//! its points: faces on both sides are unions of the same pieces (no
//! hanging corners), as a constrained mesh needs. A point of a sheet is
//! (s, depth), s from 0 at its first pillar to 1 at its second, mapped to
//! space along the pillars; cells' tops and bottoms are lines (their
//! depths at s = 0 and 1), and where two lines cross is computed one way
//! whichever cell asks.

use super::cpg::{lex, next, one_based, Cpg, Ijk};
use crate::error::{Error, Result};
use crate::geom::{ear_clip, newell, orient, orient3, shoelace};
use std::cmp::Ordering;

/// A piece of a cell's face: its points (outward from the cell), the live
/// cell across, and whether it lies on a throw.
pub(super) struct Part {
    pub(super) points: Vec<[f64; 3]>,
    pub(super) across: Option<Ijk>,
    pub(super) thrown: bool,
}

/// A cell's top or bottom on a sheet: its depths at s = 0 and s = 1.
type Line = [f64; 2];

/// Per column face, the corners on its sheet: top at s = 0, top at s = 1,
/// bottom at s = 0, bottom at s = 1.
const SHEET: [[usize; 4]; 4] = [[0, 2, 4, 6], [1, 3, 5, 7], [0, 1, 4, 5], [2, 3, 6, 7]];

/// A point of a sheet, and the lines through it by construction.
#[derive(Clone, Copy)]
struct Pt {
    s: f64,
    d: f64,
    on: [Line; 2],
}

/// Where two lines cross strictly between the pillars, computed in one
/// order whichever comes first.
fn cross(a: Line, b: Line) -> Option<Pt> {
    let key = |l: Line| l.map(f64::to_bits);
    let (a, b) = if key(a) <= key(b) { (a, b) } else { (b, a) };
    let den = (a[0] - b[0]) - (a[1] - b[1]);
    if a == b || den == 0.0 {
        return None;
    }
    let s = (a[0] - b[0]) / den;
    (s > 0.0 && s < 1.0).then(|| Pt {
        s,
        d: a[0] + s * (a[1] - a[0]),
        on: [a, b],
    })
}

/// The side of line l point p is on: Greater below it (deeper).
fn side(p: &Pt, l: Line) -> Ordering {
    if p.on.contains(&l) {
        Ordering::Equal
    } else if p.s == 0.0 {
        p.d.total_cmp(&l[0])
    } else if p.s == 1.0 {
        p.d.total_cmp(&l[1])
    } else {
        p.d.total_cmp(&(l[0] + p.s * (l[1] - l[0])))
    }
}

/// A strip of the column across: between two lines (None: unbounded),
/// the live cell in it.
struct Strip {
    upper: Option<Line>,
    lower: Option<Line>,
    cell: Option<Ijk>,
}

impl Strip {
    fn holds(&self, p: &Pt) -> bool {
        self.upper.is_none_or(|u| side(p, u) != Ordering::Less)
            && self.lower.is_none_or(|l| side(p, l) != Ordering::Greater)
    }
}

impl Cpg<'_> {
    /// Cell c's line (top b = 0, bottom b = 1) on the sheet of its column
    /// face f.
    fn line(&self, [i, j, k]: Ijk, f: usize, b: usize) -> Line {
        let s = SHEET[f];
        [s[2 * b], s[2 * b + 1]].map(|n| self.g.depth(i, j, k, n))
    }

    /// The pillars (i, j) of column face f of column (i, j): at s = 0, 1.
    fn sheet_pillars(&self, [i, j]: [usize; 2], f: usize) -> [[usize; 2]; 2] {
        SHEET[f][..2]
            .iter()
            .map(|&c| [i + (c & 1), j + ((c >> 1) & 1)])
            .collect::<Vec<_>>()
            .try_into()
            .unwrap_or([[i, j]; 2])
    }

    /// The strips of the column across face f of cell c's column: each
    /// cell's, the gaps between layers, and above and below them all.
    fn strips(&self, c: Ijk, f: usize) -> Vec<Strip> {
        let Some([a, b, _]) = next(self.g, c, f) else {
            return vec![Strip {
                upper: None,
                lower: None,
                cell: None,
            }];
        };
        let g = self.g;
        let theirs = f ^ 1;
        let mut out = vec![];
        let mut above: Option<Line> = None;
        for k in 0..g.nz {
            let n = [a, b, k];
            let (top, bottom) = (self.line(n, theirs, 0), self.line(n, theirs, 1));
            if above != Some(top) {
                out.push(Strip {
                    upper: above,
                    lower: Some(top),
                    cell: None,
                });
            }
            out.push(Strip {
                upper: Some(top),
                lower: Some(bottom),
                cell: self.live(n).then_some(n),
            });
            above = Some(bottom);
        }
        out.push(Strip {
            upper: above,
            lower: None,
            cell: None,
        });
        out
    }

    /// The point of a sheet at (s, depth), in the mesh's frame.
    fn sheet_point(&self, pillars: [[usize; 2]; 2], p: &Pt) -> [f64; 3] {
        let at = |[i, j]: [usize; 2]| self.g.on_pillar(i, j, p.d);
        let q = if p.s == 0.0 {
            at(pillars[0])
        } else if p.s == 1.0 {
            at(pillars[1])
        } else {
            let (a, b) = (at(pillars[0]), at(pillars[1]));
            std::array::from_fn(|k| a[k] + p.s * (b[k] - a[k]))
        };
        [q[0], q[1], -q[2]]
    }

    /// Whether pillar (i, j) holds a corner strictly between two depths.
    fn corner_between(&self, [i, j]: [usize; 2], a: f64, b: f64) -> bool {
        let (lo, hi) = (a.min(b), a.max(b));
        let d = &self.pillars[j * (self.g.nx + 1) + i];
        let at = d.partition_point(|&x| x <= lo);
        d.get(at).is_some_and(|&x| x < hi)
    }

    /// Face f of cell c as `pieces` cuts it, facing one cell.
    fn whole(&self, c: Ijk, f: usize, across: Option<Ijk>) -> Vec<Part> {
        let (q, ps) = self.face_pieces(c, f);
        ps.into_iter()
            .map(|p| Part {
                points: p.iter().map(|&n| q[n]).collect(),
                across,
                thrown: false,
            })
            .collect()
    }

    /// Face f of cell c in pieces, each with the live cell across: the
    /// face whole, or two triangles (`pieces`), where it matches the cell
    /// across and no other corner lies on its sides; else cut on its
    /// sheet. Errors where layers do not meet (a gap across its top or
    /// bottom).
    pub(super) fn parts(&self, c: Ijk, f: usize) -> Result<Vec<Part>> {
        if f >= 4 {
            return self.level_parts(c, f);
        }
        let col = [c[0], c[1]];
        let pillars = self.sheet_pillars(col, f);
        let (top, bottom) = (self.line(c, f, 0), self.line(c, f, 1));
        let thrown = self.is_thrown(col, f);
        let extra = (0..2).any(|s| self.corner_between(pillars[s], top[s], bottom[s]));
        if !thrown && !extra {
            return Ok(self.whole(c, f, self.neighbour(c, f)?));
        }
        let out = newell(&self.face(c, f));
        let mine = Strip {
            upper: Some(top),
            lower: Some(bottom),
            cell: None,
        };
        // the sheet's points on the face: corners on its pillars, crossings
        let mut pts: Vec<Pt> = vec![];
        for (s, &[pi, pj]) in pillars.iter().enumerate() {
            let d = &self.pillars[pj * (self.g.nx + 1) + pi];
            for &x in d {
                let p = Pt {
                    s: s as f64,
                    d: x,
                    on: [[f64::NAN; 2]; 2],
                };
                if mine.holds(&p) {
                    pts.push(p);
                }
            }
        }
        let mut parts = vec![];
        for strip in self.strips(c, f) {
            let mut here: Vec<Pt> = pts.iter().filter(|p| strip.holds(p)).copied().collect();
            for l in [strip.upper, strip.lower].into_iter().flatten() {
                for m in [top, bottom] {
                    here.extend(cross(l, m).filter(|p| strip.holds(p) && mine.holds(p)));
                }
            }
            let (poly, ears) = match polygon_pieces(here) {
                Pieces::Area(poly, ears) => (poly, ears),
                Pieces::None => continue,
                Pieces::Stuck => {
                    return Err(Error::Usage(format!(
                        "cell {}: its face {f} could not be cut where the cells across meet it",
                        one_based(c)
                    )))
                }
            };
            let mapped: Vec<[f64; 3]> = poly.iter().map(|p| self.sheet_point(pillars, p)).collect();
            let pieces: Vec<Vec<[f64; 3]>> = if planar(&mapped) {
                vec![mapped]
            } else {
                ears.iter().map(|t| t.map(|k| mapped[k]).to_vec()).collect()
            };
            for mut points in pieces {
                let n = newell(&points);
                if n == [0.0; 3] {
                    continue;
                }
                if (0..3).map(|k| n[k] * out[k]).sum::<f64>() < 0.0 {
                    points.reverse();
                }
                parts.push(Part {
                    points,
                    across: strip.cell,
                    thrown,
                });
            }
        }
        if parts.is_empty() && !self.face_pieces(c, f).1.is_empty() {
            return Err(Error::Usage(format!(
                "cell {}: its face {f} could not be cut where the cells across meet it",
                one_based(c)
            )));
        }
        Ok(parts)
    }

    /// The points where the cells across cut cell c's line b (top 0,
    /// bottom 1) on the sheet of its column face f, in the mesh's frame,
    /// by s.
    fn cuts(&self, c: Ijk, f: usize, b: usize) -> Vec<(f64, [f64; 3])> {
        let col = [c[0], c[1]];
        if !self.is_thrown(col, f) {
            return vec![];
        }
        let l = self.line(c, f, b);
        let pillars = self.sheet_pillars(col, f);
        let mut out: Vec<(f64, [f64; 3])> = vec![];
        for strip in self.strips(c, f) {
            for m in [strip.upper, strip.lower].into_iter().flatten() {
                if let Some(p) = cross(l, m) {
                    out.push((p.s, self.sheet_point(pillars, &p)));
                }
            }
        }
        out.sort_by(|a, b| a.0.total_cmp(&b.0));
        out.dedup_by(|a, b| a.1 == b.1);
        out
    }

    /// A top (f 4) or bottom (5) face in pieces: as `pieces` cuts it, or
    /// with the points where throws cut its sides, whole if it is planar,
    /// else its ears in map view (from its least point, so both cells
    /// across cut it alike).
    fn level_parts(&self, c: Ijk, f: usize) -> Result<Vec<Part>> {
        let across = self.neighbour(c, f)?;
        let b = f - 4;
        // its corners in turn and the column face under each side
        let (ring, sides) = match b {
            0 => ([0, 1, 3, 2], [2, 1, 3, 0]),
            _ => ([4, 6, 7, 5], [0, 3, 1, 2]),
        };
        let mut poly: Vec<[f64; 3]> = vec![];
        for e in 0..4 {
            let from = ring[e];
            poly.push(self.corner(c, from));
            let mut cuts = self.cuts(c, sides[e], b);
            // from the corner at s = 0 or at s = 1
            if SHEET[sides[e]][2 * b] != from {
                cuts.reverse();
            }
            poly.extend(cuts.into_iter().map(|(_, p)| p));
        }
        if poly.len() == 4 {
            return Ok(self.whole(c, f, across));
        }
        poly.dedup();
        while poly.len() > 1 && poly.first() == poly.last() {
            poly.pop();
        }
        let xy = |p: &[f64; 3]| [p[0], p[1]];
        if shoelace(poly.len(), |k| xy(&poly[k])) < 0.0 {
            poly.reverse();
        }
        from_least(&mut poly);
        let ears = |poly: &[[f64; 3]]| -> Result<Vec<Vec<[f64; 3]>>> {
            if planar(poly) {
                return Ok(vec![poly.to_vec()]);
            }
            let flat: Vec<[f64; 2]> = poly.iter().map(xy).collect();
            let ears = ear_clip(&flat).ok_or_else(|| {
                Error::Usage(format!(
                    "cell {}: its {} could not be cut where a throw meets it",
                    one_based(c),
                    ["top", "bottom"][b]
                ))
            })?;
            Ok(ears.iter().map(|t| t.map(|n| poly[n]).to_vec()).collect())
        };
        // not planar: in ears, but where an ear spans the column's
        // diagonal (the fold between the face's two planes, where it could
        // face into the cell: emerald (14, 41, 7)), either side of it
        let [d0, d1] = self.diagonal(c).map(|n| self.corner(c, n + 4 * b));
        let spans = |t: &Vec<[f64; 3]>| {
            let side = |p: &[f64; 3]| orient(xy(&d0), xy(&d1), xy(p));
            let s: Vec<Ordering> = t.iter().map(side).collect();
            s.contains(&Ordering::Less) && s.contains(&Ordering::Greater)
        };
        let mut tris = match planar(&poly) {
            true => vec![poly.clone()],
            false => {
                let all = ears(&poly)?;
                match all.iter().any(spans).then(|| halves(&poly, d0, d1)) {
                    Some(Some([h0, h1])) => [ears(&h0)?, ears(&h1)?].concat(),
                    _ => all,
                }
            }
        };
        // counter-clockwise seen from above: the top's outward side
        if b == 1 {
            tris.iter_mut().for_each(|t| t.reverse());
        }
        Ok(tris
            .into_iter()
            .map(|points| Part {
                points,
                across,
                thrown: false,
            })
            .collect())
    }
}

/// A polygon (points in turn) cut along its chord from point a to point
/// b: the polygons either side, each from its least point (so that both
/// cells across a face cut it alike); None unless both are its points.
fn halves(poly: &[[f64; 3]], a: [f64; 3], b: [f64; 3]) -> Option<[Vec<[f64; 3]>; 2]> {
    let n = poly.len();
    let i = poly.iter().position(|p| *p == a)?;
    let j = poly.iter().position(|p| *p == b)?;
    let arc = |from: usize, to: usize| {
        let mut h: Vec<[f64; 3]> = (0..=(to + n - from) % n)
            .map(|k| poly[(from + k) % n])
            .collect();
        from_least(&mut h);
        h
    };
    (i != j).then(|| [arc(i, j), arc(j, i)])
}

/// A polygon turned to start at its least point (`lex`), so that the
/// cells on both sides of a face cut it alike.
fn from_least(poly: &mut [[f64; 3]]) {
    let least = (0..poly.len())
        .min_by(|&a, &b| lex(&poly[a], &poly[b]))
        .unwrap_or(0);
    poly.rotate_left(least);
}

/// Whether a polygon's points lie in one plane, exactly.
fn planar(poly: &[[f64; 3]]) -> bool {
    let n = poly.len();
    (1..n.saturating_sub(1))
        .find(|&k| newell(&[poly[0], poly[k], poly[k + 1]]) != [0.0; 3])
        .is_some_and(|k| {
            poly.iter()
                .all(|&p| orient3(poly[0], poly[k], poly[k + 1], p) == Ordering::Equal)
        })
}

/// A region of a sheet: its polygon and ears, none (no area), or stuck
/// (its points in turn make no simple polygon).
enum Pieces {
    Area(Vec<Pt>, Vec<[usize; 3]>),
    None,
    Stuck,
}

/// A convex region of a sheet from its points (on its sides): the points
/// in turn around their mean, from the least, and its ears (s, depth).
/// The same points give the same polygon and triangles.
fn polygon_pieces(mut pts: Vec<Pt>) -> Pieces {
    pts.sort_by(|a, b| a.s.total_cmp(&b.s).then(a.d.total_cmp(&b.d)));
    pts.dedup_by(|a, b| a.s == b.s && a.d == b.d);
    if pts.len() < 3 {
        return Pieces::None;
    }
    let n = pts.len() as f64;
    let (ms, md) = (
        pts.iter().map(|p| p.s).sum::<f64>() / n,
        pts.iter().map(|p| p.d).sum::<f64>() / n,
    );
    let first = pts[0];
    let angle = |p: &Pt| (p.d - md).atan2(p.s - ms);
    pts.sort_by(|a, b| angle(a).total_cmp(&angle(b)));
    let at = pts
        .iter()
        .position(|p| p.s == first.s && p.d == first.d)
        .unwrap_or(0);
    pts.rotate_left(at);
    let flat: Vec<[f64; 2]> = pts.iter().map(|p| [p.s, p.d]).collect();
    match ear_clip(&flat) {
        Some(ears) if ears.is_empty() => Pieces::None,
        Some(ears) => Pieces::Area(pts, ears),
        None => Pieces::Stuck,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reservoir::CornerPointGrid;

    /// Two columns of three 4 m layers, the second 1 m deeper, on pillars
    /// leaning along y (so that no piece is planar by chance).
    fn thrown() -> CornerPointGrid {
        let mut g = CornerPointGrid::cartesian([2, 1, 3], [10.0, 10.0, 4.0]);
        for k in 0..3 {
            for b in 0..2 {
                for dj in 0..2 {
                    for di in 0..2 {
                        g.zcorn[(((2 * k + b) * 2 + dj) * 2 + 1) * 2 + di] += 1.0;
                        // ny = 1, i = 1
                    }
                }
            }
        }
        for p in &mut g.coord {
            p[5] = 20.0;
            p[4] += 3.0;
        }
        g
    }

    /// `thrown` with its second column tilted: its layers cross the
    /// first's.
    fn tilted() -> CornerPointGrid {
        let mut g = thrown();
        for k in 0..3 {
            for b in 0..2 {
                for di in 0..2 {
                    g.zcorn[(((2 * k + b) * 2 + 1) * 2 + 1) * 2 + di] += 6.0; // dj = 1, i = 1
                }
            }
        }
        g
    }

    fn area(points: &[[f64; 3]]) -> f64 {
        newell(points).iter().map(|x| x * x).sum::<f64>().sqrt() / 2.0
    }

    /// Pieces as sets of points, sorted: the same from either side.
    fn keys(parts: &[Part]) -> Vec<Vec<[u64; 3]>> {
        let mut out: Vec<Vec<[u64; 3]>> = parts
            .iter()
            .map(|p| {
                let mut k: Vec<[u64; 3]> = p.points.iter().map(|q| q.map(f64::to_bits)).collect();
                k.sort_unstable();
                k
            })
            .collect();
        out.sort();
        out
    }

    #[test]
    fn faces_across_a_throw_are_cut_alike_from_both_sides() {
        let g = thrown();
        let cpg = Cpg::new(&g);
        assert!(cpg.is_thrown([0, 0], 1) && cpg.is_thrown([1, 0], 0));
        assert!(!cpg.is_thrown([0, 0], 0));
        // cell (0, 0, 1) against the cells across: layer 1's last metre,
        // layer 2's first three
        let mine = cpg.parts([0, 0, 1], 1).unwrap();
        let total: f64 = mine.iter().map(|p| area(&p.points)).sum();
        let whole = area(&cpg.face([0, 0, 1], 1));
        assert!((total - whole).abs() < 1e-9 * whole, "{total} {whole}");
        let across: std::collections::BTreeSet<_> = mine.iter().map(|p| p.across).collect();
        assert_eq!(
            across.into_iter().collect::<Vec<_>>(),
            vec![Some([1, 0, 0]), Some([1, 0, 1])]
        );
        assert!(mine.iter().all(|p| p.thrown));
        // every piece toward (1, 0, 0) is one of (1, 0, 0)'s toward (0, 0, 1)
        let to = |parts: &[Part], n: Ijk| -> Vec<Part> {
            parts
                .iter()
                .filter(|p| p.across == Some(n))
                .map(|p| Part {
                    points: p.points.clone(),
                    across: p.across,
                    thrown: p.thrown,
                })
                .collect()
        };
        let theirs = cpg.parts([1, 0, 0], 0).unwrap();
        assert_eq!(keys(&to(&mine, [1, 0, 0])), keys(&to(&theirs, [0, 0, 1])));
        // no lines cross here: the bottom of (0, 0, 0) and the top of
        // (0, 0, 1) are their quadrilaterals, alike
        let down = cpg.parts([0, 0, 0], 5).unwrap();
        let up = cpg.parts([0, 0, 1], 4).unwrap();
        assert_eq!(keys(&down), keys(&up));
    }

    /// A twisted bottom cut where a throw meets it: no piece spans the
    /// column's diagonal (its two planes), and the cell below cuts its top
    /// alike.
    #[test]
    fn a_twisted_level_is_cut_either_side_of_its_diagonal() {
        // the second column tilted (a cut on (0, 0, 0)'s bottom), and that
        // bottom twisted at corner (0, 1)
        let mut g = tilted();
        g.zcorn[((2 + 1) * 2) * 2] += 0.5; // k = 0 bottom, j = 0 (dj = 1), i = 0, di = 0
        g.zcorn[((2 * 1) * 2 + 1) * 2 * 2] += 0.5; // k = 1 top, the same corner
        let cpg = Cpg::new(&g);
        let down = cpg.parts([0, 0, 0], 5).unwrap();
        let up = cpg.parts([0, 0, 1], 4).unwrap();
        assert_eq!(keys(&down), keys(&up));
        assert!(down.len() >= 2, "{}", down.len());
        let [d0, d1] = cpg
            .diagonal([0, 0, 0])
            .map(|n| cpg.corner([0, 0, 0], n + 4));
        let side = |p: &[f64; 3]| crate::geom::orient([d0[0], d0[1]], [d1[0], d1[1]], [p[0], p[1]]);
        for piece in &down {
            let sides: std::collections::BTreeSet<Ordering> = piece
                .points
                .iter()
                .map(side)
                .filter(|&o| o != Ordering::Equal)
                .collect();
            assert_eq!(sides.len(), 1, "{:?}", piece.points);
        }
        let total: f64 = down.iter().map(|p| area(&p.points)).sum();
        let pieces = cpg.face_pieces([0, 0, 0], 5);
        let whole: f64 = pieces
            .1
            .iter()
            .map(|t| area(&t.iter().map(|&n| pieces.0[n]).collect::<Vec<_>>()))
            .sum();
        assert!((total - whole).abs() < 1e-9 * whole, "{total} {whole}");
    }

    #[test]
    fn a_crossing_throw_cuts_the_tops_beside_it() {
        let g = tilted();
        let cpg = Cpg::new(&g);
        // (0, 0, 0)'s bottom line on the fault (4 m deep) is crossed by
        // (1, 0, 0)'s top line (1 m to 7 m): its bottom face (flat, kept
        // whole) gets the crossing as a fifth corner
        let down = cpg.parts([0, 0, 0], 5).unwrap();
        let up = cpg.parts([0, 0, 1], 4).unwrap();
        assert_eq!(down.len(), 1);
        assert_eq!(down[0].points.len(), 5);
        assert_eq!(keys(&down), keys(&up));
        let total: f64 = down.iter().map(|p| area(&p.points)).sum();
        let whole = area(&cpg.face([0, 0, 0], 5));
        assert!((total - whole).abs() < 1e-9 * whole, "{total} {whole}");
        // and every point of those pieces is a corner of some fault piece
        let fault: std::collections::BTreeSet<[u64; 3]> = (0..3)
            .flat_map(|k| cpg.parts([0, 0, k], 1).unwrap())
            .flat_map(|p| p.points)
            .map(|q| q.map(f64::to_bits))
            .collect();
        for p in &down {
            for q in &p.points {
                if q[0] == 10.0 {
                    assert!(fault.contains(&q.map(f64::to_bits)), "{q:?}");
                }
            }
        }
    }
}
