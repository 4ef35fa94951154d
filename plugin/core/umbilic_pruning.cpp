#include "umbilic_pruning.h"

#include <algorithm>
#include <cmath>

namespace symmetry {

bool has_distinct_principal_curvatures(const SurfaceSignature& s, double gamma, double radius, double flatness) {
    double largest = std::max(std::abs(s.kappa1), std::abs(s.kappa2));
    if (!(largest * radius >= flatness)) return false;
    return (s.kappa2 - s.kappa1) > (1.0 - gamma) * largest;
}

std::vector<SurfaceSignature> prune_umbilics(const std::vector<SurfaceSignature>& signatures, double gamma,
                                             double radius, double flatness) {
    std::vector<SurfaceSignature> kept;
    kept.reserve(signatures.size());
    for (const auto& s : signatures)
        if (has_distinct_principal_curvatures(s, gamma, radius, flatness)) kept.push_back(s);
    return kept;
}

}  // namespace symmetry
