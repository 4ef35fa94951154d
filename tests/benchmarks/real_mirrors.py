#!/usr/bin/env python3
"""Benchmark: does compute_partial_symmetries find the global mirror plane of real models?

    python tests/benchmarks/real_mirrors.py [--only NAME ...] [--json FILE]

For every model of tests/real_models.json (fetched by tests/fetch_real_models.sh when
missing; planes measured by tests/oracle_mirror.py) the filter runs with its DEFAULT
parameters, once with transformation_group=0 (rotations, reflections, translations) and once
with transformation_group=2 (reflections only).  Among the reported reflections (discrete
ones: a nonzero continuous_kinds entry is skipped) it takes the one closest to each true
plane and prints the angle between the planes (degrees), the offset error (% of the
diagonal), whether that is within FOUND_DEG and FOUND_OFFSET, and the seconds of the run;
then per group the number of models whose every mirror plane is found, and of planes.
The last column says whether group 2 reports group 0's own reflection of that plane too, the
same plane within 0.1 degree and 0.2 % of the diagonal (issue 11: a restricted group finds what
the full group finds; tests/group_containment.py).

It measures and does not assert: the exit status is 0 unless the filter raises an error.
"""
import argparse
import json
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
import group_containment as gc  # noqa: E402
import real_models  # noqa: E402

GROUPS = (0, 2)
#: a true plane is found when a reported reflection is this close (degrees, fraction of diag)
FOUND_DEG = 1.0
FOUND_OFFSET = 0.01


def run_filter(V, F, group):
    """The reported discrete reflections (4x4 each) and the wall seconds of one run."""
    import pymeshlab
    import meshlab_symmetry  # noqa: F401  (binds MeshSet.compute_partial_symmetries)
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(V, F), "model")
    t = time.perf_counter()
    out = ms.compute_partial_symmetries(transformation_group=group)
    seconds = time.perf_counter() - t
    n = int(out["symmetry_count"])
    T = np.asarray(out["transforms"], float).reshape(n, 4, 4)
    keep = np.asarray(out["is_reflection"], int).reshape(n) != 0
    if "continuous_kinds" in out:
        keep &= np.asarray(out["continuous_kinds"], int).reshape(n) == 0
    return T[keep], seconds


def closest(reflections, plane, diag):
    """((angle deg, offset fraction), 4x4) of the reported reflection nearest to the true
    plane, by angle in units of FOUND_DEG plus offset in units of FOUND_OFFSET; (None, None)
    if none."""
    scored = [(real_models.mirror_angle_error(T, plane, diag), T) for T in reflections]
    if not scored:
        return None, None
    return min(scored, key=lambda s: s[0][0] / FOUND_DEG + s[0][1] / FOUND_OFFSET)


def same_in(reflections, T0, plane, diag):
    """Whether one of `reflections` is the plane of reflection T0 (measured at the true
    plane's point) within gc.SAME_DEG and gc.SAME_OFFSET."""
    mine = gc.plane_of(T0, np.asarray([plane.point]))
    return any(a <= gc.SAME_DEG and o <= gc.SAME_OFFSET
               for a, o in (real_models.mirror_angle_error(T, mine, diag) for T in reflections))


def is_found(err):
    return err is not None and err[0] <= FOUND_DEG and err[1] <= FOUND_OFFSET


def cells(err, seconds):
    if err is None:
        return f"{'-':>7} {'-':>7} {'no':>5} {seconds:>6.1f}"
    return (f"{err[0]:>7.2f} {100 * err[1]:>7.2f} {'yes' if is_found(err) else 'no':>5} "
            f"{seconds:>6.1f}")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--only", nargs="+", metavar="NAME", help="only these models")
    ap.add_argument("--json", help="write the per-plane numbers to this file")
    args = ap.parse_args(argv)
    models = [m for m in real_models.real_models() if not args.only or m.name in args.only]

    group_head = " ".join(f"g{g}: {'deg':>6} {'off%':>7} {'found':>5} {'sec':>6}" for g in GROUPS)
    header = f"{'model':<18} {'tris':>6} {'kind':<6} {group_head}  g2 has g0's"
    print(header)
    print("-" * len(header))
    found = {g: 0 for g in GROUPS}          # planes
    models_found = {g: 0 for g in GROUPS}   # models with every plane found
    contained = [0, 0]                      # group 0's found planes, and those group 2 has too
    rows = []
    for m in models:
        V, F = m.load()
        runs = {g: run_filter(V, F, g) for g in GROUPS}
        all_found = {g: True for g in GROUPS}
        for k, plane in enumerate(m.planes):
            label = m.name if len(m.planes) == 1 else f"{m.name}#{k}"
            best = {g: closest(runs[g][0], plane, m.diagonal) for g in GROUPS}
            errs = {g: best[g][0] for g in GROUPS}
            for g in GROUPS:
                found[g] += is_found(errs[g])
                all_found[g] &= is_found(errs[g])
            has = "-"
            if is_found(errs[0]):
                same = same_in(runs[2][0], best[0][1], plane, m.diagonal)
                contained[0] += 1
                contained[1] += same
                has = "yes" if same else "NO"
            print(f"{label:<18} {m.triangles:>6} {m.kind[:6]:<6} "
                  + " ".join(f"    {cells(errs[g], runs[g][1])}" for g in GROUPS) + f"  {has:>11}",
                  flush=True)
            rows.append(dict(model=m.name, plane=k, triangles=m.triangles, kind=m.kind,
                             **{f"group{g}": dict(angle_deg=None if errs[g] is None else errs[g][0],
                                                  offset=None if errs[g] is None else errs[g][1],
                                                  found=is_found(errs[g]),
                                                  reflections=len(runs[g][0]),
                                                  seconds=runs[g][1]) for g in GROUPS}))
        for g in GROUPS:
            models_found[g] += all_found[g]
    print("-" * len(header))
    total = sum(len(m.planes) for m in models)
    for g in GROUPS:
        print(f"transformation_group={g}: {models_found[g]}/{len(models)} models with every "
              f"mirror plane found, {found[g]}/{total} planes (within {FOUND_DEG:g} degree and "
              f"{100 * FOUND_OFFSET:g}% of the diagonal)")
    print(f"transformation_group=2 reports {contained[1]}/{contained[0]} of the planes group 0 found, "
          f"the same plane as group 0's within {gc.SAME_DEG:g} degree and {100 * gc.SAME_OFFSET:g}% "
          f"of the diagonal; {sum(r['group2']['seconds'] for r in rows if r['plane'] == 0):.1f} s "
          f"against group 0's {sum(r['group0']['seconds'] for r in rows if r['plane'] == 0):.1f} s")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
