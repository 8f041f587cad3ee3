"""Hybrid decks that carry their input deck whole (tests/carry.rs wrote
them to DIR/decks/carried/NAME/ with a sidecar), checked in OPM Flow's own
files against the original deck's:

- a dry run of each writes its INIT: every reservoir cell's pore volume and
  every connection between two reservoir cells (TRANX folded, NNCs) equal
  the original's within 1e-6; every cell's region numbers (SATNUM,
  EQLNUM, PVTNUM, FIPNUM) its host cell's;
- the small regions deck runs to its end beside the original: field oil
  and water totals within 2% of the original's, printed side by side with
  the well's BHP and the run times (SPE9's run beside its original is
  scripts/simulate.py's: docs/limitations.md says why).

decks.py calls `check(DIR)`.
"""
import glob
import json
import os
import shutil
import subprocess
import tempfile
import time

import numpy as np
import resfo

from decks import flow_init


def pairs(init, active_of):
    """Flow's connections between cells of a dry run: TRANX/Y/Z between
    Cartesian neighbours, and the NNCs, by pair of global cells."""
    nx, ny, _ = init["DIMS"]
    out = {}
    for ax, name in enumerate(["TRANX", "TRANY", "TRANZ"]):
        step = [1, nx, nx * ny][ax]
        t = init[name]
        for c, a in active_of.items():
            if t[a] > 0:
                out[(c, c + step)] = out.get((c, c + step), 0.0) + float(t[a])
    none = np.zeros(0, int)
    for a, b, t in zip(init.get("NNC1", none) - 1, init.get("NNC2", none) - 1, init.get("TRANNNC", [])):
        key = (int(min(a, b)), int(max(a, b)))
        out[key] = out.get(key, 0.0) + float(t)
    return out


def dry(deck):
    init = flow_init(deck)
    act = init["ACTNUM"] > 0
    init["ACTIVE_OF"] = {int(c): int(init["ACTIVE"][c]) for c in np.nonzero(act)[0]}
    return init


def far_field(name, side, hyb, orig):
    reservoir = {int(p): int(g) for p, g in side["reservoir"]}
    cell_of = {g: p for p, g in reservoir.items()}
    # pore volumes
    pv = [(hyb["PORV"][hyb["ACTIVE_OF"][p]], orig["PORV"][orig["ACTIVE_OF"][g]])
          for p, g in reservoir.items() if p in hyb["ACTIVE_OF"] and g in orig["ACTIVE_OF"]]
    pv = np.array(pv)
    rel = np.abs(pv[:, 0] - pv[:, 1]) / pv[:, 1]
    print(f"{name}: {len(pv)} reservoir cells' pore volumes against the original's: largest "
          f"relative difference {rel.max():.2e}")
    assert rel.max() <= 1e-6, f"{name}: pore volumes differ by {rel.max():.2e}"
    # transmissibilities between reservoir cells
    ours = pairs(hyb, hyb["ACTIVE_OF"])
    theirs = pairs(orig, orig["ACTIVE_OF"])
    both = [(a, b) for a, b in theirs if a in cell_of and b in cell_of]
    got = []
    for a, b in both:
        p, q = cell_of[a], cell_of[b]
        got.append((ours.get((min(p, q), max(p, q)), 0.0), theirs[(a, b)]))
    got = np.array(got)
    rel = np.abs(got[:, 0] - got[:, 1]) / got[:, 1]
    within = (rel <= 1e-6).mean()
    print(f"{name}: {len(got)} connections between reservoir cells in Flow's INIT of the hybrid "
          f"deck against the original's: {100 * within:.3f}% within 1e-6 (largest {rel.max():.2e})")
    assert within >= 0.999, f"{name}: {100 * within:.3f}% within 1e-6"


def regions(name, side, hyb, orig):
    host = side["host"]
    for key in ["SATNUM", "EQLNUM", "PVTNUM", "FIPNUM"]:
        if key not in hyb or key not in orig:
            continue
        bad = sum(1 for p, a in hyb["ACTIVE_OF"].items()
                  if hyb[key][a] != orig[key][orig["ACTIVE_OF"][host[p]]])
        values = sorted(set(int(v) for v in hyb[key]))
        print(f"{name}: {key} {values} on {len(hyb['ACTIVE_OF'])} cells, {bad} differ from their host's")
        assert bad == 0, f"{name}: {bad} cells' {key} differ from their host cell's"


def run(deck):
    """Runs Flow on a deck in a scratch copy of its folder (the mending of
    flow_init); its summary vectors at the end and its time."""
    from resdata.summary import Summary
    with tempfile.TemporaryDirectory() as tmp:
        src = os.path.dirname(deck)
        for f in os.listdir(src):
            if os.path.isfile(os.path.join(src, f)):
                shutil.copy(os.path.join(src, f), tmp)
        copy = os.path.join(tmp, os.path.basename(deck))
        start = time.time()
        p = subprocess.run(["flow", copy, f"--output-dir={tmp}/out"], capture_output=True, text=True)
        took = time.time() - start
        assert p.returncode == 0, f"{deck}: flow failed:\n{p.stdout[-2000:]}"
        stem = os.path.splitext(os.path.basename(deck))[0].upper()
        s = Summary(f"{tmp}/out/{stem}")
        return {k: s.numpy_vector(k)[-1] for k in s.keys()}, took


def compare_runs(name, side):
    ours, t1 = run(side["deck"])
    theirs, t0 = run(side["original"])
    for k in ["FOPT", "FWPT", "FGPT", "FWIT"]:
        if k in theirs and theirs[k] > 0:
            d = (ours[k] - theirs[k]) / theirs[k]
            print(f"{name}: {k} hybrid {ours[k]:.6g}, original {theirs[k]:.6g} ({100 * d:+.2f}%)")
    for k in sorted(x for x in theirs if x.startswith("WBHP")):
        print(f"{name}: {k} at the end: hybrid {ours[k]:.2f}, original {theirs[k]:.2f}")
    print(f"{name}: Flow ran the hybrid deck in {t1:.1f} s, the original in {t0:.1f} s ({t1 / t0:.1f}x)")
    for k in ["FOPT", "FWPT"]:
        d = abs(ours[k] - theirs[k]) / theirs[k]
        assert d <= 0.02, f"{name}: {k} {100 * d:.2f}% off the original's"


def check(root):
    for side_path in sorted(glob.glob(os.path.join(root, "decks", "carried", "*", "carried.json"))):
        side = json.load(open(side_path))
        name = os.path.basename(os.path.dirname(side_path))
        hyb, orig = dry(side["deck"]), dry(side["original"])
        far_field(name, side, hyb, orig)
        regions(name, side, hyb, orig)
        if name == "regions":
            compare_runs(name, side)
