"""The detection filter on point clouds (issue 9, item 5): planted scenes of tests/scenes.py
given as their points alone (every copy tessellated apart, so no point of one copy is the
image of a point of another), with and without their normals, with noise, give the planted
relations, scored against the scenes' ground truth as the meshes are (metrics.recall).  The
per-vertex outputs and the patch layers are per point, and a cloud is left unchanged by a
refusal."""
import os
import sys

import numpy as np
import pymeshlab
import pytest
from PIL import Image

import meshlab_symmetry
from conftest import assert_mesh_unchanged, has_vertex_attribute, mesh_snapshot

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import metrics  # noqa: E402
import scenes  # noqa: E402

FILTER = meshlab_symmetry.FILTER_NAME


def cloud_of(scene, noise=0.0, normals=False, seed=0):
    """A MeshSet holding the scene's vertices as a point cloud, with Gaussian noise of
    `noise` (fraction of the diagonal) on every coordinate, and the mesh's vertex normals if
    asked (as a scanner writes them)."""
    V = scene.vertices + np.random.default_rng(seed).normal(0.0, noise * scene.diagonal, scene.vertices.shape)
    if normals:
        ms = scene.meshset()
        N = ms.current_mesh().vertex_normal_matrix()
        mesh = pymeshlab.Mesh(vertex_matrix=V, v_normals_matrix=N)
    else:
        mesh = pymeshlab.Mesh(vertex_matrix=V)
    ms = pymeshlab.MeshSet()
    ms.add_mesh(mesh, "cloud")
    return ms


def scored_cloud(name, noise=0.0):
    """The filter's defaults (plus the scene's own parameters) on the scene as a cloud
    without normals: its output, the collected result, and metrics.accuracy's scores of it
    (as the accuracy benchmark scores a mesh)."""
    scene = scenes.make_scene(name, 0)
    ms = cloud_of(scene, noise)
    raw = ms.compute_partial_symmetries(create_patch_layers=True, **scene.filter_params)
    result = metrics.collect(ms, raw, 0)
    return raw, result, metrics.accuracy(scene, result)


# The scenes whose mesh gives every planted relation (README, accuracy table); as clouds:
# without and with noise of 0.1 % of the diagonal (the noisy scenes carry their own noise).
CASES = [("mirrored", 0.0, False), ("mirrored", 0.001, False), ("row", 0.001, False),
         ("scaled", 0.0, True), ("noisy_both_0.2", 0.0, False)]


@pytest.mark.parametrize("name,noise,normals", CASES,
                         ids=[f"{n}-noise{v}-{'normals' if k else 'no_normals'}" for n, v, k in CASES])
def test_a_planted_scene_as_a_cloud_gives_the_planted_relations(requires_pipeline, name, noise, normals):
    scene = scenes.make_scene(name, 0)
    ms = cloud_of(scene, noise, normals)
    raw = ms.compute_partial_symmetries(create_patch_layers=False, **scene.filter_params)
    result = metrics.collect(ms, raw, 0)
    found = metrics.recall(scene, result.transforms)
    assert found["found"] == found["planted"], found["rows"]
    assert raw["point_cloud"] and raw["normals_estimated"] == (not normals)
    # Per point: the deviation is small where a symmetry holds (the tolerance is 1 %).
    m = ms.mesh(0)
    assert m.vertex_number() == len(scene.vertices) and m.face_number() == 0
    quality = m.vertex_scalar_array()
    assert np.all(np.abs(quality) <= 0.04)
    assert np.count_nonzero(quality) > 0.3 * len(quality)


@pytest.mark.parametrize("name", ["cylinder", "torus_pair", "wingnut"])
def test_a_clean_cloud_of_a_surface_of_revolution_gives_its_family_and_nothing_false_or_member(requires_pipeline, name):
    # The cylinder's side alone is mapped onto itself by a mirror across any plane normal to
    # its axis; its cloud reported one 1 % of the diagonal off the middle, over the side
    # only, in place of the mid-plane mirror.  The torus beside a planted pair is sparser
    # than the curvature ball holds enough points for: its samples had no curvature, and
    # neither its rotations nor its mirror were found.  The wingnut's hub: every mirror
    # through its axis spilled onto the blades' roots, so none slid, no family was found and
    # 14 mirrors and 3 turns about the axis were reported one by one (members of the hub's
    # family, which the mesh leaves out).  Scored as the accuracy benchmark scores a mesh
    # (planted relations, families and maps the oracle confirms).
    _, _, scored = scored_cloud(name)
    assert scored["found"] == scored["required"], scored["reports"]
    assert scored["counts"]["false"] == 0, scored["reports"]
    assert scored["counts"]["member"] == 0, scored["reports"]


def test_a_noisy_cloud_of_the_wingnut_gives_its_hubs_family_not_its_mirrors(requires_pipeline):
    # With noise of 0.1 % of the diagonal only two mirrors through the hub's axis were
    # verified (60 degrees apart), and the points both map held pieces of the blades: no
    # family slid there, and the two mirrors were reported as relations of their own
    # (members of the hub's family).  Scored as above.
    _, result, scored = scored_cloud("wingnut", 0.001)
    assert scored["found"] == scored["required"], scored["reports"]
    assert scored["counts"]["false"] == 0, scored["reports"]
    assert scored["counts"]["member"] == 0, scored["reports"]
    assert scenes.KIND_ROTATIONAL in list(result.kinds)


# Scenes whose noisy cloud gives what the mesh gives, and nothing false, in the cloud
# benchmark (README, "Point clouds"): holes in the surface, a torus beside a planted pair, a
# thin plate's two faces, a capped cylinder's family and mirror, a bumpy torus's two rigid
# copies and the hammer's planted pair (both lost to the curvature agreement until a
# presmoothed cloud's noise excused patches larger than a touch).  Held here so that a
# change to the core that loses one of them fails make test, not only the benchmark.
NOISY_CLOUDS_AS_MESHES = ["holes", "torus_pair", "thin_plate", "cylinder", "rigid", "hammer"]


@pytest.mark.parametrize("name", NOISY_CLOUDS_AS_MESHES)
def test_a_noisy_cloud_gives_every_required_relation_and_family_and_nothing_false(requires_pipeline, name):
    # Noise of 0.1 % of the diagonal, no normals; scored as the accuracy benchmark scores a
    # mesh (planted relations, families and maps the oracle confirms on the clean surface).
    raw, _, scored = scored_cloud(name, 0.001)
    assert raw["point_cloud"] and raw["normals_estimated"]
    assert scored["found"] == scored["required"] > 0, scored["reports"]
    assert scored["counts"]["false"] == 0, scored["reports"]


@pytest.mark.parametrize("as_cloud", [False, True], ids=["mesh_reflections_only", "noisy_cloud"])
def test_a_wall_where_two_mirrors_meet_is_no_surface_of_revolution(requires_pipeline, as_cloud):
    # facade_wide's wall: its mirrors across the two planes normal to it meet in a line along
    # its normal, and a turn about that line slides the wall's front and back faces.  So
    # does a turn about any line parallel to it, so the faces pin no axis; before that was
    # asked, slippage named them a rotational family about the line, which the oracle
    # rejects (its finite members map 47-54 % of the patch), and it took the wall's mirror
    # as its member (the mesh with transformation_group=2, reflections only, and the noisy
    # cloud).  Ground truth: the scene has no rotational family at all.
    scene = scenes.make_scene("facade_wide", 0)
    if as_cloud:
        ms = cloud_of(scene, 0.001)
        raw = ms.compute_partial_symmetries(create_patch_layers=False, **scene.filter_params)
    else:
        ms = scene.meshset()
        raw = ms.compute_partial_symmetries(create_patch_layers=False,
                                            **{**scene.filter_params, "transformation_group": 2})
    assert not any(f.kind == scenes.KIND_ROTATIONAL for f in scene.families)
    assert scenes.KIND_ROTATIONAL not in list(metrics.collect(ms, raw, 0).kinds)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_noisy_cloud_of_a_sphere_is_one_spherical_family_whatever_the_draw_of_its_noise(requires_pipeline, seed):
    # Noise of 0.1 % of the diagonal: the cloud is presmoothed, and the sphere is grown from
    # many caps whose fits differ.  Before the family found twice was fitted to both patches,
    # one draw of the noise (seed 1) kept a cap's centre, its members missed the surface and
    # nothing was reported; the sphere test for noise alone had split another into caps.
    scene = scenes.make_scene("sphere", 0)
    ms = cloud_of(scene, 0.001, seed=seed)
    raw = ms.compute_partial_symmetries(create_patch_layers=False, **scene.filter_params)
    result = metrics.collect(ms, raw, 0)
    assert list(result.kinds) == [scenes.KIND_SPHERICAL]
    (truth,) = scene.required_families()
    assert np.linalg.norm(result.axes[0][:3] - truth.point) < 0.001 * scene.diagonal
    assert result.source_areas[0] > 0.9  # of the area


def test_patch_layers_and_symmetry_id_are_per_point(requires_pipeline):
    scene = scenes.make_scene("mirrored", 0)
    ms = cloud_of(scene)
    raw = ms.compute_partial_symmetries(create_patch_layers=True)
    count = int(raw["symmetry_count"])
    assert count >= 1
    cloud = ms.mesh(0)
    assert has_vertex_attribute(cloud, "symmetry_id")
    ids = cloud.vertex_custom_scalar_attribute_array("symmetry_id")
    layers = np.asarray(raw["patch_layer_ids"], int).reshape(-1, 2)
    source = ms.mesh(int(layers[0, 0]))
    assert source.face_number() == 0 and 0.3 * len(ids) < source.vertex_number() <= len(ids)
    # The layer holds the cloud's own points, and they carry symmetry 0 in the attribute.
    held = {tuple(p) for p in np.round(source.vertex_matrix(), 9)}
    labelled = {tuple(p) for p in np.round(cloud.vertex_matrix()[ids == 0], 9)}
    assert held <= labelled


def test_a_cloud_above_the_working_resolution_is_analysed_on_an_even_subset(requires_pipeline):
    """A scan-sized cloud: 120,000 points drawn at random on the mirrored scene's surface,
    above the default max_working_vertices (50,000).  It is analysed on a Poisson-disk subset
    of about 50,000 of its points, gives the planted mirror, and every one of its points gets
    a deviation measured on the cloud itself and, in the mirror's patches, the symmetry's id
    (carried from its nearest point of the subset)."""
    scene = scenes.make_scene("mirrored", 0)
    P = scenes.sample_surface(scene.vertices, scene.faces, 120000, np.random.default_rng(1))
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(vertex_matrix=P), "scan")
    raw = ms.compute_partial_symmetries(create_patch_layers=False)
    assert raw["point_cloud"] and abs(raw["working_vertices"] - 50000) <= 0.05 * 50000
    found = metrics.recall(scene, metrics.collect(ms, raw, 0).transforms)
    assert found["found"] == found["planted"], found["rows"]
    cloud = ms.mesh(0)
    assert cloud.vertex_number() == len(P) and cloud.face_number() == 0
    ids = cloud.vertex_custom_scalar_attribute_array("symmetry_id")
    quality = cloud.vertex_scalar_array()
    # The planted mirror maps each copy onto the other: nearly every point is in a patch,
    # many more than the subset holds, and deviates by far less than the 1 % tolerance.
    assert np.count_nonzero(ids >= 0) > 0.9 * len(P) > 2 * raw["working_vertices"]
    assert np.all(np.abs(quality[ids >= 0]) <= 0.01)
    assert np.count_nonzero(quality[ids >= 0]) > 0.9 * np.count_nonzero(ids >= 0)


def test_the_patches_picture_draws_a_cloud_as_dots_in_its_patches_colour(requires_pipeline, tmp_path):
    """detect() takes (points, no faces), and patches_picture draws the cloud's points, those
    of the mirror's patches in the first palette colour."""
    scene = scenes.make_scene("mirrored", 0)
    cloud = (scene.vertices, np.zeros((0, 3), int))
    result = meshlab_symmetry.detect(cloud)
    assert result.work["point_cloud"] and len(result.symmetries) >= 1
    picture = meshlab_symmetry.patches_picture(cloud, result, str(tmp_path / "cloud.png"))
    assert picture.legend[0].startswith("#0 ")
    left, top, right, bottom = picture.plot_box
    rgb = np.asarray(Image.open(picture.path).convert("RGB"))[top:bottom, left:right].reshape(-1, 3).astype(float)
    blue = np.array(meshlab_symmetry.pictures.PALETTE[0]) * 255
    assert np.mean(np.abs(rgb - blue).max(axis=1) < 40) > 0.02


@pytest.mark.parametrize("normals", [False, True], ids=["no_normals", "normals"])
def test_a_cloud_too_small_is_refused_and_left_unchanged(requires_pipeline, normals):
    """Eight points: without normals too few to estimate them; with normals, too sparse for
    any curvature, and told so (not told to subdivide, as a coarse mesh is)."""
    V = np.random.default_rng(3).random((8, 3))
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(vertex_matrix=V, v_normals_matrix=V - 0.5) if normals else pymeshlab.Mesh(vertex_matrix=V))
    before = mesh_snapshot(ms)
    with pytest.raises(pymeshlab.PyMeshLabException,
                       match="too sparse for the curvature radius" if normals else "too few to estimate normals"):
        ms.compute_partial_symmetries()
    assert_mesh_unchanged(ms, before)
