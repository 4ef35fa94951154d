#include "mesh.h"

#include <vcg/complex/algorithms/update/bounding.h>
#include <vcg/complex/algorithms/update/normal.h>
#include <vcg/complex/algorithms/update/topology.h>

#include <cmath>

namespace symmetry {

void build_mesh(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, Mesh& mesh,
                std::vector<int>& vertex_of_input) {
    mesh.Clear();
    vertex_of_input.clear();
    if (V.rows() == 0)
        throw InputError("The mesh is empty: it has no vertices.");
    if (F.rows() == 0)
        throw InputError("The mesh has no faces: symmetry detection needs a triangle mesh, not a point cloud. "
                         "Reconstruct a surface first (e.g. Screened Poisson or Ball Pivoting).");
    if (!V.allFinite())
        throw InputError("The mesh has vertices with NaN or infinite coordinates; remove them first "
                         "(Cleaning and Repairing > Remove Unreferenced/Duplicated Vertices after fixing them).");
    if (F.minCoeff() < 0 || F.maxCoeff() >= V.rows())
        throw InputError("The mesh has faces that refer to vertices that do not exist.");

    // Keep only faces with three distinct corners and a non-zero area: a zero-area
    // face has no normal and no dihedral angle, so it would corrupt the curvature
    // tensor (§2) and the closest-point queries of the verification (§4).
    std::vector<int> kept;
    kept.reserve(F.rows());
    for (Eigen::Index f = 0; f < F.rows(); ++f) {
        int a = F(f, 0), b = F(f, 1), c = F(f, 2);
        if (a == b || b == c || a == c) continue;
        Eigen::Vector3d n = (V.row(b) - V.row(a)).cross(V.row(c) - V.row(a));
        double scale = std::max({(V.row(b) - V.row(a)).squaredNorm(), (V.row(c) - V.row(a)).squaredNorm(), 1e-300});
        if (n.norm() <= 1e-12 * scale) continue;
        kept.push_back(int(f));
    }
    if (kept.empty())
        throw InputError("Every face of the mesh is degenerate (zero area); there is no surface to analyse.");

    std::vector<int> new_index(V.rows(), -1);
    for (int f : kept)
        for (int k = 0; k < 3; ++k)
            if (new_index[F(f, k)] < 0) {
                new_index[F(f, k)] = int(vertex_of_input.size());
                vertex_of_input.push_back(F(f, k));
            }

    auto vi = vcg::tri::Allocator<Mesh>::AddVertices(mesh, vertex_of_input.size());
    for (size_t i = 0; i < vertex_of_input.size(); ++i, ++vi) {
        const auto row = V.row(vertex_of_input[i]);
        vi->P() = vcg::Point3d(row(0), row(1), row(2));
    }
    auto fi = vcg::tri::Allocator<Mesh>::AddFaces(mesh, kept.size());
    for (int f : kept) {
        for (int k = 0; k < 3; ++k) fi->V(k) = &mesh.vert[new_index[F(f, k)]];
        ++fi;
    }
    vcg::tri::UpdateBounding<Mesh>::Box(mesh);
    if (!(mesh.bbox.Diag() > 0))
        throw InputError("All vertices of the mesh are at the same position.");
    vcg::tri::UpdateTopology<Mesh>::FaceFace(mesh);
    vcg::tri::UpdateTopology<Mesh>::VertexFace(mesh);
    vcg::tri::UpdateNormal<Mesh>::PerFaceNormalized(mesh);
    vcg::tri::UpdateNormal<Mesh>::PerVertexAngleWeighted(mesh);
    vcg::tri::UpdateNormal<Mesh>::NormalizePerVertex(mesh);
}

double surface_area(const Mesh& mesh) {
    double area = 0;
    for (const auto& f : mesh.face)
        if (!f.IsD()) area += 0.5 * ((f.cP(1) - f.cP(0)) ^ (f.cP(2) - f.cP(0))).Norm();
    return area;
}

}  // namespace symmetry
