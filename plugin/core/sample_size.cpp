#include "sample_size.h"

#include <algorithm>
#include <cmath>

namespace symmetry {

double spurious_bin_height(double n_prime, double mu, int d, double extent_over_bandwidth) {
    const double bins = std::pow(extent_over_bandwidth / 2, d);  // N = (L / 2h)^d
    const double points = std::max(1.0, mu * n_prime);           // M = μ n'
    const double ratio = bins * std::log(bins) / points;
    // Below e the balls-into-bins estimate no longer applies: every bin is crowded.
    return ratio > M_E ? std::log(bins) / std::log(ratio) : INFINITY;
}

double patch_bin_height(double n_prime, double p, double alpha, int d) {
    const double expected = n_prime * p;  // votes near T: one per paired sample on the patch
    if (!(expected > 0)) return 0;
    const double chernoff = 1 - std::sqrt(-2 * std::log(alpha) / expected);
    return std::max(0.0, chernoff) * expected / std::pow(2.0, d);
}

SampleSize appendix_sample_size(int n, double p, double mu, int d, double extent_over_bandwidth, double alpha) {
    SampleSize s;
    s.p = p;
    s.alpha = alpha;
    auto meets = [&](int m) {
        return spurious_bin_height(m, mu, d, extent_over_bandwidth) < patch_bin_height(m, p, alpha, d);
    };
    // Both sides grow with n': the right one linearly, the left one slowly until the points
    // crowd every bin.  So the bound holds on an interval of n'; its start is found by
    // geometric steps, then bisection.
    s.n_prime = std::max(1, n);
    s.bound_met = false;
    int below = 0;
    for (double m = 16; m < 2.0 * n; m *= 1.25) {
        const int candidate = std::min(n, int(m));
        if (meets(candidate)) {
            int lo = below, hi = candidate;  // !meets(lo) (or lo = 0), meets(hi)
            while (hi - lo > 1) {
                const int mid = lo + (hi - lo) / 2;
                (meets(mid) ? hi : lo) = mid;
            }
            s.n_prime = hi;
            s.bound_met = true;
            break;
        }
        below = candidate;
        if (candidate == n) break;
    }
    s.noise = spurious_bin_height(s.n_prime, mu, d, extent_over_bandwidth);
    s.height = patch_bin_height(s.n_prime, p, alpha, d);
    return s;
}

}  // namespace symmetry
