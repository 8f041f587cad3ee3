//! The faces of the 3D site diagram, stored once. Each edge of the sites'
//! regular triangulation has a dual face, a cycle of power vertices (or
//! none, where the face is unbounded). Cells name their faces by number
//! and orientation instead of holding copies: a Vec per face, once in the
//! edge map and once in each of its two cells, was most of the site
//! diagram's memory on `generate field3`.

/// A face's number for an unbounded face (no polygon).
const UNBOUNDED: u32 = u32::MAX;

/// The dual faces of a triangulation's edges. Edges are kept per site as
/// sorted adjacency lists (a hash map of edges, built and read in random
/// order, was a tenth of the 3D pipeline on 10^5 facet triangles).
#[derive(Debug, Clone)]
pub struct Faces {
    /// Site a's neighbours b > a are `nbr[start[a]..start[a + 1]]`,
    /// ascending; edge i's face is number `num[i]`.
    start: Vec<u32>,
    nbr: Vec<u32>,
    num: Vec<u32>,
    /// Face k is `verts[at[k]..at[k + 1]]`.
    at: Vec<u32>,
    verts: Vec<u32>,
}

/// One face of a cell: the face's number, whether the cell sees its cycle
/// reversed (so that it turns counter-clockwise seen from outside), and the
/// site across it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Side {
    pub face: u32,
    pub reversed: bool,
    pub other: u32,
}

impl Default for Faces {
    fn default() -> Faces {
        Faces::with_edges(vec![])
    }
}

impl Faces {
    /// Frees the edges, keeping the faces' cycles (what cells read).
    pub fn drop_edges(&mut self) {
        (self.start, self.nbr, self.num) = (vec![0], vec![], vec![]);
    }

    /// The edges of `n` sites, as each site's neighbours above it
    /// (ascending), their faces to be pushed in that order.
    pub fn with_edges(above: Vec<Vec<u32>>) -> Faces {
        let mut start = Vec::with_capacity(above.len() + 1);
        start.push(0);
        let mut nbr = Vec::with_capacity(above.iter().map(Vec::len).sum());
        for list in above {
            nbr.extend(list);
            start.push(nbr.len() as u32);
        }
        Faces {
            start,
            num: Vec::with_capacity(nbr.len()),
            nbr,
            at: vec![0],
            verts: vec![],
        }
    }

    /// Every edge, in order (a ascending, then b).
    pub fn edges(&self) -> impl Iterator<Item = [u32; 2]> + '_ {
        (0..self.start.len() - 1).flat_map(move |a| {
            let (lo, hi) = (self.start[a] as usize, self.start[a + 1] as usize);
            self.nbr[lo..hi].iter().map(move |&b| [a as u32, b])
        })
    }

    /// Adds the face of the next edge (None: unbounded).
    pub fn push(&mut self, face: Option<&[u32]>) {
        let k = match face {
            Some(face) => {
                self.verts.extend_from_slice(face);
                self.at.push(self.verts.len() as u32);
                (self.at.len() - 2) as u32
            }
            None => UNBOUNDED,
        };
        self.num.push(k);
    }

    /// Edge e's place in `nbr`.
    fn find(&self, e: &[u32; 2]) -> Option<usize> {
        let a = e[0] as usize;
        let (lo, hi) = (
            *self.start.get(a)? as usize,
            *self.start.get(a + 1)? as usize,
        );
        let i = self.nbr[lo..hi].iter().position(|&b| b == e[1])?;
        Some(lo + i)
    }

    /// Face k's cycle of power vertices.
    pub fn polygon(&self, k: u32) -> &[u32] {
        &self.verts[self.at[k as usize] as usize..self.at[k as usize + 1] as usize]
    }

    /// Face k's cycle, None where it is unbounded.
    fn cycle(&self, k: u32) -> Option<&[u32]> {
        (k != UNBOUNDED).then(|| self.polygon(k))
    }

    /// The face of edge e (sorted pair): None where e is no edge,
    /// Some(None) where its face is unbounded.
    pub fn get(&self, e: &[u32; 2]) -> Option<Option<&[u32]>> {
        self.numbered(e).map(|(_, face)| face)
    }

    /// The face's number of edge e (UNBOUNDED where none), and its cycle.
    pub fn numbered(&self, e: &[u32; 2]) -> Option<(u32, Option<&[u32]>)> {
        let k = self.num[self.find(e)?];
        Some((k, self.cycle(k)))
    }

    /// Every edge with its face, in edge order.
    pub fn iter(&self) -> impl Iterator<Item = ([u32; 2], Option<&[u32]>)> {
        self.edges()
            .zip(&self.num)
            .map(|(e, &k)| (e, self.cycle(k)))
    }

    /// A side's cycle as the cell sees it.
    pub fn side(&self, s: &Side) -> impl DoubleEndedIterator<Item = u32> + ExactSizeIterator + '_ {
        let p = self.polygon(s.face);
        let (n, rev) = (p.len(), s.reversed);
        (0..n).map(move |i| p[if rev { n - 1 - i } else { i }])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn faces_are_stored_once_and_read_either_way() {
        let mut f = Faces::with_edges(vec![vec![1, 2], vec![2], vec![]]);
        f.push(Some(&[4, 5, 6]));
        f.push(None);
        f.push(Some(&[7, 8, 9, 10]));
        assert_eq!(f.get(&[0, 1]), Some(Some(&[4, 5, 6][..])));
        assert_eq!(f.get(&[0, 2]), Some(None));
        assert_eq!(f.get(&[0, 3]), None);
        assert_eq!(f.get(&[5, 6]), None);
        let (k, _) = f.numbered(&[1, 2]).unwrap();
        let side = |reversed| Side {
            face: k,
            reversed,
            other: 2,
        };
        assert_eq!(f.side(&side(false)).collect::<Vec<_>>(), [7, 8, 9, 10]);
        assert_eq!(f.side(&side(true)).collect::<Vec<_>>(), [10, 9, 8, 7]);
        assert_eq!(f.side(&side(true)).len(), 4);
        assert_eq!(f.iter().count(), 3);
        assert_eq!(f.edges().collect::<Vec<_>>(), [[0, 1], [0, 2], [1, 2]]);
    }
}
