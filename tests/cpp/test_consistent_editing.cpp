// Consistent editing: a smooth bump pushed onto one sphere of a row of three is carried to
// the other two (by one translation, twice), and onto a mirrored pair's other side turned by
// the mirror; a hand-made detection result gives the symmetries, so the stage is tested on
// its own.  The expected positions are the bump itself, evaluated where each copy's vertex
// maps back: an analytic oracle.
#include "core/consistent_editing.h"
#include "core/icp.h"
#include "test_shapes.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace symmetry;
using namespace symmetry::testing;

namespace {

constexpr double kTolerance = 0.01;

// A bump of height h along `push` on the points within rho of `centre`, zero beyond.
Eigen::Vector3d bump(const Eigen::Vector3d& x, const Eigen::Vector3d& centre, const Eigen::Vector3d& push, double rho) {
    const double r2 = (x - centre).squaredNorm() / (rho * rho);
    return r2 < 1 ? Eigen::Vector3d(push * std::pow(1 - r2, 2)) : Eigen::Vector3d::Zero();
}

std::vector<int> rows(Eigen::Index first, Eigen::Index end) {
    std::vector<int> v;
    for (Eigen::Index i = first; i < end; ++i) v.push_back(int(i));
    return v;
}

DetectionResult result_of(Eigen::Index n, const Transformation& T, std::vector<int> source, std::vector<int> target) {
    DetectionResult r;
    DetectedSymmetry s;
    s.transform = T;
    s.source_vertices = std::move(source);
    s.target_vertices = std::move(target);
    r.symmetries.push_back(s);
    r.vertex_symmetry_id.assign(size_t(n), -1);
    r.vertex_deviation.assign(size_t(n), 0);
    return r;
}

}  // namespace

TEST(ConsistentEditing, ABumpOnTheFirstOfThreeSpheresReachesTheOtherTwoAlongTheChain) {
    const Shape one = sphere(1, 4);
    const Eigen::Vector3d step(3, 0, 0);
    Shape row = merged(merged(one, transformed(one, Eigen::Matrix3d::Identity(), step)),
                       transformed(one, Eigen::Matrix3d::Identity(), 2 * step));
    const Eigen::Index n = one.V.rows();
    Transformation T;
    T.translation = step;
    // T maps spheres 0-1 onto 1-2: sphere 2 is reached only through sphere 1, in a second pass.
    const DetectionResult detected = result_of(row.V.rows(), T, rows(0, 2 * n), rows(n, 3 * n));
    const Eigen::Vector3d centre(0, 0, 1), push(0.05, 0, 0.1);
    Eigen::MatrixX3d edited = row.V;
    for (Eigen::Index v = 0; v < n; ++v) edited.row(v) += bump(row.V.row(v).transpose(), centre, push, 0.5).transpose();

    const EditingResult done = carry_edit(row.V, row.F, edited, detected, kTolerance, EditingOptions());

    EXPECT_GT(done.edited_vertices, 20);
    EXPECT_EQ(done.passes, 2);
    double worst = 0;
    for (Eigen::Index v = 0; v < row.V.rows(); ++v) {
        const int copy = int(v / n);
        const Eigen::Vector3d expected =
            row.V.row(v).transpose() + bump(row.V.row(v).transpose() - copy * step, centre, push, 0.5);
        worst = std::max(worst, (done.V.row(v).transpose() - expected).norm());
        if (copy == 0) EXPECT_EQ(done.V.row(v), edited.row(v)) << v;  // the edited sphere is as the user left it
    }
    // Only the outermost ring of the bump, where it is below a few percent of its height, is missed.
    EXPECT_LT(worst, 0.01 * push.norm());
    EXPECT_GE(done.carried_vertices, 2 * done.edited_vertices - 2 * 40);
}

TEST(ConsistentEditing, AMirroredCopyReceivesTheEditMirrored) {
    const Shape one = sphere(1, 4);
    const Eigen::Vector3d offset(2, 0, 0);
    // Two spheres at x = -2 and x = +2, mirror images under x -> -x.
    const Shape pair = merged(transformed(one, Eigen::Matrix3d::Identity(), -offset),
                              transformed(one, Eigen::Matrix3d::Identity(), offset));
    const Eigen::Index n = one.V.rows();
    const DetectionResult detected =
        result_of(pair.V.rows(), pure_mirror(Eigen::Vector3d::UnitX(), 0), rows(0, n), rows(n, 2 * n));
    // The right sphere is edited (the target side): the edit goes back through T⁻¹.
    const Eigen::Vector3d centre = offset + Eigen::Vector3d(0.6, 0.8, 0), push(0.08, 0.02, 0);
    Eigen::MatrixX3d edited = pair.V;
    for (Eigen::Index v = n; v < 2 * n; ++v) edited.row(v) += bump(pair.V.row(v).transpose(), centre, push, 0.6).transpose();

    const EditingResult done = carry_edit(pair.V, pair.F, edited, detected, kTolerance, EditingOptions());

    const Eigen::Vector3d mirrored_centre(-centre.x(), centre.y(), centre.z()), mirrored_push(-push.x(), push.y(), push.z());
    double worst = 0;
    for (Eigen::Index v = 0; v < n; ++v) {
        const Eigen::Vector3d expected = pair.V.row(v).transpose() + bump(pair.V.row(v).transpose(), mirrored_centre,
                                                                           mirrored_push, 0.6);
        worst = std::max(worst, (done.V.row(v).transpose() - expected).norm());
    }
    EXPECT_GT(done.carried_vertices, 0);
    EXPECT_LT(worst, 0.01 * push.norm());
}

TEST(ConsistentEditing, RefusesNoEditAMeshOfAnotherSizeAndOptionsOutOfRange) {
    const Shape s = sphere(1, 2);
    const DetectionResult detected = result_of(s.V.rows(), Transformation(), {}, {});
    EXPECT_THROW(carry_edit(s.V, s.F, s.V, detected, kTolerance, EditingOptions()), InputError);
    Eigen::MatrixX3d fewer = s.V.topRows(s.V.rows() - 1);
    EXPECT_THROW(carry_edit(s.V, s.F, fewer, detected, kTolerance, EditingOptions()), InputError);
    EditingOptions bad;
    bad.max_passes = 0;
    Eigen::MatrixX3d moved = s.V;
    moved(0, 0) += 0.1;
    EXPECT_THROW(carry_edit(s.V, s.F, moved, detected, kTolerance, bad), InputError);
}
