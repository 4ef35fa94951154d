"""``detect``: the symmetry filter as one Python call on a file, a pymeshlab.Mesh or arrays.

The filter itself works on a pymeshlab.MeshSet and answers with a dict of flat arrays,
patch layers and per-vertex attributes.  ``detect`` runs it on a private MeshSet (so the
caller's mesh is never changed) and gathers all of it into a SymmetryResult: each
symmetry with its kind in words, its plane or axis, and its patches as indices into the
input's vertices.

Its parameters are the filter's, with one convention for the units: every length is a
fraction of the bounding-box diagonal and the minimum patch area a fraction of the surface
area, as the filter's outputs (errors, areas) are.
"""
from __future__ import annotations

import os
import textwrap
from dataclasses import dataclass
from typing import Any, Callable, Optional, Protocol, Union

import numpy as np
import numpy.typing as npt
import pymeshlab

from .geometry import describe_discrete, describe_family
from .result import Symmetry, SymmetryResult
from .symmetry_graph import CONTINUOUS_KINDS, FILTER_NAME, _patch_layer_ids, graph_of_patches, symmetry_graph

#: names of the filter's transformation_group values
GROUPS = {"rigid": 0, "similarity": 1, "reflections": 2, "translations": 3}

_DIAGONAL = "fraction of the bounding-box diagonal"


@dataclass(frozen=True)
class Parameter:
    """A parameter of detect: its default, unit and meaning (for the docstring and the
    command line's --help), and how the filter takes it: ``convert`` is "length" (a
    fraction of the diagonal, passed as a pymeshlab.PercentageValue), "area" (a fraction,
    passed in percent), "group" (an index or a name of GROUPS) or "plain"."""
    name: str
    default: Union[int, float, bool]
    unit: str
    meaning: str
    convert: str = "plain"


PARAMETERS = (
    Parameter("transformation_group", 0, "index or name",
              "the symmetries looked for (§2): 0 'rigid', rotations, reflections (also composed with a turn "
              "or a slide) and translations, when you do not know what to expect; 1 'similarity', rigid plus "
              "uniform scale, for parts repeated at different sizes; 2 'reflections', mirror planes only, "
              "global or partial; 3 'translations', parts repeated in the same orientation", "group"),
    Parameter("sample_count", 10000, "samples",
              "points sampled uniformly on the surface before umbilic pruning (§5), 100 to 5,000,000; more "
              "find smaller symmetric parts, in more time"),
    Parameter("max_working_vertices", 50000, "vertices",
              "a mesh with more vertices is analysed on a copy simplified to about this many by quadric "
              "edge collapse; patches and deviations are carried back to every vertex and measured on the "
              "mesh itself (a point cloud: on about this many of its points, spread evenly); a mesh far "
              "coarser than the curvature ball is analysed on a copy with its long edges split, within "
              "this many vertices too; 0 always analyses the input itself (refined if coarse), else at "
              "least 1000"),
    Parameter("pair_sample_count", 0, "samples",
              "the random subset P' of the samples paired against all of them (§2.2), 0 to 5,000,000; 0 "
              "chooses it by the Appendix's Equation 1 so that a patch of min_patch_area is found with "
              "probability 0.95"),
    Parameter("curvature_radius", 0.01, _DIAGONAL,
              "radius r of the ball over which curvatures and principal directions are estimated (§2), in "
              "(0, 0.5]: above the scan's noise, below the features that matter; never less than 1.5 median "
              "edge lengths", "length"),
    Parameter("umbilic_ratio", 0.75, "ratio",
              "gamma of §2.1, in (0, 1): samples whose principal curvatures have |k1/k2| above it are nearly "
              "umbilic (ill-defined principal directions) and are not paired"),
    Parameter("signature_tolerance", 0.05, "dimensionless",
              "radius of the range query in signature space (§2.2), in (0, 10]: two samples are paired when "
              "their principal curvatures times r (for similarities, their shape indices) differ by less"),
    Parameter("cluster_bandwidth", 0.04, _DIAGONAL + ", in the metric of transformation space",
              "kernel width h of mean-shift clustering (§3.1), in (0, 1]", "length"),
    Parameter("min_cluster_support", 6, "pairs",
              "clusters with fewer votes are not verified (§3.1), at least 2"),
    Parameter("verification_tolerance", 0.01, _DIAGONAL,
              "distance accepted while growing a patch (§4), in (0, 0.25]: set it a little above the scan's "
              "noise; an approximate symmetry is kept when its deviation stays coherent under it", "length"),
    Parameter("min_patch_area", 0.01, "fraction of the surface area",
              "smaller patches are not reported, and the paired subset is sized to find this one, in [0, 1] "
              "(the filter's min_patch_area is this in percent)", "area"),
    Parameter("max_symmetries", 20, "symmetries",
              "at most this many discrete symmetries are reported, most significant first, and at most "
              "this many continuous families besides them (one report each), 1 to 1000"),
    Parameter("refine_with_icp", True, "yes/no",
              "refine each transformation by ICP while its patch grows (§4)"),
    Parameter("reduce_basis", True, "yes/no",
              "reduce the discrete symmetries to generators and write each as a word in them (§4.1, "
              "Algorithm 1)"),
    Parameter("basis_loop_length", 3, "letters",
              "eta of Algorithm 1: the longest product of generators tried, 1 to 6"),
    Parameter("basis_tolerance", 0.02, _DIAGONAL + ", in the metric of transformation space",
              "delta of Algorithm 1: a symmetry this close to a product of generators is a compound of them, "
              "not a new generator, in (0, 1]", "length"),
    Parameter("random_seed", 0, "integer",
              "seed of every random choice; the result is a deterministic function of the mesh, the "
              "parameters and the seed"),
)


class HasVerticesFaces(Protocol):
    """Any mesh object with vertex and triangle arrays, such as a trimesh.Trimesh."""
    vertices: npt.ArrayLike
    faces: npt.ArrayLike


#: what detect accepts as a mesh
MeshInput = Union[str, os.PathLike, pymeshlab.Mesh, tuple[npt.ArrayLike, npt.ArrayLike], HasVerticesFaces]


def detect(
    mesh: MeshInput,
    *,
    transformation_group: Union[int, str] = 0,
    sample_count: int = 10000,
    max_working_vertices: int = 50000,
    pair_sample_count: int = 0,
    curvature_radius: float = 0.01,
    umbilic_ratio: float = 0.75,
    signature_tolerance: float = 0.05,
    cluster_bandwidth: float = 0.04,
    min_cluster_support: int = 6,
    verification_tolerance: float = 0.01,
    min_patch_area: float = 0.01,
    max_symmetries: int = 20,
    refine_with_icp: bool = True,
    reduce_basis: bool = True,
    basis_loop_length: int = 3,
    basis_tolerance: float = 0.02,
    random_seed: int = 0,
    engine: str = "filter",
    progress: Optional[Callable[[int, str], None]] = None,
) -> SymmetryResult:
    """Detects the partial and approximate symmetries of a triangle mesh (Mitra, Guibas,
    Pauly 2006) and returns them as a SymmetryResult.

    ``mesh`` is a file path (any format pymeshlab reads; vertex indices then refer to the
    mesh as pymeshlab loads it, and an STL is welded on loading), a pymeshlab.Mesh, a
    ``(vertices, faces)`` pair of arrays (#V x 3 floats, #F x 3 integer indices) or any
    object with ``.vertices`` and ``.faces`` arrays (a trimesh.Trimesh).  The filter runs on
    a private copy with its patch layers on, so the caller's mesh is never changed.

    Raises FileNotFoundError for a missing file, ValueError or TypeError for a mesh or a
    parameter this function cannot pass on, OSError for a file whose header asks for more
    memory than there is, and pymeshlab.PyMeshLabException with the filter's sentence for
    a mesh it cannot analyse (NaN coordinates, a point cloud of a few points, a parameter
    out of range).  A point cloud (vertices, no faces) is analysed as one.

    ``engine`` is "filter" (the MeshLab filter through pymeshlab, as a filter script runs
    it) or "core" (the compiled core without pymeshlab in the loop: the same result for
    the same seed; its graph's nodes list no layers).  ``progress``, with the core only, is
    called as progress(percent, stage) on the calling thread during the run; Ctrl-C stops it.

    Every other parameter is keyword-only, with the filter's default (unit; meaning):
    """
    parameters = dict(locals())  # the parameters exactly as given, defaults included
    for name in ("mesh", "engine", "progress"):
        del parameters[name]
    parameters["transformation_group"] = _group_index(transformation_group)
    ms = _private_meshset(mesh)
    if engine == "core":
        return _detect_with_core(ms, parameters, progress)
    if engine != "filter":
        raise ValueError(f"engine '{engine}' is not one of filter, core")
    if progress is not None:
        raise ValueError("progress is reported by the core engine only (pymeshlab runs a filter without "
                         "a callback); pass engine='core'")
    return _detect_in_meshset(ms, parameters)


def _parameters_help() -> str:
    """The parameters section of detect's docstring, from PARAMETERS (which --help uses too)."""
    lines = []
    for p in PARAMETERS:
        meaning = textwrap.fill(p.meaning + ".", width=88, initial_indent=" " * 8, subsequent_indent=" " * 8)
        lines.append(f"\n    {p.name} = {p.default!r} ({p.unit})\n{meaning}")
    return "".join(lines) + "\n"


if detect.__doc__:  # None under python -OO
    detect.__doc__ += _parameters_help()


def filter_arguments(parameters: dict[str, Any]) -> dict[str, Any]:
    """detect's parameters as the filter takes them (percentages, pymeshlab values)."""
    return {p.name: _to_filter(p, parameters[p.name]) for p in PARAMETERS}


def _to_filter(p: Parameter, value: Any) -> Any:
    if p.convert == "group":
        return _group_index(value)
    if p.convert == "area":
        return 100.0 * value
    if p.convert == "length":
        # pymeshlab.PercentageValue refuses anything outside 0-100 % with its own
        # exception; say it in detect's units, naming the parameter.
        if not 0 <= value <= 1:
            raise ValueError(f"{p.name} is {value}, but it is a fraction of the bounding-box diagonal, "
                             "between 0 and 1")
        return pymeshlab.PercentageValue(100.0 * value)
    return value


def _group_index(group: Union[int, str]) -> int:
    if isinstance(group, str):
        if group not in GROUPS:
            raise ValueError(f"transformation_group '{group}' is not one of {', '.join(GROUPS)}")
        return GROUPS[group]
    return int(group)


def _detect_in_meshset(ms: pymeshlab.MeshSet, parameters: dict[str, Any]) -> SymmetryResult:
    """Runs the filter on the current mesh of ``ms`` (which keeps the patch layers and the
    per-vertex outputs afterwards, for the command line to save) and gathers the result."""
    mesh_id = ms.current_mesh_id()
    raw = getattr(ms, FILTER_NAME)(**filter_arguments(parameters), create_patch_layers=True)
    return _gather(ms, mesh_id, raw, parameters)


# --- the mesh given ---------------------------------------------------------------------------

def obj_face_index_problem(path: str) -> Union[str, None]:
    """For an OBJ file whose faces use vertex indices outside its vertex list, a sentence
    saying so; None otherwise (and for other formats).  MeshLab's OBJ reader leaves such
    faces pointing past its vertex array, and the process then crashes when it frees the
    mesh (assimp's invalid/malformed.obj, about one run in two), so the file is refused
    before pymeshlab reads it."""
    if not path.lower().endswith(".obj"):
        return None
    vertices, faces = 0, []
    with open(path, errors="replace") as f:
        for line in f:
            token = line.split(maxsplit=1)
            if not token:
                continue
            if token[0] == "v":
                vertices += 1
            elif token[0] == "f" and len(token) > 1:
                faces.append((vertices, token[1].split()))
    for seen, corners in faces:
        for corner in corners:
            try:
                index = int(corner.split("/")[0])
            except ValueError:
                return f"cannot read {path}: a face has the vertex reference '{corner}', which is not a number"
            absolute = seen + index + 1 if index < 0 else index
            if not 1 <= absolute <= vertices:
                return (f"cannot read {path}: a face refers to vertex {index}, but the file has {vertices} "
                        "vertices (the file is malformed; repair it in the program that wrote it)")
    return None


def load_mesh_file(ms: pymeshlab.MeshSet, path: str) -> None:
    """Loads ``path`` into ``ms`` as its current mesh; what pymeshlab would crash on or
    answer with a traceback is refused with a sentence (FileNotFoundError, ValueError,
    OSError)."""
    if not os.path.isfile(path):
        raise FileNotFoundError(f"no such file: {path}")
    problem = obj_face_index_problem(path)
    if problem:
        raise ValueError(problem)
    try:
        ms.load_new_mesh(os.path.abspath(path))
    except MemoryError:
        # pymeshlab's readers reserve what the header says (assimp's OutOfMemory.off
        # announces 353 billion vertices) and let std::bad_alloc through.
        raise OSError(f"cannot read {path}: the file asks for more memory than there is "
                      "(its header's vertex or face count is probably wrong)") from None


def _private_meshset(mesh: MeshInput) -> pymeshlab.MeshSet:
    """A new MeshSet whose current mesh is a copy of ``mesh`` (MeshSet.add_mesh copies)."""
    ms = pymeshlab.MeshSet()
    if isinstance(mesh, (str, os.PathLike)):
        load_mesh_file(ms, os.fspath(mesh))
    elif isinstance(mesh, pymeshlab.Mesh):
        ms.add_mesh(mesh, "input")
    elif isinstance(mesh, (tuple, list)) and len(mesh) == 2:
        ms.add_mesh(_mesh_from_arrays(*mesh), "input")
    elif hasattr(mesh, "vertices") and hasattr(mesh, "faces"):
        ms.add_mesh(_mesh_from_arrays(mesh.vertices, mesh.faces), "input")
    else:
        raise TypeError("mesh must be a file path, a pymeshlab.Mesh, a (vertices, faces) pair of arrays or an "
                        f"object with .vertices and .faces, not {type(mesh).__name__}")
    return ms


def _mesh_from_arrays(vertices: npt.ArrayLike, faces: npt.ArrayLike) -> pymeshlab.Mesh:
    """A pymeshlab.Mesh of the arrays, checked first: pymeshlab would read past the vertex
    array for a face index out of range.  No faces gives a point cloud."""
    v = np.asarray(vertices, dtype=np.float64)
    f = np.asarray(faces)
    if v.ndim != 2 or v.shape[1] != 3:
        raise ValueError(f"vertices must be an array of shape (n, 3), not {v.shape}")
    if f.size == 0:
        return pymeshlab.Mesh(vertex_matrix=v)
    if f.ndim != 2 or f.shape[1] != 3:
        raise ValueError(f"faces must be an array of triangles, shape (m, 3), not {f.shape}")
    if not np.issubdtype(f.dtype, np.integer):
        raise TypeError(f"faces must hold integer vertex indices, not {f.dtype}")
    if f.min() < 0 or f.max() >= len(v):
        raise ValueError(f"faces refer to vertex {f.min() if f.min() < 0 else f.max()}, "
                         f"but there are {len(v)} vertices")
    return pymeshlab.Mesh(vertex_matrix=v, face_matrix=f.astype(np.int32))


# --- the filter's answer, gathered --------------------------------------------------------------

class _VertexIndex:
    """Finds input vertices by exact position: the patch layers hold exact copies of input
    vertices (as symmetry_graph's _vertex_key_set relies on too), and a position that
    several input vertices share (a seam, a soup) stands for all of them."""

    def __init__(self, vertices: np.ndarray):
        self._keys, self._key_of_row = np.unique(_row_keys(vertices), return_inverse=True)
        self._key_of_row = self._key_of_row.reshape(-1)

    def rows_at(self, positions: np.ndarray) -> np.ndarray:
        keys = _row_keys(positions)
        found = np.minimum(np.searchsorted(self._keys, keys), len(self._keys) - 1)
        if len(keys) and not np.all(self._keys[found] == keys):
            raise RuntimeError("a patch layer holds a vertex that is not an input vertex; "
                               "the plugin and this package do not match")
        return np.flatnonzero(np.isin(self._key_of_row, found)).astype(np.int64)


def _row_keys(vertices: np.ndarray) -> np.ndarray:
    """Each row's 24 bytes as one opaque value, so that rows compare by exact position."""
    v = np.ascontiguousarray(vertices, dtype=np.float64).reshape(-1, 3)
    return v.view(np.dtype((np.void, 3 * v.itemsize))).reshape(-1)


def _gather(ms: pymeshlab.MeshSet, mesh_id: int, raw: dict[str, Any],
            parameters: dict[str, Any]) -> SymmetryResult:
    mesh = ms.mesh(mesh_id)
    box = mesh.bounding_box()
    diagonal, centre = float(box.diagonal()), np.asarray(box.center(), dtype=np.float64)
    count = int(raw["symmetry_count"])
    graph = symmetry_graph(ms, raw, mesh_id)
    index = _VertexIndex(mesh.vertex_matrix())
    layers = _patch_layer_ids(ms, raw, count)
    symmetries = []
    for k in range(count):
        patches = [index.rows_at(ms.mesh(layer).vertex_matrix()) for layer in layers[k]]
        symmetries.append(_symmetry(k, raw, graph["edges"][k], patches, diagonal, centre))
    scalars = {key: value for key, value in raw.items() if not isinstance(value, np.ndarray)}
    return SymmetryResult(
        symmetries=symmetries,
        deviation=np.array(mesh.vertex_scalar_array(), dtype=np.float64),
        symmetry_id=np.asarray(mesh.vertex_custom_scalar_attribute_array("symmetry_id")).astype(np.int64),
        graph=graph,
        timings={key: float(value) for key, value in scalars.items() if key.startswith("seconds_")},
        work={key: value for key, value in scalars.items()
              if not key.startswith("seconds_") and key != "symmetry_count"},
        parameters=dict(parameters),
        vertex_count=int(mesh.vertex_number()),
        diagonal=diagonal)


def _symmetry(k: int, raw: dict[str, Any], edge: dict[str, Any], patches: list[np.ndarray],
              diagonal: float, centre: np.ndarray) -> Symmetry:
    """Symmetry k of the filter's flat arrays, with its geometry read off."""
    axes = np.array(raw["continuous_axes"][6 * k:6 * k + 6], dtype=np.float64)
    return _typed_symmetry(
        k, diagonal, centre,
        matrix=np.array(raw["transforms"][16 * k:16 * k + 16], dtype=np.float64).reshape(4, 4),
        scale=float(raw["scales"][k]), is_reflection=bool(raw["is_reflection"][k]),
        continuous_kind=int(raw["continuous_kinds"][k]), axis_point=axes[:3], axis_direction=axes[3:],
        pitch=float(raw["continuous_pitches"][k]),
        source_vertices=patches[0], target_vertices=patches[1],
        rms_error=float(raw["rms_errors"][k]), max_error=float(raw["max_errors"][k]),
        systematic_error=float(raw["systematic_errors"][k]), source_area=float(raw["source_areas"][k]),
        support=int(raw["supports"][k]), is_generator=bool(edge["is_generator"]), word=tuple(edge["word"]))


def _typed_symmetry(k: int, diagonal: float, centre: np.ndarray, *, matrix: np.ndarray, scale: float,
                    is_reflection: bool, continuous_kind: int, axis_point: np.ndarray,
                    axis_direction: np.ndarray, pitch: float, **values: Any) -> Symmetry:
    """A Symmetry with its kind in words and its plane or axis read off its matrix (or, for a
    continuous family, off its axis)."""
    if continuous_kind:
        geometry = describe_family(continuous_kind, axis_point, axis_direction, pitch, diagonal, centre)
    else:
        geometry = describe_discrete(matrix, scale, is_reflection, diagonal, centre)
    return Symmetry(index=k, matrix=matrix, scale=scale, is_reflection=is_reflection, **values, **geometry)


# --- the compiled core, without pymeshlab in the loop -------------------------------------------

def _detect_with_core(ms: pymeshlab.MeshSet, parameters: dict[str, Any],
                      progress: Optional[Callable[[int, str], None]]) -> SymmetryResult:
    from . import _core  # built beside the plugin by make
    mesh = ms.current_mesh()
    vertices = np.ascontiguousarray(mesh.vertex_matrix(), dtype=np.float64)
    faces = np.ascontiguousarray(mesh.face_matrix(), dtype=np.int32)
    box = mesh.bounding_box()
    diagonal, centre = float(box.diagonal()), np.asarray(box.center(), dtype=np.float64)
    options = {p.name: parameters[p.name] for p in PARAMETERS}
    raw = _core.detect(vertices, faces, {**options, "keep_transformation_space": True}, progress)
    symmetries, edges = [], []
    for k, d in enumerate(raw["symmetries"]):
        word = [int(letter) for letter in d["word"]]
        patches = [np.asarray(d[side], dtype=np.int64) for side in ("source_vertices", "target_vertices")]
        symmetries.append(_typed_symmetry(
            k, diagonal, centre, matrix=np.asarray(d["matrix"], dtype=np.float64), scale=d["scale"],
            is_reflection=d["is_reflection"], continuous_kind=d["continuous_kind"],
            axis_point=np.asarray(d["axis_point"]), axis_direction=np.asarray(d["axis_direction"]),
            pitch=d["pitch"], source_vertices=patches[0], target_vertices=patches[1],
            rms_error=d["rms_error"], max_error=d["max_error"], systematic_error=d["systematic_error"],
            source_area=d["source_area"], support=d["support"], is_generator=d["is_generator"],
            word=tuple(word)))
        edge = {"source_vertices": patches[0], "target_vertices": patches[1],
                "transform": np.asarray(d["matrix"]).tolist(), "scale": d["scale"],
                "is_reflection": d["is_reflection"], "rms_error": d["rms_error"], "support": d["support"],
                "is_generator": d["is_generator"], "word": word,
                "continuous_kind": CONTINUOUS_KINDS[d["continuous_kind"]]}
        if d["continuous_kind"]:
            edge.update(axis_point=list(d["axis_point"]), axis_direction=list(d["axis_direction"]),
                        pitch=d["pitch"])
        edges.append(edge)
    return SymmetryResult(
        symmetries=symmetries,
        deviation=np.asarray(raw["deviation"], dtype=np.float64),
        symmetry_id=np.asarray(raw["symmetry_id"]).astype(np.int64),
        graph=graph_of_patches(vertices, faces, edges),
        timings=dict(raw["timings"]),
        work=dict(raw["work"]),
        parameters=dict(parameters),
        vertex_count=len(vertices),
        diagonal=diagonal,
        transformation_space={key: np.asarray(value) for key, value in raw["transformation_space"].items()})
