//! Extra sites' moves in 3D (docs/method.md section 5). An extra site lies
//! on the dual edge of a triangle of the regular triangulation: anywhere
//! strictly inside that edge it has power w_v at the triangle's vertices
//! and lies in their power cells only, so it may go anywhere there. A site
//! outside its own cell tries positions sampled along the edge, the one
//! farthest inside its faces with its neighbours first (in doubles, a
//! heuristic: the next site diagram decides exactly), as a 2D vertex site
//! does.

use super::cell3::Spot;
use super::d3::Sites3;
use crate::complex::Complex3;
use crate::geom::{along, f, q, Q};

/// Positions sampled along an extra site's dual edge (2D's vertex sites
/// measured 64 against 5).
const SAMPLES: usize = 64;

/// Moves an extra site makes at most: moving changes its neighbours, and
/// sites crowding one another can trade places forever (measured: twelve
/// points inside a box, one site went back and forth for 20 rounds).
const MAX_MOVES: u8 = 3;

/// Where an extra site may go: along the dual edge of an RT triangle
/// (serving its three vertices), or anywhere in one vertex's power cell
/// (`Spot`, serving that vertex alone).
#[derive(Debug, Clone)]
#[allow(clippy::large_enum_variant)] // (boxed where stored: `Sites3::track`)
pub enum Roam {
    Edge(Track),
    Cell(Spot),
}

impl Roam {
    /// Moves made so far (at most `MAX_MOVES`).
    fn moves(&self) -> u8 {
        match self {
            Roam::Edge(track) => track.moves,
            Roam::Cell(spot) => spot.moves,
        }
    }

    /// The same roam with the sites it names renumbered by `id` (u32::MAX:
    /// dropped), as `Sites3::clipped` renumbers sites.
    pub(super) fn renumbered(&self, id: &[u32]) -> Roam {
        match self {
            Roam::Edge(track) => Roam::Edge(track.clone()),
            Roam::Cell(spot) => Roam::Cell(spot.renumbered(id)),
        }
    }
}

/// The smallest distance, over `others` (doubles and weights), from a
/// site at p serving vertex pv (of weight wv: the site's weight gives it
/// power wv there) to the plane of its face with one (negative beyond it).
pub(super) fn depth(p: [f64; 3], (pv, wv): ([f64; 3], f64), others: &[[f64; 4]]) -> f64 {
    let wx = (0..3).map(|k| (p[k] - pv[k]).powi(2)).sum::<f64>() - wv;
    others
        .iter()
        .map(|o| {
            let d2 = (0..3).map(|k| (p[k] - o[k]).powi(2)).sum::<f64>();
            (d2 + wx - o[3]) / (2.0 * d2.sqrt())
        })
        .fold(f64::INFINITY, f64::min)
}

/// Where an extra site may lie: c + t n for t strictly inside (lo, hi)
/// (None: unbounded), sampled over `span` (a missing end stood in for by
/// steps of the triangle's size).
#[derive(Debug, Clone)]
pub struct Track {
    c: [Q; 3],
    n: [Q; 3],
    lo: Option<Q>,
    hi: Option<Q>,
    span: [f64; 2],
    /// Where the site is.
    t: f64,
    /// Moves made.
    moves: u8,
}

impl Track {
    /// The track of a dual edge c + t n, t in (lo, hi), `scale` a step
    /// about half the triangle's size, for a site at `t`.
    pub fn new(
        (c, n): (&[Q; 3], &[Q; 3]),
        (lo, hi): (&Option<Q>, &Option<Q>),
        scale: &Q,
        t: &Q,
    ) -> Track {
        let (l, h, s) = (lo.as_ref().map(f), hi.as_ref().map(f), f(scale));
        let span = match (l, h) {
            (Some(l), Some(h)) => [l, h],
            (Some(l), None) => [l, l + 4.0 * s],
            (None, Some(h)) => [h - 4.0 * s, h],
            (None, None) => [-2.0 * s, 2.0 * s],
        };
        Track {
            c: c.clone(),
            n: n.clone(),
            lo: lo.clone(),
            hi: hi.clone(),
            span,
            t: f(t),
            moves: 0,
        }
    }

    /// Whether t is strictly inside the dual edge, exactly.
    fn holds(&self, t: &Q) -> bool {
        self.lo.as_ref().is_none_or(|l| t > l) && self.hi.as_ref().is_none_or(|h| t < h)
    }

    /// c + t n in doubles.
    fn at(&self, t: f64) -> [f64; 3] {
        std::array::from_fn(|k| f(&self.c[k]) + t * f(&self.n[k]))
    }
}

impl Sites3 {
    /// Moves extra site x, outside its cell, to a place where it is
    /// farther inside its faces with `neighbours` (the sites next to it in
    /// the site triangulation) than where it is: sampled along its dual
    /// edge, or around its vertex (`wander_cell`). False, and it stays,
    /// when none is.
    pub fn wander(&mut self, x: usize, cx: &Complex3, w: &[Q], neighbours: &[u32]) -> bool {
        let Some(roam) = self.track[x].as_ref().filter(|r| r.moves() < MAX_MOVES) else {
            return false;
        };
        let roam = roam.clone();
        let others: Vec<[f64; 4]> = neighbours
            .iter()
            .map(|&y| {
                let (p, wy) = (&self.p[y as usize], &self.w[y as usize]);
                [f(&p[0]), f(&p[1]), f(&p[2]), f(wy)]
            })
            .collect();
        match &*roam {
            Roam::Edge(track) => self.wander_edge(x, cx, w, track, &others),
            Roam::Cell(spot) => self.wander_cell(x, cx, w, spot, &others),
        }
    }

    /// `wander` along a dual edge: to the sampled position farthest inside.
    fn wander_edge(
        &mut self,
        x: usize,
        cx: &Complex3,
        w: &[Q],
        track: &Track,
        others: &[[f64; 4]],
    ) -> bool {
        let v0 = self.serves[x][0] as usize;
        let vertex = (cx.points[v0], f(&w[v0]));
        let at = |t: f64| depth(track.at(t), vertex, others);
        let now = at(track.t);
        let [a, b] = track.span;
        let best = (1..SAMPLES)
            .map(|k| a + (b - a) * k as f64 / SAMPLES as f64)
            .filter(|&t| track.holds(&q(t)))
            .map(|t| (at(t), t))
            .filter(|&(d, _)| d > now)
            .max_by(|p, r| p.0.total_cmp(&r.0));
        let Some((_, t)) = best else {
            return false;
        };
        self.p[x] = along(&track.c, &q(t), &track.n);
        if let Some(Roam::Edge(track)) = self.track[x].as_deref_mut() {
            track.t = t;
            track.moves += 1;
        }
        self.reweigh(x, cx, w);
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::{norm2, sub};

    /// A site on the dual line x = (0, 0, t) of vertex (1, 0, 0), beaten
    /// by a heavy neighbour just above it, moves down its track to where it
    /// beats that neighbour, and stops after `MAX_MOVES` moves.
    #[test]
    fn an_extra_site_wanders_out_of_a_neighbours_reach() {
        let cx = Complex3 {
            points: vec![[1.0, 0.0, 0.0]],
            vertex_ids: vec![1],
            facets: vec![],
            holes: vec![],
        };
        let w = vec![Q::from(0)];
        let zero = || Q::from(0);
        let track = Track::new(
            (&[zero(), zero(), zero()], &[zero(), zero(), Q::from(1)]),
            (&None, &None),
            &Q::from(1),
            &q(0.1),
        );
        let mut s = Sites3::default();
        for (p, wt, tr) in [(0.1, 0.0, Some(track)), (0.3, 1.5, None)] {
            s.p.push([zero(), zero(), q(p)]);
            s.w.push(q(wt));
            s.serves.push(vec![0]);
            s.line.push(None);
            s.track.push(tr.map(|t| Box::new(Roam::Edge(t))));
        }
        s.reweigh(0, &cx, &w);
        let inside = |s: &Sites3| norm2(&sub(&s.p[0], &s.p[1])) + &s.w[0] - &s.w[1] > 0;
        assert!(!inside(&s), "the neighbour beats it where it starts");
        assert!(s.wander(0, &cx, &w, &[1]));
        assert!(inside(&s), "{:?}", s.p[0]);
        // still on its track, with power 0 at its vertex
        assert_eq!((&s.p[0][0], &s.p[0][1]), (&zero(), &zero()));
        assert_eq!(norm2(&sub(&s.p[0], &cx.points[0].map(q))) - &s.w[0], 0);
        // the one it beats now has nowhere better: it stays
        let moves = (0..5).filter(|_| s.wander(0, &cx, &w, &[1])).count();
        assert!(moves < MAX_MOVES as usize, "{moves}");
    }
}
