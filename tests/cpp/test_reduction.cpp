// Symmetry-based reduction on shapes whose copies are known by construction, with a
// hand-made detection result, so the stage is tested on its own: a row of four boxes
// (one box and three translations rebuild it), a 6-fold torus (one sixth and five turns),
// a mirrored sphere (half of it), and a shape with no symmetry (nothing removed).  The
// reconstruction is checked against the input by brute force over its vertices and face
// centres, not by the stage's own error.
#include "core/icp.h"
#include "core/reduction.h"
#include "test_shapes.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

using namespace symmetry;
using namespace symmetry::testing;

namespace {

constexpr double kTolerance = 0.01;  // the verification tolerance, fraction of the diagonal

DetectedSymmetry symmetry_of(const Transformation& t, std::vector<int> source, std::vector<int> target) {
    DetectedSymmetry s;
    s.transform = t;
    s.source_vertices = std::move(source);
    s.target_vertices = std::move(target);
    return s;
}

DetectionResult result_of(Eigen::Index rows, std::vector<DetectedSymmetry> symmetries) {
    DetectionResult r;
    r.symmetries = std::move(symmetries);
    r.vertex_symmetry_id.assign(size_t(rows), -1);
    r.vertex_deviation.assign(size_t(rows), 0);
    return r;
}

std::vector<int> all_rows(Eigen::Index rows) {
    std::vector<int> v(static_cast<size_t>(rows));
    for (size_t i = 0; i < v.size(); ++i) v[i] = int(i);
    return v;
}

double diagonal(const Eigen::MatrixX3d& V) {
    return (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm();
}

// Brute force: largest distance from any vertex or face centre of (A, FA) to the nearest
// vertex or face centre of (B, FB), as a fraction of `diag`.  Point to point, so it bounds
// the surface distance from above by about half an edge; the shapes here have short edges.
double one_sided(const Eigen::MatrixX3d& A, const Eigen::MatrixX3i& FA, const Eigen::MatrixX3d& B,
                 const Eigen::MatrixX3i& FB, double diag) {
    auto points = [](const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F) {
        Eigen::MatrixX3d P(V.rows() + F.rows(), 3);
        P.topRows(V.rows()) = V;
        for (Eigen::Index f = 0; f < F.rows(); ++f)
            P.row(V.rows() + f) = (V.row(F(f, 0)) + V.row(F(f, 1)) + V.row(F(f, 2))) / 3;
        return P;
    };
    const Eigen::MatrixX3d PA = points(A, FA), PB = points(B, FB);
    double worst = 0;
    for (Eigen::Index i = 0; i < PA.rows(); ++i)
        worst = std::max(worst, std::sqrt((PB.rowwise() - PA.row(i)).rowwise().squaredNorm().minCoeff()));
    return worst / diag;
}

double two_sided(const Shape& input, const ReductionResult& reduced) {
    Eigen::MatrixX3d RV;
    Eigen::MatrixX3i RF;
    reconstruct(input.V, input.F, reduced, RV, RF);
    const double diag = diagonal(input.V);
    return std::max(one_sided(input.V, input.F, RV, RF, diag), one_sided(RV, RF, input.V, input.F, diag));
}

Transformation rotation_about_z(double angle) {
    Transformation t;
    t.rotation = Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    return t;
}

}  // namespace

TEST(Reduction, ARowOfFourBoxesKeepsOneAndRebuildsTheOthersByTranslation) {
    const Shape one = box(0.5, 0.5, 0.5, 3);
    const Eigen::Vector3d step(2, 0, 0);
    Shape row = one;
    for (int i = 1; i < 4; ++i) row = merged(row, transformed(one, Eigen::Matrix3d::Identity(), i * step));
    const Eigen::Index n = one.V.rows();
    // T maps boxes 0-2 onto boxes 1-3, as detection reports a row.
    Transformation T;
    T.translation = step;
    std::vector<int> source, target;
    for (Eigen::Index v = 0; v < 3 * n; ++v) source.push_back(int(v)), target.push_back(int(v + n));
    const DetectionResult detected = result_of(row.V.rows(), {symmetry_of(T, source, target)});

    const ReductionResult reduced = reduce_by_symmetry(row.V, row.F, detected, kTolerance, ReductionOptions());

    EXPECT_EQ(reduced.kept_faces.size(), size_t(one.F.rows()));
    for (int f : reduced.kept_faces) EXPECT_LT(f, one.F.rows());  // the first box is the one kept
    ASSERT_EQ(reduced.instances.size(), 3u);
    for (const ReducedInstance& instance : reduced.instances) {
        const double copies = double(instance.word.size());
        EXPECT_NEAR((instance.transform.translation - copies * step).norm(), 0, 1e-12);
        EXPECT_EQ(instance.removed_faces, one.F.rows());
    }
    EXPECT_NEAR(reduced.size_ratio, 0.25, 1e-12);
    EXPECT_LT(reduced.reconstruction_error, 1e-9);
    EXPECT_LT(two_sided(row, reduced), 1e-9);
}

TEST(Reduction, ASixFoldTorusIsOneSixthAndFiveTurnsOfOneRotation) {
    const double pi = std::acos(-1.0);
    const Shape torus6 = deformed_torus(1, 0.3, 72, 16, [](double u) { return 1 + 0.25 * std::cos(6 * u); });
    const std::vector<int> rows = all_rows(torus6.V.rows());
    const DetectionResult detected = result_of(torus6.V.rows(), {symmetry_of(rotation_about_z(pi / 3), rows, rows)});

    const ReductionResult reduced = reduce_by_symmetry(torus6.V, torus6.F, detected, kTolerance, ReductionOptions());

    // One sixth of the faces, and at most one ring of faces more where the orbit closes.
    const double sixth = double(torus6.F.rows()) / 6;
    EXPECT_GE(double(reduced.kept_faces.size()), sixth);
    EXPECT_LE(double(reduced.kept_faces.size()), sixth + 2 * 16);
    size_t longest = 0;
    for (const ReducedInstance& instance : reduced.instances) longest = std::max(longest, instance.word.size());
    EXPECT_EQ(longest, 5u);
    EXPECT_LT(two_sided(torus6, reduced), 1e-9);
    EXPECT_LT(reduced.reconstruction_error, 1e-9);
}

TEST(Reduction, AMirroredSphereKeepsAboutHalfAndTheRebuiltHalfFacesOutward) {
    const Shape s = sphere(1, 4);
    const std::vector<int> rows = all_rows(s.V.rows());
    const DetectionResult detected =
        result_of(s.V.rows(), {symmetry_of(pure_mirror(Eigen::Vector3d::UnitX(), 0), rows, rows)});

    const ReductionResult reduced = reduce_by_symmetry(s.V, s.F, detected, kTolerance, ReductionOptions());

    EXPECT_GT(reduced.size_ratio, 0.45);
    EXPECT_LT(reduced.size_ratio, 0.6);
    EXPECT_LT(two_sided(s, reduced), kTolerance);
    EXPECT_LT(reduced.reconstruction_error, kTolerance);
    // The mirrored copy is turned right side out: every rebuilt face points away from the centre.
    Eigen::MatrixX3d RV;
    Eigen::MatrixX3i RF;
    reconstruct(s.V, s.F, reduced, RV, RF);
    for (Eigen::Index f = 0; f < RF.rows(); ++f) {
        const Eigen::Vector3d a = RV.row(RF(f, 0)), b = RV.row(RF(f, 1)), c = RV.row(RF(f, 2));
        EXPECT_GT((b - a).cross(c - a).dot(a + b + c), 0) << "face " << f;
    }
}

TEST(Reduction, AShapeWithoutSymmetryOrWithOnlyAContinuousFamilyKeepsEveryFace) {
    const Shape s = sphere(1, 3);
    EXPECT_EQ(reduce_by_symmetry(s.V, s.F, result_of(s.V.rows(), {}), kTolerance, ReductionOptions()).kept_faces.size(),
              size_t(s.F.rows()));
    // A sphere's spherical family: no finite set of copies, nothing removed.
    DetectedSymmetry family = symmetry_of(rotation_about_z(1), all_rows(s.V.rows()), all_rows(s.V.rows()));
    family.continuous_kind = ContinuousKind::Spherical;
    const ReductionResult reduced =
        reduce_by_symmetry(s.V, s.F, result_of(s.V.rows(), {family}), kTolerance, ReductionOptions());
    EXPECT_EQ(reduced.kept_faces.size(), size_t(s.F.rows()));
    EXPECT_TRUE(reduced.instances.empty());
    EXPECT_EQ(reduced.size_ratio, 1);
}

TEST(Reduction, ATransformationThatDoesNotHoldRemovesNothing) {
    // A sphere claimed to be a copy of itself moved by half its size: nothing lands.
    const Shape s = sphere(1, 3);
    Transformation shift;
    shift.translation = Eigen::Vector3d(0.7, 0, 0);
    const std::vector<int> rows = all_rows(s.V.rows());
    const ReductionResult reduced =
        reduce_by_symmetry(s.V, s.F, result_of(s.V.rows(), {symmetry_of(shift, rows, rows)}), kTolerance, ReductionOptions());
    // Only where the shifted sphere crosses the sphere could a face land; none may be removed
    // unless its reconstruction is within the tolerance.
    EXPECT_LT(two_sided(s, reduced), 2 * kTolerance);
}

TEST(Reduction, RefusesOptionsOutOfRangeAndAResultOfAnotherMesh) {
    const Shape s = sphere(1, 2);
    ReductionOptions bad;
    bad.max_distance_in_tolerances = 0;
    EXPECT_THROW(reduce_by_symmetry(s.V, s.F, result_of(s.V.rows(), {}), kTolerance, bad), InputError);
    bad = ReductionOptions();
    bad.max_chain_length = 0;
    EXPECT_THROW(reduce_by_symmetry(s.V, s.F, result_of(s.V.rows(), {}), kTolerance, bad), InputError);
    EXPECT_THROW(reduce_by_symmetry(s.V, s.F, result_of(s.V.rows() + 1, {}), kTolerance, ReductionOptions()),
                 InputError);
}
