"""A brute-force symmetry oracle that never calls the detector.

The accuracy benchmark must not score the detector with the detector's own acceptance rule
("the reported patch lands on the surface"): two unrelated smooth patches that merely touch
pass that rule.  This module decides geometric questions from the ground-truth surface alone:

* :class:`Surface`: dense uniform samples (with normals) of a CLEAN surface, in a kd-tree.
  Nearest-sample distances overestimate the true distance by at most about the sample
  spacing (0.1 % of the diagonal by default), far below the 1 % tolerances used here.
* :func:`relation_holds`: the fraction of a patch that a transform maps onto the surface
  with agreeing normals (normals are what tells the two faces of a thin plate apart).
* :func:`family_holds`: a continuous family checked at several finite members.
* :func:`global_mirror_planes`, :func:`self_symmetries`: brute-force searches for a mesh's
  own global symmetries, to record the bases' symmetries as ground truth.

Continuous kinds use the filter's public numbering: 0 discrete, 1 rotational,
2 translational, 3 helical, 4 planar, 5 spherical (see scenes.KIND_NAMES).
"""
from __future__ import annotations

import dataclasses
import hashlib
import inspect
import json
import math
import os
from typing import List, Optional, Sequence, Tuple

import numpy as np
import scipy
from scipy.spatial import cKDTree

import scenes as _scenes

#: a mapped normal may tilt this much from the surface normal and still agree
NORMAL_DEGREES = 30.0
#: the angles (degrees) at which a rotational, helical or spherical family is checked
MEMBER_DEGREES = tuple(range(30, 331, 30))


@dataclasses.dataclass
class Surface:
    """Dense samples of a surface: points, unit normals, a kd-tree, the bbox diagonal of the
    mesh and the typical distance between neighbouring samples."""
    points: np.ndarray
    normals: np.ndarray
    tree: cKDTree
    diagonal: float
    spacing: float

    @staticmethod
    def from_mesh(V: np.ndarray, F: np.ndarray, spacing: float = 0.001, seed: int = 0,
                  max_samples: int = 1_500_000) -> "Surface":
        """Sample (V, F) with about one point per (spacing * diagonal)^2 of area."""
        V = np.asarray(V, float)
        F = np.asarray(F, np.int64)
        diag = _scenes.bbox_diagonal(V)
        area = float(_scenes.face_areas(V, F).sum())
        n = int(min(max_samples, max(20000, area / (spacing * diag) ** 2)))
        P, f = _scenes.sample_surface(V, F, n, np.random.default_rng(seed), return_faces=True)
        return Surface(P, _scenes.face_normals(V, F)[f], cKDTree(P), diag,
                       math.sqrt(area / n))

    def distances(self, Q: np.ndarray, cap: float = 0.05) -> np.ndarray:
        """Distance from each point of Q to the nearest sample, capped at cap * diagonal
        (a bounded kd-tree query is fast; far points are all equally "off the surface")."""
        bound = cap * self.diagonal
        d = self.tree.query(np.asarray(Q, float), k=1, distance_upper_bound=bound)[0]
        return np.minimum(d, bound)

    def normals_at(self, Q: np.ndarray) -> np.ndarray:
        """The normal of the nearest sample to each point of Q."""
        return self.normals[self.tree.query(np.asarray(Q, float), k=1)[1]]

    def on_surface(self, Q: np.ndarray, QN: np.ndarray, tol: float,
                   max_degrees: float = NORMAL_DEGREES) -> np.ndarray:
        """Whether each point of Q has a sample within tol whose normal agrees with QN.
        Several neighbours are looked at so that a point near a sharp crease finds the
        samples of its own side."""
        Q = np.asarray(Q, float)
        if len(Q) == 0:
            return np.zeros(0, bool)
        d, i = self.tree.query(Q, k=16, distance_upper_bound=tol)
        found = np.isfinite(d)
        i = np.where(found, i, 0)
        dots = np.einsum("nkj,nj->nk", self.normals[i], QN)
        return (found & (dots >= math.cos(math.radians(max_degrees)))).any(1)


def as_surface(V, F=None, spacing: float = 0.001) -> Surface:
    """A Surface as given, or the dense samples of the mesh (V, F)."""
    return V if isinstance(V, Surface) else Surface.from_mesh(V, F, spacing)


def map_normals(T: np.ndarray, N: np.ndarray) -> np.ndarray:
    """Normals carried by the similarity T.  For a reflection this is the outward normal of
    the reflected solid too (its faces are flipped with it), so no sign change is needed."""
    M = np.asarray(N, float) @ np.asarray(T, float)[:3, :3].T
    return M / np.maximum(np.linalg.norm(M, axis=1, keepdims=True), 1e-300)


def relation_holds(V, F, T: np.ndarray, patch_points: np.ndarray, tol: float,
                   patch_normals: Optional[np.ndarray] = None) -> float:
    """Fraction of the patch that T maps within tol of the surface with agreeing normals.

    V, F: the clean surface as a mesh, or V a :class:`Surface` and F None.  tol is absolute.
    patch_normals default to the surface's normals at the patch points."""
    P = np.asarray(patch_points, float)
    if len(P) == 0:
        return 0.0
    return float(np.mean(mapped_mask(as_surface(V, F), T, P, tol, patch_normals)))


# ----------------------------------------------------------------------------------------
# Continuous families
# ----------------------------------------------------------------------------------------

def _unit(v) -> np.ndarray:
    v = np.asarray(v, float)
    return v / np.linalg.norm(v)


def screw(point, direction, angle: float, shift: float) -> np.ndarray:
    """Rotation by `angle` about the axis (point, direction) followed by a shift along it."""
    d = _unit(direction)
    return _scenes.translation(shift * d) @ _scenes.about(point, _scenes.rotation(d, angle))


def _in_plane_basis(n: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    a = np.eye(3)[int(np.argmin(np.abs(n)))]
    u = _unit(np.cross(n, a))
    return u, np.cross(n, u)


def family_members(kind: int, point, direction, patch_points: np.ndarray, pitch: float = 0.0
                   ) -> List[Tuple[np.ndarray, Optional[np.ndarray]]]:
    """Finite members of a continuous family chosen for a patch, each with the clip box the
    test is restricted to: a partial family (an open extrusion, a finite helix, a flat face)
    maps only the part of the patch whose image stays within the patch's extent.  A clip is
    None (no clip) or (axis, lo, hi): keep points whose image has axis . x in [lo, hi]."""
    p = np.asarray(point, float)
    d = _unit(direction) if kind != _scenes.KIND_SPHERICAL else np.zeros(3)
    P = np.asarray(patch_points, float)
    rad = [math.radians(a) for a in MEMBER_DEGREES]
    out: List[Tuple[np.ndarray, Optional[np.ndarray]]] = []
    if kind == _scenes.KIND_ROTATIONAL:
        out = [(screw(p, d, a, 0.0), None) for a in rad]
    elif kind in (_scenes.KIND_TRANSLATIONAL, _scenes.KIND_HELICAL):
        t = P @ d
        # a margin: the end of a tube is not square to the axis
        lo, hi = float(t.min()), float(t.max())
        lo, hi = lo + 0.1 * (hi - lo), hi - 0.1 * (hi - lo)
        if kind == _scenes.KIND_TRANSLATIONAL:
            out = [(_scenes.translation(f * 1.25 * (hi - lo) * d), None)
                   for f in (-0.4, -0.25, -0.1, 0.1, 0.25, 0.4)]
        else:
            out = [(screw(p, d, a, pitch * a), None) for a in rad[::2]]
            out += [(screw(p, d, -a, -pitch * a), None) for a in rad[::2]]
        out = [(T, (d, lo, hi)) for T, _ in out]
    elif kind == _scenes.KIND_PLANAR:
        # small motions, so that even a long narrow face still overlaps its own image
        u, v = _in_plane_basis(d)
        c = P.mean(0)
        c = c - ((c - p) @ d) * d
        out = [(screw(c, d, math.radians(a), 0.0), "footprint") for a in (-30, -15, 15, 30)]
        out += [(_scenes.translation(s * float(np.ptp(P @ w)) * w), "footprint")
                for w in (u, v) for s in (-0.15, 0.15)]
    elif kind == _scenes.KIND_SPHERICAL:
        out = [(screw(p, w, a, 0.0), None) for w in np.eye(3) for a in rad[::3]]
    return out


def _clipped(T, clip, P: np.ndarray, footprint: Optional[cKDTree], fp_radius: float,
             plane: Optional[Tuple[np.ndarray, np.ndarray, np.ndarray]]) -> np.ndarray:
    """Mask of the patch points whose image lies inside the patch's own extent."""
    Q = _scenes.apply(T, P)
    if clip is None:
        return np.ones(len(P), bool)
    if isinstance(clip, str):  # planar: inside the patch's 2-D footprint
        o, u, v = plane
        uv = np.stack([(Q - o) @ u, (Q - o) @ v], 1)
        return footprint.query(uv, k=1)[0] <= fp_radius
    axis, lo, hi = clip
    t = Q @ axis
    return (t >= lo) & (t <= hi)


def _interior_footprint(P: np.ndarray, point, normal: np.ndarray):
    """The patch projected into its plane, eroded: a flat face's in-plane motions are
    checked only where the image falls well inside the face, not on the band just beyond its
    edge.  Interior points have most of their neighbours all around them (a boundary point
    has about half as many within the same radius).  Returns (kd-tree of the interior 2-D
    points, query radius, (origin, u, v))."""
    u, v = _in_plane_basis(normal)
    o = np.asarray(point, float)
    uv = np.stack([(P - o) @ u, (P - o) @ v], 1)
    tree = cKDTree(uv)
    spacing = float(np.median(tree.query(uv, k=2)[0][:, 1]))
    counts = np.array([len(x) for x in tree.query_ball_point(uv, 4 * spacing)])
    interior = uv[counts >= 0.8 * np.median(counts)]
    return cKDTree(interior if len(interior) >= 10 else uv), 2.5 * spacing, (o, u, v)


def family_holds(surface: Surface, kind: int, point, direction, patch_points: np.ndarray,
                 tol: float, pitch: float = 0.0, min_fraction: float = 0.9,
                 patch_normals: Optional[np.ndarray] = None) -> dict:
    """Check a claimed continuous family on a clean surface at finite members.

    Every member must map at least min_fraction of the (clipped) patch onto the surface with
    agreeing normals, and the clip must leave at least a quarter of the patch to test.
    Returns dict(holds, worst, fractions)."""
    P = np.asarray(patch_points, float)
    if len(P) < 10:
        return dict(holds=False, worst=0.0, fractions=[])
    N = surface.normals_at(P) if patch_normals is None else patch_normals
    d = _unit(direction) if kind != _scenes.KIND_SPHERICAL else np.zeros(3)
    footprint = plane = None
    fp_radius = 0.0
    if kind == _scenes.KIND_PLANAR:
        footprint, fp_radius, plane = _interior_footprint(P, point, d)
    fractions = []
    for T, clip in family_members(kind, point, direction, P, pitch):
        keep = _clipped(T, clip, P, footprint, fp_radius, plane)
        if keep.mean() < 0.25:
            fractions.append(0.0)
            continue
        ok = surface.on_surface(_scenes.apply(T, P[keep]), map_normals(T, N[keep]), tol)
        fractions.append(float(ok.mean()))
    worst = min(fractions) if fractions else 0.0
    return dict(holds=bool(fractions) and worst >= min_fraction, worst=worst,
                fractions=fractions)


# ----------------------------------------------------------------------------------------
# Global self-symmetries of a mesh
# ----------------------------------------------------------------------------------------

@dataclasses.dataclass
class MirrorPlane:
    normal: np.ndarray
    offset: float        # the plane is {x : normal . x = offset}
    fraction: float      # of the samples mirrored within tol with agreeing normals
    residual: float      # median distance of those inliers, diagonal fraction

    @property
    def transform(self) -> np.ndarray:
        return _scenes.translation(2 * self.offset * self.normal) @ _scenes.mirror(self.normal)


def fibonacci_hemisphere(n: int) -> np.ndarray:
    """n nearly uniform unit vectors with z >= 0 (a plane normal and its negative are one)."""
    k = np.arange(n) + 0.5
    z = 1 - k / n
    r = np.sqrt(1 - z * z)
    phi = k * math.pi * (3 - math.sqrt(5))
    return np.stack([r * np.cos(phi), r * np.sin(phi), z], 1)


def _reflect(P: np.ndarray, n: np.ndarray, o: float) -> np.ndarray:
    return P - 2 * ((P @ n) - o)[:, None] * n


def _inlier_fraction(S: Surface, P: np.ndarray, n: np.ndarray, o: float, tol: float) -> float:
    """Fraction of P mirrored within tol of the surface (a bounded query: fast)."""
    d = S.tree.query(_reflect(P, n, o), k=1, distance_upper_bound=tol)[0]
    return float(np.isfinite(d).mean())


def _mirror_cost(S: Surface, P: np.ndarray, n: np.ndarray, o: float, t: float) -> float:
    """Mean distance of the mirrored samples to the surface, each capped at t: a robust
    score, so that the asymmetric rest of a partly symmetric shape does not pull the plane."""
    d = S.tree.query(_reflect(P, n, o), k=1, distance_upper_bound=t)[0]
    return float(np.minimum(d, t).mean())


def _refine_mirror(S: Surface, P: np.ndarray, n: np.ndarray, o: float, t: float,
                   steps_deg: Sequence[float] = (2.0, 1.0, 0.5, 0.25, 0.1, 0.05)
                   ) -> Tuple[np.ndarray, float]:
    """Pattern search on the plane (two tilts of the normal and the offset) minimising the
    capped mirror cost, with shrinking steps.  (Mirror ICP, which fits the plane to mirror
    pairs, drifts by a degree on a partly symmetric shape; this does not.)"""
    best = _mirror_cost(S, P, n, o, t)
    for step in steps_deg:
        a = math.radians(step)
        improved = True
        while improved:
            improved = False
            u, v = _in_plane_basis(n)
            for dn, do in ((u, 0), (-u, 0), (v, 0), (-v, 0), (0, 1), (0, -1)):
                n2 = _unit(n + math.tan(a) * dn)
                o2 = o + do * a * 0.5 * S.diagonal
                c = _mirror_cost(S, P, n2, o2, t)
                if c < best:
                    n, o, best, improved = n2, o2, c, True
    return n, o


#: tolerance (fraction of the shape's diagonal) of a (near) exact self-symmetry.  Measured:
#: exact shapes (the airplane, the bone, CAD parts) mirror 90-100 % of their surface within
#: it, random bumpy blobs at most 40 %; at 1 % a blob's best plane maps 85 % of it.
EXACT_TOL = 0.0025


def global_mirror_planes(V, F=None, min_fraction: float = 0.7, tol: float = EXACT_TOL,
                         n_directions: int = 800, n_points: int = 2000, seed: int = 0,
                         max_refined: int = 12) -> List[MirrorPlane]:
    """Mirror planes of a shape found by brute force.

    Every candidate normal of a dense hemisphere set, through the area centroid, is scored by
    the fraction of a few hundred samples it mirrors within a loose tolerance (2 % of the
    diagonal, so that a candidate a few degrees off still scores); the best local maxima are
    refined by a pattern search, first at the loose tolerance then at 2 tol, and kept if
    they mirror at least min_fraction of the samples within tol with agreeing normals.
    Returns the distinct planes, best first.  (Sampled at 0.2 % spacing when given a mesh:
    a kd-tree over four times as many samples made the search six times slower.)"""
    S = as_surface(V, F, spacing=0.002)
    t, loose = tol * S.diagonal, max(2 * tol, 0.02) * S.diagonal
    rng = np.random.default_rng(seed)
    pick = rng.choice(len(S.points), size=min(n_points, len(S.points)), replace=False)
    P, PN = S.points[pick], S.normals[pick]
    scan = P[: max(300, n_points // 4)]
    c = S.points.mean(0)
    dirs = fibonacci_hemisphere(n_directions)
    score = np.array([_inlier_fraction(S, scan, n, float(n @ c), loose) for n in dirs])
    # neighbours on the projective sphere: the closest few directions (and their negatives)
    near = cKDTree(np.concatenate([dirs, -dirs])).query(dirs, k=9)[1] % len(dirs)
    maxima = [i for i in range(len(dirs)) if score[i] >= score[near[i]].max()
              and score[i] >= 0.5 * min_fraction]
    found: List[MirrorPlane] = []
    for i in sorted(maxima, key=lambda i: -score[i])[:max_refined]:
        n, o = _refine_mirror(S, P[:1000], dirs[i], float(dirs[i] @ c), loose)
        n, o = _refine_mirror(S, P[:1000], n, o, 2 * t, steps_deg=(0.25, 0.1, 0.05, 0.02))
        if any(abs(abs(n @ m.normal) - 1) < 1e-3 and
               abs(o * np.sign(n @ m.normal) - m.offset) < 0.005 * S.diagonal for m in found):
            continue
        T = _scenes.translation(2 * o * n) @ _scenes.mirror(n)
        ok = S.on_surface(_scenes.apply(T, P), map_normals(T, PN), t)
        if ok.mean() < min_fraction:
            continue
        d = S.distances(_reflect(P[ok], n, o))
        found.append(MirrorPlane(n, o, float(ok.mean()), float(np.median(d) / S.diagonal)))
    return sorted(found, key=lambda m: -m.fraction)


#: Where self_symmetries keeps the answers it computed (one JSON file each).  The search
#: takes minutes on a small part, whose tolerance is large against its own size (2.5 minutes
#: for each part of the 1 % scene); the answer depends only on the inputs and the code, so it
#: is recorded under a key of both (see _answer_key): a changed mesh, sampling, tolerance,
#: oracle or library version is a new key, computed afresh.  Recorded by this oracle alone,
#: never by the detector; tests/python/test_hard_scenes_truth.py checks a recorded answer
#: against a fresh search.
ANSWERS_DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "oracle_answers")


def _answer_key(V, F, S: Surface, min_fraction: float, tol: float, max_fold: int) -> str:
    """A digest of everything self_symmetries' answer depends on: the mesh, its samples, the
    parameters, the source of this module and of the scenes helpers it calls, and the
    versions of numpy and scipy."""
    h = hashlib.sha256()
    for a in (np.asarray(V, np.float64), np.asarray(F, np.int64), S.points, S.normals):
        h.update(np.ascontiguousarray(a).tobytes())
    h.update(repr((min_fraction, tol, max_fold, S.diagonal, np.__version__, scipy.__version__)).encode())
    with open(__file__, "rb") as source:
        h.update(source.read())
    for helper in (_scenes.principal_frame, _scenes.candidate_self_symmetries, _scenes.about, _scenes.linear,
                   _scenes.mirror, _scenes.translation, _scenes.apply):
        h.update(inspect.getsource(helper).encode())
    return h.hexdigest()[:32]


def self_symmetries(V, F, min_fraction: float = 0.7, tol: float = EXACT_TOL, max_fold: int = 8,
                    surface: Optional[Surface] = None, recorded: bool = True
                    ) -> List[Tuple[str, np.ndarray, float]]:
    """A mesh's own global (or mostly global) symmetries as (name, 4x4 transform, fraction of
    the surface it maps within tol of the diagonal with agreeing normals): the mirror planes
    of :func:`global_mirror_planes` and those principal-axis candidates of
    scenes.candidate_self_symmetries (rotations, half-turns, point reflection) that map at
    least min_fraction of the shape onto itself.  `surface`: (V, F) already sampled.
    `recorded`: use (and keep) the answer recorded in ANSWERS_DIR for the same inputs."""
    S = surface or Surface.from_mesh(V, F, spacing=0.002)
    if not recorded:
        return _search_self_symmetries(V, F, S, min_fraction, tol, max_fold)
    path = os.path.join(ANSWERS_DIR, _answer_key(V, F, S, min_fraction, tol, max_fold) + ".json")
    if os.path.exists(path):
        with open(path) as f:
            return [(name, np.array(T, float), fraction) for name, T, fraction in json.load(f)]
    found = _search_self_symmetries(V, F, S, min_fraction, tol, max_fold)
    try:
        os.makedirs(ANSWERS_DIR, exist_ok=True)
        with open(path + ".tmp", "w") as f:  # renamed into place: a reader never sees half a file
            json.dump([(name, np.asarray(T).tolist(), float(fraction)) for name, T, fraction in found], f)
        os.replace(path + ".tmp", path)
    except OSError:
        pass  # a read-only checkout computes the answer each time
    return found


def _search_self_symmetries(V, F, S: Surface, min_fraction: float, tol: float, max_fold: int
                            ) -> List[Tuple[str, np.ndarray, float]]:
    """self_symmetries, searched by brute force."""
    found = [(f"mirror {np.round(m.normal, 3).tolist()}", m.transform, m.fraction)
             for m in global_mirror_planes(S, min_fraction=min_fraction, tol=tol)]
    rng = np.random.default_rng(1)
    pick = rng.choice(len(S.points), size=min(2000, len(S.points)), replace=False)
    m, _, _ = _scenes.principal_frame(V, F)
    for name, A in _scenes.candidate_self_symmetries(V, F, max_fold):
        if np.linalg.det(A) < 0 and abs(np.trace(A) - 1) < 1e-6:
            continue  # a plane reflection: the brute-force search above covers them
        T = _scenes.about(m, _scenes.linear(A))
        f = relation_holds(S, None, T, S.points[pick], tol * S.diagonal, S.normals[pick])
        if f >= min_fraction:
            found.append((name, T, f))
    return found


def mapped_mask(surface: Surface, T: np.ndarray, points: np.ndarray, tol: float,
                normals: Optional[np.ndarray] = None) -> np.ndarray:
    """Per point: whether T maps it within tol (absolute) of the surface, normals agreeing."""
    P = np.asarray(points, float)
    N = surface.normals_at(P) if normals is None else normals
    return surface.on_surface(_scenes.apply(T, P), map_normals(T, N), tol)


def region_samples(V: np.ndarray, F: np.ndarray, vertices: np.ndarray, n: int = 4000,
                   seed: int = 0) -> np.ndarray:
    """n points uniform over the faces whose three vertices are all in `vertices`: a dense,
    even stand-in for a region when its vertices are few or unevenly spread.  Falls back to
    the vertices themselves when no face lies wholly inside."""
    inside = np.zeros(len(V), bool)
    inside[np.asarray(vertices, np.int64)] = True
    faces = F[inside[F].all(1)]
    if len(faces) == 0:
        return V[inside]
    return _scenes.sample_surface(V, faces, n, np.random.default_rng(seed))


def subsample(P: np.ndarray, n: int = 3000, seed: int = 0) -> np.ndarray:
    """At most n of the points (deterministic), to keep brute-force checks fast."""
    P = np.asarray(P)
    if len(P) <= n:
        return P
    return P[np.random.default_rng(seed).choice(len(P), n, replace=False)]
