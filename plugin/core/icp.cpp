#include "icp.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace symmetry {

Transformation fit_transformation(const std::vector<Eigen::Vector3d>& source, const std::vector<Eigen::Vector3d>& target,
                                  TransformationGroup group, bool reflection) {
    const int n = int(source.size());
    Eigen::Matrix3Xd X(3, n), Y(3, n);
    for (int i = 0; i < n; ++i) { X.col(i) = source[size_t(i)]; Y.col(i) = target[size_t(i)]; }
    switch (group) {
    case TransformationGroup::Translations: {
        Transformation t;
        t.translation = (Y - X).rowwise().mean();
        return t;
    }
    case TransformationGroup::Reflections: {
        // A mirror moves every point along the plane normal n: n is the dominant
        // direction of the displacements, the plane passes through the midpoints.
        Eigen::Matrix3Xd D = Y - X;
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(D * D.transpose());
        Eigen::Vector3d normal = eig.eigenvectors().col(2);
        double offset = normal.dot(0.5 * (X + Y).rowwise().mean());
        Transformation t;
        t.reflection = true;
        t.rotation = (Eigen::Matrix3d::Identity() - 2 * normal * normal.transpose()) * Transformation::mirror();
        t.translation = 2 * offset * normal;
        return t;
    }
    case TransformationGroup::Rigid:
    case TransformationGroup::Similarity: {
        // Umeyama finds a proper similarity; an improper one is fitted to the mirrored
        // source and composed with the mirror, the same split as in Transformation.
        Eigen::Matrix3Xd S = reflection ? Eigen::Matrix3Xd(Transformation::mirror() * X) : X;
        Eigen::Matrix4d U = Eigen::umeyama(S, Y, group == TransformationGroup::Similarity);
        Eigen::Matrix3d A = U.topLeftCorner<3, 3>();
        if (reflection) A = A * Transformation::mirror();
        return Transformation::from_linear(A, U.topRightCorner<3, 1>());
    }
    }
    return Transformation();
}

Transformation pure_mirror(const Eigen::Vector3d& n, double d) {
    Transformation t;
    t.reflection = true;
    t.rotation = (Eigen::Matrix3d::Identity() - 2 * n * n.transpose()) * Transformation::mirror();  // H = R M
    t.translation = 2 * d * n;
    return t;
}

void mirror_plane(const Transformation& T, Eigen::Vector3d& n, double& d) {
    // The nearest pure reflection's normal: the eigenvector of the symmetric part of the
    // linear map with the lowest eigenvalue (-1 for a mirror); the plane halves T(0).
    const Eigen::Matrix3d L = T.linear() / T.scale;
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(0.5 * (L + L.transpose()));
    n = eig.eigenvectors().col(0);
    d = 0.5 * n.dot(T.translation);
}

namespace {

// One linearised point-to-plane step (Chen and Medioni; Rusinkiewicz and Levoy 2001):
// the small motion x -> x + ω × (x - c) + σ (x - c) + τ about the centroid c that best
// moves the points `moved` onto the tangent planes (q, n).  σ is fitted only for similarities.
Transformation point_to_plane_step(const std::vector<Eigen::Vector3d>& moved, const std::vector<Eigen::Vector3d>& q,
                                   const std::vector<Eigen::Vector3d>& n, const std::vector<double>& weight,
                                   bool with_scale) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    double total = 0;
    for (size_t i = 0; i < moved.size(); ++i) { c += weight[i] * moved[i]; total += weight[i]; }
    c /= total;
    const int k = with_scale ? 7 : 6;
    Eigen::MatrixXd AtA = Eigen::MatrixXd::Zero(k, k);
    Eigen::VectorXd Atb = Eigen::VectorXd::Zero(k);
    Eigen::VectorXd row(k);
    for (size_t i = 0; i < moved.size(); ++i) {
        Eigen::Vector3d x = moved[i] - c;
        row.head<3>() = x.cross(n[i]);
        row.segment<3>(3) = n[i];
        if (with_scale) row(6) = x.dot(n[i]);
        double residual = (moved[i] - q[i]).dot(n[i]);
        AtA += weight[i] * row * row.transpose();
        Atb -= weight[i] * row * residual;
    }
    // A surface that slides along itself (a cylinder turning about its axis) leaves AtA
    // singular; a faint damping keeps the step's component along that slide at zero
    // instead of whatever the factorisation makes of a null direction.
    AtA.diagonal().array() += 1e-9 * AtA.trace() / k;
    Eigen::VectorXd x = AtA.ldlt().solve(Atb);
    Transformation step;
    if (!x.allFinite()) return step;
    Eigen::Vector3d omega = x.head<3>();
    if (omega.norm() > 0) step.rotation = Eigen::AngleAxisd(omega.norm(), omega.normalized()).toRotationMatrix();
    step.scale = with_scale ? std::exp(x(6)) : 1.0;
    // x -> s R (x - c) + c + τ
    step.translation = c + x.segment<3>(3) - step.scale * step.rotation * c;
    return step;
}

// One Gauss-Newton step of point-to-plane ICP restricted to pure mirrors x -> x - 2(n·x - d) n:
// the plane's two tilts (along u, w ⟂ n) and its offset, fitted to the tangent planes
// (q, m) of the closest points of the mirrored source points p.  (Fitting the plane to
// point-to-point displacements instead is slow and biased where the surface slides.)
Transformation point_to_plane_mirror_step(const std::vector<Eigen::Vector3d>& p, const std::vector<Eigen::Vector3d>& q,
                                          const std::vector<Eigen::Vector3d>& m, const std::vector<double>& weight,
                                          const Eigen::Vector3d& n, double d) {
    const Eigen::Vector3d u = n.unitOrthogonal(), w = n.cross(u);
    Eigen::Matrix3d AtA = Eigen::Matrix3d::Zero();
    Eigen::Vector3d Atb = Eigen::Vector3d::Zero();
    for (size_t i = 0; i < p.size(); ++i) {
        const double h = n.dot(p[i]) - d;
        const Eigen::Vector3d image = p[i] - 2 * h * n;
        // ∂H/∂n along δn ⟂ n: -2((δn·p) n + h δn); ∂H/∂d = 2n.
        Eigen::Vector3d row(-2 * (u.dot(p[i]) * n.dot(m[i]) + h * u.dot(m[i])),
                            -2 * (w.dot(p[i]) * n.dot(m[i]) + h * w.dot(m[i])), 2 * n.dot(m[i]));
        const double residual = (image - q[i]).dot(m[i]);
        AtA += weight[i] * row * row.transpose();
        Atb -= weight[i] * row * residual;
    }
    AtA.diagonal().array() += 1e-9 * AtA.trace() / 3;
    const Eigen::Vector3d x = AtA.ldlt().solve(Atb);
    return pure_mirror((n + x(0) * u + x(1) * w).normalized(), d + x(2));
}

// Closest points of the moved source, within `radius`.
struct Correspondences {
    std::vector<Eigen::Vector3d> source, moved, target, normals;
    std::vector<double> weights;
    void clear() { source.clear(); moved.clear(); target.clear(); normals.clear(); weights.clear(); }
};

void match(const std::vector<Eigen::Vector3d>& points, const std::vector<double>& weights, size_t stride,
           const IcpMatcher& matcher, const Transformation& t, double radius, Correspondences& c) {
    c.clear();
    for (size_t i = 0; i < points.size(); i += stride) {
        Eigen::Vector3d m = t.apply(points[i]);
        ClosestPoint cp = matcher(i, t, m, radius);
        if (!cp.found) continue;
        c.source.push_back(points[i]);
        c.moved.push_back(m);
        c.target.push_back(cp.point);
        c.normals.push_back(cp.normal);
        // A zero-area vertex (on degenerate faces only) still counts a little, so that the
        // weights never all vanish.
        c.weights.push_back(weights.empty() ? 1.0 : std::max(weights[i], 1e-12));
    }
}

// The weighted mean of target - source: the least-squares translation.
Transformation weighted_mean_offset(const Correspondences& c) {
    Transformation t;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    double total = 0;
    for (size_t i = 0; i < c.source.size(); ++i) {
        sum += c.weights[i] * (c.target[i] - c.source[i]);
        total += c.weights[i];
    }
    t.translation = sum / total;
    return t;
}

}  // namespace

IcpResult refine_by_icp(const std::vector<Eigen::Vector3d>& points, const std::vector<double>& weights,
                        const SurfaceQuery& surface,
                        const Transformation& start, TransformationGroup group, double tolerance, int iterations,
                        const IcpOptions& options) {
    const IcpMatcher closest = [&surface](size_t, const Transformation&, const Eigen::Vector3d& image, double radius) {
        return surface.closest(image, radius);
    };
    return refine_by_icp(points, weights, closest, start, group, tolerance, iterations, options);
}

IcpResult refine_by_icp(const std::vector<Eigen::Vector3d>& points, const std::vector<double>& weights,
                        const IcpMatcher& matcher, const Transformation& start, TransformationGroup group,
                        double tolerance, int iterations, const IcpOptions& options) {
    IcpResult result;
    result.transform = start;
    if (int(points.size()) < options.min_points) return result;
    const size_t stride = std::max<size_t>(1, points.size() / size_t(std::max(1, options.max_points)));
    const bool planar = group == TransformationGroup::Rigid || group == TransformationGroup::Similarity;
    const double radius = options.search_radius_in_tolerances * tolerance;
    Correspondences c;
    Transformation& t = result.transform;
    for (int iteration = 0; iteration < iterations; ++iteration) {
        match(points, weights, stride, matcher, t, radius, c);
        if (int(c.source.size()) < options.min_points / 2) break;
        Transformation fitted;
        if (planar) {
            fitted = point_to_plane_step(c.moved, c.target, c.normals, c.weights,
                                         group == TransformationGroup::Similarity) * t;
        } else if (group == TransformationGroup::Reflections) {
            Eigen::Vector3d n;
            double d;
            mirror_plane(t, n, d);
            fitted = point_to_plane_mirror_step(c.source, c.target, c.normals, c.weights, n, d);
        } else {
            fitted = weighted_mean_offset(c);  // the Translations group
        }
        if (!fitted.matrix().allFinite()) break;
        double shift = 0;
        for (size_t i = 0; i < c.source.size(); ++i) shift = std::max(shift, (fitted.apply(c.source[i]) - c.moved[i]).norm());
        t = fitted;
        result.refitted = true;
        if (shift < options.convergence_in_tolerances * tolerance) break;
    }
    if (result.refitted) {
        double sum = 0, total = 0;
        for (size_t i = 0; i < c.source.size(); ++i) {
            sum += c.weights[i] * (t.apply(c.source[i]) - c.target[i]).squaredNorm();
            total += c.weights[i];
        }
        result.matched = int(c.source.size());
        result.rms = total > 0 ? std::sqrt(sum / total) : 0;
    }
    return result;
}

}  // namespace symmetry
