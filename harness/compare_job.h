// `taskmatrix compare BASE_DIR NEW_DIR`: reads two run directories, pairs their trials
// (harness/compare.h), prints the verdict and what changed, and with a report directory
// writes compare.md, compare.json and a self-contained report.html with a picture of each
// failed trial.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include "harness/compare.h"

namespace taskmatrix::harness {

// PNG bytes of a recorded trial's last frame, from "RUN_DIR:TRIAL_ID"; throws when it has
// no recording.
using SnapshotFn = std::function<std::vector<std::uint8_t>(const std::string& dir_and_trial)>;

struct CompareJobOptions {
  std::filesystem::path base_dir, new_dir;
  std::filesystem::path report_dir;  // empty: no files
  CompareThresholds thresholds;
  bool ignore_planner = false;  // pair trials whatever their planner (one planner per run)
  int max_snapshots = 40;
  SnapshotFn snapshot;  // null: no pictures
};

struct CompareJobResult {
  Comparison comparison;
  std::filesystem::path report;  // report.html, when written
};

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
