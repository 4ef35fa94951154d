#include "point_cloud.h"

#include "mesh.h"

#include <vcg/complex/algorithms/pointcloud_normal.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <queue>
#include <string>
#include <tuple>

namespace symmetry {

namespace {

// Step 1: MeshLab's own estimate (filter "Compute normals for point sets" calls vcglib's
// PointCloudNormal): the normal of a plane fitted to each point's nearest neighbours.  Its
// orientation pass is left to step 2, which orients each part outward as well as coherently.
std::vector<Eigen::Vector3d> fitted_plane_normals(const std::vector<Eigen::Vector3d>& points, int neighbours) {
    Mesh cloud;
    vcg::tri::Allocator<Mesh>::AddVertices(cloud, points.size());
    for (size_t i = 0; i < points.size(); ++i) cloud.vert[i].P() = vcg::Point3d(points[i].x(), points[i].y(), points[i].z());
    vcg::tri::PointCloudNormal<Mesh>::Param param;
    param.fittingAdjNum = neighbours;
    param.smoothingIterNum = 0;
    param.coherentAdjNum = 0;  // no orientation here: step 2
    vcg::tri::PointCloudNormal<Mesh>::Compute(cloud, param);
    std::vector<Eigen::Vector3d> normals(points.size());
    for (size_t i = 0; i < points.size(); ++i) {
        const vcg::Point3d& n = cloud.vert[i].cN();
        normals[i] = Eigen::Vector3d(n[0], n[1], n[2]).normalized();
    }
    return normals;
}

}  // namespace

void neighbour_graph(const std::vector<Eigen::Vector3d>& points, int k, std::vector<int>& offsets,
                     std::vector<int>& neighbours) {
    const KdTree tree(KdTree::rows_of(points));
    std::vector<std::vector<int>> lists(points.size());
    for (size_t i = 0; i < points.size(); ++i)
        for (int j : tree.nearest_k(points[i].data(), k + 1))
            if (j != int(i)) {
                lists[i].push_back(j);
                lists[size_t(j)].push_back(int(i));
            }
    offsets.assign(1, 0);
    neighbours.clear();
    for (auto& l : lists) {
        std::sort(l.begin(), l.end());
        l.erase(std::unique(l.begin(), l.end()), l.end());
        neighbours.insert(neighbours.end(), l.begin(), l.end());
        offsets.push_back(int(neighbours.size()));
    }
}

std::vector<SurfaceSample> area_weighted_points(const std::vector<Eigen::Vector3d>& points,
                                                const std::vector<double>& areas, int count, std::mt19937_64& rng) {
    std::vector<SurfaceSample> samples;
    double total = 0;
    for (double a : areas) total += a;
    if (count <= 0 || points.empty() || !(total > 0)) return samples;
    const double step = total / count;
    double next = step * (double(rng() >> 11) * 0x1.0p-53), reached = 0;  // one offset in [0, step)
    for (size_t i = 0; i < points.size(); ++i) {
        reached += areas[i];
        if (next >= reached) continue;
        samples.push_back({points[i], int(i)});
        while (next < reached) next += step;  // a point larger than a step is drawn once
    }
    return samples;
}

PointAreas point_areas(const std::vector<Eigen::Vector3d>& points, const PointCloudOptions& options) {
    PointAreas out;
    const KdTree tree(KdTree::rows_of(points));
    const int k = options.area_neighbours;
    for (const Eigen::Vector3d& p : points) {
        const std::vector<int> near = tree.nearest_k(p.data(), k + 1);  // the point itself first
        const double d = (points[size_t(near.back())] - p).norm();
        out.disc_radius.push_back(d);
        out.area.push_back(M_PI * d * d / std::max(1, int(near.size()) - 1));
    }
    return out;
}

namespace {

// Step 2, for one connected part (its points in `part`): the normal of the point farthest
// from the part's centre is turned away from the centre, as on any closed surface, and the
// orientation is carried over the graph along the edges whose normals agree best first
// (Hoppe et al. 1992, as vcglib's own pass does), so that it crosses a sharp edge last.
void orient_part(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& part,
                 const std::vector<int>& offsets, const std::vector<int>& neighbours,
                 std::vector<Eigen::Vector3d>& normals, std::vector<char>& oriented) {
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (int i : part) centre += points[size_t(i)];
    centre /= double(part.size());
    int start = part.front();
    for (int i : part)
        if ((points[size_t(i)] - centre).squaredNorm() > (points[size_t(start)] - centre).squaredNorm()) start = i;
    if (normals[size_t(start)].dot(points[size_t(start)] - centre) < 0) normals[size_t(start)] = -normals[size_t(start)];
    // (agreement, from, to): the most parallel pair first; ties by index, for determinism.
    using Arc = std::tuple<double, int, int>;
    std::priority_queue<Arc> heap;
    auto push_arcs = [&](int i) {
        for (int k = offsets[size_t(i)]; k < offsets[size_t(i) + 1]; ++k) {
            const int j = neighbours[size_t(k)];
            if (!oriented[size_t(j)]) heap.emplace(std::abs(normals[size_t(i)].dot(normals[size_t(j)])), -i, -j);
        }
    };
    oriented[size_t(start)] = 1;
    push_arcs(start);
    while (!heap.empty()) {
        const auto [agreement, from, to] = heap.top();
        heap.pop();
        const int i = -from, j = -to;
        if (oriented[size_t(j)]) continue;
        if (normals[size_t(i)].dot(normals[size_t(j)]) < 0) normals[size_t(j)] = -normals[size_t(j)];
        oriented[size_t(j)] = 1;
        push_arcs(j);
    }
}

// Step 2: every connected part of the graph oriented on its own (two copies of a part
// apart from each other must both face outward, or their curvatures differ in sign).
void orient_outward(const std::vector<Eigen::Vector3d>& points, int k, std::vector<Eigen::Vector3d>& normals) {
    std::vector<int> offsets, neighbours;
    neighbour_graph(points, k, offsets, neighbours);
    std::vector<int> part_of(points.size(), -1);
    std::vector<char> oriented(points.size(), 0);
    int parts = 0;
    for (size_t seed = 0; seed < points.size(); ++seed) {
        if (part_of[seed] >= 0) continue;
        std::vector<int> part{int(seed)};
        part_of[seed] = parts;
        for (size_t q = 0; q < part.size(); ++q)
            for (int e = offsets[size_t(part[q])]; e < offsets[size_t(part[q]) + 1]; ++e) {
                const int j = neighbours[size_t(e)];
                if (part_of[size_t(j)] < 0) { part_of[size_t(j)] = parts; part.push_back(j); }
            }
        orient_part(points, part, offsets, neighbours, normals, oriented);
        ++parts;
    }
}

// A quadric height function h(u, v) = a u^2 + b uv + c v^2 + d u + e v + f over the tangent
// plane of `normal` at `origin`, fitted by least squares to the points `ball` of radius r,
// each weighted by (1 - d^2/r^2)^2: a surface is a quadric only near the origin, and the
// far points of a uniform fit bend the estimate (by 3 % on a cylinder at r = 0.4 R).
struct HeightFit {
    Eigen::Matrix<double, 6, 1> coefficients = Eigen::Matrix<double, 6, 1>::Zero();  // a b c d e f
    Eigen::Vector3d t1, t2;
};

HeightFit fit_height(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& ball,
                     const Eigen::Vector3d& origin, const Eigen::Vector3d& normal, double radius) {
    HeightFit fit;
    tangent_basis(normal, fit.t1, fit.t2);
    Eigen::Matrix<double, 6, 6> normal_matrix = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> right = Eigen::Matrix<double, 6, 1>::Zero();
    for (int i : ball) {
        const Eigen::Vector3d q = points[size_t(i)] - origin;
        const double u = q.dot(fit.t1), v = q.dot(fit.t2), h = q.dot(normal);
        const double falloff = std::max(0.0, 1 - q.squaredNorm() / (radius * radius)), weight = falloff * falloff;
        Eigen::Matrix<double, 6, 1> row;
        row << u * u, u * v, v * v, u, v, 1;
        normal_matrix.noalias() += weight * row * row.transpose();
        right.noalias() += weight * h * row;
    }
    // LDLT of the normal equations: the ball is small and well spread, and a degenerate one
    // (points on a line) gives coefficients the caller's frame check rejects.
    fit.coefficients = normal_matrix.ldlt().solve(right);
    return fit;
}

}  // namespace

std::vector<Eigen::Vector3d> estimate_point_normals(const std::vector<Eigen::Vector3d>& points,
                                                    const PointCloudOptions& options) {
    if (options.fitting_neighbours < 3 || options.orientation_neighbours < 1)
        throw InputError("A point cloud's normals need at least 3 neighbours to fit a plane to and 1 to orient over.");
    if (int(points.size()) <= options.fitting_neighbours)
        throw InputError("The point cloud has " + std::to_string(points.size()) + " points: too few to estimate normals from " +
                         std::to_string(options.fitting_neighbours) + " neighbours each.");
    for (const Eigen::Vector3d& p : points)
        if (!p.allFinite()) throw InputError("The point cloud has coordinates that are not finite numbers (NaN or infinity).");
    std::vector<Eigen::Vector3d> normals = fitted_plane_normals(points, options.fitting_neighbours);
    orient_outward(points, options.orientation_neighbours, normals);
    return normals;
}

PointCloudSurface::PointCloudSurface(std::vector<Eigen::Vector3d> points, std::vector<Eigen::Vector3d> normals)
    : points_(std::move(points)), normals_(std::move(normals)), tree_(KdTree::rows_of(points_)) {
    if (normals_.size() != points_.size())
        throw InputError("A point cloud needs one normal per point.");
}

std::vector<int> PointCloudSurface::fit_ball(const Eigen::Vector3d& p, double& radius,
                                             const LocalFitOptions& options) const {
    const int fewest = std::max(6, options.min_points);
    std::vector<int> ball = tree_.radius_search(p.data(), radius);
    if (int(ball.size()) >= fewest) return ball;
    if (options.widened_ball_weight <= 0 || options.widened_ball_weight >= 1 || size() < fewest) return {};
    const std::vector<int> nearest = tree_.nearest_k(p.data(), fewest);
    const double farthest = (points_[size_t(nearest.back())] - p).norm();
    // (1 - d^2/r^2)^2 = w at d = farthest.
    const double widened = farthest / std::sqrt(1 - std::sqrt(options.widened_ball_weight));
    if (widened > options.max_widening * radius) return {};
    radius = std::max(radius, widened);
    ball = tree_.radius_search(p.data(), radius);
    return int(ball.size()) >= fewest ? ball : std::vector<int>{};
}

std::pair<std::vector<Eigen::Vector3d>, std::vector<Eigen::Vector3d>> PointCloudSurface::projected_on_local_fits(
    double radius, const LocalFitOptions& options) const {
    std::vector<Eigen::Vector3d> moved(points_), turned(normals_);
    // Each point writes only its own entries: the same result at any thread count.
#pragma omp parallel for schedule(dynamic, 256)
    for (long i = 0; i < long(points_.size()); ++i) {
        const Eigen::Vector3d& p = points_[size_t(i)];
        const Eigen::Vector3d& n = normals_[size_t(i)];
        double reach = radius;
        const std::vector<int> ball = fit_ball(p, reach, options);
        if (ball.empty()) continue;
        const HeightFit fit = fit_height(points_, ball, p, n, reach);
        const auto& c = fit.coefficients;
        const Eigen::Vector3d normal = (n - c(3) * fit.t1 - c(4) * fit.t2).normalized();
        if (!c.allFinite() || !normal.allFinite() || normal.dot(n) < 0.5) continue;
        moved[size_t(i)] = p + c(5) * n;
        turned[size_t(i)] = normal;
    }
    return {std::move(moved), std::move(turned)};
}

SurfaceSignature PointCloudSurface::fit_signature(int index, double radius, const LocalFitOptions& options) const {
    SurfaceSignature out = fit_at(points_[size_t(index)], normals_[size_t(index)], radius, options);
    out.face = index;
    return out;
}

SurfaceSignature PointCloudSurface::fit_at(const Eigen::Vector3d& p, const Eigen::Vector3d& start_normal,
                                           double radius, const LocalFitOptions& options) const {
    SurfaceSignature out;
    out.position = p;
    Eigen::Vector3d normal = start_normal;
    Eigen::Vector3d t1, t2;
    tangent_basis(normal, t1, t2);
    out.normal = normal;
    out.direction1 = t1;
    out.direction2 = t2;
    const std::vector<int> ball = fit_ball(p, radius, options);
    out.area = M_PI * radius * radius;
    if (ball.empty()) return out;
    // The first fit's gradient tilts the estimated normal; the second fit, on the tilted
    // normal, has a gradient near zero, where the Hessian is the second fundamental form.
    HeightFit fit = fit_height(points_, ball, p, normal, radius);
    const Eigen::Vector3d tilted = (normal - fit.coefficients(3) * fit.t1 - fit.coefficients(4) * fit.t2).normalized();
    if (tilted.allFinite() && tilted.dot(normal) > 0.5) {
        normal = tilted;
        fit = fit_height(points_, ball, p, normal, radius);
    }
    const auto& c = fit.coefficients;
    if (!c.allFinite()) return out;
    // Height is measured along the outward normal, so a convex surface bends to negative h:
    // the curvature is minus the Hessian, over the gradient's length element.
    const double gradient = std::sqrt(1 + c(3) * c(3) + c(4) * c(4));
    Eigen::Matrix2d second;
    second << -2 * c(0), -c(1), -c(1), -2 * c(2);
    second /= gradient;
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(second);
    const Eigen::Vector2d v = eigen.eigenvectors().col(0);  // of the smaller curvature
    out.kappa1 = eigen.eigenvalues()(0);
    out.kappa2 = eigen.eigenvalues()(1);
    out.normal = normal;
    out.direction1 = (v(0) * fit.t1 + v(1) * fit.t2).normalized();
    out.direction2 = normal.cross(out.direction1);  // direction1 x direction2 = normal (§2)
    return out;
}

}  // namespace symmetry
