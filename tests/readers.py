"""Reads every .vtu the Rust tests wrote with the readers users run, and
fails loudly on anything they would trip on: vtk (vtkCellValidator state 0
for every cell), pyvista, meshio; polygons counter-clockwise, cell data present."""
import sys, pathlib
import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy
import pyvista as pv
import meshio

def check(path):
    r = vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(str(path))
    r.Update()
    grid = r.GetOutput()
    n = grid.GetNumberOfCells()
    assert n > 0, f"{path}: no cells"
    v = vtk.vtkCellValidator()
    v.SetInputData(grid)
    v.Update()
    states = vtk_to_numpy(v.GetOutput().GetCellData().GetArray("ValidityState"))
    bad = np.nonzero(states)[0]
    assert len(bad) == 0, f"{path}: vtkCellValidator flags cells {bad[:10]} states {states[bad[:10]]}"
    for name in ("site", "weight", "site_inside"):
        assert grid.GetCellData().GetArray(name) is not None, f"{path}: no cell array {name}"

    m = pv.read(path)
    assert m.n_cells == n, f"{path}: pyvista reads {m.n_cells} cells, vtk {n}"
    assert set(np.unique(m.celltypes)) == {7}, f"{path}: cell types {np.unique(m.celltypes)}"
    pts = np.asarray(m.points)
    assert np.all(pts[:, 2] == 0.0)

    mm = meshio.read(path)
    total = sum(len(b.data) for b in mm.cells)
    assert total == n, f"{path}: meshio reads {total} cells, vtk {n}"
    # Counter-clockwise, no repeated vertices (VTK does not flag these).
    for block in mm.cells:
        for cell in block.data:
            assert len(set(cell)) == len(cell), f"{path}: repeated vertex in {cell}"
            xy = mm.points[cell, :2] - mm.points[cell[0], :2]  # relative: map coordinates cancel
            area = 0.5 * np.sum(xy[:, 0] * np.roll(xy[:, 1], -1) - np.roll(xy[:, 0], -1) * xy[:, 1])
            assert area > 0, f"{path}: clockwise or flat polygon {cell}"
    return n

def main(folder):
    files = sorted(pathlib.Path(folder).rglob("*.vtu"))
    assert files, f"no .vtu files under {folder}: did the Rust tests run?"
    for f in files:
        print(f"readers ok: {f.name}: {check(f)} cells")
    print(f"{len(files)} meshes read cleanly by vtk, pyvista and meshio")

if __name__ == "__main__":
    main(sys.argv[1])
