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
