#include "mesh.h"

#include "input_repair.h"

#include <vcg/complex/algorithms/update/bounding.h>
#include <vcg/complex/algorithms/update/normal.h>
#include <vcg/complex/algorithms/update/topology.h>

#include <cmath>
#include <numeric>

namespace symmetry {

void build_mesh(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, Mesh& mesh,
                std::vector<int>& vertex_of_input, MeshRepairs* repairs) {
    mesh.Clear();
    vertex_of_input.clear();
    if (V.rows() == 0)
        throw InputError("The mesh is empty: it has no vertices.");
    if (F.rows() == 0)
        throw InputError("The mesh has no faces: this needs a triangle mesh, not a point cloud (symmetry detection itself runs "
                         "on a point cloud). "
                         "Reconstruct a surface first with Filters > Remeshing, Simplification and Reconstruction > "
                         "Surface Reconstruction: Screened Poisson (pymeshlab: "
                         "generate_surface_reconstruction_screened_poisson; a cloud without normals needs "
                         "Filters > Normals, Curvatures and Orientation > Compute normals for point sets, "
                         "compute_normal_for_point_clouds, first) or Surface Reconstruction: Ball Pivoting.");
    if (!V.allFinite())
        throw InputError("The mesh has vertices with NaN or infinite coordinates; remove them first "
                         "(Cleaning and Repairing > Remove Unreferenced/Duplicated Vertices after fixing them).");
    if (F.minCoeff() < 0 || F.maxCoeff() >= V.rows())
        throw InputError("The mesh has faces that refer to vertices that do not exist.");

    MeshRepairs done;
    const std::vector<int> position = rows_at_same_position(V);
    if (is_triangle_soup(F, V.rows())) {
        done.row_at_same_position = position;
    } else {
        done.row_at_same_position.resize(size_t(V.rows()));
        std::iota(done.row_at_same_position.begin(), done.row_at_same_position.end(), 0);
    }
    const std::vector<int>& same = done.row_at_same_position;

    // Keep only faces with three distinct corners and a non-zero area: a zero-area
    // face has no normal and no dihedral angle, so it would corrupt the curvature
    // tensor (§2) and the closest-point queries of the verification (§4).
    std::vector<int> kept;
    kept.reserve(F.rows());
    for (Eigen::Index f = 0; f < F.rows(); ++f) {
        int a = same[F(f, 0)], b = same[F(f, 1)], c = same[F(f, 2)];
        if (a == b || b == c || a == c) continue;
        Eigen::Vector3d n = (V.row(b) - V.row(a)).cross(V.row(c) - V.row(a));
        double scale = std::max({(V.row(b) - V.row(a)).squaredNorm(), (V.row(c) - V.row(a)).squaredNorm(), 1e-300});
        if (n.norm() <= 1e-12 * scale) continue;
        kept.push_back(int(f));
    }
    if (kept.empty())
        throw InputError("Every face of the mesh is degenerate (zero area); there is no surface to analyse.");
    std::vector<char> referenced(V.rows(), 0);
    for (int f : kept)
        for (int k = 0; k < 3; ++k) referenced[F(f, k)] = 1;
    RepeatedFaces repeats = drop_repeated_faces(F, kept, position, done.row_at_same_position);
    kept = std::move(repeats.kept);
    done.repeated_faces = repeats.repeated;
    done.back_faces = repeats.back;

    std::vector<int> new_index(V.rows(), -1);
    for (int f : kept)
        for (int k = 0; k < 3; ++k) {
            const int row = same[F(f, k)];
            if (new_index[row] < 0) {
                new_index[row] = int(vertex_of_input.size());
                vertex_of_input.push_back(row);
            }
        }
    for (Eigen::Index r = 0; r < V.rows(); ++r) done.welded_vertices += referenced[r] && same[r] != r;

    auto vi = vcg::tri::Allocator<Mesh>::AddVertices(mesh, vertex_of_input.size());
    for (size_t i = 0; i < vertex_of_input.size(); ++i, ++vi) {
        const auto row = V.row(vertex_of_input[i]);
        vi->P() = vcg::Point3d(row(0), row(1), row(2));
    }
    auto fi = vcg::tri::Allocator<Mesh>::AddFaces(mesh, kept.size());
    for (int f : kept) {
        for (int k = 0; k < 3; ++k) fi->V(k) = &mesh.vert[new_index[same[F(f, k)]]];
        ++fi;
    }
    done.face_of_input = std::move(kept);  // only the uses of a result read it; no copy
    vcg::tri::UpdateBounding<Mesh>::Box(mesh);
    if (!(mesh.bbox.Diag() > 0))
        throw InputError("All vertices of the mesh are at the same position.");
    vcg::tri::UpdateTopology<Mesh>::FaceFace(mesh);
    const Orientation orientation = orient_components(mesh);
    done.flipped_faces = orientation.flipped_faces;
    done.orientable = orientation.orientable;
    vcg::tri::UpdateTopology<Mesh>::VertexFace(mesh);
    vcg::tri::UpdateNormal<Mesh>::PerFaceNormalized(mesh);
    vcg::tri::UpdateNormal<Mesh>::PerVertexAngleWeighted(mesh);
    vcg::tri::UpdateNormal<Mesh>::NormalizePerVertex(mesh);
    if (repairs) *repairs = std::move(done);
}

double surface_area(const Mesh& mesh) {
    double area = 0;
    for (const auto& f : mesh.face)
        if (!f.IsD()) area += 0.5 * ((f.cP(1) - f.cP(0)) ^ (f.cP(2) - f.cP(0))).Norm();
    return area;
}

}  // namespace symmetry
