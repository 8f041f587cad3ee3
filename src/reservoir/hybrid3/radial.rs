//! The well's radial mesh in space: its axis (rounded onto a lattice when
//! deviated), the levels its layers are cut at, its two ends (open on a
//! flat top or bottom of the grid, closed by a cap inside the cavity, or
//! a knee where a bent trajectory's next leg goes on), and the points of
//! its rings and outer surface.

use super::lattice::{Lattice, Level};
use super::path::Path;
use super::well::{Hybrid3Options, Well3};
use crate::error::{Error, Result};
use crate::geom::{cross_f, dist_f, dot_f};
use crate::reservoir::hybrid::{first_ring_radii, ring_radii};
use std::f64::consts::TAU;

/// An end of the radial mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum End {
    /// On the grid's flat top or bottom at this height: the cavity's face
    /// there has the well's outline as a window.
    Open(f64),
    /// Closed inside the cavity: the rings end `at` this far along the
    /// axis from the head, and a plug of sector wedges `plug` long beyond
    /// them closes the mesh with one triangle per sector (no facets at the
    /// wellbore's scale for the transition).
    Cap {
        /// Where the rings end, along the axis from the head.
        at: f64,
        /// The plug's length along the axis.
        plug: f64,
        /// The unit normal (along the axis) of the end cell's top or
        /// bottom that the cap parallels, where that face is more than 5
        /// degrees off across the axis (a trajectory through thin layers
        /// it leans through, whose faces a cap across the axis would
        /// reach past at any useful radius).
        tilt: Option<[f64; 3]>,
    },
    /// A knee (`bend`): the rings go on into the next (or previous) leg,
    /// mirrored about the mitre plane through the axes' meeting point.
    Knee(Knee),
}

/// A knee between two legs: their axes meet at `point` (the end of the
/// leg before, the head of the leg after), `normal` is the mitre plane's
/// (the sum of the axes, unit), and each leg's last (first) layer reaches
/// `depth` along its axis from the point, past its mitre's slant.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub(super) struct Knee {
    pub(super) point: [f64; 3],
    pub(super) normal: [f64; 3],
    pub(super) depth: f64,
}

/// How a leg after a knee is placed: its head at the knee's point, its
/// sectors turned by `phase` (so that they mirror the leg before's), and
/// the points of its first level as the leg before has them (q * m + s).
#[derive(Clone, Debug, Default)]
pub(super) struct After {
    pub(super) head: [f64; 3],
    pub(super) phase: f64,
    pub(super) points: Vec<[f64; 3]>,
}

/// The well's radial mesh.
pub(super) struct Radial {
    /// Sectors and rings.
    pub(super) m: usize,
    pub(super) rings: usize,
    /// The rings' radii, wellbore to outer.
    pub(super) r: Vec<f64>,
    pub(super) outer: f64,
    pub(super) vertical: bool,
    /// The axis, and two unit vectors across it.
    pub(super) u: [f64; 3],
    e1: [f64; 3],
    e2: [f64; 3],
    /// The axis' point at the head of the completed interval.
    pub(super) head: [f64; 3],
    lattice: Option<Lattice>,
    /// The layers' boundaries and mid-levels.
    pub(super) levels: Vec<Level>,
    pub(super) mid: Vec<Level>,
    pub(super) nl: usize,
    /// The ends, top and bottom.
    pub(super) ends: [End; 2],
    /// Whether the first and the last layer are plugs of sector wedges.
    plug: [bool; 2],
    /// The first level across the axis, and the outline's lattice points there.
    t1: f64,
    base: Vec<[i64; 3]>,
    /// The sectors' turn about the axis, and the points of the first level
    /// where it is a knee (`After`).
    phase: f64,
    knee_points: Vec<[f64; 3]>,
    /// Its well and leg, for a leg of a trajectory that bends.
    pub(super) leg: Option<(usize, usize)>,
}

/// The levels of a deviated well between its ends: slabs across its axis
/// (so that its cells' links are orthogonal), n of them; an open end is
/// the grid's top or bottom, which crosses the outer surface within
/// `slant` of the axis' end, so the first slab starts past it.
fn slabs(
    well: &Well3,
    path: &Path,
    ends: [End; 2],
    outer: f64,
    lattice: Option<&Lattice>,
) -> Result<(Vec<Level>, Vec<Level>)> {
    let u = path.u;
    let slant = outer * well.dip.to_radians().tan();
    let t_of = |e: End, top: bool| match e {
        End::Open(z) => (z - path.head[2]) / u[2] + if top { slant } else { -slant },
        End::Cap { at, .. } => at,
        End::Knee(k) if top => k.depth,
        End::Knee(k) => path.length - k.depth,
    };
    // a tilted cap's plane reaches `outer` tan(angle to the axis' normal
    // plane) along the axis: the rings' first slab across the axis starts
    // past twice that (a wedge layer between)
    let tilt = ends.map(|e| match e {
        End::Cap {
            tilt: Some(n),
            plug,
            ..
        } => {
            let c = dot_f(n, u).clamp(-1.0, 1.0);
            Some((n, 2.0 * outer * (1.0 - c * c).sqrt() / c + 0.25 * plug))
        }
        _ => None,
    });
    let wedge = tilt.map(|t| t.map_or(0.0, |(_, w)| w));
    let (ta, tb) = (
        t_of(ends[0], true) + wedge[0],
        t_of(ends[1], false) - wedge[1],
    );
    let n = (path.cuts.len() + 1).max(2);
    let span = match (ends[0], ends[1]) {
        (End::Open(a), End::Open(b)) => (a - b) / -u[2],
        _ => tb - ta,
    };
    let knee = ends.map(|e| match e {
        End::Knee(k) => Some(k),
        _ => None,
    });
    if knee.iter().any(Option::is_some) && tb - ta <= 0.0 {
        return Err(Error::Usage(format!(
            "well {}: its leg is {:.3} long, too short for the knees at its ends ({:.3})",
            well.name,
            path.length,
            path.length - (tb - ta)
        )));
    }
    // (NaN lengths fail too)
    let enough = tb - ta >= 0.1 * span;
    if !enough {
        return Err(Error::Usage(format!(
            "well {}: at a dip of {} degrees, its radial mesh (outer radius {outer}) needs a \
             thicker completed interval",
            well.name, well.dip
        )));
    }
    let mut t: Vec<f64> = (0..=n)
        .map(|k| ta + (tb - ta) * k as f64 / n as f64)
        .collect();
    match ends[0] {
        End::Cap {
            at,
            plug,
            tilt: Some(_),
        } => t.splice(0..0, [at - plug, at]).for_each(drop),
        End::Cap { plug, .. } => t.insert(0, ta - plug),
        End::Knee(_) => t.insert(0, 0.0),
        _ => {}
    }
    match ends[1] {
        End::Cap {
            at,
            plug,
            tilt: Some(_),
        } => t.extend([at, at + plug]),
        End::Cap { plug, .. } => t.push(tb + plug),
        End::Knee(_) => t.push(path.length),
        _ => {}
    }
    let last = t.len() - 1;
    let open = [
        matches!(ends[0], End::Open(_)),
        matches!(ends[1], End::Open(_)),
    ];
    if let Some(l) = lattice {
        // the planes across the axis a whole number of lattice steps from
        // the first
        // (a knee's mitre is no plane across the axis)
        // (nor a tilted cap's planes)
        let first = match tilt[0] {
            Some(_) => 2,
            None => usize::from(open[0] || knee[0].is_some()),
        };
        let end = match tilt[1] {
            Some(_) => last - 2,
            None if open[1] || knee[1].is_some() => last - 1,
            None => last,
        };
        for k in first + 1..=end {
            t[k] = t[first] + l.steps(t[k] - t[first]) as f64 * l.step();
        }
    }
    // a plane parallel to a tilted cap's, through the axis at t
    let axis = |t: f64| -> [f64; 3] { std::array::from_fn(|a| path.head[a] + t * u[a]) };
    let tilted = |k: usize| match (k, tilt) {
        (0 | 1, [Some((n, _)), _]) => Some(n),
        (k, [_, Some((n, _))]) if k + 1 >= last => Some(n),
        _ => None,
    };
    let level = |k: usize| match (k, ends[0], ends[1], tilted(k)) {
        (.., Some(n)) => Level::Mitre(axis(t[k]), n),
        (0, End::Open(z), ..) => Level::Height(z),
        (k, _, End::Open(z), _) if k == last => Level::Height(z),
        (0, End::Knee(n), ..) => Level::Mitre(n.point, n.normal),
        (k, _, End::Knee(n), _) if k == last => Level::Mitre(n.point, n.normal),
        _ => Level::Along(t[k]),
    };
    let levels = (0..=last).map(level).collect();
    // the ends' sites on one slab across the axis, past the slant; a
    // knee's half its depth from the point, as the other leg's (mirrored)
    let mid = (0..last).map(|k| match (k, knee, tilted(k), tilted(k + 1)) {
        // between a tilted cap's planes, one parallel halfway
        (.., Some(n), Some(_)) => Level::Mitre(axis((t[k] + t[k + 1]) / 2.0), n),
        // between one and a slab across the axis, the plane halfway along
        // the axis
        (.., Some(n), None) | (.., None, Some(n)) => {
            let c = dot_f(n, u);
            let half: [f64; 3] = std::array::from_fn(|a| n[a] / c + u[a]);
            let n = half.map(|x| x / dist_f(half, [0.0; 3]));
            Level::Mitre(axis((t[k] + t[k + 1]) / 2.0), n)
        }
        (0, [Some(n), _], ..) => Level::Along(n.depth / 2.0),
        (k, [_, Some(n)], ..) if k + 1 == last => Level::Along(path.length - n.depth / 2.0),
        _ => Level::Along((t[k] + t[k + 1]) / 2.0),
    });
    Ok((levels, mid.collect()))
}

/// Two unit vectors across a deviated axis u: the first horizontal (at
/// the azimuth's right angle), the second u x the first.
pub(super) fn frame(u: [f64; 3]) -> [[f64; 3]; 2] {
    frame_at(u[0].atan2(u[1]), u)
}

/// Two unit vectors across an axis u: the first horizontal at the right
/// angle to azimuth `az`, the second u x the first.
fn frame_at(az: f64, u: [f64; 3]) -> [[f64; 3]; 2] {
    let e1 = [az.cos(), -az.sin(), 0.0];
    [e1, cross_f(u, e1)]
}

impl Radial {
    /// The well's radial mesh along its path, with the given outer radius
    /// and ends.
    pub(super) fn new(
        well: &Well3,
        path: &Path,
        opts: &Hybrid3Options,
        outer: f64,
        ends: [End; 2],
        after: Option<&After>,
    ) -> Result<Radial> {
        let (m, rings) = (opts.sectors, opts.rings);
        if m < 3 || rings < 1 || well.radius.is_nan() || well.radius <= 0.0 {
            return Err(Error::Usage(
                "a radial mesh needs 3 sectors, a ring and a positive radius".into(),
            ));
        }
        if outer.is_nan() || outer <= well.radius {
            return Err(Error::Usage(format!(
                "well {}: its radius {} does not fit in its cell",
                well.name, well.radius
            )));
        }
        let vertical = well.path.is_none() && well.dip == 0.0;
        let az = well.azimuth.to_radians();
        let lattice = (!vertical)
            .then(|| Self::lattice(path, outer, ends))
            .flatten();
        // after a knee, from the knee's point (the leg before's axis end)
        let head = after.map_or(path.head, |a| a.head);
        let u = lattice.as_ref().map_or(path.u, Lattice::axis);
        let [e1, e2] = match vertical {
            true => frame_at(az, u),
            false => frame(u),
        };
        let r = match opts.first_ring {
            Some(f) => first_ring_radii(well.radius, outer, rings, f),
            None => ring_radii(well.radius, outer, rings),
        };
        let (levels, mid) = if vertical {
            // (knees are trajectories': never a vertical well's)
            let z = |e: End| match e {
                End::Open(z) => z,
                End::Cap { at, .. } => head[2] - at,
                End::Knee(k) => k.point[2],
            };
            let mut zs = vec![z(ends[0])];
            zs.extend(path.cuts.iter().map(|t| head[2] - t));
            zs.push(z(ends[1]));
            let (top, bottom) = (zs[0], z(ends[1]));
            zs.retain(|&h| h <= top && h >= bottom);
            zs.dedup();
            if let End::Cap { plug, .. } = ends[0] {
                zs.insert(0, top + plug);
            }
            if let End::Cap { plug, .. } = ends[1] {
                zs.push(bottom - plug);
            }
            let mid = zs.windows(2).map(|w| Level::Height((w[0] + w[1]) / 2.0));
            (
                zs.iter().map(|&z| Level::Height(z)).collect(),
                mid.collect(),
            )
        } else {
            slabs(well, path, ends, outer, lattice.as_ref())?
        };
        let nl = mid.len();
        if nl == 0 {
            return Err(Error::Usage(format!(
                "well {}: its completed interval has no length",
                well.name
            )));
        }
        let mut w = Radial {
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
            ends,
            plug: ends.map(|e| matches!(e, End::Cap { .. })),
            t1: 0.0,
            base: vec![],
            phase: after.map_or(0.0, |a| a.phase),
            knee_points: after.map_or(vec![], |a| a.points.clone()),
            leg: path.leg,
        };
        // The outline's points at the levels across the axis: on the lattice,
        // translates of the first such level's (exact rectangles between).
        if let Some(k) = (0..w.levels.len()).find(|&k| matches!(w.levels[k], Level::Along(_))) {
            if let (Some(l), Level::Along(t1)) = (&w.lattice, w.levels[k]) {
                let plane = l.plane(w.at(outer, 0.0, Level::Along(t1)));
                w.base = (0..m)
                    .map(|s| l.on(w.at(outer, w.angle(s), Level::Along(t1)), plane))
                    .collect();
                w.t1 = t1;
            }
        }
        Ok(w)
    }

    /// A deviated well's axis rounded onto a lattice, for exact
    /// rectangles: its coordinate along the axis' largest component is
    /// exact up to the ends' (and the outer radius beyond). Taken from
    /// the path alone, so that a knee's legs know each other's axes.
    pub(super) fn lattice(path: &Path, outer: f64, ends: [End; 2]) -> Option<Lattice> {
        let head = path.head;
        let end = match ends[1] {
            End::Open(z) => (z - head[2]) / path.u[2],
            End::Cap { at, plug, .. } => at + plug,
            End::Knee(_) => path.length,
        };
        let a = (0..3)
            .max_by(|&x, &y| path.u[x].abs().total_cmp(&path.u[y].abs()))
            .unwrap_or(2);
        let far = match (a, ends[1]) {
            (2, End::Open(z)) => z,
            _ => head[a] + end * path.u[a],
        };
        let extent = head[a].abs().max(far.abs()) + outer;
        Lattice::new(path.u, extent)
    }

    /// The point of the cylinder of radius r at angle a on a level.
    pub(super) fn at(&self, r: f64, a: f64, level: Level) -> [f64; 3] {
        let (e1, e2, head, u) = (self.e1, self.e2, self.head, self.u);
        let off: [f64; 3] = std::array::from_fn(|k| r * (a.cos() * e1[k] + a.sin() * e2[k]));
        let s = match level {
            Level::Height(z) => (z - head[2] - off[2]) / u[2],
            Level::Along(t) => t,
            Level::Mitre(o, n) => {
                dot_f(std::array::from_fn(|k| o[k] - head[k] - off[k]), n) / dot_f(u, n)
            }
        };
        let p: [f64; 3] = std::array::from_fn(|k| head[k] + off[k] + s * u[k]);
        match level {
            Level::Height(z) => [p[0], p[1], z],
            Level::Along(_) | Level::Mitre(..) => p,
        }
    }

    /// The angle of sector boundary s.
    pub(super) fn angle(&self, s: usize) -> f64 {
        self.phase + TAU * (s % self.m) as f64 / self.m as f64
    }

    /// The angle of sector s's middle (its sites').
    pub(super) fn mid_angle(&self, s: usize) -> f64 {
        self.phase + TAU * (s as f64 + 0.5) / self.m as f64
    }

    /// The unit vectors across the axis.
    pub(super) fn across(&self) -> [[f64; 3]; 2] {
        [self.e1, self.e2]
    }

    /// Point s of the outer surface at level k: on the lattice, translates
    /// of the first level across the axis (exact rectangles between).
    pub(super) fn surface(&self, s: usize, k: usize) -> [f64; 3] {
        if k == 0 && !self.knee_points.is_empty() {
            return self.knee_points[self.rings * self.m + s % self.m];
        }
        match (&self.lattice, self.levels[k]) {
            (Some(l), Level::Along(t)) if !self.base.is_empty() => {
                l.point(l.translate(self.base[s % self.m], l.steps(t - self.t1)))
            }
            _ => self.at(self.outer, self.angle(s), self.levels[k]),
        }
    }

    /// Point of ring boundary q (0 the wellbore, `rings` the outer surface),
    /// sector boundary s, level k.
    pub(super) fn point(&self, q: usize, s: usize, k: usize) -> [f64; 3] {
        let p = |q: usize| self.at(self.r[q], self.angle(s), self.levels[k]);
        if k == 0 && !self.knee_points.is_empty() {
            return self.knee_points[q * self.m + s % self.m];
        }
        match (q == self.rings, &self.lattice) {
            (true, _) => self.surface(s, k),
            // on a level across the axis, on the lattice's plane there (a
            // cap is then planar exactly)
            (false, Some(l)) if self.exact(k) => l.point(l.on(p(q), l.plane(self.surface(0, k)))),
            (false, _) => p(q),
        }
    }

    /// Whether level k's outline is exact on the lattice.
    pub(super) fn exact(&self, k: usize) -> bool {
        matches!(self.levels[k], Level::Along(_)) && !self.base.is_empty()
    }

    /// The axis' point at a level (at the axis itself).
    pub(super) fn axis_at(&self, k: usize) -> [f64; 3] {
        self.at(0.0, 0.0, self.levels[k])
    }

    /// The axis' point at level k, on the lattice's plane there when the
    /// level is on the lattice (the plug's triangles then share its plane).
    pub(super) fn centre(&self, k: usize) -> [f64; 3] {
        match &self.lattice {
            Some(l) if self.exact(k) => l.point(l.on(self.axis_at(k), l.plane(self.surface(0, k)))),
            _ => self.axis_at(k),
        }
    }

    /// Whether a polygon is near this mesh: its vertices' mean within
    /// twice its ball's radius (through its farthest vertex) plus the outer
    /// radius of the axis. Its facet may then take in points of the outer
    /// surface, or keep the LP from keeping the sides whole, unless cut
    /// smaller (with the ball alone, faces beside a fault's nearest one
    /// were left whole, and no side was kept whole).
    pub(super) fn reaches(&self, poly: &[[f64; 3]]) -> bool {
        let c: [f64; 3] =
            std::array::from_fn(|k| poly.iter().map(|p| p[k]).sum::<f64>() / poly.len() as f64);
        let dist = crate::geom::dist_f;
        let radius = poly.iter().map(|&p| dist(p, c)).fold(0.0, f64::max);
        // the distance from c to the axis between the first and last levels
        let (a, b) = (self.axis_at(0), self.axis_at(self.levels.len() - 1));
        let d: [f64; 3] = std::array::from_fn(|k| b[k] - a[k]);
        let dd: f64 = (0..3).map(|k| d[k] * d[k]).sum();
        let t = match dd > 0.0 {
            true => ((0..3).map(|k| (c[k] - a[k]) * d[k]).sum::<f64>() / dd).clamp(0.0, 1.0),
            false => 0.0,
        };
        let foot: [f64; 3] = std::array::from_fn(|k| a[k] + t * d[k]);
        dist(c, foot) < 2.0 * (radius + self.outer)
    }

    /// Whether layer k is a plug of sector wedges (an end closed inside
    /// the cavity).
    pub(super) fn is_plug(&self, k: usize) -> bool {
        (k == 0 && self.plug[0]) || (k + 1 == self.nl && self.plug[1])
    }

    /// The cells of layer k: rings x sectors, or a plug's sectors.
    fn cells_in(&self, k: usize) -> usize {
        if self.is_plug(k) {
            self.m
        } else {
            self.rings * self.m
        }
    }

    /// The index among the well's cells of layer k, ring q (any in a plug),
    /// sector s.
    pub(super) fn cell(&self, k: usize, q: usize, s: usize) -> usize {
        let before: usize = (0..k).map(|l| self.cells_in(l)).sum();
        before + if self.is_plug(k) { s } else { q * self.m + s }
    }
}
