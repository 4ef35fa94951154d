#!/usr/bin/env python3
"""Benchmark: the global mirror planes of CAD models as users have them.

    python tests/benchmarks/cad_mirrors.py [--built N] [--no-catalog] [--peer PATH]
                                           [--only NAME ... | --every K] [--out FILE]

Two sets of models, each run through compute_partial_symmetries at its defaults:

* built: CAD-like models assembled from parts (tests/cad_models.py: chairs, tables, lamps,
  cars, airplanes, vessels; N of each, seeds 0..N-1), tessellated coarsely and stored
  double-sided.  Their planes are known by construction.
* catalog: the chairs, tables, lamps and vehicles of a furniture catalog package
  (tests/cad_catalog.json; fetched by tests/fetch_real_models.sh), every triangle stored once
  more the other way round, as shape collections store them.  Their planes were measured by
  the brute-force oracle tests/oracle_mirror.py (tests/record_cad_catalog.py); a plane counts
  when 90 % of the surface maps within 1 % of the diagonal under it.

A plane is found when a reported reflection lies within FOUND_DEG degrees and FOUND_OFFSET of
the diagonal of it.  On a body of revolution (the oracle's planes all pass through one line,
at least REVOLUTION_PLANES of them) a rotational family reported about that line stands for
its planes: the filter reports such a body as one family, not as a mirror per plane.

With --peer, Kazhdan's ShapeSymmetry (the global descriptor users compare against; build it
with ../shared/peers/build_shapesph.sh) runs on the same files at resolution 128: a plane is
found by it when one of the three deepest minima of its reflective descriptor, a plane
through the area centroid, lies within PEER_DEG degrees of it (its grid's spacing) and
FOUND_OFFSET.

It prints a row per model and totals, and writes them to --out (default
tests/benchmarks/results/cad_mirrors.txt), overwritten by each run.  It measures and does not
assert.
"""
import argparse
import math
import os
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
import cad_models  # noqa: E402
import real_models  # noqa: E402

FOUND_DEG = 1.0
FOUND_OFFSET = 0.01
REVOLUTION_PLANES = 5
PEER_RESOLUTION = 128
PEER_MINIMA = 3
PEER_DEG = 360.0 / PEER_RESOLUTION
DEFAULT_OUT = os.path.join(HERE, "results", "cad_mirrors.txt")


class Truth:
    """A model's global planes, each (normal, offset, point on it), and its axis when it is
    a body of revolution."""

    def __init__(self, planes, diagonal, axis=None):
        self.planes = planes
        self.diagonal = diagonal
        self.axis = axis


def plane_error(T, normal, offset, point, diagonal):
    """(degrees, offset fraction) of a reported reflection from a plane (real_models' rule)."""
    plane = real_models.Plane(tuple(normal), float(offset), tuple(point), {})
    return real_models.mirror_angle_error(T, plane, diagonal)


def axis_in_plane(axis, normal, offset, diagonal):
    """Whether a line (point, direction) lies in a plane within FOUND_DEG and FOUND_OFFSET."""
    q, e = np.asarray(axis[:3]), np.asarray(axis[3:])
    tilt = math.degrees(math.asin(min(1.0, abs(float(np.dot(e, normal))))))
    return tilt <= FOUND_DEG and abs(float(np.dot(q, normal)) - offset) / diagonal <= FOUND_OFFSET


def revolution_axis(planes):
    """The common line of the planes when there are enough of them through one line."""
    if len(planes) < REVOLUTION_PLANES:
        return None
    N = np.array([p[0] for p in planes])
    e = np.linalg.svd(N)[2][-1]                  # the direction every normal is normal to
    if np.abs(N @ e).max() > math.sin(math.radians(FOUND_DEG)):
        return None
    q = np.linalg.lstsq(np.vstack([N, e]), np.r_[[p[1] for p in planes], 0.0], rcond=None)[0]
    return np.concatenate([q, e])


# -- the two sets ----------------------------------------------------------------------------

def built_models(per_category):
    for m in cad_models.models(per_category):
        c = (m.vertices[m.faces[:, 0]] + m.vertices[m.faces[:, 1]] + m.vertices[m.faces[:, 2]]) / 3
        planes = [(n, d, c.mean(0) - (n @ c.mean(0) - d) * n) for n, d in m.planes]
        yield m.name, "built", m.vertices, m.faces, m.parts, Truth(planes, m.diagonal)


def catalog_models():
    for m in real_models.cad_catalog_models():
        V, F = m.load()
        planes = [(np.asarray(p.normal), p.offset, np.asarray(p.point)) for p in m.global_planes()]
        if not planes:
            continue
        truth = Truth(planes, m.diagonal, revolution_axis([(p[0], p[1]) for p in planes]))
        yield m.name, "catalog", V, cad_models.double_sided(F), component_count(F, len(V)), truth


def component_count(F, n):
    """The connected components of the faces (V holds only vertices they use)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    e = np.concatenate([F[:, [0, 1]], F[:, [1, 2]]])
    return connected_components(coo_matrix((np.ones(len(e)), (e[:, 0], e[:, 1])), (n, n)), directed=False)[0]


# -- the filter and the peer ------------------------------------------------------------------

def run_filter(V, F):
    """(reflections, rotational axes, refusal or None, seconds)."""
    import pymeshlab
    import meshlab_symmetry  # noqa: F401  (binds MeshSet.compute_partial_symmetries)
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(V, F.astype(np.int32)), "model")
    t = time.perf_counter()
    try:
        out = ms.compute_partial_symmetries()
    except pymeshlab.PyMeshLabException as e:
        return [], [], str(e).splitlines()[0], time.perf_counter() - t
    seconds = time.perf_counter() - t
    n = int(out["symmetry_count"])
    T = np.asarray(out["transforms"], float).reshape(n, 4, 4)
    kinds = np.asarray(out["continuous_kinds"], int).reshape(n)
    axes = np.asarray(out["continuous_axes"], float).reshape(n, 6)
    reflection = np.asarray(out["is_reflection"], int).reshape(n) != 0
    return list(T[reflection & (kinds == 0)]), list(axes[kinds == 1]), None, seconds


def write_ply(path, V, F):
    with open(path, "wb") as f:
        f.write((f"ply\nformat binary_little_endian 1.0\nelement vertex {len(V)}\n"
                 "property float x\nproperty float y\nproperty float z\n"
                 f"element face {len(F)}\nproperty list uchar int vertex_indices\nend_header\n").encode())
        f.write(np.asarray(V, "<f4").tobytes())
        rows = np.empty(len(F), dtype=[("n", "u1"), ("v", "<i4", (3,))])
        rows["n"], rows["v"] = 3, F
        f.write(rows.tobytes())


def grid_directions(res):
    """The unit directions of the peer's spherical grid, in its value order (values[x*res+y]
    holds theta index y, phi index x)."""
    x, y = np.meshgrid(np.arange(res), np.arange(res), indexing="ij")
    theta, phi = 2 * np.pi * y / res, np.pi * (2 * x + 1) / (2 * res)
    return np.stack([np.sin(phi) * np.cos(theta), np.cos(phi), np.sin(phi) * np.sin(theta)], -1).reshape(-1, 3)


def peer_planes(binary, V, F):
    """The peer's PEER_MINIMA deepest local minima as planes through the area centroid, and
    its seconds (the process, reading the file included)."""
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "model.ply")
        write_ply(path, V, F)
        t = time.perf_counter()
        subprocess.run([binary, "--in", path, "--out", os.path.join(d, "out"), "--res", str(PEER_RESOLUTION)],
                       check=True, capture_output=True)
        seconds = time.perf_counter() - t
        raw = open(os.path.join(d, "out.ref.sgrid"), "rb").read()
    res = int(np.frombuffer(raw[:4], "<i4")[0])
    values = np.frombuffer(raw[4:4 + 4 * res * res], "<f4").astype(float)
    dirs = grid_directions(res)
    # a local minimum: no lower value within 1.6 grid steps, a plane and its flip being one
    from scipy.spatial import cKDTree
    tree, chord = cKDTree(dirs), 2 * math.sin(math.radians(0.8 * 360.0 / res))
    lowest = [min(values[tree.query_ball_point(s * dirs[i], chord)].min() for s in (1, -1)) for i in range(len(dirs))]
    minima = [i for i in np.argsort(values) if values[i] <= lowest[i]]
    chosen = []
    for i in minima:
        if all(abs(dirs[i] @ dirs[j]) < math.cos(math.radians(5)) for j in chosen):
            chosen.append(i)
        if len(chosen) == PEER_MINIMA:
            break
    A = np.linalg.norm(np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]), axis=1)
    c = (V[F].mean(1) * A[:, None]).sum(0) / A.sum()
    return [(dirs[i], float(dirs[i] @ c)) for i in chosen], seconds


def peer_found(planes, normal, offset, point, diagonal):
    for n, d in planes:
        T = real_models.oracle_mirror.reflection_matrix(n, d)
        angle, off = plane_error(T, normal, offset, point, diagonal)
        if angle <= PEER_DEG and off <= FOUND_OFFSET:
            return True
    return False


# -- the table ---------------------------------------------------------------------------------

def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--built", type=int, default=5, metavar="N", help="built models per category (0: none)")
    ap.add_argument("--no-catalog", action="store_true", help="only the built models")
    ap.add_argument("--peer", help="path of a ShapeSymmetry binary, run side by side")
    ap.add_argument("--only", nargs="+", metavar="NAME", help="only these models")
    ap.add_argument("--every", type=int, default=1, metavar="K", help="every K-th model of each set only")
    ap.add_argument("--out", default=DEFAULT_OUT, help="the result file this run writes")
    args = ap.parse_args(argv)

    sets = [built_models(args.built)] + ([] if args.no_catalog else [catalog_models()])
    header = (f"{'model':<26} {'set':<7} {'tris':>6} {'parts':>5} {'planes':>6} {'found':>5} {'sec':>6}"
              + (f" {'peer':>5} {'p.sec':>6}" if args.peer else "") + "  note")
    lines = [header, "-" * len(header)]
    print(header, flush=True)
    print(lines[1], flush=True)
    rows = []
    for models in sets:
        for i, (name, kind, V, F, parts, truth) in enumerate(models):
            if (args.only and name not in args.only) or i % args.every:
                continue
            reflections, axes, refused, seconds = run_filter(V, F)
            found = 0
            for n, d, q in truth.planes:
                by_mirror = any(a <= FOUND_DEG and o <= FOUND_OFFSET
                                for a, o in (plane_error(T, n, d, q, truth.diagonal) for T in reflections))
                by_family = truth.axis is not None and any(
                    axis_in_plane(a, n, d, truth.diagonal) for a in axes)
                found += by_mirror or by_family
            peer = None
            if args.peer:
                planes, peer_seconds = peer_planes(args.peer, V, F)
                peer = (sum(peer_found(planes, n, d, q, truth.diagonal) for n, d, q in truth.planes), peer_seconds)
            note = ("refused: " + refused) if refused else ("revolution" if truth.axis is not None else "")
            row = dict(name=name, set=kind, triangles=len(F), parts=int(parts), planes=len(truth.planes),
                       found=found, seconds=seconds, refused=refused is not None, peer=peer)
            rows.append(row)
            line = (f"{name[:26]:<26} {kind:<7} {len(F):>6} {parts:>5} {len(truth.planes):>6} {found:>5} {seconds:>6.1f}"
                    + (f" {peer[0]:>5} {peer[1]:>6.2f}" if peer else "") + f"  {note[:90]}")
            lines.append(line)
            print(line, flush=True)
    totals = summary(rows, bool(args.peer))
    lines += ["-" * len(header)] + totals
    print("\n".join(lines[-len(totals) - 1:]))
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    with open(args.out, "w") as f:
        f.write("$ python tests/benchmarks/cad_mirrors.py " + " ".join(argv if argv is not None else sys.argv[1:]) + "\n")
        f.write("\n".join(lines) + "\n")
    return 0


def summary(rows, peer):
    out = []
    for kind in ("built", "catalog", None):
        rs = [r for r in rows if kind is None or r["set"] == kind]
        if not rs:
            continue
        planes = sum(r["planes"] for r in rs)
        found = sum(r["found"] for r in rs)
        whole = sum(r["found"] == r["planes"] for r in rs)
        line = (f"{kind or 'all'}: {found}/{planes} planes found ({found / planes:.2f}), {whole}/{len(rs)} models "
                f"with every plane, {sum(r['refused'] for r in rs)} refused, median {statistics.median(r['seconds'] for r in rs):.1f} s")
        if peer:
            pf = sum(r["peer"][0] for r in rs)
            line += (f"; peer {pf}/{planes} ({pf / planes:.2f}), "
                     f"median {statistics.median(r['peer'][1] for r in rs):.2f} s")
        out.append(line)
    return out


if __name__ == "__main__":
    sys.exit(main())
