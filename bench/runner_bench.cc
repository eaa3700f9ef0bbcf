// The scenario runner's cost, on a fixed 16-trial suite (bench/runner_suite.yaml), in the
// same run:
//   BM_RunSuite/jobs:N   taskmatrix run with N worker processes (trial files, summaries,
//                        OMPL log and trajectories written as in a user's run). Counters:
//     trials_per_s        finished trials per second of the run's wall time
//     overhead_fraction   sum over trials of (worker wall - time inside the executive) over
//                         the sum of worker wall times: what the harness adds per trial
//                         (fork, worker skillset and layout, success check, result line,
//                         trajectory file)
//     work_fraction       (planning + simplification + IK + simulation stepping) over the
//                         worker wall time: the raw MuJoCo/OMPL work in a trial
// Two jobs should give at least 1.6x the trials per second of one (2 cores).
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <filesystem>
#include <sstream>

#include "harness/model_catalog.h"
#include "harness/run_job.h"
#include "harness/trial_record.h"
#include "taskmatrix/programs/primitives.h"

namespace {

using namespace taskmatrix;

void BM_RunSuite(benchmark::State& state) {
  const harness::ModelCatalog catalog(TASKMATRIX_BENCH_ROOT);
  char tmpl[] = "/tmp/taskmatrix_bench_run_XXXXXX";
  const std::filesystem::path out = mkdtemp(tmpl);
  harness::RunJobOptions options;
  options.scenario_file =
      std::filesystem::path(TASKMATRIX_BENCH_ROOT) / "bench" / "runner_suite.yaml";
  options.out = out;
  options.jobs = static_cast<int>(state.range(0));
  options.progress = harness::RunJobOptions::Progress::kOff;
  double trials = 0, seconds = 0, wall = 0, overhead = 0, work = 0;
  for (auto _ : state) {
    core::ProgramRegistry registry;
    programs::register_programs(registry);
    std::ostringstream sink;
    const auto t0 = std::chrono::steady_clock::now();
    const harness::RunJobResult r = harness::run_job(catalog, registry, options, sink, sink);
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    trials += r.finished;
    for (const nlohmann::json& t : harness::read_trials_file(out / "trials.jsonl").trials) {
      wall += t["wall_time_s"].get<double>();
      overhead += t["overhead_s"].get<double>();
      work += t["planning_time_s"].get<double>() + t["simplification_time_s"].get<double>() +
              t["ik_time_s"].get<double>() + t["stepping_wall_s"].get<double>();
    }
  }
  std::filesystem::remove_all(out);
  state.counters["trials_per_s"] = trials / seconds;
  state.counters["overhead_fraction"] = overhead / wall;
  state.counters["work_fraction"] = work / wall;
}
BENCHMARK(BM_RunSuite)
    ->ArgName("jobs")
    ->Arg(1)
    ->Arg(2)
    ->Iterations(1)
    ->Unit(benchmark::kSecond)
    ->UseRealTime();

}  // namespace
