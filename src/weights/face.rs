//! The maximal faces of a 3D complex the weights must put in the regular
//! triangulation, and how a polygon's triangles are found there.

/// A maximal face of the complex: it must be a face of the regular
/// triangulation, and of the power diagram of the sites.
#[derive(Debug, Clone, PartialEq)]
pub struct Face {
    /// One vertex (an isolated point), two (a dangling segment), three (a
    /// triangle), or more (a convex polygon kept whole, in cycle order).
    pub vertices: Vec<u32>,
    /// Its facet (index into `Complex3::facets`); None for a point on no
    /// facet.
    pub facet: Option<u32>,
    /// On a facet the mesh is cut at (a clip facet): it need not cross its
    /// dual, so it has no system 3 rows.
    pub cut: bool,
}

impl Face {
    /// 0, 1 or 2.
    pub fn dim(&self) -> usize {
        self.vertices.len().min(3) - 1
    }
}

/// A triangle's vertices sorted (the key of `Tetrahedralisation::triangle_apexes`).
pub(crate) fn sorted3(v: &[u32]) -> [u32; 3] {
    let mut t = [v[0], v[1], v[2]];
    t.sort_unstable();
    t
}

/// The triangles of RT among a polygon's vertices (sorted triples).
pub(crate) fn fan(vs: &[u32], tris: &crate::FastMap<[u32; 3], Vec<u32>>) -> Vec<[u32; 3]> {
    let mut out = vec![];
    for a in 0..vs.len() {
        for b in a + 1..vs.len() {
            for c in b + 1..vs.len() {
                let t = sorted3(&[vs[a], vs[b], vs[c]]);
                if tris.contains_key(&t) {
                    out.push(t);
                }
            }
        }
    }
    out
}
