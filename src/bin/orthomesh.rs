//! The orthomesh command line.

use clap::{Parser, Subcommand};
use orthomesh::conform::{conform, Options, Outcome};
use orthomesh::error::{Error, Result};
use orthomesh::{backend::default_backend, io, Complex};
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
}

#[derive(Subcommand)]
enum Command {
    /// Mesh a 2D constraint complex (Triangle .poly with holes, or CGAL .edg).
    ///
    /// The domain is what Triangle's `p` switch meshes: the region bounded by
    /// the segments minus the hole regions; with no enclosing segments, the
    /// convex hull. Every input segment becomes exactly one mesh edge.
    Conform {
        /// Input file: .poly (vertices, segments, holes) or .edg (segments).
        input: PathBuf,
        /// Output mesh (.vtu, polygons, cell data site/weight/site_inside).
        #[arg(short, long, value_name = "MESH.vtu")]
        output: PathBuf,
        /// Also draw the mesh, sites and segments as SVG.
        #[arg(long, value_name = "PICTURE.svg")]
        svg: Option<PathBuf>,
        /// Write the report (certificate, LP, timings) as JSON.
        #[arg(long, value_name = "REPORT.json")]
        report: Option<PathBuf>,
        /// Write the conforming mesh even when some sites cannot be inside
        /// their cells (the report counts them; the picture shows them red).
        #[arg(long)]
        allow_sites_outside: bool,
    },
    /// Mesh built-in data (a cavity around a well) and write mesh, picture
    /// and report into a directory.
    Demo {
        /// Where to write demo.vtu, demo.svg and demo.json.
        #[arg(long, default_value = "orthomesh-demo")]
        out_dir: PathBuf,
    },
}

const DEMO: &str = include_str!("../../data/demo.poly");

fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(cli.command) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("orthomesh: error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run(cmd: Command) -> Result<()> {
    match cmd {
        Command::Conform {
            input,
            output,
            svg,
            report,
            allow_sites_outside,
        } => {
            let cx = io::read_complex(&input)?;
            let opts = Options {
                allow_sites_outside,
                compare_with_raw: true,
            };
            let out = conform(&default_backend(), &cx, &opts)?;
            write_all(
                &out,
                &cx,
                &input,
                &output,
                svg.as_deref(),
                report.as_deref(),
            )
        }
        Command::Demo { out_dir } => {
            let name = Path::new("demo.poly");
            let cx = io::poly::parse(DEMO, name)?;
            let opts = Options {
                compare_with_raw: true,
                ..Default::default()
            };
            let out = conform(&default_backend(), &cx, &opts)?;
            std::fs::create_dir_all(&out_dir).map_err(|e| Error::Io {
                path: out_dir.clone(),
                message: e.to_string(),
            })?;
            let (vtu, svg, json) = (
                out_dir.join("demo.vtu"),
                out_dir.join("demo.svg"),
                out_dir.join("demo.json"),
            );
            write_all(&out, &cx, name, &vtu, Some(&svg), Some(&json))
        }
    }
}

/// Writes every output whole (temporary file, then rename), then a summary.
fn write_all(
    out: &Outcome,
    cx: &Complex,
    input: &Path,
    vtu: &Path,
    svg: Option<&Path>,
    report: Option<&Path>,
) -> Result<()> {
    let mut texts = vec![(
        vtu.to_path_buf(),
        io::vtu::to_string(&out.mesh, &out.site_inside),
    )];
    if let Some(p) = svg {
        texts.push((
            p.to_path_buf(),
            io::svg::to_string(&out.mesh, &out.site_inside, &out.domain.complex),
        ));
    }
    if let Some(p) = report {
        let mut value =
            serde_json::to_value(&out.report).map_err(|e| Error::Usage(e.to_string()))?;
        value["input"] = serde_json::Value::String(input.display().to_string());
        texts.push((
            p.to_path_buf(),
            serde_json::to_string_pretty(&value).unwrap_or_default() + "\n",
        ));
    }
    for (p, t) in &texts {
        io::write_atomic(p, t.as_bytes())?;
    }
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
        "certificate: vertices {} segments {} tiling {} sites-inside {}; {:.1} ms total (raw triangulation {:.2} ms)",
        ok(c.vertices_are_mesh_vertices),
        ok(c.segments_are_single_edges),
        ok(c.cells_tile_domain),
        ok(c.sites_inside_cells),
        r.total_ms,
        r.raw_triangulation_ms.unwrap_or(f64::NAN)
    );
    for n in &r.notes {
        eprintln!("note: {n}");
    }
    for (p, _) in &texts {
        eprintln!("wrote {}", p.display());
    }
    Ok(())
}

fn ok(b: bool) -> &'static str {
    if b {
        "ok"
    } else {
        "FAILED"
    }
}
