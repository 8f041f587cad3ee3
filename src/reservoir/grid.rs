//! The corner-point grid model (Eclipse's COORD/ZCORN geometry), as the
//! GRDECL reader gives it.

/// A face of a fault: cells i1..=i2, j1..=j2, k1..=k2 (0-based) and the side.
#[derive(Debug, Clone, PartialEq)]
pub struct FaultFace {
    /// Columns I (first, last).
    pub i: [usize; 2],
    /// Columns J (first, last).
    pub j: [usize; 2],
    /// Layers K (first, last).
    pub k: [usize; 2],
    /// 'X', 'Y' or 'Z' with a sign: +1 for X / X+ / I / I+, -1 for X- ...
    pub axis: char,
    /// +1 or -1: the side of the cells the face is on.
    pub sign: i8,
}

impl FaultFace {
    /// The face of its cells it names: 0 to 5 for I-, I+, J-, J+, K-, K+.
    pub fn side(&self) -> usize {
        match (self.axis, self.sign) {
            ('X', 1) => 1,
            ('X', _) => 0,
            ('Y', 1) => 3,
            ('Y', _) => 2,
            ('Z', 1) => 5,
            _ => 4,
        }
    }
}

/// A named fault.
#[derive(Debug, Clone, PartialEq)]
pub struct Fault {
    /// Its name.
    pub name: String,
    /// Its faces.
    pub faces: Vec<FaultFace>,
}

/// A corner-point grid.
#[derive(Debug, Clone)]
pub struct CornerPointGrid {
    /// Columns along x.
    pub nx: usize,
    /// Columns along y.
    pub ny: usize,
    /// Layers.
    pub nz: usize,
    /// Pillars (nx+1)(ny+1), index j (nx+1) + i: top (x, y, z), bottom (x, y, z).
    pub coord: Vec<[f64; 6]>,
    /// 8 nx ny nz depths (see `corner`).
    pub zcorn: Vec<f64>,
    /// Per cell i + nx (j + ny k).
    pub actnum: Vec<bool>,
    /// `X1 Y1 X0 Y0 X2 Y2`, when given (not applied).
    pub mapaxes: Option<[f64; 6]>,
    /// Faults (FAULTS).
    pub faults: Vec<Fault>,
}

/// The six faces' corners (c = di + 2 dj + 4 b, b = 1 at the bottom), each
/// counter-clockwise seen from outside a right-handed cell, in the order
/// I-, I+, J-, J+, top, bottom.
pub(crate) const FACES: [[usize; 4]; 6] = [
    [0, 2, 6, 4],
    [1, 5, 7, 3],
    [0, 4, 5, 1],
    [2, 3, 7, 6],
    [0, 1, 3, 2],
    [4, 6, 7, 5],
];

impl CornerPointGrid {
    /// A Cartesian block grid of nx x ny x nz cells of size dx, dy, dz,
    /// all active, from the origin, depth increasing with k.
    pub fn cartesian(n: [usize; 3], d: [f64; 3]) -> CornerPointGrid {
        let depths: Vec<f64> = (0..=n[2]).map(|k| k as f64 * d[2]).collect();
        CornerPointGrid::layered([n[0], n[1]], [d[0], d[1]], &depths)
    }

    /// A block of nx x ny columns of size dx, dy whose layers' tops and
    /// bottom are at the given depths (increasing), all active.
    pub fn layered(n: [usize; 2], d: [f64; 2], depths: &[f64]) -> CornerPointGrid {
        let [nx, ny] = n;
        let nz = depths.len().saturating_sub(1);
        let bottom = depths.last().copied().unwrap_or(0.0);
        let top = depths.first().copied().unwrap_or(0.0);
        let coord = (0..=ny)
            .flat_map(|j| {
                (0..=nx).map(move |i| {
                    let (x, y) = (i as f64 * d[0], j as f64 * d[1]);
                    [x, y, top, x, y, bottom]
                })
            })
            .collect();
        let mut zcorn = vec![0.0; 8 * nx * ny * nz];
        for k in 0..nz {
            for b in 0..2 {
                let z = depths[k + b];
                for r in 0..4 * nx * ny {
                    zcorn[(2 * k + b) * 4 * nx * ny + r] = z;
                }
            }
        }
        CornerPointGrid {
            nx,
            ny,
            nz,
            coord,
            zcorn,
            actnum: vec![true; nx * ny * nz],
            mapaxes: None,
            faults: vec![],
        }
    }

    /// The index of cell (i, j, k) in ACTNUM's order.
    pub fn cell_index(&self, i: usize, j: usize, k: usize) -> usize {
        i + self.nx * (j + self.ny * k)
    }

    /// Whether cell (i, j, k) is active.
    pub fn active(&self, i: usize, j: usize, k: usize) -> bool {
        self.actnum[self.cell_index(i, j, k)]
    }

    /// Corner c of cell (i, j, k), numbered as resdata does:
    /// c = di + 2 dj + 4 b (b = 1 at the bottom). x, y come from the
    /// corner's pillar, interpolated linearly at the corner's depth.
    pub fn corner(&self, i: usize, j: usize, k: usize, c: usize) -> [f64; 3] {
        let (di, dj) = (c & 1, (c >> 1) & 1);
        self.on_pillar(i + di, j + dj, self.depth(i, j, k, c))
    }

    /// The depth of corner c of cell (i, j, k) (its ZCORN value).
    pub fn depth(&self, i: usize, j: usize, k: usize, c: usize) -> f64 {
        let (di, dj, b) = (c & 1, (c >> 1) & 1, c >> 2);
        let (nx, ny) = (self.nx, self.ny);
        self.zcorn[((((2 * k + b) * ny + j) * 2 + dj) * nx + i) * 2 + di]
    }

    /// The point of pillar (i, j) (0..=nx, 0..=ny) at a depth, interpolated
    /// linearly between its ends.
    pub fn on_pillar(&self, i: usize, j: usize, z: f64) -> [f64; 3] {
        let p = self.coord[j * (self.nx + 1) + i];
        let (dz, t) = (p[5] - p[2], z - p[2]);
        let f = if dz != 0.0 { t / dz } else { 0.0 };
        [p[0] + f * (p[3] - p[0]), p[1] + f * (p[4] - p[1]), z]
    }
}
