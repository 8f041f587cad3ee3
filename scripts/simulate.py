#!/usr/bin/env python3
"""Runs OPM Flow on a deck that orthomesh wrote (--eclipse) and draws the
pressure at its last report step on the mesh (the VTU written with it, whose
cell array deck_cell maps mesh cells to deck cells), seen from above.

Usage: python3 scripts/simulate.py CASE.DATA MESH.vtu [-o PICTURE.png]
       (needs OPM Flow's `flow`, which scripts/setup.sh installs, and the
       Python packages of scripts/requirements-readers.txt)
"""
import argparse
import os
import shutil
import subprocess
import sys


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("deck")
    ap.add_argument("mesh")
    ap.add_argument("-o", "--output", help="picture (default: CASE.png beside the deck)")
    a = ap.parse_args()
    if shutil.which("flow") is None:
        sys.exit("simulate.py: OPM Flow (`flow`) is not installed: bash scripts/setup.sh installs it")
    import pyvista as pv
    from resdata.resfile import ResdataFile

    stem = os.path.splitext(a.deck)[0]
    out = stem + ".flow"
    run = subprocess.run(["flow", a.deck, f"--output-dir={out}"], capture_output=True, text=True)
    if run.returncode != 0:
        sys.exit(f"simulate.py: flow failed on {a.deck}:\n{run.stdout[-2000:]}{run.stderr[-2000:]}")
    restart = ResdataFile(os.path.join(out, os.path.basename(stem).upper() + ".UNRST"))
    steps = restart.num_named_kw("PRESSURE")
    pressure = restart.iget_named_kw("PRESSURE", steps - 1).numpy_copy()
    mesh = pv.read(a.mesh)
    if "deck_cell" not in mesh.cell_data:
        sys.exit(f"simulate.py: {a.mesh} has no deck_cell array (write it with the deck)")
    cell = mesh.cell_data["deck_cell"] - 1
    if len(pressure) != cell.max() + 1:
        sys.exit(f"simulate.py: the deck has {len(pressure)} cells, the mesh maps {cell.max() + 1}")
    mesh.cell_data["pressure (bar)"] = pressure[cell]
    picture = a.output or stem + ".png"
    plot = pv.Plotter(off_screen=True, window_size=(1200, 1000))
    plot.add_mesh(mesh, scalars="pressure (bar)", show_edges=True, edge_color="grey",
                  line_width=0.5, cmap="viridis")
    plot.add_text(f"{os.path.basename(a.deck)}: pressure at the end of the run",
                  font_size=12)
    plot.view_xy()
    plot.screenshot(picture)
    print(f"wrote {picture}: pressure {pressure.min():.2f} to {pressure.max():.2f} bar "
          f"over {len(pressure)} cells")


if __name__ == "__main__":
    main()
