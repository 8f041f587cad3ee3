//! Synthetic constraint complexes of any size, for benchmarks and tests.

use crate::complex::Complex;

/// The sides of an `nx` x `ny` grid of square cavities of side 50, five
/// segments per side, shared between neighbours.
fn cavity_sides(nx: usize, ny: usize) -> Complex {
    let mut cx = Complex::default();
    let side = 50.0;
    let per = 5; // points per cavity side
    let step = side / per as f64;
    let grid = |i: usize, j: usize| -> u32 { (j * (nx * per + 1) + i) as u32 };
    // Lattice points on the cavity sides only.
    let mut index = std::collections::HashMap::new();
    for j in 0..=ny * per {
        for i in 0..=nx * per {
            if i % per == 0 || j % per == 0 {
                index.insert(grid(i, j), cx.points.len() as u32);
                cx.points.push([i as f64 * step, j as f64 * step]);
            }
        }
    }
    for j in 0..=ny * per {
        for i in 0..=nx * per {
            if j % per == 0 && i < nx * per {
                cx.segments
                    .push([index[&grid(i, j)], index[&grid(i + 1, j)]]);
            }
            if i % per == 0 && j < ny * per {
                cx.segments
                    .push([index[&grid(i, j)], index[&grid(i, j + 1)]]);
            }
        }
    }
    cx
}

/// `nx` x `ny` square cavities of side 50 (10 m cells), each with a 16-gon
/// well boundary of the given radius and a hole inside it: the paper's
/// setting. At radius 14 zero weights suffice; at radius 24.5 the well
/// polygon nearly touches the cavity sides and the weights need the LP.
/// Adjacent cavities share their sides.
pub fn cavities(nx: usize, ny: usize, radius: f64) -> Complex {
    let mut cx = cavity_sides(nx, ny);
    let side = 50.0;
    let n = 16;
    for cy in 0..ny {
        for cxi in 0..nx {
            let c = [(cxi as f64 + 0.5) * side, (cy as f64 + 0.5) * side];
            let first = cx.points.len() as u32;
            for k in 0..n {
                let a = std::f64::consts::TAU * (k as f64 + 0.5) / n as f64;
                cx.points
                    .push([c[0] + radius * a.cos(), c[1] + radius * a.sin()]);
                cx.segments
                    .push([first + k as u32, first + ((k + 1) % n) as u32]);
            }
            cx.holes.push(c);
        }
    }
    cx.vertex_ids = (0..cx.points.len() as i64).collect();
    cx.segment_ids = (0..cx.segments.len() as i64).collect();
    cx
}

/// `rows` horizontal chains of `cols - 1` unit segments, rows `h` apart and
/// staggered by half a segment: for h < 0.5 the segments are not Gabriel
/// (and for small h not Delaunay), so the weights need the LP.
pub fn staggered_chains(rows: usize, cols: usize, h: f64) -> Complex {
    let mut points = vec![];
    let mut segments = vec![];
    for j in 0..rows {
        let off = 0.5 * (j % 2) as f64;
        for i in 0..cols {
            points.push([i as f64 + off, j as f64 * h]);
            if i > 0 {
                let v = (j * cols + i) as u32;
                segments.push([v - 1, v]);
            }
        }
    }
    Complex::new(points, segments)
}

pub use crate::geom::uniform;

/// Appends the points of a polyline (closed: a polygon) and its segments;
/// the index of its first point.
fn chain(cx: &mut Complex, pts: &[[f64; 2]], closed: bool) -> u32 {
    let first = cx.points.len() as u32;
    cx.points.extend_from_slice(pts);
    let n = pts.len() as u32;
    for k in 0..if closed { n } else { n - 1 } {
        cx.segments.push([first + k, first + (k + 1) % n]);
    }
    first
}

/// The scale test's mix (issue 5): an `nx` x `ny` grid of separate square
/// cavities of side 50 (five segments per side), 10 apart, like the
/// cavities around wells in a reservoir grid. In a checkerboard half, a
/// 16-gon well of radius 24.5 (nearly touching the sides: the LP) with a
/// hole, and a fault of three segments from the cavity's lower-left corner
/// towards the well, ending inside (a free end). In the other half, a
/// chain of six unit segments and a short segment 0.4 above one of its
/// vertices, jittered (reproducibly, from `seed`): not Gabriel, so they
/// need the LP too.
pub fn mixed(nx: usize, ny: usize, seed: u64) -> Complex {
    let mut cx = Complex::default();
    let mut u = uniform(seed);
    let mut jitter = move || u() - 0.5;
    let (side, pitch) = (50.0, 60.0);
    for cy in 0..ny {
        for cxi in 0..nx {
            let (x0, y0) = (cxi as f64 * pitch, cy as f64 * pitch);
            let c = [x0 + side / 2.0, y0 + side / 2.0];
            // Counter-clockwise from the lower-left corner.
            let step = side / 5.0;
            let boundary: Vec<[f64; 2]> = (0..20)
                .map(|k| {
                    let t = (k % 5) as f64 * step;
                    match k / 5 {
                        0 => [x0 + t, y0],
                        1 => [x0 + side, y0 + t],
                        2 => [x0 + side - t, y0 + side],
                        _ => [x0, y0 + side - t],
                    }
                })
                .collect();
            let corner = chain(&mut cx, &boundary, true);
            if (cxi + cy) % 2 == 0 {
                let r = 24.5;
                let well: Vec<[f64; 2]> = (0..16)
                    .map(|k| {
                        let a = std::f64::consts::TAU * (k as f64 + 0.5) / 16.0;
                        [c[0] + r * a.cos(), c[1] + r * a.sin()]
                    })
                    .collect();
                chain(&mut cx, &well, true);
                cx.holes.push(c);
                // From the corner towards the centre, ending 4.3 from the well.
                let first = chain(
                    &mut cx,
                    &[
                        [x0 + 2.0, y0 + 1.7],
                        [x0 + 3.6, y0 + 3.9],
                        [x0 + 5.0, y0 + 4.6],
                    ],
                    false,
                );
                cx.segments.push([corner, first]);
            } else {
                // A chain of six segments, and 0.4 above its third vertex
                // a segment 0.6 long: inside the diametral discs of the
                // chain's segments beside that vertex (not Gabriel), but
                // with the vertex outside its own disc, so system 3 holds.
                let row: Vec<[f64; 2]> = (0..7)
                    .map(|i| {
                        [
                            c[0] - 3.5 + i as f64 + 0.1 * jitter(),
                            c[1] + 0.05 * jitter(),
                        ]
                    })
                    .collect();
                let top = [row[2][0], row[2][1] + 0.4 + 0.02 * jitter()];
                chain(&mut cx, &row, false);
                chain(
                    &mut cx,
                    &[
                        [top[0] - 0.3, top[1]],
                        [top[0] + 0.3, top[1] + 0.02 * jitter()],
                    ],
                    false,
                );
            }
        }
    }
    cx.vertex_ids = (0..cx.points.len() as i64).collect();
    cx.segment_ids = (0..cx.segments.len() as i64).collect();
    cx
}

/// A field of `nx` x `ny` separate square cavities of 16 unit sides (side
/// 4, one apart), like the cavities around wells in a reservoir grid:
/// each holds a 12-gon well off centre (radius 0.6, its interior a hole), a
/// fault of three segments with two free ends, and `isolated` points
/// scattered (reproducibly, from `seed`) in a band along its top side. 31
/// segments a cavity: 180 x 180 cavities are 10^6 segments. Every segment
/// is strictly Gabriel, so zero weights suffice; the free ends and
/// isolated points need extra sites (issue 21).
pub fn field(nx: usize, ny: usize, isolated: usize, seed: u64) -> Complex {
    let mut cx = Complex::default();
    let mut u = uniform(seed);
    for cy in 0..ny {
        for cxi in 0..nx {
            let (x0, y0) = (cxi as f64 * 5.0, cy as f64 * 5.0);
            // Counter-clockwise from the lower-left corner.
            let boundary: Vec<[f64; 2]> = (0..16)
                .map(|k| {
                    let t = (k % 4) as f64;
                    match k / 4 {
                        0 => [x0 + t, y0],
                        1 => [x0 + 4.0, y0 + t],
                        2 => [x0 + 4.0 - t, y0 + 4.0],
                        _ => [x0, y0 + 4.0 - t],
                    }
                })
                .collect();
            chain(&mut cx, &boundary, true);
            let c = [x0 + 1.6, y0 + 2.0];
            let well: Vec<[f64; 2]> = (0..12)
                .map(|k| {
                    let a = std::f64::consts::TAU * k as f64 / 12.0;
                    [c[0] + 0.6 * a.cos(), c[1] + 0.6 * a.sin()]
                })
                .collect();
            chain(&mut cx, &well, true);
            cx.holes.push(c);
            let fault = [[2.7, 0.5], [3.2, 1.0], [3.0, 1.6], [3.3, 2.3]];
            chain(&mut cx, &fault.map(|[x, y]| [x0 + x, y0 + y]), false);
            for _ in 0..isolated {
                cx.points.push([x0 + 0.3 + 3.4 * u(), y0 + 3.1 + 0.6 * u()]);
            }
        }
    }
    cx.vertex_ids = (0..cx.points.len() as i64).collect();
    cx.segment_ids = (0..cx.segments.len() as i64).collect();
    cx
}

/// A fixed pseudo-random number in [0, 1) for each key (splitmix64):
/// reproducible, so output is deterministic.
pub fn scatter(key: u64) -> f64 {
    let mut z = key.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    (z ^ (z >> 31)) as f64 / 2f64.powi(64)
}

/// Boxes stacked along z, sharing their horizontal rectangles: the 4 (k + 1)
/// corners of [0, 2] x [0, 1] x [0, k] and their rectangles (a 3D complex
/// whose faces are all kept whole).
pub fn stacked_boxes(k: usize) -> crate::complex::Complex3 {
    let mut points = vec![];
    for z in 0..=k {
        for (x, y) in [(0.0, 0.0), (2.0, 0.0), (2.0, 1.0), (0.0, 1.0)] {
            points.push([x, y, z as f64]);
        }
    }
    let facet = |p: [u32; 4]| crate::complex::Facet {
        polygons: vec![p.to_vec()],
        ..Default::default()
    };
    let mut facets = vec![];
    for z in 0..=k as u32 {
        facets.push(facet([4 * z, 4 * z + 1, 4 * z + 2, 4 * z + 3]));
    }
    for z in 0..k as u32 {
        for s in 0..4 {
            let (a, b) = (4 * z + s, 4 * z + (s + 1) % 4);
            facets.push(facet([a, b, b + 4, a + 4]));
        }
    }
    let n = points.len() as i64;
    crate::complex::Complex3 {
        points,
        vertex_ids: (1..=n).collect(),
        facets,
        holes: vec![],
    }
}

/// A 3D field (issue 23): an `n` x `n` x `layers` block of unit columns,
/// each with a vertical hexagonal prism well of radius 0.25 at its centre
/// through every layer. Each level z = 0..=layers is one horizontal facet
/// holding the block's rectangle and every well's hexagon; the block's
/// sides and the wells' sides are vertical rectangles, one per layer. The
/// wells' insides are meshed too (no holes).
pub fn field3(n: usize, layers: usize) -> crate::complex::Complex3 {
    use crate::complex::Facet;
    let side = n as f64;
    let corners = [(0.0, 0.0), (side, 0.0), (side, side), (0.0, side)];
    let hexagon: Vec<(f64, f64)> = (0..6)
        .map(|k| {
            let a = std::f64::consts::FRAC_PI_3 * k as f64;
            (0.25 * a.cos(), 0.25 * a.sin())
        })
        .collect();
    // per level: 4 corners, then 6 vertices per well
    let per_level = 4 + 6 * n * n;
    let mut points = vec![];
    for z in 0..=layers {
        points.extend(corners.iter().map(|&(x, y)| [x, y, z as f64]));
        for j in 0..n {
            for i in 0..n {
                let (cx, cy) = (i as f64 + 0.5, j as f64 + 0.5);
                points.extend(hexagon.iter().map(|&(dx, dy)| [cx + dx, cy + dy, z as f64]));
            }
        }
    }
    let at = |z: usize, k: usize| (z * per_level + k) as u32;
    let well = |w: usize, k: usize| 4 + 6 * w + k % 6;
    let rectangle = |z: usize, a: usize, b: usize| Facet {
        polygons: vec![vec![at(z, a), at(z, b), at(z + 1, b), at(z + 1, a)]],
        ..Default::default()
    };
    let mut facets = vec![];
    for z in 0..=layers {
        let mut polygons = vec![(0..4).map(|k| at(z, k)).collect::<Vec<u32>>()];
        polygons.extend((0..n * n).map(|w| (0..6).map(|k| at(z, well(w, k))).collect()));
        facets.push(Facet {
            polygons,
            ..Default::default()
        });
    }
    for z in 0..layers {
        facets.extend((0..4).map(|k| rectangle(z, k, (k + 1) % 4)));
        for w in 0..n * n {
            facets.extend((0..6).map(|k| rectangle(z, well(w, k), well(w, k + 1))));
        }
    }
    let count = points.len() as i64;
    crate::complex::Complex3 {
        points,
        vertex_ids: (1..=count).collect(),
        facets,
        holes: vec![],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn generated_complexes_are_valid() {
        let c = cavities(2, 3, 14.0);
        c.validate().unwrap();
        assert_eq!(c.holes.len(), 6);
        assert_eq!(c.segments.len(), 2 * 5 * 4 + 3 * 5 * 3 + 6 * 16);
        let s = staggered_chains(4, 10, 0.3);
        s.validate().unwrap();
        assert_eq!(s.segments.len(), 36);
        let m = mixed(3, 2, 5);
        m.validate().unwrap();
        assert_eq!(m.holes.len(), 3);
        // 20 sides each; wells of 16 and faults of 3; chains of 6 + 1.
        assert_eq!(m.segments.len(), 6 * 20 + 3 * (16 + 3) + 3 * 7);
        // 3 levels of 4 + 4 x 6 points; 3 horizontal facets, and per layer
        // 4 block sides and 4 x 6 well sides
        let f = field3(2, 2);
        assert_eq!(f.points.len(), 3 * 28);
        assert_eq!(f.facets.len(), 3 + 2 * (4 + 24));
        assert_eq!(f.facets[0].polygons.len(), 5);
    }
}
