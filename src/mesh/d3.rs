//! The 3D mesh as written: polyhedral cells with their sites, the faces
//! between them, and the faces on the domain's boundary.

use super::{CellArray, CellMesh, Cells, Connection, Element, Network};

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

    /// An element per cell (node at its site), a connection per face
    /// between cells (ISOT by the face normal's main axis; z up).
    pub fn network(&self) -> Network {
        let elements: Vec<Element> = self
            .volumes
            .iter()
            .zip(&self.sites)
            .map(|(&volume, &node)| Element { volume, node })
            .collect();
        let connections: Vec<Connection> = self
            .links
            .iter()
            .map(|l| {
                let axis = (0..3)
                    .max_by(|&a, &b| l.normal[a].abs().total_cmp(&l.normal[b].abs()))
                    .unwrap_or(0);
                let (a, b) = (self.sites[l.cells[0]], self.sites[l.cells[1]]);
                Connection {
                    isot: axis as u8 + 1,
                    ..Connection::lateral(l.cells, a, b, l.d, l.area)
                }
            })
            .collect();
        Network {
            elements,
            connections,
        }
    }
}
