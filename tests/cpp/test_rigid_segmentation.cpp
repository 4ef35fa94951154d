// Rigid segments between two poses (the paper's Figure 8): a shape of two rigid parts, a
// swollen torus and an ellipsoid, posed twice with known motions per part.  Every vertex of
// both poses must be labelled with its own part, and each segment's transform must carry
// its part of the first pose onto the second pose (measured against the planted surface by
// brute force).
#include "core/rigid_segmentation.h"
#include "test_shapes.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <map>

using namespace symmetry;
using namespace symmetry::testing;

namespace {

struct Part {
    Shape first, second;  // the part in either pose
    Transformation motion;
};

struct TwoPoses {
    Shape first, second;
    std::vector<int> first_part, second_part;  // per vertex, the part it belongs to
    std::vector<Part> parts;
};

Transformation motion(double angle, const Eigen::Vector3d& axis, const Eigen::Vector3d& t) {
    Transformation T;
    T.rotation = Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
    T.translation = t;
    return T;
}

// Appends `part` to the pose, labelling its vertices.
void add(Shape& pose, std::vector<int>& labels, const Shape& part, int id) {
    pose = pose.V.rows() == 0 ? part : merged(pose, part);
    labels.insert(labels.end(), size_t(part.V.rows()), id);
}

TwoPoses torus_and_ellipsoid() {
    const Shape torus = deformed_torus(2.0, 1.0, 160, 48, [](double u) { return 0.6 + 0.25 * std::cos(u); });
    const Shape torus_again = deformed_torus(2.0, 1.0, 149, 43, [](double u) { return 0.6 + 0.25 * std::cos(u); });
    const Eigen::Matrix3d stretch = Eigen::Vector3d(2.2, 1.2, 0.7).asDiagonal();
    const Shape ellipsoid = transformed(sphere(1, 4), stretch, Eigen::Vector3d(5.5, 0, 0));
    TwoPoses poses;
    poses.parts = {{torus, {}, motion(0.9, {0, 1, 1}, {0.5, -1, 2})},
                   {ellipsoid, {}, motion(2.1, {1, -1, 0.3}, {-2, 3, 1})}};
    poses.parts[0].second = transformed(torus_again, poses.parts[0].motion.linear(), poses.parts[0].motion.translation);
    poses.parts[1].second = transformed(ellipsoid, poses.parts[1].motion.linear(), poses.parts[1].motion.translation);
    for (int id = 0; id < 2; ++id) {
        add(poses.first, poses.first_part, poses.parts[size_t(id)].first, id);
        add(poses.second, poses.second_part, poses.parts[size_t(id)].second, id);
    }
    return poses;
}

// The part most of a segment's vertices belong to.
int majority(const std::vector<int>& vertices, const std::vector<int>& part_of) {
    std::map<int, int> votes;
    for (int v : vertices) ++votes[part_of[size_t(v)]];
    int best = -1, most = 0;
    for (const auto& [part, count] : votes)
        if (count > most) best = part, most = count;
    return best;
}

double diagonal_of(const Eigen::MatrixX3d& V) { return (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm(); }

// Largest distance from T(p), p every 7th of `points`, to the nearest vertex of `target`.
double worst_landing(const Transformation& T, const Eigen::MatrixX3d& points, const Eigen::MatrixX3d& target) {
    double worst = 0;
    for (Eigen::Index i = 0; i < points.rows(); i += 7) {
        const Eigen::RowVector3d x = T.apply(points.row(i).transpose()).transpose();
        worst = std::max(worst, std::sqrt((target.rowwise() - x).rowwise().squaredNorm().minCoeff()));
    }
    return worst;
}

}  // namespace

TEST(RigidSegmentation, EveryVertexOfBothPosesIsLabelledWithItsOwnPart) {
    const TwoPoses poses = torus_and_ellipsoid();
    DetectionOptions options;
    options.sample_count = 3000;  // the paper's Figure 8 sampled 1000 points a pose
    const SegmentationResult result =
        segment_rigid_parts(poses.first.V, poses.first.F, poses.second.V, poses.second.F, options);
    ASSERT_GE(result.segments.size(), 2u);
    ASSERT_EQ(result.first_segment_id.size(), size_t(poses.first.V.rows()));
    ASSERT_EQ(result.second_segment_id.size(), size_t(poses.second.V.rows()));

    // Each segment is the part most of its vertices belong to; both parts have a segment.
    std::vector<int> part_of_segment;
    std::vector<bool> part_found(poses.parts.size(), false);
    for (const RigidSegment& s : result.segments) {
        const int part = majority(s.first_vertices, poses.first_part);
        EXPECT_EQ(majority(s.second_vertices, poses.second_part), part);
        part_of_segment.push_back(part);
        part_found[size_t(part)] = true;
    }
    for (size_t p = 0; p < part_found.size(); ++p) EXPECT_TRUE(part_found[p]) << "part " << p;

    // Nearly every vertex is labelled, and with its own part.
    for (const auto* labels : {&result.first_segment_id, &result.second_segment_id}) {
        const std::vector<int>& truth = labels == &result.first_segment_id ? poses.first_part : poses.second_part;
        int right = 0;
        for (size_t v = 0; v < labels->size(); ++v)
            if ((*labels)[v] >= 0 && part_of_segment[size_t((*labels)[v])] == truth[v]) ++right;
        EXPECT_GT(double(right) / double(labels->size()), 0.95);
    }

    // A segment's transform carries its part onto the part's second pose (the ellipsoid may
    // land turned by one of its own symmetries: only the landing is checked).
    const double diagonal = diagonal_of(poses.first.V);
    for (size_t k = 0; k < result.segments.size(); ++k) {
        const Part& part = poses.parts[size_t(part_of_segment[k])];
        EXPECT_LT(worst_landing(result.segments[k].transform, part.first.V, part.second.V), 0.01 * diagonal)
            << "segment " << k;
        EXPECT_LT(result.segments[k].rms_error, 0.002);
    }
}

TEST(RigidSegmentation, RefusesAnUnusablePoseNamingIt) {
    const Shape torus = sphere(1, 3);
    Shape cloud = torus;
    cloud.F.resize(0, 3);
    try {
        segment_rigid_parts(torus.V, torus.F, cloud.V, cloud.F, DetectionOptions());
        FAIL() << "a point cloud as second pose was accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("second mesh (second_mesh)"), std::string::npos) << e.what();
    }
    SegmentationOptions absurd;
    absurd.gap_in_diagonals = -1;
    EXPECT_THROW(segment_rigid_parts(torus.V, torus.F, torus.V, torus.F, DetectionOptions(), absurd), InputError);
}
