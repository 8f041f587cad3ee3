//! Single-phase incompressible flow with two-point fluxes on a polygon mesh:
//! what an orthogonal mesh is for, and the check that it gives Thiem's
//! radial solution around a well (docs/method.md section 6).

use crate::error::{Error, Result};
use crate::mesh::{Mesh, Network};
use serde::Serialize;

/// A connection between two cells across a face: its length (area per unit
/// thickness) and the signed distances from each site to the face's line
/// (TOUGH's D1, D2; positive on the cell's own side). Transmissibility per
/// unit permeability: area / (d1 + d2).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Connection {
    /// The two cells.
    pub cells: [u32; 2],
    /// The face's length (area in 3D).
    pub area: f64,
    /// Distances from each site to the face.
    pub d: [f64; 2],
}

/// A face on the mesh's boundary: its cell, points, length and the site's
/// distance to it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoundaryFace {
    /// Its cell.
    pub cell: u32,
    /// Its end points.
    pub points: [u32; 2],
    /// Its length.
    pub area: f64,
    /// Distance from the cell's site to it.
    pub d: f64,
}

fn signed_distance(mesh: &Mesh, a: u32, b: u32, x: [f64; 2]) -> (f64, f64) {
    let (pa, pb) = (mesh.points[a as usize], mesh.points[b as usize]);
    let e = [pb[0] - pa[0], pb[1] - pa[1]];
    let len = e[0].hypot(e[1]);
    // positive on the left of a -> b
    ((e[0] * (x[1] - pa[1]) - e[1] * (x[0] - pa[0])) / len, len)
}

/// The connections of a mesh's interior faces.
pub fn connections(mesh: &Mesh) -> Vec<Connection> {
    mesh.faces
        .iter()
        .map(|&[a, b, c, d]| {
            let (dc, len) = signed_distance(mesh, a, b, mesh.sites[c as usize]);
            let (dd, _) = signed_distance(mesh, a, b, mesh.sites[d as usize]);
            Connection {
                cells: [c, d],
                area: len,
                d: [dc, -dd],
            }
        })
        .collect()
}

/// The two-point flux network of a plane mesh whose cells have thickness
/// and mid-depth: an element per cell at its site and mid-depth (z up),
/// volume = area x thickness; a connection per interior face with each
/// site's distance to the face, the face's area (length x the two cells'
/// mean thickness) and the gravity cosine from the depths.
pub fn network(mesh: &Mesh, thickness: &[f64], depth: &[f64]) -> Network {
    use crate::mesh::{Connection as Link, Element};
    let node = |c: usize| [mesh.sites[c][0], mesh.sites[c][1], -depth[c]];
    Network {
        elements: (0..mesh.cells.len())
            .map(|c| Element {
                volume: mesh.area(&mesh.cells[c]) * thickness[c],
                node: node(c),
            })
            .collect(),
        connections: connections(mesh)
            .into_iter()
            .map(|c| {
                let [a, b] = c.cells.map(|x| x as usize);
                let area = c.area * (thickness[a] + thickness[b]) / 2.0;
                Link::lateral([a, b], node(a), node(b), c.d, area)
            })
            .collect(),
    }
}

/// Cell edges without a twin: the boundary.
pub fn boundary_faces(mesh: &Mesh) -> Vec<BoundaryFace> {
    let owner = mesh.edge_owners();
    let mut out: Vec<BoundaryFace> = owner
        .iter()
        .filter(|(&(a, b), _)| !owner.contains_key(&(b, a)))
        .map(|(&(a, b), &c)| {
            let (d, area) = signed_distance(mesh, a, b, mesh.sites[c as usize]);
            BoundaryFace {
                cell: c,
                points: [a, b],
                area,
                d,
            }
        })
        .collect();
    out.sort_by_key(|f| (f.cell, f.points));
    out
}

/// Connections whose two-point transmissibility is not positive, and those
/// whose face is not orthogonal to the line between their sites.
#[derive(Debug, Clone, Default, Serialize)]
pub struct TransmissibilityStats {
    /// Connections in all.
    pub connections: usize,
    /// Those with a negative transmissibility.
    pub negative: usize,
    /// Those whose face is not orthogonal to the link (defect above ORTHOGONAL).
    pub non_orthogonal: usize,
}

/// |cos| above which a connection counts as non-orthogonal.
pub const ORTHOGONAL: f64 = 1e-6;

/// Transmissibility counts over the connections whose cells `which` accepts.
pub fn stats(
    mesh: &Mesh,
    conns: &[Connection],
    only: impl Fn([u32; 2]) -> bool,
) -> TransmissibilityStats {
    let mut s = TransmissibilityStats::default();
    for (c, f) in conns.iter().zip(&mesh.faces) {
        if !only(c.cells) {
            continue;
        }
        s.connections += 1;
        s.negative += usize::from(c.d[0] + c.d[1] <= 0.0);
        s.non_orthogonal += usize::from(mesh.face_defect(*f) > ORTHOGONAL);
    }
    s
}

/// Pressures of incompressible single-phase flow with unit permeability and
/// viscosity: sources per cell (volume per time per unit thickness), and
/// fixed pressures at some boundary faces. Conjugate gradients with a
/// Jacobi preconditioner on the (symmetric positive definite) system.
pub fn pressures(
    n: usize,
    conns: &[Connection],
    fixed: &[(BoundaryFace, f64)],
    source: &[f64],
) -> Result<Vec<f64>> {
    let fixed: Vec<(u32, f64, f64)> = fixed
        .iter()
        .map(|(f, p)| (f.cell, f.area / f.d, *p))
        .collect();
    solve(n, conns, &fixed, source)
}

/// `pressures` with the fixed pressures given as (cell, transmissibility
/// to the boundary, pressure): any dimension.
pub fn solve(
    n: usize,
    conns: &[Connection],
    fixed: &[(u32, f64, f64)],
    source: &[f64],
) -> Result<Vec<f64>> {
    let mut diag = vec![0.0; n];
    let mut rhs = source.to_vec();
    let mut off: Vec<(u32, u32, f64)> = vec![];
    for c in conns {
        let t = c.area / (c.d[0] + c.d[1]);
        if !(t.is_finite() && t > 0.0) {
            return Err(Error::Usage(format!(
                "cells {} and {}: transmissibility {t} is not positive",
                c.cells[0], c.cells[1]
            )));
        }
        let [a, b] = c.cells.map(|x| x as usize);
        diag[a] += t;
        diag[b] += t;
        off.push((c.cells[0], c.cells[1], t));
    }
    for &(cell, t, p) in fixed {
        diag[cell as usize] += t;
        rhs[cell as usize] += t * p;
    }
    if diag.iter().any(|&d| d <= 0.0) {
        return Err(Error::Usage("a cell is not connected to anything".into()));
    }
    let apply = |x: &[f64], y: &mut [f64]| {
        for i in 0..n {
            y[i] = diag[i] * x[i];
        }
        for &(a, b, t) in &off {
            let (a, b) = (a as usize, b as usize);
            y[a] -= t * x[b];
            y[b] -= t * x[a];
        }
    };
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let mut x = vec![0.0; n];
    let mut r = rhs.clone();
    let mut z: Vec<f64> = r.iter().zip(&diag).map(|(r, d)| r / d).collect();
    let mut p = z.clone();
    let mut ap = vec![0.0; n];
    let mut rz = dot(&r, &z);
    let goal = 1e-13 * dot(&rhs, &rhs).sqrt();
    for _ in 0..10 * n + 100 {
        if dot(&r, &r).sqrt() <= goal {
            return Ok(x);
        }
        apply(&p, &mut ap);
        let alpha = rz / dot(&p, &ap);
        for i in 0..n {
            x[i] += alpha * p[i];
            r[i] -= alpha * ap[i];
        }
        for i in 0..n {
            z[i] = r[i] / diag[i];
        }
        let rz2 = dot(&r, &z);
        for i in 0..n {
            p[i] = z[i] + rz2 / rz * p[i];
        }
        rz = rz2;
    }
    Err(Error::Usage("the pressure solve did not converge".into()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn linear_pressure_on_a_row_of_squares() {
        // Three unit squares in a row, pressure 1 on the left side and 0 on
        // the right: the cells read 5/6, 1/2, 1/6.
        let mut m = Mesh {
            points: (0..4)
                .flat_map(|i| [[i as f64, 0.0], [i as f64, 1.0]])
                .collect(),
            cells: (0..3u32)
                .map(|i| vec![2 * i, 2 * i + 2, 2 * i + 3, 2 * i + 1])
                .collect(),
            sites: (0..3).map(|i| [i as f64 + 0.5, 0.5]).collect(),
            weights: vec![0.0; 3],
            size: 3.0,
            ..Default::default()
        };
        m.match_faces(&Default::default());
        let conns = connections(&m);
        assert_eq!(conns.len(), 2);
        assert!(conns.iter().all(|c| c.d == [0.5, 0.5] && c.area == 1.0));
        let fixed: Vec<(BoundaryFace, f64)> = boundary_faces(&m)
            .into_iter()
            .filter(|f| {
                (m.points[f.points[0] as usize][0] - m.points[f.points[1] as usize][0]).abs()
                    < 1e-12
            })
            .map(|f| {
                let x = m.points[f.points[0] as usize][0];
                (f, if x == 0.0 { 1.0 } else { 0.0 })
            })
            .collect();
        assert_eq!(fixed.len(), 2);
        let p = pressures(3, &conns, &fixed, &[0.0; 3]).unwrap();
        for (got, want) in p.iter().zip([5.0 / 6.0, 0.5, 1.0 / 6.0]) {
            assert!((got - want).abs() < 1e-12, "{p:?}");
        }
        let s = stats(&m, &conns, |_| true);
        assert_eq!((s.connections, s.negative, s.non_orthogonal), (2, 0, 0));
    }
}
