// Stage 3 (§2.1): discard samples whose principal directions are not defined, so
// that every remaining pair determines one transformation instead of a curve.
#pragma once

#include "signatures.h"

#include <vector>

namespace symmetry {

/// True where the paper keeps the sample: |kappa1/kappa2| < gamma.  The paper's
/// ratio is only meaningful for curvatures of equal sign ordered by magnitude; we use
/// the equivalent, sign-safe form (kappa2 - kappa1) > (1 - gamma) max(|kappa1|, |kappa2|),
/// which is the paper's test for equal signs and always keeps saddles (whose
/// directions are well defined).  Flat samples are discarded too: those whose largest curvature
/// bends the surface by less than flatness * r / 2 across the ball of radius r
/// (DetectionOptions::flatness).
bool has_distinct_principal_curvatures(const SurfaceSignature& s, double gamma, double radius, double flatness);

/// Keeps the samples that pass has_distinct_principal_curvatures, in order.
std::vector<SurfaceSignature> prune_umbilics(const std::vector<SurfaceSignature>& signatures, double gamma,
                                             double radius, double flatness);

}  // namespace symmetry
