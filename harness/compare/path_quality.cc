#include "harness/compare/path_quality.h"

#include <boost/math/distributions/students_t.hpp>
#include <cmath>

#include "harness/compare/paired_stats.h"
#include "harness/results/json_input.h"
#include "harness/results/summary.h"

namespace taskmatrix::harness {

namespace {

double number(const nlohmann::json& t, const char* key) {
  const auto it = t.find(key);
  return it != t.end() && it->is_number() ? it->get<double>() : NAN;
}

std::string with_unit(const char* format, double v, const std::string& unit) {
  return format_number(format, v) + (unit.empty() ? "" : " " + unit);
}

// Enough digits for the measure's size.
const char* format_for(double typical) {
  const double a = std::fabs(typical);
  if (a >= 100) return "%+.0f";
  if (a >= 1) return "%+.2f";
  if (a >= 0.01) return "%+.3f";
  return "%+.4f";
}

}  // namespace

double student_t_quantile(double p, double df) {
  return boost::math::quantile(boost::math::students_t(df), p);
}

std::vector<PathQualityChange> compare_path_quality(const std::vector<TrialPair>& pairs,
                                                    std::span<const TrialField> fields) {
  std::vector<PathQualityChange> out;
  for (const TrialField& f : fields) {
    const FieldDisplay& shown = f.display;
    if (shown.path_quality == Better::kNone) continue;
    PathQualityChange c;
    c.field = f.name;
    c.name = shown.label;
    c.unit = shown.unit;
    c.lower_is_better = shown.path_quality == Better::kLower;
    c.better_word = shown.better_word;
    c.worse_word = shown.worse_word;
    std::vector<double> base, fresh, change;
    for (const TrialPair& p : pairs) {
      if (!p.base->value("success", false) || !p.fresh->value("success", false)) continue;
      const double b = number(*p.base, c.field.c_str()), n = number(*p.fresh, c.field.c_str());
      if (!std::isfinite(b) || !std::isfinite(n)) continue;
      base.push_back(b);
      fresh.push_back(n);
      change.push_back(n - b);
    }
    c.pairs = static_cast<int>(change.size());
    if (c.pairs > 0) {
      c.base_median = quantile(base, 0.5);
      c.new_median = quantile(fresh, 0.5);
      double sum_b = 0, sum_d = 0;
      for (size_t i = 0; i < change.size(); ++i) {
        sum_b += base[i];
        sum_d += change[i];
      }
      c.base_mean = sum_b / c.pairs;
      c.mean_change = sum_d / c.pairs;
      if (c.pairs >= 2) {
        double ss = 0;
        for (double d : change) ss += (d - c.mean_change) * (d - c.mean_change);
        const double se = std::sqrt(ss / (c.pairs - 1) / c.pairs);
        const double t = student_t_quantile(0.975, c.pairs - 1);
        c.change_low = c.mean_change - t * se;
        c.change_high = c.mean_change + t * se;
      }
      c.wilcoxon_p = wilcoxon_signed_rank_p(change);
    }
    out.push_back(std::move(c));
  }
  return out;
}

nlohmann::json path_quality_json(const std::vector<PathQualityChange>& changes) {
  nlohmann::json j = nlohmann::json::object();
  for (const PathQualityChange& c : changes) {
    j[c.field] = {{"pairs", c.pairs},
                  {"lower_is_better", c.lower_is_better},
                  {"base_median", number_or_null(c.base_median)},
                  {"new_median", number_or_null(c.new_median)},
                  {"base_mean", number_or_null(c.base_mean)},
                  {"mean_change", number_or_null(c.mean_change)},
                  {"change_ci95", {number_or_null(c.change_low), number_or_null(c.change_high)}},
                  {"percent_change", number_or_null(c.percent())},
                  {"wilcoxon_p", number_or_null(c.wilcoxon_p)},
                  {"significant", c.significant()}};
  }
  return j;
}

std::string path_change_text(const PathQualityChange& c) {
  if (c.pairs == 0) return "-";
  const char* f = format_for(std::isfinite(c.base_median) ? c.base_median : c.mean_change);
  std::string s = format_number(f, c.mean_change);
  if (std::isfinite(c.change_low)) {
    s += " (" + format_number(f, c.change_low) + ".." + format_number(f, c.change_high) + ")";
  }
  if (!c.unit.empty()) s += " " + c.unit;
  if (std::isfinite(c.percent())) s += ", " + format_number("%+.0f%%", c.percent());
  return s;
}

std::vector<std::string> path_quality_findings(const std::vector<PathQualityChange>& changes) {
  std::vector<std::string> out;
  for (const PathQualityChange& c : changes) {
    if (!c.significant()) continue;
    const char* f = format_for(c.base_median);
    std::string amount = std::isfinite(c.percent())
                             ? format_number("%.0f%%", std::fabs(c.percent()))
                             : with_unit(f, std::fabs(c.mean_change), c.unit);
    out.push_back(c.name + " " + amount + " " + (c.better() ? c.better_word : c.worse_word) +
                  " (mean change " + path_change_text(c) + ", " + std::to_string(c.pairs) +
                  " pairs)");
  }
  return out;
}

}  // namespace taskmatrix::harness
