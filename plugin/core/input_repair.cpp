#include "input_repair.h"

#include <vcg/complex/algorithms/clean.h>
#include <vcg/complex/algorithms/update/topology.h>

#include <algorithm>
#include <array>
#include <numeric>

namespace symmetry {

bool is_triangle_soup(const Eigen::MatrixX3i& F, Eigen::Index vertex_count) {
    std::vector<int> faces_at(size_t(vertex_count), 0);
    for (Eigen::Index f = 0; f < F.rows(); ++f)
        for (int k = 0; k < 3; ++k) ++faces_at[size_t(F(f, k))];
    Eigen::Index alone = 0;
    for (Eigen::Index f = 0; f < F.rows(); ++f)
        alone += faces_at[size_t(F(f, 0))] == 1 && faces_at[size_t(F(f, 1))] == 1 && faces_at[size_t(F(f, 2))] == 1;
    return 2 * alone > F.rows();
}

std::vector<int> rows_at_same_position(const Eigen::MatrixX3d& V) {
    std::vector<int> order(size_t(V.rows()));
    std::iota(order.begin(), order.end(), 0);
    auto less = [&V](int a, int b) {
        for (int k = 0; k < 3; ++k)
            if (V(a, k) != V(b, k)) return V(a, k) < V(b, k);
        return a < b;  // the first row of a run is the lowest
    };
    std::sort(order.begin(), order.end(), less);
    std::vector<int> same(size_t(V.rows()));
    for (size_t i = 0; i < order.size(); ++i) {
        const int r = order[i];
        const bool repeats = i > 0 && V.row(r) == V.row(order[i - 1]);
        same[size_t(r)] = repeats ? same[size_t(order[i - 1])] : r;
    }
    return same;
}

namespace {

// The lowest row a row is welded with, halving paths as it goes.
int root(std::vector<int>& parent, int r) {
    while (parent[size_t(r)] != r) {
        parent[size_t(r)] = parent[size_t(parent[size_t(r)])];
        r = parent[size_t(r)];
    }
    return r;
}

void weld(std::vector<int>& parent, int a, int b) {
    a = root(parent, a);
    b = root(parent, b);
    if (a != b) parent[size_t(std::max(a, b))] = std::min(a, b);
}

// Whether the corners a0 a1 a2 and b0 b1 b2 (the same three, in some order) run the same
// cyclic way round.
bool same_cycle(const std::array<int, 3>& a, const std::array<int, 3>& b) {
    for (int s = 0; s < 3; ++s)
        if (a[0] == b[size_t(s)] && a[1] == b[size_t((s + 1) % 3)]) return true;
    return false;
}

}  // namespace

RepeatedFaces drop_repeated_faces(const Eigen::MatrixX3i& F, const std::vector<int>& faces,
                                  const std::vector<int>& position, std::vector<int>& row_at_same_position) {
    auto positions_of = [&](int f) {
        return std::array<int, 3>{position[size_t(F(f, 0))], position[size_t(F(f, 1))], position[size_t(F(f, 2))]};
    };
    auto key_of = [&](int f) {
        std::array<int, 3> key = positions_of(f);
        std::sort(key.begin(), key.end());
        return key;
    };
    // Faces in order of their three positions, then of their rows: the first of a run is kept.
    std::vector<std::pair<std::array<int, 3>, int>> keyed;
    keyed.reserve(faces.size());
    for (int f : faces) keyed.emplace_back(key_of(f), f);
    std::sort(keyed.begin(), keyed.end());

    RepeatedFaces out;
    std::vector<char> dropped(size_t(F.rows()), 0);
    std::vector<int>& parent = row_at_same_position;
    for (size_t i = 1, first = 0; i < keyed.size(); ++i) {
        if (keyed[i].first != keyed[first].first) {
            first = i;
            continue;
        }
        const int kept = keyed[first].second, copy = keyed[i].second;
        dropped[size_t(copy)] = 1;
        const std::array<int, 3> at_kept = positions_of(kept), at_copy = positions_of(copy);
        ++(same_cycle(at_kept, at_copy) ? out.repeated : out.back);
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k)
                if (at_copy[size_t(j)] == at_kept[size_t(k)]) weld(parent, F(copy, j), F(kept, k));
    }
    for (size_t r = 0; r < parent.size(); ++r) parent[r] = root(parent, int(r));
    for (int f : faces)
        if (!dropped[size_t(f)]) out.kept.push_back(f);
    return out;
}

namespace {

using FaceCorners = std::array<const Vertex*, 3>;

FaceCorners corners(const Face& f) { return {f.cV(0), f.cV(1), f.cV(2)}; }

// Whether the face's corners run in the same cyclic order as `before`.
bool same_turn(const Face& f, const FaceCorners& before) {
    for (int s = 0; s < 3; ++s)
        if (f.cV(0) == before[size_t(s)] && f.cV(1) == before[size_t((s + 1) % 3)]) return true;
    return false;
}

void turn(Face& f) { std::swap(f.V(1), f.V(2)); }

// The faces reached from each other across manifold interior edges: the ones
// OrientCoherentlyMesh orients together.  Also whether each such component is closed.
std::vector<int> coherent_components(Mesh& mesh, std::vector<char>& closed) {
    std::vector<int> component(mesh.face.size(), -1);
    closed.clear();
    std::vector<Face*> stack;
    for (size_t start = 0; start < mesh.face.size(); ++start) {
        if (mesh.face[start].IsD() || component[start] >= 0) continue;
        const int c = int(closed.size());
        closed.push_back(1);
        component[start] = c;
        stack.push_back(&mesh.face[start]);
        while (!stack.empty()) {
            Face* f = stack.back();
            stack.pop_back();
            for (int j = 0; j < 3; ++j) {
                if (vcg::face::IsBorder(*f, j) || !vcg::face::IsManifold(*f, j)) {
                    closed[size_t(c)] = 0;
                    continue;
                }
                const size_t g = size_t(vcg::tri::Index(mesh, f->FFp(j)));
                if (component[g] < 0) {
                    component[g] = c;
                    stack.push_back(f->FFp(j));
                }
            }
        }
    }
    return component;
}

}  // namespace

Orientation orient_components(Mesh& mesh) {
    Orientation out;
    std::vector<FaceCorners> before(mesh.face.size());
    for (size_t f = 0; f < mesh.face.size(); ++f) before[f] = corners(mesh.face[f]);
    bool oriented = true, orientable = true;
    vcg::tri::Clean<Mesh>::OrientCoherentlyMesh(mesh, oriented, orientable);
    if (!orientable) {  // left as it came: a partial orientation would be neither
        for (size_t f = 0; f < mesh.face.size(); ++f)
            for (int k = 0; k < 3; ++k) mesh.face[f].V(k) = const_cast<Vertex*>(before[f][size_t(k)]);
        vcg::tri::UpdateTopology<Mesh>::FaceFace(mesh);
        out.orientable = false;
        return out;
    }

    // Per component: twice the signed volume (of a closed one) and the area the
    // coherent orientation turned against the input's.
    std::vector<char> closed;
    const std::vector<int> component = coherent_components(mesh, closed);
    std::vector<double> volume(closed.size(), 0), area(closed.size(), 0), turned_area(closed.size(), 0);
    for (size_t f = 0; f < mesh.face.size(); ++f) {
        const Face& face = mesh.face[f];
        if (face.IsD()) continue;
        const size_t c = size_t(component[f]);
        const vcg::Point3d &a = face.cP(0), &b = face.cP(1), &d = face.cP(2);
        volume[c] += a * (b ^ d);
        const double face_area = ((b - a) ^ (d - a)).Norm();
        area[c] += face_area;
        if (!same_turn(face, before[f])) turned_area[c] += face_area;
    }
    std::vector<char> flip(closed.size(), 0);
    for (size_t c = 0; c < closed.size(); ++c)
        flip[c] = closed[c] ? volume[c] < 0 : turned_area[c] > 0.5 * area[c];
    // Each face gets its input corners back, turned where its final orientation is the
    // other one: a face that keeps its orientation keeps its corners' order too.
    for (size_t f = 0; f < mesh.face.size(); ++f) {
        Face& face = mesh.face[f];
        if (face.IsD()) continue;
        const bool turned = same_turn(face, before[f]) == bool(flip[size_t(component[f])]);
        for (int k = 0; k < 3; ++k) face.V(k) = const_cast<Vertex*>(before[f][size_t(k)]);
        if (turned) {
            turn(face);
            ++out.flipped_faces;
        }
    }
    if (out.flipped_faces > 0 || !oriented) vcg::tri::UpdateTopology<Mesh>::FaceFace(mesh);
    return out;
}

}  // namespace symmetry
