#include "harness/compare/compare.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <stdexcept>
#include <tuple>

#include "harness/compare/compare_sections.h"
#include "harness/compare/paired_stats.h"
#include "harness/report/report_table.h"
#include "harness/results/json_input.h"
#include "harness/results/trial_record.h"
#include "harness/results/trial_schema.h"

namespace taskmatrix::harness {

namespace {

std::string text(const nlohmann::json& t, const char* key) {
  const auto it = t.find(key);
  if (it == t.end() || it->is_null()) return "";
  return it->is_string() ? it->get<std::string>() : json_text(*it);
}

// A finite number, or NaN for null, missing or not a number.
double number(const nlohmann::json& t, const char* key) {
  const auto it = t.find(key);
  return it != t.end() && it->is_number() ? it->get<double>() : NAN;
}

std::string printf_string(const char* format, double a, double b = 0, double c = 0, double d = 0) {
  char buf[160];
  std::snprintf(buf, sizeof buf, format, a, b, c, d);
  return buf;
}

struct Pair {
  const nlohmann::json* base;
  const nlohmann::json* fresh;
};

// The digests of a trial's planned paths, in order; "" when its record has none.
std::string path_digests(const nlohmann::json& t) {
  const auto plans = t.find("plans");
  if (plans == t.end() || !plans->is_array()) return "";
  std::string all;
  for (const nlohmann::json& p : *plans) {
    const auto d = p.find("path_digest");
    if (d == p.end() || !d->is_string()) return "";
    all += d->get<std::string>() + ";";
  }
  return all.empty() ? "-" : all;
}

void measure(PairedGroup& g, const std::vector<Pair>& pairs) {
  g.pairs = static_cast<int>(pairs.size());
  std::vector<double> log_ratios;
  std::map<std::string, WorkCountChange> work;
  const std::vector<std::string> work_fields = exact_work_fields();
  for (const std::string& f : work_fields) work[f].field = f;
  for (const Pair& p : pairs) {
    const bool b = p.base->value("success", false), n = p.fresh->value("success", false);
    g.base_successes += b;
    g.new_successes += n;
    g.only_base_success += b && !n;
    g.only_new_success += n && !b;
    const double tb = number(*p.base, kPlanningTimeField), tn = number(*p.fresh, kPlanningTimeField);
    if (tb > 0 && tn > 0) {
      log_ratios.push_back(std::log(tn / tb));
      g.base_planning_s.push_back(tb);
      g.new_planning_s.push_back(tn);
      g.time_pair_ids.push_back(text(*p.fresh, "trial_id"));
    }
    const std::string db = path_digests(*p.base), dn = path_digests(*p.fresh);
    if (!db.empty() && !dn.empty()) {
      ++g.path_pairs;
      g.changed_paths += db != dn;
    }
    for (const std::string& f : work_fields) {
      const double wb = number(*p.base, f.c_str()), wn = number(*p.fresh, f.c_str());
      WorkCountChange& w = work[f];
      if (!std::isfinite(wb) || !std::isfinite(wn)) {
        ++w.missing;
        w.missing_in_successful_new += !std::isfinite(wn) && n;
        continue;
      }
      w.base_total += wb;
      w.new_total += wn;
      w.changed_trials += wb != wn;
    }
  }
  g.base_ci = wilson_interval(g.base_successes, g.pairs);
  g.new_ci = wilson_interval(g.new_successes, g.pairs);
  g.mcnemar_p = mcnemar_exact_p(g.only_base_success, g.only_new_success);
  g.time_pairs = static_cast<int>(log_ratios.size());
  if (!log_ratios.empty()) {
    const MeanInterval m = bootstrap_mean_interval(log_ratios);
    g.time_ratio = std::exp(m.mean);
    g.time_ratio_low = std::exp(m.low);
    g.time_ratio_high = std::exp(m.high);
    g.wilcoxon_p = wilcoxon_signed_rank_p(log_ratios);
  }
  for (const std::string& f : work_fields) g.work.push_back(work[f]);
}

// Whether more time and checks of the new run are its planner's design (an anytime planner
// spending its budget), and for an anytime planner that is not, why not.
struct BudgetJudgement {
  bool by_design = false;
  std::string why_not;  // "" when by design or not an anytime planner
};

void judge(PairedGroup& g, const CompareThresholds& t, const BudgetJudgement& budget = {}) {
  if (g.pairs == 0) return;
  // More time and checks from a planner that spends its budget by design are no regression;
  // an anytime planner's that are not say why not.
  struct Costlier {
    std::vector<std::string>& list;
    const std::string& why_not;
    void push_back(const std::string& what) {
      list.push_back(why_not.empty() ? what : what + " (not by design: " + why_not + ")");
    }
  } costlier{budget.by_design ? g.by_design : g.regressions, budget.why_not};
  const double base_rate = static_cast<double>(g.base_successes) / g.pairs;
  const double new_rate = static_cast<double>(g.new_successes) / g.pairs;
  const std::string success =
      printf_string("success %.0f%% -> %.0f%% (%.0f pairs: %.0f now fail", 100 * base_rate,
                    100 * new_rate, g.pairs, g.only_base_success) +
      printf_string(", %.0f now succeed; McNemar p ", g.only_new_success) +
      p_value_phrase(g.mcnemar_p) + ")";
  constexpr double kEps = 1e-12;
  if (g.mcnemar_p < t.alpha && base_rate - new_rate >= t.max_success_drop - kEps) {
    g.regressions.push_back(success);
  } else if (g.mcnemar_p < t.alpha && new_rate - base_rate >= t.max_success_drop - kEps) {
    g.improvements.push_back(success);
  }
  if (g.time_pairs >= t.min_time_pairs && g.wilcoxon_p < t.alpha) {
    const std::string time =
        printf_string("planning time x%.2f (95%% CI %.2f..%.2f, %.0f pairs; Wilcoxon p ",
                      g.time_ratio, g.time_ratio_low, g.time_ratio_high, g.time_pairs) +
        p_value_phrase(g.wilcoxon_p) + ")";
    if (g.time_ratio_low > t.max_time_ratio) costlier.push_back(time);
    if (g.time_ratio_high < 1.0 / t.max_time_ratio) g.improvements.push_back(time);
  }
  if (t.exact_work) {
    for (const WorkCountChange& w : g.work) {
      if (w.changed_trials > 0) {
        g.regressions.push_back(
            trials_changed(w.changed_trials) + " " + w.field +
            printf_string(" (%.0f -> %.0f; exact counts required)", w.base_total, w.new_total));
      }
    }
    if (g.changed_paths > 0) {
      g.regressions.push_back(printf_string("%.0f trials planned other paths", g.changed_paths) +
                              " (exact paths required)");
    }
  }
  for (const WorkCountChange& w : g.work) {
    if (w.missing_in_successful_new > 0) {
      g.regressions.push_back(
          printf_string("%.0f successful new trials lack ", w.missing_in_successful_new) + w.field);
    }
    if (w.field != kCollisionChecksField) continue;
    if (w.base_total <= 0) {
      if (w.new_total > 0) {
        costlier.push_back(printf_string("collision checks 0 -> %.0f (", w.new_total) +
                           trials_changed(w.changed_trials) + ")");
      }
      continue;
    }
    const double ratio = w.new_total / w.base_total;
    const std::string work =
        printf_string("collision checks x%.2f (%.0f -> %.0f; ", ratio, w.base_total, w.new_total) +
        trials_changed(w.changed_trials) + ")";
    if (ratio > t.max_work_ratio) costlier.push_back(work);
    if (ratio < 1.0 / t.max_work_ratio) g.improvements.push_back(work);
  }
}

// Whether the new trials' planner optimizes until its time limit (every new trial's), kept
// every plan call within that limit (where the scenario's limit is known), and the programs
// asked for no more plans than in the base: then more time and more checks are its design.
BudgetJudgement within_budget_by_design(const std::vector<Pair>& pairs,
                                        const PlannerBudgets& budgets) {
  if (pairs.empty() || budgets.anytime_planners.empty()) return {};
  double base_calls = 0, new_calls = 0;
  for (const Pair& p : pairs) {
    if (!budgets.anytime_planners.count(text(*p.fresh, "planner_name"))) return {};
  }
  for (const Pair& p : pairs) {
    const auto limit = budgets.plan_time_limit_s.find(text(*p.fresh, "scenario"));
    const auto plans = p.fresh->find("plans");
    if (limit != budgets.plan_time_limit_s.end() && plans != p.fresh->end() && plans->is_array()) {
      for (const nlohmann::json& call : *plans) {
        // A call may run the planner several times (one per candidate goal pose), each with
        // the limit. OMPL checks its clock between iterations: allow an iteration's overshoot.
        const double runs = number(call, "planner_runs");
        const double budget = limit->second * (std::isfinite(runs) && runs > 1 ? runs : 1);
        const double took = number(call, kPlanningTimeField);
        if (took > budget * 1.1 + 0.02) {
          return {false, "a plan call of " + text(*p.fresh, "trial_id") +
                             printf_string(" planned %.2f s, over its %.2f s limit", took, budget)};
        }
      }
    }
    const double cb = number(*p.base, "plan_calls"), cn = number(*p.fresh, "plan_calls");
    if (std::isfinite(cb) && std::isfinite(cn)) {
      base_calls += cb;
      new_calls += cn;
    }
  }
  if (new_calls <= base_calls) return {true, ""};
  return {false, printf_string("%.0f plan calls against the base's %.0f", new_calls, base_calls)};
}

std::string failure_text(const nlohmann::json& t) {
  const std::string where = failure_location(t), reason = text(t, "failure_reason");
  const std::string why = reason.empty() ? text(t, "status") : reason;
  return where.empty() || why.find(where) != std::string::npos ? why : where + ": " + why;
}

// What the group's numbers do not judge: path quality, power, and where trials failed.
void describe(PairedGroup& g, const std::vector<Pair>& pairs, const CompareThresholds& t) {
  std::vector<TrialPair> trial_pairs;
  for (const Pair& p : pairs) {
    trial_pairs.push_back({p.base, p.fresh});
    if (!p.base->value("success", false)) ++g.base_failures[failure_text(*p.base)];
    if (!p.fresh->value("success", false)) ++g.new_failures[failure_text(*p.fresh)];
  }
  g.path_quality = compare_path_quality(trial_pairs);
  g.path_findings = path_quality_findings(g.path_quality);
  std::vector<double> log_ratios;
  for (size_t i = 0; i < g.base_planning_s.size(); ++i) {
    log_ratios.push_back(std::log(g.new_planning_s[i] / g.base_planning_s[i]));
  }
  g.power = group_power(g.pairs, g.base_successes, log_ratios, t.min_time_pairs, t.alpha,
                        t.power_success_target,
                        t.power_time_target > 0 ? t.power_time_target : t.max_time_ratio);
}

}  // namespace

std::string failure_location(const nlohmann::json& trial) {
  // A reason that names its path: "tidy > greet > postural(rest): invalid_goal: ...".
  const std::string reason = text(trial, "failure_reason");
  for (size_t start = 0; start < reason.size();) {
    const size_t end = std::min(reason.find(": ", start), reason.size());
    const std::string segment = reason.substr(start, end - start);
    if (segment.find(" > ") != std::string::npos) return segment;
    start = end + 2;
  }
  // Else the programs that failed with the first failure's reason, outermost first.
  const auto events = trial.find("events");
  if (events == trial.end() || !events->is_array()) return "";
  std::vector<std::string> chain;
  std::string first_reason;
  for (const nlohmann::json& e : *events) {
    if (!e.is_object() || text(e, "type") != "failed") continue;
    const std::string why = text(e, "reason");
    if (chain.empty()) {
      first_reason = why;
    } else if (why.find(first_reason) == std::string::npos) {
      continue;
    }
    chain.push_back(text(e, "program"));
  }
  std::string path;
  for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
    path += (path.empty() ? "" : " > ") + *it;
  }
  return path;
}

std::string no_change_text(const PairedGroup& g, const CompareThresholds& t) {
  const GroupPower& p = g.power;
  if (!std::isfinite(p.success_change)) {
    return printf_string(
        "no significant change (underpowered: no success change is detectable with %.0f pairs)",
        g.pairs);
  }
  if (p.success_change > t.max_success_drop + 1e-9) {
    return "no significant change (underpowered: only a success " +
           std::string(p.success_rise ? "rise" : "drop") + " of " + success_change_text(p) +
           " or more was detectable)";
  }
  return "no significant change";
}

std::string p_value_text(double p) {
  if (!std::isfinite(p)) return "-";
  return p < 0.001 ? std::string("<0.001") : format_number("%.3f", p);
}

std::string trials_changed(double n) {
  return printf_string(n == 1 ? "%.0f trial changed" : "%.0f trials changed", n);
}

std::string p_value_phrase(double p) {
  if (!std::isfinite(p)) return "= -";
  return p < 0.001 ? std::string("< 0.001") : "= " + format_number("%.3f", p);
}

bool Comparison::regression() const {
  if (!overall.regressions.empty()) return true;
  return std::any_of(groups.begin(), groups.end(),
                     [](const PairedGroup& g) { return !g.regressions.empty(); });
}

std::string pairing_key(const nlohmann::json& trial, bool with_planner) {
  std::string key = text(trial, "scenario") + "\x1f" + text(trial, "robot") + "\x1f" +
                    text(trial, "environment") + "\x1f" + text(trial, "layout_seed") + "\x1f" +
                    text(trial, "seed");
  if (with_planner) key += "\x1f" + text(trial, "planner");
  return key;
}

Comparison compare_trials(const std::vector<nlohmann::json>& base,
                          const std::vector<nlohmann::json>& fresh, bool with_planner,
                          const CompareThresholds& thresholds, const PlannerBudgets& budgets) {
  Comparison c;
  c.thresholds = thresholds;
  auto index = [&](const std::vector<nlohmann::json>& trials, const char* side) {
    std::map<std::string, const nlohmann::json*> by_key;
    for (const nlohmann::json& t : trials) {
      if (!by_key.emplace(pairing_key(t, with_planner), &t).second) {
        throw std::invalid_argument(std::string(side) + " has two trials with the identity of '" +
                                    text(t, "trial_id") + "'" +
                                    (with_planner ? "" : " once planners are ignored"));
      }
    }
    return by_key;
  };
  const auto base_by_key = index(base, "the base");
  const auto new_by_key = index(fresh, "the new run");

  using GroupKey =
      std::tuple<std::string, std::string, std::string, std::string, std::string, std::string>;
  std::map<GroupKey, std::vector<Pair>> groups;
  std::vector<Pair> all;
  for (const auto& [key, b] : base_by_key) {
    const auto it = new_by_key.find(key);
    if (it == new_by_key.end()) {
      c.only_in_base.push_back(text(*b, "trial_id"));
      continue;
    }
    const nlohmann::json* n = it->second;
    std::string clock;
    for (const auto& [side, trial] : {std::pair{"base", b}, std::pair{"new", n}}) {
      for (const std::string& what : clock_bounds_hit(*trial)) {
        clock += (clock.empty() ? "" : ", ") + std::string(side) + " " + what;
      }
    }
    if (!clock.empty()) {
      const std::string bid = text(*b, "trial_id"), nid = text(*n, "trial_id");
      c.nonreproducible.push_back((bid == nid ? bid : bid + " / " + nid) + ": " + clock);
      if (!thresholds.include_nonreproducible) continue;
    }
    const Pair pair{b, n};
    all.push_back(pair);
    groups[{text(*b, "scenario"), text(*b, "program"), text(*b, "robot"), text(*b, "environment"),
            text(*b, "planner"), text(*n, "planner")}]
        .push_back(pair);
    const bool bs = b->value("success", false), ns = n->value("success", false);
    if (bs != ns) {
      const nlohmann::json& failed = ns ? *b : *n;
      c.flips.push_back({text(*b, "trial_id"), text(*n, "trial_id"), text(*b, "status"),
                         text(*n, "status"), ns, failure_location(failed),
                         text(failed, "failure_reason")});
    }
  }
  for (const auto& [key, n] : new_by_key) {
    if (!base_by_key.count(key)) c.only_in_new.push_back(text(*n, "trial_id"));
  }
  std::sort(c.only_in_base.begin(), c.only_in_base.end());
  std::sort(c.only_in_new.begin(), c.only_in_new.end());
  std::sort(
      c.flips.begin(), c.flips.end(),
      [](const Comparison::Flip& a, const Comparison::Flip& b) { return a.base_id < b.base_id; });
  for (const auto& [key, pairs] : groups) {
    PairedGroup g;
    std::tie(g.scenario, g.program, g.robot, g.environment, g.base_planner, g.new_planner) = key;
    measure(g, pairs);
    judge(g, thresholds, within_budget_by_design(pairs, budgets));
    describe(g, pairs, thresholds);
    c.groups.push_back(std::move(g));
  }
  c.overall.scenario = "all";
  measure(c.overall, all);
  judge(c.overall, thresholds, within_budget_by_design(all, budgets));
  describe(c.overall, all, thresholds);
  if (thresholds.fail_on_unpaired && !c.only_in_new.empty()) {
    c.overall.regressions.push_back(
        printf_string("%.0f trials of the new run have no partner in the base",
                      static_cast<double>(c.only_in_new.size())));
  }
  if (thresholds.fail_on_unpaired && !thresholds.new_is_subset && !c.only_in_base.empty()) {
    c.overall.regressions.push_back(printf_string("%.0f trials of the base are missing",
                                                  static_cast<double>(c.only_in_base.size())));
  }
  if (thresholds.fail_on_nonreproducible && !c.nonreproducible.empty()) {
    c.overall.regressions.push_back(
        printf_string("%.0f pairs are not reproducible: a clock bound decided a trial",
                      static_cast<double>(c.nonreproducible.size())));
  }
  if (thresholds.max_new_failures >= 0 &&
      c.overall.only_base_success > thresholds.max_new_failures) {
    c.overall.regressions.push_back(printf_string("%.0f trials now fail (at most %.0f allowed)",
                                                  c.overall.only_base_success,
                                                  thresholds.max_new_failures));
  }
  return c;
}

namespace {

nlohmann::json group_json(const PairedGroup& g) {
  nlohmann::json j;
  j["scenario"] = g.scenario;
  j["program"] = g.program;
  j["robot"] = g.robot;
  j["environment"] = g.environment;
  j["base_planner"] = g.base_planner;
  j["new_planner"] = g.new_planner;
  j["pairs"] = g.pairs;
  j["success"] = {{"base", g.base_successes},
                  {"new", g.new_successes},
                  {"base_ci95", {g.base_ci.low, g.base_ci.high}},
                  {"new_ci95", {g.new_ci.low, g.new_ci.high}},
                  {"only_base", g.only_base_success},
                  {"only_new", g.only_new_success},
                  {"mcnemar_p", g.mcnemar_p}};
  j["planning_time"] = {
      {"pairs", g.time_pairs},
      {"ratio", number_or_null(g.time_ratio)},
      {"ratio_ci95", {number_or_null(g.time_ratio_low), number_or_null(g.time_ratio_high)}},
      {"wilcoxon_p", number_or_null(g.wilcoxon_p)}};
  nlohmann::json work = nlohmann::json::object();
  for (const WorkCountChange& w : g.work) {
    work[w.field] = {{"base", w.base_total},
                     {"new", w.new_total},
                     {"changed_trials", w.changed_trials},
                     {"missing", w.missing}};
  }
  j["work"] = work;
  j["paths"] = {{"pairs", g.path_pairs}, {"changed_trials", g.changed_paths}};
  j["regressions"] = g.regressions;
  j["improvements"] = g.improvements;
  j["within_budget_by_design"] = g.by_design;
  j["path_quality"] = path_quality_json(g.path_quality);
  j["path_findings"] = g.path_findings;
  j["power"] = group_power_json(g.power);
  j["failures"] = {{"base", g.base_failures}, {"new", g.new_failures}};
  return j;
}

std::string verdict(const PairedGroup& g, const CompareThresholds& t) {
  std::string v;
  for (const std::string& r : g.regressions) v += (v.empty() ? "**regression**: " : "; ") + r;
  std::string design;
  for (const std::string& r : g.by_design) {
    design += (design.empty() ? std::string(kByDesign) + ": " : "; ") + r;
  }
  if (!design.empty()) v += (v.empty() ? "" : "; ") + design;
  std::string better;
  for (const std::string& r : g.improvements) better += (better.empty() ? "better: " : "; ") + r;
  if (!better.empty()) v += (v.empty() ? "" : "; ") + better;
  return v.empty() ? no_change_text(g, t) : v;
}

std::string success_cell(const PairedGroup& g) {
  return printf_string("%.0f/%.0f -> %.0f/%.0f", g.base_successes, g.pairs, g.new_successes,
                       g.pairs);
}

std::string time_cell(const PairedGroup& g) {
  if (g.time_pairs == 0) return "-";
  return printf_string("x%.2f (%.2f..%.2f)", g.time_ratio, g.time_ratio_low, g.time_ratio_high);
}

std::string work_cell(const PairedGroup& g, const std::string& field) {
  for (const WorkCountChange& w : g.work) {
    if (w.field != field) continue;
    std::string cell = printf_string("%.0f -> %.0f", w.base_total, w.new_total);
    if (w.changed_trials > 0) cell += printf_string(" (%.0f changed)", w.changed_trials);
    return cell;
  }
  return "-";
}

}  // namespace

nlohmann::json comparison_json(const Comparison& c) {
  nlohmann::json j;
  j["base"] = c.base_label;
  j["new"] = c.new_label;
  j["thresholds"] = {{"alpha", c.thresholds.alpha},
                     {"max_success_drop", c.thresholds.max_success_drop},
                     {"max_time_ratio", c.thresholds.max_time_ratio},
                     {"max_work_ratio", c.thresholds.max_work_ratio},
                     {"min_time_pairs", c.thresholds.min_time_pairs},
                     {"max_new_failures", c.thresholds.max_new_failures},
                     {"fail_on_unpaired", c.thresholds.fail_on_unpaired},
                     {"new_is_subset", c.thresholds.new_is_subset},
                     {"include_nonreproducible", c.thresholds.include_nonreproducible},
                     {"fail_on_nonreproducible", c.thresholds.fail_on_nonreproducible},
                     {"exact_work", c.thresholds.exact_work}};
  j["regression"] = c.regression();
  j["overall"] = group_json(c.overall);
  j["groups"] = nlohmann::json::array();
  for (const PairedGroup& g : c.groups) j["groups"].push_back(group_json(g));
  j["only_in_base"] = c.only_in_base;
  j["only_in_new"] = c.only_in_new;
  j["nonreproducible"] = c.nonreproducible;
  j["flips"] = nlohmann::json::array();
  for (const Comparison::Flip& f : c.flips) {
    j["flips"].push_back({{"base_id", f.base_id},
                          {"new_id", f.new_id},
                          {"base_status", f.base_status},
                          {"new_status", f.new_status},
                          {"now_succeeds", f.now_succeeds},
                          {"where", f.where},
                          {"reason", f.reason}});
  }
  return j;
}

std::string comparison_markdown(const Comparison& c) {
  const PairedGroup& o = c.overall;
  const CompareThresholds& t = c.thresholds;
  std::string md =
      "# Compare " + markdown_cell(c.base_label) + " -> " + markdown_cell(c.new_label) + "\n\n";
  md += printf_string("%.0f trials paired", o.pairs);
  if (!c.only_in_base.empty() || !c.only_in_new.empty()) {
    md += printf_string(" (%.0f only in the base, %.0f only in the new run, left out)",
                        static_cast<double>(c.only_in_base.size()),
                        static_cast<double>(c.only_in_new.size()));
  }
  md += ".\n\n";
  if (!c.nonreproducible.empty()) {
    md += printf_string("%.0f pairs are not reproducible (a clock bound decided a trial) and ",
                        static_cast<double>(c.nonreproducible.size())) +
          (c.thresholds.include_nonreproducible ? "are judged anyway" : "are left out") +
          "; see \"Pairs a clock bound decided\".\n\n";
  }
  md += c.regression()         ? "**Verdict: regression.**\n\n"
        : c.overall.pairs == 0 ? "**Verdict: not judged: no pair left to judge.**\n\n"
                               : "**Verdict: no regression.**\n\n";
  md += printf_string(
      "Thresholds: a success drop of at least %.0f points with McNemar p < %.2f; a planning "
      "time ratio whose 95%% interval lies above x%.2f with Wilcoxon p < %.2f",
      100 * t.max_success_drop, t.alpha, t.max_time_ratio, t.alpha);
  md += printf_string(" (at least %.0f pairs); total collision checks above x%.2f",
                      t.min_time_pairs, t.max_work_ratio);
  if (t.max_new_failures >= 0) {
    md += printf_string("; more than %.0f trials that now fail", t.max_new_failures);
  }
  if (t.fail_on_unpaired) {
    md += t.new_is_subset ? "; a new trial without a partner" : "; a trial without a partner";
  }
  if (t.fail_on_nonreproducible) md += "; a pair that a clock bound decided";
  if (t.exact_work) md += "; any change of a work count or planned path";
  md += ".\n\n";
  md += "| | base | new | change |\n|---|---|---|---|\n";
  md += printf_string("| success | %.0f/%.0f (%.1f%%..%.1f%%) |", o.base_successes, o.pairs,
                      100 * o.base_ci.low, 100 * o.base_ci.high) +
        printf_string(" %.0f/%.0f (%.1f%%..%.1f%%) |", o.new_successes, o.pairs, 100 * o.new_ci.low,
                      100 * o.new_ci.high) +
        printf_string(" %.0f now fail, %.0f now succeed; McNemar p ", o.only_base_success,
                      o.only_new_success) +
        p_value_phrase(o.mcnemar_p) + " |\n";
  if (o.time_pairs > 0) {
    md += printf_string("| planning time (median s) | %.4f | %.4f |",
                        quantile(o.base_planning_s, 0.5), quantile(o.new_planning_s, 0.5)) +
          printf_string(" x%.3f (95%% CI %.3f..%.3f, %.0f pairs); Wilcoxon p ", o.time_ratio,
                        o.time_ratio_low, o.time_ratio_high, o.time_pairs) +
          p_value_phrase(o.wilcoxon_p) + " |\n";
  }
  for (const WorkCountChange& w : o.work) {
    md += "| " + w.field + printf_string(" | %.0f | %.0f |", w.base_total, w.new_total) +
          (w.base_total > 0 ? printf_string(" x%.3f;", w.new_total / w.base_total) : "") + " " +
          trials_changed(w.changed_trials) +
          (w.missing > 0 ? printf_string("; %.0f pairs without it", w.missing) : "") + " |\n";
  }
  md += "\nOverall: " + verdict(o, t) + "\n\n## Per group\n\n";
  // The work counts the table shows per group (FieldDisplay::compare_groups), as columns.
  md +=
      "| scenario | robot | environment | planner | success | McNemar p | planning time ratio "
      "(95% CI) | Wilcoxon p |";
  std::string rule = "|---|---|---|---|---|---|---|---|";
  for (const TrialField& f : kTrialFields) {
    if (!f.display.compare_groups) continue;
    md += " " + std::string(f.display.label) + " |";
    rule += "---|";
  }
  md += " verdict |\n" + rule + "---|\n";
  for (const PairedGroup& g : c.groups) {
    const std::string planner =
        g.base_planner == g.new_planner
            ? markdown_cell(g.base_planner)
            : markdown_cell(g.base_planner) + " -> " + markdown_cell(g.new_planner);
    md += "| " + markdown_cell(g.scenario) + " | " + markdown_cell(g.robot) + " | " +
          markdown_cell(g.environment) + " | " + planner + " | " + success_cell(g) + " | " +
          p_value_text(g.mcnemar_p) + " | " + time_cell(g) + " | " + p_value_text(g.wilcoxon_p) +
          " |";
    for (const TrialField& f : kTrialFields) {
      if (f.display.compare_groups) md += " " + work_cell(g, std::string(f.name)) + " |";
    }
    md += " " + verdict(g, t) + " |\n";
  }
  if (!c.flips.empty()) {
    md += "\n## Trials whose outcome changed\n\n" + markdown_table(flips_table(c));
  }
  if (!c.nonreproducible.empty()) {
    md += "\n## Pairs a clock bound decided\n\n";
    for (const std::string& p : c.nonreproducible) md += "- " + markdown_cell(p) + "\n";
  }
  md += comparison_sections_markdown(c);
  if (!c.only_in_base.empty() || !c.only_in_new.empty()) {
    md += "\n## Unpaired trials\n\n";
    for (const std::string& id : c.only_in_base) {
      md += "- only in the base: " + markdown_cell(id) + "\n";
    }
    for (const std::string& id : c.only_in_new) {
      md += "- only in the new run: " + markdown_cell(id) + "\n";
    }
  }
  return md;
}

}  // namespace taskmatrix::harness
