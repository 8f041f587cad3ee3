//! The transition stage: the constraint complex of the cavities (their
//! sides, faults inside them, the wells' outer polygons with holes) meshed
//! by the 2D core; where system 3 is infeasible the cavities beside the
//! failing segments grow by a ring of cells and the problem is redone.

use super::map::{clip_to_cavity, distance_to_polygon, fault_edges, to_segment};
use super::wells::{polygon_point, radial_site, site_radii, Placed};
use super::{HybridOptions, Layer};
use crate::backend::Backend;
use crate::complex::Complex;
use crate::conform::{conform2, Outcome, D2};
use crate::error::{Error, Result};
use crate::options::Options;
use crate::FastMap;

/// Times a cavity may grow before system 3's infeasibility is an error.
const MAX_GROWTH: usize = 4;

/// The transition problem of the current cavities.
struct Built {
    cx: Complex,
    /// Per segment, the cavity column it bounds.
    owner: Vec<usize>,
    /// Pieces of cavity sides on the mesh's outer boundary.
    outer_pieces: Vec<(u32, u32)>,
    fault_segments: usize,
}

/// The certified transition mesh and what it took.
pub(super) struct Transition {
    pub(super) cx: Complex,
    pub(super) out: Outcome<D2>,
    pub(super) outer_pieces: Vec<(u32, u32)>,
    pub(super) fault_segments: usize,
    /// Cavities grown because system 3 was infeasible.
    pub(super) notes: Vec<String>,
}

/// Pieces for a side that may be split: none longer than `share` of its
/// distance to the nearest well polygon (at most 1, so that it stays
/// Gabriel), nor than `longest`.
fn pieces_near_wells(
    placed: &[Placed],
    pp: [f64; 2],
    pq: [f64; 2],
    share: f64,
    longest: f64,
) -> usize {
    let gap = share
        * placed
            .iter()
            .map(|w| to_segment(w.centre, [pp, pq]) - w.radii.last().unwrap())
            .fold(f64::INFINITY, f64::min);
    let gap = gap.min(longest);
    let len = (pq[0] - pp[0]).hypot(pq[1] - pp[1]);
    ((len / gap.max(len / 64.0)).ceil() as usize).clamp(1, 64)
}

/// Where a side a -> b is cut (shares of it, strictly inside) so that
/// each piece is no longer than `share` of its own distance to the nearest
/// well polygon: short near the wells, longer away from them (at most 64
/// pieces). Marched from a, then scaled to end at b, so pieces only shrink.
fn graded_cuts(placed: &[Placed], a: [f64; 2], b: [f64; 2], share: f64) -> Vec<f64> {
    let len = (b[0] - a[0]).hypot(b[1] - a[1]);
    let at = |t: f64| [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
    // the distance to the nearest well polygon over the part [t0, t1]
    let gap = |t0: f64, t1: f64| {
        placed
            .iter()
            .map(|w| to_segment(w.centre, [at(t0), at(t1)]) - w.radii.last().unwrap())
            .fold(f64::INFINITY, f64::min)
    };
    let (mut t, mut cuts) = (0.0, vec![]);
    while t < 1.0 && cuts.len() < 64 {
        let mut step = (share * gap(t, t) / len).max(1.0 / 64.0);
        for _ in 0..4 {
            step = (share * gap(t, (t + step).min(1.0)) / len).max(1.0 / 64.0);
        }
        t += step;
        cuts.push(t);
    }
    let total = cuts.pop().unwrap_or(1.0).max(1.0);
    cuts.into_iter().map(|c| c / total).collect()
}

/// The side u - v cut at shares `cuts` (increasing, strictly inside).
fn split_at(cx: &mut Complex, u: u32, v: u32, cuts: &[f64]) -> Vec<(u32, u32)> {
    let (pu, pv) = (cx.points[u as usize], cx.points[v as usize]);
    let mut ids = vec![u];
    for t in cuts {
        ids.push(push_point(
            cx,
            [pu[0] + t * (pv[0] - pu[0]), pu[1] + t * (pv[1] - pu[1])],
        ));
    }
    ids.push(v);
    ids.windows(2).map(|w| (w[0], w[1])).collect()
}

/// A new point of the complex, its id.
fn push_point(cx: &mut Complex, x: [f64; 2]) -> u32 {
    cx.points.push(x);
    cx.points.len() as u32 - 1
}

/// The side u - v cut into equal pieces (new vertices in between).
fn split(cx: &mut Complex, u: u32, v: u32, pieces: usize) -> Vec<(u32, u32)> {
    split_ends(cx, u, v, pieces, [0.0; 2])
}

/// The side u - v with pieces of `ends` (shares of it, 0 for none) cut off
/// at its ends, the rest cut into equal pieces.
fn split_ends(cx: &mut Complex, u: u32, v: u32, pieces: usize, ends: [f64; 2]) -> Vec<(u32, u32)> {
    let (t0, t1) = (ends[0], 1.0 - ends[1]);
    // the ends exactly (t0 + (t1 - t0) can round short of t1)
    let mut ts: Vec<f64> = (0..=pieces)
        .map(|k| match k {
            0 => t0,
            k if k == pieces => t1,
            k => t0 + (t1 - t0) * k as f64 / pieces as f64,
        })
        .collect();
    ts.retain(|&t| t > 0.0 && t < 1.0);
    split_at(cx, u, v, &ts)
}

/// A cavity side a -> b (pillars, their vertices and points) as segments:
/// in `pieces` with `ends` cut off (`split_ends`); where an end's pillar
/// is a reflex one moved in whose own point lies on the side
/// (`HybridOptions::inner_pillars`), first cut there (the point shared,
/// in `inner`, with the column sides inside that start at that pillar).
fn side_parts(
    cx: &mut Complex,
    opts: &HybridOptions,
    [(p, u, pp), (q, v, pq)]: [(u32, u32, [f64; 2]); 2],
    pieces: usize,
    ends: [f64; 2],
    inner: &mut FastMap<u32, u32>,
) -> Vec<(u32, u32)> {
    let own = |r: u32| {
        let x = opts.inner_pillars.iter().find(|x| x.0 == r as usize)?.1;
        let (dx, dy) = (pq[0] - pp[0], pq[1] - pp[1]);
        let t = ((x[0] - pp[0]) * dx + (x[1] - pp[1]) * dy) / (dx * dx + dy * dy);
        (t > 0.0 && t < 1.0 && on_line(x, pp, pq)).then_some((x, t))
    };
    let mut at = |cx: &mut Complex, r: u32, x: [f64; 2]| {
        *inner.entry(r).or_insert_with(|| push_point(cx, x))
    };
    match (own(p), own(q)) {
        (Some((x, t)), _) => {
            let id = at(cx, p, x);
            let mut out = vec![(u, id)];
            out.extend(split_ends(cx, id, v, pieces, [0.0, ends[1] / (1.0 - t)]));
            out
        }
        (None, Some((x, t))) => {
            let id = at(cx, q, x);
            let mut out = split_ends(cx, u, id, pieces, [ends[0] / t, 0.0]);
            out.push((id, v));
            out
        }
        _ => split_ends(cx, u, v, pieces, ends),
    }
}

/// Whether point m lies on the line through a and b (within 1e-9 of |b - a|).
fn on_line(m: [f64; 2], a: [f64; 2], b: [f64; 2]) -> bool {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    (dx * (m[1] - a[1]) - dy * (m[0] - a[0])).abs() <= 1e-9 * (dx * dx + dy * dy)
}

/// A layered section's corner pieces: at a pillar where the cavity has one
/// column of the four (a convex corner of its outline), the side's share
/// cut off there, so that the corner's triangle is in the weighted
/// Delaunay triangulation and one cell can own the corner (`corner_sites`):
/// an eighth of the side, within half the distance to the nearest well
/// polygon.
fn corner_ends(layer: &Layer, cavity: &[bool], placed: &[Placed], (p, q): (u32, u32)) -> [f64; 2] {
    let (nx, ny) = (layer.nx, layer.ny);
    let convex = |pid: u32| {
        let (pi, pj) = (pid as usize % (nx + 1), pid as usize / (nx + 1));
        let around = [(0, 0), (1, 0), (0, 1), (1, 1)]
            .iter()
            .filter(|(di, dj)| {
                let (i, j) = ((pi + di).wrapping_sub(1), (pj + dj).wrapping_sub(1));
                i < nx && j < ny && cavity[layer.col(i, j)]
            })
            .count();
        around == 1
    };
    let (pp, pq) = (layer.view.pillar[p as usize], layer.view.pillar[q as usize]);
    let len = (pq[0] - pp[0]).hypot(pq[1] - pp[1]);
    [p, q].map(|x| {
        if !convex(x) {
            return 0.0;
        }
        let at = layer.view.pillar[x as usize];
        let gap = placed
            .iter()
            .map(|w| (w.centre[0] - at[0]).hypot(w.centre[1] - at[1]) - w.radii.last().unwrap())
            .fold(f64::INFINITY, f64::min);
        (len / 8.0).min(0.5 * gap) / len
    })
}

/// The longest piece a split side may have (layered sections): two outer
/// radii of the smallest radial mesh. In a column nearly a triangle with
/// the well near its long side (emerald (12, 39)), pieces as long as their
/// distance to the well left system 3 infeasible at every radius; so
/// short, feasible. Unbounded where sides are not split.
fn longest_piece(placed: &[Placed], opts: &HybridOptions) -> f64 {
    match opts.split_sides {
        true => {
            2.0 * placed
                .iter()
                .map(|w| *w.radii.last().unwrap())
                .fold(f64::INFINITY, f64::min)
        }
        false => f64::INFINITY,
    }
}

/// Each well's outer polygon (m sides, anchored at the outer ring's sites
/// across its chords, owned by the well's column), with a hole at it.
fn well_polygons(
    cx: &mut Complex,
    anchors: &mut Vec<Option<[f64; 2]>>,
    owner: &mut Vec<usize>,
    placed: &[Placed],
    well_column: &[usize],
    m: usize,
) {
    for (w, &c) in placed.iter().zip(well_column) {
        let r = *w.radii.last().unwrap();
        // the outer ring's sites, across the chords
        let rho = *site_radii(&w.radii, m).last().unwrap();
        let first = cx.points.len() as u32;
        for s in 0..m {
            cx.points.push(polygon_point(w.centre, r, s, m));
        }
        for s in 0..m {
            cx.segments
                .push([first + s as u32, first + ((s + 1) % m) as u32]);
            anchors.push(Some(radial_site(w.centre, rho, s, m)));
            owner.push(c);
        }
        cx.holes.push(w.centre);
    }
}

/// The constraint complex of the cavities: column sides between a cavity
/// column and anything else (anchored at the reservoir site across), faults
/// inside cavities, and the wells' outer polygons (anchored at the radial
/// sites across), with a hole at each well.
fn complex(
    layer: &Layer,
    placed: &[Placed],
    cavity: &[bool],
    well_column: &[usize],
    opts: &HybridOptions,
) -> Built {
    let (grid, k, view, nx, ny) = (layer.grid, layer.k, &layer.view, layer.nx, layer.ny);
    let col = |i: usize, j: usize| layer.col(i, j);
    let m = opts.sectors;
    let mut cx = Complex::default();
    let mut owner = vec![]; // per segment, the cavity column it bounds
    let mut anchors = vec![]; // per segment, the site across it
    let mut outer_pieces: Vec<(u32, u32)> = vec![]; // on the outer boundary
    let mut fault_segments = 0;
    let longest = longest_piece(placed, opts);
    // reflex pillars' own points on the outline (`inner_pillars`)
    let mut inner: FastMap<u32, u32> = FastMap::default();
    let mut vid: FastMap<u32, u32> = FastMap::default();
    let mut vertex = |cx: &mut Complex, p: u32| -> u32 {
        *vid.entry(p).or_insert_with(|| {
            cx.points.push(view.pillar[p as usize]);
            cx.points.len() as u32 - 1
        })
    };
    for j in 0..ny {
        for i in 0..nx {
            if !cavity[col(i, j)] {
                continue;
            }
            let sides = [
                ((i, j.wrapping_sub(1)), (view.pid(i, j), view.pid(i + 1, j))),
                ((i + 1, j), (view.pid(i + 1, j), view.pid(i + 1, j + 1))),
                ((i, j + 1), (view.pid(i + 1, j + 1), view.pid(i, j + 1))),
                ((i.wrapping_sub(1), j), (view.pid(i, j + 1), view.pid(i, j))),
            ];
            for ((a, b), (p, q)) in sides {
                if a < nx && b < ny && cavity[col(a, b)] {
                    continue;
                }
                let (u, v) = (vertex(&mut cx, p), vertex(&mut cx, q));
                // A side on the mesh's outer boundary (no cell across)
                // may take extra vertices: split it into pieces no
                // longer than its distance to the nearest well polygon,
                // so that a well near the edge does not make system 3
                // infeasible.
                let outer_side = !(a < nx && b < ny && grid.active(a, b, k));
                let (pp, pq) = (view.pillar[p as usize], view.pillar[q as usize]);
                let pieces = if outer_side || opts.split_sides {
                    pieces_near_wells(placed, pp, pq, 1.0, longest)
                } else {
                    1
                };
                // The reservoir cell across: its site should be on the
                // dual line of each piece (orthogonal interface); a
                // layered section keeps no reservoir cells.
                let across = (!outer_side && !opts.layered_section).then(|| view.centroid(a, b));
                let ends = match opts.corner_cells {
                    true => corner_ends(layer, cavity, placed, (p, q)),
                    false => [0.0; 2],
                };
                let sides = [(p, u, pp), (q, v, pq)];
                for (from, to) in side_parts(&mut cx, opts, sides, pieces, ends, &mut inner) {
                    cx.segments.push([from, to]);
                    anchors.push(across);
                    owner.push(col(i, j));
                    if outer_side {
                        outer_pieces.push((from, to));
                    }
                }
            }
        }
    }
    // Faults (and, where asked, column sides) between two cavity columns
    // become chains of segments with free ends inside the cavity (sides
    // between a cavity column and another already are segments). Inside
    // a cavity a side may take extra vertices (cells on both sides are
    // transition cells): pieces no longer than its distance to the nearest
    // well polygon.
    let own: FastMap<u32, [f64; 2]> = inner
        .iter()
        .map(|(&r, &id)| (r, cx.points[id as usize]))
        .collect();
    // a side inside from reflex pillar r to pillar o starts at r's own
    // point where the moved pillar lies off its line (a side that runs on
    // along the outline's piece there keeps the moved pillar)
    let pos = |r: u32, o: u32| -> ([f64; 2], bool) {
        let (m, b) = (view.pillar[r as usize], view.pillar[o as usize]);
        match own.get(&r) {
            Some(&x) if !on_line(m, x, b) => (x, true),
            _ => (m, false),
        }
    };
    let at_side = |r: u32, o: u32| pos(r, o).0;
    for (p, q, home, fault, [t0, t1]) in inner_sides(layer, placed, cavity, opts, &at_side) {
        let ((pp, own_p), (pq, own_q)) = (pos(p, q), pos(q, p));
        let at = |t: f64| [pp[0] + t * (pq[0] - pp[0]), pp[1] + t * (pq[1] - pp[1])];
        // a part's ends: the pillars, or new points where it is cut
        let mut end = |cx: &mut Complex, t: f64, pillar: u32, own: bool| match t == 0.0 || t == 1.0
        {
            true if own => inner[&pillar],
            true => vertex(cx, pillar),
            false => push_point(cx, at(t)),
        };
        let (u, v) = (end(&mut cx, t0, p, own_p), end(&mut cx, t1, q, own_q));
        let share = opts.piece_share.min(1.0);
        let cuts: Vec<f64> = match opts.layered_section && !fault && !opts.in_column {
            // radial meshes over columns: column sides graded from them
            true => graded_cuts(placed, at(t0), at(t1), share),
            false => {
                let n = pieces_near_wells(placed, at(t0), at(t1), share, f64::INFINITY);
                (1..n).map(|k| k as f64 / n as f64).collect()
            }
        };
        for (from, to) in split_at(&mut cx, u, v, &cuts) {
            cx.segments.push([from, to]);
            anchors.push(None);
            owner.push(home);
            fault_segments += usize::from(fault);
        }
    }
    fault_segments += fault_chains(
        layer,
        placed,
        cavity,
        well_column[0],
        opts,
        &mut cx,
        &mut anchors,
        &mut owner,
    );
    well_polygons(&mut cx, &mut anchors, &mut owner, placed, well_column, m);
    let cx = Complex {
        holes: cx.holes,
        anchors,
        ..Complex::new(cx.points, cx.segments)
    };
    Built {
        cx,
        owner,
        outer_pieces,
        fault_segments,
    }
}

/// Fault polylines: the parts inside cavities, pulled back a quarter
/// cell from where they leave one, so that they end inside it, as
/// segments (their cavity column `home_column` where none holds their
/// start); how many.
#[allow(clippy::too_many_arguments)]
fn fault_chains(
    layer: &Layer,
    placed: &[Placed],
    cavity: &[bool],
    home_column: usize,
    opts: &HybridOptions,
    cx: &mut Complex,
    anchors: &mut Vec<Option<[f64; 2]>>,
    owner: &mut Vec<usize>,
) -> usize {
    let (nx, ny) = (layer.nx, layer.ny);
    let quad_points = |i: usize, j: usize| layer.quad_points(i, j);
    let typical_side = placed.iter().map(|w| w.reach).fold(f64::INFINITY, f64::min);
    let mut added = 0;
    let boundary_sides: Vec<[[f64; 2]; 2]> = cx
        .segments
        .iter()
        .map(|s| [cx.points[s[0] as usize], cx.points[s[1] as usize]])
        .collect();
    let cavity_column_at = |x: [f64; 2]| {
        (0..nx * ny)
            .find(|&c| cavity[c] && distance_to_polygon(x, &quad_points(c % nx, c / nx)) == 0.0)
    };
    let in_cavity_at = |x: [f64; 2]| cavity_column_at(x).is_some();
    for line in &opts.fault_lines {
        for chain in clip_to_cavity(line, &boundary_sides, &in_cavity_at, 0.5 * typical_side) {
            // the cavity the chain is in, should it need to grow
            let home = cavity_column_at(chain[0]).unwrap_or(home_column);
            let mut prev: Option<u32> = None;
            for x in chain {
                let id = push_point(cx, x);
                if let Some(p) = prev {
                    let pieces =
                        pieces_near_wells(placed, cx.points[p as usize], x, 1.0, f64::INFINITY);
                    for (from, to) in split(cx, p, id, pieces) {
                        cx.segments.push([from, to]);
                        anchors.push(None);
                        owner.push(home);
                        added += 1;
                    }
                }
                prev = Some(id);
            }
        }
    }
    added
}

/// The transition mesh, the cavities grown (at most MAX_GROWTH times)
/// while system 3 is infeasible.
pub(super) fn solve<B: Backend + ?Sized>(
    backend: &B,
    layer: &Layer,
    placed: &[Placed],
    cavity: &mut Vec<bool>,
    opts: &HybridOptions,
    tell: &dyn Fn(&str, usize, usize),
) -> Result<Transition> {
    let well_column: Vec<usize> = placed
        .iter()
        .map(|w| layer.col(w.column.0, w.column.1))
        .collect();
    let mut notes = vec![];
    let mut give_up = false;
    // sites left outside by relocation (not an infeasible system 3, which
    // grows the cavity): the mesh is kept with them where that is allowed
    let mut outside = false;
    loop {
        let Built {
            cx,
            owner,
            outer_pieces,
            fault_segments,
        } = complex(layer, placed, cavity, &well_column, opts);
        tell("transition mesh (attempt)", notes.len() + 1, MAX_GROWTH + 1);
        let allow = opts.allow_sites_outside && (give_up || outside);
        let options = Options {
            allow_sites_outside: allow,
            // a layered section's prisms lean off the walls: each corner
            // of a cavity then belongs to one cell
            corner_sites: opts.corner_cells,
            ..Default::default()
        };
        match conform2(backend, &cx, &options) {
            Ok(out) => {
                return Ok(Transition {
                    cx,
                    out,
                    outer_pieces,
                    fault_segments,
                    notes,
                })
            }
            Err(Error::SegmentsMissTheirDuals { segments, .. }) if !give_up => {
                let label = layer.components(cavity);
                let grown: crate::FastSet<usize> =
                    segments.iter().map(|&s| label[owner[s as usize]]).collect();
                let names: Vec<String> = placed
                    .iter()
                    .zip(&well_column)
                    .filter(|(_, &c)| grown.contains(&label[c]))
                    .map(|(w, _)| w.name.clone())
                    .collect();
                let before = cavity.clone();
                layer.grow(cavity, &|c| grown.contains(&label[c]));
                let changed = *cavity != before;
                notes.push(if changed {
                    format!(
                        "system 3 infeasible for {} segments: the cavity around {} grew by a ring of cells",
                        segments.len(),
                        if names.is_empty() { "no well".to_string() } else { names.join(", ") }
                    )
                } else {
                    format!(
                        "system 3 infeasible for {} segments and the cavity cannot grow (grid edge or inactive cells){}",
                        segments.len(),
                        if opts.allow_sites_outside { ": sites outside their cells allowed" } else { "" }
                    )
                });
                give_up = !changed || notes.len() >= MAX_GROWTH;
                if give_up && !opts.allow_sites_outside {
                    return Err(Error::SitesOutsideCells {
                        sites: vec![format!(
                            "{}; segments {:?} cannot cross their dual edges",
                            notes.last().expect("just pushed"),
                            segments
                        )],
                        crowding: vec![],
                    });
                }
            }
            Err(Error::SitesOutsideCells { .. }) if opts.allow_sites_outside && !allow => {
                outside = true;
            }
            Err(e) => return Err(e),
        }
    }
}

/// Pillar edges between two cavity columns that are constraints: (pillars,
/// the column they bound, whether a fault's, the part of p -> q taken):
/// the faults', then where asked the other column sides, their parts
/// beyond 1.25 outer radii of every well (layered 3D cavities: each cell
/// then lies in one column).
fn inner_sides(
    layer: &Layer,
    placed: &[Placed],
    cavity: &[bool],
    opts: &HybridOptions,
    pos: &dyn Fn(u32, u32) -> [f64; 2],
) -> Vec<(u32, u32, usize, bool, [f64; 2])> {
    let (view, nx, ny) = (&layer.view, layer.nx, layer.ny);
    let col = |i: usize, j: usize| layer.col(i, j);
    let in_cavity = |c: (usize, usize)| c.0 < nx && c.1 < ny && cavity[col(c.0, c.1)];
    let mut seen = crate::FastSet::default();
    let mut out = vec![];
    for (p, q, a, b) in fault_edges(layer.grid, layer.k, view) {
        if in_cavity(a) && in_cavity(b) && seen.insert((p.min(q), p.max(q))) {
            out.push((p, q, col(a.0, a.1), true, [0.0, 1.0]));
        }
    }
    if !opts.layered_section {
        return out;
    }
    for j in 0..ny {
        for i in (0..nx).filter(|&i| cavity[col(i, j)]) {
            for (a, (p, q)) in [
                ((i + 1, j), (view.pid(i + 1, j), view.pid(i + 1, j + 1))),
                ((i, j + 1), (view.pid(i, j + 1), view.pid(i + 1, j + 1))),
            ] {
                let (pp, pq) = (pos(p, q), pos(q, p));
                if in_cavity(a) && seen.insert((p.min(q), p.max(q))) {
                    for part in clear_of_wells(placed, pp, pq) {
                        out.push((p, q, col(i, j), false, part));
                    }
                }
            }
        }
    }
    out
}

/// The parts [t0, t1] of segment a -> b beyond 1.25 outer radii of every
/// well (but where it only grazes that circle, by under a tenth of it),
/// each at least half of it: a shorter stub from the cavity's outline
/// leaves slivers along it and a cluster of small cells at its free end
/// (SPE9 with radial meshes over columns: 2,000 of 8,200 transition cells),
/// and the cells there may as well reach over the column side.
fn clear_of_wells(placed: &[Placed], a: [f64; 2], b: [f64; 2]) -> Vec<[f64; 2]> {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let len2 = dx * dx + dy * dy;
    let mut parts: Vec<[f64; 2]> = vec![[0.0, 1.0]];
    for w in placed {
        let r = 1.25 * *w.radii.last().unwrap_or(&0.0);
        if len2 == 0.0 || distance_to_segment(w.centre, a, b) > r {
            continue;
        }
        // |a + t d - c|^2 = r^2
        let (ex, ey) = (a[0] - w.centre[0], a[1] - w.centre[1]);
        let (bh, c) = (
            (ex * dx + ey * dy) / len2,
            (ex * ex + ey * ey - r * r) / len2,
        );
        let root = (bh * bh - c).max(0.0).sqrt();
        let (s0, s1) = (-bh - root, -bh + root);
        // a line that only grazes the circle stays whole (cut there, its
        // two parts would share their end)
        if s1 - s0 < 0.1 {
            continue;
        }
        parts = parts
            .into_iter()
            .flat_map(|[t0, t1]| [[t0, t1.min(s0)], [t0.max(s1), t1]])
            .filter(|[t0, t1]| t1 - t0 >= 0.5)
            .collect();
    }
    parts
}

/// The distance from x to segment a-b.
fn distance_to_segment(x: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let len2 = dx * dx + dy * dy;
    let t = if len2 > 0.0 {
        (((x[0] - a[0]) * dx + (x[1] - a[1]) * dy) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (x[0] - a[0] - t * dx).hypot(x[1] - a[1] - t * dy)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn column_sides_are_cut_clear_of_wells() {
        let well = |x: f64| Placed {
            name: "W".into(),
            centre: [x, 1.0],
            radii: vec![0.1, 2.0],
            reach: 2.0,
            column: (0, 0),
        };
        // 1.25 outer radii: 2.5 around (x, 1), 1 from the side: 2.29 each
        // way; a part under half the side is dropped (a stub)
        let d = (2.5f64 * 2.5 - 1.0).sqrt() / 10.0;
        let parts = clear_of_wells(&[well(2.0)], [0.0, 0.0], [10.0, 0.0]);
        assert_eq!(parts.len(), 1);
        assert!((parts[0][0] - (0.2 + d)).abs() < 1e-12 && parts[0][1] == 1.0);
        assert!(clear_of_wells(&[well(5.0)], [0.0, 0.0], [10.0, 0.0]).is_empty());
        // a far well leaves all of it
        let all = clear_of_wells(&[well(50.0)], [0.0, 0.0], [10.0, 0.0]);
        assert_eq!(all, vec![[0.0, 1.0]]);
        // a side at 1.25 outer radii, or grazing that circle, stays whole
        // (the 3D Thiem block's own column at 0.4 of its side: cut at the
        // tangent point, its two parts shared an end, duplicate vertices)
        let side = |y: f64| clear_of_wells(&[well(5.0)], [0.0, y], [10.0, y]);
        assert_eq!(side(3.5), vec![[0.0, 1.0]]);
        assert_eq!(side(3.49), vec![[0.0, 1.0]]);
        assert!(side(3.0).is_empty());
    }

    #[test]
    fn a_side_cut_off_at_one_end_ends_at_its_other_end() {
        // 0.0525 + 0.9475 rounds short of 1: the last piece ended 8e-14
        // before the side's end, a segment the mesher cannot take
        let mut cx = Complex {
            points: vec![
                [459.2356040870743, -247.8260870391841],
                [459.2356040870743, 52.17391296081592],
            ],
            ..Default::default()
        };
        let parts = split_ends(&mut cx, 0, 1, 6, [0.052466947260185935, 0.0]);
        assert_eq!(parts.len(), 7);
        assert_eq!(parts.last().unwrap().1, 1);
        let short = parts.iter().map(|&(a, b)| {
            let (p, q) = (cx.points[a as usize], cx.points[b as usize]);
            (q[0] - p[0]).hypot(q[1] - p[1])
        });
        assert!(short.fold(f64::INFINITY, f64::min) > 15.0);
    }

    #[test]
    fn a_reflex_pillars_own_point_cuts_the_side_through_it() {
        // the side from a reflex pillar moved to (16, 0) on to (300, 0):
        // the pillar's own point at (0, 0) lies off it, and leaves it
        // whole; at (20, 0) it cuts it (shared with the sides inside)
        let mut cx = Complex {
            points: vec![[16.0, 0.0], [300.0, 0.0]],
            ..Default::default()
        };
        let at = |x: f64| HybridOptions {
            inner_pillars: vec![(7, [x, 0.0])],
            ..Default::default()
        };
        let ends = [(7, 0, [16.0, 0.0]), (9, 1, [300.0, 0.0])];
        let mut inner = FastMap::default();
        assert_eq!(
            side_parts(&mut cx, &at(0.0), ends, 1, [0.0; 2], &mut inner),
            vec![(0, 1)]
        );
        assert!(inner.is_empty());
        let parts = side_parts(&mut cx, &at(20.0), ends, 2, [0.0; 2], &mut inner);
        assert_eq!(parts.len(), 3);
        assert_eq!(parts[0], (0, inner[&7]));
        assert_eq!(cx.points[inner[&7] as usize], [20.0, 0.0]);
        assert!(on_line([20.0, 0.0], [0.0, 0.0], [300.0, 0.0]));
    }
}
