// ompl.log: the run in OMPL's benchmark log format (ompl::tools::Benchmark::saveResultsToStream),
// so that `ompl_benchmark_statistics ompl.log -d run.db` (Debian's ompl-demos) builds a
// Planner Arena database. One experiment (the run); one planner entry per planner label
// ("geometric_<label>", its parameters as common properties); one run per trial, in trial-id
// order, with properties: time (planning time of the trial, s), simplification time, solved
// (the trial's success), trial status, scenario, program, robot, environment (enums; an
// enum's values are those of this log, and a database keeps the first log's), layout seed,
// seed, plan calls, collision checks, ik time, path length joint, path length ee, duration,
// smoothness, min clearance, wall time, memory (peak MB). Unmeasured values are written as
// nan, which the script stores as NULL.
#pragma once

#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness/results/trial_schema.h"

namespace taskmatrix::harness {

struct OmplLogInfo {
  std::string experiment;  // no spaces
  std::string setup;       // the scenario text(s)
  std::string hostname;
  std::string cpuinfo;
  std::string date;
  std::uint32_t seed = 1;
  double time_limit_s = 0;  // per trial (the wall-clock limit)
  double total_time_s = 0;
  // Planner label -> (OMPL name, parameters), in run order.
  struct Planner {
    std::string label, name;
    std::vector<std::pair<std::string, std::string>> params;
  };
  std::vector<Planner> planners;
};

// `fields`: the trial fields whose OMPL type is not kNone are the runs' properties.
std::string ompl_log_text(const OmplLogInfo& info, std::vector<nlohmann::json> trials,
                          std::span<const TrialField> fields = kTrialFields);

}  // namespace taskmatrix::harness
