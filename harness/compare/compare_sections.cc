#include "harness/compare/compare_sections.h"

#include <algorithm>
#include <cmath>

#include "harness/results/trial_schema.h"

namespace taskmatrix::harness {

namespace {

std::string pairs_text(int n) { return std::to_string(n); }

std::string median_text(double v, const std::string& unit) {
  if (!std::isfinite(v)) return "-";
  const double a = std::fabs(v);
  const char* f = a >= 100 ? "%.0f" : a >= 1 ? "%.2f" : a >= 0.01 ? "%.3f" : "%.4f";
  return format_number(f, v) + (unit.empty() ? "" : " " + unit);
}

void add_path_rows(ReportTable& t, const std::string& name, const PairedGroup& g,
                   bool every_measure) {
  for (const PathQualityChange& q : g.path_quality) {
    if (q.pairs == 0 && !every_measure) continue;
    std::string finding = "-";
    if (q.significant()) finding = q.better() ? "better" : "worse";
    t.rows.push_back({{name, q.name, pairs_text(q.pairs), median_text(q.base_median, q.unit),
                       median_text(q.new_median, q.unit), path_change_text(q),
                       p_value_text(q.wilcoxon_p), finding},
                      q.significant() ? (q.better() ? "good" : "bad") : ""});
  }
}

void add_power_row(ReportTable& t, const std::string& name, const PairedGroup& g) {
  const GroupPower& p = g.power;
  t.rows.push_back(
      {{name, pairs_text(p.pairs), std::to_string(g.base_successes) + "/" + std::to_string(g.pairs),
        success_change_text(p), pairs_needed_text(p.pairs_for_success_target),
        pairs_text(p.time_pairs), format_number("%.3f", p.log_ratio_sd), time_ratio_text(p),
        pairs_needed_text(p.pairs_for_time_target)},
       ""});
}

}  // namespace

std::string group_name(const PairedGroup& g) {
  const std::string planner =
      g.base_planner == g.new_planner ? g.new_planner : g.base_planner + " -> " + g.new_planner;
  return g.scenario + " · " + g.robot + " · " + g.environment + " · " + planner;
}

ReportTable path_quality_table(const Comparison& c) {
  ReportTable t;
  t.columns = {"group",       "measure",    "pairs",
               "base median", "new median", "mean change new - base (95% CI), % of base mean",
               "Wilcoxon p",  "finding"};
  // One group is the pooled pairs: its rows alone.
  if (c.groups.size() != 1) add_path_rows(t, "all pairs", c.overall, true);
  for (const PairedGroup& g : c.groups) add_path_rows(t, group_name(g), g, c.groups.size() == 1);
  return t;
}

ReportTable power_table(const Comparison& c) {
  const GroupPower& o = c.overall.power;
  ReportTable t;
  t.columns = {"group",
               "pairs",
               "base success",
               "smallest detectable success drop",
               "pairs for a " + format_number("%.0f", 100 * o.success_target) + "-point drop",
               "time pairs",
               "sd of log time ratio",
               "smallest detectable time ratio",
               "pairs for x" + format_number("%.2f", o.time_target)};
  if (c.groups.size() != 1) add_power_row(t, "all pairs", c.overall);
  for (const PairedGroup& g : c.groups) add_power_row(t, group_name(g), g);
  return t;
}

ReportTable failures_table(const Comparison& c) {
  ReportTable t;
  t.columns = {"group", "run", "trials", "where it failed: why"};
  for (const PairedGroup& g : c.groups) {
    for (const auto& [run, failures] : {std::pair{std::string("base"), &g.base_failures},
                                        {std::string("new"), &g.new_failures}}) {
      for (const auto& [what, count] : *failures) {
        t.rows.push_back({{group_name(g), run, std::to_string(count), what}, ""});
      }
    }
  }
  return t;
}

ReportTable flips_table(const Comparison& c) {
  ReportTable t;
  t.columns = {"trial", "base", "new", "where it failed", "reason"};
  for (const Comparison::Flip& f : c.flips) {
    const std::string id = f.base_id == f.new_id ? f.base_id : f.base_id + " / " + f.new_id;
    t.rows.push_back({{id, f.base_status, f.new_status, f.where.empty() ? "-" : f.where,
                       f.reason.empty() ? "-" : f.reason},
                      f.now_succeeds ? "good" : "bad"});
  }
  return t;
}

std::string path_quality_method(const Comparison&) {
  // Which way is better, from the table's path-quality measures.
  std::vector<std::string> higher;
  for (const TrialField& f : kTrialFields) {
    if (f.display.path_quality == Better::kHigher) higher.emplace_back(f.display.label);
  }
  std::string direction = "Lower is better";
  for (size_t i = 0; i < higher.size(); ++i) {
    direction += (i == 0                   ? " except for the "
                  : i + 1 == higher.size() ? " and the "
                                           : ", the ") +
                 higher[i];
  }
  return "Over the pairs in which both trials succeeded (a failed trial stops early), the mean "
         "paired change new - base with its 95% Student t interval, and Wilcoxon's signed-rank "
         "test on the changes; a change is better or worse when its interval excludes 0. " +
         direction + ". Joint path: rad and m mixed; smoothness: RMS joint jerk.";
}

std::string power_method(const Comparison& c) {
  const GroupPower& o = c.overall.power;
  return "What each group could have detected at alpha = " + format_number("%.2g", o.alpha) +
         " with " + format_number("%.0f", 100 * kTargetPower) +
         "% power. Success: the exact power of McNemar's exact test, with the two runs' outcomes "
         "taken as independent at the base rate (trials that repeat, as these do, are detected "
         "sooner: a conservative figure); a rise where the base never succeeded. Planning time: "
         "the paired t test's noncentral-t power with the pairs scaled by Wilcoxon's asymptotic "
         "relative efficiency 3/pi, at the group's own spread of log ratios; none below " +
         std::to_string(std::max(c.thresholds.min_time_pairs, wilcoxon_min_pairs(o.alpha))) +
         " pairs. The last columns say how many pairs per group would detect a " +
         format_number("%.0f", 100 * o.success_target) + "-point drop and a ratio of x" +
         format_number("%.2f", o.time_target) + ".";
}

std::string comparison_sections_markdown(const Comparison& c) {
  std::string md = "\n## Path quality\n\n" + path_quality_method(c) + "\n\n" +
                   markdown_table(path_quality_table(c));
  md += "\n## Statistical power\n\n" + power_method(c) + "\n\n" + markdown_table(power_table(c));
  const ReportTable failures = failures_table(c);
  if (!failures.rows.empty()) md += "\n## Failures by group\n\n" + markdown_table(failures);
  return md;
}

}  // namespace taskmatrix::harness
