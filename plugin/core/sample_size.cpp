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
    // The left side falls and the right side grows with n': the first n' that meets the
    // bound is found by bisection.
    s.n_prime = std::max(1, n);
    s.bound_met = n > 0 && meets(n);
    if (s.bound_met) {
        int lo = 0, hi = n;  // meets(hi), !meets(lo)
        while (hi - lo > 1) {
            const int mid = lo + (hi - lo) / 2;
            (meets(mid) ? hi : lo) = mid;
        }
        s.n_prime = hi;
    }
    s.noise = spurious_bin_height(s.n_prime, mu, d, extent_over_bandwidth);
    s.height = patch_bin_height(s.n_prime, p, alpha, d);
    return s;
}

}  // namespace symmetry
