"""CAD-like models built the way shape collections and CAD exports store them.

Everyday objects (chairs, tables, lamps, cars, airplanes, vessels) assembled from parts, each
part a separate connected component, tessellated as a CAD exporter does it: a box as twelve
triangles, a cylinder as a prism of few sides whose caps are fans of long thin triangles from
one rim vertex, a flat panel as two triangles, a revolved or lofted body as quads split in two.
Parts overlap or sit inside others (a seat's frame inside its cushion, an engine inside a car's
body), and every triangle is stored twice, once each way round, on the same vertices (the
double-sided surfaces of shape collections).

Every model is mirror-symmetric by construction about the planes in `CadModel.planes`, as a
unit normal n and offset d (n . x = d): each part is either centred on those planes or placed
with its mirror image.  The models are then turned and moved as a whole by a random rigid
motion, with their planes.  numpy only; the detector never sees the planes.

    import cad_models
    m = cad_models.make_model("chair", seed=3)
    m.vertices, m.faces, m.planes
"""
from __future__ import annotations

import dataclasses
import math
from typing import Callable, Dict, List, Sequence, Tuple

import numpy as np

Mesh = Tuple[np.ndarray, np.ndarray]

#: Bump when a change alters any generated model.
GENERATOR_VERSION = 1


@dataclasses.dataclass
class CadModel:
    name: str
    category: str
    seed: int
    vertices: np.ndarray
    faces: np.ndarray
    #: the global mirror planes, each (unit normal, offset): n . x = offset
    planes: List[Tuple[np.ndarray, float]]
    parts: int

    @property
    def diagonal(self) -> float:
        return float(np.linalg.norm(self.vertices.max(0) - self.vertices.min(0)))


# -- parts, tessellated as CAD exports are ------------------------------------------------

def _quad(a: int, b: int, c: int, d: int, alt: bool) -> List[List[int]]:
    """The quad a b c d (counter-clockwise) as two triangles, split along a c, or along b d
    when `alt`: the same planar face tessellated the other way."""
    return [[b, c, d], [b, d, a]] if alt else [[a, b, c], [a, c, d]]


def box(size, center, alt: bool = False) -> Mesh:
    """An axis-aligned box of 8 vertices and 12 triangles (an elongated face is two slivers)."""
    h = np.asarray(size, float) / 2
    V = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], float) * h
    F = []
    for q in ((0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)):
        F += _quad(*q, alt)
    return V + np.asarray(center, float), np.asarray(F)


def _fan(ring: Sequence[int], reverse: bool, alt: bool = False) -> List[List[int]]:
    """A polygon's cap as a fan from its first vertex (from the middle one when `alt`): long
    thin triangles, as CAD exports triangulate planar faces."""
    ring = list(ring)
    if alt:
        ring = ring[len(ring) // 2:] + ring[:len(ring) // 2]
    tris = [[ring[0], ring[k], ring[k + 1]] for k in range(1, len(ring) - 1)]
    return [t[::-1] for t in tris] if reverse else tris


def prism(polygon: np.ndarray, z0: float, z1: float, alt: bool = False) -> Mesh:
    """A convex polygon (counter-clockwise, in x y) extruded from z0 to z1, its caps fans."""
    return frustum_of(np.asarray(polygon, float), np.asarray(polygon, float), z0, z1, alt)


def frustum_of(bottom: np.ndarray, top: np.ndarray, z0: float, z1: float, alt: bool = False) -> Mesh:
    """The body between a convex polygon at height z0 and a scaled copy at z1 (each
    counter-clockwise in x y): planar sides, caps that are fans."""
    n = len(bottom)
    V = np.concatenate([np.c_[bottom, np.full(n, z0)], np.c_[top, np.full(n, z1)]])
    F = _fan(list(range(n)), True, alt) + _fan(list(range(n, 2 * n)), False, alt)
    for k in range(n):
        a, b = k, (k + 1) % n
        F += _quad(a, b, n + b, n + a, alt)
    return V, np.asarray(F)


def cylinder(radius: float, height: float, sides: int, center, axis: int = 2,
             phase: float = 0.5, alt: bool = False) -> Mesh:
    """A prism of `sides` sides about the given coordinate axis (0, 1, 2), centred at `center`.
    With an even number of sides it is mirror-symmetric across the coordinate planes
    through its axis."""
    t = 2 * np.pi * (np.arange(sides) + phase) / sides
    V, F = prism(radius * np.c_[np.cos(t), np.sin(t)], -height / 2, height / 2, alt)
    return _along(V, axis) + np.asarray(center, float), F


def frustum(r0: float, r1: float, height: float, sides: int, center, axis: int = 2,
            alt: bool = False) -> Mesh:
    """A truncated cone (radius r0 at the bottom, r1 at the top), as `cylinder`."""
    t = 2 * np.pi * (np.arange(sides) + 0.5) / sides
    ring = np.c_[np.cos(t), np.sin(t)]
    V, F = frustum_of(r0 * ring, r1 * ring, -height / 2, height / 2, alt)
    return _along(V, axis) + np.asarray(center, float), F


def _along(V: np.ndarray, axis: int) -> np.ndarray:
    """Coordinates with z turned onto `axis` (a cyclic permutation keeps orientation)."""
    return np.roll(V, axis - 2, axis=1) if axis != 2 else V


def loft(sections: Sequence[np.ndarray], alt: bool = False) -> Mesh:
    """A closed body through closed cross-sections (each k points, counter-clockwise seen
    from the next), quads split in two, the end sections capped by fans.  The quads are not
    planar, so `alt` changes the caps' fans only: the surface stays the same."""
    k = len(sections[0])
    V = np.concatenate(sections)
    F = _fan(list(range(k)), True, alt) + _fan(list(range((len(sections) - 1) * k, len(sections) * k)), False, alt)
    for s in range(len(sections) - 1):
        for j in range(k):
            a, b = s * k + j, s * k + (j + 1) % k
            F += [[a, b, b + k], [a, b + k, a + k]]
    return V, np.asarray(F)


def mirrored_x(V: np.ndarray, F: np.ndarray) -> Mesh:
    """A part's mirror image across x = 0, its faces turned to stay outward."""
    return V * np.array([-1.0, 1, 1]), F[:, ::-1]


# -- the objects, each mirror-symmetric about x = 0 ------------------------------------------

class _Parts:
    def __init__(self, alt: bool):
        self.alt = alt  # tessellate every part the other way (see _quad, _fan)
        self.meshes: List[Mesh] = []

    def add(self, mesh: Mesh) -> None:
        self.meshes.append((np.asarray(mesh[0], float), np.asarray(mesh[1], np.int64)))

    def pair(self, mesh: Mesh) -> None:
        """A part and its mirror image across x = 0."""
        self.add(mesh)
        self.add(mirrored_x(*mesh))

    def mesh(self) -> Mesh:
        Vs, Fs, n = [], [], 0
        for V, F in self.meshes:
            Vs.append(V)
            Fs.append(F + n)
            n += len(V)
        return np.concatenate(Vs), np.concatenate(Fs)


def _even(rng: np.random.Generator, low: int, high: int) -> int:
    """An even count in [low, high]: a prism centred on a mirror plane must have one."""
    return 2 * int(rng.integers(low // 2, high // 2 + 1))


X = np.array([1.0, 0, 0])
Y = np.array([0, 1.0, 0])


def chair(rng: np.random.Generator, alt: bool) -> Tuple[_Parts, list]:
    p = _Parts(alt)
    w, d, h = rng.uniform(0.40, 0.55), rng.uniform(0.38, 0.5), rng.uniform(0.40, 0.48)
    t = rng.uniform(0.03, 0.06)
    p.add(box((w, d, t), (0, 0, h), alt=p.alt))                                    # seat
    p.add(box((w - 0.04, d - 0.04, t / 2), (0, 0, h - t / 4), alt=p.alt))          # its frame, inside
    leg = rng.uniform(0.025, 0.045)
    round_legs = rng.random() < 0.5
    for y in (-1, 1):
        c = (w / 2 - leg, y * (d / 2 - leg), h / 2)
        p.pair(cylinder(leg / 2, h, int(rng.integers(8, 13)), c, alt=p.alt) if round_legs else box((leg, leg, h), c, alt=p.alt))
    back = rng.uniform(0.35, 0.5)
    for_posts = (w / 2 - leg, d / 2 - leg, h + back / 2)
    p.pair(box((leg, leg, back), for_posts, alt=p.alt))                             # back posts
    slats = int(rng.integers(2, 5))
    for k in range(slats):
        z = h + back * (k + 1) / (slats + 1)
        p.add(box((w - 2 * leg, leg / 2, rng.uniform(0.03, 0.06)), (0, d / 2 - leg, z), alt=p.alt))
    if rng.random() < 0.5:                                               # arm rests
        p.pair(box((leg, d * 0.8, leg), (w / 2 - leg / 2, 0, h + 0.22), alt=p.alt))
        p.pair(box((leg, leg, 0.22), (w / 2 - leg / 2, -d / 2 + 0.06, h + 0.11), alt=p.alt))
    return p, [X]


def table(rng: np.random.Generator, alt: bool) -> Tuple[_Parts, list]:
    p = _Parts(alt)
    w, d, h = rng.uniform(0.9, 1.6), rng.uniform(0.6, 0.85), rng.uniform(0.7, 0.78)
    t = rng.uniform(0.025, 0.05)
    p.add(box((w, d, t), (0, 0, h), alt=p.alt))                                    # top
    leg = rng.uniform(0.04, 0.07)
    for y in (-1, 1):
        c = (w / 2 - 2 * leg, y * (d / 2 - 2 * leg), h / 2)
        p.pair(box((leg, leg, h - t), c, alt=p.alt))
        p.add(box((w - 4 * leg, leg / 2, 0.08), (0, y * (d / 2 - 2 * leg), h - t / 2 - 0.04), alt=p.alt))  # aprons
    p.pair(box((leg / 2, d - 4 * leg, 0.08), (w / 2 - 2 * leg, 0, h - t / 2 - 0.04), alt=p.alt))
    planes = [X, Y]
    if rng.random() < 0.5:                                               # a drawer on one side
        p.add(box((0.4, 0.3, 0.07), (0, -d / 2 + 0.2, h - 0.09), alt=p.alt))
        planes = [X]
    return p, planes


def lamp(rng: np.random.Generator, alt: bool) -> Tuple[_Parts, list]:
    p = _Parts(alt)
    r = rng.uniform(0.1, 0.16)
    p.add(cylinder(r, 0.03, _even(rng, 16, 32), (0, 0, 0.015), alt=p.alt))  # base
    pole = rng.uniform(0.35, 0.55)
    p.add(cylinder(0.012, pole, 8, (0, 0, pole / 2 + 0.03), alt=p.alt))
    arm = rng.uniform(0.15, 0.3)
    p.add(box((0.02, arm, 0.02), (0, arm / 2, pole + 0.03), alt=p.alt))             # reaches out along y
    p.add(frustum(rng.uniform(0.08, 0.12), 0.03, 0.12, _even(rng, 12, 24),
                  (0, arm, pole - 0.04), alt=p.alt))                                # shade
    p.add(box((0.05, 0.03, 0.04), (0, 0, 0.05), alt=p.alt))                         # switch on the base
    return p, [X]


def car(rng: np.random.Generator, alt: bool) -> Tuple[_Parts, list]:
    p = _Parts(alt)
    L, W, H = rng.uniform(3.8, 4.8), rng.uniform(1.6, 1.9), rng.uniform(0.5, 0.7)
    side = np.array([[-L / 2, 0.3], [L / 2, 0.3], [L / 2, 0.3 + H * 0.8], [L / 2 - 0.3, 0.3 + H],
                     [-L / 2 + 0.2, 0.3 + H], [-L / 2, 0.3 + H * 0.7]])
    V, F = prism(side, -W / 2, W / 2, alt=p.alt)                                    # body: its side extruded
    p.add((V[:, [2, 0, 1]], F))
    cab = np.array([[-L * 0.25, 0.3 + H], [L * 0.15, 0.3 + H], [L * 0.05, 0.3 + H + 0.45],
                    [-L * 0.2, 0.3 + H + 0.45]])
    V, F = prism(cab, -W / 2 + 0.1, W / 2 - 0.1, alt=p.alt)                         # cabin
    p.add((V[:, [2, 0, 1]], F))
    p.add(box((0.8, 0.7, 0.5), (0, L / 2 - 0.6, 0.6), alt=p.alt))                   # engine, inside the body
    wheel = rng.uniform(0.3, 0.36)
    for y in (-L / 2 + 0.75, L / 2 - 0.8):
        p.pair(cylinder(wheel, 0.22, int(rng.integers(12, 21)), (W / 2 - 0.1, y, wheel), axis=0, alt=p.alt))
    p.pair(box((0.25, 0.05, 0.1), (W / 2 - 0.3, L / 2, 0.3 + H * 0.6), alt=p.alt))  # headlights
    return p, [X]


def airplane(rng: np.random.Generator, alt: bool) -> Tuple[_Parts, list]:
    p = _Parts(alt)
    L, R = rng.uniform(10, 14), rng.uniform(0.5, 0.8)
    k = _even(rng, 10, 16)
    t = 2 * np.pi * (np.arange(k) + 0.5) / k
    ring = np.c_[np.cos(t), np.zeros(k), np.sin(t)]
    stations = [(-L / 2, 0.2), (-L / 2 + 1.5, 0.8), (-L / 4, 1), (L / 4, 1), (L / 2 - 1.2, 0.6), (L / 2, 0.15)]
    p.add(loft([ring * [R * s, 0, R * s] + [0, y, 0] for y, s in stations], alt=p.alt))  # fuselage
    span, chord = rng.uniform(5, 7), rng.uniform(1.4, 2.0)
    airfoil = np.array([[0, 0], [chord * 0.3, 0.12], [chord, 0.02], [chord, -0.02], [chord * 0.3, -0.06]])
    V, F = prism(airfoil[::-1] * [1, 1], 0.3, span, alt=p.alt)                      # a wing along x
    wing = (np.c_[V[:, 2], -V[:, 0] + chord / 2, V[:, 1]], F[:, ::-1])
    p.pair(wing)
    V, F = prism(airfoil[::-1] * [0.5, 0.5], 0.2, span / 3, alt=p.alt)               # a tailplane
    p.pair((np.c_[V[:, 2], -V[:, 0] - L / 2 + 1.2, V[:, 1] + 0.2], F[:, ::-1]))
    fin = np.array([[0, 0], [1.5, 0], [0.9, 1.8], [0.4, 1.8]])
    V, F = prism(fin, -0.06, 0.06, alt=p.alt)                                       # the fin, on the plane
    p.add((np.c_[V[:, 2], V[:, 0] - L / 2 + 0.3, V[:, 1] + R * 0.5], F))
    p.pair(cylinder(0.35, 2.0, int(rng.integers(10, 17)), (span * 0.4, 0.3, -0.5), axis=1, alt=p.alt))  # engines
    return p, [X]


def vessel(rng: np.random.Generator, alt: bool) -> Tuple[_Parts, list]:
    p = _Parts(alt)
    L, B, D = rng.uniform(6, 10), rng.uniform(2, 3), rng.uniform(1, 1.5)

    def section(y: float, s: float) -> np.ndarray:
        """The hull's cross-section at y: a deck line and a rounded keel."""
        half = B / 2 * s
        pts = [[-half, y, D], [-half * 0.9, y, D * 0.3], [-half * 0.5, y, 0.05], [0, y, 0],
               [half * 0.5, y, 0.05], [half * 0.9, y, D * 0.3], [half, y, D]]
        return np.asarray(pts[::-1], float)

    stations = [(-L / 2, 0.75), (-L / 4, 0.95), (0, 1), (L / 4, 0.85), (L / 2 - 0.8, 0.45), (L / 2, 0.08)]
    p.add(loft([section(y, s) for y, s in stations], alt=p.alt))                   # hull
    p.add(box((B * 0.5, L * 0.3, 1.0), (0, -L * 0.1, D + 0.5), alt=p.alt))          # cabin
    p.add(cylinder(0.06, 4.0, 8, (0, L * 0.1, D + 2.0), alt=p.alt))                 # mast
    p.pair(box((0.1, L * 0.6, 0.4), (B / 2 - 0.05, 0, D + 0.2), alt=p.alt))         # railings
    return p, [X]


CATEGORIES: Dict[str, Callable[[np.random.Generator, bool], Tuple[_Parts, list]]] = dict(
    chair=chair, table=table, lamp=lamp, car=car, airplane=airplane, vessel=vessel)


def double_sided(F: np.ndarray) -> np.ndarray:
    """Every triangle once more the other way round, on the same vertices."""
    return np.concatenate([F, F[:, ::-1]])


def random_rotation(rng: np.random.Generator) -> np.ndarray:
    Q, R = np.linalg.qr(rng.normal(size=(3, 3)))
    Q = Q * np.sign(np.diag(R))
    return Q if np.linalg.det(Q) > 0 else -Q


def make_model(category: str, seed: int = 0, posed: bool = True, alt: bool = False) -> CadModel:
    """A model of the category, double-sided, turned and moved at random when `posed`;
    with `alt` the same surface tessellated otherwise (quads split along their other
    diagonal, fans from another vertex)."""
    rng = np.random.default_rng([seed, GENERATOR_VERSION, list(CATEGORIES).index(category)])
    parts, normals = CATEGORIES[category](rng, alt)
    V, F = parts.mesh()
    R, t = (random_rotation(rng), rng.normal(size=3)) if posed else (np.eye(3), np.zeros(3))
    V = V @ R.T + t
    planes = []
    for n in normals:
        m = R @ n
        planes.append((m, float(m @ t)))
    return CadModel(f"{category}_{seed}", category, seed, V, double_sided(F), planes, len(parts.meshes))


def models(per_category: int, first_seed: int = 0) -> List[CadModel]:
    return [make_model(c, s) for c in CATEGORIES for s in range(first_seed, first_seed + per_category)]
