"""A MeshLab filter script (.mlx) holding the symmetry filter runs headless through pymeshlab
(`load_filter_script` / `apply_filter_script`) with the result of the direct call (issue 7).

The script is written by MeshLab's own serializer (pymeshlab's save_filter_script, the
FilterScript code the GUI's "Save Script" uses), with parameters other than the defaults,
and replayed on a fresh document holding the same mesh: the same deviation per vertex, the
same symmetry per vertex, the same patch layers.  Ground truth: the mesh's only symmetry is
the mirror x -> -x, which both runs must find.
"""
import os
import sys

import numpy as np
import pymeshlab

sys.path.insert(0, os.path.dirname(__file__))
from conftest import has_vertex_attribute, mirror_symmetric_mesh  # noqa: E402

import meshlab_symmetry  # noqa: E402, F401  (loads the plugin)


def _document():
    V, F = mirror_symmetric_mesh(3)
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(V, F), "input")
    return ms


def _state(ms):
    ms.set_current_mesh(0)
    m = ms.current_mesh()
    layers = [ms.mesh(i).vertex_number() for i in range(1, ms.mesh_number())]
    return m.vertex_scalar_array().copy(), m.vertex_custom_scalar_attribute_array("symmetry_id").copy(), layers


def test_saved_filter_script_replays_the_filter(tmp_path):
    direct = _document()
    out = direct.compute_partial_symmetries(transformation_group=2, sample_count=6000, random_seed=3,
                                            verification_tolerance=pymeshlab.PercentageValue(1.5),
                                            create_patch_layers=True)
    assert out["symmetry_count"] >= 1
    T = out["transforms"].reshape(-1, 4, 4)[0]
    assert np.allclose(T[:3, :3], np.diag([-1.0, 1.0, 1.0]), atol=0.02)  # the planted mirror x -> -x
    script = str(tmp_path / "detect.mlx")
    direct.save_filter_script(script)
    text = open(script).read()
    assert 'filter name="Detect Partial and Approximate Symmetries"' in text
    assert 'name="random_seed"' in text and 'value="3"' in text

    replay = _document()
    replay.load_filter_script(script)
    replay.apply_filter_script()
    quality, ids, layers = _state(replay)
    expected_quality, expected_ids, expected_layers = _state(direct)
    assert has_vertex_attribute(replay.mesh(0), "symmetry_id")
    assert layers == expected_layers and len(layers) == 2 * out["symmetry_count"]
    np.testing.assert_array_equal(ids, expected_ids)
    np.testing.assert_allclose(quality, expected_quality, atol=1e-12)
