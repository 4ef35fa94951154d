"""Rigid segments between two poses (compute_rigid_segments_between_meshes, issue 9; the
paper's Figure 8): the parts of a shape that moved rigidly from one pose to the other.

Ground truth by construction (tests/two_poses.py): a chain of three different bumpy parts
posed twice, each part with its own planted motion, the second pose re-tessellated, the parts
of each pose fused into one closed surface at their joints.  Every vertex of both poses knows
its part; each part knows its motion."""
import os
import sys

import numpy as np
import pymeshlab
import pytest

import meshlab_symmetry
from conftest import has_vertex_attribute

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import two_poses  # noqa: E402

#: Fewer samples than the defaults (the paper's Figure 8 sampled 1000 points a pose): the
#: parts are a fifth to a half of the surface.  tests/benchmarks/rigid_segmentation.py runs
#: the defaults.
SAMPLES = dict(sample_count=4000, random_seed=0)


def both_poses(poses):
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(poses.first.V, poses.first.F), "first")
    ms.add_mesh(pymeshlab.Mesh(poses.second.V, poses.second.F), "second")
    return ms


@pytest.mark.long_under_sanitizers  # one segmentation of two 9,000- and 13,000-face poses
def test_every_vertex_of_both_poses_is_labelled_with_its_own_part(tmp_path):
    poses = two_poses.make_two_poses(0, fused=True)
    ms = both_poses(poses)
    out = ms.compute_rigid_segments_between_meshes(first_mesh=0, second_mesh=1, **SAMPLES)

    first_ids = ms.mesh(0).vertex_custom_scalar_attribute_array("segment_id")
    second_ids = ms.mesh(1).vertex_custom_scalar_attribute_array("segment_id")
    assert len(first_ids) == len(poses.first.V) and len(second_ids) == len(poses.second.V)
    score = two_poses.score(poses, first_ids, second_ids)
    assert score["parts_found"] == len(two_poses.PARTS)
    assert score["first_right"] >= 0.95 and score["second_right"] >= 0.95, score
    assert out["segment_count"] == len(score["segment_part"])
    # Each segment moves its part as planted (measured over the part's vertices; the skin
    # over a joint is not rigid, and pulls a little).
    transforms = np.asarray(out["segment_transforms"]).reshape(-1, 4, 4)
    for segment, part in score["segment_part"].items():
        assert two_poses.transform_error(poses, part, transforms[segment]) < 0.005, (segment, part)
    # The returned counts are the labels, and the layers hold them.
    counts = np.asarray(out["segment_first_vertex_counts"])
    np.testing.assert_array_equal(counts, [np.sum(first_ids == k) for k in range(out["segment_count"])])
    layer_ids = np.asarray(out["segment_layer_ids"], int)
    assert len(layer_ids) == 2 * out["segment_count"]
    for k in range(out["segment_count"]):
        assert ms.mesh(layer_ids[2 * k]).vertex_number() == counts[k]
        assert ms.mesh(layer_ids[2 * k + 1]).vertex_number() == out["segment_second_vertex_counts"][k]
    assert out["first_labelled_share"] == pytest.approx(np.mean(first_ids >= 0))
    # Segments have colours of their own.
    colours = ms.mesh(0).vertex_color_matrix()
    assert len({tuple(np.round(colours[first_ids == k][0], 3)) for k in range(out["segment_count"])}) == \
        out["segment_count"]
    picture = meshlab_symmetry.segmentation_picture((poses.first.V, poses.first.F), (poses.second.V, poses.second.F),
                                                    first_ids, second_ids, str(tmp_path / "segments.png"))
    assert os.path.getsize(picture.path) > 10000
    assert len(picture.legend) == out["segment_count"] + 1 and picture.legend[-1] == "no rigid part"


def snapshot(ms):
    """Every mesh's positions, colours and whether it has a segment_id, and the layer count."""
    meshes = [ms.mesh(k) for k in range(ms.mesh_number())]
    return (ms.mesh_number(), [(m.vertex_matrix().copy(), m.vertex_color_matrix().copy(),
                                has_vertex_attribute(m, "segment_id")) for m in meshes])


def test_refusals_name_the_mesh_and_leave_both_unchanged():
    poses = two_poses.make_two_poses(0, fused=True)
    ms = both_poses(poses)
    ms.add_mesh(pymeshlab.Mesh(vertex_matrix=poses.second.V), "cloud")
    before = snapshot(ms)
    with pytest.raises(pymeshlab.PyMeshLabException, match="same mesh"):
        ms.compute_rigid_segments_between_meshes(first_mesh=0, second_mesh=0, **SAMPLES)
    with pytest.raises(pymeshlab.PyMeshLabException, match=r"second mesh \(second_mesh\) cannot be segmented.*"
                                                           r"point cloud"):
        ms.compute_rigid_segments_between_meshes(first_mesh=0, second_mesh=2, **SAMPLES)
    with pytest.raises(pymeshlab.PyMeshLabException, match="sample_count"):
        ms.compute_rigid_segments_between_meshes(first_mesh=0, second_mesh=1, sample_count=-5)
    after = snapshot(ms)
    assert after[0] == before[0] == 3
    for (V, C, has_ids), (V0, C0, has_ids0) in zip(after[1], before[1]):
        np.testing.assert_array_equal(V, V0)
        np.testing.assert_array_equal(C, C0)
        assert has_ids == has_ids0 is False
