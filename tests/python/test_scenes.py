"""Tests of the planted-symmetry scene generator (tests/scenes.py) and of the metrics
(tests/metrics.py).  They need pymeshlab and numpy only, not the plugin."""
import math
import os
import sys

import numpy as np
import pytest

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import metrics  # noqa: E402
import scenes  # noqa: E402
from conftest import cgal_meshes_dir  # noqa: E402

_CACHE = {}


def get_scene(name, seed=0):
    if (name, seed) not in _CACHE:
        _CACHE[(name, seed)] = scenes.make_scene(name, seed)
    return _CACHE[(name, seed)]


def part_closed_volume(V, F):
    return float(np.einsum("ij,ij->i", V[F[:, 0]], np.cross(V[F[:, 1]], V[F[:, 2]])).sum() / 6)


# ---------------------------------------------------------------------------- generator --

@pytest.mark.parametrize("name", scenes.SCENE_NAMES)
def test_scene_size_and_structure(name):
    s = get_scene(name)
    assert 20000 <= s.triangle_count <= 80000, s.triangle_count
    assert s.faces.min() >= 0 and s.faces.max() < len(s.vertices)
    assert np.isfinite(s.vertices).all()
    # parts tile the mesh and every part is a closed surface with outward normals
    assert sum(v1 - v0 for v0, v1, _, _ in s.parts.values()) == len(s.vertices)
    assert sum(f1 - f0 for _, _, f0, f1 in s.parts.values()) == len(s.faces)
    for part in s.parts:
        V, F = s.part_mesh(part)
        assert part_closed_volume(V, F) > 0, f"{part} is inside out"
    if name != "asymmetric":
        assert s.required_symmetries(), "a scene with planted symmetry must require one"
    for sym in s.symmetries:
        assert sym.transform.shape == (4, 4)
        assert sym.reflection == (np.linalg.det(sym.transform[:3, :3]) < 0)
        assert 0 < sym.source_area_fraction < 1


@pytest.mark.parametrize("name", scenes.SCENE_NAMES)
def test_same_seed_same_scene_other_seed_other_scene(name):
    a = get_scene(name, 0)
    b = scenes.make_scene(name, 0)
    assert np.array_equal(a.vertices, b.vertices) and np.array_equal(a.faces, b.faces)
    for x, y in zip(a.symmetries, b.symmetries):
        assert np.array_equal(x.transform, y.transform)
    c = get_scene(name, 1)
    assert not (c.vertices.shape == a.vertices.shape and np.allclose(c.vertices, a.vertices))


def _copy_relations(s):
    for part, (src, T, tol) in s.copies.items():
        yield part, src, T, tol


@pytest.mark.parametrize("name", [n for n in scenes.SCENE_NAMES if n != "asymmetric"])
def test_copies_are_retessellated(name):
    """No vertex of a copy, mapped back by the inverse planted transform, lies within 1e-9
    of a vertex of its source part."""
    s = get_scene(name)
    assert s.copies
    for part, src, T, _ in _copy_relations(s):
        back = scenes.apply(np.linalg.inv(T), s.part_mesh(part)[0])
        d = scenes.min_distances_bruteforce(back, s.part_mesh(src)[0])
        assert d.min() > 1e-9, f"{part}: a vertex coincides with one of {src}"
        # and not a near-coincidence either: a new tessellation, not a jittered copy
        assert np.median(d) > 0.15 * scenes.mean_edge_length(*s.part_mesh(src))


@pytest.mark.parametrize("name", [n for n in scenes.SCENE_NAMES if n != "asymmetric"])
def test_copies_are_the_same_surface(name):
    """The copy's surface lies within a small tolerance of the mapped source surface, both
    ways (a two-sided Hausdorff distance estimated from dense samples)."""
    s = get_scene(name)
    rng = np.random.default_rng(0)
    diag = s.diagonal
    for part, src, T, tol in _copy_relations(s):
        Vs, Fs = s.part_mesh(src)
        Vc, Fc = s.part_mesh(part)
        Vm, Fm = scenes.transform_mesh(T, Vs, Fs)
        d1 = scenes.point_to_surface_distance(scenes.sample_surface(Vc, Fc, 20000, rng), Vm, Fm)
        d2 = scenes.point_to_surface_distance(scenes.sample_surface(Vm, Fm, 20000, rng), Vc, Fc)
        assert max(d1.max(), d2.max()) <= tol * diag, (part, d1.max() / diag, d2.max() / diag)
        assert max(d1.mean(), d2.mean()) <= 0.1 * tol * diag


@pytest.mark.parametrize("name", [n for n in scenes.SCENE_NAMES if n != "asymmetric"])
def test_planted_transforms_map_source_onto_target(name):
    s = get_scene(name)
    diag = s.diagonal
    for sym in s.symmetries:
        P = s.vertices[sym.source_vertices]
        tV, tF = s.part_mesh(sym.target_part)
        d = scenes.point_to_surface_distance(scenes.apply(sym.transform, P), tV, tF)
        assert np.quantile(d, 0.99) <= 0.006 * diag, (sym.name, d.max() / diag)


def test_mirrored_scene_plants_a_reflection():
    (sym,) = get_scene("mirrored").symmetries
    assert sym.reflection and sym.required and abs(sym.scale - 1) < 1e-12


def test_rigid_scene_angles_far_from_zero():
    s = get_scene("rigid")
    req = s.required_symmetries()
    assert len(req) == 2
    for sym in req:
        R = sym.transform[:3, :3]
        angle = math.degrees(math.acos(np.clip((np.trace(R) - 1) / 2, -1, 1)))
        assert 60 <= angle <= 180 and not sym.reflection


def test_scaled_scene_scale():
    s = get_scene("scaled")
    (sym,) = s.symmetries
    assert abs(sym.scale - 0.6) < 1e-12 and not sym.reflection
    assert s.filter_params == {"transformation_group": 1}


def test_noisy_scene_is_noisy_but_close():
    s = get_scene("noisy")
    (sym,) = s.symmetries
    Vs, Fs = s.part_mesh("base")
    Vn, _ = s.part_mesh("noisy")
    d = scenes.point_to_surface_distance(scenes.apply(np.linalg.inv(sym.transform), Vn), Vs, Fs)
    rms = math.sqrt(np.mean(d ** 2)) / s.diagonal
    assert 0.0005 < rms < 0.002, rms


def test_row_scene_is_one_translation_family():
    s = get_scene("row")
    fam = [x for x in s.symmetries if x.family == "row"]
    gen = [x for x in fam if x.power == 1 and x.source_part == "copy0"][0]
    step = gen.transform[:3, 3]
    assert np.allclose(gen.transform[:3, :3], np.eye(3))
    for x in fam:
        assert np.allclose(x.transform[:3, 3], x.power * step)
    assert [x.name for x in s.required_symmetries()] == [gen.name]
    assert s.expected_generators == {"row": 1}
    assert len(s.parts) == 4


def test_small_part_is_small():
    s = get_scene("small_part")
    (sym,) = s.symmetries
    assert sym.source_area_fraction < 0.05
    total = s.area()
    V2, F2 = s.part_mesh("small2")
    assert scenes.face_areas(V2, F2).sum() / total < 0.05


@pytest.mark.parametrize("name,part", [("asymmetric", "blob"), ("rigid", "base"),
                                       ("scaled", "base"), ("small_part", "small1"),
                                       ("mirrored", "base"), ("row", "copy0")])
def test_bases_have_no_global_symmetry(name, part):
    """A global isometric self-symmetry fixes the centroid and permutes the principal axes;
    none of those candidates maps the shape onto itself."""
    V, F = get_scene(name).part_mesh(part)
    _, _, ev = scenes.principal_frame(V, F)
    assert np.min(np.diff(ev)) / ev.max() > 0.02, "principal variances too close to decide"
    m, _, _ = scenes.principal_frame(V, F)
    worst = min(scenes.self_symmetry_residual(V, F, A, m, n=1500)
                for _, A in scenes.candidate_self_symmetries(V, F, max_fold=6))
    assert worst > 0.005, worst


def test_asymmetric_scene_has_no_planted_symmetry():
    s = get_scene("asymmetric")
    assert s.symmetries == [] and s.max_reported_area_fraction == 0.05


def test_moved_scene_keeps_ground_truth():
    s = get_scene("mirrored")
    G = scenes.translation([3.0, -1.0, 2.0]) @ scenes.rotation([1, 2, 3], 1.1)
    m = s.transformed(G)
    for a, b in zip(s.symmetries, m.symmetries):
        P = m.vertices[b.source_vertices]
        assert np.allclose(scenes.apply(b.transform, P),
                           scenes.apply(G, scenes.apply(a.transform, s.vertices[a.source_vertices])))
    assert part_closed_volume(*m.part_mesh("mirror")) > 0


def test_subdivided_scene_keeps_surface_and_ground_truth():
    # accuracy.py --above-working-resolution scores the filter on scenes split this way.
    s = get_scene("rigid")
    d = s.subdivided(50000)
    assert len(d.vertices) > 50000 and len(d.faces) == 4 * len(s.faces)
    assert d.area() == pytest.approx(s.area(), rel=1e-12)
    assert np.array_equal(d.vertices[d.part_vertices("base")][:len(s.part_vertices("base"))],
                          s.vertices[s.part_vertices("base")])
    for a, b in zip(s.symmetries, d.symmetries):
        # the source region about quadruples (three midpoints per face, shared by two faces)
        assert 3.5 * len(a.source_vertices) < len(b.source_vertices) < 4.5 * len(a.source_vertices)
        # ...and is still mapped onto the target part by the planted transform
        P = d.vertices[b.source_vertices]
        tV, tF = d.part_mesh(b.target_part)
        dist = scenes.point_to_surface_distance(scenes.apply(b.transform, P), tV, tF)
        assert np.quantile(dist, 0.99) <= 0.006 * d.diagonal, (b.name, dist.max() / d.diagonal)


def test_near_mask_matches_bruteforce():
    rng = np.random.default_rng(3)
    A = rng.random((3000, 3))
    B = np.concatenate([A[:500] + rng.normal(0, 1e-8, (500, 3)), rng.random((2000, 3))])
    tol = 1e-7
    d = scenes.min_distances_bruteforce(A, B)
    assert np.array_equal(scenes.near_mask(A, B, tol), d <= tol)


def test_geodesic_sphere_counts():
    V, F = scenes.geodesic_sphere(7)
    assert len(F) == 20 * 49 and len(V) == 10 * 49 + 2
    assert np.allclose(np.linalg.norm(V, axis=1), 1)


def test_point_to_surface_distance_exact_on_a_triangle():
    V = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]])
    F = np.array([[0, 1, 2]])
    P = np.array([[0.2, 0.2, 0.5], [2.0, 0.0, 0.0], [-1.0, -1.0, 0.0]])
    d = scenes.point_to_surface_distance(P, V, F)
    assert np.allclose(d, [0.5, 1.0, math.sqrt(2)], atol=1e-6)


# ------------------------------------------------------------------------------ metrics --
# An "oracle detector" reports exactly the planted transforms: the metrics must score it 1,
# and must score wrong answers low.  This checks the metric code, not the filter.

def _oracle(s, transforms=None, patches=None):
    transforms = [x.transform for x in s.symmetries] if transforms is None else transforms
    patches = ({k: s.vertices[x.source_vertices] for k, x in enumerate(s.symmetries)}
               if patches is None else patches)
    return transforms, patches


@pytest.mark.parametrize("name", ["mirrored", "rigid", "row", "scaled"])
def test_metrics_score_the_oracle_perfectly(name):
    s = get_scene(name)
    T, P = _oracle(s)
    assert metrics.recall(s, T)["recall"] == 1.0
    assert metrics.precision(s, T, P)["precision"] == 1.0


def test_metrics_accept_inverse_transforms():
    s = get_scene("rigid")
    T = [np.linalg.inv(x.transform) for x in s.symmetries]
    P = {k: s.vertices[x.target_vertices] for k, x in enumerate(s.symmetries)}
    assert metrics.recall(s, T)["recall"] == 1.0
    assert metrics.precision(s, T, P)["precision"] == 1.0


def test_metrics_reject_wrong_transforms():
    s = get_scene("rigid")
    diag = s.diagonal
    off = scenes.translation([0.02 * diag, 0, 0])
    T = [off @ x.transform for x in s.symmetries]
    _, P = _oracle(s)
    assert metrics.recall(s, T)["recall"] == 0.0
    assert metrics.precision(s, T, P)["precision"] == 0.0
    # a small error inside the tolerance still counts
    near = scenes.translation([0.002 * diag, 0, 0])
    assert metrics.recall(s, [near @ x.transform for x in s.symmetries])["recall"] == 1.0
    # identity maps every patch onto the surface but is no symmetry
    assert metrics.precision(s, [np.eye(4)], {0: P[0]})["precision"] == 0.0
    # a missing patch cannot be checked: counted wrong
    assert metrics.precision(s, [s.symmetries[0].transform], {})["precision"] == 0.0


def test_metrics_recall_partial_and_extras():
    s = get_scene("rigid")
    req = s.required_symmetries()
    T, P = [req[0].transform], {0: s.vertices[req[0].source_vertices]}
    assert metrics.recall(s, T)["recall"] == 0.5
    # a correct extra symmetry (copy1 -> copy2) is precise although it is not required
    extra = [x for x in s.symmetries if not x.required][0]
    T2 = T + [extra.transform]
    P2 = {**P, 1: s.vertices[extra.source_vertices]}
    assert metrics.precision(s, T2, P2)["precision"] == 1.0
    assert metrics.recall(s, T2)["recall"] == 0.5


def test_metrics_mirror_is_not_a_rotation():
    s = get_scene("mirrored")
    (sym,) = s.symmetries
    # the rigid map with the same translation and a proper rotation is far from the mirror
    R = sym.transform.copy()
    R[:3, :3] = -R[:3, :3]
    assert metrics.recall(s, [R])["recall"] == 0.0


def test_metrics_iou_of_a_mirror_counts_either_side():
    # A mirror is its own inverse: a report of it matches the planted relation both ways, by
    # errors that differ in the fifth decimal, and its patch may lie on either copy (the
    # filter grows it on both).  Which direction fits a hair better must not decide the IoU.
    s = scenes.make_scene("cad_fandisk", 0, cgal_dir=cgal_meshes_dir())
    (mirror,) = [x for x in s.symmetries if x.name == "mirror"]
    (turn,) = [x for x in s.symmetries if x.name == "rotation"]
    assert np.allclose(mirror.transform @ mirror.transform, np.eye(4), atol=1e-9)
    scorer = metrics.AccuracyScorer(s)
    relation = {r.name: r for r in scorer.relations}
    nudge = scenes.translation([1e-5 * s.diagonal, 0, 0])
    for R in (nudge @ mirror.transform, mirror.transform @ nudge):
        sides = metrics.matched_sides(R, relation["mirror"], s.vertices, scorer.tol)
        assert sorted(len(x) for x in sides) == sorted([len(mirror.source_vertices), len(mirror.target_vertices)])
        for patch in (mirror.source_vertices, mirror.target_vertices,
                      np.concatenate([mirror.source_vertices, mirror.target_vertices])):
            rs = scorer.score_discrete(0, R, np.asarray(patch))
            assert rs.label == "correct"
            assert rs.iou == pytest.approx(1.0)
    # a turn is no involution: only its own direction's source
    sides = metrics.matched_sides(turn.transform, relation["rotation"], s.vertices, scorer.tol)
    assert len(sides) == 1 and np.array_equal(sides[0], relation["rotation"].source)


def test_metrics_small_patch_mapped_elsewhere_is_wrong():
    s = get_scene("small_part")
    (sym,) = s.symmetries
    P = s.vertices[sym.source_vertices]
    wrong = scenes.translation([0.0, 0.0, 0.3 * s.diagonal]) @ sym.transform
    assert metrics.precision(s, [wrong], {0: P})["precision"] == 0.0
    assert metrics.precision(s, [sym.transform], {0: P})["precision"] == 1.0


# ------------------------------------------------------------------------------ CAD data --

def test_cad_scene_copies_are_retessellated_and_faithful():
    s = scenes.make_scene("cad_fandisk", 0, cgal_dir=cgal_meshes_dir())
    assert 20000 <= s.triangle_count <= 80000
    rng = np.random.default_rng(0)
    for part, (src, T, tol) in s.copies.items():
        back = scenes.apply(np.linalg.inv(T), s.part_mesh(part)[0])
        assert scenes.min_distances_bruteforce(back, s.part_mesh(src)[0]).min() > 1e-9
        Vm, Fm = scenes.transform_mesh(T, *s.part_mesh(src))
        d = scenes.point_to_surface_distance(
            scenes.sample_surface(*s.part_mesh(part), 20000, rng), Vm, Fm)
        assert d.max() <= tol * s.diagonal


def test_demo_mesh_is_the_cad_demo_scene():
    path = os.path.join(scenes.REPO_DIR, "meshes", "demo.ply")
    assert os.path.getsize(path) <= 2 * 1024 * 1024
    import pymeshlab
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(path)
    m = ms.current_mesh()
    s = scenes.make_scene(*scenes.DEMO_SCENE, cgal_dir=cgal_meshes_dir())
    assert m.face_number() == s.triangle_count
    assert np.allclose(m.vertex_matrix(), s.vertices, atol=1e-12)
