"""An articulated shape in two poses, with its exact ground truth (the paper's Figure 8).

The shape is a chain of rigid parts, each a different bumpy superquadric (no part is a copy
of another, and none has a symmetry of its own that a motion could confuse with another
part's): a body, an upper limb and a lower limb.  The second pose moves the whole shape and
bends both joints, so every part has its own rigid motion.  Every part of the second pose is
re-tessellated (isotropic remeshing at another edge length, vertices slid off the first
pose's), so segmentation cannot match vertices.

Two kinds of joint: ``fused=False`` leaves a gap between neighbouring parts (separate
components); ``fused=True`` lets them overlap and joins each pose into one closed surface by
a boolean union (pymeshlab's), as a skin over the joints: the union's seams differ between the
poses, so near a joint neither pose is a rigid copy of the other, as around the bending joints
of the paper's horse.  A vertex belongs to the part on whose surface it lies (the nearest).

Usage::

    import two_poses
    p = two_poses.make_two_poses(seed=0)
    p.first.V, p.first.F, p.first.part   # per vertex: the part it belongs to
    p.motions[k]                          # 4x4: part k in the first pose onto the second
"""
from __future__ import annotations

import dataclasses
import functools
import math
from typing import List, Tuple

import numpy as np

import scenes

#: (name, semi-axes, where its joint with the previous part is, as a fraction of its length)
PARTS = (("body", (0.55, 0.30, 0.24)),
         ("upper_limb", (0.34, 0.13, 0.11)),
         ("lower_limb", (0.30, 0.11, 0.10)))
#: the space left between two parts at a joint, absolute (the shape is about 2.6 long)
JOINT_GAP = 0.06
#: how far neighbouring parts overlap at a fused joint, absolute
JOINT_OVERLAP = 0.08
#: faces of each part's first-pose tessellation per unit of area
FACES_PER_AREA = 3500.0


@dataclasses.dataclass
class Pose:
    V: np.ndarray
    F: np.ndarray
    part: np.ndarray  # per vertex: the index into PARTS of its part


@dataclasses.dataclass
class TwoPoses:
    first: Pose
    second: Pose
    motions: List[np.ndarray]  # per part: 4x4 from the first pose onto the second

    @property
    def diagonal(self) -> float:
        return scenes.bbox_diagonal(self.first.V)


def _part_mesh(axes, rng: np.random.Generator) -> Tuple[np.ndarray, np.ndarray]:
    shape = scenes.StarShape(axes=tuple(axes), exponent=2.0, amplitude=0.12,
                             field=scenes.RadialField(rng, n_bumps=7, width=0.5))
    V, F = shape.mesh(40)
    area = scenes.face_areas(V, F).sum()
    return scenes.remeshed(V, F, int(FACES_PER_AREA * area))


def _chain_placements(angles: Tuple[float, float], axes: List[np.ndarray], gap: float) -> List[np.ndarray]:
    """Where each part sits (4x4 from its own frame), the chain bent at each joint by the
    given angle about the joint's own axis."""
    placements = [np.eye(4)]
    tip = np.array([PARTS[0][1][0], 0.0, 0.0])  # the body's end along x
    for k in range(1, len(PARTS)):
        half = PARTS[k][1][0]
        joint = placements[-1] @ np.append(tip + [gap / 2, 0, 0], 1.0)
        bend = scenes.about(joint[:3], scenes.rotation(axes[k - 1], angles[k - 1]))
        # The part's centre lies half its length past the joint, along the previous part's x.
        direction = placements[-1][:3, :3] @ np.array([1.0, 0, 0])
        centre = joint[:3] + direction * (gap / 2 + half)
        placed = scenes.translation(centre) @ _rotation_only(placements[-1])
        placements.append(bend @ placed)
        tip = np.array([half, 0.0, 0.0])
    return placements


def _rotation_only(T: np.ndarray) -> np.ndarray:
    R = np.eye(4)
    R[:3, :3] = T[:3, :3]
    return R


@functools.lru_cache(maxsize=4)
def _build(seed: int, fused: bool) -> TwoPoses:
    rng = np.random.default_rng(seed)
    meshes = [_part_mesh(axes, rng) for _, axes in PARTS]
    joint_axes = [np.array([0.0, 0.3, 1.0]) / np.linalg.norm([0.0, 0.3, 1.0]),
                  np.array([0.2, 1.0, 0.4]) / np.linalg.norm([0.2, 1.0, 0.4])]
    gap = -JOINT_OVERLAP if fused else JOINT_GAP
    rest = _chain_placements((0.35, -0.5), joint_axes, gap)
    bent = _chain_placements((-0.6, 0.9), joint_axes, gap)
    whole = scenes.about(np.zeros(3), scenes.rotation(np.array([1.0, 2.0, 0.5]), 0.8))
    whole = scenes.translation([0.4, -0.3, 0.2]) @ whole
    first, second, motions = [], [], []
    for k, (V, F) in enumerate(meshes):
        A = rest[k]
        B = whole @ bent[k]
        motions.append(B @ np.linalg.inv(A))
        first.append((scenes.apply(A, V), F))
        V2, F2 = scenes.retessellate(V, F, length_ratio=0.8, rng=np.random.default_rng(seed + 100 + k))
        second.append((scenes.apply(B, V2), F2))
    join = _union if fused else _merge
    return TwoPoses(join(first), join(second), motions)


def _union(pieces) -> Pose:
    """The pieces joined into one surface by boolean union; each vertex labelled with the
    piece whose surface is nearest."""
    import pymeshlab
    ms = pymeshlab.MeshSet()
    for V, F in pieces:
        ms.add_mesh(pymeshlab.Mesh(V, F))
    current = 0
    for k in range(1, len(pieces)):
        ms.generate_boolean_union(first_mesh=current, second_mesh=k)
        current = ms.current_mesh_id()
    ms.meshing_remove_unreferenced_vertices()
    V, F = ms.current_mesh().vertex_matrix().copy(), ms.current_mesh().face_matrix().astype(np.int64)
    distances = np.stack([scenes.point_to_surface_distance(V, *piece) for piece in pieces])
    return Pose(V, F, np.argmin(distances, axis=0))


def _merge(pieces) -> Pose:
    Vs, Fs, labels, offset = [], [], [], 0
    for k, (V, F) in enumerate(pieces):
        Vs.append(V)
        Fs.append(F + offset)
        labels.append(np.full(len(V), k))
        offset += len(V)
    return Pose(np.vstack(Vs), np.vstack(Fs).astype(np.int64), np.concatenate(labels))


def make_two_poses(seed: int = 0, fused: bool = False) -> TwoPoses:
    built = _build(seed, fused)
    return TwoPoses(Pose(built.first.V.copy(), built.first.F.copy(), built.first.part.copy()),
                    Pose(built.second.V.copy(), built.second.F.copy(), built.second.part.copy()),
                    [m.copy() for m in built.motions])


def score(poses: TwoPoses, first_ids: np.ndarray, second_ids: np.ndarray) -> dict:
    """Each reported segment stands for the part most of its first-pose vertices belong to;
    a vertex is right when its segment stands for its own part.  Returns the share of right
    vertices in each pose and the segment-to-part map."""
    first_ids = np.asarray(first_ids, int)
    second_ids = np.asarray(second_ids, int)
    segment_part = {}
    for s in np.unique(first_ids[first_ids >= 0]):
        parts, counts = np.unique(poses.first.part[first_ids == s], return_counts=True)
        segment_part[int(s)] = int(parts[np.argmax(counts)])

    def right(ids, truth):
        mapped = np.array([segment_part.get(int(s), -1) for s in ids])
        return float(np.mean(mapped == truth))

    return {"first_right": right(first_ids, poses.first.part),
            "second_right": right(second_ids, poses.second.part),
            "segment_part": segment_part,
            "parts_found": len(set(segment_part.values()))}


def transform_error(poses: TwoPoses, part: int, T: np.ndarray) -> float:
    """Largest distance, over the part's first-pose vertices, between T and the planted
    motion, as a fraction of the diagonal."""
    P = poses.first.V[poses.first.part == part]
    return float(np.max(np.linalg.norm(scenes.apply(T, P) - scenes.apply(poses.motions[part], P), axis=1))
                 / poses.diagonal)


if __name__ == "__main__":
    p = make_two_poses(0, fused=True)
    print("first pose", len(p.first.V), "vertices", len(p.first.F), "faces;",
          "second pose", len(p.second.V), "vertices", len(p.second.F), "faces; diagonal", round(p.diagonal, 3))
    for k, m in enumerate(p.motions):
        angle = math.degrees(math.acos(np.clip((np.trace(m[:3, :3]) - 1) / 2, -1, 1)))
        print(f"part {k} ({PARTS[k][0]}): turned by {angle:.1f} degrees")
