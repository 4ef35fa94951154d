#!/usr/bin/env python3
"""Consistent editing (apply_coord_consistent_editing) on the planted row, judged by an
analytic oracle.

    python tests/benchmarks/consistent_editing.py [--pictures DIR]

The row scene of tests/scenes.py is four re-tessellated copies of one part; a smooth bump
(tests/editing_oracle.py) is pushed onto the top of copy 0 only, and the filter runs with its
default parameters.  For each other copy it prints how many vertices received the edit and
the error against what the copy must receive (the bump at the planted preimage of each vertex,
turned by the planted transform), as fractions of the bump's height: the median where the
bump is above half its height, and the largest anywhere.  With --pictures it draws the edited
row (editing_row.png), coloured by how far each face moved.

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
import editing_oracle  # noqa: E402
import scenes  # noqa: E402
import meshlab_symmetry  # noqa: E402  (binds the filters)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--pictures", metavar="DIR", help="write editing_row.png there")
    args = parser.parse_args()
    scene = scenes.make_scene("row", 0)
    V, F = scene.vertices, scene.faces
    edited, centre, push, radius = editing_oracle.row_edit(scene)
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(V, F), "original")
    ms.add_mesh(pymeshlab.Mesh(edited, F), "edited")
    start = time.time()
    out = ms.apply_coord_consistent_editing(original_mesh=0, **scene.filter_params)
    seconds = time.time() - start
    result = ms.current_mesh().vertex_matrix()
    height = float(np.linalg.norm(push))
    print(f"row scene, {len(F)} faces; bump of {100 * height / scene.diagonal:.2f} % of the diagonal on "
          f"{out['edited_vertices']} vertices of copy 0; {out['symmetry_count']} symmetries, "
          f"{out['carried_vertices']} vertices received it in {out['passes']} passes, {seconds:.1f} s")
    print(f"{'copy':>4} {'received':>8} {'median error (high part)':>25} {'largest error':>14}")
    for k in (1, 2, 3):
        rows, expected, _ = editing_oracle.expected_on_copy(scene, k, centre, push, radius)
        received = int((np.abs(result[rows] - V[rows]).max(axis=1) > 0).sum())
        error = np.linalg.norm(result[rows] - V[rows] - expected, axis=1) / height
        high = np.linalg.norm(expected, axis=1) > 0.5 * height
        print(f"{k:>4} {received:>8} {np.median(error[high]):>25.3f} {error.max():>14.3f}")
    if args.pictures:
        path = os.path.join(args.pictures, "editing_row.png")
        meshlab_symmetry.editing_picture((V, F), result, path,
                                         title="Consistent editing: a bump on one copy, carried to three")
        print(f"wrote {path}")


if __name__ == "__main__":
    main()
