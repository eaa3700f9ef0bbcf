#include "harness/compare/power.h"

#include <algorithm>
#include <boost/math/distributions/non_central_t.hpp>
#include <boost/math/distributions/students_t.hpp>
#include <cmath>
#include <numbers>

#include "harness/report/report_table.h"
#include "harness/results/json_input.h"
#include "harness/results/summary.h"

namespace taskmatrix::harness {

namespace {

double binomial_pmf(int n, int k, double p) {
  if (k < 0 || k > n) return 0;
  if (p <= 0) return k == 0 ? 1 : 0;
  if (p >= 1) return k == n ? 1 : 0;
  return std::exp(std::lgamma(n + 1.0) - std::lgamma(k + 1.0) - std::lgamma(n - k + 1.0) +
                  k * std::log(p) + (n - k) * std::log1p(-p));
}

// The largest k for which McNemar's exact p-value with k pairs one way and d - k the other,
// 2 P(Binomial(d, 1/2) <= k), is below alpha; -1 when there is none.
int mcnemar_critical(int d, double alpha) {
  int k = -1;
  double cdf = 0;
  for (int i = 0; 2 * i < d; ++i) {
    cdf += binomial_pmf(d, i, 0.5);
    if (2 * cdf >= alpha) break;
    k = i;
  }
  return k;
}

// Bisection for the smallest x in (lo, hi] with pred(x) true, given pred(hi) true.
template <typename Pred>
double smallest_true(double lo, double hi, Pred pred) {
  for (int i = 0; i < 60 && hi - lo > 1e-7 * std::max(1.0, hi); ++i) {
    const double mid = (lo + hi) / 2;
    (pred(mid) ? hi : lo) = mid;
  }
  return hi;
}

}  // namespace

double mcnemar_power(int pairs, double p_base, double p_new, double alpha) {
  if (pairs <= 0) return 0;
  p_base = std::clamp(p_base, 0.0, 1.0);
  p_new = std::clamp(p_new, 0.0, 1.0);
  const double p10 = p_base * (1 - p_new), p01 = p_new * (1 - p_base);
  const double psi = p10 + p01;
  if (psi <= 0) return 0;
  const double r = p10 / psi;
  // Discordant counts far outside D's distribution contribute nothing.
  const double mean = pairs * psi, sd = std::sqrt(pairs * psi * (1 - psi));
  const int d_lo = std::max(0, static_cast<int>(std::floor(mean - 12 * sd - 1)));
  const int d_hi = std::min(pairs, static_cast<int>(std::ceil(mean + 12 * sd + 1)));
  double power = 0;
  for (int d = d_lo; d <= d_hi; ++d) {
    const double pd = binomial_pmf(pairs, d, psi);
    if (pd <= 0) continue;
    const int k = mcnemar_critical(d, alpha);
    double reject = 0;
    for (int i = 0; i <= k; ++i) reject += binomial_pmf(d, i, r) + binomial_pmf(d, d - i, r);
    power += pd * reject;
  }
  return std::min(1.0, power);
}

double detectable_success_change(int pairs, double p_base, double alpha) {
  if (pairs <= 0) return NAN;
  const bool rise = p_base <= 0;
  const auto power = [&](double change) {
    return rise ? mcnemar_power(pairs, 0, change, alpha)
                : mcnemar_power(pairs, p_base, p_base - change, alpha);
  };
  const double most = rise ? 1.0 : p_base;
  if (power(most) < kTargetPower) return NAN;
  return smallest_true(0, most, [&](double c) { return power(c) >= kTargetPower; });
}

int pairs_for_success_change(double p_base, double change, double alpha, int max_pairs) {
  if (!(change > 0)) return -1;
  double p_new;
  if (p_base > 0 && p_base - change >= -1e-12) {
    p_new = std::max(0.0, p_base - change);
  } else if (p_base + change <= 1 + 1e-12) {
    p_new = std::min(1.0, p_base + change);
  } else {
    return -1;
  }
  const auto enough = [&](int n) { return mcnemar_power(n, p_base, p_new, alpha) >= kTargetPower; };
  int hi = 1;
  while (!enough(hi)) {
    if (hi >= max_pairs) return -1;
    hi = std::min(max_pairs, 2 * hi);
  }
  int lo = hi / 2;  // enough(lo) false (or lo = 0)
  while (hi - lo > 1) {
    const int mid = (lo + hi) / 2;
    (enough(mid) ? hi : lo) = mid;
  }
  // Exact power rises in a saw-tooth with n: look a little below for an earlier crossing.
  const int window = std::min(30, 3 + hi / 20);
  for (int n = std::max(1, hi - window); n < hi; ++n) {
    if (enough(n)) return n;
  }
  return hi;
}

// Log-ratio spreads below this are rounding, not spread (a ratio's log is exact to ~1e-16).
constexpr double kNoSpread = 1e-12;

int wilcoxon_min_pairs(double alpha) {
  int n = 1;
  while (std::ldexp(2.0, -n) >= alpha && n < 64) ++n;
  return n;
}

double wilcoxon_power(int pairs, double effect, double alpha) {
  if (pairs < wilcoxon_min_pairs(alpha)) return 0;
  const double n = pairs * 3 / std::numbers::pi;  // the ARE-equivalent t test's size
  const double df = n - 1;
  const double critical =
      boost::math::quantile(boost::math::complement(boost::math::students_t(df), alpha / 2));
  const double lambda = std::fabs(effect) * std::sqrt(n);
  if (lambda == 0) return alpha;
  // Far beyond the critical value (under 3 for the fewest pairs a verdict needs): the power is
  // 1 to double precision, and boost's series would overflow.
  if (lambda > 64) return 1.0;
  const boost::math::non_central_t shifted(df, lambda);
  return boost::math::cdf(boost::math::complement(shifted, critical)) +
         boost::math::cdf(shifted, -critical);
}

double detectable_time_ratio(int pairs, double log_sd, double alpha) {
  if (pairs < wilcoxon_min_pairs(alpha) || !std::isfinite(log_sd) || log_sd < 0) return NAN;
  // No spread (log ratios equal up to rounding): any consistent change is detected.
  if (log_sd <= kNoSpread) return 1.0;
  const auto enough = [&](double e) { return wilcoxon_power(pairs, e, alpha) >= kTargetPower; };
  double hi = 1;
  while (!enough(hi)) hi *= 2;
  return std::exp(smallest_true(0, hi, enough) * log_sd);
}

int pairs_for_time_ratio(double ratio, double log_sd, double alpha, int max_pairs) {
  const int least = wilcoxon_min_pairs(alpha);
  if (!(ratio > 0) || ratio == 1 || !std::isfinite(log_sd) || log_sd < 0) return -1;
  if (log_sd <= kNoSpread) return least;
  const double effect = std::fabs(std::log(ratio)) / log_sd;
  const auto enough = [&](int n) { return wilcoxon_power(n, effect, alpha) >= kTargetPower; };
  if (!enough(max_pairs)) return -1;
  int lo = least - 1, hi = max_pairs;  // power rises with n
  while (hi - lo > 1) {
    const int mid = lo + (hi - lo) / 2;
    (enough(mid) ? hi : lo) = mid;
  }
  return hi;
}

GroupPower group_power(int pairs, int base_successes, const std::vector<double>& log_ratios,
                       int min_time_pairs, double alpha, double success_target,
                       double time_target) {
  GroupPower p;
  p.alpha = alpha;
  p.pairs = pairs;
  p.base_rate = pairs > 0 ? static_cast<double>(base_successes) / pairs : 0;
  p.success_change = detectable_success_change(pairs, p.base_rate, alpha);
  p.success_rise = p.base_rate <= 0;
  p.success_target = success_target;
  p.time_target = time_target;
  p.pairs_for_success_target = pairs_for_success_change(p.base_rate, success_target, alpha);
  p.time_pairs = static_cast<int>(log_ratios.size());
  if (p.time_pairs >= 2) {
    double mean = 0;
    for (double v : log_ratios) mean += v;
    mean /= p.time_pairs;
    double ss = 0;
    for (double v : log_ratios) ss += (v - mean) * (v - mean);
    p.log_ratio_sd = std::sqrt(ss / (p.time_pairs - 1));
  }
  if (p.time_pairs >= min_time_pairs) {
    p.time_ratio = detectable_time_ratio(p.time_pairs, p.log_ratio_sd, alpha);
  }
  const int needed = pairs_for_time_ratio(time_target, p.log_ratio_sd, alpha);
  p.pairs_for_time_target = needed < 0 ? -1 : std::max(needed, min_time_pairs);
  return p;
}

namespace {

nlohmann::json count_or_null(int n) { return n < 0 ? nlohmann::json(nullptr) : nlohmann::json(n); }

}  // namespace

nlohmann::json group_power_json(const GroupPower& p) {
  return {{"alpha", p.alpha},
          {"power", kTargetPower},
          {"pairs", p.pairs},
          {"base_rate", p.base_rate},
          {"detectable_success_change", number_or_null(p.success_change)},
          {"success_change_is_rise", p.success_rise},
          {"time_pairs", p.time_pairs},
          {"log_ratio_sd", number_or_null(p.log_ratio_sd)},
          {"detectable_time_ratio", number_or_null(p.time_ratio)},
          {"success_target", p.success_target},
          {"pairs_for_success_target", count_or_null(p.pairs_for_success_target)},
          {"time_target", p.time_target},
          {"pairs_for_time_target", count_or_null(p.pairs_for_time_target)}};
}

std::string success_change_text(const GroupPower& p, const std::string& unit) {
  if (!std::isfinite(p.success_change)) {
    return "none (" + std::to_string(p.pairs) + " " +
           (p.pairs == 1 ? unit.substr(0, unit.size() - 1) : unit) + ")";
  }
  const double points = 100 * p.success_change;
  return (p.success_rise ? "+" : "") + format_number(points < 9.95 ? "%.1f" : "%.0f", points) +
         " points";
}

std::string time_ratio_text(const GroupPower& p) {
  if (!std::isfinite(p.time_ratio)) {
    return "none (" + std::to_string(p.time_pairs) + (p.time_pairs == 1 ? " pair)" : " pairs)");
  }
  if (p.time_ratio == 1.0) return "any (no spread)";
  return format_number("x%.2f", p.time_ratio);
}

std::string pairs_needed_text(int pairs) {
  return pairs < 0 ? std::string("> 100000") : std::to_string(pairs);
}

namespace {

// One group's (or the whole run's) row of summary.json's "power".
nlohmann::json summary_power_row(const nlohmann::json& group, double target) {
  constexpr double kAlpha = 0.05;
  const int n = group.value("trials", 0), s = group.value("successes", 0);
  const GroupPower p = group_power(n, s, {}, 1, kAlpha, target, 1.25);
  return {{"trials", n},
          {"successes", s},
          {"detectable_success_change", number_or_null(p.success_change)},
          {"success_change_is_rise", p.success_rise},
          {"trials_for_target", count_or_null(p.pairs_for_success_target)}};
}

}  // namespace

nlohmann::json summary_power_json(const nlohmann::json& summary, double target) {
  nlohmann::json groups = nlohmann::json::array();
  for (const nlohmann::json& g : summary.value("groups", nlohmann::json::array())) {
    nlohmann::json row = {{"scenario", g.value("scenario", "")},
                          {"robot", g.value("robot", "")},
                          {"environment", g.value("environment", "")},
                          {"planner", g.value("planner", "")}};
    row.update(summary_power_row(g, target));
    groups.push_back(std::move(row));
  }
  return {
      {"alpha", 0.05},
      {"power", kTargetPower},
      {"target", target},
      {"overall", summary_power_row(summary.value("overall", nlohmann::json::object()), target)},
      {"groups", groups}};
}

std::string summary_power_markdown(const nlohmann::json& power) {
  const double target = power.value("target", 0.1);
  const std::string points = format_number("%.0f", 100 * target);
  ReportTable table;
  table.columns = {"scenario",
                   "robot",
                   "environment",
                   "planner",
                   "trials",
                   "success",
                   "smallest detectable drop",
                   "trials for a " + points + "-point change"};
  const auto add = [&](const nlohmann::json& g, std::vector<std::string> names) {
    GroupPower p;
    p.pairs = g.value("trials", 0);
    p.success_rise = g.value("success_change_is_rise", false);
    const nlohmann::json& change = g["detectable_success_change"];
    p.success_change = change.is_number() ? change.get<double>() : NAN;
    const nlohmann::json& needed = g["trials_for_target"];
    names.insert(names.end(),
                 {std::to_string(p.pairs),
                  std::to_string(g.value("successes", 0)) + "/" + std::to_string(p.pairs),
                  success_change_text(p, "trials"),
                  pairs_needed_text(needed.is_number() ? needed.get<int>() : -1)});
    table.rows.push_back({std::move(names), ""});
  };
  const nlohmann::json groups = power.value("groups", nlohmann::json::array());
  if (groups.size() != 1 && power.contains("overall")) {
    add(power["overall"], {"all trials", "", "", ""});
  }
  for (const nlohmann::json& g : groups) {
    add(g, {g.value("scenario", ""), g.value("robot", ""), g.value("environment", ""),
            g.value("planner", "")});
  }
  return "\n## Statistical power\n\nHow small a change of the success rate a paired comparison "
         "with another run of the same trials (`taskmatrix compare`) could detect at alpha = "
         "0.05 with 80% power (exact power of McNemar's exact test, outcomes taken as independent "
         "at this run's rate: conservative; a rise where nothing succeeded), and how many trials "
         "per group (all trials: in all) a " +
         points + "-point change needs (a drop; a rise where the rate is below " + points +
         "%). \"none\": no change is detectable with so few trials.\n\n" + markdown_table(table);
}

}  // namespace taskmatrix::harness
