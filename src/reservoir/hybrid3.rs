//! The 3D hybrid mesh (issue 6, part 6): a Cartesian block grid, a well
//! (vertical or deviated, straight through the grid's whole thickness)
//! with a radial mesh of rings x sectors x layers (a vertical well's are
//! the grid's; a deviated well's are slabs across its axis, the first and
//! last cut by the grid's top and bottom, so that its own links are
//! orthogonal), a cavity of
//! the 3 x 3 columns around the well's head, and a conforming orthogonal
//! transition mesh (`conform3`) between the cavity's walls and the well
//! mesh's outer surface. The walls are rectangles kept whole, so the
//! reservoir cells beyond stay hexahedra; the well's outer faces are
//! rectangles too (a deviated well's exact on a lattice, `Lattice`),
//! except in a deviated well's first and last layers, where they are
//! split in two triangles and their links to the transition need not be
//! orthogonal.

use crate::backend::Backend;
use crate::complex::{Complex3, Facet};
use crate::conform::{conform3, Report3};
use crate::error::{Error, Result};
use crate::geom::{cross_f, volume, Plane};
use crate::mesh::{CellArray, CellMesh, Cells, Link3, Mesh3};
use crate::options::Options;
use crate::reservoir::hybrid::{ring_radii, site_radii, Region};
use crate::reservoir::CornerPointGrid;
use serde::Serialize;
use std::collections::HashMap;
use std::f64::consts::TAU;

/// A well: its column (0-based), wellbore radius, and its deviation from
/// vertical (degrees) towards the azimuth (degrees clockwise from +y). A
/// deviated well's axis is rounded onto a lattice (its slopes to multiples
/// of 2^-16 or finer) for exact rectangles on its outer surface.
#[derive(Debug, Clone, PartialEq)]
pub struct Well3 {
    pub name: String,
    pub i: usize,
    pub j: usize,
    pub radius: f64,
    pub dip: f64,
    pub azimuth: f64,
}

/// Choices of the radial mesh.
#[derive(Debug, Clone)]
pub struct Hybrid3Options {
    pub rings: usize,
    pub sectors: usize,
    /// Outer radius of the radial mesh, in the well cell's shorter sides
    /// (as in 2D; it may reach into the cavity's other columns). Measured
    /// with the flow check (tests/hybrid3.rs, 16 sectors, 10 m cells, the
    /// annuli as faces): 0.4 gives 9.4% off Thiem's pressure drop, 1.0
    /// gives 0.16%, 1.3 gives 3.9%; as in 2D, the well polygon belongs near the cavity's sides but
    /// not at them.
    pub outer: f64,
    pub allow_sites_outside: bool,
    /// Steiner points in the top and bottom annuli where their triangles
    /// miss their duals (`Options3::split_facets`).
    pub split_facets: bool,
    /// Cut the transition cells at the grid's top and bottom with mirrored
    /// sites (`Options3::clip`) instead of making the annuli there faces
    /// (whose triangles may miss their duals and leave sites outside);
    /// falls back to the annuli as faces when clipping fails.
    pub clip: bool,
}

impl Default for Hybrid3Options {
    fn default() -> Self {
        Hybrid3Options {
            rings: 6,
            sectors: 16,
            outer: 1.0,
            allow_sites_outside: false,
            split_facets: false,
            clip: true,
        }
    }
}

/// The 3D hybrid mesh: reservoir hexahedra, transition polyhedra, well
/// cells, all as polyhedra with one point numbering.
#[derive(Debug, Clone)]
pub struct Hybrid3 {
    pub mesh: Mesh3,
    pub region: Vec<Region>,
    /// Per cell, its grid cell (reservoir cells).
    pub ijk: Vec<Option<[usize; 3]>>,
    pub report: Hybrid3Report,
}

/// What the build did.
#[derive(Debug, Clone, Serialize, Default)]
pub struct Hybrid3Report {
    /// Cells per region: reservoir, transition, well.
    pub cells: [usize; 3],
    pub transition: Report3,
    /// Connections between cells, and those whose two sites are not on the
    /// normal of their face (|cos| above 1e-6).
    pub connections: usize,
    pub non_orthogonal: usize,
}

/// Checks that the grid is a Cartesian block grid (vertical pillars, flat
/// horizons, axis-aligned cells) and returns its node coordinates per axis
/// (x, y, and z up = -depth).
fn axes(g: &CornerPointGrid) -> Result<[Vec<f64>; 3]> {
    let x: Vec<f64> = (0..=g.nx)
        .map(|i| g.corner(i.min(g.nx - 1), 0, 0, (i == g.nx) as usize)[0])
        .collect();
    let y: Vec<f64> = (0..=g.ny)
        .map(|j| g.corner(0, j.min(g.ny - 1), 0, 2 * (j == g.ny) as usize)[1])
        .collect();
    let z: Vec<f64> = (0..=g.nz)
        .map(|k| -g.corner(0, 0, k.min(g.nz - 1), 4 * (k == g.nz) as usize)[2])
        .collect();
    for k in 0..g.nz {
        for j in 0..g.ny {
            for i in 0..g.nx {
                for c in 0..8 {
                    let (di, dj, b) = (c & 1, (c >> 1) & 1, c >> 2);
                    let p = g.corner(i, j, k, c);
                    if p != [x[i + di], y[j + dj], -z[k + b]] {
                        return Err(Error::Usage(format!(
                            "the 3D hybrid mesh needs a Cartesian block grid (vertical pillars, flat \
                             horizons): cell ({}, {}, {}) is not a box",
                            i + 1,
                            j + 1,
                            k + 1
                        )));
                    }
                }
            }
        }
    }
    let increasing = |v: &[f64]| v.windows(2).all(|w| w[0] < w[1]);
    let decreasing = |v: &[f64]| v.windows(2).all(|w| w[0] > w[1]);
    if !(increasing(&x) && increasing(&y) && decreasing(&z)) {
        return Err(Error::Usage(
            "the grid's cells have no volume or are not ordered".into(),
        ));
    }
    Ok([x, y, z])
}

/// Builds the 3D hybrid mesh around one well.
pub fn build<B: Backend + ?Sized>(
    backend: &B,
    g: &CornerPointGrid,
    well: &Well3,
    opts: &Hybrid3Options,
) -> Result<Hybrid3> {
    let [xs, ys, zs] = axes(g)?;
    let (i0, j0) = (well.i, well.j);
    if i0 == 0 || j0 == 0 || i0 + 1 >= g.nx || j0 + 1 >= g.ny {
        return Err(Error::Usage(format!(
            "well {}: column ({}, {}) must have a column on every side (its cavity is the 3 x 3 columns around it)",
            well.name,
            i0 + 1,
            j0 + 1
        )));
    }
    if (0..g.nz).any(|k| (i0 - 1..=i0 + 1).any(|i| (j0 - 1..=j0 + 1).any(|j| !g.active(i, j, k)))) {
        return Err(Error::Usage(format!(
            "well {}: its cavity has inactive cells",
            well.name
        )));
    }
    let (m, rings) = (opts.sectors, opts.rings);
    if m < 3 || rings < 1 || well.radius.is_nan() || well.radius <= 0.0 {
        return Err(Error::Usage(
            "a radial mesh needs 3 sectors, a ring and a positive radius".into(),
        ));
    }
    let half_side = (xs[i0 + 1] - xs[i0]).min(ys[j0 + 1] - ys[j0]) / 2.0;
    let outer = opts.outer * 2.0 * half_side;
    if outer.is_nan() || outer <= well.radius {
        return Err(Error::Usage(format!(
            "well {}: its radius {} does not fit in its cell",
            well.name, well.radius
        )));
    }
    // The axis: from the column's centre at the top, going down.
    let (dip, az) = (well.dip.to_radians(), well.azimuth.to_radians());
    let u = [dip.sin() * az.sin(), dip.sin() * az.cos(), -dip.cos()];
    if u[2].is_nan() || u[2] >= -1e-3 {
        return Err(Error::Usage(format!(
            "well {}: a dip of {} degrees is not through the layers",
            well.name, well.dip
        )));
    }
    let vertical = well.dip == 0.0;
    // A deviated well's axis rounded onto a lattice, for exact rectangles.
    let zmax = zs.iter().fold(0.0f64, |a, z| a.max(z.abs())) + outer;
    let lattice = (!vertical).then(|| Lattice::new(u, zmax)).flatten();
    let u = lattice.as_ref().map_or(u, Lattice::axis);
    let az = if vertical { az } else { u[0].atan2(u[1]) };
    let head = [
        (xs[i0] + xs[i0 + 1]) / 2.0,
        (ys[j0] + ys[j0 + 1]) / 2.0,
        zs[0],
    ];
    let e1 = [az.cos(), -az.sin(), 0.0];
    let e2 = cross_f(u, e1);
    // The point of the cylinder of radius r at angle a on a level.
    let at = |r: f64, a: f64, level: Level| -> [f64; 3] {
        let off: [f64; 3] = std::array::from_fn(|k| r * (a.cos() * e1[k] + a.sin() * e2[k]));
        let s = match level {
            Level::Height(z) => (z - head[2] - off[2]) / u[2],
            Level::Along(t) => t,
        };
        let p: [f64; 3] = std::array::from_fn(|k| head[k] + off[k] + s * u[k]);
        match level {
            Level::Height(z) => [p[0], p[1], z],
            Level::Along(_) => p,
        }
    };
    let r = ring_radii(well.radius, outer, rings);
    let angle = |s: usize| TAU * (s % m) as f64 / m as f64;
    // The well's layers: a vertical well's are the grid's; a deviated
    // well's are slabs across its axis (so that its cells' links are
    // orthogonal), the first and last cut by the grid's top and bottom,
    // which cross the outer surface within `slant` of the axis' ends.
    let (levels, mid): (Vec<Level>, Vec<Level>) = if vertical {
        let mid = zs.windows(2).map(|w| Level::Height((w[0] + w[1]) / 2.0));
        (
            zs.iter().map(|&z| Level::Height(z)).collect(),
            mid.collect(),
        )
    } else {
        let length = (zs[g.nz] - zs[0]) / u[2];
        let slant = outer * dip.tan();
        let n = g.nz.max(2);
        if length - 2.0 * slant < 0.1 * length {
            return Err(Error::Usage(format!(
                "well {}: at a dip of {} degrees, its radial mesh (outer radius {outer}) needs a thicker grid",
                well.name, well.dip
            )));
        }
        let mut t: Vec<f64> = (0..=n)
            .map(|k| slant + (length - 2.0 * slant) * k as f64 / n as f64)
            .collect();
        if let Some(l) = &lattice {
            // the planes across the axis a whole number of lattice steps
            // from the first
            for k in 2..n {
                t[k] = t[1] + l.steps(t[k] - t[1]) as f64 * l.step();
            }
        }
        let mut levels = vec![Level::Height(zs[0])];
        levels.extend(t[1..n].iter().map(|&t| Level::Along(t)));
        levels.push(Level::Height(zs[g.nz]));
        // the ends' sites on one slab across the axis, past the slant
        let mid = (0..n).map(|k| Level::Along((t[k] + t[k + 1]) / 2.0));
        (levels, mid.collect())
    };
    let nl = mid.len();
    // The outline's points at the levels across the axis: on the lattice,
    // translates of the first such level's (exact rectangles between).
    let t1 = match levels.get(1) {
        Some(&Level::Along(t1)) => t1,
        _ => 0.0,
    };
    let base: Vec<[i64; 3]> = match (&lattice, levels.get(1)) {
        (Some(l), Some(Level::Along(_))) => {
            let plane = l.plane(at(outer, 0.0, Level::Along(t1)));
            (0..m)
                .map(|s| l.on(at(outer, angle(s), Level::Along(t1)), plane))
                .collect()
        }
        _ => vec![],
    };
    let surface = |s: usize, k: usize| -> [f64; 3] {
        match (&lattice, levels[k]) {
            (Some(l), Level::Along(t)) if !base.is_empty() => {
                l.point(l.translate(base[s % m], l.steps(t - t1)))
            }
            _ => at(outer, angle(s), levels[k]),
        }
    };
    let exact = |k: usize| matches!(levels[k], Level::Along(_)) && !base.is_empty();
    // The outer surface must stay inside the cavity, clear of its walls.
    let clear = 0.25 * half_side;
    for (k, &level) in levels.iter().enumerate() {
        for s in 0..m {
            let p = at(outer, angle(s), level);
            if !(p[0] > xs[i0 - 1] + clear
                && p[0] < xs[i0 + 2] - clear
                && p[1] > ys[j0 - 1] + clear
                && p[1] < ys[j0 + 2] - clear)
            {
                return Err(Error::Usage(format!(
                    "well {}: its radial mesh leaves the cavity of the 3 x 3 columns around ({}, {}) at layer {}",
                    well.name,
                    i0 + 1,
                    j0 + 1,
                    k.min(nl - 1) + 1
                )));
            }
        }
    }

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
    let node = |i: usize, j: usize, k: usize| [xs[i], ys[j], zs[k]];
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
    const WALL: i64 = 1;
    const WELL: i64 = 2;
    let mut wall_cells: Vec<[usize; 3]> = vec![]; // per wall facet: the reservoir cell beyond
    for k in 0..g.nz {
        for w in 0..lp.len() {
            let (a, b) = (lp[w], lp[(w + 1) % lp.len()]);
            let ids = vec![
                point(&mut cx, node(a.0, a.1, k)),
                point(&mut cx, node(b.0, b.1, k)),
                point(&mut cx, node(b.0, b.1, k + 1)),
                point(&mut cx, node(a.0, a.1, k + 1)),
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
     -> Vec<u32> { (0..m).map(|s| point(cx, surface(s, k))).collect() };
    for k in [0, nl] {
        let rim: Vec<u32> = lp
            .iter()
            .map(|&(i, j)| point(&mut cx, node(i, j, k)))
            .collect();
        let window = outline(&mut cx, &mut point, k);
        let inside = at(0.0, 0.0, levels[k]);
        cx.facets.push(facet(vec![rim, window], vec![inside], WALL));
    }
    let first_well_facet = cx.facets.len();
    let mut well_facets: Vec<(usize, usize)> = vec![]; // per facet: (layer, sector)
    for k in 0..nl {
        let lo = outline(&mut cx, &mut point, k + 1);
        let hi = outline(&mut cx, &mut point, k);
        for s in 0..m {
            let (a, b, c, d) = (hi[s], hi[(s + 1) % m], lo[(s + 1) % m], lo[s]);
            if vertical || (exact(k) && exact(k + 1)) {
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
        .push(at(0.0, 0.0, Level::Height((zs[0] + zs[g.nz]) / 2.0)));
    let top = first_well_facet as u32 - 2;
    let run = |clip: Vec<u32>| {
        conform3(
            backend,
            &cx,
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

    // Assembly: one point numbering over the three meshes.
    let mut out = Mesh3::default();
    let mut region = vec![];
    let mut ijk = vec![];
    let mut ids: HashMap<[u64; 3], u32> = HashMap::new();
    let mut pid = |out: &mut Mesh3, p: [f64; 3]| -> u32 {
        *ids.entry(p.map(f64::to_bits)).or_insert_with(|| {
            out.points.push(p);
            out.points.len() as u32 - 1
        })
    };
    // reservoir hexahedra outside the cavity
    let in_cavity =
        |i: usize, j: usize| (i0 - 1..=i0 + 1).contains(&i) && (j0 - 1..=j0 + 1).contains(&j);
    let mut res_cell: HashMap<[usize; 3], usize> = HashMap::new();
    for k in 0..g.nz {
        for j in 0..g.ny {
            for i in 0..g.nx {
                if in_cavity(i, j) || !g.active(i, j, k) {
                    continue;
                }
                let c = |di: usize, dj: usize, dk: usize| node(i + di, j + dj, k + dk);
                let faces: Vec<Vec<[f64; 3]>> = vec![
                    vec![c(0, 0, 0), c(0, 1, 0), c(1, 1, 0), c(1, 0, 0)],
                    vec![c(0, 0, 1), c(1, 0, 1), c(1, 1, 1), c(0, 1, 1)],
                    vec![c(0, 0, 0), c(1, 0, 0), c(1, 0, 1), c(0, 0, 1)],
                    vec![c(1, 1, 0), c(0, 1, 0), c(0, 1, 1), c(1, 1, 1)],
                    vec![c(0, 1, 0), c(0, 0, 0), c(0, 0, 1), c(0, 1, 1)],
                    vec![c(1, 0, 0), c(1, 1, 0), c(1, 1, 1), c(1, 0, 1)],
                ];
                let faces: Vec<Vec<u32>> = faces
                    .into_iter()
                    .map(|f| f.into_iter().map(|p| pid(&mut out, p)).collect())
                    .collect();
                let site = [
                    (xs[i] + xs[i + 1]) / 2.0,
                    (ys[j] + ys[j + 1]) / 2.0,
                    (zs[k] + zs[k + 1]) / 2.0,
                ];
                res_cell.insert([i, j, k], out.cells.len());
                out.cells.push(orient_faces(faces, &out.points, site));
                out.sites.push(site);
                out.weights.push(0.0);
                out.volumes
                    .push((xs[i + 1] - xs[i]) * (ys[j + 1] - ys[j]) * (zs[k] - zs[k + 1]));
                out.site_inside.push(true);
                region.push(Region::Reservoir);
                ijk.push(Some([i, j, k]));
            }
        }
    }
    // reservoir connections
    // in grid order: the same input gives the same connections' order
    let mut grid_order: Vec<([usize; 3], usize)> = res_cell.iter().map(|(&c, &a)| (c, a)).collect();
    grid_order.sort_unstable_by_key(|&(_, a)| a);
    for ([i, j, k], a) in grid_order {
        let (dx, dy, dz) = (xs[i + 1] - xs[i], ys[j + 1] - ys[j], zs[k] - zs[k + 1]);
        for (n, area, normal) in [
            ([i + 1, j, k], dy * dz, [1.0, 0.0, 0.0]),
            ([i, j + 1, k], dx * dz, [0.0, 1.0, 0.0]),
            ([i, j, k + 1], dx * dy, [0.0, 0.0, -1.0]),
        ] {
            if let Some(&b) = res_cell.get(&n) {
                let d = [
                    dist(out.sites[a], out.sites[b], normal) / 2.0,
                    dist(out.sites[a], out.sites[b], normal) / 2.0,
                ];
                out.links.push(Link3 {
                    cells: [a, b],
                    face: vec![],
                    area,
                    d,
                    normal,
                });
            }
        }
    }
    // the transition's cells
    let first_t = out.cells.len();
    for (c, faces) in t.mesh.cells.iter().enumerate() {
        let faces: Vec<Vec<u32>> = faces
            .iter()
            .map(|f| {
                f.iter()
                    .map(|&v| pid(&mut out, t.mesh.points[v as usize]))
                    .collect()
            })
            .collect();
        out.cells.push(faces);
        out.sites.push(t.mesh.sites[c]);
        out.weights.push(t.mesh.weights[c]);
        out.volumes.push(t.mesh.volumes[c]);
        out.site_inside.push(t.mesh.site_inside[c]);
        region.push(Region::Transition);
        ijk.push(None);
    }
    for l in &t.mesh.links {
        out.links.push(Link3 {
            cells: l.cells.map(|c| c + first_t),
            face: vec![],
            ..l.clone()
        });
    }
    // the well's cells: ring q, sector s, layer k
    let first_w = out.cells.len();
    let rho = site_radii(&r, m);
    let well_cell = |q: usize, s: usize, k: usize| first_w + (k * rings + q) * m + s;
    for (k, &mid_k) in mid.iter().enumerate() {
        for (q, &rho_q) in rho.iter().enumerate() {
            for s in 0..m {
                let p = |qq: usize, ss: usize, kk: usize| match qq == rings {
                    true => surface(ss, kk),
                    false => at(r[qq], angle(ss), levels[kk]),
                };
                let corners = [
                    p(q, s, k),
                    p(q + 1, s, k),
                    p(q + 1, s + 1, k),
                    p(q, s + 1, k),
                    p(q, s, k + 1),
                    p(q + 1, s, k + 1),
                    p(q + 1, s + 1, k + 1),
                    p(q, s + 1, k + 1),
                ];
                let v: Vec<u32> = corners.iter().map(|&c| pid(&mut out, c)).collect();
                let mut faces = vec![
                    vec![v[0], v[3], v[2], v[1]], // top: outward +z seen from above
                    vec![v[4], v[5], v[6], v[7]],
                    vec![v[0], v[1], v[5], v[4]], // sector s side
                    vec![v[2], v[3], v[7], v[6]], // sector s + 1 side
                    vec![v[3], v[0], v[4], v[7]], // inner ring (wellbore for q = 0)
                ];
                // the outer face whole, also where the transition has it as
                // two triangles (vtk's convexity test fails coplanar faces)
                faces.push(vec![v[1], v[2], v[6], v[5]]);
                // on the sector's mid-angle ray at the layer's mid-height
                let site = at(rho_q, TAU * (s as f64 + 0.5) / m as f64, mid_k);
                out.cells.push(orient_faces(faces, &out.points, site));
                out.sites.push(site);
                out.weights.push(0.0);
                out.volumes.push(0.0);
                out.site_inside.push(true);
                region.push(Region::Well);
                ijk.push(None);
            }
        }
    }
    // well volumes from their faces, and the well's own connections
    for c in first_w..out.cells.len() {
        out.volumes[c] = volume(&out.cells[c], &out.points);
    }
    let plane = |out: &Mesh3, face: &[u32]| {
        let pts: Vec<[f64; 3]> = face.iter().map(|&v| out.points[v as usize]).collect();
        Plane::of(&pts)
    };
    let link = |out: &mut Mesh3, a: usize, b: usize, face: &[u32]| {
        let pl = plane(out, face);
        out.links.push(Link3 {
            cells: [a, b],
            face: face.to_vec(),
            area: pl.area,
            d: [pl.distance(out.sites[a]), pl.distance(out.sites[b])],
            normal: pl.unit,
        });
    };
    for k in 0..nl {
        for q in 0..rings {
            for s in 0..m {
                let a = well_cell(q, s, k);
                let mut next = vec![well_cell(q, (s + 1) % m, k)];
                if q + 1 < rings {
                    next.push(well_cell(q + 1, s, k));
                }
                if k + 1 < nl {
                    next.push(well_cell(q, s, k + 1));
                }
                for b in next {
                    let face = find_face(&out.cells[a], &out.cells[b]);
                    link(&mut out, a, b, &face);
                }
            }
        }
    }
    // interfaces: transition faces on walls and on the well's surface
    for f in &t.mesh.facet_faces {
        let a = first_t + f.cell;
        let face: Vec<u32> = f
            .points
            .iter()
            .map(|&v| pid(&mut out, t.mesh.points[v as usize]))
            .collect();
        let fi = f.facet as usize;
        let b = match cx.facets[fi].marker {
            WALL if fi < wall_cells.len() => res_cell.get(&wall_cells[fi]).copied(),
            WELL => {
                let (k, s) = well_facets[fi - first_well_facet];
                Some(well_cell(rings - 1, s, k))
            }
            _ => None,
        };
        let Some(b) = b else { continue };
        let pl = plane(&out, &face);
        out.links.push(Link3 {
            cells: [a, b],
            face,
            area: f.area,
            d: [f.d, pl.distance(out.sites[b])],
            normal: pl.unit,
        });
    }
    // A deviated well's outer parallelogram is two transition faces: one
    // connection per pair of cells, their areas added.
    let mut seen: HashMap<[usize; 2], usize> = HashMap::new();
    let mut merged: Vec<Link3> = vec![];
    for l in std::mem::take(&mut out.links) {
        match seen.get(&l.cells) {
            Some(&i) => merged[i].area += l.area,
            None => {
                seen.insert(l.cells, merged.len());
                merged.push(l);
            }
        }
    }
    out.links = merged;
    let non_orthogonal = out
        .links
        .iter()
        .filter(|l| out.link_defect(l) > 1e-6)
        .count();
    let report = Hybrid3Report {
        cells: [
            region.iter().filter(|r| **r == Region::Reservoir).count(),
            region.iter().filter(|r| **r == Region::Transition).count(),
            region.iter().filter(|r| **r == Region::Well).count(),
        ],
        transition: t.report,
        connections: out.links.len(),
        non_orthogonal,
    };
    Ok(Hybrid3 {
        mesh: out,
        region,
        ijk,
        report,
    })
}

/// Points x = X h, y = Y h, z = Z h / 2^K (integers X, Y, Z) on planes
/// across the axis w = (Wx, Wy, -2^K) / 2^K: w.p = (Wx X + Wy Y - Z) h /
/// 2^K exactly, so a translate by a whole number of steps along w stays
/// on the lattice, and a deviated well's outer faces between two such
/// planes are exact rectangles (kept whole: their links orthogonal).
struct Lattice {
    h: f64,
    k: i32,
    w: [i64; 2],
}

impl Lattice {
    /// The lattice for an axis (unit, going down) and points with |z| up
    /// to zmax; None where z would not be exact.
    fn new(u: [f64; 3], zmax: f64) -> Option<Lattice> {
        let e = zmax.log2().ceil() as i32;
        // K bits of the axis' slopes (16 or more for depths up to 16 km),
        // steps along the axis of at most 2^-5 (h 2^K), and as fine a
        // lattice as the doubles hold z on: |Z| < 2^51
        let k = ((46 - e) / 2).clamp(8, 20);
        let h = 2f64.powi(e + k - 51);
        let one = 2f64.powi(k);
        let w = [
            (-u[0] / u[2] * one).round() as i64,
            (-u[1] / u[2] * one).round() as i64,
        ];
        (h.is_normal() && w.iter().all(|x| x.unsigned_abs() < 1 << 40)).then_some(Lattice {
            h,
            k,
            w,
        })
    }

    /// The axis' direction w (unit z).
    fn slopes(&self) -> [f64; 3] {
        let one = 2f64.powi(self.k);
        [self.w[0] as f64 / one, self.w[1] as f64 / one, -1.0]
    }

    /// The unit axis.
    fn axis(&self) -> [f64; 3] {
        let v = self.slopes();
        let n = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        v.map(|x| x / n)
    }

    /// The length along the axis of one step (h 2^K w).
    fn step(&self) -> f64 {
        let [a, b, _] = self.slopes();
        self.h * 2f64.powi(self.k) * (1.0 + a.powi(2) + b.powi(2)).sqrt()
    }

    /// The unit of Z.
    fn z_unit(&self) -> f64 {
        self.h / 2f64.powi(self.k)
    }

    /// Whole steps nearest to a length along the axis.
    fn steps(&self, t: f64) -> i64 {
        (t / self.step()).round() as i64
    }

    /// The plane across the axis through p (rounded): Wx X + Wy Y - Z.
    fn plane(&self, p: [f64; 3]) -> i128 {
        let [x, y, z] = self.round(p);
        self.w[0] as i128 * x as i128 + self.w[1] as i128 * y as i128 - z as i128
    }

    fn round(&self, p: [f64; 3]) -> [i64; 3] {
        [p[0] / self.h, p[1] / self.h, p[2] / self.z_unit()].map(|c| c.round() as i64)
    }

    /// The lattice point with p's x and y rounded, on a plane.
    fn on(&self, p: [f64; 3], plane: i128) -> [i64; 3] {
        let [x, y, _] = self.round(p);
        let z = self.w[0] as i128 * x as i128 + self.w[1] as i128 * y as i128 - plane;
        [x, y, z as i64]
    }

    fn translate(&self, p: [i64; 3], steps: i64) -> [i64; 3] {
        [
            p[0] + steps * self.w[0],
            p[1] + steps * self.w[1],
            p[2] - steps * (1i64 << (2 * self.k)),
        ]
    }

    fn point(&self, p: [i64; 3]) -> [f64; 3] {
        [
            p[0] as f64 * self.h,
            p[1] as f64 * self.h,
            p[2] as f64 * self.z_unit(),
        ]
    }
}

/// Where a point of the well's surfaces is: on a horizontal plane, or on a
/// plane across the axis (at a distance along it from the head).
#[derive(Clone, Copy)]
enum Level {
    Height(f64),
    Along(f64),
}

/// Distance between two sites along a unit direction.
fn dist(a: [f64; 3], b: [f64; 3], n: [f64; 3]) -> f64 {
    (0..3).map(|k| (b[k] - a[k]) * n[k]).sum::<f64>().abs()
}

/// The faces turned so that each is counter-clockwise seen from outside
/// (its Newell normal points away from the site).
fn orient_faces(faces: Vec<Vec<u32>>, points: &[[f64; 3]], site: [f64; 3]) -> Vec<Vec<u32>> {
    faces
        .into_iter()
        .map(|mut f| {
            let pts: Vec<[f64; 3]> = f.iter().map(|&v| points[v as usize]).collect();
            let n = crate::geom::newell(&pts);
            if (0..3).map(|k| n[k] * (pts[0][k] - site[k])).sum::<f64>() < 0.0 {
                f.reverse();
            }
            f
        })
        .collect()
}

/// The face two cells share (same point set).
fn find_face(a: &[Vec<u32>], b: &[Vec<u32>]) -> Vec<u32> {
    let key = |f: &Vec<u32>| {
        let mut k = f.clone();
        k.sort_unstable();
        k
    };
    let theirs: Vec<Vec<u32>> = b.iter().map(key).collect();
    a.iter()
        .find(|f| theirs.contains(&key(f)))
        .cloned()
        .unwrap_or_default()
}

impl Hybrid3 {
    /// Polyhedra with cell data site, weight, volume, region, ijk
    /// (1-based, -1 outside the grid).
    pub fn cells(&self) -> CellMesh {
        let m = &self.mesh;
        CellMesh {
            points: m.points.clone(),
            cells: Cells::Polyhedra(m.cells.clone()),
            data: vec![
                CellArray::float("site", 3, m.sites.iter().flatten().copied().collect()),
                CellArray::float("weight", 1, m.weights.clone()),
                CellArray::float("volume", 1, m.volumes.clone()),
                CellArray::int("region", 1, self.region.iter().map(|&r| r as i64).collect()),
                CellArray::ijk(self.ijk.iter().copied()),
            ],
            scalars: "region",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::{dot, q, sub, Q};

    /// Translates of points on one plane across the axis make exact
    /// rectangles, in the doubles themselves, for axes and coordinates
    /// as a reservoir has them.
    #[test]
    fn lattice_rectangles_are_exact() {
        for (dip, az, x0, zmax) in [
            (10.0f64, 30.0f64, 45.0, 20.0),
            (37.0, 211.0, 612_345.7, 3100.0),
            (1.0, 359.0, -2.5e4, 9000.0),
        ] {
            let (d, a) = (dip.to_radians(), az.to_radians());
            let u = [d.sin() * a.sin(), d.sin() * a.cos(), -d.cos()];
            let l = Lattice::new(u, zmax).unwrap();
            let v = l.axis();
            assert!(
                (0..3).all(|k| (v[k] - u[k]).abs() < 2f64.powi(-14)),
                "{v:?} {u:?}"
            );
            assert!(l.step() < 0.04, "{}", l.step());
            let p0 = [x0, x0 * 0.7, -zmax / 2.0];
            let plane = l.plane(p0);
            let base: Vec<[i64; 3]> = (0..5)
                .map(|s| {
                    let t = s as f64;
                    l.on([p0[0] + 3.1 * t.cos(), p0[1] + 3.1 * t.sin(), p0[2]], plane)
                })
                .collect();
            for s in 0..4 {
                let steps = l.steps(2.7);
                let [a, b] = [base[s], base[s + 1]].map(|p| l.point(p));
                let [c, d] = [base[s + 1], base[s]].map(|p| l.point(l.translate(p, steps)));
                // doubles that round-trip, a parallelogram, a right angle
                let [a, b, c, d] = [a, b, c, d].map(|p| p.map(q));
                assert_eq!(sub(&c, &b), sub(&d, &a));
                assert_eq!(dot(&sub(&b, &a), &sub(&d, &a)), Q::from(0));
                let len = crate::geom::f(&dot(&sub(&d, &a), &sub(&d, &a))).sqrt();
                assert!((len - steps as f64 * l.step()).abs() < 1e-9 * len);
            }
        }
    }
}
