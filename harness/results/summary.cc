#include "harness/results/summary.h"

#include <signal.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <tuple>

#include "harness/results/json_input.h"
#include "harness/results/trial_schema.h"
#include "taskmatrix/core/utf8.h"
#include "taskmatrix/io/text_file.h"

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

std::string valid_utf8(const std::string& text) { return core::valid_utf8(text); }

namespace {

std::string markdown(const std::string& text, bool keep_newlines) {
  std::string out;
  for (char c : valid_utf8(text)) {
    switch (c) {
      case '|':
      case '\\':
      case '`':
      case '*':
      case '[':
      case ']':
        out += '\\';
        out += c;
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '&':
        out += "&amp;";
        break;
      case '\n':
        out += keep_newlines ? "\n" : " ";
        break;
      case '\r':
        out += ' ';
        break;
      default:
        out += c;
    }
  }
  return out;
}

}  // namespace

std::string markdown_cell(const std::string& text) { return markdown(text, false); }
std::string markdown_text(const std::string& text) { return markdown(text, true); }

namespace {

std::vector<double> field(const std::vector<const nlohmann::json*>& trials, const char* key) {
  std::vector<double> out;
  for (const nlohmann::json* t : trials) {
    const auto it = t->find(key);
    if (it != t->end() && it->is_number()) out.push_back(it->get<double>());
  }
  return out;
}

nlohmann::json group_stats(const std::vector<const nlohmann::json*>& trials,
                           std::span<const TrialField> fields) {
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
  for (const TrialField& f : fields) {
    if (f.summary == FieldSummary::kNone) continue;
    const std::string key(f.name);
    const std::vector<double> values = field(trials, key.c_str());
    nlohmann::json& stats = g[key];
    stats["median"] = number_or_null(quantile(values, 0.5));
    if (f.summary == FieldSummary::kMedianP90) {
      stats["p90"] = number_or_null(quantile(values, 0.9));
      stats["n"] = values.size();
    }
  }
  return g;
}

std::string fmt(const nlohmann::json& v, const char* format) {
  return v.is_number() ? format_number(format, v.get<double>()) : "-";
}

// A group's statistic of a field (null when the summary lacks it).
nlohmann::json statistic(const nlohmann::json& group, const std::string& field, const char* stat) {
  const auto f = group.find(field);
  if (f == group.end() || !f->is_object()) return nullptr;
  const auto v = f->find(stat);
  return v == f->end() ? nlohmann::json() : *v;
}

}  // namespace

nlohmann::json make_summary(const RunInfo& run, std::vector<nlohmann::json> trials,
                            std::span<const TrialField> fields) {
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
  s["overall"] = group_stats(all, fields);
  nlohmann::json planners = nlohmann::json::object();
  for (const auto& [name, list] : by_planner) planners[name] = group_stats(list, fields);
  s["planners"] = planners;
  nlohmann::json out = nlohmann::json::array();
  for (const auto& [key, list] : groups) {
    nlohmann::json g = group_stats(list, fields);
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

std::string summary_markdown(const nlohmann::json& s, std::span<const TrialField> fields) {
  const nlohmann::json& run = s["run"];
  const nlohmann::json& all = s["overall"];
  auto text = [](const nlohmann::json& v) { return markdown_cell(v.get<std::string>()); };
  std::string md = "# Run " + text(run["name"]) + "\n\n";
  if (!run["doc"].get<std::string>().empty()) {
    md += markdown_text(run["doc"].get<std::string>()) + "\n\n";
  }
  md += std::to_string(run["finished_trials"].get<int>()) + " of " +
        std::to_string(run["planned_trials"].get<int>()) + " trials finished" +
        (run["interrupted"].get<bool>() ? " (interrupted)" : "") + "; " +
        std::to_string(all["successes"].get<int>()) +
        " succeeded: " + format_number("%.1f", 100.0 * all["success_rate"].get<double>()) +
        "% (95% Wilson interval " +
        format_number("%.1f", 100.0 * all["success_ci95"][0].get<double>()) + "%.." +
        format_number("%.1f", 100.0 * all["success_ci95"][1].get<double>()) +
        "%). Planning time per trial: median " + fmt(all[kPlanningTimeField]["median"], "%.3f") +
        " s, p90 " + fmt(all[kPlanningTimeField]["p90"], "%.3f") + " s.\n\n";
  // The groups' columns: identity, success, the table's summary.md fields, failures.
  md += "| scenario | robot | environment | planner | success | 95% CI |";
  std::string rule = "|---|---|---|---|---|---|";
  for (const TrialField& f : fields) {
    if (f.display.summary_md.empty()) continue;
    md += " " + std::string(f.display.summary_md) +
          (f.summary == FieldSummary::kMedianP90 ? " (median / p90)" : "") + " |";
    rule += "---|";
  }
  md += " failures |\n" + rule + "---|\n";
  for (const nlohmann::json& g : s["groups"]) {
    std::string failures;
    for (const auto& [status, count] : g["statuses"].items()) {
      if (status == "success") continue;
      failures += (failures.empty() ? "" : ", ") + markdown_cell(status) + " " +
                  std::to_string(count.get<int>());
    }
    md += "| " + text(g["scenario"]) + " | " + text(g["robot"]) + " | " + text(g["environment"]) +
          " | " + text(g["planner"]) + " | " + std::to_string(g["successes"].get<int>()) + "/" +
          std::to_string(g["trials"].get<int>()) + " | " +
          format_number("%.0f", 100.0 * g["success_ci95"][0].get<double>()) + "%.." +
          format_number("%.0f", 100.0 * g["success_ci95"][1].get<double>()) + "% |";
    for (const TrialField& f : fields) {
      if (f.display.summary_md.empty()) continue;
      const std::string format(f.display.format), name(f.name);
      md += " " + fmt(statistic(g, name, "median"), format.c_str());
      if (f.summary == FieldSummary::kMedianP90) {
        md += " / " + fmt(statistic(g, name, "p90"), format.c_str());
      }
      md += " |";
    }
    md += " " + (failures.empty() ? std::string("-") : failures) + " |\n";
  }
  return md;
}

namespace {

// Blocks SIGINT and SIGTERM while files are renamed into place: a Ctrl-C then takes effect
// after the last rename, never between two.
class DeferStopSignals {
 public:
  DeferStopSignals() {
    sigset_t stop;
    sigemptyset(&stop);
    sigaddset(&stop, SIGINT);
    sigaddset(&stop, SIGTERM);
    sigprocmask(SIG_BLOCK, &stop, &old_);
  }
  ~DeferStopSignals() { sigprocmask(SIG_SETMASK, &old_, nullptr); }
  DeferStopSignals(const DeferStopSignals&) = delete;
  DeferStopSignals& operator=(const DeferStopSignals&) = delete;

 private:
  sigset_t old_;
};

}  // namespace

void write_file_atomically(const std::filesystem::path& file, const std::string& text) {
  write_files_atomically({{file, text}});
}

void write_files_atomically(
    const std::vector<std::pair<std::filesystem::path, std::string>>& files) {
  std::vector<std::filesystem::path> written;
  try {
    for (const auto& [file, text] : files) {
      io::write_file_checked(file.string() + ".tmp", text);
      written.push_back(file.string() + ".tmp");
    }
  } catch (...) {
    std::error_code ignored;
    for (const std::filesystem::path& tmp : written) std::filesystem::remove(tmp, ignored);
    throw;
  }
  const DeferStopSignals defer;
  for (const auto& [file, text] : files) std::filesystem::rename(file.string() + ".tmp", file);
}

void write_summary(const std::filesystem::path& dir, const nlohmann::json& summary,
                   const std::string& appendix) {
  write_files_atomically({{dir / "summary.json", json_text(summary, 2) + "\n"},
                          {dir / "summary.md", summary_markdown(summary) + appendix}});
}

}  // namespace taskmatrix::harness
