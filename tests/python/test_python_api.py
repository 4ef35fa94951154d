"""The Python API (meshlab_symmetry.detect, SymmetryResult, its JSON and exports) and the
`meshlab-symmetry detect` command line, checked against shapes whose symmetries are known
by construction: the bumpy sphere of conftest (only the mirror x -> -x) and a bumpy sphere
with a 3-fold rotation and no mirror."""
import dataclasses
import inspect
import json
import math
import os
import subprocess
import sys

import numpy as np
import pymeshlab
import pytest
from scipy.spatial import cKDTree

from conftest import FILTER, make_meshset, mirror_symmetric_mesh, sphere
from meshlab_symmetry import Axis, Plane, SymmetryResult, detect
from meshlab_symmetry.api import PARAMETERS
from meshlab_symmetry.api import _VertexIndex as VertexIndex
from meshlab_symmetry.geometry import describe_discrete, describe_family, rotation_about_line
from meshlab_symmetry.result import SCHEMA_PATH

# Light settings, as the other output tests use: a few seconds per run.
RUN = dict(random_seed=1, sample_count=2000, pair_sample_count=500)
SCRIPT = os.path.join(os.path.dirname(sys.executable), "meshlab-symmetry")
MIRROR_KINDS = ("reflection", "glide reflection", "rotoreflection")

# The 3-fold shape: its axis is a 3-fold axis of the icosphere's own tessellation (the
# cyclic permutation of x, y, z), so the copies match vertex for vertex.
AXIS = np.ones(3) / math.sqrt(3)
E1 = np.array([1.0, -1.0, 0.0]) / math.sqrt(2)
E2 = np.cross(AXIS, E1)
CENTRE = np.array([0.3, -0.2, 0.5])


def three_fold_radius(u):
    """r(u) = 1 + 0.35 (Re w^3 + z Im w^3) + 0.15 z^3, w = x + iy in the axis frame: w^3
    turns by 360 degrees under a turn of 120 about the axis; the z Im w^3 term breaks the
    vertical mirrors, and z^3 the horizontal mirror, the half turns about horizontal axes and
    the rotoreflections."""
    x, y, z = u @ E1, u @ E2, u @ AXIS
    return 1 + 0.35 * ((x ** 3 - 3 * x * y ** 2) + z * (3 * x ** 2 * y - y ** 3)) + 0.15 * z ** 3


def three_fold_mesh():
    V, F = sphere(3)
    u = V / np.linalg.norm(V, axis=1, keepdims=True)
    return u * three_fold_radius(u)[:, None] + CENTRE, F


def diagonal_of(V):
    return float(np.linalg.norm(V.max(axis=0) - V.min(axis=0)))


def angle_between_lines(a, b):
    return math.degrees(math.acos(min(1.0, abs(float(a @ b)) / (np.linalg.norm(a) * np.linalg.norm(b)))))


def fibonacci_sphere(n):
    i = np.arange(n) + 0.5
    z = 1 - 2 * i / n
    phi = math.pi * (1 + 5 ** 0.5) * i
    rho = np.sqrt(1 - z ** 2)
    return np.column_stack([rho * np.cos(phi), rho * np.sin(phi), z])


class DuckMesh:
    """What trimesh.Trimesh offers detect: .vertices and .faces arrays."""

    def __init__(self, vertices, faces):
        self.vertices, self.faces = vertices, faces.astype(np.int64)


# --- runs shared by the tests ----------------------------------------------------------------

@pytest.fixture(scope="module")
def mirror_file(tmp_path_factory):
    """The mirror-symmetric bumpy sphere as a PLY file, and its vertices and faces as
    pymeshlab reads them back (the arrays every other input form is given)."""
    path = tmp_path_factory.mktemp("mirror") / "bumpy.ply"
    make_meshset(*mirror_symmetric_mesh(3)).save_current_mesh(str(path))
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(str(path))
    return path, ms.current_mesh().vertex_matrix().copy(), ms.current_mesh().face_matrix().copy()


@pytest.fixture(scope="module")
def mirror_result(mirror_file):
    return detect(str(mirror_file[0]), transformation_group="reflections", **RUN)


@pytest.fixture(scope="module")
def other_forms(mirror_file):
    """detect on the same mesh given as a pymeshlab.Mesh, as arrays and as a duck-typed
    object; with the caller's pymeshlab.Mesh before and after."""
    _, V, F = mirror_file
    mesh = pymeshlab.Mesh(vertex_matrix=V, face_matrix=F)
    before = mesh_state(mesh)
    results = {"pymeshlab.Mesh": detect(mesh, transformation_group=2, **RUN)}
    after = mesh_state(mesh)
    results["(V, F)"] = detect((V, F), transformation_group=2, **RUN)
    results["duck"] = detect(DuckMesh(V, F), transformation_group=2, **RUN)
    return results, before, after


@pytest.fixture(scope="module")
def rotation_result():
    return detect(three_fold_mesh(), **RUN)


def mesh_state(mesh):
    state = {"vertices": mesh.vertex_matrix().copy(), "faces": mesh.face_matrix().copy(),
             "quality": mesh.vertex_scalar_array().copy(), "colours": mesh.vertex_color_matrix().copy()}
    try:
        state["symmetry_id"] = mesh.vertex_custom_scalar_attribute_array("symmetry_id").copy()
    except pymeshlab.PyMeshLabException:
        state["symmetry_id"] = None
    return state


def comparable(result):
    """The result as JSON data, without the run's timings."""
    data = json.loads(result.to_json())
    del data["timings"]
    return data


# --- the signature and the parameters --------------------------------------------------------

def test_detect_has_every_filter_parameter_with_its_default_and_help():
    ms = make_meshset(*sphere(2))
    values = ms.filter_parameter_values(FILTER)
    diagonal = ms.current_mesh().bounding_box().diagonal()
    signature = inspect.signature(detect)
    # the mesh, the filter's parameters, then how to run it (engine, progress)
    names = [n for n in signature.parameters if n not in ("mesh", "engine", "progress")]
    assert names == [n for n in values if n != "create_patch_layers"] == [p.name for p in PARAMETERS]
    assert list(signature.parameters)[-2:] == ["engine", "progress"]
    assert "engine" in detect.__doc__ and "progress(percent, stage)" in detect.__doc__
    assert signature.return_annotation == "SymmetryResult"
    for p in PARAMETERS:
        parameter = signature.parameters[p.name]
        assert parameter.kind is inspect.Parameter.KEYWORD_ONLY and parameter.annotation is not inspect.Parameter.empty
        assert parameter.default == p.default, p.name
        assert f"{p.name} = {p.default!r} ({p.unit})" in detect.__doc__
        if p.convert == "length":   # the filter gives an absolute length, detect a fraction
            assert values[p.name] / diagonal == pytest.approx(p.default, rel=1e-6), p.name
        elif p.convert == "area":   # the filter's percent
            assert values[p.name] == pytest.approx(100 * p.default), p.name
        else:   # MeshLab keeps its floats in single precision
            assert values[p.name] == pytest.approx(p.default, rel=1e-6), p.name


@pytest.mark.parametrize("name,value,said", [("curvature_radius", 0.75, "curvature_radius is 0.75,"),
                                             ("verification_tolerance", 0.3, "verification_tolerance is 0.3,"),
                                             ("min_patch_area", 1.5, r"min_patch_area \(percent of the surface area\) is 150,")])
def test_fractions_reach_the_filter_as_the_same_fraction(name, value, said):
    """The core refuses each of these, naming the value it received (min_patch_area in the
    percent of MeshLab's dialog): had detect passed 0.3 as 0.3 %, the core would have
    received 0.003 and run."""
    with pytest.raises(pymeshlab.PyMeshLabException, match="The parameter " + said):
        detect(sphere(2), **{name: value})


@pytest.mark.parametrize("name", ["cluster_bandwidth", "basis_tolerance", "curvature_radius"])
def test_a_length_beyond_the_diagonal_is_refused_by_name(name):
    with pytest.raises(ValueError, match=f"{name} is 1.5, but it is a fraction of the bounding-box diagonal"):
        detect(sphere(2), **{name: 1.5})


@pytest.mark.parametrize("mesh,error", [
    ((sphere(1)[0], np.array([[0, 1, 999]])), ValueError),
    ((sphere(1)[0], np.array([[0.0, 1.0, 2.0]])), TypeError),
    ((sphere(1)[0][:, :2], sphere(1)[1]), ValueError),
    (42, TypeError),
    ("/no/such/mesh.ply", FileNotFoundError),
], ids=["face_index_out_of_range", "float_faces", "2d_vertices", "not_a_mesh", "missing_file"])
def test_unusable_input_is_refused_before_the_filter(mesh, error):
    with pytest.raises(error):
        detect(mesh)


def test_unknown_group_name_is_refused():
    with pytest.raises(ValueError, match="transformation_group 'mirrors'"):
        detect(sphere(2), transformation_group="mirrors")


# --- the mirror of the bumpy sphere ------------------------------------------------------------

def test_mirror_plane_is_x_equals_zero(mirror_result, mirror_file):
    _, V, _ = mirror_file
    d = diagonal_of(V)
    assert mirror_result.vertex_count == len(V) and mirror_result.diagonal == pytest.approx(d)
    assert mirror_result.parameters["transformation_group"] == 2
    (mirror,) = [s for s in mirror_result.symmetries if s.source_area >= 0.9]
    assert mirror.kind == "reflection" and mirror.is_reflection
    n = mirror.plane.normal
    assert np.linalg.norm(n) == pytest.approx(1) and angle_between_lines(n, np.array([1.0, 0, 0])) < 1
    assert abs(mirror.plane.offset) < 1e-3 * d and abs(mirror.plane.point[0]) < 1e-3 * d
    assert n @ mirror.plane.point == pytest.approx(mirror.plane.offset, abs=1e-9 * d)
    assert mirror.axis is None and mirror.angle_degrees is None and mirror.translation is None


def test_patches_are_input_vertices_that_the_mirror_maps_onto_each_other(mirror_result, mirror_file):
    _, V, _ = mirror_file
    d = diagonal_of(V)
    for s in mirror_result.symmetries:
        for rows in (s.source_vertices, s.target_vertices):
            assert rows.dtype == np.int64 and len(rows) > 0
            assert np.all(np.diff(rows) > 0) and rows[0] >= 0 and rows[-1] < len(V)
        if s.source_area >= 0.9:
            mirrored = V[s.source_vertices] * np.array([-1.0, 1, 1])   # the true mirror
            gaps, _ = cKDTree(V[s.target_vertices]).query(mirrored)
            assert gaps.max() < 0.01 * d


def test_per_vertex_outputs_follow_the_patches(mirror_result, rotation_result):
    for result in (mirror_result, rotation_result):
        assert result.deviation.dtype == np.float64 and result.deviation.shape == (result.vertex_count,)
        assert result.symmetry_id.dtype == np.int64 and result.symmetry_id.shape == (result.vertex_count,)
        assert np.all(result.deviation[result.symmetry_id < 0] == 0)
        for s in result.symmetries:
            labelled = np.flatnonzero(result.symmetry_id == s.index)
            assert np.all(np.isin(labelled, np.union1d(s.source_vertices, s.target_vertices)))


def test_every_input_form_gives_the_same_result(mirror_result, other_forms):
    results, _, _ = other_forms
    expected = comparable(mirror_result)
    for form, result in results.items():
        assert comparable(result) == expected, form


def test_the_callers_mesh_is_unchanged(other_forms):
    _, before, after = other_forms
    assert after["symmetry_id"] is None and before["symmetry_id"] is None
    for key in ("vertices", "faces", "quality", "colours"):
        np.testing.assert_array_equal(after[key], before[key], err_msg=key)


# --- JSON --------------------------------------------------------------------------------------

def assert_same(a, b, where):
    """Equal value by value: arrays of the same dtype and shape, scalars of the same type."""
    if isinstance(a, np.ndarray):
        assert isinstance(b, np.ndarray) and (a.dtype, a.shape) == (b.dtype, b.shape), where
        np.testing.assert_array_equal(a, b, err_msg=where)
    elif dataclasses.is_dataclass(a):
        assert type(a) is type(b), where
        for f in dataclasses.fields(a):
            assert_same(getattr(a, f.name), getattr(b, f.name), f"{where}.{f.name}")
    elif isinstance(a, list) and a and dataclasses.is_dataclass(a[0]):
        assert len(a) == len(b), where
        for k, (x, y) in enumerate(zip(a, b)):
            assert_same(x, y, f"{where}[{k}]")
    else:
        assert type(a) is type(b) and a == b, where


def test_json_round_trip_is_exact(mirror_result, rotation_result):
    for result in (mirror_result, rotation_result):
        text = result.to_json()
        again = SymmetryResult.from_json(text)
        assert_same(result, again, "result")
        assert again.to_json() == text


def test_from_json_refuses_other_documents(rotation_result):
    data = json.loads(rotation_result.to_json())
    with pytest.raises(ValueError, match="schema_version"):
        SymmetryResult.from_json(json.dumps(dict(data, schema_version=2)))
    with pytest.raises(ValueError, match="not a meshlab-symmetry-result"):
        SymmetryResult.from_json(json.dumps({"symmetries": []}))


def check_by_hand(document, schema):
    """The schema's required keys, closed objects, constants and kinds, without jsonschema."""
    assert set(document) == set(schema["required"]) == set(schema["properties"])
    assert document["schema"] == schema["properties"]["schema"]["const"]
    assert document["schema_version"] == schema["properties"]["schema_version"]["const"]
    symmetry = schema["$defs"]["symmetry"]
    for s in document["symmetries"]:
        assert set(s) == set(symmetry["required"]) == set(symmetry["properties"])
        assert s["kind"] in symmetry["properties"]["kind"]["enum"]
        assert len(s["matrix"]) == 4 and all(len(row) == 4 for row in s["matrix"])
        for name in ("plane", "axis"):
            if s[name] is not None:
                assert set(s[name]) == set(schema["$defs"][name]["required"])
    assert set(schema["properties"]["graph"]["required"]) <= set(document["graph"])
    assert all(isinstance(v, float) for v in document["deviation"])
    assert all(isinstance(v, int) and v >= -1 for v in document["symmetry_id"])


def test_json_follows_its_schema(mirror_result, rotation_result):
    with open(SCHEMA_PATH) as f:
        schema = json.load(f)
    try:
        import jsonschema
    except ImportError:
        jsonschema = None
    for result in (mirror_result, rotation_result):
        document = json.loads(result.to_json())
        check_by_hand(document, schema)
        if jsonschema is not None:
            jsonschema.Draft202012Validator.check_schema(schema)
            jsonschema.validate(document, schema, cls=jsonschema.Draft202012Validator)


# --- the 3-fold rotation ---------------------------------------------------------------------

def test_the_three_fold_shape_is_what_it_claims():
    """Ground truth for the next tests: the 120-degree turn maps the shape onto itself, and
    no mirror or half turn comes near (each leaves an RMS radius change above 0.05)."""
    u = fibonacci_sphere(1500)
    r = three_fold_radius(u)
    turn = rotation_about_line(np.zeros(3), AXIS, 120.0)[:3, :3]
    np.testing.assert_allclose(three_fold_radius(u @ turn.T), r, atol=1e-12)
    for n in fibonacci_sphere(3000):
        mirror = np.eye(3) - 2 * np.outer(n, n)
        for m in (mirror, -mirror):   # -mirror is the half turn about n
            assert np.sqrt(np.mean((three_fold_radius(u @ m.T) - r) ** 2)) > 0.05, n


def test_planted_rotation_is_found_with_its_axis_and_order(rotation_result):
    V, _ = three_fold_mesh()
    d = diagonal_of(V)
    whole = [s for s in rotation_result.symmetries if s.source_area >= 0.95]
    assert whole and all(s.kind == "rotation" for s in whole), [s.kind for s in whole]
    for s in whole:
        assert s.order == 3 and abs(s.angle_degrees - 120) < 1
        assert angle_between_lines(s.axis.direction, AXIS) < 1
        off_axis = (s.axis.point - CENTRE) - AXIS * ((s.axis.point - CENTRE) @ AXIS)
        assert np.linalg.norm(off_axis) < 0.005 * d
    assert not any(s.kind in MIRROR_KINDS and s.source_area >= 0.5 for s in rotation_result.symmetries)


def signed_turn_about_axis(rotation):
    """Degrees in [0, 360) by which ``rotation`` turns E1 about AXIS."""
    image = rotation @ E1
    return math.degrees(math.atan2(image @ E2, image @ E1)) % 360


def test_bop_export_lists_the_two_turns_of_the_three_fold_rotation(rotation_result):
    V, _ = three_fold_mesh()
    d = diagonal_of(V)
    info = rotation_result.to_bop_models_info(model_id=7)
    json.dumps(info)
    assert list(info) == ["7"] and info["7"]["symmetries_continuous"] == []
    matrices = [np.array(m, dtype=float).reshape(4, 4) for m in info["7"]["symmetries_discrete"]]
    assert len(matrices) == 2   # 120 and 240 degrees; not the partial half turns, not the identity
    turns = sorted(signed_turn_about_axis(m[:3, :3]) for m in matrices)
    assert turns == pytest.approx([120, 240], abs=1)
    tree = cKDTree(V)
    for m in matrices:
        assert np.linalg.det(m[:3, :3]) == pytest.approx(1) and np.allclose(m[3], [0, 0, 0, 1])
        np.testing.assert_allclose(m[:3, :3] @ AXIS, AXIS, atol=0.02)
        assert np.linalg.norm(m[:3, :3] @ CENTRE + m[:3, 3] - CENTRE) < 0.005 * d
        assert tree.query(V @ m[:3, :3].T + m[:3, 3])[0].max() < 0.01 * d


def test_bop_export_never_takes_a_reflection(mirror_result):
    assert mirror_result.to_bop_models_info() == {"1": {"symmetries_discrete": [], "symmetries_continuous": []}}


def test_shrec_export_gives_the_mirror_plane(mirror_result, mirror_file, rotation_result):
    _, V, _ = mirror_file
    d = diagonal_of(V)
    lines = mirror_result.to_shrec_planes().splitlines()
    assert len(lines) == 1
    numbers = np.array([float(x) for x in lines[0].split()])
    assert numbers.shape == (6,)
    normal, point = numbers[:3], numbers[3:]
    assert np.linalg.norm(normal) == pytest.approx(1) and angle_between_lines(normal, np.array([1.0, 0, 0])) < 1
    centre = (V.min(axis=0) + V.max(axis=0)) / 2
    assert abs(point[0]) < 1e-3 * d and np.allclose(point[1:], centre[1:], atol=1e-3 * d)
    assert rotation_result.to_shrec_planes() == ""


# --- what the matrices are, on transformations built by hand ------------------------------------

def motion(linear, shift):
    m = np.eye(4)
    m[:3, :3], m[:3, 3] = linear, shift
    return m


N = np.array([1.0, 2.0, 2.0]) / 3          # a unit normal / axis
Q = np.array([0.4, -0.1, 0.3])            # a point of the plane / axis
C = np.array([0.1, 0.2, -0.3])            # the bounding-box centre
G = np.cross(N, [0.0, 0.0, 1.0])          # a slide along the plane
G *= 0.3 / np.linalg.norm(G)
MIRROR = np.eye(3) - 2 * np.outer(N, N)


def nearest_on_line(point, direction, to):
    return point + direction * ((to - point) @ direction)


def test_reflection_and_glide_reflection():
    fields = describe_discrete(motion(MIRROR, 2 * (N @ Q) * N), 1.0, True, 1.0, C)
    assert fields["kind"] == "reflection" and "translation" not in fields
    plane = fields["plane"]
    assert angle_between_lines(plane.normal, N) < 1e-6
    assert plane.normal @ Q == pytest.approx(plane.offset)
    np.testing.assert_allclose(plane.point, C - N * (N @ C - N @ Q), atol=1e-12)
    glide = describe_discrete(motion(MIRROR, 2 * (N @ Q) * N + G), 1.0, True, 1.0, C)
    assert glide["kind"] == "glide reflection"
    np.testing.assert_allclose(glide["translation"], G, atol=1e-12)


@pytest.mark.parametrize("degrees,angle,order,direction", [
    (72.0, 72.0, 5, N), (250.0, 110.0, None, -N), (180.0, 180.0, 2, N), (120.4, 120.4, 3, N), (120.6, 120.6, None, N)])
def test_rotation_about_a_line_off_the_origin(degrees, angle, order, direction):
    fields = describe_discrete(rotation_about_line(Q, N, degrees), 1.0, False, 1.0, C)
    assert fields["kind"] == "rotation" and fields["order"] == order
    assert fields["angle_degrees"] == pytest.approx(angle)
    if angle < 180:   # a half turn has no handedness to orient its axis by
        np.testing.assert_allclose(fields["axis"].direction, direction, atol=1e-9)
    np.testing.assert_allclose(fields["axis"].point, nearest_on_line(Q, N, C), atol=1e-9)


def test_screw_rotoreflection_translation_and_scaling():
    screw = rotation_about_line(Q, N, 90.0)
    screw[:3, 3] += 0.2 * N
    fields = describe_discrete(screw, 1.0, False, 1.0, C)
    assert fields["kind"] == "screw" and fields["order"] == 4
    np.testing.assert_allclose(fields["translation"], 0.2 * N, atol=1e-12)

    turn = rotation_about_line(Q, N, 60.0)
    mirror = motion(MIRROR, 2 * (N @ Q) * N)
    fields = describe_discrete(turn @ mirror, 1.0, True, 1.0, C)
    assert fields["kind"] == "rotoreflection" and fields["order"] == 6
    assert fields["angle_degrees"] == pytest.approx(60)
    np.testing.assert_allclose(fields["axis"].point, Q, atol=1e-12)   # its one fixed point
    assert fields["plane"].normal @ Q == pytest.approx(fields["plane"].offset)

    fields = describe_discrete(motion(np.eye(3), G), 1.0, False, 1.0, C)
    assert set(fields) == {"kind", "translation"} and fields["kind"] == "translation"
    np.testing.assert_array_equal(fields["translation"], G)
    assert describe_discrete(motion(2 * np.eye(3), Q), 2.0, False, 1.0, C) == {"kind": "uniform scaling"}


def test_families():
    helix = describe_family(3, Q, N, 0.05, 2.0, C)
    assert helix["kind"] == "helical family" and helix["pitch"] == pytest.approx(0.1)
    np.testing.assert_allclose(helix["axis"].point, nearest_on_line(Q, N, C), atol=1e-12)
    assert isinstance(describe_family(4, Q, N, 0.0, 2.0, C)["plane"], Plane)
    np.testing.assert_array_equal(describe_family(5, Q, np.zeros(3), 0.0, 2.0, C)["center"], Q)
    assert isinstance(describe_family(1, Q, N, 0.0, 2.0, C)["axis"], Axis)


# --- the command line ------------------------------------------------------------------------

def run_script(*args):
    assert os.path.exists(SCRIPT), ("the console script is not installed: run "
                                    ".venv/bin/python -m pip install --no-deps -e python_bindings")
    return subprocess.run([SCRIPT, *args], capture_output=True, text=True, timeout=600)


@pytest.mark.parametrize("engine", ["core", "filter"])
def test_cli_detect_writes_every_file(mirror_file, mirror_result, tmp_path, engine):
    path, V, _ = mirror_file
    out = tmp_path / "out"
    proc = run_script("detect", str(path), "-o", str(out), "--transformation-group", "reflections",
                      "--sample-count", "2000", "--pair-sample-count", "500", "--random-seed", "1",
                      "--engine", engine)
    assert proc.returncode == 0, proc.stderr
    assert proc.stderr == ""  # no progress bar when stderr is not a terminal, unless asked for
    result = SymmetryResult.from_json((out / "symmetries.json").read_text())
    expected = mirror_result if engine == "filter" else detect(str(path), transformation_group="reflections",
                                                               engine="core", **RUN)
    assert comparable(result) == comparable(expected)   # the options reached the engine
    patches = {f"bumpy.symmetry_{k}_{side}.ply" for k in range(len(result.symmetries)) for side in ("source", "target")}
    assert set(os.listdir(out)) == {"bumpy.symmetry.ply", "symmetries.json"} | patches
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(str(out / "bumpy.symmetry.ply"))
    m = ms.current_mesh()
    assert m.vertex_number() == len(V) and m.has_vertex_color()
    np.testing.assert_allclose(m.vertex_scalar_array(), result.deviation, atol=1e-7)
    for s in result.symmetries:
        ms.load_new_mesh(str(out / f"bumpy.symmetry_{s.index}_source.ply"))
        assert ms.current_mesh().vertex_number() == len(s.source_vertices)
    assert "reflection" in proc.stdout and "verification" in proc.stdout


def test_cli_progress_bar_names_each_stage_up_to_100(mirror_file, tmp_path):
    proc = run_script("detect", str(mirror_file[0]), "-o", str(tmp_path / "out"), "--progress",
                      "--sample-count", "2000", "--pair-sample-count", "500")
    assert proc.returncode == 0, proc.stderr
    lines = proc.stderr.splitlines()
    assert all(line.startswith("[") and "%" in line for line in lines), lines
    assert any("Verification" in line for line in lines) and lines[-1].endswith("100% Done"), lines
    percents = [int(line.split("]")[1].split("%")[0]) for line in lines]
    assert percents == sorted(percents)


def test_cli_progress_needs_the_core_engine(mirror_file, tmp_path):
    proc = run_script("detect", str(mirror_file[0]), "-o", str(tmp_path / "out"), "--progress", "--engine", "filter")
    assert proc.returncode == 2
    assert proc.stderr.strip().splitlines() == [
        "meshlab-symmetry: error: --progress needs --engine core (pymeshlab runs a filter without a callback)"]


def test_cli_help_lists_every_filter_parameter():
    proc = run_script("detect", "--help")
    assert proc.returncode == 0
    names = [n for n in make_meshset(*sphere(1)).filter_parameter_values(FILTER) if n != "create_patch_layers"]
    text = " ".join(proc.stdout.split())
    for name in names:
        assert f"--{name.replace('_', '-')}" in text, name
    assert text.count("default: ") >= len(names)
    assert "fraction of the bounding-box diagonal" in text


def point_cloud_file(directory):
    """Eight points: too few for the normals of a point cloud."""
    path = directory / "cloud.ply"
    make_meshset(np.random.default_rng(1).random((8, 3))).save_current_mesh(str(path))
    return str(path)


@pytest.mark.parametrize("case", ["missing_file", "point_cloud", "parameter_out_of_range", "parameter_not_a_number"])
def test_cli_errors_are_one_line(case, mirror_file, tmp_path):
    mesh = str(mirror_file[0])
    args = {
        "missing_file": [str(tmp_path / "missing.ply")],
        "point_cloud": [point_cloud_file(tmp_path)],
        "parameter_out_of_range": [mesh, "--umbilic-ratio", "1.5"],
        "parameter_not_a_number": [mesh, "--sample-count", "many"],
    }[case]
    out = tmp_path / "out"
    proc = run_script("detect", *args, "-o", str(out))
    assert proc.returncode != 0
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("meshlab-symmetry: error: "), proc.stderr
    assert "Traceback" not in proc.stderr
    assert not out.exists() or not os.listdir(out)


def test_a_position_shared_by_several_input_vertices_maps_to_all_of_them():
    V = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 0, 0], [0, 0, 1]])
    index = VertexIndex(V)
    np.testing.assert_array_equal(index.rows_at(np.array([[1.0, 0, 0], [0, 0, 1]])), [1, 3, 4])
    with pytest.raises(RuntimeError):
        index.rows_at(np.array([[1.0, 0, 1e-12]]))
