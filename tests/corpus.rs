//! The malformed and adversarial input corpus (`tests/corpus/expected.txt`):
//! every case through the command line on every backend compiled in. Each
//! gives its error (exit 1, the expected message, no file written) or a
//! certified mesh; never a panic, a signal (an abort in C++), or a hang.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// A case runs at most this long (a hang is a failure, not a stuck CI).
const LIMIT: Duration = Duration::from_secs(120);

struct Case {
    line: usize,
    args: Vec<String>,
    /// None: a mesh; Some(text): an error whose message has the text.
    error: Option<String>,
}

fn corpus() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/corpus")
}

fn cases() -> Vec<Case> {
    let text = std::fs::read_to_string(corpus().join("expected.txt")).unwrap();
    text.lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty() && !l.starts_with('#'))
        .map(|(k, l)| {
            let (cmd, expect) = l.split_once(" => ").expect("COMMAND => EXPECTATION");
            let error = match expect.trim() {
                "mesh" => None,
                e => Some(
                    e.strip_prefix("error: ")
                        .expect("'mesh' or 'error: TEXT'")
                        .to_string(),
                ),
            };
            let args = cmd
                .split_whitespace()
                .map(|a| {
                    // File names (with an extension) live in the corpus folder.
                    if a.contains('.') && !a.starts_with('-') && !a.contains(':') {
                        corpus().join(a).display().to_string()
                    } else {
                        a.to_string()
                    }
                })
                .collect();
            Case {
                line: k + 1,
                args,
                error,
            }
        })
        .collect()
}

/// Runs one case; Err says how it went wrong.
/// Whether the 3D hybrid's summary says every transition face is exact
/// ("certificates: faces N/N exact").
fn every_face_exact(stderr: &str) -> bool {
    stderr
        .split("certificates: faces ")
        .nth(1)
        .and_then(|r| r.split(' ').next())
        .and_then(|f| f.split_once('/'))
        .is_some_and(|(a, b)| a == b)
}

fn check(case: &Case, backend: &str, dir: &Path) -> Result<(), String> {
    let outputs: Vec<PathBuf> = ["m.vtu", "m.json", "m.svg", "m.mesh"]
        .iter()
        .map(|f| dir.join(f))
        .collect();
    // (left over from a run that stopped)
    for p in &outputs {
        let _ = std::fs::remove_file(p);
    }
    let mut args = case.args.clone();
    let path = |k: usize| outputs[k].display().to_string();
    args.extend(["-o".into(), path(0)]);
    // 3D inputs (named *_3d.*) get a TOUGH MESH where 2D ones get a picture
    let three_d = args.iter().any(|a| a.contains("_3d.") || a == "--3d");
    if args[0] != "generate" {
        args.extend(["--report".into(), path(1)]);
        if !three_d {
            args.extend(["--svg".into(), path(2)]);
        }
    }
    if args[0] == "hybrid" || three_d {
        args.extend(["--tough".into(), path(3)]);
    }
    args.extend(["--backend".into(), backend.into()]);
    let mut child = Command::new(env!("CARGO_BIN_EXE_orthomesh"))
        .args(&args)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| e.to_string())?;
    let start = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().map_err(|e| e.to_string())? {
            break s;
        }
        if start.elapsed() > LIMIT {
            let _ = child.kill();
            return Err(format!("still running after {} s", LIMIT.as_secs()));
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    let mut stderr = String::new();
    std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut stderr)
        .map_err(|e| e.to_string())?;
    let Some(code) = status.code() else {
        return Err(format!("killed by a signal ({status}): {stderr}"));
    };
    if stderr.contains("panicked") {
        return Err(format!("panicked: {stderr}"));
    }
    let written: Vec<&PathBuf> = outputs.iter().filter(|p| p.exists()).collect();
    match &case.error {
        Some(text) => {
            if code != 1
                || !stderr.contains("orthomesh: error: ")
                || !stderr.contains(text.as_str())
            {
                return Err(format!(
                    "expected exit 1 and '{text}', got exit {code}: {stderr}"
                ));
            }
            if !written.is_empty() {
                return Err(format!("an error, yet files were written: {written:?}"));
            }
        }
        None => {
            if code != 0
                || !(stderr.contains("certificate: vertices ok segments ok tiling ok")
                    || every_face_exact(&stderr))
            {
                return Err(format!(
                    "expected a certified mesh, got exit {code}: {stderr}"
                ));
            }
            let expected = if args[0] == "hybrid" && !three_d {
                4
            } else {
                3
            };
            if written.len() != expected {
                return Err(format!("a mesh, but only {written:?} written"));
            }
        }
    }
    for p in &outputs {
        let _ = std::fs::remove_file(p);
    }
    Ok(())
}

#[test]
fn every_corpus_case_gives_its_error_or_a_certified_mesh() {
    let cases = cases();
    assert!(cases.len() >= 50, "the corpus has {} cases", cases.len());
    let backends: Vec<String> = orthomesh::backend::compiled()
        .iter()
        .map(|b| b.name().to_string())
        .collect();
    let jobs: Vec<(&Case, &str)> = backends
        .iter()
        .flat_map(|b| cases.iter().map(move |c| (c, b.as_str())))
        .collect();
    let next = std::sync::atomic::AtomicUsize::new(0);
    let failures = std::sync::Mutex::new(vec![]);
    std::thread::scope(|s| {
        for worker in 0..4 {
            let (jobs, next, failures) = (&jobs, &next, &failures);
            s.spawn(move || {
                let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
                    .join("corpus")
                    .join(worker.to_string());
                std::fs::create_dir_all(&dir).unwrap();
                loop {
                    let k = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                    let Some(&(case, backend)) = jobs.get(k) else {
                        break;
                    };
                    if let Err(e) = check(case, backend, &dir) {
                        failures.lock().unwrap().push(format!(
                            "expected.txt:{} ({backend}) {}: {e}",
                            case.line,
                            case.args.join(" ")
                        ));
                    }
                }
            });
        }
    });
    let failures = failures.into_inner().unwrap();
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}
