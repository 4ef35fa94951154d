"""Recall and precision of a symmetry detector against the planted ground truth of a scene,
and a thin runner that calls the filter and collects everything it outputs.

recall    = fraction of the planted (required) symmetries for which some reported transform
            R is within RECALL_TOL * bbox diagonal of the planted T, measured as the largest
            displacement between R x and T x over the planted source part's vertices x.
            A symmetry relation is unordered, so R^-1 is compared too (R ~ T^-1 counts).
precision = fraction of the reported symmetries whose source-patch vertices, mapped by the
            reported transform, lie within PRECISION_TOL * diagonal of the mesh surface for
            at least PRECISION_FRACTION of the vertices.  This checks geometry, not a list,
            so correct extra symmetries (a base's own mirror plane, compositions) count as
            correct.  A transform that barely moves its patch (mean displacement below
            TRIVIAL_TOL * diagonal) is the identity in disguise and counts as wrong.
"""
from __future__ import annotations

import dataclasses
import time
from typing import Dict, List, Optional, Sequence

import numpy as np

import scenes as _scenes

RECALL_TOL = 0.005
PRECISION_TOL = 0.01
PRECISION_FRACTION = 0.8
TRIVIAL_TOL = 0.001

#: the exception text by which the unfinished pipeline announces itself
NOT_BUILT_MESSAGE = "not built yet"


def is_not_built_error(exc: BaseException) -> bool:
    return NOT_BUILT_MESSAGE in str(exc)


@dataclasses.dataclass
class DetectionResult:
    """Everything one run of compute_partial_symmetries produced."""
    raw: dict
    transforms: np.ndarray            # (n, 4, 4)
    scales: np.ndarray
    is_reflection: np.ndarray
    rms_errors: np.ndarray
    source_areas: np.ndarray
    supports: np.ndarray
    is_generator: np.ndarray
    source_patches: Dict[int, np.ndarray]   # k -> (m, 3) vertices of layer symmetry_k_source
    target_patches: Dict[int, np.ndarray]
    symmetry_id: Optional[np.ndarray]       # per input vertex
    quality: Optional[np.ndarray]           # per input vertex (signed deviation)
    seconds_wall: float

    @property
    def count(self) -> int:
        return int(len(self.transforms))

    def stage_seconds(self) -> Dict[str, float]:
        return {k[len("seconds_"):]: float(v) for k, v in self.raw.items()
                if k.startswith("seconds_")}


def _array(raw: dict, key: str, n: int, dtype=float) -> np.ndarray:
    v = raw.get(key)
    if v is None:
        return np.zeros(n, dtype)
    return np.atleast_1d(np.asarray(v, dtype=dtype)).ravel()


def _mesh_ids(ms) -> List[int]:
    ids, i = [], 0
    while len(ids) < ms.mesh_number() and i < 100000:
        if ms.mesh_id_exists(i):
            ids.append(i)
        i += 1
    return ids


def collect(ms, raw: dict, input_id: int, seconds: float = 0.0) -> DetectionResult:
    """Turn the filter's output dict and the layers it added into a DetectionResult."""
    n = int(raw.get("symmetry_count", 0))
    T = np.asarray(raw.get("transforms", np.zeros(0)), float).reshape(-1, 4, 4)[:n]
    src, dst = {}, {}
    for i in _mesh_ids(ms):
        label = ms.mesh(i).label()
        parts = label.split("_")
        if len(parts) == 3 and parts[0] == "symmetry" and parts[1].isdigit():
            k = int(parts[1])
            if parts[2] == "source":
                src[k] = ms.mesh(i).vertex_matrix().copy()
            elif parts[2] == "target":
                dst[k] = ms.mesh(i).vertex_matrix().copy()
    m = ms.mesh(input_id)
    try:
        sid = np.asarray(m.vertex_custom_scalar_attribute_array("symmetry_id")).copy()
    except Exception:  # attribute absent (e.g. nothing found)
        sid = None
    q = m.vertex_scalar_array().copy() if m.has_vertex_scalar() else None
    return DetectionResult(
        raw=dict(raw), transforms=T, scales=_array(raw, "scales", n),
        is_reflection=_array(raw, "is_reflection", n, int),
        rms_errors=_array(raw, "rms_errors", n), source_areas=_array(raw, "source_areas", n),
        supports=_array(raw, "supports", n), is_generator=_array(raw, "is_generator", n, int),
        source_patches=src, target_patches=dst, symmetry_id=sid, quality=q,
        seconds_wall=seconds)


def run_filter(scene_or_ms, **params) -> DetectionResult:
    """Run compute_partial_symmetries on a Scene (or on the current mesh of a MeshSet) and
    collect its outputs.  Raises whatever the filter raises (see is_not_built_error)."""
    import meshlab_symmetry  # noqa: F401  (binds MeshSet.compute_partial_symmetries)
    ms = scene_or_ms.meshset() if isinstance(scene_or_ms, _scenes.Scene) else scene_or_ms
    input_id = ms.current_mesh_id()
    t = time.perf_counter()
    raw = ms.compute_partial_symmetries(**params)
    seconds = time.perf_counter() - t
    ms.set_current_mesh(input_id)
    return collect(ms, raw or {}, input_id, seconds)


# ----------------------------------------------------------------------------------------
# Recall
# ----------------------------------------------------------------------------------------

def transform_distance(R: np.ndarray, T: np.ndarray, P: np.ndarray) -> float:
    """Largest displacement between R x and T x over the points P."""
    return float(np.max(np.linalg.norm(_scenes.apply(R, P) - _scenes.apply(T, P), axis=1)))


def relation_distance(R: np.ndarray, T: np.ndarray, P: np.ndarray) -> float:
    """Distance of the reported R to the planted relation T on P, either direction."""
    d = transform_distance(R, T, P)
    try:
        Ri = np.linalg.inv(R)
    except np.linalg.LinAlgError:
        return d
    return min(d, transform_distance(Ri, T, P))


def match_planted(scene, transforms: Sequence[np.ndarray], planted,
                  tol: float = RECALL_TOL):
    """(index of the best reported transform, its distance as a diagonal fraction)."""
    P = scene.vertices[planted.source_vertices]
    diag = scene.diagonal
    best, best_d = -1, np.inf
    for k, R in enumerate(transforms):
        for C in [planted.transform] + list(planted.equivalents):
            d = relation_distance(np.asarray(R, float), C, P) / diag
            if d < best_d:
                best, best_d = k, d
    return (best if best_d <= tol else -1), best_d


def recall(scene, transforms: Sequence[np.ndarray], tol: float = RECALL_TOL,
           required_only: bool = True) -> dict:
    planted = scene.required_symmetries() if required_only else scene.symmetries
    rows = []
    for s in planted:
        k, d = match_planted(scene, transforms, s, tol)
        rows.append(dict(name=s.name, matched=k, distance=d))
    found = sum(r["matched"] >= 0 for r in rows)
    return dict(recall=(found / len(rows)) if rows else None, found=found, planted=len(rows),
                rows=rows)


# ----------------------------------------------------------------------------------------
# Precision
# ----------------------------------------------------------------------------------------

def patch_on_surface(R: np.ndarray, Q: np.ndarray, V: np.ndarray, F: np.ndarray,
                     tol: float = PRECISION_TOL) -> dict:
    """How well R maps the patch vertices Q onto the surface (V, F)."""
    diag = _scenes.bbox_diagonal(V)
    if Q is None or len(Q) == 0:
        return dict(fraction=0.0, moved=0.0, ok=False, reason="empty patch")
    RQ = _scenes.apply(R, Q)
    dist = _scenes.point_to_surface_distance(RQ, V, F) / diag
    frac = float(np.mean(dist <= tol))
    moved = float(np.mean(np.linalg.norm(RQ - Q, axis=1)) / diag)
    ok = frac >= PRECISION_FRACTION and moved >= TRIVIAL_TOL
    reason = "" if ok else ("trivial (patch barely moves)" if moved < TRIVIAL_TOL
                            else f"only {frac:.0%} of the patch lands on the surface")
    return dict(fraction=frac, moved=moved, ok=ok, reason=reason)


def precision(scene, transforms: Sequence[np.ndarray],
              source_patches: Dict[int, np.ndarray], tol: float = PRECISION_TOL) -> dict:
    rows = []
    for k, R in enumerate(transforms):
        r = patch_on_surface(np.asarray(R, float), source_patches.get(k), scene.vertices,
                             scene.faces, tol)
        r["index"] = k
        rows.append(r)
    good = sum(r["ok"] for r in rows)
    return dict(precision=(good / len(rows)) if rows else None, correct=good,
                reported=len(rows), rows=rows)


def evaluate(scene, result: DetectionResult) -> dict:
    """Recall and precision of one detection result on its scene."""
    r = recall(scene, result.transforms)
    p = precision(scene, result.transforms, result.source_patches)
    return dict(recall=r, precision=p)
