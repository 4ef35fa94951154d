// Presmoothing of a noisy model (§5, limitations: "In such a situation, presmoothing of
// the model is required [...] until noise is sufficiently blurred out").
//
// Curvature is a second derivative: vertex noise of a fraction of the edge length makes
// the curvature tensor of §2 and its principal frames meaningless, and no pair votes for
// the true symmetry.  When the mesh is noisy, the signatures (§2) and the region growing
// (§4) work on a smoothed copy instead; the deviation from perfect symmetry is still
// measured on the input.  A clean mesh is left exactly as it is.
#pragma once

#include "mesh.h"
#include "region_growing.h"

#include <vector>

namespace symmetry {

struct DenoisingOptions {
    /// Meshes whose estimated noise is below this many mean edge lengths are left as they
    /// are.  Measured: clean scans and coarse models 0.04-0.18, a copy with Gaussian noise
    /// of 0.15 and 0.3 edge lengths 0.21 and 0.39; the first is still found unsmoothed.
    double noise_threshold_in_edges = 0.25;
    /// Quantile of the per-vertex noise taken as the mesh's noise: above the median, so
    /// that a model half of which is noisy (one noisy copy of a clean part) counts as noisy.
    double noise_quantile = 0.75;
    /// Face normals around a vertex within this angle (degrees) are one side of a crease:
    /// a vertex with two or three such sides is a crease or corner, not noise.
    double crease_side_degrees = 5;
    /// Vertices whose longest edge is this many times their shortest are skipped: on a
    /// coarse CAD tessellation (long thin triangles) no quadric fits the two-ring.
    double max_edge_ratio = 3;
    /// The smoothing blurs over ρ = factor · sqrt(noise · edge): the length over which the
    /// averaged noise falls to a fiftieth of ρ, so its curvature stays below a fiftieth of
    /// the signature tolerance's scale (noise σ averaged over (ρ/e)² vertices is σe/ρ).
    double smoothing_radius_factor = 7;
    /// The curvature ball r grows to the smoothing radius ρ when ρ exceeds it, up to this
    /// fraction of the bounding-box diagonal.
    double max_radius_for_noise = 0.03;
    int max_smoothing_steps = 300;  ///< explicit diffusion steps at most
    int max_vertices_measured = 20000;  ///< the noise is estimated on at most this many vertices
};

struct NoiseEstimate {
    double noise = 0;            ///< estimated vertex noise, absolute units
    double edge_length = 0;      ///< mean edge length, absolute units
    int vertices_measured = 0;   ///< vertices that entered the estimate (creases and corners do not)
    double noise_in_edges() const { return edge_length > 0 ? noise / edge_length : 0; }
};

/// The noise measure at single vertices, computed on demand and kept: the residual at v
/// of a quadric height field fitted to its two-ring, minus the mean of that residual at
/// its neighbours, in units of v's mean edge length.  NaN where it cannot be measured
/// (creases, corners, irregular or small neighbourhoods).  One object serves one thread.
class Roughness {
public:
    Roughness(const MeshNeighbourhoods& mesh, const DenoisingOptions& options);
    double at(int v);
    double edge_at(int v);  ///< mean length of v's edges

private:
    void measure(int v);
    const MeshNeighbourhoods& mesh_;
    DenoisingOptions options_;
    double side_cosine_;
    std::vector<int> stamp_;
    std::vector<double> residual_, edge_;
};

/// Per vertex (on a subset), the residual at the vertex of a least-squares quadric height
/// field fitted to its two-ring in the frame of its normal, minus the mean of that residual
/// at its neighbours: about zero on a clean tessellation of a smooth surface, and on a
/// coarse one too (whose residuals vary smoothly), the noise level on a noisy one.  Crease
/// and corner vertices, which no quadric fits but which are not noise, are skipped; the
/// estimate is the `noise_quantile` of the rest.
NoiseEstimate estimate_noise(const MeshNeighbourhoods& mesh, const DenoisingOptions& options);

/// Smoothing radius ρ for the estimate, or 0 when the mesh is clean.
double smoothing_radius(const NoiseEstimate& estimate, const DenoisingOptions& options);

/// Heat diffusion of the vertex positions over the time that blurs by `radius`: explicit
/// umbrella steps whose per-vertex rate is scaled by the vertex's own squared edge length,
/// so two tessellations of one surface are blurred alike (a plain umbrella operator blurs
/// a coarse copy more than a fine one, and their curvatures would no longer match).
/// Border vertices move along the border only.  Returns the number of steps taken.
int smooth_positions(Mesh& mesh, double radius, const DenoisingOptions& options);

}  // namespace symmetry
