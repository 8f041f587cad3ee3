//! The exact certificate of a finished mesh (docs/method.md section 7), decided
//! on the power diagram of an exactly checked regular triangulation of the
//! sites (vertex identities exact, see diagram.rs), plus floating-point
//! checks on the mesh as written.

use crate::backend::Triangulation;
use crate::diagram::Diagram;
use crate::domain::Domain;
use crate::mesh::Mesh;
use crate::sites::Sites;
use rayon::prelude::*;
use serde::Serialize;

/// What the mesh proves about itself.
#[derive(Debug, Clone, Serialize, Default)]
pub struct Certificate {
    /// Every domain vertex of the complex is a mesh vertex (exact).
    pub vertices_are_mesh_vertices: bool,
    /// Every segment is exactly one edge of the cells beside it (exact).
    pub segments_are_single_edges: bool,
    /// Cells are power cells of the checked regular triangulation (convex,
    /// counter-clockwise) with at least three distinct vertices, interior
    /// edges are shared by exactly two cells with opposite orientation, the
    /// unshared edges are exactly the domain boundary, and no component of
    /// cells leaks across a segment: the cells tile the domain (exact;
    /// implies the areas add up).
    pub cells_tile_domain: bool,
    /// Every domain site strictly inside its own cell (exact).
    pub sites_inside_cells: bool,
    /// Sites not strictly inside their cells.
    pub sites_outside: usize,
    /// Edges of the site triangulation checked for regularity, and the
    /// predicates (over the whole run) that needed exact rationals.
    pub checked_edges: usize,
    /// Predicates the filters could not decide (decided in rationals).
    pub exact_evaluations: usize,
    /// Relative difference of the summed cell areas and the domain area, as written.
    pub area_relative_error: f64,
    /// Largest |cos| between an interior face and the segment joining its two sites, as written.
    pub max_orthogonality_defect: f64,
    /// Failures, named.
    pub problems: Vec<String>,
}

impl Certificate {
    /// Whether the mesh conforms (sites inside are checked separately).
    pub fn conforms(&self) -> bool {
        self.vertices_are_mesh_vertices && self.segments_are_single_edges && self.cells_tile_domain
    }
}

/// Checks the exact diagram against the domain, and the written mesh.
pub fn certify(
    dom: &Domain,
    sites: &Sites,
    rt: &Triangulation,
    diagram: &Diagram,
    outside: &[usize],
    mesh: &Mesh,
) -> Certificate {
    let cx = &dom.complex;
    let mut c = Certificate {
        sites_outside: outside.len(),
        sites_inside_cells: outside.is_empty(),
        checked_edges: diagram.checked_edges,
        exact_evaluations: sites
            .exact_evaluations
            .load(std::sync::atomic::Ordering::Relaxed),
        ..Default::default()
    };
    let mut vid: Vec<Option<u32>> = vec![None; cx.points.len()];
    for (id, v) in diagram.input_vertex.iter().enumerate() {
        if let Some(v) = v {
            vid[*v as usize] = Some(id as u32);
        }
    }

    // A mesh vertex is a corner of some domain cell.
    let mut corner = vec![false; diagram.points.len()];
    for s in (0..diagram.cells.len()).filter(|&s| diagram.in_domain[s]) {
        for &v in diagram.cells[s].iter().flatten() {
            corner[v as usize] = true;
        }
    }
    let missing: Vec<i64> = (0..cx.points.len())
        .filter(|&v| vid[v].is_none_or(|id| !corner[id as usize]))
        .map(|v| cx.vertex_ids[v])
        .collect();
    c.vertices_are_mesh_vertices = missing.is_empty();
    if !missing.is_empty() {
        c.problems
            .push(format!("vertices that are not mesh vertices: {missing:?}"));
    }

    let mut convex = true;
    for (s, cell) in diagram.cells.iter().enumerate() {
        let k = cell.as_ref().map_or(0, Vec::len);
        if diagram.in_domain[s] && k < 3 {
            convex = false;
            c.problems
                .push(format!("cell of site {s} has {k} vertices"));
        }
    }
    if diagram.leaking_components > 0 {
        convex = false;
        c.problems.push(format!(
            "{} components of cells leak across segments",
            diagram.leaking_components
        ));
    }

    // Segments: a single edge of each domain cell beside them.
    let pairs = sites.segment_pairs(cx.segments.len());
    let single = |k: usize| {
        let [i, j] = cx.segments[k];
        let (Some(a), Some(b)) = (vid[i as usize], vid[j as usize]) else {
            return false;
        };
        let beside: Vec<u32> = pairs[k]
            .iter()
            .copied()
            .filter(|&s| diagram.in_domain[s as usize])
            .collect();
        !beside.is_empty()
            && beside.iter().all(|&s| {
                let cell = diagram.cells[s as usize].as_ref().unwrap();
                let m = cell.len();
                (0..m).any(|e| {
                    let (x, y) = (cell[e], cell[(e + 1) % m]);
                    (x, y) == (a, b) || (x, y) == (b, a)
                })
            })
    };
    let bad_segments: Vec<i64> = (0..cx.segments.len())
        .into_par_iter()
        .filter(|&k| !single(k))
        .map(|k| cx.segment_ids[k])
        .collect();
    c.segments_are_single_edges = bad_segments.is_empty();
    if !bad_segments.is_empty() {
        c.problems.push(format!(
            "segments that are not single mesh edges: {bad_segments:?}"
        ));
    }

    // Tiling: the cells are those of a checked triangulation, so they fit
    // together; what remains is that the dual edges between domain and
    // other cells are exactly the domain boundary, each once. The cell of a
    // lies left of the dual edge from the vertex of the triangle across to
    // that of the triangle on the left of a -> b.
    // Both lists sorted (in parallel): equal when each boundary edge is
    // crossed exactly once and nothing else is.
    let edges = dom.boundary();
    let mut boundary: Vec<(u32, u32)> = edges
        .iter()
        .filter_map(|&(a, b)| Some((vid[a as usize]?, vid[b as usize]?)))
        .collect();
    boundary.par_sort_unstable();
    let distinct = boundary.windows(2).all(|w| w[0] != w[1]);
    let mut tiles = convex && distinct && boundary.len() == edges.len();
    // The dual edges between domain and other cells, found in parallel;
    // None for one on the hull (a domain cell there would be unbounded).
    let crossing: Option<Vec<(u32, u32)>> = rt
        .par_edge_triangles()
        .filter_map(|(a, b, t, u)| {
            let (ia, ib) = (diagram.in_domain[a as usize], diagram.in_domain[b as usize]);
            if ia == ib {
                return None;
            }
            let Some(u) = u else {
                return Some(None);
            };
            let (from, to) = (diagram.vertex_of[u as usize], diagram.vertex_of[t as usize]);
            // a dual edge of length zero: the cells touch at a point
            (from != to).then_some(Some(if ia { (from, to) } else { (to, from) }))
        })
        .collect();
    match crossing {
        Some(mut crossing) => {
            crossing.par_sort_unstable();
            tiles &= crossing == boundary;
        }
        None => tiles = false,
    }
    c.cells_tile_domain = tiles;
    if !tiles {
        c.problems
            .push("the domain cells do not tile the domain exactly".into());
    }

    // As written: areas and orthogonality in floating point.
    // (each cell's in parallel, summed in order: the same on any threads)
    let areas: Vec<f64> = mesh.cells.par_iter().map(|cell| mesh.area(cell)).collect();
    let area: f64 = areas.iter().sum();
    let dom_area = dom.area();
    c.area_relative_error = ((area - dom_area) / dom_area).abs();
    c.max_orthogonality_defect = mesh.orthogonality_defect();
    c
}
