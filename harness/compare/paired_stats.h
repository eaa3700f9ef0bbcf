// Statistics for paired comparisons of two runs of the same trials (harness/compare/compare.h):
// McNemar's exact test for a change of a binary outcome, Wilcoxon's signed-rank test and a
// percentile bootstrap interval for paired differences.
#pragma once

#include <cstdint>
#include <vector>

namespace taskmatrix::harness {

// McNemar's exact (binomial) test, two-sided: `only_base` pairs succeeded in the base run only,
// `only_new` in the new run only. p = min(1, 2 P(X <= min(b, c))), X ~ Binomial(b + c, 1/2);
// 1 when there are no discordant pairs.
double mcnemar_exact_p(int only_base, int only_new);

// Wilcoxon's signed-rank test, two-sided, of paired differences `d` against 0. Zeros are
// dropped (Wilcoxon's convention); ties share their average rank. Exact distribution for up
// to 30 non-zero differences without ties, else the normal approximation with tie and
// continuity corrections. 1 when no difference is non-zero.
double wilcoxon_signed_rank_p(const std::vector<double>& d);

struct MeanInterval {
  double mean = 0, low = 0, high = 0;
};
// The mean of `values` and its percentile bootstrap interval at `level` (0.95: the 2.5% and
// 97.5% quantiles of `resamples` resampled means). Deterministic for a given `seed`.
MeanInterval bootstrap_mean_interval(const std::vector<double>& values, double level = 0.95,
                                     int resamples = 4000, std::uint64_t seed = 1);

}  // namespace taskmatrix::harness
