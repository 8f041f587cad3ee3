//! Triangulating a simple polygon by its ears, decided exactly.

use super::orient;
use std::cmp::Ordering;

/// Whether p lies in the closed triangle abc (counter-clockwise), exactly.
fn in_closed(a: [f64; 2], b: [f64; 2], c: [f64; 2], p: [f64; 2]) -> bool {
    [orient(a, b, p), orient(b, c, p), orient(c, a, p)]
        .iter()
        .all(|&o| o != Ordering::Less)
}

/// The triangles (indices, counter-clockwise) of a simple polygon given
/// counter-clockwise, cut ear by ear: each ear turns strictly left and
/// holds no other vertex, even on its sides, so no triangle is flat and
/// vertices on a side (collinear runs) stay corners of the triangles
/// beside them. The first ear from the polygon's first vertex is cut
/// first: the same polygon from the same vertex gives the same triangles.
/// None where no ear is left before the polygon is used up (it is not
/// simple, or not counter-clockwise).
pub fn ear_clip(poly: &[[f64; 2]]) -> Option<Vec<[usize; 3]>> {
    let mut left: Vec<usize> = (0..poly.len()).collect();
    let mut out = vec![];
    while left.len() > 3 {
        let n = left.len();
        let ear = (0..n).find(|&k| {
            let (a, b, c) = (left[(k + n - 1) % n], left[k], left[(k + 1) % n]);
            orient(poly[a], poly[b], poly[c]) == Ordering::Greater
                && left
                    .iter()
                    .filter(|&&v| v != a && v != b && v != c)
                    .all(|&v| !in_closed(poly[a], poly[b], poly[c], poly[v]))
        })?;
        out.push([left[(ear + n - 1) % n], left[ear], left[(ear + 1) % n]]);
        left.remove(ear);
    }
    if left.len() == 3 {
        let [a, b, c] = [left[0], left[1], left[2]];
        match orient(poly[a], poly[b], poly[c]) {
            Ordering::Greater => out.push([a, b, c]),
            Ordering::Equal => {}
            Ordering::Less => return None,
        }
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_square_with_points_on_its_sides_has_no_flat_triangle() {
        // corners and a point on each of two sides
        let p = [
            [0.0, 0.0],
            [0.5, 0.0],
            [1.0, 0.0],
            [1.0, 1.0],
            [0.0, 1.0],
            [0.0, 0.5],
        ];
        let t = ear_clip(&p).unwrap();
        assert_eq!(t.len(), 4);
        let area: f64 = t
            .iter()
            .map(|&[a, b, c]| {
                let (u, v) = (p[b], p[c]);
                ((u[0] - p[a][0]) * (v[1] - p[a][1]) - (u[1] - p[a][1]) * (v[0] - p[a][0])) / 2.0
            })
            .sum();
        assert_eq!(area, 1.0);
        for &[a, b, c] in &t {
            assert_eq!(orient(p[a], p[b], p[c]), Ordering::Greater);
        }
        // clockwise: refused
        let mut r = p;
        r.reverse();
        assert!(ear_clip(&r).is_none());
        // an L shape (a reflex corner)
        let l = [
            [0.0, 0.0],
            [2.0, 0.0],
            [2.0, 1.0],
            [1.0, 1.0],
            [1.0, 2.0],
            [0.0, 2.0],
        ];
        assert_eq!(ear_clip(&l).unwrap().len(), 4);
    }
}
