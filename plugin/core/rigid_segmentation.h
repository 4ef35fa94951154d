// A use of the pipeline (§5, the paper's Figure 8): the rigid parts of a shape seen in two
// poses.  Samples of the first pose are paired only with samples of the second ("the
// mapping to transformation space is thus restricted to only include pairs that contain
// one sample from either pose"); every cluster that verification confirms is a part that
// moved rigidly from one pose to the other, and labels the vertices of both poses.
#pragma once

#include "detection.h"

#include <Eigen/Core>
#include <vector>

namespace symmetry {

struct SegmentationOptions {
    /// The poses are analysed side by side in one mesh, this many pose diagonals apart
    /// (the larger pose's diagonal).  Dimensionless.  Far enough that no closest point of a
    /// transformed patch of one pose falls on the other pose (tolerances are a few
    /// hundredths of a diagonal); the results do not depend on it beyond that.
    double gap_in_diagonals = 0.5;
    /// Points in Γ clustering may be given at most (DetectionOptions::max_transformation_points,
    /// which an automatic n' respects): half detection's budget.  Between two poses every vote
    /// is a motion, so Γ has one sheet where detection's votes split between two (the
    /// rotations and the mirrors), and mean shift's work grows faster than the points of a
    /// sheet.  The same points per sheet as detection.
    int max_transformation_points = 125000;

    /// Throws InputError, with a sentence naming the parameter, for values outside their range.
    void validate() const;
};

/// One part that moved rigidly between the poses.
struct RigidSegment {
    Transformation transform;          ///< maps the part in the first pose onto the second pose
    std::vector<int> first_vertices;   ///< rows of the first pose's V labelled with this part, increasing
    std::vector<int> second_vertices;  ///< rows of the second pose's V, increasing
    double rms_error = 0;              ///< RMS distance of the mapped part to the second pose, fraction of the first's diagonal
    double first_area = 0;             ///< the verified patch on the first pose, fraction of its area
    int support = 0;                   ///< pairs in the cluster (§3.1)
};

struct SegmentationResult {
    std::vector<RigidSegment> segments;  ///< largest first
    std::vector<int> first_segment_id;   ///< per vertex of the first pose: its segment, -1 where none holds
    std::vector<int> second_segment_id;  ///< per vertex of the second pose
    /// The detection run on both poses side by side: samples, pairs, clusters, seconds.
    /// Its rows and fractions are those of that joint mesh.
    DetectionResult detection;
};

/// The rigid parts between the pose (V1, F1) and the pose (V2, F2).  `options` are the
/// detection's, with lengths as fractions of the first pose's diagonal and areas as
/// fractions of its area; the transformation group is the rigid motions
/// whatever it says, and basis reduction is not run (a part's motion is no word in others).
/// Throws InputError, naming the pose, for unusable input; the input is never modified.
SegmentationResult segment_rigid_parts(const Eigen::MatrixX3d& V1, const Eigen::MatrixX3i& F1,
                                       const Eigen::MatrixX3d& V2, const Eigen::MatrixX3i& F2,
                                       const DetectionOptions& options,
                                       const SegmentationOptions& segmentation = {},
                                       const Progress& progress = {});

}  // namespace symmetry
