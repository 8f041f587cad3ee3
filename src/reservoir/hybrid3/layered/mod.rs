//! Layered cavities: where the cells around the wells lie between parallel
//! planes (a dipping layer cake, as SPE9), the transition follows the
//! layers. A 2D hybrid mesh of the wells on a section across the layers
//! (`section`), each of its transition and radial cells taken through
//! each layer of the cavity as a prism across the layers, cut by the
//! columns' walls (`cells`). Links inside the cavity are orthogonal by
//! construction, every cell lies in one grid layer, and the wells' radial
//! meshes run along the layers' normal through the middle of their
//! completions (the axis a simulator's connection factors assume).

mod assemble;
mod cells;
mod cones;
mod frame;
mod join;
mod reflex;
mod section;

pub(crate) use assemble::{assemble, unfilled};
pub(crate) use cells::{Across, Cavity, Cell};
pub(crate) use frame::Frame;

use super::cpg::Cpg;
use super::path::Path;
use super::well::{Section, Well3};
use crate::backend::Backend;
use crate::error::Result;
use crate::geom::Cutter;
use crate::reservoir::hybrid::{Hybrid, Region};
use section::Ask;
use std::collections::BTreeSet;

/// A group of wells meshed on one section.
pub(crate) struct Group {
    pub(crate) frame: Frame,
    /// The section's 2D hybrid mesh (its wells in the group's order).
    pub(crate) section: Hybrid,
    pub(crate) wells: Vec<usize>,
    /// Per cavity: its columns, layers and section cells; its points and
    /// cells.
    pub(crate) cavities: Vec<(Cavity, Cutter, Vec<Cell>)>,
    /// What the section's cavities share.
    pub(crate) shared: cells::Shared,
}

/// The layered cavities of all the wells, or why they cannot be layered
/// (then the 3D transition serves).
pub(crate) fn build<B: Backend + ?Sized>(
    backend: &B,
    cpg: &Cpg,
    wells: &[Well3],
    paths: &[Path],
    section: &Section,
) -> Result<std::result::Result<Vec<Group>, String>> {
    let g = cpg.g;
    // each well down one column, its completed layers and one beyond
    let mut spans = vec![];
    for (w, p) in wells.iter().zip(paths) {
        let [i, j, _] = p.cells[0];
        // a trajectory from a file, or a straight axis asked for
        let given = w.path.is_some() && w.cells.is_empty();
        if given || (w.straight && w.dip != 0.0) || p.cells.iter().any(|c| [c[0], c[1]] != [i, j]) {
            return Ok(Err(format!("well {} does not run down one column", w.name)));
        }
        let k0 = p.cells.iter().map(|c| c[2]).min().unwrap_or(0);
        let k1 = p.cells.iter().map(|c| c[2]).max().unwrap_or(0);
        // a layer beyond each end where the cell there is live (an
        // inactive cell over a completion ends the cavity instead)
        let lo = k0.checked_sub(1).filter(|&k| cpg.live([i, j, k]));
        let hi = Some(k1 + 1).filter(|&k| k < g.nz && cpg.live([i, j, k]));
        spans.push([lo.unwrap_or(k0), hi.unwrap_or(k1)]);
    }
    // wells whose spans overlap or touch share a section (so that
    // cavities of two sections never meet face to face)
    let mut order: Vec<usize> = (0..wells.len()).collect();
    order.sort_by_key(|&w| spans[w]);
    let mut groups: Vec<(Vec<usize>, [usize; 2])> = vec![];
    for w in order {
        match groups.last_mut() {
            Some((ws, s)) if spans[w][0] <= s[1] + 1 => {
                ws.push(w);
                s[1] = s[1].max(spans[w][1]);
            }
            _ => groups.push((vec![w], spans[w])),
        }
    }
    let mut out = vec![];
    for (ws, [k0, k1]) in groups {
        // the frame over the columns within 4 of the wells'
        let mut cols = BTreeSet::new();
        for &w in &ws {
            let [i, j, _] = paths[w].cells[0];
            for jj in j.saturating_sub(4)..=(j + 4).min(g.ny - 1) {
                for ii in i.saturating_sub(4)..=(i + 4).min(g.nx - 1) {
                    cols.insert([ii, jj]);
                }
            }
        }
        let cols: Vec<[usize; 2]> = cols.into_iter().collect();
        // where the layers around are not parallel planes, the wells' own
        // columns' frame, their cells cut by the grid's own faces
        let own: Vec<[usize; 2]> = ws
            .iter()
            .map(|&w| [paths[w].cells[0][0], paths[w].cells[0][1]])
            .collect::<BTreeSet<_>>()
            .into_iter()
            .collect();
        let frame = match Frame::fit(cpg, &cols, k0, k1) {
            Ok(f) => f,
            Err(why) => match Frame::twisted(cpg, &own, [k0, k1]) {
                Ok(f) => f,
                Err(_) => return Ok(Err(format!("around wells {}: {why}", names(wells, &ws)))),
            },
        };
        let (frame, [k0, k1]) = trim(cpg, frame, &cols, [k0, k1], &ws, paths);
        let at = section_height(cpg, &frame, &cols, [k0, k1]);
        let alive = |[i, j]: [usize; 2]| (k0..=k1).all(|k| cpg.live([i, j, k]));
        // twisted layers: the wells' fault block only (a prism across a
        // throw would be a cell in two pieces, its layers apart)
        let block = frame.twisted.then(|| fault_block(cpg, &own, &cols, &alive));
        let live = |c: [usize; 2]| alive(c) && block.as_ref().is_none_or(|b| b.contains(&c));
        let grid = section::grid(g, &frame, at, live);
        let points = section_points(cpg, &frame, wells, paths, &ws);
        let sec = Sec {
            g,
            frame: &frame,
            grid: &grid,
            points: &points,
            rs: [section.rings, section.sectors],
            live: &live,
            k: [k0, k1],
            at,
            in_column: section.in_column,
            first_ring: section.first_ring,
        };
        let who = names(wells, &ws);
        let (mesh2, found) = match pick(cpg, &sec, backend, section.outer, &own, &cols, &who)? {
            Ok(x) => x,
            Err(why) => return Ok(Err(why)),
        };
        // cells that a simulator cannot take are errors, as in the 3D
        // transition; planar layers cannot hold them
        if frame.twisted {
            for c in &found {
                usable(cpg, c, &names(wells, &ws))?;
            }
        }
        let mut built = vec![];
        let shared = cells::Shared::new(&mesh2.mesh, &mesh2.region);
        for c in found {
            let section = (&mesh2.mesh, mesh2.region.as_slice());
            match cells::cells(cpg, &frame, section, &shared, &c) {
                Ok((cut, cells)) => built.push((c, cut, cells)),
                Err(why) => return Ok(Err(format!("around wells {}: {why}", names(wells, &ws)))),
            }
        }
        out.push(Group {
            frame,
            section: mesh2,
            wells: ws,
            cavities: built,
            shared,
        });
    }
    Ok(Ok(out))
}

/// Planes: the layer beyond a completion's end left out of the cavity
/// where reservoir cells lie beyond it (kept where it ends at the grid's
/// top or bottom, so that the section is taken at the cavity's other end).
/// Each layer of a cavity costs a link at each pillar in the middle of a
/// side along the dip (docs/limitations.md).
fn trim(
    cpg: &Cpg,
    frame: Frame,
    cols: &[[usize; 2]],
    [k0, k1]: [usize; 2],
    ws: &[usize],
    paths: &[Path],
) -> (Frame, [usize; 2]) {
    if frame.twisted {
        return (frame, [k0, k1]);
    }
    let done = ws.iter().flat_map(|&w| paths[w].cells.iter().map(|c| c[2]));
    let (c0, c1) = done.fold((usize::MAX, 0), |(a, b), k| (a.min(k), b.max(k)));
    let meets = |k: Option<usize>| live_across(cpg, cols, k) > 0;
    let lo = if k0 < c0 && meets(k0.checked_sub(1)) {
        c0
    } else {
        k0
    };
    let hi = if k1 > c1 && meets(Some(k1 + 1)) {
        c1
    } else {
        k1
    };
    if [lo, hi] == [k0, k1] {
        return (frame, [k0, k1]);
    }
    match Frame::fit(cpg, cols, lo, hi) {
        Ok(f) => (f, [lo, hi]),
        Err(_) => (frame, [k0, k1]),
    }
}

/// How many of the columns have a live cell in layer k (none if k is
/// outside the grid).
fn live_across(cpg: &Cpg, cols: &[[usize; 2]], k: Option<usize>) -> usize {
    k.filter(|&k| k < cpg.g.nz).map_or(0, |k| {
        cols.iter().filter(|c| cpg.live([c[0], c[1], k])).count()
    })
}

/// The height (frame coordinates) of the plane the section is taken at.
/// Planes: the cavity's end that meets more live cells across (its top
/// or its bottom), so that the column sides there are the section's own
/// lines and no prism at that end reaches under two cells across (their
/// links then cross their faces: the reservoir cell's node mirrored);
/// midway where both ends meet as many. Twisted layers: midway.
fn section_height(cpg: &Cpg, frame: &Frame, cols: &[[usize; 2]], [k0, k1]: [usize; 2]) -> f64 {
    let [top, bottom] = frame.ends();
    let across = |k: Option<usize>| live_across(cpg, cols, k);
    let (above, below) = (across(k0.checked_sub(1)), across(Some(k1 + 1)));
    match (frame.twisted, above.cmp(&below)) {
        (false, std::cmp::Ordering::Greater) => top,
        (false, std::cmp::Ordering::Less) => bottom,
        _ => 0.5 * (top + bottom),
    }
}

/// Where a try's cavities start: the wells' own columns, the columns a
/// radial mesh of the outer radius asked would reach, or as the 2D hybrid
/// grows them.
#[derive(Clone, Copy)]
enum Start {
    Own,
    Reach,
    Grown,
}

/// The section's tries, the first that serves kept. Planes: radial meshes
/// in their own columns in cavities as wide as the outer radius asked
/// (every column side a constraint, so that no cell at the cavity's end
/// lies under two cells across: SPE9's links to the reservoir 94% by
/// count, 100% to the radial cells, against 81% and 93% with radial
/// meshes over several columns), then as wide as asked. Twisted layers:
/// in the wells' own columns at 0.4, 0.25 and 0.15 of the head cell's
/// side, then kept in their columns in cavities as wide as asked (within
/// the frame: emerald (21, 36) and (12, 39), whose own columns fail), then
/// as wide as asked, each first with its sides split near the
/// wells, then whole (a well near a whole side: system 3 infeasible at
/// every radius in emerald's (7, 4) and edge columns): the first
/// whose links to the wells are all orthogonal (the ring's sites mirrored
/// across its sides) and whose cavities no throw crosses, else the one
/// with fewest links off.
fn pick<B: Backend + ?Sized>(
    cpg: &Cpg,
    sec: &Sec,
    backend: &B,
    outer: f64,
    own: &[[usize; 2]],
    cols: &[[usize; 2]],
    who: &str,
) -> Result<std::result::Result<(Hybrid, Vec<Cavity>), String>> {
    let twisted = sec.frame.twisted;
    // where the walls lean off the prisms, each convex corner of a cavity
    // is owned by one cell
    let corners = !twisted && leaning(cpg, sec.frame, own);
    let ask = |split, in_column| Ask {
        split,
        in_column,
        corners,
        first_ring: sec.first_ring,
    };
    let tries: Vec<(f64, Start, Ask)> = match twisted {
        true => OWN_COLUMN
            .into_iter()
            .filter(|&o| o < outer)
            .map(|o| (o, Start::Own, false))
            .chain([(outer, Start::Reach, true), (outer, Start::Grown, false)])
            .flat_map(|(o, s, c)| [(o, s, ask(true, c)), (o, s, ask(false, c))])
            .collect(),
        false => [
            (Start::Reach, ask(false, true)),
            (Start::Grown, ask(false, false)),
        ]
        .into_iter()
        .filter(|t| sec.in_column || !t.1.in_column)
        .map(|(s, a)| (outer, s, a))
        .collect(),
    };
    // the columns the outer radius reaches (within the frame), once
    let reach: Option<BTreeSet<[usize; 2]>> =
        match tries.iter().any(|t| matches!(t.1, Start::Reach)) {
            true => Some(
                section::columns(sec.grid, sec.points, sec.rs, outer)?
                    .into_iter()
                    .filter(|c| cols.contains(c))
                    .collect(),
            ),
            false => None,
        };
    let mut best: Option<(usize, Hybrid, Vec<Cavity>)> = None;
    let mut why = "the section's sides could not be moved in".to_string();
    for (r, from, ask) in tries {
        let start = match from {
            Start::Own => Some(own.iter().copied().collect()),
            Start::Reach => reach.clone(),
            Start::Grown => None,
        };
        let Some((m, found)) = sec.mesh(backend, r, start, ask)? else {
            continue;
        };
        if let Some(c) = found
            .iter()
            .flat_map(|c| c.cols.iter())
            .find(|c| !cols.contains(c))
        {
            return Ok(Err(format!(
                "the cavity of wells {who} reaches column ({}, {}), past the frame's",
                c[0] + 1,
                c[1] + 1
            )));
        }
        if !twisted {
            return Ok(Ok((m, found)));
        }
        if let Some(w) = found.iter().find_map(|c| unmatched_walls(cpg, c)) {
            why = w;
            continue;
        }
        let off = m
            .report
            .non_orthogonal_interfaces
            .iter()
            .filter(|x| x.1 == "transition-well")
            .count();
        if off == 0 {
            return Ok(Ok((m, found)));
        }
        if best.as_ref().is_none_or(|b| off < b.0) {
            best = Some((off, m, found));
        }
    }
    Ok(best
        .map(|(_, m, found)| (m, found))
        .ok_or_else(|| format!("around wells {who}: {why}")))
}

/// The wells' points on the section: the mean of their completed cells'
/// centres, with their names and radii.
fn section_points(
    cpg: &Cpg,
    frame: &Frame,
    wells: &[Well3],
    paths: &[Path],
    ws: &[usize],
) -> Vec<(String, [f64; 2], f64)> {
    ws.iter()
        .map(|&w| {
            let cs = &paths[w].cells;
            let m: [f64; 3] = std::array::from_fn(|a| {
                cs.iter().map(|&c| cpg.centre(c)[a]).sum::<f64>() / cs.len() as f64
            });
            let q = frame.to(m);
            (wells[w].name.clone(), [q[0], q[1]], wells[w].radius)
        })
        .collect()
}

/// Whether the wells' columns' pillars lean, between the frame's top and
/// bottom, along their columns' I or J sides (in the frame, where prisms
/// stand upright): a prism beside a pillar then reaches past it.
fn leaning(cpg: &Cpg, f: &Frame, own: &[[usize; 2]]) -> bool {
    let g = cpg.g;
    let [top, bottom] = f.ends();
    let at = |i: usize, j: usize, h: f64| f.crossing(g.coord[j * (g.nx + 1) + i], h);
    let mut out = false;
    for &[i, j] in own {
        let (lo, hi) = (at(i, j, bottom), at(i, j, top));
        let lean = [hi[0] - lo[0], hi[1] - lo[1]];
        for far in [at(i + 1, j, top), at(i, j + 1, top)] {
            let t = [far[0] - hi[0], far[1] - hi[1]];
            let len = t[0].hypot(t[1]);
            out |= (lean[0] * t[0] + lean[1] * t[1]).abs() > f.tol() * len;
        }
    }
    out
}

/// The outer radii (of the head cell's side) at which twisted layers'
/// radial meshes are tried in their own columns.
const OWN_COLUMN: [f64; 3] = [0.4, 0.25, 0.15];

/// A group's section: the grid, its frame, wells and layers.
struct Sec<'a> {
    g: &'a crate::reservoir::CornerPointGrid,
    frame: &'a Frame,
    grid: &'a crate::reservoir::CornerPointGrid,
    points: &'a [(String, [f64; 2], f64)],
    rs: [usize; 2],
    live: &'a dyn Fn([usize; 2]) -> bool,
    k: [usize; 2],
    /// The height of the section's plane (frame coordinates).
    at: f64,
    /// Planes: radial meshes first tried in their own columns.
    in_column: bool,
    first_ring: Option<f64>,
}

impl Sec<'_> {
    /// The section's mesh at outer radius `outer` and its cavities: their
    /// sides moved in by their walls' lean, so that no prism crosses a
    /// wall within the cavity's layers, with the columns the wells reach
    /// (again where the mesher grew them), or from the columns given
    /// (None if the mesher grew those, or grew a cavity with split
    /// sides). Planes: as they are where a
    /// cavity touches itself at a pillar or that fails; twisted layers and
    /// radial meshes kept in their columns: None then.
    fn mesh<B: Backend + ?Sized>(
        &self,
        backend: &B,
        outer: f64,
        start: Option<BTreeSet<[usize; 2]>>,
        ask: Ask,
    ) -> Result<Option<(Hybrid, Vec<Cavity>)>> {
        let (f, [k0, k1]) = (self.frame, self.k);
        let [top, bottom] = f.ends();
        let heights = [self.at, top, bottom];
        let layers = f.twisted.then_some([k0, k1]);
        let found = |m: &Hybrid| cavities(m, [self.g.nx, self.g.ny], self.live, self.k);
        let grow = !ask.split && start.is_none();
        let mut set = match start {
            Some(s) => s,
            None => section::columns(self.grid, self.points, self.rs, outer)?,
        };
        for _ in 0..3 {
            let mut moved = self.grid.clone();
            let Some(inner) = section::inset(self.g, f, heights, &mut moved, &set, layers) else {
                break;
            };
            let m = section::mesh(
                backend,
                &moved,
                self.points,
                self.rs,
                outer,
                Some((&set, &inner[..])),
                ask,
            );
            let Ok(m) = m else { break };
            let mut cavs = found(&m);
            let now: BTreeSet<[usize; 2]> = cavs.iter().flat_map(|c| c.cols.clone()).collect();
            if now == set {
                // each reflex pillar's moved point and own point
                let reflex: Vec<[[f64; 2]; 2]> = inner
                    .iter()
                    .map(|&(p, x)| [[moved.coord[p][0], moved.coord[p][1]], x])
                    .collect();
                for c in &mut cavs {
                    c.reflex = reflex.clone();
                }
                return Ok(Some((m, cavs)));
            }
            if !grow {
                // the wells' own columns and split sides are tries for
                // cavities that fit as they are; grown, the 2D hybrid's
                // LP grows with them (emerald (12, 39): 1, 12, then 19
                // columns, over a minute and a half)
                return Ok(None);
            }
            set = now;
        }
        if f.twisted || ask.in_column {
            return Ok(None);
        }
        let m = section::mesh(backend, self.grid, self.points, self.rs, outer, None, ask)?;
        let cavs = found(&m);
        Ok(Some((m, cavs)))
    }
}

/// The section's cavities: its transition and radial cells, by the
/// 4-connected components of the columns that hold no reservoir cell.
fn cavities(
    h: &Hybrid,
    [nx, ny]: [usize; 2],
    live: &dyn Fn([usize; 2]) -> bool,
    k: [usize; 2],
) -> Vec<Cavity> {
    let res: BTreeSet<[usize; 2]> = h.ijk.iter().flatten().map(|c| [c[0], c[1]]).collect();
    let mine: Vec<(usize, [usize; 2])> = (0..h.region.len())
        .filter(|&c| h.region[c] != Region::Reservoir)
        .map(|c| (c, [h.host[c][0], h.host[c][1]]))
        .collect();
    let mut free: BTreeSet<[usize; 2]> = (0..ny)
        .flat_map(|j| (0..nx).map(move |i| [i, j]))
        .filter(|&c| live(c) && !res.contains(&c))
        .collect();
    let mut out = vec![];
    while let Some(&start) = free.iter().next() {
        let mut cols = BTreeSet::new();
        let mut stack = vec![start];
        while let Some(c) = stack.pop() {
            if !free.remove(&c) {
                continue;
            }
            cols.insert(c);
            let [i, j] = c;
            for n in [
                [i + 1, j],
                [i, j + 1],
                [i.wrapping_sub(1), j],
                [i, j.wrapping_sub(1)],
            ] {
                if free.contains(&n) {
                    stack.push(n);
                }
            }
        }
        let cells = mine
            .iter()
            .filter(|m| cols.contains(&m.1))
            .map(|m| m.0)
            .collect();
        out.push(Cavity {
            cols,
            k,
            cells,
            reflex: vec![],
        });
    }
    out
}

/// A twisted cavity's cells, checked as the 3D transition checks its own:
/// an inverted cell, or layers that do not meet (a gap or an overlap, a
/// wall across which cells do not match but for a throw) are errors.
fn usable(cpg: &Cpg, cav: &Cavity, wells: &str) -> Result<()> {
    for &[i, j] in &cav.cols {
        for k in cav.k[0]..=cav.k[1] {
            let c = [i, j, k];
            if let Some(n) = cpg.inverted(c) {
                let s = if wells.contains(", ") {
                    "wells"
                } else {
                    "well"
                };
                return Err(crate::error::Error::Usage(format!(
                    "{s} {wells}: cell {} of the cavity is inverted: at pillar {} its top lies below \
                     its bottom",
                    super::cpg::one_based(c),
                    cpg.pillar_name(c, n)
                )));
            }
            for f in (0..6).filter(|&f| f >= 4 || !cpg.is_thrown([i, j], f)) {
                cpg.neighbour(c, f)?;
            }
        }
    }
    Ok(())
}

/// The columns (among `cols`, live) reached from the wells' own columns
/// without crossing a throw.
fn fault_block(
    cpg: &Cpg,
    own: &[[usize; 2]],
    cols: &[[usize; 2]],
    live: &dyn Fn([usize; 2]) -> bool,
) -> BTreeSet<[usize; 2]> {
    let mut block: BTreeSet<[usize; 2]> = BTreeSet::new();
    let mut stack: Vec<[usize; 2]> = own.to_vec();
    while let Some(c) = stack.pop() {
        if !block.insert(c) {
            continue;
        }
        for f in 0..4 {
            if cpg.is_thrown(c, f) {
                continue;
            }
            if let Some([i, j, _]) = super::cpg::next(cpg.g, [c[0], c[1], 0], f) {
                if cols.contains(&[i, j]) && live([i, j]) && !block.contains(&[i, j]) {
                    stack.push([i, j]);
                }
            }
        }
    }
    block
}

/// Why a twisted cavity cannot be layered: a throw between two of its
/// columns (a prism across it would be a cell in two pieces, the layers
/// apart). Throws on its outer walls are cut by the cells across.
fn unmatched_walls(cpg: &Cpg, cav: &Cavity) -> Option<String> {
    for &[i, j] in &cav.cols {
        for f in 0..4 {
            let across = super::cpg::next(cpg.g, [i, j, 0], f);
            if across.is_some_and(|[a, b, _]| cav.cols.contains(&[a, b]))
                && cpg.is_thrown([i, j], f)
            {
                return Some(format!(
                    "a fault's throw runs between columns of its cavity, at column ({}, {}), and its layers are not planes",
                    i + 1,
                    j + 1
                ));
            }
        }
    }
    None
}

fn names(wells: &[Well3], ws: &[usize]) -> String {
    ws.iter()
        .map(|&w| wells[w].name.as_str())
        .collect::<Vec<_>>()
        .join(", ")
}
