"""The compiled core (meshlab_symmetry._core, issue 8): detect(..., engine="core") runs the
pipeline without pymeshlab in the loop and gives the filter's answer for the same seed, with
progress on the calling thread, and the core's sentences as ValueError.

The filter passes its lengths through MeshLab's single-precision percentages (a radius of
1 % arrives as 0.0099999992 of the diagonal), the core takes them exactly: so transforms
and deviations are compared to 1e-9 of the diagonal, patches and kinds exactly."""
import json

import numpy as np
import pytest

from conftest import mirror_symmetric_mesh
from meshlab_symmetry import detect
from test_python_api import RUN, three_fold_mesh


@pytest.fixture(scope="module", params=["mirror", "three-fold"])
def both_engines(request):
    mesh = mirror_symmetric_mesh(3) if request.param == "mirror" else three_fold_mesh()
    calls = []
    core = detect(mesh, engine="core", progress=lambda percent, stage: calls.append((percent, stage)), **RUN)
    return detect(mesh, **RUN), core, calls


def test_the_core_gives_the_filters_symmetries(both_engines):
    filtered, core, _ = both_engines
    assert filtered.symmetries, "the shape has a planted symmetry: the comparison must not be empty"
    assert [s.kind for s in core.symmetries] == [s.kind for s in filtered.symmetries]
    for a, b in zip(filtered.symmetries, core.symmetries):
        assert np.array_equal(a.source_vertices, b.source_vertices)
        assert np.array_equal(a.target_vertices, b.target_vertices)
        assert np.abs(a.matrix - b.matrix).max() <= 1e-9 * filtered.diagonal
        assert a.rms_error == pytest.approx(b.rms_error, abs=1e-9)
        assert (a.is_generator, a.word, a.support) == (b.is_generator, b.word, b.support)
    assert np.abs(filtered.deviation - core.deviation).max() <= 1e-9
    assert np.array_equal(filtered.symmetry_id, core.symmetry_id)


def test_the_core_gives_the_filters_graph(both_engines):
    filtered, core, _ = both_engines

    def without_layers(graph):
        graph = json.loads(json.dumps(graph))
        for node in graph["nodes"]:
            del node["layers"], node["layer_ids"]
        for edge in graph["edges"]:
            del edge["transform"], edge["rms_error"]  # compared above, to rounding
        return graph
    assert without_layers(core.graph) == without_layers(filtered.graph)


def test_progress_rises_to_100_through_the_papers_stages(both_engines):
    _, _, calls = both_engines
    percents = [p for p, _ in calls]
    assert percents == sorted(percents) and percents[-1] == 100
    stages = {s for _, s in calls}
    assert any("curvature" in s for s in stages) and any("Verification" in s for s in stages), stages


def test_the_core_result_round_trips_through_json(both_engines):
    _, core, _ = both_engines
    assert type(core).from_json(core.to_json()).to_json() == core.to_json()


def test_the_cores_sentence_arrives_as_value_error():
    V, F = mirror_symmetric_mesh(2)
    V = V.copy()
    V[3] = np.nan
    with pytest.raises(ValueError, match="NaN|not a number"):
        detect((V, F), engine="core", **RUN)
    with pytest.raises(ValueError, match="point cloud|no faces"):
        detect((V[:10] * 0 + np.arange(30).reshape(10, 3), np.zeros((0, 3), int)), engine="core")
    with pytest.raises(ValueError, match="curvature_radius"):
        detect(mirror_symmetric_mesh(2), engine="core", curvature_radius=0.9)


def test_an_exception_in_the_progress_callback_stops_the_run():
    def stop(percent, stage):
        if percent >= 45:
            raise KeyboardInterrupt
    with pytest.raises(KeyboardInterrupt):
        detect(mirror_symmetric_mesh(3), engine="core", progress=stop, **RUN)


def test_engine_and_progress_are_checked():
    with pytest.raises(ValueError, match="engine"):
        detect(mirror_symmetric_mesh(2), engine="gpu")
    with pytest.raises(ValueError, match="core engine"):
        detect(mirror_symmetric_mesh(2), progress=print)
