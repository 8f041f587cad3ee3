//! VTK XML UnstructuredGrid (.vtu), classic layout, ASCII: polygons (type 7,
//! counter-clockwise, z = 0) or polyhedra (type 42, faces/faceoffsets),
//! with named cell arrays. Doubles are written in their shortest round-trip
//! form, so they read back exactly.

use crate::mesh::{CellArray, CellMesh, Cells, Values};
use std::collections::BTreeSet;
use std::fmt::Write;

/// The .vtu text of a mesh. Polyhedra faces lose the vertices where they
/// run straight on (see `corners`).
pub fn to_string(mesh: &CellMesh) -> String {
    let n = match &mesh.cells {
        Cells::Polygons(c) => c.len(),
        Cells::Polyhedra(c) => c.len(),
    };
    let mut s = String::with_capacity(64 * (mesh.points.len() + n));
    begin(&mut s, &mesh.points, n);
    s.push_str("</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n");
    match &mesh.cells {
        Cells::Polygons(cells) => polygons(&mut s, cells),
        Cells::Polyhedra(cells) => polyhedra(&mut s, &mesh.points, cells),
    }
    let _ = write!(
        s,
        "</DataArray>\n</Cells>\n<CellData Scalars=\"{}\">\n",
        mesh.scalars
    );
    for a in &mesh.data {
        array(&mut s, a);
    }
    s.push_str("</CellData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n");
    s
}

/// Connectivity, offsets and types of polygons.
fn polygons(s: &mut String, cells: &[Vec<u32>]) {
    for c in cells {
        let line: Vec<String> = c.iter().map(u32::to_string).collect();
        let _ = writeln!(s, "{}", line.join(" "));
    }
    s.push_str("</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n");
    let mut off = 0;
    for c in cells {
        off += c.len();
        let _ = writeln!(s, "{off}");
    }
    s.push_str("</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n");
    for _ in cells {
        s.push_str("7\n");
    }
}

/// Connectivity, offsets, types, faces and face offsets of polyhedra.
fn polyhedra(s: &mut String, points: &[[f64; 3]], cells: &[Vec<Vec<u32>>]) {
    let cells: Vec<Vec<Vec<u32>>> = cells
        .iter()
        .map(|faces| {
            let joined = coplanar_joined(points, faces);
            // a point another face of the cell turns at stays in each face
            let turns: BTreeSet<u32> = joined
                .iter()
                .flat_map(|f| corners(points, f, &Default::default()))
                .collect();
            joined.iter().map(|f| corners(points, f, &turns)).collect()
        })
        .collect();
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
}

/// One cell array, a line per cell.
fn array(s: &mut String, a: &CellArray) {
    let ty = match a.values {
        Values::Int(_) => "Int64",
        Values::Float(_) | Values::Planar(_) => "Float64",
    };
    let name = a.name;
    match a.components {
        Some(c) => {
            let _ = writeln!(
                s,
                "<DataArray type=\"{ty}\" Name=\"{name}\" NumberOfComponents=\"{c}\" format=\"ascii\">"
            );
        }
        None => {
            let _ = writeln!(
                s,
                "<DataArray type=\"{ty}\" Name=\"{name}\" format=\"ascii\">"
            );
        }
    }
    let per = a.components.unwrap_or(1);
    match &a.values {
        Values::Float(v) => {
            for c in v.chunks(per) {
                let line: Vec<String> = c.iter().map(|x| format!("{x:e}")).collect();
                let _ = writeln!(s, "{}", line.join(" "));
            }
        }
        Values::Int(v) => {
            for c in v.chunks(per) {
                let line: Vec<String> = c.iter().map(i64::to_string).collect();
                let _ = writeln!(s, "{}", line.join(" "));
            }
        }
        Values::Planar(v) => {
            for p in v {
                let _ = writeln!(s, "{:e} {:e} 0", p[0], p[1]);
            }
        }
    }
    s.push_str("</DataArray>\n");
}

/// The file's start up to the points (written exactly), leaving the
/// Points element open.
fn begin(s: &mut String, points: &[[f64; 3]], cells: usize) {
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

/// A cell's faces, those in one plane that share an edge joined into one
/// (the mesh keeps them apart where they face two cells). Otherwise a
/// point where they meet a third face's edge would be left there as a
/// corner of theirs and taken out of the third face by `corners`, and vtk
/// would find their edges unpaired.
fn coplanar_joined(points: &[[f64; 3]], faces: &[Vec<u32>]) -> Vec<Vec<u32>> {
    use nalgebra::Vector3;
    let p = |v: u32| Vector3::from(points[v as usize]);
    let planes: Vec<(Vector3<f64>, Vector3<f64>)> = faces
        .iter()
        .map(|f| {
            let pts: Vec<[f64; 3]> = f.iter().map(|&v| points[v as usize]).collect();
            let plane = crate::geom::Plane::of(&pts);
            (Vector3::from(plane.origin), Vector3::from(plane.unit))
        })
        .collect();
    let size = faces
        .iter()
        .flatten()
        .map(|&v| (p(v) - p(faces[0][0])).norm())
        .fold(0.0, f64::max);
    let mut group: Vec<usize> = (0..faces.len()).collect();
    for i in 0..faces.len() {
        for j in 0..i {
            let (o, n) = planes[j];
            let flat = n.dot(&planes[i].1) > 1.0 - 1e-12
                && faces[i]
                    .iter()
                    .all(|&v| n.dot(&(p(v) - o)).abs() <= 1e-9 * size);
            let (a, b) = (&faces[i], &faces[j]);
            let shared = || {
                (0..a.len()).any(|k| {
                    let (x, y) = (a[k], a[(k + 1) % a.len()]);
                    (0..b.len()).any(|l| b[l] == y && b[(l + 1) % b.len()] == x)
                })
            };
            if flat && shared() {
                let (gi, gj) = (group[i], group[j]);
                group.iter_mut().filter(|g| **g == gi).for_each(|g| *g = gj);
            }
        }
    }
    let mut out = vec![];
    for g in 0..faces.len() {
        let members: Vec<Vec<u32>> = (0..faces.len())
            .filter(|&f| group[f] == g)
            .map(|f| faces[f].clone())
            .collect();
        match members.len() {
            0 => {}
            1 => out.extend(members),
            _ => match crate::mesh::join(&members) {
                Some(f) => out.push(f),
                None => out.extend(members),
            },
        }
    }
    out
}

/// A face without the vertices where it runs straight on (to 1e-7 in
/// angle): a power vertex of a neighbouring cell in the middle of this
/// cell's edge is exactly on that edge, but rounded to doubles it makes the
/// face slightly non-convex, and vtk's convexity test has no tolerance
/// (vtkCellValidator then flags the cell, state 32). The neighbour keeps
/// it as its corner, and so does this face where another face of the cell
/// turns at it (in `keep`: else the cell has a hanging point, state 1).
fn corners(points: &[[f64; 3]], face: &[u32], keep: &BTreeSet<u32>) -> Vec<u32> {
    let n = face.len();
    let p = |k: usize| nalgebra::Vector3::from(points[face[k % n] as usize]);
    let kept: Vec<u32> = (0..n)
        .filter(|&k| {
            let (a, b) = (p(k + n) - p(k + n - 1), p(k + 1) - p(k));
            // the sine of the turn: layered cells' points, found by
            // cutting planes and welded within 1e-7 of the block, leave 1e-8
            keep.contains(&face[k])
                || a.cross(&b).norm() > 1e-7 * a.norm() * b.norm()
                || a.dot(&b) < 0.0
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
    use crate::mesh::Mesh;

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
        let text = to_string(&mesh.cells(&[true]));
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
    fn coplanar_faces_join() {
        // a unit cube whose bottom is two faces (toward two cells): points
        // 0-3 bottom, 4-7 top, 8 and 9 halve the bottom's front and back
        let mut pts = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        pts.extend(pts.clone().iter().map(|p| [p[0], p[1], 1.0]));
        pts.push([0.5, 0.0, 0.0]);
        pts.push([0.5, 1.0, 0.0]);
        let faces = vec![
            vec![0, 9, 8],
            vec![0, 3, 9],
            vec![8, 9, 2, 1],
            vec![4, 5, 6, 7],
            vec![0, 8, 1, 5, 4],
            vec![2, 9, 3, 7, 6],
            vec![1, 2, 6, 5],
            vec![0, 4, 7, 3],
        ];
        let joined = coplanar_joined(&pts, &faces);
        assert_eq!(joined.len(), 6);
        assert!(joined.contains(&vec![0, 3, 9, 2, 1, 8]), "{joined:?}");
        // every edge left is paired
        let faces: Vec<Vec<u32>> = joined
            .iter()
            .map(|f| corners(&pts, f, &BTreeSet::new()))
            .collect();
        for f in &faces {
            for k in 0..f.len() {
                let (x, y) = (f[k], f[(k + 1) % f.len()]);
                let back = faces
                    .iter()
                    .filter(|g| (0..g.len()).any(|l| g[l] == y && g[(l + 1) % g.len()] == x));
                assert_eq!(back.count(), 1, "edge {x}-{y}");
            }
        }
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
        let none = BTreeSet::new();
        assert_eq!(corners(&pts, &[0, 4, 1, 2, 3], &none), vec![0, 1, 2, 3]);
        assert_eq!(corners(&pts, &[4, 1, 2, 3, 0], &none), vec![1, 2, 3, 0]);
        // but where another face of the cell turns at it
        let turns = BTreeSet::from([4]);
        assert_eq!(corners(&pts, &[0, 4, 1, 2, 3], &turns), vec![0, 4, 1, 2, 3]);
        // a real corner stays
        let mut bent = pts;
        bent[4][1] = -0.1;
        assert_eq!(corners(&bent, &[0, 4, 1, 2, 3], &none), vec![0, 4, 1, 2, 3]);
    }
}
