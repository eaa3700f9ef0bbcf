// Scenarios: what to run (a program, or a state machine written inline, with its parameters,
// after optional set-up programs), where (robots x environments, randomized obstacle layouts,
// the visitor), how (perception mode, planners, time limits) and what counts as success (a
// condition on the world at the end). Suites run several scenarios with shared overrides.
//
// Formats: scenarios/README.md. Everything is checked when a file is read: unknown keys,
// types, NaN, names of robots, environments, programs, planners, planner parameters and
// program parameters, the condition's syntax, included files. Errors name file, line, key.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "harness/scenario/model_catalog.h"
#include "harness/scenario/scenario_variation.h"
#include "taskmatrix/core/obstacle_layout.h"
#include "taskmatrix/core/planning_types.h"
#include "taskmatrix/core/task_program.h"
#include "taskmatrix/core/task_variation.h"

namespace taskmatrix::harness {

struct ProgramCall {
  std::string program;
  core::RawParams params;
};

// A planner of the trial matrix: a registered planner's name and parameters (a plugin's once
// its `plugin:` is loaded), under a label (default: the name) that names it in trial ids and
// results, so one planner may appear with two settings.
struct PlannerConfig {
  std::string label;
  core::PlannerSpec spec;
};

// A name the scenario gives to something in the world (a program's object or surface
// parameter, an object argument of `success:` or of a machine's guard or invariant), and where
// it is written: checked against every environment the scenario runs in (check_names).
struct NameRef {
  std::string name;
  std::filesystem::path file;
  std::string key;
  int line = 0;
  std::string use;  // the program and parameter that use it, e.g. "pickup > reach(reach): parameter
                    // 'object'"
};

struct Scenario {
  std::string name;  // [A-Za-z0-9_-]+; defaults to the file's stem
  std::string doc;
  std::filesystem::path file;
  ProgramCall run;
  std::vector<ProgramCall> setup;
  std::vector<std::string> robots, environments;
  std::string perception = "ground_truth";
  // How motion is executed: "physics" (simulated dynamics, contacts that cannot matter pruned;
  // contact_pruning.h), "kinematic" (the robot is set to its commanded configurations;
  // mujoco_skillset.h) or "physics_unpruned" (physics computing every contact, as MuJoCo does
  // with the scene's own options: the reference that physics is measured and checked against).
  std::string execution = "physics";
  core::ObstacleOptions obstacles;
  core::VariationOptions variation;      // objects:, surfaces:, robot_start:
  KeyLines key_lines;                    // of the variation and targeted obstacle keys
  std::filesystem::path variation_file;  // where the variation keys are: the file or its suite
  std::vector<PlannerConfig> planners{{"RRTConnect", {}}};
  std::uint64_t layout_seed = 1;  // trial k (0-based) uses layout_seed + k
  std::uint32_t seed = 1;         // of the executive's plan-seed sequence; trial k: seed + k
  int trials = 1;
  double visitor_speed_mps = 0;
  // The planner's budget per plan call: "iterations" (at most plan_iterations; the trial then
  // repeats exactly and plan_time_limit_s is a safety net) or "time" (plan_time_limit_s alone:
  // anytime planners then depend on the machine's load).
  std::string planner_budget = "iterations";
  unsigned plan_iterations = 10000;
  double plan_time_limit_s = 60.0;
  double time_limit_s = 60.0;   // simulated seconds for the program (and each set-up step)
  double wall_limit_s = 120.0;  // wall-clock seconds a trial's worker may take before it is killed
  std::string success;          // condition text; empty: the program's completion is the success
  std::vector<NameRef> names;   // of the run, the set-up steps and `success:`
  std::string file_text;        // the file's bytes (for the run's scenario hash)
};

// The robots and environments lists something else replaces (a suite's keys, a command's
// overrides): their names in a scenario need not be models of the catalog's root, so a root
// with the user's own robot and environments, and no built-in robot, still runs the built-in
// program scenarios.
struct ReplacedLists {
  bool robots = false;
  bool environments = false;
};

// Reads and checks a scenario. An inline `machine:` is registered in `registry` under its
// name. Throws core::InputError naming the file, line and key. Names in the lists `replaced`
// marks are checked for form only.
Scenario load_scenario(const std::filesystem::path& file, const ModelCatalog& catalog,
                       core::ProgramRegistry& registry, ReplacedLists replaced = {});

// Throws core::InputError naming the file, line and key of the first of `s.names` that
// `environment` does not know: as the perceptual model names them, its objects and surfaces
// (a debris object's bodies each), `visitor` where it has one and `obstacle_<slot>` for its
// obstacle slots.
void check_names(const Scenario& s, const core::EnvironmentSpec& environment);

// What `taskmatrix run FILE` runs: the scenario in FILE, or the scenarios a suite includes.
//   suite: default                # marks a suite and names it
//   doc: ...
//   scenarios: [programs/reach.yaml, ...]   # relative to the suite file
//   trials: 3                     # optional overrides for every scenario: trials,
//                                 # layout_seed, seed, planners, robots, environments,
//                                 # planner_budget, plan_iterations, plan_time_limit_s,
//                                 # wall_limit_s, execution, and the variation keys
//                                 # objects, surfaces, robot_start (replacing the scenario's)
struct RunPlan {
  std::string name;
  std::string doc;
  std::filesystem::path file;
  bool suite = false;
  std::vector<Scenario> scenarios;  // names unique
  std::string text;                 // the suite file's bytes (empty for a single scenario)
};

// `replaced`: lists the caller's overrides will replace (RunOverrides::robots, environments),
// as for load_scenario; a suite's own lists replace the scenarios' in the same way.
RunPlan load_run_plan(const std::filesystem::path& file, const ModelCatalog& catalog,
                      core::ProgramRegistry& registry, ReplacedLists replaced = {});

// The execution modes a scenario's `execution` key and `run --execution` accept:
// "physics", "kinematic" and "physics_unpruned".
const std::vector<std::string>& execution_modes();
bool is_execution_mode(const std::string& name);
// "physics, kinematic or physics_unpruned", for messages and help text.
std::string execution_modes_text();

// Overrides from the command line (--trials, --seed, --planners, --execution; check-robot's
// robot and environment); each applies to every scenario. Throws core::InputError naming the
// option for an unknown planner or execution mode. A run's provenance.json records them all
// (matrix_provenance), so that merge rebuilds the same matrix.
struct RunOverrides {
  int trials = 0;                     // 0: keep
  std::uint32_t seed = 0;             // 0: keep
  std::vector<std::string> planners;  // empty: keep
  std::string execution;              // empty: keep; else an execution mode
  // Empty: keep. Names are checked when the scenes are loaded (taskmatrix check-robot).
  std::vector<std::string> robots, environments;
};
void apply_overrides(RunPlan& plan, const RunOverrides& overrides);
// The lists `overrides` replace (for load_run_plan).
ReplacedLists replaced_by(const RunOverrides& overrides);

// Checks a planner name and parameters against the planner registry (built-in planners and
// plugins loaded so far: harness/scenario/planner_plugins.h). Returns "" or what is wrong.
std::string check_planner(const core::PlannerSpec& spec);

}  // namespace taskmatrix::harness
