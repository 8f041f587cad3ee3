//! Golden outputs: the command line with `--reproducible` on a small corpus,
//! the SHA-256 of every file it writes pinned in `tests/golden/<backend>.sha256`.
//!
//! A refactor must leave every hash unchanged. A change of behaviour that is
//! meant (a bug fix) rewrites the file in a commit of its own that says why:
//! `ORTHOMESH_BLESS=1 cargo test --test golden`.
//!
//! Each build runs the cases of its default backend only (CGAL when compiled
//! in, else the pure-Rust engine), so that the suite's two passes share the
//! work instead of repeating it; `ORTHOMESH_GOLDEN_BACKEND=pure` picks the
//! other in a build that has both.

use sha2::{Digest, Sha256};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

/// One case: input files copied into its folder, then commands run there
/// (file names relative to it). `@` stands for `--backend NAME --reproducible`.
/// A command that fails writes nothing; its message is pinned instead.
struct Case {
    name: &'static str,
    inputs: &'static [&'static str],
    commands: &'static [&'static [&'static str]],
}

const fn case(
    name: &'static str,
    inputs: &'static [&'static str],
    commands: &'static [&'static [&'static str]],
) -> Case {
    Case {
        name,
        inputs,
        commands,
    }
}

const PSLG: &str = "tests/data/pslg/";

/// Every shared 2D input, with the flags it needs to give a mesh.
const CONFORM_2D: &[(&str, &[&str])] = &[
    ("A.poly", &["--allow-sites-outside"]),
    ("box.poly", &[]),
    ("double_hex.poly", &[]),
    ("double_hex2.poly", &[]),
    ("double_hex3.poly", &["--allow-sites-outside"]),
    ("face.poly", &["--allow-sites-outside"]),
    ("fish-and-rectangle.poly", &["--allow-sites-outside"]),
    ("la.poly", &["--allow-sites-outside"]),
    ("square_circle_hole.poly", &[]),
    ("butterfly.edg", &["--allow-sites-outside"]),
    ("clusters.edg", &["--allow-sites-outside"]),
    ("fish.edg", &["--allow-sites-outside"]),
    ("lettre_A.edg", &["--allow-sites-outside"]),
];

const CASES: &[Case] = &[
    case(
        "A-split",
        &["tests/data/pslg/A.poly"],
        &[&[
            "conform",
            "A.poly",
            "-o",
            "m.vtu",
            "--svg",
            "m.svg",
            "--report",
            "m.json",
            "--split-segments",
            "@",
        ]],
    ),
    case(
        "face-split",
        &["tests/data/pslg/face.poly"],
        &[&[
            "conform",
            "face.poly",
            "-o",
            "m.vtu",
            "--svg",
            "m.svg",
            "--report",
            "m.json",
            "--split-segments",
            "--allow-sites-outside",
            "@",
        ]],
    ),
    case(
        "la-split",
        &["tests/data/pslg/la.poly"],
        &[&[
            "conform",
            "la.poly",
            "-o",
            "m.vtu",
            "--report",
            "m.json",
            "--split-segments",
            "@",
        ]],
    ),
    case(
        "mixed3",
        &[],
        &[
            &["generate", "mixed", "3", "-o", "mixed.poly"],
            &[
                "conform",
                "mixed.poly",
                "-o",
                "m.vtu",
                "--svg",
                "m.svg",
                "--report",
                "m.json",
                "--allow-sites-outside",
                "@",
            ],
        ],
    ),
    case(
        "cavities2",
        &[],
        &[
            &["generate", "cavities", "2", "-o", "cavities.poly"],
            &[
                "conform",
                "cavities.poly",
                "-o",
                "m.vtu",
                "--svg",
                "m.svg",
                "--report",
                "m.json",
                "@",
            ],
        ],
    ),
    case(
        "tetgen",
        &["tests/data/plc3d/example.poly"],
        &[&[
            "conform",
            "example.poly",
            "-o",
            "m.vtu",
            "--tough",
            "m.mesh",
            "--report",
            "m.json",
            "--allow-sites-outside",
            "@",
        ]],
    ),
    case(
        "tetgen-clip",
        &["tests/data/plc3d/example.poly"],
        &[&[
            "conform",
            "example.poly",
            "-o",
            "m.vtu",
            "--report",
            "m.json",
            "--allow-sites-outside",
            "--clip-hull",
            "@",
        ]],
    ),
    case(
        "stacked",
        &["tests/golden/stacked3.poly"],
        &[&[
            "conform",
            "stacked3.poly",
            "-o",
            "m.vtu",
            "--tough",
            "m.mesh",
            "--report",
            "m.json",
            "@",
        ]],
    ),
    case(
        "stacked-clip",
        &["tests/golden/stacked3.poly"],
        &[&[
            "conform",
            "stacked3.poly",
            "-o",
            "m.vtu",
            "--report",
            "m.json",
            "--clip-hull",
            "@",
        ]],
    ),
    case(
        "stacked-split",
        &["tests/golden/stacked3.poly"],
        &[&[
            "conform",
            "stacked3.poly",
            "-o",
            "m.vtu",
            "--report",
            "m.json",
            "--split-facets",
            "--whole-polygons",
            "coplanar",
            "@",
        ]],
    ),
    case(
        "spe9-deck",
        &[
            "tests/data/grids/SPE9.GRDECL",
            "tests/data/grids/SPE9_CP.DATA",
        ],
        &[&[
            "hybrid",
            "--grid",
            "SPE9.GRDECL",
            "--deck",
            "SPE9_CP.DATA",
            "-o",
            "m.vtu",
            "--svg",
            "m.svg",
            "--tough",
            "m.mesh",
            "--report",
            "m.json",
            "@",
        ]],
    ),
    case(
        "spe9-layers",
        &["tests/data/grids/SPE9.GRDECL"],
        &[&[
            "hybrid",
            "--grid",
            "SPE9.GRDECL",
            "--well",
            "A:5:5:0.5",
            "--well-xy",
            "B:4000:4000",
            "--layers",
            "--rings",
            "4",
            "--sectors",
            "12",
            "-o",
            "m.vtu",
            "--tough",
            "m.mesh",
            "--report",
            "m.json",
            "@",
        ]],
    ),
    case(
        "faulted",
        &["tests/golden/faulted11.grdecl"],
        &[&[
            "hybrid",
            "--grid",
            "faulted11.grdecl",
            "--well",
            "W:6:4:0.1",
            "-o",
            "m.vtu",
            "--svg",
            "m.svg",
            "--tough",
            "m.mesh",
            "--report",
            "m.json",
            "@",
        ]],
    ),
    case(
        "faulted-line",
        &["tests/golden/faulted11.grdecl"],
        &[&[
            "hybrid",
            "--grid",
            "faulted11.grdecl",
            "--well",
            "W:3:8:0.1",
            "--fault",
            "12,92,30,70",
            "--layer",
            "2",
            "--layers",
            "-o",
            "m.vtu",
            "--svg",
            "m.svg",
            "--report",
            "m.json",
            "@",
        ]],
    ),
    case(
        "hybrid3-vertical",
        &["tests/golden/block7x7x2.grdecl"],
        &[&[
            "hybrid",
            "--3d",
            "--grid",
            "block7x7x2.grdecl",
            "--well",
            "W:4:4:0.1",
            "--rings",
            "4",
            "--sectors",
            "12",
            "-o",
            "m.vtu",
            "--tough",
            "m.mesh",
            "--report",
            "m.json",
            "@",
        ]],
    ),
    case(
        "hybrid3-deviated",
        &["tests/golden/block7x7x2.grdecl"],
        &[&[
            "hybrid",
            "--3d",
            "--grid",
            "block7x7x2.grdecl",
            "--well",
            "W:4:4:0.1:20:30",
            "--rings",
            "2",
            "--sectors",
            "8",
            "--allow-sites-outside",
            "-o",
            "m.vtu",
            "--tough",
            "m.mesh",
            "--report",
            "m.json",
            "@",
        ]],
    ),
];

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The cases of the 2D shared inputs, then the named ones.
fn all_cases() -> Vec<(String, Vec<String>, Vec<Vec<String>>)> {
    let mut v = vec![];
    for (file, flags) in CONFORM_2D {
        let mut cmd: Vec<String> = [
            "conform", file, "-o", "m.vtu", "--svg", "m.svg", "--report", "m.json",
        ]
        .map(String::from)
        .to_vec();
        cmd.extend(flags.iter().map(|s| s.to_string()));
        cmd.push("@".into());
        v.push((file.to_string(), vec![format!("{PSLG}{file}")], vec![cmd]));
    }
    for c in CASES {
        let cmds = c
            .commands
            .iter()
            .map(|cmd| cmd.iter().map(|s| s.to_string()).collect())
            .collect();
        v.push((
            c.name.to_string(),
            c.inputs.iter().map(|s| s.to_string()).collect(),
            cmds,
        ));
    }
    v
}

/// Runs one case in its own folder; returns its lines of the hash file.
fn run_case(backend: &str, name: &str, inputs: &[String], commands: &[Vec<String>]) -> String {
    let dir: PathBuf = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("golden")
        .join(backend)
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    for i in inputs {
        let from = root().join(i);
        std::fs::copy(&from, dir.join(from.file_name().unwrap())).unwrap();
    }
    let mut lines = String::new();
    for (k, cmd) in commands.iter().enumerate() {
        let before: Vec<PathBuf> = files(&dir);
        let mut args: Vec<String> = vec![];
        for a in cmd {
            if a == "@" {
                args.extend(["--backend", backend, "--reproducible"].map(String::from));
            } else {
                args.push(a.clone());
            }
        }
        let out = Command::new(env!("CARGO_BIN_EXE_orthomesh"))
            .args(&args)
            .current_dir(&dir)
            .output()
            .unwrap();
        let code = out.status.code().unwrap_or(-1);
        let _ = writeln!(lines, "{name}#{k} exit {code}");
        if code != 0 {
            // what a failing run says is behaviour too
            let hash = Sha256::digest(&out.stderr);
            let _ = writeln!(lines, "{hash:x}  {name}#{k} stderr");
        }
        for f in files(&dir) {
            if before.contains(&f) {
                continue;
            }
            let bytes = std::fs::read(&f).unwrap();
            let hash = Sha256::digest(&bytes);
            let rel = f.file_name().unwrap().to_string_lossy();
            let _ = writeln!(lines, "{hash:x}  {name}/{rel}");
        }
    }
    lines
}

/// The files in a folder, sorted.
fn files(dir: &Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    v.sort();
    v
}

#[test]
fn outputs_keep_their_hashes() {
    // (the library's default backend; not asked of the library, so that
    // this test stays the same while the library changes around it)
    // ORTHOMESH_GOLDEN_BACKEND=pure runs the other backend's cases in a
    // build that has both.
    let backend = std::env::var("ORTHOMESH_GOLDEN_BACKEND").unwrap_or_else(|_| {
        if cfg!(feature = "cgal") {
            "cgal"
        } else {
            "pure"
        }
        .into()
    });
    let built = (backend == "cgal" && cfg!(feature = "cgal"))
        || (backend == "pure" && cfg!(feature = "pure-rust"));
    // (else every case would pin the error "backend not built")
    assert!(
        built,
        "backend {backend} is not in this build (--features?)"
    );
    let cases = all_cases();
    // two workers: each run is a separate process
    let next = std::sync::atomic::AtomicUsize::new(0);
    let mut results: Vec<(usize, String)> = std::thread::scope(|s| {
        let workers: Vec<_> = (0..2)
            .map(|_| {
                s.spawn(|| {
                    let mut done = vec![];
                    loop {
                        let k = next.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
                        let Some((name, inputs, cmds)) = cases.get(k) else {
                            break done;
                        };
                        let t = std::time::Instant::now();
                        done.push((k, run_case(&backend, name, inputs, cmds)));
                        eprintln!(
                            "golden {backend} {name}: {:.1} s",
                            t.elapsed().as_secs_f64()
                        );
                    }
                })
            })
            .collect();
        workers
            .into_iter()
            .flat_map(|w| w.join().unwrap())
            .collect()
    });
    results.sort();
    let text: String = results.into_iter().map(|(_, l)| l).collect();
    let pinned = root().join(format!("tests/golden/{backend}.sha256"));
    if std::env::var_os("ORTHOMESH_BLESS").is_some() {
        std::fs::write(&pinned, &text).unwrap();
        return;
    }
    let want = std::fs::read_to_string(&pinned)
        .unwrap_or_else(|e| panic!("{}: {e} (ORTHOMESH_BLESS=1 writes it)", pinned.display()));
    let changed: Vec<String> = text
        .lines()
        .filter(|l| !want.lines().any(|w| w == *l))
        .map(|l| format!("now    {l}"))
        .chain(
            want.lines()
                .filter(|w| !text.lines().any(|l| l == *w))
                .map(|w| format!("pinned {w}")),
        )
        .collect();
    assert!(
        changed.is_empty(),
        "golden outputs changed (a refactor must keep them):\n{}",
        changed.join("\n")
    );
}
