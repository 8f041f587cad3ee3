//! The command line's OPM Flow decks (`--eclipse`, docs/simulators.md).

use clap::Args;
use orthomesh::reservoir::deck::{DeckChoices, Rock, WellLinks};
use orthomesh::{io, CellArray, CellMesh, Error, Network, Result};
use std::path::{Path, PathBuf};

/// An OPM Flow deck of the mesh (docs/simulators.md).
#[derive(Args)]
pub(crate) struct DeckArgs {
    /// Also write an Eclipse deck that OPM Flow runs: one cell per mesh
    /// cell, every connection an NNC with its two-point transmissibility,
    /// wells connected through their innermost ring, single-phase water.
    #[arg(long, value_name = "CASE.DATA")]
    pub(crate) eclipse: Option<PathBuf>,
    /// Deck: permeability (mD, along x, y and z; default 100).
    #[arg(long, value_name = "MD")]
    perm: Option<f64>,
    /// Deck: porosity (default 0.2).
    #[arg(long)]
    poro: Option<f64>,
    /// Deck: every well produces water at this rate (sm3/day); default: at
    /// a bottom-hole pressure 10 bar below the initial 200 bar.
    #[arg(long, value_name = "SM3/DAY")]
    rate: Option<f64>,
    /// Deck, `hybrid`: hold the cells on the mesh's outer boundary at their
    /// initial pressure (an open boundary, as an aquifer around the field).
    #[arg(long)]
    aquifer: bool,
    /// Deck: run only this many days (default: 10 days, or the whole
    /// schedule of the input deck).
    #[arg(long)]
    days: Option<f64>,
    /// Deck, `hybrid` with a whole --deck: write the single-phase
    /// water model of the mesh instead of carrying the deck whole (for the
    /// Thiem checks).
    #[arg(long)]
    single_phase: bool,
    /// Deck, a whole --deck carried: merge the cavities' cells whose
    /// transmissibilities over their pore volume exceed SHARE of the
    /// original grid's stiffest cell (an innermost ring's sectors into an
    /// annulus per layer), for Flow's speed; 0.25 on SPE9
    /// (docs/simulators.md).
    #[arg(long = "merge-stiff", value_name = "SHARE")]
    merge_stiff: Option<f64>,
}

impl DeckArgs {
    /// Whether a deck is asked for.
    pub(crate) fn wanted(&self) -> bool {
        self.eclipse.is_some()
    }

    /// Whether the deck carries the input deck whole: asked for, a --deck
    /// with a PROPS section, not --single-phase.
    pub(crate) fn carries(&self, deck: Option<&Path>) -> Result<bool> {
        match (self.wanted() && !self.single_phase, deck) {
            (true, Some(p)) => io::carry::has_section(p, "PROPS"),
            _ => Ok(false),
        }
    }

    /// The deck that carries the input deck whole onto a 3D hybrid mesh,
    /// what it mended and assumed said on standard error.
    pub(crate) fn carried(&self, deck: &Path, mesh: &io::carry::Mesh) -> Result<DeckOut> {
        let Some(path) = &self.eclipse else {
            return Ok(DeckOut::default());
        };
        let c = io::carry::carry(deck, mesh, self.merge_stiff)?;
        Ok(DeckOut::written(path, c.text, &c.notes, &c.position))
    }

    /// Checks the deck's options before any meshing: those that need
    /// --eclipse, --aquifer (for `hybrid` only), and their ranges.
    pub(crate) fn check(&self, hybrid: bool) -> Result<()> {
        let given = [self.perm, self.poro, self.rate, self.days];
        if !self.wanted() && (given.iter().any(Option::is_some) || self.aquifer) {
            return Err(Error::Usage(
                "--perm, --poro, --rate, --days and --aquifer are for --eclipse".into(),
            ));
        }
        if self.single_phase && !self.wanted() {
            return Err(Error::Usage("--single-phase is for --eclipse".into()));
        }
        if let Some(m) = self.merge_stiff {
            if !(self.wanted() && !self.single_phase) {
                return Err(Error::Usage(
                    "--merge-stiff is for a deck carried whole (--eclipse with a whole --deck)"
                        .into(),
                ));
            }
            if !(m.is_finite() && m > 0.0) {
                return Err(Error::Usage(format!("--merge-stiff {m}: a share above 0")));
            }
        }
        if self.aquifer && !hybrid {
            return Err(Error::Usage("--aquifer is for `hybrid`".into()));
        }
        self.choices().check()
    }

    /// Whether an option of the single-phase model is given.
    pub(crate) fn single_phase_options(&self) -> bool {
        [self.perm, self.poro, self.rate, self.days]
            .iter()
            .any(Option::is_some)
            || self.aquifer
    }

    /// The user's choices, before what the input gives.
    fn choices(&self) -> DeckChoices {
        DeckChoices {
            perm: self.perm,
            poro: self.poro,
            rate: self.rate,
            days: self.days,
            ..Default::default()
        }
    }

    /// The deck's file and text for a network and its wells (when a deck
    /// is asked for), with what it assumed said on standard error.
    /// `outer`: the cells an open boundary holds (`--aquifer`).
    pub(crate) fn text<'a>(
        &self,
        title: &str,
        network: &Network,
        wells: &[WellLinks],
        outer: impl FnOnce() -> Vec<usize>,
        input: impl FnOnce() -> Result<FromInput<'a>>,
    ) -> Result<DeckOut> {
        let Some(path) = &self.eclipse else {
            return Ok(DeckOut::default());
        };
        let input = input()?;
        let names: Vec<String> = wells.iter().map(|w| w.name.clone()).collect();
        let choices = DeckChoices {
            length: input.length,
            rock: input.rock,
            aquifer: if self.aquifer { outer() } else { vec![] },
            schedule: input
                .deck
                .map(|p| io::schedule::read_schedule(p, &names))
                .transpose()?,
            equil: match input.deck {
                Some(p) => io::schedule::read_equil(p)?,
                None => None,
            },
            ..self.choices()
        };
        let (text, notes, position) = orthomesh::io::deck::write(title, network, wells, &choices)?;
        Ok(DeckOut::written(path, text, &notes, &position))
    }

    /// The deck of a `conform` mesh when one is asked for (and so the
    /// network built): its wells by Peaceman's factor, nothing from the
    /// input.
    pub(crate) fn plain(
        &self,
        input: &Path,
        network: Option<&Network>,
        wells: &[WellLinks],
    ) -> Result<DeckOut> {
        let Some(network) = network.filter(|_| self.wanted()) else {
            return Ok(DeckOut::default());
        };
        let title = input.display().to_string();
        self.text(
            &title,
            network,
            wells,
            Vec::new,
            || Ok(FromInput::default()),
        )
    }
}

/// What the input gives a deck: its length unit, its deck (whose schedule
/// and EQUIL are read), its rock per mesh cell.
#[derive(Default)]
pub(crate) struct FromInput<'a> {
    pub(crate) length: Option<(f64, String)>,
    pub(crate) deck: Option<&'a Path>,
    pub(crate) rock: Option<(Rock, Vec<String>)>,
}

/// The rock of a grid's cells (`hosts`), from the grid and the deck of
/// wells, with what was assumed and which includes were missing.
pub(crate) fn grid_rock(
    a: &crate::HybridArgs,
    g: &orthomesh::reservoir::CornerPointGrid,
    hosts: &[[usize; 3]],
) -> Result<(Rock, Vec<String>)> {
    let paths: Vec<&Path> = std::iter::once(a.grid.as_path())
        .chain(a.deck.as_deref())
        .collect();
    let (props, missing) = io::eclipse::read_properties(&paths, g.nx * g.ny * g.nz)?;
    let (rock, mut notes) = io::deck::rock_from(&props, hosts, [g.nx, g.ny]);
    for m in missing {
        notes.push(format!("include {m} not found: its arrays are not used"));
    }
    Ok((rock, notes))
}

/// The simulators' files (deck, TOUGH MESH), and the cell arrays that map
/// the mesh's cells onto theirs for the VTU: `deck_cell` (1-based) and
/// `tough_element` (the element's five-character name as ASCII codes).
#[derive(Default)]
pub(crate) struct DeckOut {
    pub(crate) files: Vec<(PathBuf, String)>,
    pub(crate) arrays: Vec<CellArray>,
}

impl DeckOut {
    /// A deck's file and its cells' map for the VTU (`deck_cell`, 1-based),
    /// what it assumed said on standard error.
    fn written(path: &Path, text: String, notes: &[String], position: &[usize]) -> DeckOut {
        for n in notes {
            eprintln!("deck: {n}");
        }
        let cells = position.iter().map(|&i| i as i64 + 1).collect();
        DeckOut {
            files: vec![(path.to_path_buf(), text)],
            arrays: vec![CellArray::int("deck_cell", 1, cells)],
        }
    }

    /// Adds a TOUGH MESH file of the network, and its element names.
    pub(crate) fn tough(mut self, path: Option<&Path>, network: Option<&Network>) -> Result<Self> {
        if let (Some(path), Some(network)) = (path, network) {
            self.files
                .push((path.to_path_buf(), io::tough::to_string(network)?));
            self.arrays
                .push(io::tough::names_array(network.elements.len())?);
        }
        Ok(self)
    }

    /// The VTU text of a mesh, with the simulators' cell arrays.
    pub(crate) fn vtu(&self, mut mesh: CellMesh) -> String {
        mesh.data.extend(self.arrays.iter().cloned());
        io::vtu::to_string(&mesh)
    }
}

/// The grid's length unit: its GRIDUNIT, else the unit system of the
/// grid or of the deck of wells (for the deck).
pub(crate) fn grid_unit(a: &crate::HybridArgs) -> Result<Option<(f64, String)>> {
    for p in std::iter::once(&a.grid).chain(&a.deck) {
        if let Some((f, name)) = io::eclipse::length_unit(p)? {
            return Ok(Some((f, format!("{name} in {}", p.display()))));
        }
    }
    Ok(None)
}

/// The wells of a 2D `conform` deck (`--well-xy NAME:X:Y[:RADIUS]`): each
/// connected to the one cell that holds its point by Peaceman's factor,
/// what it assumed said on standard error.
pub(crate) fn point_wells(
    specs: &[String],
    mesh: &orthomesh::Mesh,
    network: &Network,
    thickness: f64,
) -> Result<Vec<WellLinks>> {
    let mut wells: Vec<WellLinks> = vec![];
    for spec in specs {
        let (name, x, y, radius) = crate::well_spec(spec)?;
        if wells.iter().any(|w| w.name == name) {
            return Err(Error::Usage(format!("well {name} is given twice")));
        }
        if radius <= 0.0 {
            return Err(Error::Usage(format!(
                "well {name}: radius {radius} is not positive"
            )));
        }
        let cell = match mesh.locate([x, y])[..] {
            [c] => c,
            [] => {
                return Err(Error::Usage(format!(
                    "well {name}: ({x}, {y}) is outside the mesh"
                )))
            }
            ref cells => {
                return Err(Error::Usage(format!(
                "well {name}: ({x}, {y}) is on the boundary of cells {cells:?}: move it into one"
            )))
            }
        };
        let (factor, r_o) = orthomesh::reservoir::deck::peaceman(network, cell, thickness, radius)
            .map_err(|e| Error::Usage(format!("well {name}: {e}")))?;
        let s = mesh.sites[cell];
        eprintln!(
            "deck: well {name} in cell {cell} by Peaceman's factor (equivalent radius {r_o:.4}); \
             the factor takes the well at the site, {:.4} from ({x}, {y})",
            (s[0] - x).hypot(s[1] - y)
        );
        wells.push(WellLinks {
            name,
            radius,
            links: vec![(cell, factor)],
            log: (r_o / radius).ln(),
        });
    }
    Ok(wells)
}
