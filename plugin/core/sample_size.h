// The size n' of the random subset P' ⊂ P that is paired against P (§2.2), from the
// Appendix's bound: with n' samples drawn, a symmetric patch covering a fraction p of the
// samples yields, with probability 1 - α, a cluster that stands above the noise of
// spurious pairs in transformation space (Equation 1):
//
//     E(n', μ) = log N / log(N log N / M)  <  (1 - sqrt(-2 log α / (n' p))) n' p / 2^d
//
// N = (L / 2h)^d bins of Γ, M = μ n' points in Γ, μ points per paired sample, d the
// dimension of the group.  The bound is conservative (the paper found symmetries with far
// fewer samples); it is what the filter guarantees when pair_sample_count is 0.
#pragma once

namespace symmetry {

struct SampleSizeOptions {
    double confidence = 0.95;  ///< 1 - α: probability that a patch of the smallest size is found
    /// L of the Appendix, the extent of Γ along any of its dimensions, in units of the
    /// bounding-box diagonal (Γ's translations span about one diagonal).
    double transformation_space_extent = 1.0;
    int pilot_samples = 200;  ///< samples paired first to measure μ
};

struct SampleSize {
    int n_prime = 0;      ///< |P'| chosen
    double p = 0;         ///< the patch fraction it was chosen for
    double alpha = 0;     ///< 1 - the confidence
    double noise = 0;     ///< E(n', μ): the expected height of the tallest spurious bin
    double height = 0;    ///< the right-hand side: the height a patch of fraction p reaches
    bool bound_met = false;  ///< false when even n' = |P| does not meet Equation 1
};

/// Equation 1's left-hand side E(n', μ) for d dimensions and L/h.
double spurious_bin_height(double n_prime, double mu, int d, double extent_over_bandwidth);
/// Equation 1's right-hand side for patch fraction p and failure probability α.
double patch_bin_height(double n_prime, double p, double alpha, int d);

/// The smallest n' in [1, n] that meets Equation 1, or n when none does.
SampleSize appendix_sample_size(int n, double p, double mu, int d, double extent_over_bandwidth, double alpha);

}  // namespace symmetry
