"""The detector on CAD models as users have them (tests/cad_catalog.json: a furniture catalog
package's OBJ files, their global planes measured by the brute-force oracle
tests/oracle_mirror.py, never by the detector), each triangle stored once more the other way
round as shape collections store them.

With default parameters the filter must report a reflection within 1 degree and 1 % of the
diagonal of every global plane, and say what it repaired.  The models here were refused as
too coarse or gave no global plane before the repairs of issue 44, and are fast; the full
table over the catalog is tests/benchmarks/cad_mirrors.py.
"""
import os
import sys

import numpy as np
import pytest

TESTS_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, TESTS_DIR)
import cad_models  # noqa: E402
import metrics  # noqa: E402
import real_models  # noqa: E402

FOUND_DEG = 1.0
FOUND_OFFSET = 0.01
MODELS = ("Scopia/bar_table", "Scopia/desk_table", "Scopia/changing-table", "BlendSwap-CC-0/table",
          "BlendSwap-CC-0/technicalTable1")


@pytest.mark.parametrize("name", MODELS)
def test_every_global_plane_of_a_double_sided_cad_model_is_found(cad_catalog_set, name):
    import pymeshlab
    m = cad_catalog_set[name]
    V, F = m.load()
    faces = cad_models.double_sided(F)
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(V, faces), "model")
    res = metrics.run_filter(ms)
    assert int(res.raw["back_faces"]) == len(F)  # each face's other side, and nothing else
    found = res.transforms[(res.is_reflection != 0) & (res.kinds == 0)]
    planes = m.global_planes()
    assert planes
    for plane in planes:
        errors = [real_models.mirror_angle_error(T, plane, m.diagonal) for T in found]
        assert any(deg <= FOUND_DEG and off <= FOUND_OFFSET for deg, off in errors), \
            (plane.normal, sorted(errors)[:3])
    # the mesh given is the mesh kept
    np.testing.assert_array_equal(ms.current_mesh().face_matrix(), faces)
