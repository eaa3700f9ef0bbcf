#include "harness/compare/compare_job.h"

#include <algorithm>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <stdexcept>

#include "harness/compare/compare_sections.h"
#include "harness/compare/html_report.h"
#include "harness/compare/planner_comparison.h"
#include "harness/results/json_input.h"
#include "harness/results/trial_record.h"
#include "taskmatrix/core/input_error.h"

namespace taskmatrix::harness {

namespace {

using core::InputError;

nlohmann::json read_provenance(const std::filesystem::path& dir) {
  const std::filesystem::path file = dir / "provenance.json";
  std::error_code ec;
  if (!std::filesystem::exists(file, ec)) return nullptr;
  nlohmann::json p = read_json_file(file);
  if (!p.is_object()) throw InputError(file.string(), "", "must be a JSON object");
  return p;
}

}  // namespace

std::string shell_word(const std::string& s) {
  const bool plain = !s.empty() && s.find_first_not_of(
                                       "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz"
                                       "0123456789_./:=,+-") == std::string::npos;
  if (plain) return s;
  std::string out = "'";
  for (char ch : s) out += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
  return out + "'";
}

namespace {

std::vector<TrialSnapshot> snapshots(const CompareJobOptions& o,
                                     const std::vector<nlohmann::json>& base,
                                     const std::vector<nlohmann::json>& fresh, int& left_out) {
  // Failures of the new run first, then the base's failures of paired trials that the new
  // run does not repeat (a base trial without a partner is not part of the comparison).
  std::vector<std::pair<const nlohmann::json*, bool>> failed;  // trial, is the new run's
  std::set<std::string> in_new, failed_in_new;
  for (const nlohmann::json& t : fresh) {
    const std::string key = pairing_key(t, !o.ignore_planner);
    in_new.insert(key);
    if (!t.value("success", false)) {
      failed.push_back({&t, true});
      failed_in_new.insert(key);
    }
  }
  for (const nlohmann::json& t : base) {
    const std::string key = pairing_key(t, !o.ignore_planner);
    if (!t.value("success", false) && in_new.count(key) && !failed_in_new.count(key)) {
      failed.push_back({&t, false});
    }
  }
  std::stable_sort(failed.begin(), failed.end(), [](const auto& a, const auto& b) {
    return a.second != b.second ? a.second
                                : (*a.first)["trial_id"].template get<std::string>() <
                                      (*b.first)["trial_id"].template get<std::string>();
  });
  std::vector<TrialSnapshot> out;
  left_out = 0;
  for (const auto& [t, is_new] : failed) {
    if (static_cast<int>(out.size()) >= o.max_snapshots) {
      ++left_out;
      continue;
    }
    TrialSnapshot s;
    s.run = is_new ? "new" : "base";
    s.trial_id = (*t)["trial_id"].get<std::string>();
    s.status = t->value("status", std::string());
    s.reason = t->value("failure_reason", std::string());
    s.where = failure_location(*t);
    const std::string trial =
        std::filesystem::absolute(is_new ? o.new_dir : o.base_dir).lexically_normal().string() +
        ":" + s.trial_id;
    if (o.snapshot) {
      try {
        FailurePictures pictures = o.snapshot(trial, failure_time(*t));
        s.png = std::move(pictures.overview);
        s.close_up = std::move(pictures.close_up);
        s.time_s = pictures.time_s;
        s.focus = pictures.focus;
        const std::string render = o.render_command + " render --trial " + shell_word(trial);
        s.commands = {render + " --video " + shell_word(s.trial_id + ".mp4"),
                      render + " --video " + shell_word(s.trial_id + "-closeup.mp4") +
                          " --camera " + shell_word(pictures.close_up_camera)};
      } catch (const std::exception& e) {
        s.note = std::string("no picture: ") + e.what();
      }
    }
    out.push_back(std::move(s));
  }
  return out;
}

// The beginning of the Markdown (verdict and overall table) and every group with a verdict.
std::string console_text(const Comparison& c) {
  const std::string md = comparison_markdown(c);
  std::string text = md.substr(0, md.find("## Per group"));
  for (const PairedGroup& g : c.groups) {
    const std::string name =
        g.scenario + " " + g.robot + " " + g.environment + " " +
        (g.base_planner == g.new_planner ? g.new_planner : g.base_planner + "->" + g.new_planner);
    for (const std::string& r : g.regressions) text += "REGRESSION " + name + ": " + r + "\n";
    for (const std::string& r : g.improvements) text += "better     " + name + ": " + r + "\n";
  }
  for (const std::string& p : c.nonreproducible) text += "not reproducible " + p + "\n";
  return text;
}

// The "What ran" section of compare.md.
std::string provenance_markdown(const ProvenanceDiff& d) {
  const ReportTable table = provenance_diff_table(d);
  return "\n## What ran\n\n" +
         (table.rows.empty()
              ? std::string("The same build loaded the same model and scenario files.\n")
              : markdown_table(table));
}

}  // namespace

double failure_time(const nlohmann::json& trial) {
  const auto events = trial.find("events");
  if (events == trial.end() || !events->is_array()) return -1;
  for (const nlohmann::json& e : *events) {
    if (e.is_object() && e.value("type", std::string()) == "failed" && e.contains("t") &&
        e["t"].is_number()) {
      return e["t"].get<double>();
    }
  }
  return -1;
}

std::vector<nlohmann::json> read_run_trials(const std::filesystem::path& run_dir,
                                            std::vector<std::string>* warnings) {
  std::error_code ec;
  if (!std::filesystem::is_directory(run_dir, ec)) {
    throw InputError(run_dir.string(), "", "no such run directory");
  }
  const std::filesystem::path file = run_dir / "trials.jsonl";
  if (!std::filesystem::exists(file, ec)) {
    throw InputError(file.string(), "", "missing: not a run directory of taskmatrix run");
  }
  TrialsFile f = read_trials_file(file);
  if (warnings && !f.duplicates.empty()) warnings->push_back(describe_duplicates(file, f));
  // A resumed run's file may hold trials of another matrix; summary.json names this run's.
  const std::filesystem::path summary_file = run_dir / "summary.json";
  if (std::filesystem::exists(summary_file, ec)) {
    const nlohmann::json summary = read_json_file(summary_file);
    const JsonPlace where{summary_file.string(), 0, ""};
    const nlohmann::json& listed =
        json_optional_field(summary, "trial_ids", JsonKind::kArray, where);
    if (listed.is_array()) {
      std::set<std::string> ids;
      for (size_t i = 0; i < listed.size(); ++i) {
        if (!listed[i].is_string()) {
          where.at("trial_ids[" + std::to_string(i) + "]").fail("must be a string");
        }
        ids.insert(listed[i].get<std::string>());
      }
      std::erase_if(f.trials, [&](const nlohmann::json& t) {
        return !ids.count(t["trial_id"].get<std::string>());
      });
    }
  }
  if (f.trials.empty()) throw InputError(file.string(), "", "holds no finished trial");
  return std::move(f.trials);
}

CompareJobResult run_compare_job(const CompareJobOptions& o, std::ostream& out) {
  std::vector<std::string> warnings;
  const std::vector<nlohmann::json> base = read_run_trials(o.base_dir, &warnings);
  const std::vector<nlohmann::json> fresh = read_run_trials(o.new_dir, &warnings);
  const nlohmann::json base_provenance = read_provenance(o.base_dir);
  const nlohmann::json new_provenance = read_provenance(o.new_dir);
  for (const std::string& w : warnings) std::cerr << "taskmatrix: warning: " << w << "\n";
  CompareJobResult r;
  r.differences = diff_provenance(base_provenance, new_provenance);
  try {
    r.comparison = compare_trials(base, fresh, !o.ignore_planner, o.thresholds,
                                  planner_budgets(new_provenance));
  } catch (const std::invalid_argument& e) {
    throw InputError(
        (o.base_dir / "trials.jsonl").string() + ", " + (o.new_dir / "trials.jsonl").string(), "",
        e.what());
  }
  Comparison& c = r.comparison;
  c.base_label = o.base_dir.string();
  c.new_label = o.new_dir.string();
  if (c.overall.pairs == 0 && c.nonreproducible.empty()) {
    std::set<std::string> bp, np;
    for (const nlohmann::json& t : base) bp.insert(t["planner"].get<std::string>());
    for (const nlohmann::json& t : fresh) np.insert(t["planner"].get<std::string>());
    std::string hint;
    if (bp != np && !o.ignore_planner) {
      auto list = [](const std::set<std::string>& s) {
        std::string joined;
        for (const std::string& p : s) joined += (joined.empty() ? "" : ", ") + p;
        return joined;
      };
      hint = " (the base's planners are " + list(bp) + ", the new run's " + list(np) +
             "; --ignore-planner pairs them anyway)";
    }
    throw InputError(o.new_dir.string(), "trial_id",
                     "no trial has a partner in " + o.base_dir.string() +
                         ": the runs hold different scenarios, robots, environments or seeds" +
                         hint);
  }
  const std::string warning = provenance_warning(r.differences);
  out << warning << console_text(c);
  if (o.print_power) {
    out << "\nStatistical power: " << power_method(c) << "\n\n" << markdown_table(power_table(c));
  }
  if (!o.report_dir.empty()) {
    std::filesystem::create_directories(o.report_dir);
    int left_out = 0;
    const std::vector<TrialSnapshot> pictures = snapshots(o, base, fresh, left_out);
    std::string md = comparison_markdown(c);
    if (!warning.empty()) md.insert(md.find("\n\n") + 2, "```\n" + warning + "```\n\n");
    md += provenance_markdown(r.differences);
    nlohmann::json j = comparison_json(c);
    j["provenance_differences"] = provenance_diff_json(r.differences);
    r.report = o.report_dir / "report.html";
    // The three files of a report are replaced together: never a mix of two comparisons.
    write_files_atomically({{o.report_dir / "compare.md", md},
                            {o.report_dir / "compare.json", json_text(j, 2) + "\n"},
                            {r.report, compare_html(c, base, fresh, base_provenance, new_provenance,
                                                    pictures, left_out, &r.differences)}});
    out << "report: " << r.report.string() << " (" << pictures.size()
        << " failed trials pictured)\n";
  }
  return r;
}

}  // namespace taskmatrix::harness
