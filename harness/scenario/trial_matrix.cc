#include "harness/scenario/trial_matrix.h"

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <sstream>

#include "taskmatrix/core/input_error.h"

namespace taskmatrix::harness {

std::string trial_id(const std::string& scenario, const std::string& robot,
                     const std::string& environment, const std::string& planner,
                     std::uint64_t layout_seed, std::uint32_t seed) {
  return scenario + "." + robot + "." + environment + "." + planner + ".l" +
         std::to_string(layout_seed) + ".s" + std::to_string(seed);
}

std::vector<TrialSpec> trial_matrix(const RunPlan& plan) {
  std::vector<TrialSpec> out;
  for (size_t i = 0; i < plan.scenarios.size(); ++i) {
    const Scenario& s = plan.scenarios[i];
    for (const std::string& robot : s.robots) {
      for (const std::string& env : s.environments) {
        for (size_t p = 0; p < s.planners.size(); ++p) {
          for (int k = 0; k < s.trials; ++k) {
            TrialSpec t;
            t.scenario = static_cast<int>(i);
            t.robot = robot;
            t.environment = env;
            t.planner = static_cast<int>(p);
            t.layout_seed = s.layout_seed + static_cast<std::uint64_t>(k);
            t.seed = s.seed + static_cast<std::uint32_t>(k);
            t.id = trial_id(s.name, robot, env, s.planners[p].label, t.layout_seed, t.seed);
            out.push_back(std::move(t));
          }
        }
      }
    }
  }
  return out;
}

namespace {

// A non-negative decimal integer of at most 9 digits, or -1.
long long small_number(const std::string& text) {
  if (text.empty() || text.size() > 9 ||
      !std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; })) {
    return -1;
  }
  return std::stoll(text);
}

}  // namespace

Shard parse_shard(const std::string& spec, const std::string& key) {
  const size_t slash = spec.find('/');
  const long long index = slash == std::string::npos ? -1 : small_number(spec.substr(0, slash));
  const long long count = slash == std::string::npos ? -1 : small_number(spec.substr(slash + 1));
  if (index < 0 || count < 1 || count > kMaxShards || index >= count) {
    throw core::InputError(
        key, "",
        "expected I/N with 0 <= I < N <= " + std::to_string(kMaxShards) + ", not '" + spec + "'");
  }
  return {static_cast<int>(index), static_cast<int>(count), key};
}

std::optional<Shard> slurm_array_shard(const std::function<const char*(const char*)>& env) {
  const char* id_text = env("SLURM_ARRAY_TASK_ID");
  if (id_text == nullptr) return std::nullopt;
  auto number = [&](const char* name) -> long long {
    const char* text = env(name);
    if (text == nullptr) {
      throw core::InputError(name, "", "is not set, but SLURM_ARRAY_TASK_ID is; pass --shard I/N");
    }
    const long long v = small_number(text);
    if (v < 0) {
      throw core::InputError(name, "",
                             std::string("expected a non-negative number, not '") + text + "'");
    }
    return v;
  };
  const long long id = number("SLURM_ARRAY_TASK_ID");
  const long long count = number("SLURM_ARRAY_TASK_COUNT");
  const long long min = env("SLURM_ARRAY_TASK_MIN") ? number("SLURM_ARRAY_TASK_MIN") : 0;
  const long long max =
      env("SLURM_ARRAY_TASK_MAX") ? number("SLURM_ARRAY_TASK_MAX") : min + count - 1;
  const long long step = env("SLURM_ARRAY_TASK_STEP") ? number("SLURM_ARRAY_TASK_STEP") : 1;
  if (count < 1 || count > kMaxShards || step != 1 || max - min + 1 != count || id < min ||
      id > max) {
    throw core::InputError("SLURM_ARRAY_TASK_ID", "",
                           "task " + std::to_string(id) +
                               " of an array that is not one range with step 1 (min " +
                               std::to_string(min) + ", max " + std::to_string(max) + ", step " +
                               std::to_string(step) + ", count " + std::to_string(count) +
                               "): the shard count is unknown; pass --shard I/N");
  }
  return Shard{static_cast<int>(id - min), static_cast<int>(count), "SLURM_ARRAY_TASK_ID"};
}

std::vector<TrialSpec> select_shard(const std::vector<TrialSpec>& matrix, const Shard& shard) {
  std::vector<TrialSpec> out;
  for (size_t i = static_cast<size_t>(shard.index); i < matrix.size();
       i += static_cast<size_t>(shard.count)) {
    out.push_back(matrix[i]);
  }
  return out;
}

TrialSpec parse_trial_id(const RunPlan& plan, const std::string& id) {
  std::vector<std::string> parts;
  std::stringstream in(id);
  for (std::string part; std::getline(in, part, '.');) parts.push_back(part);
  auto fail = [&](const std::string& why) -> TrialSpec {
    throw core::InputError("--only", "", "trial id '" + id + "': " + why);
  };
  if (parts.size() != 6) {
    return fail("expected <scenario>.<robot>.<environment>.<planner>.l<layout seed>.s<seed>");
  }
  TrialSpec t;
  const auto scenario = std::find_if(plan.scenarios.begin(), plan.scenarios.end(),
                                     [&](const Scenario& s) { return s.name == parts[0]; });
  if (scenario == plan.scenarios.end()) return fail("no scenario '" + parts[0] + "' in this run");
  t.scenario = static_cast<int>(scenario - plan.scenarios.begin());
  auto member = [&](const std::vector<std::string>& list, const std::string& v, const char* what) {
    if (std::find(list.begin(), list.end(), v) == list.end()) {
      fail(std::string("the scenario has no ") + what + " '" + v + "'");
    }
  };
  member(scenario->robots, parts[1], "robot");
  member(scenario->environments, parts[2], "environment");
  t.robot = parts[1];
  t.environment = parts[2];
  const auto planner = std::find_if(scenario->planners.begin(), scenario->planners.end(),
                                    [&](const PlannerConfig& p) { return p.label == parts[3]; });
  if (planner == scenario->planners.end()) fail("the scenario has no planner '" + parts[3] + "'");
  t.planner = static_cast<int>(planner - scenario->planners.begin());
  auto number = [&](const std::string& part, char prefix) -> unsigned long long {
    errno = 0;
    const unsigned long long v =
        part.size() >= 2 ? std::strtoull(part.c_str() + 1, nullptr, 10) : 0;
    if (part.size() < 2 || part[0] != prefix ||
        !std::all_of(part.begin() + 1, part.end(), [](char c) { return c >= '0' && c <= '9'; }) ||
        part.size() > 21 || errno == ERANGE) {
      fail(std::string("expected ") + prefix + "<number> (at most 2^64 - 1), not '" + part + "'");
    }
    return v;
  };
  t.layout_seed = number(parts[4], 'l');
  const unsigned long long seed = number(parts[5], 's');
  if (seed < 1 || seed > 0xffffffffULL) fail("the planner seed must be in 1..4294967295");
  t.seed = static_cast<std::uint32_t>(seed);
  t.id = id;
  return t;
}

}  // namespace taskmatrix::harness
