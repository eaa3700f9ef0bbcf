// The validity check, raw MuJoCo against ours, on the same stored configurations of the tall
// robot in the kitchen with 20 random obstacles (layout seed 5):
//   BM_ValidityCheck_Raw          mj_kinematics + mj_collision, any robot contact
//   BM_ValidityCheck_Skillset     ValidityChecker over every robot joint
//   BM_ValidityCheck_SkillsetArm  ValidityChecker for one arm (the planning case), on the
//                                 same configurations with only the left arm varying
// 4096 configurations drawn once with a fixed seed; the loop cycles through them.
#include <benchmark/benchmark.h>

#include <random>

#include "harness/scenario/model_catalog.h"
#include "taskmatrix/mujoco/validity_checker.h"

namespace {

using namespace taskmatrix;

struct Fixture {
  std::shared_ptr<const mujoco::Scene> scene;
  std::vector<int> all_joints, arm_joints;
  std::vector<std::vector<double>> all_configs, arm_configs;  // 4096 each

  // A fresh worker with the benchmark's 20 obstacles (layout seed 5), at the start.
  mujoco::WorkerScene cluttered_worker() const {
    mujoco::WorkerScene worker(scene);
    worker.apply_layout(scene->make_layout(20, 5));
    worker.reset_to_start();
    return worker;
  }

  Fixture() {
    const harness::ModelCatalog catalog(TASKMATRIX_BENCH_ROOT);
    scene = mujoco::Scene::load(catalog.robot_dir("tallbot"), catalog.environment_dir("kitchen"));
    std::mt19937_64 rng(42);
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<double> lo, hi;
    for (const mujoco::ChainIndex& c : scene->chains()) {
      if (c.name == "base") continue;  // the robot stays at its start
      for (size_t i = 0; i < c.joints.size(); ++i) {
        all_joints.push_back(c.joints[i]);
        lo.push_back(c.lower[i]);
        hi.push_back(c.upper[i]);
      }
    }
    arm_joints = scene->chain("left_arm").joints;
    const mujoco::ChainIndex& arm = scene->chain("left_arm");
    for (int k = 0; k < 4096; ++k) {
      std::vector<double> q(all_joints.size()), qa(arm_joints.size());
      for (size_t i = 0; i < q.size(); ++i) q[i] = lo[i] + (hi[i] - lo[i]) * u(rng);
      for (size_t i = 0; i < qa.size(); ++i)
        qa[i] = arm.lower[i] + (arm.upper[i] - arm.lower[i]) * u(rng);
      all_configs.push_back(q);
      arm_configs.push_back(qa);
    }
  }
};

Fixture& fixture() {
  static Fixture f;
  return f;
}

void BM_ValidityCheck_Raw(benchmark::State& state) {
  Fixture& f = fixture();
  const bool arm_only = state.range(0) == 1;
  mujoco::WorkerScene worker = f.cluttered_worker();
  const auto& joints = arm_only ? f.arm_joints : f.all_joints;
  const auto& configs = arm_only ? f.arm_configs : f.all_configs;
  size_t k = 0;
  int64_t collisions = 0;
  for (auto _ : state) {
    const std::vector<double>& q = configs[k++ % configs.size()];
    for (size_t i = 0; i < q.size(); ++i)
      worker.data()->qpos[worker.model()->jnt_qposadr[joints[i]]] = q[i];
    collisions += mujoco::raw_robot_in_collision(*f.scene, worker.model(), worker.data());
  }
  state.counters["in_collision"] =
      benchmark::Counter(static_cast<double>(collisions) / state.iterations());
}
BENCHMARK(BM_ValidityCheck_Raw)->Arg(0)->Arg(1)->ArgName("arm_only")->Unit(benchmark::kMicrosecond);

void BM_ValidityCheck_Skillset(benchmark::State& state) {
  Fixture& f = fixture();
  const bool arm_only = state.range(0) == 1;
  mujoco::WorkerScene worker = f.cluttered_worker();
  const auto& joints = arm_only ? f.arm_joints : f.all_joints;
  const auto& configs = arm_only ? f.arm_configs : f.all_configs;
  mujoco::ValidityChecker checker(*f.scene, worker.model(), worker.data(), joints);
  size_t k = 0;
  int64_t collisions = 0;
  for (auto _ : state) collisions += checker.in_collision(configs[k++ % configs.size()].data());
  state.counters["in_collision"] =
      benchmark::Counter(static_cast<double>(collisions) / state.iterations());
}
BENCHMARK(BM_ValidityCheck_Skillset)
    ->Arg(0)
    ->Arg(1)
    ->ArgName("arm_only")
    ->Unit(benchmark::kMicrosecond);

}  // namespace
