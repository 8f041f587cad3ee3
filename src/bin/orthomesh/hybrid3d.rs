//! `hybrid --3d`: wells from the deck and the command line, their 3D
//! hybrid mesh, and its files.

use crate::deck::{grid_rock, grid_unit, DeckOut, FromInput};
use crate::{bar, deck_wells, finish_bar, one_based, report_text, write_texts, HybridArgs};
use crate::{DEFAULT_WELL_RADIUS, MANY_WELLS};
use orthomesh::reservoir::{hybrid3, Hybrid3Options, Section, Well3};
use orthomesh::{io, Backend, Error, Progress, Result};
use std::io::IsTerminal;

/// NAME:I:J[:K1-K2][:RADIUS[:DIP:AZIMUTH]] (I, J, K 1-based; degrees).
fn well3_spec(spec: &str) -> Result<Well3> {
    let mut parts: Vec<&str> = spec.split(':').collect();
    let bad = || {
        Error::Usage(format!(
            "well '{spec}': expected NAME:I:J[:K1-K2][:RADIUS[:DIP:AZIMUTH]]"
        ))
    };
    let num = |t: &str| {
        t.parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(bad)
    };
    let k = match parts.get(3).and_then(|t| t.split_once('-')) {
        Some((a, b)) => {
            let k = [one_based(num(a)?, spec)?, one_based(num(b)?, spec)?];
            parts.remove(3);
            Some(k)
        }
        None => None,
    };
    if ![3, 4, 6].contains(&parts.len()) || parts[0].is_empty() {
        return Err(bad());
    }
    let angle = |k: usize| parts.get(k).map_or(Ok(0.0), |t| num(t));
    Ok(Well3 {
        name: parts[0].to_string(),
        i: one_based(num(parts[1])?, spec)?,
        j: one_based(num(parts[2])?, spec)?,
        k,
        radius: parts.get(3).map_or(Ok(DEFAULT_WELL_RADIUS), |t| num(t))?,
        dip: angle(4)?,
        azimuth: angle(5)?,
        // a dip and azimuth given ask for a straight axis (0:0 vertical)
        straight: parts.len() == 6,
        ..Default::default()
    })
}

/// NAME:FILE[:RADIUS]: a well along the trajectory in FILE.
fn well_path_spec(spec: &str) -> Result<Well3> {
    let bad = || Error::Usage(format!("well path '{spec}': expected NAME:FILE[:RADIUS]"));
    let (name, rest) = spec.split_once(':').ok_or_else(bad)?;
    // a radius after the last colon, if it parses (file names may hold colons)
    let (file, radius) = match rest.rsplit_once(':') {
        Some((f, r)) if r.parse::<f64>().is_ok() => (f, r.parse::<f64>().ok()),
        _ => (rest, None),
    };
    if name.is_empty() || file.is_empty() {
        return Err(bad());
    }
    let radius = radius.unwrap_or(DEFAULT_WELL_RADIUS);
    if !(radius.is_finite() && radius > 0.0) {
        return Err(bad());
    }
    Ok(Well3 {
        name: name.to_string(),
        radius,
        path: Some(io::wellpath::read_well_path(std::path::Path::new(file))?),
        ..Default::default()
    })
}

/// The wells: the deck's (WELSPECS head, COMPDAT layers and diameter),
/// then --well, then --well-path (a name given again replaces the earlier
/// well), those --radial names.
fn wells(a: &HybridArgs) -> Result<Vec<Well3>> {
    let mut list: Vec<Well3> = vec![];
    list.extend(
        deck_wells(a)?
            .into_iter()
            .map(|w| w.well3(DEFAULT_WELL_RADIUS)),
    );
    for spec in &a.wells {
        let w = well3_spec(spec)?;
        list.retain(|x| x.name != w.name);
        list.push(w);
    }
    for spec in &a.well_paths {
        let w = well_path_spec(spec)?;
        list.retain(|x| x.name != w.name);
        list.push(w);
    }
    crate::only_radial(a, &mut list, |w| &w.name)?;
    if list.is_empty() {
        return Err(Error::Usage(
            "--3d needs a well: --well NAME:I:J[:K1-K2][:RADIUS[:DIP:AZIMUTH]], --well-path \
             NAME:FILE[:RADIUS] or a --deck with WELSPECS/COMPDAT"
                .into(),
        ));
    }
    Ok(list)
}

/// `hybrid --3d`.
pub(crate) fn run(backend: &dyn Backend, a: HybridArgs) -> Result<()> {
    let g = io::eclipse::read_grid(&a.grid)?;
    let list = wells(&a)?;
    a.simulator.check(true)?;
    let carries = a.simulator.carries(a.deck.as_deref())?;
    if carries && a.simulator.single_phase_options() {
        return Err(Error::Usage(
            "--perm, --poro, --rate, --days and --aquifer are for --single-phase decks: a whole \
             --deck is carried as it is"
                .into(),
        ));
    }
    let watched = std::io::stderr().is_terminal() && (list.len() >= MANY_WELLS || g.nz > 1);
    let opts = Hybrid3Options {
        rings: a.rings.unwrap_or(6),
        sectors: a.sectors.unwrap_or(16),
        outer: a.outer.unwrap_or(1.0),
        first_ring: a.first_ring,
        allow_sites_outside: !a.strict,
        split_facets: a.split_facets,
        layered: (!a.transition_3d).then(|| {
            let d = Section::default();
            Section {
                rings: a.rings.unwrap_or(d.rings),
                sectors: a.sectors.unwrap_or(d.sectors),
                outer: a.outer.unwrap_or(d.outer),
                in_column: !a.rings_over_columns,
                first_ring: a.first_ring,
            }
        }),
        // a bar over the cavities when someone watches
        progress: watched.then_some(bar as Progress),
        ..Default::default()
    };
    let built = hybrid3::build(backend, &g, &list, &opts);
    finish_bar();
    let mut h = built?;
    for n in &h.report.notes {
        eprintln!("note: {n}");
    }
    if a.out.reproducible {
        for c in &mut h.report.cavities {
            c.transition.timing = None;
        }
        for s in &mut h.report.sections {
            s.transition.timing = None;
        }
    }
    // The network only where a file needs it.
    let network = (a.tough.is_some() || a.simulator.wanted()).then(|| h.mesh.network());
    let deck = deck_of(&a, &g, &h, network.as_ref(), carries)?;
    let deck = deck.tough(a.tough.as_deref(), network.as_ref())?;
    let mut texts = vec![(a.out.output.clone(), deck.vtu(h.cells()))];
    texts.extend(deck.files);
    if let Some(p) = &a.out.report {
        texts.push((p.clone(), report_text(&h.report, &a.grid)?));
    }
    write_texts(&texts, || {
        let r = &h.report;
        let (faces, exact, inside, sites) = r.cavities.iter().fold((0, 0, 0, 0), |s, c| {
            let k = &c.transition.certificate;
            (
                s.0 + k.faces,
                s.1 + k.faces_exact,
                s.2 + k.sites_inside,
                s.3 + k.domain_sites,
            )
        });
        let layered: usize = r.sections.iter().map(|s| s.cavities.len()).sum();
        eprintln!(
            "3D hybrid: {} wells in {} cavities ({layered} layered); {} reservoir, {} transition, \
             {} well cells; {} connections, {} non-orthogonal; 3D transitions' certificates: \
             faces {exact}/{faces} exact, sites inside {inside}/{sites}",
            h.wellbore.len(),
            r.cavities.len() + layered,
            r.cells[0],
            r.cells[1],
            r.cells[2],
            r.connections,
            r.non_orthogonal,
        );
        for s in &r.sections {
            let cells: usize = s.cavities.iter().map(|c| c.cells).sum();
            let inside: usize = s.cavities.iter().map(|c| c.sites_inside).sum();
            eprintln!(
                "  layered: wells {} in {} cavities on a section across layers {:.2} degrees \
                 off horizontal (corners within {:.1e} of their planes); {cells} cells, sites \
                 inside {inside}, filling their cavities' grid cells to {:.1e} of their volume; \
                 section certificate: {}",
                s.wells.join(", "),
                s.cavities.len(),
                s.dip,
                s.off_plane,
                s.cavities.iter().map(|c| c.volume_gap).fold(0.0, f64::max),
                if s.transition.certificate.conforms() {
                    "conforms"
                } else {
                    "FAILS"
                }
            );
        }
        for (pair, c) in &r.by_regions {
            let [median, p99, max] = c.angle;
            let mirrored = match pair.starts_with("reservoir-") && pair != "reservoir-reservoir" {
                true => format!(
                    "; {} orthogonal with the reservoir cell's node mirrored across the face \
                     ({:.1}% of the area)",
                    c.mirrored,
                    100.0 * c.mirrored_area
                ),
                false => String::new(),
            };
            eprintln!(
                "  {pair}: {} links, {} off orthogonal; angle median {median:.3}, 99% \
                 {p99:.3}, largest {max:.3} degrees; {} with both sites on one side{mirrored}",
                c.connections, c.non_orthogonal, c.one_sided
            );
        }
        eprintln!(
            "  transition: {} sites outside their cells, {} cells under 1e-3 of their \
             cavity's median volume (smallest {:.3e}; {} such merged into the cell across \
             their largest face)",
            r.sites_outside, r.slivers, r.smallest_volume_share, r.slivers_merged
        );
        // where the cavity's geometry, not the relocation, keeps sites out
        let (proved, outside) = r
            .cavities
            .iter()
            .filter(|c| c.transition.sites.sites_outside > 0)
            .fold((0, 0), |(p, o), c| {
                let w = &c.transition.weights;
                (p + usize::from(w.system3_proof.is_some()), o + 1)
            });
        if proved > 0 {
            eprintln!(
                "  of the {outside} cavities with sites outside, {proved} have facets that no \
                 weights let all cross their duals (an exact proof: `system3_proof` in the \
                 report), so some of their sites cannot be inside: docs/limitations.md"
            );
        }
    })
}

/// The deck asked for: the input deck carried whole (`carries`), or the
/// single-phase model of the mesh.
fn deck_of(
    a: &HybridArgs,
    g: &orthomesh::reservoir::CornerPointGrid,
    h: &hybrid3::Hybrid3,
    network: Option<&orthomesh::Network>,
    carries: bool,
) -> Result<DeckOut> {
    Ok(match (network, &a.deck) {
        (Some(network), Some(input)) if carries => {
            let extent = io::carry::extents(&h.mesh.points, &h.mesh.cells);
            let mesh = io::carry::Mesh {
                grid: g,
                network,
                host: &h.host,
                ijk: &h.ijk,
                wells: &h.wellbore,
                region: &h.region,
                extent: &extent,
            };
            a.simulator.carried(input, &mesh)?
        }
        (Some(network), _) if a.simulator.wanted() => {
            let title = format!("{} (3D)", a.grid.display());
            let outer = || h.outer_cells(g);
            a.simulator.text(&title, network, &h.wellbore, outer, || {
                Ok(FromInput {
                    length: grid_unit(a)?,
                    deck: a.deck.as_deref(),
                    rock: Some(grid_rock(a, g, &h.host)?),
                })
            })?
        }
        _ => DeckOut::default(),
    })
}
