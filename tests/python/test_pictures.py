"""The pictures of meshlab_symmetry.pictures and the HTML report, on the bumpy sphere of
conftest (its only symmetry is the mirror x -> -x): each picture is a PNG of PICTURE_SIZE
that shows something, the deviation picture's colours follow the signs of the deviation
(checked on the detected deviation and on deviations constructed with known signs), the
patches picture's legend names the mirror, the transformation-space picture's pairs cluster
at the detected mirror, and report.html links every picture and names every kind."""
import dataclasses
import os
import re
import subprocess
import sys

import numpy as np
import pymeshlab
import pytest
from PIL import Image

from conftest import mirror_symmetric_mesh
from meshlab_symmetry import SymmetryResult, detect, pictures

# Light settings, as the other output tests use: a second or two per run.
RUN = dict(random_seed=1, sample_count=2000, pair_sample_count=500)
SCRIPT = os.path.join(os.path.dirname(sys.executable), "meshlab-symmetry")
PICTURE_FUNCTIONS = ("deviation_picture", "patches_picture", "transformation_space_picture")


@pytest.fixture(scope="module")
def sphere():
    """((V, F), result) of the bumpy sphere."""
    mesh = mirror_symmetric_mesh(3)
    return mesh, detect(mesh, **RUN)


@pytest.fixture(scope="module")
def drawn(sphere, tmp_path_factory):
    """Each picture of the sphere, by function name, as the Picture it returned."""
    folder = tmp_path_factory.mktemp("pictures")
    mesh, result = sphere
    return {name: getattr(pictures, name)(mesh, result, str(folder / f"{name}.png")) for name in PICTURE_FUNCTIONS}


def pixels(picture):
    """The RGB pixels (int) of a picture's plot box; fails unless the file is a PNG."""
    with Image.open(picture.path) as image:
        assert image.format == "PNG"
        assert image.size == pictures.PICTURE_SIZE
        rgb = np.asarray(image.convert("RGB")).astype(int)
    left, top, right, bottom = picture.plot_box
    return rgb[top:bottom, left:right].reshape(-1, 3)


def drawn_share(rgb):
    """Share of pixels that are not the white background."""
    return float(np.mean(rgb.sum(axis=1) < 3 * 250))


def red_share(rgb):
    return float(np.mean(rgb[:, 0] - rgb[:, 2] > 40))


def blue_share(rgb):
    return float(np.mean(rgb[:, 2] - rgb[:, 0] > 40))


@pytest.mark.parametrize("name", PICTURE_FUNCTIONS)
def test_each_picture_is_a_png_of_its_size_that_shows_something(drawn, name):
    picture = drawn[name]
    assert os.path.getsize(picture.path) > 10_000
    rgb = pixels(picture)
    assert len(np.unique(rgb, axis=0)) > 100, "too few colours: a blank or flat picture"
    assert 0.05 < drawn_share(rgb) < 0.9


def deviation_cases(result, vertices):
    """(label, deviation) pairs: the detected one, and three with signs known by construction
    (values between half and all of a scale well above MIN_DEVIATION_SCALE)."""
    x = vertices[:, 0] / np.abs(vertices[:, 0]).max()
    magnitude = 0.003 * (0.5 + 0.5 * np.abs(x))
    return [("detected", result.deviation), ("both signs", np.where(x < 0, -magnitude, magnitude)),
            ("positive", magnitude), ("negative", -magnitude)]


@pytest.mark.parametrize("case", ["detected", "both signs", "positive", "negative"])
def test_deviation_colours_follow_the_signs_of_the_deviation(sphere, tmp_path, case):
    mesh, result = sphere
    deviation = dict(deviation_cases(result, mesh[0]))[case]
    shown = dataclasses.replace(result, deviation=deviation)
    strong = 0.5 * pictures.deviation_scale(shown)
    inside = shown.symmetry_id >= 0
    rgb = pixels(pictures.deviation_picture(mesh, shown, str(tmp_path / "d.png")))
    # A sign is in the picture (over 1 % of its pixels) exactly when over 5 % of the
    # vertices in a symmetry deviate that way by at least half the colour scale.
    assert (red_share(rgb) > 0.01) == (np.mean(deviation[inside] > strong) > 0.05)
    assert (blue_share(rgb) > 0.01) == (np.mean(deviation[inside] < -strong) > 0.05)


def test_the_detected_mirror_is_exact_so_its_deviation_picture_is_neutral(sphere, drawn):
    mesh, result = sphere
    assert np.abs(result.deviation).max() < 1e-9
    rgb = pixels(drawn["deviation_picture"])
    assert red_share(rgb) < 0.001 and blue_share(rgb) < 0.001


def test_vertices_in_no_symmetry_are_grey(sphere, tmp_path):
    mesh, result = sphere
    _, both = deviation_cases(result, mesh[0])[1]
    shown = dataclasses.replace(result, deviation=both, symmetry_id=np.full_like(result.symmetry_id, -1))
    rgb = pixels(pictures.deviation_picture(mesh, shown, str(tmp_path / "grey.png")))
    surface = rgb[rgb.sum(axis=1) < 3 * 250]
    assert len(surface) > 0.05 * len(rgb)
    assert np.mean(np.ptp(surface, axis=1) <= 6) > 0.98, "the surface is not grey"


def test_patches_legend_lists_the_reflection_in_its_colour(sphere, drawn):
    _, result = sphere
    picture = drawn["patches_picture"]
    assert [s.kind for s in result.symmetries] == ["reflection"]
    assert picture.legend[0] == "#0 reflection, area 100.0 %"
    assert "translucent: mirror plane" in picture.legend
    rgb = pixels(picture)
    blue = np.array(pictures.PALETTE[0]) * 255  # matplotlib's C0, shaded
    hue = rgb / np.maximum(rgb.max(axis=1, keepdims=True), 1)
    assert np.mean(np.abs(hue - blue / blue.max()).max(axis=1) < 0.08) > 0.05


def test_the_detected_mirror_sits_at_a_dense_place_of_the_detectors_own_gamma(sphere):
    """The picture's data is the detector's Γ: its improper votes pile up at the reported
    mirror (among the densest tenth of the places its votes lie), and a result of the filter
    engine gets the very Γ of a core run with the same parameters and seed."""
    mesh, result = sphere
    gamma = pictures.detector_transformation_space(mesh, result)  # the filter's result: the core reruns
    points = gamma["points"][gamma["improper"]]
    mirror = gamma["symmetries"][0]
    near = lambda p: np.sum(np.linalg.norm(points - p, axis=1) < 0.04)  # noqa: E731  (the default bandwidth)
    densities = [near(p) for p in points[::max(1, len(points) // 300)]]
    assert result.symmetries[0].kind == "reflection" and len(points) > 1000
    assert near(mirror) >= np.percentile(densities, 90), "the mirror is not among the densest places"
    core = detect(mesh, engine="core", **RUN).transformation_space
    assert np.array_equal(core["points"], gamma["points"]) and np.array_equal(core["modes"], gamma["modes"])
    assert len(gamma["modes"]) == len(gamma["mode_heights"]) == len(gamma["mode_improper"]) > 0


def test_gamma_is_not_written_to_json(sphere):
    mesh, _ = sphere
    result = detect(mesh, engine="core", **RUN)
    assert result.transformation_space is not None
    assert "transformation_space" not in result.to_json()
    assert SymmetryResult.from_json(result.to_json()).transformation_space is None


def test_plane_in_box_and_line_in_box():
    low, high = -np.ones(3), np.ones(3)
    square = pictures.plane_in_box(np.array([1.0, 0, 0]), 0.0, low, high)
    assert square.shape == (4, 3) and np.allclose(square[:, 0], 0)
    hexagon = pictures.plane_in_box(np.ones(3) / np.sqrt(3), 0.0, low, high)
    assert hexagon.shape == (6, 3)
    assert len(pictures.plane_in_box(np.array([0, 0, 1.0]), 2.0, low, high)) == 0
    segment = pictures.line_in_box(np.zeros(3), np.array([0, 1.0, 0]), low, high)
    assert np.allclose(sorted(segment[:, 1]), [-1, 1]) and np.allclose(segment[:, [0, 2]], 0)


def distances(points):
    return np.linalg.norm(points[:, None] - points[None], axis=2)


def test_classical_mds_keeps_the_distances_of_planar_points():
    rng = np.random.default_rng(0)
    flat = rng.normal(size=(50, 2)) @ rng.normal(size=(2, 6))  # 50 points on a plane of R^6
    assert np.allclose(distances(pictures.classical_mds(flat)), distances(flat), atol=1e-9)


def test_classical_mds_is_torgersons_double_centring():
    points = np.random.default_rng(2).normal(size=(40, 6)) * [3, 2, 1, 0.5, 0.2, 0.1]
    n = len(points)
    centring = np.eye(n) - 1.0 / n
    values, vectors = np.linalg.eigh(-0.5 * centring @ distances(points) ** 2 @ centring)
    expected = vectors[:, -2:][:, ::-1] * np.sqrt(values[-2:][::-1])
    xy = pictures.classical_mds(points)
    signs = np.sign(np.sum(xy * expected, axis=0))  # an eigenvector's sign is arbitrary
    assert np.allclose(xy * signs, expected, atol=1e-9)


def check_report(folder, result):
    """report.html links exactly the PNG files beside it, names every symmetry's kind and
    gives the parameters it ran with."""
    with open(os.path.join(folder, "report.html"), encoding="utf-8") as f:
        page = f.read()
    beside = {name for name in os.listdir(folder) if name.endswith(".png")}
    assert beside == {name for name, _, _ in pictures.REPORT_PICTURES}
    assert set(re.findall(r'<img src="([^"]+)"', page)) == beside
    for s in result.symmetries:
        assert f"<td>{s.kind}</td>" in page
    assert f"<td>sample_count</td><td>{result.parameters['sample_count']}</td>" in page


def test_report_links_every_picture_and_names_every_kind(sphere, tmp_path):
    mesh, result = sphere
    path = pictures.report_html(mesh, result, str(tmp_path))
    assert path == os.path.join(str(tmp_path), "report.html")
    check_report(str(tmp_path), result)


def test_cli_report_writes_the_report_beside_the_other_files(sphere, tmp_path):
    (V, F), _ = sphere
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(vertex_matrix=V, face_matrix=F))
    ms.save_current_mesh(str(tmp_path / "bumpy.ply"))
    out = tmp_path / "out"
    # Lighter still than RUN: this is a second detection, and only the files are checked.
    args = [SCRIPT, "detect", str(tmp_path / "bumpy.ply"), "-o", str(out), "--report", "--random-seed", "1",
            "--sample-count", "1000", "--pair-sample-count", "150"]
    proc = subprocess.run(args, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert "average vertex num" not in proc.stdout  # MeshLab's chatter is kept out
    with open(out / "symmetries.json") as f:
        result = SymmetryResult.from_json(f.read())
    assert result.parameters["sample_count"] == 1000
    check_report(str(out), result)
    assert os.path.exists(out / "bumpy.symmetry.ply")


def test_sample_size_curve_counts_what_each_run_finds(tmp_path):
    """The Figure 5 curve on the bumpy sphere (one mirror): a point per n' asked for plus the
    automatic one, each the count that a detection at that n' reports, drawn in a picture
    that shows something."""
    mesh = mirror_symmetric_mesh(3)
    light = dict(random_seed=1, sample_count=2000, transformation_group=2)
    picture, points = pictures.sample_size_curve(mesh, str(tmp_path / "figure5.png"), sizes=(20, 500), **light)
    assert len(points) == 3
    assert [p[0] for p in points[:2]] == [20, 500]
    assert points[1][1] == len(detect(mesh, engine="core", pair_sample_count=500, **light).symmetries) >= 1
    assert any("automatic" in text for text in picture.legend)
    assert len(np.unique(pixels(picture), axis=0)) > 20
