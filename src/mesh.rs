//! The mesh as written: the domain cells of the exact diagram rounded to
//! doubles. Distinct exact vertices that round to the same double point
//! (edges of length ~1e-17 on nearly symmetric input) are merged and counted.

use crate::diagram::Diagram;
use crate::error::{Error, Result};
use crate::exact::{f, fp};
use crate::sites::Sites;
use std::collections::HashMap;

/// A polygonal mesh with one site and weight per cell.
#[derive(Debug, Clone, Default)]
pub struct Mesh {
    pub points: Vec<[f64; 2]>,
    /// Counter-clockwise polygons.
    pub cells: Vec<Vec<u32>>,
    pub sites: Vec<[f64; 2]>,
    pub weights: Vec<f64>,
    /// Exact vertices merged because they round to the same double point.
    pub collapsed: usize,
}

impl Mesh {
    /// Rounds the domain cells of a diagram.
    pub fn from_diagram(diagram: &Diagram, sites: &Sites) -> Result<Mesh> {
        let mut m = Mesh::default();
        let mut index: HashMap<[u64; 2], u32> = HashMap::new();
        let mut map: HashMap<u32, u32> = HashMap::new();
        for (s, cell) in diagram.cells.iter().enumerate() {
            if !diagram.in_domain[s] {
                continue;
            }
            let cell = cell.as_ref().expect("domain cells are bounded");
            let mut poly: Vec<u32> = cell
                .iter()
                .map(|&v| {
                    *map.entry(v).or_insert_with(|| {
                        let p = fp(&diagram.points[v as usize]);
                        let key = [(p[0] + 0.0).to_bits(), (p[1] + 0.0).to_bits()];
                        match index.get(&key) {
                            Some(&id) => {
                                m.collapsed += 1;
                                id
                            }
                            None => {
                                m.points.push(p);
                                index.insert(key, m.points.len() as u32 - 1);
                                m.points.len() as u32 - 1
                            }
                        }
                    })
                })
                .collect();
            poly.dedup();
            if poly.len() > 1 && poly.first() == poly.last() {
                poly.pop();
            }
            if poly.len() < 3 {
                return Err(Error::Certificate(format!(
                    "the cell of site {s} collapses below three vertices when written in double precision"
                )));
            }
            m.cells.push(poly);
            m.sites.push(fp(&sites.pos[s]));
            m.weights.push(f(&sites.weight[s]));
        }
        Ok(m)
    }

    /// Signed area of a cell (shoelace).
    pub fn area(&self, cell: &[u32]) -> f64 {
        let k = cell.len();
        (0..k)
            .map(|e| {
                let a = self.points[cell[e] as usize];
                let b = self.points[cell[(e + 1) % k] as usize];
                a[0] * b[1] - a[1] * b[0]
            })
            .sum::<f64>()
            / 2.0
    }

    /// Largest |cos| between an interior face and the line joining the two
    /// sites beside it (0 for an orthogonal mesh).
    pub fn orthogonality_defect(&self) -> f64 {
        let mut owner: HashMap<(u32, u32), usize> = HashMap::new();
        for (c, cell) in self.cells.iter().enumerate() {
            for e in 0..cell.len() {
                owner.insert((cell[e], cell[(e + 1) % cell.len()]), c);
            }
        }
        let mut worst: f64 = 0.0;
        for (&(a, b), &c) in &owner {
            let Some(&d) = owner.get(&(b, a)) else { continue };
            let (pa, pb) = (self.points[a as usize], self.points[b as usize]);
            let (sc, sd) = (self.sites[c], self.sites[d]);
            let e = [pb[0] - pa[0], pb[1] - pa[1]];
            let s = [sd[0] - sc[0], sd[1] - sc[1]];
            let ne = e[0].hypot(e[1]);
            let ns = s[0].hypot(s[1]);
            if ne > 0.0 && ns > 0.0 {
                worst = worst.max(((e[0] * s[0] + e[1] * s[1]) / (ne * ns)).abs());
            }
        }
        worst
    }
}
