#include "symmetrization.h"

#include "surface_query.h"

#include <cmath>
#include <string>
#include <vector>

namespace symmetry {
namespace {

// Per vertex: the discrete symmetry it moves under, and whether it is in that symmetry's
// source patch, its target patch or both.
struct Membership {
    std::vector<int> symmetry;  // -1: does not move
    std::vector<char> in_source, in_target;
};

Membership membership(const DetectionResult& detected, Eigen::Index rows) {
    Membership m{std::vector<int>(size_t(rows), -1), std::vector<char>(size_t(rows), 0),
                 std::vector<char>(size_t(rows), 0)};
    for (size_t k = 0; k < detected.symmetries.size(); ++k) {
        const DetectedSymmetry& s = detected.symmetries[k];
        if (s.continuous_kind != ContinuousKind::Discrete) continue;
        for (int v : s.source_vertices)
            if (detected.vertex_symmetry_id[size_t(v)] == int(k)) m.in_source[size_t(v)] = 1;
        for (int v : s.target_vertices)
            if (detected.vertex_symmetry_id[size_t(v)] == int(k)) m.in_target[size_t(v)] = 1;
    }
    for (size_t v = 0; v < m.symmetry.size(); ++v)
        if (m.in_source[v] || m.in_target[v]) m.symmetry[v] = detected.vertex_symmetry_id[v];
    return m;
}

// What a pass measured before it moved anything.
struct PassOutcome {
    double rms = 0;   // RMS deviation of the images that found the surface, absolute units
    int moved = 0;    // vertices that moved (none for strength 0)
};

// One Jacobi pass: every displacement measured on the surface (V, F), then applied.
PassOutcome symmetrization_pass(Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, const DetectionResult& detected,
                                const Membership& m, double max_distance, double strength) {
    Mesh mesh;
    std::vector<int> vertex_of_input;
    build_mesh(V, F, mesh, vertex_of_input);
    const SurfaceQuery surface(mesh, 8);
    Eigen::MatrixX3d displacement = Eigen::MatrixX3d::Zero(V.rows(), 3);
    double squares = 0;
    int measurements = 0;  // a vertex in both patches (a mirror's own half) is measured twice
    std::vector<Eigen::Index> moving;
    for (Eigen::Index v = 0; v < V.rows(); ++v) {
        const int k = m.symmetry[size_t(v)];
        if (k < 0) continue;
        const Transformation& T = detected.symmetries[size_t(k)].transform;
        const Eigen::Vector3d p = V.row(v).transpose();
        Eigen::Vector3d sum = Eigen::Vector3d::Zero();
        int rules = 0;
        // Source side: T(p) half-way to the surface it lands on, pulled back by T⁻¹;
        // target side the same under T⁻¹ (whose distances are divided by the scale).
        for (const bool source : {true, false}) {
            if (!(source ? m.in_source : m.in_target)[size_t(v)]) continue;
            const Transformation map = source ? T : T.inverse();
            const Eigen::Vector3d image = map.apply(p);
            const ClosestPoint c = surface.closest(image, source ? max_distance : max_distance / T.scale);
            if (!c.found) continue;
            const Eigen::Vector3d goal = (source ? T.inverse() : T).apply(0.5 * (image + c.point));
            sum += goal - p;
            squares += std::pow(source ? c.distance : c.distance * T.scale, 2);
            ++rules;
        }
        if (rules == 0) continue;
        measurements += rules;
        displacement.row(v) = strength * sum.transpose() / rules;
        if (strength > 0) moving.push_back(v);
    }
    // Only the vertices that move are written: adding a zero would turn a -0 into +0.
    for (Eigen::Index v : moving) V.row(v) += displacement.row(v);
    return {measurements ? std::sqrt(squares / measurements) : 0, int(moving.size())};
}

}  // namespace

void SymmetrizationOptions::validate() const {
    require_parameter(strength >= 0 && strength <= 1, "strength", strength, "between 0 and 1");
    require_parameter(iterations >= 1 && iterations <= 100, "symmetrization_iterations", iterations, "between 1 and 100");
    require_parameter(max_distance_in_tolerances > 0, "max_distance_in_tolerances", max_distance_in_tolerances,
                      "greater than 0");
}

SymmetrizationResult symmetrize(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, const DetectionResult& detected,
                                double verification_tolerance, const SymmetrizationOptions& options) {
    options.validate();
    require_result_of_mesh(detected, V.rows());
    const Membership m = membership(detected, V.rows());
    const double diagonal = (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm();
    const double max_distance = options.max_distance_in_tolerances * verification_tolerance * diagonal;
    SymmetrizationResult out;
    out.V = V;
    for (int pass = 0; pass < options.iterations; ++pass) {
        const PassOutcome outcome = symmetrization_pass(out.V, F, detected, m, max_distance, options.strength);
        if (pass == 0) {
            out.rms_before = outcome.rms / diagonal;
            out.moved_vertices = outcome.moved;
        }
    }
    // The deviation left: a pass of strength 0 measures without moving.
    out.rms_after = symmetrization_pass(out.V, F, detected, m, max_distance, 0).rms / diagonal;
    return out;
}

}  // namespace symmetry
