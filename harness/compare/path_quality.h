// Paired path quality for comparisons (harness/compare/compare.h): for each measure of the executed
// motion (the trial fields harness/results/trial_schema.h marks as path-quality measures: joint
// path, end-effector path, duration, smoothness, minimum clearance), over the
// pairs in which both trials succeeded and both measured it (a failed trial stops early, so
// its path is not comparable), the mean paired change new - base with its 95% Student t
// interval (mean +- t(0.975, n - 1) sd / sqrt(n)), the medians, and Wilcoxon's signed-rank
// test on the changes. A change is significant when its interval excludes 0.
#pragma once

#include <cmath>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness/results/trial_schema.h"

namespace taskmatrix::harness {

struct TrialPair {
  const nlohmann::json* base;
  const nlohmann::json* fresh;
};

struct PathQualityChange {
  std::string field;  // the trial field: path_length_joint, path_length_ee_m, duration_s, ...
  std::string name;   // "joint path", "end-effector path", ...
  std::string unit;   // "", "m", "s", "rad/s^3"
  bool lower_is_better = true;
  std::string better_word, worse_word;  // "shorter", "longer"
  int pairs = 0;
  double base_median = NAN, new_median = NAN, base_mean = NAN;
  double mean_change = NAN, change_low = NAN, change_high = NAN;  // new - base, 95% t interval
  double wilcoxon_p = NAN;

  bool significant() const { return change_low > 0 || change_high < 0; }
  bool better() const { return significant() && ((mean_change < 0) == lower_is_better); }
  // mean_change relative to the base mean, in percent; NaN unless the base mean is positive (a
  // minimum clearance can be negative, a penetration, or near 0: no scale to take a share of).
  double percent() const { return base_mean > 0 ? 100 * mean_change / base_mean : NAN; }
};

// The measures compared: the rows of `fields` with a FieldDisplay::path_quality, in table
// order (name, unit, direction and words from their display).
std::vector<PathQualityChange> compare_path_quality(
    const std::vector<TrialPair>& pairs, std::span<const TrialField> fields = kTrialFields);

// Student's t quantile (boost); for the interval and its tests.
double student_t_quantile(double p, double df);

nlohmann::json path_quality_json(const std::vector<PathQualityChange>& changes);
// "-0.62 (-0.91..-0.33), -15%" with the unit, or "-" without pairs.
std::string path_change_text(const PathQualityChange& c);
// Significant changes as phrases for a verdict: "joint path 15% shorter (95% CI ...)".
std::vector<std::string> path_quality_findings(const std::vector<PathQualityChange>& changes);

}  // namespace taskmatrix::harness
