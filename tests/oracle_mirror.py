#!/usr/bin/env python3
"""Brute-force oracle for the global mirror planes of a triangle mesh.

It is the ground truth of the real-model benchmark (tests/real_models.json), so it shares
nothing with the detector under test: numpy, scipy's kd-tree and pymeshlab's file loader only.

    python tests/oracle_mirror.py MESH [--directions N] [--seed S]

How it works, and why:

* The surface is sampled area-uniformly (so that a residual statistic weighs the surface, not
  the tessellation) with each sample's face normal.
* A mirror plane of the whole surface maps the surface onto itself, so it maps the area
  centroid onto itself: the plane passes through the centroid.  The search therefore only
  has to try normals: a Fibonacci grid over the half sphere (a plane and its flipped normal
  are one plane) plus the principal axes.
* A candidate plane is scored by a robust statistic (the 80th percentile) of the distance
  from each reflected query sample to the surface, counting only surface points whose normal
  agrees with the reflected normal, so that a reflection which lays a surface across another
  one (a thin plate mirrored onto its flank) does not score well.  The percentile tolerates
  the parts of a scan that are not symmetric (a raised arm, a scan hole).
* The best few directions (after non-maximum suppression) are refined by reflection-only ICP
  (point-to-plane Gauss-Newton on the plane's two tilts and offset, trimmed to the best 80 %
  of the pairs).
* Final residuals use exact point-to-triangle distances (no sampling floor), as fractions of
  the bounding-box diagonal: median, 80th and 90th percentiles, and the fraction of the
  surface within 0.5 %, 1 % and 2 % of the diagonal.  A sample with no counterpart within
  5 % counts as 5 %, so the statistics saturate there.
* The mirror planes are the refined planes before the largest gap in residual, the last within
  2 % (mirror_count).  The verdict is clear when the best plane more than 10 degrees from all
  of them is at least twice as bad (OracleResult.margin), and each mirror plane gets a
  spread: how far it moves when refined on other sample sets.

A plane is given as a unit normal n and an offset d: the points x with n . x = d.
"""
from __future__ import annotations

import argparse
import dataclasses
import math
import os
import sys
from typing import Dict, List, Optional, Sequence, Tuple

import numpy as np
from scipy.spatial import cKDTree

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from scenes import bbox_diagonal, face_areas  # noqa: E402  (numpy only)

#: the percentile that scores a plane: tolerant to 20 % of the surface being asymmetric
SCORE_PERCENTILE = 80.0
#: a surface point counts as the mirror counterpart only if the normals agree this well
#: (unoriented: the test meshes are not all consistently oriented)
NORMAL_AGREEMENT_DEG = 45.0
#: the distance given to a sample without any counterpart of agreeing normal (fraction of diag)
NO_COUNTERPART = 0.05
#: the "within" fractions reported, as fractions of the diagonal
WITHIN = (0.005, 0.01, 0.02)
#: two planes are the same plane when their normals and offsets are this close
SAME_PLANE_DEG = 5.0
SAME_PLANE_OFFSET = 0.02
#: nearest samples whose faces are candidates of a query (exact distances, search)
NEIGHBOURS = 8
SEARCH_NEIGHBOURS = 4
#: samples in the kd-tree of the direction search (the exact distances use all of them)
COARSE_SAMPLES = 30_000


# ----------------------------------------------------------------------------------------
# Geometry
# ----------------------------------------------------------------------------------------

def load_mesh(path: str) -> Tuple[np.ndarray, np.ndarray]:
    """(V, F) of a mesh file as pymeshlab reads it, polygons triangulated; vertices that no
    face uses are dropped, since they would enlarge the bounding box."""
    import pymeshlab
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(path)
    m = ms.current_mesh()
    V, F = m.vertex_matrix().astype(np.float64), m.face_matrix().astype(np.int64)
    used, F = np.unique(F, return_inverse=True)
    return V[used], F.reshape(-1, 3)


def area_centroid(V: np.ndarray, F: np.ndarray) -> np.ndarray:
    a = face_areas(V, F)
    return (V[F].mean(1) * a[:, None]).sum(0) / a.sum()


def face_normals(V: np.ndarray, F: np.ndarray) -> np.ndarray:
    n = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    return n / np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)


def reflect(points: np.ndarray, n: np.ndarray, d: float) -> np.ndarray:
    """Mirror points across the plane n . x = d (for directions, pass d = 0)."""
    return points - 2.0 * (points @ n - d)[:, None] * n[None, :]


def reflection_matrix(n: np.ndarray, d: float) -> np.ndarray:
    """The 4x4 reflection across the plane n . x = d."""
    T = np.eye(4)
    T[:3, :3] -= 2.0 * np.outer(n, n)
    T[:3, 3] = 2.0 * d * n
    return T


def closest_points_on_triangles(P: np.ndarray, A: np.ndarray, B: np.ndarray,
                                C: np.ndarray) -> np.ndarray:
    """Closest point to P[i] on the triangle (A[i], B[i], C[i]), all rows at once
    (Ericson, Real-Time Collision Detection, 5.1.5, by barycentric regions)."""
    ab, ac, ap = B - A, C - A, P - A
    d1, d2 = (ab * ap).sum(1), (ac * ap).sum(1)
    bp = P - B
    d3, d4 = (ab * bp).sum(1), (ac * bp).sum(1)
    cp = P - C
    d5, d6 = (ab * cp).sum(1), (ac * cp).sum(1)
    va, vb, vc = d3 * d6 - d5 * d4, d5 * d2 - d1 * d6, d1 * d4 - d3 * d2
    with np.errstate(divide="ignore", invalid="ignore"):
        denom = va + vb + vc
        v, w = vb / denom, vc / denom                      # inside the face
        out = A + ab * v[:, None] + ac * w[:, None]
        regions = [  # (mask, point), later entries win, so vertices come last
            ((vc <= 0) & (d1 >= 0) & (d3 <= 0), A + ab * (d1 / (d1 - d3))[:, None]),
            ((vb <= 0) & (d2 >= 0) & (d6 <= 0), A + ac * (d2 / (d2 - d6))[:, None]),
            ((va <= 0) & (d4 - d3 >= 0) & (d5 - d6 >= 0),
             B + (C - B) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)))[:, None]),
            ((d1 <= 0) & (d2 <= 0), A), ((d3 >= 0) & (d4 <= d3), B), ((d6 >= 0) & (d5 <= d6), C),
        ]
    for mask, point in regions:
        out[mask] = point[mask]
    bad = ~np.isfinite(out).all(1)                          # degenerate triangles
    out[bad] = A[bad]
    return out


def fibonacci_hemisphere(count: int) -> np.ndarray:
    """About `count` nearly uniform unit vectors with z >= 0 (one per plane orientation)."""
    m = 2 * count
    i = np.arange(m) + 0.5
    z = 1.0 - 2.0 * i / m
    r = np.sqrt(1.0 - z * z)
    phi = i * math.pi * (3.0 - math.sqrt(5.0))
    U = np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1)
    return U[z >= 0]


def canonical_plane(n: np.ndarray, d: float) -> Tuple[np.ndarray, float]:
    """The same plane with a unit normal whose largest component is positive, so that a plane
    has one spelling in the records."""
    n = np.asarray(n, float)
    s = np.linalg.norm(n)
    n, d = n / s, d / s
    if n[np.argmax(np.abs(n))] < 0:
        n, d = -n, -d
    return n, float(d)


def same_plane(a: Tuple[np.ndarray, float], b: Tuple[np.ndarray, float], diag: float,
               max_deg: float = SAME_PLANE_DEG, max_offset: float = SAME_PLANE_OFFSET) -> bool:
    """Whether two planes (n, d) are one: normals within max_deg (either sign) and offsets
    within max_offset of the diagonal."""
    c = float(np.dot(a[0], b[0]))
    s = 1.0 if c >= 0 else -1.0
    return (math.degrees(math.acos(min(1.0, abs(c)))) <= max_deg
            and abs(a[1] - s * b[1]) <= max_offset * diag)


# ----------------------------------------------------------------------------------------
# The surface and its distance query
# ----------------------------------------------------------------------------------------

class Surface:
    """A mesh with a dense area-uniform sample set in a kd-tree.  It answers: how far is a
    point from the part of the surface whose normal agrees with a given normal?  Either to the
    nearest sample (cheap, floor of about half the sample spacing: for the search) or to the
    faces of the nearest samples (exact: for the residuals)."""

    def __init__(self, V: np.ndarray, F: np.ndarray, samples: int = 200_000, seed: int = 0):
        self.V, self.F = np.asarray(V, float), np.asarray(F, np.int64)
        self.diag = bbox_diagonal(self.V)
        self.centroid = area_centroid(self.V, self.F)
        self.normals = face_normals(self.V, self.F)
        self.area = face_areas(self.V, self.F)
        self.points, self.faces = self.sample(samples, np.random.default_rng(seed))
        self.tree = cKDTree(self.points)
        # the samples are i.i.d., so a prefix is a uniform sample too: a smaller tree for the
        # thousands of queries of the search
        self.coarse = cKDTree(self.points[:COARSE_SAMPLES])

    def sample(self, count: int, rng: np.random.Generator) -> Tuple[np.ndarray, np.ndarray]:
        """count area-uniform points and the index of the face each lies on."""
        f = rng.choice(len(self.F), size=count, p=self.area / self.area.sum())
        r1, r2 = np.sqrt(rng.random(count)), rng.random(count)
        w = np.stack([1 - r1, r1 * (1 - r2), r1 * r2], axis=1)
        return (self.V[self.F[f]] * w[:, :, None]).sum(1), f

    def distances(self, Q: np.ndarray, NQ: np.ndarray, exact: bool = False
                  ) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
        """For each point Q[i] with normal NQ[i]: the distance to the surface counted over
        faces whose normal agrees with NQ[i] (unoriented), the closest such point and its face.
        Points without an agreeing face nearby get NO_COUNTERPART * diag, themselves and -1."""
        cap = NO_COUNTERPART * self.diag
        tree = self.tree if exact else self.coarse
        # the bound makes far-off queries (most of a wrong plane's) cheap; missing neighbours
        # come back as index tree.n
        k = NEIGHBOURS if exact else SEARCH_NEIGHBOURS
        dist, idx = tree.query(Q, k=k, distance_upper_bound=cap)
        found = idx < tree.n
        idx = np.where(found, idx, 0)
        faces = self.faces[idx]
        agree = found & (np.abs(np.einsum("mkj,mj->mk", self.normals[faces], NQ))
                         >= math.cos(math.radians(NORMAL_AGREEMENT_DEG)))
        if exact:
            q = np.repeat(Q, k, axis=0)
            T = self.V[self.F[faces.ravel()]]
            C = closest_points_on_triangles(q, T[:, 0], T[:, 1], T[:, 2]).reshape(len(Q), k, 3)
            dist = np.linalg.norm(C - Q[:, None, :], axis=2)
        else:
            C = self.points[idx]
        dist = np.where(agree, dist, np.inf)
        best = np.argmin(dist, axis=1)
        rows = np.arange(len(Q))
        d, c, f = dist[rows, best], C[rows, best], faces[rows, best]
        none = ~(d <= cap)
        d[none], c[none], f[none] = cap, Q[none], -1
        return d, c, f

    def mirror_distances(self, Q: np.ndarray, NQ: np.ndarray, n: np.ndarray, d: float,
                         exact: bool = False) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
        """distances() of the samples (Q, NQ) reflected across the plane n . x = d."""
        return self.distances(reflect(Q, n, d), reflect(NQ, n, 0.0), exact)


# ----------------------------------------------------------------------------------------
# Residuals, search, refinement
# ----------------------------------------------------------------------------------------

def residual_stats(dist: np.ndarray, diag: float) -> Dict[str, float]:
    """The residual statistics of a plane, as fractions of the diagonal (and of the area)."""
    r = dist / diag
    out = {"median": float(np.median(r)),
           "p80": float(np.percentile(r, SCORE_PERCENTILE)),
           "p90": float(np.percentile(r, 90.0))}
    for t in WITHIN:
        out[f"within_{t * 100:g}pct"] = float(np.mean(r <= t))
    return out


def evaluate_plane(surface: Surface, n: Sequence[float], d: float, queries: int = 20_000,
                   seed: int = 1) -> Dict[str, float]:
    """Exact residual statistics of the plane n . x = d on fresh samples (a seed apart from
    the surface's own, so a sample is never its own counterpart)."""
    Q, f = surface.sample(queries, np.random.default_rng(seed))
    n = np.asarray(n, float)
    dist = surface.mirror_distances(Q, surface.normals[f], n, float(d), exact=True)[0]
    return residual_stats(dist, surface.diag)


def scan_directions(surface: Surface, Q: np.ndarray, NQ: np.ndarray,
                    directions: np.ndarray) -> np.ndarray:
    """The score (80th-percentile distance / diag, sample distances) of the plane through the
    area centroid with each normal."""
    scores = np.empty(len(directions))
    for i, n in enumerate(directions):
        dist = surface.mirror_distances(Q, NQ, n, float(n @ surface.centroid))[0]
        scores[i] = np.percentile(dist, SCORE_PERCENTILE) / surface.diag
    return scores


def best_directions(directions: np.ndarray, scores: np.ndarray, keep: int,
                    separation_deg: float = 10.0) -> List[int]:
    """Indices of the `keep` best-scoring directions, each at least separation_deg from the
    better ones (non-maximum suppression over unoriented normals)."""
    cos_sep = math.cos(math.radians(separation_deg))
    chosen: List[int] = []
    for i in np.argsort(scores):
        if all(abs(directions[i] @ directions[j]) < cos_sep for j in chosen):
            chosen.append(int(i))
            if len(chosen) == keep:
                break
    return chosen


def tangent_basis(n: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """Two unit vectors orthogonal to n and to each other."""
    u = np.cross(n, [1.0, 0.0, 0.0] if abs(n[0]) < 0.9 else [0.0, 1.0, 0.0])
    u /= np.linalg.norm(u)
    return u, np.cross(n, u)


def refine_plane(surface: Surface, Q: np.ndarray, NQ: np.ndarray, n: np.ndarray, d: float,
                 iterations: int = 30) -> Tuple[np.ndarray, float]:
    """Reflection-only ICP, point-to-plane.  Each sample q is paired with the surface point c
    nearest to its mirror image R(q) (best 80 % of the pairs kept), and the plane's normal
    (two tilts) and offset are solved by Gauss-Newton so that R(q) moves onto the tangent
    plane at c.  Fitting the plane to the midpoints of q and c (point-to-point) converges
    far too slowly: the pairs slide along the surface and a 3 degree error takes hundreds of
    iterations to vanish.  Coordinates are centred on the area centroid for conditioning."""
    c0 = surface.centroid
    q_all = Q - c0
    dc = d - n @ c0
    for _ in range(iterations):
        dist, C, f = surface.mirror_distances(Q, NQ, n, dc + n @ c0, exact=True)
        keep = (dist <= np.percentile(dist, SCORE_PERCENTILE)) & (f >= 0)
        q, c, m = q_all[keep], C[keep] - c0, surface.normals[f[keep]]
        h = q @ n - dc                                    # signed height over the plane
        r = ((q - 2.0 * h[:, None] * n - c) * m).sum(1)   # point-to-plane residual of R(q)
        # R(q) = q - 2 h n with h = n . q - dc: the derivatives of m . R(q) by the tilts
        # (n += a u + b v) and by dc
        u, v = tangent_basis(n)
        mn = m @ n
        J = -2.0 * np.stack([(q @ u) * mn + h * (m @ u), (q @ v) * mn + h * (m @ v), -mn], axis=1)
        JtJ = J.T @ J
        step = np.linalg.solve(JtJ + 1e-9 * np.trace(JtJ) * np.eye(3), -J.T @ r)
        tilt = np.hypot(step[0], step[1])
        if tilt > math.radians(5.0):                      # a linearisation is only local
            step *= math.radians(5.0) / tilt
        n = n + step[0] * u + step[1] * v
        n /= np.linalg.norm(n)
        dc += step[2]
        if tilt < 1e-9 and abs(step[2]) < 1e-9 * surface.diag:
            break
    return n, float(dc + n @ c0)


# ----------------------------------------------------------------------------------------
# The oracle
# ----------------------------------------------------------------------------------------

#: a mirror plane of the model, exact or approximate, has an 80th-percentile residual of at
#: most this (fraction of the diagonal)
ACCEPT_P80 = 0.02
#: ... and the model's mirror planes are unambiguous when every other plane's residual is at
#: least this many times the worst accepted one
CLEAR_MARGIN = 2.0
#: residuals below this (fraction of the diagonal) are all alike to the margin: on a part
#: made of large flat faces, a plane perpendicular to them maps 80 % of the surface into
#: itself whether or not it is a mirror plane, so two such planes must not look far apart
RESOLUTION = 1e-4
#: "every other plane": normals at least this far from every accepted plane's (also the
#: separation of the candidates refined)
OTHER_PLANE_DEG = 10.0


@dataclasses.dataclass(eq=False)
class MirrorPlane:
    normal: np.ndarray          # unit, canonical sign (canonical_plane)
    offset: float               # the plane is normal . x = offset
    stats: Dict[str, float]     # residual_stats of the plane
    #: how well the surface pins the plane down: the largest angle (degrees) to the planes
    #: refined from it on other sample sets (set for mirror planes only)
    spread_deg: Optional[float] = None

    def as_dict(self) -> dict:
        out = {"normal": [round(float(x), 9) for x in self.normal],
               "offset": round(self.offset, 9),
               "residual": {k: round(v, 6) for k, v in self.stats.items()}}
        if self.spread_deg is not None:
            out["spread_deg"] = round(self.spread_deg, 4)
        return out


@dataclasses.dataclass
class OracleResult:
    diag: float
    centroid: np.ndarray
    planes: List[MirrorPlane]     # accepted mirror planes, best (lowest p80) first
    rejected: List[MirrorPlane]   # the best other planes, best first (at least one)

    @property
    def margin(self) -> float:
        """Best rejected residual over the worst accepted one (0 when nothing is accepted):
        how clearly the mirror planes stand out from every other plane."""
        if not self.planes:
            return 0.0
        worst = max(RESOLUTION, max(p.stats["p80"] for p in self.planes))
        return max(RESOLUTION, self.rejected[0].stats["p80"]) / worst

    @property
    def is_clear(self) -> bool:
        return bool(self.planes) and self.margin >= CLEAR_MARGIN


def principal_axes(points: np.ndarray) -> np.ndarray:
    """The three principal axes of a point set (rows)."""
    return np.linalg.eigh(np.cov((points - points.mean(0)).T))[1].T


def mirror_count(p80: Sequence[float], accept: float = ACCEPT_P80) -> int:
    """How many of the planes (residuals in ascending order) are mirror planes: those before
    the largest ratio between consecutive residuals, the last of them within `accept`.  An
    absolute bound alone would not do: on a thin shape a plane tilted by 10 degrees can stay
    within 1 % while the true planes are at 0.01 %."""
    best_k, best_ratio = 0, 0.0
    for k in range(1, len(p80) + 1):
        if p80[k - 1] > accept:
            break
        # past the last candidate the gap is unknown (the caller measures it against the
        # best plane far from all of them): count it as just clear
        ratio = (max(p80[k], RESOLUTION) / max(p80[k - 1], RESOLUTION) if k < len(p80)
                 else CLEAR_MARGIN)
        if ratio > best_ratio:
            best_k, best_ratio = k, ratio
    return best_k


def refined_candidates(surface: Surface, dirs: np.ndarray, scores: np.ndarray, candidates: int,
                       rng: np.random.Generator, final_queries: int, seed: int
                       ) -> List[MirrorPlane]:
    """Refine the best distinct directions of the scan into planes with exact residuals;
    candidates that the refinement brings onto one plane are kept once."""
    Q, f = surface.sample(final_queries // 3, rng)
    planes: List[MirrorPlane] = []
    for i in best_directions(dirs, scores, candidates, OTHER_PLANE_DEG):
        start = (dirs[i], float(dirs[i] @ surface.centroid))
        refined = refine_plane(surface, Q, surface.normals[f], *start)
        tried = [(canonical_plane(*p), evaluate_plane(surface, *p, final_queries, seed + 1))
                 for p in (refined, start)]
        (n, d), stats = min(tried, key=lambda t: t[1]["p80"])  # ICP must not make it worse
        if not any(same_plane((n, d), (p.normal, p.offset), surface.diag) for p in planes):
            planes.append(MirrorPlane(n, d, stats))
    return sorted(planes, key=lambda p: p.stats["p80"])


def find_mirror_planes(V: np.ndarray, F: np.ndarray, directions: int = 4000,
                       candidates: int = 8, seed: int = 0, surface_samples: int = 200_000,
                       search_queries: int = 2000, final_queries: int = 20_000,
                       accept: float = ACCEPT_P80) -> OracleResult:
    """Scan all plane normals through the area centroid, refine the best distinct ones, and
    split them into mirror planes and the rest (mirror_count).  The rest always holds the
    best scanned plane far from every mirror plane, so that the margin is measured even when
    all candidates refine onto the mirror planes.  Deterministic."""
    surface = Surface(V, F, surface_samples, seed)
    rng = np.random.default_rng(seed + 2)
    Q, f = surface.sample(search_queries, rng)
    dirs = np.vstack([fibonacci_hemisphere(directions), principal_axes(surface.points)])
    scores = scan_directions(surface, Q, surface.normals[f], dirs)
    planes = refined_candidates(surface, dirs, scores, candidates, rng, final_queries, seed)
    k = mirror_count([p.stats["p80"] for p in planes], accept)
    good, rejected = planes[:k], planes[k:]
    cos_far = math.cos(math.radians(OTHER_PLANE_DEG))
    far = np.all([np.abs(dirs @ p.normal) < cos_far for p in good], axis=0) if good \
        else np.ones(len(dirs), bool)
    if far.any():
        n = dirs[np.flatnonzero(far)[np.argmin(scores[far])]]
        n, d = canonical_plane(n, float(n @ surface.centroid))
        rejected.append(MirrorPlane(n, d, evaluate_plane(surface, n, d, final_queries, seed + 1)))
    rejected.sort(key=lambda p: p.stats["p80"])
    for p in good:
        p.spread_deg = plane_spread(surface, p, final_queries // 3, seed)
    return OracleResult(surface.diag, surface.centroid, good, rejected)


def residual_near(V: np.ndarray, F: np.ndarray, n: Sequence[float], d: float, seed: int = 0) -> Dict[str, float]:
    """residual_stats of the shape's own best mirror plane near n . x = d (reflection-only
    ICP from it, then exact residuals on fresh samples): how mirror-symmetric the shape is
    about that plane, refined, whatever plane a detector reported."""
    surface = Surface(V, F, 200_000, seed)
    Q, f = surface.sample(20_000, np.random.default_rng(seed + 2))
    n, d = refine_plane(surface, Q, surface.normals[f], np.asarray(n, float), float(d))
    return evaluate_plane(surface, n, d, seed=seed + 1)


def plane_spread(surface: Surface, plane: MirrorPlane, queries: int, seed: int,
                 repeats: int = 2) -> float:
    """Refine the plane again on `repeats` fresh sample sets and return the largest angle
    (degrees) it moves: near zero for an exact mirror, larger where an approximate mirror
    leaves the plane loosely determined.  A detector cannot be asked to be closer than this."""
    worst = 0.0
    for k in range(repeats):
        Q, f = surface.sample(queries, np.random.default_rng([seed, 100 + k]))
        n, _ = refine_plane(surface, Q, surface.normals[f], plane.normal, plane.offset)
        worst = max(worst, math.degrees(math.acos(min(1.0, abs(float(n @ plane.normal))))))
    return worst


def format_plane(p: MirrorPlane) -> str:
    s = p.stats
    spread = "" if p.spread_deg is None else f"  spread {p.spread_deg:.3f} deg"
    pct = "  ".join(f"{k} {100 * s[k]:.3f}%" for k in ("median", "p80", "p90"))
    within = " ".join(f"{s[f'within_{t * 100:g}pct']:.2f}" for t in WITHIN)
    return (f"n=({p.normal[0]:+.5f} {p.normal[1]:+.5f} {p.normal[2]:+.5f}) d={p.offset:+.6g}  "
            f"{pct}  within 0.5/1/2%: {within}{spread}")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("mesh")
    ap.add_argument("--directions", type=int, default=4000, help="normals on the half sphere")
    ap.add_argument("--candidates", type=int, default=8, help="distinct planes refined")
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args(argv)
    V, F = load_mesh(args.mesh)
    res = find_mirror_planes(V, F, args.directions, args.candidates, args.seed)
    print(f"{args.mesh}: {len(F)} triangles, diagonal {res.diag:.6g}, "
          f"centroid {np.array2string(res.centroid, precision=5)}")
    for p in res.planes:
        print("mirror " + format_plane(p))
    for p in res.rejected:
        print("other  " + format_plane(p))
    print(f"{len(res.planes)} mirror plane(s), margin {res.margin:.2f}: "
          f"{'clear' if res.is_clear else 'NOT clear'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
