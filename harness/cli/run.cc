// taskmatrix run SCENARIO [--out DIR] [--jobs N] ...
#include <cstdlib>
#include <iostream>
#include <sstream>

#include "harness/cli/verb.h"
#include "harness/run/run_job.h"
#include "harness/scenario/scenario.h"

namespace taskmatrix::harness::cli {
namespace {

class Run final : public Verb {
 public:
  CLI::App* add_to(CLI::App& app) override {
    CLI::App* run = app.add_subcommand(
        "run", "Run a scenario or suite: trials in parallel workers, results in a run directory");
    run->add_option("SCENARIO", options_.scenario_file, "scenario or suite YAML")->required();
    run->add_option("--out", out_, "run directory (default: results/runs/<name>)");
    run->add_option("--jobs", options_.jobs, "trials run at once (worker processes)")
        ->check(CLI::Range(1, 256))
        ->capture_default_str();
    run->add_option("--trials", options_.overrides.trials,
                    "trials per (robot, environment, planner)")
        ->check(CLI::Range(1, 100000));
    run->add_option("--seed", seed_, "planner seed base (trial k uses seed + k)")
        ->check(CLI::Range(1LL, 4294967295LL));
    run->add_option("--planners", planners_, "planners, comma separated (replaces the scenario's)");
    run->add_option("--execution", options_.overrides.execution,
                    execution_modes_text() + " (replaces the scenario's)")
        ->check(CLI::IsMember(execution_modes()));
    run->add_flag("--resume", options_.resume,
                  "keep the trials already in the run directory, run the rest");
    CLI::Option* only = run->add_option("--only", options_.only,
                                        "run one trial by its id and print its result line");
    run->add_option("--shard", shard_,
                    "I/N: run only the trials whose matrix index is I mod N (default in a Slurm "
                    "array task: SLURM_ARRAY_TASK_ID - SLURM_ARRAY_TASK_MIN of "
                    "SLURM_ARRAY_TASK_COUNT)")
        ->excludes(only);
    run->add_option("--progress", progress_,
                    "progress line on stderr: auto (on a terminal), on, off")
        ->check(CLI::IsMember({"auto", "on", "off"}))
        ->capture_default_str();
    run->add_option("--record-hz", options_.record_rate_hz,
                    "trajectory frames kept per simulated second (0: none)")
        ->check(finite_range(0.0, 1000.0))
        ->capture_default_str();
    return run;
  }

  int run(VerbContext& context) override {
    const ModelCatalog& catalog = context.catalog();
    core::ProgramRegistry& programs = context.programs();
    if (!shard_.empty()) {
      options_.shard = parse_shard(shard_, "--shard");
    } else if (options_.only.empty()) {
      if (const auto shard = slurm_array_shard(std::getenv)) {
        options_.shard = *shard;
        std::cerr << "taskmatrix: shard " << shard->index << "/" << shard->count
                  << " from SLURM_ARRAY_TASK_ID (--shard I/N overrides it)\n";
      }
    }
    options_.out = out_;
    options_.overrides.seed = static_cast<std::uint32_t>(seed_);
    if (!planners_.empty()) {
      std::stringstream in(planners_);
      for (std::string name; std::getline(in, name, ',');) {
        if (!name.empty()) options_.overrides.planners.push_back(name);
      }
    }
    options_.progress = progress_ == "on"    ? RunJobOptions::Progress::kOn
                        : progress_ == "off" ? RunJobOptions::Progress::kOff
                                             : RunJobOptions::Progress::kAuto;
    options_.command_line = context.command_line();
    const RunJobResult r = run_job(catalog, programs, options_, std::cout, std::cerr);
    if (!r.dir.empty()) {
      std::cerr << "taskmatrix: " << r.finished << " of " << r.planned << " trials in "
                << r.dir.string() << " (" << r.ran << " run now, " << r.successes << " succeeded)"
                << (r.interrupted ? "; interrupted: --resume runs the rest" : "") << "\n";
    }
    return r.interrupted ? 130 : 0;
  }

 private:
  RunJobOptions options_;
  std::string out_, planners_, progress_ = "auto", shard_;
  long long seed_ = 0;
};

}  // namespace

std::unique_ptr<Verb> run_verb() { return std::make_unique<Run>(); }

}  // namespace taskmatrix::harness::cli
