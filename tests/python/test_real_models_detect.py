"""The detector on real models with a known global mirror (tests/real_models.json, planes
measured by the brute-force oracle tests/oracle_mirror.py, never by the detector).

With default parameters the filter must report a reflection within 1 degree of every
recorded plane, at the right offset, with transformation_group 0 (rotations, reflections and
translations) and 2 (reflections only).  Among them are scans whose mirror is only approximate
(the elk, the helmet): the deviation is graded, not a reason to discard the plane.  The full
table over every model is tests/benchmarks/real_mirrors.py; the models here are those it
finds, kept fast.
"""
import os
import sys

import numpy as np
import pytest

TESTS_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, TESTS_DIR)
import real_models  # noqa: E402

FOUND_DEG = 1.0
FOUND_OFFSET = 0.01
MODELS = ("head", "camel", "cow", "dino", "triceratops", "elk", "helmet", "wuson")


@pytest.fixture(scope="module")
def models(real_model_set):
    return real_model_set


def reflections(V, F, group):
    import pymeshlab
    import meshlab_symmetry  # noqa: F401  (binds MeshSet.compute_partial_symmetries)
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(V, F), "model")
    out = ms.compute_partial_symmetries(transformation_group=group)
    n = int(out["symmetry_count"])
    T = np.asarray(out["transforms"], float).reshape(n, 4, 4)
    keep = (np.asarray(out["is_reflection"]).reshape(n) != 0) & \
        (np.asarray(out["continuous_kinds"]).reshape(n) == 0)
    return T[keep], out


@pytest.mark.parametrize("group", (0, 2))
@pytest.mark.parametrize("name", MODELS)
def test_global_mirror_found_within_a_degree(models, name, group):
    m = models[name]
    V, F = m.load()
    found, out = reflections(V, F, group)
    for plane in m.planes:
        errors = [real_models.mirror_angle_error(T, plane, m.diagonal) for T in found]
        assert any(a <= FOUND_DEG and o <= FOUND_OFFSET for a, o in errors), \
            f"{name}, group {group}: nearest reported planes (deg, offset) {sorted(errors)[:3]}"
