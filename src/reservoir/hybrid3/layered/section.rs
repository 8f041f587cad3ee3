//! The cross-section of a layer cake: the grid's pillars where they cross
//! a plane across its layers, as a one-layer grid in the layers' frame, and
//! the 2D hybrid mesh of its wells on it (`reservoir::hybrid`).

use super::frame::Frame;
use crate::backend::Backend;
use crate::error::Result;
use crate::reservoir::hybrid::{self, Hybrid, HybridOptions, WellAt, WellInput};
use crate::reservoir::CornerPointGrid;
use std::collections::{BTreeMap, BTreeSet};

/// The one-layer grid of the pillars' crossings of the plane at height
/// `at` (frame coordinates; pillars vertical in it), its columns active
/// where `live`.
pub(super) fn grid(
    g: &CornerPointGrid,
    f: &Frame,
    at: f64,
    live: impl Fn([usize; 2]) -> bool,
) -> CornerPointGrid {
    let (nx, ny) = (g.nx, g.ny);
    let mut s = CornerPointGrid::layered([nx, ny], [1.0, 1.0], &[0.0, 1.0]);
    for (p, c) in g.coord.iter().enumerate() {
        let [u, v] = f.crossing(*c, at);
        s.coord[p] = [u, v, 0.0, u, v, 1.0];
    }
    for j in 0..ny {
        for i in 0..nx {
            s.actnum[i + nx * j] = live([i, j]);
        }
    }
    s
}

/// The cavities' columns, where given, with the points where the
/// section's reflex pillars were before `inset` moved them.
pub(super) type Given<'a> = Option<(&'a BTreeSet<[usize; 2]>, &'a [(usize, [f64; 2])])>;

/// How the section's 2D hybrid is asked: its cavities' sides split near
/// the wells, its radial meshes kept in their columns.
#[derive(Clone, Copy, Default)]
pub(super) struct Ask {
    pub(super) split: bool,
    pub(super) in_column: bool,
    /// Convex corners of the cavities owned by one cell each.
    pub(super) corners: bool,
    /// `HybridOptions::first_ring`.
    pub(super) first_ring: Option<f64>,
}

/// The 2D hybrid's options for the section: the 3D hybrid's rings, sectors
/// and outer radius, its wells at map points `at` (frame coordinates), the
/// cavities' columns chosen by the 2D hybrid or the given ones, as asked.
/// Radial meshes in their columns get column sides split twice as finely
/// near them: the transition then resolves the radial flow beyond the
/// rings (Thiem on a layered section, tests/hybrid3.rs: 0.6% off, 1.2%
/// with pieces as long as their distance to the well).
fn options(
    s: &CornerPointGrid,
    wells: &[(String, [f64; 2], f64)],
    [rings, sectors]: [usize; 2],
    outer: f64,
    cavity: Given,
    ask: Ask,
) -> (Vec<WellInput>, HybridOptions) {
    let input: Vec<WellInput> = wells
        .iter()
        .map(|(name, at, radius)| WellInput {
            name: name.clone(),
            at: WellAt::Xy(*at),
            radius: *radius,
        })
        .collect();
    let opts = HybridOptions {
        layer: 0,
        rings,
        sectors,
        outer,
        allow_sites_outside: true,
        layered_section: true,
        split_sides: ask.split,
        in_column: ask.in_column,
        corner_cells: ask.corners,
        piece_share: if ask.in_column { 0.5 } else { 1.0 },
        inner_pillars: cavity.map_or(vec![], |c| c.1.to_vec()),
        first_ring: ask.first_ring,
        cavity: cavity.map(|(cols, _)| {
            let mut flags = vec![false; s.nx * s.ny];
            for &[i, j] in cols {
                flags[j * s.nx + i] = true;
            }
            flags
        }),
        ..Default::default()
    };
    (input, opts)
}

/// The 2D hybrid mesh of the wells on the section grid (`options`).
pub(super) fn mesh<B: Backend + ?Sized>(
    backend: &B,
    s: &CornerPointGrid,
    wells: &[(String, [f64; 2], f64)],
    rs: [usize; 2],
    outer: f64,
    cavity: Given,
    ask: Ask,
) -> Result<Hybrid> {
    let (input, opts) = options(s, wells, rs, outer, cavity, ask);
    hybrid::build(backend, s, &input, &opts)
}

/// The columns the 2D hybrid's cavities start from on the section grid.
pub(super) fn columns(
    s: &CornerPointGrid,
    wells: &[(String, [f64; 2], f64)],
    rs: [usize; 2],
    outer: f64,
) -> Result<BTreeSet<[usize; 2]>> {
    let (input, opts) = options(s, wells, rs, outer, None, Ask::default());
    let flags = hybrid::cavity_columns(s, &input, &opts)?;
    Ok((0..s.nx * s.ny)
        .filter(|&c| flags[c])
        .map(|c| [c % s.nx, c / s.nx])
        .collect())
}

/// The section's pillars on the cavities' sides moved in, each side as far
/// as its wall leans in between the cavity's top and bottom, so that no
/// prism of the section crosses an outer wall within the cavity's layers
/// (a cell cut there has a corner of a face on the wall, far from its
/// site); the cells beside the sides then reach out to the walls. None
/// where a cavity touches itself at a pillar (the grid left as it was).
/// Twisted layers (`layers` k0..=k1 given): the lean to the cavity's own
/// top and bottom corners at each pillar, not to the planes'. Else, the
/// points where the moved pillars at reflex corners of the outline were
/// (`HybridOptions::inner_pillars`): the column sides inside that start
/// there keep their lines.
pub(super) fn inset(
    g: &CornerPointGrid,
    f: &Frame,
    [at, top, bottom]: [f64; 3],
    s: &mut CornerPointGrid,
    cols: &BTreeSet<[usize; 2]>,
    layers: Option<[usize; 2]>,
) -> Option<Vec<(usize, [f64; 2])>> {
    let pid = |i: usize, j: usize| j * (g.nx + 1) + i;
    let mid = |p: usize| f.crossing(g.coord[p], at);
    // per pillar, the lines its sides are moved to: inward unit normal n
    // and offset c (points x with n.x = c)
    let mut lines: BTreeMap<usize, Vec<([f64; 2], f64)>> = BTreeMap::new();
    for &[i, j] in cols {
        let centre = [(0, 0), (1, 0), (0, 1), (1, 1)]
            .map(|(di, dj)| mid(pid(i + di, j + dj)))
            .iter()
            .fold([0.0; 2], |a, p| [a[0] + p[0] / 4.0, a[1] + p[1] / 4.0]);
        let sides = [
            (i.checked_sub(1).map(|i| [i, j]), pid(i, j), pid(i, j + 1)),
            (Some([i + 1, j]), pid(i + 1, j), pid(i + 1, j + 1)),
            (j.checked_sub(1).map(|j| [i, j]), pid(i, j), pid(i + 1, j)),
            (Some([i, j + 1]), pid(i, j + 1), pid(i + 1, j + 1)),
        ];
        for (across, p, q) in sides {
            if across.is_some_and(|c| cols.contains(&c)) {
                continue;
            }
            let (x, y) = (mid(p), mid(q));
            let (dx, dy) = (y[0] - x[0], y[1] - x[1]);
            let len = dx.hypot(dy);
            let mut n = [-dy / len, dx / len];
            if n[0] * (centre[0] - x[0]) + n[1] * (centre[1] - x[1]) < 0.0 {
                n = [-n[0], -n[1]];
            }
            let mut shift: f64 = 0.0;
            for r in [p, q] {
                let m = mid(r);
                let ends = match layers {
                    Some([k0, k1]) => {
                        // the pillar's corner of column (i, j)
                        let (pi, pj) = (r % (g.nx + 1), r / (g.nx + 1));
                        let n = pi - i + 2 * (pj - j);
                        let uv = |k: usize, n: usize| {
                            let [x, y, d] = g.corner(i, j, k, n);
                            let q = f.to([x, y, -d]);
                            [q[0], q[1]]
                        };
                        [uv(k0, n), uv(k1, n + 4)]
                    }
                    None => [top, bottom].map(|h| f.crossing(g.coord[r], h)),
                };
                for c in ends {
                    shift = shift.max(n[0] * (c[0] - m[0]) + n[1] * (c[1] - m[1]));
                }
            }
            let c = n[0] * x[0] + n[1] * x[1] + shift;
            lines.entry(p).or_default().push((n, c));
            lines.entry(q).or_default().push((n, c));
        }
    }
    let mut moved = vec![];
    for (p, ls) in lines {
        let [(n1, c1), (n2, c2)] = ls[..] else {
            return None;
        };
        let det = n1[0] * n2[1] - n1[1] * n2[0];
        let m = mid(p);
        let x = if layers.is_some() {
            // twisted layers: sides that bend slightly at a pillar would
            // meet far off with their own shifts; both moved by the larger,
            // the pillar goes along their bisector, each side at least as
            // far in as it needs at both its ends
            let shift = (c1 - n1[0] * m[0] - n1[1] * m[1]).max(c2 - n2[0] * m[0] - n2[1] * m[1]);
            let t = shift / (1.0 + n1[0] * n2[0] + n1[1] * n2[1]);
            [m[0] + t * (n1[0] + n2[0]), m[1] + t * (n1[1] + n2[1])]
        } else if det.abs() > 1e-6 {
            [
                (c1 * n2[1] - c2 * n1[1]) / det,
                (n1[0] * c2 - n2[0] * c1) / det,
            ]
        } else {
            // one straight side through the pillar
            let shift = (c1 - n1[0] * m[0] - n1[1] * m[1]).max(c2 - n2[0] * m[0] - n2[1] * m[1]);
            [m[0] + shift * n1[0], m[1] + shift * n1[1]]
        };
        moved.push((p, x));
    }
    let mut reflex = vec![];
    for (p, [u, v]) in moved {
        let (i, j) = (p % (g.nx + 1), p / (g.nx + 1));
        let around = [(0, 0), (1, 0), (0, 1), (1, 1)]
            .into_iter()
            .filter(|&(di, dj)| {
                (i + di)
                    .checked_sub(1)
                    .zip((j + dj).checked_sub(1))
                    .is_some_and(|(a, b)| cols.contains(&[a, b]))
            })
            .count();
        let m = mid(p);
        let moved = (m[0] - u).hypot(m[1] - v) > 10.0 * f.tol();
        if around == 3 && layers.is_none() && moved {
            reflex.push((p, m));
        }
        s.coord[p] = [u, v, 0.0, u, v, 1.0];
    }
    Some(reflex)
}
