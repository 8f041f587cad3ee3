//! The 3D hybrid along trajectories that bend: straight legs joined by
//! mitred knees, sampled curves split at the radial mesh's scale, chains
//! of legs that shrink to fit their knees.

mod common;

use common::hybrid3::{lenient, write};
use orthomesh::backend::compiled;
use orthomesh::reservoir::hybrid::Region;
use orthomesh::reservoir::hybrid3::{build, Hybrid3Options, Well3};
use orthomesh::reservoir::CornerPointGrid;

/// An L-shaped trajectory (down 30 m, then 90 m along x) through a
/// 15 x 7 x 7 box of 10 m cells: two straight legs, each with its radial
/// mesh, joined in a mitred knee; one well, linked along both.
#[test]
fn a_trajectory_that_bends_is_meshed_as_its_legs() {
    let g = CornerPointGrid::cartesian([15, 7, 7], [10.0, 10.0, 10.0]);
    let w = l_shaped(5.0);
    let h = lenient(&g, w.clone());
    write("bent", &h);
    let r = &h.report;
    println!(
        "an L-shaped well: {} cavity, outer radii {:?}, {} of {} transition sites inside, links \
         {:?}",
        r.cavities.len(),
        r.cavities[0].outer_radii,
        r.cavities[0].transition.certificate.sites_inside,
        r.cells[1],
        r.by_regions
    );
    assert!(r.conforms());
    assert_eq!(r.cavities.len(), 1);
    assert_eq!(r.cavities[0].wells, vec!["L".to_string()]);
    // (at 10 m, 109 of 538 transition sites outside: tried again at 8 m, 66)
    assert_eq!(r.cavities[0].outer_radii, vec![8.0, 8.0]);
    // one well, linked along its vertical leg and along its horizontal one
    assert_eq!(h.wellbore.len(), 1);
    let sites: Vec<[f64; 3]> = h.wellbore[0]
        .links
        .iter()
        .map(|&(c, _)| h.mesh.sites[c])
        .collect();
    assert!(sites
        .iter()
        .any(|p| (p[0] - 25.0).abs() < 5.0 && p[2] > -20.0));
    assert!(sites
        .iter()
        .any(|p| p[0] > 50.0 && (p[2] + 35.0).abs() < 5.0));
    // no gap at the knee: both legs' layers there reach the mitre (their
    // sites half of 2 r tan 45 + r / 4 from the knee's point, r = 8 m)
    let knee = [25.0, 35.0, -35.0];
    let nearest = sites
        .iter()
        .map(|p| (0..3).map(|k| (p[k] - knee[k]).powi(2)).sum::<f64>().sqrt())
        .fold(f64::INFINITY, f64::min);
    assert!((9.0..9.01).contains(&nearest), "{nearest}");
    // the layers at the knee mirror each other across it: each ring cell
    // of one linked to its image, orthogonally; only the far plugs' links
    // are not
    let mirror = |p: [f64; 3]| [knee[0] + p[2] - knee[2], p[1], knee[2] + p[0] - knee[0]];
    let well = |c: usize| h.region[c] == Region::Well;
    let across = h
        .mesh
        .links
        .iter()
        .filter(|l| l.cells.iter().all(|&c| well(c)))
        .filter(|l| {
            let [a, b] = l.cells.map(|c| h.mesh.sites[c]);
            (0..3).all(|k| (mirror(a)[k] - b[k]).abs() < 1e-9)
        })
        .count();
    let opts = Hybrid3Options::default();
    assert_eq!(across, opts.rings * opts.sectors);
    let ww = &r.by_regions["well-well"];
    assert_eq!(ww.non_orthogonal, 2 * opts.rings * opts.sectors);
    // a bend too sharp, a leg too short: errors naming the well
    let b = &compiled()[0];
    for (path, says) in [
        (
            vec![[25.0, 35.0, 5.0], [65.0, 35.0, 35.0], [25.0, 35.0, 45.0]],
            "its path turns by",
        ),
        (
            vec![[25.0, 35.0, 33.0], [25.0, 35.0, 35.0], [115.0, 35.0, 35.0]],
            "its leg from point 1 to 2 is 2.000 long, too short",
        ),
    ] {
        // (a 2 m leg's knee fits a radial mesh of 0.8 m: not around a
        // wellbore of 0.5 m)
        let bad = Well3 {
            path: Some(path),
            radius: 0.5,
            ..w.clone()
        };
        let e = build(&**b, &g, &[bad], &Hybrid3Options::default())
            .unwrap_err()
            .to_string();
        assert!(e.contains("well L: ") && e.contains(says), "{e}");
    }
}

/// A build section as trajectory files give it: down 10 m, a quarter
/// circle of 45 m radius, then along x, a point every 5 m (30 points).
/// Its legs are a few at the radial mesh's scale (each point within a
/// tenth of its outer radius of its leg's line), not one per point, each
/// too short for its knees, and their knees are mitred.
#[test]
fn a_sampled_build_section_is_meshed_as_a_few_legs() {
    let g = CornerPointGrid::cartesian([15, 7, 7], [10.0, 10.0, 10.0]);
    let r = 45.0;
    let arc = (1..=14).map(|k| {
        let a = k as f64 / 14.0 * std::f64::consts::FRAC_PI_2;
        [25.0 + r * (1.0 - a.cos()), 35.0, 15.0 + r * a.sin()]
    });
    let along = (1..=13).map(|k| [70.0 + 5.0 * k as f64, 35.0, 60.0]);
    let path: Vec<[f64; 3]> = [[25.0, 35.0, 5.0], [25.0, 35.0, 10.0], [25.0, 35.0, 15.0]]
        .into_iter()
        .chain(arc)
        .chain(along)
        .collect();
    let w = Well3 {
        name: "B".into(),
        radius: 0.1,
        path: Some(path),
        ..Default::default()
    };
    let h = lenient(&g, w);
    let r = &h.report;
    let legs = r.cavities[0].outer_radii.len();
    println!(
        "a build section of 30 points: {legs} legs, {} of {} transition sites inside",
        r.cavities[0].transition.certificate.sites_inside, r.cells[1]
    );
    assert!(r.conforms());
    assert_eq!((r.cavities.len(), h.wellbore.len()), (1, 1));
    assert!((3..=8).contains(&legs), "{legs} legs");
    // one radius along the chain of knees, each knee's links orthogonal:
    // only the plugs' at the two far ends are not (their wedges' sites
    // moved onto the normals through the transition's across the caps)
    let radii = &r.cavities[0].outer_radii;
    assert!(radii.iter().all(|&x| x == radii[0]));
    // (the wedges' links to their rings)
    let opts = Hybrid3Options::default();
    let skew = r.by_regions["well-well"].non_orthogonal;
    assert_eq!(skew, 2 * opts.rings * opts.sectors);
}

/// A build section of 200 m radius sampled every 10 m in 100 m cells
/// (115 points): its legs at a tenth of the head cells' radius (100 m)
/// are too short for their knees, so the chain's radial meshes shrink
/// until they fit (54 m). Not written for the readers: vtk calls 2 of
/// its transition cells nonconvex, faces the weld bent by 1.8e-4 m
/// (docs/limitations.md).
#[test]
fn a_build_section_in_coarse_cells_shrinks_its_chain() {
    let g = CornerPointGrid::cartesian([12, 5, 6], [100.0, 100.0, 100.0]);
    let r = 200.0;
    let down = (2..=10).map(|k| [150.0, 250.0, 10.0 * k as f64]);
    let arc = (1..=31).map(|k| {
        let a = k as f64 / 31.0 * std::f64::consts::FRAC_PI_2;
        [150.0 + r * (1.0 - a.cos()), 250.0, 100.0 + r * a.sin()]
    });
    let along = (1..=75).map(|k| [350.0 + 10.0 * k as f64, 250.0, 300.0]);
    let w = Well3 {
        name: "B".into(),
        radius: 0.1,
        path: Some(down.chain(arc).chain(along).collect()),
        ..Default::default()
    };
    let h = lenient(&g, w);
    let r = &h.report;
    let radii = &r.cavities[0].outer_radii;
    println!(
        "a build section in 100 m cells: {} legs at {:.1} m, {} of {} transition sites inside",
        radii.len(),
        radii[0],
        r.cavities[0].transition.certificate.sites_inside,
        r.cells[1]
    );
    assert!(r.conforms());
    assert!(radii.len() >= 3 && radii.iter().all(|&x| x == radii[0]));
    assert!((30.0..80.0).contains(&radii[0]), "{radii:?}");
}

/// A leg too short for its knee at the head cell's radius: the radial
/// meshes shrink until the knee takes 0.9 of it (a 10 m leg, a 90 degree
/// turn: 0.9 x 10 / (2 tan 45 + 1/4) = 4 m).
#[test]
fn a_short_leg_shrinks_its_chain() {
    let g = CornerPointGrid::cartesian([15, 7, 7], [10.0, 10.0, 10.0]);
    let w = l_shaped(25.0);
    let h = lenient(&g, w);
    let r = &h.report;
    assert!(r.conforms());
    let radii = &r.cavities[0].outer_radii;
    assert_eq!(radii.len(), 2);
    assert!(radii.iter().all(|&x| (x - 4.0).abs() < 1e-9), "{radii:?}");
}

/// The L-shaped well of these tests in the 15 x 7 x 7 box of 10 m cells:
/// down from `top` to 35 m deep, then 90 m along x.
fn l_shaped(top: f64) -> Well3 {
    Well3 {
        name: "L".into(),
        radius: 0.1,
        path: Some(vec![
            [25.0, 35.0, top],
            [25.0, 35.0, 35.0],
            [115.0, 35.0, 35.0],
        ]),
        ..Default::default()
    }
}
