//! Eclipse decks that OPM Flow runs (docs/simulators.md): an unstructured
//! mesh as a dummy `DIMENS N 1 1` grid, one deck cell per mesh cell, its
//! pore volume (`PORV`) and depth (`TOPS`) per cell, the dummy grid's own
//! transmissibilities zeroed, and every connection a non-neighbour
//! connection (`NNC`) with its final transmissibility. Flow folds an NNC
//! between consecutive cells into their TRANX after the zeroing, so the
//! values written are the ones it uses. Single-phase water, METRIC units.

use crate::error::{Error, Result};
pub use crate::reservoir::deck::{Control, Deck, DeckCell, DeckWell, Fluid, Nnc, Period};
use std::fmt::Write;

/// Numbers as the deck reads them: the shortest text that reads back to
/// the same double.
pub(crate) fn num(x: f64) -> String {
    if x == 0.0 || (1e-3..1e9).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// A GRID or EDIT array: its keyword and values, six to a line (Eclipse reads 132 columns).
pub(crate) fn array(s: &mut String, keyword: &str, values: impl Iterator<Item = f64>) {
    let _ = writeln!(s, "{keyword}");
    let values: Vec<String> = values.map(num).collect();
    for line in values.chunks(6) {
        let _ = writeln!(s, " {}", line.join(" "));
    }
    s.push_str("/\n\n");
}

/// The deck's text of a network with its rock
/// (`reservoir::deck::prepare`), its notes and each element's deck cell
/// (0-based). Err on choices out of range and on what Flow could not run.
pub fn write(
    title: &str,
    network: &crate::mesh::Network,
    wells: &[crate::reservoir::deck::WellLinks],
    choices: &crate::reservoir::deck::DeckChoices,
) -> Result<(String, Vec<String>, Vec<usize>)> {
    let (deck, notes, position) = crate::reservoir::deck::prepare(title, network, wells, choices)?;
    Ok((to_string(&deck)?, notes, position))
}

/// Rock per element from a grid's arrays, each element taking the grid
/// cell `hosts[e]` (i, j, k) of an nx x ny grid; what is missing takes the
/// defaults (PERMY and PERMZ: PERMX's). NTG scales the pore volume and
/// the horizontal permeabilities, as Eclipse does. The notes say where
/// each value came from.
pub fn rock_from(
    props: &crate::io::eclipse::Properties,
    hosts: &[[usize; 3]],
    [nx, ny]: [usize; 2],
) -> (crate::reservoir::deck::Rock, Vec<String>) {
    use crate::reservoir::deck::{DEFAULT_PERM, DEFAULT_PORO};
    let at =
        |v: &Option<Vec<f64>>, h: [usize; 3]| v.as_ref().map(|v| v[h[0] + nx * (h[1] + ny * h[2])]);
    let mut notes = vec![];
    let from = |v: &Option<Vec<f64>>, key: &str, fallback: String| match v {
        Some(_) => format!("{key} from the input"),
        None => fallback,
    };
    notes.push(from(
        &props.poro,
        "PORO",
        format!("porosity {DEFAULT_PORO} (default, the input gives no PORO; --poro sets it)"),
    ));
    notes.push(from(
        &props.perm[0],
        "PERMX",
        format!(
            "permeability {DEFAULT_PERM} mD (default, the input gives no PERMX; --perm sets it)"
        ),
    ));
    for (k, key) in [(1, "PERMY"), (2, "PERMZ")] {
        if props.perm[0].is_some() && props.perm[k].is_none() {
            notes.push(format!("{key}: PERMX's (the input gives none)"));
        }
    }
    if props.ntg.is_some() {
        notes.push("NTG from the input, on pore volumes and horizontal permeabilities".into());
    }
    let (mut perm, mut poro) = (vec![], vec![]);
    for &h in hosts {
        let ntg = at(&props.ntg, h).unwrap_or(1.0);
        let kx = at(&props.perm[0], h).unwrap_or(DEFAULT_PERM);
        let ky = at(&props.perm[1], h).unwrap_or(kx);
        let kz = at(&props.perm[2], h).unwrap_or(kx);
        perm.push([kx * ntg, ky * ntg, kz]);
        poro.push(at(&props.poro, h).unwrap_or(DEFAULT_PORO) * ntg);
    }
    (crate::reservoir::deck::Rock { perm, poro }, notes)
}

/// What makes a deck unrunnable, named.
fn check(deck: &Deck) -> Result<()> {
    let bad = |what: String| Err(Error::Usage(format!("cannot write the deck: {what}")));
    let n = deck.cells.len();
    if n == 0 {
        return bad("the mesh has no cells".into());
    }
    for (i, c) in deck.cells.iter().enumerate() {
        let finite = c.depth.is_finite() && c.perm.iter().chain([&c.poro]).all(|v| v.is_finite());
        if !(c.pore_volume > 0.0 && c.pore_volume.is_finite() && finite) {
            return bad(format!(
                "cell {} has pore volume {} (depth {}, porosity {})",
                i + 1,
                c.pore_volume,
                c.depth,
                c.poro
            ));
        }
    }
    for c in &deck.nnc {
        let t = c.transmissibility;
        if c.cells.iter().any(|&i| i >= n) || c.cells[0] == c.cells[1] {
            return bad(format!("a connection joins cells {:?} of {n}", c.cells));
        }
        if !(t > 0.0 && t.is_finite()) {
            return bad(format!(
                "the connection of cells {} and {} has transmissibility {t} (a site outside its cell?)",
                c.cells[0] + 1,
                c.cells[1] + 1
            ));
        }
    }
    for w in &deck.wells {
        if w.name.is_empty()
            || w.name.len() > 8
            || !w.name.is_ascii()
            || w.name.contains(['\'', ' '])
        {
            return bad(format!(
                "well name {:?}: Eclipse takes 1-8 plain characters",
                w.name
            ));
        }
        if w.connections.is_empty() {
            return bad(format!("well {} has no connection", w.name));
        }
        for &(c, f) in &w.connections {
            if c >= n || !(f > 0.0 && f.is_finite()) {
                return bad(format!(
                    "well {}: connection to cell {} with factor {f}",
                    w.name,
                    c + 1
                ));
            }
        }
    }
    if let Some(p) = &deck.pressures {
        if p.len() != n || p.iter().any(|x| !x.is_finite()) {
            return bad(format!(
                "{} initial pressures for {n} cells, or one not finite",
                p.len()
            ));
        }
    }
    let steps = deck
        .steps
        .iter()
        .chain(deck.later.iter().flat_map(|p| &p.steps));
    if let Some(d) = steps.into_iter().find(|d| !(**d > 0.0 && d.is_finite())) {
        return bad(format!("a report step of {d} days"));
    }
    for (name, _) in deck.later.iter().flat_map(|p| &p.controls) {
        if !deck.wells.iter().any(|w| w.name == *name) {
            return bad(format!(
                "the schedule controls well {name}, which the deck does not have"
            ));
        }
    }
    if deck.watch.iter().any(|&c| c >= n) {
        return bad("a watched cell is beyond the mesh".into());
    }
    Ok(())
}

/// RUNSPEC and GRID (with the NNCs) and EDIT.
fn grid(s: &mut String, deck: &Deck) {
    let n = deck.cells.len();
    let max_conn = deck
        .wells
        .iter()
        .map(|w| w.connections.len())
        .max()
        .unwrap_or(1);
    let _ = writeln!(s, "RUNSPEC\n\nTITLE\n {}\n", deck.title);
    let _ = writeln!(s, "DIMENS\n {n} 1 1 /\n\nWATER\n");
    let _ = writeln!(s, "METRIC\n\nSTART\n 1 'JAN' 2025 /\n");
    let nw = deck.wells.len().max(1);
    let _ = writeln!(s, "WELLDIMS\n {nw} {max_conn} 1 {nw} /\n");
    s.push_str("TABDIMS\n/\n\nEQLDIMS\n/\n\nUNIFOUT\n\nGRID\n\nINIT\n\n");
    for key in ["DX", "DY", "DZ"] {
        let _ = writeln!(s, "{key}\n {n}*1 /\n");
    }
    // A dummy cell of thickness 1 centred on the node's depth.
    array(s, "TOPS", deck.cells.iter().map(|c| c.depth - 0.5));
    for (k, key) in ["PERMX", "PERMY", "PERMZ"].iter().enumerate() {
        array(s, key, deck.cells.iter().map(|c| c.perm[k]));
    }
    array(s, "PORO", deck.cells.iter().map(|c| c.poro));
    s.push_str("NNC\n");
    for c in &deck.nnc {
        let _ = writeln!(
            s,
            " {} 1 1 {} 1 1 {} /",
            c.cells[0] + 1,
            c.cells[1] + 1,
            num(c.transmissibility)
        );
    }
    s.push_str("/\n\nEDIT\n\n");
    array(s, "PORV", deck.cells.iter().map(|c| c.pore_volume));
    s.push_str("MULTIPLY\n 'TRANX' 0 /\n 'TRANY' 0 /\n 'TRANZ' 0 /\n/\n\n");
}

/// PROPS, SOLUTION and SUMMARY.
fn props(s: &mut String, deck: &Deck) {
    let f = &deck.fluid;
    let _ = writeln!(
        s,
        "PROPS\n\nPVTW\n {} {} {} {} 0 /\n\nROCK\n {} {} /\n\nDENSITY\n 800 {} 1 /\n",
        num(f.pressure),
        num(f.fvf),
        num(f.compressibility),
        num(f.viscosity),
        num(f.pressure),
        num(f.rock_compressibility),
        num(f.density)
    );
    s.push_str("SOLUTION\n\n");
    match &deck.pressures {
        Some(p) => array(s, "PRESSURE", p.iter().copied()),
        None => {
            let shallowest = || {
                deck.cells
                    .iter()
                    .map(|c| c.depth)
                    .fold(f64::INFINITY, f64::min)
            };
            let datum = deck.datum.unwrap_or_else(shallowest);
            let _ = write!(s, "EQUIL\n {} {}", num(datum), num(deck.pressure));
            // The contacts default to depth 0: a datum at or above it (a
            // site mirrored above a grid whose top is at 0) would lie in a
            // gas or oil zone, which Flow refuses without those phases, so
            // they are written a metre above it.
            if datum <= 0.0 {
                let above = num(datum - 1.0);
                let _ = write!(s, " {above} 0 {above} 0");
            }
            s.push_str(" /\n\n");
        }
    }
    s.push_str("SUMMARY\n\nFPR\n\n");
    if !deck.wells.is_empty() {
        for key in ["WBHP", "WWPR", "WWIR"] {
            let _ = writeln!(s, "{key}\n/\n");
        }
    }
    if !deck.watch.is_empty() {
        s.push_str("BPR\n");
        for &c in &deck.watch {
            let _ = writeln!(s, " {} 1 1 /", c + 1);
        }
        s.push_str("/\n\n");
    }
}

/// SCHEDULE: wells and report steps.
fn schedule(s: &mut String, deck: &Deck) {
    // Pressures at every report step, for pictures (scripts/simulate.py).
    s.push_str("SCHEDULE\n\nRPTRST\n 'BASIC=2' /\n\n");
    if !deck.wells.is_empty() {
        s.push_str("WELSPECS\n");
        for w in &deck.wells {
            let (c, _) = w.connections[0];
            let _ = writeln!(
                s,
                " '{}' 'G1' {} 1 {} 'WATER' /",
                w.name,
                c + 1,
                num(deck.cells[c].depth)
            );
        }
        s.push_str("/\n\nCOMPDAT\n");
        for w in &deck.wells {
            for &(c, f) in &w.connections {
                let _ = writeln!(
                    s,
                    " '{}' {} 1 1 1 'OPEN' 1* {} {} /",
                    w.name,
                    c + 1,
                    num(f),
                    num(w.diameter)
                );
            }
        }
        s.push_str("/\n\n");
        let first: Vec<(String, Control)> = deck
            .wells
            .iter()
            .map(|w| (w.name.clone(), w.control))
            .collect();
        controls(s, &first);
    }
    tstep(s, &deck.steps);
    for p in &deck.later {
        controls(s, &p.controls);
        tstep(s, &p.steps);
    }
    s.push_str("END\n");
}

/// Report steps.
fn tstep(s: &mut String, steps: &[f64]) {
    s.push_str("TSTEP\n");
    let steps: Vec<String> = steps.iter().map(|&d| num(d)).collect();
    for line in steps.chunks(8) {
        let _ = writeln!(s, " {}", line.join(" "));
    }
    s.push_str("/\n\n");
}

/// Well controls: producers (and shut wells) in WCONPROD, injectors in
/// WCONINJE.
fn controls(s: &mut String, list: &[(String, Control)]) {
    let (inject, produce): (Vec<_>, Vec<_>) = list
        .iter()
        .partition(|(_, c)| matches!(c, Control::Inject { .. }));
    if !produce.is_empty() {
        s.push_str("WCONPROD\n");
        for (name, c) in produce {
            let _ = match *c {
                Control::ProduceAtBhp(p) => writeln!(s, " '{name}' 'OPEN' 'BHP' 5* {} /", num(p)),
                Control::Produce { rate, min_bhp } => writeln!(
                    s,
                    " '{name}' 'OPEN' 'WRAT' 1* {} 3* {} /",
                    num(rate),
                    num(min_bhp)
                ),
                _ => writeln!(s, " '{name}' 'SHUT' 'BHP' 5* 1 /"),
            };
        }
        s.push_str("/\n\n");
    }
    if !inject.is_empty() {
        s.push_str("WCONINJE\n");
        for (name, c) in inject {
            if let Control::Inject { rate, max_bhp } = *c {
                let _ = writeln!(
                    s,
                    " '{name}' 'WATER' 'OPEN' 'RATE' {} 1* {} /",
                    num(rate),
                    num(max_bhp)
                );
            }
        }
        s.push_str("/\n\n");
    }
}

/// The deck's text; Err naming what would make Flow refuse it or run it
/// wrong (a non-positive pore volume or transmissibility, a well name
/// Eclipse cannot read), with nothing written.
pub fn to_string(deck: &Deck) -> Result<String> {
    check(deck)?;
    let mut s = String::with_capacity(48 * (deck.nnc.len() + 2 * deck.cells.len()) + 4096);
    s.push_str("-- Written by orthomesh: a conforming orthogonal mesh as a dummy N x 1 x 1\n");
    s.push_str("-- grid whose connections are all NNCs with their final transmissibilities.\n");
    for n in &deck.notes {
        let _ = writeln!(s, "-- {n}");
    }
    s.push('\n');
    grid(&mut s, deck);
    props(&mut s, deck);
    schedule(&mut s, deck);
    Ok(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn small() -> Deck {
        let cell = |depth: f64| DeckCell {
            pore_volume: 20.0,
            depth,
            perm: [100.0, 100.0, 10.0],
            poro: 0.2,
        };
        Deck {
            title: "two cells".into(),
            notes: vec!["permeability 100 mD (default)".into()],
            cells: vec![cell(1000.0), cell(1000.5)],
            nnc: vec![Nnc {
                cells: [0, 1],
                transmissibility: 0.25,
            }],
            wells: vec![DeckWell {
                name: "W1".into(),
                connections: vec![(1, 3.5)],
                diameter: 0.2,
                control: Control::Produce {
                    rate: 5.0,
                    min_bhp: 1.0,
                },
            }],
            watch: vec![0],
            fluid: Fluid::default(),
            pressure: 200.0,
            datum: None,
            pressures: None,
            steps: vec![1.0; 3],
            later: vec![],
        }
    }

    #[test]
    fn sections_and_records_are_where_flow_reads_them() {
        let text = to_string(&small()).unwrap();
        for want in [
            "DIMENS\n 2 1 1 /",
            "TOPS\n 999.5 1000\n/",
            "NNC\n 1 1 1 2 1 1 0.25 /\n/",
            "PORV\n 20 20\n/",
            " 'TRANX' 0 /",
            " 'W1' 'G1' 2 1 1000.5 'WATER' /",
            " 'W1' 2 1 1 1 'OPEN' 1* 3.5 0.2 /",
            " 'W1' 'OPEN' 'WRAT' 1* 5 3* 1 /",
            "TSTEP\n 1 1 1\n/\n\nEND",
            "BPR\n 1 1 1 /\n/",
            "-- permeability 100 mD (default)",
        ] {
            assert!(text.contains(want), "{want:?} missing from\n{text}");
        }
        assert!(text.ends_with("END\n"));
    }

    #[test]
    fn numbers_read_back_exactly() {
        for x in [0.0, 1.0, 0.1, 123456.789, 1e-7, 2.5e12, -3.25e-9] {
            assert_eq!(num(x).parse::<f64>().unwrap(), x);
        }
    }

    #[test]
    fn unrunnable_decks_are_refused_by_name() {
        let mut d = small();
        d.nnc[0].transmissibility = -1.0;
        let e = to_string(&d).unwrap_err().to_string();
        assert!(e.contains("cells 1 and 2") && e.contains("-1"), "{e}");
        let mut d = small();
        d.cells[1].pore_volume = f64::NAN;
        assert!(to_string(&d).unwrap_err().to_string().contains("cell 2"));
        let mut d = small();
        d.wells[0].name = "TOO-LONG-NAME".into();
        assert!(to_string(&d)
            .unwrap_err()
            .to_string()
            .contains("TOO-LONG-NAME"));
    }

    #[test]
    fn rock_comes_from_the_host_cells_with_ntg_and_defaults() {
        use crate::io::eclipse::Properties;
        // A 2 x 1 x 2 grid: PORO and PERMX given, NTG halves the first cell.
        let props = Properties {
            poro: Some(vec![0.1, 0.2, 0.3, 0.4]),
            perm: [Some(vec![10.0, 20.0, 30.0, 40.0]), None, None],
            ntg: Some(vec![0.5, 1.0, 1.0, 1.0]),
        };
        let (rock, notes) = rock_from(&props, &[[0, 0, 0], [1, 0, 1]], [2, 1]);
        assert_eq!(rock.poro, vec![0.05, 0.4]);
        assert_eq!(rock.perm, vec![[5.0, 5.0, 10.0], [40.0, 40.0, 40.0]]);
        assert!(
            notes.iter().any(|n| n.starts_with("PERMY: PERMX's")),
            "{notes:?}"
        );
        let (rock, notes) = rock_from(&Properties::default(), &[[0, 0, 0]], [1, 1]);
        assert_eq!(rock.poro, vec![crate::reservoir::deck::DEFAULT_PORO]);
        assert!(notes.iter().any(|n| n.contains("default")), "{notes:?}");
    }
}
