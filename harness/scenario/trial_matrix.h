// The trial matrix of a run: scenario x robot x environment x planner x trial index k, where
// trial k has layout seed layout_seed + k and planner seed seed + k. A trial id names all of
// it, so a trial can be run again from its id alone:
//   <scenario>.<robot>.<environment>.<planner label>.l<layout seed>.s<seed>
//   e.g. pickup.tallbot.kitchen.RRTConnect.l3.s1
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "harness/scenario/scenario.h"

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

// A shard of the matrix: the trials whose index in trial_matrix() is congruent to `index`
// modulo `count` (a stride, so that a suite's slow scenarios spread over the shards). Shards
// 0..count-1 together hold every trial exactly once; 0/1 is the whole matrix.
struct Shard {
  int index = 0, count = 1;
  std::string from;  // what chose it: "--shard", "SLURM_ARRAY_TASK_ID", or empty (the default)
};
constexpr int kMaxShards = 1000000;

// "I/N" with 0 <= I < N <= kMaxShards. Throws core::InputError naming `key`.
Shard parse_shard(const std::string& spec, const std::string& key);

// The shard of a Slurm array task: SLURM_ARRAY_TASK_ID - SLURM_ARRAY_TASK_MIN of
// SLURM_ARRAY_TASK_COUNT, read through `env` (std::getenv's signature). nullopt outside an
// array task. An array that is not one contiguous range with step 1 (where the count is not
// the number of shards) throws core::InputError: such a job must pass --shard.
std::optional<Shard> slurm_array_shard(const std::function<const char*(const char*)>& env);

// The trials of `shard`, in matrix order.
std::vector<TrialSpec> select_shard(const std::vector<TrialSpec>& matrix, const Shard& shard);

// The trial an id names. Its scenario, robot, environment and planner must be the plan's;
// its seeds may be any. Throws core::InputError naming --only and what does not match.
TrialSpec parse_trial_id(const RunPlan& plan, const std::string& id);

}  // namespace taskmatrix::harness
