// Second-order verification (§4, beyond the paper's region growing).
//
// Region growing checks that T maps points onto the surface (order 0) with agreeing
// normals (order 1).  Two unrelated smooth patches that merely touch pass both over a
// disc around the contact, and on a smooth model such discs reach the size of a small
// symmetric part.  A symmetry also maps the curvature onto itself everywhere on its
// patch, which a touch does only at the contact.  This is the paper's own evidence,
// pairs whose signatures and frames agree under T, measured over the whole patch instead
// of over the pairs that happened to be drawn.
//
// How well curvature can agree depends on how repeatable its estimate is: on a noisy
// or coarse surface the estimate at two points a fraction of r apart already differs.
// So the agreement under T is compared with the agreement between each point and a
// point beside it, on both sides: a symmetry agrees about as well as neighbours do, a
// touch far worse; where neighbours hardly agree at all, the test has nothing to say.
#pragma once

#include "denoising.h"
#include "region_growing.h"
#include "signatures.h"
#include "surface_query.h"
#include "transformation_space.h"

#include <optional>
#include <vector>

namespace symmetry {

struct CurvatureAgreementOptions {
    /// The agreement under T must reach this fraction of the agreement between
    /// neighbouring points (the lower of the two sides) on a patch of no area...
    /// Measured: 0.8-1.5 on true symmetries (0.8 on a finely tessellated, nearly exact
    /// mirror), 0.3-0.6 on touches, which stay small.
    double min_relative_agreement = 0.75;
    /// ...and this on a patch of at least half the model's area, in between with the square
    /// of the area fraction: an imperfect global mirror of a scanned character agrees less
    /// (measured: 0.64 on a mannequin, 0.2 on the armadillo, whose bumps differ from side to
    /// side), and no touch is that large.
    double min_relative_agreement_large = 0.15;
    /// Below this agreement between neighbouring points the estimate is too noisy to
    /// judge, and the test passes.
    double min_repeatability = 0.15;
    /// Where either side's median roughness (see Roughness) exceeds this many edge
    /// lengths, the curvature there is noise and the test passes: neighbouring points share
    /// most of their ball, hence most of their noise, and agree better than independent
    /// estimates would.  Measured medians: 0.02-0.05 on clean models, 0.12-0.13 on a
    /// copy with noise of 0.15 edge lengths.
    double max_roughness_in_edges = 0.08;
    /// A point cloud presmoothed for noise above max_roughness_in_edges (point spacings, as
    /// estimated before the smoothing) hides that noise from the test: its curvature is a fit
    /// to points already moved onto fits over the same ball, so neighbouring points share their
    /// noise and agree better than independent estimates would, and the roughness measured
    /// after the smoothing is that of a clean surface.  There the test passes a patch of at
    /// least this share of the model's area, larger than a touch grows, and judges smaller
    /// ones as before.  Measured with noise of 0.1 % of the diagonal (clouds without normals):
    /// a bumpy torus's rigid copies (a third of the area each) agree under T at 0.24-0.33 of
    /// what neighbours show, where 0.48 is asked; a hammer's head's own half-turns and mirror
    /// at 0.22-0.28 (0.29 of the area); strips of the head's faces turned about its edges,
    /// which the head's planes would leave out as their members if its end faces were large
    /// enough to be found, at 0.08-0.28 over at most 0.15 of the area.
    double min_area_excused_by_cloud_noise = 0.2;
    /// The neighbouring point lies this many curvature radii from the sample.
    double neighbour_distance_in_radii = 0.25;
    /// Largest angle, in degrees, between two first principal directions that agree
    /// (directions have no sign).
    double direction_degrees = 30;
    int max_samples = 400;  ///< samples tested per symmetry, spread over the patch
};

struct CurvatureAgreement {
    int tested = 0;            ///< samples on the patch whose image lies on the surface
    int under_transform = 0;   ///< ... whose curvature agrees with that at the image
    int beside_source = 0;     ///< ... whose curvature agrees with that at a neighbouring point
    int beside_image = 0;      ///< ... whose image's curvature agrees with that at a point beside it
    double roughness_source = 0, roughness_image = 0;  ///< median roughness at the samples and at their images
    /// `area_fraction`: the patch's share of the model's area; `smoothed_noise_in_spacings`:
    /// a presmoothed cloud's noise before smoothing (see min_area_excused_by_cloud_noise), 0 on
    /// a mesh and on a cloud left as it is.
    bool passes(const CurvatureAgreementOptions& options, double area_fraction, double smoothed_noise_in_spacings = 0) const;
};

/// The point beside each sample (a step along its first principal direction, back on the
/// surface) and the curvature there: they depend on the sample alone, not on T, so a thread
/// keeps them across the symmetries it assesses: a third of the curvature estimates of an
/// assessment (on the speed benchmark's facade, 58 symmetries assessed, verification 6.4 s
/// to 5.8 s).  Bound to one list of samples and one surface.
class NeighbourSamples {
public:
    explicit NeighbourSamples(size_t sample_count) : known_(sample_count) {}
    struct Neighbour {
        ClosestPoint point;               ///< found=false where the step leaves the surface
        std::optional<SurfaceSignature> signature;  ///< measured when first needed
    };
    /// Sample i's neighbour, measured by `measure` the first time it is asked for.
    template <class Measure>
    Neighbour& at(size_t i, const Measure& measure) {
        if (!known_[i]) known_[i] = Neighbour{measure(), std::nullopt};
        return *known_[i];
    }

private:
    std::vector<std::optional<Neighbour>> known_;
};

/// Measures the agreement of the samples (from `samples`) lying on the source patch
/// (`source_vertices`, increasing): principal curvatures within `signature_tolerance`
/// (in units of 1/radius, as in pairing; scaled by T's scale) and first principal
/// directions mapped onto each other by T.
/// `workspace`, `roughness` and `neighbours` (sized for `samples`) are the calling thread's
/// own (each keeps work of its own).
CurvatureAgreement curvature_agreement(const MeshNeighbourhoods& mesh, const SurfaceQuery& surface,
                                       const CurvatureEstimator& curvature, CurvatureEstimator::Workspace& workspace,
                                       Roughness& roughness, NeighbourSamples& neighbours,
                                       const std::vector<SurfaceSignature>& samples,
                                       const std::vector<int>& source_vertices, const Transformation& T,
                                       double radius, double signature_tolerance, double tolerance,
                                       const CurvatureAgreementOptions& options);

}  // namespace symmetry
