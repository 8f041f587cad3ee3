//! The wells stage: each well placed in its column, its radial mesh's
//! outer radius kept clear of other wells, inactive columns, the grid's
//! edge and faults; the radial mesh's rings and sites.

use super::map::{distance_to_polygon, fault_edges, to_segment};
use super::{HybridOptions, Layer, WellAt, WellInput};
use crate::error::{Error, Result};
use std::f64::consts::TAU;

/// One well placed: centre, radii of its rings, and the shortest side of
/// its column (`reach`), which sets how far its cavity extends.
pub(super) struct Placed {
    pub(super) name: String,
    pub(super) centre: [f64; 2],
    pub(super) radii: Vec<f64>,
    pub(super) reach: f64,
    /// The column the well is in.
    pub(super) column: (usize, usize),
}

/// The wells placed, with their rings' radii.
pub(super) fn place(
    layer: &Layer,
    wells: &[WellInput],
    opts: &HybridOptions,
    tell: &dyn Fn(&str, usize, usize),
) -> Result<Vec<Placed>> {
    let (grid, k, view, nx, ny) = (layer.grid, layer.k, &layer.view, layer.nx, layer.ny);
    let quad_points = |i: usize, j: usize| layer.quad_points(i, j);
    let mut placed: Vec<Placed> = vec![];
    for (n, w) in wells.iter().enumerate() {
        tell("placing wells", n + 1, wells.len());
        let (centre, column) = match w.at {
            WellAt::Column(i, j) => {
                if i >= nx || j >= ny {
                    return Err(Error::Usage(format!(
                        "well {}: column ({}, {}) outside the grid (1..{nx}, 1..{ny})",
                        w.name,
                        i + 1,
                        j + 1
                    )));
                }
                (view.centroid(i, j), (i, j))
            }
            WellAt::Xy(x) => {
                let col = (0..ny)
                    .flat_map(|j| (0..nx).map(move |i| (i, j)))
                    .find(|&(i, j)| distance_to_polygon(x, &quad_points(i, j)) == 0.0)
                    .ok_or_else(|| {
                        Error::Usage(format!("well {}: {x:?} is outside the grid", w.name))
                    })?;
                (x, col)
            }
        };
        if !grid.active(column.0, column.1, k) {
            return Err(Error::Usage(format!(
                "well {}: cell ({}, {}, {}) is inactive",
                w.name,
                column.0 + 1,
                column.1 + 1,
                k + 1
            )));
        }
        let q = quad_points(column.0, column.1);
        let side = (0..4)
            .map(|e| (q[(e + 1) % 4][0] - q[e][0]).hypot(q[(e + 1) % 4][1] - q[e][1]))
            .fold(f64::INFINITY, f64::min);
        placed.push(Placed {
            name: w.name.clone(),
            centre,
            radii: vec![w.radius, opts.outer * side],
            reach: side,
            column,
        });
    }
    // A radial mesh reaches at most 0.3 of the way to the nearest other
    // well and 0.6 of the way to the nearest inactive column, grid edge or
    // fault.
    let mut obstacles: Vec<[[f64; 2]; 2]> = vec![];
    for j in 0..ny {
        for i in 0..nx {
            let q = quad_points(i, j);
            let edge = |e: usize| [q[e], q[(e + 1) % 4]];
            if !grid.active(i, j, k) {
                obstacles.extend((0..4).map(edge));
            } else {
                // sides on the grid's edge (ccw quads: bottom, right, top, left
                // up to orientation; test all four against the neighbours)
                let open = [
                    (i, j.wrapping_sub(1)),
                    (i + 1, j),
                    (i, j + 1),
                    (i.wrapping_sub(1), j),
                ];
                for (e, &(a, b)) in open.iter().enumerate() {
                    if a >= nx || b >= ny {
                        obstacles.push(edge(e));
                    }
                }
            }
        }
    }
    // Faults are walls too: a radial mesh must not cross one.
    for (p, q, _, _) in fault_edges(grid, k, view) {
        obstacles.push([view.pillar[p as usize], view.pillar[q as usize]]);
    }
    for line in &opts.fault_lines {
        obstacles.extend(line.windows(2).map(|w| [w[0], w[1]]));
    }
    for a in 0..placed.len() {
        if let Some(b) = (0..a).find(|&b| placed[b].centre == placed[a].centre) {
            return Err(Error::Usage(format!(
                "wells {} and {} are at the same place",
                placed[b].name, placed[a].name
            )));
        }
    }
    for a in 0..placed.len() {
        let wall = obstacles
            .iter()
            .map(|&o| to_segment(placed[a].centre, o))
            .fold(f64::INFINITY, f64::min);
        let nearest = (0..placed.len())
            .filter(|&b| b != a)
            .map(|b| {
                let (p, q) = (placed[a].centre, placed[b].centre);
                (p[0] - q[0]).hypot(p[1] - q[1])
            })
            .fold(f64::INFINITY, f64::min);
        let mut outer = placed[a].radii[1].min(0.3 * nearest).min(0.6 * wall);
        if opts.in_column {
            // the column's sides beyond 1.25 outer radii, with a margin
            let (i, j) = placed[a].column;
            let q = quad_points(i, j);
            let side = (0..4)
                .map(|e| to_segment(placed[a].centre, [q[e], q[(e + 1) % 4]]))
                .fold(f64::INFINITY, f64::min);
            outer = outer.min(0.75 * side);
        }
        let rw = placed[a].radii[0];
        if !(rw > 0.0 && rw < outer / 2.0) {
            return Err(Error::Usage(format!(
                "well {}: radius {rw:?} must be positive and below half the outer radius {outer:?}",
                placed[a].name
            )));
        }
        placed[a].radii = match opts.first_ring {
            Some(f) => first_ring_radii(rw, outer, opts.rings, f),
            None => ring_radii(rw, outer, opts.rings),
        };
    }
    for a in 0..placed.len() {
        for b in a + 1..placed.len() {
            let (p, q) = (&placed[a], &placed[b]);
            let d = (p.centre[0] - q.centre[0]).hypot(p.centre[1] - q.centre[1]);
            if d <= p.radii.last().unwrap() + q.radii.last().unwrap() {
                return Err(Error::Usage(format!(
                    "wells {} and {}: their radial meshes overlap (centres {d} apart)",
                    p.name, q.name
                )));
            }
        }
    }
    Ok(placed)
}

/// Radii r_0 = wellbore ... r_n = outer, in geometric progression.
pub(crate) fn ring_radii(rw: f64, outer: f64, rings: usize) -> Vec<f64> {
    (0..=rings)
        .map(|k| rw * (outer / rw).powf(k as f64 / rings as f64))
        .collect()
}

/// Radii r_0 = wellbore, r_1 = `first` x outer, ... r_n = outer: the rings
/// beyond the first in geometric progression, the first as wide as the
/// wellbore leaves it. A simulator's time steps follow its smallest cells:
/// the innermost ring's cells are then a share of the outer ring's, not
/// (rw / outer)^(2/n) of it; the wellbore's connection factor still runs
/// from rw to the first ring's site, exactly. Geometric (`ring_radii`)
/// where that would not be wider.
pub(crate) fn first_ring_radii(rw: f64, outer: f64, rings: usize, first: f64) -> Vec<f64> {
    let r1 = first * outer;
    if rings < 2 || r1 <= rw * (outer / rw).powf(1.0 / rings as f64) {
        return ring_radii(rw, outer, rings);
    }
    let q = (outer / r1).powf(1.0 / (rings - 1) as f64);
    std::iter::once(rw)
        .chain((0..rings).map(|k| match k + 1 == rings {
            true => outer,
            false => r1 * q.powi(k as i32),
        }))
        .collect()
}

/// Radii of the ring sites (ring q between radii r[q] and r[q + 1]) of a
/// radial mesh with m sectors: see the assembly in `build`. With rings in
/// geometric progression from the wellbore, beta r_q; where the first ring
/// is wider (`first_ring_radii`), the rings' own ratio sets beta and the
/// first site lies a ratio inside the second (every ring-to-ring link
/// exact again).
pub(crate) fn site_radii(r: &[f64], m: usize) -> Vec<f64> {
    let half = TAU / (2 * m) as f64;
    let beta = |alpha: f64| alpha * half.sin() * alpha.ln() / (half * (alpha - 1.0));
    let n = r.len();
    let a0 = r[1] / r[0];
    if n > 2 && a0 > r[2] / r[1] * (1.0 + 1e-6) {
        let a1 = r[2] / r[1];
        let b = beta(a1);
        let mut rho: Vec<f64> = r[1..n - 1].iter().map(|&rq| b * rq).collect();
        rho.insert(0, rho[0] / a1);
        return rho;
    }
    let beta = beta(a0);
    r[..n - 1].iter().map(|&rq| beta * rq).collect()
}

/// The site of a radial cell: sector s's mid-angle ray at radius rho.
pub(super) fn radial_site(centre: [f64; 2], rho: f64, s: usize, m: usize) -> [f64; 2] {
    let a = TAU * (s as f64 + 0.5) / m as f64;
    [centre[0] + rho * a.cos(), centre[1] + rho * a.sin()]
}

/// Corner s of the regular m-gon of radius r around c.
pub(super) fn polygon_point(c: [f64; 2], r: f64, s: usize, m: usize) -> [f64; 2] {
    let a = TAU * s as f64 / m as f64;
    [c[0] + r * a.cos(), c[1] + r * a.sin()]
}

/// Most rings and sectors a radial mesh may have (more is a typo, and
/// would not fit in memory: rings x sectors cells per well).
pub const MAX_RINGS: usize = 1000;
/// Most sectors a radial mesh may have.
pub const MAX_SECTORS: usize = 4096;

#[cfg(test)]
mod tests {
    use super::*;

    /// A wide first ring: the rings beyond it geometric, and every
    /// ring-to-ring link between sites carries the sector's radial flow
    /// exactly (chord transmissibility = radial one), the first included.
    #[test]
    fn a_wide_first_ring_keeps_ring_links_exact() {
        let (rw, outer, m) = (0.1, 300.0, 8);
        let r = first_ring_radii(rw, outer, 3, 0.25);
        assert_eq!(r.len(), 4);
        assert_eq!((r[0], r[1], r[3]), (rw, 75.0, outer));
        assert!((r[2] / r[1] - r[3] / r[2]).abs() < 1e-12);
        let rho = site_radii(&r, m);
        let half = TAU / (2 * m) as f64;
        for q in 0..rho.len() - 1 {
            assert!(rho[q] > r[q] && rho[q] < r[q + 1], "site {q} in its ring");
            let chord = 2.0 * r[q + 1] * half.sin() / (rho[q + 1] - rho[q]);
            let radial = 2.0 * half / (rho[q + 1] / rho[q]).ln();
            assert!(
                (chord / radial - 1.0).abs() < 1e-12,
                "link {q}: {chord} {radial}"
            );
        }
        // narrower than the geometric rings' first: geometric
        assert_eq!(
            first_ring_radii(rw, outer, 3, 1e-3),
            ring_radii(rw, outer, 3)
        );
    }
}
