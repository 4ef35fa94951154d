// Stage 7 (§4): verification of a candidate symmetry by region growing over the mesh,
// with ICP refinement of the transformation and a normalised residual as its error.
#pragma once

#include "mesh.h"
#include "surface_query.h"
#include "transformation_space.h"

#include <optional>
#include <random>
#include <vector>

namespace symmetry {

struct VerificationOptions {
    double tolerance = 0;        ///< largest distance of T(v) to the surface, absolute units
    double min_patch_area = 0;   ///< smallest area of a source patch worth reporting, absolute units
    bool refine_with_icp = true; ///< re-fit T to the matched vertices while the patch grows
    TransformationGroup group = TransformationGroup::Rigid;  ///< ICP stays inside this group
};

struct VerifiedSymmetry {
    Transformation transform;             ///< maps the source patch onto the target patch
    std::vector<int> source_vertices;     ///< mesh vertex indices, increasing
    std::vector<int> target_vertices;     ///< mesh vertex indices, increasing
    std::vector<double> source_deviation; ///< signed distance of T(v) to the surface, per source vertex
    std::vector<double> target_deviation; ///< signed distance of T⁻¹(w) to the surface, per target vertex
    double rms_error = 0;                 ///< RMS of source_deviation: the normalised ICP residual, absolute units
    double source_area = 0;               ///< area of the faces whose three vertices are in the source patch
};

/// Grows patches invariant under `candidate` from the seed vertices (one per pair of the
/// cluster, the first sample of each pair): a vertex v joins when T(v) lies within the
/// tolerance of the surface with a normal that agrees with T's image of v's normal, and
/// growth continues over mesh edges until no vertex can be added.  Seeds already inside
/// a patch are skipped, as the paper removes their pairs from the cluster.  With ICP the
/// transformation is re-fitted to the matched vertices each time the patch has doubled
/// in size, and once at the end, staying inside `options.group`.  Returns nothing when
/// the patches together cover less than options.min_patch_area.
std::optional<VerifiedSymmetry> verify_by_region_growing(const Mesh& mesh, const SurfaceQuery& surface,
                                                         const Transformation& candidate,
                                                         const std::vector<int>& seed_vertices,
                                                         const VerificationOptions& options);

}  // namespace symmetry
