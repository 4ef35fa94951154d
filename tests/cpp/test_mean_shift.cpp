// Mean shift (§3.1) against a brute-force ascent: the same modes, the same heights.
#include "core/mean_shift.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

using namespace symmetry;

namespace {

// Planted clusters in `dim` dimensions over a uniform background.
KdTree::Points planted(int dim, const std::vector<Eigen::VectorXd>& centres, int per_cluster, int background,
                       double spread, std::mt19937_64& rng) {
    std::normal_distribution<double> normal(0.0, spread);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    KdTree::Points points(centres.size() * per_cluster + background, dim);
    int row = 0;
    for (const auto& c : centres)
        for (int i = 0; i < per_cluster; ++i, ++row)
            for (int d = 0; d < dim; ++d) points(row, d) = c(d) + normal(rng);
    for (int i = 0; i < background; ++i, ++row)
        for (int d = 0; d < dim; ++d) points(row, d) = uniform(rng);
    return points;
}

// Ascent with the flat kernel by scanning every point: the definition, no kd-tree.
Eigen::VectorXd brute_force_ascent(const KdTree::Points& points, Eigen::VectorXd x, double h) {
    for (int it = 0; it < 200; ++it) {
        Eigen::VectorXd mean = Eigen::VectorXd::Zero(x.size());
        int count = 0;
        for (Eigen::Index j = 0; j < points.rows(); ++j)
            if ((points.row(j).transpose() - x).norm() <= h) { mean += points.row(j).transpose(); ++count; }
        mean /= count;
        if ((mean - x).norm() < 1e-9) break;
        x = mean;
    }
    return x;
}

}  // namespace

TEST(MeanShift, FindsPlantedModesLikeBruteForce) {
    for (int dim : {3, 7, 13}) {
        std::mt19937_64 rng(dim);
        std::vector<Eigen::VectorXd> centres;
        for (int c = 0; c < 3; ++c) centres.push_back(Eigen::VectorXd::Constant(dim, -0.5 + 0.5 * c));
        KdTree::Points points = planted(dim, centres, 60 + 20 * dim, 400, 0.01, rng);
        MeanShiftOptions options;
        options.bandwidth = 0.08;
        options.min_support = 20;
        KdTree tree(points);
        std::vector<Cluster> clusters = mean_shift(tree, options);
        ASSERT_EQ(clusters.size(), 3u) << "dimension " << dim;
        for (size_t k = 0; k + 1 < clusters.size(); ++k) EXPECT_GE(clusters[k].height, clusters[k + 1].height);
        for (const auto& cluster : clusters) {
            // The mode is a fixed point of the brute-force ascent started there.
            Eigen::VectorXd oracle = brute_force_ascent(points, cluster.mode, options.bandwidth);
            EXPECT_LT((oracle - cluster.mode).norm(), 1e-3 * options.bandwidth);
            // ...and is near one planted centre.
            double nearest = INFINITY;
            for (const auto& c : centres) nearest = std::min(nearest, (c - cluster.mode).norm());
            EXPECT_LT(nearest, 0.01 * std::sqrt(double(dim)));
            // Height is the number of points within h of the mode, by brute force.
            int count = 0;
            for (Eigen::Index j = 0; j < points.rows(); ++j)
                if ((points.row(j).transpose() - cluster.mode).norm() <= options.bandwidth) ++count;
            EXPECT_EQ(cluster.height, count);
        }
        // The members are the points within h of the mode: as many as the height.
        for (const auto& cluster : clusters) {
            EXPECT_EQ(int(cluster.members.size()), cluster.height);
            for (int m : cluster.members)
                EXPECT_LE((points.row(m).transpose() - cluster.mode).norm(), options.bandwidth);
        }
    }
}

TEST(MeanShift, ProjectionKeepsModesOnTheManifold) {
    // Points on the unit circle in 2-D, clustered around angle 1; with a projection onto
    // the circle the mode stays on it, without one it would fall inside.
    std::mt19937_64 rng(5);
    std::normal_distribution<double> noise(0.0, 0.05);
    KdTree::Points points(200, 2);
    for (int i = 0; i < 200; ++i) {
        double a = 1.0 + noise(rng);
        points.row(i) << std::cos(a), std::sin(a);
    }
    MeanShiftOptions options;
    options.bandwidth = 0.3;
    options.min_support = 10;
    options.project = [](Eigen::Ref<Eigen::VectorXd> x) { x.normalize(); };
    KdTree tree(points);
    auto clusters = mean_shift(tree, options);
    ASSERT_EQ(clusters.size(), 1u);
    EXPECT_NEAR(clusters[0].mode.norm(), 1.0, 1e-12);
    EXPECT_NEAR(std::atan2(clusters[0].mode(1), clusters[0].mode(0)), 1.0, 0.02);
}

TEST(MeanShift, ThinBackgroundGivesNoCluster) {
    std::mt19937_64 rng(6);
    KdTree::Points points = planted(7, {}, 0, 500, 0.0, rng);
    MeanShiftOptions options;
    options.bandwidth = 0.05;
    options.min_support = 5;
    KdTree tree(points);
    EXPECT_TRUE(mean_shift(tree, options).empty());
}

// Ascents climbed in batches on every core are committed as if climbed one after the
// other: any batch size gives the modes, heights and members of the sequence.  A ridge
// (points along a line, as a continuous family makes) and close clusters make ascents
// join modes that earlier ascents of the same batch found.
TEST(MeanShift, BatchesOfAscentsGiveTheSequentialResult) {
    std::mt19937_64 rng(17);
    const int dim = 7;
    std::vector<Eigen::VectorXd> centres;
    for (double t : {-0.3, 0.0, 0.05, 0.4}) centres.push_back(Eigen::VectorXd::Constant(dim, t));
    KdTree::Points points = planted(dim, centres, 150, 2000, 0.03, rng);
    KdTree::Points ridge(400, dim);
    std::uniform_real_distribution<double> along(-0.8, 0.8);
    std::normal_distribution<double> off(0.0, 0.01);
    for (int i = 0; i < 400; ++i)
        for (int d = 0; d < dim; ++d) ridge(i, d) = (d == 0 ? along(rng) : 0.6) + off(rng);
    KdTree::Points all(points.rows() + ridge.rows(), dim);
    all << points, ridge;
    const KdTree tree(all);
    MeanShiftOptions options;
    options.bandwidth = 0.12;
    options.min_support = 5;
    options.batch_size = 1;
    const std::vector<Cluster> sequential = mean_shift(tree, options);
    ASSERT_GT(sequential.size(), 4u);
    for (int batch : {2, 3, 8, 64}) {
        options.batch_size = batch;
        const std::vector<Cluster> batched = mean_shift(tree, options);
        ASSERT_EQ(batched.size(), sequential.size()) << "batch " << batch;
        for (size_t k = 0; k < batched.size(); ++k) {
            EXPECT_EQ(batched[k].height, sequential[k].height) << "batch " << batch;
            EXPECT_EQ(batched[k].members, sequential[k].members) << "batch " << batch;
            EXPECT_EQ((batched[k].mode - sequential[k].mode).norm(), 0.0) << "batch " << batch;
        }
    }
}

// Counting the densities again only around removed points gives what counting every
// point of the smaller set gives, including counts held at the cap, whichever way the
// points near a removed one are found (scanning cells, the tree of removed points where
// cells are crowded, or range queries where the points spread over more cells than a key
// holds).
TEST(MeanShift, DensitiesAfterRemovalEqualACountFromScratch) {
    std::mt19937_64 rng(5);
    const int dim = 13;
    std::vector<Eigen::VectorXd> centres;
    for (double t : {-0.4, 0.0, 0.3}) centres.push_back(Eigen::VectorXd::Constant(dim, t));
    KdTree::Points all = planted(dim, centres, 400, 1500, 0.02, rng);
    // Remove most of one cluster (as a continuous family's votes leave Γ) and some background.
    std::vector<int> kept;
    std::vector<int> gone;
    std::bernoulli_distribution keep_background(0.8);
    for (int i = 0; i < int(all.rows()); ++i) {
        const bool in_first_cluster = i < 400 && i % 5 != 0;
        const bool removed = in_first_cluster || (i >= 1200 && !keep_background(rng));
        (removed ? gone : kept).push_back(i);
    }
    MeanShiftOptions options;
    options.bandwidth = 0.1;
    options.density_cap = 100;  // below the clusters' counts (400), above what one keeps (80)
    for (double far : {0.0, 250.0}) {  // 250: 2,500 cells along the first axis, more than a key holds
        for (int i = 1200; i < 1210; ++i) all(i, 0) += far;
        const KdTree before(all);
        const std::vector<int> density = densities(before, options);
        ASSERT_EQ(*std::max_element(density.begin(), density.end()), options.density_cap);
        KdTree::Points rest(kept.size(), dim), removed(gone.size(), dim);
        for (size_t k = 0; k < kept.size(); ++k) rest.row(long(k)) = all.row(kept[k]);
        for (size_t k = 0; k < gone.size(); ++k) removed.row(long(k)) = all.row(gone[k]);
        const KdTree after(rest);
        const std::vector<int> from_scratch = densities(after, options);
        for (int axes : {1, 4})
            for (int limit : {0, 100, 1 << 30}) {  // crowded cells by the tree: all, some, none
                MeanShiftOptions o = options;
                o.grid_axes = axes;
                o.max_scanned_neighbours = limit;
                EXPECT_EQ(densities_after_removal(after, density, kept, removed, o), from_scratch)
                    << axes << " axes, " << limit << " scanned at most, " << far;
            }
        // ...and the removal did change counts, capped ones among them: the test has teeth.
        int changed = 0, changed_at_cap = 0;
        for (size_t k = 0; k < kept.size(); ++k)
            if (from_scratch[k] != density[size_t(kept[k])]) {
                ++changed;
                changed_at_cap += density[size_t(kept[k])] == options.density_cap;
            }
        EXPECT_GT(changed, 50);
        EXPECT_GT(changed_at_cap, 50);
    }
}

namespace {

// Density of every point by its definition: scan all points, cap the count.
std::vector<int> brute_force_densities(const KdTree::Points& points, double h, int cap) {
    std::vector<int> density(size_t(points.rows()));
    for (Eigen::Index i = 0; i < points.rows(); ++i) {
        int count = 0;
        for (Eigen::Index j = 0; j < points.rows(); ++j) count += (points.row(i) - points.row(j)).squaredNorm() < h * h;
        density[size_t(i)] = std::min(count, cap);
    }
    return density;
}

}  // namespace

// The densities are counted by scanning cells (CellGrid in mean_shift.cpp): the count of
// points within h, capped, must be the definition's, checked by scanning every point, and
// the kd-tree's, for every number of grid axes, whichever way each point is counted.  The
// points are shaped like Γ: many votes sharing one translation (a rotational family, which
// crowds a cell), tight clusters, a background, and points on the borders of cells
// (coordinates that are multiples of h); then some moved 1,200 cells away, more than a
// cell key holds, where the tree counts all.
TEST(MeanShift, DensitiesCountedInCellsEqualBruteForceAndTree) {
    std::mt19937_64 rng(11);
    const int dim = 13;
    const double h = 0.05;
    std::vector<Eigen::VectorXd> centres;
    for (double t : {-0.3, 0.0, 0.45}) centres.push_back(Eigen::VectorXd::Constant(dim, t));
    KdTree::Points points = planted(dim, centres, 300, 1200, 0.006, rng);
    std::uniform_real_distribution<double> angle(0.0, 6.283185307179586);
    for (int i = 0; i < 300; ++i) {  // a family: translation 0, rotation entries on a circle
        points.row(i).setZero();
        const double a = angle(rng);
        points(i, 4) = 0.18 * std::cos(a);
        points(i, 5) = 0.18 * std::sin(a);
    }
    for (int i = 300; i < 340; ++i)  // on the cells' borders
        for (int d = 0; d < dim; ++d) points(i, d) = h * double(int(i % 7) - 3);
    MeanShiftOptions options;
    options.bandwidth = h;
    options.density_cap = 40;  // below the clusters' counts and the family's
    for (double far : {0.0, 60.0}) {
        for (int i = 300; i < 320; ++i) points(i, 0) += far;
        const std::vector<int> brute = brute_force_densities(points, h, options.density_cap);
        const KdTree tree(points);
        std::vector<int> by_tree(size_t(points.rows()));
        for (Eigen::Index i = 0; i < points.rows(); ++i)
            by_tree[size_t(i)] = tree.count_within(points.row(i).data(), h, options.density_cap);
        EXPECT_EQ(by_tree, brute);
        for (int axes : {1, 3, 4, 6})
            for (int limit : {0, 100, 1 << 30}) {  // all by the tree, both ways, all by scanning
                options.grid_axes = axes;
                options.max_scanned_neighbours = limit;
                EXPECT_EQ(densities(tree, options), brute) << axes << " axes, " << limit << " scanned at most, " << far;
            }
        // The test has teeth: counts at the cap, below it, and of points alone.
        EXPECT_GT(std::count(brute.begin(), brute.end(), options.density_cap), 300);
        EXPECT_GT(std::count(brute.begin(), brute.end(), 1), 300);
        EXPECT_GT(std::count_if(brute.begin(), brute.end(), [&](int c) { return c > 1 && c < options.density_cap; }), 20);
    }
}
