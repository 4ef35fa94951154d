"""Every parameter of compute_partial_symmetries at the ends of its range and just outside.

Just outside, the filter refuses in a sentence that names the parameter and leaves the mesh
as it was.  At an end of the range it finishes: with a result (the planted mirror where the
setting still allows finding it), or with a sentence saying why it could not look; never a
crash, an internal error or a changed input.
"""
import os
import sys

import numpy as np
import pymeshlab
import pytest

from conftest import FILTER, LIGHT_RUN, assert_mesh_unchanged, make_meshset, mesh_snapshot, mirror_symmetric_mesh

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenes  # noqa: E402

# Lighter than the defaults, so that the sweep stays quick; each case overrides one of them.
RUN = LIGHT_RUN
MIRROR_X = np.diag([-1.0, 1, 1])
P = pymeshlab.PercentageValue

# parameter -> values just outside its range (see DetectionOptions::validate); beyond 100 %
# of the diagonal pymeshlab itself refuses a percentage, so those are absolute lengths.
OUTSIDE = {
    "sample_count": [99, 5_000_001],
    "max_working_vertices": [999, -1],
    "pair_sample_count": [-1, 5_000_001],
    "curvature_radius": [P(0), P(50.5), pymeshlab.PureValue(-1)],
    "umbilic_ratio": [0.0, 1.0],
    "signature_tolerance": [0.0, 10.5],
    "cluster_bandwidth": [P(0), pymeshlab.PureValue(1e3)],
    "min_cluster_support": [1, -3],
    "verification_tolerance": [P(0), P(26)],
    "min_patch_area": [-0.5, 100.5],
    "max_symmetries": [0, 1001],
    "basis_loop_length": [0, 7],
    "basis_tolerance": [P(0), pymeshlab.PureValue(1e3)],
}

# (parameter, value at an end of its range, whether the planted mirror must still be found)
ENDS = [
    ("transformation_group", 3, False),  # translations only: no mirror to find
    ("sample_count", 100, False),
    ("max_working_vertices", 1000, False),
    ("max_working_vertices", 0, True),
    ("pair_sample_count", 0, True),
    ("pair_sample_count", 5_000_000, True),
    ("curvature_radius", P(1e-4), True),
    ("curvature_radius", P(50), False),
    ("umbilic_ratio", 1e-6, False),
    ("umbilic_ratio", 0.999999, True),
    ("signature_tolerance", 1e-6, False),
    ("signature_tolerance", 10.0, True),
    ("cluster_bandwidth", P(1e-4), False),
    ("cluster_bandwidth", P(100), False),
    ("min_cluster_support", 2, True),
    ("min_cluster_support", 2_000_000_000, False),
    ("verification_tolerance", P(1e-4), False),
    ("verification_tolerance", P(25), False),
    ("min_patch_area", 0.0, True),
    ("min_patch_area", 100.0, False),
    ("max_symmetries", 1, True),
    ("max_symmetries", 1000, True),
    ("refine_with_icp", False, True),
    ("reduce_basis", False, True),
    ("basis_loop_length", 1, True),
    ("basis_loop_length", 6, True),
    ("basis_tolerance", P(1e-4), True),
    ("basis_tolerance", P(100), True),
    ("create_patch_layers", False, True),
    ("random_seed", 2_147_483_647, True),
    ("random_seed", -2_147_483_648, True),
]


@pytest.fixture(scope="module")
def mirrored():
    return mirror_symmetric_mesh(3)


def mirror_error(result):
    errors = [np.linalg.norm(result["transforms"][16 * k:16 * k + 16].reshape(4, 4)[:3, :3] - MIRROR_X)
              for k in range(result["symmetry_count"]) if result["is_reflection"][k]]
    return min(errors, default=np.inf)


@pytest.mark.parametrize("name,value", [(n, v) for n, values in OUTSIDE.items() for v in values],
                         ids=[f"{n}-{k}" for n, values in OUTSIDE.items() for k in range(len(values))])
def test_just_outside_the_range_is_refused_by_name(requires_pipeline, mirrored, name, value):
    ms = make_meshset(*mirrored)
    before = mesh_snapshot(ms)
    with pytest.raises(pymeshlab.PyMeshLabException) as error:
        getattr(ms, FILTER)(**{**RUN, name: value})
    message = str(error.value)
    assert name in message and "internal error" not in message, message
    assert_mesh_unchanged(ms, before)


@pytest.mark.parametrize("value", [4, -1])
def test_a_group_past_the_list_is_refused_by_pymeshlab_itself(requires_pipeline, mirrored, value):
    """An enumeration outside its list never reaches the filter: pymeshlab refuses it (and
    MeshLab's dialog offers only the list)."""
    ms = make_meshset(*mirrored)
    before = mesh_snapshot(ms)
    with pytest.raises(pymeshlab.InvalidEnumException):
        getattr(ms, FILTER)(**{**RUN, "transformation_group": value})
    assert_mesh_unchanged(ms, before)


@pytest.mark.parametrize("name,value,finds_mirror", ENDS, ids=[f"{n}-{k}" for k, (n, _, _) in enumerate(ENDS)])
def test_an_end_of_the_range_finishes(requires_pipeline, mirrored, name, value, finds_mirror):
    ms = make_meshset(*mirrored)
    before = mesh_snapshot(ms)
    try:
        result = getattr(ms, FILTER)(**{**RUN, name: value})
    except pymeshlab.PyMeshLabException as error:
        # Allowed only as the could-not-look sentence, and never where the mirror is due.
        message = str(error)
        assert not finds_mirror and "could not" in message.lower() and "internal error" not in message, message
        assert_mesh_unchanged(ms, before)
        return
    assert result["symmetry_count"] >= 0
    if name == "max_symmetries":
        assert result["symmetry_count"] <= value
    if finds_mirror:
        assert mirror_error(result) < 0.2, result["symmetry_count"]
    assert len(ms.mesh(0).vertex_custom_scalar_attribute_array("symmetry_id")) == ms.mesh(0).vertex_number()




@pytest.mark.parametrize("limit", [1, 2, 3])
def test_max_symmetries_bounds_the_discrete_symmetries_and_families_take_none_of_their_places(
        requires_pipeline, limit):
    """The wingnut (tests/scenes.py) has three turns of its blades and three families (the
    hub's surface of revolution, its two flat ends).  `limit` discrete symmetries are
    reported, the largest patches first, whatever families are found beside them (a family
    is one report for a continuum of symmetries), and at most `limit` families."""
    scene = scenes.make_scene("wingnut", 0)
    ms = scene.meshset()
    result = getattr(ms, FILTER)(**{**scene.filter_params, "max_symmetries": limit})
    kinds = np.asarray(result["continuous_kinds"])
    discrete = kinds == scenes.KIND_DISCRETE
    assert np.count_nonzero(discrete) == limit
    assert 1 <= np.count_nonzero(~discrete) <= limit
    areas = np.asarray(result["source_areas"])
    assert list(areas) == sorted(areas, reverse=True)
