//! A well's completed interval in the grid: its straight axis from the
//! top of its first completed layer down to the bottom of its last, the
//! cells it crosses there, and whether its ends lie on a flat top or
//! bottom of the grid (where its radial mesh stays open) or inside the
//! cavity (where the mesh is closed by plugs).

use super::cpg::{one_based, Cpg, Ijk};
use super::well::Well3;
use crate::error::{Error, Result};
use crate::reservoir::CornerPointGrid;

/// A well's axis and completed cells.
pub(super) struct Path {
    /// The axis' point at the top of the completed interval.
    pub(super) head: [f64; 3],
    /// The axis' unit direction, going down.
    pub(super) u: [f64; 3],
    /// The completed interval's length along the axis.
    pub(super) length: f64,
    /// The live completed cells it crosses, and the first of them.
    pub(super) cells: Vec<Ijk>,
    pub(super) head_cell: Ijk,
    /// Where the axis crosses from one completed layer to the next (along
    /// it from the head): a vertical well's layers are the grid's.
    pub(super) cuts: Vec<f64>,
    /// Per end (top, bottom), the height of the grid's top or bottom the
    /// end lies on, where it is flat (`flat`).
    pub(super) open: [Option<f64>; 2],
    /// Whether it follows a trajectory (its ends capped within its cells)
    /// rather than a column's completed layers.
    pub(super) explicit: bool,
    /// Where it is one leg of a trajectory that bends: its well (index)
    /// and leg number (`bend`).
    pub(super) leg: Option<(usize, usize)>,
    /// Per end, where it is a knee (`bend`): half the turn there.
    pub(super) bends: [Option<f64>; 2],
    /// The largest outer radius whose knees fit along it (`bend`).
    pub(super) max_outer: f64,
}

/// The first point farther off the line from the first point to the last
/// than 1% of their distance and than `floor`: its index and how far.
pub(super) fn off_line(points: &[[f64; 3]], floor: f64) -> Option<(usize, f64)> {
    let (first, last) = (points.first()?, points.last()?);
    let d: [f64; 3] = std::array::from_fn(|a| last[a] - first[a]);
    let length = d.iter().map(|x| x * x).sum::<f64>().sqrt();
    let u = d.map(|x| x / length);
    points.iter().enumerate().find_map(|(n, q)| {
        let v: [f64; 3] = std::array::from_fn(|a| q[a] - first[a]);
        let t: f64 = (0..3).map(|a| v[a] * u[a]).sum();
        let off = (0..3)
            .map(|a| (v[a] - t * u[a]).powi(2))
            .sum::<f64>()
            .sqrt();
        (off > floor.max(0.01 * length)).then_some((n, off))
    })
}

/// The completed layers: the given range, or every layer.
fn range(g: &CornerPointGrid, well: &Well3) -> Result<[usize; 2]> {
    let [k1, k2] = well.k.unwrap_or([0, g.nz - 1]);
    if k1 > k2 || k2 >= g.nz {
        return Err(Error::Usage(format!(
            "well {}: completed layers {}..{} are not in the grid's 1..{}",
            well.name,
            k1 + 1,
            k2 + 1,
            g.nz
        )));
    }
    Ok([k1, k2])
}

/// A well's completed cells in order, each in the grid: its `cells`, or
/// its column's completed layers; the live ones, with a note for each
/// left out (inactive, pinched out). An error names a cell outside the
/// grid, or a completion with no live cell.
pub(super) fn completed(cpg: &Cpg, well: &Well3) -> Result<(Vec<Ijk>, Vec<String>)> {
    let g = cpg.g;
    let cells: Vec<Ijk> = if well.cells.is_empty() {
        column(g, well)?;
        let [k1, k2] = range(g, well)?;
        (k1..=k2).map(|k| [well.i, well.j, k]).collect()
    } else {
        well.cells.clone()
    };
    if let Some(&c) = cells
        .iter()
        .find(|c| c[0] >= g.nx || c[1] >= g.ny || c[2] >= g.nz)
    {
        return Err(Error::Usage(format!(
            "well {}: its completion in cell {} is not in the grid's {} x {} x {} cells",
            well.name,
            one_based(c),
            g.nx,
            g.ny,
            g.nz
        )));
    }
    let mut notes = vec![];
    let mut live = vec![];
    for &c in &cells {
        match (g.active(c[0], c[1], c[2]), cpg.pinched(c)) {
            (true, false) => live.push(c),
            (active, _) => notes.push(format!(
                "well {}: its completion in cell {} is left out: the cell is {}",
                well.name,
                one_based(c),
                if active { "pinched out" } else { "inactive" }
            )),
        }
    }
    if live.is_empty() {
        return Err(Error::Usage(format!(
            "well {}: its completion has no active cell with thickness (cells {} to {}, {} in \
             all)",
            well.name,
            one_based(cells[0]),
            one_based(cells[cells.len() - 1]),
            cells.len()
        )));
    }
    Ok((live, notes))
}

/// An error unless the well's head column is in the grid.
fn column(g: &CornerPointGrid, well: &Well3) -> Result<()> {
    if well.i >= g.nx || well.j >= g.ny {
        return Err(Error::Usage(format!(
            "well {}: column ({}, {}) is not in the grid's {} x {} columns",
            well.name,
            well.i + 1,
            well.j + 1,
            g.nx,
            g.ny
        )));
    }
    Ok(())
}

/// The well as the trajectory (x, y, depth) through its live completed
/// cells (then its `cells`), as the simulator connects them: from its
/// first cell's top through each cell's centre to its last cell's bottom
/// (points on the diagonal its top and bottom are split along). None
/// where the well is a straight axis: a trajectory of its own, `straight`,
/// or centres on one vertical (within 1e-9 of the first cell's side): a
/// column whose pillars stand upright, meshed as one vertical path.
pub(super) fn through_centres(cpg: &Cpg, well: &Well3) -> Result<Option<Well3>> {
    if well.path.is_some() || well.straight || well.dip != 0.0 {
        return Ok(None);
    }
    let (cells, _) = completed(cpg, well)?;
    // on the diagonal that a split top and bottom share (`Cpg::face_pieces`):
    // the mean of the corners, off it on a twisted thin cell, may lie
    // outside the cell's pieces
    let mean = |c: Ijk, ns: &[usize]| -> [f64; 3] {
        std::array::from_fn(|a| {
            ns.iter().map(|&n| cpg.corner(c, n)[a]).sum::<f64>() / ns.len() as f64
        })
    };
    let top = |c: Ijk| cpg.diagonal(c);
    let bottom = |c: Ijk| cpg.diagonal(c).map(|n| n + 4);
    let last = cells[cells.len() - 1];
    let head = mean(cells[0], &top(cells[0]));
    let toe = mean(last, &bottom(last));
    let centres: Vec<[f64; 3]> = cells
        .iter()
        .map(|&c| mean(c, &[top(c), bottom(c)].concat()))
        .collect();
    let tol = 1e-9 * cpg.side(cells[0]);
    let upright = centres
        .iter()
        .chain([&toe])
        .all(|p| (p[0] - head[0]).hypot(p[1] - head[1]) <= tol);
    let one_column = cells.iter().all(|c| c[..2] == cells[0][..2]);
    if upright && one_column {
        return Ok(None);
    }
    let depth = |p: [f64; 3]| [p[0], p[1], -p[2]];
    Ok(Some(Well3 {
        path: Some(
            std::iter::once(head)
                .chain(centres)
                .chain([toe])
                .map(depth)
                .collect(),
        ),
        cells,
        ..well.clone()
    }))
}

/// The centre of face f (top 4, bottom 5) of a cell: the mean of its corners.
fn face_centre(cpg: &Cpg, c: Ijk, f: usize) -> [f64; 3] {
    let q = cpg.face(c, f);
    std::array::from_fn(|a| q.iter().map(|p| p[a]).sum::<f64>() / 4.0)
}

/// The height of the grid's top (f = 4) or bottom (f = 5) at column
/// (i, j), when it is flat there and the columns around within `reach`
/// lie at that height or inside it (below a top, above a bottom: the step
/// of a throw): a plane the transition can be cut at.
fn flat(cpg: &Cpg, [i, j]: [usize; 2], f: usize, reach: usize) -> Option<f64> {
    let g = cpg.g;
    let k = if f == 4 { 0 } else { g.nz - 1 };
    // the column's own face flat, the others' at its level or inside
    // (below the top, above the bottom: a throw's step)
    let own = cpg.face([i, j, k], f);
    let z = own[0][2];
    if own.iter().any(|p| p[2] != z) {
        return None;
    }
    let inside = |p: [f64; 3]| if f == 4 { p[2] <= z } else { p[2] >= z };
    for jj in j.saturating_sub(reach)..=(j + reach).min(g.ny - 1) {
        for ii in i.saturating_sub(reach)..=(i + reach).min(g.nx - 1) {
            if !cpg.face([ii, jj, k], f).into_iter().all(inside) {
                return None;
            }
        }
    }
    Some(z)
}

impl Path {
    /// The well's completed interval, or why it has none.
    pub(super) fn new(cpg: &Cpg, well: &Well3) -> Result<Path> {
        if let Some(points) = &well.path {
            return Path::along(cpg, well, points);
        }
        let g = cpg.g;
        // a straight axis down the first completed cell's column, through
        // the completed layers
        let (live, _) = completed(cpg, well)?;
        let [i, j, _] = live[0];
        let first = live.iter().map(|c| c[2]).min().unwrap_or(0);
        let last = live.iter().map(|c| c[2]).max().unwrap_or(0);
        if let Some(k) = (first..=last).find(|&k| !g.active(i, j, k)) {
            return Err(Error::Usage(format!(
                "well {}: its completion in cell {} is in an inactive cell",
                well.name,
                one_based([i, j, k])
            )));
        }
        let live: Vec<usize> = (first..=last)
            .filter(|&k| !cpg.pinched([i, j, k]))
            .collect();
        let head = face_centre(cpg, [i, j, first], 4);
        let dip = well.dip.to_radians();
        let az = well.azimuth.to_radians();
        let u = [dip.sin() * az.sin(), dip.sin() * az.cos(), -dip.cos()];
        if !u.iter().all(|x| x.is_finite()) || u[2] >= -1e-3 {
            return Err(Error::Usage(format!(
                "well {}: a dip of {} degrees is not through the layers",
                well.name, well.dip
            )));
        }
        let reach = 2;
        let open = [
            (first == 0).then(|| flat(cpg, [i, j], 4, reach)).flatten(),
            (last == g.nz - 1)
                .then(|| flat(cpg, [i, j], 5, reach))
                .flatten(),
        ];
        if well.dip == 0.0 {
            let bottom = face_centre(cpg, [i, j, last], 5);
            let cuts = live[1..]
                .iter()
                .map(|&k| head[2] - face_centre(cpg, [i, j, k], 4)[2])
                .collect();
            return Ok(Path {
                head,
                u,
                length: head[2] - bottom[2],
                cells: live.iter().map(|&k| [i, j, k]).collect(),
                head_cell: [i, j, first],
                cuts,
                open,
                explicit: false,
                leg: None,
                bends: [None; 2],
                max_outer: f64::INFINITY,
            });
        }
        Path::walk(cpg, well, [i, j], head, u, [first, last], open)
    }

    /// A well along a straight trajectory (x, y, depth), completed over its
    /// whole length: its cells found by steps along it, its ends capped.
    fn along(cpg: &Cpg, well: &Well3, points: &[[f64; 3]]) -> Result<Path> {
        let bad = |why: String| Err(Error::Usage(format!("well {}: {why}", well.name)));
        let frame = |p: [f64; 3]| [p[0], p[1], -p[2]];
        let (Some(&first), Some(&last)) = (points.first(), points.last()) else {
            return bad("its path has no points".into());
        };
        if points.iter().flatten().any(|x| !x.is_finite()) {
            return bad("its path has a NaN or infinite coordinate".into());
        }
        let (head, toe) = (frame(first), frame(last));
        let d: [f64; 3] = std::array::from_fn(|a| toe[a] - head[a]);
        let length = d.iter().map(|x| x * x).sum::<f64>().sqrt();
        if length <= 0.0 {
            return bad("its path has no length".into());
        }
        let u = d.map(|x| x / length);
        // straight: every point within 1% of the length of the chord
        // (`bend` splits a trajectory into such legs first)
        if let Some((n, off)) = off_line(points, 0.0) {
            return bad(format!(
                "its path bends: point {} is {off:.3} off the line from its first to its last",
                n + 1
            ));
        }
        let all = |g: &CornerPointGrid| {
            let (nx, ny, nz) = (g.nx, g.ny, g.nz);
            (0..nz).flat_map(move |k| (0..ny).flat_map(move |j| (0..nx).map(move |i| [i, j, k])))
        };
        // A well through its cells' centres (`through_centres`) starts at
        // the mean of its first cell's top corners, on its bilinear top, not
        // always on the top's pieces: in that cell all the same (not the one
        // above), and it ends likewise on its last cell's bottom.
        let centred = well.cells.first().copied().filter(|&c| cpg.live(c));
        let candidates = centred
            .into_iter()
            .chain(all(cpg.g).filter(|&c| cpg.live(c)));
        let Some(start) = cpg.locate(head, candidates).or(centred) else {
            return bad(format!(
                "its path starts at ({:.6}, {:.6}, {:.6}), outside the grid's live cells (a \
                 path is the completed interval: from where the well enters them)",
                first[0], first[1], first[2]
            ));
        };
        let extent = |c: Ijk| {
            let t: Vec<f64> = cpg
                .corners(c)
                .iter()
                .map(|p| (0..3).map(|a| p[a] * u[a]).sum())
                .collect();
            t.iter().fold(f64::MIN, |a, &b| a.max(b)) - t.iter().fold(f64::MAX, |a, &b| a.min(b))
        };
        // a twentieth of the start cell along the axis; through completed
        // cells, of its thickness along it where that is less (thin layers
        // the axis leans through), and each crossing found by bisection
        let thickness = (0..4)
            .map(|n| cpg.corner(start, n)[2] - cpg.corner(start, n + 4)[2])
            .fold(f64::INFINITY, f64::min)
            / u[2].abs().max(1e-3);
        let step = match centred {
            Some(_) => 0.05 * extent(start).min(thickness.max(1e-6 * extent(start))),
            None => 0.05 * extent(start),
        };
        let at = |t: f64| -> [f64; 3] { std::array::from_fn(|a| head[a] + t * u[a]) };
        let mut cells = vec![start];
        let mut cuts = vec![];
        let mut t = 0.0;
        while t < length {
            let next = (t + step).min(length);
            let p = at(next);
            let prev = cells[cells.len() - 1];
            let [i, j, k] = prev;
            let g = cpg.g;
            // the cell before and its neighbours first, then the grid
            let near = (k.saturating_sub(1)..=(k + 1).min(g.nz - 1)).flat_map(move |kk| {
                (j.saturating_sub(1)..=(j + 1).min(g.ny - 1)).flat_map(move |jj| {
                    (i.saturating_sub(1)..=(i + 1).min(g.nx - 1)).map(move |ii| [ii, jj, kk])
                })
            });
            let found = cpg
                .locate(
                    p,
                    std::iter::once(prev).chain(near).filter(|&c| cpg.live(c)),
                )
                .or_else(|| cpg.locate(p, all(g).filter(|&c| cpg.live(c))));
            let found = match (found, centred) {
                (None, Some(_)) if next == length => Some(prev),
                _ => found,
            };
            let Some(c) = found else {
                return bad(format!(
                    "its path leaves the grid (or enters an inactive or pinched-out cell) at \
                     ({:.6}, {:.6}, {:.6}), after cell {}",
                    p[0],
                    p[1],
                    -p[2],
                    one_based(prev)
                ));
            };
            if c != prev {
                // where it leaves prev, to a thousandth of a step
                let (mut a, mut b) = (t, next);
                for _ in 0..centred.map_or(0, |_| 10) {
                    let m = (a + b) / 2.0;
                    match cpg.locate(at(m), [prev]) {
                        Some(_) => a = m,
                        None => b = m,
                    }
                }
                cuts.push((a + b) / 2.0);
                cells.push(c);
            }
            t = next;
        }
        // a crossing within a hundredth of a step of an end is that end: a
        // head or toe a rounding off its cell's face, in the cell beyond
        if centred.is_some() && cuts.first().is_some_and(|&c| c < 0.01 * step) {
            cuts.remove(0);
            cells.remove(0);
        }
        if centred.is_some() && cuts.last().is_some_and(|&c| c > length - 0.01 * step) {
            cuts.pop();
            cells.pop();
        }
        Ok(Path::of(head, u, length, cells, cuts, None))
    }

    /// The grid's flat top (face 4) and bottom (5) the ends lie on, with
    /// their heights.
    pub(super) fn open_faces(&self) -> impl Iterator<Item = (usize, f64)> + '_ {
        [(4, self.open[0]), (5, self.open[1])]
            .into_iter()
            .filter_map(|(f, z)| z.map(|z| (f, z)))
    }

    /// A deviated well: the cells its axis crosses from the head down to
    /// the bottom of the last completed layer, found by steps along it.
    fn walk(
        cpg: &Cpg,
        well: &Well3,
        [i, j]: [usize; 2],
        head: [f64; 3],
        u: [f64; 3],
        [first, last]: [usize; 2],
        open: [Option<f64>; 2],
    ) -> Result<Path> {
        let g = cpg.g;
        // the head column's completed cells: face f's centre less face f+1's
        let across = |f: usize| {
            (first..=last).map(move |k| {
                let (p, q) = (
                    face_centre(cpg, [i, j, k], f),
                    face_centre(cpg, [i, j, k], f + 1),
                );
                [p[0] - q[0], p[1] - q[1], p[2] - q[2]]
            })
        };
        let thickness = across(4).map(|d| d[2]).fold(f64::INFINITY, f64::min);
        // Steps shrink with the axis' slope; near the horizontal they would
        // be too many (a hang at 89 degrees' dip), so they stay above a
        // hundredth of the head cells' thickness and width.
        let width = across(0)
            .chain(across(2))
            .map(|d| d[0].hypot(d[1]))
            .fold(f64::INFINITY, f64::min);
        let step = (0.05 * thickness.max(1e-9) * -u[2]).max(0.01 * thickness.min(width));
        let at = |t: f64| -> [f64; 3] { std::array::from_fn(|a| head[a] + t * u[a]) };
        let all = |k: usize| (0..g.ny).flat_map(move |j| (0..g.nx).map(move |i| [i, j, k]));
        let find = |p: [f64; 3]| -> Option<Ijk> {
            (first..=last).find_map(|k| cpg.locate(p, all(k).filter(|&c| cpg.live(c))))
        };
        let mut cells: Vec<Ijk> = vec![[i, j, first]];
        let mut cuts: Vec<f64> = vec![];
        let mut t = 0.0;
        let length = loop {
            let next = t + step;
            let p = at(next);
            match find(p) {
                Some(c) => {
                    let prev = cells[cells.len() - 1];
                    if c != prev {
                        if c[2] != prev[2] {
                            cuts.push((t + next) / 2.0);
                        }
                        cells.push(c);
                    }
                    t = next;
                }
                None => {
                    // below the last completed layer, or out of the grid
                    let below = cpg.locate(p, (0..g.nz).flat_map(all)).map(|c| c[2] > last);
                    let under_grid = last == g.nz - 1 && open[1].is_some_and(|z| p[2] < z);
                    if below == Some(true) || under_grid {
                        break (t + next) / 2.0;
                    }
                    return Err(Error::Usage(format!(
                        "well {}: its axis leaves the grid (or enters an inactive or pinched-out \
                         cell) at ({:.6}, {:.6}, {:.6}), after cell {}",
                        well.name,
                        p[0],
                        p[1],
                        -p[2],
                        one_based(cells[cells.len() - 1])
                    )));
                }
            }
        };
        Ok(Path::of(head, u, length, cells, cuts, Some(open)))
    }

    /// A path from its axis and the cells it crosses (in any order, any
    /// repeated), with its ends' flat heights, or None for a trajectory.
    fn of(
        head: [f64; 3],
        u: [f64; 3],
        length: f64,
        mut cells: Vec<Ijk>,
        cuts: Vec<f64>,
        open: Option<[Option<f64>; 2]>,
    ) -> Path {
        let head_cell = cells[0];
        cells.sort_unstable();
        cells.dedup();
        Path {
            head,
            u,
            length,
            cells,
            head_cell,
            cuts,
            open: open.unwrap_or([None, None]),
            explicit: open.is_none(),
            leg: None,
            bends: [None; 2],
            max_outer: f64::INFINITY,
        }
    }
}
