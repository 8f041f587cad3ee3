//! The architecture, checked: each top-level module of `src/` imports only
//! modules below it (geometric kernel at the bottom, then backends and the
//! LP, then the pipeline stages, then reservoir and io on top), and CGAL's
//! bridge appears only in `backend`.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// Top-level modules from the bottom up: a module may use those before it.
const LAYERS: &[&str] = &[
    "error",
    "progress",
    "geom",
    "complex",
    "generate",
    "backend",
    "lp",
    "domain",
    "weights",
    "options",
    "sites",
    "diagram",
    "relocate",
    "mesh",
    "certify",
    "conform",
    "split",
    "mesher",
    "reservoir",
    "io",
];

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// The top-level module a source file belongs to (None: lib.rs, the CLI).
fn module_of(src: &Path, file: &Path) -> Option<String> {
    let rel = file.strip_prefix(src).unwrap();
    let first = rel
        .components()
        .next()?
        .as_os_str()
        .to_string_lossy()
        .into_owned();
    let name = first.trim_end_matches(".rs").to_string();
    (name != "lib" && name != "bin").then_some(name)
}

/// The `crate::x` paths a text names.
fn uses(text: &str) -> BTreeSet<String> {
    let mut found = BTreeSet::new();
    for (at, _) in text.match_indices("crate::") {
        let rest = &text[at + 7..];
        let name: String = rest
            .chars()
            .take_while(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || *c == '_')
            .collect();
        if !name.is_empty() {
            found.insert(name);
        }
    }
    found
}

#[test]
fn modules_import_only_what_lies_below_them() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = vec![];
    rust_files(&src, &mut files);
    let rank = |m: &str| LAYERS.iter().position(|l| *l == m);
    let mut upward = vec![];
    let mut seen = BTreeSet::new();
    for f in &files {
        let Some(m) = module_of(&src, f) else {
            continue;
        };
        seen.insert(m.clone());
        let own = rank(&m).unwrap_or_else(|| panic!("module {m} is in no layer of LAYERS"));
        let text = std::fs::read_to_string(f).unwrap();
        for u in uses(&text) {
            match rank(&u) {
                Some(r) if r > own => upward.push(format!("{} uses crate::{u}", f.display())),
                _ => {}
            }
        }
        if m != "backend" {
            for word in ["cxx::", "ffi::", "Cgal"] {
                assert!(
                    !text.contains(word),
                    "{}: CGAL's bridge ({word}) outside backend",
                    f.display()
                );
            }
        }
    }
    assert!(upward.is_empty(), "upward imports:\n{}", upward.join("\n"));
    let listed: BTreeSet<String> = LAYERS.iter().map(|s| s.to_string()).collect();
    assert_eq!(seen, listed, "LAYERS lists exactly the modules of src/");
}
