//! Transmissibilities between a corner-point grid's neighbouring cells as
//! OPM Flow computes them for the original grid (so that a hybridized deck
//! keeps the engineer's far field as Flow sees it): each cell's half
//! transmissibility is its permeability along the face's axis times
//! |A . d| / |d|^2, with A the face's area vector (half the cross product of
//! its diagonals) and d the vector from the cell's centre (the mean of its
//! eight corners) to its own face's centre (the mean of that face's four
//! corners); across x and y, times the cell's NTG. The full value is their
//! harmonic mean times the Darcy constant of the deck's units. Measured
//! against Flow 2022.10's INIT on SPE9 (a prototype of this formula): every
//! TRANX, TRANY, TRANZ within 1.3e-7 relative (single precision).
//!
//! Cells of neighbouring columns connect where their side faces overlap
//! (across a fault's throw too: Flow's non-neighbour connections), through
//! the vector area of the overlap as opm-grid builds it. Face multipliers
//! MULTX ... MULTZ-, MULTFLT and MULTREGT as Flow applies them. With
//! PINCH, as Flow 2022.10 does (measured against its INIT), a cell also
//! connects down across inactive cells collapsed to its bottom face (its
//! TRANZ in Flow's INIT), and nowhere else.

use super::grid::FACES;
use super::CornerPointGrid;
use crate::geom::{cross_f, dot_f};

/// A connection between two cells (indices i + nx (j + ny k)) across
/// their shared face along axis `axis` (0 x, 1 y, 2 z).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Transmissibility {
    /// The two cells, the one on the face's lower side (along `axis`)
    /// first: across a throw it may lie in a deeper layer.
    pub cells: [usize; 2],
    /// The axis the second cell lies along from the first.
    pub axis: usize,
    /// In the units `darcy` gave.
    pub value: f64,
}

/// The Darcy constant, in the deck's units, per mD: METRIC m3 cP / day /
/// bar per mD m, FIELD rb cP / day / psi per mD ft; exact from SI as Flow
/// converts (9.869233e-16 m2 per mD).
pub fn darcy(field: bool) -> f64 {
    let md = 9.869233e-16; // m2
    let (length, volume, pressure) = match field {
        true => (0.3048, 0.158987294928, 6894.757293168),
        false => (1.0, 1.0, 1e5),
    };
    md * length / 1e-3 * 86_400.0 / volume * pressure
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|k| a[k] - b[k])
}

fn mean(p: impl Iterator<Item = [f64; 3]>) -> [f64; 3] {
    let (mut s, mut n) = ([0.0; 3], 0.0);
    for q in p {
        s = [s[0] + q[0], s[1] + q[1], s[2] + q[2]];
        n += 1.0;
    }
    s.map(|x| x / n)
}

/// What the transmissibilities take from each cell: whether Flow keeps it
/// active, permeabilities (mD, per axis), NTG, and the face multipliers
/// where the deck gives them, in the order MULTX, MULTX-, MULTY, MULTY-,
/// MULTZ, MULTZ- (the + one on the cell's face towards its higher
/// neighbour, the - one on the other's), MULTFLT already applied to them.
#[derive(Debug, Clone, Copy)]
pub struct CellProps<'a> {
    /// PINCH: a cell connects down to the next active cell past inactive
    /// ones where its bottom face is that cell's top (they collapsed).
    pub pinch: bool,
    /// Per cell: ACTNUM and a pore volume above MINPV (`active_cells`).
    pub active: &'a [bool],
    /// PERMX, PERMY, PERMZ per cell.
    pub perm: &'a [[f64; 3]],
    /// NTG per cell.
    pub ntg: &'a [f64],
    /// MULTX, MULTX-, MULTY, MULTY-, MULTZ, MULTZ- per cell, where given.
    pub mult: [Option<&'a [f64]>; 6],
}

/// The eight corners of a cell.
fn corners(g: &CornerPointGrid, [i, j, k]: [usize; 3]) -> [[f64; 3]; 8] {
    std::array::from_fn(|n| g.corner(i, j, k, n))
}

/// A cell's bulk volume: the divergence theorem over its faces, each
/// face split into four triangles about the mean of its corners.
pub fn bulk_volume(g: &CornerPointGrid, i: usize, j: usize, k: usize) -> f64 {
    let c = corners(g, [i, j, k]);
    let mut v = 0.0;
    for face in FACES {
        let m = mean(face.iter().map(|&n| c[n]));
        for e in 0..4 {
            let (a, b) = (c[face[e]], c[face[(e + 1) % 4]]);
            v += dot_f(m, cross_f(a, b));
        }
    }
    // the sign is the grid's handedness
    (v / 6.0).abs()
}

/// What a COMPDAT line gives for a connection whose factor Flow computes:
/// the wellbore's radius and skin, and the KH product and equivalent
/// radius where given (deck lengths).
#[derive(Debug, Clone, Copy, Default)]
pub struct Completion {
    /// The wellbore's radius.
    pub radius: f64,
    /// The skin factor.
    pub skin: f64,
    /// The permeability-thickness product, where given.
    pub kh: Option<f64>,
    /// The pressure-equivalent radius, where given.
    pub r0: Option<f64>,
}

/// The factor Flow gives a vertical well's connection to cell (i, j, k)
/// where COMPDAT gives none (Peaceman): darcy 2 pi Kh / (ln(r0 / rw) + S),
/// K = sqrt(kx ky), h the cell's thickness times `ntg`, r0 Peaceman's
/// anisotropic equivalent radius on the cell's widths (as opm-common
/// measures them: in map view, between the means of the corners of
/// opposite sides; the thickness between the means of the top and bottom
/// corners' depths). `f` turns grid lengths into the deck's. None where
/// r0 is not above the wellbore's radius.
pub fn peaceman_factor(
    g: &CornerPointGrid,
    cell: [usize; 3],
    perm: [f64; 2],
    ntg: f64,
    f: f64,
    darcy: f64,
    w: &Completion,
) -> Option<f64> {
    let c = corners(g, cell);
    let side = |a: [usize; 4], b: [usize; 4]| {
        let (p, q) = (mean(a.iter().map(|&n| c[n])), mean(b.iter().map(|&n| c[n])));
        f * (p[0] - q[0]).hypot(p[1] - q[1])
    };
    let (dx, dy) = (
        side([0, 2, 4, 6], [1, 3, 5, 7]),
        side([0, 1, 4, 5], [2, 3, 6, 7]),
    );
    let [i, j, k] = cell;
    let z = |b: usize| (0..4).map(|n| g.depth(i, j, k, n + 4 * b)).sum::<f64>() / 4.0;
    let dz = f * (z(1) - z(0)).abs();
    let [kx, ky] = perm;
    let kh = w.kh.unwrap_or((kx * ky).sqrt() * dz * ntg);
    let r0 = w.r0.unwrap_or_else(|| {
        let (a, b) = ((ky / kx).sqrt(), (kx / ky).sqrt());
        0.28 * (a * dx * dx + b * dy * dy).sqrt() / (a.sqrt() + b.sqrt())
    });
    (r0 > w.radius)
        .then(|| darcy * 2.0 * std::f64::consts::PI * kh / ((r0 / w.radius).ln() + w.skin))
}

/// The cells Flow keeps: active in ACTNUM and with a pore volume above
/// `minpv` (Flow's default 1e-6 of the deck's volume unit).
pub fn active_cells(g: &CornerPointGrid, pore_volume: &[f64], minpv: f64) -> Vec<bool> {
    (0..g.actnum.len())
        .map(|c| g.actnum[c] && pore_volume[c] > minpv)
        .collect()
}

/// The polygon, in (s, depth) with s from 0 on the face's first pillar to
/// 1 on its second, where two cells' side faces between the same pillars
/// overlap. `a` and `b` hold each cell's top and bottom depths on the first
/// pillar, then on the second. Its corners are those of the intervals on
/// the pillars and the crossings of one cell's top or bottom edge with the
/// other's, as opm-grid finds them, in order around it.
fn overlap(a: [f64; 4], b: [f64; 4]) -> Vec<[f64; 2]> {
    let mut pts = vec![];
    for (s, n) in [(0.0, 0), (1.0, 2)] {
        let (lo, hi) = (a[n].max(b[n]), a[n + 1].min(b[n + 1]));
        if lo < hi {
            pts.extend([[s, lo], [s, hi]]);
        } else if lo == hi {
            pts.push([s, lo]);
        }
    }
    let at = |z0: f64, z1: f64, s: f64| z0 + s * (z1 - z0);
    // inside both cells at s, to the rounding of the crossing's depth
    let inside = |s: f64, z: f64| {
        [a, b].iter().all(|c| {
            let (top, bottom) = (at(c[0], c[2], s), at(c[1], c[3], s));
            let tol = 1e-12 * (top.abs() + bottom.abs());
            top - tol <= z && z <= bottom + tol
        })
    };
    for u in [(a[0], a[2]), (a[1], a[3])] {
        for w in [(b[0], b[2]), (b[1], b[3])] {
            let den = (u.1 - u.0) - (w.1 - w.0);
            if den == 0.0 {
                continue;
            }
            let s = (w.0 - u.0) / den;
            let z = at(u.0, u.1, s);
            if 0.0 < s && s < 1.0 && inside(s, z) {
                pts.push([s, z]);
            }
        }
    }
    if pts.len() < 3 {
        return vec![];
    }
    let c = mean(pts.iter().map(|p| [p[0], p[1], 0.0]));
    // the corners of a convex polygon, in order of angle about its mean
    // (an affine map of (s, z) keeps that order)
    pts.sort_by(|p, q| {
        let ang = |p: &[f64; 2]| (p[1] - c[1]).atan2(p[0] - c[0]);
        ang(p).total_cmp(&ang(q))
    });
    pts
}

/// The vector area of a closed polygon (half the sum of its edges' cross
/// products; for four corners, half the cross product of the diagonals).
fn vector_area(p: &[[f64; 3]]) -> [f64; 3] {
    let mut a = [0.0; 3];
    for (n, &q) in p.iter().enumerate() {
        let c = cross_f(q, p[(n + 1) % p.len()]);
        a = std::array::from_fn(|k| a[k] + 0.5 * c[k]);
    }
    a
}

/// The transmissibilities between every pair of active cells that share
/// a face: vertical neighbours whose shared face matches (the same four
/// corners on both sides), and cells of neighbouring columns whose side
/// faces overlap, across a fault's throw too (Flow's non-neighbour
/// connections), times the two cells' multipliers on that face.
pub fn transmissibilities(
    g: &CornerPointGrid,
    props: &CellProps,
    darcy: f64,
) -> Vec<Transmissibility> {
    let mut out = vec![];
    for k in 0..g.nz {
        for j in 0..g.ny {
            for i in 0..g.nx {
                if props.active[g.cell_index(i, j, k)] {
                    across_columns(g, props, darcy, [i, j, k], &mut out);
                    below(g, props, darcy, [i, j, k], &mut out);
                }
            }
        }
    }
    out
}

/// One connection from cell `a` across its + face along `axis` to `b`,
/// through the face's vector area `area`.
fn connect(
    g: &CornerPointGrid,
    props: &CellProps,
    darcy: f64,
    (a, b, axis): ([usize; 3], [usize; 3], usize),
    (ca, cb): (&[[f64; 3]; 8], &[[f64; 3]; 8]),
    area: [f64; 3],
) -> Transmissibility {
    let at = |[i, j, k]: [usize; 3]| g.cell_index(i, j, k);
    let mult = |m: usize, c: usize| props.mult[m].map_or(1.0, |v| v[c]);
    // each cell's centre (the mean of its corners) to its own face's centre
    let half = |c: [usize; 3], cs: &[[f64; 3]; 8], face: [usize; 4]| {
        let d = sub(mean(face.iter().map(|&m| cs[m])), mean(cs.iter().copied()));
        let t = props.perm[at(c)][axis] * dot_f(area, d).abs() / dot_f(d, d);
        match axis < 2 {
            true => t * props.ntg[at(c)],
            false => t,
        }
    };
    let fa = FACES[2 * axis + 1];
    let (ta, tb) = (half(a, ca, fa), half(b, cb, FACES[2 * axis]));
    let value = match ta > 0.0 && tb > 0.0 {
        true => {
            let m = mult(2 * axis, at(a)) * mult(2 * axis + 1, at(b));
            m * darcy / (1.0 / ta + 1.0 / tb)
        }
        false => 0.0,
    };
    Transmissibility {
        cells: [at(a), at(b)],
        axis,
        value,
    }
}

/// Cell `a`'s connection to the cell below, where their faces match.
fn below(
    g: &CornerPointGrid,
    props: &CellProps,
    darcy: f64,
    a: [usize; 3],
    out: &mut Vec<Transmissibility>,
) {
    let active = |k: usize| props.active[g.cell_index(a[0], a[1], k)];
    let mut k = a[2] + 1;
    while props.pinch && k < g.nz && !active(k) {
        k += 1;
    }
    if k >= g.nz || !active(k) {
        return;
    }
    let b = [a[0], a[1], k];
    let (ca, cb) = (corners(g, a), corners(g, b));
    let (fa, fb) = (FACES[5], FACES[5].map(|c| c ^ 4));
    if (0..4).all(|m| ca[fa[m]] == cb[fb[m]]) {
        let p = fa.map(|m| ca[m]);
        out.push(connect(
            g,
            props,
            darcy,
            (a, b, 2),
            (&ca, &cb),
            vector_area(&p),
        ));
    }
}

/// Cell `a`'s connections to the cells of the next column along x and
/// along y whose side faces overlap its own.
fn across_columns(
    g: &CornerPointGrid,
    props: &CellProps,
    darcy: f64,
    a: [usize; 3],
    out: &mut Vec<Transmissibility>,
) {
    let [i, j, _] = a;
    for axis in 0..2 {
        let (step, lat) = (1 << axis, 1 << (1 - axis));
        let (ni, nj) = (i + (axis == 0) as usize, j + (axis == 1) as usize);
        if ni >= g.nx || nj >= g.ny {
            continue;
        }
        // a's corners on the face's two pillars, then b's same ones
        let (p, q) = (step, step | lat);
        let depths = |[i, j, k]: [usize; 3], p: usize, q: usize| {
            [p, p | 4, q, q | 4].map(|c| g.depth(i, j, k, c))
        };
        let za = depths(a, p, q);
        let ca = corners(g, a);
        let pillar = |c: usize| (i + (c & 1), j + ((c >> 1) & 1));
        let (pp, pq) = (pillar(p), pillar(q));
        for k2 in 0..g.nz {
            let b = [ni, nj, k2];
            if !props.active[g.cell_index(ni, nj, k2)] {
                continue;
            }
            let zb = depths(b, p ^ step, q ^ step);
            if (zb[1] <= za[0] && zb[3] <= za[2]) || (zb[0] >= za[1] && zb[2] >= za[3]) {
                continue; // wholly above or below
            }
            let poly = overlap(za, zb);
            if poly.is_empty() {
                continue;
            }
            // opm-grid's points: at the depth z, s of the way between the
            // two pillars' points at z
            let pts: Vec<[f64; 3]> = poly
                .iter()
                .map(|&[s, z]| {
                    let (u, w) = (g.on_pillar(pp.0, pp.1, z), g.on_pillar(pq.0, pq.1, z));
                    std::array::from_fn(|n| (1.0 - s) * u[n] + s * w[n])
                })
                .collect();
            let area = vector_area(&pts);
            if dot_f(area, area) > 0.0 {
                out.push(connect(
                    g,
                    props,
                    darcy,
                    (a, b, axis),
                    (&ca, &corners(g, b)),
                    area,
                ));
            }
        }
    }
}

/// A MULTREGT record: connections between cells of regions `regions` (in
/// either order) of region array `set` along `axes` are multiplied by
/// `value`; `nnc` says which: Some(true) across non-neighbours only,
/// Some(false) between Cartesian neighbours only, None all.
#[derive(Debug, Clone, PartialEq)]
pub struct RegionMultiplier {
    /// The two regions, None for every region of the set.
    pub regions: [Option<i64>; 2],
    /// The multiplier.
    pub value: f64,
    /// Along x, y, z.
    pub axes: [bool; 3],
    /// Non-neighbours only, neighbours only, or all.
    pub nnc: Option<bool>,
    /// The region array (MULTNUM, FLUXNUM, OPERNUM).
    pub set: String,
}

/// Applies MULTREGT as Flow 2022.10 does: a record names a pair of
/// different regions of its set (a defaulted region: each of the set's),
/// a later record for the same pair (of any set) replaces an earlier one,
/// and a
/// connection takes the multiplier of the first set (by name) with a
/// record for its cells' pair along its axis. `sets` holds each set's
/// region per cell.
pub fn apply_multregt(
    g: &CornerPointGrid,
    records: &[RegionMultiplier],
    sets: &std::collections::BTreeMap<String, Vec<i64>>,
    out: &mut [Transmissibility],
) {
    use std::collections::{BTreeMap, BTreeSet, HashMap};
    // the latest record per pair of regions, whatever its set
    let mut latest: HashMap<(i64, i64), usize> = HashMap::new();
    for (n, r) in records.iter().enumerate() {
        let Some(cells) = sets.get(&r.set) else {
            continue;
        };
        let all: BTreeSet<i64> = cells.iter().copied().collect();
        let each = |x: Option<i64>| x.map_or(all.iter().copied().collect(), |x| vec![x]);
        for a in each(r.regions[0]) {
            for b in each(r.regions[1]) {
                if a != b {
                    latest.insert((a, b), n);
                    latest.insert((b, a), n);
                }
            }
        }
    }
    let mut search: BTreeMap<&str, HashMap<(i64, i64), usize>> = BTreeMap::new();
    for (pair, n) in latest {
        search.entry(&records[n].set).or_default().insert(pair, n);
    }
    if search.is_empty() {
        return;
    }
    // Flow 2022.10's neighbours for NNC and NONNC: one step in i or in
    // its j, which it takes modulo nz; vertical neighbours are not
    let ij = |c: usize| [c % g.nx, (c / g.nx) % g.nz];
    for t in out.iter_mut() {
        let (p, q) = (ij(t.cells[0]), ij(t.cells[1]));
        let adjacent = p[0].abs_diff(q[0]) + p[1].abs_diff(q[1]) == 1;
        for (set, map) in &search {
            let region = &sets[*set];
            let pair = (region[t.cells[0]], region[t.cells[1]]);
            let Some(&n) = map.get(&pair).filter(|&&n| records[n].axes[t.axis]) else {
                continue;
            };
            if records[n].nnc.is_none_or(|only| only != adjacent) {
                t.value *= records[n].value;
                break;
            }
        }
    }
}

/// Folds MULTFLT into the face multipliers: each fault's value (the last
/// MULTFLT naming it, as Flow takes it; a name ending in `*` names every
/// fault it starts) times the multiplier of every face the fault lists.
/// `mult` holds MULTX, MULTX-, ... MULTZ- per cell, 1 where not given.
pub fn apply_multflt(g: &CornerPointGrid, multflt: &[(String, f64)], mult: &mut [Vec<f64>; 6]) {
    for f in &g.faults {
        let named = |p: &String| match p.strip_suffix('*') {
            Some(stem) => f.name.starts_with(stem),
            None => *p == f.name,
        };
        let Some(&(_, m)) = multflt.iter().rev().find(|(p, _)| named(p)) else {
            continue;
        };
        for face in &f.faces {
            // FAULTS' face X is the + one, MULTX's; X- is MULTX-'s
            let slot = match face.side() {
                s if s % 2 == 1 => s - 1,
                s => s + 1,
            };
            for k in face.k[0]..=face.k[1] {
                for j in face.j[0]..=face.j[1] {
                    for i in face.i[0]..=face.i[1] {
                        mult[slot][g.cell_index(i, j, k)] *= m;
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn darcy_constants() {
        // Flow's METRIC and FIELD constants, to the digits they print
        assert!((darcy(false) - 0.008527017).abs() < 1e-9);
        assert!((darcy(true) - 0.001127116).abs() < 1e-9);
    }

    /// Flow 2022.10 gave SPE9's PROD2 in its layer 2 (300 x 300 x 15 ft,
    /// 40.18363 mD, NTG 0.8 added, 0.5 ft diameter, factor defaulted)
    /// 0.62423617 in its restart file (SCON), Kh 482.20355.
    #[test]
    fn peaceman_as_flow_computes_it() {
        let g = CornerPointGrid::cartesian([1, 1, 1], [300.0, 300.0, 15.0]);
        let mut w = Completion {
            radius: 0.25,
            ..Default::default()
        };
        let cf = |w: &Completion| {
            peaceman_factor(&g, [0; 3], [40.18363; 2], 0.8, 1.0, darcy(true), w).unwrap()
        };
        assert!((cf(&w) / 0.62423617 - 1.0).abs() < 1e-6, "{}", cf(&w));
        // a skin adds to the log; a given Kh replaces the computed one
        let plain = cf(&w);
        w.skin = 2.0;
        let log = (0.28 * 300.0 * 2f64.sqrt() / 2.0 / 0.25f64).ln();
        assert!((cf(&w) - plain * log / (log + 2.0)).abs() < 1e-12);
        w.kh = Some(2.0 * 482.20355);
        assert!((cf(&w) - 2.0 * plain * log / (log + 2.0)).abs() < 1e-6);
        // a wellbore as wide as the equivalent radius has no factor
        w.radius = 60.0;
        assert!(peaceman_factor(&g, [0; 3], [40.0; 2], 1.0, 1.0, darcy(true), &w).is_none());
    }

    /// MULTREGT: the pair's record along its axes, neighbours or not as
    /// it says; a later record for the pair replaces an earlier one.
    #[test]
    fn region_multipliers() {
        let g = CornerPointGrid::cartesian([2, 2, 2], [10.0, 10.0, 5.0]);
        let t = |cells: [usize; 2], axis: usize| Transmissibility {
            cells,
            axis,
            value: 1.0,
        };
        let record = |value: f64, axes: [bool; 3], nnc: Option<bool>| RegionMultiplier {
            regions: [Some(2), None],
            value,
            axes,
            nnc,
            set: "MULTNUM".into(),
        };
        // region 1 in the first cell, 2 elsewhere; (0, 3) is a diagonal,
        // not neighbours; along y only the first record would apply, which
        // the second replaced; vertical neighbours are not neighbours to
        // Flow
        let sets = [("MULTNUM".to_string(), vec![1, 2, 2, 2, 2, 2, 2, 2])].into();
        let mut out = [t([0, 1], 0), t([0, 2], 1), t([0, 3], 0), t([0, 4], 2)];
        let records = [
            record(0.1, [true; 3], None),
            record(0.5, [true, false, true], Some(false)),
        ];
        apply_multregt(&g, &records, &sets, &mut out);
        let v: Vec<f64> = out.iter().map(|t| t.value).collect();
        assert_eq!(v, [0.5, 1.0, 1.0, 1.0]);
    }

    /// A Cartesian block: T = c / (dx1 / (2 k1 A) + dx2 / (2 k2 A)).
    #[test]
    fn a_cartesian_block() {
        let g = CornerPointGrid::cartesian([2, 1, 2], [10.0, 20.0, 5.0]);
        let perm = vec![
            [100.0, 50.0, 10.0],
            [300.0, 50.0, 10.0],
            [100.0, 50.0, 30.0],
            [1.0; 3],
        ];
        let ntg = vec![0.5, 1.0, 1.0, 1.0];
        let multx = [1.0, 1.0, 0.5, 1.0];
        let multz_minus = [1.0, 1.0, 0.25, 1.0];
        let props = CellProps {
            pinch: false,
            active: &[true; 4],
            perm: &perm,
            ntg: &ntg,
            mult: [Some(&multx), None, None, None, None, Some(&multz_minus)],
        };
        let t = transmissibilities(&g, &props, 1.0);
        assert_eq!(t.len(), 4);
        let x = t.iter().find(|c| c.cells == [0, 1]).unwrap();
        let (a, half) = (20.0 * 5.0, 5.0);
        let want = 1.0 / (half / (100.0 * 0.5 * a) + half / (300.0 * a));
        assert!((x.value - want).abs() < 1e-12 * want, "{x:?} {want}");
        let z = t.iter().find(|c| c.cells == [0, 2]).unwrap();
        let (a, half) = (10.0 * 20.0, 2.5);
        let want = 0.25 / (half / (10.0 * a) + half / (30.0 * a));
        assert!((z.value - want).abs() < 1e-12 * want, "{z:?} {want}");
        // MULTX on cell 2's face towards cell 3
        let x2 = t.iter().find(|c| c.cells == [2, 3]).unwrap();
        let free = transmissibilities(
            &g,
            &CellProps {
                mult: [None; 6],
                ..props
            },
            1.0,
        );
        let x2free = free.iter().find(|c| c.cells == [2, 3]).unwrap();
        assert!((x2.value - 0.5 * x2free.value).abs() < 1e-15 * x2free.value);
    }

    /// A dipping pair: the face's area vector leans with the dip, and the
    /// half transmissibility takes its component along the centre-to-face
    /// vector.
    #[test]
    fn a_dipping_pair() {
        let mut g = CornerPointGrid::cartesian([2, 1, 1], [10.0, 10.0, 2.0]);
        // every corner dropped by 0.2 x: a slope of 0.2 along x
        for c in g.coord.iter_mut() {
            let drop = 0.2 * c[0];
            c[2] += drop;
            c[5] += drop;
        }
        for (n, z) in g.zcorn.iter_mut().enumerate() {
            let i = n % 4; // x index of the corner along the row
            let x = [0.0, 10.0, 10.0, 20.0][i];
            *z += 0.2 * x;
        }
        let props = CellProps {
            pinch: false,
            active: &[true; 2],
            perm: &[[1.0; 3]; 2],
            ntg: &[1.0; 2],
            mult: [None; 6],
        };
        let t = transmissibilities(&g, &props, 1.0);
        let x = t.iter().find(|c| c.axis == 0).expect("a face along x");
        // face: x = 10, y in [0, 10], depth in [2, 4]: A = (20, 0, 0); the
        // centre-to-face vector (5, 0, 1): |A.d| / |d|^2 = 100 / 26
        let half = 100.0 / 26.0;
        assert!((x.value - half / 2.0).abs() < 1e-12, "{x:?}");
    }

    /// Two columns, the second thrown down by half a layer: the lower cell
    /// of the first faces both of the second, the upper one the upper one,
    /// each through half a face.
    #[test]
    fn across_a_throw() {
        let mut g = CornerPointGrid::cartesian([2, 1, 2], [10.0, 10.0, 4.0]);
        for (n, z) in g.zcorn.iter_mut().enumerate() {
            if n % 4 >= 2 {
                *z += 2.0; // the second column's corners
            }
        }
        let props = CellProps {
            pinch: false,
            active: &[true; 4],
            perm: &[[1.0; 3]; 4],
            ntg: &[1.0; 4],
            mult: [None; 6],
        };
        let t = transmissibilities(&g, &props, 1.0);
        let mut x: Vec<_> = t.iter().filter(|c| c.axis == 0).collect();
        x.sort_by_key(|c| c.cells);
        let pairs: Vec<_> = x.iter().map(|c| c.cells).collect();
        assert_eq!(pairs, [[0, 1], [2, 1], [2, 3]]);
        // area 10 x 2, centre-to-face 5: 2 x 20 / 5 halves, 2 in all
        for c in &x {
            assert!((c.value - 2.0).abs() < 1e-12, "{c:?}");
        }
        assert_eq!(t.iter().filter(|c| c.axis == 2).count(), 2);
        // MULTFLT on a fault over the first column's + x faces
        use super::super::grid::{Fault, FaultFace};
        g.faults.push(Fault {
            name: "F1".into(),
            faces: vec![FaultFace {
                i: [0, 0],
                j: [0, 0],
                k: [1, 1],
                axis: 'X',
                sign: 1,
            }],
        });
        let mut mult: [Vec<f64>; 6] = std::array::from_fn(|_| vec![1.0; 4]);
        let given = [("F*".to_string(), 0.1), ("F1".to_string(), 0.5)];
        apply_multflt(&g, &given, &mut mult);
        assert_eq!(mult[0], [1.0, 1.0, 0.5, 1.0]);
        assert!(mult[1..].iter().all(|m| m == &[1.0; 4]));
    }

    /// A sloping throw: the overlap of a cell and the next column's is a
    /// triangle where their edges cross between the pillars.
    #[test]
    fn overlaps_where_edges_cross() {
        // a: 0..2 on both pillars; b: 1..3 on the first, -1..1 on the second
        let p = overlap([0.0, 2.0, 0.0, 2.0], [1.0, 3.0, -1.0, 1.0]);
        let area = vector_area(&p.iter().map(|q| [q[0], q[1], 0.0]).collect::<Vec<_>>());
        // the parallelogram between z = 0 and 2 clipped by b's strip: 1.5
        assert!((area[2].abs() - 1.5).abs() < 1e-12, "{p:?} {area:?}");
        assert!(overlap([0.0, 1.0, 0.0, 1.0], [1.0, 2.0, 1.0, 2.0]).is_empty());
    }

    #[test]
    fn bulk_volume_of_a_block() {
        let g = CornerPointGrid::cartesian([1, 1, 1], [10.0, 20.0, 5.0]);
        assert!((bulk_volume(&g, 0, 0, 0) - 1000.0).abs() < 1e-9);
    }
}
