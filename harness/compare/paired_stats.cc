#include "harness/compare/paired_stats.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

#include "harness/results/summary.h"

namespace taskmatrix::harness {

double mcnemar_exact_p(int only_base, int only_new) {
  const int n = only_base + only_new;
  if (n <= 0) return 1.0;
  const int k = std::min(only_base, only_new);
  // P(X <= k) for X ~ Binomial(n, 1/2), summed in logs so large n does not overflow.
  double tail = 0;
  for (int i = 0; i <= k; ++i) {
    const double log_term =
        std::lgamma(n + 1.0) - std::lgamma(i + 1.0) - std::lgamma(n - i + 1.0) - n * std::log(2.0);
    tail += std::exp(log_term);
  }
  return std::min(1.0, 2.0 * tail);
}

namespace {

double normal_two_sided_p(double z) { return std::erfc(std::fabs(z) / std::sqrt(2.0)); }

}  // namespace

double wilcoxon_signed_rank_p(const std::vector<double>& d) {
  std::vector<double> nz;
  for (double v : d) {
    if (v != 0 && std::isfinite(v)) nz.push_back(v);
  }
  const size_t n = nz.size();
  if (n == 0) return 1.0;
  std::vector<size_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
            [&](size_t a, size_t b) { return std::fabs(nz[a]) < std::fabs(nz[b]); });
  std::vector<double> rank(n);
  bool ties = false;
  double tie_term = 0;  // sum of t^3 - t over tie groups
  for (size_t i = 0; i < n;) {
    size_t j = i;
    while (j + 1 < n && std::fabs(nz[order[j + 1]]) == std::fabs(nz[order[i]])) ++j;
    const double avg = (static_cast<double>(i) + static_cast<double>(j)) / 2.0 + 1.0;
    for (size_t k = i; k <= j; ++k) rank[order[k]] = avg;
    const double t = static_cast<double>(j - i + 1);
    if (t > 1) {
      ties = true;
      tie_term += t * t * t - t;
    }
    i = j + 1;
  }
  double w_plus = 0;
  for (size_t i = 0; i < n; ++i) {
    if (nz[i] > 0) w_plus += rank[i];
  }
  const double total = static_cast<double>(n) * (n + 1) / 2.0;
  if (!ties && n <= 30) {
    // Exact: count the subsets of {1..n} by their rank sum.
    const int max_sum = static_cast<int>(total);
    std::vector<double> count(static_cast<size_t>(max_sum) + 1, 0.0);
    count[0] = 1;
    for (int r = 1; r <= static_cast<int>(n); ++r) {
      for (int s = max_sum; s >= r; --s) count[s] += count[s - r];
    }
    const int w = static_cast<int>(std::lround(std::min(w_plus, total - w_plus)));
    double tail = 0;
    for (int s = 0; s <= w; ++s) tail += count[s];
    return std::min(1.0, 2.0 * tail / std::ldexp(1.0, static_cast<int>(n)));
  }
  const double mean = total / 2.0;
  const double var = static_cast<double>(n) * (n + 1) * (2.0 * n + 1) / 24.0 - tie_term / 48.0;
  if (var <= 0) return 1.0;
  const double diff = w_plus - mean;
  const double corrected = std::max(0.0, std::fabs(diff) - 0.5);
  return normal_two_sided_p(corrected / std::sqrt(var));
}

MeanInterval bootstrap_mean_interval(const std::vector<double>& values, double level, int resamples,
                                     std::uint64_t seed) {
  MeanInterval out;
  if (values.empty()) return {NAN, NAN, NAN};
  const size_t n = values.size();
  out.mean = std::accumulate(values.begin(), values.end(), 0.0) / static_cast<double>(n);
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<size_t> pick(0, n - 1);
  std::vector<double> means(static_cast<size_t>(std::max(1, resamples)));
  for (double& m : means) {
    double sum = 0;
    for (size_t i = 0; i < n; ++i) sum += values[pick(rng)];
    m = sum / static_cast<double>(n);
  }
  const double tail = (1.0 - level) / 2.0;
  out.low = quantile(means, tail);
  out.high = quantile(means, 1.0 - tail);
  return out;
}

}  // namespace taskmatrix::harness
