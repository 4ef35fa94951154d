// The whole pipeline of Figure 2, from a triangle mesh to verified partial symmetries.
// This is the one entry point the hosts call (MeshLab plugins, Python); it knows
// nothing of Qt or MeshLab.
#pragma once

#include "basis_reduction.h"
#include "continuous_families.h"
#include "curvature_agreement.h"
#include "denoising.h"
#include "mesh.h"
#include "pairing.h"
#include "point_cloud.h"
#include "sample_size.h"
#include "transformation_space.h"
#include "verification.h"
#include "working_mesh.h"

#include <Eigen/Core>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

namespace symmetry {

/// Throws InputError "The parameter <name> is <value>, but it must be <range>." unless ok:
/// how every options struct's validate() says what is wrong.
template <class T>
void require_parameter(bool ok, const char* name, T value, const char* range) {
    if (ok) return;
    std::ostringstream s;
    s << "The parameter " << name << " is " << value << ", but it must be " << range << ".";
    throw InputError(s.str());
}

/// Every parameter of the filter, in the core's units.  Lengths are fractions of the
/// bounding-box diagonal, areas fractions of the total surface area.
struct DetectionOptions {
    TransformationGroup group = TransformationGroup::Rigid;
    int sample_count = 10000;           ///< |initial samples| before pruning (§5)
    /// |P'|, samples paired against all of P (§2.2); 0 chooses it by the Appendix's bound
    /// (sample_size.h) for patches of min_patch_area, within max_transformation_points.
    int pair_sample_count = 0;
    /// Points in Γ that clustering may be given at most (its work grows with them): an
    /// automatic n' is lowered to keep μ n' below this.
    int max_transformation_points = 250000;
    double curvature_radius = 0.01;     ///< r of the curvature ball (§2), fraction of the diagonal
    /// r is at least this many median edge lengths, whatever curvature_radius says.
    double min_radius_in_edges = 1.5;
    /// A mesh so coarse that r would grow past this many times curvature_radius to hold
    /// min_radius_in_edges of its edges (a CAD export's long thin triangles) is analysed on a
    /// copy whose long edges are split (working_mesh.h refined_copy) instead, if it is faceted
    /// as CAD parts are (WorkingMeshOptions::max_smooth_edge_share); 0: never.
    double max_radius_growth = 2.0;
    /// Components that together hold at most this share of the area, smallest first, each
    /// smaller than the great disc of the ball curvature_radius asks for, are debris
    /// (scanner specks, stray triangles; DebrisRule in region_growing.h): their edges do not
    /// count in the median edge length, and verification sweeps none of them into a patch.
    /// Fraction of the total area: half the default min_patch_area, so a part as small as
    /// the smallest patch reported still counts.
    double debris_area_share = 0.005;
    double umbilic_ratio = 0.75;        ///< γ of §2.1
    /// A sample is flat, and pruned with the umbilics, when its largest curvature bends the
    /// surface by less than flatness · r / 2 across the ball of radius r (0.05: 2.5 % of r):
    /// there both curvatures are at the level of tessellation noise, and so are the
    /// directions.  The same bound tells a cylinder's vanishing curvature.  Dimensionless.
    double flatness = 0.05;
    double signature_tolerance = 0.05;  ///< range-query radius in Ω (§2.2), dimensionless
    double cluster_bandwidth = 0.04;    ///< h of mean shift (§3.1), fraction of the diagonal in Γ's metric
    int min_cluster_support = 6;        ///< smallest cluster height worth verifying
    /// Share of the clusters verified that may go first to those whose votes lie outside
    /// every patch found so far (a small part beside a large mirror-symmetric body) and away
    /// from the votes of every cluster verified before, in (0, 1]; the rest follow in vote
    /// order.
    double first_pass_share = 0.5;
    /// "Away from the votes" of a cluster verified: farther than this many curvature radii
    /// (r, of the ball) over the mesh from both ends of most of the candidate's votes.  A
    /// smooth body offers dozens of clusters of chance near-mirrors, one region after
    /// another, above the cluster of a small part beside it (a bunny beside a part of 2 % of
    /// its area, 75,000 vertices analysed at 50,000: the part's cluster came 81st by height,
    /// after the 60 that are verified; passing over the regions tried, the first pass
    /// reached it 22nd at 2 radii, 14th at 3, 10th at 5).
    double tried_region_radius = 3;
    /// A candidate whose estimate of T, refitted while its patch grows, comes within the
    /// bandwidth of a transformation that acceptance rejected before, with at least this
    /// share of its patch's vertices inside the patch rejected, stops there: it would regrow
    /// that patch under that T and be rejected again.  On a scan whose pose is nearly
    /// mirror-symmetric, seven of the sixty clusters verified converged onto one rejected
    /// near-mirror, each regrowing 25,000-33,000 of 50,000 vertices.  A share, in (0, 1].
    double rejected_patch_share = 0.8;
    /// When the two passes found something and the samples away from what they verified are
    /// at most `pair_away_share` of P, a last pass verifies at most `clusters_away` more
    /// clusters, of the votes of those samples, every one of them paired (not a share n'/n of
    /// them): the cluster of a small part beside a large body may lie below the modes kept,
    /// or under the minimum support (pass_over_votes_away in detection.cpp).  A number of
    /// clusters; a share of P.
    int clusters_away = 10;
    double pair_away_share = 0.25;
    /// Candidates verified ahead of their turn, per thread (hand_out_ahead in
    /// detection.cpp).  The results do not depend on it; the time does: a candidate that an
    /// earlier one explains was verified for nothing, and too few ahead leave a thread idle.
    /// Measured on the facade of 120 windows, whole processes paired with farm-bench: 1 per
    /// thread took 1.08 times as long as 2 (runs 0.86-1.22).
    int candidates_per_thread = 2;
    double verification_tolerance = 0.01;  ///< distance accepted in region growing (§4), fraction of the diagonal
    double min_patch_area = 0.01;       ///< smallest reported patch, fraction of the total area
    /// At most this many discrete symmetries are reported, and at most this many continuous
    /// families besides them (a family is one report for a continuum and takes no discrete place).
    int max_symmetries = 20;
    bool refine_with_icp = true;        ///< ICP refinement during region growing (§4)
    bool reduce_basis = true;           ///< Algorithm 1 (§4.1)
    int basis_loop_length = 3;          ///< η of Algorithm 1
    double basis_tolerance = 0.02;      ///< δ of Algorithm 1, fraction of the diagonal in Γ's metric
    unsigned random_seed = 0;           ///< the whole run is a function of this seed
    /// An output switch, not a tunable: keep Γ in DetectionResult::transformation_space
    /// (13 numbers per point of Γ; pictures of §3, the paper's Figure 7(b)).
    bool keep_transformation_space = false;

    // Tunables of the stages, with their units in their own structs.
    WorkingMeshOptions working;               ///< the resolution large inputs are analysed at
    DenoisingOptions denoising;               ///< presmoothing of noisy meshes (§5 limitations)
    SampleSizeOptions sample_size;            ///< the Appendix's bound for an automatic n'
    PairingOptions pairing;                   ///< partners per sample (§2.2)
    /// Region growing, ICP and acceptance (§4).  Its tolerance, min_patch_area,
    /// min_displacement, refine_with_icp and group are set from the fields above.
    VerificationOptions verification;
    CurvatureAgreementOptions agreement;      ///< second-order verification (beyond §4)
    ContinuousFamilyOptions continuous;       ///< continuous families (beyond the paper)
    PointCloudOptions point_cloud;            ///< normals, areas and neighbours of a point cloud

    /// Throws InputError, with a sentence naming the parameter, for values outside their range.
    void validate() const;
};

struct DetectedSymmetry {
    /// Maps the source patch onto the target patch.  For a continuous family: the member
    /// that verification grew (one rotation of a surface of revolution, say).
    Transformation transform;
    ContinuousKind continuous_kind = ContinuousKind::Discrete;
    /// Continuous families only (see ContinuousFamily): a point on the axis or plane, or
    /// the centre; the unit axis, normal or direction (zero for a sphere); the pitch.
    Eigen::Vector3d axis_point = Eigen::Vector3d::Zero();
    Eigen::Vector3d axis_direction = Eigen::Vector3d::Zero();
    double pitch = 0;                     ///< helical: advance per turn, fraction of the diagonal
    std::vector<int> source_vertices;     ///< rows of the input V, increasing
    std::vector<int> target_vertices;     ///< rows of the input V, increasing
    double rms_error = 0;                 ///< RMS deviation from perfect symmetry, fraction of the diagonal
    double max_error = 0;                 ///< largest deviation, fraction of the diagonal
    double systematic_error = 0;          ///< RMS of the locally averaged deviation (see VerificationOptions)
    double source_area = 0;               ///< fraction of the total surface area
    int support = 0;                      ///< pairs in the cluster (§3.1)
    bool is_generator = true;             ///< part of the reduced basis (§4.1); false for a family
    Word word;                            ///< this transformation in the generators; empty for a family
};

/// Γ as the detector saw it (§3, the paper's Figure 7(b)), kept on request
/// (DetectionOptions::keep_transformation_space).  Points are rows of their
/// TransformationSpace::coordinates, in which Euclidean distance is Γ's metric (fractions of
/// the diagonal); proper and improper transformations are its two sheets (the coordinates
/// hold the rotation, not the mirror, so the sheet is given beside them).
struct TransformationSpaceSnapshot {
    Eigen::MatrixXd points;         ///< one row per point of Γ (a pair's transformation)
    std::vector<char> improper;     ///< per point: a reflection, rotoreflection or glide
    Eigen::MatrixXd modes;          ///< the clusters of the first mean shift, most votes first
    std::vector<int> mode_heights;  ///< ...their votes
    std::vector<char> mode_improper;  ///< ...and their sheet
    Eigen::MatrixXd symmetries;     ///< the reported symmetries, in result order
};

struct DetectionResult {
    std::vector<DetectedSymmetry> symmetries;  ///< most significant first
    int generator_count = 0;
    /// Per input vertex: signed deviation of its image under the most significant
    /// symmetry it belongs to, as a fraction of the diagonal (Figure 1); 0 elsewhere.
    std::vector<double> vertex_deviation;
    /// Per input vertex: index of that symmetry, -1 where no symmetry holds.
    std::vector<int> vertex_symmetry_id;
    // Work done, for the log and for benchmarks.
    int samples = 0, pruned_samples = 0, pairs = 0, transformation_points = 0, clusters = 0;
    int verified_candidates = 0;   ///< clusters that went through region growing
    int skipped_members = 0;       ///< clusters skipped as members of a continuous family found before
    int working_vertices = 0;      ///< vertices of the simplified or refined copy analysed; 0 when the input itself was
    bool working_refined = false;  ///< that copy is the input refined (a coarse mesh), not simplified
    bool point_cloud = false;      ///< the input was a point cloud (detect_partial_symmetries_in_point_cloud)
    bool normals_estimated = false;  ///< ...whose normals were estimated, as it gave none
    int welded_vertices = 0;       ///< vertices welded onto another at the same position (a soup's, a repeated face's)
    int repeated_faces = 0;        ///< faces dropped as a copy of another over the same three positions
    int back_faces = 0;            ///< faces dropped as the other side of a double-sided surface
    int flipped_faces = 0;         ///< faces turned to orient the surface coherently and outward
    bool orientable = true;        ///< false: some component could not be oriented, and was analysed as it came
    double noise = 0;              ///< estimated vertex noise, fraction of the diagonal
    double smoothing_radius = 0;   ///< presmoothing applied for signatures and growth, fraction of the diagonal
    double curvature_radius = 0;   ///< the radius r used (see min_radius_in_edges), fraction of the diagonal
    int pairs_sample_count_used = 0;  ///< n' = |P'| paired (§2.2)
    SampleSize pair_sample_size;      ///< for an automatic n': the Appendix's bound behind it
    bool pair_sample_count_automatic = false;
    /// For a restricted group's automatic n': the n' the rigid group would pair, which caps it
    /// (see pair_sample_count in detection.cpp); 0 otherwise.
    int rigid_pair_sample_count = 0;
    double partners_per_sample = 0;  ///< μ: points in Γ per paired sample, measured on a pilot
    double seconds_signatures = 0, seconds_pairing = 0, seconds_clustering = 0, seconds_verification = 0;
    TransformationSpaceSnapshot transformation_space;  ///< empty unless asked for
};

/// Called with a percentage (0..100) and the stage's name.  Always on the calling thread,
/// so a MeshLab callback that pumps the GUI event loop is safe.
using Progress = std::function<void(int percent, const char* stage)>;

/// Runs the pipeline on the mesh (V: #V by 3 positions, F: #F by 3 triangles).
/// Throws InputError for unusable input or parameters; the input is never modified.
DetectionResult detect_partial_symmetries(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F,
                                          const DetectionOptions& options, const Progress& progress = {});

/// Runs the pipeline on a point cloud (V: #V by 3 positions; N: #V by 3 normals, or no
/// rows, and they are estimated as MeshLab's point-set filter does).  Curvature comes from
/// a local fit and verification grows over the k-nearest-neighbour graph (point_cloud.h);
/// the per-vertex outputs are per point.  A cloud of more than working.max_vertices points
/// is analysed on a Poisson-disk subset of about that many (working_mesh.h); patches reach
/// every point from its nearest point of the subset, and deviations are measured on every
/// point itself.
DetectionResult detect_partial_symmetries_in_point_cloud(const Eigen::MatrixX3d& V, const Eigen::MatrixX3d& N,
                                                         const DetectionOptions& options, const Progress& progress = {});

/// For the uses of a result (symmetrization, reduction): throws InputError unless `detected`
/// fits a mesh of `rows` vertices (its per-vertex outputs and patches are rows of that V).
void require_result_of_mesh(const DetectionResult& detected, Eigen::Index rows);

}  // namespace symmetry
