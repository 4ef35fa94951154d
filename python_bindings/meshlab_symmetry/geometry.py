"""What a symmetry is, in words and in geometry, from the numbers the filter returns.

The filter reports each symmetry as a 4x4 matrix (plus its scale and whether it mirrors),
or for a continuous family as its kind and axis.  A user wants the plane of a mirror, the
axis and angle of a rotation, the slide of a glide reflection or a screw.  They are read off
the matrix here with the thresholds of the plugin's own log (``kindLabel`` in
``plugin/filter_symmetry/filter_symmetry.cpp``), so that the words agree with the log.

Every point given (on a plane or an axis) is the one nearest the centre of the mesh's
bounding box: a plane or a line has no point of its own, and that one is the same whatever
the numerics of the solve that found the plane.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Optional

import numpy as np

#: the filter's continuous_kinds 1..5, in words (0 is a discrete symmetry)
FAMILY_KINDS = {1: "rotational family", 2: "translational family", 3: "helical family",
                4: "planar patch", 5: "spherical patch"}
#: every kind a Symmetry may have
KINDS = ("reflection", "glide reflection", "rotoreflection", "rotation", "screw", "translation",
         "uniform scaling", *FAMILY_KINDS.values())

# The plugin's kindLabel thresholds.
SCALE_TOLERANCE = 1e-6       # |scale - 1| above this: a similarity
IDENTITY_TOLERANCE = 1e-6    # Frobenius distance of the linear part from I: a translation
MIRROR_TOLERANCE = 1e-3      # Frobenius norm of L L - I: a pure mirror (else a rotoreflection)
SLIDE_FLOOR = 1e-3           # a slide shorter than this fraction of the diagonal is none
#: a rotation by 360/k degrees within this many degrees is k-fold
ORDER_TOLERANCE_DEGREES = 0.5


@dataclass(eq=False)
class Plane:
    """The plane n.x = offset: unit ``normal`` n, ``offset`` and the ``point`` of the plane
    nearest the centre of the mesh's bounding box (all in the mesh's units)."""
    normal: np.ndarray
    offset: float
    point: np.ndarray


@dataclass(eq=False)
class Axis:
    """A line: its ``point`` nearest the centre of the mesh's bounding box and its unit
    ``direction``."""
    point: np.ndarray
    direction: np.ndarray


def canonical_sign(v: np.ndarray) -> np.ndarray:
    """v or -v, whichever has its largest component positive: a normal or an axis has no
    sign of its own, and a fixed choice makes two runs comparable."""
    return v if v[np.argmax(np.abs(v))] >= 0 else -v


def point_nearest_on_line(point: np.ndarray, direction: np.ndarray, centre: np.ndarray) -> np.ndarray:
    return point + direction * float(direction @ (centre - point))


def rotation_matrix(direction: np.ndarray, degrees: float) -> np.ndarray:
    """The 3x3 rotation by ``degrees`` about the unit ``direction`` (right-handed)."""
    a = math.radians(degrees)
    x, y, z = direction
    k = np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])
    return np.eye(3) + math.sin(a) * k + (1 - math.cos(a)) * (k @ k)


def rotation_about_line(point: np.ndarray, direction: np.ndarray, degrees: float) -> np.ndarray:
    """The 4x4 rigid motion turning space by ``degrees`` about the line through ``point``."""
    m = np.eye(4)
    m[:3, :3] = rotation_matrix(direction, degrees)
    m[:3, 3] = point - m[:3, :3] @ point
    return m


def angle_and_axis(rotation: np.ndarray) -> tuple[float, np.ndarray]:
    """(degrees in [0, 180], unit axis) of a 3x3 rotation, the axis oriented so that the
    turn is right-handed.  Near 0 and 180 degrees the antisymmetric part vanishes, so the
    axis is then the symmetric part's eigenvector of eigenvalue 1."""
    cosine = np.clip((np.trace(rotation) - 1) / 2, -1.0, 1.0)
    degrees = math.degrees(math.acos(cosine))
    w = np.array([rotation[2, 1] - rotation[1, 2], rotation[0, 2] - rotation[2, 0],
                  rotation[1, 0] - rotation[0, 1]])  # 2 sin(angle) axis
    if np.linalg.norm(w) > 0.1:
        return degrees, w / np.linalg.norm(w)
    axis = np.linalg.eigh(0.5 * (rotation + rotation.T))[1][:, -1]
    if abs(axis @ w) > 1e-12:
        return degrees, axis if axis @ w > 0 else -axis
    return degrees, canonical_sign(axis)


def order_of(degrees: float) -> Optional[int]:
    """k when ``degrees`` is 360/k (k >= 2) within ORDER_TOLERANCE_DEGREES, else None."""
    if degrees <= ORDER_TOLERANCE_DEGREES:
        return None
    k = round(360 / degrees)
    return k if k >= 2 and abs(360 / k - degrees) <= ORDER_TOLERANCE_DEGREES else None


def describe_discrete(matrix: np.ndarray, scale: float, is_reflection: bool, diagonal: float,
                      centre: np.ndarray) -> dict[str, Any]:
    """The kind and the geometric fields of a discrete symmetry x -> matrix x."""
    if abs(scale - 1) > SCALE_TOLERANCE:
        return {"kind": "uniform scaling"}
    linear, shift = matrix[:3, :3] / scale, matrix[:3, 3]
    if is_reflection:
        if np.linalg.norm(linear @ linear - np.eye(3)) < MIRROR_TOLERANCE:
            return _mirror(linear, shift, diagonal, centre)
        return _rotoreflection(linear, shift, centre)
    if np.linalg.norm(linear - np.eye(3)) < IDENTITY_TOLERANCE:
        return {"kind": "translation", "translation": shift.copy()}
    return _rotation(linear, shift, diagonal, centre)


def _plane(normal: np.ndarray, offset: float, centre: np.ndarray) -> Plane:
    return Plane(normal, float(offset), centre - normal * float(normal @ centre - offset))


def _mirror(linear: np.ndarray, shift: np.ndarray, diagonal: float, centre: np.ndarray) -> dict[str, Any]:
    """x -> x - 2 (n.x - d) n + g, g along the plane: a glide reflection when g is longer
    than the slide floor."""
    normal = canonical_sign(np.linalg.eigh(0.5 * (linear + linear.T))[1][:, 0])
    along = float(normal @ shift)
    glide = shift - along * normal
    fields: dict[str, Any] = {"kind": "reflection", "plane": _plane(normal, along / 2, centre)}
    if np.linalg.norm(glide) > SLIDE_FLOOR * diagonal:
        fields.update(kind="glide reflection", translation=glide)
    return fields


def _rotation(linear: np.ndarray, shift: np.ndarray, diagonal: float, centre: np.ndarray) -> dict[str, Any]:
    """A turn about an axis, with a slide along it when it is a screw.  The axis passes
    through the solutions p of (I - L) p = t - slide; lstsq gives the one nearest the
    origin, which is then moved along the axis to the one nearest the centre."""
    degrees, direction = angle_and_axis(linear)
    slide = float(direction @ shift)
    point = np.linalg.lstsq(np.eye(3) - linear, shift - slide * direction, rcond=None)[0]
    fields: dict[str, Any] = {"kind": "rotation", "angle_degrees": degrees, "order": order_of(degrees),
                              "axis": Axis(point_nearest_on_line(point, direction, centre), direction)}
    if abs(slide) > SLIDE_FLOOR * diagonal:
        fields.update(kind="screw", translation=slide * direction)
    return fields


def _rotoreflection(linear: np.ndarray, shift: np.ndarray, centre: np.ndarray) -> dict[str, Any]:
    """A mirror composed with a turn about the mirror's normal (L L != I): it fixes one
    point p, (I - L) p = t, through which both the plane and the axis pass."""
    normal = canonical_sign(np.linalg.eigh(0.5 * (linear + linear.T))[1][:, 0])
    turn = linear @ (np.eye(3) - 2 * np.outer(normal, normal))
    degrees, direction = angle_and_axis(turn)
    fixed = np.linalg.solve(np.eye(3) - linear, shift)
    return {"kind": "rotoreflection", "angle_degrees": degrees, "order": order_of(degrees),
            "axis": Axis(fixed, direction), "plane": _plane(normal, float(normal @ fixed), centre)}


def describe_family(kind_code: int, point: np.ndarray, direction: np.ndarray, pitch_fraction: float,
                    diagonal: float, centre: np.ndarray) -> dict[str, Any]:
    """The kind and the geometric fields of a continuous family, from the filter's
    continuous_axes (a point and a unit direction, normal or nothing for a sphere) and its
    pitch (a fraction of the diagonal, turned here into the mesh's units)."""
    kind = FAMILY_KINDS[kind_code]
    if kind == "spherical patch":
        return {"kind": kind, "center": point.copy()}
    if kind == "planar patch":
        return {"kind": kind, "plane": _plane(direction, float(direction @ point), centre)}
    fields: dict[str, Any] = {"kind": kind, "axis": Axis(point_nearest_on_line(point, direction, centre), direction)}
    if kind == "helical family":
        fields["pitch"] = float(pitch_fraction * diagonal)
    return fields
