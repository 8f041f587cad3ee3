//! The orthomesh command line: each subcommand parses its arguments, calls
//! the library, and writes every output whole or none.

use clap::{Args, Parser, Subcommand, ValueEnum};
use orthomesh::reservoir::deck::DeckChoices;
use orthomesh::reservoir::{self as hybrid};
use orthomesh::Keep;
use orthomesh::Progress;
use orthomesh::{io, Backend, CellArray, Complex, Complex3, Mesher, Options};
use orthomesh::{Error, Result};
use orthomesh::{Outcome, D2, D3};
mod allocator;
mod deck;
mod hybrid2d;
mod hybrid3d;

use deck::{DeckArgs, DeckOut};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Conforming orthogonal meshes: power diagrams whose edges contain your
/// constraint segments exactly, with sites inside their cells, and an exact
/// certificate.
#[derive(Parser)]
#[command(
    name = "orthomesh",
    version,
    after_help = "Examples:\n  orthomesh demo --out-dir out\n  orthomesh conform A.poly -o A.vtu --svg A.svg --report A.json\n\n\
Exit status: 0 when the mesh is written and its exact certificate holds; 1 on\n\
any error (bad input, no conforming mesh, sites outside cells), with nothing written."
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
    /// Triangulation backend: cgal (default when compiled in) or pure
    /// (feature pure-rust).
    #[arg(long, global = true, default_value_t = orthomesh::default_backend().name().to_string(),
          value_parser = clap::builder::PossibleValuesParser::new(backend_names()))]
    backend: String,
}

/// The names of the backends compiled in.
fn backend_names() -> Vec<&'static str> {
    orthomesh::compiled().iter().map(|b| b.name()).collect()
}

#[derive(Subcommand)]
enum Command {
    /// Mesh a constraint complex: 2D (Triangle .poly with holes, CGAL .edg)
    /// or 3D (TetGen .poly or .smesh); the file tells the dimension.
    ///
    /// 2D: the domain is what Triangle's `p` switch meshes: the region
    /// bounded by the segments minus the hole regions; with no enclosing
    /// segments, the convex hull. Every input segment becomes exactly one
    /// mesh edge. 3D: the domain is the region the facets enclose minus the
    /// volume holes; every facet triangle (or rectangle kept whole) becomes
    /// exactly one face of the polyhedral cells (VTU type 42).
    Conform(ConformArgs),
    /// Hybrid reservoir mesh of one layer of a corner-point grid: reservoir
    /// cells, radial meshes around vertical wells, and conforming orthogonal
    /// transition meshes in cavities between them.
    ///
    /// Wells come from the deck (WELSPECS head column, COMPDAT diameter) and
    /// from --well options. Cell data: region (0 reservoir, 1 transition,
    /// 2 well), ijk (1-based; -1 outside the reservoir grid), site, weight.
    Hybrid(HybridArgs),
    /// Write a synthetic input of any size as a .poly file (benchmarks,
    /// scale tests): `mixed N` is N x N separate cavities with wells,
    /// faults and non-Gabriel chains (about 33 N^2 segments, all needing
    /// the LP); `cavities N` is N x N cavities sharing sides, wells at
    /// radius 14 (zero weights); `wells N` is a corner-point grid with
    /// N x N wells (GRDECL and a .DATA beside it).
    Generate(GenerateArgs),
    /// Mesh built-in data (a cavity around a well) and write mesh, picture
    /// and report into a directory.
    Demo(DemoArgs),
}

#[derive(Args)]
struct ConformArgs {
    /// Input file: .poly (2D or 3D), .edg (2D segments), .smesh (3D).
    input: PathBuf,
    #[command(flatten)]
    out: Outputs,
    /// 3D: also write a TOUGH2 MESH file (ELEME/CONNE; nodes at the sites).
    #[arg(long, value_name = "MESH")]
    tough: Option<PathBuf>,
    /// Write the conforming mesh even when some sites cannot be inside
    /// their cells (the report counts them; the picture shows them red).
    #[arg(long)]
    allow_sites_outside: bool,
    /// Where some segments cannot cross their dual edges (system 3
    /// infeasible), split them at Steiner points, as few as needed for
    /// every site to lie in its cell: they become chains of mesh edges
    /// (listed in the report) instead of single edges.
    #[arg(long)]
    split_segments: bool,
    /// 3D: how polygons kept whole keep their lifts coplanar: shared
    /// (one weight per group of polygons joined at vertices, so that
    /// each polygon's power centre is its circumcentre: orthogonal links
    /// to cells centred on it), coplanar (docs/method.md's equality rows,
    /// exact: more freedom), or auto (shared, then coplanar where
    /// shared weights leave no solution).
    #[arg(long, value_name = "WAY", value_enum, default_value_t = Keep::Auto)]
    whole_polygons: Keep,
    /// 3D: where facet triangles miss their dual edges (so that a site
    /// stays outside its cell), add Steiner points inside the facets at
    /// the triangles' power centres, round by round while fewer sites
    /// stay outside; the points are listed in the report.
    #[arg(long)]
    split_facets: bool,
    /// 3D: facets on the convex hull (every point on one side) bound
    /// the mesh with nothing beyond: cut the cells at their planes
    /// (mirrored sites) instead of making each one face. Their
    /// triangles then need not cross their duals; the report lists
    /// them (clip_facets).
    #[arg(long)]
    clip_hull: bool,
    #[command(flatten)]
    deck: DeckArgs,
    /// Deck, 2D: a vertical well at X, Y, connected to the cell there by
    /// Peaceman's factor (radius default 0.1).
    #[arg(long = "well-xy", value_name = "NAME:X:Y[:RADIUS]")]
    wells_xy: Vec<String>,
    /// Deck, 2D: the cells' thickness (m).
    #[arg(long, default_value_t = 1.0)]
    thickness: f64,
    /// Deck, 2D: the cells' mid-depth (m).
    #[arg(long, default_value_t = 1000.0)]
    depth: f64,
}

#[derive(Args)]
struct HybridArgs {
    /// The corner-point grid (Eclipse GRDECL).
    #[arg(long, value_name = "GRID.grdecl")]
    grid: PathBuf,
    /// A deck whose WELSPECS/COMPDAT give wells.
    #[arg(long, value_name = "CASE.DATA")]
    deck: Option<PathBuf>,
    /// A vertical well in column I, J (1-based, as in the deck), with a
    /// wellbore radius in grid units (default: the deck's, else 0.1).
    #[arg(long = "well", value_name = "NAME:I:J[:RADIUS]")]
    wells: Vec<String>,
    /// A vertical well at map position X, Y.
    #[arg(long = "well-xy", value_name = "NAME:X:Y[:RADIUS]")]
    wells_xy: Vec<String>,
    /// 3D: a well along a trajectory file (a point per line: x, y, depth
    /// positive down, further columns such as measured depth ignored; as
    /// xtgeo and RMS export them), completed over its whole length;
    /// horizontal wells come this way. Where it bends, it is meshed as its
    /// straight legs (points within a tenth of the outer radius of them),
    /// joined by mitred knees (docs/reservoir.md).
    #[arg(
        long = "well-path",
        value_name = "NAME:FILE[:RADIUS]",
        requires = "three_d"
    )]
    well_paths: Vec<String>,
    /// A fault as a map polyline: its parts inside cavities become
    /// constraint chains (FAULTS in the grid are used too).
    #[arg(long = "fault", value_name = "X1,Y1,X2,Y2[,...]")]
    faults: Vec<String>,
    /// Radial meshes for these wells only (names, comma-separated); the
    /// others are left out of the mesh, and a deck carried whole keeps
    /// their connections on their cells (the input's factors, else Flow's
    /// own).
    #[arg(long, value_name = "NAME[,NAME...]", value_delimiter = ',')]
    radial: Vec<String>,
    /// The layer whose map view is meshed (1-based).
    #[arg(long, default_value_t = 1)]
    layer: usize,
    /// 2.5D: map the mesh onto every layer of the grid and write
    /// polyhedra (type 42) and, with --tough, vertical connections too.
    #[arg(long)]
    layers: bool,
    /// Rings of each radial mesh (default 12; with --3d, 6 where the
    /// transition is meshed in 3D).
    #[arg(long)]
    rings: Option<usize>,
    /// Sectors of each radial mesh (default 32; with --3d, 16 where the
    /// transition is meshed in 3D).
    #[arg(long)]
    sectors: Option<usize>,
    /// Outer radius of the radial meshes, in shortest sides of the well's
    /// cell (default 1.9; with --3d, 1.0 where the transition is meshed in
    /// 3D).
    #[arg(long)]
    outer: Option<f64>,
    /// True 3D: wells from the deck (WELSPECS, COMPDAT's cells and
    /// diameter) or --well NAME:I:J[:K1-K2][:RADIUS[:DIP:AZIMUTH]] (K1-K2
    /// the completed layers, default all), each with a radial mesh through
    /// its completed cells (following leaning columns and changes of
    /// column; DIP:AZIMUTH, degrees from vertical and clockwise from +y,
    /// asks for a straight axis instead, 0:0 vertical), in a cavity of the
    /// cells within one cell of them (polyhedra). Where those cells lie
    /// between parallel planes (a dipping layer cake, as SPE9), the
    /// transition is a 2D section across the layers taken through each
    /// layer, the radial meshes along the layers' normal; else it is meshed
    /// in 3D.
    #[arg(long = "3d", conflicts_with_all = ["wells_xy", "faults", "layers", "margin", "svg"])]
    three_d: bool,
    /// Layers of cells added to each cavity around what the radial mesh reaches.
    #[arg(long, default_value_t = 0)]
    margin: usize,
    /// Refuse (exit 1, no file) when some transition sites cannot be
    /// inside their cells once the cavities have grown as far as they can.
    /// By default the certified mesh is written and the sites outside are
    /// counted: the grid imposes its geometry.
    #[arg(long)]
    strict: bool,
    /// The default (kept for scripts written before --strict).
    #[arg(long, hide = true, conflicts_with = "strict")]
    allow_sites_outside: bool,
    /// 3D: where facet triangles miss their dual edges (so that a site
    /// stays outside its cell), add Steiner points inside the facets at
    /// the triangles' power centres, round by round while fewer sites
    /// stay outside; the points are listed in the report.
    #[arg(long, requires = "three_d")]
    split_facets: bool,
    /// 3D: mesh the transition in 3D even where the cavities' layers are
    /// parallel planes (where the layered transition would serve).
    #[arg(long = "transition-3d", requires = "three_d")]
    transition_3d: bool,
    /// 3D, layered sections on planes: radial meshes out to --outer over
    /// several columns (the well's inflow closer to Thiem's, fewer links
    /// to the reservoir cells below and above orthogonal) instead of
    /// inside their well's column.
    #[arg(long = "rings-over-columns", requires = "three_d")]
    rings_over_columns: bool,
    /// 3D: the innermost ring's outer radius as a share of the outer
    /// radius (between 0 and 1), the rings beyond it geometric. For
    /// simulators: the innermost cells then hold a share of the well's
    /// cell instead of a sliver of wellbore (Flow's steps follow its
    /// smallest cells); the wellbore's connection factor still runs
    /// exactly from the wellbore to the first ring's sites.
    #[arg(long = "first-ring", requires = "three_d", value_parser = share)]
    first_ring: Option<f64>,
    /// Also write a TOUGH2 MESH file (ELEME/CONNE; nodes at the sites).
    #[arg(long, value_name = "MESH")]
    tough: Option<PathBuf>,
    #[command(flatten)]
    simulator: DeckArgs,
    #[command(flatten)]
    out: Outputs,
}

/// Synthetic inputs.
#[derive(Clone, Copy, ValueEnum)]
enum Kind {
    /// Separate cavities with wells, faults and chains (the LP).
    Mixed,
    /// Cavities sharing sides, wells at radius 14 (zero weights).
    Cavities,
    /// Separate cavities of 16 unit sides, each with a well off centre, a
    /// fault with two free ends and isolated points (zero weights).
    Field,
    /// 3D: an N x N grid of unit columns, each a stack of `--layers` boxes
    /// with an octagonal prism well through it (a TetGen .poly; zero weights).
    Field3,
    /// 3D reservoir: N x N vertical wells six columns apart on a dipping
    /// layer cake of (6 N + 1)^2 columns and 6 layers (the output is its
    /// GRDECL; the wells go to a .DATA beside it, for `hybrid --3d`).
    Wells,
}

#[derive(Args)]
struct GenerateArgs {
    /// What to generate.
    #[arg(value_enum)]
    kind: Kind,
    /// Cavities per side.
    #[arg(value_parser = clap::value_parser!(u16).range(1..=1000))]
    n: u16,
    /// `field`: isolated points per cavity.
    #[arg(long, default_value_t = 2, value_parser = clap::value_parser!(u16).range(0..=100))]
    points: u16,
    /// `field3`: layers.
    #[arg(long, default_value_t = 4, value_parser = clap::value_parser!(u16).range(1..=1000))]
    layers: u16,
    /// (.poly; `field3` a TetGen .poly; `wells` a .grdecl)
    #[arg(short, long, value_name = "FILE.poly")]
    output: PathBuf,
}

#[derive(Args)]
struct DemoArgs {
    /// Where to write demo.vtu, demo.svg, demo.json, demo.mesh (TOUGH) and
    /// demo.DATA (OPM Flow).
    #[arg(long, default_value = "orthomesh-demo")]
    out_dir: PathBuf,
}

/// Where the results go.
#[derive(Args)]
struct Outputs {
    /// Output mesh (.vtu: polygons with cell data site and weight).
    #[arg(short, long, value_name = "MESH.vtu")]
    output: PathBuf,
    /// Also draw the mesh, sites and constraint segments as SVG.
    #[arg(long, value_name = "PICTURE.svg")]
    svg: Option<PathBuf>,
    /// Write the report (certificate, weights, timings) as JSON.
    #[arg(long, value_name = "REPORT.json")]
    report: Option<PathBuf>,
    /// Leave time and memory out of the report, so that the same input
    /// gives byte-identical files (mesh and report) on every run.
    #[arg(long)]
    reproducible: bool,
}

fn main() -> ExitCode {
    allocator::keep_freed_memory();
    // Usage errors exit 1 like every other error (help and version: 0).
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) if e.use_stderr() => {
            eprint!("orthomesh: {}", e.render());
            return ExitCode::FAILURE;
        }
        Err(e) => {
            let _ = e.print();
            return ExitCode::SUCCESS;
        }
    };
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("orthomesh: error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run(cli: Cli) -> Result<()> {
    let backend = orthomesh::by_name(&cli.backend)?;
    let backend = &*backend;
    match cli.command {
        Command::Conform(a) => match io::read_input(&a.input)? {
            io::Input::Plane(cx) => conform2(backend, &cx, a),
            io::Input::Space(cx) => conform3(backend, &cx, a),
        },
        Command::Hybrid(a) if a.three_d => hybrid3d::run(backend, a),
        Command::Hybrid(a) => hybrid2d::run(backend, a),
        Command::Generate(a) => generate(a),
        Command::Demo(a) => demo(backend, a),
    }
}

/// `conform` on a 2D complex.
fn conform2(backend: &dyn Backend, cx: &Complex, a: ConformArgs) -> Result<()> {
    if a.tough.is_some() {
        return Err(Error::Usage(
            "--tough is for 3D inputs (and for `hybrid`)".into(),
        ));
    }
    if a.whole_polygons != Keep::Auto || a.split_facets || a.clip_hull {
        return Err(Error::Usage(
            "--whole-polygons, --split-facets and --clip-hull are for 3D inputs".into(),
        ));
    }
    a.deck.check(false)?;
    if !a.wells_xy.is_empty() && !a.deck.wanted() {
        return Err(Error::Usage(
            "--well-xy on `conform` is for --eclipse".into(),
        ));
    }
    if !(a.thickness > 0.0 && a.thickness.is_finite() && a.depth.is_finite()) {
        return Err(Error::Usage(
            "--thickness must be positive and --depth finite".into(),
        ));
    }
    let watched = cx.segments.len() >= MANY_SEGMENTS && std::io::stderr().is_terminal();
    let opts = Options {
        allow_sites_outside: a.allow_sites_outside,
        split_segments: a.split_segments,
        compare_with_raw: true,
        // a progress bar for long runs when someone watches
        progress: watched.then_some(bar as Progress),
        ..Default::default()
    };
    let mut out = Mesher::new(backend).options(opts).conform(cx)?;
    finish_bar();
    let timing = if a.out.reproducible {
        out.report.timing.take()
    } else {
        out.report.timing.clone()
    };
    let network = a.deck.wanted().then(|| {
        let n = out.mesh.cells.len();
        orthomesh::reservoir::flow::network(&out.mesh, &vec![a.thickness; n], &vec![a.depth; n])
    });
    let wells = match &network {
        Some(net) => deck::point_wells(&a.wells_xy, &out.mesh, net, a.thickness)?,
        None => vec![],
    };
    let deck = a.deck.plain(&a.input, network.as_ref(), &wells)?;
    let o = &a.out;
    write_all(
        &out,
        cx,
        &a.input,
        &o.output,
        o.svg.as_deref(),
        o.report.as_deref(),
        deck,
    )?;
    if let Some(t) = timing {
        eprintln!(
            "{:.1} ms total (raw triangulation {:.2} ms), peak memory {:.0} MiB",
            t.total_ms,
            t.raw_triangulation_ms.unwrap_or(f64::NAN),
            t.peak_mib.unwrap_or(f64::NAN)
        );
    }
    Ok(())
}

/// `conform` on a 3D complex.
fn conform3(backend: &dyn Backend, cx: &Complex3, a: ConformArgs) -> Result<()> {
    if a.out.svg.is_some() || a.split_segments || !a.wells_xy.is_empty() {
        return Err(Error::Usage(
            "--svg, --split-segments and --well-xy are for 2D inputs (--split-facets in 3D)".into(),
        ));
    }
    a.deck.check(false)?;
    let opts = Options {
        allow_sites_outside: a.allow_sites_outside,
        whole_polygons: a.whole_polygons,
        split_facets: a.split_facets,
        clip: if a.clip_hull {
            orthomesh::hull_facets(cx)
        } else {
            vec![]
        },
        ..Default::default()
    };
    let mut out = Mesher::new(backend).options(opts).conform(cx)?;
    if a.out.reproducible {
        out.report.timing = None;
    }
    let network = (a.tough.is_some() || a.deck.wanted()).then(|| out.mesh.network());
    let deck = a
        .deck
        .plain(&a.input, network.as_ref(), &[])?
        .tough(a.tough.as_deref(), network.as_ref())?;
    let o = &a.out;
    write_all3(&out, cx, &a.input, &o.output, o.report.as_deref(), deck)
}

/// The deck's wells (WELSPECS, COMPDAT), if a deck is given; includes that
/// do not exist are noted.
fn deck_wells(a: &HybridArgs) -> Result<Vec<io::eclipse::Well>> {
    let Some(deck) = &a.deck else {
        return Ok(vec![]);
    };
    let (found, missing) = io::eclipse::read_wells(deck)?;
    for m in missing {
        eprintln!(
            "note: {}: include {m} not found (not needed for wells)",
            deck.display()
        );
    }
    Ok(found)
}

/// Keeps the wells --radial names (all where it names none); Err naming
/// one it names that is no well.
fn only_radial<T>(a: &HybridArgs, list: &mut Vec<T>, name: impl Fn(&T) -> &str) -> Result<()> {
    if a.radial.is_empty() {
        return Ok(());
    }
    if let Some(n) = a
        .radial
        .iter()
        .find(|n| !list.iter().any(|w| name(w) == n.as_str()))
    {
        let known: Vec<&str> = list.iter().map(&name).collect();
        return Err(Error::Usage(format!(
            "--radial: no well {n} (the wells: {})",
            known.join(", ")
        )));
    }
    list.retain(|w| a.radial.iter().any(|n| n == name(w)));
    Ok(())
}

/// `generate wells`: the largest N (10,000 wells on 2.2 million cells; at
/// 1,000 the grid alone would take 14 GB).
const MAX_WELLS_N: usize = 100;

/// `generate`: a synthetic input as a .poly file.
fn generate(a: GenerateArgs) -> Result<()> {
    let n = usize::from(a.n);
    let cx = match a.kind {
        Kind::Field3 => {
            let cx = orthomesh::generate::field3(n, usize::from(a.layers));
            io::write_atomic(&a.output, io::tetgen::to_string(&cx).as_bytes())?;
            let polygons: usize = cx.facets.iter().map(|f| f.polygons.len()).sum();
            let (v, f) = (cx.points.len(), cx.facets.len());
            eprintln!(
                "wrote {}: {v} vertices, {f} facets, {polygons} polygons",
                a.output.display()
            );
            return Ok(());
        }
        Kind::Wells => {
            let deck = a.output.with_extension("DATA");
            if n > MAX_WELLS_N || deck == a.output {
                return Err(Error::Usage(format!(
                    "generate wells: N is at most {MAX_WELLS_N} ({} columns a side), and the \
                     output not a .DATA (the wells' deck goes there); got {n} and {}",
                    6 * MAX_WELLS_N + 1,
                    a.output.display()
                )));
            }
            let (g, wells) = orthomesh::reservoir::synthetic::well_field(n);
            let written = io::eclipse::wells_deck(&wells, g.nz);
            io::write_atomic(&a.output, io::eclipse::grdecl(&g).as_bytes())?;
            if let Err(e) = io::write_atomic(&deck, written.as_bytes()) {
                let _ = std::fs::remove_file(&a.output); // (no grid without its wells)
                return Err(e);
            }
            eprintln!(
                "wrote {} ({} x {} x {} cells) and {} ({} wells)",
                a.output.display(),
                g.nx,
                g.ny,
                g.nz,
                deck.display(),
                wells.len()
            );
            return Ok(());
        }
        Kind::Mixed => orthomesh::generate::mixed(n, n, 7),
        Kind::Cavities => orthomesh::generate::cavities(n, n, 14.0),
        Kind::Field => orthomesh::generate::field(n, n, usize::from(a.points), 7),
    };
    io::write_atomic(&a.output, io::poly::to_string(&cx).as_bytes())?;
    eprintln!(
        "wrote {}: {} vertices, {} segments, {} holes",
        a.output.display(),
        cx.points.len(),
        cx.segments.len(),
        cx.holes.len()
    );
    Ok(())
}

/// `demo`: the built-in hybrid mesh, its picture, report, TOUGH MESH and
/// OPM Flow deck.
fn demo(backend: &dyn Backend, a: DemoArgs) -> Result<()> {
    let (g, wells, opts) = hybrid::demo();
    let h = hybrid::build(backend, &g, &wells, &opts)?;
    let out_dir = a.out_dir;
    std::fs::create_dir_all(&out_dir).map_err(|e| Error::Io {
        path: out_dir.clone(),
        message: e.to_string(),
    })?;
    let inside = vec![true; h.mesh.cells.len()];
    let report =
        serde_json::to_string_pretty(&h.report).map_err(|e| Error::Usage(e.to_string()))?;
    let choices = DeckChoices {
        length: Some((1.0, "metres (the built-in grid)".into())),
        aquifer: h.outer_cells(),
        ..Default::default()
    };
    let network = h.network();
    let (deck, _, position) =
        orthomesh::io::deck::write("orthomesh demo", &network, &h.well_links(), &choices)?;
    let cells = position.iter().map(|&i| i as i64 + 1).collect();
    let sim = DeckOut {
        files: vec![(out_dir.join("demo.DATA"), deck)],
        arrays: vec![CellArray::int("deck_cell", 1, cells)],
    }
    .tough(Some(&out_dir.join("demo.mesh")), Some(&network))?;
    let mut texts = vec![
        (out_dir.join("demo.vtu"), sim.vtu(h.cells())),
        (
            out_dir.join("demo.svg"),
            io::svg::to_string(&h.mesh, &inside, &h.constraints),
        ),
        (out_dir.join("demo.json"), report + "\n"),
    ];
    texts.extend(sim.files);
    write_texts(&texts, || {
        hybrid2d::summarise("built-in grid (15 x 15 cells, a fault)", &h);
    })
}

/// Writes every output whole (temporary file, then rename), then a summary.
fn write_all(
    out: &Outcome<D2>,
    cx: &Complex,
    input: &Path,
    vtu: &Path,
    svg: Option<&Path>,
    report: Option<&Path>,
    deck: DeckOut,
) -> Result<()> {
    let mut texts = vec![(
        vtu.to_path_buf(),
        deck.vtu(out.mesh.cells(&out.site_inside)),
    )];
    texts.extend(deck.files);
    if let Some(p) = svg {
        texts.push((
            p.to_path_buf(),
            io::svg::to_string(&out.mesh, &out.site_inside, &out.constraints),
        ));
    }
    if let Some(p) = report {
        texts.push((p.to_path_buf(), report_text(&out.report, input)?));
    }
    write_texts(&texts, || {
        let r = &out.report;
        let c = &r.certificate;
        eprintln!(
            "{}: {} vertices, {} segments -> {} cells ({} mesh vertices); weights: {}{}; sites outside their cells: {}",
            input.display(),
            cx.points.len(),
            cx.segments.len(),
            r.cells,
            r.mesh_vertices,
            r.weights.method,
            r.weights.margin.map(|m| format!(" (LP margin {m:.3e})")).unwrap_or_default(),
            c.sites_outside
        );
        eprintln!(
            "certificate: vertices {} segments {} tiling {} sites-inside {}",
            ok(c.vertices_are_mesh_vertices),
            ok(c.segments_are_single_edges),
            ok(c.cells_tile_domain),
            ok(c.sites_inside_cells),
        );
        for n in &r.input.notes {
            eprintln!("note: {n}");
        }
    })?;
    Ok(())
}

/// Writes every text whole (temporary file, then rename), and only when
/// all are written the summary and the paths.
fn write_texts(texts: &[(PathBuf, String)], summary: impl FnOnce()) -> Result<()> {
    for (p, t) in texts {
        io::write_atomic(p, t.as_bytes())?;
    }
    summary();
    for (p, _) in texts {
        eprintln!("wrote {}", p.display());
    }
    Ok(())
}

/// A report as pretty JSON, with the input's path.
fn report_text<R: serde::Serialize>(report: &R, input: &Path) -> Result<String> {
    let mut value = serde_json::to_value(report).map_err(|e| Error::Usage(e.to_string()))?;
    value["input"] = serde_json::Value::String(input.display().to_string());
    Ok(serde_json::to_string_pretty(&value).unwrap_or_default() + "\n")
}

fn write_all3(
    out: &Outcome<D3>,
    cx: &Complex3,
    input: &Path,
    vtu: &Path,
    report: Option<&Path>,
    deck: DeckOut,
) -> Result<()> {
    let mut texts = vec![(vtu.to_path_buf(), deck.vtu(out.mesh.cells()))];
    texts.extend(deck.files);
    if let Some(p) = report {
        texts.push((p.to_path_buf(), report_text(&out.report, input)?));
    }
    write_texts(&texts, || {
        let r = &out.report;
        let c = &r.certificate;
        eprintln!(
            "{}: {} vertices, {} facets ({} triangles, {} polygons kept whole by {} lifts, {} cut at) -> {} cells ({} mesh vertices); \
             weights: {}{}; sites outside their cells: {}",
            input.display(),
            cx.points.len(),
            cx.facets.len(),
            r.input.triangles,
            r.input.whole_polygons,
            r.input.whole_polygons_kept,
            r.input.clip_facets.len(),
            r.cells,
            r.mesh_vertices,
            r.weights.method,
            r.weights.margin.map(|m| format!(" (LP margin {m:.3e})")).unwrap_or_default(),
            r.sites.sites_outside
        );
        eprintln!(
            "certificate: faces {}/{} vertices {}/{} segments {}/{} volume {:.6e} of {:.6e} sites-inside {}/{}",
            c.faces_exact,
            c.faces,
            c.vertices_exact,
            c.vertices,
            c.segments_exact,
            c.segments,
            c.cells_volume,
            c.domain_volume,
            c.sites_inside,
            c.domain_sites
        );
        if let Some(t) = &r.timing {
            eprintln!("{:.1} ms total", t.total_ms);
        }
    })?;
    Ok(())
}

/// From this many wells on, `hybrid` shows a progress bar on a terminal.
const MANY_WELLS: usize = 50;
/// From this many segments on, `conform` shows one.
const MANY_SEGMENTS: usize = 20_000;

/// The progress bar (`Progress` is a plain function, so the bar is global).
static BAR: std::sync::OnceLock<indicatif::ProgressBar> = std::sync::OnceLock::new();

/// Shows stage and count on the bar.
fn bar(stage: &str, done: usize, of: usize) {
    let b = BAR.get_or_init(|| {
        let b = indicatif::ProgressBar::new(0);
        let style = indicatif::ProgressStyle::with_template("{msg:<28} [{bar:30}] {pos}/{len}")
            .expect("a valid template")
            .progress_chars("#  ");
        b.set_style(style);
        b
    });
    b.set_length(of as u64);
    b.set_position(done as u64);
    b.set_message(stage.to_string());
}

/// Clears the bar, if one was shown.
fn finish_bar() {
    if let Some(b) = BAR.get() {
        b.finish_and_clear();
    }
}

/// Wellbore radius when neither the deck nor the option gives one.
const DEFAULT_WELL_RADIUS: f64 = 0.1;

/// NAME:A:B[:RADIUS]
pub(crate) fn well_spec(spec: &str) -> Result<(String, f64, f64, f64)> {
    let parts: Vec<&str> = spec.split(':').collect();
    let bad = || Error::Usage(format!("well '{spec}': expected NAME:A:B[:RADIUS]"));
    if !(3..=4).contains(&parts.len()) || parts[0].is_empty() {
        return Err(bad());
    }
    let num = |t: &str| {
        t.parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(bad)
    };
    let r = match parts.get(3) {
        Some(t) => num(t)?,
        None => DEFAULT_WELL_RADIUS,
    };
    Ok((parts[0].to_string(), num(parts[1])?, num(parts[2])?, r))
}

/// X1,Y1,X2,Y2[,...]
fn polyline(spec: &str) -> Result<Vec<[f64; 2]>> {
    let v: Vec<f64> = spec
        .split(',')
        .map(|t| t.trim().parse::<f64>().ok().filter(|x| x.is_finite()))
        .collect::<Option<_>>()
        .filter(|v: &Vec<f64>| v.len() >= 4 && v.len() % 2 == 0)
        .ok_or_else(|| Error::Usage(format!("fault '{spec}': expected X1,Y1,X2,Y2[,...]")))?;
    Ok(v.chunks(2).map(|c| [c[0], c[1]]).collect())
}

fn one_based(v: f64, spec: &str) -> Result<usize> {
    if v >= 1.0 && v.fract() == 0.0 && v < 1e9 {
        Ok(v as usize - 1)
    } else {
        Err(Error::Usage(format!(
            "well '{spec}': I, J and K are whole numbers from 1"
        )))
    }
}

fn ok(b: bool) -> &'static str {
    if b {
        "ok"
    } else {
        "FAILED"
    }
}

/// A share strictly between 0 and 1 (`--first-ring`).
fn share(s: &str) -> std::result::Result<f64, String> {
    match s.parse::<f64>() {
        Ok(x) if x > 0.0 && x < 1.0 => Ok(x),
        _ => Err(format!("{s:?} is not a number strictly between 0 and 1")),
    }
}
