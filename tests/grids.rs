//! Corner-point grids and decks from the shared data: read, checked here for
//! what the files say, and written out (corners per cell) for
//! tests/readers.py to compare with resdata's reading of the same files.

use orthomesh::io::eclipse::{read_grid, read_wells};
use std::fmt::Write;
use std::path::{Path, PathBuf};

fn grid(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/grids")
        .join(name)
}

/// Writes the corners of every cell as JSON where the reader check finds them.
fn export(name: &str, g: &orthomesh::reservoir::CornerPointGrid) {
    let Ok(dir) = std::env::var("ORTHOMESH_TEST_OUT") else {
        return;
    };
    let mut s = format!(
        "{{\"file\": \"{}\", \"dims\": [{}, {}, {}], \"active\": [",
        grid(name).display(),
        g.nx,
        g.ny,
        g.nz
    );
    let cells = g.nx * g.ny * g.nz;
    for c in 0..cells {
        let _ = write!(
            s,
            "{}{}",
            if c > 0 { "," } else { "" },
            u8::from(g.actnum[c])
        );
    }
    s += "], \"corners\": [";
    for k in 0..g.nz {
        for j in 0..g.ny {
            for i in 0..g.nx {
                let sep = if i + j + k > 0 { "," } else { "" };
                let cs: Vec<String> = (0..8)
                    .map(|c| {
                        let p = g.corner(i, j, k, c);
                        format!("[{:?},{:?},{:?}]", p[0], p[1], p[2])
                    })
                    .collect();
                let _ = write!(s, "{sep}[{}]", cs.join(","));
            }
        }
    }
    s += "]}\n";
    let dir = Path::new(&dir).join("grids");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join(format!("{name}.corners.json")), s).unwrap();
}

#[test]
fn shared_grids_read_with_their_dimensions() {
    for (name, dims, active) in [
        ("SPE9.GRDECL", [24, 25, 15], 9000),
        ("emerald.grdecl", [4, 4, 3], 48),
        ("twocell.grdecl", [1, 2, 1], 2),
        ("concave.grdecl", [1, 1, 3], 3),
        ("sixcells_lefthanded_hdr1.grdecl", [1, 2, 3], 5),
        ("dual_distorted1.grdecl", [5, 3, 1], 13),
    ] {
        let g = read_grid(&grid(name)).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!([g.nx, g.ny, g.nz], dims, "{name}");
        assert_eq!(g.actnum.iter().filter(|&&a| a).count(), active, "{name}");
        assert!(g.faults.is_empty(), "{name}");
        export(name, &g);
    }
}

#[test]
fn spe9_deck_wells() {
    let (wells, missing) = read_wells(&grid("SPE9_CP.DATA")).unwrap();
    assert_eq!(wells.len(), 26);
    assert!(
        missing.iter().any(|m| m.ends_with("PERMVALUES.DATA")),
        "{missing:?}"
    );
    let inje = &wells[0];
    assert_eq!((inje.name.as_str(), inje.i, inje.j), ("INJE1", 23, 24));
    assert_eq!(inje.k, Some([10, 14]));
    assert_eq!(inje.radius, Some(0.5));
    let p26 = wells.iter().find(|w| w.name == "PRODU26").unwrap();
    assert_eq!((p26.i, p26.j, p26.k), (16, 24, Some([1, 3])));
}

#[test]
fn a_deck_with_a_missing_grid_include_is_an_error_for_the_grid() {
    // The deck includes PERMVALUES.DATA, which is not shipped: reading the
    // grid from the deck names it; reading the wells does not need it.
    let e = read_grid(&grid("SPE9_CP.DATA")).unwrap_err().to_string();
    assert!(e.contains("PERMVALUES.DATA"), "{e}");
}
