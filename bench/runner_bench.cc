// The scenario runner's cost, on a fixed 16-trial suite (bench/runner_suite.yaml), in the
// same run, in each execution mode:
//   BM_RunSuite/jobs:N/mode:M   taskmatrix run with N worker processes, every scenario's
//                        execution mode replaced (M = 0: physics_unpruned, every contact
//                        computed as before contact pruning; 1: physics; 2: kinematic), trial
//                        files, summaries, OMPL log and trajectories written as in a user's run.
//                        Counters:
//     cpu_s_per_trial     CPU seconds (user + system) of the run's worker processes per finished
//                         trial: the cost of a trial, whatever else the machine runs
//     trials_per_s        finished trials per second of the run's wall time
//     overhead_fraction   sum over trials of (worker wall - time inside the executive) over
//                         the sum of worker wall times: what the harness adds per trial
//                         (fork, worker skillset and layout, success check, result line,
//                         trajectory file)
//     work_fraction       (planning + simplification + simulation stepping) over the worker wall
//                         time: the raw MuJoCo/OMPL work in a trial
//     ik_fraction         the project's own IK loop (programs' IK and IK for pose goals) over the
//                         worker wall time, reported apart from the raw work
//     sim_speed           simulated seconds per second of stepping (simulation, feed-forward,
//                         the visitor, held objects)
//     contacts_per_pass   contacts per collision detection (per timestep in physics, per
//                         control period in kinematic mode)
//     cpu_s_per_sim_s     the workers' CPU seconds per simulated second of the trials (everything
//                         a trial does: planning, IK, stepping, the harness)
//     succeeded           trials that succeeded
//   BM_RunSuite_RawStepping  the raw MuJoCo baseline in the same run: the same 16 trials' worlds
//                        (robot, room, drawn layout, start state with the actuators holding it)
//                        stepped by plain mj_step, nothing pruned, for 2 simulated seconds each.
//                        Counters cpu_s_per_sim_s (stepping only), sim_speed and
//                        contacts_per_pass (MuJoCo's contacts per mj_step), as above.
// Two jobs should give at least 1.6x the trials per second of one (2 cores).
#include <benchmark/benchmark.h>
#include <sys/resource.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <map>
#include <sstream>

#include "harness/results/trial_record.h"
#include "harness/run/run_job.h"
#include "harness/run/trial.h"
#include "harness/scenario/model_catalog.h"
#include "harness/scenario/trial_matrix.h"
#include "taskmatrix/mujoco/mujoco_backend.h"
#include "taskmatrix/programs/primitives.h"

namespace {

using namespace taskmatrix;

double cpu_s(int who) {
  rusage u{};
  getrusage(who, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

void BM_RunSuite(benchmark::State& state) {
  const harness::ModelCatalog catalog(TASKMATRIX_BENCH_ROOT);
  char tmpl[] = "/tmp/taskmatrix_bench_run_XXXXXX";
  const std::filesystem::path out = mkdtemp(tmpl);
  harness::RunJobOptions options;
  options.scenario_file =
      std::filesystem::path(TASKMATRIX_BENCH_ROOT) / "bench" / "runner_suite.yaml";
  options.out = out;
  options.jobs = static_cast<int>(state.range(0));
  constexpr const char* kModes[] = {"physics_unpruned", "physics", "kinematic"};
  options.overrides.execution = kModes[state.range(1)];
  options.progress = harness::RunJobOptions::Progress::kOff;
  double trials = 0, seconds = 0, cpu = 0, wall = 0, overhead = 0, work = 0, ik = 0;
  double sim = 0, stepping = 0, contacts = 0, passes = 0, succeeded = 0;
  for (auto _ : state) {
    core::ProgramRegistry registry;
    programs::register_programs(registry);
    std::ostringstream sink;
    const double cpu0 = cpu_s(RUSAGE_CHILDREN);
    const auto t0 = std::chrono::steady_clock::now();
    const harness::RunJobResult r = harness::run_job(catalog, registry, options, sink, sink);
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    cpu += cpu_s(RUSAGE_CHILDREN) - cpu0;
    trials += r.finished;
    for (const nlohmann::json& t : harness::read_trials_file(out / "trials.jsonl").trials) {
      wall += t["wall_time_s"].get<double>();
      overhead += t["overhead_s"].get<double>();
      work += t["planning_time_s"].get<double>() + t["simplification_time_s"].get<double>() +
              t["stepping_wall_s"].get<double>();
      ik += t["ik_time_s"].get<double>();
      sim += t["sim_time_s"].get<double>();
      stepping += t["stepping_wall_s"].get<double>();
      passes += t["control_periods"].get<double>();
      if (t["contacts_per_pass"].is_number()) {
        contacts += t["contacts_per_pass"].get<double>() * t["control_periods"].get<double>();
      }
      succeeded += t["success"].get<bool>() ? 1 : 0;
    }
  }
  std::filesystem::remove_all(out);
  const double n = static_cast<double>(state.iterations());
  state.counters["cpu_s_per_trial"] = cpu / trials;
  state.counters["trials_per_s"] = trials / seconds;
  state.counters["overhead_fraction"] = overhead / wall;
  state.counters["work_fraction"] = work / wall;
  state.counters["ik_fraction"] = ik / wall;
  state.counters["sim_speed"] = sim / stepping;
  state.counters["contacts_per_pass"] = contacts / passes;
  state.counters["cpu_s_per_sim_s"] = cpu / sim;
  state.counters["succeeded"] = succeeded / n;
}
BENCHMARK(BM_RunSuite)
    ->ArgNames({"jobs", "mode"})
    ->Args({1, 0})
    ->Args({1, 1})
    ->Args({1, 2})
    ->Args({2, 1})
    ->Args({2, 2})
    ->Iterations(1)
    ->Unit(benchmark::kSecond)
    ->UseRealTime();

void BM_RunSuite_RawStepping(benchmark::State& state) {
  const harness::ModelCatalog catalog(TASKMATRIX_BENCH_ROOT);
  core::ProgramRegistry registry;
  programs::register_programs(registry);
  const harness::RunPlan plan = harness::load_run_plan(
      std::filesystem::path(TASKMATRIX_BENCH_ROOT) / "bench" / "runner_suite.yaml", catalog,
      registry);
  constexpr double kSimulatedS = 2.0;
  std::map<std::string, std::shared_ptr<const mujoco::Scene>> scenes;
  double cpu = 0, wall = 0, sim = 0, contacts = 0, steps = 0;
  for (auto _ : state) {
    for (const harness::TrialSpec& spec : harness::trial_matrix(plan)) {
      std::shared_ptr<const mujoco::Scene>& scene = scenes[spec.robot + "/" + spec.environment];
      if (!scene) {
        scene = mujoco::Scene::load(catalog.robot_dir(spec.robot),
                                    catalog.environment_dir(spec.environment));
      }
      // The trial's world and start state as its worker has them, nothing pruned.
      const core::TrialLayout layout =
          harness::draw_trial_layout(plan.scenarios[static_cast<size_t>(spec.scenario)],
                                     mujoco::MujocoLoadedScene(scene), spec.layout_seed, spec.id);
      mujoco::SimulationOptions options;
      options.pruning = {false, false};
      options.sparse_jacobian = false;
      options.candidate_pairs = false;
      mujoco::MujocoSkillset skills(scene, options);
      skills.apply_layout(layout);
      const mjModel* m = skills.model();
      mujoco::DataPtr d = mujoco::make_data(m);
      mju_copy(d->qpos, skills.sim_data()->qpos, m->nq);
      mju_copy(d->ctrl, skills.sim_data()->ctrl, m->nu);
      mj_forward(m, d.get());
      const double cpu0 = cpu_s(RUSAGE_SELF);
      const auto t0 = std::chrono::steady_clock::now();
      while (d->time < kSimulatedS) {
        mj_step(m, d.get());
        contacts += d->ncon;
        steps += 1;
      }
      wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      cpu += cpu_s(RUSAGE_SELF) - cpu0;
      sim += d->time;
    }
  }
  state.counters["cpu_s_per_sim_s"] = cpu / sim;
  state.counters["sim_speed"] = sim / wall;
  state.counters["contacts_per_pass"] = contacts / steps;
}
BENCHMARK(BM_RunSuite_RawStepping)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();

}  // namespace
