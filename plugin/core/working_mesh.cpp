#include "working_mesh.h"

#include "kd_tree.h"

#include <algorithm>
#include <cmath>

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

class QuadricCollapse : public vcg::tri::TriEdgeCollapseQuadric<Mesh, VertexPair, QuadricCollapse, QuadricHelper> {
public:
    using Base = vcg::tri::TriEdgeCollapseQuadric<Mesh, VertexPair, QuadricCollapse, QuadricHelper>;
    QuadricCollapse(const VertexPair& p, int mark, vcg::BaseParameterClass* parameters) : Base(p, mark, parameters) {}
};

void collapse_to(Mesh& mesh, int target_faces, const WorkingMeshOptions& options) {
    vcg::math::Quadric<double> zero;
    zero.SetZero();
    QuadricData quadrics(mesh.vert, zero);
    QuadricHelper::data() = &quadrics;
    vcg::tri::TriEdgeCollapseQuadricParameter parameters;
    parameters.QualityThr = options.min_triangle_quality;
    parameters.PreserveTopology = true;
    parameters.FastPreserveBoundary = true;  // a scan's open border keeps its outline
    parameters.NormalCheck = true;
    parameters.NormalThrRad = M_PI / 4.0;
    vcg::LocalOptimization<Mesh> session(mesh, &parameters);
    session.Init<QuadricCollapse>();
    session.SetTargetSimplices(target_faces);
    while (session.DoOptimization() && mesh.fn > target_faces) {
    }
    session.Finalize<QuadricCollapse>();
    QuadricHelper::data() = nullptr;
}

}  // namespace

std::unique_ptr<Mesh> simplified_copy(const Mesh& input, int target_vertices, const WorkingMeshOptions& options) {
    Mesh copy;
    vcg::tri::Append<Mesh, Mesh>::MeshCopy(copy, const_cast<Mesh&>(input));  // vcg only reads it
    vcg::tri::UpdateTopology<Mesh>::VertexFace(copy);
    vcg::tri::UpdateFlags<Mesh>::FaceBorderFromVF(copy);
    vcg::tri::UpdateFlags<Mesh>::VertexBorderFromFaceBorder(copy);
    // Faces per vertex stay as in the input (2 on a closed surface, fewer on an open one).
    const double faces_per_vertex = double(input.fn) / double(std::max(1, input.vn));
    collapse_to(copy, int(faces_per_vertex * target_vertices), options);

    // Through build_mesh again: it drops what the collapses left degenerate or unreferenced
    // and sets up topology, normals and the bounding box as for any input.
    Eigen::MatrixX3d V(copy.vn, 3);
    std::vector<int> row(copy.vert.size(), -1);
    int n = 0;
    for (size_t i = 0; i < copy.vert.size(); ++i) {
        if (copy.vert[i].IsD()) continue;
        const auto& p = copy.vert[i].cP();
        V.row(n) << p[0], p[1], p[2];
        row[i] = n++;
    }
    Eigen::MatrixX3i F(copy.fn, 3);
    int m = 0;
    for (const Face& f : copy.face) {
        if (f.IsD()) continue;
        for (int k = 0; k < 3; ++k) F(m, k) = row[size_t(vcg::tri::Index(copy, f.cV(k)))];
        ++m;
    }
    auto simplified = std::make_unique<Mesh>();
    std::vector<int> unused;
    build_mesh(V.topRows(n), F.topRows(m), *simplified, unused);
    return simplified;
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
