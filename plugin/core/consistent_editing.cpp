#include "consistent_editing.h"

#include "surface_query.h"

#include <Eigen/Dense>
#include <cmath>
#include <vector>

namespace symmetry {
namespace {

void check_meshes(const Eigen::MatrixX3d& V_original, const Eigen::MatrixX3d& V_edited,
                  const DetectionResult& detected) {
    if (V_edited.rows() != V_original.rows())
        throw InputError("The edited mesh has " + std::to_string(V_edited.rows()) + " vertices and the original " +
                         std::to_string(V_original.rows()) +
                         ": consistent editing needs the original's vertices and faces, moved, not remeshed.");
    if (!V_edited.allFinite())
        throw InputError("The edited mesh has vertices with NaN or infinite coordinates.");
    require_result_of_mesh(detected, V_original.rows());
}

// Barycentric coordinates of p in triangle (a, b, c), p on its plane (a closest point).
Eigen::Vector3d barycentric(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                            const Eigen::Vector3d& c) {
    const Eigen::Vector3d u = b - a, v = c - a, w = p - a;
    const double uu = u.dot(u), uv = u.dot(v), vv = v.dot(v), wu = w.dot(u), wv = w.dot(v);
    const double det = uu * vv - uv * uv;
    const double beta = (vv * wu - uv * wv) / det, gamma = (uu * wv - uv * wu) / det;
    return {1 - beta - gamma, beta, gamma};
}

// What the vertices carry: their displacement, whether it is known (moved by the user, or
// carried in an earlier pass), and the transformation that brought it from the user's edit
// (the identity on the vertices the user moved).
struct Displacements {
    Eigen::MatrixX3d d;
    std::vector<char> known;
    std::vector<Transformation> origin;
};

// One pass: every vertex of a symmetry's patch that has no displacement yet, and lands under
// T⁻¹ on a face with a displaced corner, receives the corners' displacements interpolated
// (a corner without one counts as zero: the edit fades out there) and turned by T.  A vertex
// refuses a displacement that would come back to where it started (T after the origin of
// the displacement maps it onto itself): the unedited ring around the edit on the edited copy
// must stay, though the copy next to it now carries the edit.  Jacobi: computed from the
// displacements before the pass, then applied.  A displacement below min_edit (absolute) is
// none.  Returns the vertices that received one.
int carry_pass(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, const DetectionResult& detected,
               const SurfaceOfRows& surface, double max_distance, double min_edit, Displacements& field) {
    Eigen::MatrixX3d received = Eigen::MatrixX3d::Zero(V.rows(), 3);
    std::vector<Transformation> came_by(size_t(V.rows()));
    std::vector<char> receives(size_t(V.rows()), 0);
    for (const DetectedSymmetry& s : detected.symmetries) {
        if (s.continuous_kind != ContinuousKind::Discrete) continue;
        // T maps the source patch onto the target; T⁻¹ the target onto the source.
        for (const bool forward : {true, false}) {
            const Transformation T = forward ? s.transform : s.transform.inverse();
            const Transformation back = T.inverse();
            const Eigen::Matrix3d turn = T.linear();
            for (int v : forward ? s.target_vertices : s.source_vertices) {
                if (field.known[size_t(v)] || receives[size_t(v)]) continue;
                const Eigen::Vector3d p = V.row(v).transpose();
                const ClosestPoint c = surface.closest(back.apply(p), max_distance / T.scale);
                if (!c.found) continue;
                const Eigen::Vector3i corners = F.row(c.face).transpose();
                const Eigen::Vector3d w = barycentric(c.point, V.row(corners[0]).transpose(),
                                                      V.row(corners[1]).transpose(), V.row(corners[2]).transpose());
                int main = -1;  // the known corner of largest weight: whose origin the result takes
                Eigen::Vector3d d = Eigen::Vector3d::Zero();
                for (int k = 0; k < 3; ++k) {
                    if (!field.known[size_t(corners[k])]) continue;
                    d += w[k] * field.d.row(corners[k]).transpose();
                    if (main < 0 || w[k] > w[main]) main = k;
                }
                // Interpolating towards zero corners fades the edit out; where it has faded
                // below an edit, it stops (else each pass would spread it by one more ring).
                if (main < 0 || (turn * d).norm() <= min_edit) continue;
                const Transformation origin = T * field.origin[size_t(corners[main])];
                if ((origin.inverse().apply(p) - p).norm() <= max_distance) continue;
                received.row(v) = (turn * d).transpose();
                came_by[size_t(v)] = origin;
                receives[size_t(v)] = 1;
            }
        }
    }
    int count = 0;
    for (Eigen::Index v = 0; v < V.rows(); ++v)
        if (receives[size_t(v)]) {
            field.d.row(v) = received.row(v);
            field.known[size_t(v)] = 1;
            field.origin[size_t(v)] = came_by[size_t(v)];
            ++count;
        }
    return count;
}

}  // namespace

void EditingOptions::validate() const {
    require_parameter(min_edit > 0 && min_edit < 0.01, "min_edit", min_edit, "greater than 0 and below 0.01");
    require_parameter(max_distance_in_tolerances > 0 && max_distance_in_tolerances <= 10,
                      "max_distance_in_tolerances", max_distance_in_tolerances, "greater than 0 and at most 10");
    require_parameter(max_passes >= 1 && max_passes <= 64, "max_passes", max_passes, "between 1 and 64");
}

EditingResult carry_edit(const Eigen::MatrixX3d& V_original, const Eigen::MatrixX3i& F,
                         const Eigen::MatrixX3d& V_edited, const DetectionResult& detected,
                         double verification_tolerance, const EditingOptions& options) {
    options.validate();
    check_meshes(V_original, V_edited, detected);
    const double diagonal = (V_original.colwise().maxCoeff() - V_original.colwise().minCoeff()).norm();
    EditingResult out;
    Displacements field{V_edited - V_original, std::vector<char>(size_t(V_original.rows()), 0),
                        std::vector<Transformation>(size_t(V_original.rows()))};
    for (Eigen::Index v = 0; v < V_original.rows(); ++v)
        if (field.d.row(v).norm() > options.min_edit * diagonal) {
            field.known[size_t(v)] = 1;
            ++out.edited_vertices;
        }
    if (out.edited_vertices == 0)
        throw InputError("The edited mesh does not differ from the original: there is no edit to carry. Move some "
                         "vertices of one copy first (on a duplicate of the original, which stays as it was).");
    const SurfaceOfRows surface(V_original, F);
    const double max_distance = options.max_distance_in_tolerances * verification_tolerance * diagonal;
    for (int pass = 0; pass < options.max_passes; ++pass) {
        const int carried =
            carry_pass(V_original, F, detected, surface, max_distance, options.min_edit * diagonal, field);
        if (carried == 0) break;
        out.carried_vertices += carried;
        ++out.passes;
    }
    // The user's vertices stay exactly where the user put them; the others move by what
    // they received (zero where nothing was carried).
    out.V = V_edited;
    for (Eigen::Index v = 0; v < V_original.rows(); ++v)
        if (field.known[size_t(v)] && (V_edited.row(v) - V_original.row(v)).norm() <= options.min_edit * diagonal)
            out.V.row(v) = V_original.row(v) + field.d.row(v);
    return out;
}

}  // namespace symmetry
