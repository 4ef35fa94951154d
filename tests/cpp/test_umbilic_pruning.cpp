// Stage 3 (§2.1): umbilic pruning on analytic shapes (sphere, cylinder, plane,
// torus saddle) and at the boundary of the paper's threshold gamma.
#include "core/umbilic_pruning.h"
#include "test_shapes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace symmetry {
namespace {

using testing::Shape;

constexpr double kGamma = 0.75;  // the paper's value (§2.1)
constexpr double kFlatness = 0.05;  // DetectionOptions::flatness by default

std::vector<SurfaceSignature> signatures_of(const Shape& shape, int count, uint64_t seed, double radius) {
    Mesh mesh;
    std::vector<int> vertex_of_input;
    build_mesh(shape.V, shape.F, mesh, vertex_of_input);
    std::mt19937_64 rng(seed);
    return compute_signatures(mesh, uniform_area_sampling(mesh, count, rng), radius);
}

SurfaceSignature with_curvatures(double kappa1, double kappa2) {
    SurfaceSignature s;
    s.kappa1 = kappa1;
    s.kappa2 = kappa2;
    return s;
}

TEST(UmbilicPruning, SphereSamplesAreAllPruned) {
    const double radius = 0.2;
    auto signatures = signatures_of(testing::sphere(1, 5), 500, 21, radius);
    EXPECT_TRUE(prune_umbilics(signatures, kGamma, radius, kFlatness).empty());
}

TEST(UmbilicPruning, CylinderSamplesAreKept) {
    const double radius = 0.15;
    auto signatures = signatures_of(testing::cylinder(1, 4, 128, 80), 500, 22, radius);
    auto kept = prune_umbilics(signatures, kGamma, radius, kFlatness);
    EXPECT_EQ(kept.size(), signatures.size());
}

TEST(UmbilicPruning, FlatSamplesArePruned) {
    // A flat square, as a cylinder of huge radius would look: curvatures ~0.
    Shape plane;
    plane.V.resize(4, 3);
    plane.V << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0;
    plane.F.resize(2, 3);
    plane.F << 0, 1, 2, 0, 2, 3;
    const double radius = 0.2;
    auto signatures = signatures_of(plane, 200, 23, radius);
    EXPECT_TRUE(prune_umbilics(signatures, kGamma, radius, kFlatness).empty());
    // A nearly flat cylinder: curvature 1/100 bends the ball of radius 0.2 by
    // 0.0002, below kFlatness * r / 2 = 0.005.
    auto wide = signatures_of(testing::cylinder(100, 4, 2000, 40), 200, 24, radius);
    EXPECT_TRUE(prune_umbilics(wide, kGamma, radius, kFlatness).empty());
}

TEST(UmbilicPruning, SaddleSamplesAreKept) {
    // Torus (R = 3, r = 1): the inner ring is a saddle (kappa1 = -1/2, kappa2 = 1),
    // the outer ring has kappa1/kappa2 = 1/4; both are kept.
    const double radius = 0.2;
    auto signatures = signatures_of(testing::torus(3, 1, 288, 96), 2000, 25, radius);
    int saddles = 0;
    for (const auto& s : signatures) {
        if (s.kappa1 < 0 && s.kappa2 > 0) ++saddles;
        if (std::abs(s.position.z()) < 0.1) EXPECT_TRUE(has_distinct_principal_curvatures(s, kGamma, radius, kFlatness));
    }
    EXPECT_GT(saddles, 100);
    // Synthetic saddles: kept whatever the magnitudes, even at ratio -1.
    EXPECT_TRUE(has_distinct_principal_curvatures(with_curvatures(-1, 1), kGamma, 1, kFlatness));
    EXPECT_TRUE(has_distinct_principal_curvatures(with_curvatures(-0.1, 3), kGamma, 1, kFlatness));
    EXPECT_TRUE(has_distinct_principal_curvatures(with_curvatures(-3, 0.1), kGamma, 1, kFlatness));
}

TEST(UmbilicPruning, BoundaryOfGamma) {
    // The paper keeps |kappa1/kappa2| < gamma, strictly (values exact in binary).
    EXPECT_FALSE(has_distinct_principal_curvatures(with_curvatures(0.75, 1), kGamma, 1, kFlatness));
    EXPECT_TRUE(has_distinct_principal_curvatures(with_curvatures(0.7499, 1), kGamma, 1, kFlatness));
    EXPECT_FALSE(has_distinct_principal_curvatures(with_curvatures(-1, -0.75), kGamma, 1, kFlatness));
    EXPECT_TRUE(has_distinct_principal_curvatures(with_curvatures(-1, -0.7499), kGamma, 1, kFlatness));
    // Same ratio at another scale: the test is scale invariant (§2.2, Ω7).
    EXPECT_FALSE(has_distinct_principal_curvatures(with_curvatures(7.5, 10), kGamma, 1, kFlatness));
    EXPECT_TRUE(has_distinct_principal_curvatures(with_curvatures(7.4, 10), kGamma, 1, kFlatness));
}

TEST(UmbilicPruning, BoundaryOfFlatness) {
    // Flat below kFlatness / r, whatever the ratio.
    const double radius = 0.5;
    EXPECT_TRUE(has_distinct_principal_curvatures(with_curvatures(0, kFlatness / radius), kGamma, radius, kFlatness));
    EXPECT_FALSE(has_distinct_principal_curvatures(with_curvatures(0, 0.99 * kFlatness / radius), kGamma, radius, kFlatness));
    EXPECT_FALSE(has_distinct_principal_curvatures(with_curvatures(-0.99 * kFlatness / radius, 0), kGamma, radius, kFlatness));
    EXPECT_FALSE(has_distinct_principal_curvatures(with_curvatures(0, 0), kGamma, radius, kFlatness));
    EXPECT_FALSE(has_distinct_principal_curvatures(with_curvatures(NAN, 1), kGamma, radius, kFlatness));
}

TEST(UmbilicPruning, AgreesWithThePapersRatioForEqualSigns) {
    // Oracle: |small / large| < gamma with the curvatures ordered by magnitude.
    std::mt19937_64 rng(26);
    auto uniform = [&rng](double lo, double hi) { return lo + (hi - lo) * double(rng() >> 11) * 0x1.0p-53; };
    for (int i = 0; i < 10000; ++i) {
        double a = uniform(0.2, 5), b = uniform(0.2, 5), sign = i % 2 ? 1 : -1;
        double k1 = sign * std::min(a, b), k2 = sign * std::max(a, b);
        if (k1 > k2) std::swap(k1, k2);
        double gamma = uniform(0.1, 0.95);
        bool paper = std::min(a, b) / std::max(a, b) < gamma;
        if (std::abs(std::min(a, b) / std::max(a, b) - gamma) < 1e-12) continue;  // rounding at the boundary
        EXPECT_EQ(has_distinct_principal_curvatures(with_curvatures(k1, k2), gamma, 1, kFlatness), paper)
            << k1 << " " << k2 << " " << gamma;
    }
}

TEST(UmbilicPruning, KeepsOrder) {
    std::vector<SurfaceSignature> in = {with_curvatures(0, 1), with_curvatures(1, 1), with_curvatures(-1, 2),
                                        with_curvatures(0.9, 1), with_curvatures(0.1, 2)};
    for (size_t i = 0; i < in.size(); ++i) in[i].face = int(i);
    auto kept = prune_umbilics(in, kGamma, 1, kFlatness);
    ASSERT_EQ(kept.size(), 3u);
    EXPECT_EQ(kept[0].face, 0);
    EXPECT_EQ(kept[1].face, 2);
    EXPECT_EQ(kept[2].face, 4);
}

}  // namespace
}  // namespace symmetry
