"""MeshLab filter scripts (.mlx) that run the symmetry filter headless in meshlabserver.

meshlabserver exists only in MeshLab up to 2020.09 (Debian 12's ``meshlab`` package), and
its script reader needs every parameter of a filter in the script (it aborts on an
assertion when one is missing).  A length parameter of a 2020.09 script
(``RichAbsPerc``) holds an absolute length, not a percentage, so a script made for one
mesh measures in that mesh's units: :func:`meshlabserver_script` writes one from the
bounding-box diagonal of the mesh it is meant for, with detect's parameters in detect's
units (lengths as fractions of that diagonal)::

    meshlab-symmetry script model.ply -o detect.mlx --verification-tolerance 0.02
    xvfb-run -a meshlabserver -i model.ply -o out.ply -m vq vc -s detect.mlx
"""
from typing import Any
from xml.sax.saxutils import quoteattr

from .api import GROUPS, PARAMETERS, _group_index

#: the menu entry of the detection filter, the name a filter script uses
DETECTION_FILTER = "Detect Partial and Approximate Symmetries"
#: the menu entry of the reduction filter (issue 9)
REDUCTION_FILTER = "Symmetry-Based Reduction"
#: the menu entry of the rigid segmentation between two poses (issue 9)
SEGMENTATION_FILTER = "Segment Rigid Parts Between Two Poses"
#: detection's parameters the segmentation filter does not take: it fixes the group and
#: reduces no basis
_NOT_SEGMENTATION = ("transformation_group", "reduce_basis", "basis_loop_length", "basis_tolerance")

# The display names of transformation_group's values, as the plugin lists them
# (symmetry_parameters.cpp); a script carries them, the filter reads only the index.
_GROUP_NAMES = ("Rotations, reflections and translations (rigid, 6-D)",
                "Similarities: rigid plus uniform scale (7-D)",
                "Reflections only",
                "Translations only")
assert len(_GROUP_NAMES) == len(GROUPS)


def meshlabserver_script(diagonal: float, create_patch_layers: bool = False, **parameters: Any) -> str:
    """The text of a MeshLab 2020.09 filter script that runs "Detect Partial and
    Approximate Symmetries" on a mesh whose bounding-box diagonal is ``diagonal``, with
    detect's parameters (any not given keeps detect's default; lengths are fractions of the
    diagonal, min_patch_area a fraction of the area).  ``create_patch_layers`` adds the
    patch layers (meshlabserver saves only the current mesh, the input).

    Raises ValueError for a diagonal that is not a positive number or an unknown parameter.
    """
    return _script(DETECTION_FILTER, diagonal, parameters, {"create_patch_layers": ("RichBool", create_patch_layers)})


def meshlabserver_reduction_script(diagonal: float, instances_file: str = "",
                                   create_reconstruction_layer: bool = False, **parameters: Any) -> str:
    """The same for "Symmetry-Based Reduction": detection with detect's parameters, then the
    faces that are copies of others removed.  meshlabserver saves the current mesh, which
    the filter makes the reduced one; ``instances_file`` names the JSON of the instances that
    rebuild the rest (none when empty)."""
    return _script(REDUCTION_FILTER, diagonal, parameters, {},
                   [_element("create_reconstruction_layer", "RichBool", "true" if create_reconstruction_layer else "false"),
                    _element("instances_file", "RichString", str(instances_file))])


def meshlabserver_segmentation_script(diagonal: float, first_mesh: int = 0, second_mesh: int = 1,
                                      create_segment_layers: bool = False, **parameters: Any) -> str:
    """The same for "Segment Rigid Parts Between Two Poses": the meshes are the layers
    ``first_mesh`` and ``second_mesh`` in the order meshlabserver loaded them (``-i a.ply
    b.ply``: 0 and 1), ``diagonal`` the first pose's, and detect's parameters but the group
    and the basis reduction's (ValueError for those).  meshlabserver saves only the current
    mesh: with ``-o`` and ``-m vc`` it is the first pose, coloured by segment, and the log
    holds one line per segment with its transform."""
    refused = sorted(set(parameters) & set(_NOT_SEGMENTATION))
    if refused:
        raise ValueError(f"{', '.join(refused)}: the segmentation filter has no such parameter (its group is the "
                         "rigid motions, and it reduces no basis)")
    meshes = [_element("first_mesh", "RichMesh", str(int(first_mesh))),
              _element("second_mesh", "RichMesh", str(int(second_mesh)))]
    return _script(SEGMENTATION_FILTER, diagonal, parameters, {},
                   [_element("create_segment_layers", "RichBool", "true" if create_segment_layers else "false")],
                   first=meshes, leave_out=_NOT_SEGMENTATION)


def _script(filter_name, diagonal, parameters, before_seed, after=(), first=(), leave_out=()):
    """A script of one filter: the elements `first`, detect's parameters but `leave_out` in
    the plugin's order, `before_seed` ({name: (type, bool)}) just before random_seed as the
    detection filter has it, and the elements `after` at the end."""
    if not diagonal > 0:
        raise ValueError(f"the diagonal is {diagonal}; a filter script needs the positive bounding-box diagonal "
                         "of the mesh it is for")
    known = {p.name for p in PARAMETERS}
    unknown = sorted(set(parameters) - known)
    if unknown:
        raise ValueError(f"unknown parameter(s) {', '.join(unknown)}; detect takes {', '.join(sorted(known))}")
    lines = ["<!DOCTYPE FilterScript>", "<FilterScript>", f" <filter name={quoteattr(filter_name)}>"]
    lines += ["  " + e for e in first]
    for p in PARAMETERS:
        if p.name in leave_out:
            continue
        if p.name == "random_seed":
            for name, (kind, value) in before_seed.items():
                lines.append("  " + _element(name, kind, "true" if value else "false"))
        lines.append("  " + _param(p, parameters.get(p.name, p.default), diagonal))
    lines += ["  " + e for e in after]
    lines += [" </filter>", "</FilterScript>", ""]
    return "\n".join(lines)


def _param(p, value, diagonal):
    if p.convert == "group":
        index = _group_index(value)
        extra = {"enum_cardinality": str(len(_GROUP_NAMES)),
                 **{f"enum_val{i}": name for i, name in enumerate(_GROUP_NAMES)}}
        return _element(p.name, "RichEnum", str(index), extra)
    if p.convert == "length":
        if not 0 <= value <= 1:
            raise ValueError(f"{p.name} is {value}, but it is a fraction of the bounding-box diagonal, between 0 and 1")
        return _element(p.name, "RichAbsPerc", repr(float(value) * diagonal), {"min": "0", "max": repr(float(diagonal))})
    if p.convert == "area":
        return _element(p.name, "RichFloat", repr(100.0 * float(value)))
    if isinstance(p.default, bool):
        return _element(p.name, "RichBool", "true" if value else "false")
    if isinstance(p.default, int):
        if isinstance(value, bool) or int(value) != value:
            raise ValueError(f"{p.name} is {value!r}, but it is a whole number")
        return _element(p.name, "RichInt", str(int(value)))
    return _element(p.name, "RichFloat", repr(float(value)))


def _element(name, kind, value, extra=None):
    attributes = {"name": name, "type": kind, "value": value, **(extra or {})}
    return "<Param " + " ".join(f"{k}={quoteattr(v)}" for k, v in attributes.items()) + "/>"
