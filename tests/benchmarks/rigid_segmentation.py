#!/usr/bin/env python3
"""Rigid segments between two poses (compute_rigid_segments_between_meshes) on articulated
shapes with planted per-part motions.

    python tests/benchmarks/rigid_segmentation.py [--seeds 0,1,2] [--pictures DIR]

Each seed builds another shape of tests/two_poses.py: a chain of three different bumpy parts,
posed twice with its own rigid motion per part, the second pose re-tessellated; each shape
twice, with gaps at the joints (`gaps`: separate components) and fused at them into one closed
surface (`fused`: a skin over the joints that no rigid motion maps).  The filter runs with its
default parameters.  Per shape it prints the faces of either pose, the segments
reported, the parts found, the share of each pose's vertices labelled with their own part (a
segment stands for the part most of its first-pose vertices belong to), the largest distance
between a segment's transform and its part's planted motion over the part's vertices (in
percent of the diagonal), and the seconds.  With --pictures it draws seed 0's segments
(segmentation_poses.png, the fused shape).

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
import two_poses  # noqa: E402
import meshlab_symmetry  # noqa: E402  (binds the filters)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seeds", default="0,1,2", help="shapes to build, comma-separated")
    parser.add_argument("--pictures", metavar="DIR", help="write segmentation_poses.png there")
    args = parser.parse_args()
    print(f"{'shape':>5} {'joints':>6} {'faces':>13} {'segments':>8} {'parts':>5} {'right 1st':>9} {'right 2nd':>9} "
          f"{'T err %':>8} {'sec':>6}")
    for seed, fused in ((int(s), fused) for s in args.seeds.split(",") for fused in (False, True)):
        poses = two_poses.make_two_poses(seed, fused=fused)
        ms = pymeshlab.MeshSet()
        ms.add_mesh(pymeshlab.Mesh(poses.first.V, poses.first.F), "first")
        ms.add_mesh(pymeshlab.Mesh(poses.second.V, poses.second.F), "second")
        start = time.time()
        out = ms.compute_rigid_segments_between_meshes(first_mesh=0, second_mesh=1, create_segment_layers=False)
        seconds = time.time() - start
        first_ids = ms.mesh(0).vertex_custom_scalar_attribute_array("segment_id")
        second_ids = ms.mesh(1).vertex_custom_scalar_attribute_array("segment_id")
        score = two_poses.score(poses, first_ids, second_ids)
        transforms = np.asarray(out["segment_transforms"]).reshape(-1, 4, 4)
        error = max((two_poses.transform_error(poses, part, transforms[s]) for s, part in
                     score["segment_part"].items()), default=float("nan"))
        faces = f"{len(poses.first.F)}+{len(poses.second.F)}"
        print(f"{seed:>5} {'fused' if fused else 'gaps':>6} {faces:>13} {out['segment_count']:>8} {score['parts_found']:>3}/{len(two_poses.PARTS)} "
              f"{score['first_right']:>9.3f} {score['second_right']:>9.3f} {100 * error:>8.3f} {seconds:>6.1f}")
        if args.pictures and seed == 0 and fused:
            meshlab_symmetry.segmentation_picture((poses.first.V, poses.first.F), (poses.second.V, poses.second.F),
                                                  first_ids, second_ids,
                                                  os.path.join(args.pictures, "segmentation_poses.png"))


if __name__ == "__main__":
    main()
