"""Does a restricted transformation group find what the full group finds?

transformation_group 2 (reflections only) and 3 (translations only) ask for one kind of the
symmetries that group 0 (rotations, reflections and translations) looks for.  A user who picks
one expects at least the symmetries of that kind that group 0 reports.  This module compares
two detection results (metrics.DetectionResult) of one mesh: for every discrete report of
group 0 that is of the restricted group's kind, the nearest discrete report of the restricted
run, and how far it is:

- a reflection: the angle between the two mirror planes (degrees) and the offset between
  them (fraction of the diagonal), measured at the group-0 source patch's centroid projected
  onto its plane;
- a translation (a rigid map whose rotation part is the identity): the length of the
  difference of the two translation vectors, either direction (fraction of the diagonal).

Which group-0 reports must be matched is the caller's choice (tests/benchmarks/
restricted_groups.py takes those its ground truth confirms: planted relations, the oracle's
self-symmetries, a real model's measured mirror plane), less the mirrors whose plane their
patch does not determine (plane_is_determined: one of a continuum of planes through an axis,
where a restricted run rightly picks another).
"""
import dataclasses
import math
from typing import List, Optional, Sequence

import numpy as np

import oracle
import real_models

#: a report is a translation when its rotation part is the identity, and a mirror when its
#: linear part is a plain reflection, within this angle (degrees), and a mirror's glide along
#: its plane is at most KIND_GLIDE (fraction of the diagonal): group 0 fits any rigid map, so
#: its mirror of an approximate symmetry is a little off a plain one
KIND_DEG = 1.0
KIND_GLIDE = 0.01
#: the same symmetry in both results: planes within this angle and offset, translations
#: within this distance (the issue's bar is 0.1 degree)
SAME_DEG = 0.1
SAME_OFFSET = 0.002

#: a mirror plane is determined by its patch unless shifting it, or tilting it about some
#: line in it, far enough to move the patch's points by TILT_MOVES oracle tolerances on
#: average (tilts at most TILT_MAX_DEG), keeps at least TILT_KEEP of the patch's inliers
#: (a tilted plane's offset fitted again): then the patch has a continuum of mirror planes
#: (the planes through the axis of a surface of revolution, across a prism), and any one
#: of them is as right as another
TILT_MOVES = 4.0
TILT_MAX_DEG = 10.0
TILT_KEEP = 0.8

REFLECTION, TRANSLATION = "reflection", "translation"
#: the kind each restricted group asks for
GROUP_KIND = {2: REFLECTION, 3: TRANSLATION}


#: (unit normal n, offset d) of the plane n.x = d of a reflection
mirror_plane = real_models.reflection_plane


def rotation_angle_deg(T: np.ndarray) -> float:
    """The rotation angle of the orthogonal part of T's linear map (degrees)."""
    Q = real_models._orthogonal_part(np.asarray(T, float)[:3, :3])
    return math.degrees(math.acos(np.clip((np.trace(Q) - 1.0) / 2.0, -1.0, 1.0)))


def kind_of(T: np.ndarray, is_reflection: bool, scale: float, diag: float) -> Optional[str]:
    """REFLECTION, TRANSLATION or None (any other kind: rotation, glide reflection, screw,
    scaling)."""
    if abs(scale - 1.0) > 1e-6:
        return None
    if is_reflection:
        mirror = rotoreflection_angle_deg(T) <= KIND_DEG
        return REFLECTION if mirror and glide_length(T) <= KIND_GLIDE * diag else None
    return TRANSLATION if rotation_angle_deg(T) <= KIND_DEG else None


def rotoreflection_angle_deg(T: np.ndarray) -> float:
    """How far a reflection also turns about its plane's normal: the rotation angle of A H,
    with H the mirror across the plane of A's -1 eigenvector (zero for a mirror)."""
    n, _ = mirror_plane(T)
    H = np.eye(4)
    H[:3, :3] -= 2.0 * np.outer(n, n)
    return rotation_angle_deg(np.asarray(T, float) @ H)


def glide_length(T: np.ndarray) -> float:
    """How far a reflection also slides along its plane: the part of t in the plane (zero
    for a mirror, whose image of a point on the plane is the point itself)."""
    n, _ = mirror_plane(T)
    t = np.asarray(T, float)[:3, 3]
    return float(np.linalg.norm(t - np.dot(t, n) * n))


def plane_of(T: np.ndarray, points: np.ndarray) -> real_models.Plane:
    """The mirror plane of reflection T, its offset measured at the centroid of `points`
    projected onto it."""
    n, d = mirror_plane(T)
    c = np.mean(points, axis=0)
    return real_models.Plane(normal=tuple(n), offset=d, point=tuple(c - (np.dot(n, c) - d) * n),
                             residual={})


def plane_is_determined(surface: oracle.Surface, T: np.ndarray, patch_points: np.ndarray) -> bool:
    """Whether the mirror plane of T is the only one near it that maps its patch (see
    TILT_KEEP): shifted both ways, or tilted about 8 lines through the patch's centroid both
    ways with its offset searched within 4 oracle tolerances, no plane keeps TILT_KEEP of
    T's inliers."""
    tol = oracle.EXACT_TOL * surface.diagonal
    P = oracle.subsample(np.asarray(patch_points, float), 2000)
    P = surface.points[surface.tree.query(P)[1]]  # on the clean surface: noise is no continuum
    n, d = mirror_plane(T)
    base = oracle._inlier_fraction(surface, P, n, d, tol)
    if base == 0:
        return True
    for shift in (1, -1):  # a slide along a prism: every parallel plane maps it
        if oracle._inlier_fraction(surface, P, n, d + shift * TILT_MOVES * tol / 2, tol) >= TILT_KEEP * base:
            return False
    c = P.mean(axis=0)
    spread = float(np.sqrt(np.mean(np.sum((P - c) ** 2, axis=1))))
    tilt = math.radians(min(TILT_MAX_DEG, math.degrees(math.asin(min(1.0, TILT_MOVES * tol / (2 * spread))))))
    u, v = oracle._in_plane_basis(n)
    for phi in np.arange(8) * math.pi / 8:
        line = math.cos(phi) * u + math.sin(phi) * v
        for sign in (1, -1):
            n2 = math.cos(tilt) * n + sign * math.sin(tilt) * np.cross(line, n)
            o2 = float(n2 @ (c - (n @ c - d) * n))  # through the plane's point nearest c
            kept = max(oracle._inlier_fraction(surface, P, n2, o2 + k * tol / 2, tol) for k in range(-8, 9))
            if kept >= TILT_KEEP * base:
                return False
    return True


@dataclasses.dataclass
class Match:
    """One group-0 report and the nearest restricted report."""
    index: int                  # in the group-0 result
    kind: str
    nearest: int = -1           # in the restricted result, -1 if it reported none of the kind
    angle_deg: float = math.inf  # reflections only
    distance: float = math.inf  # offset (reflection) or translation difference, diagonal fractions
    determined: bool = True     # False: a mirror whose plane its patch does not fix (see containment)

    @property
    def same(self) -> bool:
        if self.kind == REFLECTION:
            return self.angle_deg <= SAME_DEG and self.distance <= SAME_OFFSET
        return self.distance <= SAME_OFFSET


def reports_of_kind(result, kind: str, diag: float) -> List[int]:
    """Indices of the discrete reports of this kind."""
    kinds = result.kinds if result.kinds is not None else np.zeros(result.count, int)
    return [k for k in range(result.count)
            if int(kinds[k]) == 0 and
            kind_of(result.transforms[k], bool(result.is_reflection[k]), float(result.scales[k]),
                    diag) == kind]


def nearest(full, k: int, restricted, kind: str, diag: float, points: np.ndarray) -> Match:
    """The restricted report nearest to group-0 report k (its source patch vertices:
    `points`)."""
    T0 = full.transforms[k]
    m = Match(index=k, kind=kind)
    for j in reports_of_kind(restricted, kind, diag):
        T = restricted.transforms[j]
        if kind == REFLECTION:
            a, o = real_models.mirror_angle_error(T, plane_of(T0, points), diag)
            better = (a / SAME_DEG + o / SAME_OFFSET) < (m.angle_deg / SAME_DEG + m.distance / SAME_OFFSET)
        else:
            a, o = math.nan, min(np.linalg.norm(T[:3, 3] - T0[:3, 3]),
                                 np.linalg.norm(T[:3, 3] + T0[:3, 3])) / diag
            better = o < m.distance
        if better:
            m.nearest, m.angle_deg, m.distance = j, a, o
    return m


def found_as_well(m: Match, full_figures: dict, restricted_figures: dict) -> bool:
    """Whether the restricted run found m's symmetry: the same within SAME_DEG and
    SAME_OFFSET, or (an approximate symmetry, whose plane two fits on different patches put
    a little apart) matching the same planted relation at least as closely as group 0's
    report, by metrics.AccuracyScorer's transform error against ground truth."""
    if m.same:
        return True
    if m.nearest < 0:
        return False
    a = full_figures["reports"][m.index]
    b = restricted_figures["reports"][m.nearest]
    return (a["label"] == "correct" and b["label"] == "correct" and a["matched"] == b["matched"]
            and b["error"] <= a["error"])


def containment(full, restricted, group: int, required: Sequence[int], diag: float,
                vertices: np.ndarray, surface: Optional[oracle.Surface] = None) -> List[Match]:
    """For every group-0 report in `required` of the restricted group's kind, its nearest
    restricted report.  `vertices` stands in for a report's source patch when the result
    carries no patch layer.  Given the clean `surface` (an oracle.Surface), a mirror whose
    plane its patch does not determine is marked so (Match.determined) and need not be
    matched."""
    kind = GROUP_KIND[group]
    of_kind = set(reports_of_kind(full, kind, diag))
    out = []
    for k in required:
        if k not in of_kind:
            continue
        P = full.source_patches.get(k)
        P = P if P is not None and len(P) else vertices
        m = nearest(full, k, restricted, kind, diag, P)
        if kind == REFLECTION and surface is not None:
            m.determined = plane_is_determined(surface, full.transforms[k], P)
        out.append(m)
    return out
