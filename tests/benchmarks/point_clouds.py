#!/usr/bin/env python3
"""The planted scenes as point clouds against the same scenes as meshes.

    python tests/benchmarks/point_clouds.py [--noise F] [--scenes a,b,c] [--json FILE]
    python tests/benchmarks/point_clouds.py --dense 200000,1000000 [--scenes mirrored]

For every scene of tests/scenes.py (core, CAD and hard scenes), runs compute_partial_symmetries
with its defaults (plus the scene's filter_params) on the mesh, and on its vertices alone as a
point cloud: no faces, no normals (the filter estimates them), with Gaussian noise of F (a
fraction of the diagonal, default 0.001) on every coordinate.  Every copy of a scene is
tessellated apart, so no point of one copy is the image of a point of another.  With
--sampled the cloud is as many points drawn at random on the surface instead (area-weighted,
as a scan samples a surface evenly: a CAD part's vertices crowd at its small features and
leave its flat faces bare); --no-mesh leaves the mesh runs out.

Per scene it prints the points, then for the mesh and for the cloud: reports, the required
planted relations found (metrics.recall, against the scenes' ground truth, within
metrics.RECALL_TOL of the diagonal), the reports that are true (metrics.accuracy, the
accuracy benchmark's scorer: a planted relation, a composition of them, or a map the
brute-force oracle confirms on the clean surface; a cloud's patch points are the scene's
vertices moved by the noise, and are scored as the vertices nearest them) and seconds.
Scenes with no required relation (the analytic continuous shapes, whose ground truth is a
family) are listed with '-' under found.

With --dense, each scene is instead drawn as clouds of that many points at random on its
surface (a scan's density, above max_working_vertices): per size it prints the points the
filter worked on (its Poisson-disk subset), reports, relations found, seconds and the
process's peak memory so far (sizes run in increasing order, so it is the largest run's).

It measures and does not assert: the exit status is 0 unless a run raises an error other
than the filter's refusal, which is printed in the row.
"""
import argparse
import json
import os
import sys
import time

import numpy as np
import pymeshlab

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
import metrics  # noqa: E402
import scenes  # noqa: E402

import meshlab_symmetry  # noqa: E402,F401  (binds compute_partial_symmetries)

ALL = scenes.SCENE_NAMES + scenes.CAD_SCENE_NAMES + scenes.HARD_SCENE_NAMES


def run(ms, scene):
    """One run's reports, required relations found and planted, true reports, false reports
    and seconds, or the filter's refusal as a string.  The patch layers are made because the
    scorer reads each report's patch from them."""
    t = time.perf_counter()
    try:
        raw = ms.compute_partial_symmetries(create_patch_layers=True, **scene.filter_params)
    except pymeshlab.PyMeshLabException as e:
        return str(e).splitlines()[-1][:60]
    seconds = time.perf_counter() - t
    result = metrics.collect(ms, raw, 0, seconds)
    r = metrics.recall(scene, result.transforms)
    scored = metrics.accuracy(scene, result)
    return dict(reports=len(result.transforms), found=r["found"], planted=r["planted"],
                true=scored["correct"], false=scored["counts"]["false"], seconds=seconds)


def cloud(scene, noise, seed=0, sampled=False):
    """The scene's vertices, or as many points at random on its surface (sampled), with
    Gaussian noise of `noise` (a fraction of the diagonal) on every coordinate."""
    V = scenes.sample_surface(scene.vertices, scene.faces, len(scene.vertices), np.random.default_rng(1)) \
        if sampled else scene.vertices
    V = V + np.random.default_rng(seed).normal(0.0, noise * scene.diagonal, V.shape)
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(vertex_matrix=V), "cloud")
    return ms


def dense(scene_names, sizes):
    """The --dense table: every scene drawn as random clouds of each size."""
    import resource
    print(f"{'scene':<16} {'points':>8} {'worked on':>9} {'rep':>4} {'found':>6} {'time':>7} {'peak RSS':>9}")
    for name in scene_names:
        scene = scenes.make_scene(name, 0)
        for n in sorted(sizes):
            P = scenes.sample_surface(scene.vertices, scene.faces, n, np.random.default_rng(1))
            ms = pymeshlab.MeshSet()
            ms.add_mesh(pymeshlab.Mesh(vertex_matrix=P), "cloud")
            t = time.perf_counter()
            raw = ms.compute_partial_symmetries(create_patch_layers=False, **scene.filter_params)
            seconds = time.perf_counter() - t
            r = metrics.recall(scene, metrics.collect(ms, raw, 0, seconds).transforms)
            worked = raw["working_vertices"] or n
            peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
            print(f"{name:<16} {n:>8} {worked:>9} {int(raw['symmetry_count']):>4} "
                  f"{r['found']:>3}/{r['planted']:<2} {seconds:>6.1f}s {peak:>6.0f} MB", flush=True)


def cell(r):
    if r is None:
        return f"{'not run':<34}"
    if isinstance(r, str):
        return f"{'refused: ' + r:<34}"
    recall = f"{r['found']}/{r['planted']}" if r["planted"] else "-"
    return f"{r['reports']:>4} {recall:>6} {r['true']:>5} {r['false']:>5} {r['seconds']:>6.1f}s  "


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--noise", type=float, default=0.001)
    parser.add_argument("--scenes", default=",".join(ALL))
    parser.add_argument("--json")
    parser.add_argument("--dense", help="comma-separated point counts (default scene: mirrored)")
    parser.add_argument("--sampled", action="store_true",
                        help="the cloud is as many points at random on the surface as the mesh has vertices "
                             "(a scan's even density), not the vertices")
    parser.add_argument("--no-mesh", action="store_true", help="run the clouds only")
    args = parser.parse_args()
    if args.dense:
        names = args.scenes.split(",") if args.scenes != ",".join(ALL) else ["mirrored"]
        dense(names, [int(n) for n in args.dense.split(",")])
        return
    print(f"noise on the cloud: {100 * args.noise:.2g} % of the diagonal on every coordinate; no normals; "
          f"{'points at random on the surface' if args.sampled else 'the vertices'}")
    print(f"{'scene':<16} {'points':>7}   {'mesh: rep  found  true false    time':<34} "
          f"{'cloud: rep found  true false    time':<34}")
    rows = []
    totals = {kind: dict(found=0, planted=0, reports=0, true=0, false=0) for kind in ("mesh", "cloud")}
    for name in args.scenes.split(","):
        scene = scenes.make_scene(name, 0)
        mesh = None if args.no_mesh else run(scene.meshset(), scene)
        points = run(cloud(scene, args.noise, sampled=args.sampled), scene)
        for kind, r in (("mesh", mesh), ("cloud", points)):
            if isinstance(r, dict):
                for key in totals[kind]:
                    totals[kind][key] += r[key]
        print(f"{name:<16} {len(scene.vertices):>7}   {cell(mesh)} {cell(points)}", flush=True)
        rows.append(dict(scene=name, points=len(scene.vertices), mesh=mesh, cloud=points))
    for kind, t in totals.items():
        print(f"{kind}: {t['found']} of {t['planted']} required relations found; "
              f"{t['true']} of {t['reports']} reports true, {t['false']} false")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(dict(noise=args.noise, sampled=args.sampled, rows=rows, totals=totals), f, indent=1)


if __name__ == "__main__":
    main()
