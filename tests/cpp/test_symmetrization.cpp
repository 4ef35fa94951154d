// Symmetrization: a sphere mirrored across x = 0, with its x > 0 half pushed out along the
// normal by a smooth ripple, is moved towards the exact mirror; a hand-made detection
// result gives the symmetry, so the stage is tested on its own.
#include "core/icp.h"
#include "core/symmetrization.h"
#include "test_shapes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

using namespace symmetry;
using namespace symmetry::testing;

namespace {

// The mirror x -> -x as the detection would report it: every vertex in both patches,
// except those with |y| > 0.8, which are left in no symmetry.
DetectionResult mirror_of(const Eigen::MatrixX3d& V) {
    DetectionResult r;
    DetectedSymmetry s;
    s.transform = pure_mirror(Eigen::Vector3d::UnitX(), 0);
    r.vertex_symmetry_id.assign(size_t(V.rows()), -1);
    for (Eigen::Index v = 0; v < V.rows(); ++v)
        if (std::abs(V(v, 1)) <= 0.8) {
            s.source_vertices.push_back(int(v));
            r.vertex_symmetry_id[size_t(v)] = 0;
        }
    s.target_vertices = s.source_vertices;
    r.symmetries.push_back(s);
    r.vertex_deviation.assign(size_t(V.rows()), 0);
    return r;
}

// RMS over the rows of |radius - 1| - the exact sphere is its own mirror image.
double rms_off_sphere(const Eigen::MatrixX3d& V, const std::vector<int>& rows) {
    double sum = 0;
    for (int v : rows) sum += std::pow(V.row(v).norm() - 1, 2);
    return std::sqrt(sum / double(rows.size()));
}

}  // namespace

TEST(Symmetrization, TheMirrorImagesMeetHalfWayAndTheRestStays) {
    const Shape sphere_shape = sphere(1.0, 4);
    Eigen::MatrixX3d V = sphere_shape.V;
    for (Eigen::Index v = 0; v < V.rows(); ++v)
        if (V(v, 0) > 0) V.row(v) *= 1 + 0.004 * std::cos(7 * V(v, 1)) * V(v, 0);  // ripple on one half only
    const DetectionResult detected = mirror_of(V);
    const std::vector<int>& inside = detected.symmetries[0].source_vertices;
    std::vector<int> right;
    for (int v : inside)
        if (V(v, 0) > 0.3) right.push_back(v);

    SymmetrizationOptions options;
    const SymmetrizationResult out = symmetrize(V, sphere_shape.F, detected, 0.01, options);
    EXPECT_EQ(out.moved_vertices, int(inside.size()));
    EXPECT_LT(out.rms_after, 0.3 * out.rms_before);
    // The rippled half moves back towards the sphere, by about half the ripple: both sides
    // meet at their average, and the clean half takes the other half of it.
    EXPECT_LT(rms_off_sphere(out.V, right), 0.7 * rms_off_sphere(V, right));
    for (Eigen::Index v = 0; v < V.rows(); ++v)
        if (detected.vertex_symmetry_id[size_t(v)] < 0) EXPECT_EQ(out.V.row(v), V.row(v)) << v;
}

TEST(Symmetrization, AnExactMirrorDoesNotMove) {
    const Shape s = sphere(1.0, 3);
    const SymmetrizationResult out = symmetrize(s.V, s.F, mirror_of(s.V), 0.01, SymmetrizationOptions());
    EXPECT_LT((out.V - s.V).cwiseAbs().maxCoeff(), 1e-9);
    EXPECT_LT(out.rms_before, 1e-9);
}

TEST(Symmetrization, OptionsOutOfRangeAndForeignResultsAreRefused) {
    const Shape s = sphere(1.0, 2);
    SymmetrizationOptions options;
    options.strength = 2;
    EXPECT_THROW(symmetrize(s.V, s.F, mirror_of(s.V), 0.01, options), InputError);
    options = SymmetrizationOptions();
    options.iterations = 0;
    EXPECT_THROW(symmetrize(s.V, s.F, mirror_of(s.V), 0.01, options), InputError);
    const Shape other = sphere(1.0, 3);
    EXPECT_THROW(symmetrize(s.V, s.F, mirror_of(other.V), 0.01, SymmetrizationOptions()), InputError);
}
