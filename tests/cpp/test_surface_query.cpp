// Closest-point queries: the grid searches against an exhaustive scan of every face.
#include "core/surface_query.h"
#include "test_shapes.h"

#include <vcg/simplex/face/distance.h>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <thread>
#include <vector>

namespace symmetry {
namespace {

struct Exhaustive {
    double nearest = std::numeric_limits<double>::max();
    double facing = std::numeric_limits<double>::max();  // nearest face agreeing with the normal
};

Exhaustive scan(const Mesh& mesh, const Eigen::Vector3d& q, const Eigen::Vector3d& normal, double min_cosine) {
    Exhaustive e;
    const vcg::Point3d p(q.x(), q.y(), q.z());
    for (const Face& f : mesh.face) {
        double d = std::numeric_limits<double>::max();
        vcg::Point3d c;
        vcg::face::PointDistanceBase(f, p, d, c);
        e.nearest = std::min(e.nearest, d);
        const Eigen::Vector3d n(f.cN()[0], f.cN()[1], f.cN()[2]);
        if (n.dot(normal) >= min_cosine) e.facing = std::min(e.facing, d);
    }
    return e;
}

// The answers do not depend on the grid's resolution, only the work does.
class SurfaceQueryGrid : public ::testing::TestWithParam<double> {};

TEST_P(SurfaceQueryGrid, LandingAgreesWithAnExhaustiveScan) {
    // A box: its creases are where the nearest face and the facing face differ.
    const testing::Shape s = testing::box(1.0, 0.6, 0.4, 6);
    auto mesh = std::make_unique<Mesh>();
    std::vector<int> map;
    build_mesh(s.V, s.F, *mesh, map);
    const SurfaceQuery surface(*mesh, GetParam());
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> coordinate(-0.7, 0.7);
    const double max_distance = 0.1, tie = 1e-4, min_cosine = std::cos(M_PI / 4);
    int landed = 0, facing = 0;
    for (int i = 0; i < 2000; ++i) {
        const Eigen::Vector3d q(coordinate(rng), coordinate(rng), coordinate(rng));
        Eigen::Vector3d normal(coordinate(rng), coordinate(rng), coordinate(rng));
        normal.normalize();
        const SurfaceQuery::Landing l = surface.landing(q, max_distance, tie, {normal}, min_cosine);
        const Exhaustive e = scan(*mesh, q, normal, min_cosine);
        ASSERT_EQ(l.nearest.found, e.nearest <= max_distance);
        if (!l.nearest.found) continue;
        ++landed;
        EXPECT_NEAR(l.nearest.distance, e.nearest, 1e-12);
        // The facing face counts only within the tie of the nearest distance.
        const bool expect_facing = e.facing <= e.nearest + tie;
        ASSERT_EQ(l.facing.found, expect_facing);
        if (expect_facing) {
            ++facing;
            EXPECT_NEAR(l.facing.distance, e.facing, 1e-12);
            EXPECT_GE(l.facing.normal.dot(normal), min_cosine - 1e-12);
        }
        // closest() is the nearest face alone.
        const ClosestPoint c = surface.closest(q, max_distance);
        ASSERT_TRUE(c.found);
        EXPECT_NEAR(c.distance, e.nearest, 1e-12);
    }
    EXPECT_GT(landed, 100);
    EXPECT_GT(facing, 20);
}

INSTANTIATE_TEST_SUITE_P(CellsPerFace, SurfaceQueryGrid, ::testing::Values(1.0, 8.0, 64.0));

// A search marks the faces it has tested, per thread, for the last two surfaces searched:
// queries taking turns over three surfaces, from two threads at once, find what a scan finds.
TEST(SurfaceQueryMarks, QueriesTakingTurnsOverThreeSurfacesFromTwoThreadsAgreeWithAScan) {
    std::vector<std::unique_ptr<Mesh>> meshes;
    std::vector<std::unique_ptr<SurfaceQuery>> surfaces;
    for (int k = 0; k < 3; ++k) {
        const testing::Shape s = testing::box(1.0 - 0.2 * k, 0.6, 0.4 + 0.1 * k, 5 + k);
        meshes.push_back(std::make_unique<Mesh>());
        std::vector<int> map;
        build_mesh(s.V, s.F, *meshes.back(), map);
        surfaces.push_back(std::make_unique<SurfaceQuery>(*meshes.back(), 8.0));
    }
    const double max_distance = 0.1;
    std::vector<int> disagreements(2, 0), found(2, 0);
    auto ask = [&](int thread) {
        std::mt19937 rng(unsigned(11 + thread));
        std::uniform_real_distribution<double> coordinate(-0.7, 0.7);
        for (int i = 0; i < 1500; ++i) {
            const int k = i % 3;
            const Eigen::Vector3d q(coordinate(rng), coordinate(rng), coordinate(rng));
            const ClosestPoint c = surfaces[size_t(k)]->closest(q, max_distance);
            const double nearest = scan(*meshes[size_t(k)], q, Eigen::Vector3d::UnitX(), 2).nearest;
            if (c.found != (nearest <= max_distance) || (c.found && std::abs(c.distance - nearest) > 1e-12))
                ++disagreements[size_t(thread)];
            found[size_t(thread)] += c.found;
        }
    };
    std::thread other(ask, 1);
    ask(0);
    other.join();
    EXPECT_EQ(disagreements[0], 0);
    EXPECT_EQ(disagreements[1], 0);
    EXPECT_GT(found[0], 100);
    EXPECT_GT(found[1], 100);
}

}  // namespace
}  // namespace symmetry
