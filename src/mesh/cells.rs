//! What a mesh writer takes: points, cells (polygons or polyhedra) and
//! named cell arrays. Every mesh of the crate (2D, 3D, hybrid, 2.5D) gives
//! one, so that each format has one writer.

/// Cells as point ids.
#[derive(Debug, Clone)]
pub enum Cells {
    /// Counter-clockwise polygons (z = 0).
    Polygons(Vec<Vec<u32>>),
    /// Polyhedra: per cell its faces, each counter-clockwise seen from
    /// outside.
    Polyhedra(Vec<Vec<Vec<u32>>>),
}

/// Values of a cell array, per cell `components` of them.
#[derive(Debug, Clone)]
pub enum Values {
    /// Doubles.
    Float(Vec<f64>),
    /// Integers.
    Int(Vec<i64>),
    /// Points of the plane, written as 3D points with z = 0.
    Planar(Vec<[f64; 2]>),
}

/// A named cell array.
#[derive(Debug, Clone)]
pub struct CellArray {
    /// Its name in the file.
    pub name: &'static str,
    /// Values per cell; None: one, and left unsaid in the file.
    pub components: Option<usize>,
    /// The values, cell after cell.
    pub values: Values,
}

impl CellArray {
    /// An array of doubles.
    pub fn float(name: &'static str, components: usize, values: Vec<f64>) -> CellArray {
        CellArray {
            name,
            components: Some(components),
            values: Values::Float(values),
        }
    }

    /// An array of integers.
    pub fn int(name: &'static str, components: usize, values: Vec<i64>) -> CellArray {
        CellArray {
            name,
            components: Some(components),
            values: Values::Int(values),
        }
    }

    /// Per cell, 1-based grid indices (i, j, k), or -1s for cells outside
    /// the grid.
    pub fn ijk(values: impl Iterator<Item = Option<[usize; 3]>>) -> CellArray {
        let one_based = |c: Option<[usize; 3]>| c.map_or([-1; 3], |c| c.map(|x| x as i64 + 1));
        CellArray::int("ijk", 3, values.flat_map(one_based).collect())
    }
}

/// A mesh as its writers see it.
#[derive(Debug, Clone)]
pub struct CellMesh {
    /// The points (z = 0 for 2D meshes).
    pub points: Vec<[f64; 3]>,
    /// The cells.
    pub cells: Cells,
    /// Cell arrays, in the order they are written.
    pub data: Vec<CellArray>,
    /// The array a viewer shows first.
    pub scalars: &'static str,
}

/// Polygons (point ids, all turning the same way) that share edges, joined
/// into the one polygon they make; None where they make more than one
/// boundary (apart, or with a hole).
pub fn join(polys: &[Vec<u32>]) -> Option<Vec<u32>> {
    let mut edges: std::collections::BTreeSet<(u32, u32)> = Default::default();
    for p in polys {
        for k in 0..p.len() {
            let e = (p[k], p[(k + 1) % p.len()]);
            if !edges.remove(&(e.1, e.0)) {
                edges.insert(e);
            }
        }
    }
    let next: std::collections::BTreeMap<u32, u32> = edges.iter().copied().collect();
    let start = edges.iter().next()?.0;
    if next.len() != edges.len() {
        return None;
    }
    let mut cycle = vec![start];
    let mut at = next[&start];
    while at != start && cycle.len() <= next.len() {
        cycle.push(at);
        at = *next.get(&at)?;
    }
    (cycle.len() == next.len()).then_some(cycle)
}

#[cfg(test)]
mod tests {
    use super::join;

    #[test]
    fn squares_sharing_an_edge_join() {
        // 3 2 5
        // 0 1 4
        let j = join(&[vec![0, 1, 2, 3], vec![1, 4, 5, 2]]).unwrap();
        let at = j.iter().position(|&x| x == 0).unwrap();
        let turned: Vec<u32> = (0..j.len()).map(|k| j[(at + k) % j.len()]).collect();
        assert_eq!(turned, vec![0, 1, 4, 5, 2, 3]);
        // apart: two boundaries
        assert_eq!(join(&[vec![0, 1, 2], vec![3, 4, 5]]), None);
        assert_eq!(join(&[]), None);
    }
}
