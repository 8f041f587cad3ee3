//! Simulator decks from meshes (docs/simulators.md): a two-point flux
//! network with rock properties per element and wells linked to elements
//! becomes an OPM Flow deck (`io::deck`) whose cells follow a Hilbert curve
//! (measured: a random order ran 2.7x slower in Flow than a local one).

use crate::error::{Error, Result};
use crate::mesh::Network;

/// A deck cell.
#[derive(Debug, Clone, PartialEq)]
pub struct DeckCell {
    /// Pore volume (m^3): what the cell holds, whatever its dummy size.
    pub pore_volume: f64,
    /// Depth of its node (m, down).
    pub depth: f64,
    /// Permeability along x, y, z (mD), for reference (the NNCs carry it).
    pub perm: [f64; 3],
    /// Porosity, for reference (the pore volume carries it).
    pub poro: f64,
}

/// A connection between deck cells (0-based) and its transmissibility
/// (METRIC: cP m^3 / day / bar).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Nnc {
    /// The two cells.
    pub cells: [usize; 2],
    /// Its transmissibility.
    pub transmissibility: f64,
}

/// How a well is run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Control {
    /// Produces water at this bottom-hole pressure (bar).
    ProduceAtBhp(f64),
    /// Produces water at a rate (sm^3/day) down to a bottom-hole pressure
    /// (bar).
    Produce {
        /// The rate.
        rate: f64,
        /// The lowest bottom-hole pressure.
        min_bhp: f64,
    },
    /// Injects water at a rate (sm^3/day) up to a bottom-hole pressure
    /// (bar).
    Inject {
        /// The rate.
        rate: f64,
        /// The highest bottom-hole pressure.
        max_bhp: f64,
    },
    /// Shut.
    Shut,
}

/// A period of a schedule: controls that change at its start, then its
/// report steps (days).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Period {
    /// (well, control) for the wells whose control changes.
    pub controls: Vec<(String, Control)>,
    /// Report steps.
    pub steps: Vec<f64>,
}

/// A well: its connections (cell, connection factor in cP m^3 / day /
/// bar) and control.
#[derive(Debug, Clone, PartialEq)]
pub struct DeckWell {
    /// Up to eight characters, as Eclipse reads names.
    pub name: String,
    /// Connections: cell (0-based) and connection factor.
    pub connections: Vec<(usize, f64)>,
    /// Wellbore diameter (m), for reference (the factors carry it).
    pub diameter: f64,
    /// How it runs.
    pub control: Control,
}

/// Water and rock (PVTW, ROCK, DENSITY).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fluid {
    /// Reference pressure (bar).
    pub pressure: f64,
    /// Formation volume factor at the reference pressure.
    pub fvf: f64,
    /// Water compressibility (1/bar).
    pub compressibility: f64,
    /// Water viscosity (cP).
    pub viscosity: f64,
    /// Rock compressibility (1/bar).
    pub rock_compressibility: f64,
    /// Water density at surface conditions (kg/m^3).
    pub density: f64,
}

impl Default for Fluid {
    fn default() -> Self {
        Fluid {
            pressure: 200.0,
            fvf: 1.0,
            compressibility: 4.5e-5,
            viscosity: 0.5,
            rock_compressibility: 4.5e-5,
            density: 1000.0,
        }
    }
}

/// A whole deck.
#[derive(Debug, Clone, PartialEq)]
pub struct Deck {
    /// TITLE.
    pub title: String,
    /// Comment lines written at the top (what was assumed).
    pub notes: Vec<String>,
    /// Cells, in deck order.
    pub cells: Vec<DeckCell>,
    /// Connections.
    pub nnc: Vec<Nnc>,
    /// Wells.
    pub wells: Vec<DeckWell>,
    /// Cells whose pressure goes into the summary (BPR).
    pub watch: Vec<usize>,
    /// Water and rock.
    pub fluid: Fluid,
    /// Initial pressure (bar) at the datum, in hydrostatic equilibrium
    /// (EQUIL).
    pub pressure: f64,
    /// The datum's depth (m); None: the shallowest node's.
    pub datum: Option<f64>,
    /// Instead, every cell's initial pressure (bar; PRESSURE).
    pub pressures: Option<Vec<f64>>,
    /// Report steps (days) under the wells' first controls.
    pub steps: Vec<f64>,
    /// Later periods: controls that change, and their steps.
    pub later: Vec<Period>,
}

/// Darcy's constant in METRIC units: transmissibility (cP m^3 / day / bar)
/// from permeability (mD), area (m^2) and length (m).
pub const DARCY: f64 = 0.00852702;

/// Rock properties per element.
#[derive(Debug, Clone, PartialEq)]
pub struct Rock {
    /// Permeability along x, y, z (mD).
    pub perm: Vec<[f64; 3]>,
    /// Porosity (pore volume over bulk volume).
    pub poro: Vec<f64>,
}

impl Rock {
    /// The same rock in n elements.
    pub fn uniform(n: usize, perm: [f64; 3], poro: f64) -> Rock {
        Rock {
            perm: vec![perm; n],
            poro: vec![poro; n],
        }
    }
}

/// A well's links to the network: per element the geometric part of its
/// connection factor (theta h / ln(rho / r_w), in m; `WellMesh::links`).
#[derive(Debug, Clone, PartialEq)]
pub struct WellLinks {
    /// The well's name.
    pub name: String,
    /// The wellbore's radius (m).
    pub radius: f64,
    /// (element, geometric factor).
    pub links: Vec<(usize, f64)>,
    /// ln(rho / r_w) of its factors' radial flow (Peaceman's r_o for rho
    /// in an ordinary cell): a skin S makes each factor g log / (log + S).
    pub log: f64,
}

/// The geometric part of the connection factor of a well of radius `rw`
/// at the node of element `e` of height `h` (m), in an ordinary cell:
/// Peaceman's equivalent radius from the cell's own lateral connections
/// (Palagi and Aziz's form for PEBI cells), ln r_o = (sum t ln d - 2 pi h)
/// / sum t with t = A / d per connection, then 2 pi h / ln(r_o / rw).
/// On a square cell of side D, r_o = 0.208 D (Peaceman's measured value:
/// 0.198 D). Returns the factor and r_o. Err when the cell has no lateral
/// connection or r_o <= rw.
pub fn peaceman(network: &Network, e: usize, h: f64, rw: f64) -> Result<(f64, f64)> {
    let (mut t_sum, mut t_log) = (0.0, 0.0);
    for c in &network.connections {
        if !c.elements.contains(&e) || c.cos_gravity != 0.0 || c.area <= 0.0 {
            continue;
        }
        let d = c.d[0] + c.d[1];
        t_sum += c.area / d;
        t_log += c.area / d * d.ln();
    }
    if t_sum <= 0.0 {
        return Err(Error::Usage(format!(
            "cell {e} has no lateral connection for Peaceman's well factor"
        )));
    }
    let r_o = ((t_log - std::f64::consts::TAU * h) / t_sum).exp();
    if r_o.is_nan() || r_o <= rw {
        return Err(Error::Usage(format!(
            "the well's radius {rw} is not below the equivalent radius {r_o:.4} of cell {e} (Peaceman): its cell is too small for it"
        )));
    }
    Ok((std::f64::consts::TAU * h / (r_o / rw).ln(), r_o))
}

/// What the deck runs: well control, initial pressure, report steps,
/// fluid.
#[derive(Debug, Clone, PartialEq)]
pub struct DeckSettings {
    /// The control of every well.
    pub control: Control,
    /// Initial pressure (bar) at the datum.
    pub pressure: f64,
    /// The datum's depth (m); None: the shallowest node's.
    pub datum: Option<f64>,
    /// Report steps (days).
    pub steps: Vec<f64>,
    /// Water and rock compressibility.
    pub fluid: Fluid,
}

impl Default for DeckSettings {
    fn default() -> Self {
        DeckSettings {
            control: Control::ProduceAtBhp(190.0),
            pressure: 200.0,
            datum: None,
            steps: vec![1.0; 10],
            fluid: Fluid::default(),
        }
    }
}

/// Elements in the order of a Hilbert curve over their nodes' map
/// positions, deeper after shallower where the map position is the same.
pub fn hilbert_order(network: &Network) -> Vec<usize> {
    let nodes: Vec<[f64; 3]> = network.elements.iter().map(|e| e.node).collect();
    let map: Vec<[f64; 2]> = nodes.iter().map(|p| [p[0], p[1]]).collect();
    let key = crate::geom::hilbert_keys(&map);
    let mut order: Vec<usize> = (0..nodes.len()).collect();
    order.sort_by(|&a, &b| {
        key[a]
            .cmp(&key[b])
            .then(nodes[b][2].total_cmp(&nodes[a][2]))
            .then(a.cmp(&b))
    });
    order
}

/// Transmissibility of a connection: Darcy's constant times the area over
/// the two half-distances, each over its cell's permeability along the
/// connection's axis.
fn transmissibility(area: f64, d: [f64; 2], k: [f64; 2]) -> f64 {
    DARCY * area / (d[0] / k[0] + d[1] / k[1])
}

/// The deck of a network, and each element's deck cell (0-based). The
/// writer (`io::deck::to_string`) refuses what Flow could not run: a
/// non-positive transmissibility (a site outside its cell) or pore volume.
pub fn deck(
    title: &str,
    network: &Network,
    rock: &Rock,
    wells: &[WellLinks],
    settings: &DeckSettings,
) -> (Deck, Vec<usize>) {
    let order = hilbert_order(network);
    let mut position = vec![0; order.len()];
    for (i, &e) in order.iter().enumerate() {
        position[e] = i;
    }
    let cells = order
        .iter()
        .map(|&e| {
            let el = &network.elements[e];
            DeckCell {
                pore_volume: el.volume * rock.poro[e],
                depth: -el.node[2],
                perm: rock.perm[e],
                poro: rock.poro[e],
            }
        })
        .collect();
    let nnc = network
        .connections
        .iter()
        .filter(|c| c.area != 0.0)
        .map(|c| {
            let [a, b] = c.elements;
            let axis = usize::from(c.isot.clamp(1, 3)) - 1;
            Nnc {
                cells: [position[a], position[b]],
                transmissibility: transmissibility(
                    c.area,
                    c.d,
                    [rock.perm[a][axis], rock.perm[b][axis]],
                ),
            }
        })
        .collect();
    let wells = wells
        .iter()
        .map(|w| DeckWell {
            name: w.name.clone(),
            connections: w
                .links
                .iter()
                .map(|&(e, g)| {
                    let [kx, ky, _] = rock.perm[e];
                    (position[e], DARCY * (kx * ky).sqrt() * g)
                })
                .collect(),
            diameter: 2.0 * w.radius,
            control: settings.control,
        })
        .collect();
    let deck = Deck {
        title: title.into(),
        notes: vec![],
        cells,
        nnc,
        wells,
        watch: vec![],
        fluid: settings.fluid,
        pressure: settings.pressure,
        datum: settings.datum,
        pressures: None,
        steps: settings.steps.clone(),
        later: vec![],
    };
    (deck, position)
}

/// A network and its wells with lengths in units of f metres, in metres.
pub fn in_metres(network: &Network, wells: &[WellLinks], f: f64) -> (Network, Vec<WellLinks>) {
    let mut n = network.clone();
    for e in &mut n.elements {
        e.volume *= f * f * f;
        e.node = e.node.map(|x| x * f);
    }
    for c in &mut n.connections {
        c.area *= f * f;
        c.d = c.d.map(|x| x * f);
    }
    let wells = wells
        .iter()
        .map(|w| WellLinks {
            name: w.name.clone(),
            radius: w.radius * f,
            links: w.links.iter().map(|&(e, g)| (e, g * f)).collect(),
            log: w.log,
        })
        .collect();
    (n, wells)
}

/// What a user chose for a deck; None takes the default, which the
/// deck's notes say.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct DeckChoices {
    /// The input's length unit in metres and its name (None: metres, said).
    pub length: Option<(f64, String)>,
    /// Permeability (mD) along x, y and z.
    pub perm: Option<f64>,
    /// Porosity.
    pub poro: Option<f64>,
    /// Every well's water production rate (sm^3/day).
    pub rate: Option<f64>,
    /// Elements held at their initial pressure (an open boundary, as an
    /// aquifer around the field); empty: a closed boundary.
    pub aquifer: Vec<usize>,
    /// The input deck's schedule (`io::schedule::read_schedule`) and what
    /// its reading said; `rate` replaces it.
    pub schedule: Option<(Vec<Period>, Vec<String>)>,
    /// Run only this many days.
    pub days: Option<f64>,
    /// The input's initial state (`io::schedule::read_equil`): datum depth
    /// (m), pressure there (bar), and the input's words for them.
    pub equil: Option<(f64, f64, String)>,
    /// Rock per element from the input (`io::deck::rock_from`) and what it
    /// assumed; `perm` and `poro` replace its values where given.
    pub rock: Option<(Rock, Vec<String>)>,
}

/// The first `days` of a schedule (whole periods, the last one cut).
fn first_days(periods: &[Period], days: f64) -> Vec<Period> {
    let mut left = days;
    let mut out = vec![];
    for p in periods {
        if left <= 0.0 {
            break;
        }
        let mut steps = vec![];
        for &d in &p.steps {
            if left <= 0.0 {
                break;
            }
            steps.push(d.min(left));
            left -= d;
        }
        out.push(Period {
            controls: p.controls.clone(),
            steps,
        });
    }
    out
}

/// Puts a schedule on a deck: its first period's controls on the wells
/// (wells it does not name stay shut, said), its steps, the later periods.
fn apply_schedule(deck: &mut Deck, periods: &[Period], notes: &mut Vec<String>) {
    let Some(first) = periods.first() else {
        return;
    };
    let mut shut = vec![];
    for w in &mut deck.wells {
        match first.controls.iter().find(|(n, _)| *n == w.name) {
            Some((_, c)) => w.control = *c,
            None => {
                w.control = Control::Shut;
                shut.push(w.name.clone());
            }
        }
    }
    if !shut.is_empty() {
        notes.push(format!(
            "no control before the schedule's first step, so shut: {}",
            shut.join(", ")
        ));
    }
    deck.steps = first.steps.clone();
    deck.later = periods[1..].to_vec();
    let days: f64 = periods.iter().flat_map(|p| &p.steps).sum();
    notes.push(format!(
        "the input deck's schedule: {} periods, {days} days, as single-phase water (oil, liquid and reservoir rates become water rates)",
        periods.len()
    ));
}

impl DeckChoices {
    /// Err naming a choice out of range: permeability, porosity, rate or
    /// days.
    pub fn check(&self) -> Result<()> {
        let within = |v: Option<f64>, what: &str, max: f64| match v {
            Some(x) if !(x > 0.0 && x <= max) => Err(Error::Usage(format!(
                "{what} {x} is out of range (0, {max}]"
            ))),
            _ => Ok(()),
        };
        within(self.perm, "--perm", 1e9)?;
        within(self.poro, "--poro", 1.0)?;
        within(self.rate, "--rate", 1e12)?;
        within(self.days, "--days", 1e6)
    }
}

/// How much an aquifer cell's pore volume grows: enough that a well's
/// production for the deck's ten days moves its pressure by far less than
/// a bar.
pub const AQUIFER: f64 = 1e6;

/// Permeability where neither input nor user gives one (mD).
pub const DEFAULT_PERM: f64 = 100.0;
/// Porosity where neither input nor user gives one.
pub const DEFAULT_PORO: f64 = 0.2;

/// The rock of n elements (the input's, or uniform) with `--perm` and
/// `--poro` applied, and the notes that say where it came from.
fn rock_of(n: usize, choices: &DeckChoices) -> Result<(Rock, Vec<String>)> {
    let perm = choices.perm.unwrap_or(DEFAULT_PERM);
    let poro = choices.poro.unwrap_or(DEFAULT_PORO);
    let said = |given: bool, flag: &str| {
        if given {
            format!("({flag})")
        } else {
            format!("(default, the input gives none; {flag} sets it)")
        }
    };
    let mut notes = match &choices.rock {
        Some((_, said)) => said.clone(),
        None => vec![
            format!(
                "permeability {perm} mD along x, y and z {}",
                said(choices.perm.is_some(), "--perm")
            ),
            format!("porosity {poro} {}", said(choices.poro.is_some(), "--poro")),
        ],
    };
    if choices.rock.is_some() {
        if let Some(k) = choices.perm {
            notes.push(format!(
                "permeability {k} mD along x, y and z everywhere (--perm)"
            ));
        }
        if let Some(f) = choices.poro {
            notes.push(format!("porosity {f} everywhere (--poro)"));
        }
    }
    let rock = match &choices.rock {
        Some((r, _)) => Rock {
            perm: match choices.perm {
                Some(k) => vec![[k; 3]; r.perm.len()],
                None => r.perm.clone(),
            },
            poro: match choices.poro {
                Some(f) => vec![f; r.poro.len()],
                None => r.poro.clone(),
            },
        },
        None => Rock::uniform(n, [perm; 3], poro),
    };
    if rock.perm.len() != n || rock.poro.len() != n {
        return Err(Error::Usage(format!(
            "rock for {} cells, the mesh has {n}",
            rock.poro.len()
        )));
    }
    Ok((rock, notes))
}

/// The deck of a network with its rock (the input's, or uniform), its
/// notes (what was assumed, also written at the deck's top) and each
/// element's deck cell (0-based). Err on choices out of range.
pub fn prepare(
    title: &str,
    network: &Network,
    wells: &[WellLinks],
    choices: &DeckChoices,
) -> Result<(Deck, Vec<String>, Vec<usize>)> {
    choices.check()?;
    let (rock, mut notes) = rock_of(network.elements.len(), choices)?;
    let mut settings = DeckSettings::default();
    match &choices.equil {
        Some((datum, p, said)) => {
            (settings.datum, settings.pressure) = (Some(*datum), *p);
            settings.fluid.pressure = *p;
            settings.control = Control::ProduceAtBhp(p - 10.0);
            notes.push(format!(
                "initial pressure {p:.4} bar at {datum:.4} m deep, from the input's {said}"
            ));
        }
        None => notes.push(format!(
            "initial pressure {} bar at the shallowest node (default, the input has no EQUIL)",
            settings.pressure
        )),
    }
    notes.push(format!(
        "water of viscosity {} cP",
        settings.fluid.viscosity
    ));
    if let Some(q) = choices.rate {
        settings.control = Control::Produce {
            rate: q,
            min_bhp: 1.0,
        };
    }
    if let Some(d) = choices.days {
        settings.steps = first_days(
            &[Period {
                controls: vec![],
                steps: settings.steps,
            }],
            d,
        )
        .into_iter()
        .flat_map(|p| p.steps)
        .collect();
    }
    let schedule = match &choices.schedule {
        Some((periods, said)) if !periods.is_empty() && !wells.is_empty() => {
            if choices.rate.is_some() {
                notes.push("--rate replaces the input deck's schedule".into());
                None
            } else {
                Some((periods, said))
            }
        }
        _ => None,
    };
    notes.push(match (wells.len(), settings.control) {
        _ if schedule.is_some() => format!("{} wells on the input deck's schedule", wells.len()),
        (0, _) => "no wells: the mesh has none, so the deck runs its initial state".into(),
        (n, Control::Produce { rate: q, .. }) => {
            format!("{n} wells, each producing {q} sm3/day of water (--rate), down to 1 bar")
        }
        (n, _) => format!(
            "{n} wells, each producing water at a bottom-hole pressure of {:.4} bar (default: 10 bar below the initial pressure; --rate sets a rate)",
            settings.pressure - 10.0
        ),
    });
    let (network, wells) = match &choices.length {
        Some((f, name)) if *f != 1.0 => {
            notes.push(format!("lengths in {name} converted to metres"));
            in_metres(network, wells, *f)
        }
        Some((_, name)) => {
            notes.push(format!("lengths in {name}"));
            (network.clone(), wells.to_vec())
        }
        None => {
            notes.push("lengths taken as metres (the input does not say its unit)".into());
            (network.clone(), wells.to_vec())
        }
    };
    let (mut deck, position) = deck(title, &network, &rock, &wells, &settings);
    if let Some((periods, said)) = schedule {
        let periods = match choices.days {
            Some(d) => first_days(periods, d),
            None => periods.clone(),
        };
        apply_schedule(&mut deck, &periods, &mut notes);
        let mut said = said.clone();
        said.dedup();
        notes.extend(said);
    }
    if !choices.aquifer.is_empty() {
        for &e in &choices.aquifer {
            deck.cells[position[e]].pore_volume *= AQUIFER;
        }
        notes.push(format!(
            "an open boundary: its {} cells hold their initial pressure (pore volume x {AQUIFER:e})",
            choices.aquifer.len()
        ));
    }
    let steps: Vec<f64> = deck
        .steps
        .iter()
        .chain(deck.later.iter().flat_map(|p| &p.steps))
        .copied()
        .collect();
    notes.push(format!(
        "{} report steps, {} days{}",
        steps.len(),
        steps.iter().sum::<f64>(),
        if choices.days.is_some() {
            " (--days)"
        } else {
            ""
        }
    ));
    deck.watch = deck
        .wells
        .iter()
        .filter_map(|w| w.connections.first())
        .map(|c| c.0)
        .collect();
    deck.watch.push(0);
    deck.watch.push(deck.cells.len().saturating_sub(1));
    deck.watch.sort_unstable();
    deck.watch.dedup();
    deck.notes = notes.clone();
    Ok((deck, notes, position))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{Connection, Element};

    fn row(n: usize) -> Network {
        Network {
            elements: (0..n)
                .map(|i| Element {
                    volume: 10.0,
                    node: [i as f64, 0.0, -1000.0],
                })
                .collect(),
            connections: (1..n)
                .map(|i| Connection {
                    elements: [i - 1, i],
                    isot: 1,
                    d: [0.5, 0.5],
                    area: 2.0,
                    cos_gravity: 0.0,
                })
                .collect(),
        }
    }

    #[test]
    fn transmissibility_is_harmonic_in_the_half_distances() {
        // Equal halves: T = c A k / d.
        let t = transmissibility(2.0, [0.5, 0.5], [100.0, 100.0]);
        assert!((t - DARCY * 2.0 * 100.0 / 1.0).abs() < 1e-12);
        // A tight half dominates.
        let t = transmissibility(1.0, [1.0, 1.0], [1.0, 1e9]);
        assert!((t / DARCY - 1.0).abs() < 1e-6);
    }

    #[test]
    fn cells_follow_the_curve_and_links_follow_the_cells() {
        // Two elements listed right to left; the curve starts at the left.
        let mut net = row(2);
        net.elements.reverse();
        let rock = Rock::uniform(2, [100.0, 100.0, 10.0], 0.25);
        let wells = [WellLinks {
            name: "W".into(),
            radius: 0.1,
            links: vec![(0, 2.0)],
            log: 1.0,
        }];
        let (deck, position) = deck("row", &net, &rock, &wells, &DeckSettings::default());
        assert_eq!(position, vec![1, 0]);
        assert_eq!(deck.cells[0].pore_volume, 2.5);
        assert_eq!(deck.nnc[0].cells, [1, 0]);
        assert_eq!(deck.wells[0].connections, vec![(1, DARCY * 100.0 * 2.0)]);
    }

    #[test]
    fn peaceman_on_a_square_cell_is_0_208_of_its_side() {
        // The centre of 3 x 3 cells of side 10 and height 2.
        let at = |i: usize| [(i % 3) as f64 * 10.0, (i / 3) as f64 * 10.0, -1000.0];
        let mut net = row(9);
        net.elements = (0..9)
            .map(|i| Element {
                volume: 200.0,
                node: at(i),
            })
            .collect();
        net.connections = [1, 3, 5, 7]
            .iter()
            .map(|&n| Connection {
                elements: [4, n],
                isot: 1,
                d: [5.0, 5.0],
                area: 20.0,
                cos_gravity: 0.0,
            })
            .collect();
        let (g, r) = peaceman(&net, 4, 2.0, 0.1).unwrap();
        let r_o = 10.0 * (-std::f64::consts::FRAC_PI_2).exp();
        assert!((g - std::f64::consts::TAU * 2.0 / (r_o / 0.1).ln()).abs() < 1e-12);
        assert!((r - r_o).abs() < 1e-12 && (r_o / 10.0 - 0.2079).abs() < 1e-4);
        assert!(peaceman(&net, 4, 2.0, 3.0)
            .unwrap_err()
            .to_string()
            .contains("equivalent radius"));
        assert!(peaceman(&net, 0, 2.0, 0.1)
            .unwrap_err()
            .to_string()
            .contains("no lateral"));
    }

    #[test]
    fn a_column_goes_down_before_the_curve_moves_on() {
        let mut net = row(2);
        net.elements.push(Element {
            volume: 1.0,
            node: [0.0, 0.0, -1010.0],
        });
        assert_eq!(hilbert_order(&net), vec![0, 2, 1]);
    }
}
