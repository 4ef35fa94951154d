#include "detection.h"

#include "kd_tree.h"
#include "mean_shift.h"
#include "pairing.h"
#include "sampling.h"
#include "signatures.h"
#include "surface_query.h"
#include "umbilic_pruning.h"
#include "verification.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <random>
#include <sstream>

namespace symmetry {

namespace {

template <class T>
void require(bool ok, const char* name, T value, const char* range) {
    if (ok) return;
    std::ostringstream s;
    s << "The parameter " << name << " is " << value << ", but it must be " << range << ".";
    throw InputError(s.str());
}

double seconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// A cluster of §3.1 turned into a candidate symmetry: its mode and the pairs voting for it.
struct Candidate {
    Transformation transform;
    int height = 0;
    std::vector<int> votes;  // indices into the transformation points
};

// The vertex of the sample's face nearest to the sample: where region growing starts.
int seed_vertex(const Mesh& mesh, const SurfaceSignature& s) {
    const Face& f = mesh.face[s.face];
    int best = 0;
    double best_d = INFINITY;
    for (int k = 0; k < 3; ++k) {
        double d = (Eigen::Vector3d(f.cP(k)[0], f.cP(k)[1], f.cP(k)[2]) - s.position).squaredNorm();
        if (d < best_d) { best_d = d; best = k; }
    }
    return int(vcg::tri::Index(mesh, f.cV(best)));
}

}  // namespace

void DetectionOptions::validate() const {
    int g = int(group);
    require(g >= 0 && g <= 3, "transformation_group", g, "0, 1, 2 or 3");
    require(sample_count >= 100 && sample_count <= 5000000, "sample_count", sample_count, "between 100 and 5,000,000");
    require(pair_sample_count >= 1 && pair_sample_count <= 5000000, "pair_sample_count", pair_sample_count,
            "between 1 and 5,000,000");
    require(curvature_radius > 0 && curvature_radius <= 0.5, "curvature_radius", curvature_radius,
            "greater than 0 and at most half the bounding-box diagonal");
    require(umbilic_ratio > 0 && umbilic_ratio < 1, "umbilic_ratio", umbilic_ratio, "strictly between 0 and 1");
    require(signature_tolerance > 0 && signature_tolerance <= 10, "signature_tolerance", signature_tolerance,
            "greater than 0 and at most 10");
    require(cluster_bandwidth > 0 && cluster_bandwidth <= 1, "cluster_bandwidth", cluster_bandwidth,
            "greater than 0 and at most the bounding-box diagonal");
    require(min_cluster_support >= 2, "min_cluster_support", min_cluster_support, "at least 2");
    require(verification_tolerance > 0 && verification_tolerance <= 0.25, "verification_tolerance",
            verification_tolerance, "greater than 0 and at most a quarter of the bounding-box diagonal");
    require(min_patch_area >= 0 && min_patch_area <= 1, "min_patch_area", min_patch_area,
            "between 0 and 100 percent of the surface area");
    require(max_symmetries >= 1 && max_symmetries <= 1000, "max_symmetries", max_symmetries, "between 1 and 1000");
    require(basis_loop_length >= 1 && basis_loop_length <= 6, "basis_loop_length", basis_loop_length,
            "between 1 and 6 (the search grows exponentially with it)");
    require(basis_tolerance > 0 && basis_tolerance <= 1, "basis_tolerance", basis_tolerance,
            "greater than 0 and at most the bounding-box diagonal");
}

DetectionResult detect_partial_symmetries(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F,
                                          const DetectionOptions& options, const Progress& progress) {
    options.validate();
    auto report = [&](int percent, const char* stage) {
        if (progress) progress(percent, stage);
    };
    DetectionResult result;

    Mesh mesh;
    std::vector<int> vertex_of_input;
    build_mesh(V, F, mesh, vertex_of_input);
    const double diagonal = mesh.bbox.Diag();
    const Eigen::Vector3d center(mesh.bbox.Center()[0], mesh.bbox.Center()[1], mesh.bbox.Center()[2]);
    const double total_area = surface_area(mesh);
    const double radius = options.curvature_radius * diagonal;
    const TransformationGroup group = options.group;
    std::mt19937_64 rng(options.random_seed);

    // §2, §2.1: samples, signatures, pruning.
    auto start = std::chrono::steady_clock::now();
    report(0, "Sampling and curvature signatures");
    std::vector<SurfaceSample> samples = uniform_area_sampling(mesh, options.sample_count, rng);
    std::vector<SurfaceSignature> P = prune_umbilics(compute_signatures(mesh, samples, radius),
                                                     options.umbilic_ratio, radius);
    result.samples = int(samples.size());
    result.pruned_samples = int(P.size());
    result.seconds_signatures = seconds_since(start);

    // §2.2: pairs in signature space, one or more points in Γ per pair.  Pairs closer
    // than the curvature ball share their neighbourhood and only vote for the identity.
    start = std::chrono::steady_clock::now();
    report(25, "Pairing in signature space");
    std::vector<SignaturePair> pairs = pair_in_signature_space(P, group, radius, options.signature_tolerance,
                                                               options.pair_sample_count, 2 * radius, rng);
    const TransformationSpace space(center, diagonal);
    std::vector<Transformation> points;
    std::vector<int> pair_of_point;
    for (size_t k = 0; k < pairs.size(); ++k)
        for (const Transformation& t : transformations_from_frames(P[pairs[k].first], P[pairs[k].second], group)) {
            points.push_back(t);
            pair_of_point.push_back(int(k));
        }
    result.pairs = int(pairs.size());
    result.transformation_points = int(points.size());
    result.seconds_pairing = seconds_since(start);

    // §3.1: mean shift, separately for proper and improper transformations (they are
    // different sheets of Γ; no path of small steps joins them).
    start = std::chrono::steady_clock::now();
    report(45, "Mean-shift clustering in transformation space");
    std::vector<Candidate> candidates;
    // At most this many clusters are verified (§4); each sheet of Γ may offer them all.
    const size_t max_tries = size_t(std::max(60, 3 * options.max_symmetries));
    for (bool reflection : {false, true}) {
        std::vector<int> index;
        for (size_t i = 0; i < points.size(); ++i)
            if (points[i].reflection == reflection) index.push_back(int(i));
        if (index.empty()) continue;
        KdTree::Points coordinates(index.size(), TransformationSpace::kDimension);
        for (size_t i = 0; i < index.size(); ++i) coordinates.row(i) = space.coordinates(points[index[i]]).transpose();
        const KdTree tree(std::move(coordinates));
        MeanShiftOptions ms;
        ms.bandwidth = options.cluster_bandwidth;
        ms.min_support = options.min_cluster_support;
        ms.max_modes = int(4 * max_tries);  // merges and repeats of T⁻¹ use up some
        ms.project = [&space](Eigen::Ref<Eigen::VectorXd> x) { space.project(x); };
        for (const Cluster& c : mean_shift(tree, ms)) {
            Candidate candidate;
            candidate.transform = space.transformation(c.mode, reflection);
            candidate.height = c.height;
            for (int m : c.members) candidate.votes.push_back(index[m]);
            candidates.push_back(std::move(candidate));
        }
    }
    std::stable_sort(candidates.begin(), candidates.end(),
                     [](const Candidate& a, const Candidate& b) { return a.height > b.height; });
    result.clusters = int(candidates.size());
    result.seconds_clustering = seconds_since(start);

    // §4: verification by region growing, most significant cluster first.
    start = std::chrono::steady_clock::now();
    report(60, "Verification by region growing");
    const VertexNeighbours adjacency = vertex_neighbours(mesh);
    const SurfaceQuery surface(mesh);
    VerificationOptions vo;
    vo.tolerance = options.verification_tolerance * diagonal;
    vo.min_patch_area = options.min_patch_area * total_area;
    vo.min_displacement = std::max(2 * radius, 4 * vo.tolerance);
    vo.refine_with_icp = options.refine_with_icp;
    vo.group = group;

    struct Found {
        VerifiedSymmetry symmetry;
        int support;
    };
    std::vector<Found> found;
    std::vector<Transformation> tried;
    // The same relation is found as T and as T⁻¹ (pairs are ordered), and nearby modes
    // may refine to the same T: one verification and one report per relation.
    auto same_relation = [&](const Transformation& a, const Transformation& b) {
        return space.distance(a, b) < options.cluster_bandwidth ||
               space.distance(a, b.inverse()) < options.cluster_bandwidth;
    };
    // A relation already reported is credited with the votes of this cluster too.
    auto merge_into_found = [&](const Transformation& t, int support) {
        for (auto& f : found)
            if (same_relation(t, f.symmetry.transform)) {
                f.support += support;
                return true;
            }
        return false;
    };
    for (size_t c = 0; c < candidates.size() && c < max_tries; ++c) {
        report(60 + int(38 * c / std::min(candidates.size(), max_tries)), "Verification by region growing");
        if (int(found.size()) >= options.max_symmetries) break;
        const Candidate& candidate = candidates[c];
        if (merge_into_found(candidate.transform, candidate.height)) continue;
        if (std::any_of(tried.begin(), tried.end(),
                        [&](const Transformation& t) { return same_relation(candidate.transform, t); }))
            continue;
        tried.push_back(candidate.transform);
        std::vector<int> seeds;
        for (int v : candidate.votes) seeds.push_back(seed_vertex(mesh, P[pairs[pair_of_point[v]].first]));
        auto verified = verify_by_region_growing(mesh, adjacency, surface, candidate.transform, seeds, vo);
        if (!verified) continue;
        if (merge_into_found(verified->transform, candidate.height)) continue;
        found.push_back({std::move(*verified), candidate.height});
    }
    result.seconds_verification = seconds_since(start);

    // Most significant first: the larger the patch, the more of the model it explains.
    std::stable_sort(found.begin(), found.end(), [](const Found& a, const Found& b) {
        if (a.symmetry.source_area != b.symmetry.source_area) return a.symmetry.source_area > b.symmetry.source_area;
        return a.support > b.support;
    });

    // §4.1: generators and compound transforms.
    std::vector<Transformation> transforms;
    for (const auto& f : found) transforms.push_back(f.symmetry.transform);
    SymmetryBasis basis;
    if (options.reduce_basis) {
        basis = reduce_basis(transforms, space, options.basis_loop_length, options.basis_tolerance);
    } else {
        // Without reduction every symmetry is its own generator: the trivial basis.
        for (size_t k = 0; k < found.size(); ++k) {
            basis.generators.push_back(int(k));
            basis.words.push_back({int(k) + 1});
        }
    }
    result.generator_count = int(basis.generators.size());

    // Outputs in the input's vertex numbering.
    result.vertex_deviation.assign(V.rows(), 0.0);
    result.vertex_symmetry_id.assign(V.rows(), -1);
    for (size_t k = 0; k < found.size(); ++k) {
        const VerifiedSymmetry& s = found[k].symmetry;
        DetectedSymmetry d;
        d.transform = s.transform;
        d.rms_error = s.rms_error / diagonal;
        d.source_area = s.source_area / total_area;
        d.support = found[k].support;
        d.is_generator = std::find(basis.generators.begin(), basis.generators.end(), int(k)) != basis.generators.end();
        d.word = basis.words[k];
        auto write = [&](const std::vector<int>& vertices, const std::vector<double>& deviation, std::vector<int>& out) {
            for (size_t i = 0; i < vertices.size(); ++i) {
                int row = vertex_of_input[vertices[i]];
                out.push_back(row);
                if (result.vertex_symmetry_id[row] < 0) {
                    result.vertex_symmetry_id[row] = int(k);
                    result.vertex_deviation[row] = deviation[i] / diagonal;
                }
            }
            std::sort(out.begin(), out.end());
        };
        write(s.source_vertices, s.source_deviation, d.source_vertices);
        write(s.target_vertices, s.target_deviation, d.target_vertices);
        result.symmetries.push_back(std::move(d));
    }
    report(100, "Done");
    return result;
}

}  // namespace symmetry
