// Scenarios: what to run (a program and its parameters, after optional set-up programs), where
// (robots x environments, obstacle layouts, the visitor), how (perception mode, planner time
// limit, trial time limit) and what counts as success (a condition on the world at the end).
//
// File format (scenarios/programs/<program>.yaml; see scenarios/README.md):
//   name: pickup                        # defaults to the file's stem
//   doc: reach for the cup and grasp it
//   program: pickup                     # any registered program
//   params: {object: cup}
//   setup:                              # run first, each must complete (optional)
//     - {program: reach, params: {object: cup}}
//   robots: [tallbot, minibot]
//   environments: [kitchen, office]
//   perception: ground_truth            # or sensor
//   obstacles: {count: 8}               # randomized per layout seed
//   layout_seed: 3                      # the default layout; trial k uses layout_seed + k
//   seed: 1                             # planner seeds; trial k uses seed + k
//   trials: 1
//   visitor: {walk_speed: 0.0}          # m/s along the environment's path
//   plan_time_limit_s: 5
//   time_limit_s: 60                    # simulated seconds for the program
//   success: grasping(cup)              # parse_condition text, checked on ground truth
// Everything is checked when the file is read: unknown keys, types, names of robots,
// environments, programs and parameters, the condition's syntax. Errors name file, line, key.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "harness/model_catalog.h"
#include "taskmatrix/core/task_program.h"

namespace taskmatrix::harness {

struct ProgramCall {
  std::string program;
  core::RawParams params;
};

struct Scenario {
  std::string name;
  std::string doc;
  std::filesystem::path file;
  ProgramCall run;
  std::vector<ProgramCall> setup;
  std::vector<std::string> robots, environments;
  std::string perception = "ground_truth";
  int obstacles = 0;
  std::uint64_t layout_seed = 1;
  std::uint32_t seed = 1;  // of the executive's plan-seed sequence
  int trials = 1;
  double visitor_speed_mps = 0;
  double plan_time_limit_s = 5.0;
  double time_limit_s = 60.0;
  std::string success;  // condition text; empty: the program's completion is the success
};

// Reads and checks a scenario. Throws core::InputError naming the file, line and key.
Scenario load_scenario(const std::filesystem::path& file, const ModelCatalog& catalog,
                       const core::ProgramRegistry& registry);

}  // namespace taskmatrix::harness
