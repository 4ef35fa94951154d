#include "sampling.h"

#include <algorithm>
#include <cmath>

namespace symmetry {

namespace {
// A double uniform in [0, 1) from the top 53 bits of one draw.  Written out rather
// than std::uniform_real_distribution because the standard leaves that
// distribution's algorithm to the library: libstdc++ and libc++ would give
// different samples for the same seed, and the pipeline must be reproducible
// whatever host (GUI, pymeshlab wheel) it was built for.
double uniform01(std::mt19937_64& rng) { return double(rng() >> 11) * 0x1.0p-53; }
}  // namespace

std::vector<SurfaceSample> uniform_area_sampling(const Mesh& mesh, int count, std::mt19937_64& rng) {
    std::vector<SurfaceSample> samples;
    if (count <= 0) return samples;

    // Cumulative area over mesh.face (deleted faces add nothing, so a draw never
    // lands on them): picking a face by a uniform draw on [0, total) makes the
    // density proportional to area, the Appendix's p = m/n for every patch.
    std::vector<double> cumulative(mesh.face.size());
    double total = 0;
    int last_live = -1;
    for (size_t i = 0; i < mesh.face.size(); ++i) {
        const Face& f = mesh.face[i];
        if (!f.IsD()) {
            total += 0.5 * ((f.cP(1) - f.cP(0)) ^ (f.cP(2) - f.cP(0))).Norm();
            last_live = int(i);
        }
        cumulative[i] = total;
    }
    if (!(total > 0) || last_live < 0)
        throw InputError("The mesh has no surface area to sample.");

    samples.reserve(size_t(count));
    for (int k = 0; k < count; ++k) {
        // upper_bound skips zero-area (and deleted) faces: their cumulative value
        // equals their predecessor's, which is found first.
        double x = uniform01(rng) * total;
        auto it = std::upper_bound(cumulative.begin(), cumulative.end(), x);
        int face = it == cumulative.end() ? last_live : int(it - cumulative.begin());  // x rounded up to total
        const Face& f = mesh.face[size_t(face)];

        // Uniform point in the triangle: with s = sqrt(u) the first barycentric
        // weight 1 - s has the density of a triangle's cross-section, so the
        // point is uniform by area, with no rejection (two draws per sample).
        double s = std::sqrt(uniform01(rng));
        double v = uniform01(rng);
        vcg::Point3d p = f.cP(0) * (1 - s) + f.cP(1) * (s * (1 - v)) + f.cP(2) * (s * v);
        samples.push_back({Eigen::Vector3d(p[0], p[1], p[2]), face});
    }
    return samples;
}

}  // namespace symmetry
