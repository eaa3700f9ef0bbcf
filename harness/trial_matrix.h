// The trial matrix of a run: scenario x robot x environment x planner x trial index k, where
// trial k has layout seed layout_seed + k and planner seed seed + k. A trial id names all of
// it, so a trial can be run again from its id alone:
//   <scenario>.<robot>.<environment>.<planner label>.l<layout seed>.s<seed>
//   e.g. pickup.tallbot.kitchen.RRTConnect.l3.s1
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "harness/scenario.h"

namespace taskmatrix::harness {

struct TrialSpec {
  int scenario = 0;  // index into RunPlan::scenarios
  std::string robot, environment;
  int planner = 0;  // index into the scenario's planners
  std::uint64_t layout_seed = 0;
  std::uint32_t seed = 1;
  std::string id;
};

std::string trial_id(const std::string& scenario, const std::string& robot,
                     const std::string& environment, const std::string& planner,
                     std::uint64_t layout_seed, std::uint32_t seed);

// Every trial of the plan, in a fixed order (scenario, robot, environment, planner, k).
std::vector<TrialSpec> trial_matrix(const RunPlan& plan);

// The trial an id names. Its scenario, robot, environment and planner must be the plan's;
// its seeds may be any. Throws core::InputError naming --only and what does not match.
TrialSpec parse_trial_id(const RunPlan& plan, const std::string& id);

}  // namespace taskmatrix::harness
