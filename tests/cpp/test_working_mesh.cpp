// The working resolution: a simplified copy that keeps the shape and its components, and
// the map from every input vertex to the nearest vertex of the copy (against brute force).
#include "core/working_mesh.h"
#include "test_shapes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>

namespace symmetry {
namespace {

std::unique_ptr<Mesh> mesh_of(const testing::Shape& s) {
    auto mesh = std::make_unique<Mesh>();
    std::vector<int> map;
    build_mesh(s.V, s.F, *mesh, map);
    return mesh;
}

TEST(WorkingMesh, SimplifiesToTheTargetAndKeepsTheShape) {
    // A sphere of radius 1 with 10,242 vertices, simplified to 2,000.
    const auto input_mesh = mesh_of(testing::sphere(1.0, 5));
    const Mesh& input = *input_mesh;
    ASSERT_GT(input.vn, 10000);
    const auto copy = simplified_copy(input, 2000, WorkingMeshOptions{});
    EXPECT_NEAR(copy->vn, 2000, 100);
    EXPECT_EQ(copy->fn, 2 * copy->vn - 4);  // still one closed genus-0 surface (Euler)
    // Every vertex of the copy stays near the sphere (quadric collapse keeps it within a
    // small fraction of the edge length), and so does the area.
    for (const auto& v : copy->vert) EXPECT_NEAR(v.cP().Norm(), 1.0, 0.01);
    EXPECT_NEAR(surface_area(*copy), surface_area(input), 0.01 * surface_area(input));
}

TEST(WorkingMesh, KeepsSeparateComponents) {
    // Two tori apart: the copy has two components of about equal size (topology preserved).
    const testing::Shape a = testing::torus(1.0, 0.3, 96, 48);
    const testing::Shape b = testing::transformed(a, Eigen::Matrix3d::Identity(), Eigen::Vector3d(4, 0, 0));
    const auto input_mesh = mesh_of(testing::merged(a, b));
    const Mesh& input = *input_mesh;
    const auto copy = simplified_copy(input, 1500, WorkingMeshOptions{});
    int left = 0, right = 0;
    for (const auto& v : copy->vert) (v.cP()[0] < 2 ? left : right)++;
    EXPECT_NEAR(left, right, 0.1 * (left + right));
    EXPECT_EQ(copy->fn, copy->vn * 2);  // two closed genus-1 surfaces (Euler: V - E + F = 0 each)
}

TEST(WorkingMesh, NearestVerticesAgreeWithBruteForce) {
    const auto input_mesh = mesh_of(testing::sphere(1.0, 4));
    const Mesh& input = *input_mesh;
    const auto copy = simplified_copy(input, 600, WorkingMeshOptions{});
    const std::vector<int> nearest = nearest_vertices(input, *copy);
    ASSERT_EQ(nearest.size(), input.vert.size());
    for (size_t i = 0; i < input.vert.size(); i += 7) {
        double best = std::numeric_limits<double>::max();
        for (const auto& w : copy->vert) best = std::min(best, (w.cP() - input.vert[i].cP()).Norm());
        EXPECT_DOUBLE_EQ((copy->vert[size_t(nearest[i])].cP() - input.vert[i].cP()).Norm(), best);
    }
}

}  // namespace
}  // namespace symmetry
