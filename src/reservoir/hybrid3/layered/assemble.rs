//! The 3D hybrid from layered cavities: the reservoir cells outside them
//! (as `assembly` has them), the cavities' cells and links, and each
//! well's links to its innermost ring in its completed layers.

use super::super::assembly::Assembly;
use super::super::cpg::{Cpg, Ijk};
use super::super::path::Path;
use super::super::report::{Hybrid3, Hybrid3Report, LayeredCavity, SectionReport};
use super::super::well::Well3;
use super::{Across, Cavity, Group};
use crate::error::Result;
use crate::geom::{dist_f, volume, Plane};
use crate::reservoir::deck::WellLinks;
use crate::reservoir::hybrid::Region;
use std::collections::{BTreeSet, HashMap};
use std::f64::consts::TAU;

/// The 3D hybrid of layered cavities, with its report.
pub(crate) fn assemble(
    cpg: &Cpg,
    wells: &[Well3],
    paths: &[Path],
    groups: Vec<Group>,
) -> Result<Hybrid3> {
    let in_cavity: BTreeSet<Ijk> = groups
        .iter()
        .flat_map(|g| g.cavities.iter())
        .flat_map(|(c, _, _)| {
            c.cols
                .iter()
                .flat_map(move |&[i, j]| (c.k[0]..=c.k[1]).map(move |k| [i, j, k]))
        })
        .collect();
    let mut a = Assembly::default();
    a.reservoir(cpg, &|c| in_cavity.contains(&c));
    let [unmatched, thrown] = a.reservoir_links(cpg)?;
    let first_t = a.out.cells.len();
    let mut wellbore: Vec<Option<WellLinks>> = vec![None; wells.len()];
    let (mut host, mut cavity_of): (Vec<Ijk>, Vec<usize>) = (vec![], vec![]);
    let mut sections = vec![];
    // faces toward a grid cell that is in a cavity: they have no cell
    // across (0: sections keep their cavities apart)
    let mut unpaired = 0;
    // per cavity, its grid cells' volume and its grid cells (cavities
    // numbered from 1)
    let mut grid_volumes = vec![];
    let mut cavity_cells: Vec<Vec<Ijk>> = vec![];
    for g in &groups {
        let mut weld = Weld::new(
            &a.out.points,
            g.frame.twisted.then_some(g.frame.size * SCATTER),
        );
        let mut id: HashMap<(usize, usize), usize> = HashMap::new();
        let mut span: HashMap<(usize, usize), f64> = HashMap::new();
        let mut reports = vec![];
        for (cav, cut, cells) in &g.cavities {
            let at = |p: u32| g.frame.from(cut.points[p as usize]);
            let cells: Vec<_> = cells.iter().filter(|c| !c.faces.is_empty()).collect();
            let grid_cells: Vec<Ijk> = cav
                .cols
                .iter()
                .flat_map(|&[i, j]| (cav.k[0]..=cav.k[1]).map(move |k| [i, j, k]))
                .collect();
            let mut fixed: Vec<Vec<Vec<u32>>> = vec![];
            for cell in &cells {
                let faces = weld.faces(&mut a, &cell.faces, &at, g.frame.weld());
                fixed.push(faces.clone());
                let faces = faces.into_iter().filter(|f| f.len() >= 3).collect();
                let site = g.frame.from(cell.site);
                id.insert((cell.c, cell.k), a.out.cells.len());
                span.insert((cell.c, cell.k), cell.span);
                // reflex corners' mirror cells are past the section's
                let region = g.section.region.get(cell.c).copied();
                a.push_cell(faces, site, region.unwrap_or(Region::Transition), None);
                *a.out.site_inside.last_mut().expect("a cell") = cell.inside;
                host.push(host_of(cpg, site, &grid_cells));
                cavity_of.push(grid_volumes.len() + 1);
            }
            for (cell, faces) in cells.iter().zip(&fixed) {
                let me = id[&(cell.c, cell.k)];
                for ((across, _), face) in cell.faces.iter().zip(faces) {
                    let other = match across {
                        Across::Cell(d, k) => id.get(&(*d, *k)).copied().filter(|&o| o > me),
                        Across::Grid(Some(c)) => {
                            unpaired += usize::from(in_cavity.contains(c));
                            a.res_cell.get(c).copied()
                        }
                        _ => None,
                    };
                    if let Some(o) = other.filter(|_| face.len() >= 3) {
                        let face = face.clone();
                        let xyz: Vec<[f64; 3]> =
                            face.iter().map(|&v| a.out.points[v as usize]).collect();
                        a.link(me, o, face, Plane::of(&xyz));
                    }
                }
            }
            reports.push(LayeredCavity {
                columns: cav.cols.len(),
                layers: [cav.k[0] + 1, cav.k[1] + 1],
                cells: cells.len(),
                sites_inside: cells.iter().filter(|c| c.inside).count(),
                volume_gap: 0.0,
            });
            let fill = to_fill(cpg, g, cav, &grid_cells, hole_height(g, &cells));
            grid_volumes.push(fill);
            cavity_cells.push(grid_cells);
        }
        for (n, &w) in g.wells.iter().enumerate() {
            wellbore[w] = Some(wellbore_links(g, n, &wells[w].name, &paths[w], &id, &span));
        }
        let n = g.frame.n;
        sections.push(SectionReport {
            wells: g.wells.iter().map(|&w| wells[w].name.clone()).collect(),
            normal: n,
            dip: n[2].clamp(-1.0, 1.0).acos().to_degrees(),
            off_plane: g.frame.off,
            cavities: reports,
            transition: g.section.report.transition.clone(),
        });
    }
    let (mut out, mut region, mut ijk) = a.finish();
    volume_gaps(
        &mut sections,
        &grid_volumes,
        &out.volumes[first_t..],
        &cavity_of,
    );
    let mut host: Vec<Ijk> = ijk
        .iter()
        .take(first_t)
        .map(|c| c.unwrap_or([0; 3]))
        .chain(host)
        .collect();
    // slivers (tiny cells of the section through every layer) joined to
    // their neighbour in the same grid cell
    let mut wellbore: Vec<WellLinks> = wellbore.into_iter().flatten().collect();
    let locate = |p: [f64; 3], cav: usize| cpg.locate(p, cavity_cells[cav - 1].iter().copied());
    let (slivers_merged, merged) = super::super::slivers::merge(super::super::slivers::Cells {
        locate: &locate,
        clear: &|c| clear(cpg, c),
        mesh: &mut out,
        region: &mut region,
        ijk: &mut ijk,
        host: &mut host,
        cavity_of: &mut cavity_of,
        first: first_t,
        wellbore: &mut wellbore,
    });
    let h = Hybrid3 {
        mesh: out,
        region,
        ijk,
        host,
        wellbore,
        merged,
        report: Hybrid3Report {
            unpaired_faces: unpaired,
            unmatched_faces: unmatched,
            across_throws: thrown,
            sections,
            slivers_merged,
            ..Default::default()
        },
    };
    Ok(measured(h, first_t, &cavity_of))
}

/// The hybrid with its report's measures: cells, links per pair of
/// regions, sites outside and slivers (per cell from `first_t`, its
/// cavity).
fn measured(mut h: Hybrid3, first_t: usize, cavity_of: &[usize]) -> Hybrid3 {
    let (out, region) = (&h.mesh, &h.region);
    let by_regions = super::super::stats::by_regions(out, region);
    let t_cells: Vec<usize> = (first_t..region.len())
        .filter(|&c| region[c] == Region::Transition)
        .collect();
    let (slivers, smallest_volume_share) = super::super::stats::slivers(
        &t_cells.iter().map(|&c| out.volumes[c]).collect::<Vec<_>>(),
        &t_cells
            .iter()
            .map(|&c| cavity_of[c - first_t])
            .collect::<Vec<_>>(),
    );
    let count = |r: Region| region.iter().filter(|&&x| x == r).count();
    let r = &mut h.report;
    r.cells = [
        count(Region::Reservoir),
        count(Region::Transition),
        count(Region::Well),
    ];
    r.connections = out.links.len();
    r.non_orthogonal = by_regions.values().map(|c| c.non_orthogonal).sum();
    r.by_regions = by_regions;
    r.sites_outside = t_cells.iter().filter(|&&c| !out.site_inside[c]).count();
    r.slivers = slivers;
    r.smallest_volume_share = smallest_volume_share;
    h
}

/// Well n of a section's links to its innermost ring in its completed
/// layers: radial flow from the wellbore to the sites' radius within a
/// sector, theta L / ln(rho / r_w), L the cell's length along the
/// normal (the radial mesh's axis).
fn wellbore_links(
    g: &Group,
    n: usize,
    name: &str,
    path: &Path,
    id: &HashMap<(usize, usize), usize>,
    span: &HashMap<(usize, usize), f64>,
) -> WellLinks {
    let wm = &g.section.wells[n];
    let theta = TAU / wm.inner.len() as f64;
    let log = (wm.site_radius / wm.radius).ln();
    let layers: BTreeSet<usize> = path.cells.iter().map(|c| c[2]).collect();
    let mut links = vec![];
    for &k in &layers {
        for &c in &wm.inner {
            if let Some(&cell) = id.get(&(c as usize, k)) {
                links.push((cell, theta * span[&(c as usize, k)] / log));
            }
        }
    }
    WellLinks {
        name: name.to_string(),
        radius: wm.radius,
        links,
        log,
    }
}

/// How far apart, of the block's size, points of a twisted cavity are
/// taken as one: where many nearly parallel planes meet at a pillar, their
/// cut points scatter by up to 5e-7 of it (emerald (8, 4): 7e-5 m in a
/// 150 m column), and vtk sees edges that cross.
const SCATTER: f64 = 1e-6;

/// Points of twisted cavities within `SCATTER` of one another taken as
/// one.
struct Weld {
    tol: Option<f64>,
    near: HashMap<[i64; 3], Vec<u32>>,
}

impl Weld {
    fn new(points: &[[f64; 3]], tol: Option<f64>) -> Weld {
        let mut w = Weld {
            tol,
            near: HashMap::new(),
        };
        if let Some(t) = tol {
            for (n, p) in points.iter().enumerate() {
                w.near.entry(key(*p, t)).or_default().push(n as u32);
            }
        }
        w
    }

    fn point(&mut self, a: &mut Assembly, p: [f64; 3]) -> u32 {
        let Some(t) = self.tol else {
            return a.point(p);
        };
        let k = key(p, t);
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    let c = [k[0] + dx, k[1] + dy, k[2] + dz];
                    let hit = self.near.get(&c).and_then(|v| {
                        v.iter()
                            .copied()
                            .find(|&q| dist_f(a.out.points[q as usize], p) <= t)
                    });
                    if let Some(q) = hit {
                        return q;
                    }
                }
            }
        }
        let n = a.point(p);
        self.near.entry(k).or_default().push(n);
        n
    }

    /// A cell's faces as points of the assembly, with the points of other
    /// faces on their edges put in.
    fn faces(
        &mut self,
        a: &mut Assembly,
        faces: &[(Across, Vec<u32>)],
        at: &dyn Fn(u32) -> [f64; 3],
        tol: f64,
    ) -> Vec<Vec<u32>> {
        let faces = faces
            .iter()
            .map(|(_, pts)| clean(pts.iter().map(|&p| self.point(a, at(p))).collect()))
            .collect();
        super::join::on_edges(faces, &a.out.points, tol)
    }
}

fn key(p: [f64; 3], t: f64) -> [i64; 3] {
    p.map(|x| (x / t).floor() as i64)
}

/// A face without repeated points in a row (two cut points that the data's
/// rounding puts at one place).
fn clean(mut f: Vec<u32>) -> Vec<u32> {
    f.dedup();
    while f.len() > 1 && f.first() == f.last() {
        f.pop();
    }
    f
}

/// The grid cell of the cavity that holds a site, or else the nearest by
/// its centre (a site outside its cell).
fn host_of(cpg: &Cpg, site: [f64; 3], grid_cells: &[Ijk]) -> Ijk {
    cpg.locate(site, grid_cells.iter().copied())
        .unwrap_or_else(|| {
            let d = |c: &Ijk| dist_f(cpg.centre(*c), site);
            grid_cells
                .iter()
                .copied()
                .min_by(|x, y| d(x).total_cmp(&d(y)))
                .unwrap_or([0; 3])
        })
}

/// A layered cavity whose cells and grid cells differ in volume by more
/// than this share of theirs is not kept: its cells overlap or leave a
/// hole (emerald (14, 41), beside a throw to a column whose top lies
/// layers below: 3e-2; kept ones measure up to 4e-9).
const FILLED: f64 = 1e-6;

/// Whether a cavity's volume gap is small enough to keep it (not NaN).
fn fills(gap: f64) -> bool {
    gap <= FILLED
}

/// Why a layered mesh cannot be kept: a cavity whose cells do not fill
/// its grid cells once, with its wells.
pub(crate) fn unfilled(h: &Hybrid3) -> Option<String> {
    h.report.sections.iter().find_map(|s| {
        let gap = s
            .cavities
            .iter()
            .map(|c| c.volume_gap)
            .find(|&g| !fills(g))?;
        Some(format!(
            "the layered cavity of wells {} fills its grid cells to only {gap:.1e} of their \
             volume (its cells overlap or leave a hole)",
            s.wells.join(", ")
        ))
    })
}

/// Each cavity's cells' volumes (per cavity cell, its volume and cavity,
/// numbered from 1) against its grid cells' volume.
fn volume_gaps(sections: &mut [SectionReport], grid: &[f64], volumes: &[f64], cavity_of: &[usize]) {
    let mut filled = vec![0.0; grid.len() + 1];
    for (v, &c) in volumes.iter().zip(cavity_of) {
        filled[c] += v;
    }
    let cavities = sections.iter_mut().flat_map(|s| s.cavities.iter_mut());
    for (n, cav) in cavities.enumerate() {
        cav.volume_gap = (filled[n + 1] - grid[n]).abs() / grid[n];
    }
}

/// The height of the wellbores through a cavity: its layers' planes' span,
/// or where they are twisted, the lengths of a radial cell's layers.
fn hole_height(g: &Group, cells: &[&super::Cell]) -> f64 {
    let h = &g.frame.h;
    if !g.frame.twisted {
        return (h[h.len() - 1] - h[0]).abs();
    }
    let Some(c) = cells
        .iter()
        .find(|c| g.section.region.get(c.c) == Some(&Region::Well))
        .map(|c| c.c)
    else {
        return 0.0;
    };
    cells.iter().filter(|x| x.c == c).map(|x| x.span).sum()
}

/// The volume a cavity's cells should fill: its grid cells' less its
/// wellbores (the holes its radial cells leave, prisms through all its
/// layers: their polygons' area in the section, from the radial cells'
/// edges with no cell across taken backwards, times their height).
fn to_fill(cpg: &Cpg, g: &Group, cav: &Cavity, grid_cells: &[Ijk], height: f64) -> f64 {
    let grid: f64 = grid_cells.iter().map(|&c| grid_volume(cpg, c)).sum();
    let (m, owner) = (&g.section.mesh, &g.shared.owner);
    let mut area = 0.0;
    for &c in cav
        .cells
        .iter()
        .filter(|&&c| g.section.region[c] == Region::Well)
    {
        let poly = &m.cells[c];
        for k in 0..poly.len() {
            let (p, q) = (poly[k], poly[(k + 1) % poly.len()]);
            if !owner.contains_key(&(q, p)) {
                let (a, b) = (m.points[p as usize], m.points[q as usize]);
                area -= 0.5 * (a[0] * b[1] - a[1] * b[0]);
            }
        }
    }
    grid - area * height
}

/// A grid cell's volume: its faces' pieces as the cavity's cells are cut
/// by them (twisted ones as two triangles, or where cells across a throw
/// meet them, on its sheet).
fn grid_volume(cpg: &Cpg, c: Ijk) -> f64 {
    let mut points = vec![];
    let mut faces = vec![];
    for f in 0..6 {
        let pieces: Vec<Vec<[f64; 3]>> = match cpg.parts(c, f) {
            Ok(parts) => parts.into_iter().map(|p| p.points).collect(),
            Err(_) => {
                let (q, pieces) = cpg.face_pieces(c, f);
                pieces
                    .iter()
                    .map(|p| p.iter().map(|&k| q[k]).collect())
                    .collect()
            }
        };
        for piece in pieces {
            let at = points.len() as u32;
            faces.push((at..at + piece.len() as u32).collect());
            points.extend(piece);
        }
    }
    volume(&faces, &points)
}

#[cfg(test)]
mod tests {
    use super::fills;

    #[test]
    fn cavities_not_filled_once_are_not_kept() {
        // SPE9's and emerald's kept cavities, emerald (14, 41)'s overlap,
        // and a gap that could not be measured
        assert!(fills(9e-12) && fills(4.2e-9));
        assert!(!fills(3e-2));
        assert!(!fills(f64::NAN));
    }
}

/// Whether a grid cell's side faces are clear of faults and throws.
fn clear(cpg: &Cpg, c: Ijk) -> bool {
    let [i, j, _] = c;
    (0..4).all(|f| !cpg.on_fault(c, f) && !cpg.is_thrown([i, j], f))
}
