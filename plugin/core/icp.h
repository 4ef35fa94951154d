// Stage 7b (§4): "we incrementally refine T_k during the patch growing using the
// iterated closest points (ICP) algorithm [Rusinkiewicz and Levoy 2001]", staying
// inside the transformation group the user asked for.
#pragma once

#include "surface_query.h"
#include "transformation_space.h"

#include <Eigen/Core>
#include <functional>
#include <vector>

namespace symmetry {

struct IcpOptions {
    /// Fewest matched points an ICP step is fitted to: a patch of a few hundred vertices
    /// pins down every degree of freedom; fitted on fewer, ICP follows a small patch's noise.
    int min_points = 256;
    int iterations = 20;               ///< iterations of the final refinement of a patch
    int iterations_while_growing = 2;  ///< per refit while a patch grows (each starts from the last)
    int max_points = 1500;             ///< a stride keeps each iteration to about this many points
    /// Closest points are searched within this many verification tolerances.
    double search_radius_in_tolerances = 2;
    /// Stop when no point moved more than this fraction of the tolerance in an iteration.
    /// A hundredth: a fit whose pairs change from one iteration to the next (a face's
    /// neighbour becomes nearer) moves its farthest point by 0.001-0.01 tolerances forever
    /// while its RMS stays put to four digits, so a thousandth ran nearly every final fit
    /// to its 20 iterations (measured on the speed benchmark's scan: 8 of its 16 final
    /// fits; the accuracy benchmark's results are the same at either value).
    double convergence_in_tolerances = 1e-2;
};

/// The transformation of `group` that best maps `source` onto `target` in the least-squares
/// sense: Umeyama for rigid and similarity (through the fixed mirror when `reflection`), a
/// plane fit for mirrors, the mean offset for translations.
Transformation fit_transformation(const std::vector<Eigen::Vector3d>& source, const std::vector<Eigen::Vector3d>& target,
                                  TransformationGroup group, bool reflection);

/// The mirror across the plane n·x = d (n unit).
Transformation pure_mirror(const Eigen::Vector3d& n, double d);
/// The plane (n, d) of the pure mirror nearest to the improper transformation T.
void mirror_plane(const Transformation& T, Eigen::Vector3d& n, double& d);

struct IcpResult {
    Transformation transform;
    bool refitted = false;   ///< false when too few points matched to fit anything
    double rms = 0;          ///< RMS distance of the matched points after the last fit, weighted like them
    int matched = 0;         ///< points with a closest point within the search radius
};

/// ICP of `points` (source positions) onto the surface, starting from `start`, each point's
/// residual weighted by `weights` (the area it stands for; empty: all alike).  Weighing by
/// area makes the fit the surface's, not the tessellation's: on a scan meshed finely in
/// one place, unweighted least squares tilts an approximate mirror towards that place
/// (measured: 1.1 degrees on a scanned bust, 0.1-0.4 weighted by area).
/// Point-to-plane steps (point-to-point steps crawl along directions in which the surface
/// nearly slides onto itself): over all rigid motions or similarities, or over the pure
/// mirrors for the Reflections group; the mean offset for translations.
IcpResult refine_by_icp(const std::vector<Eigen::Vector3d>& points, const std::vector<double>& weights,
                        const SurfaceQuery& surface,
                        const Transformation& start, TransformationGroup group, double tolerance, int iterations,
                        const IcpOptions& options);

/// The point of the surface that point i of the source, moved by T to `image`, is paired
/// with, within `radius`; found=false leaves it out of this iteration.
using IcpMatcher = std::function<ClosestPoint(size_t i, const Transformation& T, const Eigen::Vector3d& image,
                                              double radius)>;

/// The same ICP with the pairs chosen by `matcher` instead of the closest point alone:
/// verification pairs a vertex only with a face its normal agrees with (facing_landing in
/// region_growing.h), as region growing accepts it.  With the closest point alone, a patch
/// that slides along itself (a wall under a translation along it) is pulled along the
/// slide by the few points whose images pass its end and land on the end face: the
/// estimate creeps, refit after refit, off the discrete symmetry that started it (measured:
/// a facade's translation by one window spacing crept to 0.81 of it on the wall).
IcpResult refine_by_icp(const std::vector<Eigen::Vector3d>& points, const std::vector<double>& weights,
                        const IcpMatcher& matcher, const Transformation& start, TransformationGroup group,
                        double tolerance, int iterations, const IcpOptions& options);

}  // namespace symmetry
