"""Consistent editing (apply_coord_consistent_editing, issue 9; the paper's Figure 7(d)): an
edit of one copy carried to every copy a detected symmetry relates it to.

Ground truth by construction: the row scene of tests/scenes.py is four re-tessellated copies
of one part, copy k the first translated by k steps (planted).  A smooth bump, an analytic
displacement field around a point of copy 0, is applied to copy 0 only; copy k must receive
the same field carried by its planted transform: at a vertex q, the field at T_k⁻¹(q) turned
by T_k."""
import os
import sys

import numpy as np
import pymeshlab
import pytest

import meshlab_symmetry
from conftest import LIGHT_RUN, assert_mesh_unchanged, mesh_snapshot, mirror_symmetric_mesh

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenes  # noqa: E402
from editing_oracle import bump, expected_on_copy, row_edit  # noqa: E402


def two_layers(original, edited):
    """A MeshSet with the original (id 0) and the edited copy (id 1, current)."""
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(*original), "original")
    ms.add_mesh(pymeshlab.Mesh(*edited), "edited")
    return ms


@pytest.mark.long_under_sanitizers  # one default detection of a 34,000-face scene
def test_a_bump_on_one_copy_of_a_row_reaches_every_copy():
    scene = scenes.make_scene("row", 0)
    V, F = scene.vertices, scene.faces
    first, end = scene.parts["copy0"][:2]
    edited, centre, push, radius = row_edit(scene)
    ms = two_layers((V, F), (edited, F))

    out = ms.apply_coord_consistent_editing(original_mesh=0, **scene.filter_params)

    result = ms.current_mesh().vertex_matrix()
    height = np.linalg.norm(push)
    moved_by_user = np.linalg.norm(edited - V, axis=1)
    # Moves below 1e-7 of the diagonal are rounding, not an edit (EditingOptions::min_edit).
    assert (moved_by_user > 1e-6 * scene.diagonal).sum() <= out["edited_vertices"] <= (moved_by_user > 0).sum()
    np.testing.assert_array_equal(result[first:end], edited[first:end])  # copy 0 as the user left it
    for k in (1, 2, 3):
        rows, expected, back = expected_on_copy(scene, k, centre, push, radius)
        Q = V[rows]
        error = np.linalg.norm(result[rows] - Q - expected, axis=1)
        moved = np.linalg.norm(expected, axis=1) > 0.5 * height
        assert moved.sum() > 20, k
        # The copy received the bump: where it is high, within a tenth of its height...
        assert np.median(error[moved]) < 0.1 * height, (k, np.median(error[moved]))
        # ...everywhere within a third (a re-tessellated copy lies up to 0.4 % of the diagonal
        # off the planted image, and the bump is steep at its flank)...
        assert error.max() < 0.35 * height, (k, error.max())
        # ...and away from it nothing moved.
        far = np.linalg.norm(back - centre, axis=1) > 1.5 * radius
        assert np.abs(result[rows][far] - Q[far]).max() == 0
    # The original is not changed.
    np.testing.assert_array_equal(ms.mesh(0).vertex_matrix(), V)


def test_a_mirrored_edit_and_refusals_leave_the_meshes_unchanged(tmp_path):
    V, F = mirror_symmetric_mesh(3)
    diagonal = np.linalg.norm(V.max(axis=0) - V.min(axis=0))
    centre = V[np.argmax(V[:, 0])]
    push = np.array([0.03, 0.01, 0.0]) * diagonal
    edited = V + bump(V, centre, push, 0.25 * diagonal)
    ms = two_layers((V, F), (edited, F))
    out = ms.apply_coord_consistent_editing(original_mesh=0, **LIGHT_RUN)
    result = ms.current_mesh().vertex_matrix()
    mirrored = np.array([-1.0, 1.0, 1.0])
    expected = V + bump(V, centre * mirrored, push * mirrored, 0.25 * diagonal)
    other_side = V[:, 0] < 0
    assert out["carried_vertices"] > 0
    error = np.linalg.norm(result[other_side] - expected[other_side], axis=1)
    assert np.median(error[np.linalg.norm(expected - V, axis=1)[other_side] > 0.5 * np.linalg.norm(push)]) \
        < 0.15 * np.linalg.norm(push)
    picture = meshlab_symmetry.editing_picture((V, F), result, str(tmp_path / "editing.png"))
    assert os.path.getsize(picture.path) > 10000 and picture.legend == ["not moved"]

    # Refused, each with a sentence, nothing changed: no edit, the same mesh twice, a remeshed copy.
    for make, said in (((V, F), "does not differ from the original"),
                       (None, "both name the same mesh"),
                       ((V[:-1], F[(F < len(V) - 1).all(axis=1)]), "not a remeshed copy")):
        ms = two_layers((V, F), make if make is not None else (edited, F))
        before = mesh_snapshot(ms)
        with pytest.raises(pymeshlab.PyMeshLabException, match=said):
            ms.apply_coord_consistent_editing(original_mesh=0 if make is not None else 1, **LIGHT_RUN)
        assert_mesh_unchanged(ms, before)
        np.testing.assert_array_equal(ms.mesh(0).vertex_matrix(), V)
