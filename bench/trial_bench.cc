// One whole trial in-process, as a runner's worker runs it: harness::run_trial of
// scenarios/programs/<program>.yaml on tallbot in the kitchen in the scenario's default layout
// (8 obstacles, layout seed 3, planner seed 1): a fresh MujocoSkillset on the shared compiled
// scene, the layout, the executive, the program, the success check on ground truth:
//   BM_Trial/reach    reach for the cup
//   BM_Trial/pickup   reach, grasp and fixate on the cup
// Counters per trial (exact: the same in every iteration, repetition and run):
//   success, plan_calls, collision_checks, ik_calls   from the trial's WorkRecord
// and one that measures the machine:
//   raw_work_fraction  (planning + simplification + IK + simulation stepping wall time) over
//                      the trial's wall time: the raw MuJoCo/OMPL work in a trial
// Determinism in one process: every plan reseeds OMPL's process-global RNG with the plan's own
// seed (MotionPlanner) and the executive derives plan seeds from the trial's seed, so a trial
// repeats exactly without a fresh process. The benchmark checks it: an iteration (or a
// repetition) whose exact counters differ from the first ends the benchmark with an error.
// Planning is bounded by iterations and simplification by rounds, so the counters do not depend
// on the machine's load; the clock bounds are safety nets, and should one fire the error says so.
#include <benchmark/benchmark.h>

#include <map>
#include <sstream>

#include "harness/backends/backends.h"
#include "harness/run/trial.h"
#include "harness/scenario/model_catalog.h"
#include "harness/scenario/scenario.h"
#include "taskmatrix/programs/primitives.h"

namespace {

using namespace taskmatrix;

struct Fixture {
  harness::ModelCatalog catalog{TASKMATRIX_BENCH_ROOT};
  core::ProgramRegistry registry;
  std::shared_ptr<const core::LoadedScene> scene;

  Fixture() {
    programs::register_programs(registry);
    scene =
        harness::backend().load(catalog.robot_dir("tallbot"), catalog.environment_dir("kitchen"));
  }

  harness::Scenario scenario(const std::string& program) {
    return harness::load_scenario(catalog.root() / "scenarios" / "programs" / (program + ".yaml"),
                                  catalog, registry);
  }
};

Fixture& fixture() {
  static Fixture f;
  return f;
}

// The exact counters of one trial, as text: compared between iterations and repetitions.
std::string exact_counters(const harness::TrialResult& r) {
  std::ostringstream out;
  out << "success " << r.success << " (" << harness::trial_status(r) << "), plan_calls "
      << r.work.plans.size() << ", collision_checks " << r.work.collision_checks << ", ik_calls "
      << r.work.ik_calls;
  return out.str();
}

void BM_Trial(benchmark::State& state, const std::string& program) {
  Fixture& f = fixture();
  const harness::Scenario s = f.scenario(program);
  static std::map<std::string, std::string> first_seen;  // per program, over repetitions
  double success = 0, plan_calls = 0, checks = 0, ik_calls = 0, raw_work = 0, wall = 0;
  for (auto _ : state) {
    const harness::TrialResult r =
        harness::run_trial(s, *f.scene, s.layout_seed, s.seed, f.registry);
    const std::string counters = exact_counters(r);
    const auto [seen, first] = first_seen.emplace(program, counters);
    if (!first && seen->second != counters) {
      bool hit_bound = false;
      for (const core::PlanCallRecord& p : r.work.plans)
        hit_bound = hit_bound || p.simplification_hit_time_limit || p.planning_hit_time_limit;
      state.SkipWithError(("not deterministic: " + counters + " after " + seen->second +
                           (hit_bound ? " (a clock safety net of planning or simplification "
                                        "fired: the machine is far too busy)"
                                      : ""))
                              .c_str());
      break;
    }
    success += r.success;
    plan_calls += static_cast<double>(r.work.plans.size());
    checks += static_cast<double>(r.work.collision_checks);
    ik_calls += r.work.ik_calls;
    raw_work += r.work.planning_time_s() + r.work.simplification_time_s() + r.work.ik_time_s +
                r.work.plan_ik_time_s() + r.work.stepping_wall_s;
    wall += r.trial_wall_s;
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["success"] = success / n;
  state.counters["plan_calls"] = plan_calls / n;
  state.counters["collision_checks"] = checks / n;
  state.counters["ik_calls"] = ik_calls / n;
  state.counters["raw_work_fraction"] = raw_work / wall;
}
BENCHMARK_CAPTURE(BM_Trial, reach, std::string("reach"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Trial, pickup, std::string("pickup"))->Unit(benchmark::kMillisecond);

// Counters that must be identical from run to run (bench-compare reports any change as a
// regression): work counts, not times or rates. Declared here for every benchmark file.
[[maybe_unused]] const bool kExactCountersDeclared = [] {
  benchmark::AddCustomContext("taskmatrix_exact_counters",
                              "collision_checks,exact,solved,ik_iterations,success,plan_calls,"
                              "ik_calls");
  return true;
}();

}  // namespace
