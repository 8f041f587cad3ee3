//! On request (`hybrid --merge-stiff SHARE`), deck cells of the cavities
//! whose connections are far stiffer than any of the original grid's are
//! merged into one deck cell. Such a cell (two
//! transition sites close together across a long face; an innermost
//! ring's sector, linked to its neighbours across the whole ring's width)
//! holds its neighbours' pressure in the flow's sense, but its
//! transmissibilities over its pore volume reached 580 times the stiffest
//! grid cell's on SPE9, and where gas came out of solution Flow's Newton
//! iterations oscillated there and cut its steps. The mesh keeps its cells
//! (the VTU's deck_cell maps them). Reservoir cells never merge; a radial
//! cell merges only with its own ring's in its layer, into an annulus
//! whose pressure stays on its sites' circle so that the ring's exact
//! links hold (merged with transition cells, a ring's pressure leaves its
//! circle: +7% oil on a small deck, +20% injected water on SPE9). An
//! innermost annulus still too stiff takes in the next ring, whose circle
//! it then stands for, the wells' factors running on to it in series
//! (exact for radial flow): on SPE9, 21 such annuli alone made Flow cut
//! five steps. Transition cells merge with transition cells; cells of
//! different regions (any *NUM array) never merge.

use super::cells::{Cell, Table};
use crate::reservoir::Region;
use std::collections::{BTreeMap, HashMap, HashSet};

/// A radial mesh's ring: well, layer, rings out from the innermost.
type Ring = (usize, usize, usize);

/// The share `hybrid --merge-stiff` suggests. Measured on SPE9 with the
/// simulator-sized radial meshes of docs/simulators.md (oil, gas, injected
/// water against the original; Flow's time against the original's): no
/// merge +0.30%, +0.07%, -3.65%, 10x; 0.25 +0.29%, -1.86%, +1.01%, 2.0x.
/// On a 7 x 7 x 2 block with 6 rings in a
/// column (the regions deck of tests/carry.rs), whose transition cells are
/// all far stiffer than its grid cells, 1 merges half the cells and moves
/// field oil by 3%: not a default.
pub const SUGGESTED: f64 = 0.25;

fn root(parent: &mut [usize], mut a: usize) -> usize {
    while parent[a] != a {
        parent[a] = parent[parent[a]];
        a = parent[a];
    }
    a
}

impl Table<'_> {
    /// The stiffest reservoir cell's transmissibilities over its pore
    /// volume (to other reservoir cells, as Flow sees the original grid).
    fn stiffest(&self, reservoir: &[bool]) -> f64 {
        let mut sum = vec![0.0; self.cells.len()];
        for &([a, b], t) in &self.nnc {
            if reservoir[a] && reservoir[b] {
                sum[a] += t;
                sum[b] += t;
            }
        }
        (0..sum.len())
            .filter(|&c| reservoir[c] && self.cells[c].active)
            .map(|c| sum[c] / self.cells[c].porv)
            .fold(0.0, f64::max)
    }

    /// Merges the stiff cavity cells, round by round, each with its
    /// stiffest partner (the stiffest cells first), until no cell's
    /// transmissibilities over its pore volume reach more than `factor`
    /// times the original grid's stiffest cell's, where it may merge.
    /// Returns how many deck cells went.
    pub fn merge_stiff(&mut self, factor: f64) -> usize {
        let n = self.cells.len();
        let mut reservoir = vec![false; n];
        for (e, ijk) in self.mesh.ijk.iter().enumerate() {
            reservoir[self.position[e]] = ijk.is_some();
        }
        let limit = factor * self.stiffest(&reservoir);
        if limit.is_nan() || limit <= 0.0 {
            return 0;
        }
        // per cell its region numbers: cells of different regions stay
        let regions: Vec<&Vec<f64>> = (self.arrays.values.iter())
            .filter(|(k, _)| k.ends_with("NUM"))
            .map(|(_, v)| v)
            .collect();
        let region = |c: usize| -> Vec<f64> {
            let h = self.host_of(c);
            regions.iter().map(|v| v[h]).collect()
        };
        let region: Vec<Vec<f64>> = (0..n).map(region).collect();
        // radial cells merge only with their ring's in their layer (an
        // annulus keeps the ring's pressure on its sites' circle)
        let mut radial = vec![false; n];
        for (e, r) in self.mesh.region.iter().enumerate() {
            radial[self.position[e]] |= *r == Region::Well;
        }
        let ring = self.rings(&radial);
        let mergeable = |c: usize| !reservoir[c] && self.cells[c].active;
        let mut parent: Vec<usize> = (0..n).collect();
        for _round in 0..50 {
            let (pv, sum) = self.sums(&mut parent);
            // per pair of cells that may merge, their transmissibilities
            let mut t: HashMap<(usize, usize), f64> = HashMap::new();
            for &([a, b], v) in &self.nnc {
                let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
                if ra != rb && mergeable(a) && mergeable(b) {
                    *t.entry((ra.min(rb), ra.max(rb))).or_default() += v;
                }
            }
            // each stiff cell's stiffest partner it may merge with
            let mut best: HashMap<usize, (f64, usize)> = HashMap::new();
            for (&(a, b), &v) in &t {
                if ring[a] != ring[b] || radial[a] != radial[b] || region[a] != region[b] {
                    continue;
                }
                let s = v / pv[a].min(pv[b]);
                for (x, y) in [(a, b), (b, a)] {
                    if sum[x] / pv[x] > limit
                        && best.get(&x).is_none_or(|&(bs, by)| (s, y) > (bs, by))
                    {
                        best.insert(x, (s, y));
                    }
                }
            }
            if best.is_empty() {
                break;
            }
            let mut stiff: Vec<(f64, usize, usize)> = best
                .into_iter()
                .map(|(x, (_, y))| (sum[x] / pv[x], x, y))
                .collect();
            stiff.sort_by(|p, q| q.0.total_cmp(&p.0).then((p.1, p.2).cmp(&(q.1, q.2))));
            let mut used = HashSet::new();
            for (_, a, b) in stiff {
                if !used.contains(&a) && !used.contains(&b) {
                    used.insert(a);
                    used.insert(b);
                    parent[b] = a;
                }
            }
        }
        self.merge_outwards(&mut parent, &ring, limit);
        self.regroup(&mut parent)
    }

    /// An innermost ring still stiffer than `limit` as an annulus takes in
    /// the next ring of its layer, and so on out while it stays stiff: the
    /// merged cell's pressure is the outer ring's, on its sites' circle,
    /// and each of the well's factors runs on to those sites through its
    /// sector's ring links in series (radial flow's, so still exact).
    fn merge_outwards(&mut self, parent: &mut [usize], ring: &[Option<Ring>], limit: f64) {
        let n = self.cells.len();
        let mut of: BTreeMap<Ring, Vec<usize>> = BTreeMap::new();
        for (c, r) in ring.iter().enumerate() {
            if let Some(r) = r {
                of.entry(*r).or_default().push(c);
            }
        }
        // links between a layer's rings, per cell
        let mut next: Vec<Vec<(usize, f64)>> = vec![vec![]; n];
        for &([a, b], t) in &self.nnc {
            if let (Some((w, k, p)), Some((v, l, q))) = (ring[a], ring[b]) {
                if (w, k) == (v, l) && p.abs_diff(q) == 1 {
                    next[a].push((b, t));
                    next[b].push((a, t));
                }
            }
        }
        // per innermost ring's cell, the cells its sector has reached
        let mut front: Vec<Vec<usize>> = (0..n).map(|c| vec![c]).collect();
        let mut reached: BTreeMap<(usize, usize), usize> = (of.keys())
            .filter(|r| r.2 == 0)
            .map(|r| ((r.0, r.1), 0))
            .collect();
        loop {
            let (pv, sum) = self.sums(parent);
            let mut grew = false;
            for (&(w, k), r) in reached.iter_mut() {
                let c = root(parent, of[&(w, k, *r)][0]);
                let Some(outer) = of.get(&(w, k, *r + 1)) else {
                    continue;
                };
                if sum[c] / pv[c] <= limit {
                    continue;
                }
                for &e in &of[&(w, k, 0)] {
                    let out: Vec<(usize, f64)> = (front[e].iter())
                        .flat_map(|&f| next[f].iter().copied())
                        .filter(|&(d, _)| ring[d] == Some((w, k, *r + 1)))
                        .collect();
                    let t: f64 = out.iter().map(|o| o.1).sum();
                    if t > 0.0 {
                        *self.outward.entry(self.cells[e].element).or_default() += 1.0 / t;
                        front[e] = out.into_iter().map(|o| o.0).collect();
                    }
                }
                for &d in outer {
                    let d = root(parent, d);
                    let c = root(parent, c);
                    parent[d] = c;
                }
                *r += 1;
                grew = true;
            }
            if !grew {
                return;
            }
        }
    }

    /// Per merged cell (its root), its pore volume and its
    /// transmissibilities' sum to other cells.
    fn sums(&self, parent: &mut [usize]) -> (Vec<f64>, Vec<f64>) {
        let n = self.cells.len();
        let mut pv = vec![0.0; n];
        for c in 0..n {
            let r = root(parent, c);
            pv[r] += self.cells[c].porv;
        }
        let mut sum = vec![0.0; n];
        for &([a, b], v) in &self.nnc {
            let (ra, rb) = (root(parent, a), root(parent, b));
            if ra != rb {
                sum[ra] += v;
                sum[rb] += v;
            }
        }
        (pv, sum)
    }

    /// Per deck cell of a radial mesh, its ring (well, layer, rings out
    /// from the innermost), found outwards from the cells the wells
    /// connect to through the radial cells of their layer.
    fn rings(&self, radial: &[bool]) -> Vec<Option<Ring>> {
        let n = self.cells.len();
        let layer = |c: usize| self.mesh.host[self.cells[c].element][2];
        let mut next = vec![vec![]; n];
        for &([a, b], _) in &self.nnc {
            if radial[a] && radial[b] && layer(a) == layer(b) {
                next[a].push(b);
                next[b].push(a);
            }
        }
        let mut ring = vec![None; n];
        let mut queue = std::collections::VecDeque::new();
        for (w, links) in self.mesh.wells.iter().enumerate() {
            for &(e, _) in &links.links {
                let c = self.position[e];
                if ring[c].is_none() {
                    ring[c] = Some((w, layer(c), 0));
                    queue.push_back(c);
                }
            }
        }
        while let Some(c) = queue.pop_front() {
            let Some((w, k, r)) = ring[c] else { continue };
            for &d in &next[c] {
                if ring[d].is_none() {
                    ring[d] = Some((w, k, r + 1));
                    queue.push_back(d);
                }
            }
        }
        ring
    }

    /// The deck's cells, positions and connections after the merges in
    /// `parent`: a merged cell holds its members' pore volume at their
    /// pore-volume-weighted depth, spans their heights, and takes its rock
    /// from its largest member; parallel connections add up.
    fn regroup(&mut self, parent: &mut [usize]) -> usize {
        let n = self.cells.len();
        let mut index = vec![usize::MAX; n];
        let mut members: Vec<Vec<usize>> = vec![];
        for c in 0..n {
            let r = root(parent, c);
            if index[r] == usize::MAX {
                index[r] = members.len();
                members.push(vec![]);
            }
            members[index[r]].push(c);
        }
        let gone = n - members.len();
        if gone == 0 {
            return 0;
        }
        let cells: Vec<Cell> = (members.iter())
            .map(|m| {
                let cs: Vec<&Cell> = m.iter().map(|&c| &self.cells[c]).collect();
                let porv: f64 = cs.iter().map(|c| c.porv).sum();
                let largest = cs.iter().max_by(|a, b| a.porv.total_cmp(&b.porv)).unwrap();
                let depth = cs.iter().map(|c| c.porv * c.depth).sum::<f64>() / porv;
                let top = cs
                    .iter()
                    .map(|c| c.depth - 0.5 * c.dz)
                    .fold(f64::INFINITY, f64::min);
                let bottom = cs
                    .iter()
                    .map(|c| c.depth + 0.5 * c.dz)
                    .fold(f64::NEG_INFINITY, f64::max);
                Cell {
                    element: largest.element,
                    porv,
                    depth,
                    dz: 2.0 * (depth - top).max(bottom - depth),
                    active: cs.iter().any(|c| c.active),
                }
            })
            .collect();
        let at = |c: usize, parent: &mut [usize]| index[root(parent, c)];
        for p in self.position.iter_mut() {
            *p = at(*p, parent);
        }
        let mut t: HashMap<(usize, usize), f64> = HashMap::new();
        let mut order = vec![];
        for &([a, b], v) in &self.nnc {
            let (a, b) = (at(a, parent), at(b, parent));
            if a != b {
                let key = (a.min(b), a.max(b));
                if !t.contains_key(&key) {
                    order.push(key);
                }
                *t.entry(key).or_default() += v;
            }
        }
        self.nnc = order.into_iter().map(|k| ([k.0, k.1], t[&k])).collect();
        self.cells = cells;
        gone
    }
}

#[cfg(test)]
mod tests {
    use super::super::cells::Table;
    use super::super::tests::{row, row_deck};
    use crate::mesh::{Connection, Element, Network};
    use crate::reservoir::{CornerPointGrid, Region};

    /// Four 10 m cells in a row: the first two and the last reservoir
    /// cells, the third split into two transition cells whose sites are
    /// 2 cm apart across its whole width, the second with the last cell's
    /// rock (SATNUM `satnum`).
    fn table(satnum: &str, check: impl Fn(&Table)) {
        let g = CornerPointGrid::cartesian([4, 1, 1], [10.0, 10.0, 2.0]);
        let e = |x: f64, volume: f64| Element {
            volume,
            node: [x, 5.0, -1.0],
        };
        let link = |a: usize, b: usize, d: [f64; 2]| Connection {
            elements: [a, b],
            isot: 1,
            d,
            area: 20.0,
            cos_gravity: 0.0,
        };
        let network = Network {
            elements: vec![
                e(5.0, 200.0),
                e(15.0, 200.0),
                e(24.99, 100.0),
                e(25.01, 100.0),
                e(35.0, 200.0),
            ],
            connections: vec![
                link(0, 1, [5.0, 5.0]),
                link(1, 2, [5.0, 4.99]),
                link(2, 3, [0.01, 0.01]),
                link(3, 4, [4.99, 5.0]),
            ],
        };
        // the second transition cell takes its rock from the last cell
        let host = [[0, 0, 0], [1, 0, 0], [2, 0, 0], [3, 0, 0], [3, 0, 0]];
        let ijk = [
            Some([0, 0, 0]),
            Some([1, 0, 0]),
            None,
            None,
            Some([3, 0, 0]),
        ];
        let region = [
            Region::Reservoir,
            Region::Reservoir,
            Region::Transition,
            Region::Transition,
            Region::Reservoir,
        ];
        let mesh = row(&g, &network, &host, &ijk, &region);
        let tail = format!("REGIONS\nSATNUM\n {satnum} /\n");
        let p = row_deck(&format!("M{}", satnum.len()), 4, &tail);
        let mut t = Table::new(&p, &mesh).unwrap();
        t.merge_stiff(1.0);
        check(&t);
    }

    #[test]
    fn stiff_transition_cells_merge() {
        table("4*1", |t| {
            assert_eq!(t.cells.len(), 4);
            // the two transition cells share a deck cell holding both
            assert_eq!(t.position[2], t.position[3]);
            let merged = &t.cells[t.position[2]];
            assert!((merged.porv - 40.0).abs() < 1e-9, "{}", merged.porv);
            assert!((merged.depth - 1.0).abs() < 1e-9);
            // its connections: one to each reservoir neighbour, none inside
            let to = |c: usize| {
                t.nnc
                    .iter()
                    .filter(|n| n.0.contains(&t.position[c]))
                    .count()
            };
            assert_eq!((to(2), t.nnc.len()), (2, 3));
        });
        // cells of different regions stay apart
        table("3*1 2", |t| assert_eq!(t.cells.len(), 5));
    }

    /// A well in the third of four grid cells, its radial mesh two rings
    /// of two sectors: the innermost ring, tiny and stiff, merges into an
    /// annulus, which stays stiff and takes in the outer ring; the well's
    /// factors then run on through their sectors' ring links in series.
    #[test]
    fn a_stiff_annulus_takes_in_the_next_ring() {
        let g = CornerPointGrid::cartesian([4, 1, 1], [10.0, 10.0, 2.0]);
        let e = |x: f64, volume: f64| Element {
            volume,
            node: [x, 5.0, -1.0],
        };
        let link = |a: usize, b: usize, area: f64, d: [f64; 2]| Connection {
            elements: [a, b],
            isot: 1,
            d,
            area,
            cos_gravity: 0.0,
        };
        // reservoir 0, 1 and 6; ring 0 elements 2, 3; ring 1 elements 4, 5
        let network = Network {
            elements: vec![
                e(5.0, 200.0),
                e(15.0, 200.0),
                e(24.9, 1.0),
                e(25.1, 1.0),
                e(24.0, 50.0),
                e(26.0, 50.0),
                e(35.0, 200.0),
            ],
            connections: vec![
                link(0, 1, 20.0, [5.0, 5.0]),
                link(1, 4, 10.0, [5.0, 2.5]),
                link(1, 5, 10.0, [5.0, 2.5]),
                link(4, 2, 5.0, [1.0, 1.0]),
                link(5, 3, 5.0, [1.0, 1.0]),
                link(2, 3, 2.0, [0.5, 0.5]),
                link(4, 5, 2.0, [2.0, 2.0]),
                link(4, 6, 10.0, [2.5, 5.0]),
                link(5, 6, 10.0, [2.5, 5.0]),
            ],
        };
        let column = [0, 1, 2, 2, 2, 2, 3];
        let host = column.map(|i| [i, 0, 0]);
        let ijk = column.map(|i| Some([i, 0, 0]));
        let ijk = ijk.map(|c| c.filter(|c| c[0] != 2));
        let mut region = [Region::Well; 7];
        for r in [0, 1, 6] {
            region[r] = Region::Reservoir;
        }
        let wells = [crate::reservoir::deck::WellLinks {
            name: "W".into(),
            radius: 0.1,
            links: vec![(2, 1.0), (3, 1.0)],
            log: 1.0,
        }];
        let mut mesh = row(&g, &network, &host, &ijk, &region);
        let extent = [2.0; 7];
        mesh.wells = &wells;
        mesh.extent = &extent;
        let p = row_deck("RINGS", 4, "");
        let mut t = Table::new(&p, &mesh).unwrap();
        let ring_link = |t: &Table, a: usize, b: usize| {
            let (a, b) = (t.position[a], t.position[b]);
            let n = t.nnc.iter().find(|n| n.0 == [a, b] || n.0 == [b, a]);
            n.unwrap().1
        };
        let outer = [ring_link(&t, 2, 4), ring_link(&t, 3, 5)];
        assert_eq!(t.merge_stiff(1.0), 3);
        let cell = t.position[2];
        assert!((2..6).all(|e| t.position[e] == cell));
        assert!((t.cells[cell].porv - 20.4).abs() < 1e-9);
        for (e, t_out) in [(2, outer[0]), (3, outer[1])] {
            let r = t.outward[&e];
            assert!(
                (r * t_out - 1.0).abs() < 1e-12,
                "{e}: {r} against 1 / {t_out}"
            );
        }
    }
}
