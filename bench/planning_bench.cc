// Planning a reach of tallbot's left arm in the kitchen with 12 obstacles (layout seed 3),
// from the rest posture to 8 stored collision-free goals, RRTConnect, the same OMPL seed per
// problem in both benchmarks, no simplification:
//   BM_PlanReach_OMPLRaw    plain ompl::geometric::SimpleSetup, validity = mj_kinematics +
//                           mj_collision on the whole model
//   BM_PlanReach_Skillset   MotionPlanner (ValidityChecker, status mapping, goal checks)
// Counters: collision checks per plan and the share of exact solutions.
#include <benchmark/benchmark.h>

#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/geometric/SimpleSetup.h>
#include <ompl/geometric/planners/rrt/RRTConnect.h>
#include <ompl/util/Console.h>
#include <ompl/util/RandomNumbers.h>

#include <atomic>
#include <random>

#include "harness/scenario/model_catalog.h"
#include "harness/scenario/planner_plugins.h"
#include "taskmatrix/mujoco/motion_planner.h"
#include "taskmatrix/mujoco/validity_checker.h"

namespace {

using namespace taskmatrix;

// The benchmarks plan with the built-in planners, registered as the CLI registers them.
[[maybe_unused]] const bool builtin_planners = (harness::register_builtin_planners(), true);
namespace ob = ompl::base;
namespace og = ompl::geometric;

struct Problems {
  std::shared_ptr<const mujoco::Scene> scene;
  std::vector<int> joints;
  std::vector<std::vector<double>> goals;

  Problems() {
    const harness::ModelCatalog catalog(TASKMATRIX_BENCH_ROOT);
    scene = mujoco::Scene::load(catalog.robot_dir("tallbot"), catalog.environment_dir("kitchen"));
    const mujoco::ChainIndex& arm = scene->chain("left_arm");
    joints = arm.joints;
    mujoco::WorkerScene worker = cluttered_worker();
    mujoco::ValidityChecker checker(*scene, worker.model(), worker.data(), joints);
    std::mt19937_64 rng(2024);
    std::uniform_real_distribution<double> u(0, 1);
    while (goals.size() < 8) {
      std::vector<double> q(joints.size());
      for (size_t i = 0; i < q.size(); ++i)
        q[i] = arm.lower[i] + (arm.upper[i] - arm.lower[i]) * u(rng);
      if (!checker.in_collision(q.data())) goals.push_back(q);
    }
  }

  mujoco::WorkerScene cluttered_worker() const {
    mujoco::WorkerScene worker(scene);
    worker.apply_layout(scene->make_layout(12, 3));
    worker.reset_to_start();
    return worker;
  }
};

const Problems& problems() {
  static const Problems p;
  return p;
}

constexpr double kResolution = 0.005;
constexpr double kTimeLimit = 10.0;

void BM_PlanReach_OMPLRaw(benchmark::State& state) {
  const Problems& p = problems();
  mujoco::WorkerScene worker = p.cluttered_worker();
  const mjModel* m = worker.model();
  mjData* d = worker.data();
  const std::vector<double> rest(d->qpos, d->qpos + m->nq);
  ompl::msg::setLogLevel(ompl::msg::LOG_NONE);
  const unsigned n = static_cast<unsigned>(p.joints.size());
  size_t k = 0;
  double checks = 0, exact = 0;
  for (auto _ : state) {
    const std::vector<double>& goal = p.goals[k % p.goals.size()];
    ompl::RNG::setSeed(static_cast<std::uint32_t>(1 + k % p.goals.size()));
    ++k;
    auto space = std::make_shared<ob::RealVectorStateSpace>(n);
    ob::RealVectorBounds bounds(n);
    for (unsigned i = 0; i < n; ++i) {
      bounds.setLow(i, m->jnt_range[2 * p.joints[i]]);
      bounds.setHigh(i, m->jnt_range[2 * p.joints[i] + 1]);
    }
    space->setBounds(bounds);
    og::SimpleSetup setup(space);
    std::uint64_t count = 0;
    setup.setStateValidityChecker([&](const ob::State* s) {
      ++count;
      const double* v = s->as<ob::RealVectorStateSpace::StateType>()->values;
      for (unsigned i = 0; i < n; ++i) d->qpos[m->jnt_qposadr[p.joints[i]]] = v[i];
      return !mujoco::raw_robot_in_collision(*p.scene, m, d);
    });
    setup.getSpaceInformation()->setStateValidityCheckingResolution(kResolution);
    setup.setPlanner(std::make_shared<og::RRTConnect>(setup.getSpaceInformation()));
    ob::ScopedState<> start(space), goal_state(space);
    for (unsigned i = 0; i < n; ++i) {
      start[i] = rest[m->jnt_qposadr[p.joints[i]]];
      goal_state[i] = goal[i];
    }
    setup.setStartAndGoalStates(start, goal_state);
    const ob::PlannerStatus status = setup.solve(kTimeLimit);
    exact += status == ob::PlannerStatus::EXACT_SOLUTION;
    checks += static_cast<double>(count);
    std::copy(rest.begin(), rest.end(), d->qpos);
  }
  state.counters["collision_checks"] = benchmark::Counter(checks / state.iterations());
  state.counters["exact"] = benchmark::Counter(exact / state.iterations());
}
BENCHMARK(BM_PlanReach_OMPLRaw)->Unit(benchmark::kMillisecond)->Iterations(16);

void BM_PlanReach_Skillset(benchmark::State& state) {
  const Problems& p = problems();
  mujoco::WorkerScene worker = p.cluttered_worker();
  mujoco::MotionPlanner planner(*p.scene, worker, p.joints);
  mujoco::PlanOptions options;
  options.time_limit_s = kTimeLimit;
  options.motion_resolution = kResolution;
  options.simplify_rounds = 0;
  options.clearance_m = static_cast<double>(state.range(0)) * 1e-3;  // 0: the raw problem
  size_t k = 0;
  double checks = 0, exact = 0;
  for (auto _ : state) {
    options.seed = static_cast<std::uint32_t>(1 + k % p.goals.size());
    const core::PlanResult r = planner.plan({p.goals[k++ % p.goals.size()]}, options);
    exact += r.success();
    checks += static_cast<double>(r.collision_checks);
  }
  state.counters["collision_checks"] = benchmark::Counter(checks / state.iterations());
  state.counters["exact"] = benchmark::Counter(exact / state.iterations());
}
BENCHMARK(BM_PlanReach_Skillset)
    ->ArgName("clearance_mm")
    ->Arg(0)
    ->Arg(10)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(16);

}  // namespace
