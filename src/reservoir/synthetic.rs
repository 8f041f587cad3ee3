//! Synthetic reservoirs of any size, for benchmarks and scale tests.

use super::{CornerPointGrid, Well3};

/// A field of `n` x `n` vertical wells, six columns apart, on a dipping
/// layer cake of 100 m columns and 6 layers of 5 m (2 degrees' dip along
/// x, as SPE9's 10 degrees but gentler): (6 n + 1)^2 columns, each well in
/// every layer, wellbore radius 0.1 m. Grid and wells grow together, so
/// the time to mesh it should grow linearly with the wells. (Four columns
/// apart, the default radial meshes' cavities touch and merge into one.)
pub fn well_field(n: usize) -> (CornerPointGrid, Vec<Well3>) {
    let cols = 6 * n + 1;
    let (d, layers) = ([100.0, 100.0], 6);
    let depths: Vec<f64> = (0..=layers).map(|k| 2000.0 + 5.0 * k as f64).collect();
    let mut grid = CornerPointGrid::layered([cols, cols], d, &depths);
    // ZCORN's corners: layer k top (b = 0) or bottom, row 2 j + dj, then
    // 2 i + di; each shifted down by its x times the dip's slope.
    let slope = 2f64.to_radians().tan();
    for (at, z) in grid.zcorn.iter_mut().enumerate() {
        let col = at % (2 * cols);
        let x = (col / 2 + col % 2) as f64 * d[0];
        *z += x * slope;
    }
    for p in &mut grid.coord {
        p[5] += cols as f64 * d[0] * slope;
    }
    let wells = (0..n * n)
        .map(|w| Well3 {
            name: format!("W{}", w + 1),
            i: 3 + 6 * (w % n),
            j: 3 + 6 * (w / n),
            k: Some([0, layers - 1]),
            radius: 0.1,
            cells: (0..layers)
                .map(|k| [3 + 6 * (w % n), 3 + 6 * (w / n), k])
                .collect(),
            ..Default::default()
        })
        .collect();
    (grid, wells)
}
