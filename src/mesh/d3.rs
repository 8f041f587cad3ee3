//! The 3D mesh as written: polyhedral cells with their sites, the faces
//! between them, and the faces on the domain's boundary.

use super::{CellArray, CellMesh, Cells, Connection, Element, Network};
use crate::geom::{cross_f, dot_f};

fn sub_f(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|i| a[i] - b[i])
}

/// A polyhedral mesh: the domain's cells.
#[derive(Debug, Clone, Default)]
pub struct Mesh3 {
    /// The vertices.
    pub points: Vec<[f64; 3]>,
    /// Per cell, its faces as point ids counter-clockwise seen from outside.
    pub cells: Vec<Vec<Vec<u32>>>,
    /// Per cell: its site (rounded), weight (rounded), volume, and whether
    /// the site lies strictly inside (exact).
    pub sites: Vec<[f64; 3]>,
    /// Per cell, its weight.
    pub weights: Vec<f64>,
    /// Per cell, its volume.
    pub volumes: Vec<f64>,
    /// Per cell, whether its site is strictly inside (exact).
    pub site_inside: Vec<bool>,
    /// Faces between two cells, once each.
    pub links: Vec<Link3>,
    /// Power vertices merged into a neighbour closer than the output
    /// precision (`mesh::COLLAPSE`).
    pub collapsed: usize,
    /// Faces of the complex on the domain's boundary, with their cell.
    pub facet_faces: Vec<FacetFace>,
}

/// A triangle or whole polygon of the complex with a domain cell on one
/// side only: where the mesh meets what lies beyond (another mesh, a
/// boundary condition).
#[derive(Debug, Clone)]
pub struct FacetFace {
    /// Its facet (index into `Complex3::facets`).
    pub facet: u32,
    /// Its points (mesh ids), in the complex's order.
    pub points: Vec<u32>,
    /// Its cell.
    pub cell: usize,
    /// Its area.
    pub area: f64,
    /// Distance from the cell's site to the face's plane.
    pub d: f64,
}

/// A face between two cells: its area and the distances from each site to
/// its plane (two-point flux: transmissibility ~ area / (d0 + d1)).
#[derive(Debug, Clone)]
pub struct Link3 {
    /// The two cells.
    pub cells: [usize; 2],
    /// The face's points.
    pub face: Vec<u32>,
    /// Its area.
    pub area: f64,
    /// Distances from each site to the face's plane.
    pub d: [f64; 2],
    /// Unit normal from cell 0 to cell 1.
    pub normal: [f64; 3],
}

impl Mesh3 {
    /// Largest |cos| between a face's in-plane directions and the segment
    /// joining its two sites.
    pub fn orthogonality_defect(&self) -> f64 {
        self.links
            .iter()
            .map(|l| self.link_defect(l))
            .fold(0.0, f64::max)
    }

    /// Largest |cos| between this link's face's in-plane directions and
    /// the segment joining its two sites (0 for a link without a face).
    pub fn link_defect(&self, l: &Link3) -> f64 {
        let (a, b) = (self.sites[l.cells[0]], self.sites[l.cells[1]]);
        let d: [f64; 3] = std::array::from_fn(|k| b[k] - a[k]);
        let dot = |u: [f64; 3], w: [f64; 3]| u[0] * w[0] + u[1] * w[1] + u[2] * w[2];
        let Some((first, rest)) = l.face.split_first() else {
            return 0.0;
        };
        let p0 = self.points[*first as usize];
        rest.iter()
            .map(|&v| {
                let p = self.points[v as usize];
                let e: [f64; 3] = std::array::from_fn(|k| p[k] - p0[k]);
                dot(e, d).abs() / (dot(e, e) * dot(d, d)).sqrt()
            })
            .filter(|c| c.is_finite())
            .fold(0.0, f64::max)
    }

    /// Polyhedra with cell data site, weight, volume, site_inside.
    pub fn cells(&self) -> CellMesh {
        CellMesh {
            points: self.points.clone(),
            cells: Cells::Polyhedra(self.cells.clone()),
            data: vec![
                CellArray::float("site", 3, self.sites.iter().flatten().copied().collect()),
                CellArray::float("weight", 1, self.weights.clone()),
                CellArray::float("volume", 1, self.volumes.clone()),
                CellArray::int(
                    "site_inside",
                    1,
                    self.site_inside.iter().map(|&b| i64::from(b)).collect(),
                ),
            ],
            scalars: "weight",
        }
    }

    /// The cell's centroid (its volume's, from a fan of tetrahedra).
    pub fn centroid(&self, c: usize) -> [f64; 3] {
        let faces = &self.cells[c];
        let p = |v: u32| self.points[v as usize];
        let Some(&o) = faces.first().and_then(|f| f.first()) else {
            return self.sites[c];
        };
        let o = p(o);
        let (mut sum, mut vol) = ([0.0; 3], 0.0);
        for f in faces {
            for k in 1..f.len().saturating_sub(1) {
                let [a, b, d] = [p(f[0]), p(f[k]), p(f[k + 1])].map(|x| sub_f(x, o));
                let v = dot_f(a, cross_f(b, d)) / 6.0;
                vol += v;
                for i in 0..3 {
                    sum[i] += v * (a[i] + b[i] + d[i]) / 4.0;
                }
            }
        }
        match vol > 0.0 {
            true => std::array::from_fn(|i| o[i] + sum[i] / vol),
            false => self.sites[c],
        }
    }

    /// An element per cell, a connection per face between cells (ISOT by
    /// the face normal's main axis; z up). The node is the site, or where
    /// the site lies outside its cell, the cell's centroid, with its
    /// distances to its faces' planes: a site beyond its face would give
    /// two-point flux a distance with no meaning there.
    pub fn network(&self) -> Network {
        let nodes: Vec<[f64; 3]> = (0..self.cells.len())
            .map(|c| match self.site_inside[c] {
                true => self.sites[c],
                false => self.centroid(c),
            })
            .collect();
        let elements: Vec<Element> = self
            .volumes
            .iter()
            .zip(&nodes)
            .map(|(&volume, &node)| Element { volume, node })
            .collect();
        let connections: Vec<Connection> = self
            .links
            .iter()
            .map(|l| {
                let axis = (0..3)
                    .max_by(|&a, &b| l.normal[a].abs().total_cmp(&l.normal[b].abs()))
                    .unwrap_or(0);
                let (a, b) = (nodes[l.cells[0]], nodes[l.cells[1]]);
                let d = std::array::from_fn(|k| match self.site_inside[l.cells[k]] {
                    true => l.d[k],
                    false => l.face.first().map_or(l.d[k], |&v| {
                        let q = sub_f(nodes[l.cells[k]], self.points[v as usize]);
                        dot_f(q, l.normal).abs()
                    }),
                });
                Connection {
                    isot: axis as u8 + 1,
                    ..Connection::lateral(l.cells, a, b, d, l.area)
                }
            })
            .collect();
        Network {
            elements,
            connections,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two unit cubes side by side along x, linked across x = 1.
    fn two_cubes(sites: [[f64; 3]; 2], inside: [bool; 2]) -> Mesh3 {
        let points: Vec<[f64; 3]> = (0..12)
            .map(|n| [(n % 3) as f64, ((n / 3) % 2) as f64, (n / 6) as f64])
            .collect();
        // point (x, y, z) is x + 3 y + 6 z
        let id = |x: u32, y: u32, z: u32| x + 3 * y + 6 * z;
        let cube = |x: u32| {
            vec![
                vec![id(x, 0, 0), id(x, 1, 0), id(x + 1, 1, 0), id(x + 1, 0, 0)],
                vec![id(x, 0, 1), id(x + 1, 0, 1), id(x + 1, 1, 1), id(x, 1, 1)],
                vec![id(x, 0, 0), id(x + 1, 0, 0), id(x + 1, 0, 1), id(x, 0, 1)],
                vec![id(x, 1, 0), id(x, 1, 1), id(x + 1, 1, 1), id(x + 1, 1, 0)],
                vec![id(x, 0, 0), id(x, 0, 1), id(x, 1, 1), id(x, 1, 0)],
                vec![
                    id(x + 1, 0, 0),
                    id(x + 1, 1, 0),
                    id(x + 1, 1, 1),
                    id(x + 1, 0, 1),
                ],
            ]
        };
        let d = |s: [f64; 3]| (s[0] - 1.0).abs();
        Mesh3 {
            points,
            cells: vec![cube(0), cube(1)],
            sites: sites.to_vec(),
            weights: vec![0.0; 2],
            volumes: vec![1.0; 2],
            site_inside: inside.to_vec(),
            links: vec![Link3 {
                cells: [0, 1],
                face: vec![id(1, 0, 0), id(1, 1, 0), id(1, 1, 1), id(1, 0, 1)],
                area: 1.0,
                d: [d(sites[0]), d(sites[1])],
                normal: [1.0, 0.0, 0.0],
            }],
            ..Default::default()
        }
    }

    #[test]
    fn a_site_outside_its_cell_gives_way_to_its_centroid() {
        let m = two_cubes([[0.25, 0.5, 0.5], [1.5, 0.5, 0.5]], [true, true]);
        let net = m.network();
        assert_eq!(net.connections[0].d, [0.75, 0.5]);
        // cell 0's site beyond the shared face (in cell 1): its centroid
        // (0.5, 0.5, 0.5) is the node, half a unit from the face
        let near = |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-12);
        let m = two_cubes([[1.2, 0.5, 0.5], [1.5, 0.5, 0.5]], [false, true]);
        assert!(near(&m.centroid(0), &[0.5; 3]));
        let net = m.network();
        assert!(near(&net.elements[0].node, &[0.5; 3]));
        assert!(near(&net.connections[0].d, &[0.5, 0.5]));
    }
}
