#!/usr/bin/env python3
"""Benchmark: do the restricted groups find what the full group finds, and no slower?

    python tests/benchmarks/restricted_groups.py [--scenes a,b,c] [--seed N]

On every scene of tests/benchmarks/accuracy.py (for the real models see the last column
of tests/benchmarks/real_mirrors.py) the filter runs with its DEFAULT parameters (plus a
scene's filter_params) and transformation_group 0 (rotations, reflections, translations).
The group-0 reports that ground truth confirms are kept: those metrics.AccuracyScorer labels
correct (a planted relation, a composition, an oracle self-symmetry of a base).  If any is a
mirror, the filter runs again with group 2 (reflections only); if any is a translation, with
group 3 (translations only).  For each kept report it prints the nearest report of the
restricted run (tests/group_containment.py: plane angle and offset, or translation
difference), whether that is the same symmetry (within 0.1 degree and 0.2 % of the
diagonal; "truer" when it is not, but matches the same planted relation at least as
closely as group 0's report, gc.found_as_well; "(any)" for a mirror whose patch has a
continuum of planes, one as right as another, gc.plane_is_determined), the restricted run's false reports (matching no ground truth), and the seconds of
both runs.  At the end: how many of the kept reports each restricted group found, and the
restricted runs' total time against group 0's.

It measures and does not assert: the exit status is 0 unless the filter raises an error.
"""
import argparse
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
sys.path.insert(0, HERE)
import group_containment as gc  # noqa: E402
import metrics  # noqa: E402
import oracle  # noqa: E402
import scenes  # noqa: E402
from accuracy import ALL, ensure_cad_meshes  # noqa: E402


def confirmed(fig):
    """Indices of the reports the scene's ground truth confirms."""
    return [r["index"] for r in fig["reports"] if r["label"] in ("correct", "oracle")]


def detect(scene, group):
    res = metrics.run_filter(scene, **dict(scene.filter_params, transformation_group=group,
                                           create_patch_layers=True))
    return res, metrics.accuracy(scene, res)


def compare(name, scene, totals):
    """Run group 0, then each restricted group whose kind group 0 confirmed; print rows."""
    full, fig = detect(scene, 0)
    for group, kind in gc.GROUP_KIND.items():
        wanted = [k for k in confirmed(fig) if k in gc.reports_of_kind(full, kind, scene.diagonal)]
        if not wanted:
            continue
        restricted, rfig = detect(scene, group)
        surface = oracle.Surface.from_mesh(*scene.clean_mesh(), spacing=0.0015)
        matches = gc.containment(full, restricted, group, wanted, scene.diagonal, scene.vertices, surface)
        t = totals[group]
        found = [gc.found_as_well(m, fig, rfig) for m in matches]
        t["kept"] += len(matches)
        t["same"] += sum(found)
        t["continuum"] += sum(not f and not m.determined for f, m in zip(found, matches))
        t["false"] += rfig["counts"]["false"]
        t["full_s"] += full.seconds_wall
        t["restricted_s"] += restricted.seconds_wall
        for m, f in zip(matches, found):
            angle = "-" if m.kind == gc.TRANSLATION or m.nearest < 0 else f"{m.angle_deg:.3f}"
            dist = "-" if m.nearest < 0 else f"{100 * m.distance:.3f}"
            same = "yes" if m.same else "truer" if f else "NO" if m.determined else "(any)"
            print(f"{name:<16} g{group} #{m.index:<3} {kind:<11} {angle:>7} {dist:>7} "
                  f"{same:>5} {rfig['counts']['false']:>3} "
                  f"{full.seconds_wall:>6.1f} {restricted.seconds_wall:>6.1f}", flush=True)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scenes", help="comma-separated scene names (default: all of accuracy.py)")
    ap.add_argument("--seed", type=int, default=0, help="scene generator seed")
    args = ap.parse_args(argv)
    names = ensure_cad_meshes(args.scenes.split(",") if args.scenes else list(ALL))

    print(f"{'scene':<16} grp rep  {'kind':<11} {'deg':>7} {'off%':>7} {'same':>5} {'fp':>3} "
          f"{'g0 s':>6} {'grp s':>6}")
    totals = {g: dict(kept=0, same=0, continuum=0, false=0, full_s=0.0, restricted_s=0.0)
              for g in gc.GROUP_KIND}
    for name in names:
        compare(name, scenes.make_scene(name, args.seed), totals)
    print("-" * 80)
    for g, t in totals.items():
        ratio = t["restricted_s"] / t["full_s"] if t["full_s"] else float("nan")
        print(f"transformation_group={g} ({gc.GROUP_KIND[g]}s): {t['same']}/{t['kept']} of group 0's "
              f"confirmed {gc.GROUP_KIND[g]}s found (within {gc.SAME_DEG:g} degree and "
              f"{100 * gc.SAME_OFFSET:g}% of the diagonal, or truer), {t['continuum']} one of a "
              f"continuum of planes where another was found, {t['kept'] - t['same'] - t['continuum']} "
              f"missed; {t['false']} false reports; "
              f"{t['restricted_s']:.1f} s against group 0's {t['full_s']:.1f} s on the same scenes "
              f"(ratio {ratio:.2f})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
