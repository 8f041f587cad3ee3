//! The 3D hybrid on a real corner-point field: Emerald with its inactive
//! hole (21 x 41 x 18, pillars leaning up to 40 degrees, cells 2.5 m thick
//! and 150 m wide whose tops twist by up to 4 m). A well in each class of
//! its columns, along its completed cells; each prints what a simulator
//! will see (sites outside, links off orthogonal, slivers).

mod common;

use common::hybrid3::lenient;
use orthomesh::reservoir::hybrid3::{Hybrid3, Well3};
use orthomesh::reservoir::CornerPointGrid;
use std::path::Path;
use std::sync::OnceLock;

fn emerald() -> &'static CornerPointGrid {
    static G: OnceLock<CornerPointGrid> = OnceLock::new();
    G.get_or_init(|| {
        orthomesh::io::eclipse::read_grid(Path::new("tests/data/grids/eme_small_w_hole.grdecl"))
            .unwrap()
    })
}

/// A well completed in cells (1-based I, J, K), in order.
fn along(name: &str, cells: &[[usize; 3]]) -> Well3 {
    Well3 {
        name: name.into(),
        i: cells[0][0] - 1,
        j: cells[0][1] - 1,
        radius: 0.1,
        cells: cells.iter().map(|c| c.map(|x| x - 1)).collect(),
        ..Default::default()
    }
}

/// The column's cells from layer k1 to k2 (1-based).
fn column(i: usize, j: usize, k1: usize, k2: usize) -> Vec<[usize; 3]> {
    (k1..=k2).map(|k| [i, j, k]).collect()
}

fn print(what: &str, h: &Hybrid3) {
    let r = &h.report;
    println!(
        "emerald, {what}: outer radii {:?}, {} transition cells, {} sites outside, {} slivers \
         (smallest {:.2e} of the median; {} merged into their neighbours)",
        r.cavities
            .iter()
            .map(|c| &c.outer_radii)
            .collect::<Vec<_>>(),
        r.cells[1],
        r.sites_outside,
        r.slivers,
        r.smallest_volume_share,
        r.slivers_merged
    );
    for (pair, c) in &r.by_regions {
        println!(
            "  {pair}: {} links, {} off orthogonal (angle median {:.2}, 99% {:.2}, largest \
             {:.2}), {} one-sided",
            c.connections, c.non_orthogonal, c.angle[0], c.angle[1], c.angle[2], c.one_sided
        );
    }
}

/// Leaning columns, the hole's rim, the grid's edge: each well follows its
/// column through its completed layers (a trajectory through its cells,
/// not a vertical line that leaves them), and is certified.
#[test]
fn wells_in_each_class_of_emeralds_columns() {
    for (what, cells) in [
        (
            "a leaning column (19, 18), layers 5-8",
            column(19, 18, 5, 8),
        ),
        ("beside the hole (8, 4), layers 5-8", column(8, 4, 5, 8)),
        ("at the edge (1, 20), layers 5-8", column(1, 20, 5, 8)),
        (
            "a completion that changes column, (19, 18) to (20, 18)",
            [column(19, 18, 5, 6), column(20, 18, 7, 8)].concat(),
        ),
    ] {
        let h = lenient(emerald(), along("W", &cells));
        print(what, &h);
        // for tests/readers.py (check_twisted; PyTOUGH), by its first and
        // last column: slivers whose volume rounds below zero are merged
        // away, since TOUGH readers refuse them
        assert!(h.mesh.volumes.iter().all(|&v| v > 0.0), "{what}");
        let ([i, j, _], [i2, j2, _]) = (cells[0], cells[cells.len() - 1]);
        if let Ok(dir) = std::env::var("ORTHOMESH_TEST_OUT") {
            let name = format!("twisted3-emerald-{i}-{j}-{i2}-{j2}");
            let vtu = orthomesh::io::vtu::to_string(&h.cells());
            orthomesh::io::write_atomic(
                &Path::new(&dir).join(format!("{name}.vtu")),
                vtu.as_bytes(),
            )
            .unwrap();
            let tough = orthomesh::io::tough::to_string(&h.mesh.network()).unwrap();
            orthomesh::io::write_atomic(
                &Path::new(&dir).join(format!("{name}.tough")),
                tough.as_bytes(),
            )
            .unwrap();
        }
        assert!(h.report.conforms(), "{what}");
        // the well's cells are among its completed cells' cavity: its
        // radial mesh is linked to the transition
        assert!(h.report.by_regions["transition-well"].connections > 0);
        // every completed cell holds a transition or well site: the well
        // runs through them all
        for c in &cells {
            let c = c.map(|x| x - 1);
            assert!(
                h.host
                    .iter()
                    .zip(&h.ijk)
                    .any(|(&host, ijk)| ijk.is_none() && host == c),
                "{what}: no site in cell {c:?}"
            );
        }
    }
}

/// A completion down to the grid's bottom in a leaning column: no layer
/// beyond, so its end is capped parallel to the bottom cell's face
/// (across the axis, in 2.5 m layers, no radial mesh fitted).
#[test]
fn a_completion_to_the_grids_bottom_in_a_leaning_column() {
    let h = lenient(emerald(), along("W", &column(5, 4, 12, 18)));
    print("column (5, 4), layers 12-18", &h);
    assert!(h.report.conforms());
    assert!(h.report.cavities[0].outer_radii[0] > 5.0);
}
