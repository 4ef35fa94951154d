// Stage 1 (§5, "uniformly sampling the input model"): random points spread over
// the surface with a density proportional to area, so that every part of the
// model gets samples in proportion to its size (the Appendix's p = m/n).
#pragma once

#include "mesh.h"

#include <Eigen/Core>
#include <random>
#include <vector>

namespace symmetry {

struct SurfaceSample {
    Eigen::Vector3d position;
    int face = -1;  ///< index into mesh.face of the triangle the sample lies on
};

/// Draws `count` samples uniformly by area.  Deterministic for a given `rng` state.
/// @param[in]     mesh   the core mesh (faces must be live)
/// @param[in]     count  number of samples, > 0
/// @param[in,out] rng    random generator, advanced by the call
std::vector<SurfaceSample> uniform_area_sampling(const Mesh& mesh, int count, std::mt19937_64& rng);

}  // namespace symmetry
