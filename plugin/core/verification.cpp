#include "verification.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <deque>

namespace symmetry {

VertexNeighbours vertex_neighbours(const Mesh& mesh) {
    const int n = int(mesh.vert.size());
    std::vector<std::vector<int>> lists(n);
    for (const auto& f : mesh.face) {
        if (f.IsD()) continue;
        for (int k = 0; k < 3; ++k) {
            int a = int(vcg::tri::Index(mesh, f.cV(k))), b = int(vcg::tri::Index(mesh, f.cV((k + 1) % 3)));
            lists[a].push_back(b);
            lists[b].push_back(a);
        }
    }
    VertexNeighbours adjacency;
    adjacency.offsets.reserve(n + 1);
    adjacency.offsets.push_back(0);
    for (auto& l : lists) {
        std::sort(l.begin(), l.end());
        l.erase(std::unique(l.begin(), l.end()), l.end());
        adjacency.neighbours.insert(adjacency.neighbours.end(), l.begin(), l.end());
        adjacency.offsets.push_back(int(adjacency.neighbours.size()));
    }
    return adjacency;
}

Transformation fit_transformation(const std::vector<Eigen::Vector3d>& source, const std::vector<Eigen::Vector3d>& target,
                                  TransformationGroup group, bool reflection) {
    const int n = int(source.size());
    Eigen::Matrix3Xd X(3, n), Y(3, n);
    for (int i = 0; i < n; ++i) { X.col(i) = source[i]; Y.col(i) = target[i]; }
    switch (group) {
    case TransformationGroup::Translations: {
        Transformation t;
        t.translation = (Y - X).rowwise().mean();
        return t;
    }
    case TransformationGroup::Reflections: {
        // A mirror moves every point along the plane normal n: n is the dominant
        // direction of the displacements, the plane passes through the midpoints.
        Eigen::Matrix3Xd D = Y - X;
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(D * D.transpose());
        Eigen::Vector3d normal = eig.eigenvectors().col(2);
        double offset = normal.dot(0.5 * (X + Y).rowwise().mean());
        Transformation t;
        t.reflection = true;
        t.rotation = (Eigen::Matrix3d::Identity() - 2 * normal * normal.transpose()) * Transformation::mirror();
        t.translation = 2 * offset * normal;
        return t;
    }
    case TransformationGroup::Rigid:
    case TransformationGroup::Similarity: {
        // Umeyama finds a proper similarity; an improper one is fitted to the mirrored
        // source and composed with the mirror, the same split as in Transformation.
        Eigen::Matrix3Xd S = reflection ? Eigen::Matrix3Xd(Transformation::mirror() * X) : X;
        Eigen::Matrix4d U = Eigen::umeyama(S, Y, group == TransformationGroup::Similarity);
        Eigen::Matrix3d A = U.topLeftCorner<3, 3>();
        if (reflection) A = A * Transformation::mirror();
        return Transformation::from_linear(A, U.topRightCorner<3, 1>());
    }
    }
    return Transformation();
}

namespace {

// One linearised point-to-plane step (Chen and Medioni; Rusinkiewicz and Levoy 2001):
// the small motion x -> x + ω × (x - c) + σ (x - c) + τ about the centroid c that best
// moves the points `moved` onto the tangent planes (q, n).  Point-to-point steps crawl
// along directions in which the surface nearly slides onto itself (a bumpy torus turning
// about its axis); point-to-plane steps do not.  σ is fitted only for similarities.
Transformation point_to_plane_step(const std::vector<Eigen::Vector3d>& moved, const std::vector<Eigen::Vector3d>& q,
                                   const std::vector<Eigen::Vector3d>& n, bool with_scale) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (const auto& p : moved) c += p;
    c /= double(moved.size());
    const int k = with_scale ? 7 : 6;
    Eigen::MatrixXd AtA = Eigen::MatrixXd::Zero(k, k);
    Eigen::VectorXd Atb = Eigen::VectorXd::Zero(k);
    Eigen::VectorXd row(k);
    for (size_t i = 0; i < moved.size(); ++i) {
        Eigen::Vector3d x = moved[i] - c;
        row.head<3>() = x.cross(n[i]);
        row.segment<3>(3) = n[i];
        if (with_scale) row(6) = x.dot(n[i]);
        double residual = (moved[i] - q[i]).dot(n[i]);
        AtA += row * row.transpose();
        Atb -= row * residual;
    }
    Eigen::VectorXd x = AtA.ldlt().solve(Atb);
    Transformation step;
    if (!x.allFinite()) return step;
    Eigen::Vector3d omega = x.head<3>();
    if (omega.norm() > 0) step.rotation = Eigen::AngleAxisd(omega.norm(), omega.normalized()).toRotationMatrix();
    step.scale = with_scale ? std::exp(x(6)) : 1.0;
    // x -> s R (x - c) + c + τ
    step.translation = c + x.segment<3>(3) - step.scale * step.rotation * c;
    return step;
}

Eigen::Vector3d position(const Vertex& v) { return Eigen::Vector3d(v.cP()[0], v.cP()[1], v.cP()[2]); }
Eigen::Vector3d normal(const Vertex& v) { return Eigen::Vector3d(v.cN()[0], v.cN()[1], v.cN()[2]); }

// Normals must agree too: otherwise a thin plate's two sides, or a surface crossing
// another, would pass the distance test alone.
const double kNormalAgreement = std::cos(M_PI / 4);

// A symmetry must hold well inside the tolerance over its patch.  Two unrelated smooth
// patches with equal curvatures (which pairing brings together) also touch: their gap
// grows from zero at the contact to the tolerance at the patch border, which gives an
// RMS of about tolerance/2 (cubic growth over a disk).  A true, even noisy, symmetry
// has an RMS far below that, set by noise and tessellation.
const double kMaxRmsToTolerance = 0.25;

// A patch of a few hundred vertices pins down all degrees of freedom of the
// transformation; fitted on fewer, ICP follows the noise of a small patch.
const size_t kMinIcpVertices = 256;
const int kIcpIterations = 20;
const int kIcpIterationsWhileGrowing = 4;

// One side of a symmetry: grows the set of vertices v whose image T(v) lies on the
// surface, restricted (for the target side) to images that land on `allowed` faces.
class RegionGrower {
public:
    RegionGrower(const Mesh& mesh, const VertexNeighbours& adjacency, const SurfaceQuery& surface, double tolerance)
        : mesh_(mesh), adjacency_(adjacency), surface_(surface), tolerance_(tolerance),
          state_(mesh.vert.size(), kUnknown), deviation_(mesh.vert.size(), 0.0) {}

    bool accepts(int v, const Transformation& T, const std::vector<char>* allowed_faces) {
        const Vertex& vertex = mesh_.vert[v];
        ClosestPoint cp = surface_.closest(T.apply(position(vertex)), tolerance_);
        if (!cp.found) return false;
        if (T.apply_to_normal(normal(vertex)).dot(cp.normal) < kNormalAgreement) return false;
        if (allowed_faces && !(*allowed_faces)[cp.face]) return false;
        deviation_[v] = cp.signed_distance;
        return true;
    }

    // Breadth-first growth from `seed` over mesh edges; calls refit(patch) whenever the
    // patch has doubled, and retries the rejected border with the refined transformation.
    template <class Refit>
    std::vector<int> grow(int seed, Transformation& T, const std::vector<char>* allowed_faces, Refit&& refit,
                          const bool& stop) {
        std::vector<int> patch;
        if (state_[seed] == kInPatch) return patch;
        if (!accepts(seed, T, allowed_faces)) { state_[seed] = kRejected; return patch; }
        std::deque<int> queue{seed};
        std::vector<int> rejected;
        state_[seed] = kInPatch;
        patch.push_back(seed);
        size_t next_refit = kMinIcpVertices;
        while (!queue.empty() && !stop) {
            int v = queue.front();
            queue.pop_front();
            for (int k = adjacency_.offsets[v]; k < adjacency_.offsets[v + 1]; ++k) {
                int u = adjacency_.neighbours[k];
                if (state_[u] == kInPatch) continue;
                if (state_[u] == kRejected) continue;
                if (accepts(u, T, allowed_faces)) {
                    state_[u] = kInPatch;
                    patch.push_back(u);
                    queue.push_back(u);
                } else {
                    state_[u] = kRejected;
                    rejected.push_back(u);
                }
            }
            if (patch.size() >= next_refit && refit(patch, T)) {
                next_refit *= 2;
                // The border rejected under the old transformation may match now.
                for (int u : rejected)
                    if (state_[u] == kRejected && accepts(u, T, allowed_faces)) {
                        state_[u] = kInPatch;
                        patch.push_back(u);
                        queue.push_back(u);
                    }
                rejected.erase(std::remove_if(rejected.begin(), rejected.end(),
                                              [&](int u) { return state_[u] == kInPatch; }),
                               rejected.end());
            }
        }
        return patch;
    }

    void release(const std::vector<int>& patch) {
        for (int v : patch) state_[v] = kRejected;
    }
    bool in_patch(int v) const { return state_[v] == kInPatch; }
    double deviation(int v) const { return deviation_[v]; }

private:
    enum : char { kUnknown = 0, kInPatch = 1, kRejected = 2 };
    const Mesh& mesh_;
    const VertexNeighbours& adjacency_;
    const SurfaceQuery& surface_;
    double tolerance_;
    std::vector<char> state_;
    std::vector<double> deviation_;
};

double patch_area(const Mesh& mesh, const std::vector<char>& in_patch) {
    double area = 0;
    for (const auto& f : mesh.face) {
        if (f.IsD()) continue;
        if (in_patch[vcg::tri::Index(mesh, f.cV(0))] && in_patch[vcg::tri::Index(mesh, f.cV(1))] &&
            in_patch[vcg::tri::Index(mesh, f.cV(2))])
            area += 0.5 * ((f.cP(1) - f.cP(0)) ^ (f.cP(2) - f.cP(0))).Norm();
    }
    return area;
}

}  // namespace

std::optional<VerifiedSymmetry> verify_by_region_growing(const Mesh& mesh, const VertexNeighbours& adjacency,
                                                         const SurfaceQuery& surface,
                                                         const Transformation& candidate,
                                                         const std::vector<int>& seed_vertices,
                                                         const VerificationOptions& options) {
    const size_t nv = mesh.vert.size();
    Transformation T = candidate;

    // ICP (Rusinkiewicz and Levoy 2001): closest points of the transformed patch, then
    // the best transformation of the group for those correspondences, iterated until the
    // patch stops moving.  A stride keeps each iteration to a few thousand points.
    bool hopeless = false;   // set when a refit shows the candidate cannot pass
    auto refit_with = [&](const std::vector<int>& patch, Transformation& t, int iterations) {
        if (!options.refine_with_icp || patch.size() < kMinIcpVertices) return false;
        const size_t stride = std::max<size_t>(1, patch.size() / 4000);
        const bool planar = options.group == TransformationGroup::Rigid || options.group == TransformationGroup::Similarity;
        std::vector<Eigen::Vector3d> src, moved, dst, normals;
        bool changed = false;
        for (int iteration = 0; iteration < iterations; ++iteration) {
            src.clear();
            moved.clear();
            dst.clear();
            normals.clear();
            for (size_t i = 0; i < patch.size(); i += stride) {
                Eigen::Vector3d p = position(mesh.vert[patch[i]]);
                ClosestPoint cp = surface.closest(t.apply(p), 2 * options.tolerance);
                if (!cp.found) continue;
                src.push_back(p);
                moved.push_back(t.apply(p));
                dst.push_back(cp.point);
                normals.push_back(cp.normal);
            }
            if (src.size() < kMinIcpVertices / 2) break;
            Transformation fitted = planar ? point_to_plane_step(moved, dst, normals,
                                                                 options.group == TransformationGroup::Similarity) * t
                                           : fit_transformation(src, dst, options.group, t.reflection);
            if (!fitted.matrix().allFinite()) break;
            double shift = 0;
            for (size_t i = 0; i < src.size(); ++i) shift = std::max(shift, (fitted.apply(src[i]) - moved[i]).norm());
            t = fitted;
            changed = true;
            if (shift < 1e-3 * options.tolerance) break;
        }
        if (changed) {
            double sum = 0;
            for (size_t i = 0; i < src.size(); ++i) sum += (t.apply(src[i]) - dst[i]).squaredNorm();
            // Far above the final bound even after refitting: two patches merely touching;
            // stop growing rather than cover the model with them.
            if (std::sqrt(sum / double(src.size())) > 2 * kMaxRmsToTolerance * options.tolerance) hopeless = true;
        }
        return changed;
    };
    // While the patch grows a few ICP iterations suffice, since each refit starts from the
    // previous one; the final refit converges fully.
    auto refit = [&](const std::vector<int>& patch, Transformation& t) {
        return refit_with(patch, t, kIcpIterationsWhileGrowing);
    };
    auto no_refit = [](const std::vector<int>&, Transformation&) { return false; };

    // Source side: one connected patch per seed that is not yet covered.
    RegionGrower source(mesh, adjacency, surface, options.tolerance);
    std::vector<char> in_source(nv, 0);
    for (int seed : seed_vertices) {
        if (seed < 0 || size_t(seed) >= nv || source.in_patch(seed)) continue;
        std::vector<int> component = source.grow(seed, T, nullptr, refit, hopeless);
        if (hopeless) return std::nullopt;
        if (component.empty()) continue;
        std::vector<char> mask(nv, 0);
        for (int v : component) mask[v] = 1;
        if (patch_area(mesh, mask) < options.min_patch_area) {
            source.release(component);  // too small to be a symmetry (§4: significant patches only)
            continue;
        }
        for (int v : component) in_source[v] = 1;
    }

    VerifiedSymmetry result;
    for (size_t v = 0; v < nv; ++v)
        if (in_source[v]) result.source_vertices.push_back(int(v));
    if (result.source_vertices.empty()) return std::nullopt;

    // Final ICP over the whole patch, then deviations under the final transformation.
    refit_with(result.source_vertices, T, kIcpIterations);
    double displacement2 = 0, deviation2 = 0;
    std::vector<int> kept;
    std::vector<int> landing_faces;  // where T(v) lands: the target side grows from there
    for (int v : result.source_vertices) {
        Eigen::Vector3d p = position(mesh.vert[v]);
        ClosestPoint cp = surface.closest(T.apply(p), 2 * options.tolerance);
        if (!cp.found) { in_source[v] = 0; continue; }  // drifted away under the refined T
        kept.push_back(v);
        landing_faces.push_back(cp.face);
        result.source_deviation.push_back(cp.signed_distance);
        deviation2 += cp.distance * cp.distance;
        displacement2 += (T.apply(p) - p).squaredNorm();
    }
    result.source_vertices = std::move(kept);
    if (result.source_vertices.empty()) return std::nullopt;
    const double count = double(result.source_vertices.size());
    if (std::sqrt(displacement2 / count) < options.min_displacement) return std::nullopt;
    result.source_area = patch_area(mesh, in_source);
    if (result.source_area < options.min_patch_area) return std::nullopt;
    result.rms_error = std::sqrt(deviation2 / count);
    if (result.rms_error > kMaxRmsToTolerance * options.tolerance) return std::nullopt;
    result.transform = T;

    // Target side: the vertices w whose preimage T⁻¹(w) lands on a face of the source patch.
    std::vector<char> source_faces(mesh.face.size(), 0);
    for (size_t f = 0; f < mesh.face.size(); ++f) {
        const Face& face = mesh.face[f];
        if (face.IsD()) continue;
        for (int k = 0; k < 3; ++k)
            if (in_source[vcg::tri::Index(mesh, face.cV(k))]) source_faces[f] = 1;
    }
    const Transformation inverse = T.inverse();
    const bool never = false;
    // T⁻¹ divides distances by the scale, so the same tolerance shrinks with it.
    RegionGrower target(mesh, adjacency, surface, options.tolerance / T.scale);
    std::vector<char> in_target(nv, 0);
    for (int f : landing_faces) {
        const Face& face = mesh.face[f];
        for (int k = 0; k < 3; ++k) {
            int w = int(vcg::tri::Index(mesh, face.cV(k)));
            if (in_target[w]) continue;
            Transformation inv = inverse;
            for (int u : target.grow(w, inv, &source_faces, no_refit, never)) in_target[u] = 1;
        }
    }
    for (size_t w = 0; w < nv; ++w)
        if (in_target[w]) {
            result.target_vertices.push_back(int(w));
            // Deviation measured in the target's own units.
            result.target_deviation.push_back(target.deviation(int(w)) * T.scale);
        }
    return result;
}

}  // namespace symmetry
