"""Input that files and pipelines often write broken, and that the filter repairs on its own
copy (plugin/core/input_repair.h): a triangle soup, faces turned both ways, a part turned
inward.  The planted symmetry is found as on the clean mesh, the mesh itself is unchanged,
and the outputs say what was repaired.  (Input the filter refuses is in test_filter_api.py.)"""
import numpy as np
import pytest

from conftest import FILTER, LIGHT_RUN as RUN, make_meshset, mirror_symmetric_mesh

MIRROR_X = np.diag([-1.0, 1, 1])


def soup(V, F):
    """Every triangle with three vertices of its own, as an STL file stores it."""
    return V[F.reshape(-1)].copy(), np.arange(3 * len(F)).reshape(-1, 3)


def turned(F, which):
    F = F.copy()
    F[which] = F[which][:, [0, 2, 1]]
    return F


def half_turned(F, seed=0):
    return np.random.default_rng(seed).random(len(F)) < 0.5


def detect(V, F):
    ms = make_meshset(V, F)
    result = getattr(ms, FILTER)(**RUN)
    return ms, result


def mirror_error(result, M):
    """How far the reported reflection nearest to x -> M x is from it (linear part)."""
    errors = [np.linalg.norm(result["transforms"][16 * k:16 * k + 16].reshape(4, 4)[:3, :3] - M)
              for k in range(result["symmetry_count"]) if result["is_reflection"][k]]
    return min(errors, default=np.inf)


@pytest.fixture(scope="module")
def bumpy():
    return mirror_symmetric_mesh(3)


@pytest.fixture(scope="module")
def clean_run(bumpy):
    return detect(*bumpy)


def test_a_clean_mesh_needs_no_repair(requires_pipeline, clean_run):
    _, r = clean_run
    assert r["welded_vertices"] == 0 and r["flipped_faces"] == 0
    assert mirror_error(r, MIRROR_X) < 0.2


def test_a_triangle_soup_is_welded_and_its_mirror_found(requires_pipeline, bumpy, clean_run):
    V, F = soup(*bumpy)
    ms, r = detect(V, F)
    assert r["welded_vertices"] == len(V) - len(bumpy[0])
    assert r["flipped_faces"] == 0
    assert mirror_error(r, MIRROR_X) < 0.2
    # The mesh is the soup it was, and each of its rows carries the outputs of its vertex.
    m = ms.mesh(0)
    np.testing.assert_array_equal(m.vertex_matrix(), V)
    np.testing.assert_array_equal(m.face_matrix(), F)
    ids = m.vertex_custom_scalar_attribute_array("symmetry_id").astype(int)
    quality = m.vertex_scalar_array()
    first_row = {}
    for row, p in enumerate(map(bytes, np.ascontiguousarray(V))):
        first = first_row.setdefault(p, row)
        assert ids[row] == ids[first] and quality[row] == quality[first]
    assert np.mean(ids >= 0) > 0.5
    # A patch layer holds faces: its rows include every copy of its vertices.
    source = ms.mesh(int(r["patch_layer_ids"][0]))
    assert source.face_number() > 0


def test_faces_turned_both_ways_are_oriented_and_the_mirror_found(requires_pipeline, bumpy):
    V, F = bumpy
    which = half_turned(F)
    G = turned(F, which)
    ms, r = detect(V, G)
    assert r["flipped_faces"] == int(which.sum())  # a closed surface: all turned outward
    assert r["welded_vertices"] == 0
    assert mirror_error(r, MIRROR_X) < 0.2
    np.testing.assert_array_equal(ms.mesh(0).face_matrix(), G)


def test_a_copy_turned_inward_still_mirrors_the_other(requires_pipeline, bumpy):
    """Two copies of an asymmetric part, x -> -x of each other; the second one's faces all
    turned inward, and a soup besides."""
    V, F = bumpy
    A = V.copy()
    A[:, 0] += 0.4 * np.maximum(A[:, 1], 0) ** 2 + 3.0  # no longer its own mirror image
    B = A * np.array([-1.0, 1, 1])                     # the mirror image, faces now inward
    V2 = np.vstack([A, B])
    F2 = np.vstack([F, F + len(A)])
    P, Q = soup(V2, F2)
    ms, r = detect(P, Q)
    assert r["flipped_faces"] == len(F)
    assert mirror_error(r, MIRROR_X) < 0.2
    np.testing.assert_array_equal(ms.mesh(0).face_matrix(), Q)


def test_a_double_sided_mesh_keeps_one_side_and_finds_the_mirror(requires_pipeline, bumpy):
    """Every triangle once more the other way round on the same vertices, as shape
    collections store double-sided surfaces: each edge has four faces and the two sides'
    vertex normals cancel.  One side is kept on the filter's copy; the mesh is unchanged."""
    V, F = bumpy
    G = np.vstack([F, F[:, ::-1]])
    ms, r = detect(V, G)
    assert r["back_faces"] == len(F) and r["repeated_faces"] == 0
    assert r["welded_vertices"] == 0
    assert mirror_error(r, MIRROR_X) < 0.2
    np.testing.assert_array_equal(ms.mesh(0).face_matrix(), G)
    ids = ms.mesh(0).vertex_custom_scalar_attribute_array("symmetry_id")
    assert np.mean(ids >= 0) > 0.5


def test_a_back_side_with_vertices_of_its_own_is_welded_to_the_front(requires_pipeline, bumpy):
    """The back side on copies of the vertices, and which side of each triangle comes first
    chosen at random: only welding the copies gives one surface.  Every copy carries the
    outputs of the vertex it was welded to."""
    V, F = bumpy
    n = len(V)
    V2 = np.vstack([V, V])
    back = F[:, ::-1] + n
    first = np.random.default_rng(6).random(len(F)) < 0.5
    G = np.vstack([np.where(first[:, None], back, F), np.where(first[:, None], F, back)])
    ms, r = detect(V2, G)
    assert r["back_faces"] == len(F)
    assert r["welded_vertices"] == n
    assert mirror_error(r, MIRROR_X) < 0.2
    m = ms.mesh(0)
    np.testing.assert_array_equal(m.vertex_matrix(), V2)
    ids = m.vertex_custom_scalar_attribute_array("symmetry_id")
    np.testing.assert_array_equal(ids[:n], ids[n:])
    np.testing.assert_array_equal(m.vertex_scalar_array()[:n], m.vertex_scalar_array()[n:])


def test_every_face_given_twice_is_kept_once(requires_pipeline, bumpy):
    V, F = bumpy
    G = np.vstack([F, F])
    ms, r = detect(V, G)
    assert r["repeated_faces"] == len(F) and r["back_faces"] == 0
    assert mirror_error(r, MIRROR_X) < 0.2
    np.testing.assert_array_equal(ms.mesh(0).face_matrix(), G)


@pytest.mark.long_under_sanitizers
@pytest.mark.parametrize("name", ("box", "torus", "noisy_both_0.2", "fine_row"))
def test_the_planted_scenes_need_no_repair(requires_pipeline, name):
    """The repair leaves a clean mesh exactly as it is, and a fine one is not refined: the
    scenes (and the real models, see test_real_models_detect.py) are analysed as before."""
    from conftest import scene_detection
    _, result, _ = scene_detection(name)
    assert result.raw["welded_vertices"] == 0 and result.raw["flipped_faces"] == 0
    assert result.raw["repeated_faces"] == 0 and result.raw["back_faces"] == 0
    assert result.raw["working_vertices"] == 0  # fine enough for the curvature ball: not refined


# More of what exporters and scanners write, each on the mirror-symmetric bumpy sphere; the
# core welds, orients, skips zero-area faces and analyses what remains, so the planted
# mirror must still be found (the mesh itself, as everywhere, left as it came).
def with_holes(V, F):
    keep = np.random.default_rng(2).random(len(F)) > 0.03
    return V, F[keep]


def with_zero_area_faces(V, F):
    pick = np.random.default_rng(3).choice(len(F), 40, replace=False)
    repeated_corner = F[pick][:, [0, 0, 1]]
    return V, np.vstack([F, repeated_corner, F[pick[:10]]])  # and faces given twice


def with_duplicate_and_unreferenced_vertices(V, F):
    rng = np.random.default_rng(4)
    pick = rng.choice(len(V), 60, replace=False)
    V2 = np.vstack([V, V[pick], rng.random((25, 3)) * 0.5])  # copies, then 25 no face uses
    F2 = F.copy()
    copy_of = {int(v): len(V) + i for i, v in enumerate(pick)}
    for f in range(0, len(F2), 3):
        F2[f] = [copy_of.get(int(v), int(v)) for v in F2[f]]
    return V2, F2


def with_non_manifold_fins(V, F):
    """A third face on 30 edges, its apex just outside the surface: non-manifold edges."""
    apex = V[F[:30, 0]] * 1.01 + 0.005
    V2 = np.vstack([V, apex])
    fins = np.column_stack([F[:30, 0], F[:30, 1], len(V) + np.arange(30)])
    return V2, np.vstack([F, fins])


def with_non_manifold_vertex(V, F):
    """A small flap of two triangles hanging from one surface vertex, touching the surface
    nowhere else: that vertex is non-manifold (two fans meet at it)."""
    tip = V[0]
    outward = tip / np.linalg.norm(tip)
    side = np.cross(outward, [0.0, 0.0, 1.0] if abs(outward[2]) < 0.9 else [1.0, 0.0, 0.0])
    side /= np.linalg.norm(side)
    flap = np.array([tip + 0.05 * outward + 0.03 * side, tip + 0.05 * outward - 0.03 * side, tip + 0.1 * outward])
    k = len(V)
    return np.vstack([V, flap]), np.vstack([F, [[0, k, k + 1], [k, k + 2, k + 1]]])


def with_many_components(V, F):
    """3000 tiny triangles inside the bounding box besides the surface: thousands of
    components, 0.3 % of the area."""
    rng = np.random.default_rng(5)
    corners = rng.uniform(-1, 1, (3000, 1, 3)) + rng.normal(0, 0.003, (3000, 3, 3))
    V2 = np.vstack([V, corners.reshape(-1, 3)])
    return V2, np.vstack([F, len(V) + np.arange(9000).reshape(-1, 3)])


def far_from_the_origin(V, F):
    return V + np.array([1e8, -1e8, 5e7]), F


def tiny(V, F):
    return V * 1e-8, F


def huge(V, F):
    return V * 1e8, F


BROKEN = dict(holes=with_holes, zero_area_faces=with_zero_area_faces,
              duplicate_and_unreferenced_vertices=with_duplicate_and_unreferenced_vertices,
              non_manifold_fins=with_non_manifold_fins, non_manifold_vertex=with_non_manifold_vertex,
              many_components=with_many_components,
              far_from_the_origin=far_from_the_origin, tiny=tiny, huge=huge)


@pytest.mark.parametrize("name", list(BROKEN))
def test_broken_but_readable_input_still_gives_the_mirror(requires_pipeline, bumpy, name):
    V, F = BROKEN[name](*bumpy)
    ms, r = detect(V, F)
    assert mirror_error(r, MIRROR_X) < 0.2
    np.testing.assert_array_equal(ms.mesh(0).vertex_matrix(), V)
    np.testing.assert_array_equal(ms.mesh(0).face_matrix(), F)
    assert len(ms.mesh(0).vertex_custom_scalar_attribute_array("symmetry_id")) == len(V)


def test_specks_do_not_shrink_the_curvature_ball(requires_pipeline, bumpy, clean_run):
    """The ball holds min_radius_in_edges of the surface's median edges, not of the specks'
    (which, counted per edge, would make it a sixth as large and see single facets)."""
    _, r = detect(*with_many_components(*bumpy))
    clean = clean_run[1]["curvature_radius_used"]
    # The specks widen the bounding box a little; the ball's absolute size is the same.
    assert r["curvature_radius_used"] == pytest.approx(clean, rel=0.1)


def test_specks_are_left_out_of_the_mirror_patch(requires_pipeline, bumpy):
    """Specks are debris (plugin/core/detection.h, debris_area_share): under the mirror a
    speck near the surface lands on it within the tolerance, and swept into the patch its
    vertices would weigh as much as the surface's in the deviation (the mirror was rejected
    so).  The surface is in the patch, the specks are not."""
    V, F = with_many_components(*bumpy)
    ms, r = detect(V, F)
    assert mirror_error(r, MIRROR_X) < 0.2
    ids = ms.mesh(0).vertex_custom_scalar_attribute_array("symmetry_id")
    surface = len(bumpy[0])
    assert np.mean(ids[:surface] >= 0) > 0.95
    assert np.all(ids[surface:] < 0)
