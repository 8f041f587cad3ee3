//! An independent dense LP over a whole 2D complex, to confirm the
//! pipeline's infeasibility verdicts: written here from the definitions
//! (lifted points, supporting planes, radical points), not from the crate's
//! row generators, and solved with HiGHS directly.

use highs::{HighsModelStatus, RowProblem, Sense};

/// The largest common margin (capped at 1) of system 1 (every segment an
/// edge of the regular triangulation, no vertex hidden) and, with `with3`,
/// system 3 (every segment crosses its dual edge), on every vertex and
/// every segment; coordinates scaled into [-1, 1]. None when HiGHS gives no
/// optimum.
pub fn dense_margin(points: &[[f64; 2]], segments: &[[u32; 2]], with3: bool) -> Option<f64> {
    let p = unit(points);
    let n = p.len();
    let free = f64::NEG_INFINITY..f64::INFINITY;
    let mut pb = RowProblem::default();
    let w: Vec<_> = (0..n).map(|_| pb.add_column(0.0, free.clone())).collect();
    let delta = pb.add_column(1.0, f64::NEG_INFINITY..1.0);
    let sq = |a: [f64; 2]| a[0] * a[0] + a[1] * a[1];
    // A lifted point (p, |p|^2 - w) on the lower hull, through a plane
    // z = a.x + b under every other lifted point by delta.
    let supported = |on: &[u32], pb: &mut RowProblem| {
        let (ax, ay, b) = (
            pb.add_column(0.0, free.clone()),
            pb.add_column(0.0, free.clone()),
            pb.add_column(0.0, free.clone()),
        );
        for m in 0..n {
            // |p_m|^2 - w_m - a.p_m - b  (= 0 on the plane, >= delta above)
            let terms = [(w[m], -1.0), (ax, -p[m][0]), (ay, -p[m][1]), (b, -1.0)];
            if on.contains(&(m as u32)) {
                pb.add_row(-sq(p[m])..=-sq(p[m]), terms);
            } else {
                let mut t = terms.to_vec();
                t.push((delta, -1.0));
                pb.add_row(-sq(p[m]).., t);
            }
        }
    };
    for &[i, j] in segments {
        supported(&[i, j], &mut pb);
    }
    for k in 0..n as u32 {
        supported(&[k], &mut pb);
    }
    if with3 {
        for &[i, j] in segments {
            let (i, j) = (i as usize, j as usize);
            let u = [p[j][0] - p[i][0], p[j][1] - p[i][1]];
            let l = sq(u);
            // the radical point strictly inside the segment: |w_i - w_j| < L
            pb.add_row(-l.., [(w[i], 1.0), (w[j], -1.0), (delta, -1.0)]);
            pb.add_row(-l.., [(w[i], -1.0), (w[j], 1.0), (delta, -1.0)]);
            // and of lower power for i (and j) than for any other vertex:
            // pow_m(q) - pow_i(q) = |p_m - p_i|^2 - d - (w_i - w_j) d / L
            // - w_m + w_i, with d = u.(p_m - p_i)
            for m in (0..n).filter(|&m| m != i && m != j) {
                let v = [p[m][0] - p[i][0], p[m][1] - p[i][1]];
                let d = u[0] * v[0] + u[1] * v[1];
                let terms = [
                    (w[i], 1.0 - d / l),
                    (w[j], d / l),
                    (w[m], -1.0),
                    (delta, -1.0),
                ];
                pb.add_row((d - sq(v)).., terms);
            }
        }
    }
    let mut model = pb.optimise(Sense::Maximise);
    model.make_quiet();
    let solved = model.solve();
    match solved.status() {
        HighsModelStatus::Optimal => Some(solved.get_solution().columns()[delta.index()]),
        _ => None,
    }
}

/// The points translated and scaled into [-1, 1] by a power of two (exact).
fn unit(points: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in points {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let c = [(lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0];
    let half = ((hi[0] - lo[0]).max(hi[1] - lo[1]) / 2.0).max(f64::MIN_POSITIVE);
    let s = 2f64.powi(half.log2().ceil() as i32);
    points
        .iter()
        .map(|p| [(p[0] - c[0]) / s, (p[1] - c[1]) / s])
        .collect()
}
