//! The hybrid deck's cells: one per mesh cell in the order of a Hilbert
//! curve, in the input deck's units. Reservoir cells keep what OPM Flow
//! gives them on the original grid (pore volume, depth at the mean of the
//! corners, the transmissibilities between them, across throws too); the
//! transition and well cells take their volume and node from the mesh and
//! their rock from the host cell, their connections the two-point
//! transmissibility of the orthogonal mesh.

use super::super::arrays::{read_arrays, Arrays};
use super::super::eclipse::{length_unit, unit_system};
use crate::error::{Error, Result};
use crate::mesh::Network;
use crate::reservoir::deck::{hilbert_order, WellLinks};
use crate::reservoir::{trans, CornerPointGrid};
use std::collections::{HashMap, HashSet};
use std::fmt::Write;

pub(super) use super::super::deck::{array as write_array, num};
use std::path::Path;

/// The hybrid mesh a deck is carried onto.
pub struct Mesh<'a> {
    /// The original grid.
    pub grid: &'a CornerPointGrid,
    /// The mesh's elements and connections, lengths in the grid's unit,
    /// z up.
    pub network: &'a Network,
    /// Per element, the grid cell whose rock it takes.
    pub host: &'a [[usize; 3]],
    /// Per element, its grid cell if it is one (a reservoir cell).
    pub ijk: &'a [Option<[usize; 3]>],
    /// The radially meshed wells' links to their innermost rings.
    pub wells: &'a [WellLinks],
    /// Per element, which part of the hybrid mesh it belongs to.
    pub region: &'a [crate::reservoir::Region],
    /// Per element, its vertical extent (grid units; `extents`).
    pub extent: &'a [f64],
}

/// Each cell's vertical extent: the span of its points' heights (cells as
/// faces of point ids).
pub fn extents(points: &[[f64; 3]], cells: &[Vec<Vec<u32>>]) -> Vec<f64> {
    cells
        .iter()
        .map(|faces| {
            let z = faces.iter().flatten().map(|&p| points[p as usize][2]);
            let (lo, hi) = z.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), z| {
                (a.min(z), b.max(z))
            });
            hi - lo
        })
        .collect()
}

/// A deck cell.
#[derive(Debug, Clone)]
pub(super) struct Cell {
    /// Its mesh element.
    pub element: usize,
    /// Pore volume (deck units).
    pub porv: f64,
    /// Depth of its centre (deck units).
    pub depth: f64,
    /// Its vertical extent (deck units): the span over which Flow's
    /// equilibration averages its initial saturations.
    pub dz: f64,
    /// Whether Flow keeps it (pore volume above MINPV).
    pub active: bool,
}

/// The deck's cells and connections.
pub(super) struct Table<'a> {
    pub mesh: &'a Mesh<'a>,
    pub cells: Vec<Cell>,
    /// Per element, its deck cell.
    pub position: Vec<usize>,
    /// (deck cells, transmissibility).
    pub nnc: Vec<([usize; 2], f64)>,
    pub arrays: Arrays,
    pub notes: Vec<String>,
    /// Deck length units per grid length unit.
    pub f: f64,
    /// The deck units' Darcy constant.
    pub darcy: f64,
    /// Per element, the grid index of its host.
    host: Vec<usize>,
    /// Per reservoir cell's grid index, its element.
    reservoir: HashMap<usize, usize>,
    /// Per element of a well's innermost ring whose deck cell took in the
    /// rings beyond it (`merge_stiff`), the resistance (1 / T) from its
    /// site out to theirs: its well's factor runs on in series.
    pub outward: HashMap<usize, f64>,
}

impl<'a> Table<'a> {
    pub fn new(path: &Path, mesh: &'a Mesh<'a>) -> Result<Table<'a>> {
        let g = mesh.grid;
        let bad = |message: String| Error::Parse {
            path: path.into(),
            line: 0,
            message,
        };
        let system = unit_system(path)?;
        let (deck_unit, volume) = match system {
            "FIELD" => (0.3048, 1.0 / 5.614583333333333),
            "METRIC" => (1.0, 1.0),
            _ => {
                return Err(bad(format!(
                    "{system} units: the hybrid deck takes FIELD or METRIC"
                )))
            }
        };
        let grid_unit = length_unit(path)?.map_or(deck_unit, |u| u.0);
        let f = grid_unit / deck_unit;
        let darcy = trans::darcy(system == "FIELD");
        let arrays = read_arrays(path, [g.nx, g.ny, g.nz])?;
        let far = arrays.transmissibilities(g, darcy)?;
        let pv_grid = arrays.pore_volumes(g);
        let minpv = arrays.minpv.unwrap_or(1e-6);
        let at = |[i, j, k]: [usize; 3]| g.cell_index(i, j, k);
        let host: Vec<usize> = mesh.host.iter().map(|&h| at(h)).collect();
        let net = mesh.network;
        let order = hilbert_order(net);
        let mut position = vec![0; order.len()];
        for (n, &e) in order.iter().enumerate() {
            position[e] = n;
        }
        let pv3 = volume * f * f * f;
        let cells: Vec<Cell> = order
            .iter()
            .map(|&e| {
                // pore volume, depth (a grid cell's: the mean of its
                // corners') and height
                let (porv, depth, dz) = match mesh.ijk[e] {
                    Some(c) => {
                        let (mean, span) = depths(g, c);
                        (pv_grid[at(c)] * pv3, mean * f, span)
                    }
                    None => {
                        let el = &net.elements[e];
                        let porv = el.volume * pv3 * arrays.pore_fraction(host[e]);
                        (porv, -el.node[2] * f, mesh.extent[e])
                    }
                };
                Cell {
                    element: e,
                    porv,
                    depth,
                    dz: (dz * f).max(1e-3),
                    active: porv > minpv,
                }
            })
            .collect();
        let mut t = Table {
            mesh,
            cells,
            position,
            nnc: vec![],
            notes: vec![],
            f,
            darcy,
            host,
            arrays,
            reservoir: (mesh.ijk.iter().enumerate())
                .filter_map(|(e, c)| c.map(|c| (at(c), e)))
                .collect(),
            outward: HashMap::new(),
        };
        t.connect(&far);
        Ok(t)
    }

    /// Permeability of element e along axis a (x and y times NTG, as Flow
    /// takes them for transmissibilities).
    pub fn perm(&self, e: usize, a: usize) -> f64 {
        let c = self.host[e];
        let v = &self.arrays.values;
        let k = v.get(["PERMX", "PERMY", "PERMZ"][a]).map_or(0.0, |p| p[c]);
        match a < 2 {
            true => k * v.get("NTG").map_or(1.0, |n| n[c]),
            false => k,
        }
    }

    /// The connections: the far field's between reservoir cells, the
    /// mesh's two-point ones elsewhere; none to a cell Flow leaves out.
    fn connect(&mut self, far: &[trans::Transmissibility]) {
        let net = self.mesh.network;
        let alive = |e: usize| self.cells[self.position[e]].active;
        let mut pairs = HashSet::new();
        let mut nnc = vec![];
        for t in far {
            let (Some(&a), Some(&b)) = (
                self.reservoir.get(&t.cells[0]),
                self.reservoir.get(&t.cells[1]),
            ) else {
                continue;
            };
            if t.value > 0.0 && alive(a) && alive(b) {
                pairs.insert((a.min(b), a.max(b)));
                nnc.push(([self.position[a], self.position[b]], t.value));
            }
        }
        let (mut unmatched, mut own) = (0, 0);
        for c in &net.connections {
            let [a, b] = c.elements;
            if c.area == 0.0 || !alive(a) || !alive(b) {
                continue;
            }
            if self.mesh.ijk[a].is_some() && self.mesh.ijk[b].is_some() {
                unmatched += usize::from(!pairs.contains(&(a.min(b), a.max(b))));
                continue;
            }
            let axis = usize::from(c.isot.clamp(1, 3)) - 1;
            let (ka, kb) = (self.perm(a, axis), self.perm(b, axis));
            let value = self.darcy * self.f * c.area / (c.d[0] / ka + c.d[1] / kb);
            if value > 0.0 {
                own += 1;
                nnc.push(([self.position[a], self.position[b]], value));
            }
        }
        self.notes.push(format!(
            "{} connections between reservoir cells as Flow computes them on the original grid; \
             {own} of the orthogonal mesh touching the transition or the wells (their \
             transmissibilities two-point, rock from the host cells, face multipliers not applied)",
            nnc.len() - own
        ));
        if unmatched > 0 {
            self.notes.push(format!(
                "{unmatched} faces between reservoir cells that Flow does not connect left out"
            ));
        }
        let dead = self.cells.iter().filter(|c| !c.active).count();
        if dead > 0 {
            self.notes.push(format!(
                "{dead} cells with a pore volume at or below MINPV inactive, as Flow makes them"
            ));
        }
        self.nnc = nnc;
    }

    /// The grid index of deck cell c's host.
    pub fn host_of(&self, c: usize) -> usize {
        self.host[self.cells[c].element]
    }

    /// Whether a keyword is a per-cell array the deck sets.
    pub fn is_array(&self, name: &str) -> bool {
        self.arrays.values.contains_key(name)
    }

    /// A per-cell array through the host cells, in deck order.
    pub fn array(&self, s: &mut String, name: &str) -> Result<()> {
        let Some(v) = self.arrays.values.get(name) else {
            return Ok(()); // an operation on an array that is not per cell
        };
        write_array(s, name, self.cells.iter().map(|c| v[self.host[c.element]]));
        Ok(())
    }

    /// A per-cell array of a section: SOLUTION's by depth (`state`), the
    /// others the host's.
    pub fn section_array(&self, s: &mut String, section: &str, name: &str) -> Result<()> {
        match section {
            "SOLUTION" => self.state(s, name),
            _ => self.array(s, name),
        }
    }

    /// SOLUTION's explicit initial state: a cell of the cavities takes its
    /// host's value moved along the host's column to its own depth (linear
    /// between the centres of the host and the live cell above or below).
    /// A state in equilibrium (pressure linear in depth within a phase)
    /// stays in it: SPE9's host values are up to 10.6 psi off their cells'
    /// depths, and Flow failed a third more Newton iterations re-balancing.
    pub fn state(&self, s: &mut String, name: &str) -> Result<()> {
        let Some(v) = self.arrays.values.get(name) else {
            return Ok(());
        };
        let g = self.mesh.grid;
        let depth = |c: [usize; 3]| depths(g, c).0 * self.f;
        let live = |c: [usize; 3]| {
            g.active(c[0], c[1], c[2]) && v[g.cell_index(c[0], c[1], c[2])].is_finite()
        };
        let value = |c: &Cell| {
            let e = c.element;
            let h = self.mesh.host[e];
            let vh = v[self.host[e]];
            if self.mesh.ijk[e].is_some() {
                return vh;
            }
            let dh = depth(h);
            let [i, j, k] = h;
            // the column's next cell towards the cell's depth
            let next = match c.depth > dh {
                true => (k + 1 < g.nz).then(|| [i, j, k + 1]),
                false => k.checked_sub(1).map(|k| [i, j, k]),
            };
            match next.filter(|&n| live(n)) {
                Some(n) => {
                    let dn = depth(n);
                    let t = ((c.depth - dh) / (dn - dh)).clamp(0.0, 1.0);
                    match t.is_finite() {
                        true => vh + t * (v[g.cell_index(n[0], n[1], n[2])] - vh),
                        false => vh,
                    }
                }
                None => vh,
            }
        };
        write_array(s, name, self.cells.iter().map(value));
        Ok(())
    }

    /// GRID: the dummy cells, their rock for reference, the connections.
    pub fn grid(&self, s: &mut String) {
        let n = self.cells.len();
        for key in ["DX", "DY"] {
            let _ = write!(s, "{key}\n {n}*1 /\n\n");
        }
        // centred on its depth, as tall as the cell (the span equilibration
        // averages over); a cell's top and bottom play no other role
        write_array(s, "DZ", self.cells.iter().map(|c| c.dz));
        write_array(s, "TOPS", self.cells.iter().map(|c| c.depth - 0.5 * c.dz));
        if self.cells.iter().any(|c| !c.active) {
            write_array(
                s,
                "ACTNUM",
                self.cells.iter().map(|c| f64::from(u8::from(c.active))),
            );
        }
        for key in ["PERMX", "PERMY", "PERMZ", "PORO", "NTG"] {
            let _ = self.array(s, key);
        }
        s.push_str("NNC\n");
        for &([a, b], t) in &self.nnc {
            let _ = writeln!(s, " {} 1 1 {} 1 1 {} /", a + 1, b + 1, num(t));
        }
        s.push_str("/\n\n");
    }

    /// EDIT: the pore volumes, the dummy grid's own connections zeroed.
    pub fn edit(&self, s: &mut String) {
        s.push_str("EDIT\n\n");
        write_array(s, "PORV", self.cells.iter().map(|c| c.porv));
        s.push_str("MULTIPLY\n 'TRANX' 0 /\n 'TRANY' 0 /\n 'TRANZ' 0 /\n/\n\n");
    }

    /// The deck cell that is grid cell c unchanged (a reservoir cell), if
    /// any.
    pub fn unchanged(&self, [i, j, k]: [usize; 3]) -> Option<usize> {
        let e = self.reservoir.get(&self.mesh.grid.cell_index(i, j, k))?;
        Some(self.position[*e])
    }

    /// Whether some cell of the mesh takes its rock from grid cell c.
    pub fn hosts(&self, c: [usize; 3]) -> bool {
        let [i, j, k] = c;
        let c = self.mesh.grid.cell_index(i, j, k);
        self.host.contains(&c)
    }

    /// The deck cell that holds grid cell c's centre: its own where it is
    /// a reservoir cell, else the cell hosted there whose node is nearest
    /// the centre (any cell's where none is hosted there).
    pub fn block(&self, [i, j, k]: [usize; 3]) -> Option<usize> {
        let g = self.mesh.grid;
        let c = g.cell_index(i, j, k);
        let net = self.mesh.network;
        let centre: [f64; 3] = {
            let p: Vec<[f64; 3]> = (0..8).map(|n| g.corner(i, j, k, n)).collect();
            std::array::from_fn(|a| p.iter().map(|q| q[a]).sum::<f64>() / 8.0)
        };
        let d2 = |e: usize| {
            let n = net.elements[e].node;
            let q = [n[0], n[1], -n[2]];
            (0..3).map(|a| (q[a] - centre[a]).powi(2)).sum::<f64>()
        };
        // where no cell takes its rock from the block (a 2.5D column
        // covered by its neighbours' transition cells), the nearest node
        let hosted = (0..net.elements.len()).any(|e| self.host[e] == c);
        (0..net.elements.len())
            .filter(|&e| self.host[e] == c || !hosted)
            .min_by(|&a, &b| {
                let own = |e: usize| self.mesh.ijk[e].is_none();
                own(a).cmp(&own(b)).then(d2(a).total_cmp(&d2(b)))
            })
            .map(|e| self.position[e])
    }
}

/// A grid cell's depth (the mean of its corners', as Flow takes it) and the
/// span of its corners' depths, in grid units.
fn depths(g: &CornerPointGrid, [i, j, k]: [usize; 3]) -> (f64, f64) {
    let z: [f64; 8] = std::array::from_fn(|n| g.depth(i, j, k, n));
    let (lo, hi) = z
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &z| {
            (a.min(z), b.max(z))
        });
    (z.iter().sum::<f64>() / 8.0, hi - lo)
}
