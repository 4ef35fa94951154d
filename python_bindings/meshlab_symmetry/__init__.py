"""Partial and approximate symmetry detection for pymeshlab.

Importing this package loads the ``filter_symmetry`` MeshLab plugin into pymeshlab and
binds its filter as a ``pymeshlab.MeshSet`` method, so that::

    import pymeshlab
    import meshlab_symmetry
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh("model.ply")
    out = ms.compute_partial_symmetries()

works like any built-in filter.  ``meshlab_symmetry.detect("model.ply")`` does the same in
one call on a file, a pymeshlab.Mesh or arrays, and returns a SymmetryResult.
"""
import functools
import os

import pymeshlab

FILTER_NAME = "compute_partial_symmetries"
#: the plugin's second filter (issue 9): detection, then the approximate symmetries made exact
SYMMETRIZATION_FILTER_NAME = "apply_coord_symmetrization"
#: the third (issue 9): detection, then the faces that are copies of others removed, with the
#: instances that rebuild them (the paper's Figure 7(c))
REDUCTION_FILTER_NAME = "generate_symmetry_based_reduction"
#: the fourth (issue 9): an edit of one copy carried to every copy (the paper's Figure 7(d))
EDITING_FILTER_NAME = "apply_coord_consistent_editing"
#: the fifth (issue 9): the rigid parts of a shape between two poses (the paper's Figure 8)
SEGMENTATION_FILTER_NAME = "compute_rigid_segments_between_meshes"
# MESHLAB_SYMMETRY_PLUGIN loads another build of the plugin instead (make test-sanitize
# loads the sanitized one).
_PLUGIN_FILE = (os.environ.get("MESHLAB_SYMMETRY_PLUGIN")
                or os.path.join(os.path.dirname(os.path.abspath(__file__)), "libfilter_symmetry.so"))


def plugin_path():
    """Path of the plugin file loaded into pymeshlab."""
    return _PLUGIN_FILE


def _load_plugin():
    if not os.path.exists(_PLUGIN_FILE):
        raise ImportError(
            f"The symmetry plugin is not built ({_PLUGIN_FILE} is missing). "
            "Run `make` at the top of the meshlab-symmetry repository.")
    pymeshlab.load_plugin(_PLUGIN_FILE)
    for name in (FILTER_NAME, SYMMETRIZATION_FILTER_NAME, REDUCTION_FILTER_NAME, EDITING_FILTER_NAME,
                 SEGMENTATION_FILTER_NAME):
        setattr(pymeshlab.MeshSet, name, _releasing_on_failure(pymeshlab.bind_function(name)))


def _releasing_on_failure(function):
    """The bound filter, made safe to fail.  When a filter raises, pymeshlab 2025.7 leaves its
    progress logger pointing at the MeshSet's log (it resets it only after a success:
    PyMeshLab issue #384).  Once that MeshSet is gone, the next mesh loaded in any MeshSet
    logs its progress into freed memory, and Python crashes or raises MemoryError: a batch
    loop that catches a refusal and loads the next file would die on it.  So after a
    failure, one filter that succeeds and changes nothing (get_geometric_measures) runs on
    the same MeshSet, resetting the logger, before the error is raised on."""
    @functools.wraps(function)
    def call(ms, *args, **kwargs):
        try:
            return function(ms, *args, **kwargs)
        except pymeshlab.PyMeshLabException:
            try:
                if ms.mesh_number() > 0:
                    ms.get_geometric_measures()
            except pymeshlab.PyMeshLabException:
                pass  # a mesh it cannot measure either: nothing more to do
            raise
    return call


_load_plugin()

from .symmetry_graph import detect_symmetries, symmetry_graph, to_json  # noqa: E402
from .geometry import Axis, Plane  # noqa: E402
from .result import Symmetry, SymmetryResult  # noqa: E402
from .api import detect  # noqa: E402

#: the picture functions of meshlab_symmetry.pictures, importable from the package itself
_PICTURES = ("deviation_picture", "patches_picture", "reduction_picture", "editing_picture", "segmentation_picture",
             "transformation_space_picture", "sample_size_curve", "report_html")

__all__ = ["FILTER_NAME", "SYMMETRIZATION_FILTER_NAME", "REDUCTION_FILTER_NAME", "EDITING_FILTER_NAME",
           "SEGMENTATION_FILTER_NAME", "plugin_path",
           "detect_symmetries", "symmetry_graph", "to_json", "detect", "SymmetryResult", "Symmetry", "Plane", "Axis", *_PICTURES]


def __getattr__(name):
    """The picture functions, imported on first use: matplotlib takes a while to import and
    only the pictures need it."""
    if name in _PICTURES:
        from . import pictures
        return getattr(pictures, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
