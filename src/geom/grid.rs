//! Points bucketed in a uniform grid: box queries in doubles, to find
//! candidates that exact tests then decide.

use crate::FastMap;

/// Points bucketed in a uniform grid of about one point per cell.
pub struct Grid<'a> {
    points: &'a [[f64; 3]],
    lo: [f64; 3],
    h: f64,
    cells: FastMap<[i64; 3], Vec<u32>>,
}

impl<'a> Grid<'a> {
    /// Buckets `points`, about one a cell.
    pub fn new(points: &'a [[f64; 3]]) -> Grid<'a> {
        let (lo, hi) = crate::geom::bbox(points);
        let extent = (0..3).fold(0.0f64, |m, k| m.max(hi[k] - lo[k]));
        let h = (extent / (points.len() as f64).cbrt()).max(f64::MIN_POSITIVE);
        let mut grid = Grid {
            points,
            lo,
            h,
            cells: FastMap::default(),
        };
        for (i, &p) in points.iter().enumerate() {
            let key = grid.key(p);
            grid.cells.entry(key).or_default().push(i as u32);
        }
        grid
    }

    fn key(&self, p: [f64; 3]) -> [i64; 3] {
        std::array::from_fn(|k| ((p[k] - self.lo[k]) / self.h).floor() as i64)
    }

    /// The points in the box [lo, hi].
    pub fn within(&self, lo: [f64; 3], hi: [f64; 3]) -> impl Iterator<Item = u32> + '_ {
        let (a, b) = (self.key(lo), self.key(hi));
        let cells = (a[0]..=b[0]).flat_map(move |i| {
            (a[1]..=b[1]).flat_map(move |j| (a[2]..=b[2]).map(move |k| [i, j, k]))
        });
        cells
            .filter_map(|key| self.cells.get(&key))
            .flatten()
            .copied()
            .filter(move |&m| {
                let p = self.points[m as usize];
                (0..3).all(|k| lo[k] <= p[k] && p[k] <= hi[k])
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_grid_finds_exactly_the_points_in_a_box() {
        let points: Vec<[f64; 3]> = (0..1000)
            .map(|i| [(i % 10) as f64, ((i / 10) % 10) as f64, (i / 100) as f64])
            .collect();
        let grid = Grid::new(&points);
        let mut got: Vec<u32> = grid.within([2.0, 3.0, 4.0], [3.5, 3.0, 9.0]).collect();
        got.sort_unstable();
        let want: Vec<u32> = (0..1000u32)
            .filter(|&i| {
                let p = points[i as usize];
                (2.0..=3.5).contains(&p[0]) && p[1] == 3.0 && (4.0..=9.0).contains(&p[2])
            })
            .collect();
        assert_eq!(got, want);
    }
}
