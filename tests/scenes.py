"""Test scenes with planted partial symmetries and their exact ground truth.

Every scene is built deterministically from a seed.  It is one triangle mesh made of several
*parts* (connected pieces placed side by side) plus a list of :class:`PlantedSymmetry`, each
holding the exact 4x4 transform that maps a known source part onto a known target part.

Every copy is RE-TESSELLATED: it is the same surface as its source but none of its vertices
sits where a vertex of the source sits (after mapping back by the inverse planted transform),
so a detector cannot succeed by matching vertex positions or connectivity.

* Analytic bases (bumpy torus, bumpy superquadric, bumpy sphere) are re-sampled exactly: the
  copy uses another resolution and a rotated / shifted parametrisation of the same analytic
  surface, so all its vertices lie exactly on that surface.
* Mesh bases (pymeshlab's bundled samples, CAD meshes from Debian's libcgal-demo) are remeshed
  with pymeshlab's isotropic explicit remeshing at another target edge length; the few
  vertices the remesher leaves in place (sharp corners) are slid a little inside an incident
  face.

Usage::

    import scenes
    s = scenes.make_scene("mirrored", seed=0)
    s.vertices, s.faces, s.symmetries, s.required_symmetries()

The scene names are in :data:`SCENE_NAMES` (the seven core scenes) and :data:`CAD_SCENE_NAMES`
(scenes that need the CAD meshes fetched by ``tests/fetch_cgal_meshes.sh``).

:data:`HARD_SCENE_NAMES` is a second group (noise on both copies, a partial symmetry inside one
fused surface, holes, anisotropic triangles, a coarse CAD part, a thin plate, a fine row, a 1 %
part, scaled copies, analytic continuous shapes and scenes mixing them with discrete ones).
Their ground truth adds :class:`PlantedFamily` (continuous families: kind, axis, region),
relations that hold modulo a family, clean meshes for the oracle (tests/oracle.py), and
``Scene.self_symmetries()``: the oracle's symmetries of the parts nobody planted any on.
"""
from __future__ import annotations

import dataclasses
import functools
import math
import os
from typing import Callable, Dict, List, Optional, Sequence, Tuple

import numpy as np

#: Bump when a change alters any generated scene (invalidates on-disk caches).
GENERATOR_VERSION = 1

#: Kinds of symmetry, numbered as the filter's `continuous_kinds` output (public API).
KIND_DISCRETE, KIND_ROTATIONAL, KIND_TRANSLATIONAL, KIND_HELICAL, KIND_PLANAR, KIND_SPHERICAL = \
    range(6)
KIND_NAMES = ("discrete", "rotational", "translational", "helical", "planar", "spherical")

TESTS_DIR = os.path.dirname(os.path.abspath(__file__))
REPO_DIR = os.path.dirname(TESTS_DIR)
#: Where tests/fetch_cgal_meshes.sh puts the CAD meshes by default (git-ignored).
DEFAULT_CGAL_DIR = os.path.join(TESTS_DIR, "data", "cgal")


def sample_mesh_dir() -> str:
    """The folder of sample meshes bundled with the pymeshlab wheel."""
    import pymeshlab
    return os.path.join(os.path.dirname(pymeshlab.__file__), "tests", "sample_meshes")


# ----------------------------------------------------------------------------------------
# Transforms (4x4 homogeneous, acting on column vectors: x' = T[:3,:3] x + T[:3,3])
# ----------------------------------------------------------------------------------------

def translation(t) -> np.ndarray:
    T = np.eye(4)
    T[:3, 3] = t
    return T


def linear(A) -> np.ndarray:
    T = np.eye(4)
    T[:3, :3] = A
    return T


def rotation(axis, angle: float) -> np.ndarray:
    """Rotation by `angle` radians about `axis` through the origin (Rodrigues)."""
    a = np.asarray(axis, float)
    a = a / np.linalg.norm(a)
    K = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    R = np.eye(3) + math.sin(angle) * K + (1 - math.cos(angle)) * (K @ K)
    return linear(R)


def mirror(normal) -> np.ndarray:
    """Reflection across the plane through the origin with the given normal (Householder)."""
    n = np.asarray(normal, float)
    n = n / np.linalg.norm(n)
    return linear(np.eye(3) - 2.0 * np.outer(n, n))


def scaling(s: float) -> np.ndarray:
    return linear(np.eye(3) * s)


def about(point, T: np.ndarray) -> np.ndarray:
    """The map T (a rotation, mirror or scaling about the origin) applied about `point`."""
    p = np.asarray(point, float)
    return translation(p) @ np.asarray(T, float) @ translation(-p)


def apply(T: np.ndarray, P: np.ndarray) -> np.ndarray:
    """Apply a 4x4 transform to an (n, 3) array of points."""
    P = np.asarray(P, float)
    return P @ T[:3, :3].T + T[:3, 3]


def random_unit_vector(rng: np.random.Generator) -> np.ndarray:
    v = rng.normal(size=3)
    return v / np.linalg.norm(v)


def random_rotation(rng: np.random.Generator, min_deg: float = 60.0,
                    max_deg: float = 150.0) -> np.ndarray:
    """A rotation about a random axis by an angle far from 0 (uniform in [min, max] deg)."""
    angle = math.radians(rng.uniform(min_deg, max_deg))
    return rotation(random_unit_vector(rng), angle)


def transform_scale(T: np.ndarray) -> float:
    """Uniform scale factor of a similarity transform."""
    return float(abs(np.linalg.det(T[:3, :3])) ** (1.0 / 3.0))


def is_reflection(T: np.ndarray) -> bool:
    return bool(np.linalg.det(T[:3, :3]) < 0)


# ----------------------------------------------------------------------------------------
# Mesh utilities (numpy only)
# ----------------------------------------------------------------------------------------

def face_areas(V: np.ndarray, F: np.ndarray) -> np.ndarray:
    e1 = V[F[:, 1]] - V[F[:, 0]]
    e2 = V[F[:, 2]] - V[F[:, 0]]
    return 0.5 * np.linalg.norm(np.cross(e1, e2), axis=1)


def vertex_normals(V: np.ndarray, F: np.ndarray) -> np.ndarray:
    """Area-weighted vertex normals (unit length)."""
    fn = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    N = np.zeros_like(V)
    for k in range(3):
        np.add.at(N, F[:, k], fn)
    n = np.linalg.norm(N, axis=1, keepdims=True)
    return N / np.maximum(n, 1e-300)


def bbox_diagonal(V: np.ndarray) -> float:
    return float(np.linalg.norm(V.max(0) - V.min(0)))


def mean_edge_length(V: np.ndarray, F: np.ndarray) -> float:
    E = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    return float(np.linalg.norm(V[E[:, 0]] - V[E[:, 1]], axis=1).mean())


def flip_faces(F: np.ndarray) -> np.ndarray:
    return F[:, [0, 2, 1]].copy()


def transform_mesh(T: np.ndarray, V: np.ndarray, F: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """Transform a mesh; flips the faces of an orientation-reversing transform so the
    normals stay outward."""
    return apply(T, V), (flip_faces(F) if is_reflection(T) else F.copy())


def sample_surface(V: np.ndarray, F: np.ndarray, n: int, rng: np.random.Generator,
                   return_faces: bool = False):
    """n points uniformly distributed (by area) over the surface; with return_faces, also the
    index of the face each point lies in (for its normal)."""
    a = face_areas(V, F)
    f = rng.choice(len(F), size=n, p=a / a.sum())
    r1 = np.sqrt(rng.random(n))
    r2 = rng.random(n)
    w = np.stack([1 - r1, r1 * (1 - r2), r1 * r2], axis=1)
    P = (V[F[f]] * w[:, :, None]).sum(1)
    return (P, f) if return_faces else P


def face_normals(V: np.ndarray, F: np.ndarray) -> np.ndarray:
    """Unit normals of the faces (right-hand rule on the vertex order)."""
    fn = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    return fn / np.maximum(np.linalg.norm(fn, axis=1, keepdims=True), 1e-300)


def near_mask(A: np.ndarray, B: np.ndarray, tol: float) -> np.ndarray:
    """For each point of A, whether some point of B lies within `tol` (fast, exact for
    `tol`-neighbours: eight shifted hash grids of cell 2*tol, candidates checked exactly)."""
    A = np.asarray(A, float)
    B = np.asarray(B, float)
    out = np.zeros(len(A), bool)
    if len(A) == 0 or len(B) == 0:
        return out
    cell = 2.0 * tol
    origin = np.minimum(A.min(0), B.min(0)) - 2 * cell
    for sx in (0, 1):
        for sy in (0, 1):
            for sz in (0, 1):
                shift = np.array([sx, sy, sz]) * (cell / 2)
                ka = np.floor((A - origin + shift) / cell).astype(np.int64)
                kb = np.floor((B - origin + shift) / cell).astype(np.int64)
                keys = np.concatenate([ka, kb])
                _, inv = np.unique(keys, axis=0, return_inverse=True)
                inv = inv.ravel()
                ia, ib = inv[:len(A)], inv[len(A):]
                order = np.argsort(ib, kind="stable")
                sorted_ib = ib[order]
                lo = np.searchsorted(sorted_ib, ia, side="left")
                hi = np.searchsorted(sorted_ib, ia, side="right")
                cand = np.nonzero(hi > lo)[0]
                for i in cand:
                    if out[i]:
                        continue
                    idx = order[lo[i]:hi[i]]
                    if np.min(np.linalg.norm(B[idx] - A[i], axis=1)) <= tol:
                        out[i] = True
    return out


def min_distances_bruteforce(A: np.ndarray, B: np.ndarray, chunk: int = 1024) -> np.ndarray:
    """For each point of A, the distance to the nearest point of B (brute force in chunks)."""
    B2 = (B * B).sum(1)
    out = np.empty(len(A))
    for i in range(0, len(A), chunk):
        a = A[i:i + chunk]
        d2 = (a * a).sum(1)[:, None] - 2 * a @ B.T + B2[None, :]
        j = np.argmin(d2, axis=1)
        out[i:i + chunk] = np.linalg.norm(B[j] - a, axis=1)
    return out


def weld(V: np.ndarray, F: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """Merge vertices that coincide (to 1e-9) and drop the faces that collapse: how grids
    with poles and seams, and polyhedra built face by face, become one closed mesh."""
    key = np.round(V * 1e9).astype(np.int64)
    _, first, inv = np.unique(key, axis=0, return_index=True, return_inverse=True)
    V = V[first]
    F = inv.ravel()[F]
    keep = (F[:, 0] != F[:, 1]) & (F[:, 1] != F[:, 2]) & (F[:, 2] != F[:, 0])
    return V, F[keep]


# ----------------------------------------------------------------------------------------
# Analytic surfaces, re-sampleable exactly
# ----------------------------------------------------------------------------------------

def geodesic_sphere(freq: int, Q: Optional[np.ndarray] = None) -> Tuple[np.ndarray, np.ndarray]:
    """Unit sphere: an icosahedron whose faces are split into freq^2 triangles, projected, then
    rotated by the 3x3 matrix Q (a rotated parametrisation).  20*freq^2 faces."""
    t = (1 + 5 ** 0.5) / 2
    IV = np.array([[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0], [0, -1, t], [0, 1, t],
                   [0, -1, -t], [0, 1, -t], [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]], float)
    IF = np.array([[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9],
                   [5, 11, 4], [11, 10, 2], [10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2],
                   [3, 2, 6], [3, 6, 8], [3, 8, 9], [4, 9, 5], [2, 4, 11], [6, 2, 10],
                   [8, 6, 7], [9, 8, 1]])
    n = freq
    # barycentric lattice of one face
    ij = [(i, j) for i in range(n + 1) for j in range(n + 1 - i)]
    index = {p: k for k, p in enumerate(ij)}
    tris = []
    for i in range(n):
        for j in range(n - i):
            tris.append((index[(i, j)], index[(i + 1, j)], index[(i, j + 1)]))
            if j < n - i - 1:
                tris.append((index[(i + 1, j)], index[(i + 1, j + 1)], index[(i, j + 1)]))
    ij = np.array(ij, float)
    tris = np.array(tris)
    w = np.stack([n - ij[:, 0] - ij[:, 1], ij[:, 0], ij[:, 1]], axis=1) / n
    Vs, Fs = [], []
    for f in IF:
        P = w @ IV[f]
        Fs.append(tris + sum(len(v) for v in Vs))
        Vs.append(P / np.linalg.norm(P, axis=1, keepdims=True))
    V = np.concatenate(Vs)
    F = np.concatenate(Fs)
    V, F = weld(V, F)  # the edge vertices shared by neighbouring icosahedron faces
    if Q is not None:
        V = V @ np.asarray(Q).T
    return V, F


class RadialField:
    """A smooth random function on the unit sphere: a sum of Gaussian bumps."""

    def __init__(self, rng: np.random.Generator, n_bumps: int = 9, width: float = 0.55):
        self.centers = np.stack([random_unit_vector(rng) for _ in range(n_bumps)])
        self.amps = rng.uniform(0.4, 1.0, n_bumps) * rng.choice([-1.0, 1.0], n_bumps)
        self.width = width

    def __call__(self, U: np.ndarray) -> np.ndarray:
        d2 = ((U[:, None, :] - self.centers[None]) ** 2).sum(-1)
        return (self.amps[None] * np.exp(-d2 / (2 * self.width ** 2))).sum(1)


@dataclasses.dataclass
class StarShape:
    """A star-shaped surface r(u) u over unit directions u: an axis-aligned superquadric
    |x/a|^e + |y/b|^e + |z/c|^e = 1 (e = 2: ellipsoid) whose radius is multiplied by
    (1 + amplitude * field(u))."""
    axes: Tuple[float, float, float] = (1.0, 1.0, 1.0)
    exponent: float = 2.0
    amplitude: float = 0.0
    field: Optional[RadialField] = None

    def radius(self, U: np.ndarray) -> np.ndarray:
        a = np.asarray(self.axes, float)
        r = (np.abs(U / a) ** self.exponent).sum(1) ** (-1.0 / self.exponent)
        if self.field is not None and self.amplitude:
            r = r * (1.0 + self.amplitude * self.field(U))
        return r

    def mesh(self, freq: int, Q: Optional[np.ndarray] = None) -> Tuple[np.ndarray, np.ndarray]:
        U, F = geodesic_sphere(freq, Q)
        return U * self.radius(U)[:, None], F


@dataclasses.dataclass
class BumpyTorus:
    """Torus around z (major radius R, tube radius r) whose tube radius is multiplied by
    1 + amplitude * f(theta, phi), f a random low-frequency trigonometric polynomial."""
    R: float
    r: float
    amplitude: float
    coeffs: np.ndarray  # rows (m, n, a, phase)

    @staticmethod
    def random(rng: np.random.Generator, R: float = 1.0, r: float = 0.38,
               amplitude: float = 0.35) -> "BumpyTorus":
        rows = []
        for m in range(0, 4):
            for n in range(-2, 3):
                if m == 0 and n <= 0:
                    continue
                rows.append((m, n, rng.normal() / (1 + m + abs(n)), rng.uniform(0, 2 * np.pi)))
        c = np.array(rows)
        c[:, 2] /= np.abs(c[:, 2]).sum()
        return BumpyTorus(R, r, amplitude, c)

    def point(self, th: np.ndarray, ph: np.ndarray) -> np.ndarray:
        f = np.zeros_like(th)
        for m, n, a, p in self.coeffs:
            f += a * np.cos(m * th + n * ph + p)
        rr = self.r * (1 + self.amplitude * f)
        return np.stack([(self.R + rr * np.cos(ph)) * np.cos(th),
                         (self.R + rr * np.cos(ph)) * np.sin(th), rr * np.sin(ph)], axis=1)

    def mesh(self, n_around: int, n_tube: int, phase_around: float = 0.0,
             phase_tube: float = 0.0) -> Tuple[np.ndarray, np.ndarray]:
        """Periodic grid of n_around x n_tube quads split in two; the phases (fractions of a
        cell) shift the parametrisation so that two meshes share no vertex."""
        i, j = np.meshgrid(np.arange(n_around), np.arange(n_tube), indexing="ij")
        th = 2 * np.pi * (i.ravel() + phase_around) / n_around
        ph = 2 * np.pi * (j.ravel() + phase_tube) / n_tube
        V = self.point(th, ph)
        idx = lambda a, b: (a % n_around) * n_tube + (b % n_tube)  # noqa: E731
        a, b = i.ravel(), j.ravel()
        q00, q10, q01, q11 = idx(a, b), idx(a + 1, b), idx(a, b + 1), idx(a + 1, b + 1)
        F = np.concatenate([np.stack([q00, q10, q11], 1), np.stack([q00, q11, q01], 1)])
        return V, F


# ----------------------------------------------------------------------------------------
# Continuous shapes: point grids swept along curves, exact on their analytic surface
# ----------------------------------------------------------------------------------------

def grid_mesh(P: np.ndarray, closed: bool = True) -> Tuple[np.ndarray, np.ndarray]:
    """Triangulate a grid of points P (rows, cols, 3) whose rows run along a sweep and whose
    cols go around it (closing up when `closed`); poles and seams are welded.  With the
    cols counter-clockwise about the sweep direction the normals point outward."""
    rows, cols = P.shape[:2]
    i, j = np.meshgrid(np.arange(rows - 1), np.arange(cols if closed else cols - 1),
                       indexing="ij")
    i, j = i.ravel(), j.ravel()
    v = lambda a, b: a * cols + b % cols  # noqa: E731
    F = np.concatenate([np.stack([v(i, j), v(i, j + 1), v(i + 1, j)], 1),
                        np.stack([v(i, j + 1), v(i + 1, j + 1), v(i + 1, j)], 1)])
    return weld(P.reshape(-1, 3), F)


def resample_polyline(C: np.ndarray, h: float, closed: bool = False) -> np.ndarray:
    """Points about h apart by arc length along the polyline C (a closed one without its
    repeated first point); an open polyline keeps both ends."""
    C = np.asarray(C, float)
    D = np.concatenate([C, C[:1]]) if closed else C
    s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(D, axis=0), axis=1))])
    n = max(2, int(math.ceil(s[-1] / h)))
    t = np.linspace(0, s[-1], n + 1)[:-1] if closed else np.linspace(0, s[-1], n + 1)
    return np.stack([np.interp(t, s, D[:, k]) for k in range(D.shape[1])], 1)


def profile(pieces: Sequence[np.ndarray], h: float) -> np.ndarray:
    """An (r, z) profile from polyline pieces sharing their end points; each piece is
    resampled on its own so the corners between pieces (sharp creases) are kept."""
    out = [resample_polyline(pieces[0], h)]
    for p in pieces[1:]:
        out.append(resample_polyline(p, h)[1:])
    return np.concatenate(out)


def revolve(rz: np.ndarray, n_around: int, phase: float = 0.0) -> Tuple[np.ndarray, np.ndarray]:
    """Surface of revolution about z of a profile (r, z) running from bottom to top; points
    with r = 0 become poles (caps closed there)."""
    th = 2 * np.pi * (np.arange(n_around) + phase) / n_around
    r, z = rz[:, :1], rz[:, 1:]
    P = np.stack([r * np.cos(th), r * np.sin(th), np.repeat(z, n_around, 1)], -1)
    return grid_mesh(P)


def orient_outward(V: np.ndarray, F: np.ndarray, center) -> np.ndarray:
    """Faces of a convex polyhedron oriented so their normals point away from `center`."""
    out = np.einsum("ij,ij->i", face_normals(V, F), V[F].mean(1) - center) < 0
    F = F.copy()
    F[out] = F[out][:, [0, 2, 1]]
    return F


def box_mesh(size, n: int = 4) -> Tuple[np.ndarray, np.ndarray]:
    """Axis-aligned box centred at the origin, each face an n x n grid (to be remeshed)."""
    h = np.asarray(size, float) / 2
    Vs, Fs, nv = [], [], 0
    g = np.linspace(-1, 1, n + 1)
    for k in range(3):
        a, b = [x for x in range(3) if x != k]
        for sgn in (-1, 1):
            U, W = np.meshgrid(g, g, indexing="ij")
            P = np.zeros(U.shape + (3,))
            P[..., k], P[..., a], P[..., b] = sgn * h[k], U * h[a], W * h[b]
            V, F = grid_mesh(P, closed=False)
            Vs.append(V)
            Fs.append(F + nv)
            nv += len(V)
    V, F = weld(np.concatenate(Vs), np.concatenate(Fs))
    return V, orient_outward(V, F, np.zeros(3))


def helix_tube(radius: float, pitch: float, tube: float, turns: float, h: float,
               n_around: int) -> Tuple[np.ndarray, np.ndarray]:
    """A tube of radius `tube` around the helix (radius cos t, radius sin t, pitch t) about
    z, t in [-turns pi, turns pi] (pitch: rise per radian), open at both ends."""
    speed = math.hypot(radius, pitch)
    t = np.linspace(-turns * np.pi, turns * np.pi,
                    int(math.ceil(2 * turns * np.pi * speed / h)) + 1)[:, None]
    c = np.concatenate([radius * np.cos(t), radius * np.sin(t), pitch * t], 1)
    T = np.concatenate([-radius * np.sin(t), radius * np.cos(t), np.full_like(t, pitch)],
                       1) / speed
    N = np.concatenate([-np.cos(t), -np.sin(t), np.zeros_like(t)], 1)
    B = np.cross(T, N)
    psi = 2 * np.pi * np.arange(n_around) / n_around
    P = c[:, None] + tube * (np.cos(psi)[None, :, None] * N[:, None]
                             + np.sin(psi)[None, :, None] * B[:, None])
    return grid_mesh(P)


def remeshed(V: np.ndarray, F: np.ndarray, n_faces: int) -> Tuple[np.ndarray, np.ndarray]:
    """A dense analytic tessellation remeshed isotropically to about n_faces faces: generic
    triangles (no rings aligned with the symmetry, no slivers at poles) whose vertices lie
    on the dense mesh, so within its chord error of the analytic surface."""
    return _remesh(V, F, edge_length_for(V, F, n_faces))


# ----------------------------------------------------------------------------------------
# Mesh-based bases (pymeshlab samples, CGAL CAD meshes) and their re-tessellation
# ----------------------------------------------------------------------------------------

SAMPLE_BASES = {"bunny": "bunny.obj", "cow": "cow.obj", "bone": "bone.ply",
                "airplane": "airplane.obj"}
CAD_BASES = ("fandisk", "rotor", "pinion", "couplingdown", "joint", "cross")


def _remesh(V: np.ndarray, F: np.ndarray, target_len: float, iterations: int = 6,
            feature_deg: float = 30.0) -> Tuple[np.ndarray, np.ndarray]:
    import pymeshlab
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(V, F))
    ms.meshing_isotropic_explicit_remeshing(
        targetlen=pymeshlab.PureValue(target_len), iterations=iterations,
        featuredeg=feature_deg, checksurfdist=True,
        maxsurfdist=pymeshlab.PureValue(target_len * 0.2), reprojectflag=True)
    ms.meshing_remove_unreferenced_vertices()
    m = ms.current_mesh()
    return m.vertex_matrix().copy(), m.face_matrix().astype(np.int64)


def edge_length_for(V: np.ndarray, F: np.ndarray, n_faces: int) -> float:
    """Edge length of an equilateral tessellation of this surface with about n_faces faces."""
    return math.sqrt(4.0 * face_areas(V, F).sum() / (math.sqrt(3.0) * n_faces))


def _load(path: str) -> Tuple[np.ndarray, np.ndarray]:
    import pymeshlab
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(path)
    ms.meshing_remove_duplicate_vertices()
    ms.meshing_remove_unreferenced_vertices()
    m = ms.current_mesh()
    return m.vertex_matrix().copy(), m.face_matrix().astype(np.int64)


def normalized(V: np.ndarray) -> np.ndarray:
    """Centre the bounding box at the origin and scale its diagonal to 1."""
    lo, hi = V.min(0), V.max(0)
    return (V - (lo + hi) / 2) / np.linalg.norm(hi - lo)


def base_mesh_path(name: str, cgal_dir: Optional[str] = None) -> str:
    if name in SAMPLE_BASES:
        return os.path.join(sample_mesh_dir(), SAMPLE_BASES[name])
    if name in CAD_BASES:
        d = cgal_dir or os.environ.get("SYMMETRY_CGAL_DIR") or DEFAULT_CGAL_DIR
        p = os.path.join(d, name + ".off")
        if not os.path.exists(p):
            raise FileNotFoundError(
                f"CAD mesh {p} is missing: run `tests/fetch_cgal_meshes.sh {d}` first.")
        return p
    raise KeyError(f"unknown base mesh {name!r}")


@functools.lru_cache(maxsize=16)
def _base_cached(name: str, n_faces: int, cgal_dir: Optional[str]) -> Tuple[np.ndarray, np.ndarray]:
    V, F = _load(base_mesh_path(name, cgal_dir))
    V = normalized(V)
    if len(F) > 3 * n_faces:  # cheap pre-decimation of dense scans
        import pymeshlab
        ms = pymeshlab.MeshSet()
        ms.add_mesh(pymeshlab.Mesh(V, F))
        ms.meshing_decimation_quadric_edge_collapse(targetfacenum=2 * n_faces,
                                                    preservenormal=True, qualitythr=0.5)
        V, F = ms.current_mesh().vertex_matrix().copy(), ms.current_mesh().face_matrix()
    return _remesh(V, F, edge_length_for(V, F, n_faces))


def base_mesh(name: str, n_faces: int, cgal_dir: Optional[str] = None
              ) -> Tuple[np.ndarray, np.ndarray]:
    """A bundled or CAD mesh, normalised to bbox diagonal 1 centred at the origin, remeshed
    isotropically to about n_faces faces.  This is the *source* instance used in scenes."""
    V, F = _base_cached(name, int(n_faces), cgal_dir)
    return V.copy(), F.copy()


def retessellate(V: np.ndarray, F: np.ndarray, length_ratio: float = 0.75,
                 rng: Optional[np.random.Generator] = None) -> Tuple[np.ndarray, np.ndarray]:
    """The same surface with other vertices: isotropic remeshing at `length_ratio` times the
    mean edge length; vertices the remesher kept in place are slid inside an incident face."""
    L = mean_edge_length(V, F) * length_ratio
    V2, F2 = _remesh(V, F, L)
    return _slide_shared_vertices(V2, F2, V, rng), F2


def _slide_shared_vertices(V2: np.ndarray, F2: np.ndarray, V: np.ndarray,
                           rng: Optional[np.random.Generator] = None) -> np.ndarray:
    """Move the vertices of V2 that coincide with one of V a little inside an incident face
    (remeshers keep sharp corners in place), so the copy shares no vertex with its source."""
    diag = bbox_diagonal(V)
    for _ in range(5):
        shared = np.nonzero(near_mask(V2, V, 1e-6 * diag))[0]
        if len(shared) == 0:
            break
        # one incident face per shared vertex
        inc = np.full(len(V2), -1)
        inc[F2.ravel()] = np.repeat(np.arange(len(F2)), 3)
        c = V2[F2[inc[shared]]].mean(1)
        t = 0.25 if rng is None else rng.uniform(0.15, 0.35, len(shared))[:, None]
        V2[shared] = V2[shared] + t * (c - V2[shared])
    return V2


# ----------------------------------------------------------------------------------------
# Scenes
# ----------------------------------------------------------------------------------------

@dataclasses.dataclass
class PlantedSymmetry:
    """A planted symmetry: `transform` maps part `source_part` exactly onto `target_part`."""
    name: str
    transform: np.ndarray
    source_part: str
    target_part: str
    source_vertices: np.ndarray   # indices into Scene.vertices
    target_vertices: np.ndarray
    source_area_fraction: float   # area of the source part / total area of the scene
    reflection: bool
    scale: float
    required: bool = True         # counts for recall
    family: Optional[str] = None  # e.g. "row": powers of one generator
    power: int = 1
    #: other transforms equally correct for this relation (base self-symmetries composed in)
    equivalents: List[np.ndarray] = dataclasses.field(default_factory=list)
    #: name of a PlantedFamily: every T with T transform^-1 in that family is this relation
    #: too (a capped cylinder's mirror composed with any rotation about its axis)
    modulo: Optional[str] = None

    def as_dict(self) -> dict:
        d = dataclasses.asdict(self)
        d["transform"] = self.transform.tolist()
        d.pop("source_vertices")
        d.pop("target_vertices")
        d["equivalents"] = [e.tolist() for e in self.equivalents]
        return d


@dataclasses.dataclass
class PlantedFamily:
    """A continuous symmetry family: every member of the group of `kind` (KIND_*) about the
    axis maps the region `vertices` onto the surface.  point/direction follow the filter's
    `continuous_axes`: rotational and helical, a point on the axis and its direction;
    translational, the direction; planar, a point on the plane and its normal; spherical,
    the centre (direction zeros).  Helical families also carry their pitch (shift along the
    direction per radian)."""
    name: str
    kind: int
    point: np.ndarray
    direction: np.ndarray
    part: str
    vertices: np.ndarray          # indices into Scene.vertices
    area_fraction: float          # of the scene's area
    required: bool = True
    pitch: float = 0.0

    @property
    def axis(self) -> np.ndarray:
        return np.concatenate([self.point, self.direction])

    def as_dict(self) -> dict:
        return dict(name=self.name, kind=KIND_NAMES[self.kind], part=self.part,
                    axis=self.axis.tolist(), pitch=self.pitch, required=self.required,
                    area_fraction=self.area_fraction)


@dataclasses.dataclass
class Scene:
    name: str
    description: str
    seed: int
    vertices: np.ndarray
    faces: np.ndarray
    #: part name -> (first vertex, end vertex, first face, end face)
    parts: Dict[str, Tuple[int, int, int, int]]
    symmetries: List[PlantedSymmetry]
    #: extra filter parameters this scene is meant to be run with (e.g. similarity group)
    filter_params: Dict[str, int] = dataclasses.field(default_factory=dict)
    #: largest source-patch area fraction a correct detector may report (no-symmetry scene)
    max_reported_area_fraction: Optional[float] = None
    #: family name -> number of generators a correct basis reduction reports
    expected_generators: Dict[str, int] = dataclasses.field(default_factory=dict)
    #: parts that are copies of each other (same base); base self-symmetries are noted here
    notes: str = ""
    #: the shape a part was copied from, for the re-tessellation checks: part -> (source
    #: part, transform mapping source part onto it, surface tolerance as diag fraction)
    copies: Dict[str, Tuple[str, np.ndarray, float]] = dataclasses.field(default_factory=dict)
    #: continuous symmetry families (the analytic scenes' ground truth)
    families: List[PlantedFamily] = dataclasses.field(default_factory=list)
    #: part -> its noise-free (or denser analytic) mesh, for the oracle; other parts are clean
    clean_parts: Dict[str, Tuple[np.ndarray, np.ndarray]] = dataclasses.field(
        default_factory=dict)
    #: the parts whose own symmetries the oracle establishes, see self_symmetries(); build()
    #: names every part that is no planted image of another part and holds no family
    oracle_parts: Tuple[str, ...] = ()
    #: continuous reports outside `families` are checked by the oracle: scenes of real-world
    #: meshes (CAD parts with flat faces and cylindrical holes, a scanned bunny with a flat
    #: base), whose families nobody listed
    oracle_families: bool = False
    #: a CAD model's tessellation: vertices at its corners only, so a report's patch is judged
    #: by points over its faces (oracle.region_samples), not by those few vertices
    corner_vertices_only: bool = False

    @property
    def diagonal(self) -> float:
        return bbox_diagonal(self.vertices)

    @property
    def triangle_count(self) -> int:
        return int(len(self.faces))

    def area(self) -> float:
        return float(face_areas(self.vertices, self.faces).sum())

    def part_mesh(self, part: str) -> Tuple[np.ndarray, np.ndarray]:
        v0, v1, f0, f1 = self.parts[part]
        return self.vertices[v0:v1], self.faces[f0:f1] - v0

    def part_vertices(self, part: str) -> np.ndarray:
        v0, v1, _, _ = self.parts[part]
        return np.arange(v0, v1)

    def required_symmetries(self) -> List[PlantedSymmetry]:
        return [s for s in self.symmetries if s.required]

    def required_families(self) -> List[PlantedFamily]:
        return [f for f in self.families if f.required]

    def family(self, name: str) -> PlantedFamily:
        return next(f for f in self.families if f.name == name)

    def clean_mesh(self) -> Tuple[np.ndarray, np.ndarray]:
        """The whole scene's noise-free surface: each part's clean mesh where it has one."""
        Vs, Fs, nv = [], [], 0
        for part in self.parts:
            V, F = self.clean_parts.get(part) or self.part_mesh(part)
            Vs.append(V)
            Fs.append(F + nv)
            nv += len(V)
        return np.concatenate(Vs), np.concatenate(Fs)

    def self_symmetries(self) -> List[PlantedSymmetry]:
        """The oracle's (near) exact global self-symmetries of the oracle_parts, each a
        relation of the part with itself whose source region is the part of its vertices the
        symmetry maps within oracle.EXACT_TOL of the SCENE's diagonal: the detector's
        tolerance is relative to the scene, and at that scale a small bumpy part can be
        mirror-symmetric.  Computed on the clean part (tests/oracle.py, never the detector),
        optional, cached on the scene."""
        if "_self_symmetries" not in self.__dict__:
            import oracle
            self.__dict__["_self_symmetries"] = [
                x for part in self.oracle_parts
                for x in _oracle_self_symmetries(self, part, oracle.EXACT_TOL)]
        return self.__dict__["_self_symmetries"]

    def transformed(self, G: np.ndarray) -> "Scene":
        """The same scene moved as a whole by the rigid or similarity transform G: vertices
        G x, planted transforms G T G^-1."""
        Gi = np.linalg.inv(G)
        V, F = transform_mesh(G, self.vertices, self.faces)
        syms = [dataclasses.replace(s, transform=G @ s.transform @ Gi,
                                    equivalents=[G @ e @ Gi for e in s.equivalents])
                for s in self.symmetries]
        copies = {k: (src, G @ T @ Gi, tol) for k, (src, T, tol) in self.copies.items()}
        s = transform_scale(G)
        fams = [dataclasses.replace(
            f, point=apply(G, f.point[None])[0],
            direction=(G[:3, :3] @ f.direction) / s, pitch=f.pitch * s)
            for f in self.families]
        clean = {k: transform_mesh(G, *m) for k, m in self.clean_parts.items()}
        return dataclasses.replace(self, vertices=V, faces=F, symmetries=syms, copies=copies,
                                   families=fams, clean_parts=clean, name=self.name + "_moved")

    def subdivided(self, min_vertices: int) -> "Scene":
        """The same surface with more vertices: every triangle split in four at its edges'
        midpoints (vertices never move) until the scene has more than `min_vertices`.  Each
        part stays one block of vertices and faces, its old vertices first.  The ground truth
        carries over exactly: a midpoint belongs to a region (a relation's source or target,
        a family's vertices, an oracle self-symmetry's) when both ends of its edge do.  The
        parts' clean meshes for the oracle are the unsubdivided ones, the same surface."""
        scene = self
        while len(scene.vertices) <= min_vertices:
            scene = scene._midpoint_split()
        return scene

    def _midpoint_split(self) -> "Scene":
        blocks = sorted(self.parts.items(), key=lambda kv: kv[1][0])
        Vs, Fs, parts, old_to_new, edge_blocks = [], [], {}, np.empty(len(self.vertices), int), []
        nv = nf = 0
        for name, (v0, v1, f0, f1) in blocks:
            V, F = self.vertices[v0:v1], self.faces[f0:f1] - v0
            E = np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
            edges, inverse = np.unique(E, axis=0, return_inverse=True)
            m = len(V) + inverse.reshape(3, -1).T        # midpoints of edges (01, 12, 20)
            a, b, c, ab, bc, ca = F[:, 0], F[:, 1], F[:, 2], m[:, 0], m[:, 1], m[:, 2]
            Fn = np.concatenate([np.stack(t, 1) for t in
                                 ((a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca))])
            Vs.append(np.concatenate([V, 0.5 * (V[edges[:, 0]] + V[edges[:, 1]])]))
            Fs.append(Fn + nv)
            old_to_new[v0:v1] = nv + np.arange(len(V))
            edge_blocks.append(edges + nv)
            parts[name] = (nv, nv + len(Vs[-1]), nf, nf + len(Fn))
            nv, nf = nv + len(Vs[-1]), nf + len(Fn)
        edges = np.concatenate(edge_blocks)
        midpoints = np.concatenate([np.arange(p[1] - len(e), p[1])
                                    for p, e in zip(parts.values(), edge_blocks)])

        def region(vertices: np.ndarray) -> np.ndarray:
            inside = np.zeros(nv, bool)
            inside[old_to_new[vertices]] = True
            inside[midpoints] = inside[edges[:, 0]] & inside[edges[:, 1]]
            return np.nonzero(inside)[0]

        def carried(s: PlantedSymmetry) -> PlantedSymmetry:
            return dataclasses.replace(s, source_vertices=region(s.source_vertices),
                                       target_vertices=region(s.target_vertices))

        clean = {name: self.clean_parts.get(name) or self.part_mesh(name) for name in self.parts}
        out = dataclasses.replace(
            self, vertices=np.concatenate(Vs), faces=np.concatenate(Fs), parts=parts,
            symmetries=[carried(s) for s in self.symmetries], clean_parts=clean,
            families=[dataclasses.replace(f, vertices=region(f.vertices)) for f in self.families])
        out.__dict__["_self_symmetries"] = [carried(s) for s in self.self_symmetries()]
        return out

    def to_pymeshlab(self):
        import pymeshlab
        return pymeshlab.Mesh(self.vertices, self.faces)

    def meshset(self):
        """A fresh pymeshlab.MeshSet holding this scene as its only (current) mesh."""
        import pymeshlab
        ms = pymeshlab.MeshSet()
        ms.add_mesh(self.to_pymeshlab(), self.name)
        return ms

    def save(self, path: str) -> None:
        """Write the scene's mesh (binary PLY for .ply, positions and faces only)."""
        ms = self.meshset()
        if path.endswith(".ply"):
            ms.save_current_mesh(path, binary=True, save_vertex_normal=False,
                                 save_vertex_color=False, save_vertex_quality=False,
                                 save_face_color=False, save_face_quality=False)
        else:
            ms.save_current_mesh(path)

    def summary(self) -> str:
        lines = [f"{self.name}: {self.triangle_count} triangles, {len(self.vertices)} vertices, "
                 f"parts {list(self.parts)}"]
        for s in self.symmetries:
            lines.append(f"  {s.name}: {s.source_part} -> {s.target_part}  "
                         f"{'reflection' if s.reflection else 'proper'} scale {s.scale:.3f} "
                         f"area {s.source_area_fraction:.3f} "
                         f"{'required' if s.required else 'optional'}"
                         + (f" modulo {s.modulo}" if s.modulo else ""))
        for f in self.families:
            lines.append(f"  {f.name}: {KIND_NAMES[f.kind]} on {f.part} axis "
                         f"{np.round(f.axis, 3).tolist()} area {f.area_fraction:.3f} "
                         f"{'required' if f.required else 'optional'}")
        return "\n".join(lines)


class _Builder:
    """Collects parts, then assembles one mesh with planted symmetries and families.

    Regions (the vertices a relation or family holds on) are given as indices local to
    their part, or None for the whole part; build() offsets them into the scene."""

    def __init__(self):
        self.parts: List[Tuple[str, np.ndarray, np.ndarray]] = []
        self.syms: List[dict] = []
        self.fams: List[dict] = []
        self.copies: Dict[str, Tuple[str, np.ndarray, float]] = {}
        self.clean: Dict[str, Tuple[np.ndarray, np.ndarray]] = {}

    def add(self, name: str, V: np.ndarray, F: np.ndarray,
            clean: Optional[Tuple[np.ndarray, np.ndarray]] = None) -> None:
        """A part; `clean` is its noise-free or denser analytic mesh, for the oracle."""
        self.parts.append((name, np.asarray(V, float), np.asarray(F, np.int64)))
        if clean is not None:
            self.clean[name] = (np.asarray(clean[0], float), np.asarray(clean[1], np.int64))

    def plant(self, name: str, T: np.ndarray, source: str, target: str,
              source_region: Optional[np.ndarray] = None,
              target_region: Optional[np.ndarray] = None, **kw) -> None:
        self.syms.append(dict(name=name, transform=np.asarray(T, float), source_part=source,
                              target_part=target, source_region=source_region,
                              target_region=target_region, **kw))

    def family(self, name: str, kind: int, point, direction, part: str,
               region: Optional[np.ndarray] = None, required: bool = True,
               pitch: float = 0.0) -> None:
        d = np.zeros(3) if kind == KIND_SPHERICAL else np.asarray(direction, float)
        if kind != KIND_SPHERICAL:
            d = d / np.linalg.norm(d)
        self.fams.append(dict(name=name, kind=kind, point=np.asarray(point, float),
                              direction=d, part=part, region=region, required=required,
                              pitch=pitch))

    def copy_of(self, part: str, source: str, T: np.ndarray, surface_tol: float) -> None:
        self.copies[part] = (source, np.asarray(T, float), surface_tol)

    def build(self, name: str, description: str, seed: int, **kw) -> Scene:
        Vs, Fs, ranges = [], [], {}
        nv = nf = 0
        for pname, V, F in self.parts:
            ranges[pname] = (nv, nv + len(V), nf, nf + len(F))
            Vs.append(V)
            Fs.append(F + nv)
            nv += len(V)
            nf += len(F)
        V = np.concatenate(Vs)
        F = np.concatenate(Fs)
        total = face_areas(V, F).sum()

        def region(part, local):
            v0, v1, f0, f1 = ranges[part]
            idx = np.arange(v0, v1) if local is None else v0 + np.asarray(local, np.int64)
            inside = np.zeros(len(V), bool)
            inside[idx] = True
            faces = F[f0:f1][inside[F[f0:f1]].all(1)]
            return idx, float(face_areas(V, faces).sum() / total)

        syms = []
        for d in map(dict, self.syms):
            src, area = region(d["source_part"], d.pop("source_region"))
            dst, _ = region(d["target_part"], d.pop("target_region"))
            T = d["transform"]
            syms.append(PlantedSymmetry(
                source_vertices=src, target_vertices=dst, source_area_fraction=area,
                reflection=is_reflection(T), scale=transform_scale(T), **d))
        fams = []
        for d in map(dict, self.fams):
            idx, area = region(d["part"], d.pop("region"))
            fams.append(PlantedFamily(vertices=idx, area_fraction=area, **d))
        images = {x.target_part for x in syms if x.target_part != x.source_part}
        kw.setdefault("oracle_parts", tuple(
            p for p in ranges if p not in images and all(f.part != p for f in fams)))
        return Scene(name=name, description=description, seed=seed, vertices=V, faces=F,
                     parts=ranges, symmetries=syms, copies=dict(self.copies), families=fams,
                     clean_parts=dict(self.clean), **kw)


def _placed(T_local: np.ndarray, center: np.ndarray) -> np.ndarray:
    """T_local (about the origin) followed by a translation of the origin to `center`."""
    return translation(center) @ T_local


# -- (a) mirrored --------------------------------------------------------------------------

def scene_mirrored(seed: int = 0, base: str = "bunny", n_faces: int = 15000) -> Scene:
    rng = np.random.default_rng([seed, 1])
    V, F = base_mesh(base, n_faces)
    b = _Builder()
    b.add("base", V, F)
    # mirror across a random plane through the origin, then move beside the base
    M = mirror(random_unit_vector(rng))
    d = random_unit_vector(rng) * np.array([1, 1, 0.3])
    T = _placed(M, 1.2 * d / np.linalg.norm(d))
    V2, F2 = retessellate(V, F, 0.75, rng)
    b.add("mirror", *transform_mesh(T, V2, F2))
    b.copy_of("mirror", "base", T, 0.004)
    b.plant("reflection", T, "base", "mirror")
    return b.build("mirrored", f"{base} and a re-tessellated mirrored copy side by side", seed,
                   notes=f"{base} has no exact self-symmetry", oracle_families=True)


# -- (b) rigid copies ----------------------------------------------------------------------

def scene_rigid(seed: int = 0) -> Scene:
    rng = np.random.default_rng([seed, 2])
    torus = BumpyTorus.random(rng)
    b = _Builder()
    V, F = torus.mesh(190, 42)
    b.add("base", V, F)
    diag = bbox_diagonal(V)
    for k, (res, ph) in enumerate([((177, 47), (0.37, 0.61)), ((203, 39), (0.71, 0.29))], 1):
        R = random_rotation(rng, 70, 160)
        center = np.array([[1.1 * diag, 0.0, 0.0], [0.55 * diag, 1.0 * diag, 0.0]][k - 1])
        T = _placed(R, center)
        V2, F2 = torus.mesh(*res, *ph)
        b.add(f"copy{k}", *transform_mesh(T, V2, F2))
        b.copy_of(f"copy{k}", "base", T, 0.004)
        b.plant(f"rigid{k}", T, "base", f"copy{k}")
    # the relation between the two copies is implied (copy1 -> copy2 = T2 T1^-1)
    T1, T2 = b.syms[0]["transform"], b.syms[1]["transform"]
    b.plant("rigid12", T2 @ np.linalg.inv(T1), "copy1", "copy2", required=False)
    return b.build("rigid", "bumpy torus plus two rigidly moved, re-sampled copies", seed,
                   notes="random low-frequency bumps break the torus's rotational symmetry")


# -- (c) scaled ----------------------------------------------------------------------------

def scene_scaled(seed: int = 0, scale: float = 0.6) -> Scene:
    rng = np.random.default_rng([seed, 3])
    shape = StarShape(axes=(1.0, 0.75, 0.55), exponent=3.0, amplitude=0.18,
                      field=RadialField(rng, 8, 0.6))
    b = _Builder()
    V, F = shape.mesh(34)
    b.add("base", V, F)
    diag = bbox_diagonal(V)
    R = random_rotation(rng, 60, 150)
    T = _placed(scaling(scale) @ R, np.array([(0.5 + 0.5 * scale) * 1.2 * diag, 0.0, 0.0]))
    Q = random_rotation(rng, 5, 30)[:3, :3]
    V2, F2 = shape.mesh(23, Q)
    b.add("scaled", *transform_mesh(T, V2, F2))
    b.copy_of("scaled", "base", T, 0.004)
    b.plant("similarity", T, "base", "scaled")
    return b.build("scaled", f"bumpy superquadric plus a rotated copy scaled by {scale}", seed,
                   filter_params={"transformation_group": 1})


# -- (d) noisy -----------------------------------------------------------------------------

def scene_noisy(seed: int = 0, base: str = "cow", n_faces: int = 16000,
                noise: float = 0.001) -> Scene:
    rng = np.random.default_rng([seed, 4])
    V, F = base_mesh(base, n_faces)
    b = _Builder()
    b.add("base", V, F)
    R = random_rotation(rng, 60, 150)
    T = _placed(R, np.array([1.2, 0.15, 0.0]))
    V2, F2 = retessellate(V, F, 1.3, rng)
    V2, F2 = transform_mesh(T, V2, F2)
    scene_diag = bbox_diagonal(np.concatenate([V, V2]))
    V2 = V2 + vertex_normals(V2, F2) * rng.normal(0.0, noise * scene_diag, (len(V2), 1))
    b.add("noisy", V2, F2)
    b.copy_of("noisy", "base", T, 0.006)
    b.plant("rigid_noisy", T, "base", "noisy")
    return b.build("noisy", f"{base} plus a rigid copy with Gaussian normal noise "
                   f"(sigma {noise:.1%} of the diagonal)", seed,
                   notes=f"{base} is roughly bilaterally symmetric: approximate reflections "
                         "between the copies are correct extras", oracle_families=True)


# -- (e) row of translated copies ----------------------------------------------------------

def scene_row(seed: int = 0, copies: int = 4, freq: int = 20, name: str = "row") -> Scene:
    rng = np.random.default_rng([seed, 5])
    # an elongated bumpy superquadric: asymmetric, so the only relations between the copies
    # are the translations (the bundled bone is itself nearly symmetric under reflections)
    shape = StarShape(axes=(1.0, 0.45, 0.35), exponent=2.4, amplitude=0.2,
                      field=RadialField(rng, 8, 0.6))
    R = random_rotation(rng, 20, 60)  # the row is not along a principal axis of the part
    V, F = transform_mesh(R, *shape.mesh(freq))
    extent = V.max(0) - V.min(0)
    step = np.array([0.0, extent[1] * 1.25, 0.0])
    b = _Builder()
    b.add("copy0", V, F)
    for k in range(1, copies):
        Q = random_rotation(rng, 5, 30)[:3, :3]
        V2, F2 = transform_mesh(R, *shape.mesh(freq + [1, -1, 2][(k - 1) % 3], Q))
        b.add(f"copy{k}", V2 + k * step, F2)
        b.copy_of(f"copy{k}", "copy0", translation(k * step), 0.004)
    for p in range(1, copies):
        b.plant(f"translation^{p}", translation(p * step), "copy0", f"copy{p}",
                required=(p == 1), family="row", power=p)
    for k in range(1, copies - 1):
        b.plant(f"translation_{k}{k + 1}", translation(step), f"copy{k}", f"copy{k + 1}",
                required=False, family="row", power=1)
    return b.build(name, f"row of {copies} equally spaced translated copies of a bumpy "
                   "superquadric", seed, expected_generators={"row": 1})


# -- (f) small repeated part ---------------------------------------------------------------

def scene_small_part(seed: int = 0, base: str = "bunny", n_faces: int = 30000,
                     fraction: float = 0.02, name: str = "small_part") -> Scene:
    rng = np.random.default_rng([seed, 6])
    V, F = base_mesh(base, n_faces)
    big_area = face_areas(V, F).sum()
    shape = StarShape(axes=(1.0, 0.6, 0.4), exponent=2.6, amplitude=0.2,
                      field=RadialField(rng, 7, 0.6))
    S, SF = shape.mesh(14)
    s = math.sqrt(fraction / (1 - 2 * fraction) * big_area / face_areas(S, SF).sum())
    b = _Builder()
    b.add("large", V, F)
    T1 = _placed(scaling(s) @ random_rotation(rng, 0, 180), np.array([0.62, 0.18, 0.0]))
    T2 = _placed(scaling(s) @ random_rotation(rng, 0, 180), np.array([0.62, -0.22, 0.05]))
    b.add("small1", *transform_mesh(T1, S, SF))
    Q = random_rotation(rng, 5, 30)[:3, :3]
    b.add("small2", *transform_mesh(T2, *shape.mesh(15, Q)))
    T = T2 @ np.linalg.inv(T1)
    b.copy_of("small2", "small1", T, 0.004)
    b.plant("small_rigid", T, "small1", "small2")
    return b.build(name, f"a small bumpy superquadric (~{fraction:.0%} of the area) "
                   f"repeated twice beside a large {base}", seed, oracle_families=True)


# -- (g) no symmetry -----------------------------------------------------------------------

def scene_asymmetric(seed: int = 0) -> Scene:
    rng = np.random.default_rng([seed, 7])
    shape = StarShape(amplitude=0.25, field=RadialField(rng, 11, 0.5))
    b = _Builder()
    b.add("blob", *shape.mesh(40))
    return b.build("asymmetric", "sphere displaced by a random low-frequency function", seed,
                   max_reported_area_fraction=0.05)


# -- CAD scenes (need tests/fetch_cgal_meshes.sh) -------------------------------------------

def scene_cad_fandisk(seed: int = 0, cgal_dir: Optional[str] = None,
                      n_faces: int = 14000) -> Scene:
    """fandisk + a mirrored copy + a rotated copy: the demo-like CAD scene."""
    rng = np.random.default_rng([seed, 8])
    V, F = base_mesh("fandisk", n_faces, cgal_dir)
    b = _Builder()
    b.add("fandisk", V, F)
    Tm = _placed(mirror([1.0, 0.0, 0.0]), np.array([1.15, 0.0, 0.0]))
    b.add("mirrored", *transform_mesh(Tm, *retessellate(V, F, 0.75, rng)))
    b.copy_of("mirrored", "fandisk", Tm, 0.004)
    b.plant("mirror", Tm, "fandisk", "mirrored")
    Tr = _placed(rotation([0.3, 1.0, 0.2], math.radians(110)), np.array([0.55, 1.1, 0.0]))
    b.add("rotated", *transform_mesh(Tr, *retessellate(V, F, 1.3, rng)))
    b.copy_of("rotated", "fandisk", Tr, 0.004)
    b.plant("rotation", Tr, "fandisk", "rotated")
    b.plant("mirror_rotated", Tr @ np.linalg.inv(Tm), "mirrored", "rotated", required=False)
    return b.build("cad_fandisk", "CGAL fandisk, a mirrored copy and a rotated copy", seed,
                   oracle_families=True)


SCENES: Dict[str, Callable[..., Scene]] = {
    "mirrored": scene_mirrored,
    "rigid": scene_rigid,
    "scaled": scene_scaled,
    "noisy": scene_noisy,
    "row": scene_row,
    "small_part": scene_small_part,
    "asymmetric": scene_asymmetric,
}
#: the seven core scenes (no download needed)
SCENE_NAMES: Tuple[str, ...] = tuple(SCENES)
CAD_SCENES: Dict[str, Callable[..., Scene]] = {"cad_fandisk": scene_cad_fandisk}
CAD_SCENE_NAMES: Tuple[str, ...] = tuple(CAD_SCENES)


# ========================================================================================
# Hard scenes (issue 5, "tests that prove it"): noise on both copies, a partial symmetry
# inside one fused surface, holes, anisotropic triangles, a coarse CAD part, a thin plate,
# a fine row, a 1 % part, scaled copies of other bases, analytic continuous shapes, and
# scenes where continuous shapes could flood the report list.  A group of their own, so
# that the core scenes' figures stay comparable over time.
# ========================================================================================

def _oracle_self_symmetries(scene: Scene, part: str, tol: float) -> List[PlantedSymmetry]:
    """Scene.self_symmetries for one part: the oracle's symmetries of its clean mesh within
    tol of the scene's diagonal, each with the vertices it maps (source) and the vertices its
    inverse maps (target)."""
    import oracle
    V, F = scene.clean_parts.get(part) or scene.part_mesh(part)
    Vp, Fp = scene.part_mesh(part)
    Vr = V if len(V) == len(Vp) else Vp  # a noisy part's clean twin has the same vertices
    S = oracle.Surface.from_mesh(V, F, spacing=0.002)
    v0 = scene.parts[part][0]
    share = face_areas(Vp, Fp).sum() / scene.area()
    out = []
    t = tol * scene.diagonal
    for name, T, fraction in oracle.self_symmetries(V, F, tol=t / S.diagonal, surface=S):
        src = np.nonzero(oracle.mapped_mask(S, T, Vr, t))[0]
        dst = np.nonzero(oracle.mapped_mask(S, np.linalg.inv(T), Vr, t))[0]
        out.append(PlantedSymmetry(
            name=f"{part} self {name}", transform=T, source_part=part, target_part=part,
            source_vertices=v0 + src, target_vertices=v0 + dst,
            source_area_fraction=float(fraction * share), reflection=is_reflection(T),
            scale=transform_scale(T), required=False))
    return out


def _posed(scene: Scene, rng: np.random.Generator) -> Scene:
    """The scene moved by a random rigid motion, so that no axis or plane of its ground
    truth lies along the coordinate axes (the shapes are built about z)."""
    G = translation(rng.uniform(-0.5, 0.5, 3)) @ random_rotation(rng, 20, 160)
    return dataclasses.replace(scene.transformed(G), name=scene.name)


def _analytic_part(b: _Builder, part: str, dense: Tuple[np.ndarray, np.ndarray],
                   n_faces: int, offset=(0.0, 0.0, 0.0)) -> np.ndarray:
    """Add the remeshed dense analytic mesh (moved by offset) as a part whose clean surface
    is the dense mesh; returns the part's vertices relative to `offset`, for regions."""
    V, F = remeshed(*dense, n_faces)
    o = np.asarray(offset, float)
    b.add(part, V + o, F, clean=(dense[0] + o, dense[1]))
    return V


def _n_around(radius: float, h: float) -> int:
    return max(64, int(math.ceil(2 * math.pi * radius / h)))


def _cylinder(b: _Builder, part: str, radius: float, height: float, center, n_faces: int,
              mirror_required: bool = True, h: float = 0.01) -> None:
    """A capped cylinder about z through `center` with its ground truth: the rotational
    family (required); the side's translations and the caps' planar families (optional); the
    mirror across its mid-plane, modulo the rotations (with them it makes every half-turn
    about a diameter and the point reflection)."""
    z0, z1 = -height / 2, height / 2
    rz = profile([np.array([[0, z0], [radius, z0]]), np.array([[radius, z0], [radius, z1]]),
                  np.array([[radius, z1], [0, z1]])], h)
    c = np.asarray(center, float)
    V = _analytic_part(b, part, revolve(rz, _n_around(radius, h)), n_faces, c)
    up = np.array([0.0, 0.0, 1.0])
    b.family(f"{part}_rotation", KIND_ROTATIONAL, c, up, part)
    side = np.nonzero(np.abs(np.hypot(V[:, 0], V[:, 1]) - radius) < 1e-3 * radius)[0]
    b.family(f"{part}_side_translation", KIND_TRANSLATIONAL, c, up, part, side, required=False)
    for sign, zc in ((-1, z0), (1, z1)):
        cap = np.nonzero(np.abs(V[:, 2] - zc) < 1e-9)[0]
        b.family(f"{part}_cap{'+' if sign > 0 else '-'}", KIND_PLANAR, c + zc * up, sign * up,
                 part, cap, required=False)
    b.plant(f"{part}_mid_mirror", about(c, mirror(up)), part, part, required=mirror_required,
            modulo=f"{part}_rotation")


def _torus(b: _Builder, part: str, R: float, r: float, center, n_faces: int) -> None:
    """A round torus about z with its rotational family and its equatorial mirror (modulo
    the rotations), both required."""
    shape = BumpyTorus(R, r, 0.0, np.zeros((0, 4)))
    c = np.asarray(center, float)
    _analytic_part(b, part, shape.mesh(_n_around(R + r, 0.012), _n_around(r, 0.012)),
                   n_faces, c)
    up = np.array([0.0, 0.0, 1.0])
    b.family(f"{part}_rotation", KIND_ROTATIONAL, c, up, part)
    b.plant(f"{part}_equator_mirror", about(c, mirror(up)), part, part,
            modulo=f"{part}_rotation")


def _box(b: _Builder, part: str, size, center, n_faces: int, faces_required: bool = True,
         mirrors_required: bool = True) -> None:
    """An axis-aligned box (three different sides) with its six planar families, its three translational families
    (the four faces parallel to an edge are an extrusion along it; optional) and its discrete
    group: three mirrors (required unless told), three half-turns and the point reflection
    (optional: a user would not insist on the 180-degree flips)."""
    c = np.asarray(center, float)
    size = np.asarray(size, float)
    V, F = remeshed(*box_mesh(size), n_faces)
    b.add(part, V + c, F)
    for k in range(3):
        e = np.eye(3)[k]
        for sign in (-1, 1):
            face = np.nonzero(np.abs(V[:, k] - sign * size[k] / 2) < 1e-9)[0]
            b.family(f"{part}_face{'xyz'[k]}{'+' if sign > 0 else '-'}", KIND_PLANAR,
                     c + sign * size[k] / 2 * e, sign * e, part, face, required=faces_required)
        others = [a for a in range(3) if a != k]
        sides = np.nonzero((np.abs(np.abs(V[:, others]) - size[others] / 2) < 1e-9).any(1))[0]
        b.family(f"{part}_along_{'xyz'[k]}", KIND_TRANSLATIONAL, c, e, part, sides,
                 required=False)
        b.plant(f"{part}_mirror_{'xyz'[k]}", about(c, mirror(e)), part, part,
                required=mirrors_required)
        b.plant(f"{part}_half_turn_{'xyz'[k]}", about(c, rotation(e, math.pi)), part, part,
                required=False)
    b.plant(f"{part}_point_reflection", about(c, linear(-np.eye(3))), part, part,
            required=False)


def _planted_pair(b: _Builder, rng: np.random.Generator, size: float, c1, c2,
                  freq: int = 16) -> None:
    """An asymmetric bumpy superquadric and a re-sampled rigid copy (required relation).
    Its bumps are strong and narrow: milder ones left a part this small mirror-symmetric
    within the detector's tolerance, which is relative to the whole scene."""
    shape = StarShape(axes=(1.0, 0.7, 0.5), exponent=2.2, amplitude=0.35,
                      field=RadialField(rng, 10, 0.45))
    T1 = _placed(scaling(size) @ random_rotation(rng, 0, 180), np.asarray(c1, float))
    T2 = _placed(scaling(size) @ random_rotation(rng, 0, 180), np.asarray(c2, float))
    b.add("pair1", *transform_mesh(T1, *shape.mesh(freq)))
    Q = random_rotation(rng, 5, 30)[:3, :3]
    b.add("pair2", *transform_mesh(T2, *shape.mesh(freq + 1, Q)))
    T = T2 @ np.linalg.inv(T1)
    b.copy_of("pair2", "pair1", T, 0.004)
    b.plant("pair", T, "pair1", "pair2")


# -- noise on both copies --------------------------------------------------------------------

def scene_noisy_both(seed: int = 0, level: float = 0.001, base: str = "cow",
                     n_faces: int = 16000) -> Scene:
    """Both the base and its rigid copy carry Gaussian noise along the normal (sigma = level
    times the scene's diagonal); the oracle sees their clean twins."""
    rng = np.random.default_rng([seed, 11, int(round(level * 1e4))])
    V, F = base_mesh(base, n_faces)
    T = _placed(random_rotation(rng, 60, 150), np.array([1.2, 0.15, 0.0]))
    V2, F2 = transform_mesh(T, *retessellate(V, F, 1.3, rng))
    sigma = level * bbox_diagonal(np.concatenate([V, V2]))
    b = _Builder()
    for part, (X, XF) in (("base", (V, F)), ("copy", (V2, F2))):
        noisy = X + vertex_normals(X, XF) * rng.normal(0.0, sigma, (len(X), 1))
        b.add(part, noisy, XF, clean=(X, XF))
    b.copy_of("copy", "base", T, 0.004 + 5 * level)
    b.plant("rigid_noisy", T, "base", "copy")
    return b.build(f"noisy_both_{level * 100:.1f}", f"{base} and a rigid copy, both with "
                   f"Gaussian normal noise of sigma {level:.1%} of the diagonal", seed,
                   oracle_families=True)


# -- a partial symmetry inside one connected surface -------------------------------------------

def _fused_union(shape: StarShape, T: np.ndarray, rng: np.random.Generator, depth: int,
                 n_points: int = 120000) -> Tuple[np.ndarray, np.ndarray, Callable]:
    """Screened Poisson surface of the union of the shape and T(shape), from oriented
    samples of each surface outside the other solid.  Returns (V, F, inside1, inside2)."""
    import pymeshlab

    def inside1(X):
        r = np.linalg.norm(X, axis=1)
        return r < shape.radius(X / np.maximum(r, 1e-12)[:, None])

    def inside2(X):
        return inside1(apply(np.linalg.inv(T), X))

    P, N = [], []
    for k, (V, F) in enumerate([shape.mesh(44), transform_mesh(T, *shape.mesh(45))]):
        X, f = sample_surface(V, F, n_points, rng, return_faces=True)
        keep = ~(inside2 if k == 0 else inside1)(X)
        P.append(X[keep])
        N.append(face_normals(V, F)[f][keep])
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(vertex_matrix=np.concatenate(P),
                               v_normals_matrix=np.concatenate(N)))
    # One thread: with more, the reconstruction differs from run to run.
    ms.generate_surface_reconstruction_screened_poisson(depth=depth, preclean=True, threads=1)
    ms.meshing_remove_connected_component_by_face_number(mincomponentsize=1000)
    ms.meshing_remove_unreferenced_vertices()
    m = ms.current_mesh()
    return m.vertex_matrix().copy(), m.face_matrix().astype(np.int64), inside1, inside2


def scene_poisson_fused(seed: int = 0, n_faces: int = 24000, depth: int = 7) -> Scene:
    """Two overlapping copies of an elongated bumpy part fused into ONE watertight surface:
    the planted rotation about the pivot of the overlap maps the first half onto the second.
    The ground-truth regions are the fused vertices near one copy, away (5 % of the
    diagonal) from the other copy and whose image is away from the first.  Poisson depth 7
    keeps the generation to seconds; its surface stays within 0.3 % of the diagonal of the
    copies away from the overlap."""
    rng = np.random.default_rng([seed, 12])
    shape = StarShape(axes=(1.0, 0.34, 0.27), exponent=2.4, amplitude=0.15,
                      field=RadialField(rng, 8, 0.6))
    axis = np.array([rng.normal(0, 0.3), rng.normal(0, 0.3), 1.0])
    T = about([0.72, 0.0, 0.0], rotation(axis, math.radians(rng.uniform(95, 125))))
    Vp, Fp, inside1, inside2 = _fused_union(shape, T, rng, depth)
    V, F = remeshed(Vp, Fp, n_faces)
    diag, Ti = bbox_diagonal(V), np.linalg.inv(T)
    copy1 = shape.mesh(44)
    copy2 = transform_mesh(T, *copy1)

    def away(X, mesh, inside):  # outside the solid and 5 % of the diagonal from its surface
        return ~inside(X) & (point_to_surface_distance(X, *mesh) > 0.05 * diag)

    src = ((point_to_surface_distance(V, *copy1) < 0.003 * diag) & away(V, copy2, inside2)
           & away(apply(T, V), copy1, inside1))
    dst = ((point_to_surface_distance(V, *copy2) < 0.003 * diag) & away(V, copy1, inside1)
           & away(apply(Ti, V), copy2, inside2))
    b = _Builder()
    b.add("fused", V, F, clean=(Vp, Fp))
    b.plant("fused_halves", T, "fused", "fused", source_region=np.nonzero(src)[0],
            target_region=np.nonzero(dst)[0])
    return b.build("poisson_fused", "two overlapping copies of a bumpy part fused into one "
                   "surface by screened Poisson reconstruction", seed)


# -- holes and open boundaries -----------------------------------------------------------------

def _cut_holes(V: np.ndarray, F: np.ndarray, rng: np.random.Generator, holes: int,
               radius: float, slice_fraction: float) -> Tuple[np.ndarray, np.ndarray]:
    """Remove the faces in `holes` discs (well apart) and a slice beyond a random plane."""
    C = V[F].mean(1)
    cand = V[rng.choice(len(V), 300, replace=False)]
    centres = [cand[0]]
    for _ in range(holes - 1):  # farthest-point choice keeps the holes apart
        d = np.min([np.linalg.norm(cand - c, axis=1) for c in centres], axis=0)
        centres.append(cand[int(np.argmax(d))])
    cut = np.zeros(len(F), bool)
    for c in centres:
        cut |= np.linalg.norm(C - c, axis=1) < radius * rng.uniform(0.7, 1.3)
    h = C @ random_unit_vector(rng)
    cut |= h > np.quantile(h, 1 - slice_fraction)
    F = F[~cut]
    used, F = np.unique(F, return_inverse=True)
    return V[used], F.reshape(-1, 3)


def scene_holes(seed: int = 0, base: str = "bunny", n_faces: int = 15000) -> Scene:
    """A base and a rigid copy with five holes and a slice cut off (open boundaries); the
    relation holds on the base vertices that land on what is left of the copy."""
    rng = np.random.default_rng([seed, 13])
    V, F = base_mesh(base, n_faces)
    Vh, Fh = _cut_holes(*retessellate(V, F, 0.85, rng), rng, holes=5, radius=0.05,
                        slice_fraction=0.08)
    T = _placed(random_rotation(rng, 60, 150), np.array([1.15, 0.1, 0.0]))
    copy = transform_mesh(T, Vh, Fh)
    b = _Builder()
    b.add("base", V, F)
    b.add("holed", *copy)
    mapped = point_to_surface_distance(apply(T, V), *copy) < 0.002
    b.plant("rigid_holed", T, "base", "holed", source_region=np.nonzero(mapped)[0])
    return b.build("holes", f"{base} and a rigid copy with five holes and a slice cut off",
                   seed, oracle_families=True)


# -- anisotropic tessellation ------------------------------------------------------------------

def _base_and_rigid_copy(base: str, base_mesh_: Tuple[np.ndarray, np.ndarray], copy: str,
                         copy_mesh: Tuple[np.ndarray, np.ndarray], T: np.ndarray,
                         relation: str) -> "_Builder":
    """A builder holding a base and T applied to its re-tessellated copy, with the planted
    relation between them."""
    b = _Builder()
    b.add(base, *base_mesh_)
    b.add(copy, *transform_mesh(T, *copy_mesh))
    b.copy_of(copy, base, T, 0.004)
    b.plant(relation, T, base, copy)
    return b


def scene_anisotropic(seed: int = 0, base: str = "bone", n_faces: int = 15000,
                      stretch: float = 4.0) -> Scene:
    """A base and a rigid copy tessellated with long thin triangles: squeezed by `stretch`
    along the base's long axis, remeshed isotropically, stretched back.  (Squeezing along a
    random direction can leave a flat part's triangles as they were.)"""
    rng = np.random.default_rng([seed, 14])
    V, F = base_mesh(base, n_faces)
    u = principal_frame(V, F)[1][:, 2]
    A = np.eye(3) + (1.0 / stretch - 1.0) * np.outer(u, u)
    Vc = V @ A.T
    V2, F2 = _remesh(Vc, F, edge_length_for(Vc, F, n_faces))
    V2 = _slide_shared_vertices(V2 @ np.linalg.inv(A).T, F2, V, rng)
    T = _placed(random_rotation(rng, 60, 150), np.array([1.1, 0.0, 0.0]))
    b = _base_and_rigid_copy("base", (V, F), "anisotropic", (V2, F2), T, "rigid_anisotropic")
    return b.build("anisotropic", f"{base} and a rigid copy tessellated with triangles "
                   f"{stretch:g} times longer along one direction", seed,
                   oracle_families=True)


# -- a coarse CAD part -------------------------------------------------------------------------

def scene_cad_joint(seed: int = 0, cgal_dir: Optional[str] = None,
                    n_faces: int = 20000) -> Scene:
    """CGAL's joint as distributed (a coarse CAD tessellation, long triangles and sharp
    creases) beside a densely re-tessellated rigid copy.  Its flat faces and cylinders are
    continuous families nobody listed: the oracle checks continuous reports."""
    rng = np.random.default_rng([seed, 15])
    V, F = _load(base_mesh_path("joint", cgal_dir))
    V = normalized(V)
    ratio = edge_length_for(V, F, n_faces) / mean_edge_length(V, F)
    V2, F2 = retessellate(V, F, ratio, rng)
    T = _placed(random_rotation(rng, 60, 150), np.array([1.1, 0.2, 0.0]))
    b = _base_and_rigid_copy("joint", (V, F), "copy", (V2, F2), T, "rigid")
    return b.build("cad_joint", "coarse CGAL joint and a densely re-tessellated rigid copy",
                   seed, oracle_families=True)


# -- a thin plate mirrored about its mid-plane -------------------------------------------------

def scene_thin_plate(seed: int = 0, n_faces: int = 24000, half_thickness: float = 0.015,
                     K: int = 60, n_around: int = 320) -> Scene:
    """A thin plate whose bottom face is the mirror image of its top face across the
    mid-plane z = 0: that mirror is its only symmetry.  The faces are 1-2 % of the diagonal
    apart where no bump rises (a translation across the plate maps positions there, not
    normals); a dome and sixteen random bumps curve them, so that no patch of a face of more
    than about 1 % of the area is a plane within a tenth of the detector's 1 % tolerance
    (gently bulging faces are reported as planes, rightly).  The rim is a band ruled along
    the plate's normal, and where the outline has an inflection a strip of it is that flat
    (one of 1.4 % of the area was found on the scene split above 50,000 vertices): a
    continuous report is the oracle's to judge."""
    rng = np.random.default_rng([seed, 16])
    a = rng.uniform(0, 2 * np.pi, 3)
    phi = 2 * np.pi * np.arange(n_around) / n_around
    outline = 1 + 0.22 * np.cos(2 * phi + a[0]) + 0.12 * np.sin(3 * phi + a[1]) \
        + 0.06 * np.cos(5 * phi + a[2])
    bumps = rng.uniform(-0.9, 0.9, (16, 2))
    heights = rng.uniform(0.03, 0.06, 16)

    def top(x, y):  # curved everywhere: a convex quadratic plus many random bumps
        h = 0.12 * (x ** 2 + 0.5 * y ** 2 + 0.3 * x * y)
        for (cx, cy), a in zip(bumps, heights):
            h = h + a * np.exp(-((x - cx) ** 2 + (y - cy) ** 2) / 0.12)
        return half_thickness + h

    rho = np.linspace(0, 1, K + 1)[:, None]
    x, y = rho * outline * np.cos(phi), rho * outline * np.sin(phi)
    z = top(x, y)
    rim = np.linspace(-1, 1, 7)[1:-1, None] * z[-1]
    # one grid: the bottom from the centre out, the rim upwards, the top back to the centre
    X = np.concatenate([x, np.repeat(x[-1:], 5, 0), x[::-1]])
    Y = np.concatenate([y, np.repeat(y[-1:], 5, 0), y[::-1]])
    Z = np.concatenate([-z, rim, z[::-1]])
    dense = grid_mesh(np.stack([X, Y, Z], -1))
    b = _Builder()
    _analytic_part(b, "plate", dense, n_faces)
    b.plant("mid_plane_mirror", mirror([0, 0, 1]), "plate", "plate")
    return _posed(b.build("thin_plate", "a thin bumpy plate, mirror-symmetric about its "
                          "mid-plane only", seed, oracle_families=True), rng)


# -- scaled copies on other bases --------------------------------------------------------------

def scene_scaled_cow(seed: int = 0, scale: float = 0.6, n_faces: int = 16000) -> Scene:
    rng = np.random.default_rng([seed, 17])
    V, F = base_mesh("cow", n_faces)
    T = _placed(scaling(scale) @ random_rotation(rng, 60, 150), np.array([0.95, 0.1, 0.0]))
    b = _Builder()
    b.add("base", V, F)
    b.add("scaled", *transform_mesh(T, *retessellate(V, F, 1.3, rng)))
    b.copy_of("scaled", "base", T, 0.004)
    b.plant("similarity", T, "base", "scaled")
    return b.build("scaled_cow", f"cow plus a rotated copy scaled by {scale}", seed,
                   filter_params={"transformation_group": 1}, oracle_families=True)


def scene_scaled_torus(seed: int = 0, scale: float = 0.55) -> Scene:
    rng = np.random.default_rng([seed, 18])
    torus = BumpyTorus.random(rng)
    V, F = torus.mesh(150, 36)
    diag = bbox_diagonal(V)
    T = _placed(scaling(scale) @ random_rotation(rng, 60, 150),
                np.array([(0.5 + 0.5 * scale) * 1.1 * diag, 0.2, 0.0]))
    b = _Builder()
    b.add("base", V, F)
    b.add("scaled", *transform_mesh(T, *torus.mesh(131, 41, 0.43, 0.57)))
    b.copy_of("scaled", "base", T, 0.004)
    b.plant("similarity", T, "base", "scaled")
    return b.build("scaled_torus", f"bumpy torus plus a rotated copy scaled by {scale}", seed,
                   filter_params={"transformation_group": 1})


# -- analytic continuous shapes ----------------------------------------------------------------

def scene_cylinder(seed: int = 0, n_faces: int = 20000) -> Scene:
    rng = np.random.default_rng([seed, 21])
    b = _Builder()
    _cylinder(b, "cylinder", 0.3, 1.0, np.zeros(3), n_faces)
    return _posed(b.build("cylinder", "capped cylinder (radius 0.3, height 1)", seed), rng)


def scene_cone(seed: int = 0, n_faces: int = 20000, h: float = 0.01) -> Scene:
    """A capped cone: rotational family, a planar base, no mirror normal to its axis."""
    rng = np.random.default_rng([seed, 22])
    radius, height = 0.4, 0.9
    rz = profile([np.array([[0, 0], [radius, 0]]), np.array([[radius, 0], [0, height]])], h)
    b = _Builder()
    V = _analytic_part(b, "cone", revolve(rz, _n_around(radius, h)), n_faces)
    up = np.array([0.0, 0.0, 1.0])
    b.family("cone_rotation", KIND_ROTATIONAL, np.zeros(3), up, "cone")
    b.family("cone_base", KIND_PLANAR, np.zeros(3), -up, "cone",
             np.nonzero(np.abs(V[:, 2]) < 1e-9)[0], required=False)
    return _posed(b.build("cone", "capped cone (radius 0.4, height 0.9)", seed), rng)


def scene_vase(seed: int = 0, n_faces: int = 20000, h: float = 0.01) -> Scene:
    """A vase: a wavy profile revolved, closed at the bottom, open at the top."""
    rng = np.random.default_rng([seed, 23])
    a = rng.uniform(0, 2 * np.pi)
    z = np.linspace(0, 1.0, 400)
    r = 0.24 + 0.07 * np.sin(5.5 * z + a) + 0.06 * z
    rz = profile([np.array([[0, 0], [r[0], 0]]), np.stack([r, z], 1)], h)
    b = _Builder()
    V = _analytic_part(b, "vase", revolve(rz, _n_around(r.max(), h)), n_faces)
    up = np.array([0.0, 0.0, 1.0])
    b.family("vase_rotation", KIND_ROTATIONAL, np.zeros(3), up, "vase")
    b.family("vase_bottom", KIND_PLANAR, np.zeros(3), -up, "vase",
             np.nonzero(np.abs(V[:, 2]) < 1e-9)[0], required=False)
    return _posed(b.build("vase", "surface of revolution of a wavy profile, open at the "
                          "top", seed), rng)


def scene_extrusion(seed: int = 0, n_faces: int = 20000, h: float = 0.01) -> Scene:
    """A non-circular, non-symmetric closed profile swept along z, open at both ends: its
    translations along z form a (partial) family; a mirror across any plane normal to z maps
    it partly onto itself (one mirror, modulo the translations; optional)."""
    rng = np.random.default_rng([seed, 24])
    a = rng.uniform(0, 2 * np.pi, 3)
    phi = np.linspace(0, 2 * np.pi, 2000, endpoint=False)
    rho = 0.3 * (1 + 0.25 * np.cos(2 * phi + a[0]) + 0.12 * np.sin(3 * phi + a[1])
                 + 0.05 * np.cos(5 * phi + a[2]))
    C = resample_polyline(np.stack([rho * np.cos(phi), rho * np.sin(phi)], 1), h, closed=True)
    zs = np.linspace(-0.6, 0.6, int(math.ceil(1.2 / h)) + 1)
    P = np.concatenate([np.broadcast_to(C, (len(zs),) + C.shape),
                        np.broadcast_to(zs[:, None, None], (len(zs), len(C), 1))], -1)
    b = _Builder()
    _analytic_part(b, "prism", grid_mesh(P), n_faces)
    up = np.array([0.0, 0.0, 1.0])
    b.family("extrusion", KIND_TRANSLATIONAL, np.zeros(3), up, "prism")
    b.plant("cross_mirror", mirror(up), "prism", "prism", required=False, modulo="extrusion")
    return _posed(b.build("extrusion", "an asymmetric profile extruded along a line, open "
                          "ends", seed), rng)


def scene_helix(seed: int = 0, n_faces: int = 20000, pitch_per_turn: float = 0.3) -> Scene:
    """A helical tube (three turns, open ends): the screw motions about its axis form its
    family; the half-turn about the perpendicular through its middle (and, modulo the screw
    motions, every such half-turn) is a discrete symmetry (optional)."""
    rng = np.random.default_rng([seed, 25])
    pitch = pitch_per_turn / (2 * np.pi)
    b = _Builder()
    _analytic_part(b, "tube", helix_tube(0.35, pitch, 0.07, 3.0, 0.01, 48), n_faces)
    b.family("helix", KIND_HELICAL, np.zeros(3), [0, 0, 1], "tube", pitch=pitch)
    b.plant("half_turn", rotation([1, 0, 0], math.pi), "tube", "tube", required=False,
            modulo="helix")
    return _posed(b.build("helix", "helical tube, three turns", seed), rng)


def scene_box(seed: int = 0, n_faces: int = 20000) -> Scene:
    rng = np.random.default_rng([seed, 26])
    b = _Builder()
    _box(b, "box", (1.0, 0.7, 0.45), np.zeros(3), n_faces)
    return _posed(b.build("box", "box 1 x 0.7 x 0.45: six planar faces, three mirrors", seed),
                  rng)


def scene_sphere(seed: int = 0, n_faces: int = 20000) -> Scene:
    rng = np.random.default_rng([seed, 27])
    V, F = geodesic_sphere(50)
    b = _Builder()
    _analytic_part(b, "sphere", (0.5 * V, F), n_faces)
    b.family("sphere", KIND_SPHERICAL, np.zeros(3), None, "sphere")
    return _posed(b.build("sphere", "sphere of radius 0.5", seed), rng)


def scene_torus(seed: int = 0, n_faces: int = 20000) -> Scene:
    rng = np.random.default_rng([seed, 28])
    b = _Builder()
    _torus(b, "torus", 0.6, 0.2, np.zeros(3), n_faces)
    return _posed(b.build("torus", "round torus (radii 0.6 and 0.2)", seed), rng)


# -- continuous shapes beside discrete ones ("continuous flood") -------------------------------

def scene_hammer(seed: int = 0) -> Scene:
    """A hammer (a box head touching a capped cylindrical handle) and an asymmetric planted
    pair beside it.  Required: the pair and the handle's rotations; the box's group and
    faces, the handle's mirror and side, optional."""
    rng = np.random.default_rng([seed, 41])
    b = _Builder()
    _cylinder(b, "handle", 0.045, 1.0, [0, 0, 0.5], 9000, mirror_required=False)
    # the head's sides differ (0.18 and 0.14): a square section would add a 4-fold turn and
    # diagonal mirrors to its group
    _box(b, "head", (0.5, 0.18, 0.14), [0, 0, 1.07], 9000, faces_required=False,
         mirrors_required=False)
    _planted_pair(b, rng, 0.2, [0.6, 0.3, 0.5], [0.65, -0.35, 0.2])
    return _posed(b.build("hammer", "hammer (box head, cylindrical handle) beside an "
                          "asymmetric planted pair", seed), rng)


def scene_torus_pair(seed: int = 0) -> Scene:
    rng = np.random.default_rng([seed, 42])
    b = _Builder()
    _torus(b, "torus", 0.5, 0.16, np.zeros(3), 14000)
    _planted_pair(b, rng, 0.22, [1.1, 0.35, 0.0], [1.05, -0.45, 0.15])
    return _posed(b.build("torus_pair", "round torus beside an asymmetric planted pair", seed),
                  rng)


def scene_wingnut(seed: int = 0, blades: int = 6, h: float = 0.01) -> Scene:
    """A tapered hub of revolution with six identical asymmetric blades: the rotation by 60
    degrees (blade0 -> blade1) is the required generator of the discrete family, the hub's
    rotations the required continuous family."""
    rng = np.random.default_rng([seed, 43])
    z = np.linspace(0, 0.45, 200)
    r = 0.19 + 0.03 * np.sin(np.pi * z / 0.45) - 0.06 * z
    rz = profile([np.array([[0, 0], [r[0], 0]]), np.stack([r, z], 1),
                  np.array([[r[-1], z[-1]], [0, z[-1]]])], h)
    b = _Builder()
    V = _analytic_part(b, "hub", revolve(rz, _n_around(r.max(), h)), 9000)
    up = np.array([0.0, 0.0, 1.0])
    b.family("hub_rotation", KIND_ROTATIONAL, np.zeros(3), up, "hub")
    for name, zc, sign in (("hub_bottom", 0.0, -1), ("hub_top", z[-1], 1)):
        b.family(name, KIND_PLANAR, zc * up, sign * up, "hub",
                 np.nonzero(np.abs(V[:, 2] - zc) < 1e-9)[0], required=False)
    # strong bumps and a 25-degree pitch about the radial axis: a milder blade made the whole
    # wingnut mirror-symmetric within the detector's tolerance
    blade = StarShape(axes=(0.3, 0.07, 0.15), exponent=2.4, amplitude=0.35,
                      field=RadialField(rng, 10, 0.45))
    place = translation([0.4, 0.0, 0.22]) @ rotation([1, 0, 0], math.radians(25))
    for k in range(blades):
        Q = None if k == 0 else random_rotation(rng, 5, 30)[:3, :3]
        Rk = rotation(up, 2 * math.pi * k / blades)
        b.add(f"blade{k}", *transform_mesh(Rk @ place, *blade.mesh(14 + (k % 3), Q)))
        if k:
            b.copy_of(f"blade{k}", "blade0", Rk, 0.004)
            b.plant(f"rotation^{k}", Rk, "blade0", f"blade{k}", required=(k == 1),
                    family="wing", power=k)
    return _posed(b.build("wingnut", f"hub of revolution with {blades} identical blades", seed,
                          expected_generators={"wing": 1}), rng)


def scene_boat(seed: int = 0, deck: float = 0.08) -> Scene:
    """A hull mirror-symmetric about y = 0 (bumps mirrored in pairs) with a flat deck, and a
    cylindrical mast standing on the deck in the mirror plane."""
    rng = np.random.default_rng([seed, 44])
    field = RadialField(rng, 6, 0.6)
    field.centers = np.concatenate([field.centers, field.centers * [1, -1, 1]])
    field.amps = np.concatenate([field.amps, field.amps])
    hull = StarShape(axes=(1.0, 0.36, 0.3), exponent=2.3, amplitude=0.1, field=field)
    Vd, Fd = hull.mesh(48)  # the icosahedral grid is itself symmetric under y -> -y
    Vd[:, 2] = np.minimum(Vd[:, 2], deck)
    b = _Builder()
    V = _analytic_part(b, "hull", (Vd, Fd), 16000)
    up = np.array([0.0, 0.0, 1.0])
    b.plant("hull_mirror", mirror([0, 1, 0]), "hull", "hull")
    b.family("deck", KIND_PLANAR, deck * up, up, "hull",
             np.nonzero(V[:, 2] > deck - 1e-9)[0], required=False)
    _cylinder(b, "mast", 0.03, 0.6, [0.12, 0.0, deck + 0.3], 6000, mirror_required=False)
    return _posed(b.build("boat", "hull with a mirror plane and a flat deck, cylindrical mast",
                          seed), rng)


#: one window of the facade: (size, centre) of its boxes, the window's centre at the origin
#: and the wall's front at z = 0, each box set 0.05 into the wall (a box standing on the
#: front would put its back face on the wall's, facing the other way).  Two jambs, a head,
#: a sill deeper, wider and taller than the head (no mirror across the horizontal) and a
#: mullion off the centre (none across the vertical).  Every box is two or more detector tolerances (1 % of the diagonal) thick, and
#: no two differ by less than that: thinner relief lies within the tolerance of the wall,
#: and a head nearly as tall as the sill would map onto the next row's sill.
FACADE_WINDOW = (((0.2, 1.2, 0.3), (-0.5, 0.0, 0.1)), ((0.2, 1.2, 0.3), (0.5, 0.0, 0.1)),
                 ((1.2, 0.2, 0.3), (0.0, 0.7, 0.1)), ((1.4, 0.4, 0.5), (0.0, -0.8, 0.2)),
                 ((0.16, 1.2, 0.2), (0.15, 0.0, 0.05)))


def _facade_window(edge: float) -> Tuple[np.ndarray, np.ndarray]:
    """The window's boxes, each remeshed at `edge`, as one mesh of separate closed boxes."""
    Vs, Fs, nv = [], [], 0
    for size, centre in FACADE_WINDOW:
        V, F = _remesh(*box_mesh(size), edge)
        Vs.append(V + np.asarray(centre))
        Fs.append(F + nv)
        nv += len(V)
    return np.concatenate(Vs), np.concatenate(Fs)


def scene_facade(seed: int = 0, columns: int = 4, rows: int = 2,
                 window_faces: int = 2300, margin: float = 0.6, name: str = "facade") -> Scene:
    """A CAD facade: a wall slab with columns x rows identical windows standing on its front,
    each window five boxes re-tessellated on its own.  Required: the lattice's two generators
    (one column, one row; window_0_0 onto its neighbours) and the wall's front and back
    planes.  Every other translation of the lattice, the wall's other faces, its extrusions
    and mirrors are optional; the windows' own boxes and the relations inside a window (a
    jamb onto the other) are unlisted, left to the oracle (oracle_families).  `margin` is the
    wall's width beyond the outer windows, in all (the spacing is 1.6 by 2.2)."""
    rng = np.random.default_rng([seed, 45])
    cell = np.array([1.6, 2.2, 0.0])
    wall = np.array([columns * cell[0] + margin, rows * cell[1] + margin, 0.4])
    b = _Builder()
    _box(b, "wall", wall, [0, 0, -wall[2] / 2], 8000, faces_required=False,
         mirrors_required=False)
    for f in b.fams:
        if f["name"] in ("wall_facez+", "wall_facez-"):
            f["required"] = True
    area = sum(2 * (x * y + y * z + z * x) for (x, y, z), _ in FACADE_WINDOW)
    edge = math.sqrt(4.0 * area / (math.sqrt(3.0) * window_faces))
    def origin(i, j):
        return np.array([(i - (columns - 1) / 2) * cell[0], (j - (rows - 1) / 2) * cell[1], 0])

    source = _facade_window(edge)
    b.add("window_0_0", source[0] + origin(0, 0), source[1])
    for i in range(columns):
        for j in range(rows):
            k = i * rows + j
            if k == 0:
                continue
            V, F = _facade_window(edge * (1 + 0.07 * (1 + k % 4)))
            V = _slide_shared_vertices(V, F, source[0], rng)
            b.add(f"window_{i}_{j}", V + origin(i, j), F)
            T = translation(origin(i, j) - origin(0, 0))
            b.copy_of(f"window_{i}_{j}", "window_0_0", T, 0.004)
            b.plant(f"lattice_{i}_{j}", T, "window_0_0", f"window_{i}_{j}",
                    required=(i, j) in ((1, 0), (0, 1)), family="lattice", power=i + j)
    return _posed(b.build(name, f"wall with {columns} x {rows} identical windows of five "
                          f"boxes each, {margin} of wall around them", seed,
                          expected_generators={"lattice": 2},
                          oracle_families=True), rng)


# -- CAD models as shape collections store them ------------------------------------------------

def _plane_mirror(normal: np.ndarray, offset: float) -> np.ndarray:
    """The reflection across the plane normal . x = offset."""
    return about(normal * offset, mirror(normal))


def scene_cad_chair(seed: int = 0) -> Scene:
    """A chair as shape collections store CAD models (tests/cad_models.py): 14-17 parts that
    overlap, a frame inside the seat, boxes of twelve triangles and prisms with fans of long
    thin triangles, every triangle twice, once each way round.  Its mirror plane is required;
    the parts' own exact symmetries (legs onto legs, a slat onto itself) the oracle checks."""
    import cad_models
    m = cad_models.make_model("chair", seed)
    b = _Builder()
    b.add("chair", m.vertices, m.faces)
    for k, (n, d) in enumerate(m.planes):
        b.plant(f"mirror{k}", _plane_mirror(n, d), "chair", "chair")
    return b.build("cad_chair", "a coarse double-sided CAD chair of many parts", seed, oracle_families=True,
                   corner_vertices_only=True)


def scene_cad_cars(seed: int = 0) -> Scene:
    """Two copies of a coarse double-sided CAD car (an extruded body, a cabin, an engine inside
    the body, four wheels of few sides, headlights): the second turned and moved, its flat
    faces triangulated the other way (the same surface on the same corners, which a CAD part
    has no others).  Required: the copy and each car's mirror plane."""
    import cad_models
    rng = np.random.default_rng([seed, 41])
    a = cad_models.make_model("car", seed, posed=False)
    c = cad_models.make_model("car", seed, posed=False, alt=True)
    T = _placed(random_rotation(rng, 60, 150), np.array([0.0, 1.4, 0.3]) * a.diagonal)
    M = _plane_mirror(*a.planes[0])
    b = _Builder()
    b.add("car", a.vertices, a.faces)
    b.add("copy", *transform_mesh(T, c.vertices, c.faces))
    b.copy_of("copy", "car", T, 0.0)
    b.plant("copy", T, "car", "copy")
    b.plant("mirror", M, "car", "car")
    b.plant("copy_mirror", T @ M @ np.linalg.inv(T), "copy", "copy")
    return b.build("cad_cars", "a coarse double-sided CAD car and a copy tessellated otherwise", seed,
                   oracle_families=True, corner_vertices_only=True)


HARD_SCENES: Dict[str, Callable[..., Scene]] = {
    "noisy_both_0.1": functools.partial(scene_noisy_both, level=0.001),
    "noisy_both_0.2": functools.partial(scene_noisy_both, level=0.002),
    "noisy_both_0.5": functools.partial(scene_noisy_both, level=0.005),
    "poisson_fused": scene_poisson_fused,
    "holes": scene_holes,
    "anisotropic": scene_anisotropic,
    "cad_joint": scene_cad_joint,
    "thin_plate": scene_thin_plate,
    "fine_row": functools.partial(scene_row, copies=12, freq=9, name="fine_row"),
    "small_part_1pct": functools.partial(scene_small_part, base="cow", n_faces=24000,
                                         fraction=0.01, name="small_part_1pct"),
    "scaled_cow": scene_scaled_cow,
    "scaled_torus": scene_scaled_torus,
    "cylinder": scene_cylinder,
    "cone": scene_cone,
    "vase": scene_vase,
    "extrusion": scene_extrusion,
    "helix": scene_helix,
    "box": scene_box,
    "sphere": scene_sphere,
    "torus": scene_torus,
    "hammer": scene_hammer,
    "torus_pair": scene_torus_pair,
    "wingnut": scene_wingnut,
    "boat": scene_boat,
    "facade": scene_facade,
    # the same windows on a wall with 4 of margin around them: a step's patch lies nearly all
    # on the wall's planes and extrusions (whose patches take in the windows' faces too)
    "facade_wide": functools.partial(scene_facade, margin=4.0, name="facade_wide"),
    "cad_chair": scene_cad_chair,
    "cad_cars": scene_cad_cars,
}
#: the hard scenes (cad_joint needs the CAD meshes, like CAD_SCENE_NAMES)
HARD_SCENE_NAMES: Tuple[str, ...] = tuple(HARD_SCENES)
#: CAD models as shape collections store them (tests/cad_models.py): a few hundred triangles
#: over their corners only, so below the other scenes' size and with copies on the same corners
CAD_LIKE_SCENE_NAMES: Tuple[str, ...] = ("cad_chair", "cad_cars")
#: scenes built from the CGAL meshes that tests/fetch_cgal_meshes.sh fetches
NEEDS_CAD_MESHES = frozenset({"cad_fandisk", "cad_joint"})


def cad_meshes_available(cgal_dir: Optional[str] = None) -> bool:
    d = cgal_dir or os.environ.get("SYMMETRY_CGAL_DIR") or DEFAULT_CGAL_DIR
    return all(os.path.exists(os.path.join(d, n + ".off")) for n in CAD_BASES)


def make_scene(name: str, seed: int = 0, **kw) -> Scene:
    """Build the named scene (deterministic in `seed`)."""
    for group in (SCENES, CAD_SCENES, HARD_SCENES):
        if name in group:
            return group[name](seed, **kw)
    raise KeyError(f"unknown scene {name!r}; known: "
                   f"{SCENE_NAMES + CAD_SCENE_NAMES + HARD_SCENE_NAMES}")


def all_scenes(seed: int = 0, include_cad: bool = False) -> List[Scene]:
    names = SCENE_NAMES + (CAD_SCENE_NAMES if include_cad else ())
    return [make_scene(n, seed) for n in names]


# ----------------------------------------------------------------------------------------
# Checks of global self-symmetry (used to show a base is asymmetric and to describe meshes)
# ----------------------------------------------------------------------------------------

def point_to_surface_distance(P: np.ndarray, V: np.ndarray, F: np.ndarray) -> np.ndarray:
    """Unsigned distance from each point of P to the triangle mesh (V, F), exact closest
    point on the surface (MeshLab's per-vertex distance filter on a point cloud)."""
    import pymeshlab
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(np.asarray(V, float), np.asarray(F, np.int32)), "ref")
    ms.add_mesh(pymeshlab.Mesh(np.asarray(P, float)), "points")
    ms.compute_scalar_by_distance_from_another_mesh_per_vertex(
        measuremesh=1, refmesh=0, signeddist=False, maxdist=pymeshlab.PureValue(1e30))
    return np.abs(ms.mesh(1).vertex_scalar_array().copy())


def principal_frame(V: np.ndarray, F: np.ndarray) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Area-weighted centroid, principal axes (columns) and their variances of the surface."""
    a = face_areas(V, F)
    c = V[F].mean(1)
    w = a / a.sum()
    m = (w[:, None] * c).sum(0)
    d = c - m
    C = (w[:, None, None] * d[:, :, None] * d[:, None, :]).sum(0)
    ev, E = np.linalg.eigh(C)
    return m, E, ev


def self_symmetry_residual(V: np.ndarray, F: np.ndarray, A: np.ndarray,
                           center: np.ndarray, n: int = 4000, seed: int = 0,
                           quantile: float = 0.9) -> float:
    """A high quantile of the distance (fraction of the bbox diagonal) from the surface
    mapped by the orthogonal map A about `center` to the surface itself: ~0 for a global
    self-symmetry, small for a shape that is symmetric except for a few spots."""
    rng = np.random.default_rng(seed)
    P = sample_surface(V, F, n, rng)
    Q = (P - center) @ np.asarray(A).T + center
    return float(np.quantile(point_to_surface_distance(Q, V, F), quantile) / bbox_diagonal(V))


def candidate_self_symmetries(V: np.ndarray, F: np.ndarray, max_fold: int = 24
                              ) -> List[Tuple[str, np.ndarray]]:
    """Isometries that could be global symmetries: a symmetry fixes the centroid and permutes
    the principal axes (with distinct variances it maps each to +-itself): the three
    reflections across principal planes, the half-turns and point reflection, and for an
    axis of a (near) rotationally symmetric inertia, rotations by 2 pi / k about it."""
    m, E, ev = principal_frame(V, F)
    out = []
    for i in range(3):
        n = E[:, i]
        out.append((f"reflection across principal plane {i}", np.eye(3) - 2 * np.outer(n, n)))
        out.append((f"half-turn about principal axis {i}", rotation(n, math.pi)[:3, :3]))
    out.append(("point reflection", -np.eye(3)))
    for k in range(3, max_fold + 1):
        for i in range(3):
            out.append((f"{k}-fold rotation about principal axis {i}",
                        rotation(E[:, i], 2 * math.pi / k)[:3, :3]))
    return out


def global_symmetries(V: np.ndarray, F: np.ndarray, tol: float = 0.002,
                      max_fold: int = 24) -> List[Tuple[str, float]]:
    """The candidate self-symmetries (see above) with residual below `tol`."""
    m, _, _ = principal_frame(V, F)
    found = []
    for name, A in candidate_self_symmetries(V, F, max_fold):
        r = self_symmetry_residual(V, F, A, m, n=1500)
        if r < tol:
            found.append((name, r))
    return found


# ----------------------------------------------------------------------------------------
# Command line: list the scenes, or write the bundled demo mesh
# ----------------------------------------------------------------------------------------

#: meshes/demo.ply is `python tests/scenes.py --demo meshes/demo.ply` (needs the CAD meshes)
DEMO_SCENE = ("cad_fandisk", 0)


def _main(argv=None) -> int:
    import argparse
    import time
    ap = argparse.ArgumentParser(description="Scenes with planted symmetries.")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--cad", action="store_true", help="include the CAD scenes")
    ap.add_argument("--hard", action="store_true", help="include the hard scenes")
    ap.add_argument("--save-dir", help="write every scene as DIR/NAME.ply")
    ap.add_argument("--demo", metavar="PATH", help="write the demo mesh to PATH and stop")
    args = ap.parse_args(argv)
    if args.demo:
        make_scene(*DEMO_SCENE).save(args.demo)
        print(f"wrote {args.demo}")
        return 0
    names = SCENE_NAMES + (CAD_SCENE_NAMES if args.cad else ()) + \
        (tuple(n for n in HARD_SCENE_NAMES if args.cad or n not in NEEDS_CAD_MESHES)
         if args.hard else ())
    for name in names:
        t = time.perf_counter()
        s = make_scene(name, args.seed)
        print(s.summary(), f"  [{time.perf_counter() - t:.1f} s]")
        if args.save_dir:
            os.makedirs(args.save_dir, exist_ok=True)
            s.save(os.path.join(args.save_dir, name + ".ply"))
    return 0


if __name__ == "__main__":
    raise SystemExit(_main())
