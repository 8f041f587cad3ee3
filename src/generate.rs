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

/// A 3D field (issue 23): an `n` x `n` grid of unit columns, each a stack
/// of `layers` unit boxes (cells), with a vertical octagonal prism well of
/// radius 13/64 at each column's centre through every layer.
///
/// Each cell's side is two half-width rectangles (a vertex at each grid
/// edge's midpoint), shared with the neighbour; each well side is a
/// rectangle per layer. At each level a cell's top is an octagon (the
/// well's section) and the ring between it and the cell's square. The
/// midpoints make the ring's 16 triangles acute (largest angle 82 degrees),
/// so every face is Delaunay with its centre inside: zero weights serve.
pub fn field3(n: usize, layers: usize) -> crate::complex::Complex3 {
    use crate::complex::Facet;
    // (12, 5, 13) / 64: dyadic, so the eight corners are exactly on one
    // circle (radius 0.203) and the octagon is kept whole; 22.6 degrees
    // off the axes, nearly regular
    let octagon: Vec<[f64; 2]> = [
        [12, 5],
        [5, 12],
        [-5, 12],
        [-12, 5],
        [-12, -5],
        [-5, -12],
        [5, -12],
        [12, -5],
    ]
    .iter()
    .map(|&[a, b]| [f64::from(a) / 64.0, f64::from(b) / 64.0])
    .collect();
    // per level: corners, midpoints of x-edges, of y-edges, octagons
    let (m, hx, hy) = (n + 1, n * (n + 1), n * (n + 1));
    let per_level = m * m + hx + hy + 8 * n * n;
    let corner = |i: usize, j: usize| i + m * j;
    let xmid = |i: usize, j: usize| m * m + i + n * j;
    let ymid = |i: usize, j: usize| m * m + hx + i + m * j;
    let oct = |i: usize, j: usize, k: usize| m * m + hx + hy + 8 * (i + n * j) + k % 8;
    let mut points = vec![];
    for z in 0..=layers {
        let z = z as f64;
        points.extend((0..m * m).map(|c| [(c % m) as f64, (c / m) as f64, z]));
        points.extend((0..hx).map(|c| [(c % n) as f64 + 0.5, (c / n) as f64, z]));
        points.extend((0..hy).map(|c| [(c % m) as f64, (c / m) as f64 + 0.5, z]));
        for c in 0..n * n {
            let (x, y) = ((c % n) as f64 + 0.5, (c / n) as f64 + 0.5);
            points.extend(octagon.iter().map(|o| [x + o[0], y + o[1], z]));
        }
    }
    let at = |z: usize, k: usize| (z * per_level + k) as u32;
    let wall = |z: usize, a: usize, b: usize| Facet {
        polygons: vec![vec![at(z, a), at(z, b), at(z + 1, b), at(z + 1, a)]],
        ..Default::default()
    };
    let mut facets = vec![];
    for z in 0..=layers {
        for (i, j) in (0..n * n).map(|c| (c % n, c / n)) {
            let square = [
                corner(i, j),
                xmid(i, j),
                corner(i + 1, j),
                ymid(i + 1, j),
                corner(i + 1, j + 1),
                xmid(i, j + 1),
                corner(i, j + 1),
                ymid(i, j),
            ];
            let well: Vec<u32> = (0..8).map(|k| at(z, oct(i, j, k))).collect();
            facets.push(Facet {
                polygons: vec![square.iter().map(|&v| at(z, v)).collect(), well.clone()],
                holes: vec![[i as f64 + 0.5, j as f64 + 0.5, z as f64]],
                ..Default::default()
            });
            facets.push(Facet {
                polygons: vec![well],
                ..Default::default()
            });
        }
    }
    for z in 0..layers {
        for j in 0..m {
            for i in 0..n {
                facets.push(wall(z, corner(i, j), xmid(i, j)));
                facets.push(wall(z, xmid(i, j), corner(i + 1, j)));
                facets.push(wall(z, corner(j, i), ymid(j, i)));
                facets.push(wall(z, ymid(j, i), corner(j, i + 1)));
            }
        }
        for (i, j) in (0..n * n).map(|c| (c % n, c / n)) {
            facets.extend((0..8).map(|k| wall(z, oct(i, j, k), oct(i, j, k + 1))));
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
        // 3 levels of 9 corners, 12 midpoints and 4 x 8 octagon points;
        // per level 4 rings and 4 octagons, per layer 2 x 12 half walls and
        // 4 x 8 well sides
        let f = field3(2, 2);
        f.validate().unwrap();
        assert_eq!(f.points.len(), 3 * (9 + 12 + 32));
        assert_eq!(f.facets.len(), 3 * 8 + 2 * (24 + 32));
        assert_eq!(f.facets[0].polygons.len(), 2);
    }
}
