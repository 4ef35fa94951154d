#include "reduction.h"

#include "surface_query.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <string>
#include <utility>

namespace symmetry {
namespace {

// The input as one searchable surface, answering with rows of F.
class Surface {
public:
    Surface(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F) : rows_(V, F) {}
    /// The row of F of the face nearest to x within max_distance; -1 if none.
    int face_at(const Eigen::Vector3d& x, double max_distance) const {
        return rows_.closest(x, max_distance).face;
    }
    double distance(const Eigen::Vector3d& x, double max_distance) const {
        const ClosestPoint c = rows_.closest(x, max_distance);
        return c.found ? c.distance : max_distance;
    }

private:
    SurfaceOfRows rows_;
};

// The points of a face that must all land back on the surface for it to be a copy: its
// corners, the midpoints of its edges and its centre.  Where the other copy is tessellated
// more finely, the faces these land on are what rebuilds the face, so more points leave
// fewer gaps.
std::vector<Eigen::Vector3d> probe_points(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, int f) {
    const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    return {a, b, c, 0.5 * (a + b), 0.5 * (b + c), 0.5 * (c + a), (a + b + c) / 3};
}

enum class FaceState : char { Free, Locked, Removed };

// Where the reduction stands: per face whether it is kept, kept as what rebuilds a copy
// (locked), or removed, and for a removed face the instance that rebuilds it.
struct ReductionState {
    std::vector<FaceState> state;
    std::vector<int> instance_of;  // per removed face: index into instances
    std::vector<ReducedInstance> instances;
    std::map<std::vector<int>, int> instance_of_word;
};

// A face traced back to kept faces: per probe point, the word that maps kept faces onto
// it and the face it lands on.  Points of one face may come back by different words: near
// the end of an orbit a corner lands where one chain ends and the next begins.
struct Trace {
    std::vector<std::vector<int>> words;
    std::vector<int> faces;
};

// The transformation a letter of a word stands for: +(k+1) symmetry k, -(k+1) its inverse.
Transformation letter_transform(const DetectionResult& detected, int letter) {
    const Transformation& T = detected.symmetries[size_t(std::abs(letter) - 1)].transform;
    return letter > 0 ? T : T.inverse();
}

Transformation composed(const DetectionResult& detected, const std::vector<int>& word) {
    Transformation t;
    for (int letter : word) t = t * letter_transform(detected, letter);
    return t;
}

// Follows one point of a face the letter's transformation T maps onto back to a kept face:
// T⁻¹, then, while it lands on a removed face, that face's instance inverted.  Returns false
// where it leaves the surface or the chain grows too long.
bool trace_point(const Eigen::Vector3d& p, int letter, const DetectionResult& detected, const ReductionState& r,
                 const Surface& surface, double max_distance, int max_chain, std::vector<int>& word, int& face) {
    const Transformation T = letter_transform(detected, letter);
    word.assign(1, letter);
    Eigen::Vector3d x = T.inverse().apply(p);
    double scale = T.scale;  // distances at x are those at p divided by the composed scale
    for (;;) {
        face = surface.face_at(x, max_distance / scale);
        if (face < 0) return false;
        if (r.state[size_t(face)] != FaceState::Removed) return true;
        const ReducedInstance& through = r.instances[size_t(r.instance_of[size_t(face)])];
        if (int(word.size() + through.word.size()) > max_chain) return false;
        word.insert(word.end(), through.word.begin(), through.word.end());
        x = through.transform.inverse().apply(x);
        scale *= through.transform.scale;
    }
}

// Face f, of the patch the letter's transformation maps onto, traced back, or nothing when
// it is no copy: a point leaves the surface, comes back to f itself, or comes back by a word
// that maps it onto itself (a point on a mirror's plane, or a mirror applied twice).
std::optional<Trace> trace_face(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, int f, int letter,
                                const DetectionResult& detected, const ReductionState& r, const Surface& surface,
                                double max_distance, int max_chain) {
    Trace trace;
    for (const Eigen::Vector3d& p : probe_points(V, F, f)) {
        std::vector<int> word;
        int face = -1;
        if (!trace_point(p, letter, detected, r, surface, max_distance, max_chain, word, face)) return {};
        if (face == f) return {};
        if ((composed(detected, word).inverse().apply(p) - p).norm() <= max_distance) return {};
        trace.words.push_back(std::move(word));
        trace.faces.push_back(face);
    }
    return trace;
}

// Removes f: each point's kept face joins the instance of its word, and is locked.  f is
// rebuilt, for later traces through it, by the instance of its centre (the last point).
void remove_face(int f, const Trace& trace, const DetectionResult& detected, ReductionState& r) {
    int instance_of_centre = -1;
    for (size_t i = 0; i < trace.words.size(); ++i) {
        auto [it, created] = r.instance_of_word.try_emplace(trace.words[i], int(r.instances.size()));
        if (created) {
            ReducedInstance instance;
            instance.word = trace.words[i];
            instance.transform = composed(detected, trace.words[i]);
            r.instances.push_back(std::move(instance));
        }
        r.instances[size_t(it->second)].faces.push_back(trace.faces[i]);
        r.state[size_t(trace.faces[i])] = FaceState::Locked;
        instance_of_centre = it->second;
    }
    ++r.instances[size_t(instance_of_centre)].removed_faces;
    r.state[size_t(f)] = FaceState::Removed;
    r.instance_of[size_t(f)] = instance_of_centre;
}

// The faces whose three corners are in `patch`.
std::vector<int> faces_of_patch(const Eigen::MatrixX3i& F, const std::vector<int>& patch, Eigen::Index rows) {
    std::vector<char> in_target(size_t(rows), 0);
    for (int v : patch) in_target[size_t(v)] = 1;
    std::vector<int> faces;
    for (Eigen::Index f = 0; f < F.rows(); ++f)
        if (in_target[size_t(F(f, 0))] && in_target[size_t(F(f, 1))] && in_target[size_t(F(f, 2))])
            faces.push_back(int(f));
    return faces;
}

// Where a point lies along the orbit of T: a phase that T advances by one step.  For a
// translation t the position along t (in steps of |t|); for a rotation by θ about an axis
// (or a screw) the angle about the axis, in steps of θ; for a mirror (or a glide) minus the
// signed distance to the plane, which T turns into its negative.  Nothing for a
// similarity, whose copies are other parts.
struct OrbitPhase {
    enum class Kind { None, Translation, Rotation, Mirror } kind = Kind::None;
    Eigen::Vector3d point = Eigen::Vector3d::Zero();      // on the axis or plane
    Eigen::Vector3d direction = Eigen::Vector3d::Zero();  // translation / |t|², unit axis or normal
    Eigen::Vector3d reference = Eigen::Vector3d::Zero();  // a rotation's angle 0, unit, ⟂ axis
    double step = 1;                                       // a rotation's angle θ

    explicit OrbitPhase(const Transformation& T, double min_angle) {
        if (std::abs(T.scale - 1) > 1e-9) return;
        const Eigen::Matrix3d L = T.linear();
        if (T.reflection) {
            // The normal n of the mirror plane: L n = -n, the eigenvector of L's symmetric part
            // with the smallest eigenvalue; T(x) = x - 2 (n·x - d) n puts the plane at
            // d = n·T(0) / 2 (a glide's slide along the plane does not change it).
            Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> e(0.5 * (L + L.transpose()));
            direction = e.eigenvectors().col(0);
            point = 0.5 * direction.dot(T.translation) * direction;
            kind = Kind::Mirror;
            return;
        }
        const Eigen::AngleAxisd turn(T.rotation);
        if (std::abs(turn.angle()) < min_angle) {
            if (T.translation.squaredNorm() == 0) return;
            direction = T.translation / T.translation.squaredNorm();
            kind = Kind::Translation;
            return;
        }
        // The axis a, through the point c with (I - R) c = t minus its part along a.
        direction = turn.axis();
        step = turn.angle();
        const Eigen::Vector3d t = T.translation - T.translation.dot(direction) * direction;
        point = (Eigen::Matrix3d::Identity() - T.rotation + direction * direction.transpose())
                    .colPivHouseholderQr()
                    .solve(t);
        reference = direction.unitOrthogonal();
        kind = Kind::Rotation;
    }

    double operator()(const Eigen::Vector3d& x) const {
        const Eigen::Vector3d r = x - point;
        switch (kind) {
        case Kind::Translation: return r.dot(direction);
        case Kind::Mirror: return -r.dot(direction);
        case Kind::Rotation: {
            const double angle = std::atan2(direction.cross(reference).dot(r), reference.dot(r));
            return (angle < 0 ? angle + 2 * M_PI : angle) / step;
        }
        case Kind::None: break;
        }
        return 0;
    }
};

// The target faces in orbit order: each after the face it is a copy of, so that an orbit is
// rebuilt from its first member (a row from its first copy, a turned orbit from one sector,
// a mirror from one side).  Faces are taken by the phase of their centres; around a rotation
// the order starts after the widest gap in angle, so a partial orbit (three of six blades)
// is not cut in two.  A similarity keeps the rows' order.
std::vector<int> orbit_order(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, const std::vector<int>& faces,
                             const Transformation& T, double min_angle) {
    const OrbitPhase phase(T, min_angle);
    if (phase.kind == OrbitPhase::Kind::None || faces.empty()) return faces;
    std::vector<std::pair<double, int>> order;
    for (int f : faces)
        order.emplace_back(phase((V.row(F(f, 0)) + V.row(F(f, 1)) + V.row(F(f, 2))).transpose() / 3), f);
    std::sort(order.begin(), order.end());
    if (phase.kind == OrbitPhase::Kind::Rotation) {
        const double turn = 2 * M_PI / phase.step;  // the phase of a whole turn
        size_t widest = 0;  // the face after the widest gap, wrapping round
        double gap = order.front().first + turn - order.back().first;
        for (size_t i = 1; i < order.size(); ++i)
            if (order[i].first - order[i - 1].first > gap) gap = order[i].first - order[i - 1].first, widest = i;
        std::rotate(order.begin(), order.begin() + std::ptrdiff_t(widest), order.end());
    }
    std::vector<int> rows;
    for (const auto& [p, f] : order) rows.push_back(f);
    return rows;
}

// Largest distance from the points (vertices and face centres) of the faces `rows` of (V, F)
// to `surface`, capped at `cap`.
double farthest(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, const std::vector<int>& rows,
                const Surface& surface, double cap) {
    double worst = 0;
    for (int f : rows) {
        const std::vector<Eigen::Vector3d> points = probe_points(V, F, f);
        for (size_t i : {0, 1, 2, 6}) worst = std::max(worst, surface.distance(points[i], cap));
    }
    return worst;
}

double reconstruction_error(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, const ReductionResult& reduced,
                            const Surface& input, double diagonal) {
    if (reduced.instances.empty()) return 0;
    Eigen::MatrixX3d RV;
    Eigen::MatrixX3i RF;
    reconstruct(V, F, reduced, RV, RF);
    const Surface rebuilt(RV, RF);
    std::vector<int> removed, copies;
    std::vector<char> kept(size_t(F.rows()), 0);
    for (int f : reduced.kept_faces) kept[size_t(f)] = 1;
    for (Eigen::Index f = 0; f < F.rows(); ++f)
        if (!kept[size_t(f)]) removed.push_back(int(f));
    for (Eigen::Index f = Eigen::Index(reduced.kept_faces.size()); f < RF.rows(); ++f) copies.push_back(int(f));
    const double cap = 0.25 * diagonal;  // "far off": a distance beyond is reported as this
    return std::max(farthest(V, F, removed, rebuilt, cap), farthest(RV, RF, copies, input, cap)) / diagonal;
}

}  // namespace

void ReductionOptions::validate() const {
    require_parameter(max_distance_in_tolerances > 0 && max_distance_in_tolerances <= 10,
                      "max_distance_in_tolerances", max_distance_in_tolerances, "greater than 0 and at most 10");
    require_parameter(max_chain_length >= 1 && max_chain_length <= 64, "max_chain_length", max_chain_length,
                      "between 1 and 64");
    require_parameter(min_rotation_angle > 0 && min_rotation_angle < 1, "min_rotation_angle", min_rotation_angle,
                      "strictly between 0 and 1 radian");
}

ReductionResult reduce_by_symmetry(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F,
                                   const DetectionResult& detected, double verification_tolerance,
                                   const ReductionOptions& options) {
    options.validate();
    require_result_of_mesh(detected, V.rows());
    const Surface surface(V, F);
    const double diagonal = (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm();
    const double max_distance = options.max_distance_in_tolerances * verification_tolerance * diagonal;
    ReductionState r;
    r.state.assign(size_t(F.rows()), FaceState::Free);
    r.instance_of.assign(size_t(F.rows()), -1);
    // Each symmetry both ways: T maps its source patch onto its target, T⁻¹ the target onto
    // the source; which copy an earlier symmetry locked decides which way removes faces.
    for (size_t k = 0; k < detected.symmetries.size(); ++k) {
        const DetectedSymmetry& s = detected.symmetries[k];
        if (s.continuous_kind != ContinuousKind::Discrete) continue;
        for (const int letter : {int(k) + 1, -int(k) - 1}) {
            const std::vector<int>& patch = letter > 0 ? s.target_vertices : s.source_vertices;
            const std::vector<int> faces = faces_of_patch(F, patch, V.rows());
            const Transformation T = letter_transform(detected, letter);
            for (int f : orbit_order(V, F, faces, T, options.min_rotation_angle)) {
                if (r.state[size_t(f)] != FaceState::Free) continue;
                std::optional<Trace> trace =
                    trace_face(V, F, f, letter, detected, r, surface, max_distance, options.max_chain_length);
                if (trace) remove_face(f, *trace, detected, r);
            }
        }
    }
    ReductionResult out;
    for (Eigen::Index f = 0; f < F.rows(); ++f)
        if (r.state[size_t(f)] != FaceState::Removed) out.kept_faces.push_back(int(f));
    for (ReducedInstance& instance : r.instances) {
        std::sort(instance.faces.begin(), instance.faces.end());
        instance.faces.erase(std::unique(instance.faces.begin(), instance.faces.end()), instance.faces.end());
    }
    out.instances = std::move(r.instances);
    out.size_ratio = F.rows() ? double(out.kept_faces.size()) / double(F.rows()) : 1;
    out.reconstruction_error = reconstruction_error(V, F, out, surface, diagonal);
    return out;
}

void reconstruct(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, const ReductionResult& reduction,
                 Eigen::MatrixX3d& rebuilt_V, Eigen::MatrixX3i& rebuilt_F) {
    std::vector<Eigen::Vector3d> positions;
    std::vector<Eigen::Vector3i> triangles;
    // Appends the faces `rows`, each vertex once, mapped by t.
    auto append = [&](const std::vector<int>& rows, const Transformation& t) {
        std::map<int, int> at;
        for (int f : rows) {
            Eigen::Vector3i triangle;
            for (int c = 0; c < 3; ++c) {
                auto [it, created] = at.try_emplace(F(f, c), int(positions.size()));
                if (created) positions.push_back(t.apply(V.row(F(f, c)).transpose()));
                triangle[c] = it->second;
            }
            // A reflection turns the faces inside out: reverse them to keep the normals outward.
            if (t.reflection) std::swap(triangle[1], triangle[2]);
            triangles.push_back(triangle);
        }
    };
    append(reduction.kept_faces, Transformation());
    for (const ReducedInstance& instance : reduction.instances) append(instance.faces, instance.transform);
    rebuilt_V.resize(Eigen::Index(positions.size()), 3);
    for (size_t i = 0; i < positions.size(); ++i) rebuilt_V.row(Eigen::Index(i)) = positions[i].transpose();
    rebuilt_F.resize(Eigen::Index(triangles.size()), 3);
    for (size_t i = 0; i < triangles.size(); ++i) rebuilt_F.row(Eigen::Index(i)) = triangles[i].transpose();
}

}  // namespace symmetry
