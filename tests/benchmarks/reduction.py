#!/usr/bin/env python3
"""Symmetry-based reduction (generate_symmetry_based_reduction) on planted scenes, judged
by an oracle that shares nothing with the filter.

    python tests/benchmarks/reduction.py [--pictures DIR]

For each scene of tests/scenes.py named below it runs the filter with its default
parameters (plus the scene's own) and prints the faces kept, the share of the input that is
(size ratio), the instances, the filter's own reconstruction error, and the oracle's: the
reduced mesh with every instance applied, rebuilt with numpy (tests/reduction_oracle.py), and
its two-sided distance to the input by dense samples and a kd-tree, as fractions of the
diagonal.  The ideal ratio is what one copy of each repeated part and the unrepeated rest
would keep.  With --pictures it draws the rebuilt row and wingnut.

It measures and does not assert.
"""
import argparse
import os
import sys
import time

import numpy as np
import pymeshlab

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
import reduction_oracle  # noqa: E402
import scenes  # noqa: E402
import meshlab_symmetry  # noqa: E402  (binds the filters)

#: scene -> (what one copy of it is, the ideal share of faces kept)
SCENES = {
    "row": ("4 translated copies: one copy", 0.25),
    "wingnut": ("6 blades about an axis: one blade and a sixth of the hub", 1 / 6),
    "mirrored": ("2 mirrored copies: one copy", 0.5),
    "rigid": ("3 copies moved rigidly: one copy", 1 / 3),
}


def reduce(scene):
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(scene.vertices, scene.faces))
    start = time.time()
    out = ms.generate_symmetry_based_reduction(**scene.filter_params)
    reduced = ms.mesh(out["reduced_layer_id"])
    return out, (reduced.vertex_matrix().copy(), reduced.face_matrix().copy()), time.time() - start


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--pictures", metavar="DIR", help="write reduction_<scene>.png for the row and the wingnut")
    args = parser.parse_args()
    print(f"{'scene':<10} {'faces':>7} {'kept':>7} {'ratio':>6} {'ideal':>6} {'instances':>9} "
          f"{'filter error':>12} {'oracle error':>12} {'seconds':>7}  what is kept ideally")
    for name, (ideal_text, ideal) in SCENES.items():
        scene = scenes.make_scene(name, 0)
        out, (Vr, Fr), seconds = reduce(scene)
        instances = reduction_oracle.instances_of(out)
        W, G = reduction_oracle.rebuilt(Vr, Fr, instances)
        oracle = reduction_oracle.two_sided(scene.vertices, scene.faces, W, G, np.random.default_rng(0))
        print(f"{name:<10} {len(scene.faces):>7} {out['reduced_faces']:>7} {out['size_ratio']:>6.3f} {ideal:>6.3f} "
              f"{out['instance_count']:>9} {100 * out['reconstruction_error']:>11.3f}% "
              f"{100 * oracle / scene.diagonal:>11.3f}% {seconds:>7.1f}  {ideal_text}")
        if args.pictures and name in ("row", "wingnut"):
            path = os.path.join(args.pictures, f"reduction_{name}.png")
            meshlab_symmetry.reduction_picture((Vr, Fr), instances, path)
            print(f"wrote {path}")


if __name__ == "__main__":
    main()
