#include "region_growing.h"

#include "point_cloud.h"
#include "statistics.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <deque>
#include <numeric>

namespace symmetry {

namespace {
// Faces within this fraction of the tolerance of the nearest one are as near as it.
constexpr double kTie = 1e-3;

Eigen::Vector3d to_eigen(const vcg::Point3d& p) { return {p[0], p[1], p[2]}; }

// Compressed rows from per-vertex lists, each list sorted and without repeats.
void compress(std::vector<std::vector<int>>& lists, std::vector<int>& offsets, std::vector<int>& items) {
    offsets.assign(1, 0);
    offsets.reserve(lists.size() + 1);
    for (auto& l : lists) {
        std::sort(l.begin(), l.end());
        l.erase(std::unique(l.begin(), l.end()), l.end());
        items.insert(items.end(), l.begin(), l.end());
        offsets.push_back(int(items.size()));
    }
}
}  // namespace

namespace {
// Breadth-first labelling of the connected components, with their vertices and areas.
void label_components(MeshNeighbourhoods& n) {
    const int nv = n.vertex_count();
    n.component_of.assign(size_t(nv), -1);
    n.member_offsets.assign(1, 0);
    n.members.clear();
    n.members.reserve(size_t(nv));
    for (int start = 0; start < nv; ++start) {
        if (n.component_of[size_t(start)] >= 0) continue;
        const int c = int(n.member_offsets.size()) - 1;
        n.component_of[size_t(start)] = c;
        size_t first = n.members.size();
        n.members.push_back(start);
        for (size_t i = first; i < n.members.size(); ++i)
            for (int k = n.neighbour_offsets[n.members[i]]; k < n.neighbour_offsets[n.members[i] + 1]; ++k) {
                const int u = n.neighbours[size_t(k)];
                if (n.component_of[size_t(u)] < 0) { n.component_of[size_t(u)] = c; n.members.push_back(u); }
            }
        n.member_offsets.push_back(int(n.members.size()));
    }
    n.component_areas.assign(n.member_offsets.size() - 1, 0.0);
    for (size_t f = 0; f < n.faces.size(); ++f)
        if (n.faces[f][0] >= 0) n.component_areas[size_t(n.component_of[size_t(n.faces[f][0])])] += n.face_areas[f];
}

}  // namespace

MeshNeighbourhoods mesh_neighbourhoods(const Mesh& mesh) {
    MeshNeighbourhoods n;
    const size_t nv = mesh.vert.size();
    n.positions.resize(nv);
    for (size_t v = 0; v < nv; ++v) n.positions[v] = to_eigen(mesh.vert[v].cP());
    std::vector<std::vector<int>> around(nv), faces_of(nv);
    n.faces.assign(mesh.face.size(), {-1, -1, -1});
    n.face_normals.assign(mesh.face.size(), Eigen::Vector3d::Zero());
    n.face_areas.assign(mesh.face.size(), 0.0);
    for (size_t f = 0; f < mesh.face.size(); ++f) {
        const Face& face = mesh.face[f];
        if (face.IsD()) continue;
        for (int k = 0; k < 3; ++k) n.faces[f][k] = int(vcg::tri::Index(mesh, face.cV(k)));
        const auto& c = n.faces[f];
        Eigen::Vector3d cross = (n.positions[c[1]] - n.positions[c[0]]).cross(n.positions[c[2]] - n.positions[c[0]]);
        n.face_areas[f] = 0.5 * cross.norm();
        if (n.face_areas[f] > 0) n.face_normals[f] = cross.normalized();
        for (int k = 0; k < 3; ++k) {
            around[c[k]].push_back(c[(k + 1) % 3]);
            around[c[k]].push_back(c[(k + 2) % 3]);
            faces_of[c[k]].push_back(int(f));
        }
    }
    n.vertex_areas.assign(nv, 0.0);
    for (size_t f = 0; f < n.faces.size(); ++f)
        if (n.faces[f][0] >= 0)
            for (int v : n.faces[f]) n.vertex_areas[size_t(v)] += n.face_areas[f] / 3;
    compress(around, n.neighbour_offsets, n.neighbours);
    compress(faces_of, n.face_offsets, n.faces_around);
    label_components(n);
    n.component_open.assign(n.component_areas.size(), 0);
    for (size_t f = 0; f < mesh.face.size(); ++f) {
        const Face& face = mesh.face[f];
        if (face.IsD()) continue;
        for (int k = 0; k < 3; ++k)
            if (face.cFFp(k) == &face) n.component_open[size_t(n.component_of[size_t(n.faces[f][0])])] = 1;
    }
    return n;
}

namespace {
// The surface variation of every point over itself and its neighbours in the graph (see
// MeshNeighbourhoods::surface_variation).
std::vector<double> surface_variations(const MeshNeighbourhoods& n) {
    std::vector<double> out(n.positions.size(), 0.0);
    for (int i = 0; i < n.vertex_count(); ++i) {
        const int first = n.neighbour_offsets[size_t(i)], last = n.neighbour_offsets[size_t(i) + 1];
        Eigen::Vector3d mean = n.positions[size_t(i)];
        for (int k = first; k < last; ++k) mean += n.positions[size_t(n.neighbours[size_t(k)])];
        mean /= double(last - first + 1);
        Eigen::Matrix3d covariance = (n.positions[size_t(i)] - mean) * (n.positions[size_t(i)] - mean).transpose();
        for (int k = first; k < last; ++k) {
            const Eigen::Vector3d d = n.positions[size_t(n.neighbours[size_t(k)])] - mean;
            covariance += d * d.transpose();
        }
        const Eigen::Vector3d lambda = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(covariance, Eigen::EigenvaluesOnly).eigenvalues();
        const double sum = lambda.sum();
        out[size_t(i)] = sum > 0 ? std::max(0.0, lambda[0]) / sum : 0.0;
    }
    return out;
}
}  // namespace

MeshNeighbourhoods cloud_neighbourhoods(const std::vector<Eigen::Vector3d>& points,
                                        const std::vector<Eigen::Vector3d>& normals,
                                        const std::vector<double>& areas, int neighbours) {
    MeshNeighbourhoods n;
    n.positions = points;
    neighbour_graph(points, neighbours, n.neighbour_offsets, n.neighbours);
    const int count = int(points.size());
    n.faces.resize(size_t(count));
    n.face_offsets.resize(size_t(count) + 1);
    n.faces_around.resize(size_t(count));
    for (int i = 0; i < count; ++i) {
        n.faces[size_t(i)] = {i, i, i};
        n.face_offsets[size_t(i)] = i;
        n.faces_around[size_t(i)] = i;
    }
    n.face_offsets[size_t(count)] = count;
    n.face_normals = normals;
    n.face_areas = areas;
    n.vertex_areas = areas;
    label_components(n);
    n.component_open.assign(n.component_areas.size(), 0);
    n.surface_variation = surface_variations(n);
    n.median_surface_variation = median(n.surface_variation);
    return n;
}

std::vector<char> components_beyond_debris(const MeshNeighbourhoods& mesh, const DebrisRule& debris) {
    std::vector<char> counted(mesh.component_areas.size(), 1);
    if (debris.area_share <= 0 || counted.size() < 2) return counted;
    std::vector<int> smallest_first(counted.size());
    std::iota(smallest_first.begin(), smallest_first.end(), 0);
    std::stable_sort(smallest_first.begin(), smallest_first.end(),
                     [&](int a, int b) { return mesh.component_areas[size_t(a)] < mesh.component_areas[size_t(b)]; });
    const double total = std::accumulate(mesh.component_areas.begin(), mesh.component_areas.end(), 0.0);
    double dropped = 0;
    for (int c : smallest_first) {
        const double area = mesh.component_areas[size_t(c)];
        if (area >= debris.max_component_area || dropped + area > debris.area_share * total) break;
        dropped += area;
        counted[size_t(c)] = 0;
    }
    // A mesh of nothing but specks has no surface to prefer: count them all.
    if (std::none_of(counted.begin(), counted.end(), [](char k) { return k != 0; })) counted.assign(counted.size(), 1);
    return counted;
}

// Counted per edge, three thousand specks would outvote a surface of two thousand edges,
// and a curvature ball sized from their edges would see single facets of the surface.
double median_edge_length(const MeshNeighbourhoods& mesh, const DebrisRule& debris) {
    const std::vector<char> counted = components_beyond_debris(mesh, debris);
    std::vector<double> lengths;
    lengths.reserve(mesh.neighbours.size() / 2);
    for (int v = 0; v < mesh.vertex_count(); ++v) {
        if (!counted[size_t(mesh.component_of[size_t(v)])]) continue;
        for (int k = mesh.neighbour_offsets[v]; k < mesh.neighbour_offsets[v + 1]; ++k)
            if (mesh.neighbours[size_t(k)] > v)
                lengths.push_back((mesh.positions[size_t(mesh.neighbours[size_t(k)])] - mesh.positions[size_t(v)]).norm());
    }
    return median(std::move(lengths));
}

double patch_area(const MeshNeighbourhoods& mesh, const std::vector<int>& vertices, const std::vector<char>& member) {
    double area = 0;
    for (int v : vertices)
        for (int k = mesh.face_offsets[v]; k < mesh.face_offsets[v + 1]; ++k) {
            const auto& c = mesh.faces[size_t(mesh.faces_around[k])];
            // Each face is counted once, from its first corner.
            if (c[0] == v && member[size_t(c[1])] && member[size_t(c[2])]) area += mesh.face_areas[size_t(mesh.faces_around[k])];
        }
    return area;
}

double area_of(const MeshNeighbourhoods& mesh, const std::vector<int>& vertices, std::vector<char>& scratch) {
    for (int v : vertices) scratch[size_t(v)] = 1;
    const double area = patch_area(mesh, vertices, scratch);
    for (int v : vertices) scratch[size_t(v)] = 0;
    return area;
}

RegionGrower::RegionGrower(const MeshNeighbourhoods& mesh, const SurfaceQuery& surface,
                           const RegionGrowingOptions& options)
    : mesh_(mesh), surface_(surface), tolerance_(options.tolerance),
      min_normal_cosine_(std::cos(options.normal_agreement_degrees * M_PI / 180.0)),
      state_(size_t(mesh.vertex_count()), kUntried), deviation_(size_t(mesh.vertex_count()), 0.0),
      landing_face_(size_t(mesh.vertex_count()), -1),
      any_open_(any_open_component(mesh)) {}

ClosestPoint facing_landing(const MeshNeighbourhoods& mesh, const SurfaceQuery& surface, int v,
                            const Transformation& T, double max_distance, double min_normal_cosine, bool any_open,
                            std::vector<Eigen::Vector3d>& normals) {
    // The images of the normals of the faces around v: T(v) must land on a face that
    // agrees with one of them.
    normals.clear();
    for (int k = mesh.face_offsets[v]; k < mesh.face_offsets[v + 1]; ++k)
        normals.push_back(T.apply_to_normal(mesh.face_normals[size_t(mesh.faces_around[size_t(k)])]));
    const Eigen::Vector3d image = T.apply(mesh.positions[size_t(v)]);
    // Among the faces as near as the nearest one (they meet there: a crease, or separate
    // parts touching), one whose normal agrees.  Only as near: a farther face that agrees
    // (the other side of a thin plate) is not where T(v) lands.
    const SurfaceQuery::Landing landing =
        surface.landing(image, max_distance, kTie * max_distance, normals, min_normal_cosine);
    if (!landing.nearest.found) return ClosestPoint{};
    // An open surface (a sheet) may face either way: the other sign counts too.
    return landing.facing.found || !any_open ? landing.facing : landing.facing_either_sign;
}

bool any_open_component(const MeshNeighbourhoods& mesh) {
    return std::any_of(mesh.component_open.begin(), mesh.component_open.end(), [](char o) { return o != 0; });
}

bool RegionGrower::accepts(int v, const Transformation& T, const std::vector<char>* allowed_faces) {
    const ClosestPoint cp = facing_landing(mesh_, surface_, v, T, tolerance_, min_normal_cosine_, any_open_, normals_);
    if (!cp.found) return false;
    if (allowed_faces && !(*allowed_faces)[size_t(cp.face)]) return false;
    deviation_[size_t(v)] = cp.signed_distance;
    landing_face_[size_t(v)] = cp.face;
    return true;
}

std::vector<int> RegionGrower::grow(int seed, Transformation& T, const std::vector<char>* allowed_faces,
                                    const Refit& refit, bool& hopeless) {
    hopeless = false;
    std::vector<int> patch;
    if (state_[size_t(seed)] != kUntried) return patch;
    if (!accepts(seed, T, allowed_faces)) {
        state_[size_t(seed)] = kRejected;
        return patch;
    }
    std::deque<int> queue{seed};
    std::vector<int> rejected;  // the border, retried after a refit
    state_[size_t(seed)] = kInPatch;
    patch.push_back(seed);
    size_t next_refit = 1;
    auto admit = [&](int u) {
        state_[size_t(u)] = kInPatch;
        patch.push_back(u);
        queue.push_back(u);
    };
    while (!queue.empty()) {
        const int v = queue.front();
        queue.pop_front();
        for (int k = mesh_.neighbour_offsets[v]; k < mesh_.neighbour_offsets[v + 1]; ++k) {
            const int u = mesh_.neighbours[size_t(k)];
            if (state_[size_t(u)] != kUntried) continue;
            if (accepts(u, T, allowed_faces)) {
                admit(u);
            } else {
                state_[size_t(u)] = kRejected;
                rejected.push_back(u);
            }
        }
        if (!refit || patch.size() < 2 * next_refit) continue;
        next_refit = patch.size();
        RefitOutcome outcome = refit(patch, T);
        if (outcome == RefitOutcome::Hopeless) {
            hopeless = true;
            return patch;
        }
        if (outcome != RefitOutcome::Refitted) continue;
        // The border rejected under the old transformation may match now.
        std::vector<int> still_rejected;
        for (int u : rejected) {
            if (state_[size_t(u)] != kRejected) continue;
            if (accepts(u, T, allowed_faces)) admit(u);
            else still_rejected.push_back(u);
        }
        rejected.swap(still_rejected);
    }
    return patch;
}

void RegionGrower::forbid(const std::vector<int>& patch) {
    for (int v : patch) state_[size_t(v)] = kRejected;
}

}  // namespace symmetry
