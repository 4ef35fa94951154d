"""Pictures of what :func:`meshlab_symmetry.detect` found, and an HTML report of them.

Rendered off-screen with matplotlib's Agg canvas: no display, no OpenGL, so the same
code runs on a laptop, a server and in CI.  A 3-D view is matplotlib's mplot3d
Poly3DCollection with flat shading computed here (one colour per face, dimmed by the angle
between its normal and a light near the eye); a mesh of more than MAX_DRAWN_FACES faces is
drawn from a copy simplified by quadric edge collapse, so a picture takes seconds.  mplot3d
sorts faces by depth (the painter's algorithm), which is exact for the convex and nearly
convex parts that make up most models and may misorder faces of deep concavities.

- :func:`deviation_picture`: the signed deviation from perfect symmetry (the paper's Figure 1);
- :func:`patches_picture`: the symmetric patches, mirror planes, rotation axes, translations;
- :func:`transformation_space_picture`: the detector's own transformation space Γ, its two
  sheets projected to 2-D by multidimensional scaling (the paper's Figure 7(b));
- :func:`sample_size_curve`: symmetries found against the size of P' (the paper's Figure 5);
- :func:`report_html`: the three pictures and a table of the symmetries in one HTML page.

Each picture function writes a PNG of PICTURE_SIZE pixels and returns a :class:`Picture`.
"""
from __future__ import annotations

import html
import os
from dataclasses import dataclass
from typing import Any, Optional, Sequence

import numpy as np
from matplotlib.cm import ScalarMappable
from matplotlib.colors import Normalize, to_rgb
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch
from mpl_toolkits.mplot3d.art3d import Line3DCollection, Poly3DCollection
from scipy.spatial import cKDTree

from .api import MeshInput, _private_meshset, detect
from .geometry import FAMILY_KINDS
from .result import Symmetry, SymmetryResult

#: a mesh with more faces is drawn from a simplified copy (mplot3d draws ~20k faces in seconds)
MAX_DRAWN_FACES = 20000
#: width and height of every picture, in pixels
FIGURE_INCHES, DPI = (10.0, 7.0), 120
PICTURE_SIZE = (int(FIGURE_INCHES[0] * DPI), int(FIGURE_INCHES[1] * DPI))
#: where the 3-D view sits in a mesh picture (figure fractions: left, bottom, width, height);
#: the right-hand strip holds the colour bar or the legend
MESH_RECT = (0.0, 0.0, 0.66, 0.92)
#: at most this many symmetries get a colour of their own in patches_picture
COLOURED_SYMMETRIES = 10
#: a deviation scale never narrower than this fraction of the diagonal, so that rounding
#: noise on an exact symmetry (1e-17) is drawn as the neutral colour, not as full red and blue
MIN_DEVIATION_SCALE = 1e-4
NO_SYMMETRY_GREY = (0.45, 0.45, 0.45)
PALETTE = [to_rgb(f"C{k}") for k in range(COLOURED_SYMMETRIES)]  # matplotlib's tab10
MIRROR_KINDS = ("reflection", "glide reflection", "rotoreflection")
AXIS_KINDS = ("rotation", "screw", "rotoreflection", "rotational family", "helical family", "translational family")


@dataclass
class Picture:
    """A written picture: its ``path``, ``plot_box`` (left, top, right, bottom pixels of the
    main drawing in the PNG: the 3-D view or the 2-D plot, without title, colour bar or
    legend) and the ``legend`` texts as drawn."""
    path: str
    plot_box: tuple[int, int, int, int]
    legend: list[str]


@dataclass
class _DrawnMesh:
    """The triangles drawn: ``vertices``, ``faces``, and for each drawn vertex the input
    vertex it stands for (itself, or the nearest one when the mesh was simplified)."""
    vertices: np.ndarray
    faces: np.ndarray
    input_vertex: np.ndarray
    input_vertices: np.ndarray

    def face_values(self, per_input_vertex: np.ndarray) -> np.ndarray:
        """A per-input-vertex array read at the three corners of every drawn face (#F x 3)."""
        return per_input_vertex[self.input_vertex][self.faces]


# --- the mesh and its shading ---------------------------------------------------------------------

def _drawn_mesh(mesh: MeshInput, result: SymmetryResult) -> _DrawnMesh:
    """The input as detect read it (same vertex order, so result's per-vertex arrays apply),
    simplified on a copy when it has more than MAX_DRAWN_FACES faces."""
    ms = _private_meshset(mesh)
    vertices = ms.current_mesh().vertex_matrix().copy()
    if len(vertices) != result.vertex_count:
        raise ValueError(f"the mesh has {len(vertices)} vertices but the result is of a mesh with "
                         f"{result.vertex_count}; pass the mesh detect was run on")
    if ms.current_mesh().face_number() > MAX_DRAWN_FACES:
        ms.meshing_decimation_quadric_edge_collapse(targetfacenum=MAX_DRAWN_FACES, preservenormal=True)
    drawn = ms.current_mesh()
    drawn_vertices = drawn.vertex_matrix().copy()
    nearest = cKDTree(vertices).query(drawn_vertices)[1]
    return _DrawnMesh(drawn_vertices, drawn.face_matrix().copy(), np.asarray(nearest, dtype=np.int64), vertices)


def _eye(view: tuple[float, float]) -> np.ndarray:
    """Unit vector towards the viewer for mplot3d's (elevation, azimuth) in degrees."""
    elevation, azimuth = np.radians(view)
    return np.array([np.cos(elevation) * np.cos(azimuth), np.cos(elevation) * np.sin(azimuth), np.sin(elevation)])


def _shaded(rgb: np.ndarray, triangles: np.ndarray, view: tuple[float, float]) -> np.ndarray:
    """Flat shading: each face's colour dimmed by the angle between its normal and a light
    above and beside the eye (two-sided, so a mesh turned inward still reads as a shape)."""
    normals = np.cross(triangles[:, 1] - triangles[:, 0], triangles[:, 2] - triangles[:, 0])
    normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-300)
    light = _eye(view) + 0.6 * _eye((view[0] + 60.0, view[1] + 40.0))
    light /= np.linalg.norm(light)
    intensity = 0.35 + 0.65 * np.abs(normals @ light)
    return np.clip(rgb * intensity[:, None], 0.0, 1.0)


def _mesh_axes(fig: Figure, vertices: np.ndarray, view: tuple[float, float]):
    """A 3-D axes in MESH_RECT with equal scales and no box, looking at ``vertices``.
    Artists are drawn in zorder (lines and arrows over the surface, so they stay visible);
    the surface collection sorts its own faces by depth."""
    ax = fig.add_axes(MESH_RECT, projection="3d", computed_zorder=False)
    ax.view_init(elev=view[0], azim=view[1])
    low, high = vertices.min(axis=0), vertices.max(axis=0)
    middle, half = (low + high) / 2, max(float((high - low).max()) / 2, 1e-12)
    for setter, m in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), middle):
        setter(m - half, m + half)
    ax.set_box_aspect((1, 1, 1), zoom=1.1)
    ax.set_axis_off()
    return ax


def _add_surface(ax, triangles: np.ndarray, rgba: np.ndarray) -> None:
    """The faces, each edged in its own colour: without an edge, antialiasing leaves hairline
    seams of background between neighbouring faces.  Translucent faces get no edge."""
    edges = np.where(rgba[:, 3:] < 1, 0.0, rgba)
    ax.add_collection3d(Poly3DCollection(triangles, facecolors=rgba, edgecolors=edges, linewidths=0.3,
                                         zorder=1))


def _plot_box(ax) -> tuple[int, int, int, int]:
    """The pixel box of ``ax`` in the saved PNG (y from the top, as image rows count)."""
    left, bottom, right, top = ax.get_position().extents
    width, height = PICTURE_SIZE
    return (int(left * width), int((1 - top) * height), int(right * width), int((1 - bottom) * height))


def _save(fig: Figure, path: str, plot_box, legend: list[str]) -> Picture:
    """Writes the PNG at exactly PICTURE_SIZE (no tight bounding box, so plot_box holds)."""
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    fig.savefig(path, dpi=DPI, facecolor="white")
    return Picture(os.fspath(path), plot_box, legend)


def _new_figure(title: str) -> Figure:
    fig = Figure(figsize=FIGURE_INCHES, dpi=DPI)
    fig.suptitle(title, fontsize=13, x=0.02, ha="left")
    return fig


def _count(result: SymmetryResult) -> str:
    n = len(result.symmetries)
    return f"{n} symmetr{'y' if n == 1 else 'ies'}"


# --- a. deviation ---------------------------------------------------------------------------------

def deviation_scale(result: SymmetryResult) -> float:
    """Half the width of the colour scale, a fraction of the diagonal: the 99th percentile of
    |deviation| over the vertices in a symmetry (so that a few outliers do not wash the rest
    out; larger values saturate), never below MIN_DEVIATION_SCALE."""
    inside = np.abs(result.deviation[result.symmetry_id >= 0])
    return max(float(np.percentile(inside, 99)) if inside.size else 0.0, MIN_DEVIATION_SCALE)


def deviation_picture(mesh: MeshInput, result: SymmetryResult, path: str, *,
                      view: tuple[float, float] = (20.0, -60.0), scale: Optional[float] = None,
                      title: Optional[str] = None) -> Picture:
    """The mesh coloured by the signed deviation from perfect symmetry, ``result.deviation``
    (the distance of each vertex's image from the surface under the most significant symmetry
    it is in, as a fraction of the diagonal; the paper's Figure 1), on a diverging colour map
    symmetric about 0 (blue below, red above, white at 0) with a colour bar in percent of
    the diagonal; faces whose vertices are mostly in no symmetry are dark grey.  ``mesh`` is
    the mesh detect was run on, in any form detect takes.  ``scale`` fixes half the colour
    scale's width (fraction of the diagonal; default deviation_scale), so that pictures of
    two results compare; ``title`` replaces the default title."""
    drawn = _drawn_mesh(mesh, result)
    scale = deviation_scale(result) if scale is None else scale
    norm = Normalize(-100 * scale, 100 * scale)
    colours = ScalarMappable(norm=norm, cmap="RdBu_r")
    value = drawn.face_values(result.deviation).mean(axis=1)
    in_symmetry = (drawn.face_values(result.symmetry_id) >= 0).mean(axis=1) >= 0.5
    rgb = np.where(in_symmetry[:, None], colours.to_rgba(100 * value)[:, :3], NO_SYMMETRY_GREY)
    triangles = drawn.vertices[drawn.faces]
    fig = _new_figure(title or f"Deviation from perfect symmetry ({_count(result)})")
    ax = _mesh_axes(fig, drawn.vertices, view)
    _add_surface(ax, triangles, np.hstack([_shaded(rgb, triangles, view), np.ones((len(rgb), 1))]))
    bar = fig.colorbar(colours, cax=fig.add_axes((0.72, 0.2, 0.03, 0.6)), extend="both")
    bar.set_label("signed deviation, % of the bounding-box diagonal")
    legend = fig.legend(handles=[Patch(color=NO_SYMMETRY_GREY, label="in no symmetry")],
                        loc="lower left", bbox_to_anchor=(0.69, 0.06), frameon=False)
    return _save(fig, path, _plot_box(ax), [t.get_text() for t in legend.get_texts()])


# --- b. patches -----------------------------------------------------------------------------------

def symmetry_label(s: Symmetry) -> str:
    """'#k kind, angle, area %' as the patches picture's legend and the report say it."""
    detail = ""
    if s.angle_degrees is not None:
        detail = f" {s.angle_degrees:.1f}°" + (f" ({s.order}-fold)" if s.order else "")
    return f"#{s.index} {s.kind}{detail}, area {100 * s.source_area:.1f} %"


def _vertex_symmetry(result: SymmetryResult, shown: int) -> np.ndarray:
    """Per input vertex, the most significant of the first ``shown`` symmetries whose source
    or target patch holds it; -1 for none."""
    label = np.full(result.vertex_count, -1, dtype=np.int64)
    for s in reversed(result.symmetries[:shown]):
        label[s.source_vertices] = s.index
        label[s.target_vertices] = s.index
    return label


def _box_corners_and_edges(low: np.ndarray, high: np.ndarray) -> tuple[np.ndarray, list[tuple[int, int]]]:
    corners = np.array([[(low, high)[(i >> a) & 1][a] for a in range(3)] for i in range(8)])
    edges = [(i, i | (1 << a)) for i in range(8) for a in range(3) if not i & (1 << a)]
    return corners, edges


def plane_in_box(normal: np.ndarray, offset: float, low: np.ndarray, high: np.ndarray) -> np.ndarray:
    """The convex polygon (k x 3, k in 0 or 3..6) where the plane n.x = offset cuts the box,
    its corners in order around it."""
    corners, edges = _box_corners_and_edges(low, high)
    side = corners @ normal - offset
    points = [corners[i] + (corners[j] - corners[i]) * side[i] / (side[i] - side[j])
              for i, j in edges if side[i] * side[j] < 0 or (side[i] == 0 and side[j] != 0)]
    if len(points) < 3:
        return np.zeros((0, 3))
    points = np.unique(np.round(np.array(points), 12), axis=0)
    centre = points.mean(axis=0)
    u = points[0] - centre
    u /= np.linalg.norm(u)
    v = np.cross(normal, u)
    return points[np.argsort(np.arctan2((points - centre) @ v, (points - centre) @ u))]


def _tiles(polygon: np.ndarray, divisions: int = 8) -> np.ndarray:
    """The convex polygon cut into small triangles (a fan, each triangle subdivided), so that
    mplot3d's depth sort puts each piece of a translucent plane in front of or behind the
    surface where it is, not the whole plane at once."""
    tiles = []
    centre = polygon.mean(axis=0)
    for a, b in zip(polygon, np.roll(polygon, -1, axis=0)):
        for i in range(divisions):
            for j in range(divisions - i):
                p = lambda i_, j_: centre + (a - centre) * i_ / divisions + (b - centre) * j_ / divisions  # noqa: E731
                tiles.append((p(i, j), p(i + 1, j), p(i, j + 1)))
                if j < divisions - i - 1:
                    tiles.append((p(i + 1, j), p(i + 1, j + 1), p(i, j + 1)))
    return np.array(tiles)


def line_in_box(point: np.ndarray, direction: np.ndarray, low: np.ndarray, high: np.ndarray) -> np.ndarray:
    """The segment (2 x 3) of the line through ``point`` along ``direction`` inside the box
    (slab clipping); empty (0 x 3) when the line misses it."""
    with np.errstate(divide="ignore", invalid="ignore"):
        t1, t2 = (low - point) / direction, (high - point) / direction
    along = np.abs(direction) > 1e-12
    t_in = np.max(np.where(along, np.minimum(t1, t2), -np.inf))
    t_out = np.min(np.where(along, np.maximum(t1, t2), np.inf))
    inside = np.all(along | ((low <= point) & (point <= high)))
    return np.array([point + t_in * direction, point + t_out * direction]) if inside and t_in < t_out else np.zeros((0, 3))


def _patch_box(s: Symmetry, vertices: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The bounding box of the symmetry's source and target patches, enlarged by 10 % (and by
    1 % of the mesh's size, for a flat patch): the region where the symmetry holds, to which
    its plane and axis are clipped, so that a partial symmetry's plane stays at its part."""
    patch = vertices[np.concatenate([s.source_vertices, s.target_vertices])]
    if not len(patch):
        patch = vertices
    low, high = patch.min(axis=0), patch.max(axis=0)
    margin = 0.1 * (high - low) + 0.01 * float(np.ptp(vertices, axis=0).max())
    return low - margin, high + margin


def _draw_elements(ax, s: Symmetry, colour, vertices: np.ndarray) -> list[np.ndarray]:
    """Draws the axis line and the translation arrow of ``s`` (over the surface) and returns
    the translucent tiles of its mirror plane, to be depth-sorted with the surface."""
    low, high = _patch_box(s, vertices)
    if s.axis is not None and s.kind in AXIS_KINDS:
        segment = line_in_box(s.axis.point, s.axis.direction, low, high)
        if len(segment):
            ax.add_collection3d(Line3DCollection([segment], colors=[colour], linewidths=2.5,
                                                 linestyles="--", zorder=5))
    if s.translation is not None:
        start = vertices[s.source_vertices].mean(axis=0) if len(s.source_vertices) else (low + high) / 2
        ax.quiver(*start, *s.translation, color=colour, linewidth=2.5, arrow_length_ratio=0.15, zorder=6)
    if s.kind == "spherical patch":
        ax.scatter(*s.center, color=colour, s=60, marker="x", zorder=6)
    if s.plane is not None and s.kind in MIRROR_KINDS:
        polygon = plane_in_box(s.plane.normal, s.plane.offset, low, high)
        if len(polygon):
            ax.add_collection3d(Line3DCollection([np.vstack([polygon, polygon[:1]])], colors=[colour],
                                                 linewidths=1.5, zorder=5))
            return [_tiles(polygon)]
    return []


def _patch_handles(result: SymmetryResult, shown: int) -> list:
    handles = [Patch(color=PALETTE[s.index], label=symmetry_label(s)) for s in result.symmetries[:shown]]
    if len(result.symmetries) > shown:
        handles.append(Patch(color=(0.75, 0.75, 0.75), label=f"{len(result.symmetries) - shown} more (grey)"))
    return handles


def _cloud_patches_picture(drawn: _DrawnMesh, result: SymmetryResult, shown: int, path: str,
                           view: tuple[float, float]) -> Picture:
    """patches_picture for a point cloud: its points as dots in their patch's colour."""
    symmetry = _vertex_symmetry(result, shown)[drawn.input_vertex]
    rgb = np.array(PALETTE + [(0.75, 0.75, 0.75)])[np.where(symmetry < 0, COLOURED_SYMMETRIES, symmetry)]
    fig = _new_figure(f"Symmetric patches of a point cloud ({_count(result)})")
    ax = _mesh_axes(fig, drawn.vertices, view)
    ax.scatter(*drawn.vertices.T, c=rgb, s=1.5, depthshade=False, linewidths=0)
    legend = fig.legend(handles=_patch_handles(result, shown), loc="center left", bbox_to_anchor=(0.66, 0.5),
                        fontsize=9, title="patches: source and target")
    return _save(fig, path, _plot_box(ax), [t.get_text() for t in legend.get_texts()])


def patches_picture(mesh: MeshInput, result: SymmetryResult, path: str, *,
                    view: tuple[float, float] = (20.0, -60.0)) -> Picture:
    """The mesh coloured by patch: the source and target patch of each of the first
    COLOURED_SYMMETRIES symmetries in one colour (a vertex in several, in the most
    significant one's), the rest grey; each symmetry's mirror plane as a translucent polygon
    clipped to the bounding box of its two patches (enlarged by 10 %), its rotation axis as a dashed line, its
    translation (or slide) as an arrow from the source patch's centroid, in the same colour;
    a legend gives each one's kind, angle and source area."""
    drawn = _drawn_mesh(mesh, result)
    shown = min(len(result.symmetries), COLOURED_SYMMETRIES)
    if len(drawn.faces) == 0:
        return _cloud_patches_picture(drawn, result, shown, path, view)
    face_symmetry = drawn.face_values(_vertex_symmetry(result, shown))
    face_symmetry = np.where(face_symmetry < 0, COLOURED_SYMMETRIES, face_symmetry).min(axis=1)
    rgb = np.array(PALETTE + [(0.75, 0.75, 0.75)])[face_symmetry]
    triangles = drawn.vertices[drawn.faces]
    fig = _new_figure(f"Symmetric patches ({_count(result)})")
    ax = _mesh_axes(fig, drawn.vertices, view)
    rgba, tiles = [np.hstack([_shaded(rgb, triangles, view), np.ones((len(rgb), 1))])], [triangles]
    for s in result.symmetries[:shown]:
        for t in _draw_elements(ax, s, PALETTE[s.index], drawn.input_vertices):
            tiles.append(t)
            rgba.append(np.tile((*PALETTE[s.index], 0.28), (len(t), 1)))
    _add_surface(ax, np.concatenate(tiles), np.concatenate(rgba))
    handles = _patch_handles(result, shown)
    kinds = {s.kind for s in result.symmetries[:shown]}
    if kinds & set(AXIS_KINDS):
        handles.append(Line2D([], [], color="k", ls="--", label="dashed: rotation axis"))
    if kinds & set(MIRROR_KINDS):
        handles.append(Patch(facecolor=(0, 0, 0, 0.28), label="translucent: mirror plane"))
    legend = fig.legend(handles=handles, loc="center left", bbox_to_anchor=(0.66, 0.5), fontsize=9,
                        title="patches: source and target")
    return _save(fig, path, _plot_box(ax), [t.get_text() for t in legend.get_texts()])


def reduction_picture(reduced: tuple[np.ndarray, np.ndarray], instances: Sequence[tuple[np.ndarray, np.ndarray]],
                      path: str, *, view: tuple[float, float] = (20.0, -60.0)) -> Picture:
    """The model rebuilt from a symmetry-based reduction (generate_symmetry_based_reduction):
    the reduced mesh ``reduced`` = (vertices, faces) in the first colour, and each instance,
    (its 4x4 matrix, the reduced mesh's faces it copies), transformed into place in grey,
    lighter the later it comes; the legend gives the share of faces kept."""
    V, F = (np.asarray(a) for a in reduced)
    pieces = [(V, F, np.asarray(PALETTE[0]))]
    for k, (M, faces) in enumerate(instances):
        M = np.asarray(M, dtype=float)
        grey = 0.55 + 0.3 * k / max(len(instances) - 1, 1)
        pieces.append((V @ M[:3, :3].T + M[:3, 3], F[np.asarray(faces, dtype=np.int64)], np.full(3, grey)))
    copied = sum(len(piece[1]) for piece in pieces[1:])
    total = len(F) + copied
    tiles, rgb = [], []
    for W, G, colour in pieces:
        # Each piece simplified on its own to its share of MAX_DRAWN_FACES: drawing every face
        # of a large model takes minutes, and dropping faces would draw holes.
        share = max(int(MAX_DRAWN_FACES * len(G) / total), 4)
        if len(G) > share:
            ms = _private_meshset((W, G))
            ms.meshing_decimation_quadric_edge_collapse(targetfacenum=share, preservenormal=True)
            W, G = ms.current_mesh().vertex_matrix(), ms.current_mesh().face_matrix()
        tiles.append(W[G])
        rgb.append(np.tile(colour, (len(G), 1)))
    triangles, rgb = np.concatenate(tiles), np.concatenate(rgb)
    instances_text = f"{len(instances)} instance" + ("" if len(instances) == 1 else "s")
    fig = _new_figure(f"Symmetry-based reduction: {len(F)} faces kept, {instances_text}")
    ax = _mesh_axes(fig, triangles.reshape(-1, 3), view)
    _add_surface(ax, triangles, np.hstack([_shaded(rgb, triangles, view), np.ones((len(rgb), 1))]))
    handles = [Patch(color=PALETTE[0], label=f"kept: {len(F)} faces"),
               Patch(color=(0.7, 0.7, 0.7), label=f"rebuilt by {instances_text} ({copied} faces copied)")]
    legend = fig.legend(handles=handles, loc="center left", bbox_to_anchor=(0.66, 0.5), fontsize=9)
    return _save(fig, path, _plot_box(ax), [t.get_text() for t in legend.get_texts()])


def editing_picture(original: tuple[np.ndarray, np.ndarray], edited: np.ndarray, path: str, *,
                    view: tuple[float, float] = (20.0, -60.0), title: Optional[str] = None) -> Picture:
    """The result of consistent editing (apply_coord_consistent_editing): the mesh with the
    vertices ``edited`` (rows of the original's), each face coloured by how far its vertices
    moved from the ``original`` = (vertices, faces), in percent of the diagonal; unmoved faces
    light grey.  The mesh is drawn as it is (a large one takes a while)."""
    V, F = (np.asarray(a) for a in original)
    W = np.asarray(edited)
    diagonal = float(np.linalg.norm(V.max(axis=0) - V.min(axis=0)))
    moved = 100 * np.linalg.norm(W - V, axis=1)[F].mean(axis=1) / diagonal
    colours = ScalarMappable(norm=Normalize(0, max(float(moved.max()), 1e-12)), cmap="viridis")
    rgb = np.where(moved[:, None] > 0, colours.to_rgba(moved)[:, :3], 0.82)
    triangles = W[F]
    fig = _new_figure(title or "Consistent editing: how far each face moved")
    ax = _mesh_axes(fig, W, view)
    _add_surface(ax, triangles, np.hstack([_shaded(rgb, triangles, view), np.ones((len(rgb), 1))]))
    bar = fig.colorbar(colours, cax=fig.add_axes((0.72, 0.2, 0.03, 0.6)))
    bar.set_label("displacement, % of the bounding-box diagonal")
    legend = fig.legend(handles=[Patch(color=(0.82, 0.82, 0.82), label="not moved")],
                        loc="lower left", bbox_to_anchor=(0.69, 0.06), frameon=False)
    return _save(fig, path, _plot_box(ax), [t.get_text() for t in legend.get_texts()])


def segmentation_picture(first: tuple[np.ndarray, np.ndarray], second: tuple[np.ndarray, np.ndarray],
                         first_ids: np.ndarray, second_ids: np.ndarray, path: str, *,
                         view: tuple[float, float] = (20.0, -60.0), title: Optional[str] = None) -> Picture:
    """The rigid segments between two poses (compute_rigid_segments_between_meshes): the
    ``first`` pose = (vertices, faces) on the left and the ``second`` beside it, each face in
    the colour of its vertices' segment (``first_ids``, ``second_ids``: the per-vertex
    segment_id of either mesh), light grey where no segment holds.  A pose of more than half
    MAX_DRAWN_FACES faces is drawn simplified, each drawn vertex coloured as the nearest one."""
    poses = []
    for (V, F), ids in ((first, first_ids), (second, second_ids)):
        V, F, ids = np.asarray(V, dtype=float), np.asarray(F, dtype=np.int64), np.asarray(ids, dtype=np.int64)
        if len(F) > MAX_DRAWN_FACES // 2:
            ms = _private_meshset((V, F))
            ms.meshing_decimation_quadric_edge_collapse(targetfacenum=MAX_DRAWN_FACES // 2, preservenormal=True)
            W, F = ms.current_mesh().vertex_matrix().copy(), ms.current_mesh().face_matrix().copy()
            ids = ids[cKDTree(V).query(W)[1]]
            V = W
        poses.append((V, F, ids))
    # The second pose beside the first, to the right as the view looks.
    elevation, azimuth = np.radians(view)
    right = np.array([-np.sin(azimuth), np.cos(azimuth), 0.0])
    (V1, F1, ids1), (V2, F2, ids2) = poses
    width = float(np.ptp(V1 @ right)) + float(np.ptp(V2 @ right))
    shift = right * (float((V1 @ right).max() - (V2 @ right).min()) + 0.15 * width)
    triangles = np.concatenate([V1[F1], (V2 + shift)[F2]])
    labels = np.concatenate([ids1[F1], ids2[F2]])
    # A face takes the segment of most of its corners (a corner's own when all differ).
    face_ids = np.where(labels[:, 1] == labels[:, 2], labels[:, 1], labels[:, 0])
    segments = int(max(ids1.max(initial=-1), ids2.max(initial=-1))) + 1
    palette = np.array([PALETTE[k % len(PALETTE)] for k in range(max(segments, 1))])
    rgb = np.where(face_ids[:, None] >= 0, palette[np.maximum(face_ids, 0)], 0.82)
    fig = _new_figure(title or f"Rigid segments between two poses: {segments} parts")
    ax = _mesh_axes(fig, triangles.reshape(-1, 3), view)
    _add_surface(ax, triangles, np.hstack([_shaded(rgb, triangles, view), np.ones((len(rgb), 1))]))
    handles = [Patch(color=palette[k], label=f"segment {k}: {int(np.sum(first_ids == k))} + "
                                             f"{int(np.sum(second_ids == k))} vertices") for k in range(segments)]
    handles.append(Patch(color=(0.82, 0.82, 0.82), label="no rigid part"))
    legend = fig.legend(handles=handles, loc="center left", bbox_to_anchor=(0.66, 0.5), fontsize=9,
                        title="first pose + second pose")
    return _save(fig, path, _plot_box(ax), [t.get_text() for t in legend.get_texts()])


# --- c. transformation space: the detector's own Γ (§3) ----------------------------------------------

def detector_transformation_space(mesh: MeshInput, result: SymmetryResult) -> dict[str, np.ndarray]:
    """The detector's own transformation space Γ for this result: the one detect(...,
    engine="core") kept on the result, else the core run again on the mesh with the result's
    parameters and seed (the same run, so the same Γ).  A dict: ``points`` (n x 13, each pair's
    transformation in Γ's coordinates, where Euclidean distance is Γ's metric in fractions
    of the diagonal), ``improper`` (n, reflections), ``modes``, ``mode_heights`` and
    ``mode_improper`` (the clusters of the first mean shift), ``symmetries`` (the reported
    ones, in result order)."""
    if result.transformation_space is not None:
        return result.transformation_space
    return detect(mesh, engine="core", **result.parameters).transformation_space


def _draw_sheet(ax, fig, points: np.ndarray, modes: np.ndarray, heights: np.ndarray, stars: np.ndarray,
                starred: list[Symmetry], colour_bar_box) -> list:
    """One sheet of Γ on `ax`: its points' density (hexagonal bins, log scale), its 30 highest
    modes as circles sized by their votes, the reported symmetries on it as stars in their
    patches_picture colours, all projected together by classical_mds."""
    handles = []
    if len(points) + len(modes) + len(stars) < 3:
        ax.text(0.5, 0.5, "no points on this sheet", ha="center", transform=ax.transAxes)
        return handles
    xy = classical_mds(np.vstack([points, modes, stars]))
    pts, mds, sts = xy[:len(points)], xy[len(points):len(points) + len(modes)], xy[len(points) + len(modes):]
    if len(pts):
        bins = ax.hexbin(pts[:, 0], pts[:, 1], gridsize=40, bins="log", mincnt=1, cmap="Greys")
        fig.colorbar(bins, cax=fig.add_axes(colour_bar_box), label="points of Γ per bin")
    if len(mds):
        ax.scatter(mds[:, 0], mds[:, 1], s=20 + 200 * heights / max(1, heights.max()), facecolors="none",
                   edgecolors="#b2182b", linewidths=1.2, zorder=2)
    for s, (x, y) in zip(starred, sts):
        handles.append(ax.scatter([x], [y], marker="*", s=320, color=PALETTE[s.index % COLOURED_SYMMETRIES],
                                  edgecolors="black", label=symmetry_label(s), zorder=3))
    ax.set_xlabel("MDS coordinate 1 (fraction of the diagonal)")
    ax.set_ylabel("MDS coordinate 2")
    return handles


def transformation_space_picture(mesh: MeshInput, result: SymmetryResult, path: str, *,
                                 max_points: int = 3000, shown_modes: int = 30, seed: int = 0) -> Picture:
    """The paper's Figure 7(b) from the detector's own Γ (detector_transformation_space): its
    two sheets side by side, rotations and translations (proper) and reflections (improper),
    each projected to 2-D by classical multidimensional scaling of Γ's metric; at most
    ``max_points`` points drawn at random, their density as hexagonal bins; the
    ``shown_modes`` modes of mean shift with most votes as red circles sized by their votes;
    the reported discrete symmetries as stars in their patches_picture colours.  A cluster
    of votes at a star is the evidence for that symmetry."""
    gamma = detector_transformation_space(mesh, result)
    points, improper = np.asarray(gamma["points"]), np.asarray(gamma["improper"], dtype=bool)
    rng = np.random.default_rng(seed)
    drawn = np.sort(rng.choice(len(points), size=min(max_points, len(points)), replace=False))
    modes, heights = np.asarray(gamma["modes"]).reshape(-1, 13), np.asarray(gamma["mode_heights"])
    reported = np.asarray(gamma["symmetries"]).reshape(-1, 13)
    fig = _new_figure("The detector's transformation space Γ, projected to 2-D (Figure 7(b))")
    handles, boxes = [], []
    for column, (reflections, title) in enumerate(((False, "rotations and translations"), (True, "reflections"))):
        left = 0.07 + 0.34 * column
        ax = fig.add_axes((left, 0.17, 0.21, 0.66))
        ax.set_title(title, fontsize=11)
        sheet_modes = np.flatnonzero(np.asarray(gamma["mode_improper"], dtype=bool) == reflections)
        sheet_modes = sheet_modes[np.argsort(-heights[sheet_modes], kind="stable")][:shown_modes]
        starred = [s for s in result.symmetries
                   if s.kind not in FAMILY_KINDS.values() and s.is_reflection == reflections]
        handles += _draw_sheet(ax, fig, points[drawn][improper[drawn] == reflections], modes[sheet_modes],
                               heights[sheet_modes], reported[[s.index for s in starred]].reshape(-1, 13), starred,
                               (left + 0.22, 0.17, 0.01, 0.66))
        if column:
            ax.set_ylabel("")  # the left sheet's colour bar label stands there
        boxes.append(_plot_box(ax))
    fig.text(0.02, 0.02, f"{len(points)} points of Γ ({len(drawn)} drawn), {len(modes)} modes of mean shift "
             f"({shown_modes} with most votes per sheet drawn as circles); the detector's own pairs, "
             "with Γ's metric (§3).", fontsize=8, wrap=True)
    legend = fig.legend(handles=handles, loc="upper left", bbox_to_anchor=(0.705, 0.83), fontsize=8,
                        title="reported symmetries" if handles else "no discrete symmetry reported")
    box = (min(b[0] for b in boxes), min(b[1] for b in boxes), max(b[2] for b in boxes), max(b[3] for b in boxes))
    return _save(fig, path, box, [t.get_text() for t in legend.get_texts()])


def classical_mds(points: np.ndarray, dimensions: int = 2) -> np.ndarray:
    """Classical (Torgerson) metric multidimensional scaling of the Euclidean distances
    between ``points``: the top eigenvectors of the double-centred matrix of squared
    distances, B = -J D2 J / 2, scaled by the roots of their eigenvalues.  For Euclidean
    distances B is the Gram matrix X X^T of the centred points (Gower 1966), whose top
    eigenvectors so scaled are X times its top right singular vectors; that is computed
    here, from an n x 13 matrix instead of the n x n one, in milliseconds, and without the
    multi-threaded n x n eigensolver that crawls on a machine shared with other work."""
    centred = points - points.mean(axis=0)
    _, _, right = np.linalg.svd(centred, full_matrices=False)
    return centred @ right[:dimensions].T


# --- d. the report ----------------------------------------------------------------------------------

#: the pictures of a report: file name, function, caption
REPORT_PICTURES = (
    ("deviation.png", deviation_picture,
     "Signed deviation from perfect symmetry, in percent of the bounding-box diagonal (the paper's Figure 1)."),
    ("patches.png", patches_picture,
     "Source and target patch of each symmetry in one colour, with its mirror plane, rotation axis or "
     "translation."),
    ("transformation_space.png", transformation_space_picture,
     "The detector's transformation space Γ, its two sheets projected to 2-D by multidimensional scaling "
     "(the paper's Figure 7(b)): the density of the pairs' votes, the modes of mean shift (circles) and the "
     "reported symmetries (stars)."),
)


def _geometry_text(s: Symmetry) -> str:
    """The plane, axis, centre or translation of a symmetry, in the mesh's units."""
    def v(x) -> str:
        return "(" + ", ".join(f"{c:.4g}" for c in x) + ")"
    parts = []
    if s.plane is not None:
        parts.append(f"plane n = {v(s.plane.normal)}, n·x = {s.plane.offset:.4g}")
    if s.axis is not None:
        parts.append(f"axis through {v(s.axis.point)} along {v(s.axis.direction)}")
    if s.center is not None:
        parts.append(f"centre {v(s.center)}")
    if s.translation is not None:
        parts.append(f"translation {v(s.translation)}")
    return "; ".join(parts) or "-"


def _symmetry_rows(result: SymmetryResult) -> str:
    rows = []
    for s in result.symmetries:
        angle = "" if s.angle_degrees is None else f"{s.angle_degrees:.2f}" + (f" ({s.order}-fold)" if s.order else "")
        cells = (s.index, s.kind, _geometry_text(s), angle, f"{100 * s.source_area:.2f}",
                 f"{100 * s.rms_error:.4f}", s.support)
        rows.append("<tr>" + "".join(f"<td>{html.escape(str(c))}</td>" for c in cells) + "</tr>")
    return "\n".join(rows)


def report_html(mesh: MeshInput, result: SymmetryResult, outdir: str) -> str:
    """Writes ``outdir/report.html``, with the three pictures beside it (REPORT_PICTURES,
    linked relatively, so the folder can be moved or published as it is), a table of the
    symmetries (kind, plane or axis, angle, source area in % of the surface, RMS deviation in
    % of the diagonal, supporting pairs) and the parameters detect ran with.  Returns its path."""
    os.makedirs(outdir, exist_ok=True)
    figures = []
    for name, draw, caption in REPORT_PICTURES:
        draw(mesh, result, os.path.join(outdir, name))
        figures.append(f'<figure><img src="{name}" alt="{html.escape(caption)}">'
                       f"<figcaption>{html.escape(caption)}</figcaption></figure>")
    title = os.path.basename(os.fspath(mesh)) if isinstance(mesh, (str, os.PathLike)) else "mesh"
    parameters = "".join(f"<tr><td>{html.escape(k)}</td><td>{html.escape(repr(v))}</td></tr>"
                         for k, v in result.parameters.items())
    page = _REPORT_TEMPLATE.format(
        title=html.escape(f"Symmetries of {title}"), count=html.escape(_count(result)),
        vertices=result.vertex_count, diagonal=result.diagonal, figures="\n".join(figures),
        rows=_symmetry_rows(result), parameters=parameters)
    path = os.path.join(outdir, "report.html")
    with open(path, "w", encoding="utf-8") as f:
        f.write(page)
    return path


_REPORT_TEMPLATE = """<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>{title}</title>
<style>body{{font-family:sans-serif;max-width:1250px;margin:2em auto}} img{{max-width:100%}}
table{{border-collapse:collapse}} td,th{{border:1px solid #bbb;padding:2px 8px;text-align:left}}</style>
</head><body>
<h1>{title}</h1>
<p>{count}; {vertices} vertices, bounding-box diagonal {diagonal:.6g} (mesh units).</p>
<h2>Symmetries</h2>
<table>
<tr><th>#</th><th>kind</th><th>plane / axis</th><th>angle (°)</th><th>source area (% of surface)</th>
<th>RMS deviation (% of diagonal)</th><th>support (pairs)</th></tr>
{rows}
</table>
<h2>Pictures</h2>
{figures}
<h2>Parameters</h2>
<table><tr><th>parameter</th><th>value</th></tr>{parameters}</table>
</body></html>
"""


# --- e. symmetries found against |P'| (the paper's Figure 5, left) ------------------------------

def sample_size_curve(mesh: MeshInput, path: str, sizes: Sequence[int] = (100, 200, 500, 1000, 2000, 5000),
                      **parameters: Any) -> tuple[Picture, list[tuple[int, int]]]:
    """Runs the detector once per size n' of the paired subset P' (``pair_sample_count``;
    the compiled core, the other ``parameters`` as given to detect) and plots the number of
    symmetries found against n', with the automatic n' of the Appendix's bound marked: the
    paper's Figure 5, left, which shows the count levelling off once P' holds enough samples
    of the smallest patch.  Returns the Picture and the (n', count) points; it takes as long
    as len(sizes) + 1 detections."""
    points = []
    for size in sizes:
        found = detect(mesh, engine="core", **{**parameters, "pair_sample_count": int(size)})
        points.append((int(found.work["pair_sample_count_used"]), len(found.symmetries)))
    automatic = detect(mesh, engine="core", **{**parameters, "pair_sample_count": 0})
    chosen = (int(automatic.work["pair_sample_count_used"]), len(automatic.symmetries))
    fig = _new_figure("Symmetries found against the size of P' (Figure 5)")
    ax = fig.add_axes((0.1, 0.12, 0.85, 0.76))
    ax.plot([p[0] for p in points], [p[1] for p in points], "o-", color="#2166ac", label="fixed n'")
    ax.plot([chosen[0]], [chosen[1]], "s", color="#b2182b", markersize=10,
            label=f"automatic n' = {chosen[0]} (Appendix, Equation 1)")
    ax.set_xscale("log")
    ax.set_xlabel("n' = |P'|, samples paired against all (log scale)")
    ax.set_ylabel("symmetries reported")
    ax.yaxis.get_major_locator().set_params(integer=True)
    ax.grid(True, alpha=0.3)
    legend = ax.legend(loc="lower right")
    return _save(fig, path, _plot_box(ax), [t.get_text() for t in legend.get_texts()]), points + [chosen]
