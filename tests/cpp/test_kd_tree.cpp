// The kd-tree behind every neighbourhood query (§2, §2.2, §3.1), checked against
// brute force in the dimensions the pipeline uses (3: edges, 2: signature space Ω6,
// 7: transformation space Γ) and one more.
#include "core/kd_tree.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <utility>

namespace symmetry {
namespace {

double uniform01(std::mt19937_64& rng) { return double(rng() >> 11) * 0x1.0p-53; }

KdTree::Points random_points(int count, int dimension, std::mt19937_64& rng) {
    KdTree::Points p(count, dimension);
    for (int i = 0; i < count; ++i)
        for (int d = 0; d < dimension; ++d) p(i, d) = uniform01(rng);
    return p;
}

std::vector<int> brute_force_radius(const KdTree::Points& p, const Eigen::VectorXd& q, double radius) {
    std::vector<int> found;
    for (Eigen::Index i = 0; i < p.rows(); ++i)
        if ((p.row(i).transpose() - q).norm() < radius) found.push_back(int(i));
    return found;
}

std::pair<int, double> brute_force_nearest(const KdTree::Points& p, const Eigen::VectorXd& q) {
    int best = -1;
    double distance = INFINITY;
    for (Eigen::Index i = 0; i < p.rows(); ++i) {
        double d = (p.row(i).transpose() - q).norm();
        if (d < distance) distance = d, best = int(i);
    }
    return {best, distance};
}

class KdTreeAgainstBruteForce : public ::testing::TestWithParam<int> {};

TEST_P(KdTreeAgainstBruteForce, RadiusSearchAndNearest) {
    const int dimension = GetParam();
    std::mt19937_64 rng(100 + dimension);
    const int count = 3000;
    const KdTree::Points points = random_points(count, dimension, rng);
    const KdTree tree(points);
    ASSERT_EQ(tree.size(), count);
    ASSERT_EQ(tree.dimension(), dimension);
    // A radius that holds about 20 of the points: volume fraction 20 / count of the unit cube.
    const double unit_ball = std::pow(M_PI, dimension / 2.0) / std::tgamma(dimension / 2.0 + 1);
    const double radius = std::pow(20.0 / count / unit_ball, 1.0 / dimension);
    size_t total_found = 0;
    for (int k = 0; k < 200; ++k) {
        // Half the queries on data points, half anywhere (also outside the cube).
        Eigen::VectorXd q(dimension);
        if (k % 2) q = points.row(k).transpose();
        else
            for (int d = 0; d < dimension; ++d) q(d) = 1.2 * uniform01(rng) - 0.1;
        const std::vector<int> expected = brute_force_radius(points, q, radius);
        const std::vector<int> found = tree.radius_search(q.data(), radius);
        EXPECT_EQ(found, expected) << "query " << k;  // same indices, increasing
        total_found += found.size();

        auto [index, distance] = tree.nearest(q.data());
        auto [best, best_distance] = brute_force_nearest(points, q);
        EXPECT_EQ(index, best);
        EXPECT_NEAR(distance, best_distance, 1e-12);
        if (k % 2) EXPECT_EQ(distance, 0.0);
    }
    // The radius is not trivially small (fewer than 20 per query in high dimension,
    // where much of the ball lies outside the cube).
    EXPECT_GT(total_found, 200u * 2);
}

INSTANTIATE_TEST_SUITE_P(Dimensions, KdTreeAgainstBruteForce, ::testing::Values(2, 3, 7, 13));

TEST(KdTree, MoveKeepsWorking) {
    std::mt19937_64 rng(7);
    const KdTree::Points points = random_points(500, 3, rng);
    KdTree original(points);
    const double q[3] = {0.5, 0.5, 0.5};
    const auto before = original.radius_search(q, 0.2);
    const auto nearest_before = original.nearest(q);
    ASSERT_FALSE(before.empty());

    KdTree moved(std::move(original));
    EXPECT_EQ(moved.radius_search(q, 0.2), before);
    EXPECT_EQ(moved.nearest(q), nearest_before);

    KdTree assigned(random_points(10, 3, rng));
    assigned = std::move(moved);
    EXPECT_EQ(assigned.size(), 500);
    EXPECT_EQ(assigned.radius_search(q, 0.2), before);

    // A vector of trees moves them as it grows.
    std::vector<KdTree> trees;
    for (int i = 0; i < 20; ++i) trees.emplace_back(points);
    for (const auto& t : trees) EXPECT_EQ(t.radius_search(q, 0.2), before);
}

TEST(KdTree, EmptyAndDuplicatePoints) {
    const KdTree empty(KdTree::Points(0, 3));
    const double q[3] = {0, 0, 0};
    EXPECT_TRUE(empty.radius_search(q, 1).empty());
    EXPECT_EQ(empty.nearest(q).first, -1);

    // Many copies of one point (a tree that cannot split them) are all found.
    KdTree::Points same = KdTree::Points::Constant(100, 3, 0.25);
    const KdTree tree(same);
    EXPECT_EQ(tree.radius_search(q, 1).size(), 100u);
    EXPECT_NEAR(tree.nearest(q).second, 0.25 * std::sqrt(3.0), 1e-15);
}

}  // namespace
}  // namespace symmetry
