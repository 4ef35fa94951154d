"""Shared fixtures for the Python tests of the symmetry filter (they use the built plugin).

- ``meshset(V, F=None, label="input")``: a pymeshlab.MeshSet whose current mesh has
  the given vertices (#V by 3) and triangles (#F by 3); F=None gives a point cloud.
- ``mesh_snapshot(ms)`` / ``assert_mesh_unchanged(ms, snapshot)``: what a failed filter
  call must leave as it was.
- ``pipeline_built``: False while the core still throws "not built yet";
  ``requires_pipeline``: skips a test in exactly that case, so such tests run by
  themselves as soon as the pipeline lands.
- ``mirror_symmetric_mesh()``: (V, F) of a closed surface whose only symmetry is the
  mirror x -> -x, with curvature that varies everywhere (no umbilic plateaus).
- ``real_model_set``: the real models of tests/real_models.json by name, fetched once
  per session (a failed fetch fails the tests that need them, with the fetch's reason).
- ``cad_catalog_set``: the CAD models of tests/cad_catalog.json by name, likewise.
- ``cgal_dir``: the folder of CGAL's CAD meshes (tests/fetch_cgal_meshes.sh), fetched once
  per session if missing, likewise.
- ``scene_detection(name, group=None)``: (scene, result, accuracy figures) of one scene of
  tests/scenes.py at seed 0, the filter run with its defaults plus the scene's filter_params
  (and transformation_group=group when given), once per session for all test modules.
"""
import os

import numpy as np
import pymeshlab
import pytest

import meshlab_symmetry

FILTER = meshlab_symmetry.FILTER_NAME
NOT_BUILT_MESSAGE = "detection pipeline is not built yet"
#: A lighter run than the defaults, for tests of everything but the detector's accuracy (the
#: interface, bad input, parameter extremes): on the bumpy sphere of mirror_symmetric_mesh(3)
#: 250 pair samples give 7,000 pairs, clustered in 1.5 s; 500 gave 15,000 in 3.4 s, and 17 s
#: under the sanitizers.  The mirror is found either way.
LIGHT_RUN = dict(random_seed=1, sample_count=2000, pair_sample_count=250)


def pytest_configure(config):
    config.addinivalue_line(
        "markers", "long_under_sanitizers: a whole detection that adds no code path to `make test-sanitize` "
        "(its core is in the sanitized C++ tests, its host code in lighter cases); that run leaves it out")


def make_meshset(vertices, faces=None, label="input"):
    vertices = np.asarray(vertices, dtype=np.float64).reshape(-1, 3)
    if faces is None or len(faces) == 0:
        mesh = pymeshlab.Mesh(vertex_matrix=vertices)
    else:
        mesh = pymeshlab.Mesh(vertex_matrix=vertices, face_matrix=np.asarray(faces, dtype=np.int32).reshape(-1, 3))
    ms = pymeshlab.MeshSet()
    ms.add_mesh(mesh, label)
    return ms


@pytest.fixture
def meshset():
    """Factory: ``meshset(V, F=None, label="input") -> pymeshlab.MeshSet``."""
    return make_meshset


def sphere(subdivisions=3):
    """(V, F) of pymeshlab's icosphere of radius 1."""
    ms = pymeshlab.MeshSet()
    ms.create_sphere(subdiv=subdivisions)
    m = ms.current_mesh()
    return m.vertex_matrix().copy(), m.face_matrix().copy()


def mirror_symmetric_mesh(subdivisions=4):
    """A bumpy sphere r(p) = 1 + 0.35 x^2 + 0.2 y + 0.15 z^3 (p on the unit sphere): symmetric
    under x -> -x only (the y and z^3 terms break every other mirror and rotation)."""
    V, F = sphere(subdivisions)
    u = V / np.linalg.norm(V, axis=1, keepdims=True)
    x, y, z = u[:, 0], u[:, 1], u[:, 2]
    r = 1 + 0.35 * x ** 2 + 0.2 * y + 0.15 * z ** 3
    return u * r[:, None], F


def noisy_mirror_mesh(sigma=0.002, bump=0.0):
    """mirror_symmetric_mesh(4) made approximate: normal noise of sigma (fraction of the
    diagonal) on its x > 0 half, and optionally a bump of that height (fraction of the
    radius) there, which has no mirror image.  Deterministic."""
    V, F = mirror_symmetric_mesh(4)
    unit = V / np.linalg.norm(V, axis=1, keepdims=True)
    rng = np.random.default_rng(0)
    right = V[:, 0] > 0
    diagonal = float(np.linalg.norm(V.max(axis=0) - V.min(axis=0)))
    W = V.copy()
    W[right] += unit[right] * rng.normal(0.0, sigma * diagonal, (int(right.sum()), 1))
    if bump:
        centre = np.array([0.6, 0.0, 0.8])
        W += unit * (bump * np.exp(-np.sum((unit - centre) ** 2, axis=1) / 0.05))[:, None]
    return W, F


def mesh_snapshot(ms):
    """Everything about the document a failed call must not change."""
    m = ms.current_mesh()
    return {
        "current_id": ms.current_mesh_id(),
        "mesh_count": ms.mesh_number(),
        "vertex_count": m.vertex_number(),
        "face_count": m.face_number(),
        "vertices": m.vertex_matrix().copy(),
        "faces": m.face_matrix().copy(),
        "quality": m.vertex_scalar_array().copy() if m.has_vertex_scalar() else None,
        "selection": m.vertex_selection_array().copy(),
        "has_symmetry_id": has_vertex_attribute(m, "symmetry_id"),
    }


def assert_mesh_unchanged(ms, snapshot):
    after = mesh_snapshot(ms)
    for key in ("current_id", "mesh_count", "vertex_count", "face_count", "has_symmetry_id"):
        assert after[key] == snapshot[key], key
    for key in ("vertices", "faces", "quality", "selection"):  # NaN equals NaN here
        np.testing.assert_array_equal(after[key], snapshot[key], err_msg=key)


def skip_unless_ci(reason):
    """A host's test whose prerequisite is missing (`reason`, or None when nothing is): off
    CI a skip, since a developer may not have built that host; on CI (CI=true) a failure,
    since `make test` builds every host before its tests run."""
    if reason is None:
        return
    if os.environ.get("CI") == "true":
        pytest.fail(reason)
    pytest.skip(reason)


def has_vertex_attribute(mesh, name):
    try:
        mesh.vertex_custom_scalar_attribute_array(name)
        return True
    except pymeshlab.PyMeshLabException:
        return False


@pytest.fixture(scope="session")
def pipeline_built():
    """Runs the filter once on a tetrahedron (cheap, valid defaults): False only if the core
    says it is not built."""
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=np.float64)
    F = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    ms = make_meshset(V, F)
    try:
        getattr(ms, FILTER)(create_patch_layers=False)
    except pymeshlab.PyMeshLabException as e:
        if NOT_BUILT_MESSAGE in str(e):
            return False
    return True


@pytest.fixture
def requires_pipeline(pipeline_built):
    if not pipeline_built:
        pytest.skip("the core's detection pipeline is not built yet")


def _models_by_name(load):
    """{name: model} of real_models' `load` (it fetches them); a failed fetch fails the test."""
    import os
    import sys
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    import real_models
    try:
        return {m.name: m for m in load(real_models)}
    except RuntimeError as e:
        pytest.fail(str(e))


@pytest.fixture(scope="session")
def real_model_set():
    return _models_by_name(lambda real_models: real_models.real_models())


@pytest.fixture(scope="session")
def cad_catalog_set():
    return _models_by_name(lambda real_models: real_models.cad_catalog_models())


def cgal_meshes_dir():
    """The folder of CGAL's CAD meshes, fetched by tests/fetch_cgal_meshes.sh if missing;
    a failed fetch fails the calling test with the script's output."""
    import os
    import subprocess
    import sys
    tests = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    sys.path.insert(0, tests)
    import scenes
    d = os.environ.get("SYMMETRY_CGAL_DIR") or scenes.DEFAULT_CGAL_DIR
    if not scenes.cad_meshes_available(d):
        script = os.path.join(tests, "fetch_cgal_meshes.sh")
        proc = subprocess.run([script, d], capture_output=True, text=True)
        if proc.returncode != 0:
            pytest.fail(f"{script} failed:\n{proc.stdout}{proc.stderr}")
    return d


@pytest.fixture(scope="session")
def cgal_dir():
    return cgal_meshes_dir()


_scene_runs = {}


def scene_detection(name, group=None):
    """(scene, metrics.DetectionResult, metrics.accuracy figures) of scene `name` at seed 0,
    detected with create_patch_layers and the scene's filter_params, transformation_group
    overridden by `group` if given; computed once per session."""
    import os
    import sys
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    import metrics
    import scenes
    key = (name, group)
    if key not in _scene_runs:
        s = scenes.make_scene(name, 0)
        params = dict(s.filter_params, create_patch_layers=True)
        if group is not None:
            params["transformation_group"] = group
        res = metrics.run_filter(s, **params)
        _scene_runs[key] = (s, res, metrics.accuracy(s, res))
    return _scene_runs[key]
