#include "denoising.h"

#include <vcg/complex/algorithms/update/bounding.h>
#include <vcg/complex/algorithms/update/normal.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

namespace symmetry {

namespace {

// Two or three tight groups of face normals around v: a crease or a corner of a
// piecewise-flat surface, whose residual to any quadric says nothing about noise.
bool is_crease_or_corner(const MeshNeighbourhoods& mesh, int v, double side_cosine) {
    std::vector<Eigen::Vector3d> sides;
    for (int k = mesh.face_offsets[v]; k < mesh.face_offsets[v + 1]; ++k) {
        const Eigen::Vector3d& n = mesh.face_normals[size_t(mesh.faces_around[size_t(k)])];
        bool grouped = false;
        for (const auto& s : sides)
            if (s.dot(n) >= side_cosine) { grouped = true; break; }
        if (!grouped) sides.push_back(n);
        if (sides.size() > 3) return false;
    }
    return sides.size() >= 2;
}

// v's neighbours and their neighbours (v included), without repeats.
std::vector<int> two_ring(const MeshNeighbourhoods& mesh, int v, std::vector<int>& stamp) {
    std::vector<int> ring{v};
    stamp[size_t(v)] = v;
    for (size_t i = 0; i < ring.size() && i < 1 + size_t(mesh.neighbour_offsets[v + 1] - mesh.neighbour_offsets[v]); ++i)
        for (int k = mesh.neighbour_offsets[ring[i]]; k < mesh.neighbour_offsets[ring[i] + 1]; ++k) {
            int u = mesh.neighbours[size_t(k)];
            if (stamp[size_t(u)] != v) { stamp[size_t(u)] = v; ring.push_back(u); }
        }
    return ring;
}

// The signed residual at v itself of z = a x² + b xy + c y² + d x + e y + f, fitted by
// least squares to the two-ring in the frame of the area-weighted normal at v.  NaN where
// there is no normal.
double centre_residual(const MeshNeighbourhoods& mesh, int v, const std::vector<int>& ring) {
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();
    for (int k = mesh.face_offsets[v]; k < mesh.face_offsets[v + 1]; ++k) {
        int f = mesh.faces_around[size_t(k)];
        normal += mesh.face_areas[size_t(f)] * mesh.face_normals[size_t(f)];
    }
    if (!(normal.norm() > 0)) return NAN;
    normal.normalize();
    Eigen::Vector3d helper = std::abs(normal.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
    Eigen::Vector3d t1 = normal.cross(helper).normalized(), t2 = normal.cross(t1);
    Eigen::Matrix<double, 6, 6> AtA = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> Atz = Eigen::Matrix<double, 6, 1>::Zero();
    for (int u : ring) {
        Eigen::Vector3d q = mesh.positions[size_t(u)] - mesh.positions[size_t(v)];
        double x = q.dot(t1), y = q.dot(t2);
        Eigen::Matrix<double, 6, 1> row;
        row << x * x, x * y, y * y, x, y, 1;
        AtA += row * row.transpose();
        Atz += row * q.dot(normal);
    }
    Eigen::Matrix<double, 6, 1> c = AtA.ldlt().solve(Atz);
    return c.allFinite() ? -c(5) : NAN;  // z(v) = 0, the fit there is c(5)
}

// Mean, shortest and longest distance to the neighbours.
struct EdgeLengths {
    double mean = 0, shortest = INFINITY, longest = 0;
};
EdgeLengths edge_lengths(const MeshNeighbourhoods& mesh, int v) {
    EdgeLengths e;
    int count = 0;
    for (int k = mesh.neighbour_offsets[v]; k < mesh.neighbour_offsets[v + 1]; ++k, ++count) {
        double d = (mesh.positions[size_t(mesh.neighbours[size_t(k)])] - mesh.positions[size_t(v)]).norm();
        e.mean += d;
        e.shortest = std::min(e.shortest, d);
        e.longest = std::max(e.longest, d);
    }
    if (count) e.mean /= count;
    return e;
}

}  // namespace

Roughness::Roughness(const MeshNeighbourhoods& mesh, const DenoisingOptions& options)
    : mesh_(mesh), options_(options), side_cosine_(std::cos(options.crease_side_degrees * M_PI / 180.0)),
      stamp_(size_t(mesh.vertex_count()), -1), residual_(size_t(mesh.vertex_count()), NAN),
      edge_(size_t(mesh.vertex_count()), -1) {}

void Roughness::measure(int v) {
    if (edge_[size_t(v)] >= 0) return;
    const EdgeLengths e = edge_lengths(mesh_, v);
    edge_[size_t(v)] = e.mean;
    if (!(e.mean > 0) || e.longest > options_.max_edge_ratio * e.shortest || is_crease_or_corner(mesh_, v, side_cosine_))
        return;
    std::vector<int> ring = two_ring(mesh_, v, stamp_);
    if (ring.size() >= 10) residual_[size_t(v)] = centre_residual(mesh_, v, ring);  // fewer cannot tell noise from shape
}

double Roughness::edge_at(int v) {
    measure(v);
    return edge_[size_t(v)];
}

double Roughness::at(int v) {
    measure(v);
    if (std::isnan(residual_[size_t(v)])) return NAN;
    double sum = 0;
    int count = 0;
    for (int k = mesh_.neighbour_offsets[v]; k < mesh_.neighbour_offsets[v + 1]; ++k) {
        const int u = mesh_.neighbours[size_t(k)];
        measure(u);
        if (!std::isnan(residual_[size_t(u)])) { sum += residual_[size_t(u)]; ++count; }
    }
    if (count < 3) return NAN;
    return std::abs(residual_[size_t(v)] - sum / count) / edge_[size_t(v)];
}

NoiseEstimate estimate_noise(const MeshNeighbourhoods& mesh, const DenoisingOptions& options) {
    NoiseEstimate estimate;
    const int nv = mesh.vertex_count();
    if (nv == 0) return estimate;
    const int stride = std::max(1, nv / std::max(1, options.max_vertices_measured));
    Roughness roughness(mesh, options);
    std::vector<double> measured;
    double edge_sum = 0;
    int edge_count = 0;
    for (int v = 0; v < nv; v += stride) {
        const double r = roughness.at(v), e = roughness.edge_at(v);
        if (e > 0) { edge_sum += e; ++edge_count; }
        if (!std::isnan(r)) measured.push_back(r);
    }
    if (edge_count) estimate.edge_length = edge_sum / edge_count;
    estimate.vertices_measured = int(measured.size());
    if (measured.empty()) return estimate;
    size_t k = std::min(measured.size() - 1, size_t(options.noise_quantile * double(measured.size())));
    std::nth_element(measured.begin(), measured.begin() + long(k), measured.end());
    estimate.noise = measured[k] * estimate.edge_length;
    return estimate;
}

double smoothing_radius(const NoiseEstimate& estimate, const DenoisingOptions& options) {
    if (estimate.noise_in_edges() < options.noise_threshold_in_edges) return 0;
    return options.smoothing_radius_factor * std::sqrt(estimate.noise * estimate.edge_length);
}

int smooth_positions(Mesh& mesh, double radius, const DenoisingOptions& options) {
    const size_t nv = mesh.vert.size();
    if (!(radius > 0) || nv == 0) return 0;
    // Neighbours a vertex averages over: all of them inside, the border ones on the border.
    std::vector<std::vector<int>> all(nv), border(nv);
    for (const Face& f : mesh.face) {
        if (f.IsD()) continue;
        for (int k = 0; k < 3; ++k) {
            int a = int(vcg::tri::Index(mesh, f.cV0(k))), b = int(vcg::tri::Index(mesh, f.cV1(k)));
            all[size_t(a)].push_back(b);
            all[size_t(b)].push_back(a);
            if (f.cFFp(k) == &f) {
                border[size_t(a)].push_back(b);
                border[size_t(b)].push_back(a);
            }
        }
    }
    std::vector<Eigen::Vector3d> x(nv), next(nv);
    for (size_t v = 0; v < nv; ++v) x[v] = Eigen::Vector3d(mesh.vert[v].cP()[0], mesh.vert[v].cP()[1], mesh.vert[v].cP()[2]);
    std::vector<double> h2(nv, 0);
    std::vector<double> sorted;
    for (size_t v = 0; v < nv; ++v) {
        if (!border[v].empty()) all[v] = border[v];
        for (int u : all[v]) h2[v] += (x[size_t(u)] - x[v]).squaredNorm();
        if (!all[v].empty()) h2[v] /= double(all[v].size());
        if (h2[v] > 0) sorted.push_back(h2[v]);
    }
    if (sorted.empty()) return 0;
    // The step is set by the finer vertices (a tenth are finer still and move at the
    // stability limit, a little slower than the rest).
    std::nth_element(sorted.begin(), sorted.begin() + long(sorted.size() / 10), sorted.end());
    const double h2_ref = sorted[sorted.size() / 10];
    const double dt = h2_ref / 8;  // the umbrella operator is about h²/4 times the Laplacian
    const int steps = std::min(options.max_smoothing_steps, int(std::ceil(0.5 * radius * radius / dt)));
    for (int s = 0; s < steps; ++s) {
        for (size_t v = 0; v < nv; ++v) {
            next[v] = x[v];
            if (all[v].empty() || !(h2[v] > 0)) continue;
            Eigen::Vector3d mean = Eigen::Vector3d::Zero();
            for (int u : all[v]) mean += x[size_t(u)];
            mean /= double(all[v].size());
            const double rate = std::min(0.5, 4 * dt / h2[v]);
            next[v] += rate * (mean - x[v]);
        }
        x.swap(next);
    }
    for (size_t v = 0; v < nv; ++v) mesh.vert[v].P() = vcg::Point3d(x[v].x(), x[v].y(), x[v].z());
    vcg::tri::UpdateBounding<Mesh>::Box(mesh);
    vcg::tri::UpdateNormal<Mesh>::PerFaceNormalized(mesh);
    vcg::tri::UpdateNormal<Mesh>::PerVertexAngleWeighted(mesh);
    vcg::tri::UpdateNormal<Mesh>::NormalizePerVertex(mesh);
    return steps;
}

}  // namespace symmetry
