"""Checks of the real-model ground truth (tests/real_models.json) and of the oracle that
measured it (tests/oracle_mirror.py).  They do not run the detector.

- every recorded plane's residuals are what the oracle measures on the fetched file now, and
  the recorded best other plane is still clearly worse (the models are fetched by
  tests/fetch_real_models.sh when missing, which checks every sha256);
- the oracle accepts no plane on a deliberately asymmetric blob;
- the oracle recovers the plane of a synthetic mirror-symmetric shape placed at random;
- mirror_angle_error measures what it says on reflections built by hand.
"""
import json
import math
import os
import sys

import numpy as np
import pytest

TESTS_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, TESTS_DIR)
import oracle_mirror  # noqa: E402
import real_models  # noqa: E402
import scenes  # noqa: E402
from conftest import mirror_symmetric_mesh  # noqa: E402

with open(real_models.GROUND_TRUTH) as _f:
    TRUTH = json.load(_f)
#: a residual statistic may differ this much from the record (relative, absolute): the
#: evaluation is deterministic, this only absorbs floating-point differences between machines
REL_TOL, ABS_TOL = 0.05, 2e-5
#: a cheaper search for the synthetic shapes (they are smooth and small)
QUICK = dict(directions=1000, candidates=4, surface_samples=60_000, final_queries=8000)


@pytest.fixture(scope="module")
def models(real_model_set):
    return real_model_set


@pytest.fixture(scope="module")
def surfaces(models):
    """One oracle Surface per model, built as the recording did (same samples, same seed)."""
    cache = {}

    def get(name):
        if name not in cache:
            V, F = models[name].load()
            cache[name] = oracle_mirror.Surface(V, F, TRUTH["oracle"]["surface_samples"],
                                                TRUTH["oracle"]["seed"])
        return cache[name]
    return get


def assert_residual_close(measured, recorded, what):
    for key, want in recorded.items():
        got = measured[key]
        assert abs(got - want) <= REL_TOL * abs(want) + ABS_TOL, \
            f"{what}: {key} is {got:.6g} now, {want:.6g} recorded"


def evaluate(surface, plane):
    o = TRUTH["oracle"]
    return oracle_mirror.evaluate_plane(surface, plane["normal"], plane["offset"],
                                        o["final_queries"], o["seed"] + 1)


@pytest.mark.parametrize("entry", TRUTH["models"], ids=[m["name"] for m in TRUTH["models"]])
def test_recorded_planes_hold(entry, models, surfaces):
    m = models[entry["name"]]
    surface = surfaces(entry["name"])
    assert len(surface.F) == entry["triangles"] == m.triangles
    assert surface.diag == pytest.approx(entry["diagonal"], rel=1e-6)
    worst = 0.0
    for k, plane in enumerate(entry["planes"]):
        assert np.linalg.norm(plane["normal"]) == pytest.approx(1.0, abs=1e-6)
        stats = evaluate(surface, plane)
        assert_residual_close(stats, plane["residual"], f"{m.name} plane {k}")
        assert stats["p80"] <= TRUTH["oracle"]["accept_p80"]
        worst = max(worst, stats["p80"])
    other = evaluate(surface, entry["best_other_plane"])
    assert_residual_close(other, entry["best_other_plane"]["residual"], f"{m.name} other plane")
    assert other["p80"] >= TRUTH["oracle"]["clear_margin"] * worst, \
        f"{m.name}: another plane is almost as good as the recorded one(s)"


def test_ground_truth_is_consistent():
    """The json's own bookkeeping: unique names, a known kind, planes of distinct models."""
    names = [m["name"] for m in TRUTH["models"]]
    assert len(names) == len(set(names))
    for m in TRUTH["models"]:
        assert m["kind"] in ("exact", "approximate")
        assert m["planes"], m["name"]
        for p in m["planes"]:
            n = np.asarray(p["normal"])
            assert abs(n @ np.asarray(p["point"]) - p["offset"]) <= 1e-6 * m["diagonal"]


def test_oracle_finds_no_plane_on_an_asymmetric_blob():
    rng = np.random.default_rng(11)
    shape = scenes.StarShape(amplitude=0.25, field=scenes.RadialField(rng, 11, 0.5))
    V, F = shape.mesh(24)
    res = oracle_mirror.find_mirror_planes(V, F, **QUICK)
    assert not res.is_clear, [oracle_mirror.format_plane(p) for p in res.planes]
    assert all(p.stats["p80"] > 0.005 for p in res.planes + res.rejected)


def random_rigid(rng):
    Q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    return Q * np.sign(np.linalg.det(Q)), rng.normal(size=3)


def test_oracle_recovers_the_plane_of_a_synthetic_mirror_shape():
    """conftest's bumpy sphere is symmetric under x -> -x only; moved by a random rigid
    motion (R, t) its plane is n = R e_x through t."""
    V, F = mirror_symmetric_mesh(4)
    R, t = random_rigid(np.random.default_rng(3))
    res = oracle_mirror.find_mirror_planes(V @ R.T + t, F, **QUICK)
    assert res.is_clear and len(res.planes) == 1
    p = res.planes[0]
    n = R[:, 0]
    truth = real_models.Plane(tuple(n), float(n @ t), tuple(t), {})
    angle, offset = real_models.mirror_angle_error(
        oracle_mirror.reflection_matrix(p.normal, p.offset), truth, res.diag)
    assert angle < 0.05 and offset < 1e-4
    assert p.stats["p80"] < 0.002 and p.stats["within_0.5pct"] > 0.95
    assert res.margin > 5


def test_mirror_angle_error_on_known_reflections():
    error = real_models.mirror_angle_error
    n = np.array([0.0, 0.6, 0.8])
    plane = real_models.Plane(tuple(n), 0.5, tuple(0.5 * n), {})
    diag = 2.0
    assert error(plane.reflection(), plane, diag) == pytest.approx((0, 0), abs=1e-6)
    # the same plane tilted by 2 degrees about the x axis, through the same point
    a = math.radians(2.0)
    Rx = np.array([[1, 0, 0], [0, math.cos(a), -math.sin(a)], [0, math.sin(a), math.cos(a)]])
    m = Rx @ n
    tilted = oracle_mirror.reflection_matrix(m, float(m @ (0.5 * n)))
    assert error(tilted, plane, diag) == pytest.approx((2.0, 0.0), abs=1e-6)
    # shifted by 0.02 along the normal: 1 % of the diagonal
    shifted = oracle_mirror.reflection_matrix(n, 0.52)
    assert error(shifted, plane, diag) == pytest.approx((0.0, 0.01), abs=1e-9)
    # a rotoreflection: the mirror followed by a quarter turn about its normal (the same -1
    # eigenvector) is not the mirror
    u, v = oracle_mirror.tangent_basis(n)
    quarter_turn = np.outer(n, n) + np.outer(v, u) - np.outer(u, v)
    roto = plane.reflection()
    roto[:3, :3] = quarter_turn @ roto[:3, :3]
    assert error(roto, plane, diag)[0] == pytest.approx(45.0, abs=1e-6)
    # and the plane read back from a reflection is the plane
    back_n, back_d = real_models.reflection_plane(tilted)
    assert abs(back_n @ m) == pytest.approx(1.0, abs=1e-9)
    assert back_d * np.sign(back_n @ m) == pytest.approx(float(m @ (0.5 * n)), abs=1e-9)
