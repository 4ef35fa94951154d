"""The symmetrization filter (apply_coord_symmetrization, issue 9): detection, then each
approximately symmetric patch pair moved towards its exactly symmetric average.

Ground truth by construction: the bumpy sphere of conftest is symmetric under x -> -x only;
noise along the normal on its x > 0 half makes the mirror approximate, and how symmetric the
shape is, before and after, is measured by the brute-force oracle of the real-model benchmark
(tests/oracle_mirror.py), which shares nothing with the filter: the median distance of the
reflected surface to the surface under the shape's own best mirror plane near x = 0."""
import os
import sys

import numpy as np
import pymeshlab
import pytest

from conftest import mirror_symmetric_mesh, noisy_mirror_mesh as noisy_sphere

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import oracle_mirror  # noqa: E402

LIGHT = dict(transformation_group=2, random_seed=1, sample_count=2000, pair_sample_count=250)


def diagonal(V):
    return float(np.linalg.norm(V.max(axis=0) - V.min(axis=0)))


def oracle_median(V, F):
    """Median residual (fraction of the diagonal) of the shape's own best mirror plane near
    x = 0, by the brute-force oracle (tests/oracle_mirror.py)."""
    return oracle_mirror.residual_near(V, F, [1.0, 0.0, 0.0], 0.0)["median"]


def run(V, F, **parameters):
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(V, F))
    out = ms.apply_coord_symmetrization(**LIGHT, **parameters)
    return ms.current_mesh().vertex_matrix().copy(), out


@pytest.mark.long_under_sanitizers  # the oracle's Python search is most of it
def test_the_approximate_mirror_becomes_nearly_exact():
    V, F = noisy_sphere()
    before = oracle_median(V, F)
    W, out = run(V, F)
    after = oracle_median(W, F)
    assert out["symmetry_count"] >= 1 and out["symmetrized_vertices"] > 0.9 * len(V)
    assert before > 0.0005  # the noise made it approximate
    assert after < 0.2 * before, (before, after)
    assert out["rms_after"] < 0.35 * out["rms_before"], out
    # the shape is kept: no vertex moves further than a few noise levels
    assert np.abs(W - V).max() < 0.01 * diagonal(V)


def test_vertices_in_no_symmetry_do_not_move():
    V, F = noisy_sphere(bump=0.3)
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(V, F))
    ms.compute_partial_symmetries(**LIGHT)
    outside = np.asarray(ms.current_mesh().vertex_custom_scalar_attribute_array("symmetry_id")) < 0
    assert outside.sum() > 20  # the bump has no mirror image
    W, out = run(V, F)
    assert np.array_equal(W[outside], V[outside])
    assert not np.array_equal(W[~outside], V[~outside])


def test_strength_zero_and_an_exact_mirror_change_nothing():
    V, F = noisy_sphere()
    W, out = run(V, F, strength=0.0)
    assert np.array_equal(W, V) and out["symmetrized_vertices"] == 0
    assert out["rms_after"] == pytest.approx(out["rms_before"])
    exact, F = mirror_symmetric_mesh(4)
    W, out = run(exact, F)
    assert np.abs(W - exact).max() < 1e-6 * diagonal(exact)


def test_half_strength_moves_half_way_in_one_pass():
    V, F = noisy_sphere()
    full, _ = run(V, F, strength=1.0, symmetrization_iterations=1)
    half, _ = run(V, F, strength=0.5, symmetrization_iterations=1)
    np.testing.assert_allclose(half - V, 0.5 * (full - V), atol=1e-12 * diagonal(V))


@pytest.mark.parametrize("parameter,value,said", [("strength", 1.5, "strength is 1.5, but it must be between 0 and 1"),
                                                  ("symmetrization_iterations", 0, "symmetrization_iterations is 0, but")])
def test_a_bad_parameter_is_refused_and_the_mesh_is_unchanged(parameter, value, said):
    V, F = noisy_sphere()
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(V, F))
    with pytest.raises(pymeshlab.PyMeshLabException, match=said):
        ms.apply_coord_symmetrization(**LIGHT, **{parameter: value})
    assert np.array_equal(ms.current_mesh().vertex_matrix(), V)
