// Stages 1-2 for a point cloud: normals against the analytic normals of a sphere and of two
// separate parts, and the local fit's principal curvatures and directions against those of
// a sphere, a cylinder, a saddle and a plane, with and without noise.  Then the cloud as
// verification walks it (its discs, its neighbour graph): distances against a sphere's,
// and growth under a planted mirror against growth under a motion that is no symmetry.
#include "core/continuous_families.h"
#include "core/mesh.h"
#include "core/point_cloud.h"
#include "core/region_growing.h"
#include "core/surface_query.h"

#include <gtest/gtest.h>

#include <cmath>
#include <algorithm>
#include <limits>
#include <random>

#include <Eigen/Geometry>

namespace symmetry {
namespace {

// n points spread evenly over a sphere (a Fibonacci lattice).
std::vector<Eigen::Vector3d> sphere_cloud(double radius, int n, const Eigen::Vector3d& centre = Eigen::Vector3d::Zero()) {
    std::vector<Eigen::Vector3d> points;
    const double golden = M_PI * (3 - std::sqrt(5.0));
    for (int i = 0; i < n; ++i) {
        const double z = 1 - 2 * (i + 0.5) / n, r = std::sqrt(1 - z * z), phi = golden * i;
        points.push_back(centre + radius * Eigen::Vector3d(r * std::cos(phi), r * std::sin(phi), z));
    }
    return points;
}

// A closed cylinder's side (radius r around the z axis, z in [0, height]) at random points.
std::vector<Eigen::Vector3d> cylinder_cloud(double radius, double height, int n, std::mt19937_64& rng) {
    std::uniform_real_distribution<double> angle(0, 2 * M_PI), z(0, height);
    std::vector<Eigen::Vector3d> points;
    for (int i = 0; i < n; ++i) {
        const double a = angle(rng);
        points.push_back({radius * std::cos(a), radius * std::sin(a), z(rng)});
    }
    return points;
}

// Points of the graph z = f(x, y) over a square grid of `cells` by `cells` in [-1, 1]^2.
template <class F>
std::vector<Eigen::Vector3d> height_cloud(F f, int cells) {
    std::vector<Eigen::Vector3d> points;
    for (int j = 0; j <= cells; ++j)
        for (int i = 0; i <= cells; ++i) {
            const double x = -1 + 2.0 * i / cells, y = -1 + 2.0 * j / cells;
            points.push_back({x, y, f(x, y)});
        }
    return points;
}

void add_noise(std::vector<Eigen::Vector3d>& points, double sigma, std::mt19937_64& rng) {
    std::normal_distribution<double> noise(0, sigma);
    for (Eigen::Vector3d& p : points) p += Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
}

// 20,000 points of the unit sphere with Gaussian noise of `sigma` on every coordinate.
std::vector<Eigen::Vector3d> noisy_unit_sphere(double sigma, unsigned seed) {
    std::mt19937_64 rng(seed);
    std::vector<Eigen::Vector3d> points = sphere_cloud(1.0, 20000);
    add_noise(points, sigma, rng);
    return points;
}

int index_nearest(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& q) {
    int best = 0;
    for (size_t i = 0; i < points.size(); ++i)
        if ((points[i] - q).squaredNorm() < (points[size_t(best)] - q).squaredNorm()) best = int(i);
    return best;
}

void expect_right_handed(const SurfaceSignature& s) {
    EXPECT_NEAR(s.normal.norm(), 1, 1e-9);
    EXPECT_NEAR(s.direction1.dot(s.direction2), 0, 1e-9);
    EXPECT_LT((s.direction1.cross(s.direction2) - s.normal).norm(), 1e-9);
    EXPECT_LE(s.kappa1, s.kappa2);
}

TEST(PointCloud, NormalsOfASpherePointOutwardAlongTheRadius) {
    const std::vector<Eigen::Vector3d> points = sphere_cloud(2.0, 3000);
    const std::vector<Eigen::Vector3d> normals = estimate_point_normals(points);
    ASSERT_EQ(normals.size(), points.size());
    double worst = 1;
    for (size_t i = 0; i < points.size(); ++i) worst = std::min(worst, normals[i].dot(points[i].normalized()));
    EXPECT_GT(worst, std::cos(3 * M_PI / 180));  // every normal within 3 degrees, none inward
}

// Two copies apart are two parts of the neighbour graph: each is turned outward on its own,
// or the copies' curvatures would have opposite signs and never pair.
TEST(PointCloud, EachSeparatePartIsTurnedOutwardOnItsOwn) {
    std::vector<Eigen::Vector3d> points = sphere_cloud(1.0, 1500);
    for (const Eigen::Vector3d& p : sphere_cloud(1.0, 1500, Eigen::Vector3d(5, 0, 0))) points.push_back(p);
    const std::vector<Eigen::Vector3d> normals = estimate_point_normals(points);
    int inward = 0;
    for (size_t i = 0; i < points.size(); ++i) {
        const Eigen::Vector3d centre = i < 1500 ? Eigen::Vector3d::Zero() : Eigen::Vector3d(5, 0, 0);
        if (normals[i].dot(points[i] - centre) < 0) ++inward;
    }
    EXPECT_EQ(inward, 0);
}

TEST(PointCloud, RefusesACloudTooSmallOrNotFinite) {
    EXPECT_THROW(estimate_point_normals(sphere_cloud(1, 8)), InputError);
    std::vector<Eigen::Vector3d> points = sphere_cloud(1, 100);
    points[7].x() = NAN;
    EXPECT_THROW(estimate_point_normals(points), InputError);
    EXPECT_THROW(PointCloudSurface(sphere_cloud(1, 100), {}), InputError);
}

TEST(PointCloud, ASphereIsUmbilicWithCurvatureOneOverRadius) {
    const std::vector<Eigen::Vector3d> points = sphere_cloud(2.0, 20000);
    const PointCloudSurface cloud(points, estimate_point_normals(points));
    for (int i = 0; i < cloud.size(); i += 997) {
        const SurfaceSignature s = cloud.fit_signature(i, 0.3);
        expect_right_handed(s);
        EXPECT_NEAR(s.kappa1, 0.5, 0.01);
        EXPECT_NEAR(s.kappa2, 0.5, 0.01);
        EXPECT_GT(s.normal.dot(points[size_t(i)].normalized()), std::cos(M_PI / 180));
    }
}

// The cylinder's axis is the direction of the smaller curvature, 0; around it, 1/r.
TEST(PointCloud, ACylinderBendsOnlyAroundItsAxis) {
    std::mt19937_64 rng(3);
    const std::vector<Eigen::Vector3d> points = cylinder_cloud(1.0, 4.0, 30000, rng);
    const PointCloudSurface cloud(points, estimate_point_normals(points));
    for (double z : {1.0, 2.0, 3.0}) {
        const int i = index_nearest(points, Eigen::Vector3d(std::cos(z), std::sin(z), z));
        const SurfaceSignature s = cloud.fit_signature(i, 0.4);
        expect_right_handed(s);
        EXPECT_NEAR(s.kappa1, 0.0, 0.02);
        EXPECT_NEAR(s.kappa2, 1.0, 0.03);
        EXPECT_GT(std::abs(s.direction1.z()), std::cos(3 * M_PI / 180));
    }
}

// z = (x^2 - y^2) / 2 at the origin, seen from +z: it bends towards the normal along x
// (curvature -1, concave) and away from it along y (+1, convex).
TEST(PointCloud, ASaddleHasOppositeCurvaturesAlongItsAxes) {
    const std::vector<Eigen::Vector3d> points = height_cloud([](double x, double y) { return 0.5 * (x * x - y * y); }, 100);
    std::vector<Eigen::Vector3d> up(points.size(), Eigen::Vector3d::UnitZ());
    const PointCloudSurface cloud(points, up);
    const SurfaceSignature s = cloud.fit_signature(index_nearest(points, Eigen::Vector3d::Zero()), 0.15);
    expect_right_handed(s);
    EXPECT_NEAR(s.kappa1, -1.0, 0.03);
    EXPECT_NEAR(s.kappa2, 1.0, 0.03);
    EXPECT_GT(std::abs(s.direction1.x()), std::cos(2 * M_PI / 180));
}

// Noise of 0.2 % of the diagonal on a sphere: the ball (a tenth of the diagonal) averages it
// out, as the mesh's tensor does at that radius.
TEST(PointCloud, NoiseOfAFifthOfAPercentLeavesTheCurvatureWithinAFewPercent) {
    const double diagonal = 2 * std::sqrt(3.0);
    const std::vector<Eigen::Vector3d> points = noisy_unit_sphere(0.002 * diagonal, 5);
    const PointCloudSurface cloud(points, estimate_point_normals(points));
    double sum = 0, worst = 0;
    int n = 0;
    for (int i = 0; i < cloud.size(); i += 211, ++n) {
        const SurfaceSignature s = cloud.fit_signature(i, 0.1 * diagonal);
        sum += s.kappa1 + s.kappa2;
        worst = std::max({worst, std::abs(s.kappa1 - 1), std::abs(s.kappa2 - 1)});
    }
    EXPECT_NEAR(sum / (2 * n), 1.0, 0.02);
    EXPECT_LT(worst, 0.12);
}

// Presmoothing: noise of 0.2 % of the diagonal on a sphere, projected on the local fits over
// a ball of a tenth of the diagonal, is at most a third of what it was, and the normals of
// the fits point along the radius.
TEST(PointCloud, ProjectionOnLocalFitsTakesMostOfTheNoiseAway) {
    const double diagonal = 2 * std::sqrt(3.0);
    const std::vector<Eigen::Vector3d> points = noisy_unit_sphere(0.002 * diagonal, 7);
    const PointCloudSurface cloud(points, estimate_point_normals(points));
    const auto [moved, normals] = cloud.projected_on_local_fits(0.1 * diagonal);
    auto rms_off_sphere = [](const std::vector<Eigen::Vector3d>& p) {
        double sum = 0;
        for (const Eigen::Vector3d& x : p) sum += (x.norm() - 1) * (x.norm() - 1);
        return std::sqrt(sum / double(p.size()));
    };
    EXPECT_LT(rms_off_sphere(moved), rms_off_sphere(points) / 3);
    double worst = 1;
    for (size_t i = 0; i < moved.size(); ++i) worst = std::min(worst, normals[i].dot(moved[i].normalized()));
    EXPECT_GT(worst, std::cos(2 * M_PI / 180));
}

TEST(PointCloud, APlaneIsFlatAndTooFewPointsGiveNoCurvature) {
    const std::vector<Eigen::Vector3d> points = height_cloud([](double, double) { return 0.0; }, 40);
    const PointCloudSurface cloud(points, std::vector<Eigen::Vector3d>(points.size(), Eigen::Vector3d::UnitZ()));
    const int centre = index_nearest(points, Eigen::Vector3d::Zero());
    const SurfaceSignature flat = cloud.fit_signature(centre, 0.2);
    EXPECT_NEAR(flat.kappa1, 0, 1e-9);
    EXPECT_NEAR(flat.kappa2, 0, 1e-9);
    EXPECT_NEAR(flat.normal.z(), 1, 1e-9);
    // A ball holding only the point itself would have to be widened far beyond twice its
    // radius to hold 10 points (the grid is 0.05 apart): no curvature, as before.
    const SurfaceSignature alone = cloud.fit_signature(centre, 0.01);
    EXPECT_EQ(alone.kappa1, 0);
    EXPECT_EQ(alone.kappa2, 0);
    expect_right_handed(alone);
    // One of 0.08 holds 9 and is widened (to 0.14, under twice 0.08): still flat.
    const SurfaceSignature widened = cloud.fit_signature(centre, 0.08);
    EXPECT_NEAR(widened.kappa1, 0, 1e-9);
    EXPECT_NEAR(widened.kappa2, 0, 1e-9);
    EXPECT_GT(widened.area, M_PI * 0.08 * 0.08);
    // Unless told not to widen it, or the cloud has fewer points than a fit needs.
    LocalFitOptions as_it_is;
    as_it_is.widened_ball_weight = 0;
    EXPECT_EQ(cloud.fit_signature(centre, 0.08, as_it_is).area, M_PI * 0.08 * 0.08);
    const std::vector<Eigen::Vector3d> few(points.begin(), points.begin() + 8);
    const PointCloudSurface sparse(few, std::vector<Eigen::Vector3d>(few.size(), Eigen::Vector3d::UnitZ()));
    const SurfaceSignature none = sparse.fit_signature(0, 10.0);
    EXPECT_EQ(none.kappa1, 0);
    EXPECT_EQ(none.kappa2, 0);
}

// A cloud sparser than the ball (a sphere of radius 2 in 2,000 points, about 0.17 apart,
// under a ball of 0.25 that holds fewer than 10 of them): the ball is widened to its 10
// nearest, and the curvature is still 1/2 (the paper's ball is a mesh's; a fit needs
// points).
TEST(PointCloud, ABallSparserThanAFitNeedsIsWidenedToItsNearestPoints) {
    const std::vector<Eigen::Vector3d> points = sphere_cloud(2.0, 2000);
    const PointCloudSurface cloud(points, estimate_point_normals(points));
    LocalFitOptions as_it_is;
    as_it_is.widened_ball_weight = 0;
    const double radius = 0.25;
    int sparse = 0;
    for (int i = 0; i < cloud.size(); i += 7) {
        int inside = 0;
        for (const Eigen::Vector3d& q : points) inside += (q - points[size_t(i)]).norm() <= radius;
        if (inside >= 10) continue;
        ++sparse;
        EXPECT_EQ(cloud.fit_signature(i, radius, as_it_is).kappa2, 0);
        const SurfaceSignature s = cloud.fit_signature(i, radius);
        expect_right_handed(s);
        EXPECT_NEAR(s.kappa1, 0.5, 0.03);
        EXPECT_NEAR(s.kappa2, 0.5, 0.03);
        EXPECT_GT(s.area, M_PI * radius * radius);
    }
    EXPECT_GT(sparse, 100);
}

// The bumpy sphere's radius in direction u.
double bumpy_radius(const Eigen::Vector3d& u) {
    return 1 + 0.35 * u.x() * u.x() + 0.2 * u.y() + 0.15 * u.z() * u.z() * u.z();
}

// A bumpy sphere r(u) = 1 + 0.35 x^2 + 0.2 y + 0.15 z^3 (u on the unit sphere), symmetric
// under x -> -x only, sampled at a Fibonacci lattice, which is not symmetric itself: the
// mirror image of a point is not a point of the cloud.
std::vector<Eigen::Vector3d> bumpy_cloud(int n) {
    std::vector<Eigen::Vector3d> points = sphere_cloud(1.0, n);
    for (Eigen::Vector3d& u : points) u *= bumpy_radius(u);
    return points;
}

// Points at a known height above a sphere of radius 2 (pointing away from it is positive):
// the distance to its discs is that height, up to the discs' sagitta rho^2 / (2 R).
TEST(PointCloud, TheDiscsOfASphereAreAtTheSpheresDistance) {
    const std::vector<Eigen::Vector3d> points = sphere_cloud(2.0, 20000);
    const std::vector<Eigen::Vector3d> normals = estimate_point_normals(points);
    const PointAreas areas = point_areas(points);
    const SurfaceQuery discs(points, normals, areas.disc_radius);
    const double rho = *std::max_element(areas.disc_radius.begin(), areas.disc_radius.end());
    const double sagitta = rho * rho / (2 * 2.0);
    double total_area = 0;
    for (double a : areas.area) total_area += a;
    EXPECT_NEAR(total_area / (4 * M_PI * 4), 1.0, 0.4);  // pi d_k^2 / k: the right order, not exact
    std::mt19937_64 rng(9);
    std::normal_distribution<double> gauss;
    for (int i = 0; i < 200; ++i) {
        const Eigen::Vector3d u = Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng)).normalized();
        const double height = 0.05 * (i % 5 - 2);
        const ClosestPoint c = discs.closest((2.0 + height) * u, 1.0);
        ASSERT_TRUE(c.found);
        EXPECT_NEAR(c.signed_distance, height, sagitta + 1e-3);
        // The nearest disc's centre may lie up to a disc radius away from u's direction.
        EXPECT_GT(c.normal.dot(u), std::cos(rho / 2.0 + 3 * M_PI / 180));
    }
    EXPECT_FALSE(discs.closest(Eigen::Vector3d(0, 0, 3), 0.5).found);
}

// Growth over the neighbour graph, landing on the discs: under the shape's mirror it covers
// the whole cloud from one seed.  A turn of 40 degrees about z is no symmetry of it, but
// near the poles, where x and y are small, it nearly is: growth covers part of the cloud,
// and only points whose image lies near the true surface (measured along the radius,
// which is longer than the distance where the surface slopes).
// Points at random on a box's surface, [0, 1] x [0, 0.8] x [0, 0.6], each face getting its
// share of `n` by area, as a scan samples it.
std::vector<Eigen::Vector3d> box_cloud(int n, std::mt19937_64& rng) {
    const Eigen::Vector3d size(1, 0.8, 0.6);
    const double total = 2 * (size.x() * size.y() + size.y() * size.z() + size.z() * size.x());
    std::uniform_real_distribution<double> unit(0, 1);
    std::vector<Eigen::Vector3d> points;
    for (int axis = 0; axis < 3; ++axis) {
        const int u = (axis + 1) % 3, v = (axis + 2) % 3;
        const int count = int(std::round(n * size[u] * size[v] / total));
        for (double side : {0.0, size[axis]})
            for (int k = 0; k < count; ++k) {
                Eigen::Vector3d p;
                p[axis] = side;
                p[u] = size[u] * unit(rng);
                p[v] = size[v] * unit(rng);
                points.push_back(p);
            }
    }
    return points;
}

TEST(PointCloud, TheSidesOfABoxSlideAlongItWithoutTheNormalsFittedAcrossItsEdges) {
    std::mt19937_64 rng(3);
    const std::vector<Eigen::Vector3d> points = box_cloud(6000, rng);
    const std::vector<Eigen::Vector3d> normals = estimate_point_normals(points);
    const PointAreas areas = point_areas(points);
    const MeshNeighbourhoods graph = cloud_neighbourhoods(points, normals, areas.area, 8);
    // The four sides, with their rims: the points at the caps' edges have a normal fitted
    // across the edge, tilted towards the length of the box.
    std::vector<int> sides;
    int tilted = 0;
    for (int i = 0; i < int(points.size()); ++i) {
        if (points[size_t(i)].x() <= 0 || points[size_t(i)].x() >= 1) continue;
        sides.push_back(i);
        tilted += std::abs(normals[size_t(i)].x()) > 0.2;
    }
    ASSERT_GT(tilted, 0);
    const double tolerance = 0.01 * std::sqrt(1 + 0.64 + 0.36);
    ContinuousFamilyOptions options;
    const ContinuousFamily family = slippable_family(graph, sides, tolerance, options);
    ASSERT_EQ(family.kind, ContinuousKind::Translational);
    EXPECT_GT(std::abs(family.direction.x()), 0.999);
    // With every point's normal counted, the tilted ones forbid the slide.
    options.cloud_edge_variation_floor = std::numeric_limits<double>::infinity();
    EXPECT_EQ(slippable_family(graph, sides, tolerance, options).kind, ContinuousKind::Discrete);
}

TEST(PointCloud, GrowthOverTheNeighbourGraphCoversTheMirrorOnly) {
    const std::vector<Eigen::Vector3d> points = bumpy_cloud(8000);
    const std::vector<Eigen::Vector3d> normals = estimate_point_normals(points);
    const PointAreas areas = point_areas(points);
    const MeshNeighbourhoods graph = cloud_neighbourhoods(points, normals, areas.area, 8);
    const SurfaceQuery discs(points, normals, areas.disc_radius);
    ASSERT_EQ(graph.component_areas.size(), 1u);
    const double diagonal = 2 * std::sqrt(3.0) * 1.3, tolerance = 0.01 * diagonal;
    Transformation mirror;
    mirror.reflection = true;  // M = diag(-1, 1, 1): the mirror x -> -x itself
    std::vector<char> scratch(points.size(), 0);
    {
        RegionGrower grower(graph, discs, {tolerance, 45});
        bool hopeless = false;
        Transformation T = mirror;
        const std::vector<int> patch = grower.grow(0, T, nullptr, nullptr, hopeless);
        EXPECT_EQ(patch.size(), points.size());
        EXPECT_NEAR(area_of(graph, patch, scratch), graph.component_areas[0], 1e-9);
        double worst = 0;
        for (int v : patch) worst = std::max(worst, std::abs(grower.deviation(v)));
        EXPECT_LT(worst, 0.2 * tolerance);
    }
    {
        RegionGrower grower(graph, discs, {tolerance, 45});
        bool hopeless = false;
        Transformation turn;
        turn.rotation = Eigen::AngleAxisd(40 * M_PI / 180, Eigen::Vector3d::UnitZ()).toRotationMatrix();
        size_t grown = 0;
        for (int seed = 0; seed < int(points.size()); seed += 97) {
            Transformation T = turn;
            for (int v : grower.grow(seed, T, nullptr, nullptr, hopeless)) {
                const Eigen::Vector3d image = turn.apply(points[size_t(v)]);
                EXPECT_LT(std::abs(image.norm() - bumpy_radius(image.normalized())), 1.5 * tolerance);
                ++grown;
            }
        }
        EXPECT_GT(grown, 0u);
        EXPECT_LT(grown, points.size() / 2);
    }
}

}  // namespace
}  // namespace symmetry
