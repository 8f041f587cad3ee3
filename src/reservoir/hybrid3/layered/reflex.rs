//! The section's reflex corners where `section::inset` moved a pillar
//! along one of its sides: the outline then has a short piece from the
//! moved point P' to the pillar's own point X, on the line L of a column
//! side inside the cavity. Across that piece lies no reservoir but the
//! strip the other side's leaning wall leaves in the next column. The cell
//! g on the piece, reaching over it, faced the reservoir from the wrong
//! column (SPE9: about two links per corner off their faces). So the strip
//! gets a cell of its own, g's mirror image across L (its site mirrored,
//! its weight g's): L is then their power bisector, and every other face
//! of the mirror cell a power bisector with an open cell (`cells`).

use crate::mesh::Mesh;
use crate::reservoir::hybrid::Region;
use std::collections::BTreeSet;

/// One corner: the points P' and X (section point ids) and the cell g on
/// the piece P' -> X.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Corner {
    pub(super) p: u32,
    pub(super) x: u32,
    pub(super) g: usize,
}

/// How far y lies left of the line a -> z (times |z - a|).
pub(super) fn left_of(a: [f64; 2], z: [f64; 2], y: [f64; 2]) -> f64 {
    (z[0] - a[0]) * (y[1] - a[1]) - (z[1] - a[1]) * (y[0] - a[0])
}

/// The corners of a cavity (its cells `cells`, edge owners `owner`, the
/// moved and own points of its reflex pillars `pairs`) where a transition
/// cell's edge P' -> X lies on the cavity's side.
pub(super) fn corners(
    m: &Mesh,
    region: &[Region],
    cells: &[usize],
    owner: &crate::FastMap<(u32, u32), u32>,
    pairs: &[[[f64; 2]; 2]],
) -> Vec<Corner> {
    let mine: BTreeSet<usize> = cells
        .iter()
        .copied()
        .filter(|&c| region[c] == Region::Transition)
        .collect();
    let open = |a: u32, b: u32| {
        !owner
            .get(&(b, a))
            .is_some_and(|&d| mine.contains(&(d as usize)))
    };
    let find = |q: [f64; 2]| m.points.iter().position(|&y| y == q).map(|i| i as u32);
    let mut out = vec![];
    for &[pm, own] in pairs {
        let (Some(p), Some(x)) = (find(pm), find(own)) else {
            continue;
        };
        let g = mine.iter().copied().find(|&c| {
            let poly = &m.cells[c];
            (0..poly.len()).any(|k| {
                let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
                open(a, b) && ((a, b) == (p, x) || (a, b) == (x, p))
            })
        });
        if let Some(g) = g {
            out.push(Corner { p, x, g });
        }
    }
    out
}

/// The mesh with each corner's mirror cell appended (cell
/// `m.cells.len() + i` for corner i): g's site and weight mirrored across
/// the line P' -> X, its polygon the triangle of P', X and its site (it is
/// open on the two sides from its site: its reach, not g's polygon
/// mirrored, is its cell, and g's mirrored corners may lie across its
/// power bisectors with the open cells beside it).
pub(super) fn mirrored(m: &Mesh, corners: &[Corner]) -> Mesh {
    let mut out = m.clone();
    for k in corners {
        let (p, x) = (m.points[k.p as usize], m.points[k.x as usize]);
        let d = [x[0] - p[0], x[1] - p[1]];
        let dd = d[0] * d[0] + d[1] * d[1];
        let flip = |q: [f64; 2]| {
            let r = [q[0] - p[0], q[1] - p[1]];
            let t = 2.0 * (r[0] * d[0] + r[1] * d[1]) / dd;
            [p[0] + t * d[0] - r[0], p[1] + t * d[1] - r[1]]
        };
        // g's edge on the piece, u -> v; the mirror's v -> u
        let poly = &m.cells[k.g];
        let n = poly.len();
        let Some(e) = (0..n).find(|&e| {
            [poly[e], poly[(e + 1) % n]].contains(&k.p)
                && [poly[e], poly[(e + 1) % n]].contains(&k.x)
        }) else {
            continue;
        };
        let (u, v) = (poly[e], poly[(e + 1) % n]);
        let site = flip(m.sites[k.g]);
        out.points.push(site);
        out.cells.push(vec![v, u, out.points.len() as u32 - 1]);
        out.sites.push(site);
        out.weights.push(m.weights[k.g]);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An outline's corner: P' = (-1, 0), X = (0, 0), g the triangle on
    /// P' -> X above, with two closed neighbours.
    fn corner() -> Mesh {
        Mesh {
            points: vec![
                [-1.0, 0.0], // 0 P'
                [0.0, 0.0],  // 1 X
                [-1.0, 0.5], // 2
                [4.0, 0.0],  // 3
                [0.0, 3.0],  // 4
                [-4.0, 0.0], // 5
                [-4.0, 3.0], // 6
            ],
            cells: vec![
                vec![0, 1, 2],          // g
                vec![1, 3, 4],          // right of X
                vec![5, 0, 2, 1, 4, 6], // left
            ],
            sites: vec![[-0.5, 0.1], [1.0, 1.0], [-2.0, 1.0]],
            weights: vec![0.25, 0.0, 0.0],
            ..Mesh::default()
        }
    }

    #[test]
    fn a_corner_is_found_by_its_piece() {
        let m = corner();
        let owner = m.edge_owners();
        let region = vec![Region::Transition; 3];
        let pairs = [[[-1.0, 0.0], [0.0, 0.0]]];
        let found = corners(&m, &region, &[0, 1, 2], &owner, &pairs);
        assert_eq!(found, vec![Corner { p: 0, x: 1, g: 0 }]);
        // points not in the mesh, or g not the cavity's: none
        let none = corners(&m, &region, &[0, 1, 2], &owner, &[[[9.0, 9.0], [0.0, 0.0]]]);
        assert!(none.is_empty());
        let none = corners(&m, &region, &[1, 2], &owner, &pairs);
        assert!(none.is_empty());
    }

    #[test]
    fn the_mirror_cell_shares_the_piece() {
        let m = corner();
        let out = mirrored(&m, &[Corner { p: 0, x: 1, g: 0 }]);
        assert_eq!(out.cells.len(), 4);
        // X -> P' reversed against g's P' -> X, then g's site mirrored
        assert_eq!(out.cells[3], vec![1, 0, out.points.len() as u32 - 1]);
        assert_eq!(*out.points.last().unwrap(), [-0.5, -0.1]);
        assert_eq!(out.sites[3], [-0.5, -0.1]);
        assert_eq!(out.weights[3], 0.25);
        // counter-clockwise, as the section's cells are
        let q: Vec<[f64; 2]> = out.cells[3]
            .iter()
            .map(|&v| out.points[v as usize])
            .collect();
        assert!(left_of(q[0], q[1], q[2]) > 0.0);
    }
}
