#include "rigid_segmentation.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace symmetry {
namespace {

// What segmentation needs of one pose: that the pipeline can work on it, and its size.
struct Pose {
    double diagonal = 0, area = 0;
    Eigen::Vector3d min = Eigen::Vector3d::Zero(), max = Eigen::Vector3d::Zero();  // bounding box
};

// Builds the pose as detection would (so unusable input is refused with the pose named,
// not as a fault of the joint mesh), and measures it.
Pose measure_pose(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, const char* which) {
    Mesh mesh;
    std::vector<int> vertex_of_input;
    try {
        build_mesh(V, F, mesh, vertex_of_input);
    } catch (const InputError& e) {
        throw InputError(std::string("The ") + which + " cannot be segmented. " + e.what());
    }
    Pose pose;
    pose.diagonal = mesh.bbox.Diag();
    pose.area = surface_area(mesh);
    for (int c = 0; c < 3; ++c) {
        pose.min[c] = mesh.bbox.min[c];
        pose.max[c] = mesh.bbox.max[c];
    }
    return pose;
}

// The two poses in one mesh, the second shifted along x past the first by the gap: one
// surface for sampling, signatures, clustering and verification, as in the paper, where a
// transformed patch of the first pose can only land on the second.
struct JointMesh {
    Eigen::MatrixX3d V;
    Eigen::MatrixX3i F;
    Eigen::Vector3d shift = Eigen::Vector3d::Zero();  // added to the second pose
    double boundary_x = 0;                            // the first pose lies below it, the second above
    double diagonal = 0;                              // of the bounding box of both
};

JointMesh side_by_side(const Eigen::MatrixX3d& V1, const Eigen::MatrixX3i& F1, const Pose& first,
                       const Eigen::MatrixX3d& V2, const Eigen::MatrixX3i& F2, const Pose& second, double gap) {
    JointMesh joint;
    joint.shift.x() = first.max.x() - second.min.x() + gap;
    joint.boundary_x = first.max.x() + gap / 2;
    joint.diagonal = (first.max.cwiseMax(second.max + joint.shift) - first.min.cwiseMin(second.min + joint.shift)).norm();
    joint.V.resize(V1.rows() + V2.rows(), 3);
    joint.V.topRows(V1.rows()) = V1;
    joint.V.bottomRows(V2.rows()) = V2.rowwise() + joint.shift.transpose();
    joint.F.resize(F1.rows() + F2.rows(), 3);
    joint.F.topRows(F1.rows()) = F1;
    joint.F.bottomRows(F2.rows()) = F2.array() + int(V1.rows());
    return joint;
}

// The user's options, in the pose's units, turned into the joint mesh's: lengths are
// fractions of the joint diagonal, areas of the joint area.  The group is the rigid
// motions (a part moves, it is neither mirrored nor scaled), pairs join the two poses, and
// there is no basis to reduce.
DetectionOptions joint_options(DetectionOptions options, const SegmentationOptions& segmentation,
                               double length_scale, double area_scale, double boundary_x) {
    options.group = TransformationGroup::Rigid;
    options.max_transformation_points = std::min(options.max_transformation_points,
                                                 segmentation.max_transformation_points);
    options.pairing.proper_only = true;
    options.pairing.first_pose_below_x = boundary_x;
    options.reduce_basis = false;
    options.curvature_radius *= length_scale;
    options.verification_tolerance *= length_scale;
    options.cluster_bandwidth *= length_scale;
    options.basis_tolerance *= length_scale;
    options.denoising.max_radius_for_noise *= length_scale;
    options.min_patch_area *= area_scale;
    options.debris_area_share *= area_scale;
    if (options.working.max_vertices > 0) options.working.max_vertices *= 2;
    return options;
}

// A detected symmetry is a part between the poses when it is a motion from the first
// pose (rows below first_rows) onto the second.
bool is_between_poses(const DetectedSymmetry& s, int first_rows) {
    if (s.continuous_kind != ContinuousKind::Discrete || s.transform.reflection) return false;
    if (s.source_vertices.empty() || s.target_vertices.empty()) return false;
    return s.source_vertices.back() < first_rows && s.target_vertices.front() >= first_rows;
}

// Labels every vertex with the most significant part that holds it (detection reports the
// largest patch first): a vertex near a joint can lie in two verified patches.  Parts left
// with no vertex are dropped.
void label_vertices(const DetectionResult& detected, const JointMesh& joint, int first_rows, int second_rows,
                    double length_scale, double area_scale, SegmentationResult& result) {
    result.first_segment_id.assign(size_t(first_rows), -1);
    result.second_segment_id.assign(size_t(second_rows), -1);
    Transformation unshift;
    unshift.translation = -joint.shift;
    for (const DetectedSymmetry& s : detected.symmetries) {
        if (!is_between_poses(s, first_rows)) continue;
        const int id = int(result.segments.size());
        RigidSegment segment;
        for (int v : s.source_vertices)
            if (result.first_segment_id[size_t(v)] < 0) {
                result.first_segment_id[size_t(v)] = id;
                segment.first_vertices.push_back(v);
            }
        for (int v : s.target_vertices)
            if (result.second_segment_id[size_t(v - first_rows)] < 0) {
                result.second_segment_id[size_t(v - first_rows)] = id;
                segment.second_vertices.push_back(v - first_rows);
            }
        if (segment.first_vertices.empty() || segment.second_vertices.empty()) {
            for (int v : segment.first_vertices) result.first_segment_id[size_t(v)] = -1;
            for (int v : segment.second_vertices) result.second_segment_id[size_t(v)] = -1;
            continue;
        }
        segment.transform = unshift * s.transform;
        segment.rms_error = s.rms_error / length_scale;
        segment.first_area = s.source_area / area_scale;
        segment.support = s.support;
        result.segments.push_back(std::move(segment));
    }
}

}  // namespace

void SegmentationOptions::validate() const {
    require_parameter(std::isfinite(gap_in_diagonals) && gap_in_diagonals > 0 && gap_in_diagonals <= 100,
                      "gap_in_diagonals", gap_in_diagonals, "above 0 and at most 100");
    require_parameter(max_transformation_points >= 1000, "max_transformation_points", max_transformation_points,
                      "at least 1000");
}

SegmentationResult segment_rigid_parts(const Eigen::MatrixX3d& V1, const Eigen::MatrixX3i& F1,
                                       const Eigen::MatrixX3d& V2, const Eigen::MatrixX3i& F2,
                                       const DetectionOptions& options, const SegmentationOptions& segmentation,
                                       const Progress& progress) {
    options.validate();
    segmentation.validate();
    const Pose first = measure_pose(V1, F1, "first mesh (first_mesh)");
    const Pose second = measure_pose(V2, F2, "second mesh (second_mesh)");
    const double gap = segmentation.gap_in_diagonals * std::max(first.diagonal, second.diagonal);
    const JointMesh joint = side_by_side(V1, F1, first, V2, F2, second, gap);
    const double length_scale = first.diagonal / joint.diagonal;
    const double area_scale = first.area / (first.area + second.area);

    SegmentationResult result;
    result.detection = detect_partial_symmetries(
        joint.V, joint.F, joint_options(options, segmentation, length_scale, area_scale, joint.boundary_x), progress);
    label_vertices(result.detection, joint, int(V1.rows()), int(V2.rows()), length_scale, area_scale, result);
    return result;
}

}  // namespace symmetry
