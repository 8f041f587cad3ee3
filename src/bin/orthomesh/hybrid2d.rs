//! `hybrid` in 2D (one layer in map view) and 2.5D (`--layers`): wells
//! from the deck and the command line, the hybrid mesh, and its files.

use crate::deck::{grid_rock, grid_unit, DeckOut, FromInput};
use crate::{bar, deck_wells, finish_bar, ok, one_based, only_radial, polyline, well_spec};
use crate::{write_texts, HybridArgs, DEFAULT_WELL_RADIUS, MANY_WELLS};
use orthomesh::reservoir::{
    self as hybrid, CornerPointGrid, HybridOptions, Layered, WellAt, WellInput,
};
use orthomesh::{io, Backend, Error, Network, Progress, Result};
use std::io::IsTerminal;

/// The wells of a 2D hybrid: the deck's, then --well and --well-xy (a
/// name given again replaces the earlier well), those --radial names.
fn wells_2d(a: &HybridArgs) -> Result<Vec<WellInput>> {
    let mut list: Vec<WellInput> = vec![];
    for w in deck_wells(a)? {
        list.push(WellInput {
            name: w.name,
            at: WellAt::Column(w.i, w.j),
            radius: w.radius.unwrap_or(DEFAULT_WELL_RADIUS),
        });
    }
    for spec in &a.wells {
        let (name, x, y, r) = well_spec(spec)?;
        let (i, j) = (one_based(x, spec)?, one_based(y, spec)?);
        list.retain(|w| w.name != name);
        list.push(WellInput {
            name,
            at: WellAt::Column(i, j),
            radius: r,
        });
    }
    for spec in &a.wells_xy {
        let (name, x, y, r) = well_spec(spec)?;
        list.retain(|w| w.name != name);
        list.push(WellInput {
            name,
            at: WellAt::Xy([x, y]),
            radius: r,
        });
    }
    only_radial(a, &mut list, |w| &w.name)?;
    Ok(list)
}

/// `hybrid` in 2D (one layer in map view) or 2.5D (`--layers`).
pub(crate) fn run(backend: &dyn Backend, a: HybridArgs) -> Result<()> {
    let g = io::eclipse::read_grid(&a.grid)?;
    let list = wells_2d(&a)?;
    if a.layer == 0 {
        return Err(Error::Usage("--layer is 1-based".into()));
    }
    a.simulator.check(true)?;
    // one layer in map view is not the deck's model: only its layers are
    let whole = a.simulator.carries(a.deck.as_deref())?;
    let carries = whole && a.layers;
    if whole && !a.layers {
        eprintln!(
            "note: one layer in map view is not the deck's model; --layers (2.5D) or --3d \
             carry the deck whole, this writes the single-phase model of the layer"
        );
    }
    if carries && a.simulator.single_phase_options() {
        return Err(Error::Usage(
            "--perm, --poro, --rate, --days and --aquifer are for --single-phase decks: a whole \
             --deck is carried as it is"
                .into(),
        ));
    }
    let watched = list.len() >= MANY_WELLS && std::io::stderr().is_terminal();
    let opts = HybridOptions {
        layer: a.layer - 1,
        rings: a.rings.unwrap_or(12),
        sectors: a.sectors.unwrap_or(32),
        outer: a.outer.unwrap_or(1.9),
        margin: a.margin,
        fault_lines: a
            .faults
            .iter()
            .map(|f| polyline(f))
            .collect::<Result<_>>()?,
        allow_sites_outside: !a.strict,
        // a progress bar when there are many wells and someone watches
        progress: watched.then_some(bar as Progress),
        ..Default::default()
    };
    let mut h = hybrid::build(backend, &g, &list, &opts)?;
    finish_bar();
    if a.out.reproducible {
        h.report.transition.timing = None;
    }
    let layered = if a.layers {
        let l = orthomesh::reservoir::extrude(&h, &g)?;
        eprintln!(
            "2.5D: {} polyhedra over {} layers ({} top faces split where the horizon warps)",
            l.cells.len(),
            g.nz,
            l.split_faces
        );
        Some(l)
    } else {
        None
    };
    let cells = match &layered {
        Some(l) => l.cells(&h),
        None => h.cells(),
    };
    // The network only where a file needs it.
    let network = (a.tough.is_some() || a.simulator.wanted()).then(|| match &layered {
        Some(l) => l.network(&h),
        None => h.network(),
    });
    let deck = deck_of(&a, &g, &h, layered.as_ref(), network.as_ref(), carries)?;
    let deck = deck.tough(a.tough.as_deref(), network.as_ref())?;
    let mut texts = vec![(a.out.output.clone(), deck.vtu(cells))];
    texts.extend(deck.files);
    if let Some(p) = a.out.svg {
        let inside = vec![true; h.mesh.cells.len()];
        texts.push((p, io::svg::to_string(&h.mesh, &inside, &h.constraints)));
    }
    if let Some(p) = a.out.report {
        let text =
            serde_json::to_string_pretty(&h.report).map_err(|e| Error::Usage(e.to_string()))?;
        texts.push((p, text + "\n"));
    }
    let layer = a.layer;
    write_texts(&texts, || {
        summarise(&format!("{}, layer {layer}", a.grid.display()), &h);
        for (pair, d) in &h.report.orthogonality_defect {
            eprintln!("orthogonality defect {pair}: {d:.2e}");
        }
    })
}

/// What the hybrid mesh came to, on standard error.
pub(crate) fn summarise(what: &str, h: &hybrid::Hybrid) {
    let r = &h.report;
    let c = &r.transition.certificate;
    eprintln!(
        "{what}: {} wells -> {} reservoir, {} transition, {} well cells; {} cavities ({} columns); {} fault segments in cavities",
        r.wells.len(), r.cells[0], r.cells[1], r.cells[2], r.cavities, r.cavity_cells, r.fault_segments
    );
    eprintln!(
        "transition certificate: vertices {} segments {} tiling {} sites-inside {}; faces without a twin: {}; negative transmissibilities {}, non-orthogonal connections {}",
        ok(c.vertices_are_mesh_vertices),
        ok(c.segments_are_single_edges),
        ok(c.cells_tile_domain),
        ok(c.sites_inside_cells),
        r.unmatched_faces,
        r.transmissibility.negative,
        r.transmissibility.non_orthogonal
    );
    for n in &r.notes {
        eprintln!("note: {n}");
    }
}

/// The deck asked for: the input deck carried whole (a --deck with PROPS)
/// onto the 2D mesh's layer or the 2.5D layers, or the single-phase model.
fn deck_of(
    a: &HybridArgs,
    g: &CornerPointGrid,
    h: &hybrid::Hybrid,
    layered: Option<&Layered>,
    network: Option<&Network>,
    carries: bool,
) -> Result<DeckOut> {
    let Some(network) = network.filter(|_| a.simulator.wanted()) else {
        return Ok(DeckOut::default());
    };
    let (hosts, ijk) = match layered {
        Some(l) => l.hosts(h),
        None => (h.host.clone(), h.ijk.clone()),
    };
    if let (Some(input), Some(l), true) = (a.deck.as_deref(), layered, carries) {
        let (links, extent) = (
            l.well_links(h, &[]),
            io::carry::extents(&l.points, &l.cells),
        );
        let region = l.regions(h);
        let mesh = io::carry::Mesh {
            grid: g,
            network,
            host: &hosts,
            ijk: &ijk,
            wells: &links,
            region: &region,
            extent: &extent,
        };
        return a.simulator.carried(input, &mesh);
    }
    let (links, title) = match layered {
        Some(l) => {
            // COMPDAT's layers: a well given again by --well is open over
            // the whole grid
            let completed: Vec<(String, [usize; 2])> = deck_wells(a)?
                .into_iter()
                .filter(|w| !a.wells.iter().any(|s| s.split(':').next() == Some(&w.name)))
                .filter_map(|w| Some((w.name, w.k?)))
                .collect();
            (
                l.well_links(h, &completed),
                format!("{} (2.5D)", a.grid.display()),
            )
        }
        None => (
            h.well_links(),
            format!("{}, layer {}", a.grid.display(), a.layer),
        ),
    };
    let outer = || match layered {
        Some(l) => l.outer_cells(h),
        None => h.outer_cells(),
    };
    let input = || {
        Ok(FromInput {
            length: grid_unit(a)?,
            deck: a.deck.as_deref(),
            rock: Some(grid_rock(a, g, &hosts)?),
        })
    };
    a.simulator.text(&title, network, &links, outer, input)
}
