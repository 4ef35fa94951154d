// Presmoothing: the noise estimate tells a noisy surface from a clean one, fine or coarse,
// and the smoothing removes the noise without moving a clean surface far.
#include "core/denoising.h"
#include "test_shapes.h"

#include <gtest/gtest.h>

#include <random>

using namespace symmetry;
using namespace symmetry::testing;

namespace {

Shape noisy(Shape s, double sigma, unsigned seed) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> n(0.0, sigma);
    for (Eigen::Index i = 0; i < s.V.rows(); ++i) {
        Eigen::Vector3d p = s.V.row(i);
        s.V.row(i) = (p + n(rng) * p.normalized()).transpose();  // along the sphere's normal
    }
    return s;
}

NoiseEstimate estimate(const Shape& s) {
    Mesh mesh;
    std::vector<int> rows;
    build_mesh(s.V, s.F, mesh, rows);
    return estimate_noise(mesh_neighbourhoods(mesh), DenoisingOptions());
}

double mean_edge(const Shape& s) {
    Mesh mesh;
    std::vector<int> rows;
    build_mesh(s.V, s.F, mesh, rows);
    return median_edge_length(mesh_neighbourhoods(mesh));
}

}  // namespace

TEST(Denoising, CleanSurfacesFineOrCoarseAreNotNoisy) {
    const DenoisingOptions options;
    for (int levels : {2, 3, 5}) {  // 320 to 20480 faces
        NoiseEstimate e = estimate(sphere(1.0, levels));
        EXPECT_LT(e.noise_in_edges(), options.noise_threshold_in_edges / 2) << levels;
        EXPECT_EQ(smoothing_radius(e, options), 0.0) << levels;
    }
    // Flat faces and sharp creases (a box) are shape, not noise.
    EXPECT_EQ(smoothing_radius(estimate(box(1, 0.7, 0.4, 12)), options), 0.0);
}

TEST(Denoising, NoiseIsMeasuredAndSmoothedAway) {
    const DenoisingOptions options;
    const Shape clean = sphere(1.0, 5);
    const double edge = mean_edge(clean);
    const Shape rough = noisy(clean, 0.4 * edge, 3);
    NoiseEstimate e = estimate(rough);
    EXPECT_GT(e.noise_in_edges(), options.noise_threshold_in_edges);
    const double radius = smoothing_radius(e, options);
    ASSERT_GT(radius, 0.0);

    Mesh mesh;
    std::vector<int> rows;
    build_mesh(rough.V, rough.F, mesh, rows);
    EXPECT_GT(smooth_positions(mesh, radius, options), 0);
    // The noise is gone: the estimate falls below the threshold, and the vertices lie on a
    // sphere again (heat flow shrinks it a little, uniformly).
    NoiseEstimate after = estimate_noise(mesh_neighbourhoods(mesh), options);
    EXPECT_LT(after.noise_in_edges(), options.noise_threshold_in_edges);
    double mean_radius = 0, spread = 0;
    for (const auto& v : mesh.vert) mean_radius += v.cP().Norm();
    mean_radius /= double(mesh.vert.size());
    for (const auto& v : mesh.vert) spread = std::max(spread, std::abs(v.cP().Norm() - mean_radius));
    // Heat flow for a time t = ρ²/2 shrinks a sphere of radius 1 by about t · 2H = ρ².
    EXPECT_GT(mean_radius, 1.0 - 2 * radius * radius);
    EXPECT_LT(mean_radius, 1.0);
    EXPECT_LT(spread, 0.4 * edge);
}
