// Stage 1 (§5): uniform area sampling, checked for geometry (samples on their
// face), for density (counts proportional to area) and for reproducibility.
#include "core/sampling.h"
#include "test_shapes.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>

namespace symmetry {
namespace {

using testing::Shape;

void build(const Shape& shape, Mesh& mesh) {
    std::vector<int> vertex_of_input;
    build_mesh(shape.V, shape.F, mesh, vertex_of_input);
}

// A mesh of the single triangle (a, b, c).
void build_triangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c, Mesh& mesh) {
    Shape tri;
    tri.V.resize(3, 3);
    tri.V << a.transpose(), b.transpose(), c.transpose();
    tri.F.resize(1, 3);
    tri.F << 0, 1, 2;
    build(tri, mesh);
}

Eigen::Vector3d corner(const Mesh& mesh, int face, int k) {
    const auto& p = mesh.face[size_t(face)].cP(k);
    return {p[0], p[1], p[2]};
}

// Barycentric coordinates of p in the face, and its distance to the face's plane.
Eigen::Vector3d barycentric(const Mesh& mesh, int face, const Eigen::Vector3d& p, double& off_plane) {
    Eigen::Vector3d a = corner(mesh, face, 0), b = corner(mesh, face, 1), c = corner(mesh, face, 2);
    Eigen::Vector3d n = (b - a).cross(c - a);
    double area2 = n.squaredNorm();
    off_plane = std::abs(n.normalized().dot(p - a));
    double wb = n.dot((p - a).cross(c - a)) / area2, wc = n.dot((b - a).cross(p - a)) / area2;
    return {1 - wb - wc, wb, wc};
}

TEST(Sampling, SamplesLieOnTheirFace) {
    Mesh mesh;
    build(testing::torus(3, 1, 40, 16), mesh);
    std::mt19937_64 rng(11);
    auto samples = uniform_area_sampling(mesh, 5000, rng);
    ASSERT_EQ(samples.size(), 5000u);
    for (const auto& s : samples) {
        ASSERT_GE(s.face, 0);
        ASSERT_LT(size_t(s.face), mesh.face.size());
        double off_plane = 0;
        Eigen::Vector3d w = barycentric(mesh, s.face, s.position, off_plane);
        EXPECT_LT(off_plane, 1e-12);
        EXPECT_GE(w.minCoeff(), -1e-12);
        EXPECT_LE(w.maxCoeff(), 1 + 1e-12);
    }
}

TEST(Sampling, CountsAreProportionalToArea) {
    // A unit sphere and one scaled by 2: the second part has 4 times the area.
    const Shape small = testing::sphere(1, 3);
    const Shape large = testing::transformed(small, 2 * Eigen::Matrix3d::Identity(), Eigen::Vector3d(5, 0, 0));
    Mesh mesh;
    build(testing::merged(small, large), mesh);
    const size_t small_faces = size_t(small.F.rows());
    ASSERT_EQ(mesh.face.size(), 2 * small_faces);
    const int n = 20000;
    std::mt19937_64 rng(12);
    int in_small = 0;
    for (const auto& s : uniform_area_sampling(mesh, n, rng)) in_small += size_t(s.face) < small_faces;
    // Binomial: p = 1/5 exactly (scaling multiplies every face's area by 4).
    const double p = 0.2, mean = n * p, sd = std::sqrt(n * p * (1 - p));
    EXPECT_LT(std::abs(in_small - mean), 4 * sd) << in_small << " samples on the small part, expected " << mean;
}

TEST(Sampling, PointsAreUniformInsideATriangle) {
    // One triangle: by area, a quarter of the samples fall where the first
    // barycentric weight exceeds 1/2 (the corner triangle with half the edges),
    // and the mean of the samples is the centroid.
    Mesh mesh;
    build_triangle(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(3, 0, 0), Eigen::Vector3d(1, 2, 0), mesh);
    const int n = 40000;
    std::mt19937_64 rng(13);
    int near_first = 0;
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const auto& s : uniform_area_sampling(mesh, n, rng)) {
        double off_plane = 0;
        near_first += barycentric(mesh, 0, s.position, off_plane)(0) > 0.5;
        mean += s.position / n;
    }
    const double sd = std::sqrt(n * 0.25 * 0.75);
    EXPECT_LT(std::abs(near_first - 0.25 * n), 4 * sd);
    // Each coordinate of a uniform point in this triangle has a standard deviation below 1.
    EXPECT_LT((mean - Eigen::Vector3d(4.0 / 3, 2.0 / 3, 0)).norm(), 4.0 / std::sqrt(n));
}

TEST(Sampling, SameSeedSameSamples) {
    Mesh mesh;
    build(testing::sphere(1, 2), mesh);
    std::mt19937_64 a(7), b(7), c(8);
    auto first = uniform_area_sampling(mesh, 200, a);
    auto second = uniform_area_sampling(mesh, 200, b);
    auto other = uniform_area_sampling(mesh, 200, c);
    ASSERT_EQ(first.size(), second.size());
    int differences = 0;
    for (size_t i = 0; i < first.size(); ++i) {
        EXPECT_EQ(first[i].face, second[i].face);
        EXPECT_EQ(first[i].position, second[i].position);
        differences += first[i].position != other[i].position;
    }
    EXPECT_GT(differences, 190);
    // The generator is advanced: the next call continues the stream.
    auto next = uniform_area_sampling(mesh, 1, a);
    EXPECT_NE(next[0].position, first[0].position);
}

TEST(Sampling, SameSamplesWithEveryStandardLibrary) {
    // std::mt19937_64 is fully specified by the standard and the conversion to
    // [0, 1) is our own, so these values hold with libstdc++, libc++ and MSVC alike.
    Mesh mesh;
    build_triangle(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 0), mesh);
    std::mt19937_64 rng(42);
    auto s = uniform_area_sampling(mesh, 1, rng);
    // The three draws of this sample (one face pick, two for the point).
    std::mt19937_64 check(42);
    check();
    double u = double(check() >> 11) * 0x1.0p-53, v = double(check() >> 11) * 0x1.0p-53;
    double root = std::sqrt(u);
    EXPECT_DOUBLE_EQ(s[0].position.x(), root * (1 - v));
    EXPECT_DOUBLE_EQ(s[0].position.y(), root * v);
    EXPECT_EQ(s[0].position.z(), 0.0);
}

TEST(Sampling, SkipsDeletedFaces) {
    Mesh mesh;
    build(testing::sphere(1, 2), mesh);
    for (size_t i = 0; i < mesh.face.size(); i += 2) vcg::tri::Allocator<Mesh>::DeleteFace(mesh, mesh.face[i]);
    // Delete the last face too: a draw rounded up to the total must not land on it.
    if (!mesh.face.back().IsD()) vcg::tri::Allocator<Mesh>::DeleteFace(mesh, mesh.face.back());
    std::mt19937_64 rng(14);
    for (const auto& s : uniform_area_sampling(mesh, 3000, rng)) EXPECT_FALSE(mesh.face[size_t(s.face)].IsD());
}

TEST(Sampling, NoCountNoSamples) {
    Mesh mesh;
    build(testing::sphere(1, 0), mesh);
    std::mt19937_64 rng(15);
    EXPECT_TRUE(uniform_area_sampling(mesh, 0, rng).empty());
}

}  // namespace
}  // namespace symmetry
