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

/// Vertex-to-vertex adjacency over mesh edges, in compressed rows: the neighbours of
/// vertex v are neighbours[offsets[v] .. offsets[v+1]).  Built once per mesh.
struct VertexNeighbours {
    std::vector<int> offsets;
    std::vector<int> neighbours;
};
VertexNeighbours vertex_neighbours(const Mesh& mesh);

struct VerificationOptions {
    double tolerance = 0;        ///< largest distance of T(v) to the surface, absolute units
    double min_patch_area = 0;   ///< smallest area of a connected source patch worth keeping, absolute units
    double min_displacement = 0; ///< a transformation that moves its patch less than this (RMS) is
                                 ///< a continuous self-map of the surface, not a symmetry; rejected
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

/// The transformation of `options.group` that best maps `source` onto `target` in the
/// least-squares sense (Umeyama for rigid and similarity, through the fixed mirror when
/// `reflection`; a plane fit for mirrors; the mean offset for translations).
Transformation fit_transformation(const std::vector<Eigen::Vector3d>& source, const std::vector<Eigen::Vector3d>& target,
                                  TransformationGroup group, bool reflection);

/// Grows patches invariant under `candidate` from the seed vertices (one per pair of the
/// cluster, the first sample of each pair): a vertex v joins when T(v) lies within the
/// tolerance of the surface with a normal that agrees with T's image of v's normal, and
/// growth continues over mesh edges until no vertex can be added.  Seeds already inside
/// a patch are skipped, as the paper removes their pairs from the cluster.  With ICP the
/// transformation is re-fitted to the matched vertices each time the patch has doubled
/// in size, and once at the end, staying inside `options.group`.  Connected patches
/// smaller than options.min_patch_area are dropped; returns nothing when none is left.
/// A result whose RMS deviation exceeds a quarter of the tolerance is rejected: it is two
/// smooth patches that touch, not a symmetry (see verification.cpp).
/// The target patch is grown the same way under T⁻¹, from the vertices T(source) lands on.
std::optional<VerifiedSymmetry> verify_by_region_growing(const Mesh& mesh, const VertexNeighbours& adjacency,
                                                         const SurfaceQuery& surface,
                                                         const Transformation& candidate,
                                                         const std::vector<int>& seed_vertices,
                                                         const VerificationOptions& options);

}  // namespace symmetry
