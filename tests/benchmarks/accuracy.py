#!/usr/bin/env python3
"""Accuracy of compute_partial_symmetries against ground truth it did not produce.

    python tests/benchmarks/accuracy.py [--quick] [--seed N] [--scenes a,b,c] [--json FILE]
                                        [--working-fraction F | --above-working-resolution]

Runs the filter with its DEFAULT parameters (plus each scene's filter_params and
create_patch_layers=1) on the core scenes, cad_fandisk and the hard scenes of
tests/scenes.py, and scores every report with metrics.AccuracyScorer: a discrete report is
correct only if it matches a planted relation, a composition of them or an oracle-established
self-symmetry of a base (within 1 % of the diagonal over the source region); a continuous
report only if it matches a ground-truth family (or, on CAD scenes, the oracle confirms it);
a discrete report inside a continuous family is a redundant member, not a correct answer.

Per scene it prints: triangles, reports, recall (required relations and families found),
precision, redundant reports (duplicates + family members), false positives, mean patch IoU
with the ground-truth source region, the largest transform error of matched reports (fraction
of the diagonal), the filter's stage seconds and its total.  Then the overall figures against
the bar: recall >= 0.95, precision >= 0.95, no scene over 30 s.

--working-fraction F sets max_working_vertices to F times each scene's vertex count, so that
the filter analyses a simplified copy of every scene as it does a mesh above 50,000 vertices
(the scenes are smaller), and scores what it carries back to the input.  The copies are
coarse: a 10,000-vertex scene at 0.5 has edges about as long as the verification tolerance.

--above-working-resolution splits every triangle of each scene at its edges' midpoints until
the scene has more than the filter's default working resolution (50,000 vertices): the same
surface at 50,000-190,000 vertices, which the filter, at its defaults, analyses on a copy
simplified to 50,000 vertices, as it does every large mesh a user gives it.

It measures and does not assert: the exit status is 0 unless the filter raises an error.
"""
import argparse
import json
import os
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
import meshlab_symmetry  # noqa: E402
import metrics  # noqa: E402
import pymeshlab  # noqa: E402
import scenes  # noqa: E402

QUICK = ("mirrored", "thin_plate", "cylinder", "hammer", "noisy_both_0.2")
ALL = scenes.SCENE_NAMES + scenes.CAD_SCENE_NAMES + scenes.HARD_SCENE_NAMES
BAR_RECALL = 0.95
BAR_PRECISION = 0.95
BAR_SECONDS = 30.0
STAGES = ("signatures", "pairing", "clustering", "verification")


def filter_working_vertices() -> int:
    """The filter's default max_working_vertices, above which it analyses a simplified
    copy, as the filter declares it (pymeshlab lists a filter's defaults only with a mesh
    loaded)."""
    ms = pymeshlab.MeshSet()
    ms.create_sphere()
    return int(ms.filter_parameter_values(meshlab_symmetry.FILTER_NAME)["max_working_vertices"])
HEADER = (f"{'scene':<16} {'tris':>6} {'rep':>4} {'recall':>7} {'prec':>7} {'red':>4} "
          f"{'fp':>3} {'IoU':>5} {'T err':>6} " + " ".join(f"{s[:6]:>6}" for s in STAGES)
          + f" {'total':>6}")


def ensure_cad_meshes(names):
    """Fetch the CGAL meshes when a requested scene needs them; drop those scenes if that
    fails (the benchmark measures, it does not stop)."""
    need = [n for n in names if n in scenes.NEEDS_CAD_MESHES]
    d = os.environ.get("SYMMETRY_CGAL_DIR") or scenes.DEFAULT_CGAL_DIR
    if need and not scenes.cad_meshes_available(d):
        script = os.path.join(os.path.dirname(HERE), "fetch_cgal_meshes.sh")
        if os.system(f'"{script}" "{d}"') != 0:
            print(f"accuracy: could not fetch the CAD meshes; skipping {', '.join(need)}")
            return [n for n in names if n not in need]
    return names


def fmt(x, spec, dash="-"):
    return dash if x is None else format(x, spec)


def print_row(name, s, res, fig):
    st = res.stage_seconds()
    found = f"{fig['found']}/{fig['required']}" if fig["required"] else "-"
    prec = f"{fig['correct']}/{fig['reported']}" if fig["reported"] else "-"
    print(f"{name:<16} {s.triangle_count:>6} {res.count:>4} {found:>7} {prec:>7} "
          f"{fig['redundant']:>4} {fig['counts']['false']:>3} {fmt(fig['iou'], '5.2f'):>5} "
          f"{fmt(fig['max_error'], '6.4f'):>6} "
          + " ".join(f"{st.get(k, float('nan')):>6.2f}" for k in STAGES)
          + f" {res.seconds_wall:>6.2f}")
    for missed in fig["missed"]:
        print(f"    missed {missed}")
    for r in fig["reports"]:
        if r["label"] in ("false", "member"):
            what = "false" if r["label"] == "false" else f"member of {r['matched']}"
            print(f"    #{r['index']} {scenes.KIND_NAMES[r['kind']]}: {what}"
                  + (f" ({r['note']})" if r["note"] else ""))


def run_scene(name, seed, working_fraction=None, above_working_resolution=False):
    """Generate, detect, score one scene; returns (scene, result, figures, generation s)."""
    t = time.perf_counter()
    s = scenes.make_scene(name, seed)
    if above_working_resolution:
        s = s.subdivided(filter_working_vertices())
    gen = time.perf_counter() - t
    params = dict(s.filter_params, create_patch_layers=True)
    if working_fraction:
        params["max_working_vertices"] = max(1000, int(working_fraction * len(s.vertices)))
    res = metrics.run_filter(s, **params)
    return s, res, metrics.accuracy(s, res), gen


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help=f"only {', '.join(QUICK)}")
    ap.add_argument("--seed", type=int, default=0, help="scene generator seed")
    ap.add_argument("--scenes", help="comma-separated scene names (default: all)")
    ap.add_argument("--json", help="write the per-scene figures and reports to this file")
    ap.add_argument("--working-fraction", type=float,
                    help="analyse each scene on a simplified copy of this fraction of its vertices")
    ap.add_argument("--above-working-resolution", action="store_true",
                    help="subdivide each scene above the filter's max_working_vertices first")
    args = ap.parse_args(argv)
    if args.working_fraction is not None and not 0 < args.working_fraction < 1:
        ap.error("--working-fraction must lie between 0 and 1")
    if args.working_fraction is not None and args.above_working_resolution:
        ap.error("--working-fraction and --above-working-resolution exclude each other")
    names = args.scenes.split(",") if args.scenes else list(QUICK if args.quick else ALL)
    unknown = [n for n in names if n not in ALL]
    if unknown:
        ap.error(f"unknown scenes {unknown}; known: {', '.join(ALL)}")
    names = ensure_cad_meshes(names)

    print(HEADER)
    print("-" * len(HEADER))
    rows = []
    for name in names:
        try:
            s, res, fig, gen = run_scene(name, args.seed, args.working_fraction,
                                         args.above_working_resolution)
        except Exception as e:  # the filter errored: report and stop with a failure status
            print(f"{name:<16} FILTER ERROR: {str(e).strip().splitlines()[-1]}")
            return 1
        print_row(name, s, res, fig)
        sys.stdout.flush()
        rows.append(dict(scene=name, triangles=s.triangle_count, generation_seconds=gen,
                         seconds=res.seconds_wall, stages=res.stage_seconds(), **fig))
    summarize(rows)
    if args.json:
        with open(args.json, "w") as f:
            json.dump(dict(seed=args.seed, scenes=rows), f, indent=1, default=float)
    return 0


def summarize(rows):
    found = sum(r["found"] for r in rows)
    required = sum(r["required"] for r in rows)
    correct = sum(r["correct"] for r in rows)
    reported = sum(r["reported"] for r in rows)
    recall = found / required if required else float("nan")
    precision = correct / reported if reported else 1.0
    slowest = max((r["seconds"] for r in rows), default=0.0)
    counts = {k: sum(r["counts"][k] for r in rows) for k in rows[0]["counts"]} if rows else {}
    print("-" * len(HEADER))
    print(f"overall recall    {recall:.3f} ({found}/{required})   bar >= {BAR_RECALL}: "
          f"{'met' if recall >= BAR_RECALL else 'NOT met'}")
    print(f"overall precision {precision:.3f} ({correct}/{reported})   bar >= {BAR_PRECISION}: "
          f"{'met' if precision >= BAR_PRECISION else 'NOT met'}")
    print(f"slowest scene     {slowest:.1f} s   bar <= {BAR_SECONDS:.0f} s: "
          f"{'met' if slowest <= BAR_SECONDS else 'NOT met'}")
    print("reports by label  " + ", ".join(f"{k} {v}" for k, v in counts.items()))


if __name__ == "__main__":
    sys.exit(main())
