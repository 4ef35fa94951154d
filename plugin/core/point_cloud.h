// Stages 1-2 for a point cloud (issue 9, beyond the paper, which samples meshes): the
// outward normals a scan may arrive without, and the principal curvatures and frame of §2
// from a local fit, since a cloud has no edges for the normal cycle's tensor.
//
// The steps, each a function in point_cloud.cpp:
//   1. normals: a plane fitted to each point's nearest neighbours and oriented coherently by
//      propagation, as MeshLab's own "Compute normals for point sets" does (vcglib's
//      PointCloudNormal, which that filter calls);
//   2. outward: each connected part of the cloud (over its nearest-neighbour graph) turned
//      so that most of its normals point away from its centre;
//   3. signature: the points inside a ball of radius r fitted by a quadric height function
//      over the tangent plane, twice (the second fit on the first fit's normal), whose
//      Hessian gives the principal curvatures and directions.
// The fit is not the mesh's tensor: signatures of a cloud are compared with signatures of
// the same cloud, never with a mesh's.
#pragma once

#include "kd_tree.h"
#include "signatures.h"

#include <Eigen/Core>
#include <utility>
#include <vector>

namespace symmetry {

struct PointCloudOptions {
    /// Neighbours a point's tangent plane is fitted to (MeshLab's default for point sets: 10).
    int fitting_neighbours = 10;
    /// Neighbours the orientation is propagated over, and that define the connected parts
    /// turned outward in step 2 (MeshLab's default: 8).
    int orientation_neighbours = 8;
    /// Neighbours that set the surface a point stands for: pi d^2 / k, with d the distance
    /// to its k-th nearest neighbour, and the radius d of its disc (SurfaceQuery).
    int area_neighbours = 8;
    /// Neighbours of a point in the graph region growing walks (cloud_neighbourhoods).
    int graph_neighbours = 8;
    /// A cloud whose estimated noise exceeds this many point spacings (median neighbour
    /// distances) is presmoothed (PointCloudSurface::projected_on_local_fits); a mesh's
    /// threshold is DenoisingOptions::noise_threshold_in_edges.
    double noise_threshold_in_spacings = 0.05;
};

struct LocalFitOptions {
    /// Fewest points in the ball worth a fit of the quadric's six coefficients: with fewer,
    /// a few points of noise decide the curvature (6 at the very least).
    int min_points = 10;
    /// A ball holding fewer points (the cloud sparser than the ball is small: on a torus of
    /// 7,000 points beside a planted pair, 6,038 of its 6,060 samples' balls of 1 % of the
    /// scene's diagonal) is widened until its min_points-th nearest point weighs this much in
    /// the fit (the weights fall off as (1 - d^2/r^2)^2; 1/4 at d = r / sqrt(2)).  0 leaves
    /// it as it is, and the point without curvature.
    double widened_ball_weight = 0.25;
    /// ...but never beyond this multiple of its radius: the surface a far wider ball sees is
    /// not the one the curvature radius asks about (a coarse CAD face's few points, whose
    /// widened ball takes in the faces beside it, are left without curvature, and so flat,
    /// as before).  Pairing's second scale is twice the radius.
    double max_widening = 2;
};

/// Unit normals of a cloud, pointing outward in each of its connected parts (steps 1-2).
/// Points must be finite, and there must be more of them than fitting_neighbours
/// (InputError otherwise).
std::vector<Eigen::Vector3d> estimate_point_normals(const std::vector<Eigen::Vector3d>& points,
                                                    const PointCloudOptions& options = {});

/// The symmetric k-nearest-neighbour graph as compressed rows: j is a neighbour of i when
/// either is among the other's k nearest.  Region growing walks it as it walks mesh edges.
void neighbour_graph(const std::vector<Eigen::Vector3d>& points, int k, std::vector<int>& offsets,
                     std::vector<int>& neighbours);

/// Per point, the area it stands for and the radius of its disc (PointCloudOptions::area_neighbours).
struct PointAreas {
    std::vector<double> area, disc_radius;
};
PointAreas point_areas(const std::vector<Eigen::Vector3d>& points, const PointCloudOptions& options = {});

/// Stage 1 on a cloud: `count` of its points drawn with probability proportional to the
/// area each stands for (systematic sampling along the cumulative area, from one random
/// offset), each once; `face` is the point's index.  Deterministic for a given `rng` state.
std::vector<SurfaceSample> area_weighted_points(const std::vector<Eigen::Vector3d>& points,
                                                const std::vector<double>& areas, int count, std::mt19937_64& rng);

/// A cloud as the local fit reads it: positions, outward unit normals and a kd-tree.
class PointCloudSurface {
public:
    /// `normals`: one unit normal per point, outward (estimate_point_normals gives them).
    PointCloudSurface(std::vector<Eigen::Vector3d> points, std::vector<Eigen::Vector3d> normals);

    int size() const { return int(points_.size()); }
    const std::vector<Eigen::Vector3d>& points() const { return points_; }
    const std::vector<Eigen::Vector3d>& normals() const { return normals_; }
    const KdTree& tree() const { return tree_; }

    /// Step 3 at point `index`: kappa1 <= kappa2, positive where the cloud is convex, the
    /// principal directions and the fitted normal as a right-handed frame, and as `area` the
    /// disc the ball cuts from a plane (pi r^2).  A ball with fewer than options.min_points
    /// points is widened (LocalFitOptions::widened_ball_weight); where it would have to grow
    /// beyond LocalFitOptions::max_widening, or the whole cloud has fewer, the curvatures are
    /// 0 and the frame is the point's normal with any tangent basis.
    SurfaceSignature fit_signature(int index, double radius, const LocalFitOptions& options = {}) const;
    /// The same fit at any `position` near the cloud, starting from the unit `normal` (of
    /// a point near it).
    SurfaceSignature fit_at(const Eigen::Vector3d& position, const Eigen::Vector3d& normal, double radius,
                            const LocalFitOptions& options = {}) const;

    /// Presmoothing of a noisy cloud (denoising.h does it for a mesh): every point moved
    /// along its normal onto the quadric fitted to the points within `radius` of it (one
    /// pass, a moving-least-squares projection), and given that quadric's normal.  A
    /// quadric, not a plane, so that the smoothing keeps the curvature the signatures
    /// measure.  Returns the moved points and their normals.
    std::pair<std::vector<Eigen::Vector3d>, std::vector<Eigen::Vector3d>> projected_on_local_fits(
        double radius, const LocalFitOptions& options = {}) const;

private:
    /// The points a fit at p uses: those within `radius`, widened as the options say
    /// (`radius` then grows with it); empty when there are too few for a fit.
    std::vector<int> fit_ball(const Eigen::Vector3d& p, double& radius, const LocalFitOptions& options) const;

    std::vector<Eigen::Vector3d> points_;
    std::vector<Eigen::Vector3d> normals_;
    KdTree tree_;
};

}  // namespace symmetry
