//! The transition's complex in a cavity: its sides (facing reservoir
//! cells, another cavity's cells or nothing), the grid's flat top or
//! bottom merged into one facet with open wells' outlines as windows, each
//! well's outer surface and its plugs' triangles; and its certified mesh.

use super::cavity::Side;
use super::cpg::Ijk;
use super::radial::{End, Radial};
use super::refine;
use super::well::Hybrid3Options;
use crate::backend::Backend;
use crate::complex::{Complex3, Facet};
use crate::conform::{conform3, Outcome, D3};
use crate::error::{Error, Result};
use crate::geom::cross_f;
use crate::options::Options;
use std::collections::HashMap;

/// What lies across a facet of the transition's complex.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Across {
    /// A grid cell: a reservoir cell, or another cavity's.
    Cell(Ijk),
    /// Nothing: the grid's boundary, inactive cells.
    Outside,
    /// Well `w` (of the cavity's), its cell (layer, ring, sector).
    Well(usize, [usize; 3]),
    /// The transition itself: a fault inside the cavity.
    Inner,
}

/// The transition's constraints and what each facet faces.
pub(super) struct Transition {
    pub(super) cx: Complex3,
    pub(super) across: Vec<Across>,
    /// The facets on the grid's flat top and bottom (cut at when asked).
    pub(super) open: Vec<u32>,
}

/// Points shared by exact coordinates.
#[derive(Default)]
struct Points {
    cx: Complex3,
    ids: HashMap<[u64; 3], u32>,
}

impl Points {
    fn id(&mut self, p: [f64; 3]) -> u32 {
        let cx = &mut self.cx;
        *self.ids.entry(p.map(f64::to_bits)).or_insert_with(|| {
            cx.points.push(p);
            cx.vertex_ids.push(cx.points.len() as i64);
            cx.points.len() as u32 - 1
        })
    }
}

/// The boundary loops of a union of pieces (edges without their reverse),
/// in an order that does not depend on hashing (reproducible outputs).
fn loops(pieces: &[Vec<u32>]) -> Vec<Vec<u32>> {
    let mut edges: std::collections::BTreeMap<u32, Vec<u32>> = Default::default();
    let all: std::collections::BTreeSet<(u32, u32)> = pieces
        .iter()
        .flat_map(|p| (0..p.len()).map(move |k| (p[k], p[(k + 1) % p.len()])))
        .collect();
    for &(a, b) in &all {
        if !all.contains(&(b, a)) {
            edges.entry(a).or_default().push(b);
        }
    }
    let starts: Vec<u32> = edges.keys().copied().collect();
    let mut out = vec![];
    for s in starts {
        while let Some(b) = edges.get_mut(&s).and_then(Vec::pop) {
            let mut cycle = vec![s];
            let mut at = b;
            while at != s {
                cycle.push(at);
                match edges.get_mut(&at).and_then(Vec::pop) {
                    Some(n) => at = n,
                    None => break,
                }
            }
            out.push(cycle);
        }
    }
    out
}

/// Whether (x, y) is inside a polygon's projection (even-odd rule).
fn inside_xy(poly: &[[f64; 3]], p: [f64; 3]) -> bool {
    let mut inside = false;
    for k in 0..poly.len() {
        let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
        if (a[1] > p[1]) != (b[1] > p[1]) {
            let x = a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
            if p[0] < x {
                inside = !inside;
            }
        }
    }
    inside
}

impl Transition {
    /// The complex of a cavity's sides and wells; with `cut`, faults
    /// inside it and sides facing nothing near a well cut to about the
    /// wells' outer radius (`refine`).
    pub(super) fn new<B: Backend + ?Sized>(
        backend: &B,
        sides: &[Side],
        wells: &[Radial],
        cut: bool,
    ) -> Result<Transition> {
        let mut pts = Points::default();
        let mut across = vec![];
        let mut facet =
            |pts: &mut Points, polygons: Vec<Vec<u32>>, holes: Vec<[f64; 3]>, a: Across| {
                pts.cx.facets.push(Facet {
                    polygons,
                    holes,
                    marker: 1 + matches!(a, Across::Well(..)) as i64,
                });
                across.push(a);
            };
        let h = wells.iter().map(|w| w.outer).fold(f64::INFINITY, f64::min);
        let near = |poly: &[[f64; 3]]| wells.iter().any(|w| w.reaches(poly));
        let (cuts, whole) = match cut {
            true => refine::faults(backend, sides, h, &near)?,
            false => refine::faults(backend, sides, h, &|_| false)?,
        };
        for (s, cut) in sides.iter().zip(cuts).filter(|(s, _)| s.open.is_none()) {
            let across = match (s.inner, s.across) {
                (true, _) => Across::Inner,
                (false, Some(c)) => Across::Cell(c),
                (false, None) => Across::Outside,
            };
            match cut {
                Some(triangles) => {
                    for t in triangles {
                        let ids = t.iter().map(|&p| pts.id(p)).collect();
                        facet(&mut pts, vec![ids], vec![], across);
                    }
                }
                None => {
                    let ids = s.points.iter().map(|&p| pts.id(p)).collect();
                    facet(&mut pts, vec![ids], vec![], across);
                }
            }
        }
        // The grid's flat top and bottom: one facet per loop, with the
        // outlines of the wells open there as windows.
        let mut open = vec![];
        for (f, level) in [(4usize, 0usize), (5, usize::MAX)] {
            // numbered apart first: the points inside the loops are no
            // vertices of the complex
            let mut local = Points::default();
            let pieces: Vec<Vec<u32>> = sides
                .iter()
                .filter(|s| s.open == Some(f))
                .map(|s| s.points.iter().map(|&p| local.id(p)).collect())
                .collect();
            for rim in loops(&pieces) {
                let poly: Vec<[f64; 3]> =
                    rim.iter().map(|&v| local.cx.points[v as usize]).collect();
                // with the points of the cut facets beside it
                let n = poly.len();
                let rim = (0..n)
                    .flat_map(|k| {
                        let mut e = refine::split(poly[k], poly[(k + 1) % n], h, &whole);
                        e.pop();
                        e
                    })
                    .map(|p| pts.id(p))
                    .collect();
                let mut polygons = vec![rim];
                let mut holes = vec![];
                for w in wells {
                    let (k, end) = match level {
                        0 => (0, w.ends[0]),
                        _ => (w.nl, w.ends[1]),
                    };
                    let axis = w.axis_at(k);
                    if matches!(end, End::Open(_)) && inside_xy(&poly, axis) {
                        polygons.push((0..w.m).map(|s| pts.id(w.surface(s, k))).collect());
                        holes.push(axis);
                    }
                }
                // faults inside the cavity meet the face in segments
                let z = poly[0][2];
                for s in sides.iter().filter(|s| s.inner) {
                    let n = s.points.len();
                    for k in 0..n {
                        let (a, b) = (s.points[k], s.points[(k + 1) % n]);
                        let mid: [f64; 3] = std::array::from_fn(|c| (a[c] + b[c]) / 2.0);
                        if a[2] == z && b[2] == z && inside_xy(&poly, mid) {
                            // in the pieces the fault's refined facet has there
                            for e in refine::split(a, b, h, &whole).windows(2) {
                                polygons.push(vec![pts.id(e[0]), pts.id(e[1])]);
                            }
                        }
                    }
                }
                open.push(pts.cx.facets.len() as u32);
                facet(&mut pts, polygons, holes, Across::Outside);
            }
        }
        for (n, w) in wells.iter().enumerate() {
            outer_surface(&mut pts, &mut facet, n, w);
            for (end, k, layer) in [(w.ends[0], 0, 0), (w.ends[1], w.nl, w.nl - 1)] {
                if let End::Cap { .. } = end {
                    cap(&mut pts, &mut facet, n, w, k, layer);
                }
            }
            let mid = w.at(0.0, 0.0, w.mid[w.nl / 2]);
            pts.cx.holes.push(mid);
        }
        Ok(Transition {
            cx: pts.cx,
            across,
            open,
        })
    }

    /// The certified transition mesh: cut at the grid's flat top and bottom
    /// when asked, else (or when that fails) with the faces there kept.
    pub(super) fn mesh<B: Backend + ?Sized>(
        &self,
        backend: &B,
        opts: &Hybrid3Options,
    ) -> Result<Outcome<D3>> {
        let run = |clip: Vec<u32>| {
            conform3(
                backend,
                &self.cx,
                &Options {
                    allow_sites_outside: opts.allow_sites_outside,
                    // The sides' and the wells' rectangles face cells centred on
                    // them: orthogonal links need their power centres at their
                    // centres, hence equal weights.
                    whole_polygons: crate::weights::Keep::Shared,
                    split_facets: opts.split_facets,
                    clip,
                    ..Default::default()
                },
            )
        };
        // Clipping needs every side's and well face's sites below the top and
        // above the bottom (a deviated well's triangles may have theirs
        // beyond); where it fails, the faces there are kept.
        if opts.clip && !self.open.is_empty() {
            run(self.open.clone()).or_else(|cut| {
                run(vec![]).map_err(|faces| {
                    Error::Tried(vec![
                        ("cut at the grid's top and bottom".into(), cut),
                        ("with the faces there kept".into(), faces),
                    ])
                })
            })
        } else {
            run(vec![])
        }
    }
}

/// How many times the facets the cut complex may have (`mesh`).
const CUT_MAX: f64 = 6.0;

/// A cavity's transition and its mesh. Beside a fault, also with the
/// faults and the sides facing nothing near its wells cut smaller
/// (`refine`) when some polygons that could be whole are not, unless that
/// makes over `CUT_MAX` times the facets: kept when that keeps more
/// polygons whole (their links to the reservoir and the wells
/// orthogonal), or when only it meshes.
pub(super) fn mesh<B: Backend + ?Sized>(
    backend: &B,
    sides: &[Side],
    wells: &[Radial],
    opts: &Hybrid3Options,
) -> Result<(Transition, Result<Outcome<D3>>)> {
    let plain = Transition::new(backend, sides, wells, false)?;
    let first = plain.mesh(backend, opts);
    let whole = |o: &Result<Outcome<D3>>| o.as_ref().ok().map(|o| o.report.input.whole_polygons);
    // (all that could be whole are: leaning pillars' sides never are)
    let could = crate::weights::kept_whole(&plain.cx)
        .iter()
        .filter(|&&w| w)
        .count();
    if !sides.iter().any(|s| s.fault) || whole(&first) == Some(could) {
        return Ok((plain, first));
    }
    let cut = Transition::new(backend, sides, wells, true)?;
    // (emerald's 360 m throw cut at its 134 m outer radius: 8 times the
    // facets, and HiGHS takes minutes)
    let more = cut.cx.facets.len() as f64 / plain.cx.facets.len() as f64;
    if more == 1.0 || more > CUT_MAX {
        return Ok((plain, first));
    }
    let second = cut.mesh(backend, opts);
    Ok(match (whole(&first), whole(&second)) {
        (None, Some(_)) => (cut, second),
        (Some(a), Some(b)) if b > a => (cut, second),
        _ => (plain, first),
    })
}

type AddFacet<'a> = dyn FnMut(&mut Points, Vec<Vec<u32>>, Vec<[f64; 3]>, Across) + 'a;

/// A well's outer surface: rectangles between levels across its axis (or
/// horizontal for a vertical well), else two triangles; a plug's too.
fn outer_surface(pts: &mut Points, facet: &mut AddFacet, n: usize, w: &Radial) {
    let (m, rings) = (w.m, w.rings);
    for k in 0..w.nl {
        let lo: Vec<u32> = (0..m).map(|s| pts.id(w.surface(s, k + 1))).collect();
        let hi: Vec<u32> = (0..m).map(|s| pts.id(w.surface(s, k))).collect();
        for s in 0..m {
            let (a, b, c, d) = (hi[s], hi[(s + 1) % m], lo[(s + 1) % m], lo[s]);
            let cell = Across::Well(n, [k, rings - 1, s]);
            if w.vertical || (w.exact(k) && w.exact(k + 1)) {
                facet(pts, vec![vec![a, b, c, d]], vec![], cell);
            } else {
                // The in-plane Delaunay diagonal. Measured against
                // diagonals alternating from sector to sector (which avoid
                // twisted prisms, Schoenhardt, Rambau) on five wells, dips
                // 5 to 30: fewer sites outside on three (7x7x2, dip 20: 2
                // of 72 against 9), as many on one, 2 more on one.
                let angle_at = |o: u32, x: u32, y: u32| {
                    let [po, px, py] = [o, x, y].map(|v| pts.cx.points[v as usize]);
                    let e: [f64; 3] = std::array::from_fn(|i| px[i] - po[i]);
                    let f: [f64; 3] = std::array::from_fn(|i| py[i] - po[i]);
                    let dot: f64 = (0..3).map(|i| e[i] * f[i]).sum();
                    let n = cross_f(e, f);
                    n.iter().map(|x| x * x).sum::<f64>().sqrt().atan2(dot)
                };
                let ac = angle_at(b, a, c) + angle_at(d, c, a) <= std::f64::consts::PI;
                let halves = if ac {
                    [vec![a, b, c], vec![a, c, d]]
                } else {
                    [vec![a, b, d], vec![b, c, d]]
                };
                for t in halves {
                    facet(pts, vec![t], vec![], cell);
                }
            }
        }
    }
}

/// A cap at level k: the plug's triangle of each sector (its wedge cell
/// in layer `layer` beyond), around the axis' point there.
fn cap(pts: &mut Points, facet: &mut AddFacet, n: usize, w: &Radial, k: usize, layer: usize) {
    let c = pts.id(w.centre(k));
    let o: Vec<u32> = (0..w.m).map(|s| pts.id(w.surface(s, k))).collect();
    for s in 0..w.m {
        let cell = Across::Well(n, [layer, 0, s]);
        facet(pts, vec![vec![c, o[s], o[(s + 1) % w.m]]], vec![], cell);
    }
}
