// `taskmatrix run`: a scenario or a suite, as a matrix of trials run in worker processes, with
// results written as they finish. A run directory holds:
//   trials.jsonl     one line per finished trial (harness/results/trial_record.h), flushed
//                    and synced as each ends: a killed run loses no finished trial
//   trajectories/    the executed trajectory of each trial (harness/replay/trajectory_file.h)
//   summary.json, summary.md, ompl.log (harness/results/summary.h, harness/results/ompl_log.h)
//   provenance.json  (harness/results/provenance.h)
// Everything is read and checked (scenario files, models, layouts of every trial) before the
// first trial; an error throws core::InputError and writes nothing.
//
// Without --resume an existing run directory's results are replaced. With --resume, trials
// already in trials.jsonl are kept (a torn last line is dropped) and only the others run; the
// directory must come from the same scenario files (same hash).
// With --only, one trial runs (from its id alone) and its line is printed on stdout; a run
// directory is written only when --out is given.
// With a shard I/N (harness/scenario/trial_matrix.h) the run holds only that shard's trials, in a
// directory of its own (default results/runs/<run name>-shard-<I>-of-<N>; resumable like any
// other); `taskmatrix merge` (harness/run/merge_job.h) unions the shards' directories into one.
#pragma once

#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness/results/summary.h"
#include "harness/scenario/model_catalog.h"
#include "harness/scenario/scenario.h"
#include "harness/scenario/trial_matrix.h"
#include "taskmatrix/core/task_program.h"

namespace taskmatrix::harness {

struct RunJobOptions {
  std::filesystem::path scenario_file;
  std::filesystem::path out;  // empty: results/runs/<run name> under the catalog root
  int jobs = 1;
  RunOverrides overrides;
  bool resume = false;
  std::string only;
  Shard shard;                                                          // 0/1: the whole matrix
  enum class Progress { kAuto, kOn, kOff } progress = Progress::kAuto;  // auto: on a terminal
  double record_rate_hz = 25.0;  // trajectory frames per simulated second; 0: none kept
  std::vector<std::string> command_line;
};

struct RunJobResult {
  std::filesystem::path dir;  // empty for --only without --out
  int planned = 0, finished = 0, successes = 0, ran = 0;
  bool interrupted = false;
  std::vector<std::string> scenarios;  // the run plan's scenario names, in its order
};

// Installs a SIGINT/SIGTERM handler for the duration of the run: the first signal stops
// new trials, kills running workers (their trials are left for --resume), writes the
// summary of what finished, and returns with interrupted = true.
RunJobResult run_job(const ModelCatalog& catalog, core::ProgramRegistry& registry,
                     const RunJobOptions& options, std::ostream& out, std::ostream& err);

// Every job that writes a run directory (run, merge) locks it with a RunDirectoryLock
// (harness/results/run_directory.h) and writes its results with this, so that the directory's files
// mean the same whoever wrote them.
// Writes summary.json and summary.md (with the run's trial ids and, with several planners,
// each planner against the first; then also planners.md and planners.html), ompl.log and
// `provenance` as provenance.json. `finished` are the run's own trials. Returns the Markdown
// summary (with the planner table).
std::string write_run_results(const std::filesystem::path& dir, const RunPlan& plan,
                              const RunInfo& info, const std::vector<nlohmann::json>& finished,
                              const nlohmann::json& provenance);

// `taskmatrix validate`: reads and checks everything run_job would before its first trial,
// without running. Returns the number of trials the file defines. Throws core::InputError.
// `warnings`, if given, receives what the state machines the scenarios run leave without a way
// to succeed (core::machine_warnings; nested machines too), each naming the machine's file.
int validate_run_plan(const ModelCatalog& catalog, core::ProgramRegistry& registry,
                      const std::filesystem::path& file,
                      std::vector<std::string>* warnings = nullptr);

// The MuJoCo version the backend runs, e.g. "2.2.2" (provenance.json's mujoco_version).
std::string mujoco_version();

}  // namespace taskmatrix::harness
