#!/usr/bin/env python3
"""orthomesh against Triangle's conforming Delaunay triangulation and its
Voronoi diagram (the Python `triangle` package), on the shared inputs and
on generated ones: time, and the Steiner points each needs.

Triangle ('pD': conforming Delaunay of the PSLG, holes eaten as orthomesh
does) makes its Voronoi diagram conform by inserting Steiner points on the
segments; orthomesh chooses weights instead and inserts none (with
--split-segments, a few where system 3 is infeasible). Times: best of
several runs; Triangle's in-process (the C call through Python, plus
triangle.voronoi of its output vertices), orthomesh's pipeline time from
its report (process start and file writing excluded).

Usage: python3 scripts/bench_triangle.py [--quick | --generated | --goals]   (builds the release CLI)
--quick: the shared inputs and mixed 5; --generated: mixed 5, 20 and 55 alone;
--goals: mixed 20 and 55, seven runs of each tool taken in turn, one line each
"goal mixed N: TRIANGLE_MS BEST_MS MEDIAN_MS" (read by `cargo bench`).
"""
import json
import os
import subprocess
import sys
import tempfile
import time

try:
    import numpy as np
    import triangle
except ImportError:
    sys.exit("bench_triangle.py needs the Python triangle package: pip install triangle")

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CLI = os.path.join(ROOT, "target", "release", "orthomesh")


def records(path):
    out = []
    for line in open(path):
        t = line.split("#")[0].split()
        if t:
            out.append(t)
    return out


def read_poly(path):
    r = records(path)
    nv = int(r[0][0])
    k = 1
    if nv == 0:
        node = records(path[: -len(".poly")] + ".node")
        nv = int(node[0][0])
        vrec = node[1 : 1 + nv]
    else:
        vrec = r[1 : 1 + nv]
        k = 1 + nv
    ids = {int(v[0]): i for i, v in enumerate(vrec)}
    vertices = [(float(v[1]), float(v[2])) for v in vrec]
    ns = int(r[k][0])
    segments = [(ids[int(s[1])], ids[int(s[2])]) for s in r[k + 1 : k + 1 + ns]]
    k += 1 + ns
    holes = []
    if k < len(r):
        nh = int(r[k][0])
        holes = [(float(h[1]), float(h[2])) for h in r[k + 1 : k + 1 + nh]]
    return vertices, segments, holes


def read_edg(path):
    r = records(path)
    index, vertices, segments = {}, [], []
    for s in r[1 : 1 + int(r[0][0])]:
        ends = []
        for p in [(float(s[0]), float(s[1])), (float(s[2]), float(s[3]))]:
            if p not in index:
                index[p] = len(vertices)
                vertices.append(p)
            ends.append(index[p])
        if ends[0] != ends[1]:
            segments.append(tuple(ends))
    return vertices, segments, []


def best(f, runs, budget=2.0):
    times, start, out = [], time.perf_counter(), None
    for _ in range(runs):
        t = time.perf_counter()
        out = f()
        times.append(time.perf_counter() - t)
        if time.perf_counter() - start > budget:
            break
    return min(times) * 1e3, out


def run_triangle(vertices, segments, holes, runs=5):
    data = {"vertices": np.array(vertices), "segments": np.array(segments)}
    if holes:
        data["holes"] = np.array(holes)

    def once():
        t = triangle.triangulate(data, "pDQ")
        triangle.voronoi(t["vertices"])
        return t

    ms, t = best(once, runs)
    return ms, len(t["vertices"]) - len(vertices)


def run_orthomesh(path, extra, runs):
    with tempfile.TemporaryDirectory() as d:
        report = os.path.join(d, "r.json")
        times, rep = [], None
        for _ in range(runs):
            p = subprocess.run(
                [CLI, "conform", path, "-o", os.path.join(d, "m.vtu"), "--report", report,
                 "--allow-sites-outside"] + extra,
                capture_output=True, text=True)
            if p.returncode != 0:
                return None
            rep = json.load(open(report))
            times.append(rep["timing"]["total_ms"])
        return min(times), rep


def goals():
    """mixed 20 and 55: Triangle and orthomesh taken in turn, seven runs each
    (both see the same state of the machine); Triangle's best, orthomesh's
    best and median pipeline time."""
    tmp = tempfile.mkdtemp()
    for n in [20, 55]:
        path = os.path.join(tmp, f"mixed-{n}.poly")
        subprocess.run([CLI, "generate", "mixed", str(n), "-o", path],
                       check=True, capture_output=True)
        vs, ss, hs = read_poly(path)
        tri, ours = [], []
        for _ in range(7):
            tri.append(run_triangle(vs, ss, hs, 1)[0])
            run = run_orthomesh(path, [], 1)
            if run is None:
                sys.exit(f"orthomesh failed on mixed {n}")
            ours.append(run[0])
        ours.sort()
        print(f"goal mixed {n}: {min(tri):.2f} {ours[0]:.2f} {ours[3]:.2f}", flush=True)


def main():
    quick = "--quick" in sys.argv
    subprocess.run(["cargo", "build", "--release", "--quiet"], cwd=ROOT, check=True)
    if "--goals" in sys.argv:
        return goals()
    data = os.path.join(ROOT, "tests", "data", "pslg")
    inputs = [] if "--generated" in sys.argv else [
        os.path.join(data, f) for f in sorted(os.listdir(data)) if f.endswith((".poly", ".edg"))]
    tmp = tempfile.mkdtemp()
    for n in ([5] if quick else [5, 20, 55]):
        path = os.path.join(tmp, f"mixed-{n}.poly")
        subprocess.run([CLI, "generate", "mixed", str(n), "-o", path],
                       check=True, capture_output=True)
        inputs.append(path)
    print("| input | segments | Triangle: Steiner points | Triangle ms | orthomesh ms | "
          "ratio | orthomesh: sites outside | with --split-segments: Steiner points, sites outside |")
    print("|---|---|---|---|---|---|---|---|")
    for path in inputs:
        name = os.path.basename(path)
        vs, ss, hs = (read_edg if path.endswith(".edg") else read_poly)(path)
        tri_ms, steiner = run_triangle(vs, ss, hs)
        big = len(ss) > 10000
        # Best of three even where one run takes seconds: a single run
        # carries the VM's jitter (mixed 20: 490-730 ms from run to run).
        ours = run_orthomesh(path, [], 3 if big else 5)
        if ours is None:
            print(f"| {name} | {len(ss)} | {steiner} | {tri_ms:.2f} | error | | | |")
            continue
        ms, rep = ours
        outside = rep["certificate"]["sites_outside"]
        split_cell = ""
        if outside > 0:
            s = run_orthomesh(path, ["--split-segments"], 1)
            if s is None:
                split_cell = "error"
            else:
                r = s[1]
                split_cell = f"{r.get('split', {}).get('steiner_points', 0)}, {r['certificate']['sites_outside']}"
        print(f"| {name} | {len(ss)} | {steiner} | {tri_ms:.2f} | {ms:.2f} | {ms / tri_ms:.0f} | "
              f"0 Steiner points, {outside} | {split_cell} |")


if __name__ == "__main__":
    main()
