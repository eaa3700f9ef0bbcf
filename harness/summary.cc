#include "harness/summary.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <tuple>

namespace taskmatrix::harness {

Interval wilson_interval(int successes, int n, double z) {
  if (n <= 0) return {0.0, 1.0};
  const double p = static_cast<double>(successes) / n;
  const double z2 = z * z;
  const double denom = 1.0 + z2 / n;
  const double centre = (p + z2 / (2.0 * n)) / denom;
  const double half = z * std::sqrt(p * (1.0 - p) / n + z2 / (4.0 * n * n)) / denom;
  return {std::max(0.0, centre - half), std::min(1.0, centre + half)};
}

double quantile(std::vector<double> values, double q) {
  if (values.empty()) return NAN;
  std::sort(values.begin(), values.end());
  const double h = (static_cast<double>(values.size()) - 1.0) * q;
  const size_t lo = static_cast<size_t>(std::floor(h));
  const size_t hi = std::min(values.size() - 1, lo + 1);
  return values[lo] + (h - static_cast<double>(lo)) * (values[hi] - values[lo]);
}

std::string format_number(const char* format, double v) {
  if (!std::isfinite(v)) return "-";
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

namespace {

nlohmann::json number_or_null(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

std::vector<double> field(const std::vector<const nlohmann::json*>& trials, const char* key) {
  std::vector<double> out;
  for (const nlohmann::json* t : trials) {
    const auto it = t->find(key);
    if (it != t->end() && it->is_number()) out.push_back(it->get<double>());
  }
  return out;
}

nlohmann::json group_stats(const std::vector<const nlohmann::json*>& trials) {
  nlohmann::json g;
  int successes = 0;
  std::map<std::string, int> statuses;
  for (const nlohmann::json* t : trials) {
    if (t->value("success", false)) ++successes;
    ++statuses[t->value("status", std::string("?"))];
  }
  const int n = static_cast<int>(trials.size());
  const Interval ci = wilson_interval(successes, n);
  g["trials"] = n;
  g["successes"] = successes;
  g["success_rate"] = n > 0 ? static_cast<double>(successes) / n : 0.0;
  g["success_ci95"] = {ci.low, ci.high};
  g["statuses"] = statuses;
  const std::vector<double> planning = field(trials, "planning_time_s");
  g["planning_time_s"] = {{"median", number_or_null(quantile(planning, 0.5))},
                          {"p90", number_or_null(quantile(planning, 0.9))},
                          {"n", planning.size()}};
  for (const char* key : {"simplification_time_s", "plan_calls", "collision_checks",
                          "path_length_joint", "path_length_ee_m", "duration_s", "smoothness",
                          "min_clearance_m", "wall_time_s", "peak_memory_mb"}) {
    g[std::string(key)] = {{"median", number_or_null(quantile(field(trials, key), 0.5))}};
  }
  return g;
}

std::string fmt(const nlohmann::json& v, const char* format) {
  return v.is_number() ? format_number(format, v.get<double>()) : "-";
}

}  // namespace

nlohmann::json make_summary(const RunInfo& run, std::vector<nlohmann::json> trials) {
  std::sort(trials.begin(), trials.end(), [](const nlohmann::json& a, const nlohmann::json& b) {
    return a.value("trial_id", std::string()) < b.value("trial_id", std::string());
  });
  using Key = std::tuple<std::string, std::string, std::string, std::string, std::string>;
  std::map<Key, std::vector<const nlohmann::json*>> groups;
  std::map<std::string, std::vector<const nlohmann::json*>> by_planner;
  std::vector<const nlohmann::json*> all;
  for (const nlohmann::json& t : trials) {
    const Key key{t.value("scenario", ""), t.value("program", ""), t.value("robot", ""),
                  t.value("environment", ""), t.value("planner", "")};
    groups[key].push_back(&t);
    by_planner[t.value("planner", "")].push_back(&t);
    all.push_back(&t);
  }
  nlohmann::json s;
  s["run"] = {{"name", run.name},
              {"doc", run.doc},
              {"planned_trials", run.planned_trials},
              {"finished_trials", trials.size()},
              {"complete", static_cast<int>(trials.size()) >= run.planned_trials},
              {"interrupted", run.interrupted},
              {"jobs", run.jobs},
              {"wall_s", run.wall_s}};
  s["overall"] = group_stats(all);
  nlohmann::json planners = nlohmann::json::object();
  for (const auto& [name, list] : by_planner) planners[name] = group_stats(list);
  s["planners"] = planners;
  nlohmann::json out = nlohmann::json::array();
  for (const auto& [key, list] : groups) {
    nlohmann::json g = group_stats(list);
    g["scenario"] = std::get<0>(key);
    g["program"] = std::get<1>(key);
    g["robot"] = std::get<2>(key);
    g["environment"] = std::get<3>(key);
    g["planner"] = std::get<4>(key);
    out.push_back(std::move(g));
  }
  s["groups"] = out;
  return s;
}

std::string summary_markdown(const nlohmann::json& s) {
  const nlohmann::json& run = s["run"];
  const nlohmann::json& all = s["overall"];
  std::string md = "# Run " + run["name"].get<std::string>() + "\n\n";
  if (!run["doc"].get<std::string>().empty()) md += run["doc"].get<std::string>() + "\n\n";
  char line[512];
  std::snprintf(line, sizeof line,
                "%d of %d trials finished%s; %d succeeded: %.1f%% (95%% Wilson interval "
                "%.1f%%..%.1f%%). Planning time per trial: median %s s, p90 %s s.\n\n",
                run["finished_trials"].get<int>(), run["planned_trials"].get<int>(),
                run["interrupted"].get<bool>() ? " (interrupted)" : "", all["successes"].get<int>(),
                100.0 * all["success_rate"].get<double>(),
                100.0 * all["success_ci95"][0].get<double>(),
                100.0 * all["success_ci95"][1].get<double>(),
                fmt(all["planning_time_s"]["median"], "%.3f").c_str(),
                fmt(all["planning_time_s"]["p90"], "%.3f").c_str());
  md += line;
  md +=
      "| scenario | robot | environment | planner | success | 95% CI | planning s (median / p90) "
      "| joint path | EE path m | duration s | failures |\n";
  md += "|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const nlohmann::json& g : s["groups"]) {
    std::string failures;
    for (const auto& [status, count] : g["statuses"].items()) {
      if (status == "success") continue;
      failures += (failures.empty() ? "" : ", ") + status + " " + std::to_string(count.get<int>());
    }
    std::snprintf(
        line, sizeof line,
        "| %s | %s | %s | %s | %d/%d | %.0f%%..%.0f%% | %s / %s | %s | %s | %s | %s |\n",
        g["scenario"].get<std::string>().c_str(), g["robot"].get<std::string>().c_str(),
        g["environment"].get<std::string>().c_str(), g["planner"].get<std::string>().c_str(),
        g["successes"].get<int>(), g["trials"].get<int>(),
        100.0 * g["success_ci95"][0].get<double>(), 100.0 * g["success_ci95"][1].get<double>(),
        fmt(g["planning_time_s"]["median"], "%.3f").c_str(),
        fmt(g["planning_time_s"]["p90"], "%.3f").c_str(),
        fmt(g["path_length_joint"]["median"], "%.2f").c_str(),
        fmt(g["path_length_ee_m"]["median"], "%.2f").c_str(),
        fmt(g["duration_s"]["median"], "%.1f").c_str(), failures.empty() ? "-" : failures.c_str());
    md += line;
  }
  return md;
}

void write_file_atomically(const std::filesystem::path& file, const std::string& text) {
  const std::filesystem::path tmp = file.string() + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << text;
    if (!out) throw std::runtime_error(tmp.string() + ": cannot write");
  }
  std::filesystem::rename(tmp, file);
}

void write_summary(const std::filesystem::path& dir, const nlohmann::json& summary,
                   const std::string& appendix) {
  write_file_atomically(dir / "summary.json", summary.dump(2) + "\n");
  write_file_atomically(dir / "summary.md", summary_markdown(summary) + appendix);
}

}  // namespace taskmatrix::harness
