//! The assembly stage: reservoir cells outside the cavities, the
//! transition cells and the radial well cells joined into one polygon mesh
//! by shared doubles, checked for hanging nodes, and measured.

use super::map::distance_to_polygon;
use super::transition::Transition;
use super::wells::{polygon_point, radial_site, site_radii, Placed};
use super::{Hybrid, HybridOptions, HybridReport, Layer, Region, WellMesh};
use crate::error::Result;
use crate::mesh::Mesh;
use crate::{FastMap, FastSet};
use std::f64::consts::TAU;

/// The mesh being assembled, a cell at a time, with per cell its region,
/// grid cell, thickness and mid-depth.
#[derive(Default)]
struct Assembly {
    mesh: Mesh,
    index: FastMap<[u64; 2], u32>,
    region: Vec<Region>,
    ijk: Vec<Option<[usize; 3]>>,
    thickness: Vec<f64>,
    depth: Vec<f64>,
    wells: Vec<WellMesh>,
}

impl Assembly {
    /// The id of point p: points are shared by exact coordinates.
    fn point(&mut self, p: [f64; 2]) -> u32 {
        let mesh = &mut self.mesh;
        *self
            .index
            .entry(p.map(|x| (x + 0.0).to_bits()))
            .or_insert_with(|| {
                mesh.points.push(p);
                mesh.points.len() as u32 - 1
            })
    }

    /// The active columns outside the cavities, as they are (a cell's
    /// corners have equal power from its centre); returns the layer's mean
    /// thickness and mid-depth, for the other cells.
    fn reservoir(&mut self, layer: &Layer, cavity: &[bool]) -> (f64, f64) {
        let (grid, k, view, nx, ny) = (layer.grid, layer.k, &layer.view, layer.nx, layer.ny);
        let col = |i: usize, j: usize| layer.col(i, j);
        let quad_points = |i: usize, j: usize| layer.quad_points(i, j);
        let column = |i: usize, j: usize| column(layer, i, j);
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
                let cell: Vec<u32> = q.iter().map(|&p| self.point(p)).collect();
                self.mesh.cells.push(cell);
                let c = view.centroid(i, j);
                self.mesh.sites.push(c);
                // The corners have equal power: a rectangle's cells are then
                // the power cells of their centres.
                self.mesh
                    .weights
                    .push((q[0][0] - c[0]).powi(2) + (q[0][1] - c[1]).powi(2));
                self.region.push(Region::Reservoir);
                self.ijk.push(Some([i, j, k]));
                let (h, d) = column(i, j);
                self.thickness.push(h);
                self.depth.push(d);
            }
        }
        layer
    }

    /// The transition mesh's cells.
    fn transition(&mut self, out: &Mesh, means: (f64, f64)) {
        let layer = means;
        let t = out;
        for (c, cell) in t.cells.iter().enumerate() {
            let cell: Vec<u32> = cell
                .iter()
                .map(|&p| self.point(t.points[p as usize]))
                .collect();
            self.mesh.cells.push(cell);
            self.mesh.sites.push(t.sites[c]);
            self.mesh.weights.push(t.weights[c]);
            self.region.push(Region::Transition);
            self.ijk.push(None);
            self.thickness.push(layer.0);
            self.depth.push(layer.1);
        }
    }

    /// The radial cells of every well.
    fn wells(&mut self, placed: &[Placed], opts: &HybridOptions, means: (f64, f64)) {
        let (layer, m) = (means, opts.sectors);
        for w in placed {
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
            // The innermost ring comes first: its m cells face the wellbore.
            let first = self.mesh.cells.len() as u32;
            self.wells.push(WellMesh {
                name: w.name.clone(),
                centre: w.centre,
                radius: r[0],
                site_radius: rho[0],
                inner: (first..first + m as u32).collect(),
            });
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
                        .map(|&(rq, sq)| self.point(polygon_point(w.centre, r[rq], sq, m)))
                        .collect();
                    self.mesh.cells.push(cell);
                    self.mesh.sites.push(radial_site(w.centre, rho[q], s, m));
                    self.mesh.weights.push(wt[q]);
                    self.region.push(Region::Well);
                    self.ijk.push(None);
                    self.thickness.push(layer.0);
                    self.depth.push(layer.1);
                }
            }
        }
    }

    /// The outer boundary: sides of active columns next to inactive ones or
    /// the grid's edge, cavity sides there, and the wellbores. Every other
    /// cell edge must have a twin.
    fn boundary(
        &mut self,
        layer: &Layer,
        placed: &[Placed],
        t: &Transition,
        m: usize,
    ) -> FastSet<(u32, u32)> {
        let (grid, k, nx, ny) = (layer.grid, layer.k, layer.nx, layer.ny);
        let quad_points = |i: usize, j: usize| layer.quad_points(i, j);
        let (cx, outer_pieces) = (&t.cx, &t.outer_pieces);
        // The outer boundary: sides of active columns next to inactive ones or
        // the grid's edge. Every other cell edge must have a twin.
        let active = |i: i64, j: i64| {
            i >= 0
                && j >= 0
                && (i as usize) < nx
                && (j as usize) < ny
                && grid.active(i as usize, j as usize, k)
        };
        let mut boundary = FastSet::default();
        for j in 0..ny as i64 {
            for i in 0..nx as i64 {
                if !active(i, j) {
                    continue;
                }
                let q = quad_points(i as usize, j as usize);
                let ids: Vec<u32> = q.iter().map(|&p| self.point(p)).collect();
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
        for &(a, b) in outer_pieces {
            let (pa, pb) = (cx.points[a as usize], cx.points[b as usize]);
            let (ia, ib) = (self.point(pa), self.point(pb));
            // the piece lies on the boundary one way or the other
            boundary.insert((ia, ib));
            boundary.insert((ib, ia));
        }
        for w in placed {
            for sct in 0..m {
                let a = self.point(polygon_point(w.centre, w.radii[0], sct, m));
                let b = self.point(polygon_point(w.centre, w.radii[0], (sct + 1) % m, m));
                boundary.insert((b, a)); // the wellbore, seen from its cells
            }
        }
        boundary
    }
}

/// Per cell, the grid cell whose rock it takes: its own for reservoir
/// cells; for transition and well cells, the cavity column of the layer
/// that holds its site (the nearest one where rounding leaves it outside
/// all, found by a scan). Columns are looked up in buckets about the size
/// of the largest column.
fn hosts(layer: &Layer, cavity: &[bool], a: &Assembly) -> Vec<[usize; 3]> {
    let (k, nx, ny) = (layer.k, layer.nx, layer.ny);
    let cols: Vec<(usize, usize, [[f64; 2]; 4])> = (0..ny)
        .flat_map(|j| (0..nx).map(move |i| (i, j)))
        .filter(|&(i, j)| cavity[layer.col(i, j)])
        .map(|(i, j)| (i, j, layer.quad_points(i, j)))
        .collect();
    let boxes: Vec<[f64; 4]> = cols
        .iter()
        .map(|(_, _, q)| {
            let xs = q.map(|p| p[0]);
            let ys = q.map(|p| p[1]);
            let (min, max) = (
                |v: [f64; 4]| v.iter().copied().fold(f64::INFINITY, f64::min),
                |v: [f64; 4]| v.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            );
            [min(xs), min(ys), max(xs), max(ys)]
        })
        .collect();
    // Buckets of a side about the largest column's, each listing the
    // columns whose box meets it.
    let side = boxes
        .iter()
        .map(|b| (b[2] - b[0]).max(b[3] - b[1]))
        .fold(0.0f64, f64::max)
        .max(f64::MIN_POSITIVE);
    let origin = boxes
        .iter()
        .fold([f64::INFINITY; 2], |o, b| [o[0].min(b[0]), o[1].min(b[1])]);
    let bucket = |x: f64, o: f64| ((x - o) / side).floor().clamp(0.0, 1e9) as u64;
    let mut buckets: FastMap<[u64; 2], Vec<usize>> = FastMap::default();
    for (c, b) in boxes.iter().enumerate() {
        for bx in bucket(b[0], origin[0])..=bucket(b[2], origin[0]) {
            for by in bucket(b[1], origin[1])..=bucket(b[3], origin[1]) {
                buckets.entry([bx, by]).or_default().push(c);
            }
        }
    }
    let host = |x: [f64; 2]| -> [usize; 3] {
        let near = buckets.get(&[bucket(x[0], origin[0]), bucket(x[1], origin[1])]);
        let mut best = (f64::INFINITY, 0);
        for &c in near.into_iter().flatten() {
            let d = distance_to_polygon(x, &cols[c].2);
            if d < best.0 {
                best = (d, c);
            }
        }
        if best.0 > 0.0 {
            for (c, col) in cols.iter().enumerate() {
                let d = distance_to_polygon(x, &col.2);
                if d < best.0 {
                    best = (d, c);
                }
            }
        }
        let (i, j, _) = cols[best.1];
        [i, j, k]
    };
    (0..a.mesh.cells.len())
        .map(|c| a.ijk[c].unwrap_or_else(|| host(a.mesh.sites[c])))
        .collect()
}

/// A column's cell in the layer: its mean thickness and its mid-depth.
fn column(layer: &Layer, i: usize, j: usize) -> (f64, f64) {
    let z: Vec<f64> = (0..8)
        .map(|c| layer.grid.corner(i, j, layer.k, c)[2])
        .collect();
    let h = (4..8).map(|c| z[c] - z[c - 4]).sum::<f64>() / 4.0;
    (h, z.iter().sum::<f64>() / 8.0)
}

/// The hybrid mesh from its parts, with its report.
pub(super) fn assemble(
    layer: &Layer,
    placed: &[Placed],
    cavity: &[bool],
    t: Transition,
    opts: &HybridOptions,
) -> Result<Hybrid> {
    let (k, nx, ny) = (layer.k, layer.nx, layer.ny);
    let cavity_cells = cavity.iter().filter(|&&c| c).count();
    let mut a = Assembly::default();
    let means = a.reservoir(layer, cavity);
    a.transition(&t.out.mesh, means);
    a.wells(placed, opts, means);
    let region = &a.region;
    let sizes = |r: Region| region.iter().filter(|&&x| x == r).count();
    let cells = [
        sizes(Region::Reservoir),
        sizes(Region::Transition),
        sizes(Region::Well),
    ];
    let (lo, hi) = crate::geom::bbox(&a.mesh.points);
    a.mesh.size = (hi[0] - lo[0]).max(hi[1] - lo[1]);
    let boundary = a.boundary(layer, placed, &t, opts.sectors);
    let host = hosts(layer, cavity, &a);
    // Transition and well cells take their host column's thickness and
    // depth (on a dipping layer, those of the reservoir around them); the
    // layer's means where the host has no thickness.
    for (c, &[i, j, _]) in host.iter().enumerate() {
        let (h, d) = column(layer, i, j);
        if a.ijk[c].is_none() && layer.grid.active(i, j, k) && h > 0.0 {
            (a.thickness[c], a.depth[c]) = (h, d);
        }
    }
    let Assembly {
        mut mesh,
        region,
        ijk,
        thickness,
        depth,
        wells,
        ..
    } = a;
    let unmatched = mesh.match_faces(&boundary);
    let cavities = {
        let label = layer.components(cavity);
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
        fault_segments: t.fault_segments,
        notes: t.notes,
        transition: t.out.report,
    };
    Ok(Hybrid {
        mesh,
        region,
        ijk,
        constraints: t.cx,
        thickness,
        depth,
        host,
        wells,
        report,
    })
}
