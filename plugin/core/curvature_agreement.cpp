#include "curvature_agreement.h"

#include "statistics.h"

#include <algorithm>
#include <cmath>

namespace symmetry {

bool CurvatureAgreement::passes(const CurvatureAgreementOptions& options, double area_fraction,
                                double smoothed_noise_in_spacings) const {
    if (tested == 0) return false;
    if (std::max(roughness_source, roughness_image) > options.max_roughness_in_edges) return true;
    if (smoothed_noise_in_spacings > options.max_roughness_in_edges &&
        area_fraction >= options.min_area_excused_by_cloud_noise)
        return true;
    const double repeatability = double(std::min(beside_source, beside_image)) / tested;
    if (repeatability < options.min_repeatability) return true;
    const double largeness = std::min(1.0, area_fraction / 0.5);
    const double relative = options.min_relative_agreement +
                            largeness * largeness * (options.min_relative_agreement_large - options.min_relative_agreement);
    return double(under_transform) / tested >= relative * repeatability;
}

namespace {

// The median of the measurable values (0 if none).
double median_of_measured(std::vector<double> values) {
    values.erase(std::remove_if(values.begin(), values.end(), [](double x) { return std::isnan(x); }), values.end());
    return median(std::move(values));
}

// Whether two signatures agree, the second seen through the linear map `L` (a rotation,
// possibly improper) and the scale `scale` that carried the first onto it.
bool agree(const SurfaceSignature& a, const SurfaceSignature& b, const Transformation& T, double radius,
           double signature_tolerance, double min_cosine) {
    const double d1 = a.kappa1 - T.scale * b.kappa1, d2 = a.kappa2 - T.scale * b.kappa2;
    if (std::hypot(d1, d2) * radius > signature_tolerance) return false;
    return std::abs(T.apply_to_normal(a.direction1).dot(b.direction1)) >= min_cosine;
}

}  // namespace

CurvatureAgreement curvature_agreement(const MeshNeighbourhoods& mesh, const SurfaceQuery& surface,
                                       const CurvatureEstimator& curvature, CurvatureEstimator::Workspace& workspace,
                                       Roughness& roughness, NeighbourSamples& neighbours,
                                       const std::vector<SurfaceSignature>& samples,
                                       const std::vector<int>& source_vertices, const Transformation& T,
                                       double radius, double signature_tolerance, double tolerance,
                                       const CurvatureAgreementOptions& options) {
    std::vector<char> in_patch(size_t(mesh.vertex_count()), 0);
    for (int v : source_vertices) in_patch[size_t(v)] = 1;
    std::vector<const SurfaceSignature*> on_patch;
    for (const SurfaceSignature& s : samples) {
        const auto& corners = mesh.faces[size_t(s.face)];
        if (in_patch[size_t(corners[0])] && in_patch[size_t(corners[1])] && in_patch[size_t(corners[2])])
            on_patch.push_back(&s);
    }
    // Every k-th, so the tested samples spread over the whole patch.
    const size_t stride = std::max<size_t>(1, on_patch.size() / size_t(std::max(1, options.max_samples)));
    const double min_cosine = std::cos(options.direction_degrees * M_PI / 180.0);
    const double step = options.neighbour_distance_in_radii * radius;
    const Transformation identity;
    CurvatureAgreement result;
    std::vector<double> rough_source, rough_image;
    for (size_t i = 0; i < on_patch.size(); i += stride) {
        const SurfaceSignature& a = *on_patch[i];
        ClosestPoint image = surface.closest(T.apply(a.position), tolerance);
        // The neighbouring point: a step along the first principal direction, back on the surface.
        NeighbourSamples::Neighbour& neighbour = neighbours.at(
            size_t(on_patch[i] - samples.data()), [&] { return surface.closest(a.position + step * a.direction1, step); });
        const ClosestPoint& beside = neighbour.point;
        if (!image.found || !beside.found) continue;
        ClosestPoint beside_image = surface.closest(T.apply(beside.point), tolerance);
        if (!beside_image.found) continue;
        const SurfaceSignature b = curvature.at({image.point, image.face}, radius, workspace);
        if (!neighbour.signature) neighbour.signature = curvature.at({beside.point, beside.face}, radius, workspace);
        const SurfaceSignature& a2 = *neighbour.signature;
        const SurfaceSignature b2 = curvature.at({beside_image.point, beside_image.face}, radius, workspace);
        ++result.tested;
        rough_source.push_back(roughness.at(mesh.faces[size_t(a.face)][0]));
        rough_image.push_back(roughness.at(mesh.faces[size_t(image.face)][0]));
        result.under_transform += agree(a, b, T, radius, signature_tolerance, min_cosine);
        result.beside_source += agree(a, a2, identity, radius, signature_tolerance, min_cosine);
        result.beside_image += agree(b, b2, identity, radius, signature_tolerance, min_cosine);
    }
    result.roughness_source = median_of_measured(std::move(rough_source));
    result.roughness_image = median_of_measured(std::move(rough_image));
    return result;
}

}  // namespace symmetry
