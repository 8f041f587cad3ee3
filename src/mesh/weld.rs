//! Welding a polyhedral mesh's vertices joined by edges far shorter than
//! their cells. Sites moved close to where their dual ends leave exact
//! power vertices a few 1e-6 of a cell apart around a constraint vertex;
//! such edges are below what readers resolve (vtk takes them for
//! coincident points and crossing edges), so they are collapsed when the
//! mesh is written. Input vertices never move and never merge.

/// Edges shorter than this fraction of the smallest cell holding them
/// (its bounding box's diagonal) are collapsed.
pub const WELD: f64 = 1e-6;

/// Vertices merged along short edges.
pub struct Weld {
    /// The points left.
    pub points: Vec<[f64; 3]>,
    /// Per given point, its point.
    pub map: Vec<u32>,
    /// Points merged into another.
    pub welded: usize,
}

/// A cluster of merged points: its box, the tolerance it was merged
/// under, and its fixed point if any.
#[derive(Clone)]
struct Cluster {
    lo: [f64; 3],
    hi: [f64; 3],
    fixed: Option<u32>,
}

/// Merges the ends of edges shorter than `WELD` x the smallest cell
/// holding them, shortest first, as long as a cluster stays within that
/// tolerance and holds at most one fixed point. A cluster's point is its
/// fixed point, else its points' mean.
pub fn weld(points: &[[f64; 3]], fixed: &[bool], cells: &[Vec<Vec<u32>>]) -> Weld {
    let dist = |a: u32, b: u32| {
        let (p, q) = (points[a as usize], points[b as usize]);
        (0..3).map(|k| (p[k] - q[k]).powi(2)).sum::<f64>().sqrt()
    };
    let mut short: Vec<(f64, f64, u32, u32)> = vec![];
    for cell in cells {
        let tol = WELD * diagonal(cell.iter().flatten().map(|&v| points[v as usize]));
        for face in cell {
            for k in 0..face.len() {
                let (a, b) = (face[k], face[(k + 1) % face.len()]);
                let l = dist(a, b);
                if a != b && l < tol {
                    short.push((l, tol, a.min(b), a.max(b)));
                }
            }
        }
    }
    // shortest first; an edge of two cells is tried under the smaller one's
    // tolerance first
    short.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.total_cmp(&y.1)));
    let mut parent: Vec<u32> = (0..points.len() as u32).collect();
    let mut cluster: Vec<Cluster> = points
        .iter()
        .zip(fixed)
        .enumerate()
        .map(|(i, (&p, &f))| Cluster {
            lo: p,
            hi: p,
            fixed: f.then_some(i as u32),
        })
        .collect();
    fn root(parent: &mut [u32], mut x: u32) -> u32 {
        while parent[x as usize] != x {
            let up = parent[parent[x as usize] as usize];
            parent[x as usize] = up;
            x = up;
        }
        x
    }
    let mut welded = 0usize;
    for &(_, tol, a, b) in &short {
        let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
        if ra == rb {
            continue;
        }
        let (ca, cb) = (&cluster[ra as usize], &cluster[rb as usize]);
        if ca.fixed.is_some() && cb.fixed.is_some() {
            continue;
        }
        let merged = Cluster {
            lo: std::array::from_fn(|k| ca.lo[k].min(cb.lo[k])),
            hi: std::array::from_fn(|k| ca.hi[k].max(cb.hi[k])),
            fixed: ca.fixed.or(cb.fixed),
        };
        if diagonal([merged.lo, merged.hi].into_iter()) >= tol {
            continue;
        }
        parent[rb as usize] = ra;
        cluster[ra as usize] = merged;
        welded += 1;
    }
    // compact: one point per cluster, in the order of first appearance
    let mut out = Weld {
        points: vec![],
        map: vec![u32::MAX; points.len()],
        welded,
    };
    let mut sum: Vec<([f64; 3], usize)> = vec![];
    let mut slot = vec![u32::MAX; points.len()];
    for v in 0..points.len() as u32 {
        let r = root(&mut parent, v) as usize;
        if slot[r] == u32::MAX {
            slot[r] = sum.len() as u32;
            sum.push(([0.0; 3], 0));
        }
        let s = &mut sum[slot[r] as usize];
        for (acc, x) in s.0.iter_mut().zip(points[v as usize]) {
            *acc += x;
        }
        s.1 += 1;
        out.map[v as usize] = slot[r];
    }
    out.points = sum.iter().map(|(s, n)| s.map(|x| x / *n as f64)).collect();
    for (r, c) in cluster.iter().enumerate() {
        if let (Some(f), true) = (c.fixed, slot[r] != u32::MAX) {
            out.points[slot[r] as usize] = points[f as usize];
        }
    }
    out
}

/// The diagonal of the points' bounding box (0 for none).
fn diagonal(pts: impl Iterator<Item = [f64; 3]>) -> f64 {
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    let mut any = false;
    for p in pts {
        any = true;
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    if !any {
        return 0.0;
    }
    (0..3).map(|k| (hi[k] - lo[k]).powi(2)).sum::<f64>().sqrt()
}

/// A closed polyhedron's volume from its faces (counter-clockwise seen
/// from outside), by the divergence theorem about its first point.
pub fn volume(points: &[[f64; 3]], faces: &[Vec<u32>]) -> f64 {
    let Some(&first) = faces.first().and_then(|f| f.first()) else {
        return 0.0;
    };
    let o = points[first as usize];
    let p = |v: u32| -> [f64; 3] { std::array::from_fn(|i| points[v as usize][i] - o[i]) };
    faces
        .iter()
        .map(|f| {
            (1..f.len().saturating_sub(1))
                .map(|k| crate::geom::det3_f(p(f[0]), p(f[k]), p(f[k + 1])) / 6.0)
                .sum::<f64>()
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit cube whose corner (1,1,1) is split into three points 1e-7
    /// apart, joined by a tiny triangle: they weld into one, the input
    /// corner (0,0,0) never moves, and the volume is the cube's.
    #[test]
    fn a_split_corner_welds_back() {
        let e = 1e-7;
        let mut pts: Vec<[f64; 3]> = (0..7)
            .map(|i| [(i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64])
            .collect();
        // 7, 8, 9: the corner (1,1,1) cut off on its edges along y, z, x
        pts.extend([
            [1.0, 1.0 - e, 1.0],
            [1.0, 1.0, 1.0 - e],
            [1.0 - e, 1.0, 1.0],
        ]);
        let cube: Vec<Vec<u32>> = vec![
            vec![0, 2, 3, 1],
            vec![0, 1, 5, 4],
            vec![0, 4, 6, 2],
            vec![1, 3, 8, 7, 5],
            vec![2, 6, 9, 8, 3],
            vec![4, 5, 7, 9, 6],
            vec![7, 8, 9],
        ];
        let mut fixed = vec![false; pts.len()];
        fixed[0] = true;
        let w = weld(&pts, &fixed, std::slice::from_ref(&cube));
        assert_eq!(w.welded, 2);
        assert_eq!(w.points.len(), 8);
        assert_eq!(w.points[w.map[0] as usize], [0.0; 3]);
        let c = w.map[7];
        assert!(w.map[8] == c && w.map[9] == c);
        assert!(w.points[c as usize].iter().all(|x| (x - 1.0).abs() < e));
        let faces: Vec<Vec<u32>> = cube
            .iter()
            .map(|f| {
                let mut g: Vec<u32> = f.iter().map(|&v| w.map[v as usize]).collect();
                g.dedup();
                g
            })
            .filter(|g| g.len() >= 3)
            .collect();
        assert_eq!(faces.len(), 6);
        assert!((volume(&w.points, &faces) - 1.0).abs() < 1e-6);
    }

    /// Two fixed points never merge, however close.
    #[test]
    fn input_vertices_stay() {
        let pts = [
            [0.0, 0.0, 0.0],
            [1e-12, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        let w = weld(&pts, &[true, true, false, false], &[vec![vec![0, 1, 2, 3]]]);
        assert_eq!(w.welded, 0);
        assert_eq!(w.points.len(), 4);
    }
}
