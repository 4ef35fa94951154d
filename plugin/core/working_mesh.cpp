#include "working_mesh.h"

#include "kd_tree.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <unordered_map>

#include <omp.h>
#include <vcg/complex/algorithms/local_optimization.h>
#include <vcg/complex/algorithms/local_optimization/tri_edge_collapse_quadric.h>
#include <vcg/complex/algorithms/point_sampling.h>
#include <vcg/container/simple_temporary_data.h>

namespace symmetry {

namespace {

// The per-vertex quadrics of the collapse live in temporary data beside the mesh (as in
// MeshLab's own filter), reached through a pointer the collapse class can see.
using QuadricData = vcg::SimpleTempData<Mesh::VertContainer, vcg::math::Quadric<double>>;

struct QuadricHelper {
    static void Init() {}
    static vcg::math::Quadric<double>& Qd(Vertex& v) { return (*data())[v]; }
    static vcg::math::Quadric<double>& Qd(Vertex* v) { return (*data())[*v]; }
    static double W(Vertex*) { return 1.0; }
    static double W(Vertex&) { return 1.0; }
    static void Merge(Vertex&, const Vertex&) {}
    static QuadricData*& data() {
        thread_local QuadricData* d = nullptr;
        return d;
    }
};

using VertexPair = vcg::tri::BasicVertexPair<Vertex>;

// One collapse type per lane: vcglib dates its heap entries with a counter that is a static
// of the collapse type (TriEdgeCollapse::GlobalMark), so two halves simplified at once must
// not share a type, or an entry could be taken for up to date after its edge changed.
template <int Lane>
class QuadricCollapse
    : public vcg::tri::TriEdgeCollapseQuadric<Mesh, VertexPair, QuadricCollapse<Lane>, QuadricHelper> {
public:
    using Base = vcg::tri::TriEdgeCollapseQuadric<Mesh, VertexPair, QuadricCollapse<Lane>, QuadricHelper>;
    QuadricCollapse(const VertexPair& p, int mark, vcg::BaseParameterClass* parameters) : Base(p, mark, parameters) {}
};

// Collapses edges until the mesh has at most target_faces faces (or no collapse is left).
// An open border's vertices are held (FastPreserveBoundary): a scan's outline keeps its
// shape, and so does the cut between two halves.  So are the vertices `held` marks, if given.
template <int Lane>
void collapse_to(Mesh& mesh, int target_faces, const WorkingMeshOptions& options,
                 const std::vector<char>* held = nullptr) {
    if (mesh.fn <= target_faces) return;
    vcg::tri::UpdateTopology<Mesh>::VertexFace(mesh);
    vcg::tri::UpdateFlags<Mesh>::FaceBorderFromVF(mesh);
    vcg::tri::UpdateFlags<Mesh>::VertexBorderFromFaceBorder(mesh);
    if (held)  // vcglib collapses an edge only when both its ends are writable
        for (size_t v = 0; v < mesh.vert.size(); ++v)
            if ((*held)[v]) mesh.vert[v].ClearW();
    vcg::math::Quadric<double> zero;
    zero.SetZero();
    QuadricData quadrics(mesh.vert, zero);
    QuadricHelper::data() = &quadrics;
    vcg::tri::TriEdgeCollapseQuadricParameter parameters;
    parameters.QualityThr = options.min_triangle_quality;
    parameters.PreserveTopology = true;
    parameters.FastPreserveBoundary = true;
    parameters.NormalCheck = true;
    parameters.NormalThrRad = M_PI / 4.0;
    vcg::LocalOptimization<Mesh> session(mesh, &parameters);
    session.Init<QuadricCollapse<Lane>>();
    session.SetTargetSimplices(target_faces);
    while (session.DoOptimization() && mesh.fn > target_faces) {
    }
    session.Finalize<QuadricCollapse<Lane>>();
    QuadricHelper::data() = nullptr;
}

// A part of the input as a mesh of its own, each vertex knowing the input vertex it was.
struct Part {
    Mesh mesh;
    std::vector<int> input_vertex;
    int faces_at_cut = 0;  ///< faces with a corner on the cut, which the half cannot collapse
};

// The faces of `input` for which take(f) holds, with the vertices they use.
template <class Take>
void extract_part(const Mesh& input, Take take, Part& part) {
    std::vector<int> index(input.vert.size(), -1);
    std::vector<std::array<int, 3>> faces;
    for (size_t f = 0; f < input.face.size(); ++f) {
        if (input.face[f].IsD() || !take(f)) continue;
        std::array<int, 3> corners;
        for (int k = 0; k < 3; ++k) {
            const size_t v = size_t(vcg::tri::Index(input, input.face[f].cV(k)));
            if (index[v] < 0) {
                index[v] = int(part.input_vertex.size());
                part.input_vertex.push_back(int(v));
            }
            corners[size_t(k)] = index[v];
        }
        faces.push_back(corners);
    }
    auto vi = vcg::tri::Allocator<Mesh>::AddVertices(part.mesh, part.input_vertex.size());
    for (int v : part.input_vertex) (vi++)->P() = input.vert[size_t(v)].cP();
    auto fi = vcg::tri::Allocator<Mesh>::AddFaces(part.mesh, faces.size());
    for (const auto& c : faces) {
        for (int k = 0; k < 3; ++k) fi->V(k) = &part.mesh.vert[size_t(c[size_t(k)])];
        ++fi;
    }
}

// The input cut in two halves of about as many faces, at the median of the faces' centroids
// along the longest side of its box: the shortest cut of a compact model, so the seam the
// halves hold fixed is short.
void cut_in_halves(const Mesh& input, std::array<Part, 2>& halves) {
    const vcg::Point3d size = input.bbox.Dim();  // build_mesh has set the box
    const int axis = size[0] >= size[1] && size[0] >= size[2] ? 0 : (size[1] >= size[2] ? 1 : 2);
    std::vector<double> centroid(input.face.size(), 0.0);
    std::vector<double> live;
    for (size_t f = 0; f < input.face.size(); ++f) {
        if (input.face[f].IsD()) continue;
        const Face& face = input.face[f];
        centroid[f] = (face.cP(0)[axis] + face.cP(1)[axis] + face.cP(2)[axis]) / 3;
        live.push_back(centroid[f]);
    }
    std::nth_element(live.begin(), live.begin() + long(live.size() / 2), live.end());
    const double median = live.empty() ? 0.0 : live[live.size() / 2];
    extract_part(input, [&](size_t f) { return centroid[f] < median; }, halves[0]);
    extract_part(input, [&](size_t f) { return centroid[f] >= median; }, halves[1]);
    // A vertex of the cut is in both halves.
    std::vector<char> in_first(input.vert.size(), 0);
    for (int v : halves[0].input_vertex) in_first[size_t(v)] = 1;
    std::vector<char> on_cut(input.vert.size(), 0);
    for (int v : halves[1].input_vertex) on_cut[size_t(v)] = in_first[size_t(v)];
    for (Part& h : halves)
        for (const Face& f : h.mesh.face)
            for (int k = 0; k < 3; ++k)
                if (on_cut[size_t(h.input_vertex[size_t(vcg::tri::Index(h.mesh, f.cV(k)))])]) {
                    ++h.faces_at_cut;
                    break;
                }
}

// The halves as one mesh again.  A vertex of the cut, held by both halves, is the same input
// vertex in both, unmoved: it becomes one vertex, marked in `on_cut`.  Every other vertex
// lives in one half only.
void join(const std::array<Part, 2>& halves, size_t input_vertices, Mesh& joined, std::vector<char>& on_cut) {
    std::vector<Vertex*> joined_vertex(input_vertices, nullptr);
    size_t vertices = 0, faces = 0;
    std::vector<char> counted(input_vertices, 0);
    for (const Part& h : halves) {
        for (size_t i = 0; i < h.mesh.vert.size(); ++i)
            if (!h.mesh.vert[i].IsD() && !counted[size_t(h.input_vertex[i])]++) ++vertices;
        faces += size_t(h.mesh.fn);
    }
    auto vi = vcg::tri::Allocator<Mesh>::AddVertices(joined, vertices);
    auto fi = vcg::tri::Allocator<Mesh>::AddFaces(joined, faces);
    on_cut.assign(vertices, 0);
    for (const Part& h : halves) {
        for (size_t i = 0; i < h.mesh.vert.size(); ++i) {
            Vertex*& v = joined_vertex[size_t(h.input_vertex[i])];
            if (h.mesh.vert[i].IsD()) continue;
            if (v != nullptr) {
                on_cut[size_t(vcg::tri::Index(joined, v))] = 1;
                continue;
            }
            v = &*vi++;
            v->P() = h.mesh.vert[i].cP();
        }
        for (const Face& f : h.mesh.face) {
            if (f.IsD()) continue;
            for (int k = 0; k < 3; ++k)
                fi->V(k) = joined_vertex[size_t(h.input_vertex[size_t(vcg::tri::Index(h.mesh, f.cV(k)))])];
            ++fi;
        }
    }
}

// Every vertex farther than `rings` edges from the cut: what the halves have simplified
// already, held in the last pass so that it collapses only the strip along the cut.  A
// collapse there weighs its error against the input's faces; elsewhere it would weigh it
// against faces simplified already, and the copy would drift from the input.
std::vector<char> away_from_cut(const Mesh& joined, const std::vector<char>& on_cut, int rings) {
    std::vector<int> distance(joined.vert.size(), std::numeric_limits<int>::max());
    for (size_t v = 0; v < on_cut.size(); ++v)
        if (on_cut[v]) distance[v] = 0;
    for (int r = 0; r < rings; ++r)
        for (const Face& f : joined.face) {
            int nearest = std::numeric_limits<int>::max();
            for (int k = 0; k < 3; ++k) nearest = std::min(nearest, distance[size_t(vcg::tri::Index(joined, f.cV(k)))]);
            if (nearest != r) continue;
            for (int k = 0; k < 3; ++k) {
                int& d = distance[size_t(vcg::tri::Index(joined, f.cV(k)))];
                d = std::min(d, r + 1);
            }
        }
    std::vector<char> away(joined.vert.size());
    for (size_t v = 0; v < away.size(); ++v) away[v] = distance[v] > rings;
    return away;
}

// The mesh's live vertices and faces as arrays, for build_mesh.
void live_arrays(const Mesh& mesh, Eigen::MatrixX3d& V, Eigen::MatrixX3i& F) {
    V.resize(mesh.vn, 3);
    std::vector<int> row(mesh.vert.size(), -1);
    int n = 0;
    for (size_t i = 0; i < mesh.vert.size(); ++i) {
        if (mesh.vert[i].IsD()) continue;
        const auto& p = mesh.vert[i].cP();
        V.row(n) << p[0], p[1], p[2];
        row[i] = n++;
    }
    F.resize(mesh.fn, 3);
    int m = 0;
    for (const Face& f : mesh.face) {
        if (f.IsD()) continue;
        for (int k = 0; k < 3; ++k) F(m, k) = row[size_t(vcg::tri::Index(mesh, f.cV(k)))];
        ++m;
    }
    V.conservativeResize(n, 3);
    F.conservativeResize(m, 3);
}

// The input simplified as two halves at once, each to its share of the target with the cut
// between them held, then joined, and the strip along the cut (left at the input's
// resolution) collapsed in a last pass.  Quadric collapse runs on one core; the halves are
// always two, and each is simplified alone, so the result is the same at any thread count.
void collapse_in_halves(const Mesh& input, int target_faces, const WorkingMeshOptions& options, Mesh& joined) {
    std::array<Part, 2> halves;  // filled in place: a vcg mesh must not be copied
    cut_in_halves(input, halves);
    // A half's share leaves out the faces at the cut, which it cannot collapse: spent on the
    // rest of the half, the share would leave the last pass nothing to collapse at the cut.
    auto share = [&](const Part& h) {
        return int(double(target_faces) * h.mesh.fn / std::max(1, input.fn)) + h.faces_at_cut;
    };
#pragma omp parallel sections num_threads(std::min(2, omp_get_max_threads()))
    {
#pragma omp section
        collapse_to<0>(halves[0].mesh, share(halves[0]), options);
#pragma omp section
        collapse_to<1>(halves[1].mesh, share(halves[1]), options);
    }
    std::vector<char> on_cut;
    join(halves, input.vert.size(), joined, on_cut);
    for (Part& h : halves) h.mesh.Clear();
    const std::vector<char> held = away_from_cut(joined, on_cut, options.seam_rings);
    collapse_to<0>(joined, target_faces, options, &held);
}

}  // namespace

std::unique_ptr<Mesh> simplified_copy(const Mesh& input, int target_vertices, const WorkingMeshOptions& options) {
    // Faces per vertex stay as in the input (2 on a closed surface, fewer on an open one).
    const double faces_per_vertex = double(input.fn) / double(std::max(1, input.vn));
    const int target_faces = int(faces_per_vertex * target_vertices);

    Mesh simplified_input;
    if (input.fn >= options.min_faces_to_halve) {
        collapse_in_halves(input, target_faces, options, simplified_input);
    } else {
        vcg::tri::Append<Mesh, Mesh>::MeshCopy(simplified_input, const_cast<Mesh&>(input));  // vcg only reads it
        collapse_to<0>(simplified_input, target_faces, options);
    }

    // Through build_mesh again: it drops what the collapses left degenerate or unreferenced
    // and sets up topology, normals and the bounding box as for any input.
    Eigen::MatrixX3d V;
    Eigen::MatrixX3i F;
    live_arrays(simplified_input, V, F);
    auto simplified = std::make_unique<Mesh>();
    std::vector<int> unused;
    build_mesh(V, F, *simplified, unused);
    return simplified;
}

namespace {

using Corners = std::array<int, 3>;

// The faces of one pass of midpoint splitting: a face with one edge split becomes two, with
// two edges three (the quad left beside the corner cut off split along its shorter
// diagonal), with three edges four.  `middle(a, b)` is the vertex on edge ab, or -1.
template <class Middle>
void split_face(const Corners& c, const std::vector<Eigen::Vector3d>& P, Middle middle, std::vector<Corners>& out) {
    std::array<int, 3> m;
    int splits = 0;
    for (int k = 0; k < 3; ++k) splits += (m[size_t(k)] = middle(c[size_t(k)], c[size_t((k + 1) % 3)])) >= 0;
    if (splits == 0) {
        out.push_back(c);
        return;
    }
    if (splits == 3) {
        out.push_back({c[0], m[0], m[2]});
        out.push_back({m[0], c[1], m[1]});
        out.push_back({m[2], m[1], c[2]});
        out.push_back({m[0], m[1], m[2]});
        return;
    }
    // Turned so that edge 0 (c0 c1) is split and, with two splits, edge 1 (c1 c2) too.
    int s = 0;
    while (!(m[size_t(s)] >= 0 && (splits == 1 || m[size_t((s + 1) % 3)] >= 0))) ++s;
    const int a = c[size_t(s)], b = c[size_t((s + 1) % 3)], d = c[size_t((s + 2) % 3)];
    const int ab = m[size_t(s)], bd = m[size_t((s + 1) % 3)];
    if (splits == 1) {
        out.push_back({a, ab, d});
        out.push_back({ab, b, d});
        return;
    }
    out.push_back({ab, b, bd});
    if ((P[size_t(a)] - P[size_t(bd)]).squaredNorm() <= (P[size_t(ab)] - P[size_t(d)]).squaredNorm()) {
        out.push_back({a, ab, bd});
        out.push_back({a, bd, d});
    } else {
        out.push_back({a, ab, d});
        out.push_back({ab, bd, d});
    }
}

}  // namespace

std::unique_ptr<Mesh> refined_copy(const Mesh& input, double max_edge, int max_vertices) {
    Eigen::MatrixX3d V;
    Eigen::MatrixX3i F;
    live_arrays(input, V, F);
    std::vector<Eigen::Vector3d> P(size_t(V.rows()));
    for (Eigen::Index i = 0; i < V.rows(); ++i) P[size_t(i)] = V.row(i).transpose();
    std::vector<Corners> faces(size_t(F.rows()));
    for (Eigen::Index f = 0; f < F.rows(); ++f) faces[size_t(f)] = {F(f, 0), F(f, 1), F(f, 2)};
    const double max_squared = max_edge * max_edge;
    // By hand rather than vcglib's RefineE, which asserts manifold edges: CAD exports have
    // non-manifold ones.  Each pass halves every edge longer than max_edge, the same midpoint for every face on
    // the edge (a non-manifold one too), so the copy stays conforming and its surface is the
    // input's exactly: flat faces stay flat, creases sharp.
    for (;;) {
        std::unordered_map<uint64_t, int> middle_of;
        auto key = [](int a, int b) { return (uint64_t(std::min(a, b)) << 32) | uint64_t(std::max(a, b)); };
        for (const Corners& c : faces)
            for (int k = 0; k < 3; ++k) {
                const int a = c[size_t(k)], b = c[size_t((k + 1) % 3)];
                if ((P[size_t(a)] - P[size_t(b)]).squaredNorm() <= max_squared) continue;
                if (middle_of.emplace(key(a, b), int(P.size())).second) P.push_back(0.5 * (P[size_t(a)] + P[size_t(b)]));
            }
        if (middle_of.empty()) break;
        if (max_vertices > 0 && P.size() > size_t(max_vertices)) return nullptr;
        auto middle = [&](int a, int b) {
            const auto it = middle_of.find(key(a, b));
            return it == middle_of.end() ? -1 : it->second;
        };
        std::vector<Corners> next;
        next.reserve(2 * faces.size());
        for (const Corners& c : faces) split_face(c, P, middle, next);
        faces.swap(next);
    }
    V.resize(Eigen::Index(P.size()), 3);
    for (size_t i = 0; i < P.size(); ++i) V.row(Eigen::Index(i)) = P[i].transpose();
    F.resize(Eigen::Index(faces.size()), 3);
    for (size_t f = 0; f < faces.size(); ++f)
        for (int k = 0; k < 3; ++k) F(Eigen::Index(f), k) = faces[f][size_t(k)];
    auto refined = std::make_unique<Mesh>();
    std::vector<int> unused;
    build_mesh(V, F, *refined, unused);
    return refined;
}

double smooth_edge_share(const Mesh& mesh, const WorkingMeshOptions& options) {
    const double flat = std::cos(options.flat_edge_degrees * M_PI / 180.0);
    const double crease = std::cos(options.crease_edge_degrees * M_PI / 180.0);
    long smooth = 0, interior = 0;
    for (const Face& f : mesh.face) {
        if (f.IsD()) continue;
        for (int j = 0; j < 3; ++j) {
            const Face* g = f.cFFp(j);
            if (g <= &f || !vcg::face::IsManifold(f, j)) continue;  // each edge once, from its first face
            ++interior;
            const double cosine = f.cN() * g->cN();
            smooth += cosine < flat && cosine >= crease;
        }
    }
    return interior ? double(smooth) / double(interior) : 0.0;
}

std::unique_ptr<Mesh> refined_copy_within(const Mesh& input, double max_edge, const WorkingMeshOptions& options) {
    int budget = options.max_refined_vertices;
    if (options.max_vertices > 0) budget = std::min(budget, options.max_vertices);
    // A pass past the hard limit is abandoned, so that one far vertex or sliver, whose edges
    // would be halved many times over, costs neither the time nor the memory.
    const int hard_limit = 4 * budget;
    // Triangles whose edges are at most h hold at most sqrt(3)/4 h^2 each, and a surface has
    // about half as many vertices as faces: an edge below this would surely exceed the budget.
    max_edge = std::max(max_edge, std::sqrt(2 * surface_area(input) / (std::sqrt(3.0) * budget)));
    for (int attempt = 0; attempt < options.refinement_attempts; ++attempt) {
        std::unique_ptr<Mesh> copy = refined_copy(input, max_edge, hard_limit);
        if (copy && (copy->vn <= budget || attempt + 1 == options.refinement_attempts)) return copy;
        // The vertices of a refined surface grow as 1 / max_edge^2, but in the steps of
        // halving edges: just past one, a small growth would land on the same copy again.
        max_edge *= copy ? std::max(std::sqrt(2.0), 1.05 * std::sqrt(double(copy->vn) / budget)) : 2.0;
    }
    return nullptr;
}

std::vector<int> poisson_disk_subset(const Mesh& cloud, int target_points, double area, unsigned seed,
                                     const WorkingMeshOptions& options) {
    // vcglib takes the mesh by non-const reference (it updates its bounding box).
    Mesh copy;
    vcg::tri::Append<Mesh, Mesh>::MeshCopy(copy, const_cast<Mesh&>(cloud));
    vcg::tri::UpdateBounding<Mesh>::Box(copy);
    // A maximal Poisson-disk set of radius r holds about area / (1.2 r^2) points; the count
    // falls as 1 / r^2, so each retry corrects r by the square root of the count's ratio.
    // (vcglib's PoissonPruningExact brackets r from a tenth of the diagonal instead: measured
    // on 200,000 points, 3.7 s.)
    double radius = std::sqrt(area / (1.2 * target_points));
    std::vector<Mesh::VertexPointer> kept;
    for (int attempt = 0; attempt < options.poisson_attempts; ++attempt) {
        // vcglib seeds its generator only for a nonzero seed; 0 would continue its global state.
        vcg::tri::PoissonPruning(copy, kept, float(radius), seed + 1);
        const double ratio = double(kept.size()) / target_points;
        if (std::abs(ratio - 1) <= options.poisson_count_tolerance) break;
        radius *= std::sqrt(ratio);
    }
    std::vector<int> indices;
    indices.reserve(kept.size());
    for (Mesh::VertexPointer v : kept) indices.push_back(int(vcg::tri::Index(copy, v)));
    // The pruning leaves its per-vertex "radius" attribute on the mesh, and vcglib frees a
    // mesh's attributes only when asked: 4 bytes a point, every call, for a batch job to lose.
    for (const char* name : {"radius", "fixed"})
        if (vcg::tri::HasPerVertexAttribute(copy, name)) vcg::tri::Allocator<Mesh>::DeletePerVertexAttribute(copy, name);
    std::sort(indices.begin(), indices.end());
    return indices;
}

std::vector<int> nearest_vertices(const Mesh& fine, const Mesh& coarse) {
    KdTree::Points points(coarse.vert.size(), 3);
    for (size_t i = 0; i < coarse.vert.size(); ++i)
        for (int k = 0; k < 3; ++k) points(Eigen::Index(i), k) = coarse.vert[i].cP()[k];
    const KdTree tree(std::move(points));
    std::vector<int> nearest(fine.vert.size());
    for (size_t i = 0; i < fine.vert.size(); ++i) {
        const auto& p = fine.vert[i].cP();
        const double q[3] = {p[0], p[1], p[2]};
        nearest[i] = tree.nearest(q).first;
    }
    return nearest;
}

}  // namespace symmetry
