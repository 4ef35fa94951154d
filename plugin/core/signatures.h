// Stage 2 (§2): the curvature tensor of Cohen-Steiner and Morvan's normal cycle,
// integrated over a ball of radius r as in Alliez et al. 2003, its principal
// curvatures and directions, and the right-handed local frame on the outward
// normal that every pair's transformation is computed from.
#pragma once

#include "mesh.h"
#include "sampling.h"

#include <Eigen/Core>
#include <memory>
#include <vector>

namespace symmetry {

/// A sample with its local shape signature and frame.
struct SurfaceSignature {
    Eigen::Vector3d position;
    Eigen::Vector3d normal;     ///< outward unit normal (area-weighted face normals in the ball)
    Eigen::Vector3d direction1; ///< principal direction of kappa1, unit, tangent
    Eigen::Vector3d direction2; ///< principal direction of kappa2; direction1 x direction2 = normal
    double kappa1 = 0;          ///< smaller principal curvature (signed, kappa1 <= kappa2)
    double kappa2 = 0;          ///< larger principal curvature; positive where the surface is convex
    /// The principal curvatures over a ball of twice the radius (kept for the pruned samples
    /// only): a second scale that tells true partners from chance ones in pairing (§2.2).
    double coarse_kappa1 = 0, coarse_kappa2 = 0;
    double area = 0;            ///< surface area inside the ball, used for normalisation
    int face = -1;              ///< face the sample lies on
};

/// Curvature tensor at each sample, integrated over the surface inside a ball of
/// radius `radius` around it: T = 1/|B| sum_e beta(e) |e ∩ B| ê êᵀ, with beta the
/// signed dihedral angle (positive on convex edges).  The tensor is projected on the
/// tangent plane of the averaged normal before its eigen-decomposition, because on a
/// cylinder the normal and the direction around the axis share the eigenvalue 0 and
/// would be confused otherwise.  (The tensor's eigenvector of the larger eigenvalue
/// is the direction of the smaller curvature: the axis of a cylinder gets 1/R.)
/// Edges with more than two faces (non-manifold) and boundary edges bend nothing
/// and are skipped.  The radius must be positive (InputError otherwise).
std::vector<SurfaceSignature> compute_signatures(const Mesh& mesh, const std::vector<SurfaceSample>& samples,
                                                 double radius);

/// The same estimate one sample at a time, for callers that need it at points they choose
/// (verification compares the curvature at a point with that at its image).  Reads the
/// mesh once.  An estimate needs work space (which faces and edges the ball met): `at`
/// without one uses the estimator's own, so it serves one thread; threads that share an
/// estimator each bring a Workspace of their own.
class PointCloudSurface;

class CurvatureEstimator {
public:
    /// Which faces and edges the ball met (stamps, so that nothing is cleared between estimates).
    struct Workspace {
        std::vector<int> stamp, edge_stamp;
        std::vector<int> ball_faces, ball_edges;
        int next_stamp = 0;
    };
    explicit CurvatureEstimator(const Mesh& mesh);  ///< the mesh must outlive the estimator
    /// On a point cloud the estimate is its local fit (point_cloud.h), at a sample whose
    /// `face` is the index of a point near it; the cloud must outlive the estimator.
    explicit CurvatureEstimator(const PointCloudSurface& cloud);
    ~CurvatureEstimator();
    SurfaceSignature at(const SurfaceSample& sample, double radius) const;
    SurfaceSignature at(const SurfaceSample& sample, double radius, Workspace& workspace) const;
    std::unique_ptr<Workspace> workspace() const;  ///< work space for one thread

private:
    struct Data;
    std::unique_ptr<Data> data_;
    std::unique_ptr<Workspace> own_;
    const PointCloudSurface* cloud_ = nullptr;
};

/// compute_signatures with an estimator already built on the mesh, for estimates at
/// several radii from one reading of the mesh.
std::vector<SurfaceSignature> compute_signatures(const CurvatureEstimator& estimator,
                                                 const std::vector<SurfaceSample>& samples, double radius);

/// Any orthonormal basis (t1, t2) of the plane orthogonal to the unit vector n, with
/// t1 × t2 = n: the frame a tangent-plane fit or a projected tensor is expressed in.
void tangent_basis(const Eigen::Vector3d& n, Eigen::Vector3d& t1, Eigen::Vector3d& t2);

}  // namespace symmetry
