//! Which side of a closed triangulated surface a point lies on, exactly,
//! whatever the solid's shape (not only star-shaped ones): by the parity
//! of a ray's crossings, the ray turned until it meets no edge or vertex.

use super::exact::{orient, orient3};
use super::simplices::{drop_axis, plane_axis};
use std::cmp::Ordering;

/// A triangle of a surface.
pub type Triangle = [[f64; 3]; 3];

/// Whether p lies in the closed solid the closed surface `tris` bounds
/// (on a triangle counts as in). Exact: every decision is an orientation
/// sign of doubles.
pub fn in_solid(tris: &[Triangle], p: [f64; 3]) -> bool {
    if tris.iter().any(|t| on_triangle(t, p)) {
        return true;
    }
    // a far end beyond the surface's box, so that the segment from p to it
    // is the ray as far as the surface goes
    let (mut lo, mut hi) = (p, p);
    for q in tris.iter().flatten() {
        for a in 0..3 {
            lo[a] = lo[a].min(q[a]);
            hi[a] = hi[a].max(q[a]);
        }
    }
    let reach = 4.0 * (0..3).map(|a| hi[a] - lo[a]).fold(1.0, f64::max);
    let mut draw = super::uniform(0x9e37_79b9_7f4a_7c15);
    for _ in 0..256 {
        let d: [f64; 3] = std::array::from_fn(|_| 2.0 * draw() - 1.0);
        let norm = d.iter().map(|x| x * x).sum::<f64>().sqrt();
        if norm < 0.1 {
            continue;
        }
        let q: [f64; 3] = std::array::from_fn(|a| p[a] + reach * d[a] / norm);
        let mut odd = false;
        let mut clean = true;
        for t in tris {
            match crossing(t, p, q) {
                Some(c) => odd ^= c,
                None => {
                    clean = false;
                    break;
                }
            }
        }
        if clean {
            return odd;
        }
    }
    // 256 directions each through an edge or a vertex: not for real input
    debug_assert!(false, "no generic ray from {p:?}");
    false
}

/// Whether p lies on the closed triangle t.
fn on_triangle(t: &Triangle, p: [f64; 3]) -> bool {
    let [a, b, c] = *t;
    if orient3(a, b, c, p) != Ordering::Equal {
        return false;
    }
    let Some(k) = plane_axis(a, b, c) else {
        return false; // no area
    };
    let f = |x: [f64; 3]| drop_axis(k, x);
    let o = [
        orient(f(a), f(b), f(p)),
        orient(f(b), f(c), f(p)),
        orient(f(c), f(a), f(p)),
    ];
    !(o.contains(&Ordering::Greater) && o.contains(&Ordering::Less))
}

/// Whether the segment pq (p off t, q beyond the surface) crosses t's
/// interior: Some(answer), or None where it passes through t's edges or
/// vertices or lies in its plane (another ray is needed).
fn crossing(t: &Triangle, p: [f64; 3], q: [f64; 3]) -> Option<bool> {
    let [a, b, c] = *t;
    let (sp, sq) = (orient3(a, b, c, p), orient3(a, b, c, q));
    match (sp, sq) {
        (Ordering::Equal, Ordering::Equal) => return None,
        // meets the plane only at p (not on t) or at q (beyond t)
        (Ordering::Equal, _) | (_, Ordering::Equal) => return Some(false),
        _ if sp == sq => return Some(false),
        _ => {}
    }
    let o = [
        orient3(p, q, a, b),
        orient3(p, q, b, c),
        orient3(p, q, c, a),
    ];
    let (pos, neg) = (o.contains(&Ordering::Greater), o.contains(&Ordering::Less));
    if pos && neg {
        Some(false)
    } else if o.contains(&Ordering::Equal) {
        None
    } else {
        Some(true)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An L-shaped prism's boundary: a solid not convex.
    fn l_prism() -> Vec<Triangle> {
        // an L of arms 3 long and 1 wide in the xy plane, z 0..1
        let ring: [[f64; 2]; 6] = [
            [0.0, 0.0],
            [3.0, 0.0],
            [3.0, 1.0],
            [1.0, 1.0],
            [1.0, 3.0],
            [0.0, 3.0],
        ];
        let at = |k: usize, z: f64| [ring[k % 6][0], ring[k % 6][1], z];
        let mut t = vec![];
        for k in 0..6 {
            t.push([at(k, 0.0), at(k + 1, 0.0), at(k + 1, 1.0)]);
            t.push([at(k, 0.0), at(k + 1, 1.0), at(k, 1.0)]);
        }
        // caps: fans from corner 3, the reflex one (the L is star from it)
        for k in [4, 5, 0, 1] {
            t.push([at(3, 0.0), at(k + 1, 0.0), at(k, 0.0)]);
            t.push([at(3, 1.0), at(k, 1.0), at(k + 1, 1.0)]);
        }
        t
    }

    #[test]
    fn points_in_and_out_of_an_l_shaped_prism() {
        let t = l_prism();
        assert!(in_solid(&t, [0.5, 0.5, 0.5]));
        assert!(in_solid(&t, [2.5, 0.5, 0.5]));
        assert!(in_solid(&t, [0.5, 2.5, 0.5]));
        assert!(!in_solid(&t, [2.0, 2.0, 0.5])); // the notch
        assert!(!in_solid(&t, [0.5, 0.5, 1.5]));
        assert!(!in_solid(&t, [-0.1, 0.5, 0.5]));
        // on the surface, edges and corners included
        assert!(in_solid(&t, [1.0, 2.0, 0.5]));
        assert!(in_solid(&t, [1.0, 1.0, 1.0]));
        assert!(in_solid(&t, [0.0, 0.0, 0.0]));
        // exactly on the planes of faces, off the faces
        assert!(!in_solid(&t, [2.0, 1.0 + 1e-12, 0.5]));
        assert!(in_solid(&t, [2.0, 1.0 - 1e-12, 0.5]));
    }
}
