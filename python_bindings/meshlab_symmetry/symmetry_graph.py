"""The symmetry graph of §4 of Mitra, Guibas, Pauly 2006, built from the filter's output.

Nodes are symmetric patches, edges are symmetries: each edge joins the patch a symmetry
maps from (its source) to the patch it maps onto (its target).  A patch that several
symmetries share (the same part of the surface is the source of one and the target of
another, as with a part repeated three times) is one node, so the graph shows how the
repeated parts are connected.
"""
import json

import numpy as np

FILTER_NAME = "compute_partial_symmetries"
#: the filter's continuous_kinds, by value
CONTINUOUS_KINDS = ("discrete", "rotational", "translational", "helical", "planar", "spherical")


def _vector(result, key, count, default=0.0):
    values = result.get(key)
    if values is None:
        return np.full(count, default, dtype=float)
    return np.asarray(values, dtype=float).reshape(-1)


def _surface_area(mesh):
    faces = mesh.face_matrix()
    if len(faces) == 0:
        return 0.0
    v = mesh.vertex_matrix()
    a, b, c = v[faces[:, 0]], v[faces[:, 1]], v[faces[:, 2]]
    return float(0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1).sum())


def _mesh_ids(ms):
    """Ids of all the meshes of the MeshSet (they need not be contiguous)."""
    ids, candidate = [], 0
    wanted = ms.mesh_number()
    # Ids only grow; a document holds at most a few thousand deleted ids in practice.
    while len(ids) < wanted and candidate < wanted + 100000:
        if ms.mesh_id_exists(candidate):
            ids.append(candidate)
        candidate += 1
    return ids


def _patch_layer_ids(ms, result, count):
    """(source id, target id) per symmetry: from the filter's patch_layer_ids if present,
    else by the layer names symmetry_{k}_source / symmetry_{k}_target."""
    ids = result.get("patch_layer_ids")
    if ids is not None and len(ids) == 2 * count and all(i >= 0 for i in ids):
        pairs = [(int(ids[2 * k]), int(ids[2 * k + 1])) for k in range(count)]
        if all(ms.mesh_id_exists(i) for pair in pairs for i in pair):
            return pairs
    by_label = {}
    for i in _mesh_ids(ms):
        by_label.setdefault(ms.mesh(i).label(), i)
    pairs = []
    for k in range(count):
        names = (f"symmetry_{k}_source", f"symmetry_{k}_target")
        if not all(n in by_label for n in names):
            raise ValueError(
                f"The patch layers of symmetry {k} ({names[0]}, {names[1]}) are not in the MeshSet; "
                "run compute_partial_symmetries with create_patch_layers=True.")
        pairs.append((by_label[names[0]], by_label[names[1]]))
    return pairs


def _vertex_key_set(mesh):
    """The patch's vertices, as exact positions (layers hold exact copies of input vertices)."""
    v = np.ascontiguousarray(mesh.vertex_matrix(), dtype=np.float64)
    return frozenset(row.tobytes() for row in v)


def symmetry_graph(ms, result, mesh_id=None, merge_overlap=0.9):
    """Builds the symmetry graph from the return dict of ``compute_partial_symmetries``
    and the patch layers it created in ``ms``.

    ``mesh_id`` is the input mesh (default: the current mesh, which the filter leaves on
    the input).  Two patches whose vertex sets overlap by at least ``merge_overlap``
    (intersection over union) are one node.

    Returns a dict: ``nodes`` (id, name of the layer, layers, layer_ids, vertex_count,
    area_fraction), ``edges`` (one per symmetry, in result order: symmetry, source,
    target, transform as a 4x4 list, scale, is_reflection, rms_error, support,
    is_generator, word as signed generator letters: +k is generator k-1, -k its inverse;
    continuous_kind, one of CONTINUOUS_KINDS, "discrete" for a discrete symmetry, and for a
    continuous family its axis: axis_point and axis_direction (the plane's normal, zeros
    for a sphere) and pitch),
    ``generators`` (symmetry indices) and ``symmetry_count``.
    """
    count = int(result["symmetry_count"])
    input_mesh = ms.current_mesh() if mesh_id is None else ms.mesh(mesh_id)
    total_area = _surface_area(input_mesh)

    transforms = _vector(result, "transforms", 16 * count)
    if len(transforms) != 16 * count:
        raise ValueError("The result's transforms do not hold 16 numbers per symmetry.")
    scales = _vector(result, "scales", count, 1.0)
    reflections = _vector(result, "is_reflection", count)
    rms = _vector(result, "rms_errors", count)
    supports = _vector(result, "supports", count)
    generator_flags = _vector(result, "is_generator", count, 1.0)
    words = _vector(result, "basis_words", 0)
    kinds = _vector(result, "continuous_kinds", count)
    axes = _vector(result, "continuous_axes", 6 * count)
    pitches = _vector(result, "continuous_pitches", count)
    letters = len(words) // count if count else 0

    patches = _Nodes(merge_overlap)

    def node_of(layer_id):
        mesh = ms.mesh(layer_id)
        return patches.node_of(_vertex_key_set(mesh), mesh.label(), int(mesh.vertex_number()),
                               lambda: _surface_area(mesh) / total_area if total_area > 0 else 0.0,
                               layer=(mesh.label(), int(layer_id)))

    edges = []
    for k, (source_layer, target_layer) in enumerate(_patch_layer_ids(ms, result, count)):
        word = [int(w) for w in words[k * letters:(k + 1) * letters] if w != 0]
        edges.append({
            "symmetry": k,
            "source": node_of(source_layer),
            "target": node_of(target_layer),
            "transform": transforms[16 * k:16 * (k + 1)].reshape(4, 4).tolist(),
            "scale": float(scales[k]),
            "is_reflection": bool(reflections[k]),
            "rms_error": float(rms[k]),
            "support": int(supports[k]),
            "is_generator": bool(generator_flags[k]),
            "word": word,
            "continuous_kind": CONTINUOUS_KINDS[int(kinds[k])],
        })
        if kinds[k] != 0:
            edges[-1].update(axis_point=axes[6 * k:6 * k + 3].tolist(),
                             axis_direction=axes[6 * k + 3:6 * k + 6].tolist(), pitch=float(pitches[k]))
    return _graph(patches.nodes, edges)


def _graph(nodes, edges):
    return {
        "symmetry_count": len(edges),
        "nodes": nodes,
        "edges": edges,
        "generators": [e["symmetry"] for e in edges if e["is_generator"]],
    }


class _Nodes:
    """The graph's nodes: a patch whose vertex set overlaps a node's by at least
    ``merge_overlap`` (intersection over union) is that node."""

    def __init__(self, merge_overlap):
        self.merge_overlap = merge_overlap
        self.nodes, self._sets = [], []

    def node_of(self, keys, name, vertex_count, area_fraction, layer=None):
        """The index of the node of the patch with vertex set ``keys``; ``area_fraction``
        is called for a new node only; ``layer`` is (label, id) of the patch's layer."""
        for index, other in enumerate(self._sets):
            union = len(keys | other)
            if union and len(keys & other) / union >= self.merge_overlap:
                if layer:
                    self.nodes[index]["layers"].append(layer[0])
                    self.nodes[index]["layer_ids"].append(layer[1])
                return index
        self.nodes.append({
            "id": len(self.nodes),
            "name": name,
            "layers": [layer[0]] if layer else [],
            "layer_ids": [layer[1]] if layer else [],
            "vertex_count": vertex_count,
            "area_fraction": area_fraction(),
        })
        self._sets.append(keys)
        return len(self.nodes) - 1


def graph_of_patches(vertices, faces, edges_data, merge_overlap=0.9):
    """The same graph as symmetry_graph, from patches given as input vertex indices (the
    compiled core's answer, which has no layers): ``edges_data`` holds per symmetry a dict
    with source_vertices, target_vertices and the edge's other fields (transform, scale,
    is_reflection, rms_error, support, is_generator, word, continuous_kind and, for a
    family, axis_point, axis_direction, pitch).  A patch's area is that of the faces whose
    three corners are in it, as in its layer; nodes name their patch as the layer would be
    named and list no layers."""
    vertices = np.asarray(vertices, dtype=np.float64)
    faces = np.asarray(faces).reshape(-1, 3)
    a, b, c = (vertices[faces[:, i]] for i in range(3)) if len(faces) else (np.zeros((0, 3)),) * 3
    face_areas = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)
    total_area = float(face_areas.sum())
    patches = _Nodes(merge_overlap)

    def node_of(patch, name):
        inside = np.zeros(len(vertices), dtype=bool)
        inside[np.asarray(patch, dtype=np.int64)] = True

        def area_fraction():
            area = float(face_areas[inside[faces].all(axis=1)].sum()) if len(faces) else 0.0
            return area / total_area if total_area > 0 else 0.0
        return patches.node_of(frozenset(np.flatnonzero(inside).tolist()), name, int(inside.sum()), area_fraction)

    edges = []
    for k, data in enumerate(edges_data):
        edge = {"symmetry": k,
                "source": node_of(data["source_vertices"], f"symmetry_{k}_source"),
                "target": node_of(data["target_vertices"], f"symmetry_{k}_target")}
        edge.update({key: value for key, value in data.items() if key not in ("source_vertices", "target_vertices")})
        edges.append(edge)
    return _graph(patches.nodes, edges)


def detect_symmetries(ms, **params):
    """Runs ``compute_partial_symmetries`` on the current mesh of ``ms`` (with patch
    layers, which the graph needs) and returns ``(result_dict, graph_dict)``."""
    if not params.get("create_patch_layers", True):
        raise ValueError("detect_symmetries needs the patch layers: do not pass create_patch_layers=False.")
    params["create_patch_layers"] = True
    mesh_id = ms.current_mesh_id()
    result = getattr(ms, FILTER_NAME)(**params)
    return result, symmetry_graph(ms, result, mesh_id)


def _plain(value):
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, np.generic):
        return value.item()
    raise TypeError(f"{type(value).__name__} is not JSON serialisable")


def to_json(graph, indent=2):
    """The graph (or a result dict) as a JSON string; numpy values become plain numbers."""
    return json.dumps(graph, indent=indent, default=_plain)
