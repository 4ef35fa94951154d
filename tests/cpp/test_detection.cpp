// The whole pipeline on planted scenes: the planted transformation must be among the
// detected ones, its patches must be where they were planted, and the run must be a
// function of the seed.
#include "core/detection.h"
#include "test_shapes.h"

#include <gtest/gtest.h>

#include <random>

#include <Eigen/Geometry>

using namespace symmetry;
using namespace symmetry::testing;

namespace {

// A torus whose tube swells on one side: no continuous rotational symmetry, and
// curvatures that vary along the tube, so there are many non-umbilic samples.
Shape swollen_torus(int around, int tube) {
    return deformed_torus(2.0, 1.0, around, tube, [](double u) { return 0.6 + 0.25 * std::cos(u); });
}

// Largest displacement between two transformations over the given points.
double displacement(const Transformation& a, const Transformation& b, const Eigen::MatrixX3d& points) {
    double worst = 0;
    for (Eigen::Index i = 0; i < points.rows(); ++i) {
        Eigen::Vector3d p = points.row(i);
        worst = std::max(worst, (a.apply(p) - b.apply(p)).norm());
    }
    return worst;
}

struct Scene {
    Shape shape;
    Transformation planted;  // maps the first copy onto the second
    int base_vertices;
};

Scene rigid_copy_scene() {
    Shape base = swollen_torus(160, 48);
    Shape copy_source = swollen_torus(149, 43);  // another tessellation of the same surface
    Scene scene;
    scene.planted.rotation = Eigen::AngleAxisd(2.0, Eigen::Vector3d(1, 1, 0).normalized()).toRotationMatrix();
    scene.planted.translation = Eigen::Vector3d(7, 1, 0);
    scene.shape = merged(base, transformed(copy_source, scene.planted.linear(), scene.planted.translation));
    scene.base_vertices = int(base.V.rows());
    return scene;
}

}  // namespace

TEST(Detection, FindsAPlantedRigidCopy) {
    Scene scene = rigid_copy_scene();
    DetectionOptions options;
    DetectionResult result = detect_partial_symmetries(scene.shape.V, scene.shape.F, options);
    ASSERT_GT(result.symmetries.size(), 0u);
    const double diagonal = (scene.shape.V.colwise().maxCoeff() - scene.shape.V.colwise().minCoeff()).norm();
    Eigen::MatrixX3d base = scene.shape.V.topRows(scene.base_vertices);
    bool found = false;
    for (const auto& s : result.symmetries) {
        double forward = displacement(s.transform, scene.planted, base);
        double backward = displacement(s.transform.inverse(), scene.planted, base);
        if (std::min(forward, backward) < 0.005 * diagonal) {
            found = true;
            // The source patch covers most of one copy.
            EXPECT_GT(s.source_area, 0.4);
            EXPECT_LT(s.rms_error, 0.002);
        }
    }
    EXPECT_TRUE(found);
    // Every vertex listed in a patch carries that patch's id or a more significant one.
    for (size_t k = 0; k < result.symmetries.size(); ++k)
        for (int v : result.symmetries[k].source_vertices) EXPECT_LE(result.vertex_symmetry_id[v], int(k));
}

// The same scene as a point cloud (the vertices of both tessellations, no faces, no
// normals) with noise of 0.1 % of the diagonal on every coordinate: the normals are
// estimated, the cloud presmoothed, and the planted copy is found over the neighbour graph,
// with its patch.
TEST(Detection, FindsAPlantedRigidCopyInANoisyPointCloud) {
    Scene scene = rigid_copy_scene();
    std::mt19937_64 rng(2);
    std::normal_distribution<double> noise(0, 0.001);
    const double scene_diagonal = (scene.shape.V.colwise().maxCoeff() - scene.shape.V.colwise().minCoeff()).norm();
    Eigen::MatrixX3d cloud = scene.shape.V;
    for (Eigen::Index i = 0; i < cloud.rows(); ++i)
        for (int k = 0; k < 3; ++k) cloud(i, k) += scene_diagonal * noise(rng);
    DetectionOptions options;
    DetectionResult result = detect_partial_symmetries_in_point_cloud(cloud, Eigen::MatrixX3d(0, 3), options);
    const double diagonal = (cloud.colwise().maxCoeff() - cloud.colwise().minCoeff()).norm();
    Eigen::MatrixX3d base = scene.shape.V.topRows(scene.base_vertices);
    bool found = false;
    for (const auto& s : result.symmetries) {
        const double forward = displacement(s.transform, scene.planted, base);
        const double backward = displacement(s.transform.inverse(), scene.planted, base);
        if (std::min(forward, backward) < 0.005 * diagonal) {
            found = true;
            EXPECT_GT(s.source_area, 0.4);
            EXPECT_GT(s.source_vertices.size(), 0.8 * double(std::min<Eigen::Index>(scene.base_vertices,
                                                                                 cloud.rows() - scene.base_vertices)));
        }
    }
    EXPECT_TRUE(found) << result.symmetries.size() << " symmetries reported";
    EXPECT_TRUE(result.point_cloud && result.normals_estimated);
    EXPECT_GT(result.smoothing_radius, 0);
    ASSERT_EQ(result.vertex_symmetry_id.size(), size_t(cloud.rows()));
}

TEST(Detection, DeterministicForASeed) {
    Scene scene = rigid_copy_scene();
    DetectionOptions options;
    options.random_seed = 7;
    DetectionResult a = detect_partial_symmetries(scene.shape.V, scene.shape.F, options);
    DetectionResult b = detect_partial_symmetries(scene.shape.V, scene.shape.F, options);
    ASSERT_EQ(a.symmetries.size(), b.symmetries.size());
    for (size_t k = 0; k < a.symmetries.size(); ++k) {
        EXPECT_EQ(a.symmetries[k].transform.matrix(), b.symmetries[k].transform.matrix());
        EXPECT_EQ(a.symmetries[k].source_vertices, b.symmetries[k].source_vertices);
    }
    EXPECT_EQ(a.vertex_deviation, b.vertex_deviation);
}

TEST(Detection, RejectsAbsurdParametersWithASentence) {
    Scene scene = rigid_copy_scene();
    DetectionOptions options;
    options.umbilic_ratio = 1.5;
    try {
        detect_partial_symmetries(scene.shape.V, scene.shape.F, options);
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("umbilic_ratio"), std::string::npos);
    }
}

TEST(Detection, ATorusIsOneRotationalFamilyAndItsMirror) {
    // A torus has a continuum of symmetries (every rotation about its axis, every mirror
    // through a plane containing it, every half-turn about an axis in its equator) and one
    // more mirror, across the equator.  Reported: one rotational family and that mirror.
    const Eigen::Matrix3d tilt = Eigen::AngleAxisd(0.8, Eigen::Vector3d(1, -1, 2).normalized()).toRotationMatrix();
    Shape s = transformed(torus(2.0, 0.7, 160, 56), tilt, Eigen::Vector3d(1, 2, 3));
    DetectionResult r = detect_partial_symmetries(s.V, s.F, DetectionOptions());
    const Eigen::Vector3d axis = tilt * Eigen::Vector3d::UnitZ();
    int families = 0, mirrors = 0;
    for (const auto& sym : r.symmetries) {
        if (sym.continuous_kind == ContinuousKind::Rotational) {
            ++families;
            EXPECT_GT(std::abs(sym.axis_direction.dot(axis)), std::cos(0.5 * M_PI / 180));
            EXPECT_GT(sym.source_area, 0.95);
        } else {
            ASSERT_EQ(sym.continuous_kind, ContinuousKind::Discrete);
            EXPECT_TRUE(sym.transform.reflection);
            // The equator's mirror: it reverses the axis.
            EXPECT_LT((sym.transform.linear() * axis + axis).norm(), 0.01);
            ++mirrors;
        }
    }
    EXPECT_EQ(families, 1);
    EXPECT_EQ(mirrors, 1);
}

// Candidates are verified ahead of their turn, several at once, and settled in turn against
// what was found meanwhile (detection.cpp, hand_out_ahead): how many go ahead at once may
// change the time, never the result.  A row of four copies, each another tessellation, has
// many candidates that converge onto relations found while they were verified ahead, even
// on one thread.
TEST(Detection, CandidatesVerifiedAheadChangeNothing) {
    Shape row = swollen_torus(160, 48);
    const int tessellations[3][2] = {{149, 43}, {171, 52}, {155, 45}};
    for (int k = 0; k < 3; ++k) {
        const Shape copy = swollen_torus(tessellations[k][0], tessellations[k][1]);
        row = merged(row, transformed(copy, Eigen::Matrix3d::Identity(), Eigen::Vector3d(7.0 * (k + 1), 0, 0)));
    }
    DetectionOptions one_at_a_time;
    one_at_a_time.candidates_per_thread = 1;
    DetectionOptions many_ahead = one_at_a_time;
    many_ahead.candidates_per_thread = 16;
    const DetectionResult a = detect_partial_symmetries(row.V, row.F, one_at_a_time);
    const DetectionResult b = detect_partial_symmetries(row.V, row.F, many_ahead);
    ASSERT_GE(a.symmetries.size(), 3u);  // the three translations of the row at least
    EXPECT_EQ(a.verified_candidates, b.verified_candidates);
    ASSERT_EQ(a.symmetries.size(), b.symmetries.size());
    for (size_t k = 0; k < a.symmetries.size(); ++k) {
        EXPECT_EQ(a.symmetries[k].transform.matrix(), b.symmetries[k].transform.matrix());
        EXPECT_EQ(a.symmetries[k].source_vertices, b.symmetries[k].source_vertices);
        EXPECT_EQ(a.symmetries[k].target_vertices, b.symmetries[k].target_vertices);
    }
    EXPECT_EQ(a.vertex_deviation, b.vertex_deviation);
    EXPECT_EQ(a.vertex_symmetry_id, b.vertex_symmetry_id);
}
