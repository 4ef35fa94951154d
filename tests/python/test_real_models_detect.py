"""The detector on real models with a known global mirror (tests/real_models.json, planes
measured by the brute-force oracle tests/oracle_mirror.py, never by the detector).

With default parameters the filter must report a reflection within 1 degree of every
recorded plane, at the right offset, with transformation_group 0 (rotations, reflections and
translations) and 2 (reflections only).  Among them are scans whose mirror is only approximate
(the elk, the helmet): the deviation is graded, not a reason to discard the plane.  The full
table over every model is tests/benchmarks/real_mirrors.py; the models here are those it
finds, kept fast.  Group 2 must also report each of group 0's matching planes itself, within
0.1 degree (issue 11; every model: the last column of real_mirrors.py).
"""
import os
import sys

import pytest

TESTS_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, TESTS_DIR)
import group_containment as gc  # noqa: E402
import metrics  # noqa: E402
import real_models  # noqa: E402

FOUND_DEG = 1.0
FOUND_OFFSET = 0.01
MODELS = ("head", "camel", "cow", "dino", "triceratops", "elk", "helmet", "wuson")


@pytest.fixture(scope="module")
def models(real_model_set):
    return real_model_set


_runs = {}


def detection(m, group):
    """metrics.DetectionResult of model m with transformation_group `group`, once per session."""
    if (m.name, group) not in _runs:
        import pymeshlab
        V, F = m.load()
        ms = pymeshlab.MeshSet()
        ms.add_mesh(pymeshlab.Mesh(V, F), "model")
        _runs[(m.name, group)] = metrics.run_filter(ms, transformation_group=group, create_patch_layers=True)
    return _runs[(m.name, group)]


def reflections(m, group):
    """The discrete reflections reported for model m (4x4 each)."""
    res = detection(m, group)
    keep = (res.is_reflection != 0) & (res.kinds == 0)
    return res.transforms[keep]


@pytest.mark.parametrize("group", (0, 2))
@pytest.mark.parametrize("name", MODELS)
def test_global_mirror_found_within_a_degree(models, name, group):
    m = models[name]
    found = reflections(m, group)
    for plane in m.planes:
        errors = [real_models.mirror_angle_error(T, plane, m.diagonal) for T in found]
        assert any(a <= FOUND_DEG and o <= FOUND_OFFSET for a, o in errors), \
            f"{name}, group {group}: nearest reported planes (deg, offset) {sorted(errors)[:3]}"


@pytest.mark.parametrize("name", MODELS)
def test_reflections_only_finds_the_default_groups_mirror_planes(models, name):
    """Every reflection of group 0 that matches a measured plane is also reported by group 2
    (reflections only), the same plane within 0.1 degree (tests/group_containment.py)."""
    m = models[name]
    full, restricted = detection(m, 0), detection(m, 2)
    wanted = [k for k in gc.reports_of_kind(full, gc.REFLECTION, m.diagonal)
              if any(a <= FOUND_DEG and o <= FOUND_OFFSET for a, o in
                     (real_models.mirror_angle_error(full.transforms[k], p, m.diagonal) for p in m.planes))]
    assert wanted, f"{name}: group 0 reported none of the measured planes"
    V, _ = m.load()
    for c in gc.containment(full, restricted, 2, wanted, m.diagonal, V):
        assert c.same, (f"{name}: group 0's plane #{c.index} is not in group 2's result; nearest "
                        f"#{c.nearest}: {c.angle_deg:.3f} deg, {100 * c.distance:.3f} % of the diagonal")


@pytest.mark.parametrize("name", MODELS)
def test_the_models_are_analysed_as_they_come(models, name):
    """No model is a triangle soup or turned both ways, so the input repair
    (plugin/core/input_repair.h) leaves each as it is; the wuson's 190 parts share 1,088
    vertex positions along their seams and stay parts (welded, an airliner split likewise
    lost its mirror plane)."""
    res = detection(models[name], 0)
    assert res.raw["welded_vertices"] == 0 and res.raw["flipped_faces"] == 0
