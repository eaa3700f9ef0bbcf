// Statistical power of the paired comparisons that `compare` makes (harness/compare/compare.h): how
// small a change a run of a given size could have detected, and how many trials a user needs
// to detect a given change. At significance level alpha (two-sided) and power 0.8:
//
// Success (McNemar's exact test on the discordant pairs). The power is computed exactly for
// McNemar's exact conditional test: the number of discordant pairs D ~ Binomial(n, psi), and
// given D = d the pairs that now fail ~ Binomial(d, p10 / psi); the test rejects where its
// exact p-value is below alpha. The discordance assumes the two runs' outcomes independent at
// the given rates (p10 = p_base (1 - p_new), p01 = p_new (1 - p_base); Connor 1987's
// conservative case: trials that repeat, as here, discord less and are detected sooner). It
// agrees with the textbook normal approximation for McNemar's test (Connor 1987) within a
// point at n = 100 (the exact test, being discrete, needs a few percent more trials), and is 0
// where the exact test cannot reach alpha at all (n <= 5 at alpha = 0.05: 2 / 2^n >= alpha).
//
// Planning time (Wilcoxon's signed-rank test on the log ratios new/base): the paired t test's
// exact power (noncentral t) with the sample size scaled by the Wilcoxon test's asymptotic
// relative efficiency against the t test under normality, 3/pi (Lehmann; G*Power's "A.R.E."
// method): n' = 3n/pi, df = n' - 1, noncentrality (mean log ratio / sd) sqrt(n'). The sd of
// the log ratios is the group's own. No ratio is detectable where the exact test cannot
// reach alpha (fewer than wilcoxon_min_pairs pairs).
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace taskmatrix::harness {

inline constexpr double kTargetPower = 0.8;

// Exact power of McNemar's exact two-sided test over `pairs` pairs with success rates
// `p_base` and `p_new` (outcomes independent given the rates).
double mcnemar_power(int pairs, double p_base, double p_new, double alpha);

// The smallest drop of the success rate from `p_base` (in 0..1: 0.2 is 20 points) that
// McNemar's test over `pairs` pairs detects with power kTargetPower; NaN when no drop can be
// detected (not even one to 0%). For p_base = 0: the smallest rise instead.
double detectable_success_change(int pairs, double p_base, double alpha);

// The fewest pairs with which McNemar's test detects a drop of `change` from `p_base` (a rise
// for p_base = 0) with power kTargetPower; -1 when more than `max_pairs` are needed or the
// change is impossible (beyond 0% or 100%).
int pairs_for_success_change(double p_base, double change, double alpha, int max_pairs = 100000);

// The fewest non-zero differences with which Wilcoxon's exact test can give p < alpha.
int wilcoxon_min_pairs(double alpha);

// Power of Wilcoxon's signed-rank test over `pairs` differences whose mean is `effect`
// standard deviations from 0 (the ARE-scaled noncentral t approximation above). 0 for fewer
// than wilcoxon_min_pairs(alpha) pairs.
double wilcoxon_power(int pairs, double effect, double alpha);

// The smallest planning-time ratio (> 1) that Wilcoxon's test over `pairs` log ratios with
// standard deviation `log_sd` detects with power kTargetPower; NaN when `pairs` is below
// wilcoxon_min_pairs(alpha) or log_sd is not finite. A ratio r is as detectable as 1/r.
double detectable_time_ratio(int pairs, double log_sd, double alpha);

// The fewest pairs with which Wilcoxon's test detects a planning-time ratio `ratio` (!= 1)
// given log ratios with standard deviation `log_sd`; -1 beyond `max_pairs`.
int pairs_for_time_ratio(double ratio, double log_sd, double alpha, int max_pairs = 100000);

// What a compared group could detect, for reports.
struct GroupPower {
  int pairs = 0;
  double base_rate = 0;
  double success_change = NAN;  // smallest detectable drop (a rise when base_rate = 0)
  bool success_rise = false;    // success_change is a rise
  int time_pairs = 0;
  double log_ratio_sd = NAN;  // of the group's log planning-time ratios
  double time_ratio = NAN;    // smallest detectable ratio (> 1)
  // Trials needed per group for the targets (a drop of success_target points, a ratio of
  // time_target); -1: more than 100,000 or impossible.
  double success_target = 0.1, time_target = 1.25;
  int pairs_for_success_target = -1, pairs_for_time_target = -1;
  double alpha = 0.05;
};

// `min_time_pairs`: the fewest pairs for any time verdict (compare's threshold); below it no
// ratio is detectable.
GroupPower group_power(int pairs, int base_successes, const std::vector<double>& log_ratios,
                       int min_time_pairs, double alpha, double success_target, double time_target);

nlohmann::json group_power_json(const GroupPower& p);
// "52 points" / "none (3 pairs)"; "x1.41" / "none (2 pairs)". `unit` names what was counted.
std::string success_change_text(const GroupPower& p, const std::string& unit = "pairs");
std::string time_ratio_text(const GroupPower& p);
// "113" or "> 100000".
std::string pairs_needed_text(int pairs);

// For a run's summary (harness/results/summary.h): per group and for all trials ("overall"), the
// smallest success drop that a paired comparison with another run of the same trials could
// detect, and the trials needed for a change of `target` (0.1: 10 points; a drop, or a rise
// from a rate below `target`), at alpha = 0.05. "power" of summary.json and a section of
// summary.md.
nlohmann::json summary_power_json(const nlohmann::json& summary, double target = 0.1);
std::string summary_power_markdown(const nlohmann::json& summary_power);

}  // namespace taskmatrix::harness
