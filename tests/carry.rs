//! The engineer's deck carried whole (issue 51): the original grid's
//! transmissibilities as OPM Flow computes them (SPE9's full deck, emerald
//! with throws, faults and multipliers), and hybrid meshes' decks that
//! carry their input deck whole (SPE9's black-oil benchmark in 3D; a small
//! deck with two saturation and two equilibration regions), each written
//! with a JSON sidecar for `tests/decks.py`, which runs OPM Flow on them
//! and on the originals.

use orthomesh::backend::default_backend;
use orthomesh::io::carry::{carry, extents, Mesh, MERGE_STIFF};
use orthomesh::reservoir::hybrid3::{self, Hybrid3Options, Section, Well3};
use orthomesh::reservoir::{HybridOptions, WellAt, WellInput};
use serde_json::json;
use std::path::{Path, PathBuf};

fn out_dir() -> PathBuf {
    let dir = match std::env::var("ORTHOMESH_TEST_OUT") {
        Ok(d) => PathBuf::from(d).join("decks"),
        Err(_) => std::env::temp_dir().join(format!("orthomesh-carry-{}", std::process::id())),
    };
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Radial meshes sized for a simulator (`hybrid --3d --rings 2 --sectors 6
/// --rings-over-columns --first-ring 0.6`): the innermost cells a fifth of
/// their well's cell, every ring link exact.
fn for_simulators() -> Hybrid3Options {
    Hybrid3Options {
        allow_sites_outside: true,
        rings: 2,
        sectors: 6,
        layered: Some(Section {
            rings: 2,
            sectors: 6,
            in_column: false,
            first_ring: Some(0.6),
            ..Default::default()
        }),
        ..Default::default()
    }
}

/// Meshes a deck's wells in 3D (layered cavities), or in 2.5D where
/// `opts` is None, and writes its hybrid deck, carried whole (`write`).
/// Only the wells `radial` names are meshed, all where it names none.
fn carried(
    name: &str,
    deck: &Path,
    radius: f64,
    radial: &[&str],
    opts: Option<Hybrid3Options>,
    merge: Option<f64>,
) -> (usize, Vec<String>) {
    let g = orthomesh::io::eclipse::read_grid(deck).unwrap();
    let (found, _) = orthomesh::io::eclipse::read_wells(deck).unwrap();
    let heads: serde_json::Map<String, serde_json::Value> = found
        .iter()
        .map(|w| {
            let [i, j, k, _] = w.completions[0];
            (w.name.clone(), json!(g.cell_index(i, j, k)))
        })
        .collect();
    let found: Vec<_> = (found.into_iter())
        .filter(|w| radial.is_empty() || radial.contains(&w.name.as_str()))
        .collect();
    let meshed: Vec<String> = found.iter().map(|w| w.name.clone()).collect();
    let start = std::time::Instant::now();
    let b = default_backend();
    // the mesh's parts: network, hosts, reservoir cells, wells' links,
    // regions, vertical extents
    let (net, host, ijk, links, region, extent) = match opts {
        Some(opts) => {
            let wells: Vec<Well3> = found.into_iter().map(|w| w.well3(radius)).collect();
            let h = hybrid3::build(&b, &g, &wells, &opts).unwrap();
            assert_eq!(h.report.sites_outside, 0, "{name}");
            assert_eq!(h.report.sections.len().min(1), 1, "{name}: layered");
            let extent = extents(&h.mesh.points, &h.mesh.cells);
            (
                h.mesh.network(),
                h.host,
                h.ijk,
                h.wellbore,
                h.region,
                extent,
            )
        }
        None => {
            let wells: Vec<WellInput> = (found.into_iter())
                .map(|w| WellInput {
                    name: w.name,
                    at: WellAt::Column(w.i, w.j),
                    radius,
                })
                .collect();
            let opts = HybridOptions::default();
            let h = orthomesh::reservoir::hybrid::build(&b, &g, &wells, &opts).unwrap();
            let l = orthomesh::reservoir::extrude(&h, &g).unwrap();
            let (host, ijk) = l.hosts(&h);
            let extent = extents(&l.points, &l.cells);
            (
                l.network(&h),
                host,
                ijk,
                l.well_links(&h, &[]),
                l.regions(&h),
                extent,
            )
        }
    };
    let mesh = Mesh {
        grid: &g,
        network: &net,
        host: &host,
        ijk: &ijk,
        wells: &links,
        region: &region,
        extent: &extent,
    };
    let more = json!({ "wells": heads, "meshed": meshed });
    let (position, notes) = write(name, deck, &mesh, merge, more);
    println!(
        "{name}: {} cells, meshed and carried in {:.1} s",
        position.len(),
        start.elapsed().as_secs_f64()
    );
    (position.len(), notes)
}

/// Writes a mesh's deck, carried whole, into `decks/carried/NAME/`, with a
/// sidecar for decks.py: the original deck, per reservoir deck cell its
/// grid cell, per deck cell the host its rock comes from, what the deck's header says, and
/// `more` (per well its first completed grid cell, the meshed wells).
fn write(
    name: &str,
    deck: &Path,
    mesh: &Mesh,
    merge: Option<f64>,
    more: serde_json::Value,
) -> (Vec<usize>, Vec<String>) {
    let c = carry(deck, mesh, merge).unwrap();
    let (text, notes, position) = (c.text, c.notes, c.position);
    let dir = out_dir().join("carried").join(name);
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(format!("{}.DATA", name.to_uppercase()));
    std::fs::write(&path, &text).unwrap();
    let g = mesh.grid;
    let at = |[i, j, k]: [usize; 3]| g.cell_index(i, j, k);
    let mut reservoir = vec![];
    let host: Vec<usize> = c.rock.iter().map(|&e| at(mesh.host[e])).collect();
    for (e, &p) in position.iter().enumerate() {
        if let Some(c) = mesh.ijk[e] {
            reservoir.push([p, at(c)]);
        }
    }
    let mut side = json!({
        "deck": path, "original": std::fs::canonicalize(deck).unwrap(),
        "reservoir": reservoir, "host": host, "notes": notes,
    });
    for (k, v) in more.as_object().unwrap() {
        side[k] = v.clone();
    }
    std::fs::write(dir.join("carried.json"), side.to_string()).unwrap();
    (position, notes)
}

/// SPE9's black-oil benchmark deck (three phases, dissolved gas, 26 wells,
/// an explicit initial state, 900 days) carried whole onto its 3D hybrid:
/// decks.py checks with Flow's dry run that the reservoir cells keep the
/// original's pore volumes and transmissibilities (and times a run).
#[test]
fn spe9_carried_whole() {
    let deck = Path::new("tests/data/decks/spe9/BENCH_SPE9.DATA");
    let (cells, notes) = carried(
        "spe9",
        deck,
        0.25,
        &[],
        Some(for_simulators()),
        Some(MERGE_STIFF),
    );
    for n in &notes {
        println!("  {n}");
    }
    assert!(cells > 9000);
    let said = notes.join("\n");
    for what in [
        "padded",
        "BASIC",
        "NONNC",
        "WELLDIMS",
        "COMPDAT",
        "--merge-stiff",
    ] {
        assert!(said.contains(what), "{what}: {said}");
    }
}

/// A small black-oil deck of our own on a 7 x 7 x 2 block: two saturation
/// regions (SATNUM, split along x) and two equilibration regions (EQLNUM,
/// split along y, different contacts), SWATINIT, a producer in the
/// middle meshed, a water injector in a corner not meshed (its factor
/// Flow's own): carried whole onto its hybrid, each cell keeping its
/// host's regions (decks.py checks them in Flow's INIT and compares the
/// runs and the injector's factors).
#[test]
fn regions_carried_whole() {
    let deck = regions_input("regions-input");
    let opts = Hybrid3Options {
        allow_sites_outside: true,
        ..Default::default()
    };
    let (cells, notes) = carried("regions", &deck, 0.1, &["P1"], Some(opts), None);
    let said = notes.join("\n");
    assert!(said.contains("without a radial mesh (I1)"), "{said}");
    println!("regions: {cells} cells; {}", notes.join("; "));
}

/// The regions deck in 2.5D (`hybrid --layers`): the same writer carries
/// it onto the 2D hybrid mapped onto both layers (its default 12 rings of
/// 32 sectors),
/// its producer meshed, its injector not (decks.py checks it as the 3D
/// one).
#[test]
fn regions_carried_whole_in_2_5d() {
    let deck = regions_input("regions-layers-input");
    let (cells, notes) = carried("regions-layers", &deck, 0.1, &["P1"], None, None);
    let said = notes.join("\n");
    assert!(said.contains("without a radial mesh (I1)"), "{said}");
    println!("regions in 2.5D: {cells} cells");
}

/// The regions deck and its grid, written to `decks/carried/FOLDER`.
fn regions_input(folder: &str) -> PathBuf {
    let dir = out_dir().join("carried").join(folder);
    std::fs::create_dir_all(&dir).unwrap();
    let grid = std::fs::read_to_string("tests/golden/block7x7x2.grdecl").unwrap();
    std::fs::write(dir.join("BLOCK.GRDECL"), grid).unwrap();
    let satnum: Vec<String> = (0..98)
        .map(|c| if c % 7 < 3 { "1" } else { "2" }.to_string())
        .collect();
    let eqlnum: Vec<String> = (0..98)
        .map(|c| if (c / 7) % 7 < 3 { "1" } else { "2" }.to_string())
        .collect();
    let swatinit: Vec<String> = (0..98)
        .map(|c| format!("{}", 0.2 + 0.005 * (c % 7) as f64))
        .collect();
    let text = format!(
        "RUNSPEC\nTITLE\nregions\nDIMENS\n 7 7 2 /\nOIL\nWATER\nMETRIC\nTABDIMS\n 2 1 20 20 /\n\
         EQLDIMS\n 2 /\nWELLDIMS\n 2 2 1 2 /\nSTART\n 1 'JAN' 2020 /\nUNIFOUT\nGRID\nINIT\n\
         INCLUDE\n 'BLOCK.GRDECL' /\nPORO\n 98*0.25 /\nPERMX\n 98*200 /\nCOPY\n 'PERMX' 'PERMY' /\n\
         'PERMX' 'PERMZ' /\n/\nMULTIPLY\n 'PERMZ' 0.1 /\n/\nPROPS\nSWOF\n 0.2 0 1 0\n 0.8 0.6 0 0 /\n\
         0.1 0 1 0\n 0.9 0.9 0 0 /\nPVTW\n 250 1.02 4.5e-5 0.4 0 /\nPVDO\n 100 1.05 2\n 300 1.03 2.2 /\n\
         DENSITY\n 850 1020 1 /\nROCK\n 250 5e-5 /\nSWATINIT\n {} /\nREGIONS\nSATNUM\n {} /\n\
         EQLNUM\n {} /\nSOLUTION\nRPTRST\n 'BASIC=2' /\nEQUIL\n 2 250 7.5 0 1* 1* /\n 2 250 7 0 1* 1* /\nSUMMARY\nFOPT\nFWPT\n\
         FOPR\nWBHP\n/\nSCHEDULE\nWELSPECS\n 'P1' 'G' 4 4 1* 'OIL' /\n 'I1' 'G' 1 1 1* 'WATER' /\n/\n\
         COMPDAT\n 'P1' 4 4 1 2 'OPEN' 1* 1* 0.2 /\n 'I1' 2* 1 2 'OPEN' 1* 1* 0.3 /\n/\n\
         WCONPROD\n 'P1' 'OPEN' 'ORAT' 5 4* 50 /\n/\nWCONINJE\n 'I1' 'WATER' 'OPEN' 'RATE' 1 1* 400 /\n/\nTSTEP\n 10*10 /\nEND\n",
        swatinit.join(" "),
        satnum.join(" "),
        eqlnum.join(" ")
    );
    let deck = dir.join("REGIONS.DATA");
    std::fs::write(&deck, text).unwrap();
    deck
}

/// The command line: `hybrid --3d` with a whole --deck carries it (what it
/// mended and assumed on stderr); the single-phase model's options are
/// refused with it; --single-phase writes the water model instead.
#[test]
fn the_command_line_carries_a_whole_deck() {
    let input = regions_input("cli-input");
    // outside the test meshes' folder: readers.py checks every VTU there
    let dir = std::env::temp_dir().join(format!("orthomesh-carry-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let run = |extra: &[&str]| {
        let (deck, vtu) = (dir.join("H.DATA"), dir.join("h.vtu"));
        let _ = std::fs::remove_file(&deck);
        let mut args = vec![
            "hybrid",
            "--3d",
            "--grid",
            input.to_str().unwrap(),
            "--deck",
        ];
        args.extend([input.to_str().unwrap(), "-o", vtu.to_str().unwrap()]);
        args.extend(["--eclipse", deck.to_str().unwrap()]);
        args.extend(extra);
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_orthomesh"))
            .args(&args)
            .output()
            .unwrap();
        let text = std::fs::read_to_string(&deck).unwrap_or_default();
        (
            out.status.code(),
            String::from_utf8_lossy(&out.stderr).into_owned(),
            text,
        )
    };
    let (code, err, deck) = run(&["--radial", "P1"]);
    assert_eq!(code, Some(0), "{err}");
    assert!(err.contains("deck: COMPDAT of the meshed wells"), "{err}");
    assert!(err.contains("without a radial mesh (I1)"), "{err}");
    let (code2, err2, none) = run(&["--radial", "P1,P9"]);
    assert_eq!(code2, Some(1), "{err2}");
    assert!(
        err2.contains("--radial: no well P9") && none.is_empty(),
        "{err2}"
    );
    assert!(deck.contains("SATNUM") && deck.contains("EQLNUM") && deck.contains("COMPORD"));
    let (code, err, deck) = run(&["--rate", "5", "--radial", "P1"]);
    assert_eq!(code, Some(1), "{err}");
    assert!(err.contains("--single-phase") && deck.is_empty(), "{err}");
    let (code, err, deck) = run(&["--single-phase", "--radial", "P1"]);
    assert_eq!(code, Some(0), "{err}");
    assert!(!deck.contains("SATNUM") && deck.contains("PVTW"), "{err}");
    // merging the stiff cells: said; refused for the water model or at 0
    let (code, err, _) = run(&["--radial", "P1", "--merge-stiff", "1"]);
    assert_eq!(code, Some(0), "{err}");
    assert!(err.contains("--merge-stiff 1: "), "{err}");
    for bad in [
        &["--merge-stiff", "0"][..],
        &["--merge-stiff", "1", "--single-phase"],
    ] {
        let (code, err, deck) = run(&[&["--radial", "P1"][..], bad].concat());
        assert_eq!(code, Some(1), "{err}");
        assert!(err.contains("--merge-stiff") && deck.is_empty(), "{err}");
    }
}

/// SPE9's full black-oil deck: its grid's own transmissibilities as Flow
/// computes them (`reservoir::trans`: corner-point geometry, PERMX given,
/// PERMY and PERMZ by the deck's COPY and MULTIPLY), written for
/// tests/decks.py to compare with the INIT file Flow writes for the deck
/// (the far field a hybridized deck must keep; issue 51); and again for a
/// copy with face multipliers of our own (EQUALS in boxes, an array in a
/// BOX over part of one, MULTREGT between three MULTNUM regions).
#[test]
fn spe9_far_field_transmissibilities() {
    let src = Path::new("tests/data/decks/spe9");
    // 24 x 25 x 15 cells, all active, no throw: every neighbour pair
    let n = 23 * 25 * 15 + 24 * 24 * 15 + 24 * 25 * 14;
    assert_eq!(far_field("spe9", &src.join("BENCH_SPE9.DATA")), (n, 0));
    let dir = out_dir().join("trans").join("spe9-mult");
    std::fs::create_dir_all(&dir).unwrap();
    for f in ["SPE9.GRDECL", "INITSOL.INC"] {
        std::fs::copy(src.join(f), dir.join(f)).unwrap();
    }
    let text = std::fs::read_to_string(src.join("BENCH_SPE9.DATA")).unwrap();
    let mults = "EQUALS\n 'MULTX' 0.5 1 12 1 25 1 15 /\n 'MULTY' 0.1 1 24 10 12 1 15 /\n \
                 'MULTZ' 0.01 1 24 1 25 5 5 /\n 'MULTNUM' 1 /\n 'MULTNUM' 2 1 12 1 25 1 15 /\n \
                 'MULTNUM' 3 1 24 1 25 8 15 /\n/\nMULTREGT\n 1 2 0.1 XYZ 1* M /\n 2 3 0.5 Z ALL M /\n \
                 3 1 0.2 XY NNC /\n/\nBOX\n 1 24 20 25 1 15 /\nMULTZ\n 2160*0.5 /\nENDBOX\n\n";
    let at = text.find("\nPROPS").expect("a PROPS section");
    let deck = dir.join("BENCH_SPE9.DATA");
    std::fs::write(&deck, format!("{}\n{mults}{}", &text[..at], &text[at..])).unwrap();
    assert_eq!(far_field("spe9-mult", &deck), (n, 0));
}

/// Emerald (leaning pillars, throws, an inactive hole, PORO 0 in most
/// cells) in a small deck of our own, with face multipliers, faults on
/// the +y faces of two rows and the -x faces of a column, across throws,
/// MULTFLT given twice for one of them (the last holds), MULTREGT on the
/// NNCs between two MULTNUM regions (its region set defaulted: MULTNUM as
/// GRIDOPTS counts them): its transmissibilities across the throws
/// too, for tests/decks.py to compare with Flow's INIT and NNCs. The
/// grid's FACIES array, which Flow 2022.10 refuses, is left out of the copy.
#[test]
fn emerald_far_field_transmissibilities() {
    let dir = out_dir().join("trans").join("emerald");
    std::fs::create_dir_all(&dir).unwrap();
    let grid = std::fs::read_to_string("tests/data/grids/eme_small_w_hole.grdecl").unwrap();
    let from = grid.find("\nFACIES").expect("FACIES in emerald's grid");
    let to = from + grid[from..].find('/').unwrap() + 1;
    std::fs::write(
        dir.join("EME.GRDECL"),
        format!("{}{}", &grid[..from], &grid[to..]),
    )
    .unwrap();
    let deck = "RUNSPEC\nDIMENS\n 21 41 18 /\nOIL\nWATER\nMETRIC\nTABDIMS\n/\nWELLDIMS\n 0 0 0 0 /\n\
        GRIDOPTS\n 'NO' 2 /\n\
        START\n 1 'JAN' 2000 /\nGRID\nINIT\nINCLUDE\n 'EME.GRDECL' /\nPERMX\n 15498*100 /\n\
        COPY\n 'PERMX' 'PERMY' /\n 'PERMX' 'PERMZ' /\n/\nMULTIPLY\n 'PERMZ' 0.1 /\n 'PERMY' 2 1 21 20 41 1 18 /\n/\n\
        EQUALS\n 'MULTX' 0.5 1 10 1 41 1 18 /\n 'MULTZ' 0.2 1 21 1 41 5 9 /\n 'NTG' 0.8 1 21 1 20 1 18 /\n/\n\
        FAULTS\n 'FA' 1 21 39 39 1 18 'Y' /\n 'FA' 1 21 40 40 1 18 'Y' /\n 'FB' 13 13 1 41 1 18 'X-' /\n/\n\
        MULTFLT\n 'FA' 0.1 /\n 'FB' 0.3 /\n/\nMULTFLT\n 'FA' 0.5 /\n/\n\
        EQUALS\n 'MULTNUM' 1 /\n 'MULTNUM' 2 1 21 1 41 10 18 /\n/\nMULTREGT\n 1 2 0.25 XYZ NNC /\n/\n\
        PROPS\nSWOF\n 0 0 1 0\n 1 1 0 0 /\nPVTW\n 200 1 4e-5 0.5 0 /\nPVDO\n 100 1.0 1.0\n 300 0.99 1.1 /\n\
        DENSITY\n 800 1000 1 /\nROCK\n 200 1e-5 /\nSOLUTION\nEQUIL\n 2000 200 3000 0 0 0 1 1 0 /\n\
        SCHEDULE\nTSTEP\n 1 /\nEND\n";
    let path = dir.join("EME.DATA");
    std::fs::write(&path, deck).unwrap();
    let (n, thrown) = far_field("emerald", &path);
    eprintln!("emerald: {n} transmissibilities, {thrown} across throws between layers");
    assert!(
        thrown > 0,
        "emerald's throws connect cells of different layers"
    );
}

/// A 4 x 3 x 4 block with PINCH: its second layer collapsed to a plane
/// in the first two columns along x (the third layer raised to meet the
/// first there), its third layer inactive but 5 m thick in the last row;
/// MULTZ and MULTZ- on the cells the collapse joins, MULTREGT between
/// MULTNUM regions (an array of its own) across them. As Flow 2022.10
/// does, the collapsed cells' neighbours above and below connect (in
/// TRANZ of the upper one), the thick inactive ones' do not.
#[test]
fn pinched_out_layers_connect_as_in_flow() {
    let dir = out_dir().join("trans").join("pinch");
    std::fs::create_dir_all(&dir).unwrap();
    let (nx, ny, nz) = (4, 3, 4);
    let mut coord = String::new();
    for j in 0..=ny {
        for i in 0..=nx {
            let (x, y) = (10.0 * i as f64, 10.0 * j as f64);
            coord += &format!(" {x} {y} 1000 {x} {y} 1020\n");
        }
    }
    // depth of layer k's top (b = 0) or bottom (b = 1) in column i
    let depth = |i: usize, k: usize, b: usize| {
        let level = k + b;
        match (i < 2, level) {
            (true, 1) | (true, 2) => 1005.0,
            _ => 1000.0 + 5.0 * level as f64,
        }
    };
    let mut zcorn = vec![];
    for k in 0..nz {
        for b in 0..2 {
            for _j in 0..2 * ny {
                for i in 0..2 * nx {
                    zcorn.push(format!("{}", depth(i / 2, k, b)));
                }
            }
        }
    }
    let mut actnum = vec!["1"; nx * ny * nz];
    for i in 0..nx {
        actnum[i + nx * (2 + ny * 2)] = "0";
    }
    let grid = format!(
        "SPECGRID\n {nx} {ny} {nz} 1 F /\nCOORD\n{coord}/\nZCORN\n{} /\nACTNUM\n{} /\n",
        zcorn.join(" "),
        actnum.join(" ")
    );
    std::fs::write(dir.join("PINCH.GRDECL"), grid).unwrap();
    let perm: Vec<String> = (0..nx * ny * nz)
        .map(|c| format!("{}", 50 + 7 * c))
        .collect();
    let deck = format!(
        "RUNSPEC\nDIMENS\n {nx} {ny} {nz} /\nOIL\nWATER\nMETRIC\nTABDIMS\n/\n\
         GRIDOPTS\n 'NO' 2 /\nSTART\n 1 'JAN' 2000 /\nGRID\nINIT\nPINCH\n 0.001 GAP 1* TOPBOT TOP /\n\
         INCLUDE\n 'PINCH.GRDECL' /\nPORO\n 48*0.2 /\nPERMX\n {} /\nCOPY\n 'PERMX' 'PERMY' /\n\
         'PERMX' 'PERMZ' /\n/\nMULTIPLY\n 'PERMZ' 0.1 /\n/\nEQUALS\n 'MULTZ' 0.5 1 1 1 3 1 1 /\n\
         'MULTZ-' 0.25 2 2 1 3 3 3 /\n/\nMULTNUM\n 24*1 24*2 /\nMULTREGT\n 1 2 0.5 XYZ ALL M /\n/\nPROPS\nSWOF\n 0 0 1 0\n 1 1 0 0 /\nPVTW\n 200 1 4e-5 0.5 0 /\n\
         PVDO\n 100 1.0 1.0\n 300 0.99 1.1 /\nDENSITY\n 800 1000 1 /\nROCK\n 200 1e-5 /\nSOLUTION\n\
         EQUIL\n 1010 200 3000 0 0 0 1 1 0 /\nSCHEDULE\nTSTEP\n 1 /\nEND\n",
        perm.join(" ")
    );
    let path = dir.join("PINCH.DATA");
    std::fs::write(&path, deck).unwrap();
    let (n, _) = far_field("pinch", &path);
    // four pinch connections (two columns in two rows), none past the
    // thick inactive row
    let g = orthomesh::io::eclipse::read_grid(&path).unwrap();
    let a = orthomesh::io::arrays::read_arrays(&path, [nx, ny, nz]).unwrap();
    let t = a.transmissibilities(&g, 1.0).unwrap();
    let at = |i: usize, j: usize, k: usize| i + nx * (j + ny * k);
    let pinched: Vec<_> = t
        .iter()
        .filter(|c| c.axis == 2 && c.cells[0].abs_diff(c.cells[1]) == 2 * nx * ny)
        .collect();
    assert_eq!(pinched.len(), 4, "{pinched:?}");
    assert!(pinched
        .iter()
        .all(|c| c.cells[0] % (nx * ny) < 2 * nx && c.cells[0] % nx < 2));
    assert!(pinched
        .iter()
        .any(|c| c.cells == [at(0, 0, 0), at(0, 0, 2)]));
    assert!(n > 0);
}

/// Writes a deck's far-field transmissibilities (the pair, the axis, the
/// value) and a sidecar naming the deck for tests/decks.py; returns how
/// many there are and how many join cells of different layers (across a
/// throw).
fn far_field(stem: &str, deck: &Path) -> (usize, usize) {
    use orthomesh::io::{arrays::read_arrays, eclipse};
    use orthomesh::reservoir::trans::darcy;
    let g = eclipse::read_grid(deck).unwrap();
    let a = read_arrays(deck, [g.nx, g.ny, g.nz]).unwrap();
    let field = eclipse::unit_system(deck).unwrap() == "FIELD";
    let t = a.transmissibilities(&g, darcy(field)).unwrap();
    let mut text = String::new();
    for c in &t {
        text.push_str(&format!(
            "{} {} {} {:e}\n",
            c.cells[0], c.cells[1], c.axis, c.value
        ));
    }
    let dir = out_dir().join("trans");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join(format!("{stem}.txt")), text).unwrap();
    let side = json!({ "deck": std::fs::canonicalize(deck).unwrap(), "dims": [g.nx, g.ny, g.nz] });
    std::fs::write(dir.join(format!("{stem}.json")), side.to_string()).unwrap();
    let layer = |c: usize| c / (g.nx * g.ny);
    let thrown = t
        .iter()
        .filter(|c| layer(c.cells[0]) != layer(c.cells[1]))
        .count();
    (t.len(), thrown - t.iter().filter(|c| c.axis == 2).count())
}
