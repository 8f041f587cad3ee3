#!/usr/bin/env python3
"""Runs OPM Flow on a deck that orthomesh wrote (--eclipse) and draws the
pressure at its last report step on the mesh (the VTU written with it, whose
cell array deck_cell maps mesh cells to deck cells), seen from above.

With --original CASE.DATA (the deck a `hybrid --3d` deck carries whole), it
runs both and draws them side by side: pressure and oil saturation at the
chosen report steps on one colour scale each (the hybrid on its mesh, the
original on its grid), then each well's bottom-hole pressure and the
field's cumulative oil, gas and water against time, and prints the field
totals at the end and both run times.

Usage: python3 scripts/simulate.py CASE.DATA MESH.vtu [-o PICTURE.png]
       python3 scripts/simulate.py HYBRID.DATA MESH.vtu --original CASE.DATA
               [--steps 5,20,-1] [-o PREFIX]
       (needs OPM Flow's `flow`, which scripts/setup.sh installs, and the
       Python packages of scripts/requirements-readers.txt)
"""
import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time


def flow(deck, out):
    """Runs Flow; its output folder and the time it took. Flow 2022.10
    refuses padded well names and RPTRST BASIC above 5, which an original
    deck may hold: it runs on a mended copy, as a hybrid deck's writer
    mends them."""
    import re
    text = open(deck).read()
    mended = re.sub(r"BASIC=([6-9])", "BASIC=5", re.sub(r"'([A-Za-z0-9_-]+) +'", r"'\1'", text))
    if mended != text:
        # a copy of the deck's folder (its includes) beside the output
        src, folder = os.path.dirname(os.path.abspath(deck)), out + "-deck"
        shutil.copytree(src, folder, dirs_exist_ok=True)
        deck = os.path.join(folder, os.path.basename(deck))
        os.chmod(deck, 0o644)
        open(deck, "w").write(mended)
    start = time.time()
    # CPR for both runs: ILU(0) alone takes ~60 linear iterations per
    # Newton iteration on hybrid decks (docs/limitations.md)
    run = subprocess.run(
        ["flow", deck, f"--output-dir={out}", "--linear-solver=cpr"], capture_output=True, text=True
    )
    if run.returncode != 0:
        sys.exit(f"simulate.py: flow failed on {deck}:\n{run.stdout[-2000:]}{run.stderr[-2000:]}")
    return os.path.join(out, os.path.splitext(os.path.basename(deck))[0].upper()), time.time() - start


def restart_arrays(stem, key):
    from resdata.resfile import ResdataFile
    if not os.path.exists(stem + ".UNRST"):
        print(f"{stem}: no restart file (the deck asks none: RPTRST), so no maps")
        return []
    r = ResdataFile(stem + ".UNRST")
    if key == "SOIL" and r.num_named_kw("SOIL") == 0:
        # Flow writes the water and gas saturations; oil's is the rest
        water = [r.iget_named_kw("SWAT", n).numpy_copy() for n in range(r.num_named_kw("SWAT"))]
        gas = [r.iget_named_kw("SGAS", n).numpy_copy() for n in range(r.num_named_kw("SGAS"))]
        return [1.0 - w - (gas[n] if gas else 0.0) for n, w in enumerate(water)]
    return [r.iget_named_kw(key, n).numpy_copy() for n in range(r.num_named_kw(key))]


def grid_mesh(stem):
    """The original grid's active cells as a pyvista mesh of hexahedra."""
    import numpy as np
    import pyvista as pv
    from resdata.grid import Grid
    g = Grid(stem + ".EGRID")
    points, cells = [], []
    order = [0, 1, 3, 2, 4, 5, 7, 6]  # resdata's corners to VTK's hexahedron
    for a in range(g.get_num_active()):
        c = [g.get_cell_corner(k, active_index=a) for k in range(8)]
        base = len(points)
        points.extend((x, y, -z) for x, y, z in (c[k] for k in order))
        cells.append([8] + list(range(base, base + 8)))
    return pv.UnstructuredGrid(np.array(cells).ravel(), np.full(len(cells), 12),
                               np.array(points, float))


def side_by_side(a, hybrid, original, mesh):
    import numpy as np
    import pyvista as pv
    cell = mesh.cell_data["deck_cell"] - 1
    grid = grid_mesh(original)
    steps = [int(s) for s in a.steps.split(",")]
    for key, label in [("PRESSURE", "pressure"), ("SOIL", "oil saturation")]:
        ours, theirs = restart_arrays(hybrid, key), restart_arrays(original, key)
        if not ours or not theirs:
            continue
        for s in steps:
            x, y = ours[s], theirs[s]
            lo, hi = min(x.min(), y.min()), max(x.max(), y.max())
            plot = pv.Plotter(off_screen=True, shape=(1, 2), window_size=(2000, 900))
            for col, (m, v, name) in enumerate([(mesh, x[cell], "hybrid"), (grid, y, "original")]):
                plot.subplot(0, col)
                m = m.copy()
                m.cell_data[label] = v
                plot.add_mesh(m, scalars=label, clim=(lo, hi), cmap="viridis")
                plot.add_text(f"{name}: {label}, report step {s % len(ours)}", font_size=11)
                plot.view_xy()
            picture = f"{a.output}-{key.lower()}-{s % len(ours)}.png"
            plot.screenshot(picture)
            print(f"wrote {picture}")


def total(s, key):
    """A field total (FOPT ...) from the summary, else its field rate (FOPR
    ...) or the sum of its wells' rates (WOPR:* ...) times each step's
    length (each rate holds over the step that ends at its time)."""
    import numpy as np
    if s.has_key(key):
        return s.numpy_vector(key)
    rate = key[:-1] + "R"
    if s.has_key(rate):
        r = s.numpy_vector(rate)
    else:
        wells = s.keys("W" + rate[1:] + ":*")
        if not wells:
            return None
        r = sum(s.numpy_vector(k) for k in wells)
    t = np.array([(d - s.start_time).total_seconds() / 86400 for d in s.dates])
    return np.cumsum(r * np.diff(t, prepend=0.0))


def curves(a, hybrid, original):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from resdata.summary import Summary
    ours, theirs = Summary(hybrid), Summary(original)
    wells = sorted(k.split(":")[1] for k in theirs.keys("WBHP:*"))
    fig, ax = plt.subplots(1, 2, figsize=(14, 5))
    days = lambda s: [(d - s.start_time).total_seconds() / 86400 for d in s.dates]
    for w in wells:
        line, = ax[0].plot(days(theirs), theirs.numpy_vector(f"WBHP:{w}"), lw=1)
        if ours.has_key(f"WBHP:{w}"):
            ax[0].plot(days(ours), ours.numpy_vector(f"WBHP:{w}"), "--", color=line.get_color(), lw=1)
    ax[0].set(title="bottom-hole pressure (solid original, dashed hybrid)", xlabel="days")
    for k in ["FOPT", "FGPT", "FWPT", "FWIT"]:
        x, y = total(ours, k), total(theirs, k)
        if x is None or y is None or y[-1] <= 0:
            continue
        line, = ax[1].plot(days(theirs), y, label=f"{k} original")
        ax[1].plot(days(ours), x, "--", color=line.get_color(), label=f"{k} hybrid")
        print(f"{k}: hybrid {x[-1]:.6g}, original {y[-1]:.6g} ({100 * (x[-1] - y[-1]) / y[-1]:+.2f}%)")
    ax[1].set(title="field totals", xlabel="days", yscale="log")
    ax[1].legend()
    picture = f"{a.output}-curves.png"
    fig.savefig(picture, dpi=100, bbox_inches="tight")
    print(f"wrote {picture}")


def compare(a):
    import pyvista as pv
    mesh = pv.read(a.mesh)
    with tempfile.TemporaryDirectory() as tmp:
        hybrid, t1 = flow(a.deck, os.path.join(tmp, "hybrid"))
        original, t0 = flow(a.original, os.path.join(tmp, "original"))
        print(f"Flow: the hybrid deck in {t1:.1f} s, the original in {t0:.1f} s ({t1 / t0:.1f}x)")
        a.output = a.output or os.path.splitext(a.deck)[0]
        curves(a, hybrid, original)
        side_by_side(a, hybrid, original, mesh)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("deck")
    ap.add_argument("mesh")
    ap.add_argument("-o", "--output", help="picture (default: CASE.png beside the deck)")
    ap.add_argument("--original", help="the deck the hybrid deck carries: run and draw both")
    ap.add_argument("--steps", default="-1", help="report steps to draw (with --original)")
    a = ap.parse_args()
    if shutil.which("flow") is None:
        sys.exit("simulate.py: OPM Flow (`flow`) is not installed: bash scripts/setup.sh installs it")
    if a.original:
        return compare(a)
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
