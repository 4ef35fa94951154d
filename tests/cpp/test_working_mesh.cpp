// The working resolution: a simplified copy that keeps the shape and its components, and
// the map from every input vertex to the nearest vertex of the copy (against brute force).
#include "core/working_mesh.h"
#include "test_shapes.h"

#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <random>

namespace symmetry {
namespace {

std::unique_ptr<Mesh> mesh_of(const testing::Shape& s) {
    auto mesh = std::make_unique<Mesh>();
    std::vector<int> map;
    build_mesh(s.V, s.F, *mesh, map);
    return mesh;
}

TEST(WorkingMesh, SimplifiesToTheTargetAndKeepsTheShape) {
    // A sphere of radius 1 with 10,242 vertices, simplified to 2,000.
    const auto input_mesh = mesh_of(testing::sphere(1.0, 5));
    const Mesh& input = *input_mesh;
    ASSERT_GT(input.vn, 10000);
    for (int min_faces_to_halve : {1 << 30, 0}) {  // simplified whole, then in halves
        WorkingMeshOptions options;
        options.min_faces_to_halve = min_faces_to_halve;
        const auto copy = simplified_copy(input, 2000, options);
        EXPECT_NEAR(copy->vn, 2000, 100);
        EXPECT_EQ(copy->fn, 2 * copy->vn - 4);  // still one closed genus-0 surface (Euler)
        // Every vertex of the copy stays near the sphere (quadric collapse keeps it within a
        // small fraction of the edge length), and so does the area.
        for (const auto& v : copy->vert) EXPECT_NEAR(v.cP().Norm(), 1.0, 0.01);
        EXPECT_NEAR(surface_area(*copy), surface_area(input), 0.01 * surface_area(input));
    }
}

// Faces per edge, each edge keyed by its two vertices.
std::map<std::pair<const Vertex*, const Vertex*>, int> faces_at_edges(const Mesh& mesh) {
    std::map<std::pair<const Vertex*, const Vertex*>, int> faces;
    for (const Face& f : mesh.face)
        for (int k = 0; k < 3; ++k) {
            const Vertex* a = f.cV(k);
            const Vertex* b = f.cV((k + 1) % 3);
            ++faces[{std::min(a, b), std::max(a, b)}];
        }
    return faces;
}

TEST(WorkingMesh, ARefinedCopyIsTheSameSurfaceWithShortEdges) {
    // A box as CAD exports it (twelve triangles, long thin ones on its long faces) and a
    // coarse prism: refined, every edge is at most the length asked, the copy is closed (the
    // midpoints are shared by the faces on each edge), every input vertex is in it, and its
    // surface is the input's: the same area, every vertex on a face of the box.
    const testing::Shape box = testing::box(2.0, 0.2, 0.1, 1);
    const auto input = mesh_of(box);
    const double max_edge = 0.05;
    const auto copy = refined_copy(*input, max_edge);
    EXPECT_EQ(copy->fn, 2 * copy->vn - 4);  // one closed genus-0 surface (Euler)
    for (const auto& [edge, faces] : faces_at_edges(*copy)) {
        EXPECT_EQ(faces, 2);
        EXPECT_LE((edge.first->cP() - edge.second->cP()).Norm(), max_edge * (1 + 1e-12));
    }
    EXPECT_NEAR(surface_area(*copy), surface_area(*input), 1e-9 * surface_area(*input));
    for (const auto& v : copy->vert) {
        const vcg::Point3d p = v.cP();
        const double out = std::max({std::abs(p[0]) - 2.0, std::abs(p[1]) - 0.2, std::abs(p[2]) - 0.1});
        EXPECT_NEAR(out, 0.0, 1e-12);  // on the box's boundary
    }
    const std::vector<int> nearest = nearest_vertices(*input, *copy);
    for (size_t i = 0; i < input->vert.size(); ++i)
        EXPECT_EQ(copy->vert[size_t(nearest[i])].cP(), input->vert[i].cP());
}

TEST(WorkingMesh, ARefinedCopyStaysConformingAtNonManifoldEdges) {
    // Three squares on one edge (a fin): every face on the edge gets its one midpoint.
    Eigen::MatrixX3d V(8, 3);
    V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 0, -1, 0, 1, -1, 0, 0, 0, 1, 1, 0, 1;
    Eigen::MatrixX3i F(6, 3);
    F << 0, 1, 3, 0, 3, 2, 1, 0, 4, 1, 4, 5, 0, 1, 7, 0, 7, 6;
    Mesh input;
    std::vector<int> rows;
    build_mesh(V, F, input, rows);
    const auto copy = refined_copy(input, 0.3);
    int fin = 0;
    for (const auto& [edge, faces] : faces_at_edges(*copy)) {
        EXPECT_LE(faces, 3);
        fin += faces == 3 && std::abs(edge.first->cP()[1]) < 1e-12 && std::abs(edge.second->cP()[1]) < 1e-12 &&
               std::abs(edge.first->cP()[2]) < 1e-12 && std::abs(edge.second->cP()[2]) < 1e-12;
    }
    EXPECT_GE(fin, 4);  // the fin's edge of length 1 in pieces of at most 0.3, each on three faces
    EXPECT_NEAR(surface_area(*copy), 3.0, 1e-9);
}

TEST(WorkingMesh, ARefinedCopyWithinABudgetGrowsItsEdges) {
    const auto input = mesh_of(testing::box(1.0, 1.0, 1.0, 1));
    WorkingMeshOptions options;
    options.max_refined_vertices = 3000;
    const auto unbounded = refined_copy(*input, 0.02);
    ASSERT_GT(unbounded->vn, 3000);
    const auto copy = refined_copy_within(*input, 0.02, options);
    EXPECT_LE(copy->vn, 3000);
    EXPECT_GT(copy->vn, 300);  // not coarser than it needs to be
}

TEST(WorkingMesh, TheCutBetweenTheHalvesIsClosedAndSimplified) {
    // The copy is simplified as two halves cut across the sphere, the cut held, then joined
    // and the strip along the cut simplified.  The cut must leave no border (every edge
    // between two faces) and no strip at the input's resolution: the band 0.04 wide around
    // each coordinate plane holds 2 % of the sphere's area, so about 40 of the copy's
    // vertices (26-41 measured).  The input's band holds about 340, and the band at the cut
    // held 128 when the halves spent their share of the target away from it.
    const auto input_mesh = mesh_of(testing::sphere(1.0, 5));
    WorkingMeshOptions halved;
    halved.min_faces_to_halve = 0;  // the sphere's 20,480 faces would be simplified whole
    const auto copy = simplified_copy(*input_mesh, 2000, halved);
    std::map<std::pair<const Vertex*, const Vertex*>, int> faces_at_edge;
    for (const Face& f : copy->face)
        for (int k = 0; k < 3; ++k) {
            const Vertex* a = f.cV(k);
            const Vertex* b = f.cV((k + 1) % 3);
            ++faces_at_edge[{std::min(a, b), std::max(a, b)}];
        }
    for (const auto& edge : faces_at_edge) EXPECT_EQ(edge.second, 2);
    for (int axis = 0; axis < 3; ++axis) {
        int in_band = 0;
        for (const auto& v : copy->vert) in_band += std::abs(v.cP()[axis]) < 0.02;
        EXPECT_LT(in_band, 2 * 0.02 * copy->vn) << "axis " << axis;
    }
}

TEST(WorkingMesh, TheHalvedCopyIsTheSameAtAnyThreadCount) {
    // The halves are simplified on two threads at once, or one after the other: the copy must
    // be the same, vertex for vertex and face for face.
    const auto input_mesh = mesh_of(testing::sphere(1.0, 5));
    WorkingMeshOptions halved;
    halved.min_faces_to_halve = 0;
    const int threads = omp_get_max_threads();
    omp_set_num_threads(1);
    const auto one = simplified_copy(*input_mesh, 2000, halved);
    omp_set_num_threads(2);
    const auto two = simplified_copy(*input_mesh, 2000, halved);
    omp_set_num_threads(threads);
    ASSERT_EQ(one->vert.size(), two->vert.size());
    ASSERT_EQ(one->face.size(), two->face.size());
    for (size_t i = 0; i < one->vert.size(); ++i) EXPECT_EQ(one->vert[i].cP(), two->vert[i].cP());
    for (size_t f = 0; f < one->face.size(); ++f)
        for (int k = 0; k < 3; ++k)
            EXPECT_EQ(vcg::tri::Index(*one, one->face[f].cV(k)), vcg::tri::Index(*two, two->face[f].cV(k)));
}

TEST(WorkingMesh, KeepsSeparateComponents) {
    // Two tori apart: the copy has two components of about equal size (topology preserved).
    const testing::Shape a = testing::torus(1.0, 0.3, 96, 48);
    const testing::Shape b = testing::transformed(a, Eigen::Matrix3d::Identity(), Eigen::Vector3d(4, 0, 0));
    const auto input_mesh = mesh_of(testing::merged(a, b));
    const Mesh& input = *input_mesh;
    for (int min_faces_to_halve : {1 << 30, 0}) {  // simplified whole, then in halves
        WorkingMeshOptions options;
        options.min_faces_to_halve = min_faces_to_halve;
        const auto copy = simplified_copy(input, 1500, options);
        int left = 0, right = 0;
        for (const auto& v : copy->vert) (v.cP()[0] < 2 ? left : right)++;
        EXPECT_NEAR(left, right, 0.1 * (left + right));
        EXPECT_EQ(copy->fn, copy->vn * 2);  // two closed genus-1 surfaces (Euler: V - E + F = 0 each)
    }
}

TEST(WorkingMesh, NearestVerticesAgreeWithBruteForce) {
    const auto input_mesh = mesh_of(testing::sphere(1.0, 4));
    const Mesh& input = *input_mesh;
    const auto copy = simplified_copy(input, 600, WorkingMeshOptions{});
    const std::vector<int> nearest = nearest_vertices(input, *copy);
    ASSERT_EQ(nearest.size(), input.vert.size());
    for (size_t i = 0; i < input.vert.size(); i += 7) {
        double best = std::numeric_limits<double>::max();
        for (const auto& w : copy->vert) best = std::min(best, (w.cP() - input.vert[i].cP()).Norm());
        EXPECT_DOUBLE_EQ((copy->vert[size_t(nearest[i])].cP() - input.vert[i].cP()).Norm(), best);
    }
}

}  // namespace
}  // namespace symmetry

namespace symmetry {
namespace {

// A cloud of `n` points drawn uniformly at random on the unit sphere: clumps and gaps, as a
// scan's points have.
void random_sphere_cloud(int n, unsigned seed, Mesh& cloud) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> gauss;
    vcg::tri::Allocator<Mesh>::AddVertices(cloud, size_t(n));
    for (Vertex& v : cloud.vert) {
        Eigen::Vector3d p(gauss(rng), gauss(rng), gauss(rng));
        p.normalize();
        v.P() = vcg::Point3d(p.x(), p.y(), p.z());
    }
}

TEST(WorkingCloud, APoissonDiskSubsetHasTheTargetCountAndSpreadsEvenly) {
    Mesh cloud;
    random_sphere_cloud(20000, 7, cloud);
    const int target = 3000;
    const WorkingMeshOptions options;
    const std::vector<int> kept = poisson_disk_subset(cloud, target, 4 * M_PI, 0, options);
    EXPECT_NEAR(double(kept.size()), target, options.poisson_count_tolerance * target);
    ASSERT_TRUE(std::is_sorted(kept.begin(), kept.end()));
    EXPECT_EQ(kept, poisson_disk_subset(cloud, target, 4 * M_PI, 0, options));  // the same for a seed
    // Evenly: the spacing of `target` points on the sphere in a hexagonal pattern, against
    // the subset's closest pair and the largest gap any input point sees (brute force).
    const double spacing = std::sqrt(4 * M_PI / target / (std::sqrt(3.0) / 2));
    auto position = [&](int i) { return Eigen::Vector3d(cloud.vert[size_t(i)].cP()[0], cloud.vert[size_t(i)].cP()[1],
                                                        cloud.vert[size_t(i)].cP()[2]); };
    double closest_pair = 1e9, largest_gap = 0;
    for (size_t a = 0; a < kept.size(); ++a)
        for (size_t b = a + 1; b < kept.size(); ++b)
            closest_pair = std::min(closest_pair, (position(kept[a]) - position(kept[b])).norm());
    for (int i = 0; i < cloud.vn; i += 7) {
        double nearest = 1e9;
        for (int k : kept) nearest = std::min(nearest, (position(i) - position(k)).norm());
        largest_gap = std::max(largest_gap, nearest);
    }
    EXPECT_GT(closest_pair, 0.5 * spacing);  // a random subset's closest pair: about 0.02 of it
    EXPECT_LT(largest_gap, 1.0 * spacing);
}

}  // namespace
}  // namespace symmetry
