// Transformation algebra and the space Γ (§2, §3): exact recovery of a planted
// transformation from a pair of frames, and a metric without seams.
#include "core/transformation_space.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

using namespace symmetry;

namespace {

Eigen::Matrix3d random_rotation(std::mt19937_64& rng) {
    std::normal_distribution<double> n;
    Eigen::Quaterniond q(n(rng), n(rng), n(rng), n(rng));
    return q.normalized().toRotationMatrix();
}

Transformation random_transformation(std::mt19937_64& rng, bool reflection, double scale) {
    Transformation t;
    t.rotation = random_rotation(rng);
    t.reflection = reflection;
    t.scale = scale;
    std::normal_distribution<double> n;
    t.translation = Eigen::Vector3d(n(rng), n(rng), n(rng));
    return t;
}

SurfaceSignature random_frame(std::mt19937_64& rng) {
    SurfaceSignature s;
    Eigen::Matrix3d F = random_rotation(rng);
    s.direction1 = F.col(0);
    s.direction2 = F.col(1);
    s.normal = F.col(2);
    std::normal_distribution<double> n;
    s.position = Eigen::Vector3d(n(rng), n(rng), n(rng));
    s.kappa1 = -0.5;
    s.kappa2 = 2.0;
    return s;
}

// The frame of T(a): positions and normals map by T, the directions map by T's
// orthogonal part and are then re-signed arbitrarily (principal directions have no sign),
// keeping the frame right-handed.
SurfaceSignature image(const SurfaceSignature& a, const Transformation& T, bool flip) {
    SurfaceSignature b = a;
    b.position = T.apply(a.position);
    b.normal = T.apply_to_normal(a.normal);
    b.direction1 = T.apply_to_normal(a.direction1) * (flip ? -1.0 : 1.0);
    b.direction2 = b.normal.cross(b.direction1);
    b.kappa1 = a.kappa1 / T.scale;
    b.kappa2 = a.kappa2 / T.scale;
    return b;
}

double matrix_error(const Transformation& a, const Transformation& b) { return (a.matrix() - b.matrix()).norm(); }

}  // namespace

TEST(Transformation, InverseAndCompositionAreExact) {
    std::mt19937_64 rng(1);
    for (bool reflection : {false, true}) {
        Transformation a = random_transformation(rng, reflection, 1.7);
        Transformation b = random_transformation(rng, !reflection, 0.4);
        EXPECT_LT(((a * a.inverse()).matrix() - Eigen::Matrix4d::Identity()).norm(), 1e-12);
        EXPECT_LT(((a * b).matrix() - a.matrix() * b.matrix()).norm(), 1e-12);
        EXPECT_EQ((a * b).reflection, a.reflection != b.reflection);
        EXPECT_LT(matrix_error(Transformation::from_linear(a.linear(), a.translation), a), 1e-12);
        Eigen::Vector3d x(0.3, -1.2, 2.0);
        EXPECT_LT((a.apply(x) - (a.matrix() * x.homogeneous()).head<3>()).norm(), 1e-12);
    }
}

TEST(TransformationSpace, CoordinatesRoundTrip) {
    std::mt19937_64 rng(2);
    TransformationSpace space(Eigen::Vector3d(1, 2, 3), 7.0);
    for (bool reflection : {false, true}) {
        Transformation t = random_transformation(rng, reflection, 2.5);
        Transformation back = space.transformation(space.coordinates(t), reflection);
        EXPECT_LT(matrix_error(t, back), 1e-10);
    }
}

TEST(TransformationSpace, WeightsFollowSection3) {
    TransformationSpace space(Eigen::Vector3d::Zero(), 4.0);
    Transformation identity, half_turn, shift, scaled;
    half_turn.rotation = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    shift.translation = Eigen::Vector3d(2.0, 0, 0);  // half of the diagonal
    scaled.scale = 10;
    EXPECT_NEAR(space.distance(identity, half_turn), 0.5, 1e-12);
    EXPECT_NEAR(space.distance(identity, shift), 0.5, 1e-12);
    EXPECT_NEAR(space.distance(identity, scaled), 0.5, 1e-12);
    Transformation mirror;
    mirror.reflection = true;
    EXPECT_TRUE(std::isinf(space.distance(identity, mirror)));
}

TEST(TransformationSpace, NoSeamAtHalfTurn) {
    // Euler angles put rotations by +179° and -179° about an axis 358° apart; in Γ they
    // must be as close as the 2° between them.
    TransformationSpace space(Eigen::Vector3d::Zero(), 1.0);
    Eigen::Vector3d axis = Eigen::Vector3d(1, 2, 3).normalized();
    Transformation a, b, c;
    a.rotation = Eigen::AngleAxisd(M_PI - 0.0175, axis).toRotationMatrix();
    b.rotation = Eigen::AngleAxisd(-M_PI + 0.0175, axis).toRotationMatrix();
    c.rotation = Eigen::AngleAxisd(M_PI - 0.0525, axis).toRotationMatrix();
    EXPECT_NEAR(space.distance(a, b), space.distance(a, c), 1e-9);
    EXPECT_LT(space.distance(a, b), 0.01);
}

TEST(TransformationsFromFrames, RecoverPlantedRigidAndSimilarity) {
    std::mt19937_64 rng(3);
    for (TransformationGroup group : {TransformationGroup::Rigid, TransformationGroup::Similarity})
        for (bool reflection : {false, true})
            for (bool flip : {false, true}) {
                double scale = group == TransformationGroup::Similarity ? 0.6 : 1.0;
                Transformation T = random_transformation(rng, reflection, scale);
                SurfaceSignature a = random_frame(rng);
                SurfaceSignature b = image(a, T, flip);
                auto candidates = transformations_from_frames(a, b, group);
                ASSERT_EQ(candidates.size(), 4u);
                double best = INFINITY;
                for (const auto& c : candidates) {
                    EXPECT_LT((c.apply(a.position) - b.position).norm(), 1e-9);
                    if (c.reflection == T.reflection) best = std::min(best, matrix_error(c, T));
                }
                EXPECT_LT(best, 1e-9) << "group " << int(group) << " reflection " << reflection << " flip " << flip;
            }
}

TEST(TransformationsFromFrames, ReflectionsAndTranslationsCheckTheFrames) {
    std::mt19937_64 rng(4);
    SurfaceSignature a = random_frame(rng);
    // A mirror through the plane x = 1.
    Transformation mirror;
    mirror.reflection = true;
    mirror.translation = Eigen::Vector3d(2, 0, 0);
    SurfaceSignature b = image(a, mirror, true);
    auto found = transformations_from_frames(a, b, TransformationGroup::Reflections);
    ASSERT_EQ(found.size(), 1u);
    EXPECT_LT(matrix_error(found[0], mirror), 1e-9);
    // A rotated partner is no mirror image: rejected by its frame.
    Transformation turn;
    turn.rotation = Eigen::AngleAxisd(1.0, a.direction1).toRotationMatrix();
    turn.translation = Eigen::Vector3d(3, 0, 0);
    EXPECT_TRUE(transformations_from_frames(a, image(a, turn, false), TransformationGroup::Reflections).empty());

    Transformation shift;
    shift.translation = Eigen::Vector3d(0.5, -2, 1);
    found = transformations_from_frames(a, image(a, shift, true), TransformationGroup::Translations);
    ASSERT_EQ(found.size(), 1u);
    EXPECT_LT(matrix_error(found[0], shift), 1e-12);
    EXPECT_TRUE(transformations_from_frames(a, image(a, turn, false), TransformationGroup::Translations).empty());
}
