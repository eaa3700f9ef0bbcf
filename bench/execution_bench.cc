// One control period (10 ms = 5 MuJoCo steps) of tallbot in the kitchen with 12 obstacles,
// the left arm following a sinusoid:
//   BM_ControlPeriod_Raw       ctrl written, 5 x mj_step (nothing pruned; counter
//                              contacts_per_pass: MuJoCo's contacts per mj_step)
//   BM_ControlPeriod_Skillset  MujocoSkillset::command + advance in each execution mode:
//     /physics            computed-torque feed-forward per step, mj_step2 then mj_step1 so
//                         poses and contacts are current for the programs, contact pruning
//                         (static geoms nothing movable is near closed, resting objects
//                         asleep), contacts from the candidate pairs, sparse Jacobians
//     /physics_unpruned   the same without contact pruning, the candidate pairs' contact
//                         pass and sparse Jacobians (physics as computed before them)
//     /kinematic          the commanded configuration set, kinematics, the robot's contacts
//   counters: contacts_per_pass (contacts per collision detection: per timestep in physics,
//   per period in kinematic mode) and sim_speed (simulated seconds per second)
// and the clearance query used for the min_clearance metric:
//   BM_Clearance_RawWideMargin mj_kinematics + mj_collision with every geom margin at 0.3 m
//                              (MuJoCo 2.2.2 has no distance query; this is the nearest raw
//                              equivalent, and misreports box and cylinder distances)
//   BM_Clearance_Skillset      clearance of both arms against everything, cap 0.3 m
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>

#include "harness/scenario/model_catalog.h"
#include "taskmatrix/mujoco/mujoco_skillset.h"

namespace {

using namespace taskmatrix;

std::unique_ptr<mujoco::MujocoSkillset> make_skillset(mujoco::SimulationOptions options = {}) {
  static const std::shared_ptr<const mujoco::Scene> scene = [] {
    const harness::ModelCatalog catalog(TASKMATRIX_BENCH_ROOT);
    return mujoco::Scene::load(catalog.robot_dir("tallbot"), catalog.environment_dir("kitchen"));
  }();
  auto skills = std::make_unique<mujoco::MujocoSkillset>(scene, options);
  skills->apply_layout(scene->make_layout(12, 3));
  skills->reset();
  return skills;
}

std::vector<double> arm_target(const std::vector<double>& rest, double t) {
  std::vector<double> q = rest;
  q[0] += 0.3 * std::sin(t);
  q[3] += 0.2 * std::sin(0.7 * t);
  return q;
}

void BM_ControlPeriod_Raw(benchmark::State& state) {
  mujoco::SimulationOptions as_compiled;  // the scene's own options: MuJoCo's dense Jacobians
  as_compiled.sparse_jacobian = false;
  auto skills = make_skillset(as_compiled);
  const mjModel* m = skills->model();
  mujoco::DataPtr d = mujoco::make_data(m);
  mju_copy(d->qpos, skills->sim_data()->qpos, m->nq);
  mju_copy(d->ctrl, skills->sim_data()->ctrl, m->nu);
  mj_forward(m, d.get());
  const std::vector<int>& joints = skills->scene().chain("left_arm").joints;
  std::vector<int> actuators;
  for (int j : joints) {
    for (int a = 0; a < m->nu; ++a)
      if (m->actuator_trnid[2 * a] == j) actuators.push_back(a);
  }
  const std::vector<double> rest = skills->configuration({"left_arm"});
  const int substeps = static_cast<int>(std::lround(skills->control_period() / m->opt.timestep));
  double contacts = 0, steps = 0;
  for (auto _ : state) {
    const std::vector<double> q = arm_target(rest, d->time);
    for (size_t i = 0; i < actuators.size(); ++i) d->ctrl[actuators[i]] = q[i];
    for (int s = 0; s < substeps; ++s) {
      mj_step(m, d.get());
      contacts += d->ncon;
    }
    steps += substeps;
  }
  state.counters["contacts_per_pass"] = contacts / std::max(1.0, steps);
}
BENCHMARK(BM_ControlPeriod_Raw)->Unit(benchmark::kMicrosecond);

void BM_ControlPeriod_Skillset(benchmark::State& state, mujoco::ExecutionMode mode, bool prune) {
  mujoco::SimulationOptions options;
  options.execution = mode;
  options.pruning = {prune, prune};
  options.sparse_jacobian = prune;
  options.candidate_pairs = prune;
  auto skills = make_skillset(options);
  const std::vector<double> rest = skills->configuration({"left_arm"});
  const long passes = skills->work().contact_passes, contacts = skills->work().contacts;
  const double t0 = skills->time();
  for (auto _ : state) {
    skills->command({"left_arm"}, arm_target(rest, skills->time()));
    benchmark::DoNotOptimize(skills->advance());
  }
  state.counters["contacts_per_pass"] =
      static_cast<double>(skills->work().contacts - contacts) /
      static_cast<double>(std::max(1L, skills->work().contact_passes - passes));
  state.counters["sim_speed"] =
      benchmark::Counter(skills->time() - t0, benchmark::Counter::kIsRate);
}
BENCHMARK_CAPTURE(BM_ControlPeriod_Skillset, physics, mujoco::ExecutionMode::kPhysics, true)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_ControlPeriod_Skillset, physics_unpruned, mujoco::ExecutionMode::kPhysics,
                  false)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_ControlPeriod_Skillset, kinematic, mujoco::ExecutionMode::kKinematic, true)
    ->Unit(benchmark::kMicrosecond);

void BM_Clearance_RawWideMargin(benchmark::State& state) {
  auto skills = make_skillset();
  mujoco::ModelPtr wide = mujoco::copy_model(skills->model());
  for (int g = 0; g < wide->ngeom; ++g) wide->geom_margin[g] = 0.3;
  wide->nconmax = 20000;
  mujoco::DataPtr d = mujoco::make_data(wide.get());
  mju_copy(d->qpos, skills->sim_data()->qpos, wide->nq);
  const mujoco::Scene& scene = skills->scene();
  for (auto _ : state) {
    mj_kinematics(wide.get(), d.get());
    mj_collision(wide.get(), d.get());
    double dist = 0.3;
    for (int c = 0; c < d->ncon; ++c) {
      if (scene.is_robot_geom(d->contact[c].geom1) || scene.is_robot_geom(d->contact[c].geom2))
        dist = std::min(dist, d->contact[c].dist);
    }
    benchmark::DoNotOptimize(dist);
  }
}
BENCHMARK(BM_Clearance_RawWideMargin)->Unit(benchmark::kMicrosecond);

void BM_Clearance_Skillset(benchmark::State& state) {
  auto skills = make_skillset();
  const std::vector<std::string> arms = {"left_arm", "right_arm"};
  const std::vector<double> q = skills->configuration(arms);
  for (auto _ : state) benchmark::DoNotOptimize(skills->clearance(arms, q, 0.3));
}
BENCHMARK(BM_Clearance_Skillset)->Unit(benchmark::kMicrosecond);

}  // namespace
