//! A cell's faces, built in pieces (per column of the cavity it crosses),
//! joined again: the pieces of one face (one plane, one cell across) into
//! one polygon where they share edges.

use std::collections::BTreeMap;

/// A cell's faces with what is across them, the pieces of one face (one
/// plane, one cell across) joined where they share edges (first with the
/// points of each piece that lie inside another's edges put in them).
pub(super) fn merge<A: Ord + Copy>(
    faces: Vec<(A, u32, Vec<u32>)>,
    points: &[[f64; 3]],
    tol: f64,
) -> Vec<(A, Vec<u32>)> {
    let mut groups: BTreeMap<(A, u32), Vec<Vec<u32>>> = BTreeMap::new();
    for (a, p, pts) in faces {
        groups.entry((a, p)).or_default().push(pts);
    }
    let mut out = vec![];
    for ((a, _), polys) in groups {
        if polys.len() == 1 {
            out.extend(polys.into_iter().map(|p| (a, p)));
            continue;
        }
        match crate::mesh::join(&polys)
            .or_else(|| crate::mesh::join(&on_edges(polys.clone(), points, tol)))
        {
            Some(cycle) => out.push((a, cycle)),
            None => out.extend(polys.into_iter().map(|p| (a, p))),
        }
    }
    out
}

/// A cell's faces with each point of the cell that lies inside one of
/// their edges put in it: a face kept whole beside two pieces of a face
/// across a column line meets them at a point it would otherwise lack.
pub(super) fn on_edges(faces: Vec<Vec<u32>>, points: &[[f64; 3]], tol: f64) -> Vec<Vec<u32>> {
    let mut all: Vec<u32> = faces.iter().flatten().copied().collect();
    all.sort_unstable();
    all.dedup();
    faces
        .iter()
        .map(|f| {
            let mut out = vec![];
            for k in 0..f.len() {
                let (u, v) = (f[k], f[(k + 1) % f.len()]);
                out.push(u);
                let (p, q) = (points[u as usize], points[v as usize]);
                let d: [f64; 3] = std::array::from_fn(|i| q[i] - p[i]);
                let len2 = crate::geom::dot_f(d, d);
                let mut inside: Vec<(f64, u32)> = all
                    .iter()
                    .filter(|&&w| w != u && w != v)
                    .filter_map(|&w| {
                        let x = points[w as usize];
                        let r: [f64; 3] = std::array::from_fn(|i| x[i] - p[i]);
                        let t = crate::geom::dot_f(r, d) / len2;
                        let off: [f64; 3] = std::array::from_fn(|i| r[i] - t * d[i]);
                        let near = crate::geom::dot_f(off, off) <= (1e-18 * len2).max(tol * tol);
                        (t > 1e-9 && t < 1.0 - 1e-9 && near).then_some((t, w))
                    })
                    .collect();
                inside.sort_by(|a, b| a.0.total_cmp(&b.0));
                out.extend(inside.into_iter().map(|(_, w)| w));
            }
            out
        })
        .collect()
}
