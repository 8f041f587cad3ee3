//! Layered cavities (`hybrid3::layered`): SPE9's 26 wells on sections
//! across its dipping layers, and emerald's wells on layers that are not
//! planes. Prints what it measures.

mod common;

use common::hybrid3::write_as;
use orthomesh::backend::compiled;
use orthomesh::reservoir::hybrid3::{build, Hybrid3Options, Section, Well3};
use std::path::Path;

fn layered() -> Hybrid3Options {
    Hybrid3Options {
        allow_sites_outside: true,
        layered: Some(Section::default()),
        ..Default::default()
    }
}

/// Emerald with its hole (leaning pillars, throws, twisted tops).
fn emerald() -> orthomesh::reservoir::CornerPointGrid {
    orthomesh::io::eclipse::read_grid(Path::new("tests/data/grids/eme_small_w_hole.grdecl"))
        .unwrap()
}

/// Well W of radius 0.1 down column (i, j), in layers k (0-based; every
/// layer where None).
fn well_w([i, j]: [usize; 2], k: Option<[usize; 2]>) -> Well3 {
    Well3 {
        name: "W".into(),
        i,
        j,
        k,
        radius: 0.1,
        ..Default::default()
    }
}

/// SPE9's grid (dipping 10 degrees, layers 4 to 98 ft thick) with its
/// deck's 26 wells: every link inside the cavities orthogonal, every
/// transition site inside its cell, the cavities filled once.
#[test]
fn spe9_all_wells_on_layered_sections() {
    let data = Path::new("tests/data/grids");
    let g = orthomesh::io::eclipse::read_grid(&data.join("SPE9.GRDECL")).unwrap();
    let (ws, _) = orthomesh::io::eclipse::read_wells(&data.join("SPE9_CP.DATA")).unwrap();
    let wells: Vec<Well3> = ws.into_iter().map(|w| w.well3(0.25)).collect();
    // one backend per pass of the suite (CGAL, then pure alone)
    for b in compiled().into_iter().take(1) {
        let t = std::time::Instant::now();
        let h = build(&*b, &g, &wells, &layered()).unwrap();
        let r = &h.report;
        let secs = t.elapsed().as_secs_f64();
        println!(
            "SPE9, 26 wells, layered ({}): {secs:.1} s; cells {:?}; {} sections, dips {:?}, \
             corners off their planes by up to {:.1e} ft; {} transition sites outside; {} \
             slivers (smallest {:.1e} of its cavity's median)",
            b.name(),
            r.cells,
            r.sections.len(),
            r.sections.iter().map(|s| s.dip).collect::<Vec<_>>(),
            r.sections.iter().map(|s| s.off_plane).fold(0.0, f64::max),
            r.sites_outside,
            r.slivers,
            r.smallest_volume_share,
        );
        for (pair, c) in &r.by_regions {
            println!(
                "  {pair}: {} links, {} off orthogonal, {} orthogonal with the reservoir node \
                 mirrored ({:.1}% of the area), angle median {:.2} 99% {:.2} max {:.2}",
                c.connections,
                c.non_orthogonal,
                c.mirrored,
                100.0 * c.mirrored_area,
                c.angle[0],
                c.angle[1],
                c.angle[2]
            );
        }
        let gap = r
            .sections
            .iter()
            .flat_map(|s| s.cavities.iter().map(|c| c.volume_gap));
        let gap = gap.fold(0.0, f64::max);
        println!(
            "  cavities filled to {gap:.1e} of their grid cells' volume; {} faces unpaired",
            r.unpaired_faces
        );
        assert!(r.conforms() && r.cavities.is_empty() && r.unpaired_faces == 0);
        // the wellbores aside, filled once (SPE9's corners lie within 5e-5
        // ft of their planes)
        assert!(gap < 1e-7, "{gap}");
        assert_eq!(h.wellbore.len(), 26);
        assert!(h.wellbore.iter().all(|w| !w.links.is_empty()));
        // past the section's outline too (power bisectors out to the walls)
        for pair in ["transition-transition", "transition-well", "well-well"] {
            assert_eq!(r.by_regions[pair].non_orthogonal, 0, "{pair}");
        }
        // the sections' outlines moved in by the walls' lean (INJE1's
        // cavity: 6 layers, walls drifting 19 ft; else sites are cut off)
        assert_eq!(r.sites_outside, 0);
        // no connection whose sites lie on one side of its face
        assert!(r.by_regions.values().all(|c| c.one_sided == 0));
        // links to the reservoir crossing their faces, by area and by count
        // (radial meshes in their columns, the section at the cavity's end
        // over reservoir cells, each convex corner owned by one cell, the
        // column sides inside on their own lines at reflex corners, the
        // strips there filled by mirror cells, no layer beyond the
        // completions over reservoir cells: 97.3%, 99.7% of the area, and
        // every link to the radial cells; what is left:
        // docs/limitations.md)
        let rt = &r.by_regions["reservoir-transition"];
        assert!(rt.mirrored_area > 0.995, "{rt:?}");
        assert!(rt.mirrored as f64 > 0.97 * rt.connections as f64, "{rt:?}");
        let rw = &r.by_regions["reservoir-well"];
        assert_eq!(rw.mirrored, rw.connections, "{rw:?}");
        // every link between regions: those to the reservoir crossing their
        // faces, the others orthogonal (the 99%: 20,934 of 21,143)
        let tw = &r.by_regions["transition-well"];
        let all = rt.connections + rw.connections + tw.connections;
        let good = rt.mirrored + rw.mirrored + tw.connections - tw.non_orthogonal;
        let share = good as f64 / all as f64;
        println!(
            "  links between regions orthogonal or crossing their faces: {good} of {all} ({:.2}%)",
            100.0 * share
        );
        assert!(share >= 0.99, "{share}");
        assert!(h.mesh.volumes.iter().all(|&v| v > 0.0));
        // tests/readers.py validates each cell in its own frame (as for
        // emerald's twisted cells) and checks the volumes
        write_as(&format!("twisted3-spe9-layered-{}", b.name()), &h);
    }
}

/// Emerald's layers are not planes (tops up to 1.4 m off their planes
/// within a column, walls leaning 10 to 40 degrees): a well down one
/// column gets a layered cavity whose prisms are cut by the grid's own
/// faces. Every site inside, no sliver, the cavity filled once; links
/// within a layer orthogonal (across the twisted layer boundaries, the
/// twist). Beside a throw, its own column, its walls cut where the cells
/// across meet them; a completion that changes column, a radial mesh in
/// each column.
#[test]
fn emerald_wells_on_twisted_layers() {
    let g = emerald();
    // 1-based column, layers (1-based), what it is
    let cases: [([usize; 2], Option<[usize; 2]>, &str); 13] = [
        ([19, 18], Some([5, 8]), "leaning column, layers 5-8"),
        ([1, 20], Some([5, 8]), "at the grid's edge, layers 5-8"),
        ([19, 18], None, "leaning column, every layer"),
        ([5, 4], None, "beside a throw, every layer"),
        ([2, 30], None, "twisted by 1.4 m, every layer"),
        (
            [8, 4],
            Some([5, 8]),
            "beside the hole, its walls on a throw",
        ),
        // sections whose sides are split near the well: unsplit, system 3
        // was infeasible at every radius (the 3D transition then: 333 of
        // its sites outside; (7, 4)'s whole fault block: 12 outside)
        (
            [21, 37],
            Some([5, 8]),
            "in the grid's last column, layers 5-8",
        ),
        (
            [7, 4],
            Some([5, 8]),
            "across the throw from (8, 4), layers 5-8",
        ),
        // its bottom in layer 7 cut where the cells across a 17 m throw
        // meet it: cut in ears across the column's diagonal, a piece faced
        // into the cell (refused, the 3D transition took over 5 minutes)
        (
            [14, 41],
            Some([5, 8]),
            "beside a throw to a column 7 layers deeper, layers 5-8",
        ),
        // its section nearly a triangle (one corner a straight angle in
        // the layers' frame; the 3D transition: 457 of 602 sites outside,
        // 54 s)
        (
            [21, 36],
            Some([5, 8]),
            "a section nearly a triangle, layers 5-8",
        ),
        // its section's long sides split by points that round a hair
        // inward: slivers beyond the hull once put sites outside beyond
        // doubles (the 3D transition: 556 of 773 sites outside, 76 s)
        (
            [8, 3],
            Some([5, 8]),
            "split sides rounding inward, layers 5-8",
        ),
        // completed in layers 5-8 of which 5-7 are inactive: the cavity
        // ends at them (it once took one layer beyond and fell to the 3D
        // transition: 160 of 286 sites outside)
        ([4, 9], Some([5, 8]), "below inactive cells, layers 5-8"),
        // nearly a triangle, the well 9 m from its long side: with pieces
        // as long as their distance to the well, system 3 was infeasible
        // at every radius (grown to 19 columns: 18 sites outside, 36
        // links to the well 18.6 degrees off, 12 one-sided)
        (
            [12, 39],
            Some([5, 8]),
            "the well near a long side, layers 5-8",
        ),
    ];
    let b = &*compiled()[0];
    let mut wells: Vec<(Well3, String, &str)> = cases
        .into_iter()
        .map(|([i, j], k, what)| {
            let w = well_w([i - 1, j - 1], k.map(|k| k.map(|x| x - 1)));
            let layers = k.map_or("all".to_string(), |[a, z]| format!("{a}-{z}"));
            (w, format!("{i}-{j}-{layers}"), what)
        })
        .collect();
    // a completion in (19, 18) layer 5, then (20, 18) layer 6: a radial
    // mesh in each column, one well
    wells.push((
        Well3 {
            name: "W".into(),
            i: 18,
            j: 17,
            radius: 0.1,
            cells: vec![[18, 17, 4], [19, 17, 5]],
            ..Default::default()
        },
        "19-18-then-20-18".into(),
        "completion changing column",
    ));
    for (w, file, what) in wells {
        let t = std::time::Instant::now();
        let h = build(b, &g, &[w], &layered()).unwrap();
        let r = &h.report;
        let s = &r.sections[..];
        println!(
            "emerald {file}, {what}: {:.1} s; notes {:?}; cells {:?}; layers {:.2} m off \
             their planes; {} sites outside; {} slivers ({} merged); cavity filled to {:.1e}",
            t.elapsed().as_secs_f64(),
            r.notes,
            r.cells,
            s.first().map_or(f64::NAN, |s| s.off_plane),
            r.sites_outside,
            r.slivers,
            r.slivers_merged,
            s.iter()
                .flat_map(|s| s.cavities.iter().map(|c| c.volume_gap))
                .fold(0.0, f64::max),
        );
        for (pair, c) in &r.by_regions {
            println!(
                "  {pair}: {} links, {} off orthogonal, angle median {:.2} 99% {:.2} max {:.2}, \
                 {} one-sided, {} crossing their faces ({:.1}% of the area)",
                c.connections,
                c.non_orthogonal,
                c.angle[0],
                c.angle[1],
                c.angle[2],
                c.one_sided,
                c.mirrored,
                100.0 * c.mirrored_area
            );
        }
        assert_eq!(s.len(), 1, "{what}: {:?}", r.notes);
        assert!(r.conforms() && r.unpaired_faces == 0, "{what}");
        assert!(s[0].off_plane > 1e-3, "{what}: twisted");
        // filled once, to the points welded within 2 mm (`Frame::weld`):
        // the depths' own millimetres over 20,000 m2 tops are 20 m3 a cell
        assert!(s[0].cavities.iter().all(|c| c.volume_gap < 1e-5), "{what}");
        assert_eq!(r.sites_outside, 0, "{what}");
        assert_eq!(r.slivers, 0, "{what}");
        assert!(h.mesh.volumes.iter().all(|&v| v > 0.0), "{what}");
        for pair in ["transition-transition", "transition-well", "well-well"] {
            assert_eq!(r.by_regions[pair].one_sided, 0, "{what}: {pair}");
        }
        // a median link within the layers is orthogonal, and every link to
        // the well (the section's, in its own columns where it can be)
        assert!(r.by_regions["well-well"].angle[0] < 1e-6, "{what}");
        assert_eq!(r.by_regions["transition-well"].non_orthogonal, 0, "{what}");
        // one well, linked to its wellbore in each completed cell
        assert_eq!(h.wellbore.len(), 1);
        assert!(!h.wellbore[0].links.is_empty());
        write_as(&format!("twisted3-emerald-layered-{file}"), &h);
    }
}

/// A sweep of emerald's live columns of every other row, a well in layers
/// 5-8 of each (about two minutes; `cargo test --release --test layered3
/// -- --ignored`): every one layered, no transition site outside, and the
/// links to the wells and to the reservoir counted.
#[test]
#[ignore]
fn emerald_sweep() {
    let g = emerald();
    let b = &*compiled()[0];
    let (mut wells, mut sites, mut outside, mut slowest) = (0, 0, 0, 0.0f64);
    let sum = |h: &orthomesh::reservoir::hybrid3::Hybrid3, pair: &str, acc: &mut [usize; 3]| {
        let c = &h.report.by_regions[pair];
        acc[0] += c.connections;
        acc[1] += c.non_orthogonal;
        acc[2] += c.mirrored;
    };
    let [mut tw, mut rt, mut rw] = [[0; 3]; 3];
    for i in 0..g.nx {
        for j in (0..g.ny).step_by(2) {
            if (4..8).all(|k| !g.active(i, j, k)) {
                continue;
            }
            let w = well_w([i, j], Some([4, 7]));
            let t = std::time::Instant::now();
            // columns whose cells there are all pinched are refused
            let h = match build(b, &g, &[w], &layered()) {
                Ok(h) => h,
                Err(e) if e.to_string().contains("no active cell with thickness") => continue,
                Err(e) => panic!("({}, {}): {e}", i + 1, j + 1),
            };
            slowest = slowest.max(t.elapsed().as_secs_f64());
            let r = &h.report;
            assert_eq!(r.sections.len(), 1, "({}, {}): {:?}", i + 1, j + 1, r.notes);
            wells += 1;
            sites += r.cells[1];
            outside += r.sites_outside;
            sum(&h, "transition-well", &mut tw);
            sum(&h, "reservoir-transition", &mut rt);
            sum(&h, "reservoir-well", &mut rw);
        }
    }
    println!(
        "emerald sweep ({}): {wells} wells layered, slowest {slowest:.1} s; {outside} of {sites} \
         transition sites outside; links to the wells {} of {} off orthogonal; crossing their \
         faces: reservoir-transition {} of {}, reservoir-well {} of {}",
        b.name(),
        tw[1],
        tw[0],
        rt[2],
        rt[0],
        rw[2],
        rw[0]
    );
    assert!(wells > 200);
    assert_eq!(outside, 0);
}
