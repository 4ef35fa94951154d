"""The result of :func:`meshlab_symmetry.detect`: its symmetries, per-vertex outputs, the
JSON form that round-trips exactly, and exports to the formats of pose benchmarks (BOP)
and symmetry-detection benchmarks (SHREC's planes)."""
from __future__ import annotations

import json
import os
from dataclasses import dataclass, field, fields
from typing import Any, Optional, Union

import numpy as np

from .geometry import Axis, Plane, rotation_about_line

SCHEMA = "meshlab-symmetry-result"
SCHEMA_VERSION = 1
SCHEMA_PATH = os.path.join(os.path.dirname(os.path.abspath(__file__)), "result.schema.json")

# Two BOP symmetries closer than this are one (the same turn reported twice, or two
# powers of different reports that coincide): rotation parts within about 2 degrees,
# translations within this fraction of the diagonal.
_SAME_ROTATION = 0.05
_SAME_TRANSLATION = 0.01


@dataclass(eq=False)
class Symmetry:
    """One symmetry: a transformation that maps a patch of the surface (its source) onto
    another (its target), or a continuous family of them.

    ``kind`` is one of geometry.KINDS.  Which geometric fields are set depends on it
    (the others are None):

    - reflection: ``plane``; glide reflection: ``plane`` and ``translation`` (the slide
      along the plane);
    - rotation: ``axis``, ``angle_degrees`` in [0, 180] (right-handed about
      ``axis.direction``), ``order`` k when the angle is 360/k within 0.5 degree;
      screw: the same and ``translation`` (the slide along the axis);
    - rotoreflection (a mirror composed with a turn about its normal; the plugin's log
      calls it a reflection): ``plane``, ``axis`` (through its fixed point, along the
      normal), ``angle_degrees``, ``order``;
    - translation: ``translation``; uniform scaling (scale != 1): only ``matrix`` and ``scale``;
    - rotational, translational and helical family: ``axis`` (for a translational family
      its direction is the one that matters), helical also ``pitch`` (advance per full turn
      along ``axis.direction``, in the mesh's units); planar patch: ``plane``; spherical
      patch: ``center``.  ``matrix`` is then one member of the family.

    Lengths and points are in the mesh's units; the errors and ``source_area`` are fractions
    (of the bounding-box diagonal and of the surface area), as the filter returns them.
    ``source_vertices`` and ``target_vertices`` index the input mesh's vertices.
    ``word`` writes a discrete symmetry in the generators of the reduced basis: +k stands
    for generator k-1 (the symmetry ``result.graph["generators"][k - 1]``), -k for its
    inverse; empty for a family.
    """
    index: int
    kind: str
    matrix: np.ndarray
    scale: float
    is_reflection: bool
    source_vertices: np.ndarray
    target_vertices: np.ndarray
    rms_error: float
    max_error: float
    systematic_error: float
    source_area: float
    support: int
    is_generator: bool
    word: tuple[int, ...]
    plane: Optional[Plane] = None
    axis: Optional[Axis] = None
    center: Optional[np.ndarray] = None
    angle_degrees: Optional[float] = None
    order: Optional[int] = None
    translation: Optional[np.ndarray] = None
    pitch: Optional[float] = None

    def to_dict(self) -> dict[str, Any]:
        """Plain lists, numbers and dicts (what to_json writes)."""
        return {f.name: _plain(getattr(self, f.name)) for f in fields(self)}

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> "Symmetry":
        return cls(**{
            **d,
            "matrix": _floats(d["matrix"]),
            "source_vertices": _ints(d["source_vertices"]),
            "target_vertices": _ints(d["target_vertices"]),
            "word": tuple(d["word"]),
            "plane": None if d["plane"] is None else Plane(
                _floats(d["plane"]["normal"]), d["plane"]["offset"], _floats(d["plane"]["point"])),
            "axis": None if d["axis"] is None else Axis(_floats(d["axis"]["point"]), _floats(d["axis"]["direction"])),
            "center": None if d["center"] is None else _floats(d["center"]),
            "translation": None if d["translation"] is None else _floats(d["translation"]),
        })


@dataclass(eq=False)
class SymmetryResult:
    """What :func:`meshlab_symmetry.detect` found in a mesh.

    - ``symmetries``: list of Symmetry, most significant (largest source patch) first;
    - ``deviation``: per input vertex (float64), the signed deviation of its image from the
      surface under the most significant symmetry it belongs to, as a fraction of the
      diagonal (the filter's vertex quality); 0 where none holds;
    - ``symmetry_id``: per input vertex (int64), that symmetry's index, -1 where none holds;
    - ``graph``: the symmetry graph (see meshlab_symmetry.symmetry_graph); its layer ids
      refer to the private MeshSet detect ran in;
    - ``timings``: seconds of each stage (the filter's seconds_* values);
    - ``work``: every other number the filter returns: samples, pruned_samples, pairs,
      clusters, verified_clusters, generator_count, working_vertices, point_cloud,
      normals_estimated, welded_vertices, repeated_faces, back_faces, flipped_faces, noise, smoothing_radius,
      curvature_radius_used, pair_sample_count_used;
    - ``parameters``: every parameter of detect as it was run (defaults included, lengths
      as fractions of the diagonal, min_patch_area as a fraction of the area);
    - ``vertex_count`` and ``diagonal`` (of the bounding box, in the mesh's units) of the input;
    - ``transformation_space``: the detector's Γ when the core engine ran (not in the JSON).
    """
    symmetries: list[Symmetry]
    deviation: np.ndarray
    symmetry_id: np.ndarray
    graph: dict[str, Any]
    timings: dict[str, float]
    work: dict[str, Union[int, float]]
    parameters: dict[str, Union[int, float, bool]]
    vertex_count: int
    diagonal: float
    #: the detector's own transformation space Γ (see pictures.detector_transformation_space),
    #: kept by detect(..., engine="core"); None otherwise.  Not part of the JSON (it is large
    #: and the same run gives it again).
    transformation_space: Optional[dict[str, Any]] = field(default=None, compare=False, repr=False)

    def to_json(self, indent: Optional[int] = None) -> str:
        """The result as JSON (schema ``result.schema.json``, "schema":
        "meshlab-symmetry-result", "schema_version": 1).  Floats are written as Python's
        repr, so from_json gives back the very same numbers."""
        document = {"schema": SCHEMA, "schema_version": SCHEMA_VERSION}
        document.update({f.name: _plain(getattr(self, f.name)) for f in fields(self) if f.name != "transformation_space"})
        return json.dumps(document, indent=indent, allow_nan=False)

    @classmethod
    def from_json(cls, text: str) -> "SymmetryResult":
        """The result to_json wrote.  Raises ValueError for another document or another
        schema version."""
        d = json.loads(text)
        if not isinstance(d, dict) or d.get("schema") != SCHEMA:
            raise ValueError(f"not a {SCHEMA} document")
        if d.get("schema_version") != SCHEMA_VERSION:
            raise ValueError(f"schema_version {d.get('schema_version')!r} is not the one this package reads "
                             f"({SCHEMA_VERSION})")
        return cls(
            symmetries=[Symmetry.from_dict(s) for s in d["symmetries"]],
            deviation=_floats(d["deviation"]),
            symmetry_id=_ints(d["symmetry_id"]),
            graph=d["graph"], timings=d["timings"], work=d["work"], parameters=d["parameters"],
            vertex_count=d["vertex_count"], diagonal=d["diagonal"])

    def to_bop_models_info(self, model_id: int = 1, min_area: float = 0.95) -> dict[str, dict[str, list]]:
        """The symmetry fields of the BOP toolkit's models_info.json for this object:
        ``{"<model_id>": {"symmetries_discrete": [[16 numbers], ...],
        "symmetries_continuous": [{"axis": [x, y, z], "offset": [x, y, z]}, ...]}}``,
        to merge into the entry of that object (BOP also wants its diameter and extent there).

        BOP's symmetries are poses that leave the whole object looking the same, so only
        proper rigid motions qualify: rotations (no reflection, rotoreflection, screw,
        translation or scaling) whose source patch covers at least ``min_area`` of the
        surface, and rotational families covering as much.  A discrete one is a row-major
        4x4 matrix, translation in the mesh's units; BOP adds the identity itself and does
        not compose the ones it is given, so a k-fold rotation contributes all k-1 turns
        about its axis, by 360 j / k degrees exactly (a rotation without an order, its
        matrix as detected), each listed once.  A continuous one is the axis direction and
        a point on it ("offset", the one nearest the bounding-box centre).  A spherical
        patch (every rotation about a point) has no BOP form and is left out.
        """
        discrete: list[np.ndarray] = []
        for s in self.symmetries:
            if s.kind == "rotation" and s.source_area >= min_area:
                for motion in _turns(s):
                    if not any(self._same_motion(motion, kept) for kept in discrete):
                        discrete.append(motion)
        continuous = [{"axis": s.axis.direction.tolist(), "offset": s.axis.point.tolist()}
                      for s in self.symmetries if s.kind == "rotational family" and s.source_area >= min_area]
        return {str(model_id): {"symmetries_discrete": [m.reshape(-1).tolist() for m in discrete],
                                "symmetries_continuous": continuous}}

    def to_shrec_planes(self, min_area: float = 0.9) -> str:
        """The global mirror planes, one line ``nx ny nz px py pz`` each (unit normal, then
        the plane's point nearest the bounding-box centre, in the mesh's units): the
        reflections (not glide reflections or rotoreflections) whose source patch covers at
        least ``min_area`` of the surface.  Numbers are written exactly (Python's repr)."""
        lines = [" ".join(repr(float(x)) for x in (*s.plane.normal, *s.plane.point))
                 for s in self.symmetries if s.kind == "reflection" and s.source_area >= min_area]
        return "".join(line + "\n" for line in lines)

    def _same_motion(self, a: np.ndarray, b: np.ndarray) -> bool:
        return (np.linalg.norm(a[:3, :3] - b[:3, :3]) < _SAME_ROTATION
                and np.linalg.norm(a[:3, 3] - b[:3, 3]) < _SAME_TRANSLATION * self.diagonal)


def _turns(s: Symmetry) -> list[np.ndarray]:
    """The non-identity turns a rotation generates, for BOP (see to_bop_models_info)."""
    if s.order is None:
        return [s.matrix]
    return [rotation_about_line(s.axis.point, s.axis.direction, 360.0 * j / s.order) for j in range(1, s.order)]


def _plain(value: Any) -> Any:
    """JSON-ready form: arrays as (nested) lists, Plane and Axis as dicts, tuples as lists."""
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, (Plane, Axis)):
        return {f.name: _plain(getattr(value, f.name)) for f in fields(value)}
    if isinstance(value, tuple):
        return list(value)
    if isinstance(value, list):
        return [_plain(v) for v in value]
    if isinstance(value, Symmetry):
        return value.to_dict()
    return value


def _floats(values: Any) -> np.ndarray:
    return np.asarray(values, dtype=np.float64)


def _ints(values: Any) -> np.ndarray:
    return np.asarray(values, dtype=np.int64)
