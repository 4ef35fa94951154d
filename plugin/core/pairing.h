// Stage 4 (§2.2): pairs of samples whose signatures agree, found by range queries in
// a kd-tree over the signature space Ω.
#pragma once

#include "signatures.h"
#include "transformation_space.h"

#include <optional>
#include <random>
#include <vector>

namespace symmetry {

/// The signature σ of a sample in Ω (§2.2), for the given group:
/// - Similarity: σ7, a scale-invariant function of κ1/κ2.  We use the shape index
///   (2/π) atan((κ2+κ1)/(κ2−κ1)), a monotone remapping of the ratio κ1/κ2 onto [-1, 1]
///   that stays finite where κ2 → 0 (the plain ratio does not).
/// - every other group: σ6 = (κ1, κ2) * r, the principal curvatures made dimensionless by
///   the curvature radius r, so the tolerance does not depend on the model's units.
Eigen::VectorXd signature(const SurfaceSignature& s, TransformationGroup group, double radius);

struct SignaturePair {
    int first;   ///< index in the pruned sample set P of the sample drawn into P'
    int second;  ///< index in P of its partner
};

struct PairingOptions {
    /// On a surface whose curvature hardly varies (a sphere with bumps, a long tube) almost
    /// every sample falls within the tolerance of every other, and the pairs grow as n'·n.
    /// Keeping only this many partners per sample bounds the work of clustering at n'·k
    /// points (the Appendix's μ, the average number of partners, is 10 in the paper's
    /// example).  They are the nearest in the two-scale signature (ranking_signature), so
    /// where the range query in Ω ties, the partners whose shape also agrees over a twice
    /// larger ball are kept: a true partner does, a chance one seldom.
    int max_partners = 32;
    /// Pairing between two poses (rigid_segmentation.h, the paper's Figure 8): when set,
    /// the mesh holds two poses side by side, the first where x is below this value (absolute
    /// units).  P' is then drawn from the first pose only and its partners come from the
    /// second only: "pairs that contain one sample from either pose".
    std::optional<double> first_pose_below_x;
    /// Vote only for rotations and translations, not for their mirrored counterparts: between
    /// two poses a part moves, it is not mirrored.
    bool proper_only = false;
};

/// Whether `position` is on the side of P' (every sample, unless options pair two poses).
bool may_be_drawn(const Eigen::Vector3d& position, const PairingOptions& options);
/// Whether `position` may be a partner (every sample, unless options pair two poses).
bool may_be_partner(const Eigen::Vector3d& position, const PairingOptions& options);

/// The signature partners are ranked by: σ at the radius r and at 2r, each made
/// dimensionless by its own radius (for Similarity: the shape index at both radii).
Eigen::VectorXd ranking_signature(const SurfaceSignature& s, TransformationGroup group, double radius);

/// For `subset_size` samples drawn at random from P (the paper's P'), the partners in P
/// within `tolerance` of its signature, at most options.max_partners of them (the nearest
/// by ranking_signature),
/// excluding the sample itself and partners closer than `min_distance` in space (such
/// pairs see the same patch and vote for near-identity transformations that carry no
/// symmetry).  Between two poses (options.first_pose_below_x) P' is drawn from the first
/// pose and the partners from the second.  Deterministic for a given rng state.
std::vector<SignaturePair> pair_in_signature_space(const std::vector<SurfaceSignature>& samples,
                                                   TransformationGroup group, double radius, double tolerance,
                                                   int subset_size, double min_distance, std::mt19937_64& rng,
                                                   const PairingOptions& options = {});

/// The same for the samples `drawn` (indices into `samples`, increasing) instead of a random
/// subset: each is paired with its partners in P.
std::vector<SignaturePair> pair_drawn_samples(const std::vector<SurfaceSignature>& samples, TransformationGroup group,
                                              double radius, double tolerance, const std::vector<int>& drawn,
                                              double min_distance, const PairingOptions& options = {});

}  // namespace symmetry
