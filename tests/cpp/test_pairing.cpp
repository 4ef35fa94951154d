// Pairing in signature space (§2.2) against a brute-force scan of all pairs.
#include "core/pairing.h"

#include <gtest/gtest.h>

#include <map>
#include <random>
#include <set>

using namespace symmetry;

namespace {
std::vector<SurfaceSignature> random_samples(int n, std::mt19937_64& rng) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<SurfaceSignature> samples(n);
    for (auto& s : samples) {
        s.position = Eigen::Vector3d(u(rng), u(rng), u(rng));
        double a = 3 * u(rng), b = 3 * u(rng);
        s.kappa1 = std::min(a, b);
        s.kappa2 = std::max(a, b);
    }
    return samples;
}
}  // namespace

TEST(Pairing, SameAsBruteForce) {
    std::mt19937_64 rng(11);
    auto samples = random_samples(800, rng);
    const double radius = 0.1, min_distance = 0.2;
    for (TransformationGroup group : {TransformationGroup::Rigid, TransformationGroup::Similarity}) {
        const double tolerance = group == TransformationGroup::Similarity ? 0.01 : 0.03;
        std::mt19937_64 draw(3);
        auto pairs = pair_in_signature_space(samples, group, radius, tolerance, 200, min_distance, draw);
        std::map<int, std::set<int>> found;
        for (const auto& p : pairs) EXPECT_TRUE(found[p.first].insert(p.second).second) << "duplicate pair";
        EXPECT_LE(found.size(), 200u);
        EXPECT_GT(found.size(), 100u);
        for (const auto& [i, partners] : found) {
            std::set<int> oracle;
            for (int j = 0; j < int(samples.size()); ++j) {
                if (j == i) continue;
                if ((samples[j].position - samples[i].position).norm() < min_distance) continue;
                double d = (signature(samples[i], group, radius) - signature(samples[j], group, radius)).norm();
                if (d <= tolerance) oracle.insert(j);
            }
            EXPECT_EQ(partners, oracle) << "sample " << i;
        }
    }
}

TEST(Pairing, SubsetIsDeterministicAndDistinct) {
    std::mt19937_64 rng(12);
    auto samples = random_samples(300, rng);
    std::mt19937_64 a(5), b(5);
    auto pa = pair_in_signature_space(samples, TransformationGroup::Rigid, 0.1, 0.05, 50, 0.0, a);
    auto pb = pair_in_signature_space(samples, TransformationGroup::Rigid, 0.1, 0.05, 50, 0.0, b);
    ASSERT_EQ(pa.size(), pb.size());
    for (size_t k = 0; k < pa.size(); ++k) {
        EXPECT_EQ(pa[k].first, pb[k].first);
        EXPECT_EQ(pa[k].second, pb[k].second);
    }
}

// The last pass of the search pairs given samples (those away from what was verified):
// each gets the partners it would get if drawn into P'.
TEST(Pairing, GivenSamplesGetThePartnersOfADraw) {
    std::mt19937_64 rng(13);
    auto samples = random_samples(400, rng);
    std::mt19937_64 draw(7);
    auto drawn_pairs = pair_in_signature_space(samples, TransformationGroup::Rigid, 0.1, 0.05, 60, 0.1, draw);
    std::set<int> drawn;
    for (const auto& p : drawn_pairs) drawn.insert(p.first);
    ASSERT_GT(drawn.size(), 30u);
    auto given = pair_drawn_samples(samples, TransformationGroup::Rigid, 0.1, 0.05,
                                    std::vector<int>(drawn.begin(), drawn.end()), 0.1);
    ASSERT_EQ(given.size(), drawn_pairs.size());
    for (size_t k = 0; k < given.size(); ++k) {
        EXPECT_EQ(given[k].first, drawn_pairs[k].first);
        EXPECT_EQ(given[k].second, drawn_pairs[k].second);
    }
}

TEST(Pairing, ShapeIndexIsScaleInvariant) {
    SurfaceSignature s;
    s.kappa1 = -0.5;
    s.kappa2 = 2.0;
    SurfaceSignature scaled = s;
    scaled.kappa1 /= 3.7;
    scaled.kappa2 /= 3.7;
    EXPECT_NEAR((signature(s, TransformationGroup::Similarity, 1.0) -
                 signature(scaled, TransformationGroup::Similarity, 1.0)).norm(), 0.0, 1e-12);
    // A cylinder (κ1 = 0) has a finite signature where κ1/κ2 is fine too, and a
    // cylinder with κ2 = 0 (concave) where the plain ratio would divide by zero.
    SurfaceSignature concave;
    concave.kappa1 = -1.0;
    concave.kappa2 = 0.0;
    EXPECT_TRUE(std::isfinite(signature(concave, TransformationGroup::Similarity, 1.0)(0)));
}
