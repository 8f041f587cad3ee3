//! The well's radial mesh in space: its axis (rounded onto a lattice when
//! deviated), the levels its layers are cut at, and the points of its
//! rings and outer surface.

use super::lattice::{Lattice, Level};
use super::{Hybrid3Options, Well3};
use crate::error::{Error, Result};
use crate::geom::cross_f;
use crate::reservoir::hybrid::ring_radii;
use crate::reservoir::CornerPointGrid;
use std::f64::consts::TAU;

/// The well's geometry inside its 3 x 3 cavity.
pub(super) struct Radial {
    pub(super) xs: Vec<f64>,
    pub(super) ys: Vec<f64>,
    pub(super) zs: Vec<f64>,
    /// The well's column.
    pub(super) i0: usize,
    pub(super) j0: usize,
    /// Sectors and rings.
    pub(super) m: usize,
    pub(super) rings: usize,
    /// The rings' radii, wellbore to outer.
    pub(super) r: Vec<f64>,
    pub(super) outer: f64,
    pub(super) vertical: bool,
    /// The axis, and two unit vectors across it.
    u: [f64; 3],
    e1: [f64; 3],
    e2: [f64; 3],
    /// The axis' point at the grid's top.
    head: [f64; 3],
    lattice: Option<Lattice>,
    /// The layers' boundaries and mid-levels.
    pub(super) levels: Vec<Level>,
    pub(super) mid: Vec<Level>,
    pub(super) nl: usize,
    /// The first level across the axis, and the outline's lattice points there.
    t1: f64,
    base: Vec<[i64; 3]>,
}

/// Checks that the well's cavity and radial mesh fit its column.
fn check(
    g: &CornerPointGrid,
    well: &Well3,
    opts: &Hybrid3Options,
    xs: &[f64],
    ys: &[f64],
) -> Result<f64> {
    let (i0, j0) = (well.i, well.j);
    if i0 == 0 || j0 == 0 || i0 + 1 >= g.nx || j0 + 1 >= g.ny {
        return Err(Error::Usage(format!(
            "well {}: column ({}, {}) must have a column on every side (its cavity is the 3 x 3 columns around it)",
            well.name,
            i0 + 1,
            j0 + 1
        )));
    }
    if (0..g.nz).any(|k| (i0 - 1..=i0 + 1).any(|i| (j0 - 1..=j0 + 1).any(|j| !g.active(i, j, k)))) {
        return Err(Error::Usage(format!(
            "well {}: its cavity has inactive cells",
            well.name
        )));
    }
    let (m, rings) = (opts.sectors, opts.rings);
    if m < 3 || rings < 1 || well.radius.is_nan() || well.radius <= 0.0 {
        return Err(Error::Usage(
            "a radial mesh needs 3 sectors, a ring and a positive radius".into(),
        ));
    }
    let half_side = (xs[i0 + 1] - xs[i0]).min(ys[j0 + 1] - ys[j0]) / 2.0;
    let outer = opts.outer * 2.0 * half_side;
    if outer.is_nan() || outer <= well.radius {
        return Err(Error::Usage(format!(
            "well {}: its radius {} does not fit in its cell",
            well.name, well.radius
        )));
    }
    Ok(outer)
}

/// The well's layers: a vertical well's are the grid's; a deviated
/// well's are slabs across its axis (so that its cells' links are
/// orthogonal), the first and last cut by the grid's top and bottom,
/// which cross the outer surface within `slant` of the axis' ends.
fn layers(
    g: &CornerPointGrid,
    well: &Well3,
    zs: &[f64],
    u: [f64; 3],
    outer: f64,
    lattice: Option<&Lattice>,
) -> Result<(Vec<Level>, Vec<Level>)> {
    let vertical = well.dip == 0.0;
    let dip = well.dip.to_radians();
    Ok(if vertical {
        let mid = zs.windows(2).map(|w| Level::Height((w[0] + w[1]) / 2.0));
        (
            zs.iter().map(|&z| Level::Height(z)).collect(),
            mid.collect(),
        )
    } else {
        let length = (zs[g.nz] - zs[0]) / u[2];
        let slant = outer * dip.tan();
        let n = g.nz.max(2);
        if length - 2.0 * slant < 0.1 * length {
            return Err(Error::Usage(format!(
                "well {}: at a dip of {} degrees, its radial mesh (outer radius {outer}) needs a thicker grid",
                well.name, well.dip
            )));
        }
        let mut t: Vec<f64> = (0..=n)
            .map(|k| slant + (length - 2.0 * slant) * k as f64 / n as f64)
            .collect();
        if let Some(l) = lattice {
            // the planes across the axis a whole number of lattice steps
            // from the first
            for k in 2..n {
                t[k] = t[1] + l.steps(t[k] - t[1]) as f64 * l.step();
            }
        }
        let mut levels = vec![Level::Height(zs[0])];
        levels.extend(t[1..n].iter().map(|&t| Level::Along(t)));
        levels.push(Level::Height(zs[g.nz]));
        // the ends' sites on one slab across the axis, past the slant
        let mid = (0..n).map(|k| Level::Along((t[k] + t[k + 1]) / 2.0));
        (levels, mid.collect())
    })
}

impl Radial {
    /// The well's geometry, or why it does not fit.
    pub(super) fn new(g: &CornerPointGrid, well: &Well3, opts: &Hybrid3Options) -> Result<Radial> {
        let [xs, ys, zs] = super::axes(g)?;
        let outer = check(g, well, opts, &xs, &ys)?;
        let (i0, j0, m, rings) = (well.i, well.j, opts.sectors, opts.rings);
        let half_side = (xs[i0 + 1] - xs[i0]).min(ys[j0 + 1] - ys[j0]) / 2.0;
        // The axis: from the column's centre at the top, going down.
        let (dip, az) = (well.dip.to_radians(), well.azimuth.to_radians());
        let u = [dip.sin() * az.sin(), dip.sin() * az.cos(), -dip.cos()];
        if u[2].is_nan() || u[2] >= -1e-3 {
            return Err(Error::Usage(format!(
                "well {}: a dip of {} degrees is not through the layers",
                well.name, well.dip
            )));
        }
        let vertical = well.dip == 0.0;
        // A deviated well's axis rounded onto a lattice, for exact rectangles.
        let zmax = zs.iter().fold(0.0f64, |a, z| a.max(z.abs())) + outer;
        let lattice = (!vertical).then(|| Lattice::new(u, zmax)).flatten();
        let u = lattice.as_ref().map_or(u, Lattice::axis);
        let az = if vertical { az } else { u[0].atan2(u[1]) };
        let head = [
            (xs[i0] + xs[i0 + 1]) / 2.0,
            (ys[j0] + ys[j0 + 1]) / 2.0,
            zs[0],
        ];
        let e1 = [az.cos(), -az.sin(), 0.0];
        let e2 = cross_f(u, e1);
        // The point of the cylinder of radius r at angle a on a level.
        let at = |r: f64, a: f64, level: Level| -> [f64; 3] {
            let off: [f64; 3] = std::array::from_fn(|k| r * (a.cos() * e1[k] + a.sin() * e2[k]));
            let s = match level {
                Level::Height(z) => (z - head[2] - off[2]) / u[2],
                Level::Along(t) => t,
            };
            let p: [f64; 3] = std::array::from_fn(|k| head[k] + off[k] + s * u[k]);
            match level {
                Level::Height(z) => [p[0], p[1], z],
                Level::Along(_) => p,
            }
        };
        let r = ring_radii(well.radius, outer, rings);
        let angle = |s: usize| TAU * (s % m) as f64 / m as f64;
        // The well's layers: a vertical well's are the grid's; a deviated
        // well's are slabs across its axis (so that its cells' links are
        // orthogonal), the first and last cut by the grid's top and bottom,
        // which cross the outer surface within `slant` of the axis' ends.
        let (levels, mid) = layers(g, well, &zs, u, outer, lattice.as_ref())?;
        let nl = mid.len();
        // The outline's points at the levels across the axis: on the lattice,
        // translates of the first such level's (exact rectangles between).
        let t1 = match levels.get(1) {
            Some(&Level::Along(t1)) => t1,
            _ => 0.0,
        };
        let base: Vec<[i64; 3]> = match (&lattice, levels.get(1)) {
            (Some(l), Some(Level::Along(_))) => {
                let plane = l.plane(at(outer, 0.0, Level::Along(t1)));
                (0..m)
                    .map(|s| l.on(at(outer, angle(s), Level::Along(t1)), plane))
                    .collect()
            }
            _ => vec![],
        };
        // The outer surface must stay inside the cavity, clear of its walls.
        let clear = 0.25 * half_side;
        for (k, &level) in levels.iter().enumerate() {
            for s in 0..m {
                let p = at(outer, angle(s), level);
                if !(p[0] > xs[i0 - 1] + clear
                    && p[0] < xs[i0 + 2] - clear
                    && p[1] > ys[j0 - 1] + clear
                    && p[1] < ys[j0 + 2] - clear)
                {
                    return Err(Error::Usage(format!(
                        "well {}: its radial mesh leaves the cavity of the 3 x 3 columns around ({}, {}) at layer {}",
                        well.name,
                        i0 + 1,
                        j0 + 1,
                        k.min(nl - 1) + 1
                    )));
                }
            }
        }
        Ok(Radial {
            xs,
            ys,
            zs,
            i0,
            j0,
            m,
            rings,
            r,
            outer,
            vertical,
            u,
            e1,
            e2,
            head,
            lattice,
            levels,
            mid,
            nl,
            t1,
            base,
        })
    }

    /// The point of the cylinder of radius r at angle a on a level.
    pub(super) fn at(&self, r: f64, a: f64, level: Level) -> [f64; 3] {
        let (e1, e2, head, u) = (self.e1, self.e2, self.head, self.u);
        let off: [f64; 3] = std::array::from_fn(|k| r * (a.cos() * e1[k] + a.sin() * e2[k]));
        let s = match level {
            Level::Height(z) => (z - head[2] - off[2]) / u[2],
            Level::Along(t) => t,
        };
        let p: [f64; 3] = std::array::from_fn(|k| head[k] + off[k] + s * u[k]);
        match level {
            Level::Height(z) => [p[0], p[1], z],
            Level::Along(_) => p,
        }
    }

    /// The angle of sector boundary s.
    pub(super) fn angle(&self, s: usize) -> f64 {
        TAU * (s % self.m) as f64 / self.m as f64
    }

    /// Point s of the outer surface at level k: on the lattice, translates
    /// of the first level across the axis (exact rectangles between).
    pub(super) fn surface(&self, s: usize, k: usize) -> [f64; 3] {
        match (&self.lattice, self.levels[k]) {
            (Some(l), Level::Along(t)) if !self.base.is_empty() => {
                l.point(l.translate(self.base[s % self.m], l.steps(t - self.t1)))
            }
            _ => self.at(self.outer, self.angle(s), self.levels[k]),
        }
    }

    /// Whether level k's outline is exact on the lattice.
    pub(super) fn exact(&self, k: usize) -> bool {
        matches!(self.levels[k], Level::Along(_)) && !self.base.is_empty()
    }

    /// Grid node (i, j, k).
    pub(super) fn node(&self, i: usize, j: usize, k: usize) -> [f64; 3] {
        [self.xs[i], self.ys[j], self.zs[k]]
    }
}
