// Second-order verification: under a true symmetry the curvature at every sample agrees
// with that at its image; under a motion that only makes two patches touch it does not.
#include "core/curvature_agreement.h"
#include "core/sampling.h"
#include "test_shapes.h"

#include <gtest/gtest.h>

#include <random>

#include <Eigen/Geometry>

using namespace symmetry;
using namespace symmetry::testing;

TEST(CurvatureAgreement, TellsACopyFromATwistedTouch) {
    Shape base = deformed_torus(2.0, 0.8, 150, 50, [](double u) { return 1 + 0.3 * std::cos(u) + 0.1 * std::sin(3 * u); });
    Transformation planted;
    planted.rotation = Eigen::AngleAxisd(2.0, Eigen::Vector3d(1, 1, 0).normalized()).toRotationMatrix();
    planted.translation = Eigen::Vector3d(9, 1, 0);
    Shape copy = transformed(deformed_torus(2.0, 0.8, 137, 43, [](double u) { return 1 + 0.3 * std::cos(u) + 0.1 * std::sin(3 * u); }),
                             planted.linear(), planted.translation);
    Mesh mesh;
    std::vector<int> rows;
    build_mesh(merged(base, copy).V, merged(base, copy).F, mesh, rows);
    const MeshNeighbourhoods n = mesh_neighbourhoods(mesh);
    const SurfaceQuery surface(mesh);
    const CurvatureEstimator curvature(mesh);
    const std::unique_ptr<CurvatureEstimator::Workspace> workspace = curvature.workspace();
    Roughness roughness(n, DenoisingOptions());
    const double diagonal = mesh.bbox.Diag(), radius = 0.01 * diagonal, tolerance = 0.01 * diagonal;
    std::mt19937_64 rng(5);
    std::vector<SurfaceSignature> samples = compute_signatures(mesh, uniform_area_sampling(mesh, 20000, rng), radius);
    NeighbourSamples neighbours(samples.size());

    // The patch: the base's vertices within 0.6 of a point p0 on it.
    const Eigen::Vector3d p0 = n.positions[100];
    std::vector<int> patch;
    for (int v = 0; v < int(base.V.rows()); ++v)
        if ((n.positions[size_t(v)] - p0).norm() < 0.6) patch.push_back(v);
    const CurvatureAgreementOptions options;
    CurvatureAgreement copy_agreement =
        curvature_agreement(n, surface, curvature, *workspace, roughness, neighbours, samples, patch, planted, radius, 0.05, tolerance, options);
    EXPECT_GT(copy_agreement.tested, 20);
    EXPECT_TRUE(copy_agreement.passes(options, 0.02));

    // The same, turned by 90° about p0's normal first: p0's neighbourhood still lands on the
    // copy (the two surfaces touch there), but its curvature is turned against the copy's.
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();
    for (int k = n.face_offsets[100]; k < n.face_offsets[101]; ++k) normal += n.face_normals[size_t(n.faces_around[size_t(k)])];
    Transformation twist;
    twist.rotation = Eigen::AngleAxisd(M_PI / 2, normal.normalized()).toRotationMatrix();
    twist.translation = p0 - twist.rotation * p0;
    CurvatureAgreement touch = curvature_agreement(n, surface, curvature, *workspace, roughness, neighbours, samples, patch, planted * twist,
                                                   radius, 0.05, tolerance, options);
    EXPECT_GT(touch.tested, 3);
    EXPECT_FALSE(touch.passes(options, 0.02));
}

// A cloud presmoothed for its noise: its curvature is fitted to points already moved onto
// fits over the same ball, so neighbours agree better than the curvature under a true
// symmetry can.  The counts are those measured on a bumpy torus's rigid copy, a third of
// the area, in its cloud with noise of 0.1 % of the diagonal: 0.27 of the neighbours'
// agreement, where a third of the area asks for 0.48.
TEST(CurvatureAgreement, APresmoothedNoisyCloudPassesOnlyPatchesLargerThanATouch) {
    CurvatureAgreement rigid_copy;
    rigid_copy.tested = 418;
    rigid_copy.under_transform = 49;
    rigid_copy.beside_source = 179;
    rigid_copy.beside_image = 201;
    rigid_copy.roughness_source = rigid_copy.roughness_image = 0.01;  // measured after the smoothing
    const CurvatureAgreementOptions options;
    const double noise_before_smoothing = 0.23;  // point spacings, about the copies' cloud's
    EXPECT_FALSE(rigid_copy.passes(options, 0.33));  // a mesh, or a cloud left as it is
    EXPECT_TRUE(rigid_copy.passes(options, 0.33, noise_before_smoothing));
    EXPECT_FALSE(rigid_copy.passes(options, 0.1, noise_before_smoothing));  // the size of a touch
    EXPECT_FALSE(rigid_copy.passes(options, 0.33, 0.05));  // noise the roughness still shows
}
