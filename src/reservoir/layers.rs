//! 2.5D (paper section 5.3): the 2D hybrid mesh mapped onto every layer of
//! the corner-point grid. Each mesh point keeps its map position and gets
//! the depth of every layer horizon (pillar depths at grid corners,
//! interpolated inside a column elsewhere); each cell of each layer becomes
//! a prism-like polyhedron between two horizons. Side faces are vertical,
//! hence planar; top and bottom faces are split into triangles (the same
//! fan from above and below) when the horizon warps them.

use crate::error::{Error, Result};
use crate::mesh::{CellArray, CellMesh, Cells, Connection, Element, Network};
use crate::reservoir::hybrid::Hybrid;
use crate::reservoir::CornerPointGrid;

/// The layered mesh: points (x, y, z up), and per cell its faces, each a
/// list of point ids counter-clockwise seen from outside.
#[derive(Debug, Clone, Default)]
pub struct Layered {
    /// The vertices.
    pub points: Vec<[f64; 3]>,
    /// Per cell, its faces.
    pub cells: Vec<Vec<Vec<u32>>>,
    /// Per cell: the 2D cell and the layer.
    pub origin: Vec<(u32, usize)>,
    /// Per cell: volume, node (site at mid-depth).
    pub volume: Vec<f64>,
    /// Per cell, its node: the site at mid-depth.
    pub node: Vec<[f64; 3]>,
    /// Top faces split into triangles because the horizon is not planar there.
    pub split_faces: usize,
}

/// Relative distance from a face's plane above which it is split (vtk's
/// own tolerance for planar faces).
const PLANAR: f64 = 1.2e-7;

/// Horizon depths (positive down) at every pillar: horizon h is the top of
/// layer h (h = nz: the bottom of the last layer), averaged over the
/// corners on that pillar.
fn pillar_depths(g: &CornerPointGrid) -> Vec<Vec<f64>> {
    let (nx, ny, nz) = (g.nx, g.ny, g.nz);
    let mut sum = vec![vec![(0.0, 0u32); (nx + 1) * (ny + 1)]; nz + 1];
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                for c in 0..8 {
                    let (di, dj, b) = (c & 1, (c >> 1) & 1, c >> 2);
                    let s = &mut sum[k + b][(j + dj) * (nx + 1) + i + di];
                    s.0 += g.corner(i, j, k, c)[2];
                    s.1 += 1;
                }
            }
        }
    }
    sum.iter()
        .map(|h| h.iter().map(|&(z, n)| z / f64::from(n.max(1))).collect())
        .collect()
}

/// Barycentric weights of x in triangle (a, b, c), or None outside.
fn barycentric(x: [f64; 2], a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> Option<[f64; 3]> {
    let det = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    if det == 0.0 {
        return None;
    }
    let l1 = ((x[0] - a[0]) * (c[1] - a[1]) - (x[1] - a[1]) * (c[0] - a[0])) / det;
    let l2 = ((b[0] - a[0]) * (x[1] - a[1]) - (b[1] - a[1]) * (x[0] - a[0])) / det;
    let l0 = 1.0 - l1 - l2;
    let eps = -1e-9;
    (l0 >= eps && l1 >= eps && l2 >= eps).then_some([l0, l1, l2])
}

/// Maps a hybrid mesh built on `h.report.layer` onto every layer of `g`.
/// Reservoir cells inactive in a layer are left out of it.
pub fn extrude(h: &Hybrid, g: &CornerPointGrid) -> Result<Layered> {
    let m = &h.mesh;
    let (nx, ny, nz) = (g.nx, g.ny, g.nz);
    let view = crate::reservoir::hybrid::map_view(g, h.report.layer);
    let depth = pillar_depths(g);
    // Which pillars are mesh points (same doubles), the others: the column.
    let mut at_pillar: crate::FastMap<[u64; 2], usize> = crate::FastMap::default();
    for (p, xy) in view.iter().enumerate() {
        at_pillar.insert(xy.map(|v| (v + 0.0).to_bits()), p);
    }
    let pid = |i: usize, j: usize| j * (nx + 1) + i;
    let columns: Vec<(usize, usize)> = (0..ny).flat_map(|j| (0..nx).map(move |i| (i, j))).collect();
    // Per mesh point: pillar weights [(pillar, weight)].
    let mut weights: Vec<Vec<(usize, f64)>> = Vec::with_capacity(m.points.len());
    let mut last = 0;
    for x in &m.points {
        if let Some(&p) = at_pillar.get(&x.map(|v| (v + 0.0).to_bits())) {
            weights.push(vec![(p, 1.0)]);
            continue;
        }
        // nearby columns first: points come in runs
        let found = (0..columns.len())
            .map(|k| (last + k) % columns.len())
            .find_map(|k| {
                let (i, j) = columns[k];
                let q = [pid(i, j), pid(i + 1, j), pid(i + 1, j + 1), pid(i, j + 1)];
                let v = q.map(|p| view[p]);
                for (a, b, c) in [(0, 1, 2), (0, 2, 3)] {
                    if let Some(l) = barycentric(*x, v[a], v[b], v[c]) {
                        return Some((k, vec![(q[a], l[0]), (q[b], l[1]), (q[c], l[2])]));
                    }
                }
                None
            });
        let (k, w) = found.ok_or_else(|| {
            Error::Usage(format!("mesh point {x:?} lies in no column of the grid"))
        })?;
        last = k;
        weights.push(w);
    }
    let z_at = |p: usize, hz: usize| -> f64 {
        // z up: minus the depth
        -weights[p]
            .iter()
            .map(|&(q, w)| w * depth[hz][q])
            .sum::<f64>()
    };
    let n = m.points.len();
    let mut out = Layered::default();
    for hz in 0..=nz {
        for (p, x) in m.points.iter().enumerate() {
            out.points.push([x[0], x[1], z_at(p, hz)]);
        }
    }
    let id = |hz: usize, p: u32| (hz * n) as u32 + p;
    for k in 0..nz {
        for (c, cell) in m.cells.iter().enumerate() {
            if let Some([i, j, _]) = h.ijk[c] {
                if !g.active(i, j, k) {
                    continue;
                }
            }
            let top: Vec<u32> = cell.iter().map(|&p| id(k, p)).collect();
            let bottom: Vec<u32> = cell.iter().map(|&p| id(k + 1, p)).collect();
            let mut faces: Vec<Vec<u32>> = vec![];
            for (ring, upward) in [(&top, true), (&bottom, false)] {
                let pts: Vec<[f64; 3]> = ring.iter().map(|&q| out.points[q as usize]).collect();
                if planar(&pts) {
                    let mut f = ring.clone();
                    if !upward {
                        f.reverse();
                    }
                    faces.push(f);
                } else {
                    out.split_faces += usize::from(upward);
                    for t in 1..ring.len() - 1 {
                        faces.push(if upward {
                            vec![ring[0], ring[t], ring[t + 1]]
                        } else {
                            vec![ring[0], ring[t + 1], ring[t]]
                        });
                    }
                }
            }
            for e in 0..cell.len() {
                let f = (e + 1) % cell.len();
                faces.push(vec![top[e], bottom[e], bottom[f], top[f]]);
            }
            let area = m.area(cell);
            let mid = |p: usize, hz: usize| out.points[id(hz, cell[p]) as usize][2];
            let thick = (0..cell.len())
                .map(|p| mid(p, k) - mid(p, k + 1))
                .sum::<f64>()
                / cell.len() as f64;
            let zc = (0..cell.len())
                .map(|p| mid(p, k) + mid(p, k + 1))
                .sum::<f64>()
                / (2 * cell.len()) as f64;
            if thick.is_nan() || thick <= 0.0 {
                // pinched or inverted layer here: no volume to mesh
                continue;
            }
            out.cells.push(faces);
            out.origin.push((c as u32, k));
            out.volume.push(area * thick);
            out.node.push([m.sites[c][0], m.sites[c][1], zc]);
        }
    }
    // Points of left-out cells (inactive, pinched) would be unused points
    // in the output: readers flag those.
    let mut new_id = vec![u32::MAX; out.points.len()];
    let mut points = vec![];
    for q in out.cells.iter_mut().flatten().flatten() {
        let old = *q as usize;
        if new_id[old] == u32::MAX {
            new_id[old] = points.len() as u32;
            points.push(out.points[old]);
        }
        *q = new_id[old];
    }
    out.points = points;
    Ok(out)
}

fn planar(p: &[[f64; 3]]) -> bool {
    // Newell's normal, then the largest distance from the mean plane.
    let mut nrm = [0.0; 3];
    for k in 0..p.len() {
        let (a, b) = (p[k], p[(k + 1) % p.len()]);
        nrm[0] += (a[1] - b[1]) * (a[2] + b[2]);
        nrm[1] += (a[2] - b[2]) * (a[0] + b[0]);
        nrm[2] += (a[0] - b[0]) * (a[1] + b[1]);
    }
    let len = (nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]).sqrt();
    if len == 0.0 {
        return false;
    }
    let c: Vec<f64> = (0..3)
        .map(|d| p.iter().map(|q| q[d]).sum::<f64>() / p.len() as f64)
        .collect();
    let size = p
        .iter()
        .flat_map(|a| {
            p.iter()
                .map(move |b| (0..3).map(|d| (a[d] - b[d]).powi(2)).sum::<f64>())
        })
        .fold(0.0f64, f64::max)
        .sqrt();
    p.iter().all(|q| {
        let d = (0..3).map(|k| (q[k] - c[k]) * nrm[k]).sum::<f64>() / len;
        d.abs() <= PLANAR * size
    })
}

impl Layered {
    /// Polyhedra with cell data site, weight, region, ijk (1-based, -1
    /// outside the grid) and layer (1-based).
    pub fn cells(&self, h: &Hybrid) -> CellMesh {
        let of = |f: &dyn Fn(u32, usize) -> i64| -> Vec<i64> {
            self.origin.iter().map(|&(c, k)| f(c, k)).collect()
        };
        let weights = self.origin.iter().map(|&(c, _)| h.mesh.weights[c as usize]);
        let ijk = self
            .origin
            .iter()
            .map(|&(c, k)| h.ijk[c as usize].map(|[i, j, _]| [i, j, k]));
        CellMesh {
            points: self.points.clone(),
            cells: Cells::Polyhedra(self.cells.clone()),
            data: vec![
                CellArray::float("site", 3, self.node.iter().flatten().copied().collect()),
                CellArray::float("weight", 1, weights.collect()),
                CellArray::int("region", 1, of(&|c, _| h.region[c as usize] as i64)),
                CellArray::ijk(ijk),
                CellArray::int("layer", 1, of(&|_, k| k as i64 + 1)),
            ],
            scalars: "region",
        }
    }

    /// Per cell, the grid cell whose rock it takes (its 2D cell's host
    /// column in its layer), and the grid cell it is if it is one (a
    /// reservoir cell).
    pub fn hosts(&self, h: &Hybrid) -> (Vec<[usize; 3]>, Vec<Option<[usize; 3]>>) {
        (self.origin.iter())
            .map(|&(c, k)| {
                let [i, j, _] = h.host[c as usize];
                ([i, j, k], h.ijk[c as usize].map(|[i, j, _]| [i, j, k]))
            })
            .unzip()
    }

    /// Per cell, the part of the hybrid mesh its 2D cell belongs to.
    pub fn regions(&self, h: &Hybrid) -> Vec<crate::reservoir::hybrid::Region> {
        self.origin
            .iter()
            .map(|&(c, _)| h.region[c as usize])
            .collect()
    }

    /// The elements over the 2D mesh's outer cells (`Hybrid::outer_cells`),
    /// in every layer.
    pub fn outer_cells(&self, h: &Hybrid) -> Vec<usize> {
        let outer: crate::FastSet<u32> = h.outer_cells().into_iter().map(|c| c as u32).collect();
        (0..self.origin.len())
            .filter(|&e| outer.contains(&self.origin[e].0))
            .collect()
    }

    /// Each well's links to its innermost ring in the layers it is
    /// completed in (`completed`: first and last layer, 0-based, by well
    /// name, as COMPDAT gives them; a well not named there is open over the
    /// whole grid), by element (for `reservoir::deck`).
    pub fn well_links(
        &self,
        h: &Hybrid,
        completed: &[(String, [usize; 2])],
    ) -> Vec<crate::reservoir::deck::WellLinks> {
        let m = &h.mesh;
        h.wells
            .iter()
            .map(|w| {
                // Per inner cell, its factor per unit thickness.
                let unit: crate::FastMap<u32, f64> = w.links(|_| 1.0).into_iter().collect();
                let [k1, k2] = completed
                    .iter()
                    .find(|(n, _)| *n == w.name)
                    .map_or([0, usize::MAX], |c| c.1);
                let links = self
                    .origin
                    .iter()
                    .enumerate()
                    .filter_map(|(e, (c, k))| {
                        if !(k1..=k2).contains(k) {
                            return None;
                        }
                        let g = unit.get(c)?;
                        Some((e, g * self.volume[e] / m.area(&m.cells[*c as usize])))
                    })
                    .collect();
                crate::reservoir::deck::WellLinks {
                    name: w.name.clone(),
                    radius: w.radius,
                    links,
                    log: (w.site_radius / w.radius).ln(),
                }
            })
            .collect()
    }

    /// The two-point flux network: lateral connections from the 2D faces
    /// in each layer (area: face length x the mean thickness of the two
    /// cells), vertical ones between a cell and the one below it (area: the
    /// cell's map area).
    pub fn network(&self, h: &Hybrid) -> Network {
        let m = &h.mesh;
        let elements: Vec<Element> = self
            .volume
            .iter()
            .zip(&self.node)
            .map(|(&volume, &node)| Element { volume, node })
            .collect();
        let mut index: crate::FastMap<(u32, usize), usize> = crate::FastMap::default();
        for (e, &o) in self.origin.iter().enumerate() {
            index.insert(o, e);
        }
        let thick = |e: usize| self.volume[e] / m.area(&m.cells[self.origin[e].0 as usize]);
        let mut conns = vec![];
        let lateral = crate::reservoir::flow::connections(m);
        for k in 0..=self.origin.iter().map(|o| o.1).max().unwrap_or(0) {
            for c in &lateral {
                let (Some(&a), Some(&b)) =
                    (index.get(&(c.cells[0], k)), index.get(&(c.cells[1], k)))
                else {
                    continue;
                };
                let area = c.area * (thick(a) + thick(b)) / 2.0;
                conns.push(Connection::lateral(
                    [a, b],
                    self.node[a],
                    self.node[b],
                    c.d,
                    area,
                ));
            }
        }
        for (a, &(c, k)) in self.origin.iter().enumerate() {
            if let Some(&b) = index.get(&(c, k + 1)) {
                conns.push(Connection {
                    elements: [a, b],
                    isot: 3,
                    d: [thick(a) / 2.0, thick(b) / 2.0],
                    area: m.area(&m.cells[c as usize]),
                    cos_gravity: 1.0,
                });
            }
        }
        Network {
            elements,
            connections: conns,
        }
    }
}
