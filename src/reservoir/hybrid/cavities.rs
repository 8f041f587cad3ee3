//! The cavities stage: the columns the radial meshes reach, plus a margin,
//! plus any column they enclose, minus inactive columns (no rock to mesh);
//! grown by a ring where the transition mesh needs more room.

use super::map::distance_to_polygon;
use super::wells::Placed;
use super::Layer;

impl Layer<'_> {
    /// The column index of (i, j).
    pub(super) fn col(&self, i: usize, j: usize) -> usize {
        j * self.nx + i
    }

    /// The columns beside column c.
    pub(super) fn neighbours(&self, c: usize) -> impl Iterator<Item = usize> + '_ {
        let (nx, ny) = (self.nx, self.ny);
        let (i, j) = (c % nx, c / nx);
        [
            (i.wrapping_sub(1), j),
            (i + 1, j),
            (i, j.wrapping_sub(1)),
            (i, j + 1),
        ]
        .into_iter()
        .filter(move |&(a, b)| a < nx && b < ny)
        .map(move |(a, b)| self.col(a, b))
    }

    /// The cavities, as a flag per column: the columns within half a cell
    /// of a well polygon, those they enclose, and `margin` rings more.
    pub(super) fn cavities(&self, placed: &[Placed], margin: usize) -> Vec<bool> {
        let (nx, ny) = (self.nx, self.ny);
        let col = |i: usize, j: usize| self.col(i, j);
        let quad_points = |i: usize, j: usize| self.quad_points(i, j);
        let mut cavity = vec![false; nx * ny];
        for w in placed {
            // Columns within half a cell of the well polygon: its distance to the
            // cavity sides is then at least half their length, and they stay
            // Gabriel (zero weights do).
            let r = (w.radii.last().unwrap() + 0.5 * w.reach).max(0.75 * w.reach);
            for j in 0..ny {
                for i in 0..nx {
                    let d = distance_to_polygon(w.centre, &quad_points(i, j));
                    if d < r {
                        cavity[col(i, j)] = true;
                    }
                }
            }
        }
        self.grow(&mut cavity, &|_| false);
        for _ in 0..margin {
            self.grow(&mut cavity, &|_| true);
        }
        cavity
    }

    /// The cavity grown by a ring of columns around the columns `only`
    /// accepts; columns it then encloses join it.
    pub(super) fn grow(&self, cavity: &mut [bool], only: &dyn Fn(usize) -> bool) {
        let (nx, ny, grid, k) = (self.nx, self.ny, self.grid, self.k);
        let neighbours = |c: usize| self.neighbours(c);
        let before = cavity.to_vec();
        for c in (0..nx * ny).filter(|&c| before[c] && only(c)) {
            for d in neighbours(c) {
                cavity[d] = true;
            }
        }
        // columns enclosed by cavities join them
        let mut outside = vec![false; nx * ny];
        let mut stack: Vec<usize> = (0..nx * ny)
            .filter(|&c| c % nx == 0 || c % nx == nx - 1 || c / nx == 0 || c / nx == ny - 1)
            .collect();
        while let Some(c) = stack.pop() {
            if cavity[c] || std::mem::replace(&mut outside[c], true) {
                continue;
            }
            stack.extend(neighbours(c));
        }
        for c in 0..nx * ny {
            cavity[c] = (cavity[c] || !outside[c]) && grid.active(c % nx, c / nx, k);
        }
    }

    /// Connected cavities, as a label per column (usize::MAX outside).
    pub(super) fn components(&self, cavity: &[bool]) -> Vec<usize> {
        let (nx, ny) = (self.nx, self.ny);
        let neighbours = |c: usize| self.neighbours(c);
        let mut label = vec![usize::MAX; nx * ny];
        for start in 0..nx * ny {
            if !cavity[start] || label[start] != usize::MAX {
                continue;
            }
            let mut stack = vec![start];
            while let Some(c) = stack.pop() {
                if label[c] != usize::MAX {
                    continue;
                }
                label[c] = start;
                stack.extend(neighbours(c).filter(|&d| cavity[d] && label[d] == usize::MAX));
            }
        }
        label
    }
}
