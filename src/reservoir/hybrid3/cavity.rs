//! A cavity: the live cells within one cell of some wells' completed
//! cells (wells whose cavities share cells share one); its sides,
//! the grid cells' faces kept whole or split in two triangles alike on
//! both sides; the wells' radial meshes inside, sized to stay clear of
//! its sides and of each other.

use super::cpg::{one_based, Cpg, Ijk};
use super::path::Path;
use super::radial::{End, Knee, Radial};
use super::well::{Hybrid3Options, Well3};
use crate::error::{Error, Result};
use std::collections::{BTreeMap, BTreeSet};

/// A piece of the cavity's sides: its points, and the live cell across.
pub(super) struct Side {
    pub(super) points: Vec<[f64; 3]>,
    pub(super) across: Option<Ijk>,
    /// Whether it lies on the grid's flat top (4) or bottom (5) where a
    /// well's radial mesh ends open.
    pub(super) open: Option<usize>,
    /// Whether the cell across is the cavity's too: a fault inside it.
    pub(super) inner: bool,
    /// Whether it is on a fault (with throw, or one `FAULTS` names).
    pub(super) fault: bool,
}

/// The cells of a cavity and the wells (indices) it holds.
pub(super) struct CavityCells {
    pub(super) cells: BTreeSet<Ijk>,
    pub(super) wells: Vec<usize>,
}

/// The live cells within one cell of a path's cells: the layers above
/// and below, and the columns around as far as `reach`. Where a throw
/// parts those columns, the cells there whose depths overlap the path
/// cell's three layers'.
fn dilate(cpg: &Cpg, path: &Path, reach: usize) -> BTreeSet<Ijk> {
    let g = cpg.g;
    let mut out = BTreeSet::new();
    for &[i, j, k] in &path.cells {
        let (k0, k1) = (k.saturating_sub(1), (k + 1).min(g.nz - 1));
        let cols: Vec<[usize; 2]> = (j.saturating_sub(reach)..=(j + reach).min(g.ny - 1))
            .flat_map(|jj| {
                (i.saturating_sub(reach)..=(i + reach).min(g.nx - 1)).map(move |ii| [ii, jj])
            })
            .collect();
        let inner = |c: [usize; 2], f: usize| match f {
            0 => c[0] > i.saturating_sub(reach),
            1 => c[0] < (i + reach).min(g.nx - 1),
            2 => c[1] > j.saturating_sub(reach),
            _ => c[1] < (j + reach).min(g.ny - 1),
        };
        let faulted = cols
            .iter()
            .any(|&c| (0..4).any(|f| inner(c, f) && cpg.is_thrown(c, f)));
        if faulted {
            let depth = |c: Ijk, n: usize| cpg.g.depth(c[0], c[1], c[2], n);
            let range = |c: Ijk| {
                (0..8).fold([f64::INFINITY, f64::NEG_INFINITY], |[lo, hi], n| {
                    [lo.min(depth(c, n)), hi.max(depth(c, n))]
                })
            };
            let (top, bottom) = (range([i, j, k0])[0], range([i, j, k1])[1]);
            for [ii, jj] in cols {
                for kk in 0..g.nz {
                    let [lo, hi] = range([ii, jj, kk]);
                    if lo < bottom && hi > top && cpg.live([ii, jj, kk]) {
                        out.insert([ii, jj, kk]);
                    }
                }
            }
            continue;
        }
        for kk in k0..=k1 {
            for &[ii, jj] in &cols {
                if cpg.live([ii, jj, kk]) {
                    out.insert([ii, jj, kk]);
                }
            }
        }
    }
    out
}

/// Whether a fault (a throw, or a face FAULTS names) bounds a column of
/// the path's cells: its cavity then takes the columns around, which the
/// fault crosses.
fn beside_fault(cpg: &Cpg, path: &Path) -> bool {
    path.cells
        .iter()
        .any(|&c| (0..4).any(|f| cpg.is_thrown([c[0], c[1]], f) || cpg.on_fault(c, f)))
}

/// Radial meshes up to this many of their head cell's shorter sides fit
/// in their own columns: their cavities take no columns around.
pub(super) const OWN_COLUMN: f64 = 0.4;

/// The shorter side of a well's head cell's top, in map view.
pub(super) fn head_side(cpg: &Cpg, path: &Path) -> f64 {
    cpg.side(path.head_cell)
}

/// Whether a well's cavity takes the columns around its cells: unless its
/// radial mesh, as its own 3 x 3 columns would let it be (in dipping
/// layers it shrinks), fits in its own columns (`OWN_COLUMN`).
pub(super) fn reach(cpg: &Cpg, well: &Well3, path: &Path, opts: &Hybrid3Options) -> usize {
    if opts.outer <= OWN_COLUMN {
        return 0;
    }
    if beside_fault(cpg, path) {
        return 1;
    }
    let cells = dilate(cpg, path, 1);
    let open: Vec<(usize, f64)> = path.open_faces().collect();
    let outer = sides(cpg, &cells, &open)
        .and_then(|sides| radials(cpg, &[well], &[path], &cells, &sides, opts, 1.0))
        .map_or(f64::INFINITY, |r| r.0[0].outer);
    usize::from(outer > OWN_COLUMN * head_side(cpg, path))
}

/// The wells' cavities: completed cells with the layer beyond each end,
/// and the columns around them as far as each well reaches (`reach`);
/// merged where they share a cell. Cavities that only touch stay apart:
/// each transition conforms to the sides between them, which both cut
/// alike (`cpg::pieces`).
pub(super) fn cavities(cpg: &Cpg, paths: &[Path], reach: &[usize]) -> Vec<CavityCells> {
    let sets: Vec<BTreeSet<Ijk>> = paths
        .iter()
        .zip(reach)
        .map(|(p, &r)| dilate(cpg, p, r))
        .collect();
    // union-find over wells
    let mut root: Vec<usize> = (0..paths.len()).collect();
    fn find(root: &mut [usize], a: usize) -> usize {
        let mut a = a;
        while root[a] != a {
            root[a] = root[root[a]];
            a = root[a];
        }
        a
    }
    // (the smaller root becomes the root of both)
    fn join(root: &mut [usize], a: usize, b: usize) {
        let (a, b) = (find(root, a), find(root, b));
        root[a.max(b)] = a.min(b);
    }
    let mut owner: BTreeMap<Ijk, usize> = BTreeMap::new();
    for (w, set) in sets.iter().enumerate() {
        for c in set {
            if let Some(&o) = owner.get(c) {
                join(&mut root, o, w);
            }
        }
        for &c in set {
            owner.entry(c).or_insert(w);
        }
    }
    // a bent well's legs meet at their knees: one cavity
    for w in 1..paths.len() {
        if super::bend::adjacent(&paths[w - 1], &paths[w]) {
            join(&mut root, w - 1, w);
        }
    }
    let mut groups: BTreeMap<usize, CavityCells> = BTreeMap::new();
    for (w, set) in sets.into_iter().enumerate() {
        let r = find(&mut root, w);
        let e = groups.entry(r).or_insert_with(|| CavityCells {
            cells: BTreeSet::new(),
            wells: vec![],
        });
        e.cells.extend(set);
        e.wells.push(w);
    }
    groups.into_values().collect()
}

/// The cavity's sides: each face of a cavity cell whose neighbour is not in
/// the cavity, in pieces.
pub(super) fn sides(cpg: &Cpg, cells: &BTreeSet<Ijk>, open: &[(usize, f64)]) -> Result<Vec<Side>> {
    let mut out = vec![];
    for &c in cells {
        for f in 0..6 {
            let fault = cpg.on_fault(c, f);
            for part in cpg.parts(c, f)? {
                let across = part.across;
                // faces between the cavity's cells are none of its sides,
                // but faults there are (from one side)
                let inner = across.is_some_and(|n| cells.contains(&n));
                if inner && (!(part.thrown || fault) || across.is_some_and(|n| n < c)) {
                    continue;
                }
                let points = part.points;
                let on = open
                    .iter()
                    .find(|&&(ff, z)| {
                        ff == f && across.is_none() && points.iter().all(|p| p[2] == z)
                    })
                    .map(|&(ff, _)| ff);
                out.push(Side {
                    points,
                    across,
                    open: on,
                    inner,
                    fault: part.thrown || fault,
                });
            }
        }
    }
    Ok(out)
}

/// The squared distance from p to triangle abc.
fn dist2_triangle(p: [f64; 3], a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    let sub = |x: [f64; 3], y: [f64; 3]| -> [f64; 3] { std::array::from_fn(|k| x[k] - y[k]) };
    let dot = |x: [f64; 3], y: [f64; 3]| (0..3).map(|k| x[k] * y[k]).sum::<f64>();
    let seg = |a: [f64; 3], b: [f64; 3]| {
        let (ab, ap) = (sub(b, a), sub(p, a));
        let t = (dot(ap, ab) / dot(ab, ab)).clamp(0.0, 1.0);
        let d = sub(ap, ab.map(|x| x * t));
        dot(d, d)
    };
    let n = crate::geom::cross_f(sub(b, a), sub(c, a));
    let nn = dot(n, n);
    if nn > 0.0 {
        let h = dot(sub(p, a), n);
        let q: [f64; 3] = std::array::from_fn(|k| p[k] - h / nn * n[k]);
        // q inside abc: the same side of every edge
        let s = |x: [f64; 3], y: [f64; 3]| dot(crate::geom::cross_f(sub(y, x), sub(q, x)), n);
        if s(a, b) >= 0.0 && s(b, c) >= 0.0 && s(c, a) >= 0.0 {
            return h * h / nn;
        }
    }
    seg(a, b).min(seg(b, c)).min(seg(c, a))
}

/// Whether p lies on a side that is an open end (in map view, on or
/// inside a piece there, exactly).
fn on_open(p: [f64; 3], sides: &[Side]) -> bool {
    let xy = |q: &[f64; 3]| [q[0], q[1]];
    sides.iter().filter(|s| s.open.is_some()).any(|s| {
        let n = s.points.len();
        let turns: Vec<std::cmp::Ordering> = (0..n)
            .map(|k| crate::geom::orient(xy(&s.points[k]), xy(&s.points[(k + 1) % n]), xy(&p)))
            .collect();
        p[2] == s.points[0][2]
            && (turns.iter().all(|o| o.is_ge()) || turns.iter().all(|o| o.is_le()))
    })
}

/// The distance from p to the nearest side that is not an open end (only
/// faults inside the cavity if `inner`).
fn clearance(p: [f64; 3], sides: &[Side], inner: bool) -> f64 {
    sides
        .iter()
        .filter(|s| s.open.is_none() && (s.inner || !inner))
        .flat_map(|s| (1..s.points.len() - 1).map(move |k| (s, k)))
        .map(|(s, k)| dist2_triangle(p, s.points[0], s.points[k], s.points[k + 1]))
        .fold(f64::INFINITY, f64::min)
        .sqrt()
}

/// The shortest distance between two segments (sampled finely enough for
/// a bound on radial meshes).
fn axes_apart(a: &Path, b: &Path) -> f64 {
    let n = 64;
    let at = |p: &Path, t: f64| -> [f64; 3] {
        std::array::from_fn(|k| p.head[k] + t * p.length * p.u[k])
    };
    let mut best = f64::INFINITY;
    for x in 0..=n {
        let pa = at(a, x as f64 / n as f64);
        for y in 0..=n {
            let pb = at(b, y as f64 / n as f64);
            let d = crate::geom::dist_f(pa, pb);
            best = best.min(d);
        }
    }
    best
}

/// Each well's ends: open on the grid's flat top or bottom; else closed by
/// a plug at the completed interval's end where the cavity has a layer
/// beyond it (the plug a quarter of that layer's length along the axis),
/// else at the mid-level of the end layer (the plug a quarter of the half
/// layer beyond).
pub(super) fn ends(cpg: &Cpg, path: &Path, cells: &BTreeSet<Ijk>) -> [End; 2] {
    let first = path
        .cells
        .iter()
        .min_by_key(|c| c[2])
        .copied()
        .unwrap_or([0; 3]);
    let last = path
        .cells
        .iter()
        .max_by_key(|c| c[2])
        .copied()
        .unwrap_or([0; 3]);
    // the layer beyond an end cell, if the cavity holds it: its length
    // along the axis
    let beyond = |c: Ijk, up: bool| -> Option<f64> {
        let k = if up { c[2].checked_sub(1)? } else { c[2] + 1 };
        let n = [c[0], c[1], k];
        cells.contains(&n).then(|| {
            let mean = |f: usize| cpg.face(n, f).iter().map(|p| p[2]).sum::<f64>() / 4.0;
            (mean(4) - mean(5)) / -path.u[2]
        })
    };
    let first_layer = path.cuts.first().copied().unwrap_or(path.length);
    let last_layer = path.length - path.cuts.last().copied().unwrap_or(0.0);
    if path.explicit {
        // a trajectory: a plug beyond each end where the cavity holds what
        // lies a half cell beyond it, else within the end cell
        let inside = |t: f64| {
            let p: [f64; 3] = std::array::from_fn(|a| path.head[a] + t * path.u[a]);
            cpg.locate(p, cells.iter().copied()).is_some()
        };
        // parallel to the end cell's top or bottom where that is 5 to 60
        // degrees off across the axis (thin layers the axis leans through
        // leave a cap across it no room); nearer, across the axis, on its
        // lattice (the wedge layer between a tilted cap and the rings costs
        // orthogonal links: its sites lie on a plane oblique to the axis)
        let tilt = |c: Ijk, f: usize| {
            let n = crate::geom::newell(&cpg.face(c, f));
            let len = crate::geom::dist_f(n, [0.0; 3]);
            let along = crate::geom::dot_f(n, path.u) / len;
            let oblique = along.abs() > 0.5 && along.abs() < 5f64.to_radians().cos();
            oblique.then(|| n.map(|x| x * along.signum() / len))
        };
        let cap = |end: f64, cell: f64, out: f64, face: Option<[f64; 3]>| match inside(
            end + out * cell / 2.0,
        ) {
            true => End::Cap {
                at: end,
                plug: 0.25 * cell,
                tilt: face,
            },
            false => End::Cap {
                at: end - out * cell / 2.0,
                plug: 0.125 * cell,
                tilt: face,
            },
        };
        // the cell that holds the toe
        let toe_cell = || {
            let toe: [f64; 3] = std::array::from_fn(|a| path.head[a] + path.length * path.u[a]);
            cpg.locate(toe, path.cells.iter().copied()).unwrap_or(last)
        };
        // a knee at a bend (placed with the leg across, `bend::chain`)
        let knee = |half: Option<f64>| half.map(|_| End::Knee(Knee::default()));
        return [
            knee(path.bends[0])
                .unwrap_or_else(|| cap(0.0, first_layer, -1.0, tilt(path.head_cell, 4))),
            knee(path.bends[1])
                .unwrap_or_else(|| cap(path.length, last_layer, 1.0, tilt(toe_cell(), 5))),
        ];
    }
    [
        match (path.open[0], beyond(first, true)) {
            (Some(z), _) => End::Open(z),
            (None, Some(len)) => End::Cap {
                at: 0.0,
                plug: 0.25 * len,
                tilt: None,
            },
            (None, None) => End::Cap {
                at: first_layer / 2.0,
                plug: 0.125 * first_layer,
                tilt: None,
            },
        },
        match (path.open[1], beyond(last, false)) {
            (Some(z), _) => End::Open(z),
            (None, Some(len)) => End::Cap {
                at: path.length,
                plug: 0.25 * len,
                tilt: None,
            },
            (None, None) => End::Cap {
                at: path.length - last_layer / 2.0,
                plug: 0.125 * last_layer,
                tilt: None,
            },
        },
    ]
}

/// The wells' radial meshes in a cavity: the outer radius `outer` times
/// the head column's shorter side, at most 0.3 of the way to another
/// well's axis, shrunk until the outer surface stays inside the cavity a
/// quarter of the thinnest completed layer (or half side) from its sides.
/// A bent well's legs here are one chain at one radius (`bend::chain`).
/// `scale` shrinks every starting radius; also returns whether no chain
/// had to shrink from there.
pub(super) fn radials(
    cpg: &Cpg,
    wells: &[&Well3],
    paths: &[&Path],
    cells: &BTreeSet<Ijk>,
    sides: &[Side],
    opts: &Hybrid3Options,
    scale: f64,
) -> Result<(Vec<Radial>, bool)> {
    let mut out: Vec<Option<Radial>> = (0..wells.len()).map(|_| None).collect();
    let mut full = true;
    for chain in chains(paths) {
        let mut outer = f64::INFINITY;
        let mut clear = f64::INFINITY;
        for &n in &chain {
            let (o, c) = room(cpg, wells, paths, n, opts)?;
            outer = outer.min(o);
            clear = clear.min(c);
        }
        outer *= scale;
        let legs: Vec<(&Well3, &Path, [End; 2])> = chain
            .iter()
            .map(|&n| (wells[n], paths[n], ends(cpg, paths[n], cells)))
            .collect();
        // (a radial mesh too wide for its interval, as tilted caps' wedges
        // make it, shrinks as one that does not fit)
        let tilted = legs
            .iter()
            .flat_map(|l| l.2)
            .any(|e| matches!(e, End::Cap { tilt: Some(_), .. }));
        let mut tries = 0;
        let built = loop {
            let rs = match super::bend::chain(&legs, opts, outer) {
                Err(_) if tilted && tries < 40 && outer * 0.8 > 2.0 * wells[chain[0]].radius => {
                    outer *= 0.8;
                    tries += 1;
                    continue;
                }
                built => built?,
            };
            let bad = rs.iter().zip(&chain).find_map(|(r, &n)| {
                misfit(cpg, r, cells, sides, clear).map(|b| (n, r.levels.len(), b))
            });
            match bad {
                None => break rs,
                Some((n, levels, (k, inside, d)))
                    if tries >= 40 || outer * 0.8 <= 2.0 * wells[n].radius =>
                {
                    let how = match inside {
                        true => format!(
                            "comes within {d:.6} of the cavity's sides (it must keep {clear:.6} away)"
                        ),
                        false => "leaves the cavity".to_string(),
                    };
                    return Err(Error::Usage(format!(
                        "well {}: its radial mesh does not fit in its cavity (around cell {}): at \
                         level {} of {}, its outer surface {how}, even at an outer radius of \
                         {outer:.6}",
                        wells[n].name,
                        one_based(paths[n].head_cell),
                        k + 1,
                        levels,
                    )));
                }
                Some(_) => {
                    outer *= 0.8;
                    tries += 1;
                }
            }
        };
        full &= tries == 0;
        for (n, r) in chain.into_iter().zip(built) {
            out[n] = Some(r);
        }
    }
    Ok((out.into_iter().flatten().collect(), full))
}

/// The wells in a cavity as chains: a bent well's consecutive legs
/// together, in order; every other well alone.
fn chains(paths: &[&Path]) -> Vec<Vec<usize>> {
    let mut out: Vec<Vec<usize>> = vec![];
    for (n, p) in paths.iter().enumerate() {
        match out.last_mut() {
            Some(c) if super::bend::adjacent(paths[c[c.len() - 1]], p) => c.push(n),
            _ => out.push(vec![n]),
        }
    }
    out
}

/// A well's room: the outer radius it may start from (its head column's
/// shorter side times `outer`, at most 0.3 of the way to another well's
/// axis, 0.45 to its own legs beyond the next, and what its knees fit)
/// and the clearance its outer surface keeps from the cavity's
/// sides (a quarter of the thinnest completed cell, or of half a side).
fn room(
    cpg: &Cpg,
    wells: &[&Well3],
    paths: &[&Path],
    n: usize,
    opts: &Hybrid3Options,
) -> Result<(f64, f64)> {
    let (well, path) = (wells[n], paths[n]);
    let side = head_side(cpg, path);
    // (a leg of a bent well: no larger than its knees fit)
    let mut outer = (opts.outer * side).min(path.max_outer);
    for (m, other) in paths.iter().enumerate() {
        if m != n && !super::bend::adjacent(path, other) {
            let apart = axes_apart(path, other);
            if apart <= 2.0 * well.radius {
                return Err(Error::Usage(format!(
                    "wells {} and {}: their axes pass within {apart:.6} of each other: their \
                     radial meshes would overlap",
                    well.name, wells[m].name
                )));
            }
            // (a leg of the same well further on: only apart, the legs
            // between fill the room)
            let share = match (path.leg, other.leg) {
                (Some((a, _)), Some((b, _))) if a == b => 0.45,
                _ => 0.3,
            };
            outer = outer.min(share * apart);
        }
    }
    // the thinnest completed cell, by its corners' thicknesses (those
    // pinched to nothing left out: the clearance must be positive)
    let thinnest = path
        .cells
        .iter()
        .flat_map(|&c| (0..4).map(move |n| cpg.corner(c, n)[2] - cpg.corner(c, n + 4)[2]))
        .filter(|&t| t > 0.0)
        .fold(side / 2.0, f64::min);
    Ok((outer, 0.25 * (side / 2.0).min(thinnest)))
}

/// Where a radial mesh does not fit: the first point of its outer surface
/// outside the cavity or nearer its sides than `clear` (its level, whether
/// inside, its distance to them).
fn misfit(
    cpg: &Cpg,
    r: &Radial,
    cells: &BTreeSet<Ijk>,
    sides: &[Side],
    clear: f64,
) -> Option<(usize, bool, f64)> {
    let ends = r.ends;
    (0..r.levels.len())
        .flat_map(|k| (0..r.m).map(move |s| (k, s)))
        .find_map(|(k, s)| {
            let p = r.surface(s, k);
            let open = match (k, ends) {
                (0, [End::Open(_), _]) => true,
                (k, [_, End::Open(_)]) => k + 1 == r.levels.len(),
                _ => false,
            };
            // at an open end, on the cavity's face there
            let inside = match open {
                true => on_open(p, sides),
                false => cpg.locate(p, cells.iter().copied()).is_some(),
            };
            let d = clearance(p, sides, false);
            (!inside || d < clear).then_some((k, inside, d))
        })
        .or_else(|| {
            // a fault inside the cavity may pass between the
            // outer surface's points: the disc must clear it
            (0..r.levels.len()).find_map(|k| {
                let d = clearance(r.axis_at(k), sides, true) - r.outer;
                (d < clear).then_some((k, true, d))
            })
        })
}
