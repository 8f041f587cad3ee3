//! The map view of one layer: a point per pillar, a quadrilateral per
//! column, fault edges and polylines clipped to the cavities.

use crate::reservoir::CornerPointGrid;

pub(crate) fn map_view(g: &CornerPointGrid, k: usize) -> Vec<[f64; 2]> {
    MapView::new(g, k).pillar
}

/// Map view of one layer: a point per pillar, a quadrilateral per column.
pub(super) struct MapView {
    pub(super) pillar: Vec<[f64; 2]>,
    nx: usize,
}

impl MapView {
    /// Each pillar's point at the mean depth of the layer's top corners on it.
    pub(super) fn new(g: &CornerPointGrid, k: usize) -> MapView {
        let (nx, ny) = (g.nx, g.ny);
        let mut sum = vec![(0.0, 0u32); (nx + 1) * (ny + 1)];
        for j in 0..ny {
            for i in 0..nx {
                for c in 0..4 {
                    let (di, dj) = (c & 1, c >> 1);
                    let z = g.corner(i, j, k, c)[2];
                    let s = &mut sum[(j + dj) * (nx + 1) + i + di];
                    s.0 += z;
                    s.1 += 1;
                }
            }
        }
        let pillar = sum
            .iter()
            .enumerate()
            .map(|(p, &(z, n))| {
                let c = g.coord[p];
                let z = z / f64::from(n.max(1));
                let (dz, t) = (c[5] - c[2], z - c[2]);
                let f = if dz != 0.0 { t / dz } else { 0.0 };
                [c[0] + f * (c[3] - c[0]), c[1] + f * (c[4] - c[1])]
            })
            .collect();
        MapView { pillar, nx }
    }

    pub(super) fn pid(&self, i: usize, j: usize) -> u32 {
        (j * (self.nx + 1) + i) as u32
    }

    /// Pillar ids of column (i, j), counter-clockwise in the map.
    pub(super) fn quad(&self, i: usize, j: usize) -> [u32; 4] {
        let q = [
            self.pid(i, j),
            self.pid(i + 1, j),
            self.pid(i + 1, j + 1),
            self.pid(i, j + 1),
        ];
        if crate::geom::shoelace(4, |k| self.pillar[q[k] as usize]) < 0.0 {
            [q[0], q[3], q[2], q[1]]
        } else {
            q
        }
    }

    pub(super) fn centroid(&self, i: usize, j: usize) -> [f64; 2] {
        centroid(&self.quad(i, j).map(|p| self.pillar[p as usize]))
    }
}

fn centroid(p: &[[f64; 2]]) -> [f64; 2] {
    let (mut a, mut cx, mut cy) = (0.0, 0.0, 0.0);
    let o = p[0];
    for k in 1..p.len() - 1 {
        let (b, c) = (p[k], p[k + 1]);
        let t = ((b[0] - o[0]) * (c[1] - o[1]) - (b[1] - o[1]) * (c[0] - o[0])) / 2.0;
        a += t;
        cx += t * (o[0] + b[0] + c[0]) / 3.0;
        cy += t * (o[1] + b[1] + c[1]) / 3.0;
    }
    if a == 0.0 {
        let n = p.len() as f64;
        return [
            p.iter().map(|q| q[0]).sum::<f64>() / n,
            p.iter().map(|q| q[1]).sum::<f64>() / n,
        ];
    }
    [cx / a, cy / a]
}

/// Distance from x to the polygon (0 inside).
pub(super) fn distance_to_polygon(x: [f64; 2], p: &[[f64; 2]]) -> f64 {
    let n = p.len();
    let mut inside = true;
    let mut best = f64::INFINITY;
    for e in 0..n {
        let (a, b) = (p[e], p[(e + 1) % n]);
        inside &= (b[0] - a[0]) * (x[1] - a[1]) - (b[1] - a[1]) * (x[0] - a[0]) >= 0.0;
        best = best.min(to_segment(x, [a, b]));
    }
    if inside {
        0.0
    } else {
        best
    }
}

/// Distance from x to the segment a-b.
pub(super) fn to_segment(x: [f64; 2], [a, b]: [[f64; 2]; 2]) -> f64 {
    let (ux, uy) = (b[0] - a[0], b[1] - a[1]);
    let (vx, vy) = (x[0] - a[0], x[1] - a[1]);
    let t = ((ux * vx + uy * vy) / (ux * ux + uy * uy)).clamp(0.0, 1.0);
    (vx - t * ux).hypot(vy - t * uy)
}

pub(super) type FaultEdge = (u32, u32, (usize, usize), (usize, usize));

/// The parts of a polyline inside the cavities, as chains of points: cut
/// where it crosses a cavity side and pulled back by `gap` from there
/// (parts shorter than that are dropped).
pub(super) fn clip_to_cavity(
    line: &[[f64; 2]],
    sides: &[[[f64; 2]; 2]],
    inside: &dyn Fn([f64; 2]) -> bool,
    gap: f64,
) -> Vec<Vec<[f64; 2]>> {
    let at =
        |a: [f64; 2], b: [f64; 2], t: f64| [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
    let mut chains: Vec<Vec<[f64; 2]>> = vec![];
    let mut current: Vec<[f64; 2]> = vec![];
    // (point, whether a chain may end here without a pull-back)
    for w in line.windows(2) {
        let (a, b) = (w[0], w[1]);
        let d = [b[0] - a[0], b[1] - a[1]];
        let len = d[0].hypot(d[1]);
        if len == 0.0 {
            continue;
        }
        let mut cuts: Vec<f64> = sides
            .iter()
            .filter_map(|[p, q]| {
                let e = [q[0] - p[0], q[1] - p[1]];
                let den = d[0] * e[1] - d[1] * e[0];
                if den == 0.0 {
                    return None;
                }
                let t = ((p[0] - a[0]) * e[1] - (p[1] - a[1]) * e[0]) / den;
                let u = ((p[0] - a[0]) * d[1] - (p[1] - a[1]) * d[0]) / den;
                ((0.0..=1.0).contains(&t) && (0.0..=1.0).contains(&u)).then_some(t)
            })
            .collect();
        cuts.sort_by(f64::total_cmp);
        cuts.dedup();
        let cut = |t: f64| cuts.contains(&t);
        let mut bounds = vec![0.0];
        bounds.extend(cuts.iter().copied().filter(|&t| t > 0.0 && t < 1.0));
        bounds.push(1.0);
        for iv in bounds.windows(2) {
            let (t0, t1) = (iv[0], iv[1]);
            if !inside(at(a, b, (t0 + t1) / 2.0)) {
                if !current.is_empty() {
                    chains.push(std::mem::take(&mut current));
                }
                continue;
            }
            // pulled back from where the line meets a cavity side
            let s = if cut(t0) { t0 + gap / len } else { t0 };
            let e = if cut(t1) { t1 - gap / len } else { t1 };
            if s >= e {
                if !current.is_empty() {
                    chains.push(std::mem::take(&mut current));
                }
                continue;
            }
            if cut(t0) || current.is_empty() {
                if !current.is_empty() {
                    chains.push(std::mem::take(&mut current));
                }
                current.push(at(a, b, s));
            }
            current.push(at(a, b, e));
            if cut(t1) {
                chains.push(std::mem::take(&mut current));
            }
        }
    }
    if !current.is_empty() {
        chains.push(current);
    }
    chains.retain(|c| c.len() >= 2);
    for c in &mut chains {
        c.dedup();
    }
    chains.retain(|c| c.len() >= 2);
    chains
}

/// The pillar edges of the grid's faults at layer k, in map view: (pillar,
/// pillar, column on one side, column on the other); columns outside the
/// grid have an index of nx or ny (or wrap below 0).
pub(super) fn fault_edges(g: &CornerPointGrid, k: usize, view: &MapView) -> Vec<FaultEdge> {
    let mut out = vec![];
    for f in &g.faults {
        for face in &f.faces {
            if k < face.k[0] || k > face.k[1] {
                continue;
            }
            for j in face.j[0]..=face.j[1] {
                for i in face.i[0]..=face.i[1] {
                    // the side of column (i, j) the face names, and the column across
                    let (di, dj) = match face.side() {
                        1 => (1, 0),
                        0 => (-1, 0),
                        3 => (0, 1),
                        2 => (0, -1),
                        _ => continue, // Z faces have no trace in map view
                    };
                    let across = ((i as i64 + di) as usize, (j as i64 + dj) as usize);
                    let (p, q) = match (di, dj) {
                        (1, 0) => (view.pid(i + 1, j), view.pid(i + 1, j + 1)),
                        (-1, 0) => (view.pid(i, j), view.pid(i, j + 1)),
                        (0, 1) => (view.pid(i, j + 1), view.pid(i + 1, j + 1)),
                        _ => (view.pid(i, j), view.pid(i + 1, j)),
                    };
                    out.push((p, q, (i, j), across));
                }
            }
        }
    }
    out
}
