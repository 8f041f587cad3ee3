//! Measures in doubles: bounding boxes, areas, volumes, planes and normals
//! of the mesh as written. Nothing here decides anything exactly.

use nalgebra::Vector2;

/// Lower-left and upper-right corners of the points' bounding box.
pub fn bbox<const D: usize>(pts: &[[f64; D]]) -> ([f64; D], [f64; D]) {
    let mut lo = [f64::INFINITY; D];
    let mut hi = [f64::NEG_INFINITY; D];
    for p in pts {
        for k in 0..D {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (lo, hi)
}

/// Power centre of three weighted double points in doubles (placement
/// heuristics and mesh coordinates; never a decision). Scaled by a power of
/// two so that squares neither overflow nor underflow.
pub fn centre_f64(p: [[f64; 2]; 3], w: [f64; 3]) -> [f64; 2] {
    let u = [p[1][0] - p[0][0], p[1][1] - p[0][1]];
    let v = [p[2][0] - p[0][0], p[2][1] - p[0][1]];
    let m = u.iter().chain(&v).fold(0.0f64, |m, x| m.max(x.abs()));
    let s = if m > 0.0 && m.is_finite() {
        2f64.powi(m.log2().round() as i32)
    } else {
        1.0
    };
    let (u, v) = (u.map(|x| x / s), v.map(|x| x / s));
    let det = 2.0 * (u[0] * v[1] - u[1] * v[0]);
    let ru = u[0] * u[0] + u[1] * u[1] - (w[1] - w[0]) / s / s;
    let rv = v[0] * v[0] + v[1] * v[1] - (w[2] - w[0]) / s / s;
    [
        p[0][0] + (ru * v[1] - rv * u[1]) / det * s,
        p[0][1] + (rv * u[0] - ru * v[0]) / det * s,
    ]
}

/// Signed area of a polygon (shoelace), relative to its first vertex: far
/// from the origin (map coordinates) absolute products would cancel.
pub fn shoelace(n: usize, at: impl Fn(usize) -> [f64; 2]) -> f64 {
    let o = Vector2::from(at(0));
    let v = |k: usize| Vector2::from(at(k)) - o;
    (1..n.saturating_sub(1))
        .map(|k| v(k).perp(&v(k + 1)))
        .sum::<f64>()
        / 2.0
}

/// Distance between two points in doubles.
pub fn dist_f(p: [f64; 3], q: [f64; 3]) -> f64 {
    (0..3).map(|k| (p[k] - q[k]).powi(2)).sum::<f64>().sqrt()
}

/// Dot product in doubles.
pub fn dot_f(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Determinant of three rows in doubles.
pub fn det3_f(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
        + a[2] * (b[0] * c[1] - b[1] * c[0])
}

/// Cross product in doubles.
pub fn cross_f(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// A polyhedron's volume from its outward faces.
pub fn volume(faces: &[Vec<u32>], points: &[[f64; 3]]) -> f64 {
    let o = points[faces[0][0] as usize];
    let rel = |v: u32| -> [f64; 3] { std::array::from_fn(|k| points[v as usize][k] - o[k]) };
    faces
        .iter()
        .map(|f| {
            (1..f.len() - 1)
                .map(|k| {
                    let (a, b, c) = (rel(f[0]), rel(f[k]), rel(f[k + 1]));
                    let n = cross_f(b, c);
                    (a[0] * n[0] + a[1] * n[1] + a[2] * n[2]) / 6.0
                })
                .sum::<f64>()
        })
        .sum()
}

/// A planar polygon's plane, in doubles.
#[derive(Debug, Clone, Copy)]
pub struct Plane {
    /// A point of the polygon.
    pub origin: [f64; 3],
    /// Unit normal (the polygon counter-clockwise seen from its tip).
    pub unit: [f64; 3],
    pub area: f64,
}

impl Plane {
    /// The plane of a planar polygon (Newell's normal).
    pub fn of(pts: &[[f64; 3]]) -> Plane {
        let n = newell(pts);
        let len = dot_f(n, n).sqrt();
        Plane {
            origin: pts[0],
            unit: n.map(|c| c / len),
            area: len / 2.0,
        }
    }

    /// The distance from x to the plane.
    pub fn distance(&self, x: [f64; 3]) -> f64 {
        dot_f(std::array::from_fn(|k| self.origin[k] - x[k]), self.unit).abs()
    }
}

/// Newell's normal of a planar polygon: twice its area times the unit
/// normal (counter-clockwise seen from its tip).
pub fn newell(pts: &[[f64; 3]]) -> [f64; 3] {
    let edge = |k: usize| (pts[k], pts[(k + 1) % pts.len()]);
    std::array::from_fn(|i| {
        let (j, l) = ((i + 1) % 3, (i + 2) % 3);
        (0..pts.len())
            .map(|k| {
                let (a, b) = edge(k);
                (a[j] - b[j]) * (a[l] + b[l])
            })
            .sum()
    })
}
