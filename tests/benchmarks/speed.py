#!/usr/bin/env python3
"""Speed of compute_partial_symmetries beside MeshLab's own curvature filter (issue 6).

    python tests/benchmarks/speed.py [--only NAME ...] [--large] [--threads N] [--json FILE]

For each benchmark mesh it runs, each in a fresh process (so that peak memory is that run's
alone), pymeshlab's `compute_curvature_principal_directions_per_vertex` (the yardstick) and
the filter with its DEFAULT parameters on the same mesh, and prints a table like the paper's
Table 1: vertices, faces, the filter's stage seconds (signatures, pairing, clustering,
verification; "other" is the rest: building the mesh structures, presmoothing, outputs), its
total, the yardstick, their ratio, the symmetries found and the peak RSS of the filter's process
and of the yardstick's (each process loads the mesh into pymeshlab first).

The meshes (built once into tests/data/speed/, git-ignored):

* armadillo_160k: the armadillo of tests/real_models.json (a real scan), Loop-subdivided and
  decimated back to 320,000 faces (160,002 vertices), as in the issue's measurement;
* facade_120: a generated facade: a wall slab with 10 x 12 window frames, each frame an exact
  copy built from boxes (about 150,000 vertices): many repeated parts, CAD-like;
* armadillo_2m and armadillo_3m (with --large): the same scan at 2,000,000 and 3,000,000
  faces (the largest inputs issue 10 asks the filter to finish, with their memory).

With --curves DIR it also draws the two curves of issue 6 as PNG files in DIR, from runs of
the same kind (each point a fresh process for the filter and one for the yardstick):

* speed_vs_size.png: time against faces for one shape, the armadillo scan re-tessellated
  (subdivided, then decimated) at 10,000 ... 2,000,000 faces (--curve-faces sets the sizes);
* speed_vs_parts.png: time against the number of repeated parts, facades of 1 ... 120
  identical windows (each window 1,500 faces; the wall slab 76,800 faces whatever its size, so
  the mesh grows from 78,300 to 256,800 faces; below 50,000 vertices it is analysed whole,
  above on its simplified copy, as the filter's defaults do).

It measures and does not assert: the exit status is 0 unless a run fails.
"""
import argparse
import json
import os
import subprocess
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
TESTS = os.path.dirname(HERE)
sys.path.insert(0, TESTS)
DATA = os.path.join(TESTS, "data", "speed")
STAGES = ("signatures", "pairing", "clustering", "verification")


# ----------------------------------------------------------------------------------------
# The benchmark meshes
# ----------------------------------------------------------------------------------------

def subdivided_scan(name: str, faces: int, path: str) -> None:
    """A real scan at `faces` faces: Loop subdivision until it has twice as many, then
    quadric edge collapse down to the count (so the tessellation is irregular, as a scan's)."""
    import pymeshlab
    import real_models
    model = next(m for m in real_models.real_models() if m.name == name)
    V, F = model.load()
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(V, F), name)
    while ms.current_mesh().face_number() < 2 * faces:
        ms.meshing_surface_subdivision_loop(iterations=1, threshold=pymeshlab.PercentageValue(0))
    ms.meshing_decimation_quadric_edge_collapse(targetfacenum=faces)
    ms.save_current_mesh(path, save_vertex_color=False, save_vertex_quality=False)


def facade(columns: int = 10, rows: int = 12, path: str = "") -> None:
    """A wall with columns x rows identical window frames standing on it."""
    import pymeshlab
    import scenes
    parts = []
    cell = np.array([1.0, 1.4])                      # spacing of the windows (x, y)
    wall = np.array([columns * cell[0] + 0.6, rows * cell[1] + 0.6, 0.3])
    parts.append(_moved(scenes.box_mesh(wall, n=80), [0, 0, -wall[2] / 2]))
    for (size, centre) in _window_pieces():
        piece = scenes.box_mesh(size, n=5)
        for i in range(columns):
            for j in range(rows):
                origin = np.array([(i - (columns - 1) / 2) * cell[0], (j - (rows - 1) / 2) * cell[1], 0])
                parts.append(_moved(piece, origin + centre))
    V = np.concatenate([p[0] for p in parts])
    offsets = np.cumsum([0] + [len(p[0]) for p in parts[:-1]])
    F = np.concatenate([p[1] + o for p, o in zip(parts, offsets)])
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(V, F), "facade")
    ms.save_current_mesh(path, save_vertex_color=False, save_vertex_quality=False)


def _window_pieces():
    """(size, centre) of the boxes of one window: two jambs, head, sill (asymmetric, deeper
    and wider than the head, so a window has no mirror of its own across the horizontal) and
    a mullion off the centre (no vertical mirror either)."""
    w, h, d = 0.7, 1.0, 0.12
    return [((0.08, h, d), (-w / 2, 0, d / 2)), ((0.08, h, d), (w / 2, 0, d / 2)),
            ((w + 0.08, 0.08, d), (0, h / 2, d / 2)), ((w + 0.2, 0.1, 2 * d), (0, -h / 2 - 0.05, d)),
            ((0.05, h - 0.08, d / 2), (0.12, 0, d / 4))]


def _moved(mesh, t):
    V, F = mesh
    return V + np.asarray(t, float), F


MESHES = {
    "armadillo_160k": lambda path: subdivided_scan("armadillo", 320_000, path),
    "facade_120": lambda path: facade(path=path),
}
LARGE = {"armadillo_2m": lambda path: subdivided_scan("armadillo", 2_000_000, path),
         "armadillo_3m": lambda path: subdivided_scan("armadillo", 3_000_000, path)}


# The curves' meshes: the scan at a number of faces, facades of columns x rows windows.
CURVE_FACES = (10_000, 30_000, 100_000, 320_000, 1_000_000, 2_000_000)
CURVE_FACADES = ((1, 1), (2, 2), (3, 4), (5, 6), (8, 9), (10, 12))


def curve_builder(name: str):
    """The builder of a curve mesh from its name: armadillo_f<faces> or facade_<c>x<r>."""
    if name.startswith("armadillo_f"):
        return lambda path: subdivided_scan("armadillo", int(name[len("armadillo_f"):]), path)
    if name.startswith("facade_") and "x" in name:
        columns, rows = (int(k) for k in name[len("facade_"):].split("x"))
        return lambda path: facade(columns, rows, path)
    return None


def mesh_path(name: str) -> str:
    """The benchmark mesh's file, built first if missing.  It is built in a child process:
    on Linux a child's peak RSS counts that of the process it was forked from, so a parent
    that had held a 6-million-face subdivision would report 6.4 GB for every later run."""
    path = os.path.join(DATA, name + ".ply")
    if not os.path.exists(path):
        os.makedirs(DATA, exist_ok=True)
        print(f"building {name} ...", file=sys.stderr, flush=True)
        subprocess.run([sys.executable, os.path.abspath(__file__), "--build", name, path + ".tmp.ply"], check=True)
        os.replace(path + ".tmp.ply", path)
    return path


# ----------------------------------------------------------------------------------------
# One run in a child process
# ----------------------------------------------------------------------------------------

def child(which: str, path: str) -> None:
    """Runs the yardstick or the filter on `path` and prints its figures as JSON."""
    import pymeshlab
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(path)
    out = {"vertices": ms.current_mesh().vertex_number(), "faces": ms.current_mesh().face_number()}
    if which == "yardstick":
        t = time.perf_counter()
        ms.compute_curvature_principal_directions_per_vertex()
        out["seconds"] = time.perf_counter() - t
    else:
        import meshlab_symmetry  # noqa: F401  (binds MeshSet.compute_partial_symmetries)
        t = time.perf_counter()
        r = ms.compute_partial_symmetries()
        out["seconds"] = time.perf_counter() - t
        out["symmetries"] = int(r["symmetry_count"])
        for s in STAGES:
            out[s] = float(r["seconds_" + s])
    print(json.dumps(out))


def run_child(which: str, path: str, threads: int):
    """The child's figures and its peak resident memory (MB)."""
    env = dict(os.environ)
    if threads:
        env["OMP_NUM_THREADS"] = str(threads)
    proc = subprocess.Popen([sys.executable, os.path.abspath(__file__), "--child", which, path],
                            stdout=subprocess.PIPE, env=env, text=True)
    stdout = proc.stdout.read()
    _, status, usage = os.wait4(proc.pid, 0)
    proc.returncode = os.waitstatus_to_exitcode(status)
    if proc.returncode != 0:
        raise SystemExit(f"the {which} run on {path} failed (exit {proc.returncode})")
    figures = json.loads(stdout.strip().splitlines()[-1])
    figures["peak_mb"] = usage.ru_maxrss / 1024.0  # kilobytes on Linux
    return figures


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--only", nargs="+", metavar="NAME", help="only these meshes")
    ap.add_argument("--large", action="store_true", help="also the 2- and 3-million-face meshes")
    ap.add_argument("--threads", type=int, default=0, help="OMP_NUM_THREADS of the runs (0: default)")
    ap.add_argument("--json", help="write the figures to this file")
    ap.add_argument("--curves", metavar="DIR", help="also draw speed_vs_size.png and speed_vs_parts.png in DIR")
    ap.add_argument("--curve-faces", type=int, nargs="+", default=list(CURVE_FACES), metavar="FACES",
                    help="the scan's sizes for the size curve")
    ap.add_argument("--child", nargs=2, help=argparse.SUPPRESS)
    ap.add_argument("--build", nargs=2, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.child:
        return child(*args.child)
    if args.build:
        name, path = args.build
        return (dict(MESHES, **LARGE).get(name) or curve_builder(name))(path)
    meshes = dict(MESHES, **(LARGE if args.large else {}))
    names = [n for n in meshes if not args.only or n in args.only]

    print_head()
    rows = [measure(name, args.threads) for name in names]
    if args.curves:
        sizes = [measure(f"armadillo_f{faces}", args.threads) for faces in args.curve_faces]
        parts = [measure(f"facade_{c}x{r}", args.threads) for c, r in CURVE_FACADES]
        draw_curves(args.curves, sizes, parts)
        rows += sizes + parts
    if args.json:
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=1)


def print_head() -> None:
    head = (f"{'mesh':<16} {'verts':>8} {'faces':>8} " + " ".join(f"{s[:6]:>6}" for s in STAGES)
            + f" {'other':>6} {'filter':>7} {'yard':>6} {'ratio':>6} {'sym':>4} {'peakMB':>7} {'yardMB':>7}")
    print(head)
    print("-" * len(head))


def measure(name: str, threads: int) -> dict:
    """The yardstick and the filter on one mesh, each in a process of its own; prints the row."""
    path = mesh_path(name)
    yard = run_child("yardstick", path, threads)
    run = run_child("filter", path, threads)
    other = run["seconds"] - sum(run[s] for s in STAGES)
    ratio = run["seconds"] / yard["seconds"]
    print(f"{name:<16} {run['vertices']:>8} {run['faces']:>8} "
          + " ".join(f"{run[s]:>6.2f}" for s in STAGES)
          + f" {other:>6.2f} {run['seconds']:>7.2f} {yard['seconds']:>6.2f} {ratio:>6.1f} "
          f"{run['symmetries']:>4} {run['peak_mb']:>7.0f} {yard['peak_mb']:>7.0f}", flush=True)
    return dict(name=name, filter=run, yardstick=yard, ratio=ratio)


def draw_curves(directory: str, sizes: list, parts: list) -> None:
    """speed_vs_size.png (log-log: seconds against faces, the filter's stages stacked beside
    the yardstick) and speed_vs_parts.png (seconds against the number of windows)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    os.makedirs(directory, exist_ok=True)

    def plot(rows, x, xlabel, title, filename, log):
        fig, ax = plt.subplots(figsize=(6.4, 4.2), dpi=110)
        ax.plot(x, [r["filter"]["seconds"] for r in rows], "o-", label="filter (whole)")
        ax.plot(x, [r["filter"]["verification"] for r in rows], "s--", label="verification")
        ax.plot(x, [r["filter"]["clustering"] for r in rows], "^--", label="clustering")
        ax.plot(x, [r["yardstick"]["seconds"] for r in rows], "k:", marker="x",
                label="yardstick: curvature filter")
        if log:
            ax.set_xscale("log")
            ax.set_yscale("log")
        ax.set_xlabel(xlabel)
        ax.set_ylabel("seconds")
        ax.set_title(title, fontsize=10)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(os.path.join(directory, filename))
        plt.close(fig)

    plot(sizes, [r["filter"]["faces"] for r in sizes], "faces",
         "armadillo scan re-tessellated, default parameters", "speed_vs_size.png", log=True)
    plot(parts, [int(np.prod([int(k) for k in r["name"][len("facade_"):].split("x")])) for r in parts],
         "identical windows on the facade", "facades of repeated windows, default parameters",
         "speed_vs_parts.png", log=False)


if __name__ == "__main__":
    main()
