"""The edit the consistent-editing test and benchmark plant, and what every copy of the row
scene must receive: an analytic displacement field, carried by the planted transforms, sharing
nothing with the plugin."""
import numpy as np


def bump(P, centre, push, radius):
    """The edit: push * (1 - r²/radius²)² within radius of centre, zero beyond."""
    r2 = ((P - centre) ** 2).sum(axis=1) / radius ** 2
    return np.where(r2[:, None] < 1, push[None, :] * np.clip(1 - r2, 0, None)[:, None] ** 2, 0.0)


def row_edit(scene):
    """(edited vertices, centre, push, radius): the row scene with a bump pushed onto the top
    of copy 0 only."""
    first, end = scene.parts["copy0"][:2]
    copy0 = scene.vertices[first:end]
    extent = np.linalg.norm(copy0.max(axis=0) - copy0.min(axis=0))
    centre = copy0[np.argmax(copy0[:, 2])]
    push = np.array([0.3, -0.2, 1.0]) * 0.04 * extent
    radius = 0.35 * extent
    edited = scene.vertices.copy()
    edited[first:end] += bump(copy0, centre, push, radius)
    return edited, centre, push, radius


def expected_on_copy(scene, k, centre, push, radius):
    """(rows of copy k, what its vertices must receive): at q, the bump at T_k⁻¹(q) turned by
    T_k, T_k the planted copy 0 -> copy k; and T_k⁻¹(q) itself."""
    T = next(p.transform for p in scene.symmetries if p.source_part == "copy0" and p.target_part == f"copy{k}")
    a, b = scene.parts[f"copy{k}"][:2]
    back = (scene.vertices[a:b] - T[:3, 3]) @ np.linalg.inv(T[:3, :3]).T
    return slice(a, b), bump(back, centre, push, radius) @ T[:3, :3].T, back
