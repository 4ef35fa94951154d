"""Regression tests of the detector on the hard scenes of tests/scenes.py (issue 5):
approximate copies, continuous families reported once, small parts, creases, copies fused
into one surface.

Each test runs the filter with its DEFAULT parameters (plus the scene's own filter_params)
and scores the answer with metrics.AccuracyScorer against ground truth the detector did
not produce: the planted transforms, the analytic families and the brute-force oracle.
The full table over every scene is tests/benchmarks/accuracy.py; these are the scenes the
detector is required to keep.
"""
import os
import sys

import numpy as np
import pytest

TESTS_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, TESTS_DIR)
import scenes  # noqa: E402
from conftest import scene_detection as scored  # noqa: E402  (scene, result, figures), cached


def labels(fig):
    return [f"#{r['index']} {r['label']} {r['matched'] or ''} {r['note'] or ''}" for r in fig["reports"]]


# Every required relation and family found, every report correct (or confirmed by the
# oracle), no report of a family's member beside the family.
EXACT = ("noisy_both_0.1", "noisy_both_0.2", "noisy_both_0.5", "holes", "anisotropic", "fine_row",
         "small_part_1pct", "scaled_cow", "scaled_torus", "poisson_fused", "thin_plate",
         "cylinder", "cone", "vase", "extrusion", "helix", "box", "sphere", "torus", "torus_pair",
         "wingnut", "hammer", "boat", "facade", "facade_wide")


@pytest.mark.parametrize("name", EXACT)
def test_every_relation_found_and_nothing_else(name):
    s, res, fig = scored(name)
    assert fig["found"] == fig["required"], (fig["missed"], labels(fig))
    assert fig["counts"]["false"] == 0, labels(fig)
    assert fig["counts"]["member"] == 0, labels(fig)


@pytest.mark.parametrize("name", scenes.CAD_LIKE_SCENE_NAMES)
def test_a_double_sided_coarse_cad_model_of_many_parts_gives_every_planted_relation(name):
    """A chair of fourteen to seventeen parts, two cars (the copy triangulated otherwise),
    boxes of twelve triangles, every triangle twice: each planted mirror and copy is found,
    the back faces dropped and the model analysed on a refined copy.  Their false reports
    (partial patches of the refined copy, planar families on the cars) are not asserted on:
    see the accuracy table."""
    s, res, fig = scored(name)
    assert fig["found"] == fig["required"], (fig["missed"], labels(fig))
    assert int(res.raw["back_faces"]) > 0 and int(res.raw["working_vertices"]) > 0


@pytest.mark.parametrize("name", ("cylinder", "vase", "torus", "helix", "extrusion", "boat"))
def test_a_continuous_family_is_one_report_with_its_axis(name):
    s, res, fig = scored(name)
    families = [r for r in fig["reports"] if r["kind"] != scenes.KIND_DISCRETE]
    kinds = {f.kind for f in s.required_families()}
    assert {r["kind"] for r in families if r["label"] == "correct"} >= kinds, labels(fig)
    # one report per family: the scorer marks a second one as a duplicate
    assert fig["counts"]["duplicate"] == 0, labels(fig)


def test_approximate_copies_are_graded_not_discarded():
    """Noise of 0.2 % of the diagonal on both copies: the copy is found, and its deviation
    from perfect symmetry is measured (non-zero, of the order of the noise) rather than
    hidden."""
    s, res, fig = scored("noisy_both_0.2")
    correct = [r["index"] for r in fig["reports"] if r["label"] == "correct"]
    assert correct, labels(fig)
    rms = [res.rms_errors[k] for k in correct]
    assert 0.0005 < max(rms) < 0.01, rms
    # the per-vertex quality carries the deviation on the patch
    quality = res.quality
    assert np.count_nonzero(quality) > 0


def test_small_part_beside_a_large_surface_at_the_defaults():
    s, res, fig = scored("small_part_1pct")
    assert not fig["missed"], labels(fig)
    areas = [res.source_areas[r["index"]] for r in fig["reports"] if r["label"] == "correct"]
    assert min(areas) < 0.02, areas  # the small part itself, not only the base's mirror


@pytest.mark.parametrize("seed", (1, 3, 5))
def test_a_small_part_is_found_whatever_the_random_seed(seed):
    """The part of 1 % of the area beside a cow: the cow's global mirror explains the rest,
    and its chance near-mirrors leave the part's cluster (some 14 votes) below the modes kept,
    or under the minimum support, at most random seeds (found at 1 of seeds 0-7 before the
    last pass over the votes away from what was verified).  min_patch_area is set just under
    the part's area (0.0099999 of the total): at the default 1 % the part sits on the bound,
    and whether its patch measures above it depends on the seed."""
    import metrics
    s = scenes.make_scene("small_part_1pct", 0)
    res = metrics.run_filter(s, **s.filter_params, create_patch_layers=True, random_seed=seed,
                             min_patch_area=0.99)
    fig = metrics.accuracy(s, res)
    assert not fig["missed"], labels(fig)
    assert fig["counts"]["false"] == 0, labels(fig)


def test_a_finely_tessellated_sphere_is_a_spherical_family():
    """A whole sphere bends by 0.035 of the default curvature radius across its ball, under
    the flatness bound: its samples are pruned as flat, and the plane each suggests stops
    after a few faces.  On a coarse sphere the radius grows to hold min_radius_in_edges edges
    and they look curved; the same sphere with every triangle split (151,000 vertices, so
    analysed on a copy of 50,000) made the filter refuse the mesh as all flat or umbilic."""
    import metrics
    s = scenes.make_scene("sphere", 0).subdivided(50000)
    res = metrics.run_filter(s, create_patch_layers=True)
    fig = metrics.accuracy(s, res)
    assert fig["found"] == fig["required"] == 1, (fig["missed"], labels(fig))
    assert fig["counts"]["false"] == 0, labels(fig)


def test_a_facades_windows_are_a_lattice_of_two_generators():
    """The facade's windows repeat along two directions (issue 5: discrete symmetries are
    still found beside the wall's continuous families): every translation reported is a step
    of the lattice, and basis reduction keeps as generators the translations by one column
    and by one row (either sign), no more."""
    s, res, fig = scored("facade")
    steps = {x.name: x.transform for x in s.symmetries if x.name in ("lattice_1_0", "lattice_0_1")}
    translations = [k for k in range(res.count) if res.kinds[k] == scenes.KIND_DISCRETE
                    and np.allclose(res.transforms[k][:3, :3], np.eye(3), atol=1e-3)]
    assert translations, labels(fig)
    for k in translations:
        assert fig["reports"][k]["label"] == "correct", labels(fig)
    generators = [res.transforms[k][:3, 3] for k in translations if res.is_generator[k] == 1]
    assert len(generators) == 2, (generators, labels(fig))
    for name, T in steps.items():
        assert any(min(np.linalg.norm(t - T[:3, 3]), np.linalg.norm(t + T[:3, 3])) < 0.01 * s.diagonal
                   for t in generators), (name, generators)
