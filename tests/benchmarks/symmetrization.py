#!/usr/bin/env python3
"""Symmetrization (apply_coord_symmetrization) on an approximate mirror, measured by an oracle.

    python tests/benchmarks/symmetrization.py [--pictures DIR]

The bumpy sphere of tests/python/conftest.py is symmetric under x -> -x only; normal noise
of sigma (fraction of the diagonal) on its x > 0 half makes the mirror approximate.  For each
sigma it runs the filter with its default parameters (strength 1, 3 passes) and prints the
oracle's residual before and after: the median and 90th percentile of the distance of the
reflected surface to the surface under the shape's own best mirror plane near x = 0
(tests/oracle_mirror.py, which shares nothing with the filter), as fractions of the diagonal;
and the filter's own rms_before and rms_after (of the symmetry it detected).  With --pictures it writes the
deviation pictures of the sigma = 0.2 % mesh before and after, on one colour scale.

It measures and does not assert.
"""
import argparse
import os
import sys
import time

import pymeshlab

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "python"))
import oracle_mirror  # noqa: E402
from conftest import noisy_mirror_mesh  # noqa: E402
import meshlab_symmetry  # noqa: E402,F401  (binds the filters)

SIGMAS = (0.001, 0.002, 0.005)


def oracle_residual(V, F):
    """(median, 90th percentile) of the residual of the shape's own best mirror plane near
    x = 0 (oracle_mirror.residual_near), fractions of the diagonal."""
    stats = oracle_mirror.residual_near(V, F, [1.0, 0.0, 0.0], 0.0)
    return stats["median"], stats["p90"]


def symmetrized(V, F):
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(V, F))
    start = time.time()
    out = ms.apply_coord_symmetrization()
    return ms.current_mesh().vertex_matrix().copy(), out, time.time() - start


def pictures(V, W, F, folder):
    from meshlab_symmetry import deviation_picture, detect
    before, after = detect((V, F)), detect((W, F))
    scale = meshlab_symmetry.pictures.deviation_scale(before)
    for mesh, result, name, title in (((V, F), before, "symmetrization_before.png", "Before symmetrization"),
                                      ((W, F), after, "symmetrization_after.png", "After symmetrization")):
        path = os.path.join(folder, name)
        deviation_picture(mesh, result, path, scale=scale, title=f"{title}: deviation from the mirror")
        print(f"wrote {path}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--pictures", metavar="DIR", help="write the before/after deviation pictures here")
    args = parser.parse_args()
    print(f"{'sigma %':>8} {'moved':>6} {'oracle median % before':>23} {'after':>7} {'oracle p90 % before':>19} "
          f"{'after':>7} {'filter rms % before':>20} {'after':>7} {'sec':>5}")
    for sigma in SIGMAS:
        V, F = noisy_mirror_mesh(sigma)
        W, out, seconds = symmetrized(V, F)
        (median, p90), (median_after, p90_after) = oracle_residual(V, F), oracle_residual(W, F)
        print(f"{100 * sigma:8.2f} {out['symmetrized_vertices']:6d} {100 * median:23.4f} {100 * median_after:7.4f} "
              f"{100 * p90:19.4f} {100 * p90_after:7.4f} {100 * out['rms_before']:20.4f} "
              f"{100 * out['rms_after']:7.4f} {seconds:5.1f}")
        if args.pictures and sigma == 0.002:
            pictures(V, W, F, args.pictures)


if __name__ == "__main__":
    main()
