//! The 3D hybrid mesh (issues 6 and 24): a corner-point grid, wells
//! (vertical or deviated, each along its completed layers) with radial
//! meshes of rings x sectors x layers, a cavity of the live cells within
//! one cell of each well's completed cells (cavities that touch merge),
//! and a conforming orthogonal transition mesh (`conform3`) between the
//! cavity's sides and the wells' outer surfaces. The sides are the grid
//! cells' faces, each kept whole where it is planar and convex, else two
//! triangles along a diagonal that the reservoir cell across carries too
//! (no hanging faces); at a fault's throw, cut into the overlaps with the
//! cells across (`sheet`), which are constraint facets in a cavity, inside
//! it where the fault crosses it. A radial mesh ends open where it meets
//! its column's flat top or bottom (its outline a window in the face
//! there, the transition cut at it), else closed by a plug inside the
//! cavity. A vertical well's layers are horizontal, at its axis' crossings
//! of the grid's layers; a deviated well's are slabs across its axis,
//! exact rectangles on a lattice (`lattice`); a trajectory that bends is
//! meshed as its straight legs joined by mitred knees (`bend`). Built in stages: the corner-point
//! cells (`cpg`, `sheet`), each well's completed interval (`path`), the
//! cavities and the radial meshes in them (`cavity`, `radial`), each
//! cavity's complex and certified transition (`complex`, in parallel), the
//! assembly (`assembly`).

mod assembly;
mod bend;
mod cavity;
mod complex;
mod cpg;
mod lattice;
mod layered;
mod path;
mod radial;
mod refine;
mod report;
mod sheet;
mod slivers;
mod stats;
mod well;

pub use report::{CavityReport, Connections, Hybrid3, Hybrid3Report, LayeredCavity, SectionReport};
pub use well::{Hybrid3Options, Section, Well3};

use crate::backend::Backend;
use crate::conform::D3;
use crate::error::{Error, Result};
use crate::reservoir::CornerPointGrid;
use rayon::prelude::*;

/// Builds the 3D hybrid mesh around the wells: their cavities meshed in
/// parallel, then assembled.
pub fn build<B: Backend + ?Sized>(
    backend: &B,
    g: &CornerPointGrid,
    wells: &[Well3],
    opts: &Hybrid3Options,
) -> Result<Hybrid3> {
    let cpg = cpg::Cpg::new(g);
    if wells.is_empty() {
        return Err(Error::Usage("the 3D hybrid needs a well".into()));
    }
    // what the completions leave out (inactive, pinched-out cells), said
    let mut notes = vec![];
    for w in wells.iter().filter(|w| w.path.is_none()) {
        notes.extend(path::completed(&cpg, w)?.1);
    }
    if let Some(section) = opts.layered {
        // a completion that changes column: a radial mesh per column
        let (split, of) = stretches(wells);
        let (mut parts, mut ps) = (vec![], vec![]);
        for (n, w) in split.iter().enumerate() {
            for (leg, path) in bend::paths(&cpg, w, n, opts.outer)? {
                parts.push(leg);
                ps.push(path);
            }
        }
        if ps.len() == split.len() {
            match layered::build(backend, &cpg, &parts, &ps, &section)? {
                Ok(groups) => {
                    let mut h = layered::assemble(&cpg, &parts, &ps, groups)?;
                    match layered::unfilled(&h) {
                        Some(why) => notes.push(format!("the transition is meshed in 3D: {why}")),
                        None => {
                            h.wellbore = bend::merge_legs(std::mem::take(&mut h.wellbore), &of);
                            h.report.notes = notes;
                            return Ok(h);
                        }
                    }
                }
                Err(why) => notes.push(format!("the transition is meshed in 3D: {why}")),
            }
        }
    }
    // the 3D transition: one path per well, or per straight leg of a trajectory that bends
    let mut owner = vec![];
    let mut legs = vec![];
    let mut paths = vec![];
    for (n, w) in wells.iter().enumerate() {
        for (leg, path) in bend::paths(&cpg, w, n, opts.outer)? {
            owner.push(n);
            legs.push(leg);
            paths.push(path);
        }
    }
    let wells = &legs;
    let reach: Vec<usize> = wells
        .par_iter()
        .zip(&paths)
        .map(|(w, p)| cavity::reach(&cpg, w, p, opts))
        .collect();
    let groups = cavity::cavities(&cpg, &paths, &reach);
    let done = std::sync::atomic::AtomicUsize::new(0);
    let of = groups.len();
    let built = groups
        .into_par_iter()
        .map(|cells| {
            let ws: Vec<&Well3> = cells.wells.iter().map(|&w| &wells[w]).collect();
            let ps: Vec<&path::Path> = cells.wells.iter().map(|&w| &paths[w]).collect();
            let open: Vec<(usize, f64)> = ps.iter().flat_map(|p| p.open_faces()).collect();
            if let Some((c, n)) = cells
                .cells
                .iter()
                .find_map(|&c| cpg.inverted(c).map(|n| (c, n)))
            {
                return Err(Error::Usage(format!(
                    "{}: cell {} of the cavity is inverted: at pillar {} its top lies below its \
                     bottom",
                    well_names(&ws),
                    cpg::one_based(c),
                    cpg.pillar_name(c, n)
                )));
            }
            let sides = cavity::sides(&cpg, &cells.cells, &open)?;
            let (mut radials, full) =
                cavity::radials(&cpg, &ws, &ps, &cells.cells, &sides, opts, 1.0)?;
            let (mut transition, mut outcome) = complex::mesh(backend, &sides, &radials, opts)?;
            // Radial meshes as wide as asked come within half a cell of the
            // sides, whose facets' balls may then take them in: the sites
            // of those facets cannot all be inside (a horizontal well in a
            // box of 10 m cells: 48 of 582 outside at 10 m, none at 9 or 8).
            // Once smaller, kept if fewer are outside.
            // (an attempt that fails leaves the first)
            if full && outside(&outcome) > 0 {
                let again =
                    cavity::radials(&cpg, &ws, &ps, &cells.cells, &sides, opts, RETRY_SCALE)
                        .and_then(|(smaller, _)| {
                            complex::mesh(backend, &sides, &smaller, opts).map(|m| (smaller, m))
                        });
                if let Ok((smaller, (t, o))) = again {
                    if outside(&o) < outside(&outcome) {
                        (radials, transition, outcome) = (smaller, t, o);
                    }
                }
            }
            let outcome = outcome.map_err(|e| Error::Within {
                part: format!("the cavity of {}", well_names(&ws)),
                error: Box::new(e),
            })?;
            let n = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
            if let Some(p) = opts.progress {
                p("cavities", n, of);
            }
            Ok(assembly::Built {
                cells,
                transition,
                radials,
                outcome,
            })
        })
        .collect::<Result<Vec<_>>>()?;
    let mut h = assembly::assemble(&cpg, wells, &owner, built)?;
    h.report.notes = notes;
    Ok(h)
}

/// The radii a cavity's wells try again at when some transition sites
/// are outside their cells (`build`).
const RETRY_SCALE: f64 = 0.8;

/// A transition's sites outside their cells (an error: all of them).
fn outside(o: &Result<crate::conform::Outcome<D3>>) -> usize {
    o.as_ref()
        .map_or(usize::MAX, |o| o.report.sites.sites_outside)
}

/// "well W" or "wells A, B": a cavity's wells, each once (a bent well's
/// legs are wells of their own there).
fn well_names(ws: &[&Well3]) -> String {
    let mut names: Vec<&str> = vec![];
    for w in ws {
        if !names.contains(&w.name.as_str()) {
            names.push(&w.name);
        }
    }
    let wells = if names.len() == 1 { "well" } else { "wells" };
    format!("{wells} {}", names.join(", "))
}

/// Wells as layered cavities take them: a completion from the deck that
/// changes column, one well per column's run of cells (in order), each
/// with its own radial mesh; and per part, its well.
fn stretches(wells: &[Well3]) -> (Vec<Well3>, Vec<usize>) {
    let mut parts = vec![];
    let mut of = vec![];
    for (n, w) in wells.iter().enumerate() {
        let runs = w.cells.chunk_by(|a, b| [a[0], a[1]] == [b[0], b[1]]);
        if w.path.is_some() || w.cells.is_empty() || runs.clone().count() == 1 {
            parts.push(w.clone());
            of.push(n);
            continue;
        }
        for run in runs {
            parts.push(Well3 {
                i: run[0][0],
                j: run[0][1],
                cells: run.to_vec(),
                ..w.clone()
            });
            of.push(n);
        }
    }
    (parts, of)
}
