//! Hybrid reservoir meshes in map view (paper section 5, docs/method.md section 6):
//! a layer of a corner-point grid, radial meshes around vertical wells, and
//! between them, in cavities cut out of the grid, transition meshes from the
//! 2D core. The result is one conforming polygon mesh: active reservoir cells
//! outside the cavities, transition cells, radial cells.

use crate::backend::Backend;
use crate::complex::Complex;
use crate::conform::{conform2, Report};
use crate::error::{Error, Result};
use crate::mesh::{CellArray, CellMesh, Connection, Element, Mesh, Network};
use crate::options::Options;
use crate::reservoir::CornerPointGrid;
use crate::FastMap;
use serde::Serialize;
use std::f64::consts::TAU;

/// Where a well is: a grid column (0-based) or a map position.
#[derive(Debug, Clone, PartialEq)]
pub enum WellAt {
    Column(usize, usize),
    Xy([f64; 2]),
}

/// A vertical well.
#[derive(Debug, Clone, PartialEq)]
pub struct WellInput {
    pub name: String,
    pub at: WellAt,
    /// Wellbore radius.
    pub radius: f64,
}

impl WellInput {
    /// A well in column (i, j), 0-based.
    pub fn column(name: &str, i: usize, j: usize, radius: f64) -> WellInput {
        WellInput {
            name: name.into(),
            at: WellAt::Column(i, j),
            radius,
        }
    }
}

/// Choices for the hybrid mesh.
#[derive(Debug, Clone)]
pub struct HybridOptions {
    /// The layer (0-based) whose map view is meshed.
    pub layer: usize,
    /// Rings and sectors of each radial mesh.
    pub rings: usize,
    pub sectors: usize,
    /// Outer radius of the radial meshes, as a multiple of the shortest side
    /// of the well's cell.
    pub outer: f64,
    /// Layers of cells added around the cells the radial mesh reaches.
    pub margin: usize,
    /// Called as stages advance: (stage, done, of).
    pub progress: Option<fn(&str, usize, usize)>,
    /// Write the mesh even when some transition sites cannot be inside their
    /// cells (after the cavities have grown as far as they can).
    pub allow_sites_outside: bool,
    /// Faults given as map polylines: their parts inside cavities become
    /// constraint chains, ending a quarter cell short of the cavity sides.
    pub fault_lines: Vec<Vec<[f64; 2]>>,
}

impl Default for HybridOptions {
    fn default() -> Self {
        // The flow check (tests/flow.rs) against Thiem's solution: 0.02% off
        // with these (5 x 5-cell cavity, well polygon 0.6 cells from its
        // sides, docs/method.md section 6); 0.5-1% with an outer radius of 0.9
        // cells; 3% with 4 rings. Crowded wells get smaller radial meshes.
        HybridOptions {
            layer: 0,
            rings: 12,
            sectors: 32,
            outer: 1.9,
            margin: 0,
            progress: None,
            allow_sites_outside: false,
            fault_lines: vec![],
        }
    }
}

/// Which part of the hybrid mesh a cell belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Region {
    Reservoir = 0,
    Transition = 1,
    Well = 2,
}

/// The hybrid mesh and how it was made.
#[derive(Debug, Clone)]
pub struct Hybrid {
    /// Cells, sites, weights; faces between cells.
    pub mesh: Mesh,
    pub region: Vec<Region>,
    /// The reservoir cell (i, j, k), 0-based, for reservoir cells.
    pub ijk: Vec<Option<[usize; 3]>>,
    /// The transition meshes' constraints: cavity boundaries, well polygons.
    pub constraints: Complex,
    /// Per cell: thickness and mid-depth (the reservoir cell's own; the
    /// layer's mean for transition and well cells).
    pub thickness: Vec<f64>,
    pub depth: Vec<f64>,
    pub report: HybridReport,
}

impl Hybrid {
    /// The two-point flux network: an element per cell at its site and
    /// mid-depth (z up), volume = area x thickness; a connection per
    /// interior face with each site's distance to the face, the face's area
    /// (length x mean thickness) and the gravity cosine from the depths.
    pub fn network(&self) -> Network {
        let m = &self.mesh;
        let node = |c: usize| [m.sites[c][0], m.sites[c][1], -self.depth[c]];
        let elements: Vec<Element> = (0..m.cells.len())
            .map(|c| Element {
                volume: m.area(&m.cells[c]) * self.thickness[c],
                node: node(c),
            })
            .collect();
        let connections = crate::reservoir::flow::connections(m)
            .into_iter()
            .map(|c| {
                let [a, b] = c.cells.map(|x| x as usize);
                let area = c.area * (self.thickness[a] + self.thickness[b]) / 2.0;
                Connection::lateral([a, b], node(a), node(b), c.d, area)
            })
            .collect::<Vec<_>>();
        Network {
            elements,
            connections,
        }
    }

    /// Polygons with cell data site, weight, region (0 reservoir, 1
    /// transition, 2 well) and ijk (1-based; -1 elsewhere).
    pub fn cells(&self) -> CellMesh {
        let region = CellArray::int("region", 1, self.region.iter().map(|&r| r as i64).collect());
        let ijk = CellArray::ijk(self.ijk.iter().copied());
        self.mesh.cells_with(vec![region, ijk])
    }
}

/// Built-in example: a 15 x 15-cell Cartesian layer of 10 m cells, one well
/// of radius 0.1 m in column (7, 8) (1-based), and a fault along the east
/// sides of column I = 8 for J = 6..8 that ends inside the well's cavity.
pub fn demo() -> (CornerPointGrid, Vec<WellInput>, HybridOptions) {
    let mut grid = CornerPointGrid::cartesian([15, 15, 1], [10.0, 10.0, 5.0]);
    grid.faults.push(crate::reservoir::Fault {
        name: "F1".into(),
        faces: vec![crate::reservoir::FaultFace {
            i: [7, 7],
            j: [5, 7],
            k: [0, 0],
            axis: 'X',
            sign: 1,
        }],
    });
    let opts = HybridOptions {
        margin: 1,
        ..Default::default()
    };
    (grid, vec![WellInput::column("W1", 6, 7, 0.1)], opts)
}

/// What the report says about the hybrid mesh.
#[derive(Debug, Clone, Serialize)]
pub struct HybridReport {
    pub layer: usize,
    pub wells: Vec<String>,
    pub cavities: usize,
    pub cavity_cells: usize,
    pub cells: [usize; 3],
    /// Largest |cos| between a face and its two sites' segment, per pair
    /// of regions: reservoir-reservoir, reservoir-transition,
    /// transition-transition, transition-well, well-well.
    pub orthogonality_defect: Vec<(String, f64)>,
    /// Interface faces (between regions) whose defect exceeds 1e-6: the
    /// reservoir cell's ijk (1-based) when one side is a reservoir cell, the
    /// pair of regions, the defect. The first 100.
    pub non_orthogonal_interfaces: Vec<(Option<[usize; 3]>, String, f64)>,
    /// Two-point transmissibilities (unit permeability): all connections,
    /// and those touching the transition or well regions (where none may be
    /// negative or non-orthogonal).
    pub transmissibility: crate::reservoir::flow::TransmissibilityStats,
    pub transmissibility_near_wells: crate::reservoir::flow::TransmissibilityStats,
    /// Faces that are not shared by two cells nor on the outer boundary: 0
    /// for a conforming mesh (no hanging nodes).
    pub unmatched_faces: usize,
    /// Fault segments inside cavities (chains with free ends there).
    pub fault_segments: usize,
    /// Cavities grown because system 3 was infeasible.
    pub notes: Vec<String>,
    /// The transition meshes' own report (certificate, weights, sites).
    pub transition: Report,
}

/// The map position of every pillar for layer k (index j (nx+1) + i).
pub(crate) fn map_view(g: &CornerPointGrid, k: usize) -> Vec<[f64; 2]> {
    MapView::new(g, k).pillar
}

/// Map view of one layer: a point per pillar, a quadrilateral per column.
struct MapView {
    pillar: Vec<[f64; 2]>,
    nx: usize,
}

impl MapView {
    /// Each pillar's point at the mean depth of the layer's top corners on it.
    fn new(g: &CornerPointGrid, k: usize) -> MapView {
        let (nx, ny) = (g.nx, g.ny);
        let mut sum = vec![(0.0, 0u32); (nx + 1) * (ny + 1)];
        for j in 0..ny {
            for i in 0..nx {
                for c in 0..4 {
                    let (di, dj) = (c & 1, c >> 1);
                    let z = g.corner(i, j, k, c)[2];
                    let s = &mut sum[(j + dj) * (nx + 1) + i + di];
                    s.0 += z;
                    s.1 += 1;
                }
            }
        }
        let pillar = sum
            .iter()
            .enumerate()
            .map(|(p, &(z, n))| {
                let c = g.coord[p];
                let z = z / f64::from(n.max(1));
                let (dz, t) = (c[5] - c[2], z - c[2]);
                let f = if dz != 0.0 { t / dz } else { 0.0 };
                [c[0] + f * (c[3] - c[0]), c[1] + f * (c[4] - c[1])]
            })
            .collect();
        MapView { pillar, nx }
    }

    fn pid(&self, i: usize, j: usize) -> u32 {
        (j * (self.nx + 1) + i) as u32
    }

    /// Pillar ids of column (i, j), counter-clockwise in the map.
    fn quad(&self, i: usize, j: usize) -> [u32; 4] {
        let q = [
            self.pid(i, j),
            self.pid(i + 1, j),
            self.pid(i + 1, j + 1),
            self.pid(i, j + 1),
        ];
        if crate::geom::shoelace(4, |k| self.pillar[q[k] as usize]) < 0.0 {
            [q[0], q[3], q[2], q[1]]
        } else {
            q
        }
    }

    fn centroid(&self, i: usize, j: usize) -> [f64; 2] {
        centroid(&self.quad(i, j).map(|p| self.pillar[p as usize]))
    }
}

fn centroid(p: &[[f64; 2]]) -> [f64; 2] {
    let (mut a, mut cx, mut cy) = (0.0, 0.0, 0.0);
    let o = p[0];
    for k in 1..p.len() - 1 {
        let (b, c) = (p[k], p[k + 1]);
        let t = ((b[0] - o[0]) * (c[1] - o[1]) - (b[1] - o[1]) * (c[0] - o[0])) / 2.0;
        a += t;
        cx += t * (o[0] + b[0] + c[0]) / 3.0;
        cy += t * (o[1] + b[1] + c[1]) / 3.0;
    }
    if a == 0.0 {
        let n = p.len() as f64;
        return [
            p.iter().map(|q| q[0]).sum::<f64>() / n,
            p.iter().map(|q| q[1]).sum::<f64>() / n,
        ];
    }
    [cx / a, cy / a]
}

/// Distance from x to the polygon (0 inside).
fn distance_to_polygon(x: [f64; 2], p: &[[f64; 2]]) -> f64 {
    let n = p.len();
    let mut inside = true;
    let mut best = f64::INFINITY;
    for e in 0..n {
        let (a, b) = (p[e], p[(e + 1) % n]);
        inside &= (b[0] - a[0]) * (x[1] - a[1]) - (b[1] - a[1]) * (x[0] - a[0]) >= 0.0;
        best = best.min(to_segment(x, [a, b]));
    }
    if inside {
        0.0
    } else {
        best
    }
}

/// Distance from x to the segment a-b.
fn to_segment(x: [f64; 2], [a, b]: [[f64; 2]; 2]) -> f64 {
    let (ux, uy) = (b[0] - a[0], b[1] - a[1]);
    let (vx, vy) = (x[0] - a[0], x[1] - a[1]);
    let t = ((ux * vx + uy * vy) / (ux * ux + uy * uy)).clamp(0.0, 1.0);
    (vx - t * ux).hypot(vy - t * uy)
}

/// One well placed: centre, radii of its rings, and the shortest side of
/// its column (`reach`), which sets how far its cavity extends.
struct Placed {
    name: String,
    centre: [f64; 2],
    radii: Vec<f64>,
    reach: f64,
    /// The column the well is in.
    column: (usize, usize),
}

type FaultEdge = (u32, u32, (usize, usize), (usize, usize));

/// The parts of a polyline inside the cavities, as chains of points: cut
/// where it crosses a cavity side and pulled back by `gap` from there
/// (parts shorter than that are dropped).
fn clip_to_cavity(
    line: &[[f64; 2]],
    sides: &[[[f64; 2]; 2]],
    inside: &dyn Fn([f64; 2]) -> bool,
    gap: f64,
) -> Vec<Vec<[f64; 2]>> {
    let at =
        |a: [f64; 2], b: [f64; 2], t: f64| [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
    let mut chains: Vec<Vec<[f64; 2]>> = vec![];
    let mut current: Vec<[f64; 2]> = vec![];
    // (point, whether a chain may end here without a pull-back)
    for w in line.windows(2) {
        let (a, b) = (w[0], w[1]);
        let d = [b[0] - a[0], b[1] - a[1]];
        let len = d[0].hypot(d[1]);
        if len == 0.0 {
            continue;
        }
        let mut cuts: Vec<f64> = sides
            .iter()
            .filter_map(|[p, q]| {
                let e = [q[0] - p[0], q[1] - p[1]];
                let den = d[0] * e[1] - d[1] * e[0];
                if den == 0.0 {
                    return None;
                }
                let t = ((p[0] - a[0]) * e[1] - (p[1] - a[1]) * e[0]) / den;
                let u = ((p[0] - a[0]) * d[1] - (p[1] - a[1]) * d[0]) / den;
                ((0.0..=1.0).contains(&t) && (0.0..=1.0).contains(&u)).then_some(t)
            })
            .collect();
        cuts.sort_by(f64::total_cmp);
        cuts.dedup();
        let cut = |t: f64| cuts.contains(&t);
        let mut bounds = vec![0.0];
        bounds.extend(cuts.iter().copied().filter(|&t| t > 0.0 && t < 1.0));
        bounds.push(1.0);
        for iv in bounds.windows(2) {
            let (t0, t1) = (iv[0], iv[1]);
            if !inside(at(a, b, (t0 + t1) / 2.0)) {
                if !current.is_empty() {
                    chains.push(std::mem::take(&mut current));
                }
                continue;
            }
            // pulled back from where the line meets a cavity side
            let s = if cut(t0) { t0 + gap / len } else { t0 };
            let e = if cut(t1) { t1 - gap / len } else { t1 };
            if s >= e {
                if !current.is_empty() {
                    chains.push(std::mem::take(&mut current));
                }
                continue;
            }
            if cut(t0) || current.is_empty() {
                if !current.is_empty() {
                    chains.push(std::mem::take(&mut current));
                }
                current.push(at(a, b, s));
            }
            current.push(at(a, b, e));
            if cut(t1) {
                chains.push(std::mem::take(&mut current));
            }
        }
    }
    if !current.is_empty() {
        chains.push(current);
    }
    chains.retain(|c| c.len() >= 2);
    for c in &mut chains {
        c.dedup();
    }
    chains.retain(|c| c.len() >= 2);
    chains
}

/// The pillar edges of the grid's faults at layer k, in map view: (pillar,
/// pillar, column on one side, column on the other); columns outside the
/// grid have an index of nx or ny (or wrap below 0).
fn fault_edges(g: &CornerPointGrid, k: usize, view: &MapView) -> Vec<FaultEdge> {
    let mut out = vec![];
    for f in &g.faults {
        for face in &f.faces {
            if k < face.k[0] || k > face.k[1] {
                continue;
            }
            for j in face.j[0]..=face.j[1] {
                for i in face.i[0]..=face.i[1] {
                    // the side of column (i, j) the face names, and the column across
                    let (di, dj) = match (face.axis, face.sign) {
                        ('X', 1) => (1, 0),
                        ('X', _) => (-1, 0),
                        ('Y', 1) => (0, 1),
                        ('Y', _) => (0, -1),
                        _ => continue, // Z faces have no trace in map view
                    };
                    let across = ((i as i64 + di) as usize, (j as i64 + dj) as usize);
                    let (p, q) = match (di, dj) {
                        (1, 0) => (view.pid(i + 1, j), view.pid(i + 1, j + 1)),
                        (-1, 0) => (view.pid(i, j), view.pid(i, j + 1)),
                        (0, 1) => (view.pid(i, j + 1), view.pid(i + 1, j + 1)),
                        _ => (view.pid(i, j), view.pid(i + 1, j)),
                    };
                    out.push((p, q, (i, j), across));
                }
            }
        }
    }
    out
}

/// Times a cavity may grow before system 3's infeasibility is an error.
const MAX_GROWTH: usize = 4;

/// Radii r_0 = wellbore ... r_n = outer, in geometric progression.
pub(crate) fn ring_radii(rw: f64, outer: f64, rings: usize) -> Vec<f64> {
    (0..=rings)
        .map(|k| rw * (outer / rw).powf(k as f64 / rings as f64))
        .collect()
}

/// Radii of the ring sites (ring q between radii r[q] and r[q + 1]) of a
/// radial mesh with m sectors: see the assembly in `build`.
pub(crate) fn site_radii(r: &[f64], m: usize) -> Vec<f64> {
    let half = TAU / (2 * m) as f64;
    let alpha = r[1] / r[0];
    let beta = alpha * half.sin() * alpha.ln() / (half * (alpha - 1.0));
    r[..r.len() - 1].iter().map(|&rq| beta * rq).collect()
}

/// The site of a radial cell: sector s's mid-angle ray at radius rho.
fn radial_site(centre: [f64; 2], rho: f64, s: usize, m: usize) -> [f64; 2] {
    let a = TAU * (s as f64 + 0.5) / m as f64;
    [centre[0] + rho * a.cos(), centre[1] + rho * a.sin()]
}

fn polygon_point(c: [f64; 2], r: f64, s: usize, m: usize) -> [f64; 2] {
    let a = TAU * s as f64 / m as f64;
    [c[0] + r * a.cos(), c[1] + r * a.sin()]
}

/// Most rings and sectors a radial mesh may have (more is a typo, and
/// would not fit in memory: rings x sectors cells per well).
pub const MAX_RINGS: usize = 1000;
pub const MAX_SECTORS: usize = 4096;

/// Builds the hybrid mesh of one layer with the given wells.
pub fn build<B: Backend + ?Sized>(
    backend: &B,
    grid: &CornerPointGrid,
    wells: &[WellInput],
    opts: &HybridOptions,
) -> Result<Hybrid> {
    let k = opts.layer;
    if k >= grid.nz {
        return Err(Error::Usage(format!(
            "layer {} outside 1..{}",
            k + 1,
            grid.nz
        )));
    }
    if !(1..=MAX_RINGS).contains(&opts.rings) || !(3..=MAX_SECTORS).contains(&opts.sectors) {
        return Err(Error::Usage(format!(
            "radial meshes need 1 to {MAX_RINGS} rings and 3 to {MAX_SECTORS} sectors"
        )));
    }
    if wells.is_empty() {
        return Err(Error::Usage("a hybrid mesh needs at least one well".into()));
    }
    let view = MapView::new(grid, k);
    let (nx, ny) = (grid.nx, grid.ny);
    let quad_points = |i: usize, j: usize| view.quad(i, j).map(|p| view.pillar[p as usize]);
    let flat: Vec<String> = (0..ny)
        .flat_map(|j| (0..nx).map(move |i| (i, j)))
        .filter(|&(i, j)| {
            let q = quad_points(i, j);
            // NaN area (unreadable corners) counts as none
            grid.active(i, j, k)
                && crate::geom::shoelace(4, |c| q[c]).abs().partial_cmp(&0.0)
                    != Some(std::cmp::Ordering::Greater)
        })
        .map(|(i, j)| format!("({}, {}, {})", i + 1, j + 1, k + 1))
        .collect();
    if !flat.is_empty() {
        return Err(Error::Degenerate(format!(
            "active cells with no area in map view (collapsed pillars): {}{}",
            flat[..flat.len().min(20)].join(", "),
            if flat.len() > 20 {
                format!(" and {} more", flat.len() - 20)
            } else {
                String::new()
            }
        )));
    }

    // Place the wells.
    let mut placed: Vec<Placed> = vec![];
    let tell = |stage: &str, done: usize, of: usize| {
        if let Some(f) = opts.progress {
            f(stage, done, of);
        }
    };
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
    for (p, q, _, _) in fault_edges(grid, k, &view) {
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
        let outer = placed[a].radii[1].min(0.3 * nearest).min(0.6 * wall);
        let rw = placed[a].radii[0];
        if !(rw > 0.0 && rw < outer / 2.0) {
            return Err(Error::Usage(format!(
                "well {}: radius {rw:?} must be positive and below half the outer radius {outer:?}",
                placed[a].name
            )));
        }
        placed[a].radii = ring_radii(rw, outer, opts.rings);
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

    // Cavities: the columns the radial meshes reach, plus a margin, plus
    // any column they enclose, minus inactive columns (no rock to mesh).
    let col = |i: usize, j: usize| j * nx + i;
    let neighbours = |c: usize| {
        let (i, j) = (c % nx, c / nx);
        [
            (i.wrapping_sub(1), j),
            (i + 1, j),
            (i, j.wrapping_sub(1)),
            (i, j + 1),
        ]
        .into_iter()
        .filter(|&(a, b)| a < nx && b < ny)
        .map(move |(a, b)| col(a, b))
    };
    let grow = |cavity: &mut Vec<bool>, only: &dyn Fn(usize) -> bool| {
        let before = cavity.clone();
        for c in (0..nx * ny).filter(|&c| before[c] && only(c)) {
            for d in neighbours(c) {
                cavity[d] = true;
            }
        }
        // columns enclosed by cavities join them
        let mut outside = vec![false; nx * ny];
        let mut stack: Vec<usize> = (0..nx * ny)
            .filter(|&c| c % nx == 0 || c % nx == nx - 1 || c / nx == 0 || c / nx == ny - 1)
            .collect();
        while let Some(c) = stack.pop() {
            if cavity[c] || std::mem::replace(&mut outside[c], true) {
                continue;
            }
            stack.extend(neighbours(c));
        }
        for c in 0..nx * ny {
            cavity[c] = (cavity[c] || !outside[c]) && grid.active(c % nx, c / nx, k);
        }
    };
    // Connected cavities, as a label per column (usize::MAX outside).
    let components = |cavity: &[bool]| {
        let mut label = vec![usize::MAX; nx * ny];
        for start in 0..nx * ny {
            if !cavity[start] || label[start] != usize::MAX {
                continue;
            }
            let mut stack = vec![start];
            while let Some(c) = stack.pop() {
                if label[c] != usize::MAX {
                    continue;
                }
                label[c] = start;
                stack.extend(neighbours(c).filter(|&d| cavity[d] && label[d] == usize::MAX));
            }
        }
        label
    };
    let mut cavity = vec![false; nx * ny];
    let well_column: Vec<usize> = placed.iter().map(|w| col(w.column.0, w.column.1)).collect();
    for w in &placed {
        // Columns within half a cell of the well polygon: its distance to the
        // cavity sides is then at least half their length, and they stay
        // Gabriel (zero weights do).
        let r = (w.radii.last().unwrap() + 0.5 * w.reach).max(0.75 * w.reach);
        for j in 0..ny {
            for i in 0..nx {
                let d = distance_to_polygon(w.centre, &quad_points(i, j));
                if d < r {
                    cavity[col(i, j)] = true;
                }
            }
        }
    }
    grow(&mut cavity, &|_| false);
    for _ in 0..opts.margin {
        grow(&mut cavity, &|_| true);
    }

    // The transition problem: cavity boundaries (column sides between a
    // cavity column and anything else) and the wells' outer polygons, with
    // a hole at each well. When system 3 is infeasible, the cavities beside
    // the failing segments grow by a ring of cells and the problem is redone.
    let m = opts.sectors;
    let mut notes = vec![];
    let mut give_up = false;
    let mut fault_segments: usize;
    let typical_side = placed.iter().map(|w| w.reach).fold(f64::INFINITY, f64::min);
    // Pieces for a side that may be split: none longer than its distance to
    // the nearest well polygon, so that it stays Gabriel.
    let pieces_near_wells = |pp: [f64; 2], pq: [f64; 2]| {
        let gap = placed
            .iter()
            .map(|w| to_segment(w.centre, [pp, pq]) - w.radii.last().unwrap())
            .fold(f64::INFINITY, f64::min);
        let len = (pq[0] - pp[0]).hypot(pq[1] - pp[1]);
        ((len / gap.max(len / 64.0)).ceil() as usize).clamp(1, 64)
    };
    // The side u - v cut into equal pieces (new vertices in between).
    let split = |cx: &mut Complex, u: u32, v: u32, pieces: usize| -> Vec<(u32, u32)> {
        let (pu, pv) = (cx.points[u as usize], cx.points[v as usize]);
        let mut ids = vec![u];
        for piece in 1..pieces {
            let t = piece as f64 / pieces as f64;
            cx.points
                .push([pu[0] + t * (pv[0] - pu[0]), pu[1] + t * (pv[1] - pu[1])]);
            ids.push(cx.points.len() as u32 - 1);
        }
        ids.push(v);
        ids.windows(2).map(|w| (w[0], w[1])).collect()
    };
    let (cx, out, outer_pieces) = loop {
        let mut cx = Complex::default();
        let mut owner = vec![]; // per segment, the cavity column it bounds
        let mut anchors = vec![]; // per segment, the site across it
        let mut outer_pieces: Vec<(u32, u32)> = vec![]; // on the outer boundary
        fault_segments = 0;
        let mut vid: FastMap<u32, u32> = FastMap::default();
        let mut vertex = |cx: &mut Complex, p: u32| -> u32 {
            *vid.entry(p).or_insert_with(|| {
                cx.points.push(view.pillar[p as usize]);
                cx.points.len() as u32 - 1
            })
        };
        for j in 0..ny {
            for i in 0..nx {
                if !cavity[col(i, j)] {
                    continue;
                }
                let sides = [
                    ((i, j.wrapping_sub(1)), (view.pid(i, j), view.pid(i + 1, j))),
                    ((i + 1, j), (view.pid(i + 1, j), view.pid(i + 1, j + 1))),
                    ((i, j + 1), (view.pid(i + 1, j + 1), view.pid(i, j + 1))),
                    ((i.wrapping_sub(1), j), (view.pid(i, j + 1), view.pid(i, j))),
                ];
                for ((a, b), (p, q)) in sides {
                    if a < nx && b < ny && cavity[col(a, b)] {
                        continue;
                    }
                    let (u, v) = (vertex(&mut cx, p), vertex(&mut cx, q));
                    // A side on the mesh's outer boundary (no cell across)
                    // may take extra vertices: split it into pieces no
                    // longer than its distance to the nearest well polygon,
                    // so that a well near the edge does not make system 3
                    // infeasible.
                    let outer_side = !(a < nx && b < ny && grid.active(a, b, k));
                    let (pp, pq) = (view.pillar[p as usize], view.pillar[q as usize]);
                    let pieces = if outer_side {
                        pieces_near_wells(pp, pq)
                    } else {
                        1
                    };
                    // The reservoir cell across: its site should be on the
                    // dual line of each piece (orthogonal interface).
                    let across = (!outer_side).then(|| view.centroid(a, b));
                    for (from, to) in split(&mut cx, u, v, pieces) {
                        cx.segments.push([from, to]);
                        anchors.push(across);
                        owner.push(col(i, j));
                        if outer_side {
                            outer_pieces.push((from, to));
                        }
                    }
                }
            }
        }
        // Faults: pillar edges between two cavity columns become chains of
        // segments with free ends inside the cavity (sides between a cavity
        // column and another already are segments).
        let mut seen_fault_edges = crate::FastSet::default();
        for (p, q, a, b) in fault_edges(grid, k, &view) {
            let in_cavity = |c: (usize, usize)| c.0 < nx && c.1 < ny && cavity[col(c.0, c.1)];
            if in_cavity(a) && in_cavity(b) && seen_fault_edges.insert((p.min(q), p.max(q))) {
                // Inside a cavity a fault side may take extra vertices (cells
                // on both sides are transition cells): pieces no longer than
                // its distance to the nearest well polygon.
                let (u, v) = (vertex(&mut cx, p), vertex(&mut cx, q));
                let (pp, pq) = (view.pillar[p as usize], view.pillar[q as usize]);
                for (from, to) in split(&mut cx, u, v, pieces_near_wells(pp, pq)) {
                    cx.segments.push([from, to]);
                    anchors.push(None);
                    owner.push(col(a.0, a.1));
                    fault_segments += 1;
                }
            }
        }
        // Fault polylines: the parts inside cavities, pulled back a quarter
        // cell from where they leave one, so that they end inside it.
        let boundary_sides: Vec<[[f64; 2]; 2]> = cx
            .segments
            .iter()
            .map(|s| [cx.points[s[0] as usize], cx.points[s[1] as usize]])
            .collect();
        let cavity_column_at = |x: [f64; 2]| {
            (0..nx * ny)
                .find(|&c| cavity[c] && distance_to_polygon(x, &quad_points(c % nx, c / nx)) == 0.0)
        };
        let in_cavity_at = |x: [f64; 2]| cavity_column_at(x).is_some();
        for line in &opts.fault_lines {
            for chain in clip_to_cavity(line, &boundary_sides, &in_cavity_at, 0.5 * typical_side) {
                // the cavity the chain is in, should it need to grow
                let home = cavity_column_at(chain[0]).unwrap_or(well_column[0]);
                let mut prev: Option<u32> = None;
                for x in chain {
                    cx.points.push(x);
                    let id = cx.points.len() as u32 - 1;
                    if let Some(p) = prev {
                        let pieces = pieces_near_wells(cx.points[p as usize], x);
                        for (from, to) in split(&mut cx, p, id, pieces) {
                            cx.segments.push([from, to]);
                            anchors.push(None);
                            owner.push(home);
                            fault_segments += 1;
                        }
                    }
                    prev = Some(id);
                }
            }
        }
        for (w, &c) in placed.iter().zip(&well_column) {
            let r = *w.radii.last().unwrap();
            // the outer ring's sites, across the chords
            let rho = *site_radii(&w.radii, m).last().unwrap();
            let first = cx.points.len() as u32;
            for s in 0..m {
                cx.points.push(polygon_point(w.centre, r, s, m));
            }
            for s in 0..m {
                cx.segments
                    .push([first + s as u32, first + ((s + 1) % m) as u32]);
                anchors.push(Some(radial_site(w.centre, rho, s, m)));
                owner.push(c);
            }
            cx.holes.push(w.centre);
        }
        let cx = Complex {
            holes: cx.holes,
            anchors,
            ..Complex::new(cx.points, cx.segments)
        };
        tell("transition mesh (attempt)", notes.len() + 1, MAX_GROWTH + 1);
        let allow = opts.allow_sites_outside && give_up;
        let options = Options {
            allow_sites_outside: allow,
            ..Default::default()
        };
        match conform2(backend, &cx, &options) {
            Ok(out) => break (cx, out, outer_pieces),
            Err(Error::SegmentsMissTheirDuals { segments, .. }) if !give_up => {
                let label = components(&cavity);
                let grown: crate::FastSet<usize> =
                    segments.iter().map(|&s| label[owner[s as usize]]).collect();
                let names: Vec<String> = placed
                    .iter()
                    .zip(&well_column)
                    .filter(|(_, &c)| grown.contains(&label[c]))
                    .map(|(w, _)| w.name.clone())
                    .collect();
                let before = cavity.clone();
                grow(&mut cavity, &|c| grown.contains(&label[c]));
                let changed = cavity != before;
                notes.push(if changed {
                    format!(
                        "system 3 infeasible for {} segments: the cavity around {} grew by a ring of cells",
                        segments.len(),
                        if names.is_empty() { "no well".to_string() } else { names.join(", ") }
                    )
                } else {
                    format!(
                        "system 3 infeasible for {} segments and the cavity cannot grow (grid edge or inactive cells){}",
                        segments.len(),
                        if opts.allow_sites_outside { ": sites outside their cells allowed" } else { "" }
                    )
                });
                give_up = !changed || notes.len() >= MAX_GROWTH;
                if give_up && !opts.allow_sites_outside {
                    return Err(Error::SitesOutsideCells {
                        sites: vec![format!(
                            "{}; segments {:?} cannot cross their dual edges",
                            notes.last().expect("just pushed"),
                            segments
                        )],
                        crowding: vec![],
                    });
                }
            }
            Err(e) => return Err(e),
        }
    };
    let cavity_cells = cavity.iter().filter(|&&c| c).count();

    tell("assembling", 1, 1);
    // Assemble: points shared by exact coordinates.
    let mut mesh = Mesh::default();
    let mut index: FastMap<[u64; 2], u32> = FastMap::default();
    let mut point = |mesh: &mut Mesh, p: [f64; 2]| -> u32 {
        *index
            .entry(p.map(|x| (x + 0.0).to_bits()))
            .or_insert_with(|| {
                mesh.points.push(p);
                mesh.points.len() as u32 - 1
            })
    };
    let mut region = vec![];
    let mut ijk = vec![];
    let (mut thickness, mut depth) = (vec![], vec![]);
    let column = |i: usize, j: usize| {
        let z: Vec<f64> = (0..8).map(|c| grid.corner(i, j, k, c)[2]).collect();
        let h = (4..8).map(|c| z[c] - z[c - 4]).sum::<f64>() / 4.0;
        (h, z.iter().sum::<f64>() / 8.0)
    };
    let (mut h_sum, mut d_sum, mut n_active) = (0.0, 0.0, 0usize);
    for j in 0..ny {
        for i in 0..nx {
            if grid.active(i, j, k) {
                let (h, d) = column(i, j);
                h_sum += h;
                d_sum += d;
                n_active += 1;
            }
        }
    }
    let layer = (
        h_sum / n_active.max(1) as f64,
        d_sum / n_active.max(1) as f64,
    );
    for j in 0..ny {
        for i in 0..nx {
            if cavity[col(i, j)] || !grid.active(i, j, k) {
                continue;
            }
            let q = quad_points(i, j);
            let cell: Vec<u32> = q.iter().map(|&p| point(&mut mesh, p)).collect();
            mesh.cells.push(cell);
            let c = view.centroid(i, j);
            mesh.sites.push(c);
            // The corners have equal power: a rectangle's cells are then
            // the power cells of their centres.
            mesh.weights
                .push((q[0][0] - c[0]).powi(2) + (q[0][1] - c[1]).powi(2));
            region.push(Region::Reservoir);
            ijk.push(Some([i, j, k]));
            let (h, d) = column(i, j);
            thickness.push(h);
            depth.push(d);
        }
    }
    let t = &out.mesh;
    for (c, cell) in t.cells.iter().enumerate() {
        let cell: Vec<u32> = cell
            .iter()
            .map(|&p| point(&mut mesh, t.points[p as usize]))
            .collect();
        mesh.cells.push(cell);
        mesh.sites.push(t.sites[c]);
        mesh.weights.push(t.weights[c]);
        region.push(Region::Transition);
        ijk.push(None);
        thickness.push(layer.0);
        depth.push(layer.1);
    }
    for w in &placed {
        let r = &w.radii;
        // Sites on the mid-angle rays, at beta r_q: the ring faces are chords
        // perpendicular to those rays, the sector faces their bisectors, and
        // beta makes every ring-to-ring link carry radial flow exactly: with
        // r_{q+1} = alpha r_q, the two-point transmissibility of the chord,
        // 2 r_{q+1} sin(h) / (rho_{q+1} - rho_q), equals the sector's radial
        // one, 2h / ln(alpha) (docs/method.md section 6; beats the geometric mean
        // and the mid-radius). Weights make each chord the radical line of
        // the sites beside it.
        let half = TAU / (2 * m) as f64;
        let rho = site_radii(r, m);
        let mut wt = vec![0.0; opts.rings];
        for q in 1..opts.rings {
            let h = r[q] * half.cos();
            wt[q] = wt[q - 1] + rho[q] * rho[q]
                - rho[q - 1] * rho[q - 1]
                - 2.0 * h * (rho[q] - rho[q - 1]);
        }
        for q in 0..opts.rings {
            for s in 0..m {
                // The outer ring's corners are the transition's input
                // vertices: the very same doubles (angle index taken mod m).
                let corners = [(q, s), (q + 1, s), (q + 1, (s + 1) % m), (q, (s + 1) % m)];
                let cell: Vec<u32> = corners
                    .iter()
                    .map(|&(rq, sq)| point(&mut mesh, polygon_point(w.centre, r[rq], sq, m)))
                    .collect();
                mesh.cells.push(cell);
                mesh.sites.push(radial_site(w.centre, rho[q], s, m));
                mesh.weights.push(wt[q]);
                region.push(Region::Well);
                ijk.push(None);
                thickness.push(layer.0);
                depth.push(layer.1);
            }
        }
    }
    let sizes = |r: Region| region.iter().filter(|&&x| x == r).count();
    let cells = [
        sizes(Region::Reservoir),
        sizes(Region::Transition),
        sizes(Region::Well),
    ];
    let (lo, hi) = crate::geom::bbox(&mesh.points);
    mesh.size = (hi[0] - lo[0]).max(hi[1] - lo[1]);
    // The outer boundary: sides of active columns next to inactive ones or
    // the grid's edge. Every other cell edge must have a twin.
    let active = |i: i64, j: i64| {
        i >= 0
            && j >= 0
            && (i as usize) < nx
            && (j as usize) < ny
            && grid.active(i as usize, j as usize, k)
    };
    let mut boundary = crate::FastSet::default();
    for j in 0..ny as i64 {
        for i in 0..nx as i64 {
            if !active(i, j) {
                continue;
            }
            let q = quad_points(i as usize, j as usize);
            let ids: Vec<u32> = q.iter().map(|&p| point(&mut mesh, p)).collect();
            for e in 0..4 {
                let (a, b) = (ids[e], ids[(e + 1) % 4]);
                let mid = [
                    (q[e][0] + q[(e + 1) % 4][0]) / 2.0,
                    (q[e][1] + q[(e + 1) % 4][1]) / 2.0,
                ];
                // the column across this side
                let across = [(0, -1), (1, 0), (0, 1), (-1, 0)]
                    .iter()
                    .map(|&(di, dj)| (i + di, j + dj))
                    .find(|&(a2, b2)| {
                        a2 >= 0
                            && b2 >= 0
                            && (a2 as usize) < nx
                            && (b2 as usize) < ny
                            && distance_to_polygon(mid, &quad_points(a2 as usize, b2 as usize))
                                == 0.0
                    });
                if across.is_none_or(|(a2, b2)| !active(a2, b2)) {
                    boundary.insert((a, b));
                }
            }
        }
    }
    for &(a, b) in &outer_pieces {
        let (pa, pb) = (cx.points[a as usize], cx.points[b as usize]);
        let (ia, ib) = (point(&mut mesh, pa), point(&mut mesh, pb));
        // the piece lies on the boundary one way or the other
        boundary.insert((ia, ib));
        boundary.insert((ib, ia));
    }
    for w in &placed {
        for sct in 0..m {
            let a = point(&mut mesh, polygon_point(w.centre, w.radii[0], sct, m));
            let b = point(
                &mut mesh,
                polygon_point(w.centre, w.radii[0], (sct + 1) % m, m),
            );
            boundary.insert((b, a)); // the wellbore, seen from its cells
        }
    }
    let unmatched = mesh.match_faces(&boundary);
    let cavities = {
        let label = components(&cavity);
        (0..nx * ny).filter(|&c| label[c] == c).count()
    };
    let mut defect: Vec<(String, f64)> = vec![];
    let name = |r: Region| match r {
        Region::Reservoir => "reservoir",
        Region::Transition => "transition",
        Region::Well => "well",
    };
    let mut interfaces = vec![];
    for &[a, b, c, d] in &mesh.faces {
        let (ra, rb) = (region[c as usize], region[d as usize]);
        let (lo, hi) = if (ra as u8) <= (rb as u8) {
            (ra, rb)
        } else {
            (rb, ra)
        };
        let key = format!("{}-{}", name(lo), name(hi));
        let v = mesh.face_defect([a, b, c, d]);
        if ra != rb && v > crate::reservoir::flow::ORTHOGONAL && interfaces.len() < 100 {
            let cell = ijk[c as usize]
                .or(ijk[d as usize])
                .map(|x| x.map(|v| v + 1));
            interfaces.push((cell, key.clone(), v));
        }
        match defect.iter_mut().find(|(k, _)| *k == key) {
            Some(e) => e.1 = e.1.max(v),
            None => defect.push((key, v)),
        }
    }
    defect.sort_by(|x, y| x.0.cmp(&y.0));
    let conns = crate::reservoir::flow::connections(&mesh);
    let transmissibility = crate::reservoir::flow::stats(&mesh, &conns, |_| true);
    let transmissibility_near_wells = crate::reservoir::flow::stats(&mesh, &conns, |c| {
        c.iter().any(|&x| region[x as usize] != Region::Reservoir)
    });
    let report = HybridReport {
        transmissibility,
        transmissibility_near_wells,
        layer: k,
        wells: placed.iter().map(|w| w.name.clone()).collect(),
        cavities,
        cavity_cells,
        cells,
        orthogonality_defect: defect,
        non_orthogonal_interfaces: interfaces,
        unmatched_faces: unmatched,
        fault_segments,
        notes,
        transition: out.report,
    };
    Ok(Hybrid {
        mesh,
        region,
        ijk,
        constraints: cx,
        thickness,
        depth,
        report,
    })
}
