//! The assembly of the 3D hybrid: reservoir hexahedra outside the cavity,
//! the transition's cells, the well's radial cells, one point numbering
//! over the three, and the connections between all cells.

use super::cavity::{Cavity, WALL, WELL};
use super::lattice::{dist, find_face, orient_faces};
use super::radial::Radial;
use super::{Hybrid3, Hybrid3Report};
use crate::conform::{Outcome, D3};
use crate::geom::{volume, Plane};
use crate::mesh::{Link3, Mesh3};
use crate::reservoir::hybrid::{site_radii, Region};
use crate::reservoir::CornerPointGrid;
use std::collections::HashMap;
use std::f64::consts::TAU;

/// The mesh being assembled, with per cell its region and grid cell.
#[derive(Default)]
struct Assembly {
    out: Mesh3,
    region: Vec<Region>,
    ijk: Vec<Option<[usize; 3]>>,
    ids: HashMap<[u64; 3], u32>,
}

/// The plane of a face of the mesh.
fn plane(out: &Mesh3, face: &[u32]) -> Plane {
    let pts: Vec<[f64; 3]> = face.iter().map(|&v| out.points[v as usize]).collect();
    Plane::of(&pts)
}

impl Assembly {
    /// The id of point p: points are shared by exact coordinates.
    fn point(&mut self, p: [f64; 3]) -> u32 {
        let out = &mut self.out;
        *self.ids.entry(p.map(f64::to_bits)).or_insert_with(|| {
            out.points.push(p);
            out.points.len() as u32 - 1
        })
    }

    /// Reservoir hexahedra outside the cavity; per grid cell, its cell.
    fn reservoir(&mut self, g: &CornerPointGrid, w: &Radial) -> HashMap<[usize; 3], usize> {
        let (xs, ys, zs, i0, j0) = (&w.xs, &w.ys, &w.zs, w.i0, w.j0);
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
                    let c = |di: usize, dj: usize, dk: usize| w.node(i + di, j + dj, k + dk);
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
                        .map(|f| f.into_iter().map(|p| self.point(p)).collect())
                        .collect();
                    let site = [
                        (xs[i] + xs[i + 1]) / 2.0,
                        (ys[j] + ys[j + 1]) / 2.0,
                        (zs[k] + zs[k + 1]) / 2.0,
                    ];
                    res_cell.insert([i, j, k], self.out.cells.len());
                    self.out
                        .cells
                        .push(orient_faces(faces, &self.out.points, site));
                    self.out.sites.push(site);
                    self.out.weights.push(0.0);
                    self.out
                        .volumes
                        .push((xs[i + 1] - xs[i]) * (ys[j + 1] - ys[j]) * (zs[k] - zs[k + 1]));
                    self.out.site_inside.push(true);
                    self.region.push(Region::Reservoir);
                    self.ijk.push(Some([i, j, k]));
                }
            }
        }
        res_cell
    }

    /// Connections between reservoir cells, in grid order (the same input
    /// gives the same connections' order).
    fn reservoir_links(&mut self, w: &Radial, res_cell: &HashMap<[usize; 3], usize>) {
        let (xs, ys, zs) = (&w.xs, &w.ys, &w.zs);
        // reservoir connections
        // in grid order: the same input gives the same connections' order
        let mut grid_order: Vec<([usize; 3], usize)> =
            res_cell.iter().map(|(&c, &a)| (c, a)).collect();
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
                        dist(self.out.sites[a], self.out.sites[b], normal) / 2.0,
                        dist(self.out.sites[a], self.out.sites[b], normal) / 2.0,
                    ];
                    self.out.links.push(Link3 {
                        cells: [a, b],
                        face: vec![],
                        area,
                        d,
                        normal,
                    });
                }
            }
        }
    }

    /// The transition's cells and links; returns the first's index.
    fn transition(&mut self, t: &Outcome<D3>) -> usize {
        // the transition's cells
        let first_t = self.out.cells.len();
        for (c, faces) in t.mesh.cells.iter().enumerate() {
            let faces: Vec<Vec<u32>> = faces
                .iter()
                .map(|f| {
                    f.iter()
                        .map(|&v| self.point(t.mesh.points[v as usize]))
                        .collect()
                })
                .collect();
            self.out.cells.push(faces);
            self.out.sites.push(t.mesh.sites[c]);
            self.out.weights.push(t.mesh.weights[c]);
            self.out.volumes.push(t.mesh.volumes[c]);
            self.out.site_inside.push(t.mesh.site_inside[c]);
            self.region.push(Region::Transition);
            self.ijk.push(None);
        }
        for l in &t.mesh.links {
            self.out.links.push(Link3 {
                cells: l.cells.map(|c| c + first_t),
                face: vec![],
                ..l.clone()
            });
        }
        first_t
    }

    /// The well's cells: ring q, sector s, layer k; returns the first's index.
    fn wells(&mut self, w: &Radial) -> usize {
        let (r, m, rings, mid, levels) = (&w.r, w.m, w.rings, &w.mid, &w.levels);
        // the well's cells: ring q, sector s, layer k
        let first_w = self.out.cells.len();
        let rho = site_radii(r, m);
        for (k, &mid_k) in mid.iter().enumerate() {
            for (q, &rho_q) in rho.iter().enumerate() {
                for s in 0..m {
                    let p = |qq: usize, ss: usize, kk: usize| match qq == rings {
                        true => w.surface(ss, kk),
                        false => w.at(r[qq], w.angle(ss), levels[kk]),
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
                    let v: Vec<u32> = corners.iter().map(|&c| self.point(c)).collect();
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
                    let site = w.at(rho_q, TAU * (s as f64 + 0.5) / m as f64, mid_k);
                    self.out
                        .cells
                        .push(orient_faces(faces, &self.out.points, site));
                    self.out.sites.push(site);
                    self.out.weights.push(0.0);
                    self.out.volumes.push(0.0);
                    self.out.site_inside.push(true);
                    self.region.push(Region::Well);
                    self.ijk.push(None);
                }
            }
        }
        first_w
    }

    /// A link across a face between cells a and b.
    fn link(&mut self, a: usize, b: usize, face: &[u32]) {
        let pl = plane(&self.out, face);
        let d = [
            pl.distance(self.out.sites[a]),
            pl.distance(self.out.sites[b]),
        ];
        self.out.links.push(Link3 {
            cells: [a, b],
            face: face.to_vec(),
            area: pl.area,
            d,
            normal: pl.unit,
        });
    }

    /// Well volumes from their faces, and the well's own connections.
    fn well_links(&mut self, w: &Radial, first_w: usize) {
        let (m, rings, nl) = (w.m, w.rings, w.nl);
        let well_cell = |q: usize, s: usize, k: usize| first_w + (k * rings + q) * m + s;
        // well volumes from their faces, and the well's own connections
        for c in first_w..self.out.cells.len() {
            self.out.volumes[c] = volume(&self.out.cells[c], &self.out.points);
        }
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
                        let face = find_face(&self.out.cells[a], &self.out.cells[b]);
                        self.link(a, b, &face);
                    }
                }
            }
        }
    }

    /// Interfaces: transition faces on walls and on the well's surface.
    fn interfaces(
        &mut self,
        t: &Outcome<D3>,
        cavity: &Cavity,
        w: &Radial,
        res_cell: &HashMap<[usize; 3], usize>,
        [first_t, first_w]: [usize; 2],
    ) {
        let (m, rings) = (w.m, w.rings);
        let well_cell = |q: usize, s: usize, k: usize| first_w + (k * rings + q) * m + s;
        let (cx, wall_cells, well_facets, first_well_facet) = (
            &cavity.cx,
            &cavity.wall_cells,
            &cavity.well_facets,
            cavity.first_well_facet,
        );
        // interfaces: transition faces on walls and on the well's surface
        for f in &t.mesh.facet_faces {
            let a = first_t + f.cell;
            let face: Vec<u32> = f
                .points
                .iter()
                .map(|&v| self.point(t.mesh.points[v as usize]))
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
            let pl = plane(&self.out, &face);
            self.out.links.push(Link3 {
                cells: [a, b],
                face,
                area: f.area,
                d: [f.d, pl.distance(self.out.sites[b])],
                normal: pl.unit,
            });
        }
    }
}

/// The 3D hybrid from its parts, with its report.
pub(super) fn assemble(
    g: &CornerPointGrid,
    w: &Radial,
    cavity: &Cavity,
    t: Outcome<D3>,
) -> Hybrid3 {
    let mut a = Assembly::default();
    let res_cell = a.reservoir(g, w);
    a.reservoir_links(w, &res_cell);
    let first_t = a.transition(&t);
    let first_w = a.wells(w);
    a.well_links(w, first_w);
    let wellbore = wellbore(w, first_w);
    a.interfaces(&t, cavity, w, &res_cell, [first_t, first_w]);
    let Assembly {
        mut out,
        region,
        ijk,
        ..
    } = a;
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
    let host = hosts(w, &ijk, &out.sites);
    Hybrid3 {
        mesh: out,
        region,
        ijk,
        host,
        wellbore,
        report,
    }
}

/// Per cell, the grid cell whose rock it takes: a reservoir cell its own;
/// a transition or well cell the cavity's cell that holds its site (the
/// nearest cavity cell for a site outside its cell).
fn hosts(w: &Radial, ijk: &[Option<[usize; 3]>], sites: &[[f64; 3]]) -> Vec<[usize; 3]> {
    // the slab of `v` (nodes increasing) that holds x, clamped to lo..=hi
    let slab = |v: &[f64], x: f64, lo: usize, hi: usize| {
        v[1..v.len() - 1]
            .partition_point(|&node| node <= x)
            .clamp(lo, hi)
    };
    let nz = w.zs.len() - 1;
    // zs decrease downwards: slabs of the depths -zs
    let depths: Vec<f64> = w.zs.iter().map(|z| -z).collect();
    ijk.iter()
        .zip(sites)
        .map(|(c, p)| {
            c.unwrap_or_else(|| {
                [
                    slab(&w.xs, p[0], w.i0 - 1, w.i0 + 1),
                    slab(&w.ys, p[1], w.j0 - 1, w.j0 + 1),
                    slab(&depths, -p[2], 0, nz - 1),
                ]
            })
        })
        .collect()
}

/// The innermost ring's cells and the geometric part of their connection
/// to the wellbore: radial flow from the wellbore to the sites' radius
/// within a sector is exact, theta L / ln(rho / r_w), L the cell's length
/// along the axis.
fn wellbore(w: &Radial, first_w: usize) -> Vec<(usize, f64)> {
    let (m, rings) = (w.m, w.rings);
    let rho = site_radii(&w.r, m);
    let log = (rho[0] / w.r[0]).ln();
    let theta = TAU / m as f64;
    (0..w.nl)
        .flat_map(|k| {
            let (a, b) = (w.at(0.0, 0.0, w.levels[k]), w.at(0.0, 0.0, w.levels[k + 1]));
            let length = (0..3).map(|i| (b[i] - a[i]).powi(2)).sum::<f64>().sqrt();
            (0..m).map(move |s| (first_w + k * rings * m + s, theta * length / log))
        })
        .collect()
}
