// `taskmatrix compare BASE_DIR NEW_DIR`: reads two run directories, pairs their trials
// (harness/compare/compare.h), prints the verdict and what changed (and a warning when the runs
// loaded different model files: harness/compare/provenance_diff.h), and with a report directory
// writes compare.md, compare.json and a self-contained report.html with pictures of each
// failed trial at the moment it failed (overview and close-up) and the commands that render
// its video.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include "harness/compare/compare.h"
#include "harness/compare/provenance_diff.h"
#include "harness/report/failure_pictures.h"

namespace taskmatrix::harness {

// Pictures of a recorded trial, from "RUN_DIR:TRIAL_ID", at simulated time `time_s` (< 0: its
// last frame); throws when it has no recording (harness/replay/trial_video.h).
using SnapshotFn = std::function<FailurePictures(const std::string& dir_and_trial, double time_s)>;

struct CompareJobOptions {
  std::filesystem::path base_dir, new_dir;
  std::filesystem::path report_dir;  // empty: no files
  CompareThresholds thresholds;
  bool ignore_planner = false;  // pair trials whatever their planner (one planner per run)
  bool print_power = false;     // the power table on the console too (--power)
  int max_snapshots = 40;
  SnapshotFn snapshot;  // null: no pictures
  // How the report's video commands start: e.g. "TASKMATRIX_ROOT=/x /abs/bin/taskmatrix".
  std::string render_command = "taskmatrix";
};

struct CompareJobResult {
  Comparison comparison;
  ProvenanceDiff differences;    // between the runs' provenance.json
  std::filesystem::path report;  // report.html, when written
};

// A word for a POSIX shell: as it is when it holds only [A-Za-z0-9_./:=,+-], else in single
// quotes.
std::string shell_word(const std::string& s);

// When a failed trial failed: the simulated time of its first "failed" event (the innermost
// program's failure), else -1 (its last frame).
double failure_time(const nlohmann::json& trial);

// Throws core::InputError naming the file (and line) for a missing or malformed run, and
// when no trial of one run has a partner in the other.
CompareJobResult run_compare_job(const CompareJobOptions& options, std::ostream& out);

// A run directory's trials, checked: every line has the fields pairing and the tests need.
// When summary.json lists the run's trial ids, trials of another matrix (left in trials.jsonl
// by a --resume with other --trials, --planners or --seed) are left out, and so are repeated
// lines of one trial (described in `warnings`). Throws core::InputError naming file, line, key.
std::vector<nlohmann::json> read_run_trials(const std::filesystem::path& run_dir,
                                            std::vector<std::string>* warnings = nullptr);

}  // namespace taskmatrix::harness
