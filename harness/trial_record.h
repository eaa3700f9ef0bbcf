// A trial as one line of trials.jsonl (the DESIGN.md contract; fields are added, never
// renamed), and reading a trials.jsonl back (a torn last line, from a killed run, is ignored).
//
// Fields: trial_id, scenario, robot, environment, program, planner (label), planner_name,
// seed, layout_seed, success, status, failure_reason, planning_time_s, simplification_time_s,
// plan_calls, planner_runs, collision_checks, ik_calls, ik_time_s, path_length_joint,
// path_length_ee_m, duration_s, sim_time_s, smoothness, min_clearance_m, wall_time_s,
// trial_wall_s, executive_wall_s, stepping_wall_s, monitoring_wall_s, overhead_s,
// peak_memory_mb, events,
// plans, removed_debris, trajectory, layout (the drawn world: harness/layout_json.h; also
// for a crashed or killed trial, drawn by the runner). Unmeasured values (a crashed trial's) are
// null.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness/trial.h"
#include "harness/trial_matrix.h"

namespace taskmatrix::harness {

// What the worker measured: the trial's own fields.
nlohmann::json trial_json(const RunPlan& plan, const TrialSpec& spec, const TrialResult& result);
// A trial that produced no result (crash, timeout): identity, status and reason; the
// measurements are null.
nlohmann::json failed_trial_json(const RunPlan& plan, const TrialSpec& spec,
                                 const std::string& status, const std::string& reason);

// The fields that depend on the machine's speed or load (times, memory); every other field
// is the same for the same trial id on the same build, whatever the number of jobs.
const std::vector<std::string>& timing_fields();
// `trial` without timing_fields() (also inside its plans), for comparisons.
nlohmann::json without_timing(nlohmann::json trial);

struct TrialsFile {
  std::vector<nlohmann::json> trials;  // in file order
  size_t valid_bytes = 0;              // length of the file up to the last complete line
  bool torn_tail = false;              // a last line without newline or not JSON
};
// Reads trials.jsonl; a missing file gives no trials. A bad line other than the last one
// throws core::InputError naming the file and line.
TrialsFile read_trials_file(const std::filesystem::path& file);

}  // namespace taskmatrix::harness
