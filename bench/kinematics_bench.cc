// Forward and inverse kinematics of tallbot's left palm (site l_palm, the 7-joint left arm) in
// the kitchen with 12 obstacles (layout seed 3), raw MuJoCo against ours, in the same run, on
// 16 stored configurations drawn once with a fixed seed within the arm's joint limits and free
// of collisions; their palm poses are the IK targets, so every target is reachable:
//   BM_FK_Raw        write the arm's joints into a worker's qpos, mj_kinematics, read the
//                    site's position and rotation matrix: the least any FK can cost
//   BM_FK_Skillset   MujocoSkillset::frame_pose_at({"left_arm"}, q, "l_palm") as task programs
//                    call it (checks, copy of the simulation into the query data, kinematics,
//                    frame lookup by name, a Pose with a quaternion); one configuration per
//                    iteration, cycling through the 16
//   BM_IK_Raw        a plain damped-least-squares loop on MuJoCo (mj_kinematics, mj_comPos,
//                    mj_jacSite, MuJoCo's Cholesky on J J^T + lambda^2 I) from the rest
//                    posture: full pose, lambda 0.05, steps capped at 0.3 rad, clamped to limits,
//                    at most 150 iterations, 1 mm and 1 degree; one start, no collision checks
//   BM_IK_Skillset   mujoco::solve_ik (kinematics.h) on the same targets from the same start:
//     /same_as_raw       with the raw loop's settings (restarts 0, collision_free false,
//                        stall_iterations 0): the same iterations, so the ratio is the cost of
//                        our implementation (kinematics of the chain's bodies only, an analytic
//                        Jacobian)
//     /program_defaults  with core::IkOptions' defaults as task programs use them (up to 30
//                        seeded random restarts from the current configuration outwards, each
//                        stopped when its error stalls; converged solutions collision-checked)
// One IK iteration solves all 16 targets. Counters (exact: the same in every run):
//   solved         targets solved per iteration (of 16)
//   ik_iterations  damped-least-squares iterations per iteration, over the 16 targets
#include <benchmark/benchmark.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>

#include "harness/scenario/model_catalog.h"
#include "taskmatrix/mujoco/kinematics.h"
#include "taskmatrix/mujoco/mujoco_skillset.h"
#include "taskmatrix/mujoco/validity_checker.h"

namespace {

using namespace taskmatrix;

constexpr int kTargets = 16;
constexpr int kMaxIterations = 150;
constexpr double kPositionTolerance = 1e-3;          // m
constexpr double kOrientationTolerance = 0.0174533;  // rad (1 degree)
constexpr double kDamping = 0.05;
constexpr double kMaxStep = 0.3;  // rad
constexpr char kFrame[] = "l_palm";

struct Fixture {
  std::shared_ptr<const mujoco::Scene> scene;
  const mujoco::ChainIndex* arm = nullptr;
  int site = -1;
  std::vector<std::vector<double>> configs;  // kTargets, collision-free, within limits
  std::vector<core::Pose> targets;           // l_palm at configs[k]

  // A fresh worker with the benchmark's 12 obstacles (layout seed 3), at the start.
  mujoco::WorkerScene worker() const {
    mujoco::WorkerScene w(scene);
    w.apply_layout(scene->make_layout(12, 3));
    w.reset_to_start();
    return w;
  }

  Fixture() {
    const harness::ModelCatalog catalog(TASKMATRIX_BENCH_ROOT);
    scene = mujoco::Scene::load(catalog.robot_dir("tallbot"), catalog.environment_dir("kitchen"));
    arm = &scene->chain("left_arm");
    site = mj_name2id(scene->model(), mjOBJ_SITE, kFrame);
    mujoco::WorkerScene w = worker();
    const mjModel* m = w.model();
    mjData* d = w.data();
    mujoco::ValidityChecker checker(*scene, m, d, arm->joints);
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(0, 1);
    while (static_cast<int>(configs.size()) < kTargets) {
      std::vector<double> q(arm->joints.size());
      for (size_t i = 0; i < q.size(); ++i)
        q[i] = arm->lower[i] + (arm->upper[i] - arm->lower[i]) * u(rng);
      if (checker.in_collision(q.data())) continue;
      for (size_t i = 0; i < q.size(); ++i) d->qpos[arm->qpos_adr[i]] = q[i];
      mj_kinematics(m, d);
      core::Pose pose;
      const double* p = d->site_xpos + 3 * site;
      const double* r = d->site_xmat + 9 * site;
      pose.position = Eigen::Vector3d(p[0], p[1], p[2]);
      Eigen::Matrix3d rot;
      rot << r[0], r[1], r[2], r[3], r[4], r[5], r[6], r[7], r[8];
      pose.orientation = Eigen::Quaterniond(rot).normalized();
      configs.push_back(q);
      targets.push_back(pose);
    }
  }
};

const Fixture& fixture() {
  static const Fixture f;
  return f;
}

void BM_FK_Raw(benchmark::State& state) {
  const Fixture& f = fixture();
  mujoco::WorkerScene worker = f.worker();
  const mjModel* m = worker.model();
  mjData* d = worker.data();
  size_t k = 0;
  for (auto _ : state) {
    const std::vector<double>& q = f.configs[k++ % f.configs.size()];
    for (size_t i = 0; i < q.size(); ++i) d->qpos[f.arm->qpos_adr[i]] = q[i];
    mj_kinematics(m, d);
    benchmark::DoNotOptimize(d->site_xpos[3 * f.site]);
    benchmark::DoNotOptimize(d->site_xmat[9 * f.site]);
  }
}
BENCHMARK(BM_FK_Raw)->Unit(benchmark::kMicrosecond);

void BM_FK_Skillset(benchmark::State& state) {
  const Fixture& f = fixture();
  mujoco::MujocoSkillset skills(f.scene);
  skills.apply_layout(f.scene->make_layout(12, 3));
  skills.reset();
  const std::vector<std::string> chains = {"left_arm"};
  size_t k = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(
        skills.frame_pose_at(chains, f.configs[k++ % f.configs.size()], kFrame));
  }
}
BENCHMARK(BM_FK_Skillset)->Unit(benchmark::kMicrosecond);

// The raw damped-least-squares loop; returns whether it converged, counts iterations.
bool raw_ik(const mjModel* m, mjData* d, const mujoco::ChainIndex& arm, int site,
            const std::vector<double>& start, const core::Pose& target, long& iterations) {
  constexpr int kMaxJoints = 16;
  const int n = static_cast<int>(arm.joints.size());
  std::array<double, kMaxJoints> q{}, dq{};
  std::array<int, kMaxJoints> dof{};
  for (int i = 0; i < n; ++i) {
    q[i] = std::clamp(start[i], arm.lower[i], arm.upper[i]);
    dof[i] = m->jnt_dofadr[arm.joints[i]];
  }
  const double goal_pos[3] = {target.position.x(), target.position.y(), target.position.z()};
  const double goal_quat[4] = {target.orientation.w(), target.orientation.x(),
                               target.orientation.y(), target.orientation.z()};
  std::vector<double> jacp(3 * m->nv), jacr(3 * m->nv);
  for (int it = 0; it < kMaxIterations; ++it) {
    ++iterations;
    for (int i = 0; i < n; ++i) d->qpos[arm.qpos_adr[i]] = q[i];
    mj_kinematics(m, d);
    mj_comPos(m, d);
    double err[6], now_quat[4], now_inv[4], diff[4];
    mju_sub3(err, goal_pos, d->site_xpos + 3 * site);
    mju_mat2Quat(now_quat, d->site_xmat + 9 * site);
    mju_negQuat(now_inv, now_quat);
    mju_mulQuat(diff, goal_quat, now_inv);  // world-frame rotation from now to the goal
    if (diff[0] < 0) mju_scl(diff, diff, -1, 4);
    mju_quat2Vel(err + 3, diff, 1);
    if (mju_norm3(err) <= kPositionTolerance && mju_norm3(err + 3) <= kOrientationTolerance)
      return true;
    mj_jacSite(m, d, jacp.data(), jacr.data(), site);
    double jac[6 * kMaxJoints], jjt[36], y[6];
    for (int r = 0; r < 3; ++r) {
      for (int i = 0; i < n; ++i) {
        jac[r * n + i] = jacp[r * m->nv + dof[i]];
        jac[(3 + r) * n + i] = jacr[r * m->nv + dof[i]];
      }
    }
    mju_mulMatMatT(jjt, jac, jac, 6, n, 6);
    for (int r = 0; r < 6; ++r) jjt[7 * r] += kDamping * kDamping;
    mju_cholFactor(jjt, 6, mjMINVAL);
    mju_cholSolve(y, jjt, err, 6);
    mju_mulMatTVec(dq.data(), jac, y, 6, n);
    double step = 0;
    for (int i = 0; i < n; ++i) step = std::max(step, std::abs(dq[i]));
    const double scale = step > kMaxStep ? kMaxStep / step : 1.0;
    for (int i = 0; i < n; ++i) q[i] = std::clamp(q[i] + scale * dq[i], arm.lower[i], arm.upper[i]);
  }
  return false;
}

void BM_IK_Raw(benchmark::State& state) {
  const Fixture& f = fixture();
  mujoco::WorkerScene worker = f.worker();
  const mjModel* m = worker.model();
  mjData* d = worker.data();
  std::vector<double> rest(f.arm->joints.size());
  for (size_t i = 0; i < rest.size(); ++i) rest[i] = d->qpos[f.arm->qpos_adr[i]];
  double solved = 0;
  long iterations = 0;
  for (auto _ : state) {
    for (const core::Pose& target : f.targets)
      solved += raw_ik(m, d, *f.arm, f.site, rest, target, iterations);
  }
  state.counters["solved"] = benchmark::Counter(solved / state.iterations());
  state.counters["ik_iterations"] =
      benchmark::Counter(static_cast<double>(iterations) / state.iterations());
}
BENCHMARK(BM_IK_Raw)->Unit(benchmark::kMillisecond);

void BM_IK_Skillset(benchmark::State& state, bool program_defaults) {
  const Fixture& f = fixture();
  mujoco::WorkerScene worker = f.worker();
  core::IkOptions options;  // the defaults: full pose, 1 mm, 1 degree, 150 iterations
  if (!program_defaults) {
    options.restarts = 0;
    options.collision_free = false;
    options.stall_iterations = 0;
  }
  double solved = 0, iterations = 0;
  for (auto _ : state) {
    for (const core::Pose& target : f.targets) {
      const core::IkResult r =
          mujoco::solve_ik(*f.scene, worker, f.arm->joints, kFrame, target, options);
      solved += r.status == core::IkStatus::kSolved;
      iterations += r.iterations;
    }
  }
  state.counters["solved"] = benchmark::Counter(solved / state.iterations());
  state.counters["ik_iterations"] = benchmark::Counter(iterations / state.iterations());
}
BENCHMARK_CAPTURE(BM_IK_Skillset, same_as_raw, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_IK_Skillset, program_defaults, true)->Unit(benchmark::kMillisecond);

}  // namespace
