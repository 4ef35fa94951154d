#include "detection.h"

#include "curvature_agreement.h"
#include "kd_tree.h"
#include "lookahead.h"
#include "mean_shift.h"
#include "pairing.h"
#include "point_cloud.h"
#include "sampling.h"
#include "signatures.h"
#include "surface_query.h"
#include "umbilic_pruning.h"
#include "working_mesh.h"

#include <vcg/complex/append.h>
#include <vcg/complex/algorithms/update/topology.h>

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <numeric>
#include <random>
#include <sstream>

namespace symmetry {

namespace {

// require_parameter (detection.h) under a name short enough for validate()'s table of ranges.
template <class T>
void require(bool ok, const char* name, T value, const char* range) {
    require_parameter(ok, name, value, range);
}

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// The input as the stages see it.  A large input is analysed on a simplified copy
// (working_mesh.h).  When the input (or that copy) is noisy, signatures and region growing
// work on a presmoothed copy with the same vertices and faces (denoising.h).  Either way the
// deviation from perfect symmetry is measured on the input itself.
struct Model {
    Mesh input;
    std::unique_ptr<Mesh> working;     // the simplified copy of a large input, or the refined one of a coarse input
    std::vector<int> working_vertex;   // per input vertex, the nearest vertex of `working`
    std::unique_ptr<Mesh> smoothed;
    std::vector<int> vertex_of_input;  // row in V of every input vertex
    MeshRepairs repairs;               // a welded soup, turned faces (input_repair.h)
    double diagonal = 0, total_area = 0;
    double radius = 0;  // the curvature ball's radius r (§2), absolute units
    double noise = 0;   // estimated noise (denoising.h), absolute units
    // A presmoothed cloud's noise before smoothing, in point spacings (0 otherwise): what its
    // curvature agreement can no longer see (CurvatureAgreementOptions::min_area_excused_by_cloud_noise).
    double smoothed_noise_in_spacings = 0;
    DebrisRule debris;  // which connected components are specks (region_growing.h)
    Eigen::Vector3d center = Eigen::Vector3d::Zero();
    // A point cloud: the points the stages see (a large cloud's working subset, presmoothed
    // if noisy), their outward normals and kd-tree (point_cloud.h), and the area each point
    // stands for and its disc.  `input` then holds the points alone, and `working` the
    // subset's.  Where the stages saw other points than the input's, deviations are measured
    // on the input's own points, normals and discs (`measured_on`).
    std::unique_ptr<PointCloudSurface> cloud;
    PointAreas cloud_areas;
    struct CloudSurface {
        std::vector<Eigen::Vector3d> points, normals;
        std::vector<double> disc_radius;
    } measured_on;
    bool cloud_presmoothed = false;
    const Mesh& resolved() const { return working ? *working : input; }
    const Mesh& analysed() const { return smoothed ? *smoothed : resolved(); }
    bool measured_apart() const { return working || smoothed || !measured_on.points.empty(); }
    bool presmoothed() const { return smoothed || cloud_presmoothed; }
};

// The longest edge the working copy of a coarse mesh may keep, or 0 to analyse the mesh as it
// is.  On a coarse smooth surface (a decimated scan, a character), bent a little at every
// edge, a ball grown to hold a few edges averages the facets, as it should, and a refined copy
// would show the facets' kinks instead.  But on a CAD export, flat faces of long thin
// triangles between creases, a ball grown several times over spans whole parts until every
// sample is flat or umbilic; there the facets are the surface itself and splitting them
// loses nothing.
double edge_to_refine_to(const Model& model, const DetectionOptions& options) {
    if (options.max_radius_growth <= 0) return 0;
    const double edge = options.curvature_radius * model.diagonal / options.min_radius_in_edges;
    const double median = median_edge_length(mesh_neighbourhoods(model.input), model.debris);
    if (median <= options.max_radius_growth * edge) return 0;
    return smooth_edge_share(model.input, options.working) < options.working.max_smooth_edge_share ? edge : 0;
}

void prepare_model(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, const DetectionOptions& options,
                   const std::function<void(int, const char*)>& report, Model& model, DetectionResult& result) {
    build_mesh(V, F, model.input, model.vertex_of_input, &model.repairs);
    result.welded_vertices = model.repairs.welded_vertices;
    result.flipped_faces = model.repairs.flipped_faces;
    result.repeated_faces = model.repairs.repeated_faces;
    result.back_faces = model.repairs.back_faces;
    result.orientable = model.repairs.orientable;
    model.diagonal = model.input.bbox.Diag();
    model.center = Eigen::Vector3d(model.input.bbox.Center()[0], model.input.bbox.Center()[1], model.input.bbox.Center()[2]);
    model.total_area = surface_area(model.input);
    // A speck is smaller than the great disc of the ball curvature_radius asks for.
    const double asked_radius = options.curvature_radius * model.diagonal;
    model.debris = {options.debris_area_share, M_PI * asked_radius * asked_radius};
    const int limit = options.working.max_vertices;
    if (limit > 0 && model.input.vn > limit) {
        report(0, "Simplifying the mesh to the working resolution");
        model.working = simplified_copy(model.input, limit, options.working);
    } else if (const double edge = edge_to_refine_to(model, options); edge > 0) {
        report(0, "Refining the coarse mesh for the curvature ball");
        model.working = refined_copy_within(model.input, edge, options.working);
        result.working_refined = model.working != nullptr;
    }
    if (model.working) {
        model.working_vertex = nearest_vertices(model.input, *model.working);
        result.working_vertices = model.working->vn;
    }
    const MeshNeighbourhoods neighbourhoods = mesh_neighbourhoods(model.resolved());
    // The ball must hold a few edges, or on a coarse mesh it sees one facet's flatness
    // or a single edge's bend, and a copy tessellated otherwise gets other curvatures.
    model.radius = std::max(asked_radius, options.min_radius_in_edges * median_edge_length(neighbourhoods, model.debris));
    result.curvature_radius = model.radius / model.diagonal;
    const NoiseEstimate noise = estimate_noise(neighbourhoods, options.denoising);
    result.noise = noise.noise / model.diagonal;
    model.noise = noise.noise;
    // Never blur beyond the curvature ball: what it would remove is the shape the
    // signatures are meant to describe.  Where the noise needs more blur than the ball
    // holds, the ball grows with it (up to max_radius_for_noise): a larger ball is what
    // the paper's §6 proposes for noisy data, and smaller features are lost to the noise.
    double radius = smoothing_radius(noise, options.denoising);
    if (radius > model.radius) {
        model.radius = std::max(model.radius, std::min(radius, options.denoising.max_radius_for_noise * model.diagonal));
        result.curvature_radius = model.radius / model.diagonal;
    }
    radius = std::min(radius, model.radius);
    if (radius > 0) {
        model.smoothed = std::make_unique<Mesh>();
        // vcg's Append takes its source by non-const reference; it only reads it.
        vcg::tri::Append<Mesh, Mesh>::MeshCopy(*model.smoothed, const_cast<Mesh&>(model.resolved()));
        vcg::tri::UpdateTopology<Mesh>::FaceFace(*model.smoothed);
        vcg::tri::UpdateTopology<Mesh>::VertexFace(*model.smoothed);
        smooth_positions(*model.smoothed, radius, options.denoising);
        result.smoothing_radius = radius / model.diagonal;
    }
}

// A cloud of more than `limit` points is analysed on a Poisson-disk subset of about that
// many (working_mesh.h), as a large mesh is on a simplified copy: `points` and `normals`
// become the subset's, `working` holds it for carrying patches back to every point, and the
// input's own points, normals and discs are kept to measure deviations on.
void thin_to_working_subset(int limit, const DetectionOptions& options, Model& model, std::vector<Eigen::Vector3d>& points,
                            std::vector<Eigen::Vector3d>& normals) {
    const PointAreas areas = point_areas(points, options.point_cloud);
    const double area = std::accumulate(areas.area.begin(), areas.area.end(), 0.0);
    const std::vector<int> subset = poisson_disk_subset(model.input, limit, area, unsigned(options.random_seed), options.working);
    model.measured_on = {points, normals, areas.disc_radius};
    std::vector<Eigen::Vector3d> kept_points, kept_normals;
    for (int i : subset) {
        kept_points.push_back(points[size_t(i)]);
        kept_normals.push_back(normals[size_t(i)]);
    }
    points = std::move(kept_points);
    normals = std::move(kept_normals);
    model.working = std::make_unique<Mesh>();
    vcg::tri::Allocator<Mesh>::AddVertices(*model.working, points.size());
    for (size_t i = 0; i < points.size(); ++i)
        model.working->vert[i].P() = vcg::Point3d(points[i].x(), points[i].y(), points[i].z());
    model.working_vertex = nearest_vertices(model.input, *model.working);
}

// A point cloud as the stages see it (detect_partial_symmetries_in_point_cloud): the
// points, their normals (estimated where the cloud has none), the area each stands for,
// and the curvature ball, debris and noise as a mesh's, measured over the neighbour graph.
void prepare_cloud_model(const Eigen::MatrixX3d& V, const Eigen::MatrixX3d& N, const DetectionOptions& options,
                         const std::function<void(int, const char*)>& report, Model& model, DetectionResult& result) {
    if (V.rows() == 0) throw InputError("The point cloud is empty: it has no points.");
    if (!V.allFinite()) throw InputError("The point cloud has coordinates that are not finite numbers (NaN or infinity).");
    std::vector<Eigen::Vector3d> points(size_t(V.rows()));
    for (Eigen::Index i = 0; i < V.rows(); ++i) points[size_t(i)] = V.row(i).transpose();
    std::vector<Eigen::Vector3d> normals;
    result.point_cloud = true;
    result.normals_estimated = N.rows() == 0;
    if (N.rows() == 0) {
        normals = estimate_point_normals(points, options.point_cloud);
    } else {
        if (N.rows() != V.rows() || !N.allFinite())
            throw InputError("The point cloud's normals must be finite, one per point.");
        for (Eigen::Index i = 0; i < N.rows(); ++i) {
            const Eigen::Vector3d n = N.row(i).transpose();
            if (!(n.norm() > 0)) throw InputError("The point cloud has a zero normal: give every point one, or none.");
            normals.push_back(n.normalized());
        }
    }
    vcg::tri::Allocator<Mesh>::AddVertices(model.input, points.size());
    for (size_t i = 0; i < points.size(); ++i) {
        model.input.vert[i].P() = vcg::Point3d(points[i].x(), points[i].y(), points[i].z());
        model.input.vert[i].N() = vcg::Point3d(normals[i].x(), normals[i].y(), normals[i].z());
    }
    vcg::tri::UpdateBounding<Mesh>::Box(model.input);
    model.vertex_of_input.resize(points.size());
    std::iota(model.vertex_of_input.begin(), model.vertex_of_input.end(), 0);
    model.diagonal = model.input.bbox.Diag();
    if (!(model.diagonal > 0)) throw InputError("The point cloud's points all lie at one position.");
    model.center = Eigen::Vector3d(model.input.bbox.Center()[0], model.input.bbox.Center()[1], model.input.bbox.Center()[2]);
    const int limit = options.working.max_vertices;
    if (limit > 0 && V.rows() > limit) {
        report(0, "Thinning the point cloud to the working resolution");
        thin_to_working_subset(limit, options, model, points, normals);
        result.working_vertices = model.working->vn;
    }
    model.cloud_areas = point_areas(points, options.point_cloud);
    model.total_area = std::accumulate(model.cloud_areas.area.begin(), model.cloud_areas.area.end(), 0.0);
    model.cloud = std::make_unique<PointCloudSurface>(std::move(points), std::move(normals));
    const MeshNeighbourhoods neighbourhoods = cloud_neighbourhoods(model.cloud->points(), model.cloud->normals(),
                                                                   model.cloud_areas.area, options.point_cloud.graph_neighbours);
    const double asked_radius = options.curvature_radius * model.diagonal;
    model.debris = {options.debris_area_share, M_PI * asked_radius * asked_radius};
    model.radius = std::max(asked_radius, options.min_radius_in_edges * median_edge_length(neighbourhoods, model.debris));
    // Noise as on a mesh (denoising.h): the ball grows with it, and the points are projected
    // on their local quadric fits over the smoothing radius; deviations are measured on the
    // cloud's own points.
    const NoiseEstimate noise = estimate_noise(neighbourhoods, options.denoising);
    model.noise = noise.noise;
    result.noise = noise.noise / model.diagonal;
    // A fit to points is less forgiving than a mesh's tensor, whose edges are already a
    // piecewise-linear average: the threshold in spacings is the cloud's own.
    DenoisingOptions denoising = options.denoising;
    denoising.noise_threshold_in_edges = options.point_cloud.noise_threshold_in_spacings;
    const double blur = smoothing_radius(noise, denoising);
    if (blur > model.radius)
        model.radius = std::max(model.radius, std::min(blur, options.denoising.max_radius_for_noise * model.diagonal));
    result.curvature_radius = model.radius / model.diagonal;
    if (blur > 0) {
        const double radius = std::min(blur, model.radius);
        const bool measured_here = model.measured_on.points.empty();  // no working subset holds the input
        if (measured_here) model.measured_on = {model.cloud->points(), {}, model.cloud_areas.disc_radius};
        auto [points, normals] = model.cloud->projected_on_local_fits(radius);
        model.cloud = std::make_unique<PointCloudSurface>(std::move(points), std::move(normals));
        // The input's points under the normals of their fits: the raw normals are as noisy as the points.
        if (measured_here) model.measured_on.normals = model.cloud->normals();
        model.cloud_presmoothed = true;
        model.smoothed_noise_in_spacings = noise.noise_in_edges();
        result.smoothing_radius = radius / model.diagonal;
    }
}

// The structures of verification (§4) over what the stages analyse: a mesh's edges and
// faces, or a cloud's neighbour graph and discs.
MeshNeighbourhoods neighbourhoods_of(const Model& model, const DetectionOptions& options) {
    if (model.cloud)
        return cloud_neighbourhoods(model.cloud->points(), model.cloud->normals(), model.cloud_areas.area,
                                    options.point_cloud.graph_neighbours);
    return mesh_neighbourhoods(model.analysed());
}
SurfaceQuery surface_of(const Model& model, const DetectionOptions& options) {
    if (model.cloud) return SurfaceQuery(model.cloud->points(), model.cloud->normals(), model.cloud_areas.disc_radius);
    return SurfaceQuery(model.analysed(), options.verification.grid_cells_per_face);
}
CurvatureEstimator curvature_of(const Model& model) {
    if (model.cloud) return CurvatureEstimator(*model.cloud);
    return CurvatureEstimator(model.analysed());
}

// The dimension of Γ for the group: the degrees of freedom of its transformations.
int group_dimension(TransformationGroup group) {
    switch (group) {
    case TransformationGroup::Rigid: return 6;
    case TransformationGroup::Similarity: return 7;
    case TransformationGroup::Reflections: return 3;   // a plane
    case TransformationGroup::Translations: return 3;
    }
    return 6;
}

// A pair's points in Γ (§2.2): the transformations of `group` that map the one frame onto
// the other, without the mirrored ones where options ask for motions only (two poses).
std::vector<Transformation> points_of_pair(const SurfaceSignature& a, const SurfaceSignature& b,
                                           TransformationGroup group, const PairingOptions& options) {
    std::vector<Transformation> points = transformations_from_frames(a, b, group);
    if (options.proper_only)
        points.erase(std::remove_if(points.begin(), points.end(), [](const Transformation& t) { return t.reflection; }),
                     points.end());
    return points;
}

// The Appendix's n' for `group` (μ measured by pairing a pilot subset with a generator of
// its own, so the main sequence is the same whatever the pilot drew), lowered to keep μ n'
// within max_transformation_points.
struct AutomaticSampleCount {
    int n_prime = 0;
    double mu = 0;
    SampleSize bound;
};

AutomaticSampleCount automatic_sample_count(const std::vector<SurfaceSignature>& P, const DetectionOptions& options,
                                            TransformationGroup group, double radius, const std::mt19937_64& rng) {
    const int n = int(P.size());
    std::mt19937_64 pilot_rng = rng;
    pilot_rng.discard(1);
    const int pilot = std::min(n, options.sample_size.pilot_samples);
    std::vector<SignaturePair> pairs = pair_in_signature_space(P, group, radius, options.signature_tolerance,
                                                               pilot, 2 * radius, pilot_rng, options.pairing);
    size_t points = 0;
    for (const SignaturePair& pair : pairs)
        points += points_of_pair(P[size_t(pair.first)], P[size_t(pair.second)], group, options.pairing).size();
    AutomaticSampleCount count;
    count.mu = std::max(1.0, double(points) / std::max(1, pilot));
    count.bound = appendix_sample_size(n, std::max(options.min_patch_area, 1e-4), count.mu, group_dimension(group),
                                       options.sample_size.transformation_space_extent / options.cluster_bandwidth,
                                       1 - options.sample_size.confidence);
    const int budget = std::max(1, int(options.max_transformation_points / count.mu));
    count.n_prime = std::max(1, std::min(count.bound.n_prime, budget));
    return count;
}

// n' = |P'|: the user's, or the automatic one.  A restricted group (reflections only,
// translations only) pairs no more samples than the rigid group would: its points in Γ
// are those of the rigid group's pairs that are of its kind, so with the same n' (and
// the same draw of P') it sees every vote of its kind that the rigid group sees, against
// less background.  Its own bound, in a 3-D Γ of few points per sample, is rarely met
// and would pair every sample, slower than the full group (issue 11).
int pair_sample_count(const std::vector<SurfaceSignature>& P, const DetectionOptions& options, double radius,
                      const std::mt19937_64& rng, DetectionResult& result) {
    if (options.pair_sample_count > 0) return options.pair_sample_count;
    result.pair_sample_count_automatic = true;
    const AutomaticSampleCount own = automatic_sample_count(P, options, options.group, radius, rng);
    result.partners_per_sample = own.mu;
    result.pair_sample_size = own.bound;
    const bool restricted = options.group == TransformationGroup::Reflections ||
                            options.group == TransformationGroup::Translations;
    if (!restricted) return own.n_prime;
    const AutomaticSampleCount rigid = automatic_sample_count(P, options, TransformationGroup::Rigid, radius, rng);
    result.rigid_pair_sample_count = rigid.n_prime;
    return std::min(own.n_prime, rigid.n_prime);
}

// §2.2: the pairs of samples with similar signatures, and their points in Γ.
struct Votes {
    std::vector<SurfaceSignature> P;   // pruned samples with signatures
    std::vector<SurfaceSignature> discarded;  // the umbilic and flat samples pruning took out
    std::vector<SignaturePair> pairs;
    std::vector<Transformation> points;
    std::vector<int> pair_of_point;
};

// Appends the pairs and their points in Γ to the votes.
void add_pairs(Votes& votes, const std::vector<SignaturePair>& pairs, const DetectionOptions& options) {
    for (const SignaturePair& pair : pairs) {
        const int k = int(votes.pairs.size());
        votes.pairs.push_back(pair);
        const SurfaceSignature& a = votes.P[size_t(pair.first)];
        const SurfaceSignature& b = votes.P[size_t(pair.second)];
        for (const Transformation& t : points_of_pair(a, b, options.group, options.pairing)) {
            votes.points.push_back(t);
            votes.pair_of_point.push_back(k);
        }
    }
}

Votes vote(const Model& model, const DetectionOptions& options, std::mt19937_64& rng, DetectionResult& result) {
    const double radius = model.radius;
    Votes votes;
    auto start = Clock::now();
    std::vector<SurfaceSample> samples =
        model.cloud ? area_weighted_points(model.cloud->points(), model.cloud_areas.area, options.sample_count, rng)
                    : uniform_area_sampling(model.analysed(), options.sample_count, rng);
    // One estimator for the signatures at r and, for the samples pruning keeps, at 2r.
    const CurvatureEstimator curvature = curvature_of(model);
    for (SurfaceSignature& s : compute_signatures(curvature, samples, radius))
        (has_distinct_principal_curvatures(s, options.umbilic_ratio, radius, options.flatness) ? votes.P : votes.discarded).push_back(s);
    std::vector<SurfaceSample> kept;
    kept.reserve(votes.P.size());
    for (const SurfaceSignature& s : votes.P) kept.push_back({s.position, s.face});
    const std::vector<SurfaceSignature> coarse = compute_signatures(curvature, kept, 2 * radius);
    for (size_t i = 0; i < votes.P.size(); ++i) {
        votes.P[i].coarse_kappa1 = coarse[i].kappa1;
        votes.P[i].coarse_kappa2 = coarse[i].kappa2;
    }
    result.samples = int(samples.size());
    result.pruned_samples = int(votes.P.size());
    result.seconds_signatures = seconds_since(start);

    // Pairs closer than the curvature ball share their neighbourhood and only vote for
    // the identity.
    start = Clock::now();
    const int n_prime = pair_sample_count(votes.P, options, radius, rng, result);
    add_pairs(votes, pair_in_signature_space(votes.P, options.group, radius, options.signature_tolerance, n_prime,
                                             2 * radius, rng, options.pairing),
              options);
    result.pairs_sample_count_used = std::min(n_prime, int(votes.P.size()));
    result.seconds_pairing = seconds_since(start);
    return votes;
}

// A cluster of §3.1 turned into a candidate symmetry: its mode and the pairs voting for it.
struct Candidate {
    Transformation transform;
    int height = 0;
    std::vector<int> votes;  // indices into Votes::points
};

// §3.1: mean shift, separately for proper and improper transformations (they are different
// sheets of Γ; no path of small steps joins them).  Clustered again whenever votes leave Γ
// (see search()): a sheet that lost none keeps its candidates, and one that lost some
// counts the densities again only around the votes that left, the rest being unchanged.
class Clustering {
public:
    Clustering(const Votes& votes, const TransformationSpace& space, const DetectionOptions& options, int max_modes)
        : votes_(votes), space_(space) {
        ms_.bandwidth = options.cluster_bandwidth;
        ms_.min_support = options.min_cluster_support;
        ms_.max_modes = max_modes;
        ms_.project = [&space](Eigen::Ref<Eigen::VectorXd> x) { space.project(x); };
        for (bool reflection : {false, true}) {
            Sheet& sheet = sheets_[reflection];
            sheet.reflection = reflection;
            for (size_t i = 0; i < votes.points.size(); ++i)
                if (votes.points[i].reflection == reflection) sheet.index.push_back(int(i));
        }
    }

    /// The clusters of the active votes as candidates, most votes first.
    std::vector<Candidate> candidates(const std::vector<char>& active) {
        std::vector<Candidate> out;
        for (Sheet& sheet : sheets_) {
            update(sheet, active);
            out.insert(out.end(), sheet.candidates.begin(), sheet.candidates.end());
        }
        std::stable_sort(out.begin(), out.end(), [](const Candidate& a, const Candidate& b) { return a.height > b.height; });
        return out;
    }

private:
    struct Sheet {
        bool reflection = false;
        bool clustered = false;
        std::vector<int> index;    // its votes: indices into Votes::points
        std::vector<int> density;  // mean shift's density at each of them
        std::vector<Candidate> candidates;
    };

    KdTree::Points coordinates(const std::vector<int>& index) const {
        KdTree::Points x(index.size(), TransformationSpace::kDimension);
        for (size_t i = 0; i < index.size(); ++i) x.row(long(i)) = space_.coordinates(votes_.points[size_t(index[i])]).transpose();
        return x;
    }

    void update(Sheet& sheet, const std::vector<char>& active) {
        std::vector<int> kept, earlier, removed;  // earlier: each kept vote's entry in sheet.index
        for (size_t k = 0; k < sheet.index.size(); ++k) {
            const int v = sheet.index[k];
            if (active[size_t(v)]) {
                kept.push_back(v);
                earlier.push_back(int(k));
            } else {
                removed.push_back(v);
            }
        }
        if (sheet.clustered && removed.empty()) return;
        const bool again = sheet.clustered;
        sheet.clustered = true;
        sheet.candidates.clear();
        if (kept.empty()) {
            sheet.index.clear();
            return;
        }
        const KdTree tree(coordinates(kept));
        sheet.density = again ? densities_after_removal(tree, sheet.density, earlier, coordinates(removed), ms_)
                              : densities(tree, ms_);
        sheet.index = std::move(kept);
        for (const Cluster& c : mean_shift(tree, sheet.density, ms_)) {
            Candidate candidate;
            candidate.transform = space_.transformation(c.mode, sheet.reflection);
            candidate.height = c.height;
            for (int m : c.members) candidate.votes.push_back(sheet.index[size_t(m)]);
            sheet.candidates.push_back(std::move(candidate));
        }
    }

    const Votes& votes_;
    const TransformationSpace& space_;
    MeanShiftOptions ms_;
    Sheet sheets_[2];
};

// The vertex of the sample's face nearest to the sample: where region growing starts (on a
// cloud, the sample's point).
int seed_vertex(const Model& model, const SurfaceSignature& s) {
    if (model.cloud) return s.face;
    const Mesh& mesh = model.analysed();
    const Face& f = mesh.face[size_t(s.face)];
    int best = 0;
    double best_d = INFINITY;
    for (int k = 0; k < 3; ++k) {
        double d = (Eigen::Vector3d(f.cP(k)[0], f.cP(k)[1], f.cP(k)[2]) - s.position).squaredNorm();
        if (d < best_d) { best_d = d; best = k; }
    }
    return int(vcg::tri::Index(mesh, f.cV(best)));
}

// What verification found: discrete symmetries and continuous families.
struct Found {
    VerifiedSymmetry symmetry;
    int support = 0;
    bool slippable_source = false;  // its source patch is part of a continuous family
    std::vector<char> source_flags, target_flags;  // its patches, per vertex
};
struct Findings {
    std::vector<Found> discrete;
    std::vector<ContinuousFamily> families;
    std::vector<int> family_support;               // votes of its members
    std::vector<FamilyCheck> family_checks;        // see Verifier::check_families
    std::vector<char> family_holds;                // its finite members hold: it is reported
};

// The share of a candidate's votes whose two samples both lie in `first` and `second`
// (flags per vertex): a candidate about a patch pair already explained.
double share_of_votes_between(const Candidate& candidate, const std::vector<std::pair<int, int>>& endpoints,
                              const std::vector<char>& first, const std::vector<char>& second) {
    int inside = 0;
    for (int v : candidate.votes) {
        const auto& e = endpoints[size_t(v)];
        inside += first[size_t(e.first)] && second[size_t(e.second)];
    }
    return candidate.votes.empty() ? 0 : double(inside) / double(candidate.votes.size());
}

std::vector<char> flags(int count, const std::vector<int>& vertices) {
    std::vector<char> f(size_t(count), 0);
    for (int v : vertices) f[size_t(v)] = 1;
    return f;
}

// Two patches as one: their vertices, both increasing, merged without repeats.
std::vector<int> sorted_union(const std::vector<int>& a, const std::vector<int>& b) {
    std::vector<int> both;
    both.reserve(a.size() + b.size());
    std::set_union(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(both));
    return both;
}

double overlap(const std::vector<int>& a, const std::vector<int>& b) {  // |a ∩ b| / |a|, both sorted
    std::vector<int> common;
    std::set_intersection(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(common));
    return a.empty() ? 0 : double(common.size()) / double(a.size());
}

// §4 with the continuous families: candidates are verified most votes first.  A candidate
// whose votes lie on a family already found, and whose transformation is a member of that
// family, is skipped unverified (it does not count against the clusters verified); so is
// one whose votes join the patch pair of a discrete symmetry whose source is continuous (the
// same relation, composed with a family member).  A verified candidate whose patch pair is
// slippable is a member of a continuous family: the family is recorded once, and the
// candidate is reported beside it only if it is not one of its members.
class Verifier {
    struct Rejected {
        Transformation transform;
        std::vector<char> source;  // flags per vertex
    };
    struct KnownRelations {
        std::vector<Transformation> found;  // of the discrete symmetries found
        std::vector<std::shared_ptr<const Rejected>> rejected;
    };
    // The work space of one thread: a speculation (verification and assessment) may run on
    // each at once, each with its own.
    struct Worker {
        std::unique_ptr<CurvatureEstimator::Workspace> workspace;
        std::unique_ptr<Roughness> roughness;
        std::unique_ptr<NeighbourSamples> neighbours;  // of the samples votes_.P
    };

public:
    Verifier(const Model& model, const Votes& votes, const TransformationSpace& space, const DetectionOptions& options)
        : model_(model), votes_(votes), space_(space), options_(options),
          mesh_(neighbourhoods_of(model, options)), surface_(surface_of(model, options)), curvature_(curvature_of(model)),
          workers_(threads()) {
        for (Worker& w : workers_) {
            w.workspace = curvature_.workspace();
            w.roughness = std::make_unique<Roughness>(mesh_, options.denoising);
            w.neighbours = std::make_unique<NeighbourSamples>(votes.P.size());
        }
        const double radius = model.radius;
        vo_ = options.verification;
        vo_.tolerance = options.verification_tolerance * model.diagonal;
        vo_.min_patch_area = options.min_patch_area * model.total_area;
        vo_.large_patch_area = 0.5 * model.total_area;
        vo_.debris = model.debris;
        if (model.presmoothed()) vo_.noise = model.noise;
        co_ = options.continuous;
        if (model.noise > co_.min_noise_for_roughness * vo_.tolerance &&
            model.noise <= co_.max_noise_for_roughness * vo_.tolerance)
            co_.roughness = surface_roughness(mesh_);
        co_.presmoothed = model.presmoothed();
        vo_.min_displacement = std::max(2 * radius, 4 * vo_.tolerance);
        vo_.refine_with_icp = options.refine_with_icp;
        vo_.group = options.group;
        add_endpoints_of_new_votes();
        // A cluster's mode is only as exact as the bandwidth: so is its test for membership.
        mode_slack_distance_ = std::max(vo_.tolerance, options.cluster_bandwidth * model.diagonal);
        mode_slack_degrees_ = std::max(options.continuous.axis_agreement_degrees,
                                       TransformationSpace::rotation_degrees(options.cluster_bandwidth));
    }

    /// Whether the search is over: enough clusters verified, or every result slot filled.
    bool done(size_t max_verified) const {
        return verified_ >= max_verified || int(findings_.discrete.size()) >= options_.max_symmetries;
    }
    size_t verified() const { return verified_; }
    /// Whether a discrete symmetry or a continuous family was found.
    bool found_anything() const { return !findings_.discrete.empty() || !findings_.families.empty(); }

    /// Takes in the pairs and points appended to the votes since the last call.
    void add_endpoints_of_new_votes() {
        for (size_t k = pair_endpoints_.size(); k < votes_.pairs.size(); ++k)
            pair_endpoints_.push_back({seed_vertex(model_, votes_.P[size_t(votes_.pairs[k].first)]),
                                       seed_vertex(model_, votes_.P[size_t(votes_.pairs[k].second)])});
        for (size_t v = endpoints_.size(); v < votes_.pair_of_point.size(); ++v)
            endpoints_.push_back(pair_endpoints_[size_t(votes_.pair_of_point[v])]);
    }

    /// What classify() needs to know of a verified symmetry that depends on the symmetry
    /// alone, worked out beside its verification (see assess).
    struct Assessment {
        bool agrees = false;            // curvature agrees under T (curvature_agreement.h)
        ContinuousFamily family;        // the family the patch pair slips along; kind Discrete if none
        bool member = false;            // T is a member of that family
        bool slippable_source = false;  // the source patch alone slips along itself
    };

    /// An estimate of T that verification asked about (KnownRelation), and the source
    /// vertices it was refitted on.
    struct Ask {
        Transformation transform;
        std::vector<int> patch;
    };

    /// A candidate's verification run ahead of its turn, possibly on another core, against
    /// the discrete symmetries found and the relations rejected by then: its result, what
    /// acceptance rejected if it did, and every estimate of T that verification asked
    /// whether it was a relation assessed before, in order.  settle() recovers from it what
    /// the verification in turn returns.
    struct Speculation {
        std::optional<VerifiedSymmetry> result;
        std::optional<RejectedRelation> rejection;
        std::vector<Ask> asked;
        Assessment assessment;  // of the result
    };

    /// Threads that may speculate at once, each with its own Worker (0: the calling thread).
    static size_t threads() { return size_t(std::max(1, omp_get_max_threads())); }

    /// Whether consider() would verify the candidate now: it is neither explained nor tried.
    bool would_verify(const Candidate& candidate) { return !explaining(candidate) && !tried(candidate.transform); }

    /// Verification of the candidate against the relations known when it starts (a
    /// snapshot: the calling thread may settle others meanwhile), and the assessment of its
    /// result.  It writes only to Worker `worker` (below threads()), so candidates are
    /// speculated on several threads at once.
    Speculation speculate(const Candidate& candidate, size_t worker) const {
        std::vector<Seed> seeds;
        for (int v : candidate.votes)
            seeds.push_back({endpoints_[size_t(v)].first, space_.distance(votes_.points[size_t(v)], candidate.transform)});
        Speculation out;
        // A candidate that converges onto a discrete symmetry found before is that symmetry's;
        // one that converges onto a relation rejected before, over the same patch, would be
        // measured as it was and rejected again.
        const std::shared_ptr<const KnownRelations> relations = known_relations();
        const KnownRelation known = [this, &out, &relations](const Transformation& t, const std::vector<int>& patch) {
            out.asked.push_back({t, patch});
            return found_among(relations->found, t) || rejected_over(relations->rejected, t, patch);
        };
        RejectedRelation rejection;
        out.result = verify_candidate(mesh_, surface_, candidate.transform, std::move(seeds), vo_, known, &rejection);
        if (!rejection.source_vertices.empty()) out.rejection = std::move(rejection);
        if (out.result) out.assessment = assess(*out.result, workers_[worker]);
        return out;
    }

    /// Verifies the candidate unless it is explained already, from its speculation if it
    /// has one; returns whether a new continuous family was found.
    bool consider(const Candidate& candidate, std::optional<Speculation> ahead = std::nullopt) {
        if (explained(candidate)) return false;
        if (tried(candidate.transform)) return false;
        tried_.push_back(candidate.transform);
        ++verified_;
        const size_t families = findings_.families.size();
        if (!ahead) ahead = speculate(candidate, 0);
        mark_tried(candidate);
        const Assessment assessment = std::move(ahead->assessment);
        if (auto verified = settle(std::move(*ahead), candidate))
            classify(std::move(*verified), assessment, candidate.height);
        publish_known_relations();
        return findings_.families.size() > families;
    }

    /// Whether two transformations are one relation (see same_relation below).
    bool same_relation(const Transformation& a, const Transformation& b) const {
        return space_.distance(a, b) < options_.cluster_bandwidth ||
               space_.distance(a, b.inverse()) < options_.cluster_bandwidth;
    }

    /// Whether a candidate's estimate T, refitted on `patch`, is a relation that acceptance
    /// rejected before over most of that patch (DetectionOptions::rejected_patch_share).
    /// Only T itself: T⁻¹ over the same patch is a different hypothesis.
    bool rejected_over(const std::vector<std::shared_ptr<const Rejected>>& rejected, const Transformation& T,
                       const std::vector<int>& patch) const {
        if (patch.empty()) return false;
        for (const auto& r : rejected) {
            if (space_.distance(T, r->transform) >= options_.cluster_bandwidth) continue;
            size_t inside = 0;
            for (int v : patch) inside += size_t(r->source[size_t(v)]);
            if (double(inside) >= options_.rejected_patch_share * double(patch.size())) return true;
        }
        return false;
    }

    /// Whether T is a discrete symmetry found already.
    bool is_known(const Transformation& T) const {
        return std::any_of(findings_.discrete.begin(), findings_.discrete.end(),
                           [&](const Found& f) { return same_relation(T, f.symmetry.transform); });
    }

    /// Whether T is one of the relations `found` (a snapshot of them: see known_relations).
    bool found_among(const std::vector<Transformation>& found, const Transformation& T) const {
        return std::any_of(found.begin(), found.end(), [&](const Transformation& f) { return same_relation(T, f); });
    }

    /// Whether most of the candidate's votes join points that lie on the patches of what
    /// was found already (discrete symmetries and families).
    bool inside_explained_patches(const Candidate& candidate) {
        if (!refresh_explained()) return false;
        return share_of_votes_between(candidate, endpoints_, explained_, explained_) >= 0.8;
    }

    /// Whether the first pass leaves the candidate to the second: most of its votes join
    /// points on what was found already, or near the votes of clusters verified before.
    bool inside_what_was_verified(const Candidate& candidate) {
        return inside_explained_patches(candidate) ||
               (!tried_region_.empty() &&
                share_of_votes_between(candidate, endpoints_, tried_region_, tried_region_) >= 0.8);
    }

    /// The active votes of the samples of P' that lie away from what was verified (see
    /// away_from_what_was_verified).
    std::vector<char> votes_away_from_what_was_verified(const std::vector<char>& active) {
        std::vector<char> away = active;
        for (size_t v = 0; v < away.size(); ++v)
            if (away[v] && !away_from_what_was_verified(endpoints_[v].first)) away[v] = 0;
        return away;
    }

    /// Whether a vertex lies on no patch found and near the votes of no cluster verified.
    bool away_from_what_was_verified(int vertex) {
        const bool any_explained = refresh_explained();
        return !(any_explained && explained_[size_t(vertex)]) && !(!tried_region_.empty() && tried_region_[size_t(vertex)]);
    }

private:
    // Brings explained_ up to date with the findings; false when nothing was found yet.
    bool refresh_explained() {
        const size_t found = findings_.discrete.size() + findings_.families.size();
        if (found == 0) return false;
        if (found != explained_count_) {
            explained_.assign(size_t(mesh_.vertex_count()), 0);
            for (const auto& f : findings_.discrete)
                for (size_t v = 0; v < explained_.size(); ++v) explained_[v] |= f.source_flags[v] | f.target_flags[v];
            for (const auto& flags : family_flags_)
                for (size_t v = 0; v < explained_.size(); ++v) explained_[v] |= flags[v];
            explained_count_ = found;
        }
        return true;
    }

public:
    /// Marks the mesh within tried_region_radius of both ends of every vote of a cluster
    /// verified, over mesh neighbours (a ball of it, unless the surface folds back within
    /// the radius).
    void mark_tried(const Candidate& candidate) {
        if (tried_region_.empty()) tried_region_.assign(size_t(mesh_.vertex_count()), 0);
        const double radius = options_.tried_region_radius * model_.radius;
        std::vector<int> stack;
        for (int v : candidate.votes)
            for (int end : {endpoints_[size_t(v)].first, endpoints_[size_t(v)].second}) {
                if (tried_region_[size_t(end)]) continue;  // its ball was marked, or most of it
                const Eigen::Vector3d centre = mesh_.positions[size_t(end)];
                tried_region_[size_t(end)] = 1;
                stack.assign(1, end);
                while (!stack.empty()) {
                    const int u = stack.back();
                    stack.pop_back();
                    for (int k = mesh_.neighbour_offsets[size_t(u)]; k < mesh_.neighbour_offsets[size_t(u) + 1]; ++k) {
                        const int w = mesh_.neighbours[size_t(k)];
                        if (tried_region_[size_t(w)] || (mesh_.positions[size_t(w)] - centre).norm() > radius) continue;
                        tried_region_[size_t(w)] = 1;
                        stack.push_back(w);
                    }
                }
            }
    }

    /// The votes of the newest family's members: pairs on its patch whose transformation
    /// is a member, within what a single pair's frames can tell (as for a cluster's mode).
    std::vector<int> newest_family_votes() const {
        std::vector<int> out;
        if (findings_.families.empty()) return out;
        const ContinuousFamily& family = findings_.families.back();
        const std::vector<char>& on = family_flags_.back();
        for (size_t v = 0; v < votes_.points.size(); ++v)
            if (on[size_t(endpoints_[v].first)] && on[size_t(endpoints_[v].second)] &&
                is_member(family, votes_.points[v], mode_slack_distance_, mode_slack_degrees_))
                out.push_back(int(v));
        return out;
    }

    /// The planar and spherical patches around the samples umbilic pruning discarded
    /// (§2.1): their pairs would trace curves in Γ, so they never vote, and these families
    /// are grown directly: the plane or sphere a discarded sample suggests, grown over the
    /// mesh, refined by slippage, kept when large enough (the first that is, of the
    /// families the sample suggests).
    void add_families_of_discarded_samples() {
        std::vector<char> covered(size_t(mesh_.vertex_count()), 0);
        for (const SurfaceSignature& sample : votes_.discarded) {
            const int seed = seed_vertex(model_, sample);
            if (covered[size_t(seed)]) continue;
            covered[size_t(seed)] = 1;
            for (ContinuousFamily& family : families_of_pruned_sample(sample, model_.radius, options_.flatness))
                if (grow_family_of_seed(std::move(family), seed, covered)) break;
        }
    }

    /// Grows `family` from `seed`, refines it by slippage and records it if it keeps its
    /// kind and covers min_patch_area; marks what it grew over as covered.
    bool grow_family_of_seed(ContinuousFamily family, int seed, std::vector<char>& covered) {
        family.vertices = grow_family_patch(mesh_, family, {seed}, vo_.tolerance, co_);
        for (int v : family.vertices) covered[size_t(v)] = 1;
        if (area_of(mesh_, family.vertices, scratch_) < vo_.min_patch_area) return false;
        ContinuousFamily refined = slippable_family(mesh_, family.vertices, vo_.tolerance, co_);
        if (refined.kind != family.kind) return false;
        refined.vertices = grow_family_patch(mesh_, refined, family.vertices, vo_.tolerance, co_);
        for (int v : refined.vertices) covered[size_t(v)] = 1;
        record_family(std::move(refined), 0);
        return true;
    }

    /// The surfaces of revolution that only mirrors were found on.  Every mirror across a
    /// plane through the axis maps such a surface onto itself, but where parts are attached
    /// to it (a wingnut's blades) each mirror's patch spills onto the parts' roots, so no
    /// mirror's patch pair slides and no family is recorded; the mirrors are then reported
    /// one by one (measured on a wingnut's point cloud: 14 mirrors through its hub's axis,
    /// each over the hub and 6-32 % of its patch on the blades).  Where
    /// min_mirrors_through_axis verified mirrors pass through one line, the vertices all of
    /// them map, on both sides, and that a turn about the line slides along (tangent_vertices:
    /// not the blades' faces, which the turn moves across) are the surface of revolution:
    /// its family is recorded if slippage finds it there about that line, and the mirrors are
    /// left out as its members (drop_partial_family_relations).  Flat faces normal to the
    /// line (a wall where two of its mirrors meet) are passed over: a turn about any line
    /// parallel to it slides them too, so they pin no axis.  On the noisy cloud only two
    /// mirrors were verified, 60° apart, and the vertices both map still held pieces of the
    /// blades, enough for slippage to find no family until the blades were left out.
    void add_families_of_mirror_axes() {
        std::vector<Eigen::Vector4d> planes;
        std::vector<const VerifiedSymmetry*> mirrors;
        for (const Found& f : findings_.discrete)
            if (const std::optional<Eigen::Vector4d> plane = mirror_plane_of(f.symmetry)) {
                planes.push_back(*plane);
                mirrors.push_back(&f.symmetry);
            }
        const double degrees = co_.axis_agreement_degrees;
        for (const MirrorAxis& axis : lines_of_mirrors(planes, co_.min_mirrors_through_axis, vo_.tolerance, degrees)) {
            ContinuousFamily about_axis;
            about_axis.kind = ContinuousKind::Rotational;
            about_axis.point = axis.point;
            about_axis.direction = axis.direction;
            about_axis.motions = {Motion::turn_about(axis.point, axis.direction)};
            if (std::any_of(findings_.families.begin(), findings_.families.end(), [&](const ContinuousFamily& f) {
                    return same_family(f, about_axis, vo_.tolerance, co_);
                }))
                continue;
            // How many of the line's mirrors map each vertex, from it or onto it.
            std::vector<size_t> mapped(size_t(mesh_.vertex_count()), 0);
            for (size_t k : axis.mirrors) {
                std::vector<char> both(mapped.size(), 0);
                for (int v : mirrors[k]->source_vertices) both[size_t(v)] = 1;
                for (int v : mirrors[k]->target_vertices) both[size_t(v)] = 1;
                for (size_t v = 0; v < both.size(); ++v) mapped[v] += both[v];
            }
            std::vector<int> common;
            for (size_t v = 0; v < mapped.size(); ++v)
                if (mapped[v] == axis.mirrors.size()) common.push_back(int(v));
            common = tangent_vertices(mesh_, about_axis, common, vo_.tolerance, co_);
            if (area_of(mesh_, common, scratch_) < vo_.min_patch_area) continue;
            if (mean_lean_from(mesh_, common, axis.direction) < co_.min_lean_from_mirror_axis) continue;
            ContinuousFamily family = slippable_family(mesh_, common, vo_.tolerance, co_);
            if (!same_family(family, about_axis, vo_.tolerance, co_)) continue;
            family.vertices = grow_family_patch(mesh_, family, common, vo_.tolerance, co_);
            record_family(std::move(family), 0);
        }
    }

    /// The cylinders among the kept samples: a thin cylinder on a larger body (a boat's mast)
    /// has too few pairs for its ridge in Γ to rise above the body's clusters, but each of
    /// its samples says where its axis is (cylinder_of_sample).  Grown, refined by slippage
    /// and recorded only if it is a cylinder whose finite members hold: a cone's or a
    /// saddle's sample suggests a cylinder that is not there, and fails.
    void add_cylinders_of_kept_samples() {
        std::vector<char> covered(size_t(mesh_.vertex_count()), 0);
        for (const auto& flags : family_flags_)
            for (size_t v = 0; v < covered.size(); ++v) covered[v] |= flags[v];
        const double edge_length = median_edge_length(mesh_, model_.debris);
        for (const SurfaceSignature& sample : votes_.P) {
            const int seed = seed_vertex(model_, sample);
            if (covered[size_t(seed)]) continue;
            ContinuousFamily family = cylinder_of_sample(sample, model_.radius, options_.flatness);
            if (family.kind == ContinuousKind::Discrete) continue;
            covered[size_t(seed)] = 1;
            std::optional<ContinuousFamily> cylinder = grown_cylinder(std::move(family), seed);
            if (!cylinder) continue;
            for (int v : cylinder->vertices) covered[size_t(v)] = 1;
            if (!holds(check_members(mesh_, surface_, *cylinder, vo_.tolerance, edge_length), *cylinder)) continue;
            record_family(std::move(*cylinder), 0);
        }
    }

    /// A discrete symmetry whose patches lie on continuous families but cover some of them
    /// only in part (a box face's strip turned onto the next face, a cylinder shifted along
    /// itself) is a family member composed with another: not reported.  One that maps whole
    /// families onto whole families (a box's mirror, a copy of a cylinder) is, and so is one
    /// that carries whole parts of the mesh (area_of_whole_parts: a facade's windows, on a
    /// wall whose families their faces lie on).  Applied once every family is known.
    /// A family is reported when its finite members hold; a merely slippable patch (a
    /// fillet, a tubular ear) only keeps its members from being reported.
    void check_families() {
        const double edge_length = median_edge_length(mesh_, model_.debris);
        for (const ContinuousFamily& family : findings_.families) {
            FamilyCheck check = check_members(mesh_, surface_, family, vo_.tolerance, edge_length);
            findings_.family_holds.push_back(holds(check, family));
            findings_.family_checks.push_back(std::move(check));
        }
    }

    /// (After check_families: only the families that hold count.)
    void drop_partial_family_relations() {
        const std::vector<char> beyond_debris = components_beyond_debris(mesh_, vo_.debris);
        auto partial = [&](const std::vector<int>& patch) {
            if (patch.empty()) return false;
            if (area_of_whole_parts(patch, beyond_debris) >= vo_.min_patch_area) return false;
            std::vector<int> inside(findings_.families.size(), 0);
            size_t on_families = 0;
            for (int v : patch) {
                bool on = false;
                for (size_t k = 0; k < findings_.families.size(); ++k)
                    if (findings_.family_holds[k] && family_flags_[k][size_t(v)]) { ++inside[k]; on = true; }
                on_families += on;
            }
            if (double(on_families) < co_.min_family_share * double(patch.size())) return false;
            for (size_t k = 0; k < findings_.families.size(); ++k)
                if (inside[k] > 0.05 * double(patch.size()) &&
                    inside[k] < co_.min_family_coverage * double(findings_.families[k].vertices.size()))
                    return true;
            return false;
        };
        // Only about an axis: a mirror across a plane normal to a flat face is that face's
        // member too, yet a plate's outline may be mirror-symmetric in its own right.
        auto spilled_member = [&](const VerifiedSymmetry& s) {
            for (size_t k = 0; k < findings_.families.size(); ++k) {
                const ContinuousKind kind = findings_.families[k].kind;
                if (!findings_.family_holds[k]) continue;
                if (kind != ContinuousKind::Rotational && kind != ContinuousKind::Helical) continue;
                if (!is_member(findings_.families[k], s.transform, vo_.tolerance,
                               co_.axis_agreement_degrees))
                    continue;
                size_t on = 0;
                for (int v : s.source_vertices) on += family_flags_[k][size_t(v)] != 0;
                if (double(on) >= co_.min_member_share * double(s.source_vertices.size())) return true;
            }
            return false;
        };
        std::vector<Found> kept;
        for (auto& f : findings_.discrete)
            if (!partial(f.symmetry.source_vertices) && !partial(f.symmetry.target_vertices) &&
                !spilled_member(f.symmetry))
                kept.push_back(std::move(f));
        findings_.discrete.swap(kept);
    }

    // The area of the mesh's separate parts (connected components, flagged in
    // `beyond_debris`) of which the patch holds at least
    // ContinuousFamilyOptions::min_whole_part_share.  A relation that carries whole parts
    // onto others relates those parts, whatever families their faces lie on (a facade's
    // windows, boxes whose faces slide along the wall locally); a family member composed with
    // another only ever carries pieces of them.  (A vertex's area is a third of its faces',
    // so a component's vertex areas add up to its component_areas.)
    double area_of_whole_parts(const std::vector<int>& patch, const std::vector<char>& beyond_debris) const {
        std::vector<double> held(mesh_.component_areas.size(), 0.0);
        for (int v : patch) held[size_t(mesh_.component_of[size_t(v)])] += mesh_.vertex_areas[size_t(v)];
        double whole = 0;
        for (size_t c = 0; c < held.size(); ++c)
            if (beyond_debris[c] && held[c] >= co_.min_whole_part_share * mesh_.component_areas[c]) whole += held[c];
        return whole;
    }

    Findings take_findings(DetectionResult& result) {
        result.verified_candidates = int(verified_);
        result.skipped_members = skipped_members_;
        return std::move(findings_);
    }

    const MeshNeighbourhoods& mesh() const { return mesh_; }
    double tolerance() const { return vo_.tolerance; }

private:
    // The same relation is found as T and as T⁻¹ (pairs are ordered), and nearby modes
    // may refine to the same T (same_relation): one verification and one report per relation.
    bool tried(const Transformation& T) const {
        return std::any_of(tried_.begin(), tried_.end(), [&](const Transformation& t) { return same_relation(T, t); });
    }

    // What verifying the candidate in turn returns, from its speculation.  The findings have
    // only grown since it ran, so both runs computed alike up to the first estimate of T that
    // is a known relation now: there the verification in turn stops, and that relation
    // gets the candidate's votes, as classify() would give them after a full verification.
    // The same holds for the relations rejected since it ran: the verification in turn
    // stops at the first estimate rejected over its patch, with nothing to credit.  What
    // the candidate's own acceptance rejected is recorded in turn, so every later candidate
    // sees the same rejections at any thread count.
    std::optional<VerifiedSymmetry> settle(Speculation s, const Candidate& candidate) {
        for (const Ask& ask : s.asked) {
            for (Found& f : findings_.discrete)
                if (same_relation(ask.transform, f.symmetry.transform)) {
                    f.support += candidate.height;
                    return std::nullopt;
                }
            if (rejected_over(rejected_, ask.transform, ask.patch)) return std::nullopt;
        }
        if (s.rejection)
            rejected_.push_back(std::make_shared<const Rejected>(
                Rejected{s.rejection->transform, flags(mesh_.vertex_count(), s.rejection->source_vertices)}));
        return std::move(s.result);
    }

    // What speculations check their estimates against: the discrete symmetries found and
    // the relations rejected, as a copy, renewed after every candidate settled.  Both only
    // grow, so a speculation's copy is what its turn knows or less (see settle).
    std::shared_ptr<const KnownRelations> known_relations() const {
        std::lock_guard<std::mutex> lock(known_mutex_);
        return known_;
    }
    void publish_known_relations() {
        if (known_->found.size() == findings_.discrete.size() && known_->rejected.size() == rejected_.size()) return;
        auto relations = std::make_shared<KnownRelations>();
        for (const Found& f : findings_.discrete) relations->found.push_back(f.symmetry.transform);
        relations->rejected = rejected_;
        std::lock_guard<std::mutex> lock(known_mutex_);
        known_ = std::move(relations);
    }

    // A candidate on a surface of revolution that slides it along the axis (a glide or a
    // screw of a capped cylinder's side) is a member of the side's own family: the side maps
    // onto itself only in part, and the capped whole is not a symmetry under it.
    bool is_member_up_to_slides(ContinuousFamily family, const Transformation& T) const {
        if (family.kind == ContinuousKind::Rotational) family.slides_along_axis = true;
        return is_member(family, T, mode_slack_distance_, mode_slack_degrees_);
    }

    // Whether what the candidate's votes say is already known (see the class comment);
    // a relation already reported is credited with the votes of this cluster too.
    bool explained(const Candidate& candidate) {
        int* support = explaining(candidate);
        if (!support) return false;
        *support += candidate.height;
        ++skipped_members_;
        return true;
    }

    // The support of the family or relation that explains the candidate, or nullptr.
    int* explaining(const Candidate& candidate) {
        for (size_t k = 0; k < findings_.families.size(); ++k)
            if (is_member_up_to_slides(findings_.families[k], candidate.transform) &&
                share_of_votes_between(candidate, endpoints_, family_flags_[k], family_flags_[k]) >= 0.5)
                return &findings_.family_support[k];
        for (auto& f : findings_.discrete) {
            const bool forward = share_of_votes_between(candidate, endpoints_, f.source_flags, f.target_flags) >= 0.5;
            const bool backward = share_of_votes_between(candidate, endpoints_, f.target_flags, f.source_flags) >= 0.5;
            if (!forward && !backward) continue;
            // A relation between continuous patches (a cylinder onto another) holds for a
            // whole continuum of motions: any candidate joining its patches is the same.
            if (f.slippable_source || (forward && moves_alike(candidate.transform, f.symmetry)) ||
                (backward && moves_alike(candidate.transform.inverse(), f.symmetry)))
                return &f.support;
        }
        return nullptr;
    }

    // Whether T moves the symmetry's source patch where the symmetry does, within what a
    // cluster's mode can tell (a few vertices spread over the patch are compared).
    bool moves_alike(const Transformation& T, const VerifiedSymmetry& s) const {
        return moves_alike(T, s, mode_slack_distance_);
    }

    // Whether T moves every 32nd vertex of the symmetry's source patch within `distance` of
    // where the symmetry does.
    bool moves_alike(const Transformation& T, const VerifiedSymmetry& s, double distance) const {
        const size_t stride = std::max<size_t>(1, s.source_vertices.size() / 32);
        for (size_t i = 0; i < s.source_vertices.size(); i += stride) {
            const Eigen::Vector3d& p = mesh_.positions[size_t(s.source_vertices[i])];
            if ((T.apply(p) - s.transform.apply(p)).norm() > distance) return false;
        }
        return true;
    }

    // The part of classifying a verified symmetry that depends on it alone (see classify).
    Assessment assess(const VerifiedSymmetry& s, const Worker& worker) const {
        Assessment a;
        const CurvatureAgreement agreement =
            curvature_agreement(mesh_, surface_, curvature_, *worker.workspace, *worker.roughness, *worker.neighbours, votes_.P,
                                s.source_vertices, s.transform, model_.radius, options_.signature_tolerance,
                                vo_.tolerance, options_.agreement);
        a.agrees = agreement.passes(options_.agreement, s.source_area / model_.total_area, model_.smoothed_noise_in_spacings);
        if (!a.agrees) return a;
        const std::vector<int> both = sorted_union(s.source_vertices, s.target_vertices);
        a.family = slippable_family(mesh_, both, vo_.tolerance, co_);
        if (a.family.kind != ContinuousKind::Discrete) {
            a.family.vertices = grow_family_patch(mesh_, a.family, both, vo_.tolerance, co_);
            a.member = is_member(a.family, s.transform, vo_.tolerance, co_.axis_agreement_degrees);
            if (a.member) return a;
        }
        if (s.small_motion) return a;
        a.slippable_source =
            slippable_family(mesh_, s.source_vertices, vo_.tolerance, co_).kind != ContinuousKind::Discrete;
        return a;
    }

    // A verified symmetry whose curvature disagrees under T is two surfaces that touch, not
    // a symmetry.  One whose patch pair slips along itself records its continuous family and
    // is reported only if T is not the family's member; a small motion is not reported; a
    // relation reported before gets the votes.
    void classify(VerifiedSymmetry s, const Assessment& a, int support) {
        if (!a.agrees) return;
        if (a.family.kind != ContinuousKind::Discrete) {
            const size_t k = record_family(a.family, support);
            if (a.member) {
                verify_mirror_in(s, a.family, support);
                return;
            }
            // A pair that slides along the axis is centred on the mirror that found it,
            // wherever that is; the family as recorded may be known over more of the
            // surface (a capped cylinder's side, with its caps), whose middle the mirror
            // misses.  The mirror through the middle, where it maps more, is the relation.
            if (a.family.slides_along_axis)
                if (std::optional<Transformation> mirror = mirror_through_middle(
                        findings_.families[k], s.transform, vo_.tolerance, co_.axis_agreement_degrees))
                    if (std::optional<VerifiedSymmetry> middle = verify_held_mirror(s, *mirror);
                        middle && middle->source_area > s.source_area) {
                        classify_held_mirror(std::move(*middle), support);
                        return;
                    }
        }
        if (s.small_motion) return;  // a slide along the surface, not a discrete symmetry
        for (auto& f : findings_.discrete)
            if (same_relation(s.transform, f.symmetry.transform)) { f.support += support; return; }
        Found found{std::move(s), support, false, {}, {}};
        found.source_flags = flags(mesh_.vertex_count(), found.symmetry.source_vertices);
        found.target_flags = flags(mesh_.vertex_count(), found.symmetry.target_vertices);
        found.slippable_source = a.slippable_source;
        if (found.slippable_source && redundant_with_reported(found.symmetry)) return;
        findings_.discrete.push_back(std::move(found));
    }

    // A member that is the family's mirror composed with a turn (mirror_in_rotoreflection):
    // that mirror, where the surface has it, is a discrete symmetry beside the family (a
    // torus's equator, a cylinder's mid-plane), which ICP on a noisy surface drifts away
    // from along the family.  It is verified from the member's patch with T held, once.
    void verify_mirror_in(const VerifiedSymmetry& member, const ContinuousFamily& family, int support) {
        const std::optional<Transformation> mirror =
            mirror_in_rotoreflection(family, member.transform, co_.axis_agreement_degrees);
        if (!mirror) return;
        if (std::optional<VerifiedSymmetry> verified = verify_held_mirror(member, *mirror))
            classify_held_mirror(std::move(*verified), support);
    }

    // The mirror verified from the member's patch with T held, once.
    std::optional<VerifiedSymmetry> verify_held_mirror(const VerifiedSymmetry& member, const Transformation& mirror) {
        if (tried(mirror)) return std::nullopt;
        tried_.push_back(mirror);
        std::vector<Seed> seeds;
        const std::vector<int>& patch = member.source_vertices;
        const size_t stride = std::max<size_t>(1, patch.size() / size_t(std::max(1, co_.mirror_seeds)));
        for (size_t i = 0; i < patch.size(); i += stride) seeds.push_back({patch[i], 0.0});
        VerificationOptions held = vo_;
        held.refine_with_icp = false;
        const KnownRelation known = [this](const Transformation& t, const std::vector<int>&) { return is_known(t); };
        return verify_candidate(mesh_, surface_, mirror, std::move(seeds), held, known);
    }

    void classify_held_mirror(VerifiedSymmetry verified, int support) {
        const Assessment assessment = assess(verified, workers_[0]);  // on the calling thread
        classify(std::move(verified), assessment, support);
    }

    // An axis's point moved to the middle of the patch's span along the axis, where the
    // mirror normal to the axis that maps the whole patch passes (see is_member).
    void centre_on_patch(ContinuousFamily& family) const {
        if (family.kind != ContinuousKind::Rotational && family.kind != ContinuousKind::Helical) return;
        if (family.vertices.empty()) return;
        double lo = std::numeric_limits<double>::max(), hi = std::numeric_limits<double>::lowest();
        for (int v : family.vertices) {
            const double t = (mesh_.positions[size_t(v)] - family.point).dot(family.direction);
            lo = std::min(lo, t);
            hi = std::max(hi, t);
        }
        family.point += family.direction * (0.5 * (lo + hi));
    }

    // Whether the family's finite members map its patch onto the surface (see
    // ContinuousFamilyOptions::min_member_coverage and what follows it).
    bool holds(const FamilyCheck& check, const ContinuousFamily& family) const {
        const bool shape = family.kind == ContinuousKind::Planar || family.kind == ContinuousKind::Spherical;
        const double max_median = shape ? co_.max_shape_member_median_deviation
                                        : co_.max_member_median_deviation;
        return check.coverage >= co_.min_member_coverage &&
               check.area_coverage >= co_.min_member_area_coverage &&
               check.median_deviation <= max_median * vo_.tolerance + co_.median_per_position_roughness * co_.roughness.position;
    }

    // The suggested cylinder's patch grown from the seed, kept if it is large enough and
    // slippage finds a cylinder in it too (refined axis), regrown about that axis.
    std::optional<ContinuousFamily> grown_cylinder(ContinuousFamily family, int seed) {
        family.vertices = grow_family_patch(mesh_, family, {seed}, vo_.tolerance, co_);
        if (area_of(mesh_, family.vertices, scratch_) < vo_.min_patch_area) return std::nullopt;
        ContinuousFamily refined = slippable_family(mesh_, family.vertices, vo_.tolerance, co_);
        if (refined.kind != ContinuousKind::Rotational || !refined.slides_along_axis) return std::nullopt;
        refined.vertices = grow_family_patch(mesh_, refined, family.vertices, vo_.tolerance, co_);
        if (area_of(mesh_, refined.vertices, scratch_) < vo_.min_patch_area) return std::nullopt;
        if (!lies_on_cylinder(mesh_, refined, vo_.tolerance, co_)) return std::nullopt;
        return refined;
    }

    // The plane (n, d) of a verified mirror, n·x = d: T within the tolerance of the pure
    // mirror nearest to it over the patch (not a glide, nor a rotoreflection).
    std::optional<Eigen::Vector4d> mirror_plane_of(const VerifiedSymmetry& s) const {
        if (!s.transform.reflection || std::abs(s.transform.scale - 1) > 1e-6 || s.source_vertices.empty())
            return std::nullopt;
        Eigen::Vector3d n;
        double d;
        mirror_plane(s.transform, n, d);
        if (!moves_alike(pure_mirror(n, d), s, vo_.tolerance)) return std::nullopt;
        return Eigen::Vector4d(n.x(), n.y(), n.z(), d);
    }

    // A family found twice (two members of one surface of revolution) is one family.
    // Returns the index of the family recorded (or joined).
    size_t record_family(ContinuousFamily family, int support) {
        for (size_t k = 0; k < findings_.families.size(); ++k) {
            ContinuousFamily& known = findings_.families[k];
            std::optional<ContinuousFamily> joint = one_family(known, family);
            if (!joint && same_family(known, family, vo_.tolerance, co_)) joint = with_both_patches(known, family);
            if (!joint) continue;
            known = std::move(*joint);
            family_flags_[k] = flags(mesh_.vertex_count(), known.vertices);
            findings_.family_support[k] += support;
            return k;
        }
        centre_on_patch(family);
        family_flags_.push_back(flags(mesh_.vertex_count(), family.vertices));
        findings_.families.push_back(std::move(family));
        findings_.family_support.push_back(support);
        return findings_.families.size() - 1;
    }

    // The family `known` over both patches, as fitted before: the fit of the union where
    // slippage no longer finds the family in it (one_family).
    ContinuousFamily with_both_patches(const ContinuousFamily& known, const ContinuousFamily& found) const {
        ContinuousFamily joint = known;
        joint.vertices = sorted_union(known.vertices, found.vertices);
        centre_on_patch(joint);
        return joint;
    }

    // Two families of one kind are one when their patches together are a family of that
    // kind, fitted to both patches: also where their axes, centres or planes disagree, since
    // on a noisy surface a small patch's fit is off by more than the tolerance (measured: a
    // sphere's cap of 2,500 vertices, with noise of 0.1 % of the diagonal, centred 0.03 of
    // the diagonal away from the rest of the sphere), and where they agree, since the
    // first patch's fit is no better than its size (a noisy cloud's sphere kept the centre
    // of a cap of 1,476 points, and its members then missed the surface by 0.14 of the
    // tolerance where the fit to the whole sphere misses it by 0.01).
    std::optional<ContinuousFamily> one_family(const ContinuousFamily& a, const ContinuousFamily& b) const {
        if (a.kind != b.kind || a.kind == ContinuousKind::Discrete) return std::nullopt;
        std::vector<int> both = sorted_union(a.vertices, b.vertices);
        ContinuousFamily joint = slippable_family(mesh_, both, vo_.tolerance, co_);
        if (joint.kind != a.kind) return std::nullopt;
        joint.vertices = std::move(both);
        centre_on_patch(joint);
        return joint;
    }

    // A discrete relation between continuous patches (one cylinder onto another) holds
    // for a whole continuum of transformations: the patch pair is reported once.
    bool redundant_with_reported(const VerifiedSymmetry& s) const {
        for (const auto& f : findings_.discrete) {
            const auto& a = f.symmetry;
            if ((overlap(s.source_vertices, a.source_vertices) >= 0.5 && overlap(s.target_vertices, a.target_vertices) >= 0.5) ||
                (overlap(s.source_vertices, a.target_vertices) >= 0.5 && overlap(s.target_vertices, a.source_vertices) >= 0.5))
                return true;
        }
        return false;
    }

    const Model& model_;
    const Votes& votes_;
    const TransformationSpace& space_;
    const DetectionOptions& options_;
    const MeshNeighbourhoods mesh_;
    const SurfaceQuery surface_;
    const CurvatureEstimator curvature_;
    std::vector<Worker> workers_;
    VerificationOptions vo_;
    ContinuousFamilyOptions co_;  // options.continuous with the roughness of mesh_
    double mode_slack_distance_ = 0, mode_slack_degrees_ = 0;
    std::vector<std::pair<int, int>> pair_endpoints_, endpoints_;  // seed vertices of each pair, of each vote
    Findings findings_;
    std::vector<std::vector<char>> family_flags_;
    std::vector<char> explained_;  // vertices on any found patch, see inside_explained_patches
    std::vector<char> tried_region_;  // near the votes of every cluster verified, see mark_tried
    std::vector<char> scratch_ = std::vector<char>(size_t(mesh_.vertex_count()), 0);  // for area_of
    size_t explained_count_ = 0;
    std::vector<Transformation> tried_;
    std::vector<std::shared_ptr<const Rejected>> rejected_;  // what acceptance rejected, in turn order (settle)
    mutable std::mutex known_mutex_;
    std::shared_ptr<const KnownRelations> known_ = std::make_shared<KnownRelations>();  // see known_relations
    size_t verified_ = 0;
    int skipped_members_ = 0;
};

// Rows of Γ's coordinates, one per transformation (DetectionOptions::keep_transformation_space).
Eigen::MatrixXd coordinates_of(const std::vector<Transformation>& transformations, const TransformationSpace& space) {
    Eigen::MatrixXd rows(Eigen::Index(transformations.size()), TransformationSpace::kDimension);
    for (size_t i = 0; i < transformations.size(); ++i) rows.row(Eigen::Index(i)) = space.coordinates(transformations[i]).transpose();
    return rows;
}

void keep_modes(const std::vector<Candidate>& candidates, const TransformationSpace& space,
                TransformationSpaceSnapshot& kept) {
    std::vector<Transformation> modes;
    for (const Candidate& c : candidates) {
        modes.push_back(c.transform);
        kept.mode_heights.push_back(c.height);
        kept.mode_improper.push_back(c.transform.reflection);
    }
    kept.modes = coordinates_of(modes, space);
}

void keep_points(const Votes& votes, const TransformationSpace& space, TransformationSpaceSnapshot& kept) {
    kept.points = coordinates_of(votes.points, space);
    for (const Transformation& t : votes.points) kept.improper.push_back(t.reflection);
}

using Speculations = Lookahead<Verifier::Speculation>;

// Hands out to the lookahead's workers the candidates after `first` that would be verified
// now, up to candidates_per_thread per thread (and `budget`) handed out at once.  Each is
// settled in its turn against what was found meanwhile (Verifier::Speculation), so the
// findings are those of verifying one candidate at a time, at any thread count; a
// speculation that its turn finds explained by then is work lost, not a different result.
void hand_out_ahead(Verifier& verifier, const std::vector<Candidate>& candidates, size_t first,
                    bool outside_explained_only, size_t budget, int candidates_per_thread, Speculations& ahead) {
    if (ahead.workers() == 0) return;
    const size_t width = std::min(Verifier::threads() * size_t(candidates_per_thread), std::max<size_t>(1, budget));
    std::vector<size_t> window = ahead.handed_out_from(first);
    if (std::find(window.begin(), window.end(), first) == window.end()) window.insert(window.begin(), first);
    for (size_t j = first + 1; j < candidates.size() && window.size() < width; ++j) {
        if (std::find(window.begin(), window.end(), j) != window.end() || !verifier.would_verify(candidates[j])) continue;
        if (outside_explained_only && verifier.inside_what_was_verified(candidates[j])) continue;
        // Tried once the window's own relations are: it would be skipped in its turn.
        if (std::any_of(window.begin(), window.end(), [&](size_t w) {
                return verifier.same_relation(candidates[j].transform, candidates[w].transform);
            }))
            continue;
        ahead.hand_out(j);
        window.push_back(j);
    }
}

// The samples `away` (indices into P), paired (§2.2) where P' did not draw them: P' holds
// a share n'/n of the samples, so a part of p of the area gets about n' p of them, each one
// vote for its copy, and a cluster of so few votes may stay under the minimum support (a
// part of 1 % of the area beside a cow: about 20 votes, spread over several modes by the
// noise of the frames).
void pair_samples_away(const Model& model, Verifier& verifier, Votes& votes, const DetectionOptions& options,
                       const std::vector<int>& away) {
    std::vector<char> drawn(votes.P.size(), 0);
    for (const SignaturePair& pair : votes.pairs) drawn[size_t(pair.first)] = 1;
    std::vector<int> undrawn;
    for (int i : away)
        if (!drawn[size_t(i)]) undrawn.push_back(i);
    add_pairs(votes,
              pair_drawn_samples(votes.P, options.group, model.radius, options.signature_tolerance, undrawn,
                                 2 * model.radius, options.pairing),
              options);
    verifier.add_endpoints_of_new_votes();
}

// The last pass: the clusters of the votes of the samples away from what was verified,
// those samples all paired (pair_samples_away), up to DetectionOptions::clusters_away of
// them, when something was found and those samples are at most pair_away_share of P (on a
// scan with no symmetry the pass would cluster much of Γ again for nothing: measured on the
// speed benchmark's, 1.0 s more clustering).  On a body whose first symmetry covers most of
// it (a cow's global mirror), the cluster of a small part beside it may not be among the
// modes mean shift keeps (max_modes per sheet), below the chance near-mirrors of the body,
// which lie on that symmetry's patches; the two passes before spend their budget there.
// Without the votes of those patches, the part's cluster is among the first.  (A part of
// 1 % of the area beside a cow: its cluster of 14 votes came 220th of the 480 modes at one
// random seed, and at others after the 480th.)  After the two passes, so that it takes no
// result slot from what they find.  `active`: the votes still in Γ (families' members have
// left).  Returns the seconds spent clustering.
double pass_over_votes_away(const Model& model, Verifier& verifier, Votes& votes, const TransformationSpace& space,
                            const DetectionOptions& options, int max_modes, std::vector<char> active) {
    const size_t budget = verifier.verified() + size_t(options.clusters_away);
    if (!verifier.found_anything() || verifier.done(budget)) return 0;
    std::vector<int> samples_away;
    for (size_t i = 0; i < votes.P.size(); ++i)
        if (verifier.away_from_what_was_verified(seed_vertex(model, votes.P[i]))) samples_away.push_back(int(i));
    if (samples_away.empty() || double(samples_away.size()) > options.pair_away_share * double(votes.P.size())) return 0;
    pair_samples_away(model, verifier, votes, options, samples_away);
    active.resize(votes.points.size(), 1);
    const std::vector<char> votes_away = verifier.votes_away_from_what_was_verified(active);
    if (std::count(votes_away.begin(), votes_away.end(), 1) == 0) return 0;
    const auto start = Clock::now();
    Clustering clustering(votes, space, options, max_modes);
    const std::vector<Candidate> candidates = clustering.candidates(votes_away);
    const double seconds = seconds_since(start);
    for (const Candidate& candidate : candidates) {
        if (verifier.done(budget)) break;
        if (!verifier.inside_what_was_verified(candidate)) verifier.consider(candidate);
    }
    return seconds;
}

// §3.1 and §4 together.  At most max_verified clusters are verified; each sheet of Γ
// offers up to four times as many modes (merges and repeats of T⁻¹ use up some).  When a
// continuous family is found, its members' votes leave Γ and the clusters are found again:
// a family's votes lie all along a ridge of Γ, whose modes would otherwise crowd out the
// clusters of everything else (the paper removes the points of a verified cluster likewise).
Findings search(const Model& model, Votes& votes, const TransformationSpace& space,
                const DetectionOptions& options, const Progress& report, DetectionResult& result) {
    const size_t max_verified = size_t(std::max(60, 3 * options.max_symmetries));
    const int max_modes = int(4 * max_verified);
    std::vector<char> active(votes.points.size(), 1);
    auto start = Clock::now();
    Clustering clustering(votes, space, options, max_modes);
    std::vector<Candidate> candidates = clustering.candidates(active);
    result.clusters = int(candidates.size());
    if (options.keep_transformation_space) keep_modes(candidates, space, result.transformation_space);
    result.seconds_clustering = seconds_since(start);

    report(60, "Verification by region growing");
    start = Clock::now();
    Verifier verifier(model, votes, space, options);
    verifier.add_families_of_discarded_samples();
    double reclustering = 0;
    // Two passes: first the clusters whose votes fall outside what is explained already
    // and away from those verified before, then the rest.  A large verified symmetry (a
    // model's global mirror) leaves many clusters of near-misses on its own patches, and a
    // smooth body many of chance near-mirrors that fail; in vote order they would spend the
    // verification budget before the cluster of a small repeated part elsewhere.
    // The first pass may spend only part of the budget: on a model whose unexplained rest
    // is all near-misses, the second pass must still reach the large symmetries' neighbours
    // (a torus's equatorial mirror beside its rotational family).
    const size_t first_pass_budget = size_t(options.first_pass_share * double(max_verified));
    // Candidates verified ahead of their turn on the other threads (hand_out_ahead).
    Speculations ahead(Verifier::threads() - 1, [&verifier, &candidates](size_t j, size_t worker) {
        return verifier.speculate(candidates[j], worker);
    });
    for (int pass = 0; pass < 2; ++pass) {
        const size_t budget = pass == 0 ? first_pass_budget : max_verified;
        for (size_t i = 0; i < candidates.size() && !verifier.done(budget); ++i) {
            if (report) report(60 + int(38 * verifier.verified() / max_verified), "Verification by region growing");
            if (pass == 0 && verifier.inside_what_was_verified(candidates[i])) continue;
            std::optional<Verifier::Speculation> speculation;
            if (verifier.would_verify(candidates[i])) {
                hand_out_ahead(verifier, candidates, i, pass == 0, budget - verifier.verified(),
                               options.candidates_per_thread, ahead);
                speculation = ahead.take(i);
            } else {
                ahead.drop(i);
            }
            if (!verifier.consider(candidates[i], std::move(speculation))) continue;
            const std::vector<int> members = verifier.newest_family_votes();
            if (members.empty()) continue;
            for (int v : members) active[size_t(v)] = 0;
            ahead.clear();  // the speculations read `candidates`
            auto again = Clock::now();
            candidates = clustering.candidates(active);
            const double seconds = seconds_since(again);
            result.seconds_clustering += seconds;
            reclustering += seconds;
            i = size_t(-1);  // from the top: what was verified already is skipped as tried
        }
    }
    ahead.clear();  // the last pass adds votes, which the speculations read
    const double last_clustering = pass_over_votes_away(model, verifier, votes, space, options, max_modes, active);
    result.seconds_clustering += last_clustering;
    reclustering += last_clustering;
    verifier.add_families_of_mirror_axes();
    verifier.add_cylinders_of_kept_samples();
    verifier.check_families();
    verifier.drop_partial_family_relations();
    result.seconds_verification = seconds_since(start) - reclustering;
    return verifier.take_findings(result);
}

// A patch of the working copy in the input's vertices: those whose nearest working vertex
// is in the patch.
std::vector<int> on_input(const Model& model, const std::vector<int>& patch) {
    const std::vector<char> in_patch = flags(int(model.working->vert.size()), patch);
    std::vector<int> vertices;
    for (size_t u = 0; u < model.working_vertex.size(); ++u)
        if (in_patch[size_t(model.working_vertex[u])]) vertices.push_back(int(u));
    return vertices;
}

// The area each vertex of a mesh stands for: a third of each face around it.
std::vector<double> vertex_areas_of(const Mesh& mesh) {
    std::vector<double> area(mesh.vert.size(), 0.0);
    for (const Face& f : mesh.face) {
        if (f.IsD()) continue;
        const double third = vcg::DoubleArea(f) / 6;
        for (int k = 0; k < 3; ++k) area[size_t(vcg::tri::Index(mesh, f.cV(k)))] += third;
    }
    return area;
}

// The vertices whose deviation is within the tolerance, and their deviations.
void keep_within(double tolerance, std::vector<int>& vertices, std::vector<double>& deviation) {
    size_t kept = 0;
    for (size_t i = 0; i < vertices.size(); ++i)
        if (std::abs(deviation[i]) <= tolerance) {
            vertices[kept] = vertices[i];
            deviation[kept++] = deviation[i];
        }
    vertices.resize(kept);
    deviation.resize(kept);
}

// The RMS and largest deviation of the source patch.
void summarise_deviation(VerifiedSymmetry& s) {
    double sum = 0;
    s.max_error = 0;
    for (double d : s.source_deviation) { sum += d * d; s.max_error = std::max(s.max_error, std::abs(d)); }
    s.rms_error = s.source_deviation.empty() ? 0 : std::sqrt(sum / double(s.source_deviation.size()));
}

// When the stages saw a presmoothed or simplified copy, the deviation from perfect symmetry
// is measured again on the input: T(v) against the input surface, as Figure 1 shows it,
// for every input vertex of the patch.
void measure_on_input(const Model& model, const SurfaceQuery& input, double tolerance, VerifiedSymmetry& s) {
    if (model.working) {
        s.source_vertices = on_input(model, s.source_vertices);
        s.target_vertices = on_input(model, s.target_vertices);
    }
    const double reach = 4 * tolerance;  // beyond it a vertex counts as deviating by the reach
    auto measure = [&](const std::vector<int>& vertices, const Transformation& T, double scale, std::vector<double>& out) {
        out.assign(vertices.size(), 0.0);
        // Queries only read the grid: vertices are measured on every core, each into its own entry.
#pragma omp parallel for schedule(dynamic, 256)
        for (long i = 0; i < long(vertices.size()); ++i) {
            const auto& p = model.input.vert[size_t(vertices[size_t(i)])].cP();
            ClosestPoint cp = input.closest(T.apply(Eigen::Vector3d(p[0], p[1], p[2])), reach);
            out[size_t(i)] = scale * (cp.found ? cp.signed_distance : reach);
        }
    };
    measure(s.source_vertices, s.transform, 1.0, s.source_deviation);
    measure(s.target_vertices, s.transform.inverse(), s.transform.scale, s.target_deviation);
    summarise_deviation(s);
}

// A patch found on a simplified copy, on the input: the copy smooths away relief smaller
// than its edges, so a patch grown on it can take in input vertices that T does not map
// onto the input surface (measured, a CAD part analysed at half its vertices: patches of
// which only 73-83 % mapped within the tolerance, reported as symmetries).  The patch is
// what T maps within the tolerance on the input, as region growing would have grown it
// there, and a symmetry left with less than min_patch_area is dropped.  Returns whether it
// is kept.
bool trim_to_input(const std::vector<double>& input_vertex_area, double tolerance, double min_patch_area,
                   VerifiedSymmetry& s) {
    keep_within(tolerance, s.source_vertices, s.source_deviation);
    keep_within(tolerance, s.target_vertices, s.target_deviation);
    summarise_deviation(s);
    s.source_area = 0;
    for (int v : s.source_vertices) s.source_area += input_vertex_area[size_t(v)];
    return !s.source_vertices.empty() && s.source_area >= min_patch_area;
}

// A family found on the working copy, in the input's vertices: each input vertex takes the
// deviation of its nearest working vertex (the member that maps a vertex best varies
// smoothly over the patch; check_members measured it on the working copy).
void family_on_input(const Model& model, VerifiedSymmetry& s) {
    if (!model.working) return;
    std::vector<double> deviation(model.working->vert.size(), 0.0);
    for (size_t i = 0; i < s.source_vertices.size(); ++i) deviation[size_t(s.source_vertices[i])] = s.source_deviation[i];
    s.source_vertices = on_input(model, s.source_vertices);
    s.source_deviation.clear();
    for (int u : s.source_vertices) s.source_deviation.push_back(deviation[size_t(model.working_vertex[size_t(u)])]);
    s.target_vertices = s.source_vertices;
    s.target_deviation = s.source_deviation;
}

// A continuous family reported as a symmetry: its patch on both sides, the finite member
// that maps most of it as its transformation, and per vertex the deviation under the
// member that maps the vertex best (see check_members).
VerifiedSymmetry family_as_symmetry(const ContinuousFamily& family, const FamilyCheck& check,
                                    const MeshNeighbourhoods& mesh) {
    VerifiedSymmetry s;
    s.transform = check.best_member;
    s.source_vertices = family.vertices;
    s.target_vertices = family.vertices;
    s.source_deviation = check.deviation;
    s.target_deviation = check.deviation;
    double sum = 0;
    for (double d : check.deviation) {
        sum += d * d;
        s.max_error = std::max(s.max_error, std::abs(d));
    }
    s.rms_error = family.vertices.empty() ? 0 : std::sqrt(sum / double(family.vertices.size()));
    std::vector<char> member_flags = flags(mesh.vertex_count(), family.vertices);
    s.source_area = patch_area(mesh, family.vertices, member_flags);
    return s;
}

// One reported symmetry in the input's numbering, writing its per-vertex outputs where no
// more significant symmetry has.
DetectedSymmetry report_symmetry(const VerifiedSymmetry& s, const Model& model, int index, DetectionResult& result) {
    DetectedSymmetry d;
    d.transform = s.transform;
    d.rms_error = s.rms_error / model.diagonal;
    d.max_error = s.max_error / model.diagonal;
    d.systematic_error = s.systematic_error / model.diagonal;
    d.source_area = std::min(1.0, s.source_area / model.total_area);
    auto write = [&](const std::vector<int>& vertices, const std::vector<double>& deviation, std::vector<int>& out) {
        for (size_t i = 0; i < vertices.size(); ++i) {
            int row = model.vertex_of_input[size_t(vertices[i])];
            out.push_back(row);
            if (result.vertex_symmetry_id[size_t(row)] < 0) {
                result.vertex_symmetry_id[size_t(row)] = index;
                result.vertex_deviation[size_t(row)] = deviation[i] / model.diagonal;
            }
        }
        std::sort(out.begin(), out.end());
    };
    write(s.source_vertices, s.source_deviation, d.source_vertices);
    write(s.target_vertices, s.target_deviation, d.target_vertices);
    return d;
}

// The rows welded onto another at the same position (input_repair.h) are that vertex in
// every output: its deviation, its symmetry, its patches.
void write_to_welded_rows(const Model& model, DetectionResult& result) {
    const std::vector<int>& same = model.repairs.row_at_same_position;
    if (model.repairs.welded_vertices == 0) return;
    std::vector<std::vector<int>> welded_onto(same.size());
    for (size_t r = 0; r < same.size(); ++r) {
        if (same[r] == int(r)) continue;
        welded_onto[size_t(same[r])].push_back(int(r));
        result.vertex_deviation[r] = result.vertex_deviation[size_t(same[r])];
        result.vertex_symmetry_id[r] = result.vertex_symmetry_id[size_t(same[r])];
    }
    auto widen = [&](std::vector<int>& rows) {
        const size_t listed = rows.size();
        for (size_t i = 0; i < listed; ++i)
            rows.insert(rows.end(), welded_onto[size_t(rows[i])].begin(), welded_onto[size_t(rows[i])].end());
        std::sort(rows.begin(), rows.end());
    };
    for (DetectedSymmetry& d : result.symmetries) {
        widen(d.source_vertices);
        widen(d.target_vertices);
    }
}

// "No symmetry" and "could not look" must not look alike: when pruning left fewer than two
// samples, no pair was ever formed, and when no flat or spherical region was large enough
// either, an empty result says nothing about the mesh.  Raised before anything is written.
void refuse_if_nothing_could_be_paired(const DetectionResult& result, const DetectionOptions& options,
                                       size_t reported) {
    if (reported > 0 || result.pruned_samples >= 2) return;
    std::ostringstream s;
    s << "No symmetry could be looked for: " << (result.pruned_samples == 0 ? "all " : "all but one of the ")
      << result.samples << " surface samples are flat or umbilic at the curvature radius used ("
      << 100 * result.curvature_radius << "% of the diagonal) and no flat or spherical region covers min_patch_area";
    // The radius grows beyond curvature_radius to hold min_radius_in_edges edges (or the
    // noise): on a mesh of a few large triangles (a 12-triangle cube) the ball then sees
    // the whole model, and no parameter helps but finer triangles.
    if (result.curvature_radius > 1.01 * options.curvature_radius && result.point_cloud)
        s << "; the point cloud is too sparse for the curvature radius (its points lie far apart), so sample "
          << "the surface more densely.";
    else if (result.curvature_radius > 1.01 * options.curvature_radius)
        s << "; the mesh is too coarse for the curvature radius (its edges are long), so refine it first, e.g. "
          << "with Filters > Remeshing, Simplification and Reconstruction > Subdivision Surfaces: Midpoint "
          << "(pymeshlab: meshing_surface_subdivision_midpoint).";
    else
        s << ", so lower curvature_radius (for curved parts smaller than it) or min_patch_area (for small flat parts).";
    throw InputError(s.str());
}

// A length the host turned from a percentage of the diagonal into an absolute value and
// back (MeshLab's percentage parameters pass through single precision) may land a few
// float rounding steps beyond the bound a user typed exactly: 50 % of the diagonal for
// curvature_radius must be accepted (measured: refused at 50 %, accepted at 49.999 %).
bool within_fraction(double x, double bound) { return x > 0 && x <= bound * (1 + 1e-6); }

}  // namespace

void DetectionOptions::validate() const {
    int g = int(group);
    require(g >= 0 && g <= 3, "transformation_group", g, "0, 1, 2 or 3");
    require(sample_count >= 100 && sample_count <= 5000000, "sample_count", sample_count, "between 100 and 5,000,000");
    require(pair_sample_count >= 0 && pair_sample_count <= 5000000, "pair_sample_count", pair_sample_count,
            "between 0 (automatic) and 5,000,000");
    require(max_transformation_points >= 1000, "max_transformation_points", max_transformation_points, "at least 1000");
    require(within_fraction(curvature_radius, 0.5), "curvature_radius", curvature_radius,
            "greater than 0 and at most half the bounding-box diagonal");
    require(umbilic_ratio > 0 && umbilic_ratio < 1, "umbilic_ratio", umbilic_ratio, "strictly between 0 and 1");
    require(flatness > 0 && flatness < 1, "flatness", flatness, "strictly between 0 and 1");
    require(signature_tolerance > 0 && signature_tolerance <= 10, "signature_tolerance", signature_tolerance,
            "greater than 0 and at most 10");
    require(within_fraction(cluster_bandwidth, 1), "cluster_bandwidth", cluster_bandwidth,
            "greater than 0 and at most the bounding-box diagonal");
    require(candidates_per_thread >= 1 && candidates_per_thread <= 64, "candidates_per_thread", candidates_per_thread,
            "between 1 and 64");
    require(min_cluster_support >= 2, "min_cluster_support", min_cluster_support, "at least 2");
    require(within_fraction(verification_tolerance, 0.25), "verification_tolerance",
            verification_tolerance, "greater than 0 and at most a quarter of the bounding-box diagonal");
    // In percent, as MeshLab's dialog and pymeshlab take it (the option itself is a fraction).
    require(min_patch_area >= 0 && min_patch_area <= 1, "min_patch_area (percent of the surface area)",
            100 * min_patch_area, "between 0 and 100");
    require(working.max_vertices == 0 || working.max_vertices >= 1000, "max_working_vertices", working.max_vertices,
            "0 (never simplify) or at least 1000");
    require(max_symmetries >= 1 && max_symmetries <= 1000, "max_symmetries", max_symmetries, "between 1 and 1000");
    require(basis_loop_length >= 1 && basis_loop_length <= 6, "basis_loop_length", basis_loop_length,
            "between 1 and 6 (the search grows exponentially with it)");
    require(within_fraction(basis_tolerance, 1), "basis_tolerance", basis_tolerance,
            "greater than 0 and at most the bounding-box diagonal");
    const PointCloudOptions& c = point_cloud;
    require(c.fitting_neighbours >= 3 && c.fitting_neighbours <= 100, "point_cloud.fitting_neighbours",
            c.fitting_neighbours, "between 3 and 100");
    for (int k : {c.orientation_neighbours, c.area_neighbours, c.graph_neighbours})
        require(k >= 1 && k <= 100, "point_cloud's orientation, area and graph neighbours", k, "between 1 and 100");
}

namespace {

// The pipeline from the prepared model on; `rows` is the number of input rows (vertices or
// points) the per-vertex outputs are written for.
DetectionResult detect_on_model(const Model& model, Eigen::Index rows, const DetectionOptions& options,
                                const std::function<void(int, const char*)>& report, DetectionResult result) {
    std::mt19937_64 rng(options.random_seed);
    Votes votes = vote(model, options, rng, result);
    const TransformationSpace space(model.center, model.diagonal);

    // §3.1 and §4: clusters verified most votes first, with the continuous families beside.
    report(45, "Mean-shift clustering in transformation space");
    Findings findings = search(model, votes, space, options, report, result);
    // Read after the search: its last pass pairs more samples (pass_over_votes_away), and the
    // work done and the snapshot of Γ count those pairs too.
    result.pairs = int(votes.pairs.size());
    result.transformation_points = int(votes.points.size());
    if (options.keep_transformation_space) keep_points(votes, space, result.transformation_space);
    auto start = Clock::now();
    const MeshNeighbourhoods neighbourhoods = neighbourhoods_of(model, options);
    const double tolerance = options.verification_tolerance * model.diagonal;
    std::unique_ptr<SurfaceQuery> input_surface;
    if (!model.measured_on.points.empty())
        input_surface = std::make_unique<SurfaceQuery>(model.measured_on.points, model.measured_on.normals,
                                                       model.measured_on.disc_radius);
    else if (model.measured_apart())  // every input vertex of every patch, both ways: a finer grid pays
        input_surface = std::make_unique<SurfaceQuery>(model.input, options.verification.grid_cells_per_face);
    std::vector<VerifiedSymmetry> reported;
    std::vector<int> supports;
    std::vector<const ContinuousFamily*> family_of;
    // A simplified copy smooths relief away, so its patches are trimmed to what maps on the
    // input; a refined copy is the input's own surface, verified more finely than the
    // input's few vertices could: its patches and areas stand.
    const std::vector<double> input_vertex_area =
        model.working && !model.cloud && !result.working_refined ? vertex_areas_of(model.input) : std::vector<double>();
    for (auto& f : findings.discrete) {
        if (input_surface) measure_on_input(model, *input_surface, tolerance, f.symmetry);
        if (!input_vertex_area.empty() &&
            !trim_to_input(input_vertex_area, tolerance, options.min_patch_area * model.total_area, f.symmetry))
            continue;
        reported.push_back(std::move(f.symmetry));
        supports.push_back(f.support);
        family_of.push_back(nullptr);
    }
    // A family stands for a continuum of symmetries in one report, and takes no discrete
    // symmetry's slot: up to max_symmetries of each are reported.
    int families = 0;
    for (size_t k = 0; k < findings.families.size() && families < options.max_symmetries; ++k) {
        if (!findings.family_holds[k]) continue;
        VerifiedSymmetry family = family_as_symmetry(findings.families[k], findings.family_checks[k], neighbourhoods);
        // Refinement by slippage may have shrunk the patch grown from a pruned sample.
        if (family.source_area < options.min_patch_area * model.total_area) continue;
        family_on_input(model, family);
        reported.push_back(std::move(family));
        supports.push_back(findings.family_support[k]);
        family_of.push_back(&findings.families[k]);
        ++families;
    }
    result.seconds_verification += seconds_since(start);
    refuse_if_nothing_could_be_paired(result, options, reported.size());

    // Most significant first: the larger the patch, the more of the model it explains.
    std::vector<size_t> order(reported.size());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
        if (reported[a].source_area != reported[b].source_area) return reported[a].source_area > reported[b].source_area;
        return supports[a] > supports[b];
    });

    // §4.1: generators and compound transforms, over the discrete symmetries.
    std::vector<Transformation> discrete;
    for (size_t k : order)
        if (!family_of[k]) discrete.push_back(reported[k].transform);
    SymmetryBasis basis;
    if (options.reduce_basis) {
        basis = reduce_basis(discrete, space, options.basis_loop_length, options.basis_tolerance);
    } else {
        // Without reduction every symmetry is its own generator: the trivial basis.
        for (size_t k = 0; k < discrete.size(); ++k) {
            basis.generators.push_back(int(k));
            basis.words.push_back({int(k) + 1});
        }
    }
    result.generator_count = int(basis.generators.size());

    // Outputs in the input's vertex numbering.
    result.vertex_deviation.assign(size_t(rows), 0.0);
    result.vertex_symmetry_id.assign(size_t(rows), -1);
    int discrete_index = 0;
    for (size_t rank = 0; rank < order.size(); ++rank) {
        const size_t k = order[rank];
        DetectedSymmetry d = report_symmetry(reported[k], model, int(rank), result);
        d.support = supports[k];
        if (const ContinuousFamily* family = family_of[k]) {
            d.continuous_kind = family->kind;
            d.axis_point = family->point;
            d.axis_direction = family->direction;
            d.pitch = family->pitch / model.diagonal;
            d.is_generator = false;
        } else {
            d.is_generator = std::find(basis.generators.begin(), basis.generators.end(), discrete_index) !=
                             basis.generators.end();
            d.word = basis.words[size_t(discrete_index)];
            ++discrete_index;
        }
        result.symmetries.push_back(std::move(d));
    }
    if (options.keep_transformation_space) {
        std::vector<Transformation> reported_transforms;
        for (const DetectedSymmetry& d : result.symmetries) reported_transforms.push_back(d.transform);
        result.transformation_space.symmetries = coordinates_of(reported_transforms, space);
    }
    write_to_welded_rows(model, result);
    report(100, "Done");
    return result;
}

}  // namespace

DetectionResult detect_partial_symmetries(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F,
                                          const DetectionOptions& options, const Progress& progress) {
    options.validate();
    auto report = [&](int percent, const char* stage) {
        if (progress) progress(percent, stage);
    };
    DetectionResult result;
    // §2, §2.1, §2.2: samples, signatures, pruning, pairs and their votes in Γ.
    report(0, "Sampling and curvature signatures");
    Model model;
    prepare_model(V, F, options, report, model, result);
    return detect_on_model(model, V.rows(), options, report, std::move(result));
}

DetectionResult detect_partial_symmetries_in_point_cloud(const Eigen::MatrixX3d& V, const Eigen::MatrixX3d& N,
                                                         const DetectionOptions& options, const Progress& progress) {
    options.validate();
    auto report = [&](int percent, const char* stage) {
        if (progress) progress(percent, stage);
    };
    DetectionResult result;
    report(0, "Normals, sampling and curvature of the point cloud");
    Model model;
    prepare_cloud_model(V, N, options, report, model, result);
    return detect_on_model(model, V.rows(), options, report, std::move(result));
}

void require_result_of_mesh(const DetectionResult& detected, Eigen::Index rows) {
    if (Eigen::Index(detected.vertex_symmetry_id.size()) != rows)
        throw InputError("The detection result belongs to another mesh (its vertex count differs).");
    for (const DetectedSymmetry& s : detected.symmetries)
        for (const std::vector<int>* patch : {&s.source_vertices, &s.target_vertices})
            for (int v : *patch)
                if (v < 0 || Eigen::Index(v) >= rows)
                    throw InputError("The detection result belongs to another mesh (a patch vertex is out of range).");
}

}  // namespace symmetry
