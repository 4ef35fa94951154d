// Repairs of the input on the core's copy: a triangle soup welded, faces turned both
// ways oriented coherently (closed parts outward), and a good mesh left exactly as it is.
#include "core/input_repair.h"
#include "core/mesh.h"
#include "test_shapes.h"

#include <gtest/gtest.h>

#include <random>

namespace symmetry {
namespace {

using testing::Shape;

// Every triangle with three vertices of its own, as an STL file stores it.
Shape soup(const Shape& s) {
    Shape out;
    out.V.resize(3 * s.F.rows(), 3);
    out.F.resize(s.F.rows(), 3);
    for (Eigen::Index f = 0; f < s.F.rows(); ++f)
        for (int k = 0; k < 3; ++k) {
            out.V.row(3 * f + k) = s.V.row(s.F(f, k));
            out.F(f, k) = int(3 * f + k);
        }
    return out;
}

Eigen::MatrixX3i turned(const Eigen::MatrixX3i& F, const std::vector<char>& which) {
    Eigen::MatrixX3i out = F;
    for (Eigen::Index f = 0; f < F.rows(); ++f)
        if (which[size_t(f)]) std::swap(out(f, 1), out(f, 2));
    return out;
}

std::vector<char> every_other_at_random(Eigen::Index n, unsigned seed, double share) {
    std::mt19937 rng(seed);
    std::bernoulli_distribution coin(share);
    std::vector<char> which(static_cast<size_t>(n), 0);
    for (auto& w : which) w = coin(rng);
    return which;
}

// The faces of the built mesh as rows of V, in the mesh's corner order.
Eigen::MatrixX3i faces_as_rows(const Mesh& mesh, const std::vector<int>& vertex_of_input) {
    Eigen::MatrixX3i F(mesh.fn, 3);
    for (int f = 0; f < mesh.fn; ++f)
        for (int k = 0; k < 3; ++k) F(f, k) = vertex_of_input[size_t(vcg::tri::Index(mesh, mesh.face[size_t(f)].cV(k)))];
    return F;
}

// Every face's normal points away from the origin (the shapes are star-shaped about it).
int inward_faces(const Mesh& mesh) {
    int inward = 0;
    for (const Face& f : mesh.face) {
        const vcg::Point3d n = (f.cP(1) - f.cP(0)) ^ (f.cP(2) - f.cP(0));
        inward += n * (f.cP(0) + f.cP(1) + f.cP(2)) < 0;
    }
    return inward;
}

int border_edges(const Mesh& mesh) {
    int border = 0;
    for (const Face& f : mesh.face)
        for (int j = 0; j < 3; ++j) border += vcg::face::IsBorder(f, j);
    return border;
}

// The shape's faces below z = 0 on a copy of the vertices appended after the input's: two
// halves with vertices of their own along the equator.
Shape split_at_equator(const Shape& s) {
    Shape split = s;
    const Eigen::Index n = s.V.rows();
    split.V.conservativeResize(2 * n, 3);
    split.V.bottomRows(n) = s.V;
    for (Eigen::Index f = 0; f < split.F.rows(); ++f)
        if (s.V(s.F(f, 0), 2) + s.V(s.F(f, 1), 2) + s.V(s.F(f, 2), 2) < 0) split.F.row(f).array() += int(n);
    return split;
}

TEST(InputRepair, RowsAtSamePositionPointToTheFirst) {
    Eigen::MatrixX3d V(5, 3);
    V << 1, 2, 3, 0, 0, 0, 1, 2, 3, -0.0, 0, 0, 1, 2, 3.0000001;
    EXPECT_EQ(rows_at_same_position(V), (std::vector<int>{0, 1, 0, 1, 4}));
}

TEST(InputRepair, ASoupIsWeldedIntoOneClosedSurface) {
    const Shape sphere = testing::sphere(1.0, 2);
    const Shape pieces = soup(sphere);
    Mesh mesh;
    std::vector<int> rows;
    MeshRepairs repairs;
    build_mesh(pieces.V, pieces.F, mesh, rows, &repairs);
    EXPECT_EQ(mesh.vn, sphere.V.rows());
    EXPECT_EQ(mesh.fn, sphere.F.rows());
    EXPECT_EQ(repairs.welded_vertices, pieces.V.rows() - sphere.V.rows());
    EXPECT_EQ(border_edges(mesh), 0);
    EXPECT_EQ(repairs.flipped_faces, 0);
    // Each welded row stands for a row at its own position.
    for (Eigen::Index r = 0; r < pieces.V.rows(); ++r)
        EXPECT_EQ(pieces.V.row(repairs.row_at_same_position[size_t(r)]), pieces.V.row(r));
}

TEST(InputRepair, AMeshSplitAlongSomeEdgesIsNotWelded) {
    // Two halves of a sphere, each with vertices of its own along the equator (as a
    // flat-shaded or textured export splits them): parts, not a soup.
    const Shape sphere = testing::sphere(1.0, 2);
    const Shape split = split_at_equator(sphere);
    EXPECT_FALSE(is_triangle_soup(split.F, split.V.rows()));
    EXPECT_TRUE(is_triangle_soup(soup(sphere).F, soup(sphere).V.rows()));
    Mesh mesh;
    std::vector<int> rows;
    MeshRepairs repairs;
    build_mesh(split.V, split.F, mesh, rows, &repairs);
    EXPECT_EQ(repairs.welded_vertices, 0);
    EXPECT_GT(border_edges(mesh), 0);
    EXPECT_EQ(faces_as_rows(mesh, rows), split.F);
}

TEST(InputRepair, MixedOrientationIsMadeCoherentAndOutward) {
    const Shape sphere = testing::sphere(1.0, 2);
    const std::vector<char> which = every_other_at_random(sphere.F.rows(), 7, 0.5);
    const int expected = int(std::count(which.begin(), which.end(), 1));
    ASSERT_GT(expected, 0);
    Mesh mesh;
    std::vector<int> rows;
    MeshRepairs repairs;
    build_mesh(sphere.V, turned(sphere.F, which), mesh, rows, &repairs);
    EXPECT_EQ(repairs.flipped_faces, expected);
    EXPECT_TRUE(repairs.orientable);
    EXPECT_EQ(inward_faces(mesh), 0);
}

TEST(InputRepair, AClosedSurfaceFacingInwardIsTurnedOutward) {
    const Shape box = testing::box(1, 2, 3, 3);
    Mesh mesh;
    std::vector<int> rows;
    MeshRepairs repairs;
    build_mesh(box.V, turned(box.F, std::vector<char>(size_t(box.F.rows()), 1)), mesh, rows, &repairs);
    EXPECT_EQ(repairs.flipped_faces, box.F.rows());
    EXPECT_EQ(inward_faces(mesh), 0);
}

TEST(InputRepair, AnOpenSurfaceKeepsTheOrientationMostOfItsAreaHad) {
    const Shape tube = testing::cylinder(1.0, 2.0, 24, 8);
    const std::vector<char> which = every_other_at_random(tube.F.rows(), 3, 0.2);
    const int expected = int(std::count(which.begin(), which.end(), 1));
    Mesh mesh;
    std::vector<int> rows;
    MeshRepairs repairs;
    build_mesh(tube.V, turned(tube.F, which), mesh, rows, &repairs);
    EXPECT_EQ(repairs.flipped_faces, expected);
    EXPECT_EQ(inward_faces(mesh), 0);
}

TEST(InputRepair, AGoodMeshIsLeftExactlyAsItCame) {
    const Shape two = testing::merged(testing::torus(2, 0.5, 24, 12),
                                      testing::transformed(testing::box(0.5, 0.5, 0.5, 2), Eigen::Matrix3d::Identity(),
                                                           Eigen::Vector3d(5, 0, 0)));
    Mesh mesh;
    std::vector<int> rows;
    MeshRepairs repairs;
    build_mesh(two.V, two.F, mesh, rows, &repairs);
    EXPECT_EQ(repairs.welded_vertices, 0);
    EXPECT_EQ(repairs.flipped_faces, 0);
    EXPECT_EQ(faces_as_rows(mesh, rows), two.F);
}

TEST(InputRepair, AMoebiusBandIsLeftAsItCame) {
    const int n = 40;
    Eigen::MatrixX3d V(2 * n, 3);
    for (int i = 0; i < n; ++i) {
        const double u = 2 * M_PI * i / n;
        for (int s = 0; s < 2; ++s) {
            const double w = s ? 0.3 : -0.3;
            V.row(2 * i + s) << (1 + w * std::cos(u / 2)) * std::cos(u), (1 + w * std::cos(u / 2)) * std::sin(u),
                w * std::sin(u / 2);
        }
    }
    // The strip's last quad joins its end to its start with the sides exchanged.
    Eigen::MatrixX3i F(2 * n, 3);
    for (int i = 0; i < n; ++i) {
        const int a = 2 * i, b = 2 * i + 1;
        const int c = i + 1 < n ? 2 * (i + 1) : 1, d = i + 1 < n ? 2 * (i + 1) + 1 : 0;
        F.row(2 * i) << a, c, b;
        F.row(2 * i + 1) << b, c, d;
    }
    Mesh mesh;
    std::vector<int> rows;
    MeshRepairs repairs;
    build_mesh(V, F, mesh, rows, &repairs);
    EXPECT_FALSE(repairs.orientable);
    EXPECT_EQ(repairs.flipped_faces, 0);
    EXPECT_EQ(faces_as_rows(mesh, rows), F);
}

// Every face once more the other way round, on the same rows (`own_rows` false) or on a copy
// of the vertices appended after the input's (true), as double-sided exports store them.
Shape double_sided(const Shape& s, bool own_rows) {
    Shape out = s;
    const Eigen::Index n = s.V.rows(), m = s.F.rows();
    if (own_rows) {
        out.V.conservativeResize(2 * n, 3);
        out.V.bottomRows(n) = s.V;
    }
    out.F.conservativeResize(2 * m, 3);
    for (Eigen::Index f = 0; f < m; ++f)
        out.F.row(m + f) << s.F(f, 0), s.F(f, 2), s.F(f, 1);
    if (own_rows) out.F.bottomRows(m).array() += int(n);
    return out;
}

// Rows f and m + f exchanged wherever `which` says: which of the two sides comes first.
Eigen::MatrixX3i sides_exchanged(const Eigen::MatrixX3i& F, const std::vector<char>& which) {
    Eigen::MatrixX3i out = F;
    const Eigen::Index m = F.rows() / 2;
    for (Eigen::Index f = 0; f < m; ++f)
        if (which[size_t(f)]) {
            out.row(f) = F.row(m + f);
            out.row(m + f) = F.row(f);
        }
    return out;
}

TEST(InputRepair, ADoubleSidedSurfaceKeepsOneSideClosedAndOutward) {
    const Shape sphere = testing::sphere(1.0, 2);
    const Shape both = double_sided(sphere, false);
    Mesh mesh;
    std::vector<int> rows;
    MeshRepairs repairs;
    build_mesh(both.V, both.F, mesh, rows, &repairs);
    EXPECT_EQ(mesh.fn, sphere.F.rows());
    EXPECT_EQ(mesh.vn, sphere.V.rows());
    EXPECT_EQ(repairs.back_faces, sphere.F.rows());
    EXPECT_EQ(repairs.repeated_faces, 0);
    EXPECT_EQ(repairs.welded_vertices, 0);
    EXPECT_EQ(border_edges(mesh), 0);
    EXPECT_EQ(inward_faces(mesh), 0);
}

TEST(InputRepair, ABackSideWithVerticesOfItsOwnIsWeldedWhereTheSidesAlternate) {
    // The first copy of each triangle is, at random, the front or the back: the faces kept
    // use the rows of both, and only welding them gives one closed surface again.
    const Shape sphere = testing::sphere(1.0, 2);
    const Shape both = double_sided(sphere, true);
    const Eigen::MatrixX3i F = sides_exchanged(both.F, every_other_at_random(sphere.F.rows(), 5, 0.5));
    Mesh mesh;
    std::vector<int> rows;
    MeshRepairs repairs;
    build_mesh(both.V, F, mesh, rows, &repairs);
    EXPECT_EQ(mesh.fn, sphere.F.rows());
    EXPECT_EQ(mesh.vn, sphere.V.rows());
    EXPECT_EQ(repairs.back_faces, sphere.F.rows());
    EXPECT_EQ(repairs.welded_vertices, sphere.V.rows());  // each back row onto its front row
    EXPECT_EQ(border_edges(mesh), 0);
    EXPECT_EQ(inward_faces(mesh), 0);
    for (Eigen::Index r = 0; r < both.V.rows(); ++r)
        EXPECT_EQ(both.V.row(repairs.row_at_same_position[size_t(r)]), both.V.row(r));
}

TEST(InputRepair, AFaceRepeatedTheSameWayIsKeptOnce) {
    const Shape box = testing::box(1, 2, 3, 2);
    Shape twice = box;
    twice.F.conservativeResize(2 * box.F.rows(), 3);
    twice.F.bottomRows(box.F.rows()) = box.F;
    Mesh mesh;
    std::vector<int> rows;
    MeshRepairs repairs;
    build_mesh(twice.V, twice.F, mesh, rows, &repairs);
    EXPECT_EQ(repairs.repeated_faces, box.F.rows());
    EXPECT_EQ(repairs.back_faces, 0);
    EXPECT_EQ(faces_as_rows(mesh, rows), box.F);
}

TEST(InputRepair, ADoubleSidedMeshSplitAlongSomeEdgesStaysSplitThere) {
    // The two halves of a sphere with rows of their own along the equator, each side twice:
    // the sides are joined, the halves are not (welding only what the repeats make one).
    const Shape split = split_at_equator(testing::sphere(1.0, 2));
    Mesh alone, doubled;
    std::vector<int> rows_alone, rows_doubled;
    MeshRepairs repairs;
    build_mesh(split.V, split.F, alone, rows_alone, nullptr);
    const Shape both = double_sided(split, true);
    build_mesh(both.V, both.F, doubled, rows_doubled, &repairs);
    EXPECT_EQ(repairs.back_faces, split.F.rows());
    EXPECT_EQ(doubled.fn, alone.fn);
    EXPECT_EQ(doubled.vn, alone.vn);
    EXPECT_EQ(border_edges(doubled), border_edges(alone));
    EXPECT_GT(border_edges(doubled), 0);
}

}  // namespace
}  // namespace symmetry
