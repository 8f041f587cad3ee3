//! The faces of the 3D site diagram, stored once. Each edge of the sites'
//! regular triangulation has a dual face, a cycle of power vertices (or
//! none, where the face is unbounded). Cells name their faces by number
//! and orientation instead of holding copies: a Vec per face, once in the
//! edge map and once in each of its two cells, was most of the site
//! diagram's memory on `generate field3`.

use crate::FastMap as HashMap;

/// A face's number for an unbounded face (no polygon).
const UNBOUNDED: u32 = u32::MAX;

/// The dual faces of a triangulation's edges.
#[derive(Debug, Clone)]
pub struct Faces {
    /// Per edge (sorted pair of sites), its face's number.
    pub index: HashMap<[u32; 2], u32>,
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
        Faces {
            index: HashMap::default(),
            at: vec![0],
            verts: vec![],
        }
    }
}

impl Faces {
    /// Adds the face of edge e (None: unbounded).
    pub fn push(&mut self, e: [u32; 2], face: Option<&[u32]>) {
        let k = match face {
            Some(face) => {
                self.verts.extend_from_slice(face);
                self.at.push(self.verts.len() as u32);
                (self.at.len() - 2) as u32
            }
            None => UNBOUNDED,
        };
        self.index.insert(e, k);
    }

    /// Face k's cycle of power vertices.
    pub fn polygon(&self, k: u32) -> &[u32] {
        &self.verts[self.at[k as usize] as usize..self.at[k as usize + 1] as usize]
    }

    /// Face k's cycle, None where it is unbounded.
    fn cycle(&self, k: u32) -> Option<&[u32]> {
        (k != UNBOUNDED).then(|| self.polygon(k))
    }

    /// The face of edge e: None where e is no edge, Some(None) where its
    /// face is unbounded.
    pub fn get(&self, e: &[u32; 2]) -> Option<Option<&[u32]>> {
        self.index.get(e).map(|&k| self.cycle(k))
    }

    /// The face's number of edge e (UNBOUNDED where none), and its cycle.
    pub fn numbered(&self, e: &[u32; 2]) -> Option<(u32, Option<&[u32]>)> {
        self.index.get(e).map(|&k| (k, self.cycle(k)))
    }

    /// Every edge with its face, in the map's order.
    pub fn iter(&self) -> impl Iterator<Item = (&[u32; 2], Option<&[u32]>)> {
        self.index.iter().map(|(e, &k)| (e, self.cycle(k)))
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
        let mut f = Faces::default();
        f.push([0, 1], Some(&[4, 5, 6]));
        f.push([0, 2], None);
        f.push([1, 2], Some(&[7, 8, 9, 10]));
        assert_eq!(f.get(&[0, 1]), Some(Some(&[4, 5, 6][..])));
        assert_eq!(f.get(&[0, 2]), Some(None));
        assert_eq!(f.get(&[0, 3]), None);
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
    }
}
