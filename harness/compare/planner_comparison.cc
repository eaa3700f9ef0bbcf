#include "harness/compare/planner_comparison.h"

#include <cmath>
#include <cstdio>

#include "harness/compare/html_report.h"
#include "harness/results/summary.h"
#include "harness/results/trial_schema.h"
#include "harness/scenario/planner_plugins.h"
#include "taskmatrix/core/motion_planning.h"

namespace taskmatrix::harness {

namespace {

std::vector<nlohmann::json> of_planner(const std::vector<nlohmann::json>& trials,
                                       const std::string& planner) {
  std::vector<nlohmann::json> out;
  for (const nlohmann::json& t : trials) {
    if (t.value("planner", std::string()) == planner) out.push_back(t);
  }
  return out;
}

// Whether the registered planner optimizes its path until its budget is spent (false for a
// name this process has not registered, e.g. a plugin it has not loaded).
bool optimizes_paths(const std::string& name) {
  register_builtin_planners();
  const core::PlannerType* type = core::planner_registry().find(name);
  return type != nullptr && type->optimizes_paths;
}

}  // namespace

PlannerBudgets planner_budgets(const RunPlan& plan) {
  PlannerBudgets b;
  for (const Scenario& s : plan.scenarios) {
    b.plan_time_limit_s[s.name] = s.plan_time_limit_s;
    for (const PlannerConfig& pc : s.planners) {
      if (optimizes_paths(pc.spec.name)) b.anytime_planners.insert(pc.spec.name);
    }
  }
  return b;
}

PlannerBudgets planner_budgets(const nlohmann::json& provenance) {
  PlannerBudgets b;
  if (!provenance.is_object() || !provenance.contains("scenarios") ||
      !provenance["scenarios"].is_array()) {
    return b;
  }
  for (const nlohmann::json& s : provenance["scenarios"]) {
    if (!s.is_object()) continue;
    if (s.contains("plan_time_limit_s") && s["plan_time_limit_s"].is_number() &&
        s.contains("name") && s["name"].is_string()) {
      b.plan_time_limit_s[s["name"].get<std::string>()] = s["plan_time_limit_s"].get<double>();
    }
    if (!s.contains("planners") || !s["planners"].is_array()) continue;
    for (const nlohmann::json& p : s["planners"]) {
      if (!p.is_object() || !p.contains("name") || !p["name"].is_string()) continue;
      const std::string name = p["name"].get<std::string>();
      if (optimizes_paths(name)) b.anytime_planners.insert(name);
    }
  }
  return b;
}

std::vector<Comparison> compare_planners(const std::vector<nlohmann::json>& trials,
                                         const std::vector<std::string>& planners,
                                         const PlannerBudgets& budgets) {
  std::vector<Comparison> out;
  if (planners.size() < 2) return out;
  const std::vector<nlohmann::json> reference = of_planner(trials, planners[0]);
  if (reference.empty()) return out;
  for (size_t i = 1; i < planners.size(); ++i) {
    const std::vector<nlohmann::json> other = of_planner(trials, planners[i]);
    if (other.empty()) continue;
    Comparison c =
        compare_trials(reference, other, /*with_planner=*/false, CompareThresholds{}, budgets);
    // Another scenario's planner: nothing in common. Pairs that a clock bound decided are
    // kept, to say why nothing was judged.
    if (c.overall.pairs == 0 && c.nonreproducible.empty()) continue;
    c.base_label = planners[0];
    c.new_label = planners[i];
    out.push_back(std::move(c));
  }
  return out;
}

std::vector<std::string> planner_measure_headings(std::span<const TrialField> fields) {
  std::vector<std::string> out;
  for (const TrialField& f : fields) {
    if (!f.display.planner_table) continue;
    out.push_back(std::string(f.display.label) +
                  (f.display.unit.empty() ? "" : " " + std::string(f.display.unit)) + " (median)");
  }
  return out;
}

std::vector<std::string> planner_measure_cells(const std::vector<nlohmann::json>& trials,
                                               const std::string& planner,
                                               std::span<const TrialField> fields) {
  std::vector<std::string> out;
  for (const TrialField& f : fields) {
    if (!f.display.planner_table) continue;
    const std::string name(f.name), format(f.display.format);
    std::vector<double> values;
    for (const nlohmann::json& t : trials) {
      if (t.value("planner", std::string()) != planner) continue;
      const auto it = t.find(name);
      if (it != t.end() && it->is_number()) values.push_back(it->get<double>());
    }
    out.push_back(format_number(format.c_str(), quantile(values, 0.5)));
  }
  return out;
}

std::string planner_table_markdown(const std::vector<nlohmann::json>& trials,
                                   const std::vector<std::string>& planners,
                                   const std::vector<Comparison>& vs_reference,
                                   std::span<const TrialField> fields) {
  if (vs_reference.empty()) return "";
  std::string md = "\n## Planners, each against " + markdown_cell(planners[0]) +
                   " on the same trials\n\n| planner | success | 95% CI | planning s (median) |";
  std::string rule = "|---|---|---|---|";
  for (const std::string& heading : planner_measure_headings(fields)) {
    md += " " + markdown_cell(heading) + " |";
    rule += "---|";
  }
  md +=
      " McNemar p | planning time ratio (95% CI) | Wilcoxon p | collision checks ratio | "
      "verdict | path quality (pairs where both succeeded) |\n" +
      rule + "---|---|---|---|---|---|\n";
  for (const std::string& planner : planners) {
    const std::vector<nlohmann::json> mine = of_planner(trials, planner);
    if (mine.empty()) continue;
    int s = 0;
    std::vector<double> times;
    for (const nlohmann::json& t : mine) {
      s += t.value("success", false);
      const auto it = t.find(kPlanningTimeField);
      if (it != t.end() && it->is_number()) times.push_back(it->get<double>());
    }
    const int n = static_cast<int>(mine.size());
    const Interval ci = wilson_interval(s, n);
    md += "| " + markdown_cell(planner) + " | " + std::to_string(s) + "/" + std::to_string(n) +
          " | " + format_number("%.0f%%", 100 * ci.low) + ".." +
          format_number("%.0f%%", 100 * ci.high) + " | " +
          format_number("%.4f", quantile(times, 0.5)) + " | ";
    for (const std::string& cell : planner_measure_cells(mine, planner, fields)) {
      md += cell + " | ";
    }
    const Comparison* c = nullptr;
    for (const Comparison& v : vs_reference) {
      if (v.new_label == planner) c = &v;
    }
    if (c == nullptr) {
      md += "- | reference | - | - | reference | - |\n";
      continue;
    }
    const PairedGroup& o = c->overall;
    if (o.pairs == 0) {
      md += "- | - | - | - | not judged: a clock bound decided all " +
            std::to_string(c->nonreproducible.size()) +
            " pairs (not reproducible; planners.md lists them) | - |\n";
      continue;
    }
    double checks = NAN;
    for (const WorkCountChange& w : o.work) {
      if (w.field == kCollisionChecksField && w.base_total > 0) checks = w.new_total / w.base_total;
    }
    std::string verdict;
    for (const std::string& r : o.regressions) verdict += (verdict.empty() ? "worse: " : "; ") + r;
    for (const std::string& r : o.by_design) {
      verdict += (verdict.empty() ? std::string(kByDesign) + ": " : "; ") + r;
    }
    for (const std::string& r : o.improvements) {
      verdict += (verdict.empty() ? "better: " : "; better: ") + r;
    }
    std::string quality;
    for (const std::string& f : o.path_findings) quality += (quality.empty() ? "" : "; ") + f;
    md += p_value_text(o.mcnemar_p) + " | " +
          (o.time_pairs > 0 ? "x" + format_number("%.2f", o.time_ratio) + " (" +
                                  format_number("%.2f", o.time_ratio_low) + ".." +
                                  format_number("%.2f", o.time_ratio_high) + ")"
                            : "-") +
          " | " + p_value_text(o.wilcoxon_p) + " | " + format_number("x%.2f", checks) + " | " +
          (verdict.empty() ? no_change_text(o, c->thresholds) : verdict) + " | " +
          (quality.empty() ? "no significant difference" : quality) + " |\n";
  }
  md += "\nPer group: planners.md; plots: planners.html.\n";
  return md;
}

void write_planner_comparison(const std::filesystem::path& dir, const std::string& run_name,
                              const std::vector<nlohmann::json>& trials,
                              const std::vector<std::string>& planners,
                              const std::vector<Comparison>& vs_reference) {
  std::string md = "# Planners of run " + markdown_cell(run_name) + "\n" +
                   planner_table_markdown(trials, planners, vs_reference);
  for (const Comparison& c : vs_reference) {
    std::string section = comparison_markdown(c);
    section.replace(0, section.find('\n'),
                    "## " + markdown_cell(c.new_label) + " against " + markdown_cell(c.base_label));
    // Demote the comparison's own headings by one level.
    for (size_t at = section.find("\n## "); at != std::string::npos;
         at = section.find("\n## ", at + 5)) {
      section.insert(at + 1, "#");
    }
    md += "\n" + section;
  }
  write_files_atomically(
      {{dir / "planners.md", md},
       {dir / "planners.html", planners_html(run_name, trials, planners, vs_reference)}});
}

}  // namespace taskmatrix::harness
