//! Convex polyhedra cut by planes. Every vertex is named by the three
//! planes that meet there and computed once from them, so cells cut by the
//! same planes share their points bit for bit (a conforming mesh without
//! welding). Sides are decided in doubles within a stated tolerance: the
//! planes come from data rounded to decimals (`reservoir::hybrid3`'s
//! layered cavities), and a vertex that close to a plane is on it.

use std::collections::HashMap;

/// A plane `n . x = c`; its inside is `n . x <= c`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Halfspace {
    pub n: [f64; 3],
    pub c: f64,
}

impl Halfspace {
    /// Signed distance times |n| (positive outside).
    pub fn eval(&self, x: [f64; 3]) -> f64 {
        self.n[0] * x[0] + self.n[1] * x[1] + self.n[2] * x[2] - self.c
    }
}

/// A face: the plane it lies on and its points, counter-clockwise seen
/// from outside.
#[derive(Debug, Clone, PartialEq)]
pub struct CutFace {
    pub plane: u32,
    pub points: Vec<u32>,
}

/// Where a point is: on a line (by id) and a plane, or where three planes
/// meet. A point is computed once from its key.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
enum Key {
    Line(u32, u32),
    Planes([u32; 3]),
}

/// The planes and lines, and the points where they meet.
pub struct Cutter {
    pub planes: Vec<Halfspace>,
    /// Lines: a point and a direction.
    lines: Vec<([f64; 3], [f64; 3])>,
    pub points: Vec<[f64; 3]>,
    /// Per point, the line it lies on, if any.
    on_line: Vec<Option<u32>>,
    ids: HashMap<Key, u32>,
    /// Points by buckets of 4 tol: two keys for one point (three planes
    /// of which two coincide, as walls of neighbouring columns along one
    /// grid line) give it one id.
    buckets: HashMap<[i64; 3], Vec<u32>>,
    /// A vertex within this of a plane (in distance) is on it.
    tol: f64,
}

impl Cutter {
    /// An empty set of planes; `tol` is the distance within which a point
    /// lies on a plane.
    pub fn new(tol: f64) -> Cutter {
        Cutter {
            planes: vec![],
            lines: vec![],
            points: vec![],
            on_line: vec![],
            ids: HashMap::new(),
            buckets: HashMap::new(),
            tol,
        }
    }

    /// A new plane's id.
    pub fn plane(&mut self, h: Halfspace) -> u32 {
        self.planes.push(h);
        self.planes.len() as u32 - 1
    }

    /// A new line's id: through p along d.
    pub fn line(&mut self, p: [f64; 3], d: [f64; 3]) -> u32 {
        self.lines.push((p, d));
        self.lines.len() as u32 - 1
    }

    fn push(&mut self, key: Key, p: [f64; 3], line: Option<u32>) -> u32 {
        let size = 4.0 * self.tol;
        let b = p.map(|x| (x / size).floor() as i64);
        let mut near = None;
        'search: for d in 0..27 {
            let q = [b[0] + d % 3 - 1, b[1] + (d / 3) % 3 - 1, b[2] + d / 9 - 1];
            for &v in self.buckets.get(&q).into_iter().flatten() {
                let x = self.points[v as usize];
                if (0..3).all(|k| (x[k] - p[k]).abs() <= self.tol) {
                    near = Some(v);
                    break 'search;
                }
            }
        }
        let id = near.unwrap_or_else(|| {
            self.points.push(p);
            self.on_line.push(line);
            let id = self.points.len() as u32 - 1;
            self.buckets.entry(b).or_default().push(id);
            id
        });
        if self.on_line[id as usize].is_none() {
            self.on_line[id as usize] = line;
        }
        self.ids.insert(key, id);
        id
    }

    /// Where line l meets plane p (None where it is parallel to it).
    fn on(&mut self, l: u32, p: u32) -> Option<u32> {
        let key = Key::Line(l, p);
        if let Some(&v) = self.ids.get(&key) {
            return Some(v);
        }
        let (o, d) = self.lines[l as usize];
        let h = self.planes[p as usize];
        let nd = h.n[0] * d[0] + h.n[1] * d[1] + h.n[2] * d[2];
        if nd == 0.0 {
            return None;
        }
        let t = -h.eval(o) / nd;
        let x = std::array::from_fn(|k| o[k] + t * d[k]);
        Some(self.push(key, x, Some(l)))
    }

    /// Where three planes meet, by Cramer's rule (None where they do not
    /// meet in one point).
    fn meet(&self, key: [u32; 3]) -> Option<[f64; 3]> {
        let [a, b, c] = key.map(|k| self.planes[k as usize]);
        let m = [a.n, b.n, c.n];
        let det = det3(m);
        let scale = m
            .iter()
            .map(|r| r.iter().map(|x| x * x).sum::<f64>().sqrt())
            .product::<f64>();
        if det.abs() <= 1e-12 * scale {
            return None;
        }
        // columns replaced by the right-hand side
        let rhs = [a.c, b.c, c.c];
        Some(std::array::from_fn(|k| {
            let mut r = m;
            for (row, &v) in r.iter_mut().zip(&rhs) {
                row[k] = v;
            }
            det3(r) / det
        }))
    }

    /// Where edge a - b (on planes key[0] and key[1]) crosses plane h
    /// (key[2]): where the three planes meet, or where the two faces of
    /// the edge nearly share a plane (the point their planes give lies off
    /// the edge), the point along the edge.
    fn crossing(&mut self, key: [u32; 3], a: u32, b: u32, h: &Halfspace) -> Option<u32> {
        let mut sorted = key;
        sorted.sort_unstable();
        if let Some(&v) = self.ids.get(&Key::Planes(sorted)) {
            return Some(v);
        }
        let (pa, pb) = (self.points[a as usize], self.points[b as usize]);
        let (da, db) = (h.eval(pa), h.eval(pb));
        let t = da / (da - db);
        let along: [f64; 3] = std::array::from_fn(|k| pa[k] + t * (pb[k] - pa[k]));
        let x = match self.meet(sorted) {
            Some(x) if (0..3).all(|k| (x[k] - along[k]).abs() <= self.tol) => x,
            _ => along,
        };
        Some(self.push(Key::Planes(sorted), x, None))
    }

    /// The prism between planes `bottom` and `top` over a convex polygon
    /// of lines (counter-clockwise seen from above the top), its side k
    /// from line k to line k + 1 on plane `sides[k]`. None where a line is
    /// parallel to the bottom or the top.
    pub fn prism(
        &mut self,
        lines: &[u32],
        sides: &[u32],
        bottom: u32,
        top: u32,
    ) -> Option<Vec<CutFace>> {
        let n = lines.len();
        let mut low = vec![];
        let mut high = vec![];
        for &l in lines {
            low.push(self.on(l, bottom)?);
            high.push(self.on(l, top)?);
        }
        let mut faces = vec![
            CutFace {
                plane: bottom,
                points: low.iter().rev().copied().collect(),
            },
            CutFace {
                plane: top,
                points: high.clone(),
            },
        ];
        for k in 0..n {
            let k1 = (k + 1) % n;
            faces.push(CutFace {
                plane: sides[k],
                points: vec![low[k], low[k1], high[k1], high[k]],
            });
        }
        Some(faces)
    }

    /// The polyhedron cut by plane p, its inside kept (its outside where
    /// `flip`: cells on either side of one plane share its points); empty
    /// when nothing of it is strictly on that side. The new face on p is
    /// counter-clockwise seen from outside.
    pub fn cut(&mut self, faces: &[CutFace], p: u32, flip: bool) -> Vec<CutFace> {
        let mut h = self.planes[p as usize];
        if flip {
            h = Halfspace {
                n: h.n.map(|x| -x),
                c: -h.c,
            };
        }
        let len = (h.n[0] * h.n[0] + h.n[1] * h.n[1] + h.n[2] * h.n[2]).sqrt();
        let tol = self.tol * len;
        let mut side: HashMap<u32, i8> = HashMap::new();
        for f in faces {
            for &v in &f.points {
                side.entry(v).or_insert_with(|| {
                    let d = h.eval(self.points[v as usize]);
                    if d > tol {
                        1
                    } else if d < -tol {
                        -1
                    } else {
                        0
                    }
                });
            }
        }
        if side.values().all(|&s| s <= 0) {
            return faces.to_vec();
        }
        if side.values().all(|&s| s >= 0) {
            return vec![];
        }
        // each directed edge's face, to name the plane across an edge
        let mut edge_face: HashMap<(u32, u32), u32> = HashMap::new();
        for f in faces {
            for (k, &a) in f.points.iter().enumerate() {
                edge_face.insert((a, f.points[(k + 1) % f.points.len()]), f.plane);
            }
        }
        let mut out = vec![];
        // the new face's edges, from each cut face: (from, to) along p
        let mut on_p: Vec<(u32, u32)> = vec![];
        for f in faces {
            let m = f.points.len();
            let mut kept = vec![];
            for k in 0..m {
                let (a, b) = (f.points[k], f.points[(k + 1) % m]);
                let (sa, sb) = (side[&a], side[&b]);
                if sa <= 0 {
                    kept.push(a);
                }
                if sa * sb < 0 {
                    let across = edge_face.get(&(b, a)).copied().unwrap_or(f.plane);
                    let v = match (self.on_line[a as usize], self.on_line[b as usize]) {
                        (Some(la), Some(lb)) if la == lb => self.on(la, p),
                        _ => self.crossing([f.plane, across, p], a, b, &h),
                    };
                    if let Some(v) = v {
                        kept.push(v);
                    }
                }
            }
            kept.dedup();
            if kept.len() > 1 && kept.first() == kept.last() {
                kept.pop();
            }
            if kept.len() < 3 || kept.iter().all(|v| side.get(v).copied().unwrap_or(0) == 0) {
                continue;
            }
            // the face's edge along p, if any: the run of points on p
            let on = |v: u32| side.get(&v).copied().unwrap_or(0) == 0;
            let n = kept.len();
            for k in 0..n {
                let (a, b) = (kept[k], kept[(k + 1) % n]);
                if on(a) && on(b) {
                    // the face runs a to b along p: the new face runs b to a
                    on_p.push((b, a));
                }
            }
            out.push(CutFace {
                plane: f.plane,
                points: kept,
            });
        }
        // chain the new face's edges
        let next: HashMap<u32, u32> = on_p.iter().copied().collect();
        if let Some(&(start, _)) = on_p.first() {
            let mut cap = vec![start];
            let mut at = start;
            while let Some(&b) = next.get(&at) {
                if b == start || cap.len() > next.len() {
                    break;
                }
                cap.push(b);
                at = b;
            }
            if cap.len() >= 3 {
                out.push(CutFace {
                    plane: p,
                    points: cap,
                });
            }
        }
        out
    }
}

fn det3(m: [[f64; 3]; 3]) -> f64 {
    m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
        - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
        + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::volume;

    fn cube(c: &mut Cutter, lo: f64, hi: f64) -> Vec<CutFace> {
        let x0 = c.plane(Halfspace {
            n: [-1.0, 0.0, 0.0],
            c: -lo,
        });
        let y0 = c.plane(Halfspace {
            n: [0.0, -1.0, 0.0],
            c: -lo,
        });
        let x1 = c.plane(Halfspace {
            n: [1.0, 0.0, 0.0],
            c: hi,
        });
        let y1 = c.plane(Halfspace {
            n: [0.0, 1.0, 0.0],
            c: hi,
        });
        let z0 = c.plane(Halfspace {
            n: [0.0, 0.0, -1.0],
            c: -lo,
        });
        let z1 = c.plane(Halfspace {
            n: [0.0, 0.0, 1.0],
            c: hi,
        });
        let up = [0.0, 0.0, 1.0];
        let l = [[lo, lo], [hi, lo], [hi, hi], [lo, hi]].map(|[x, y]| c.line([x, y, 0.0], up));
        c.prism(&l, &[y0, x1, y1, x0], z0, z1).unwrap()
    }

    fn vol(c: &Cutter, f: &[CutFace]) -> f64 {
        let faces: Vec<Vec<u32>> = f.iter().map(|f| f.points.clone()).collect();
        volume(&faces, &c.points)
    }

    #[test]
    fn a_cube_cut_through_a_corner_and_across() {
        let mut c = Cutter::new(1e-12);
        let q = cube(&mut c, 0.0, 1.0);
        assert!((vol(&c, &q) - 1.0).abs() < 1e-12);
        // the corner x + y + z > 2.5 off: 1/48 of it
        let p = c.plane(Halfspace {
            n: [1.0, 1.0, 1.0],
            c: 2.5,
        });
        let r = c.cut(&q, p, false);
        assert!((vol(&c, &r) - (1.0 - 1.0 / 48.0)).abs() < 1e-12);
        assert_eq!(r.len(), 7);
        // the two halves across x = 0.5 share the new face's points
        let half = c.plane(Halfspace {
            n: [1.0, 0.0, 0.0],
            c: 0.5,
        });
        let (a, b) = (c.cut(&r, half, false), c.cut(&r, half, true));
        assert!((vol(&c, &a) + vol(&c, &b) - vol(&c, &r)).abs() < 1e-12);
        let mut fa: Vec<u32> = a.iter().find(|f| f.plane == half).unwrap().points.clone();
        let mut fb: Vec<u32> = b.iter().find(|f| f.plane == half).unwrap().points.clone();
        fa.sort_unstable();
        fb.sort_unstable();
        assert_eq!(fa, fb);
        // outside, and through a face: nothing, and all
        let out = c.plane(Halfspace {
            n: [1.0, 0.0, 0.0],
            c: -1.0,
        });
        assert!(c.cut(&q, out, false).is_empty());
        let at = c.plane(Halfspace {
            n: [1.0, 0.0, 0.0],
            c: 1.0,
        });
        assert_eq!(c.cut(&q, at, false), q);
    }
}
