#include "verification.h"

#include "statistics.h"

#include <algorithm>
#include <cmath>

namespace symmetry {

double systematic_deviation(const MeshNeighbourhoods& mesh, const std::vector<int>& patch,
                            const std::vector<double>& deviation, int iterations) {
    if (patch.empty()) return 0;
    std::vector<int> local(size_t(mesh.vertex_count()), -1);
    for (size_t i = 0; i < patch.size(); ++i) local[size_t(patch[i])] = int(i);
    std::vector<double> s(patch.size()), next(patch.size());
    for (size_t i = 0; i < patch.size(); ++i) s[i] = deviation[size_t(patch[i])];
    for (int it = 0; it < iterations; ++it) {
        for (size_t i = 0; i < patch.size(); ++i) {
            const int v = patch[i];
            double sum = s[i];
            int count = 1;
            for (int k = mesh.neighbour_offsets[v]; k < mesh.neighbour_offsets[v + 1]; ++k) {
                int j = local[size_t(mesh.neighbours[size_t(k)])];
                if (j >= 0) { sum += s[size_t(j)]; ++count; }
            }
            next[i] = sum / count;
        }
        s.swap(next);
    }
    double sum2 = 0;
    for (double x : s) sum2 += x * x;
    return std::sqrt(sum2 / double(s.size()));
}

namespace {

// The vertices as ICP fits them: positions, each weighted by the area it stands for.
struct FitPoints {
    std::vector<int> vertices;
    std::vector<Eigen::Vector3d> positions;
    std::vector<double> areas;
};

FitPoints fit_points(const MeshNeighbourhoods& mesh, const std::vector<int>& vertices) {
    FitPoints p;
    p.vertices = vertices;
    p.positions.reserve(vertices.size());
    p.areas.reserve(vertices.size());
    for (int v : vertices) {
        p.positions.push_back(mesh.positions[size_t(v)]);
        p.areas.push_back(mesh.vertex_areas[size_t(v)]);
    }
    return p;
}

// ICP pairs each vertex with a face its normal agrees with, as region growing accepts
// vertices (see the matcher overload of refine_by_icp).
IcpResult refine_by_icp(const MeshNeighbourhoods& mesh, const FitPoints& points, const SurfaceQuery& surface,
                        const Transformation& start, TransformationGroup group, int iterations,
                        const VerificationOptions& options) {
    const double min_cosine = std::cos(options.normal_agreement_degrees * M_PI / 180.0);
    const bool any_open = any_open_component(mesh);
    std::vector<Eigen::Vector3d> normals;
    const IcpMatcher facing = [&](size_t i, const Transformation& T, const Eigen::Vector3d&, double radius) {
        return facing_landing(mesh, surface, points.vertices[i], T, radius, min_cosine, any_open, normals);
    };
    return refine_by_icp(points.positions, points.areas, facing, start, group, options.tolerance, iterations,
                         options.icp);
}


// Step 1: the pairs whose vote lies nearest to the cluster's mode agree best with it, so
// they start first.  Ties are broken by vertex, so the order, and hence the result, does
// not depend on the order in which the cluster listed its pairs.
std::vector<int> order_seeds(std::vector<Seed> seeds, int vertex_count) {
    std::sort(seeds.begin(), seeds.end(), [](const Seed& a, const Seed& b) {
        return a.distance_to_mode != b.distance_to_mode ? a.distance_to_mode < b.distance_to_mode : a.vertex < b.vertex;
    });
    std::vector<int> order;
    std::vector<char> seen(size_t(vertex_count), 0);
    for (const Seed& s : seeds)
        if (s.vertex >= 0 && s.vertex < vertex_count && !seen[size_t(s.vertex)]) {
            seen[size_t(s.vertex)] = 1;
            order.push_back(s.vertex);
        }
    return order;
}

// Whether T moves every point of the box by less than `distance`.  |T(x) - x| is convex in
// x, so its largest value over the box is at a corner.  With the mesh's bounding box and the
// tolerance: T moves every patch less than the tolerance, which accept() rejects as the
// identity, and ICP started there stays there (the identity fits any patch exactly).
bool moves_less_than(const Transformation& T, const Eigen::AlignedBox3d& box, double distance) {
    for (int corner = 0; corner < 8; ++corner) {
        const Eigen::Vector3d x = box.corner(Eigen::AlignedBox3d::CornerType(corner));
        if ((T.apply(x) - x).norm() >= distance) return false;
    }
    return true;
}

// The ICP refit a patch gets each time it doubles while growing (step 2).  It gives up
// on the patch when even the refitted transformation leaves a systematic deviation far
// above the acceptance bound: two smooth patches touching, which growth would otherwise
// slide along.  (The deviations are those recorded at acceptance, under the previous
// fit: close enough for an early exit with a margin of two.)  A refit whose result is a
// known relation stops the growth too, and sets `known_hit`; so does one that has become the
// identity (moves_less_than), setting `identity_hit`: a cluster of near-identity votes would
// otherwise grow over the whole mesh, be refitted and regrown, and only then be rejected.
RegionGrower::Refit growing_refit(const MeshNeighbourhoods& mesh, const SurfaceQuery& surface,
                                  const RegionGrower& grower, const VerificationOptions& options,
                                  const KnownRelation& known, const Eigen::AlignedBox3d& box, bool& known_hit,
                                  bool& identity_hit) {
    return [&mesh, &surface, &grower, &options, &known, &box, &known_hit, &identity_hit](const std::vector<int>& patch,
                                                                                       Transformation& t) {
        if (!options.refine_with_icp) return RefitOutcome::Unchanged;
        IcpResult r = refine_by_icp(mesh, fit_points(mesh, patch), surface, t, options.group,
                                    options.icp.iterations_while_growing, options);
        if (!r.refitted) return RefitOutcome::Unchanged;
        t = r.transform;
        if (known && known(t, patch)) {
            known_hit = true;
            return RefitOutcome::Hopeless;
        }
        if (moves_less_than(t, box, options.tolerance)) {
            identity_hit = true;
            return RefitOutcome::Hopeless;
        }
        double systematic = systematic_deviation(mesh, patch, grower.deviations(), options.deviation_smoothing_iterations);
        if (systematic > 1.5 * options.max_systematic_deviation * options.tolerance) return RefitOutcome::Hopeless;
        return RefitOutcome::Refitted;
    };
}

// Step 2: one connected source component per seed not yet covered, each grown from the
// current estimate of T with a copy of its own.  A component that is hopeless or too
// small is dropped on its own (and its vertices are not tried again: a later seed inside
// it would start from the same estimate and grow the same component).  The estimate is
// refitted on all accepted components each time they have doubled.  Growth stops at
// once, with `known` set, when the estimate becomes a known relation.
struct SourceComponents {
    std::vector<int> vertices;
    Transformation estimate;
    bool known = false;
    bool identity = false;  // the estimate became the identity: the candidate is rejected
};

SourceComponents grow_source_components(const MeshNeighbourhoods& mesh, const SurfaceQuery& surface,
                                        const Transformation& mode, const std::vector<int>& seeds,
                                        const VerificationOptions& options, const KnownRelation& known,
                                        const Eigen::AlignedBox3d& box) {
    RegionGrower grower(mesh, surface, {options.tolerance, options.normal_agreement_degrees});
    SourceComponents out;
    out.identity = moves_less_than(mode, box, options.tolerance);
    if (out.identity) return out;
    const RegionGrower::Refit refit = growing_refit(mesh, surface, grower, options, known, box, out.known, out.identity);
    std::vector<char> scratch(size_t(mesh.vertex_count()), 0);
    out.estimate = mode;
    size_t refitted_at = 0;
    for (int seed : seeds) {
        if (grower.tried(seed)) continue;
        Transformation local = out.estimate;
        bool hopeless = false;
        std::vector<int> component = grower.grow(seed, local, nullptr, refit, hopeless);
        if (out.known || out.identity) return out;
        if (component.empty()) continue;
        if (hopeless || area_of(mesh, component, scratch) < options.min_patch_area) {
            grower.forbid(component);
            continue;
        }
        const bool first = out.vertices.empty();
        out.vertices.insert(out.vertices.end(), component.begin(), component.end());
        if (first) out.estimate = local;
        if (options.refine_with_icp && out.vertices.size() >= 2 * refitted_at) {
            IcpResult r = refine_by_icp(mesh, fit_points(mesh, out.vertices), surface, out.estimate, options.group,
                                        options.icp.iterations_while_growing, options);
            if (r.refitted) out.estimate = r.transform;
            refitted_at = out.vertices.size();
            if (moves_less_than(out.estimate, box, options.tolerance)) {
                out.identity = true;
                return out;
            }
            if (known && known(out.estimate, out.vertices)) {
                out.known = true;
                return out;
            }
        }
    }
    std::sort(out.vertices.begin(), out.vertices.end());
    return out;
}

// Step 3a: the final T, refined on all accepted components.  An improper T that is
// nearly its own inverse is a mirror up to the fit's freedom: ICP over all improper
// motions may tilt it into a slight rotoreflection where the shape is only
// approximately symmetric.  It is refitted as a pure mirror and kept as one unless
// that fits clearly worse (glide reflections and true rotoreflections are not involutions
// and stay as they are).
Transformation final_fit(const MeshNeighbourhoods& mesh, const SurfaceQuery& surface, const std::vector<int>& vertices,
                         const Transformation& start, const VerificationOptions& options) {
    const FitPoints points = fit_points(mesh, vertices);
    IcpResult fit = refine_by_icp(mesh, points, surface, start, options.group, options.icp.iterations, options);
    if (!fit.refitted) return start;
    const Transformation& T = fit.transform;
    if (!T.reflection || options.group == TransformationGroup::Reflections || std::abs(T.scale - 1) > 1e-6) return T;
    const Transformation twice = T * T;
    const std::vector<Eigen::Vector3d>& p = points.positions;
    const size_t stride = std::max<size_t>(1, p.size() / 64);
    for (size_t i = 0; i < p.size(); i += stride)
        if ((twice.apply(p[i]) - p[i]).norm() > 4 * options.tolerance) return T;
    Eigen::Vector3d n;
    double d;
    mirror_plane(T, n, d);
    IcpResult mirror = refine_by_icp(mesh, points, surface, pure_mirror(n, d), TransformationGroup::Reflections,
                                     options.icp.iterations, options);
    return mirror.refitted && mirror.rms <= options.mirror_snap_rms_ratio * fit.rms + 1e-3 * options.tolerance
               ? mirror.transform
               : T;
}

// Step 3b: the mesh's other connected components that T maps onto the surface (a model
// made of separate parts, a wing on each side).  No pair of the cluster need lie on them,
// so each is tried from a few vertices spread over it, and kept, whatever its size, when
// T carries most of it: "the connected components of the model that are invariant under
// the transformation" (§4).  Most of it, so that a part that merely touches the surface
// under T is not taken.  Debris is not swept (VerificationOptions::debris).
void sweep_other_components(const MeshNeighbourhoods& mesh, const Transformation& T, RegionGrower& grower,
                            const VerificationOptions& options, std::vector<int>& patch) {
    std::vector<char> scratch(size_t(mesh.vertex_count()), 0);
    std::vector<char> done(mesh.component_areas.size(), 0);
    const std::vector<char> beyond_debris = components_beyond_debris(mesh, options.debris);
    for (size_t c = 0; c < done.size(); ++c) done[c] = !beyond_debris[c];
    for (int v : patch) done[size_t(mesh.component_of[size_t(v)])] = 1;
    Transformation fixed = T;
    bool hopeless = false;
    for (size_t c = 0; c < done.size(); ++c) {
        if (done[c]) continue;
        const int first = mesh.member_offsets[c], count = mesh.member_offsets[c + 1] - first;
        const int stride = std::max(1, count / std::max(1, options.component_probes));
        for (int i = 0; i < count; i += stride) {
            const int v = mesh.members[size_t(first + i)];
            if (grower.tried(v)) continue;
            std::vector<int> grown = grower.grow(v, fixed, nullptr, nullptr, hopeless);
            if (grown.empty()) continue;
            if (area_of(mesh, grown, scratch) >= options.min_component_share * mesh.component_areas[c])
                patch.insert(patch.end(), grown.begin(), grown.end());
            break;
        }
    }
}

// Step 3: the final T, refined on all accepted components, and the source patch regrown
// under it from those components, so every vertex of the result is measured under the
// same T (and the border rejected under earlier estimates gets another chance).
std::vector<int> regrow_under_final_transform(const MeshNeighbourhoods& mesh, const std::vector<int>& accepted,
                                              const Transformation& T, RegionGrower& grower,
                                              const VerificationOptions& options) {
    std::vector<char> scratch(size_t(mesh.vertex_count()), 0);
    std::vector<int> patch;
    Transformation fixed = T;
    bool hopeless = false;
    for (int v : accepted) {
        if (grower.tried(v)) continue;
        std::vector<int> component = grower.grow(v, fixed, nullptr, nullptr, hopeless);
        if (component.empty()) continue;
        if (area_of(mesh, component, scratch) < options.min_patch_area) continue;
        patch.insert(patch.end(), component.begin(), component.end());
    }
    if (!patch.empty()) sweep_other_components(mesh, fixed, grower, options, patch);
    std::sort(patch.begin(), patch.end());
    return patch;
}

// The bound on a patch's systematic deviation, as a fraction of the tolerance: it rises
// with the square of the area up to half the model (see
// VerificationOptions::max_systematic_deviation).
double systematic_bound(double area, const VerificationOptions& options) {
    const double largeness = options.large_patch_area > 0 ? std::min(1.0, area / options.large_patch_area) : 1.0;
    return options.max_systematic_deviation_small +
           largeness * largeness * (options.max_systematic_deviation - options.max_systematic_deviation_small);
}

// Step 4a: the deviation of every source vertex (recorded by the grower under the final
// T), its RMS and largest value, and the patch's area and displacement.  Returns the RMS
// displacement of the patch under T.
double measure_patch(const MeshNeighbourhoods& mesh, const RegionGrower& grower, VerifiedSymmetry& s) {
    double displacement2 = 0, deviation2 = 0;
    for (int v : s.source_vertices) {
        const Eigen::Vector3d& p = mesh.positions[size_t(v)];
        const double d = grower.deviation(v);
        s.source_deviation.push_back(d);
        deviation2 += d * d;
        s.max_error = std::max(s.max_error, std::abs(d));
        displacement2 += (s.transform.apply(p) - p).squaredNorm();
    }
    const double count = double(s.source_vertices.size());
    s.rms_error = std::sqrt(deviation2 / count);
    std::vector<char> scratch(size_t(mesh.vertex_count()), 0);
    s.source_area = area_of(mesh, s.source_vertices, scratch);
    return std::sqrt(displacement2 / count);
}

double median_magnitude(const std::vector<double>& values) {
    std::vector<double> magnitudes;
    magnitudes.reserve(values.size());
    for (double d : values) magnitudes.push_back(std::abs(d));
    return median(std::move(magnitudes));
}

// Step 4b: the deviation is coherent under the tolerance: most of the patch maps closely
// (the median), and what does not average out (the systematic part) stays within the bound
// for the patch's size.
bool coherent(const MeshNeighbourhoods& mesh, const RegionGrower& grower, VerifiedSymmetry& s,
              const VerificationOptions& options) {
    const double median = median_magnitude(s.source_deviation);
    if (median > options.max_median_deviation * options.tolerance) return false;
    s.systematic_error = systematic_deviation(mesh, s.source_vertices, grower.deviations(),
                                              options.deviation_smoothing_iterations);
    return s.systematic_error <= systematic_bound(s.source_area, options) * options.tolerance +
                                     options.systematic_noise_allowance * options.noise;
}

// Step 4: a symmetry moves its patch (the identity and small slides along a continuous
// self-map do not), covers enough area, and deviates from perfect symmetry coherently.
bool accept(const MeshNeighbourhoods& mesh, const RegionGrower& grower, VerifiedSymmetry& s,
            const VerificationOptions& options) {
    const double moved = measure_patch(mesh, grower, s);
    if (moved < options.tolerance) return false;
    s.small_motion = moved < options.min_displacement;
    if (s.source_area < options.min_patch_area) return false;
    return coherent(mesh, grower, s, options);
}

// Step 5: the target patch, the vertices w whose preimage T⁻¹(w) lands on a face of the
// source patch, grown from the vertices of the faces the source lands on.
void grow_target_side(const MeshNeighbourhoods& mesh, const SurfaceQuery& surface, const RegionGrower& source,
                      VerifiedSymmetry& s, const VerificationOptions& options) {
    std::vector<char> in_source(size_t(mesh.vertex_count()), 0);
    for (int v : s.source_vertices) in_source[size_t(v)] = 1;
    std::vector<char> source_faces(mesh.faces.size(), 0);
    for (int v : s.source_vertices)
        for (int k = mesh.face_offsets[v]; k < mesh.face_offsets[v + 1]; ++k) source_faces[size_t(mesh.faces_around[k])] = 1;
    // T⁻¹ divides distances by the scale, so the same tolerance shrinks with it.
    RegionGrower target(mesh, surface, {options.tolerance / s.transform.scale, options.normal_agreement_degrees});
    const Transformation inverse = s.transform.inverse();
    bool hopeless = false;
    std::vector<int> patch;
    for (int v : s.source_vertices) {
        const auto& corners = mesh.faces[size_t(source.landing_face(v))];
        for (int w : corners) {
            if (target.tried(w)) continue;
            Transformation fixed = inverse;
            std::vector<int> component = target.grow(w, fixed, &source_faces, nullptr, hopeless);
            patch.insert(patch.end(), component.begin(), component.end());
        }
    }
    std::sort(patch.begin(), patch.end());
    s.target_vertices = patch;
    for (int w : patch) s.target_deviation.push_back(target.deviation(w) * s.transform.scale);
}

}  // namespace

std::optional<VerifiedSymmetry> verify_candidate(const MeshNeighbourhoods& mesh, const SurfaceQuery& surface,
                                                 const Transformation& mode, std::vector<Seed> seeds,
                                                 const VerificationOptions& options, const KnownRelation& known,
                                                 RejectedRelation* rejected) {
    const std::vector<int> order = order_seeds(std::move(seeds), mesh.vertex_count());
    Eigen::AlignedBox3d box;
    for (const Eigen::Vector3d& p : mesh.positions) box.extend(p);
    SourceComponents components = grow_source_components(mesh, surface, mode, order, options, known, box);
    if (components.known || components.identity || components.vertices.empty()) return std::nullopt;

    VerifiedSymmetry s;
    s.transform = components.estimate;
    if (options.refine_with_icp) s.transform = final_fit(mesh, surface, components.vertices, s.transform, options);
    if (std::abs(std::log(s.transform.scale / mode.scale)) > std::log(options.max_scale_change)) return std::nullopt;
    // A final fit that slid into the identity would regrow the whole mesh under it, only for
    // accept() to reject it as moving its patch less than the tolerance.
    if (moves_less_than(s.transform, box, options.tolerance)) return std::nullopt;
    RegionGrower final_source(mesh, surface, {options.tolerance, options.normal_agreement_degrees});
    s.source_vertices = regrow_under_final_transform(mesh, components.vertices, s.transform, final_source, options);
    if (s.source_vertices.empty()) return std::nullopt;
    if (!accept(mesh, final_source, s, options)) {
        if (rejected) *rejected = {s.transform, s.source_vertices};
        return std::nullopt;
    }
    grow_target_side(mesh, surface, final_source, s, options);
    return s;
}

}  // namespace symmetry
