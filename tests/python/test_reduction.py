"""Symmetry-based reduction (generate_symmetry_based_reduction, issue 9; the paper's Figure
7(c)): detection, then the faces that are copies of others removed, with the instances that
rebuild them.

Ground truth by construction: the row scene of tests/scenes.py is four re-tessellated copies
of one part, each the first translated by k steps (planted); the wingnut is six blades about
one axis.  The model is rebuilt here from the reduced layer and the returned instances with
numpy, not by the plugin, and compared with the input by dense surface samples and a kd-tree:
every point of either within the verification tolerance of the other."""
import json
import os
import sys

import numpy as np
import pymeshlab
import pytest

import meshlab_symmetry

from conftest import LIGHT_RUN, assert_mesh_unchanged, mesh_snapshot, mirror_symmetric_mesh

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenes  # noqa: E402
from reduction_oracle import farthest, instances_of, rebuilt, two_sided  # noqa: E402

TOLERANCE = 0.01  # the filter's default verification tolerance, fraction of the diagonal


def reduce(V, F, **parameters):
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(V, F))
    out = ms.generate_symmetry_based_reduction(**parameters)
    return ms, out


@pytest.fixture(scope="module")
def row():
    scene = scenes.make_scene("row", 0)
    V, F = scene.vertices, scene.faces
    path = os.path.join(os.environ.get("TMPDIR", "/tmp"), f"reduction_instances_{os.getpid()}.json")
    ms, out = reduce(V, F, instances_file=path, create_reconstruction_layer=True, **scene.filter_params)
    with open(path) as f:
        written = json.load(f)
    os.remove(path)
    return scene, ms, out, written


@pytest.mark.long_under_sanitizers  # one default detection of a 34,000-face scene
def test_a_row_of_four_copies_is_one_copy_and_three_translations(row):
    scene, ms, out, _ = row
    V, F = scene.vertices, scene.faces
    diagonal = scenes.bbox_diagonal(V)
    # One copy is a quarter of the faces; the copies are tessellated apart, so allow for a
    # coarser or finer one kept and for the seams where instances meet.
    assert out["size_ratio"] < 0.35, out
    reduced = ms.mesh(out["reduced_layer_id"])
    assert reduced.face_number() == out["reduced_faces"]
    assert ms.current_mesh_id() == out["reduced_layer_id"]
    Vr, Fr = reduced.vertex_matrix(), reduced.face_matrix()
    instances = instances_of(out)
    # Each instance is a planted translation by k steps (k = 1, 2, 3) or its inverse, whichever
    # copy was kept, and three different ones rebuild the three copies removed.
    planted = [p.transform for p in scene.symmetries if p.family == "row" and p.source_part == "copy0"]
    planted += [np.linalg.inv(T) for T in planted]
    matched = set()
    for M, _ in instances:
        errors = [np.abs(M[:3, :3] - T[:3, :3]).max() + np.linalg.norm(M[:3, 3] - T[:3, 3]) / diagonal
                  for T in planted]
        assert min(errors) < TOLERANCE, (M, errors)
        matched.add(int(np.argmin(errors)))
    assert len(matched) == 3
    # The independent reconstruction is the input, within the tolerance both ways...
    rng = np.random.default_rng(0)
    W, G = rebuilt(Vr, Fr, instances)
    assert two_sided(V, F, W, G, rng) / diagonal < TOLERANCE
    # ...which the reduced mesh alone is far from (the check can fail).
    assert farthest(V, F, Vr, Fr, rng) / diagonal > 0.2
    assert out["reconstruction_error"] < TOLERANCE
    # The plugin's own reconstruction layer is that same model.
    layer = ms.mesh(out["reconstruction_layer_id"])
    assert layer.face_number() == len(G)
    np.testing.assert_allclose(np.sort(layer.vertex_matrix(), axis=0), np.sort(W, axis=0), atol=1e-9 * diagonal)


@pytest.mark.long_under_sanitizers  # reads the run of the test above
def test_the_instances_file_holds_the_returned_instances_and_the_input_is_unchanged(row):
    scene, ms, out, written = row
    assert written["input_faces"] == len(scene.faces)
    assert written["reduced_faces"] == out["reduced_faces"]
    assert written["size_ratio"] == pytest.approx(out["size_ratio"])
    assert len(written["instances"]) == out["instance_count"]
    for (M, faces), w in zip(instances_of(out), written["instances"]):
        np.testing.assert_allclose(np.reshape(w["transform"], (4, 4)), M)
        assert w["faces"] == faces.tolist()
        assert w["symmetries"] and all(1 <= abs(k) <= out["symmetry_count"] for k in w["symmetries"])
    assert sum(w["removed_faces"] for w in written["instances"]) == len(scene.faces) - out["reduced_faces"]
    ms.set_current_mesh(0)
    np.testing.assert_array_equal(ms.current_mesh().vertex_matrix(), scene.vertices)
    np.testing.assert_array_equal(ms.current_mesh().face_matrix(), scene.faces)


@pytest.mark.long_under_sanitizers  # one default detection of a 36,000-face scene
def test_six_blades_are_rebuilt_from_one_by_turns_of_one_rotation():
    scene = scenes.make_scene("wingnut", 0)
    V, F = scene.vertices, scene.faces
    ms, out = reduce(V, F, **scene.filter_params)
    # One blade and a sixth of the hub, plus seams: well under a quarter.
    assert out["size_ratio"] < 0.25, out
    reduced = ms.mesh(out["reduced_layer_id"])
    W, G = rebuilt(reduced.vertex_matrix(), reduced.face_matrix(), instances_of(out))
    assert two_sided(V, F, W, G, np.random.default_rng(1)) / scenes.bbox_diagonal(V) < TOLERANCE


def test_a_mirror_keeps_one_side_and_a_shape_without_copies_is_kept_whole(tmp_path):
    # The bumpy sphere's one symmetry is the mirror x -> -x: one side goes, and the mirrored
    # instance rebuilds it.
    V, F = mirror_symmetric_mesh(3)
    ms, out = reduce(V, F, **LIGHT_RUN)
    assert out["symmetry_count"] >= 1 and 0.4 < out["size_ratio"] < 0.65, out
    (M, _), = instances_of(out)
    np.testing.assert_allclose(M[:3, :3], np.diag([-1.0, 1.0, 1.0]), atol=0.05)
    reduced = ms.mesh(out["reduced_layer_id"])
    W, G = rebuilt(reduced.vertex_matrix(), reduced.face_matrix(), instances_of(out))
    assert two_sided(V, F, W, G, np.random.default_rng(2)) / scenes.bbox_diagonal(V) < TOLERANCE
    # Its picture: the kept side and the one instance, counted in the legend.
    picture = meshlab_symmetry.reduction_picture((reduced.vertex_matrix(), reduced.face_matrix()),
                                                 instances_of(out), str(tmp_path / "reduction.png"))
    assert os.path.getsize(picture.path) > 10000
    assert picture.legend == [f"kept: {out['reduced_faces']} faces",
                              f"rebuilt by 1 instance ({len(instances_of(out)[0][1])} faces copied)"]
    # Among translations it has no symmetry: nothing is removed.
    ms, out = reduce(V, F, **LIGHT_RUN, transformation_group=3)
    assert out["symmetry_count"] == 0
    assert out["size_ratio"] == 1 and out["instance_count"] == 0 and out["reconstruction_error"] == 0
    assert ms.current_mesh().face_number() == len(F)


def test_an_instances_file_that_cannot_be_written_is_an_error_and_nothing_is_added(tmp_path):
    V, F = mirror_symmetric_mesh(3)
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(V, F))
    before = mesh_snapshot(ms)
    with pytest.raises(pymeshlab.PyMeshLabException, match="could not write the instances file"):
        ms.generate_symmetry_based_reduction(instances_file=str(tmp_path / "no" / "such" / "dir.json"), **LIGHT_RUN)
    assert_mesh_unchanged(ms, before)
