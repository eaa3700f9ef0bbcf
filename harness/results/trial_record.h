// A trial as one line of trials.jsonl (the contract of docs/architecture.md; fields are added,
// never renamed), and reading a trials.jsonl back (a torn last line, from a killed run, is
// ignored).
//
// Fields: the rows of kTrialFields (harness/results/trial_schema.h), with their units and what each
// output does with them; layout is the drawn world (harness/results/layout_json.h; also for a crashed
// or killed trial, drawn by the runner). Unmeasured values (a crashed trial's) are null.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness/results/json_input.h"
#include "harness/results/trial_schema.h"
#include "harness/results/trial_result.h"
#include "harness/scenario/trial_matrix.h"

namespace taskmatrix::harness {

// What the worker measured: the trial's own fields.
nlohmann::json trial_json(const RunPlan& plan, const TrialSpec& spec, const TrialResult& result);
// A trial that produced no result (crash, timeout): identity, status and reason; the
// measurements are null.
nlohmann::json failed_trial_json(const RunPlan& plan, const TrialSpec& spec,
                                 const core::Failure& failure);

// The clock bounds that decided a trial, so that its result may differ on a rerun under other
// load: "plan_time_limit" (a planner stopped by the clock), "simplify_time_limit", "wall_limit"
// (the worker was killed: status timeout). Read from the trial's clock_bound_hit and its plans
// (records written before that field existed are judged by their plans and status).
std::vector<std::string> clock_bounds_hit(const nlohmann::json& trial);

// `trial` without the fields that depend on the machine's speed or load (trial_schema.h's
// timing_fields(), also inside its plans), for comparisons: every other field is the same for
// the same trial id on the same build, whatever the number of jobs.
nlohmann::json without_timing(nlohmann::json trial);

// Checks the fields of a trial record that readers use (identity strings, success, seeds,
// numbers finite, counts >= 0, plans, a trajectory path inside the run directory). Throws
// core::InputError naming the file, line and key.
void check_trial_record(const nlohmann::json& trial, const JsonPlace& where);

struct TrialsFile {
  std::vector<nlohmann::json> trials;  // in file order, each trial id once
  size_t valid_bytes = 0;              // length of the file up to the last complete line
  bool torn_tail = false;              // a last line without newline or not JSON
  struct Duplicate {
    int line = 0, first_line = 0;
    std::string trial_id;
  };
  std::vector<Duplicate> duplicates;  // later lines of a trial id already read: left out
};
// Reads trials.jsonl; a missing file gives no trials. Every complete line is checked
// (check_trial_record); a bad line other than a torn last one throws core::InputError naming
// the file, line and key. A trial id that appears again is left out (see `duplicates`).
TrialsFile read_trials_file(const std::filesystem::path& file);
// "FILE: N duplicated trial lines ignored (line L repeats trial ID of line M)", or "" if none.
std::string describe_duplicates(const std::filesystem::path& file, const TrialsFile& f);

}  // namespace taskmatrix::harness
