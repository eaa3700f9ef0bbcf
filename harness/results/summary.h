// summary.json and summary.md of a run: per scenario (program), robot, environment and
// planner, the success rate with a 95% Wilson score interval, the status counts, planning
// time (median and 90th percentile over the group's trials, all trials included) and the
// medians of path lengths, duration and wall time: the statistics harness/results/trial_schema.h
// asks for, and summary.md's columns from the same table. Trials are taken in id order, so the
// summary of a run does not depend on the order trials finished in.
#pragma once

#include <filesystem>
#include <map>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness/results/trial_schema.h"

namespace taskmatrix::harness {

struct Interval {
  double low = 0, high = 0;
};
// Wilson score interval for `successes` of `n` at normal quantile z (1.96: 95%). n = 0: [0, 1].
Interval wilson_interval(int successes, int n, double z = 1.959963984540054);
// Linear interpolation between closest ranks (R's type 7); NaN for no values.
double quantile(std::vector<double> values, double q);
// `format` (printf, one double) applied to v for reports; "-" when v is not finite.
std::string format_number(const char* format, double v);

// Text from names, reasons and docs for a Markdown table cell: '|', '\\', '`', '*', '[', ']'
// escaped ('_' inside names emphasises nothing), '<', '>', '&' as HTML entities (no markup gets
// through), line breaks as spaces, bytes that are not UTF-8 as U+FFFD.
std::string markdown_cell(const std::string& text);
// The same for running text (a doc): line breaks kept.
std::string markdown_text(const std::string& text);
// `text` with every byte sequence that is not UTF-8 replaced by U+FFFD.
std::string valid_utf8(const std::string& text);

struct RunInfo {
  std::string name;
  std::string doc;
  int planned_trials = 0;  // of the matrix (so a partial run says how far it got)
  bool interrupted = false;
  double wall_s = 0;  // of this invocation
  int jobs = 1;
};

// `fields`: the trial fields summarised per group (TrialField::summary).
nlohmann::json make_summary(const RunInfo& run, std::vector<nlohmann::json> trials,
                            std::span<const TrialField> fields = kTrialFields);
// `fields`: the columns per group are those with a summary.md heading (FieldDisplay::summary_md),
// in table order; `summary` must summarise them (make_summary with the same fields).
std::string summary_markdown(const nlohmann::json& summary,
                             std::span<const TrialField> fields = kTrialFields);
// Writes summary.json and summary.md (with `appendix` after the table) into `dir`, each
// atomically.
void write_summary(const std::filesystem::path& dir, const nlohmann::json& summary,
                   const std::string& appendix = "");

// Writes `text` to `file` through a temporary file (every write, the sync and the close
// checked: a full disk is an error, never an empty file) and a rename. Throws
// std::runtime_error naming the file.
void write_file_atomically(const std::filesystem::path& file, const std::string& text);
// The same for several files that belong together: all are written first, then renamed with
// SIGINT and SIGTERM held back, so an interruption leaves either the old set or the new one.
void write_files_atomically(
    const std::vector<std::pair<std::filesystem::path, std::string>>& files);

}  // namespace taskmatrix::harness
