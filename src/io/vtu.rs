//! VTK XML UnstructuredGrid (.vtu), classic layout, ASCII: polygons (type 7),
//! counter-clockwise, z = 0. Doubles are written in their shortest
//! round-trip form, so they read back exactly.

use crate::mesh::Mesh;
use std::fmt::Write;

/// A cell array of integers with 1 or more components per cell.
pub struct IntArray<'a> {
    pub name: &'a str,
    pub components: usize,
    pub values: Vec<i64>,
}

/// A cell array of doubles with 1 or more components per cell.
pub struct FloatArray<'a> {
    pub name: &'a str,
    pub components: usize,
    pub values: Vec<f64>,
}

/// The .vtu text of polyhedra (type 42), classic faces/faceoffsets
/// layout: per cell its faces, each a list of point ids counter-clockwise
/// seen from outside; with the given cell data (`scalars` names the
/// active one). A vertex where a face runs straight on is left out of that
/// face (see `corners`).
pub fn polyhedra(
    points: &[[f64; 3]],
    cells: &[Vec<Vec<u32>>],
    floats: &[FloatArray],
    ints: &[IntArray],
    scalars: &str,
) -> String {
    let cells: Vec<Vec<Vec<u32>>> = cells
        .iter()
        .map(|faces| faces.iter().map(|f| corners(points, f)).collect())
        .collect();
    let mut s = String::new();
    begin(&mut s, points, cells.len());
    s.push_str("</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n");
    let mut offsets = vec![];
    let mut n = 0;
    for faces in &cells {
        let mut ids: Vec<u32> = faces.iter().flatten().copied().collect();
        ids.sort_unstable();
        ids.dedup();
        n += ids.len();
        offsets.push(n);
        let line: Vec<String> = ids.iter().map(u32::to_string).collect();
        let _ = writeln!(s, "{}", line.join(" "));
    }
    s.push_str("</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n");
    for o in offsets {
        let _ = writeln!(s, "{o}");
    }
    s.push_str("</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n");
    for _ in &cells {
        s.push_str("42\n");
    }
    s.push_str("</DataArray>\n<DataArray type=\"Int64\" Name=\"faces\" format=\"ascii\">\n");
    let mut face_offsets = vec![];
    let mut total = 0;
    for faces in &cells {
        let mut line = vec![faces.len().to_string()];
        for f in faces {
            line.push(f.len().to_string());
            line.extend(f.iter().map(u32::to_string));
        }
        total += line.len();
        face_offsets.push(total);
        let _ = writeln!(s, "{}", line.join(" "));
    }
    s.push_str("</DataArray>\n<DataArray type=\"Int64\" Name=\"faceoffsets\" format=\"ascii\">\n");
    for o in face_offsets {
        let _ = writeln!(s, "{o}");
    }
    let _ = write!(
        s,
        "</DataArray>\n</Cells>\n<CellData Scalars=\"{scalars}\">\n"
    );
    let floats = floats.iter().map(|a| {
        let text = |x: &f64| format!("{x:e}");
        (
            "Float64",
            a.name,
            a.components,
            a.values.iter().map(text).collect::<Vec<_>>(),
        )
    });
    let ints = ints.iter().map(|a| {
        let text = |x: &i64| x.to_string();
        (
            "Int64",
            a.name,
            a.components,
            a.values.iter().map(text).collect::<Vec<_>>(),
        )
    });
    for (ty, name, components, values) in floats.chain(ints) {
        let _ = writeln!(
            s,
            "<DataArray type=\"{ty}\" Name=\"{name}\" NumberOfComponents=\"{components}\" format=\"ascii\">"
        );
        for c in values.chunks(components) {
            let _ = writeln!(s, "{}", c.join(" "));
        }
        s.push_str("</DataArray>\n");
    }
    s.push_str("</CellData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n");
    s
}

/// The .vtu text of a 2D mesh, with cell data `site` (3 components),
/// `weight` (power(x) = |x - site|^2 - weight) and `site_inside` (0/1).
pub fn to_string(mesh: &Mesh, site_inside: &[bool]) -> String {
    let inside = IntArray {
        name: "site_inside",
        components: 1,
        values: site_inside.iter().map(|&b| i64::from(b)).collect(),
    };
    to_string_with(mesh, &[inside])
}

/// The file's start up to the points (written exactly), leaving the
/// Points element open.
pub(crate) fn begin(s: &mut String, points: &[[f64; 3]], cells: usize) {
    let _ = write!(
        s,
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n\
         <UnstructuredGrid>\n<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{cells}\">\n<Points>\n\
         <DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n",
        points.len()
    );
    for p in points {
        if p[2] == 0.0 {
            let _ = writeln!(s, "{:e} {:e} 0", p[0], p[1]);
        } else {
            let _ = writeln!(s, "{:e} {:e} {:e}", p[0], p[1], p[2]);
        }
    }
}

/// The .vtu text of a 2D mesh with `site`, `weight` and the given arrays.
pub fn to_string_with(mesh: &Mesh, arrays: &[IntArray]) -> String {
    let mut s = String::with_capacity(64 * (mesh.points.len() + mesh.cells.len()));
    let n_conn: usize = mesh.cells.iter().map(Vec::len).sum();
    let points: Vec<[f64; 3]> = mesh.points.iter().map(|p| [p[0], p[1], 0.0]).collect();
    begin(&mut s, &points, mesh.cells.len());
    s.push_str("</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n");
    for c in &mesh.cells {
        let line: Vec<String> = c.iter().map(u32::to_string).collect();
        let _ = writeln!(s, "{}", line.join(" "));
    }
    s.push_str("</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n");
    let mut off = 0;
    for c in &mesh.cells {
        off += c.len();
        let _ = writeln!(s, "{off}");
    }
    debug_assert_eq!(off, n_conn);
    s.push_str("</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n");
    for _ in &mesh.cells {
        s.push_str("7\n");
    }
    s.push_str("</DataArray>\n</Cells>\n<CellData Scalars=\"weight\">\n");
    s.push_str(
        "<DataArray type=\"Float64\" Name=\"site\" NumberOfComponents=\"3\" format=\"ascii\">\n",
    );
    for p in &mesh.sites {
        let _ = writeln!(s, "{:e} {:e} 0", p[0], p[1]);
    }
    s.push_str("</DataArray>\n<DataArray type=\"Float64\" Name=\"weight\" format=\"ascii\">\n");
    for w in &mesh.weights {
        let _ = writeln!(s, "{w:e}");
    }
    for a in arrays {
        let _ = write!(
            s,
            "</DataArray>\n<DataArray type=\"Int64\" Name=\"{}\" NumberOfComponents=\"{}\" format=\"ascii\">\n",
            a.name, a.components
        );
        for c in a.values.chunks(a.components) {
            let line: Vec<String> = c.iter().map(i64::to_string).collect();
            let _ = writeln!(s, "{}", line.join(" "));
        }
    }
    s.push_str("</DataArray>\n</CellData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n");
    s
}

/// A face without the vertices where it runs straight on (to 1e-10 in
/// angle): a power vertex of a neighbouring cell in the middle of this
/// cell's edge is exactly on that edge, but rounded to doubles it makes the
/// face slightly non-convex, and vtk's convexity test has no tolerance
/// (vtkCellValidator then flags the cell, state 32). The neighbour keeps
/// it as its corner.
fn corners(points: &[[f64; 3]], face: &[u32]) -> Vec<u32> {
    let n = face.len();
    let p = |k: usize| nalgebra::Vector3::from(points[face[k % n] as usize]);
    let kept: Vec<u32> = (0..n)
        .filter(|&k| {
            let (a, b) = (p(k + n) - p(k + n - 1), p(k + 1) - p(k));
            a.cross(&b).norm() > 1e-10 * a.norm() * b.norm() || a.dot(&b) < 0.0
        })
        .map(|k| face[k])
        .collect();
    if kept.len() < 3 {
        face.to_vec()
    } else {
        kept
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coordinates_read_back_exactly() {
        let x = 0.1 + 0.2;
        let mesh = Mesh {
            points: vec![[x, 1e-300], [1.0, 0.0], [0.0, 1.0]],
            cells: vec![vec![0, 1, 2]],
            sites: vec![[0.3, 0.3]],
            weights: vec![-0.0],
            ..Default::default()
        };
        let text = to_string(&mesh, &[true]);
        let line = text
            .lines()
            .find(|l| l.ends_with(" 0") && l.contains("e-300"))
            .unwrap();
        let v: Vec<f64> = line
            .split_whitespace()
            .map(|t| t.parse().unwrap())
            .collect();
        assert_eq!(v[0], x);
        assert_eq!(v[1], 1e-300);
        assert!(text.contains("<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n7\n"));
    }

    #[test]
    fn straight_vertices_leave_faces() {
        // the unit square with a point on its bottom edge, off by rounding
        let pts = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.5, 1e-17, 0.0],
        ];
        assert_eq!(corners(&pts, &[0, 4, 1, 2, 3]), vec![0, 1, 2, 3]);
        assert_eq!(corners(&pts, &[4, 1, 2, 3, 0]), vec![1, 2, 3, 0]);
        // a real corner stays
        let mut bent = pts;
        bent[4][1] = -0.1;
        assert_eq!(corners(&bent, &[0, 4, 1, 2, 3]), vec![0, 4, 1, 2, 3]);
    }
}
