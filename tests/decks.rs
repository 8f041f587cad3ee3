//! OPM Flow decks (issue 22): Thiem's case in 2D, 2.5D and 3D, the demo and
//! SPE9's top layer with its 26 wells, written with a JSON sidecar of
//! what the deck must hold and give. Here: the deck's connections against
//! the mesh's. `tests/decks.py` (run by scripts/test.sh) then parses each
//! deck with opm-common, runs Flow on it and checks the sidecar's figures.

mod common;

use common::hybrid3::lenient;
use orthomesh::backend::default_backend;
use orthomesh::io::deck::{Control, Deck, Fluid};
use orthomesh::reservoir::deck::{deck, DeckSettings, Rock, WellLinks, DARCY};
use orthomesh::reservoir::hybrid::{build, HybridOptions, Region, WellAt, WellInput};
use orthomesh::reservoir::hybrid3::{self, Hybrid3Options, Well3};
use orthomesh::reservoir::CornerPointGrid;
use orthomesh::Network;
use serde_json::json;
use std::f64::consts::TAU;
use std::path::PathBuf;

const PERM: f64 = 100.0;
const RATE: f64 = 100.0;
const RW: f64 = 0.1;
const P0: f64 = 200.0;

/// Where the decks go: beside the meshes the readers check, else a
/// directory of this test's own.
fn out_dir() -> PathBuf {
    let dir = match std::env::var("ORTHOMESH_TEST_OUT") {
        Ok(d) => PathBuf::from(d).join("decks"),
        Err(_) => std::env::temp_dir().join(format!("orthomesh-decks-{}", std::process::id())),
    };
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Writes the deck and its sidecar: NNC count and total transmissibility,
/// and whatever the case adds.
fn write(stem: &str, d: &Deck, mut extra: serde_json::Value) {
    let dir = out_dir();
    let text = orthomesh::io::deck::to_string(d).unwrap();
    orthomesh::io::write_atomic(&dir.join(format!("{stem}.DATA")), text.as_bytes()).unwrap();
    extra["nnc"] = json!(d.nnc.len());
    extra["transmissibility"] = json!(d.nnc.iter().map(|c| c.transmissibility).sum::<f64>());
    extra["cells"] = json!(d.cells.len());
    extra["days"] = json!(d.steps.iter().sum::<f64>());
    let side = serde_json::to_string_pretty(&extra).unwrap();
    orthomesh::io::write_atomic(&dir.join(format!("{stem}.json")), side.as_bytes()).unwrap();
}

/// The deck's connections are the network's, one for one, with
/// T = c A / (d1/k1 + d2/k2) (k along the connection's axis).
fn assert_matches(d: &Deck, net: &Network, rock: &Rock) {
    assert_eq!(d.nnc.len(), net.connections.len());
    let want: f64 = net
        .connections
        .iter()
        .map(|c| {
            let axis = c.isot as usize - 1;
            let k = c.elements.map(|e| rock.perm[e][axis]);
            DARCY * c.area / (c.d[0] / k[0] + c.d[1] / k[1])
        })
        .sum();
    let got: f64 = d.nnc.iter().map(|c| c.transmissibility).sum();
    assert!((got - want).abs() <= 1e-12 * want, "{got} {want}");
    assert!(d.nnc.iter().all(|c| c.transmissibility > 0.0));
}

/// Water's hydrostatic gradient (bar/m) at surface density.
const GRADIENT: f64 = 1000.0 * 9.80665e-5;

/// Thiem's steady state: cells at r = L/4 ("band") against the well at
/// their depth, the lateral boundary's cells held at Thiem's pressure by a
/// huge pore volume, every cell starting from Thiem's pressure plus the
/// hydrostatic head. (Flow 2022.10 reads NOGRAV but keeps gravity.)
struct Thiem {
    /// Per element: distance from the well's axis, whether on the lateral
    /// boundary, whether in the band.
    radius: Vec<f64>,
    boundary: Vec<bool>,
    band: Vec<bool>,
    /// Permeability times thickness over the layers (mD m), and the
    /// domain's side.
    kh: f64,
    side: f64,
    /// Per element, whether Thiem is taken with the rate per length that
    /// comes in there (the middle of a horizontal well) rather than the
    /// well's mean: decks.py reads that share from the connections.
    local: Option<Vec<bool>>,
}

impl Thiem {
    /// p = P0 + A ln(r / (L/2)), A = q mu B / (2 pi c k h).
    fn slope(&self) -> f64 {
        RATE * Fluid::default().viscosity / (TAU * DARCY * self.kh)
    }

    fn exact(&self, r: f64) -> f64 {
        P0 + self.slope() * (r / (self.side / 2.0)).ln()
    }

    fn deck(&self, stem: &str, net: &Network, wells: &[WellLinks]) {
        let rock = Rock::uniform(net.elements.len(), [PERM; 3], 0.2);
        self.deck_in(stem, net, wells, &rock, None)
    }

    /// As `deck`, with the check's tolerance (relative; decks.py's default
    /// otherwise).
    fn deck_tolerance(&self, stem: &str, net: &Network, wells: &[WellLinks], tol: f64) {
        let rock = Rock::uniform(net.elements.len(), [PERM; 3], 0.2);
        self.deck_in(stem, net, wells, &rock, Some(tol))
    }

    fn deck_in(
        &self,
        stem: &str,
        net: &Network,
        wells: &[WellLinks],
        rock: &Rock,
        tol: Option<f64>,
    ) {
        // Compressible enough for Flow's time stepping: the interior settles
        // within a day (phi mu c_t L^2 / (c k)), and in 20 days the boundary,
        // of a million times its pore volume, drifts by 1e-3 bar.
        let settings = DeckSettings {
            control: Control::Produce {
                rate: RATE,
                min_bhp: 1.0,
            },
            pressure: P0,
            datum: None,
            steps: vec![2.0; 10],
            fluid: Fluid::default(),
        };
        let (mut d, position) = deck(stem, net, rock, wells, &settings);
        assert_matches(&d, net, rock);
        let mut pressures = vec![0.0; d.cells.len()];
        let mut band = vec![];
        let top = d
            .cells
            .iter()
            .map(|c| c.depth)
            .fold(f64::INFINITY, f64::min);
        for (e, &i) in position.iter().enumerate() {
            let depth = d.cells[i].depth;
            pressures[i] = self.exact(self.radius[e]) + GRADIENT * (depth - top);
            if self.boundary[e] {
                d.cells[i].pore_volume *= 1e6;
            }
            if self.band[e] {
                band.push(json!([i + 1, self.radius[e], depth]));
            }
        }
        assert!(!band.is_empty());
        d.pressures = Some(pressures);
        d.watch = band
            .iter()
            .map(|b| b[0].as_u64().unwrap() as usize - 1)
            .collect();
        d.watch.extend(d.wells[0].connections.iter().map(|c| c.0));
        let first = d.wells[0].connections[0].0;
        let mut sidecar = json!({
            "thiem": {
                "well": wells[0].name, "rw": RW, "slope": self.slope(), "band": band,
                "ref_depth": d.cells[first].depth, "gradient": GRADIENT,
                "inner": d.wells[0].connections.iter().map(|c| json!([c.0 + 1, d.cells[c.0].depth, c.1])).collect::<Vec<_>>()
            }
        });
        if let Some(tol) = tol {
            sidecar["thiem"]["tolerance"] = json!(tol);
        }
        if let Some(local) = &self.local {
            let cells: Vec<usize> = (0..local.len())
                .filter(|&e| local[e])
                .map(|e| position[e] + 1)
                .collect();
            sidecar["thiem"]["local"] = json!(cells);
        }
        write(stem, &d, sidecar);
    }
}

/// The 2D and 2.5D cases: 31 x 31 columns of 10 m around one well (the
/// flow check's grid, tests/flow.rs), one layer of 10 m, or three of 4 m.
#[test]
fn thiem_decks_in_2d_and_25d() {
    let (n, dx) = (31, 10.0);
    for (layers, dz) in [(1, 10.0), (3, 4.0)] {
        let grid = CornerPointGrid::cartesian([n, n, layers], [dx, dx, dz]);
        let mid = n / 2;
        let well = WellInput {
            name: "W".into(),
            at: WellAt::Column(mid, mid),
            radius: RW,
        };
        let h = build(
            &default_backend(),
            &grid,
            &[well],
            &HybridOptions::default(),
        )
        .unwrap();
        let c = (mid as f64 + 0.5) * dx;
        let side = n as f64 * dx;
        let r = |x: [f64; 2]| (x[0] - c).hypot(x[1] - c);
        // 2D cells on the lateral boundary, in the band.
        let cells = h.mesh.cells.len();
        let mut edge = vec![false; cells];
        for f in orthomesh::reservoir::flow::boundary_faces(&h.mesh) {
            if r(h.mesh.points[f.points[0] as usize]) > 2.0 * RW {
                edge[f.cell as usize] = true;
            }
        }
        let in_band = |k: usize| {
            h.region[k] == Region::Reservoir && (r(h.mesh.sites[k]) - side / 4.0).abs() <= dx / 2.0
        };
        let thiem = |radius, boundary, band| Thiem {
            radius,
            boundary,
            band,
            kh: PERM * layers as f64 * dz,
            side,
            local: None,
        };
        if layers == 1 {
            let net = h.network();
            let t = thiem(
                (0..cells).map(|k| r(h.mesh.sites[k])).collect(),
                edge,
                (0..cells).map(in_band).collect(),
            );
            t.deck("thiem-2d", &net, &h.well_links());
        } else {
            let l = orthomesh::reservoir::extrude(&h, &grid).unwrap();
            let net = l.network(&h);
            let links = l.well_links(&h, &[]);
            assert_eq!(links[0].links.len(), 32 * layers);
            let t = thiem(
                l.node.iter().map(|p| r([p[0], p[1]])).collect(),
                l.origin.iter().map(|&(k, _)| edge[k as usize]).collect(),
                l.origin.iter().map(|&(k, _)| in_band(k as usize)).collect(),
            );
            t.deck("thiem-25d", &net, &links);
        }
    }
}

/// A well in an ordinary cell: a `conform` mesh of 31 x 31 squares of 10 m
/// given as segments (each square cut into four cells), the well at the
/// site of a cell beside the centre, connected by Peaceman's factor from
/// that cell's own connections (`reservoir::deck::peaceman`).
#[test]
fn thiem_deck_with_peacemans_factor_in_a_conform_mesh() {
    let (n, dx, thickness) = (31usize, 10.0, 10.0);
    let idx = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    let points = (0..=n)
        .flat_map(|j| (0..=n).map(move |i| [i as f64 * dx, j as f64 * dx]))
        .collect();
    let mut segments = vec![];
    for a in 0..=n {
        for b in 0..n {
            segments.push([idx(b, a), idx(b + 1, a)]);
            segments.push([idx(a, b), idx(a, b + 1)]);
        }
    }
    let cx = orthomesh::Complex {
        points,
        segments,
        ..Default::default()
    };
    let out = orthomesh::Mesher::new(&default_backend())
        .conform(&cx)
        .unwrap();
    let mesh = &out.mesh;
    let side = n as f64 * dx;
    let [cell] = mesh.locate([side / 2.0, side / 2.0 - 2.0])[..] else {
        panic!("the point is inside one cell")
    };
    let c = mesh.sites[cell];
    let cells = mesh.cells.len();
    let net =
        orthomesh::reservoir::flow::network(mesh, &vec![thickness; cells], &vec![1000.0; cells]);
    let (factor, r_o) = orthomesh::reservoir::deck::peaceman(&net, cell, thickness, RW).unwrap();
    println!("Peaceman: cell {cell} of {cells}, equivalent radius {r_o:.3} m");
    let wells = [WellLinks {
        name: "W".into(),
        radius: RW,
        links: vec![(cell, factor)],
        log: (r_o / RW).ln(),
    }];
    let r = |x: [f64; 2]| (x[0] - c[0]).hypot(x[1] - c[1]);
    let mut edge = vec![false; cells];
    for f in orthomesh::reservoir::flow::boundary_faces(mesh) {
        edge[f.cell as usize] = true;
    }
    let t = Thiem {
        // (the well's own cell starts from the wellbore's pressure)
        radius: mesh.sites.iter().map(|&s| r(s).max(RW)).collect(),
        boundary: edge,
        band: mesh
            .sites
            .iter()
            .map(|&s| (r(s) - side / 4.0).abs() <= dx / 2.0)
            .collect(),
        kh: PERM * thickness,
        side,
        local: None,
    };
    t.deck("thiem-peaceman", &net, &wells);
}

/// The 3D case: a vertical well through 15 x 15 x 2 blocks of 10 x 10 x 5 m,
/// its sectors turned by 30 degrees as in the crate's own 3D flow check
/// (tests/hybrid3.rs): with sector corners on the grid's axes (azimuth 0)
/// the transition mesh is 1.4% off Thiem there too (docs/limitations.md).
#[test]
fn thiem_deck_in_3d() {
    let (h, t) = thiem_3d(&[0.0, 5.0, 10.0], &[PERM, PERM]);
    let links = &h.wellbore;
    assert_eq!((links[0].name.as_str(), links[0].radius), ("W", RW));
    assert_eq!(links[0].links.len(), Hybrid3Options::default().sectors * 2);
    assert!(h.report.sections.is_empty(), "the 3D transition");
    t.deck("thiem-3d", &h.mesh.network(), links);
}

/// The 3D hybrid of a block of 15 x 15 columns of 10 m with layers at the
/// given depths and permeabilities around a vertical well (sectors turned
/// by 30 degrees), with its Thiem case.
fn thiem_3d(depths: &[f64], perm: &[f64]) -> (hybrid3::Hybrid3, Thiem) {
    let (n, dx) = (15, 10.0);
    let grid = CornerPointGrid::layered([n, n], [dx, dx], depths);
    let w = Well3 {
        name: "W".into(),
        i: n / 2,
        j: n / 2,
        radius: RW,
        azimuth: 30.0,
        ..Default::default()
    };
    // the transition meshed in 3D (thiem_deck_in_a_layered_block: layered)
    let opts = Hybrid3Options {
        layered: None,
        ..Default::default()
    };
    let h = hybrid3::build(&default_backend(), &grid, &[w], &opts).unwrap();
    let c = (n / 2) as f64 * dx + dx / 2.0;
    let side = n as f64 * dx;
    let r = |p: [f64; 3]| (p[0] - c).hypot(p[1] - c);
    let edge =
        |k: usize| h.ijk[k].is_some_and(|[i, j, _]| i == 0 || j == 0 || i == n - 1 || j == n - 1);
    let t = Thiem {
        radius: h.mesh.sites.iter().map(|&p| r(p)).collect(),
        boundary: (0..h.mesh.sites.len()).map(edge).collect(),
        band: (0..h.mesh.sites.len())
            .map(|k| {
                h.region[k] == Region::Reservoir
                    && (r(h.mesh.sites[k]) - side / 4.0).abs() <= dx / 2.0
            })
            .collect(),
        kh: (0..perm.len())
            .map(|k| perm[k] * (depths[k + 1] - depths[k]))
            .sum(),
        side,
        local: None,
    };
    (h, t)
}

/// A well beside a fault's throw (the corpus' 7 x 7 x 3 block, columns 6-7
/// 1 m deeper; completed in layers 1-2, its cavity crossed by the fault),
/// producing against the block's open sides: Flow runs it (decks.py).
#[test]
fn a_well_beside_a_throw_in_flow() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/corpus");
    let grid = orthomesh::io::eclipse::read_grid(&dir.join("throw_7x7x3.grdecl")).unwrap();
    let w = Well3 {
        name: "W".into(),
        i: 4,
        j: 3,
        k: Some([0, 1]),
        radius: RW,
        azimuth: 30.0,
        ..Default::default()
    };
    let h = lenient(&grid, w);
    assert!(h.report.conforms());
    assert!(h.report.across_throws > 0);
    open_sides_deck("beside-throw-3d", "beside a throw", &h, &grid);
}

/// A 3D hybrid's deck, its one well producing against the grid's open
/// sides for 10 days, and its sidecar, for decks.py.
fn open_sides_deck(stem: &str, title: &str, h: &hybrid3::Hybrid3, grid: &CornerPointGrid) {
    let net = h.mesh.network();
    let choices = orthomesh::reservoir::deck::DeckChoices {
        aquifer: h.outer_cells(grid),
        ..Default::default()
    };
    let (text, _, _) = orthomesh::io::deck::write(title, &net, &h.wellbore, &choices).unwrap();
    let out = out_dir();
    orthomesh::io::write_atomic(&out.join(format!("{stem}.DATA")), text.as_bytes()).unwrap();
    let sidecar = json!({ "nnc": net.connections.len(), "cells": net.elements.len(), "wells": 1, "days": 10.0 });
    orthomesh::io::write_atomic(
        &out.join(format!("{stem}.json")),
        sidecar.to_string().as_bytes(),
    )
    .unwrap();
}

/// An L-shaped well (down 30 m from 5 m deep, then 60 m along x; its
/// legs joined by a mitred knee) in a 9 x 5 x 5 block of 10 m cells whose
/// top is at depth 0, producing against the block's open sides: Flow runs
/// it (decks.py). Sites mirrored above the top put the datum above depth
/// 0, where the default contacts would leave it in a gas zone.
#[test]
fn a_bent_well_in_flow() {
    let grid = CornerPointGrid::cartesian([9, 5, 5], [10.0, 10.0, 10.0]);
    let w = Well3 {
        name: "L".into(),
        radius: RW,
        path: Some(vec![
            [25.0, 25.0, 5.0],
            [25.0, 25.0, 35.0],
            [85.0, 25.0, 35.0],
        ]),
        ..Default::default()
    };
    let h = lenient(&grid, w);
    assert!(h.report.conforms());
    assert_eq!(h.report.cavities[0].outer_radii.len(), 2);
    open_sides_deck("bent-3d", "a bent well", &h, &grid);
}

/// The 3D hybrid of a layered block (50, 200 and 100 mD in layers of 4, 2
/// and 6 m; tests/hybrid3.rs checks it with the crate's own solver), each
/// cell with its host's permeability, for decks.py's Thiem check in Flow.
#[test]
fn thiem_deck_in_a_layered_block() {
    let perm = [50.0, 200.0, 100.0];
    let (h, t) = thiem_3d(&[0.0, 4.0, 6.0, 12.0], &perm);
    let rock = Rock {
        perm: h.host.iter().map(|c| [perm[c[2]]; 3]).collect(),
        poro: vec![0.2; h.host.len()],
    };
    t.deck_in(
        "thiem-3d-layered",
        &h.mesh.network(),
        &h.wellbore,
        &rock,
        None,
    );
}

/// The horizontal well of tests/hybrid3.rs (160 m along x in the middle of
/// layer 4 of a box of 25 x 11 x 6 cells of 10 m), for decks.py's Thiem
/// check in Flow: Thiem's pressure about the axis held on the box's sides,
/// the drop from the well to 15 m from the axis (a quarter of the box's
/// height) in the middle 50 m, within 1%. Flow's well is at one pressure
/// along its length, so more of the rate comes in near its ends than in
/// the crate's check, which spreads it evenly.
#[test]
fn thiem_deck_for_a_horizontal_well() {
    let ([nx, ny, nz], h) = ([25, 11, 6], 10.0);
    let g = CornerPointGrid::cartesian([nx, ny, nz], [h, h, h]);
    let (y, depth, length) = (55.0, 35.0, 160.0);
    let w = Well3 {
        name: "H".into(),
        radius: RW,
        path: Some(vec![[45.0, y, depth], [125.0, y, depth], [205.0, y, depth]]),
        ..Default::default()
    };
    let hy = lenient(&g, w);
    assert_eq!(hy.report.sites_outside, 0);
    let m = &hy.mesh;
    let dist = |x: [f64; 3]| (x[1] - y).hypot(x[2] + depth);
    let side = |k: usize| {
        hy.ijk[k].is_some_and(|[i, j, kk]| {
            i == 0 || j == 0 || kk == 0 || i == nx - 1 || j == ny - 1 || kk == nz - 1
        })
    };
    let band = |k: usize| {
        hy.region[k] == Region::Reservoir
            && (100.0..=150.0).contains(&m.sites[k][0])
            && (dist(m.sites[k]) - 15.0).abs() <= h / 2.0
    };
    let cells = m.sites.len();
    let t = Thiem {
        // (cells beyond the well's ends may have their sites on its axis)
        radius: m.sites.iter().map(|&p| dist(p).max(RW)).collect(),
        boundary: (0..cells).map(side).collect(),
        band: (0..cells).map(band).collect(),
        // along the well, per unit of its length; Thiem's pressure is
        // taken about 30 m from the axis (half the box's height)
        kh: PERM * length,
        side: nz as f64 * h,
        local: Some(
            (0..cells)
                .map(|k| (100.0..=150.0).contains(&m.sites[k][0]))
                .collect(),
        ),
    };
    t.deck_tolerance("thiem-3d-horizontal", &m.network(), &hy.wellbore, 0.01);
}

/// The demo's mesh and SPE9's top layer with its 26 wells, as the CLI
/// writes them (defaults said in the deck's notes).
#[test]
fn demo_and_spe9_decks() {
    let (g, wells, opts) = orthomesh::reservoir::demo();
    let h = build(&default_backend(), &g, &wells, &opts).unwrap();
    // The well's innermost ring lies in its own column (6, 7), and every
    // cell takes the rock of a grid cell of the layer.
    for &c in &h.wells[0].inner {
        assert_eq!(h.host[c as usize], [6, 7, 0]);
    }
    assert!(h.host.iter().all(|&[i, j, k]| i < 15 && j < 15 && k == 0));
    // As `orthomesh demo` writes it: an open boundary.
    let choices = orthomesh::reservoir::deck::DeckChoices {
        aquifer: h.outer_cells(),
        ..Default::default()
    };
    assert_eq!(choices.aquifer.len(), 56);
    let net = h.network();
    let (text, notes, _) =
        orthomesh::io::deck::write("demo", &net, &h.well_links(), &choices).unwrap();
    assert!(notes.iter().any(|n| n.contains("default")));
    assert!(notes
        .iter()
        .any(|n| n.contains("open boundary: its 56 cells")));
    let dir = out_dir();
    orthomesh::io::write_atomic(&dir.join("demo.DATA"), text.as_bytes()).unwrap();
    let sidecar = json!({ "nnc": net.connections.len(), "cells": net.elements.len(), "wells": 1, "days": 10.0 });
    orthomesh::io::write_atomic(&dir.join("demo.json"), sidecar.to_string().as_bytes()).unwrap();

    let data = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/grids");
    let grid = orthomesh::io::eclipse::read_grid(&data.join("SPE9.GRDECL")).unwrap();
    let (found, _) = orthomesh::io::eclipse::read_wells(&data.join("SPE9_CP.DATA")).unwrap();
    let wells: Vec<WellInput> = found
        .into_iter()
        .map(|w| WellInput {
            name: w.name,
            at: WellAt::Column(w.i, w.j),
            radius: w.radius.unwrap_or(0.25),
        })
        .collect();
    assert_eq!(wells.len(), 26);
    let h = build(&default_backend(), &grid, &wells, &HybridOptions::default()).unwrap();
    let net = h.network();
    // SPE9 is in feet: the deck is in metres.
    let length = orthomesh::io::eclipse::length_unit(&data.join("SPE9_CP.DATA")).unwrap();
    assert_eq!(length.as_ref().map(|l| l.0), Some(0.3048));
    // Its own schedule for 310 days: producers at 1500 stb/day for 300
    // days, then at 100; the injector at 5000 stb/day up to 4000 psia; an
    // open boundary.
    let names: Vec<String> = h.wells.iter().map(|w| w.name.clone()).collect();
    let (periods, said) =
        orthomesh::io::schedule::read_schedule(&data.join("SPE9_CP.DATA"), &names).unwrap();
    assert_eq!(periods.len(), 3);
    assert_eq!(periods[0].controls.len(), 26);
    // Its rock: the deck's PORO on every cell's host (PERM is in an
    // include the shared data lacks: the default).
    let cells = grid.nx * grid.ny * grid.nz;
    let paths = [data.join("SPE9.GRDECL"), data.join("SPE9_CP.DATA")];
    let paths: Vec<&std::path::Path> = paths.iter().map(|p| p.as_path()).collect();
    let (props, _) = orthomesh::io::eclipse::read_properties(&paths, cells).unwrap();
    let rock = orthomesh::io::deck::rock_from(&props, &h.host, [grid.nx, grid.ny]);
    assert!(rock.0.poro.iter().all(|&p| p == 0.087));
    let choices = orthomesh::reservoir::deck::DeckChoices {
        length,
        rock: Some(rock),
        aquifer: h.outer_cells(),
        schedule: Some((periods, said)),
        days: Some(310.0),
        equil: orthomesh::io::schedule::read_equil(&data.join("SPE9_CP.DATA")).unwrap(),
        ..Default::default()
    };
    let (d, notes, position) =
        orthomesh::reservoir::deck::prepare("SPE9 top layer", &net, &h.well_links(), &choices)
            .unwrap();
    let text = orthomesh::io::deck::to_string(&d).unwrap();
    // Watched cells of the open boundary keep the initial state: their
    // 1-based deck cell and depth, for decks.py.
    let outer: Vec<usize> = choices.aquifer.iter().map(|&e| position[e]).collect();
    let initial: Vec<(usize, f64)> = d
        .watch
        .iter()
        .filter(|c| outer.contains(c))
        .map(|&c| (c + 1, d.cells[c].depth))
        .collect();
    assert!(!initial.is_empty());
    assert!(notes.iter().any(|n| n.contains("feet")), "{notes:?}");
    assert!(
        notes
            .iter()
            .any(|n| n.contains("schedule: 2 periods, 310 days")),
        "{notes:?}"
    );
    // Its initial state: 3600 psia at 9035 ft.
    assert!(text.contains("EQUIL\n 2753.868 248.2112"), "{text}");
    assert!(
        notes
            .iter()
            .any(|n| n.contains("EQUIL of") && n.contains("9035 3600 (ft, psia)")),
        "{notes:?}"
    );
    orthomesh::io::write_atomic(&dir.join("spe9-top.DATA"), text.as_bytes()).unwrap();
    // The controls of the last period, in METRIC units.
    let stb = 0.158_987_294_928;
    let psi = 0.068_947_572_931_783_1;
    let mut scheduled = serde_json::Map::new();
    for n in &names {
        let control = if n.starts_with("PRODU") {
            json!(["produce", 100.0 * stb, 1000.0 * psi])
        } else {
            json!(["inject", 5000.0 * stb, 4000.0 * psi])
        };
        scheduled.insert(n.clone(), control);
    }
    let sidecar = json!({
        "nnc": net.connections.len(), "cells": net.elements.len(), "wells": 26, "days": 310.0,
        "scheduled": scheduled,
        "equil": { "datum": d.datum, "pressure": d.pressure, "cells": initial },
        "well_depth": d.wells.iter().map(|w| (w.name.clone(), json!(d.cells[w.connections[0].0].depth))).collect::<serde_json::Map<_, _>>()
    });
    orthomesh::io::write_atomic(&dir.join("spe9-top.json"), sidecar.to_string().as_bytes())
        .unwrap();
}

/// The command line: `--eclipse` on `hybrid` (SPE9's top layer, in feet)
/// and on `conform` (no wells, said); choices out of range are errors that
/// leave no file.
#[test]
fn the_command_line_writes_decks_and_says_what_it_assumed() {
    let dir = out_dir().join("cli");
    std::fs::create_dir_all(&dir).unwrap();
    let run = |args: &[&str]| {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_orthomesh"))
            .args(args)
            .output()
            .unwrap();
        (
            out.status.code(),
            String::from_utf8_lossy(&out.stderr).into_owned(),
        )
    };
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let p = |name: &str| dir.join(name).display().to_string();
    let (grid, wells) = (
        root.join("grids/SPE9.GRDECL").display().to_string(),
        root.join("grids/SPE9_CP.DATA").display().to_string(),
    );
    let (code, err) = run(&[
        "hybrid",
        "--grid",
        &grid,
        "--deck",
        &wells,
        "-o",
        &p("hybrid-spe9.vtu"),
        "--eclipse",
        &p("SPE9.DATA"),
        "--rate",
        "50",
        "--tough",
        &p("hybrid-spe9.tough"),
    ]);
    assert_eq!(code, Some(0), "{err}");
    // The VTU maps its cells onto both simulators' (readers.py checks
    // the names against toughio's reading of the MESH).
    let vtu = std::fs::read_to_string(dir.join("hybrid-spe9.vtu")).unwrap();
    assert!(vtu.contains("Name=\"deck_cell\"") && vtu.contains("Name=\"tough_element\""));
    assert!(
        err.contains("feet (FIELD) in") && err.contains("50 sm3/day"),
        "{err}"
    );
    let deck = std::fs::read_to_string(dir.join("SPE9.DATA")).unwrap();
    assert_eq!(deck.matches("'G1'").count(), 26);
    // The top layer's porosity from the deck's PORO; its permeabilities'
    // include is not in the shared data.
    assert!(deck.contains("PORO\n 0.087 0.087"), "{}", &deck[..2000]);
    assert!(
        err.contains("PORO from the input") && err.contains("PERMVALUES.DATA not found"),
        "{err}"
    );
    assert!(deck.contains("WCONPROD"));

    // The 3D hybrid takes its grid's rock: a porosity per layer.
    let block = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/golden/block7x7x2.grdecl");
    let text = std::fs::read_to_string(block).unwrap() + "PORO\n 49*0.1 49*0.3 /\n";
    std::fs::write(dir.join("layered.grdecl"), text).unwrap();
    let (code, err) = run(&[
        "hybrid",
        "--3d",
        "--grid",
        &p("layered.grdecl"),
        "--well",
        "W:4:4:0.1:0:30",
        "-o",
        &p("hybrid3-layered.vtu"),
        "--eclipse",
        &p("LAYERED.DATA"),
    ]);
    assert_eq!(code, Some(0), "{err}");
    assert!(err.contains("PORO from the input"), "{err}");
    let deck = std::fs::read_to_string(dir.join("LAYERED.DATA")).unwrap();
    let poro = deck
        .split("PORO\n")
        .nth(1)
        .unwrap()
        .split('/')
        .next()
        .unwrap();
    let values: Vec<f64> = poro
        .split_whitespace()
        .map(|v| v.parse().unwrap())
        .collect();
    let n = |f: f64| values.iter().filter(|&&v| v == f).count();
    // half the cells each side of the layers' boundary, well and
    // transition cells included
    assert!(
        n(0.1) == n(0.3) && n(0.1) + n(0.3) == values.len(),
        "{poro}"
    );

    let poly = root.join("pslg/double_hex2.poly").display().to_string();
    let (code, err) = run(&[
        "conform",
        &poly,
        "-o",
        &p("hex.vtu"),
        "--eclipse",
        &p("HEX.DATA"),
        "--poro",
        "0.3",
    ]);
    assert_eq!(code, Some(0), "{err}");
    assert!(
        err.contains("no wells") && err.contains("porosity 0.3 (--poro)"),
        "{err}"
    );
    let deck = std::fs::read_to_string(dir.join("HEX.DATA")).unwrap();
    assert!(!deck.contains("WELSPECS") && deck.contains("TSTEP"));

    // A well in an ordinary cell of a conform mesh: 3 x 3 squares of 10 m.
    let mut text = String::from("16 2 0 0\n");
    for k in 0..16 {
        text += &format!("{} {} {}\n", k + 1, (k % 4) * 10, (k / 4) * 10);
    }
    text += "24 0\n";
    for a in 0..4 {
        for b in 0..3 {
            let n = 2 * (3 * a + b);
            text += &format!("{} {} {}\n", n + 1, 4 * a + b + 1, 4 * a + b + 2);
            text += &format!("{} {} {}\n", n + 2, 4 * b + a + 1, 4 * b + a + 5);
        }
    }
    std::fs::write(dir.join("squares.poly"), text + "0\n").unwrap();
    let squares = p("squares.poly");
    let conform = |well: &str, deck: bool| {
        let (vtu, data) = (p("squares.vtu"), p("SQUARES.DATA"));
        let mut args = vec!["conform", &squares, "-o", &vtu, "--well-xy", well];
        if deck {
            args.extend(["--eclipse", &data]);
        }
        run(&args)
    };
    let (code, err) = conform("W:15:12:0.1", true);
    assert_eq!(code, Some(0), "{err}");
    assert!(
        err.contains("well W in cell") && err.contains("Peaceman"),
        "{err}"
    );
    let deck = std::fs::read_to_string(dir.join("SQUARES.DATA")).unwrap();
    assert!(deck.contains("COMPDAT\n 'W' "), "{deck}");
    std::fs::remove_file(dir.join("SQUARES.DATA")).unwrap();
    for (well, deck, says) in [
        ("W:15:15", true, "on the boundary of cells"),
        ("W:99:5", true, "outside the mesh"),
        ("W:15:12:9", true, "not below the equivalent radius"),
        ("W:15:12", false, "is for --eclipse"),
    ] {
        let (code, err) = conform(well, deck);
        assert_eq!(code, Some(1), "{well}: {err}");
        assert!(err.contains(says), "{well}: {err}");
        assert!(!dir.join("SQUARES.DATA").exists());
    }

    for bad in [
        vec!["--eclipse", "BAD.DATA", "--perm=-3"],
        vec!["--eclipse", "BAD.DATA", "--poro", "1.5"],
        vec!["--perm", "10"],
        vec!["--eclipse", "BAD.DATA", "--aquifer"],
    ] {
        let vtu = p("bad.vtu");
        let mut args = vec!["conform", &poly, "-o", &vtu];
        let bad: Vec<String> = bad
            .iter()
            .map(|a| {
                if a.ends_with(".DATA") {
                    p(a)
                } else {
                    a.to_string()
                }
            })
            .collect();
        args.extend(bad.iter().map(|s| s.as_str()));
        let (code, err) = run(&args);
        assert_eq!(code, Some(1), "{args:?}");
        assert!(
            err.contains("--perm") || err.contains("--poro") || err.contains("--aquifer"),
            "{err}"
        );
        assert!(!dir.join("bad.vtu").exists() && !dir.join("BAD.DATA").exists());
    }
}

/// SPE9 in full 3D: its 24 x 25 x 15 grid with its 26 wells along their
/// COMPDAT layers (defaults: layered cavities on two sections across the
/// 10 degree dip), its rock, EQUIL and the first 30 days of its own
/// schedule, for decks.py to run in OPM Flow.
#[test]
fn spe9_in_3d_deck() {
    let data = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/grids");
    let case = data.join("SPE9_CP.DATA");
    let grid = orthomesh::io::eclipse::read_grid(&data.join("SPE9.GRDECL")).unwrap();
    let (found, _) = orthomesh::io::eclipse::read_wells(&case).unwrap();
    let wells: Vec<Well3> = found.into_iter().map(|w| w.well3(0.25)).collect();
    assert_eq!(wells.len(), 26);
    assert_eq!(wells[0].k, Some([10, 14]));
    let opts = Hybrid3Options {
        allow_sites_outside: true,
        ..Default::default()
    };
    let start = std::time::Instant::now();
    let h = hybrid3::build(&default_backend(), &grid, &wells, &opts).unwrap();
    let r = &h.report;
    println!(
        "SPE9 in 3D, 26 wells: {:.1} s, {} cavities, cells {:?}, {} of {} transition sites outside, {} unpaired faces, by regions {:?}",
        start.elapsed().as_secs_f64(),
        r.cavities.len(),
        r.cells,
        r.sites_outside,
        r.cells[1],
        r.unpaired_faces,
        r.by_regions
    );
    assert!(r.conforms());
    assert_eq!(r.unpaired_faces + r.unmatched_faces, 0);
    assert_eq!(h.wellbore.len(), 26);
    // every well connected along its completed layers only (layered
    // cavities, as the CLI's default)
    assert_eq!(r.sections.len(), 2);
    let m = opts.layered.map_or(opts.sectors, |s| s.sectors);
    for (w, links) in wells.iter().zip(&h.wellbore) {
        let [k1, k2] = w.k.unwrap();
        assert_eq!(links.links.len(), (k2 - k1 + 1) * m, "{}", w.name);
    }
    let net = h.mesh.network();
    let length = orthomesh::io::eclipse::length_unit(&case).unwrap();
    let names: Vec<String> = wells.iter().map(|w| w.name.clone()).collect();
    let (periods, said) = orthomesh::io::schedule::read_schedule(&case, &names).unwrap();
    let controls = periods[0].controls.clone();
    let cells = grid.nx * grid.ny * grid.nz;
    let paths = [data.join("SPE9.GRDECL"), case.clone()];
    let paths: Vec<&std::path::Path> = paths.iter().map(|p| p.as_path()).collect();
    let (props, _) = orthomesh::io::eclipse::read_properties(&paths, cells).unwrap();
    let choices = orthomesh::reservoir::deck::DeckChoices {
        length,
        rock: Some(orthomesh::io::deck::rock_from(
            &props,
            &h.host,
            [grid.nx, grid.ny],
        )),
        schedule: Some((periods, said)),
        days: Some(30.0),
        equil: orthomesh::io::schedule::read_equil(&case).unwrap(),
        ..Default::default()
    };
    let (d, _, _) =
        orthomesh::reservoir::deck::prepare("SPE9 in 3D", &net, &h.wellbore, &choices).unwrap();
    let text = orthomesh::io::deck::to_string(&d).unwrap();
    let dir = out_dir();
    orthomesh::io::write_atomic(&dir.join("spe9-3d.DATA"), text.as_bytes()).unwrap();
    let mut scheduled = serde_json::Map::new();
    for (n, c) in controls {
        let c = match c {
            orthomesh::reservoir::deck::Control::Produce { rate, min_bhp } => {
                json!(["produce", rate, min_bhp])
            }
            orthomesh::reservoir::deck::Control::Inject { rate, max_bhp } => {
                json!(["inject", rate, max_bhp])
            }
            other => panic!("{n}: {other:?}"),
        };
        scheduled.insert(n, c);
    }
    let sidecar = json!({
        "nnc": net.connections.len(), "cells": net.elements.len(), "wells": 26, "days": 30.0,
        "scheduled": scheduled,
        "equil": { "datum": d.datum, "pressure": d.pressure, "cells": [] },
        "well_depth": d.wells.iter().map(|w| (w.name.clone(), json!(d.cells[w.connections[0].0].depth))).collect::<serde_json::Map<_, _>>()
    });
    orthomesh::io::write_atomic(&dir.join("spe9-3d.json"), sidecar.to_string().as_bytes()).unwrap();
}
