// Stage 5 (§2 and §3): the transformation that maps one local frame onto another,
// and the transformation space Γ with the paper's weighted metric.
#pragma once

#include "signatures.h"

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

namespace symmetry {

/// The transformation groups the filter offers (the enum index is public API).
enum class TransformationGroup {
    Rigid = 0,        ///< rotations, reflections and translations (6-D)
    Similarity = 1,   ///< the 7-D group: rigid plus uniform scale
    Reflections = 2,  ///< mirror symmetries only
    Translations = 3  ///< pure translations only (repeated parts in the same orientation)
};

/// x -> scale * rotation * (reflection ? M x : x) + translation, where M = diag(-1, 1, 1)
/// is the paper's "arbitrary but fixed" mirror.  Splitting off M keeps rotation in SO(3)
/// for every element, so proper and improper transformations share one parameterisation.
struct Transformation {
    double scale = 1;
    Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
    Eigen::Vector3d translation = Eigen::Vector3d::Zero();
    bool reflection = false;

    static Eigen::Matrix3d mirror();                     ///< M
    Eigen::Matrix3d linear() const;                      ///< scale * rotation * M^reflection
    Eigen::Matrix4d matrix() const;                      ///< homogeneous 4x4
    Eigen::Vector3d apply(const Eigen::Vector3d& x) const;
    Eigen::Vector3d apply_to_normal(const Eigen::Vector3d& n) const;  ///< rotation * M^r * n
    Transformation inverse() const;
    Transformation operator*(const Transformation& rhs) const;  ///< this after rhs
    /// Decomposes a similarity matrix (uniform scale times an orthogonal matrix).
    static Transformation from_linear(const Eigen::Matrix3d& linear, const Eigen::Vector3d& translation);
};

/// Γ embedded in R^13 as (the translation of the bounding-box centre, log-scale, the 9
/// entries of the rotation), each weighted as in §3.
///
/// Where we depart from the paper, and why:
/// - rotations are stored as matrices, not Euler angles: Euler angles wrap at ±180°
///   and have gimbal lock, which split one symmetry into several clusters; the
///   Frobenius distance of matrices is the metric of the Appendix, ||R - R'||, and has
///   no seams.  A mean of rotation matrices is projected back onto SO(3).
/// - the translation is that of the bounding-box centre c, T(c) - c, rather than of the
///   origin, so it does not depend on where the model happens to sit.
/// - scale enters as its logarithm, so s and 1/s lie at the same distance from 1.
/// Weights follow §3: a rotation by 180° (Frobenius distance 2√2) and a scale factor of
/// 10 both weigh as much as a translation by half the bounding-box diagonal; lengths are
/// in units of the diagonal, so every distance in Γ is a fraction of the diagonal.
class TransformationSpace {
public:
    static constexpr int kDimension = 13;
    using Point = Eigen::Matrix<double, kDimension, 1>;

    TransformationSpace(const Eigen::Vector3d& center, double diagonal);

    Point coordinates(const Transformation& t) const;
    /// Inverse of coordinates(); the rotation block is projected onto SO(3) first.
    Transformation transformation(const Point& coordinates, bool reflection) const;
    /// The metric of §3; +infinity between a proper and an improper transformation.
    double distance(const Transformation& a, const Transformation& b) const;
    /// The rotation angle, in degrees, that is `distance` away from the identity in Γ: how
    /// far a cluster's mode may be turned from the truth, for a distance of the bandwidth.
    static double rotation_degrees(double distance);
    /// Projects the rotation block of `coordinates` onto SO(3) in place (used by mean shift).
    void project(Eigen::Ref<Eigen::VectorXd> coordinates) const;

    const Eigen::Vector3d& center() const { return center_; }
    double diagonal() const { return diagonal_; }

private:
    Eigen::Vector3d center_;
    double diagonal_;
};

/// Largest angle between frames, in radians, that the Reflections and Translations groups
/// accept when they reject pairs by the orientation of their frames (§2.2, Figure 3).
constexpr double kFrameAngleTolerance = 0.35;  // about 20 degrees

/// The candidate transformations that map the local frame of `a` onto that of `b` (§2),
/// each sending a.position exactly onto b.position.
/// - Rigid and Similarity: the principal directions are defined only up to sign, so the
///   paper's "smaller of the two rotations" is a guess that fails for half of the
///   180-degree symmetries; we emit both rotations instead and let the wrong one scatter
///   in Γ.  Each comes in a proper version and one through the fixed mirror: 4 candidates.
///   The scale of Similarity is the ratio of curvature magnitudes |κ(a)| / |κ(b)|, which
///   unlike the paper's mean of κ1 and κ2 ratios does not blow up where κ1 ≈ 0.
/// - Reflections: the one mirror through the bisector plane of the two positions, kept
///   only if it also maps the normal and principal directions (up to sign) within
///   kFrameAngleTolerance; otherwise none.
/// - Translations: b - a, kept only if the frames agree within kFrameAngleTolerance.
std::vector<Transformation> transformations_from_frames(const SurfaceSignature& a, const SurfaceSignature& b,
                                                        TransformationGroup group);

}  // namespace symmetry
