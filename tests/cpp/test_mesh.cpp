// The core mesh: what build_mesh rejects, what it drops, and the map back to the
// host's vertices.
#include "core/mesh.h"
#include "test_shapes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace symmetry {
namespace {

Eigen::MatrixX3d square_vertices() {
    Eigen::MatrixX3d V(4, 3);
    V << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0;
    return V;
}
Eigen::MatrixX3i square_faces() {
    Eigen::MatrixX3i F(2, 3);
    F << 0, 1, 2, 0, 2, 3;
    return F;
}

void expect_rejected(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F) {
    Mesh mesh;
    std::vector<int> map;
    EXPECT_THROW(build_mesh(V, F, mesh, map), InputError);
}

TEST(Mesh, RejectsWhatThePipelineCannotUse) {
    expect_rejected(Eigen::MatrixX3d(0, 3), square_faces());           // no vertices
    expect_rejected(square_vertices(), Eigen::MatrixX3i(0, 3));        // a point cloud
    Eigen::MatrixX3d V = square_vertices();
    V(2, 1) = std::numeric_limits<double>::quiet_NaN();
    expect_rejected(V, square_faces());                                // NaN
    V(2, 1) = std::numeric_limits<double>::infinity();
    expect_rejected(V, square_faces());                                // infinity
    Eigen::MatrixX3i F = square_faces();
    F(1, 2) = 4;
    expect_rejected(square_vertices(), F);                             // index past the end
    F(1, 2) = -1;
    expect_rejected(square_vertices(), F);                             // negative index
    Eigen::MatrixX3i degenerate(3, 3);
    degenerate << 0, 0, 1, 1, 2, 2, 0, 1, 1;
    expect_rejected(square_vertices(), degenerate);                    // repeated corners only
    Eigen::MatrixX3d line(3, 3);
    line << 0, 0, 0, 1, 1, 1, 2, 2, 2;
    Eigen::MatrixX3i one(1, 3);
    one << 0, 1, 2;
    expect_rejected(line, one);                                        // zero area (collinear)
}

TEST(Mesh, RejectionMessagesAreSentences) {
    Mesh mesh;
    std::vector<int> map;
    try {
        build_mesh(square_vertices(), Eigen::MatrixX3i(0, 3), mesh, map);
        FAIL() << "a point cloud was accepted";
    } catch (const InputError& e) {
        std::string what = e.what();
        EXPECT_FALSE(what.empty());
        EXPECT_NE(what.find("point cloud"), std::string::npos) << what;
    }
}

TEST(Mesh, DropsDegenerateFacesAndUnreferencedVertices) {
    // Row 0 is unreferenced; rows 5 and 6 are used only by degenerate faces
    // (6 lies on the segment 1-2), so only rows 1, 2, 3, 4 remain.
    Eigen::MatrixX3d V(7, 3);
    V << 9, 9, 9,  // 0: unreferenced
        0, 0, 0,   // 1
        2, 0, 0,   // 2
        0, 2, 0,   // 3
        2, 2, 1,   // 4
        5, 5, 5,   // 5: only in a face with a repeated index
        1, 0, 0;   // 6: only in a zero-area face
    Eigen::MatrixX3i F(5, 3);
    F << 1, 2, 3,  // kept
        5, 5, 1,   // repeated index
        1, 6, 2,   // collinear
        2, 4, 3,   // kept
        3, 3, 3;   // all the same
    Mesh mesh;
    std::vector<int> vertex_of_input;
    build_mesh(V, F, mesh, vertex_of_input);
    EXPECT_EQ(mesh.VN(), 4);
    EXPECT_EQ(mesh.FN(), 2);
    ASSERT_EQ(vertex_of_input.size(), size_t(mesh.VN()));
    std::vector<int> rows(vertex_of_input);
    std::sort(rows.begin(), rows.end());
    EXPECT_EQ(rows, (std::vector<int>{1, 2, 3, 4}));
    for (size_t i = 0; i < vertex_of_input.size(); ++i) {
        const auto& p = mesh.vert[i].cP();
        EXPECT_EQ(Eigen::Vector3d(p[0], p[1], p[2]), V.row(vertex_of_input[i]).transpose());
    }
    // Faces keep their input order and corners.
    const int expected_faces[2][3] = {{1, 2, 3}, {2, 4, 3}};
    for (int f = 0; f < 2; ++f)
        for (int k = 0; k < 3; ++k)
            EXPECT_EQ(vertex_of_input[size_t(vcg::tri::Index(mesh, mesh.face[size_t(f)].cV(k)))], expected_faces[f][k]);
    EXPECT_NEAR(surface_area(mesh), 2 + 0.5 * std::sqrt(24.0), 1e-12);  // |(0,2,1) x (-2,2,0)| = sqrt(24)
}

TEST(Mesh, AdjacencyNormalsAndArea) {
    const auto sphere = testing::sphere(1, 3);
    Mesh mesh;
    std::vector<int> vertex_of_input;
    build_mesh(sphere.V, sphere.F, mesh, vertex_of_input);
    EXPECT_EQ(mesh.FN(), sphere.F.rows());
    EXPECT_EQ(mesh.VN(), sphere.V.rows());
    for (auto& f : mesh.face) {
        // Closed: every edge has a neighbour across it, which points back.
        for (int k = 0; k < 3; ++k) {
            ASSERT_NE(f.FFp(k), &f);
            EXPECT_EQ(f.FFp(k)->FFp(f.FFi(k)), &f);
        }
        // Outward unit normals.
        vcg::Point3d centre = (f.P(0) + f.P(1) + f.P(2)) / 3.0;
        EXPECT_NEAR(f.N().Norm(), 1, 1e-12);
        EXPECT_GT(f.N() * centre.Normalize(), 0.99);
    }
    for (auto& v : mesh.vert) EXPECT_NEAR(v.N().Norm(), 1, 1e-12);
    // An inscribed polyhedron: a little less than 4 pi.
    double area = surface_area(mesh);
    EXPECT_LT(area, 4 * M_PI);
    EXPECT_GT(area, 0.98 * 4 * M_PI);
    EXPECT_GT(mesh.bbox.Diag(), 2 * std::sqrt(3.0) * 0.9);

    // Building into a used mesh starts afresh.
    build_mesh(square_vertices(), square_faces(), mesh, vertex_of_input);
    EXPECT_EQ(mesh.VN(), 4);
    EXPECT_EQ(mesh.FN(), 2);
    EXPECT_EQ(vertex_of_input, (std::vector<int>{0, 1, 2, 3}));
    EXPECT_NEAR(surface_area(mesh), 1, 1e-15);
}

}  // namespace
}  // namespace symmetry
