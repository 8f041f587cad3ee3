//! Exact geometry of a deviated well: its axis on a lattice whose
//! translates are exact in doubles, the levels its layers are cut at, and
//! small helpers on polyhedral cells.

use crate::geom::newell;

/// Points x = X h, y = Y h, z = Z h / 2^K (integers X, Y, Z) on planes
/// across the axis w = (Wx, Wy, -2^K) / 2^K: w.p = (Wx X + Wy Y - Z) h /
/// 2^K exactly, so a translate by a whole number of steps along w stays
/// on the lattice, and a deviated well's outer faces between two such
/// planes are exact rectangles (kept whole: their links orthogonal).
/// Coordinates are the mesh's permuted so that the axis' largest component
/// is the third (negated where it points up): any axis, horizontal too.
pub(super) struct Lattice {
    h: f64,
    k: i32,
    w: [i64; 2],
    /// The mesh's axes in the lattice's order, and the third's sign.
    perm: [usize; 3],
    flip: f64,
}

impl Lattice {
    /// The lattice for an axis (unit) and points whose coordinate along
    /// its largest component is at most `extent` in size; None where that
    /// coordinate would not be exact.
    pub(super) fn new(u: [f64; 3], extent: f64) -> Option<Lattice> {
        let a = (0..3)
            .max_by(|&x, &y| u[x].abs().total_cmp(&u[y].abs()))
            .unwrap_or(2);
        // the other two in the mesh's order (z's lattice is the mesh's own)
        let perm = match a {
            0 => [1, 2, 0],
            1 => [2, 0, 1],
            _ => [0, 1, 2],
        };
        let flip = if u[a] > 0.0 { -1.0 } else { 1.0 };
        let v = [u[perm[0]], u[perm[1]], flip * u[perm[2]]];
        let e = extent.log2().ceil() as i32;
        // K bits of the axis' slopes (16 or more for depths up to 16 km),
        // steps along the axis of at most 2^-5 (h 2^K), and as fine a
        // lattice as the doubles hold the third coordinate on: |Z| < 2^51
        let k = ((46 - e) / 2).clamp(8, 20);
        let h = 2f64.powi(e + k - 51);
        let one = 2f64.powi(k);
        let w = [
            (-v[0] / v[2] * one).round() as i64,
            (-v[1] / v[2] * one).round() as i64,
        ];
        (h.is_normal() && w.iter().all(|x| x.unsigned_abs() < 1 << 40)).then_some(Lattice {
            h,
            k,
            w,
            perm,
            flip,
        })
    }

    /// A mesh point in the lattice's coordinates.
    fn inward(&self, p: [f64; 3]) -> [f64; 3] {
        [
            p[self.perm[0]],
            p[self.perm[1]],
            self.flip * p[self.perm[2]],
        ]
    }

    /// A point in the lattice's coordinates in the mesh's.
    fn outward(&self, q: [f64; 3]) -> [f64; 3] {
        let mut p = [0.0; 3];
        p[self.perm[0]] = q[0];
        p[self.perm[1]] = q[1];
        p[self.perm[2]] = self.flip * q[2];
        p
    }

    /// The axis' direction w (unit third coordinate), in the lattice's
    /// coordinates.
    fn slopes(&self) -> [f64; 3] {
        let one = 2f64.powi(self.k);
        [self.w[0] as f64 / one, self.w[1] as f64 / one, -1.0]
    }

    /// The unit axis.
    pub(super) fn axis(&self) -> [f64; 3] {
        let v = self.slopes();
        let n = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        self.outward(v.map(|x| x / n))
    }

    /// The length along the axis of one step (h 2^K w).
    pub(super) fn step(&self) -> f64 {
        let [a, b, _] = self.slopes();
        self.h * 2f64.powi(self.k) * (1.0 + a.powi(2) + b.powi(2)).sqrt()
    }

    /// The unit of Z.
    pub(super) fn z_unit(&self) -> f64 {
        self.h / 2f64.powi(self.k)
    }

    /// Whole steps nearest to a length along the axis.
    pub(super) fn steps(&self, t: f64) -> i64 {
        (t / self.step()).round() as i64
    }

    /// The plane across the axis through p (rounded): Wx X + Wy Y - Z.
    pub(super) fn plane(&self, p: [f64; 3]) -> i128 {
        let [x, y, z] = self.round(p);
        self.w[0] as i128 * x as i128 + self.w[1] as i128 * y as i128 - z as i128
    }

    pub(super) fn round(&self, p: [f64; 3]) -> [i64; 3] {
        let q = self.inward(p);
        [q[0] / self.h, q[1] / self.h, q[2] / self.z_unit()].map(|c| c.round() as i64)
    }

    /// The lattice point with p's x and y rounded, on a plane.
    pub(super) fn on(&self, p: [f64; 3], plane: i128) -> [i64; 3] {
        let [x, y, _] = self.round(p);
        let z = self.w[0] as i128 * x as i128 + self.w[1] as i128 * y as i128 - plane;
        [x, y, z as i64]
    }

    pub(super) fn translate(&self, p: [i64; 3], steps: i64) -> [i64; 3] {
        [
            p[0] + steps * self.w[0],
            p[1] + steps * self.w[1],
            p[2] - steps * (1i64 << (2 * self.k)),
        ]
    }

    pub(super) fn point(&self, p: [i64; 3]) -> [f64; 3] {
        self.outward([
            p[0] as f64 * self.h,
            p[1] as f64 * self.h,
            p[2] as f64 * self.z_unit(),
        ])
    }
}

/// Where a point of the well's surfaces is: on a horizontal plane, on a
/// plane across the axis (at a distance along it from the head), or on a
/// knee's mitre plane (a point on it, its unit normal).
#[derive(Clone, Copy)]
pub(super) enum Level {
    Height(f64),
    Along(f64),
    Mitre([f64; 3], [f64; 3]),
}

/// The faces turned so that each is counter-clockwise seen from outside
/// (its Newell normal points away from the site).
pub(super) fn orient_faces(
    faces: Vec<Vec<u32>>,
    points: &[[f64; 3]],
    site: [f64; 3],
) -> Vec<Vec<u32>> {
    faces
        .into_iter()
        .map(|mut f| {
            let pts: Vec<[f64; 3]> = f.iter().map(|&v| points[v as usize]).collect();
            let n = newell(&pts);
            if (0..3).map(|k| n[k] * (pts[0][k] - site[k])).sum::<f64>() < 0.0 {
                f.reverse();
            }
            f
        })
        .collect()
}

/// The face two cells share (same point set).
pub(super) fn find_face(a: &[Vec<u32>], b: &[Vec<u32>]) -> Vec<u32> {
    let key = |f: &Vec<u32>| {
        let mut k = f.clone();
        k.sort_unstable();
        k
    };
    let theirs: Vec<Vec<u32>> = b.iter().map(key).collect();
    a.iter()
        .find(|f| theirs.contains(&key(f)))
        .cloned()
        .unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::{dot, q, sub, Q};

    /// Translates of points on one plane across the axis make exact
    /// rectangles, in the doubles themselves, for axes and coordinates
    /// as a reservoir has them.
    #[test]
    fn lattice_rectangles_are_exact() {
        for (dip, az, x0, zmax) in [
            (10.0f64, 30.0f64, 45.0f64, 20.0),
            (37.0, 211.0, 612_345.7, 3100.0),
            (1.0, 359.0, -2.5e4, 9000.0),
            // horizontal and nearly so, along x, y and between
            (90.0, 90.0, 45.0, 90.0),
            (88.0, 0.0, 4500.0, 9000.0),
            (95.0, 200.0, 612_345.7, 700_000.0),
        ] {
            let (d, a) = (dip.to_radians(), az.to_radians());
            let u = [d.sin() * a.sin(), d.sin() * a.cos(), -d.cos()];
            let big = (0..3)
                .max_by(|&x, &y| u[x].abs().total_cmp(&u[y].abs()))
                .unwrap();
            let extent = [x0.abs(), (x0 * 0.7).abs(), zmax][big] + 10.0;
            let l = Lattice::new(u, extent).unwrap();
            let v = l.axis();
            assert!(
                (0..3).all(|k| (v[k] - u[k]).abs() < 2f64.powi(-14)),
                "{v:?} {u:?}"
            );
            assert!(l.step() < 0.04, "{}", l.step());
            let p0 = [x0, x0 * 0.7, -zmax / 2.0];
            let plane = l.plane(p0);
            let base: Vec<[i64; 3]> = (0..5)
                .map(|s| {
                    let t = s as f64;
                    l.on([p0[0] + 3.1 * t.cos(), p0[1] + 3.1 * t.sin(), p0[2]], plane)
                })
                .collect();
            for s in 0..4 {
                let steps = l.steps(2.7);
                let [a, b] = [base[s], base[s + 1]].map(|p| l.point(p));
                let [c, d] = [base[s + 1], base[s]].map(|p| l.point(l.translate(p, steps)));
                // doubles that round-trip, a parallelogram, a right angle
                let [a, b, c, d] = [a, b, c, d].map(|p| p.map(q));
                assert_eq!(sub(&c, &b), sub(&d, &a));
                assert_eq!(dot(&sub(&b, &a), &sub(&d, &a)), Q::from(0));
                let len = crate::geom::f(&dot(&sub(&d, &a), &sub(&d, &a))).sqrt();
                assert!((len - steps as f64 * l.step()).abs() < 1e-9 * len);
            }
        }
    }
}
