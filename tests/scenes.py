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


def sample_surface(V: np.ndarray, F: np.ndarray, n: int, rng: np.random.Generator) -> np.ndarray:
    """n points uniformly distributed (by area) over the surface."""
    a = face_areas(V, F)
    f = rng.choice(len(F), size=n, p=a / a.sum())
    r1 = np.sqrt(rng.random(n))
    r2 = rng.random(n)
    w = np.stack([1 - r1, r1 * (1 - r2), r1 * r2], axis=1)
    return (V[F[f]] * w[:, :, None]).sum(1)


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
    # weld the duplicated edge vertices
    key = np.round(V * 1e9).astype(np.int64)
    _, first, inv = np.unique(key, axis=0, return_index=True, return_inverse=True)
    V = V[first]
    F = inv.ravel()[F]
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
    return V2, F2


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

    def as_dict(self) -> dict:
        d = dataclasses.asdict(self)
        d["transform"] = self.transform.tolist()
        d.pop("source_vertices")
        d.pop("target_vertices")
        d["equivalents"] = [e.tolist() for e in self.equivalents]
        return d


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

    def transformed(self, G: np.ndarray) -> "Scene":
        """The same scene moved as a whole by the rigid or similarity transform G: vertices
        G x, planted transforms G T G^-1."""
        Gi = np.linalg.inv(G)
        V, F = transform_mesh(G, self.vertices, self.faces)
        syms = [dataclasses.replace(s, transform=G @ s.transform @ Gi,
                                    equivalents=[G @ e @ Gi for e in s.equivalents])
                for s in self.symmetries]
        copies = {k: (src, G @ T @ Gi, tol) for k, (src, T, tol) in self.copies.items()}
        return dataclasses.replace(self, vertices=V, faces=F, symmetries=syms, copies=copies,
                                   name=self.name + "_moved")

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
                         f"{'required' if s.required else 'optional'}")
        return "\n".join(lines)


class _Builder:
    """Collects parts, then assembles one mesh with planted symmetries."""

    def __init__(self):
        self.parts: List[Tuple[str, np.ndarray, np.ndarray]] = []
        self.syms: List[dict] = []
        self.copies: Dict[str, Tuple[str, np.ndarray, float]] = {}

    def add(self, name: str, V: np.ndarray, F: np.ndarray) -> None:
        self.parts.append((name, np.asarray(V, float), np.asarray(F, np.int64)))

    def plant(self, name: str, T: np.ndarray, source: str, target: str, **kw) -> None:
        self.syms.append(dict(name=name, transform=np.asarray(T, float), source_part=source,
                              target_part=target, **kw))

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
        syms = []
        for d in self.syms:
            s0 = ranges[d["source_part"]]
            t0 = ranges[d["target_part"]]
            area = face_areas(V, F[s0[2]:s0[3]]).sum() / total
            T = d["transform"]
            syms.append(PlantedSymmetry(
                source_vertices=np.arange(s0[0], s0[1]), target_vertices=np.arange(t0[0], t0[1]),
                source_area_fraction=float(area), reflection=is_reflection(T),
                scale=transform_scale(T), **d))
        return Scene(name=name, description=description, seed=seed, vertices=V, faces=F,
                     parts=ranges, symmetries=syms, copies=dict(self.copies), **kw)


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
                   notes=f"{base} has no exact self-symmetry")


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
                         "between the copies are correct extras")


# -- (e) row of translated copies ----------------------------------------------------------

def scene_row(seed: int = 0, copies: int = 4) -> Scene:
    rng = np.random.default_rng([seed, 5])
    # an elongated bumpy superquadric: asymmetric, so the only relations between the copies
    # are the translations (the bundled bone is itself nearly symmetric under reflections)
    shape = StarShape(axes=(1.0, 0.45, 0.35), exponent=2.4, amplitude=0.2,
                      field=RadialField(rng, 8, 0.6))
    R = random_rotation(rng, 20, 60)  # the row is not along a principal axis of the part
    V, F = transform_mesh(R, *shape.mesh(20))
    extent = V.max(0) - V.min(0)
    step = np.array([0.0, extent[1] * 1.25, 0.0])
    b = _Builder()
    b.add("copy0", V, F)
    for k in range(1, copies):
        Q = random_rotation(rng, 5, 30)[:3, :3]
        V2, F2 = transform_mesh(R, *shape.mesh([21, 19, 22][(k - 1) % 3], Q))
        b.add(f"copy{k}", V2 + k * step, F2)
        b.copy_of(f"copy{k}", "copy0", translation(k * step), 0.004)
    for p in range(1, copies):
        b.plant(f"translation^{p}", translation(p * step), "copy0", f"copy{p}",
                required=(p == 1), family="row", power=p)
    for k in range(1, copies - 1):
        b.plant(f"translation_{k}{k + 1}", translation(step), f"copy{k}", f"copy{k + 1}",
                required=False, family="row", power=1)
    return b.build("row", f"row of {copies} equally spaced translated copies of a bumpy "
                   "superquadric", seed, expected_generators={"row": 1})


# -- (f) small repeated part ---------------------------------------------------------------

def scene_small_part(seed: int = 0, base: str = "bunny", n_faces: int = 30000,
                     fraction: float = 0.02) -> Scene:
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
    return b.build("small_part", f"a small bumpy superquadric (~{fraction:.0%} of the area) "
                   f"repeated twice beside a large {base}", seed)


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
    return b.build("cad_fandisk", "CGAL fandisk, a mirrored copy and a rotated copy", seed)


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


def cad_meshes_available(cgal_dir: Optional[str] = None) -> bool:
    d = cgal_dir or os.environ.get("SYMMETRY_CGAL_DIR") or DEFAULT_CGAL_DIR
    return all(os.path.exists(os.path.join(d, n + ".off")) for n in CAD_BASES)


def make_scene(name: str, seed: int = 0, **kw) -> Scene:
    """Build the named scene (deterministic in `seed`)."""
    if name in SCENES:
        return SCENES[name](seed, **kw)
    if name in CAD_SCENES:
        return CAD_SCENES[name](seed, **kw)
    raise KeyError(f"unknown scene {name!r}; known: {SCENE_NAMES + CAD_SCENE_NAMES}")


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
    ap.add_argument("--save-dir", help="write every scene as DIR/NAME.ply")
    ap.add_argument("--demo", metavar="PATH", help="write the demo mesh to PATH and stop")
    args = ap.parse_args(argv)
    if args.demo:
        make_scene(*DEMO_SCENE).save(args.demo)
        print(f"wrote {args.demo}")
        return 0
    for name in SCENE_NAMES + (CAD_SCENE_NAMES if args.cad else ()):
        t = time.perf_counter()
        s = make_scene(name, args.seed)
        print(s.summary(), f"  [{time.perf_counter() - t:.1f} s]")
        if args.save_dir:
            os.makedirs(args.save_dir, exist_ok=True)
            s.save(os.path.join(args.save_dir, name + ".ply"))
    return 0


if __name__ == "__main__":
    raise SystemExit(_main())
