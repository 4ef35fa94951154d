"""`meshlab-symmetry batch` (issue 7): many meshes in parallel worker processes, resumable,
one JSON per mesh plus summary.csv, a failing file reported without stopping the rest; and
the same batch on a Dask distributed cluster of two local workers.

The meshes carry ground truth of their own: a bumpy sphere whose only symmetry is the mirror
x -> -x (conftest.mirror_symmetric_mesh), the same moved by a known rigid motion (its plane
moves with it), and a file that is not a mesh.
"""
import csv
import json
import os
import sys

import numpy as np
import pymeshlab
import pytest

sys.path.insert(0, os.path.dirname(__file__))
from conftest import mirror_symmetric_mesh  # noqa: E402

from meshlab_symmetry import SymmetryResult  # noqa: E402
from meshlab_symmetry.__main__ import main  # noqa: E402
from meshlab_symmetry.batch import SUMMARY, find_jobs, run_batch  # noqa: E402

#: a rigid motion (a turn about (1, 2, 2)/3 by 50 degrees, then a shift) applied to the second mesh
_AXIS = np.array([1.0, 2.0, 2.0]) / 3.0
_ANGLE = np.radians(50.0)
_K = np.array([[0, -_AXIS[2], _AXIS[1]], [_AXIS[2], 0, -_AXIS[0]], [-_AXIS[1], _AXIS[0], 0]])
ROTATION = np.eye(3) + np.sin(_ANGLE) * _K + (1 - np.cos(_ANGLE)) * _K @ _K
SHIFT = np.array([3.0, -1.0, 0.5])
#: lighter than the defaults (the batch machinery is what is tested here): 15 s a mesh less
PARAMETERS = dict(random_seed=0, sample_count=2000, pair_sample_count=250)


def _save(path, V, F):
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(V, F))
    ms.save_current_mesh(str(path))


@pytest.fixture(scope="module")
def dataset(tmp_path_factory):
    """in/sphere.ply (mirror normal x, through the origin), in/moved/sphere.obj (the same
    moved: normal R x, through SHIFT) and in/moved/broken.off (not a mesh)."""
    root = tmp_path_factory.mktemp("batch") / "in"
    (root / "moved").mkdir(parents=True)
    V, F = mirror_symmetric_mesh(3)
    _save(root / "sphere.ply", V, F)
    _save(root / "moved" / "sphere.obj", V @ ROTATION.T + SHIFT, F)
    (root / "moved" / "broken.off").write_text("OFF\n3 1 0\n0 0 0\n1 0 0\n")
    planes = {"sphere.ply.json": (np.array([1.0, 0, 0]), np.zeros(3)),
              "moved/sphere.obj.json": (ROTATION @ np.array([1.0, 0, 0]), SHIFT)}
    return root, planes


def _without_timings(path):
    with open(path) as f:
        result = json.load(f)
    assert result.pop("timings")
    return result


def _summary(output_dir):
    with open(os.path.join(output_dir, SUMMARY)) as f:
        return {row["mesh"]: row for row in csv.DictReader(f)}


def _assert_mirror_found(result_path, normal, point):
    """The result holds a reflection through the planted plane: normal within 1 degree, the
    plane within 0.5 % of the diagonal of the planted point."""
    with open(result_path) as f:
        result = SymmetryResult.from_json(f.read())
    planes = [s.plane for s in result.symmetries if s.kind == "reflection"]
    assert planes, [s.kind for s in result.symmetries]
    best = min(planes, key=lambda p: np.degrees(np.arccos(min(1.0, abs(float(np.dot(p.normal, normal)))))))
    angle = np.degrees(np.arccos(min(1.0, abs(float(np.dot(best.normal, normal))))))
    assert angle < 1.0, angle
    assert abs(float(np.dot(np.asarray(point) - best.point, best.normal))) < 0.005 * result.diagonal


def test_batch_analyses_every_mesh_reports_the_broken_one_and_resumes(dataset, tmp_path):
    root, planes = dataset
    out = tmp_path / "out"
    outcomes = run_batch([str(root)], str(out), PARAMETERS, jobs=2)
    status = {o.job.result: o.status for o in outcomes}
    assert status == {"sphere.ply.json": "done", "moved/sphere.obj.json": "done", "moved/broken.off.json": "failed"}
    for name, (normal, point) in planes.items():
        _assert_mirror_found(out / name, normal, point)
    assert not (out / "moved" / "broken.off.json").exists()

    rows = _summary(out)
    assert set(rows) == {o.job.mesh for o in outcomes}
    broken = rows[str(root / "moved" / "broken.off")]
    assert broken["status"] == "failed" and "broken.off" in broken["error"] and "\n" not in broken["error"]
    done = rows[str(root / "sphere.ply")]
    assert int(done["symmetries"]) >= 1 and int(done["vertices"]) == len(mirror_symmetric_mesh(3)[0])

    # Resumed: the finished meshes are skipped (their files untouched), the failed one retried.
    stamps = {name: os.stat(out / name).st_mtime_ns for name in planes}
    again = run_batch([str(root)], str(out), PARAMETERS, jobs=2)
    assert {o.job.result: o.status for o in again} == {**status, "sphere.ply.json": "skipped",
                                                      "moved/sphere.obj.json": "skipped"}
    assert {name: os.stat(out / name).st_mtime_ns for name in planes} == stamps
    assert _summary(out)[str(root / "sphere.ply")]["symmetries"] == done["symmetries"]

    # A result removed (or never finished) is analysed again, and only it.
    os.remove(out / "sphere.ply.json")
    third = run_batch([str(root)], str(out), PARAMETERS, jobs=1)
    assert {o.job.result: o.status for o in third}["sphere.ply.json"] == "done"
    assert {o.job.result: o.status for o in third}["moved/sphere.obj.json"] == "skipped"


def test_batch_on_a_dask_cluster_gives_the_local_results(dataset, tmp_path):
    distributed = pytest.importorskip("distributed")
    root, planes = dataset
    local, remote = tmp_path / "local", tmp_path / "dask"
    run_batch([str(root / "sphere.ply"), str(root / "moved" / "sphere.obj")], str(local), PARAMETERS, jobs=1)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        outcomes = run_batch([str(root)], str(remote), PARAMETERS, scheduler=cluster.scheduler_address)
    assert {o.job.result: o.status for o in outcomes} == {
        "sphere.ply.json": "done", "moved/sphere.obj.json": "done", "moved/broken.off.json": "failed"}
    for name in planes:
        # the same seed gives the same result on any worker at any thread count (all but the seconds)
        assert _without_timings(remote / name) == _without_timings(local / os.path.basename(name))


def test_batch_command_line(dataset, tmp_path, capsys):
    root, _ = dataset
    out = tmp_path / "cli"
    light = [arg for name, value in PARAMETERS.items() for arg in (f"--{name.replace('_', '-')}", str(value))]
    assert main(["batch", str(root / "*.ply"), "-o", str(out), "-j", "1", "--no-progress", *light]) == 0
    assert (out / "sphere.ply.json").exists() and len(_summary(out)) == 1
    assert "1 analysed, 0 already done, 0 failed" in capsys.readouterr().out
    assert main(["batch", str(root), "-o", str(out), "--no-progress", *light]) == 1  # the broken file
    assert main(["batch", str(tmp_path / "nothing-here"), "-o", str(out)]) == 1
    assert "names no mesh file" in capsys.readouterr().err


def test_find_jobs_keeps_results_of_same_named_meshes_apart(tmp_path):
    for folder in ("a", "b"):
        (tmp_path / folder).mkdir()
        (tmp_path / folder / "m.ply").write_text("")
    (tmp_path / "a" / "m.obj").write_text("")
    jobs = find_jobs([str(tmp_path)])
    assert sorted(j.result for j in jobs) == ["a/m.obj.json", "a/m.ply.json", "b/m.ply.json"]
    with pytest.raises(ValueError, match="same result"):
        find_jobs([str(tmp_path / "a"), str(tmp_path / "b")])
