//! The transition's complex in the 3 x 3 cavity around the well: the
//! cavity's walls (rectangles, each facing a reservoir cell), its top and
//! bottom with the well's outline as a window, and the well's outer
//! surface; and its certified mesh.

use super::lattice::Level;
use super::radial::Radial;
use super::Hybrid3Options;
use crate::backend::Backend;
use crate::complex::{Complex3, Facet};
use crate::conform::{conform3, Outcome, D3};
use crate::error::{Error, Result};
use crate::geom::cross_f;
use crate::options::Options;
use crate::reservoir::CornerPointGrid;
use std::collections::HashMap;

/// Marker of the cavity's walls, top and bottom.
pub(super) const WALL: i64 = 1;
/// Marker of the well's outer faces.
pub(super) const WELL: i64 = 2;

/// The transition's constraints and what each facet faces.
pub(super) struct Cavity {
    pub(super) cx: Complex3,
    /// Per wall facet: the reservoir cell beyond.
    pub(super) wall_cells: Vec<[usize; 3]>,
    /// The first facet of the well's surface, and per such facet its
    /// (layer, sector).
    pub(super) first_well_facet: usize,
    pub(super) well_facets: Vec<(usize, usize)>,
}

impl Cavity {
    /// The cavity's complex around the well.
    pub(super) fn new(g: &CornerPointGrid, w: &Radial) -> Cavity {
        let (i0, j0, m, nl, zs) = (w.i0, w.j0, w.m, w.nl, &w.zs);
        let levels = &w.levels;
        // The transition's complex: the cavity's walls, its top and bottom with
        // the well's outline as a window, the well's outer surface.
        let mut cx = Complex3::default();
        let mut index: HashMap<[u64; 3], u32> = HashMap::new();
        let mut point = |cx: &mut Complex3, p: [f64; 3]| -> u32 {
            *index.entry(p.map(f64::to_bits)).or_insert_with(|| {
                cx.points.push(p);
                cx.vertex_ids.push(cx.points.len() as i64);
                cx.points.len() as u32 - 1
            })
        };
        let (ia, ib, ja, jb) = (i0 - 1, i0 + 2, j0 - 1, j0 + 2);
        // the cavity's boundary loop of columns' corners, counter-clockwise
        let mut lp: Vec<(usize, usize)> = vec![];
        lp.extend((ia..ib).map(|i| (i, ja)));
        lp.extend((ja..jb).map(|j| (ib, j)));
        lp.extend((ia + 1..=ib).rev().map(|i| (i, jb)));
        lp.extend((ja + 1..=jb).rev().map(|j| (ia, j)));
        let facet = |polygons: Vec<Vec<u32>>, holes: Vec<[f64; 3]>, marker: i64| Facet {
            polygons,
            holes,
            marker,
        };
        let mut wall_cells: Vec<[usize; 3]> = vec![]; // per wall facet: the reservoir cell beyond
        for k in 0..g.nz {
            for e in 0..lp.len() {
                let (a, b) = (lp[e], lp[(e + 1) % lp.len()]);
                let ids = vec![
                    point(&mut cx, w.node(a.0, a.1, k)),
                    point(&mut cx, w.node(b.0, b.1, k)),
                    point(&mut cx, w.node(b.0, b.1, k + 1)),
                    point(&mut cx, w.node(a.0, a.1, k + 1)),
                ];
                cx.facets.push(facet(vec![ids], vec![], WALL));
                // the cell outside: the loop runs counter-clockwise, so outside
                // is on the right of a -> b
                let (di, dj) = (b.0 as i64 - a.0 as i64, b.1 as i64 - a.1 as i64);
                let cell = if dj == 0 {
                    // along x: the cell below (dj = 0, di = 1) or above (di = -1)
                    let i = a.0.min(b.0);
                    if di > 0 {
                        [i, a.1 - 1, k]
                    } else {
                        [i, a.1, k]
                    }
                } else {
                    let j = a.1.min(b.1);
                    if dj > 0 {
                        [a.0, j, k]
                    } else {
                        [a.0 - 1, j, k]
                    }
                };
                wall_cells.push(cell);
            }
        }
        let outline = |cx: &mut Complex3,
                       point: &mut dyn FnMut(&mut Complex3, [f64; 3]) -> u32,
                       k: usize|
         -> Vec<u32> { (0..m).map(|s| point(cx, w.surface(s, k))).collect() };
        for k in [0, nl] {
            let rim: Vec<u32> = lp
                .iter()
                .map(|&(i, j)| point(&mut cx, w.node(i, j, k)))
                .collect();
            let window = outline(&mut cx, &mut point, k);
            let inside = w.at(0.0, 0.0, levels[k]);
            cx.facets.push(facet(vec![rim, window], vec![inside], WALL));
        }
        let first_well_facet = cx.facets.len();
        let mut well_facets: Vec<(usize, usize)> = vec![]; // per facet: (layer, sector)
        for k in 0..nl {
            let lo = outline(&mut cx, &mut point, k + 1);
            let hi = outline(&mut cx, &mut point, k);
            for s in 0..m {
                let (a, b, c, d) = (hi[s], hi[(s + 1) % m], lo[(s + 1) % m], lo[s]);
                if w.vertical || (w.exact(k) && w.exact(k + 1)) {
                    cx.facets.push(facet(vec![vec![a, b, c, d]], vec![], WELL));
                    well_facets.push((k, s));
                } else {
                    // The in-plane Delaunay diagonal. Measured against
                    // diagonals alternating from sector to sector (which avoid
                    // twisted prisms, Schoenhardt, Rambau) on five wells, dips
                    // 5 to 30: fewer sites outside on three (7x7x2, dip 20: 2
                    // of 72 against 9), as many on one, 2 more on one.
                    let angle_at = |o: u32, x: u32, y: u32| {
                        let [po, px, py] = [o, x, y].map(|v| cx.points[v as usize]);
                        let e: [f64; 3] = std::array::from_fn(|i| px[i] - po[i]);
                        let f: [f64; 3] = std::array::from_fn(|i| py[i] - po[i]);
                        let dot: f64 = (0..3).map(|i| e[i] * f[i]).sum();
                        let n = cross_f(e, f);
                        n.iter().map(|x| x * x).sum::<f64>().sqrt().atan2(dot)
                    };
                    let ac = angle_at(b, a, c) + angle_at(d, c, a) <= std::f64::consts::PI;
                    let halves = if ac {
                        [vec![a, b, c], vec![a, c, d]]
                    } else {
                        [vec![a, b, d], vec![b, c, d]]
                    };
                    for t in halves {
                        cx.facets.push(facet(vec![t], vec![], WELL));
                        well_facets.push((k, s));
                    }
                }
            }
        }
        cx.holes
            .push(w.at(0.0, 0.0, Level::Height((zs[0] + zs[g.nz]) / 2.0)));
        Cavity {
            cx,
            wall_cells,
            first_well_facet,
            well_facets,
        }
    }

    /// The certified transition mesh: cut at the grid's top and bottom
    /// when asked, else (or when that fails) with the annuli there as faces.
    pub(super) fn mesh<B: Backend + ?Sized>(
        &self,
        backend: &B,
        opts: &Hybrid3Options,
    ) -> Result<Outcome<D3>> {
        let (cx, first_well_facet) = (&self.cx, self.first_well_facet);
        let top = first_well_facet as u32 - 2;
        let run = |clip: Vec<u32>| {
            conform3(
                backend,
                cx,
                &Options {
                    allow_sites_outside: opts.allow_sites_outside,
                    // The walls' and the well's rectangles face cells centred on
                    // them: orthogonal links need their power centres at their
                    // centres, hence equal weights.
                    whole_polygons: crate::weights::Keep::Shared,
                    split_facets: opts.split_facets,
                    clip,
                    ..Default::default()
                },
            )
        };
        // Clipping needs every wall's and well face's sites below the top and
        // above the bottom (a deviated well's triangles may have theirs
        // beyond); where it fails, the annuli are faces again.
        let t = match opts.clip {
            true => run(vec![top, top + 1]).or_else(|cut| {
                run(vec![]).map_err(|faces| {
                    Error::Tried(vec![
                        ("cut at the grid's top and bottom".into(), cut),
                        ("with the annuli there as faces".into(), faces),
                    ])
                })
            })?,
            false => run(vec![])?,
        };
        Ok(t)
    }
}
