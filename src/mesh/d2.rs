//! The mesh as written: the domain cells of the diagram with their vertices
//! in doubles (input vertices exactly, the others rounded). Nearly symmetric input gives exactly non-zero edges of length
//! ~1e-17; readers merge such points, so vertices closer than `COLLAPSE`
//! times the mesh size are merged here (never two input vertices) and counted.

use super::{CellArray, CellMesh, Cells, Values};
use crate::backend::Triangulation;
use crate::diagram::Diagram;
use crate::error::{Error, Result};
use crate::geom::shoelace;
use crate::sites::Sites;
use crate::FastMap;
use nalgebra::Vector2;
use rayon::prelude::*;

/// Edges shorter than this fraction of the mesh size are collapsed.
pub const COLLAPSE: f64 = 1e-14;

/// Points with those closer than COLLAPSE x their extent merged (an input
/// vertex keeps its exact position; two input vertices never merge).
pub struct Collapsed<const D: usize> {
    pub points: Vec<[f64; D]>,
    pub fixed: Vec<bool>,
    /// Per given point, its merged point.
    pub map: Vec<u32>,
    pub collapsed: usize,
    /// The points' extent (largest side of their box).
    pub size: f64,
}

impl<const D: usize> Collapsed<D> {
    pub fn of(pts: &[[f64; D]], fixed: &[bool]) -> Collapsed<D> {
        let (mut lo, mut hi) = ([f64::INFINITY; D], [f64::NEG_INFINITY; D]);
        for p in pts {
            for k in 0..D {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let size = (0..D).map(|k| hi[k] - lo[k]).fold(0.0, f64::max);
        let tol = COLLAPSE * size;
        // Grid of cell size tol: close points are in neighbouring buckets.
        let key = |p: [f64; D]| -> [i64; D] {
            std::array::from_fn(|k| ((p[k] - lo[k]) / tol).floor() as i64)
        };
        let offsets: Vec<[i64; D]> = (0..3usize.pow(D as u32))
            .map(|mut c| {
                std::array::from_fn(|_| {
                    let d = (c % 3) as i64 - 1;
                    c /= 3;
                    d
                })
            })
            .collect();
        let mut out = Collapsed {
            points: vec![],
            fixed: vec![],
            map: Vec::with_capacity(pts.len()),
            collapsed: 0,
            size,
        };
        // Per grid cell the last point put there, chained to the previous ones.
        let mut grid: FastMap<[i64; D], u32> = FastMap::default();
        grid.reserve(pts.len());
        let mut chain: Vec<u32> = Vec::with_capacity(pts.len());
        for (&p, &is_fixed) in pts.iter().zip(fixed) {
            let g = key(p);
            let mut target = None;
            'search: for o in &offsets {
                let cell: [i64; D] = std::array::from_fn(|k| g[k] + o[k]);
                let mut id = grid.get(&cell).copied().unwrap_or(u32::MAX);
                while id != u32::MAX {
                    let q = out.points[id as usize];
                    let d2: f64 = (0..D).map(|k| (q[k] - p[k]).powi(2)).sum();
                    if d2.sqrt() <= tol && !(is_fixed && out.fixed[id as usize]) {
                        target = Some(id);
                        break 'search;
                    }
                    id = chain[id as usize];
                }
            }
            let id = match target {
                Some(id) => {
                    out.collapsed += 1;
                    if is_fixed {
                        out.points[id as usize] = p;
                        out.fixed[id as usize] = true;
                    }
                    id
                }
                None => {
                    let id = out.points.len() as u32;
                    out.points.push(p);
                    out.fixed.push(is_fixed);
                    chain.push(grid.insert(g, id).unwrap_or(u32::MAX));
                    id
                }
            };
            out.map.push(id);
        }
        out
    }
}
/// Edges shorter than this fraction are too short to measure a direction.
const MEASURE: f64 = 1e-7;

/// A polygonal mesh with one site and weight per cell.
#[derive(Debug, Clone, Default)]
pub struct Mesh {
    /// The vertices.
    pub points: Vec<[f64; 2]>,
    /// Counter-clockwise polygons.
    pub cells: Vec<Vec<u32>>,
    /// Interior faces [a, b, left cell, right cell]: the cell on the left
    /// of a -> b and the one on its right.
    pub faces: Vec<[u32; 4]>,
    /// Per cell, its site.
    pub sites: Vec<[f64; 2]>,
    /// Per cell, its weight.
    pub weights: Vec<f64>,
    /// Exact vertices merged into a neighbour closer than COLLAPSE x size.
    pub collapsed: usize,
    /// Whether each point is an input vertex.
    pub fixed: Vec<bool>,
    /// Largest extent of the mesh.
    pub size: f64,
}

impl Mesh {
    /// The domain cells of a diagram; input vertices are never merged with
    /// each other.
    pub fn from_diagram(diagram: &Diagram, sites: &Sites, rt: &Triangulation) -> Result<Mesh> {
        let mut m = Mesh::default();
        // Exact vertex -> rounded point, for the vertices of domain cells.
        let used: Vec<u32> = {
            let mut mark = vec![false; diagram.points.len()];
            for s in (0..diagram.cells.len()).filter(|&s| diagram.in_domain[s]) {
                for &v in diagram.cells[s].as_deref().unwrap_or(&[]) {
                    mark[v as usize] = true;
                }
            }
            (0..mark.len() as u32)
                .filter(|&v| mark[v as usize])
                .collect()
        };
        let pts: Vec<[f64; 2]> = used.iter().map(|&v| diagram.points[v as usize]).collect();
        let fixed: Vec<bool> = used
            .iter()
            .map(|&v| diagram.input_vertex[v as usize].is_some())
            .collect();
        let merged = Collapsed::of(&pts, &fixed);
        let mut map = vec![u32::MAX; diagram.points.len()];
        for (k, &v) in used.iter().enumerate() {
            map[v as usize] = merged.map[k];
        }
        m.points = merged.points;
        m.fixed = merged.fixed;
        m.collapsed = merged.collapsed;
        m.size = merged.size;
        // Cells in parallel; the first (by site) that fails in doubles is named.
        let cells: Vec<Result<Vec<u32>>> = (0..diagram.cells.len())
            .into_par_iter()
            .filter(|&s| diagram.in_domain[s])
            .map(|s| {
                let cell = diagram.cells[s].as_ref().expect("domain cells are bounded");
                let mut poly: Vec<u32> = cell.iter().map(|&v| map[v as usize]).collect();
                poly.dedup();
                if poly.len() > 1 && poly.first() == poly.last() {
                    poly.pop();
                }
                if poly.len() < 3 {
                    return Err(Error::Certificate(format!(
                        "the cell of site {s} collapses below three vertices when written in double precision"
                    )));
                }
                if m.area(&poly) <= 0.0 {
                    return Err(Error::Certificate(format!(
                        "the cell of site {s} turns over when written in double precision"
                    )));
                }
                Ok(poly)
            })
            .collect();
        m.cells = cells.into_iter().collect::<Result<_>>()?;
        for s in (0..diagram.cells.len()).filter(|&s| diagram.in_domain[s]) {
            let [x, y, w] = sites.approx(s);
            m.sites.push([x, y]);
            m.weights.push(w);
        }
        // Faces from the edges of the site triangulation: the cell of a is
        // on the left of the dual edge from the vertex of the triangle
        // across to the vertex of the triangle on the left of a -> b.
        let mut cell_of = vec![u32::MAX; diagram.cells.len()];
        for (c, s) in (0..diagram.cells.len())
            .filter(|&s| diagram.in_domain[s])
            .enumerate()
        {
            cell_of[s] = c as u32;
        }
        m.faces = rt
            .par_edge_triangles()
            .filter_map(|(a, b, t, u)| {
                let (ca, cb) = (cell_of[a as usize], cell_of[b as usize]);
                let u = u.filter(|_| ca != u32::MAX && cb != u32::MAX)?;
                let (from, to) = (
                    map[diagram.vertex_of[u as usize] as usize],
                    map[diagram.vertex_of[t as usize] as usize],
                );
                (from != to).then_some([from, to, ca, cb])
            })
            .collect();
        Ok(m)
    }

    /// The cells whose closed polygon holds p, decided exactly (cells
    /// are convex and counter-clockwise): one inside a cell, two or more on
    /// a face or vertex, none outside the mesh.
    pub fn locate(&self, p: [f64; 2]) -> Vec<usize> {
        use std::cmp::Ordering::Less;
        (0..self.cells.len())
            .filter(|&c| {
                let cell = &self.cells[c];
                (0..cell.len()).all(|k| {
                    let a = self.points[cell[k] as usize];
                    let b = self.points[cell[(k + 1) % cell.len()] as usize];
                    crate::geom::orient(a, b, p) != Less
                })
            })
            .collect()
    }

    /// Signed area of a cell.
    pub fn area(&self, cell: &[u32]) -> f64 {
        shoelace(cell.len(), |k| self.points[cell[k] as usize])
    }

    /// Largest |cos| between an interior face and the line joining the two
    /// sites beside it (0 for an orthogonal mesh).
    pub fn orthogonality_defect(&self) -> f64 {
        self.faces
            .par_iter()
            .map(|&f| self.face_defect(f))
            .reduce(|| 0.0, f64::max)
    }

    /// |cos| between face a -> b and the segment from site c to site d (0
    /// when too short to measure).
    pub fn face_defect(&self, [a, b, c, d]: [u32; 4]) -> f64 {
        let v = |p: [f64; 2]| Vector2::from(p);
        let e = v(self.points[b as usize]) - v(self.points[a as usize]);
        let s = v(self.sites[d as usize]) - v(self.sites[c as usize]);
        if e.norm() > MEASURE * self.size && s.norm() > 0.0 {
            (e.dot(&s) / (e.norm() * s.norm())).abs()
        } else {
            0.0
        }
    }

    /// Directed cell edge (a, b) -> the cell it bounds (on its left).
    pub(crate) fn edge_owners(&self) -> FastMap<(u32, u32), u32> {
        self.edge_owners_from(0)
    }

    /// `edge_owners` of the cells from `first` on.
    pub(crate) fn edge_owners_from(&self, first: usize) -> FastMap<(u32, u32), u32> {
        let mut owner = FastMap::default();
        for (c, cell) in self.cells.iter().enumerate().skip(first) {
            for e in 0..cell.len() {
                owner.insert((cell[e], cell[(e + 1) % cell.len()]), c as u32);
            }
        }
        owner
    }

    /// Finds the faces by matching each cell edge with its reverse in
    /// another cell; returns how many edges have no twin and are not in
    /// `boundary` (hanging nodes, overlaps: 0 for a conforming mesh).
    pub(crate) fn match_faces(&mut self, boundary: &crate::FastSet<(u32, u32)>) -> usize {
        let owner = self.edge_owners();
        self.faces.clear();
        let mut unmatched = 0;
        for (&(a, b), &c) in &owner {
            match owner.get(&(b, a)) {
                Some(&d) if a < b => self.faces.push([a, b, c, d]),
                Some(_) => {}
                None => unmatched += usize::from(!boundary.contains(&(a, b))),
            }
        }
        self.faces.sort_unstable();
        unmatched
    }
}

impl Mesh {
    /// Polygons with cell data site, weight and site_inside (0/1).
    pub fn cells(&self, site_inside: &[bool]) -> CellMesh {
        let inside = site_inside.iter().map(|&b| i64::from(b)).collect();
        self.cells_with(vec![CellArray::int("site_inside", 1, inside)])
    }

    /// Polygons with cell data site, weight and the given arrays.
    pub fn cells_with(&self, arrays: Vec<CellArray>) -> CellMesh {
        let mut data = vec![
            CellArray::float("site", 3, vec![]),
            CellArray {
                name: "weight",
                components: None,
                values: Values::Float(self.weights.clone()),
            },
        ];
        data[0].values = Values::Planar(self.sites.clone());
        data.extend(arrays);
        CellMesh {
            points: self.points.iter().map(|p| [p[0], p[1], 0.0]).collect(),
            cells: Cells::Polygons(self.cells.clone()),
            data,
            scalars: "weight",
        }
    }
}
