//! Welding a polyhedral mesh's vertices joined by edges far shorter than
//! the edges beside them. Sites whose power at a constraint vertex exceeds
//! the vertex's by a hair leave exact power vertices a few 1e-6 of a cell
//! apart around it; vtk takes the edges beside such an edge for crossing
//! (its line test is relative to their length) and close points for
//! coincident, so they are collapsed when the mesh is written. Input
//! vertices never move and never merge.

/// Edges shorter than this fraction of the longest edge at either end are
/// collapsed.
pub const WELD: f64 = 3e-5;

/// Nor longer than this fraction of the smallest cell holding them: a
/// small cell beside long edges keeps its shape.
const CELL: f64 = 1e-3;

/// A cluster is merged only if it is this much smaller than every other
/// edge leaving it.
const ISOLATION: f64 = 0.03;

/// Nor merged into a point off the plane of a face through it by more
/// than this fraction of the face's size: such a face bends, and vtk's
/// local convexity test, which compares nearly coplanar faces' centroids,
/// then calls its cell nonconvex (SPE9's bend by 1e-5 to 1e-4, emerald's
/// welds that help by less).
const FLAT: f64 = 1e-5;

/// Vertices merged along short edges.
pub struct Weld {
    /// The points left.
    pub points: Vec<[f64; 3]>,
    /// Per given point, its point.
    pub map: Vec<u32>,
    /// Points merged into another.
    pub welded: usize,
}

/// A cluster of merged points: its box and its fixed point if any.
#[derive(Clone)]
struct Cluster {
    lo: [f64; 3],
    hi: [f64; 3],
    fixed: Option<u32>,
}

/// Merges the ends of edges shorter than `WELD` x the longest edge at
/// either end (vtk takes the two edges beside such an edge for crossing),
/// as clusters holding at most one fixed point, and only clusters far
/// smaller than the other edges leaving them (`ISOLATION`), whose point
/// bends no face through them (`FLAT`). A cluster's point is its fixed
/// point, else its points' mean.
pub fn weld(points: &[[f64; 3]], fixed: &[bool], cells: &[Vec<Vec<u32>>]) -> Weld {
    let (edges, lengths, tiny) = edges(points, cells);
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
    let mut order: Vec<usize> = (0..edges.len()).filter(|&e| tiny[e]).collect();
    order.sort_by(|&x, &y| lengths[x].total_cmp(&lengths[y]));
    for e in order {
        let (a, b) = edges[e];
        let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
        let (ca, cb) = (&cluster[ra as usize], &cluster[rb as usize]);
        if ra == rb || (ca.fixed.is_some() && cb.fixed.is_some()) {
            continue;
        }
        let merged = Cluster {
            lo: std::array::from_fn(|k| ca.lo[k].min(cb.lo[k])),
            hi: std::array::from_fn(|k| ca.hi[k].max(cb.hi[k])),
            fixed: ca.fixed.or(cb.fixed),
        };
        parent[rb as usize] = ra;
        cluster[ra as usize] = merged;
    }
    // the shortest edge other than tiny ones leaving each cluster
    let roots: Vec<u32> = (0..points.len() as u32)
        .map(|v| root(&mut parent, v))
        .collect();
    let mut leaving = vec![f64::INFINITY; points.len()];
    for (e, &(a, b)) in edges.iter().enumerate() {
        let (ra, rb) = (roots[a as usize], roots[b as usize]);
        if ra != rb && !tiny[e] {
            for r in [ra, rb] {
                leaving[r as usize] = leaving[r as usize].min(lengths[e]);
            }
        }
    }
    // kept clusters: far smaller than the edges leaving them, and leaving
    // every cell they touch at least four faces
    let mut kept: Vec<bool> = (0..points.len())
        .map(|r| {
            let c = &cluster[r];
            diagonal([c.lo, c.hi].into_iter()) <= ISOLATION * leaving[r]
        })
        .collect();
    let group_of = |v: u32, kept: &[bool]| {
        let r = roots[v as usize];
        if kept[r as usize] {
            r
        } else {
            v
        }
    };
    let at = merged_points(points, fixed, &roots);
    for f in cells.iter().flatten() {
        flat(points, f, &at, &roots, &mut kept);
    }
    for cell in cells {
        let faces = cell
            .iter()
            .filter(|f| {
                let mut g: Vec<u32> = f.iter().map(|&v| group_of(v, &kept)).collect();
                g.sort_unstable();
                g.dedup();
                g.len() >= 3
            })
            .count();
        if faces < 4 {
            for &v in cell.iter().flatten() {
                kept[roots[v as usize] as usize] = false;
            }
        }
    }
    let group: Vec<usize> = (0..points.len() as u32)
        .map(|v| group_of(v, &kept) as usize)
        .collect();
    // compact: one point per group, in the order of first appearance
    let mut out = Weld {
        points: vec![],
        map: vec![u32::MAX; points.len()],
        welded: 0,
    };
    let mut slot = vec![u32::MAX; points.len()];
    for (v, &g) in group.iter().enumerate() {
        if slot[g] == u32::MAX {
            slot[g] = out.points.len() as u32;
            out.points.push(if kept[g] && roots[g] as usize == g {
                at[g]
            } else {
                points[g]
            });
        } else {
            out.welded += 1;
        }
        out.map[v] = slot[g];
    }
    out
}

/// Per root, the point its cluster would merge into: its fixed point, else
/// its points' mean.
fn merged_points(points: &[[f64; 3]], fixed: &[bool], roots: &[u32]) -> Vec<[f64; 3]> {
    let mut sum = vec![([0.0; 3], 0usize, None); points.len()];
    for (v, &r) in roots.iter().enumerate() {
        let s = &mut sum[r as usize];
        for (acc, x) in s.0.iter_mut().zip(points[v]) {
            *acc += x;
        }
        s.1 += 1;
        if fixed[v] {
            s.2 = Some(v);
        }
    }
    sum.iter()
        .map(|(s, n, f)| match f {
            Some(f) => points[*f],
            None => s.map(|x| x / (*n).max(1) as f64),
        })
        .collect()
}

/// Unkeeps the clusters of face `f` whose merged point lies off the face's
/// plane by more than `FLAT` of its size.
fn flat(points: &[[f64; 3]], f: &[u32], at: &[[f64; 3]], roots: &[u32], kept: &mut [bool]) {
    let moving: Vec<u32> = f
        .iter()
        .map(|&v| roots[v as usize])
        .filter(|&r| kept[r as usize])
        .collect();
    // a face left with three corners or fewer stays planar (or goes)
    let mut corners: Vec<u32> = f
        .iter()
        .map(|&v| match kept[roots[v as usize] as usize] {
            true => roots[v as usize],
            false => v,
        })
        .collect();
    corners.sort_unstable();
    corners.dedup();
    if moving.is_empty() || corners.len() < 4 {
        return;
    }
    // about its first point: Newell's sums lose far coordinates' digits
    let o = points[f[0] as usize];
    let pts: Vec<[f64; 3]> = f
        .iter()
        .map(|&v| std::array::from_fn(|k| points[v as usize][k] - o[k]))
        .collect();
    let plane = crate::geom::Plane::of(&pts);
    let size = diagonal(pts.iter().copied());
    for r in moving {
        let m = at[r as usize];
        // (NaN for a face without area: never off)
        let off = plane.distance(std::array::from_fn(|k| m[k] - o[k]));
        if off > FLAT * size {
            kept[r as usize] = false;
        }
    }
}

/// Each edge of the cells once (ends in order), its length, and whether it
/// is short enough to collapse (`WELD`, `CELL`).
fn edges(points: &[[f64; 3]], cells: &[Vec<Vec<u32>>]) -> (Vec<(u32, u32)>, Vec<f64>, Vec<bool>) {
    let dist = |a: u32, b: u32| crate::geom::dist_f(points[a as usize], points[b as usize]);
    // each edge once, with the smallest cell holding it (its box's diagonal)
    let mut held: Vec<((u32, u32), f64)> = vec![];
    for cell in cells {
        let size = diagonal(cell.iter().flatten().map(|&v| points[v as usize]));
        for f in cell {
            for k in 0..f.len() {
                let (a, b) = (f[k], f[(k + 1) % f.len()]);
                if a != b {
                    held.push(((a.min(b), a.max(b)), size));
                }
            }
        }
    }
    // (sizes are not negative: their bits order as they do)
    use rayon::slice::ParallelSliceMut;
    held.par_sort_unstable_by_key(|&((a, b), size)| {
        ((u64::from(a) << 32) | u64::from(b), size.to_bits())
    });
    held.dedup_by_key(|e| e.0);
    let edges: Vec<(u32, u32)> = held.iter().map(|e| e.0).collect();
    let lengths: Vec<f64> = edges.iter().map(|&(a, b)| dist(a, b)).collect();
    let mut longest = vec![0.0f64; points.len()];
    for (&(a, b), &l) in edges.iter().zip(&lengths) {
        for v in [a, b] {
            longest[v as usize] = longest[v as usize].max(l);
        }
    }
    let tiny: Vec<bool> = edges
        .iter()
        .zip(&lengths)
        .zip(&held)
        .map(|((&(a, b), &l), e)| {
            l < WELD * longest[a as usize].max(longest[b as usize]) && l < CELL * e.1
        })
        .collect();
    (edges, lengths, tiny)
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
    crate::geom::dist_f(hi, lo)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit cube whose corner (1,1,1) is cut off e wide by a triangle
    /// (points 7, 8, 9 on its edges along y, z, x), faces outward.
    fn cut_cube(e: f64) -> (Vec<[f64; 3]>, Vec<Vec<u32>>) {
        let mut pts: Vec<[f64; 3]> = (0..7)
            .map(|i| [(i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64])
            .collect();
        pts.extend([
            [1.0, 1.0 - e, 1.0],
            [1.0, 1.0, 1.0 - e],
            [1.0 - e, 1.0, 1.0],
        ]);
        let faces = vec![
            vec![0, 2, 3, 1],
            vec![0, 1, 5, 4],
            vec![0, 4, 6, 2],
            vec![1, 3, 8, 7, 5],
            vec![2, 6, 9, 8, 3],
            vec![4, 5, 7, 9, 6],
            vec![7, 8, 9],
        ];
        (pts, faces)
    }

    /// The cut 1e-7 wide welds back into one corner, the input corner
    /// (0,0,0) never moves, and the volume is the cube's.
    #[test]
    fn a_split_corner_welds_back() {
        let e = 1e-7;
        let (pts, cube) = cut_cube(e);
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
        assert!((crate::geom::volume(&faces, &w.points) - 1.0).abs() < 1e-6);
    }

    /// The same corner cut off 1e-5 wide, with a cube edge beside it
    /// shortened to 1e-4: merging the cut would bend the faces along that
    /// edge by a tenth, so nothing merges.
    #[test]
    fn a_cluster_beside_a_short_edge_stays() {
        let e = 1e-5;
        let (mut pts, cube) = cut_cube(e);
        pts[3][2] = 1.0 - e - 1e-4;
        let w = weld(&pts, &vec![false; pts.len()], &[cube]);
        assert_eq!(w.welded, 0);
        assert_eq!(w.points, pts);
    }

    /// A unit square whose corner (1,1,0) is a cluster with a point h
    /// above it: merging into their mean would lift the corner h/2 off
    /// the square's plane. At h = 1e-4 (3.5e-5 of the square's size) the
    /// cluster is unkept, at h = 1e-6 it stays.
    #[test]
    fn a_merge_that_would_bend_a_face_is_refused() {
        for (h, stays) in [(1e-4, false), (1e-6, true)] {
            let pts = [
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [1.0, 1.0, 0.0],
                [0.0, 1.0, 0.0],
                [1.0, 1.0, h],
            ];
            let roots = [0, 1, 2, 3, 2];
            let at = merged_points(&pts, &[false; 5], &roots);
            let mut kept = [true; 5];
            flat(&pts, &[0, 1, 2, 3], &at, &roots, &mut kept);
            assert_eq!(kept[2], stays, "h = {h}");
        }
    }

    /// The corner cut off 1e-7 wide as a cell of its own: its edges are
    /// not short for it, so it keeps them, and its volume.
    #[test]
    fn a_tiny_cell_keeps_its_shape() {
        let e = 1e-7;
        let (mut pts, cube) = cut_cube(e);
        pts.push([1.0; 3]);
        let corner = vec![
            vec![7, 10, 8],
            vec![8, 10, 9],
            vec![9, 10, 7],
            vec![7, 8, 9],
        ];
        let w = weld(&pts, &vec![false; pts.len()], &[cube, corner.clone()]);
        assert_eq!(w.welded, 0);
        let tet = crate::geom::volume(&corner, &w.points).abs();
        assert!((tet - e * e * e / 6.0).abs() < 1e-3 * tet, "{tet}");
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
