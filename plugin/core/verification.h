// Stage 7 (§4): verification of a candidate symmetry, "by extracting the connected
// components of the model that are invariant under the corresponding transformation T_k",
// grown from the cluster's pairs with ICP refinement, and graded by its deviation.
//
// The steps, each a function in verification.cpp:
//   1. order the seeds: the pairs whose vote lies nearest to the cluster's mode first;
//   2. grow one source component per seed, each from the current estimate of T with its
//      own copy of it (region_growing.h, icp.h); a component that fails is dropped alone,
//      so a wrong seed cannot pull T off or abort the symmetry; an estimate that becomes a
//      relation verified before ends the verification there;
//   3. refine T on all accepted components together and regrow them under the final T,
//      with the mesh's other connected components that T maps onto the surface;
//   4. accept or reject the symmetry from its area, displacement and deviation;
//   5. grow the target side under T⁻¹ onto the faces the source lands on.
#pragma once

#include "icp.h"
#include "region_growing.h"
#include "surface_query.h"
#include "transformation_space.h"

#include <functional>
#include <optional>
#include <vector>

namespace symmetry {

struct VerificationOptions {
    double tolerance = 0;        ///< largest distance of T(v) to the surface, absolute units
    double min_patch_area = 0;   ///< smallest area of a connected source patch worth keeping, absolute units
    double min_displacement = 0; ///< a transformation that moves its patch less than this (RMS, absolute
                                 ///< units) is a continuous self-map of the surface, not a discrete
                                 ///< symmetry: marked small_motion (one that moves it less than the
                                 ///< tolerance is the identity: rejected)
    bool refine_with_icp = true; ///< re-fit T to the matched vertices while the patch grows (§4)
    TransformationGroup group = TransformationGroup::Rigid;  ///< ICP stays inside this group
    double normal_agreement_degrees = 45;  ///< see RegionGrowingOptions
    /// The systematic deviation of a patch is its signed deviation averaged over each
    /// vertex's neighbourhood (`deviation_smoothing_iterations` rounds of averaging over
    /// mesh neighbours), which removes noise and keeps what is smooth.  Its RMS must stay
    /// below a fraction of the tolerance: this one for a patch of at least
    /// `large_patch_area` (measured: 0.15-0.18 on the imperfect mirrors of a scanned elk and
    /// helmet, at most 0.07 on ten other real models, 0.32 on a scanned mannequin; 0.26-0.30
    /// on the near-mirrors of a smooth random blob and of a bumpy hull, which hold
    /// everywhere but nowhere closely; 0.24 on a torus's mirror whose patch spills onto the
    /// parts beside it), ...
    double max_systematic_deviation = 0.25;
    /// ... and this one for a patch of no area, in between with the square of the area.
    /// Noise on a true copy averages out; two unrelated smooth patches that merely touch do
    /// not: their gap grows smoothly from 0 at the contact to the tolerance at the border
    /// (measured: 0.15-0.25 of it on patches of 2-12% of the area).  A touch stays small,
    /// so a small patch must be more exact to be believed than a large one.
    double max_systematic_deviation_small = 0.1;
    double large_patch_area = 0;  ///< absolute units; the pipeline sets half the model's area
    /// On a mesh presmoothed for its noise (denoising.h), averaging over neighbourhoods leaves
    /// a part of the noise, and two copies tessellated apart are smoothed a little apart: the
    /// bound grows by this fraction of the estimated noise (measured: a copy with noise of
    /// 0.5 % of the diagonal on both sides deviates systematically by 0.121 of the 1 %
    /// tolerance where the bound for its size is 0.118).
    double systematic_noise_allowance = 0.25;
    double noise = 0;             ///< estimated noise, absolute units; the pipeline sets it if it presmoothed
    /// The median |deviation| must stay below this fraction of the tolerance: most of a
    /// symmetric patch maps closely, even where parts of it do not (measured: 0.03-0.21 on
    /// true mirrors of scanned and CAD models, 0.31-0.34 on the near-mirrors of a smooth blob,
    /// whose gap is moderate everywhere).
    double max_median_deviation = 0.25;
    int deviation_smoothing_iterations = 4;  ///< rounds of averaging over mesh neighbours
    /// Step 3: the final scale may differ from the cluster mode's by at most this factor
    /// (either way).  The mode's scale is the ratio of curvatures of many pairs; ICP in the
    /// 7-D group may otherwise shrink T towards scale 0, where every patch maps onto a point
    /// of the surface with no deviation at all.
    double max_scale_change = 1.5;
    /// Step 3a: an improper T that is nearly an involution becomes a pure mirror unless
    /// that raises the fit's RMS by more than this factor.
    double mirror_snap_rms_ratio = 1.1;
    /// Step 3b: vertices tried per other connected component of the mesh...
    int component_probes = 8;
    /// ...which joins the patch when T maps at least this fraction of its area,...
    double min_component_share = 0.5;
    /// ...unless it is debris (DebrisRule, region_growing.h).  A speck lands
    /// on some surface under any T once the tolerance exceeds its distance from one, and
    /// three vertices of a speck weigh as much in the patch's deviation as three of the
    /// surface: measured, 176 of 3000 specks swept into a bumpy sphere's exact mirror took
    /// its systematic deviation from 0 to 0.40 of the tolerance.  The pipeline sets it.
    DebrisRule debris;
    IcpOptions icp;
    /// Cells per face of the grid that region growing queries (see SurfaceQuery): measured
    /// on a 40k-face scene, 8 takes verification from 15.2 s to 10.4 s (32: 9.8 s) at 8 bytes
    /// a cell.  Since a search marks the faces it has tested, finer is no faster (on the
    /// speed benchmark's scan: 4.5 s at 8, 4.8 s at 16, 4.5 s at 32).
    double grid_cells_per_face = 8;
};

/// A pair of the cluster, as a place to start growing: the source sample's vertex and
/// the distance of the pair's vote to the cluster's mode in Γ.
struct Seed {
    int vertex = -1;
    double distance_to_mode = 0;
};

struct VerifiedSymmetry {
    Transformation transform;             ///< maps the source patch onto the target patch
    std::vector<int> source_vertices;     ///< mesh vertex indices, increasing
    std::vector<int> target_vertices;     ///< mesh vertex indices, increasing
    std::vector<double> source_deviation; ///< signed distance of T(v) to the surface, per source vertex
    std::vector<double> target_deviation; ///< signed distance of T⁻¹(w) to the surface times the scale, per target vertex
    double rms_error = 0;                 ///< RMS of source_deviation: the normalised ICP residual, absolute units
    double max_error = 0;                 ///< largest |source_deviation|, absolute units
    double systematic_error = 0;          ///< RMS of the locally averaged deviation, absolute units
    double source_area = 0;               ///< area of the faces whose three vertices are in the source patch
    /// T moves the patch less than min_displacement: a slide along a continuous self-map (a
    /// turn of a thin cylinder about its axis), which is a family's member, not a symmetry.
    bool small_motion = false;
};

/// Whether an estimate of T, refitted on `patch` (the source vertices grown so far), is a
/// relation assessed before: the caller's test, which may credit a relation verified before
/// with the candidate's votes, or find that T was rejected over that patch already.
using KnownRelation = std::function<bool(const Transformation&, const std::vector<int>& patch)>;

/// A candidate that converged and was then rejected by the acceptance of step 4: the
/// transformation it converged to and the source patch regrown and measured under it.
struct RejectedRelation {
    Transformation transform;
    std::vector<int> source_vertices;  ///< increasing
};

/// Verifies the candidate `mode` from its seeds (steps 1-5 above).  The result does not
/// depend on the order of `seeds`.  Returns nothing when no patch of sufficient area is
/// invariant under the transformation, or the patch fails the acceptance of step 4, or
/// (with `known`) as soon as the estimate of T, refitted while the first components grow,
/// is a relation verified before: a neighbouring mode of a large symmetry would otherwise
/// regrow the whole patch of that symmetry only to be merged with it.  When the acceptance
/// of step 4 rejects the patch, `rejected` (if given) receives what was rejected.
std::optional<VerifiedSymmetry> verify_candidate(const MeshNeighbourhoods& mesh, const SurfaceQuery& surface,
                                                 const Transformation& mode, std::vector<Seed> seeds,
                                                 const VerificationOptions& options, const KnownRelation& known = {},
                                                 RejectedRelation* rejected = nullptr);

/// The RMS over `patch` of the deviation averaged over mesh neighbours inside the patch,
/// `iterations` times (the systematic deviation of VerificationOptions).
double systematic_deviation(const MeshNeighbourhoods& mesh, const std::vector<int>& patch,
                            const std::vector<double>& deviation, int iterations);

}  // namespace symmetry
