// The Appendix's bound (Equation 1) against the paper's own worked example, and the
// properties the automatic n' relies on.
#include "core/sample_size.h"

#include <gtest/gtest.h>

using namespace symmetry;

TEST(SampleSize, ReproducesThePapersExample) {
    // "d = 6, L/h ≈ 20, and μ = 10 [...] Equation 1 prescribes n' ≈ 300 to detect a global
    // symmetry where p = 0.5 with probability more than 95 %."
    SampleSize s = appendix_sample_size(100000, 0.5, 10, 6, 20, 0.05);
    EXPECT_TRUE(s.bound_met);
    EXPECT_NEAR(s.n_prime, 300, 50);
    EXPECT_LT(s.noise, s.height);
    // One sample fewer does not meet the bound: n' is the smallest that does.
    EXPECT_GE(spurious_bin_height(s.n_prime - 1, 10, 6, 20), patch_bin_height(s.n_prime - 1, 0.5, 0.05, 6));
}

TEST(SampleSize, SmallerPatchesNeedMoreSamples) {
    int previous = 0;
    for (double p : {0.5, 0.2, 0.1, 0.05}) {
        SampleSize s = appendix_sample_size(1000000, p, 40, 6, 25, 0.05);
        EXPECT_TRUE(s.bound_met) << p;
        EXPECT_GT(s.n_prime, previous) << p;
        previous = s.n_prime;
    }
    // Higher confidence costs samples too.
    EXPECT_GT(appendix_sample_size(1000000, 0.1, 40, 6, 25, 0.01).n_prime,
              appendix_sample_size(1000000, 0.1, 40, 6, 25, 0.1).n_prime);
}

TEST(SampleSize, SaysWhenThereAreTooFewSamples) {
    SampleSize s = appendix_sample_size(2000, 0.01, 120, 6, 25, 0.05);
    EXPECT_FALSE(s.bound_met);
    EXPECT_EQ(s.n_prime, 2000);  // all of them, and the caller is told the bound is not met
}
