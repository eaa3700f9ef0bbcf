#include "harness/run/check_robot.h"

#include <algorithm>
#include <map>
#include <ostream>
#include <sstream>

#include "harness/backends/backends.h"
#include "harness/results/summary.h"
#include "harness/results/trial_record.h"
#include "harness/run/run_job.h"
#include "taskmatrix/core/input_error.h"

namespace taskmatrix::harness {

namespace {

using core::RobotFinding;

// One table cell: no line breaks, no column separators, at most `limit` characters.
std::string cell(std::string text, size_t limit = 400) {
  std::replace(text.begin(), text.end(), '\n', ' ');
  std::replace(text.begin(), text.end(), '|', '/');
  if (text.size() > limit) text = text.substr(0, limit - 3) + "...";
  return text;
}

std::string quick_run_environment(const ModelCatalog& catalog, const std::string& asked) {
  if (!asked.empty()) {
    catalog.environment_dir(asked);  // throws for an unknown name, listing the known ones
    return asked;
  }
  const std::vector<std::string> envs = catalog.environments();
  if (envs.empty()) throw core::InputError(catalog.root().string(), "", "no environments");
  return std::find(envs.begin(), envs.end(), "kitchen") != envs.end() ? "kitchen" : envs.front();
}

}  // namespace

int run_check_robot(const ModelCatalog& catalog, core::ProgramRegistry& registry,
                    const CheckRobotOptions& options, std::ostream& out, std::ostream& err) {
  const std::filesystem::path robot_dir = catalog.robot_dir(options.robot);  // throws if unknown
  const std::string environment = quick_run_environment(catalog, options.environment);
  out << "check-robot " << options.robot << ": " << (robot_dir / "profile.yaml").string()
      << "\n\n| check | result | finding |\n|---|---|---|\n";

  std::vector<RobotFinding> findings;
  std::vector<std::shared_ptr<const core::LoadedScene>> scenes;
  std::shared_ptr<const core::LoadedScene> home;
  for (const std::string& env : catalog.environments()) {
    try {
      scenes.push_back(backend().load(robot_dir, catalog.environment_dir(env)));
    } catch (const core::InputError& e) {
      findings.push_back(
          {RobotFinding::Level::kError, "load", std::string("in ") + env + ": " + e.what()});
      break;
    }
    if (env == environment) home = scenes.back();
  }
  if (findings.empty()) {
    findings.push_back({RobotFinding::Level::kOk, "load",
                        "compiles with every environment (" + std::to_string(scenes.size()) +
                            "); profile keys and names, joint limits, postures, canned motions "
                            "and the head camera convention hold"});
    for (RobotFinding& f : backend().check_robot(*home, scenes)) findings.push_back(std::move(f));
  }
  int errors = 0, warnings = 0;
  for (const RobotFinding& f : findings) {
    errors += f.level == RobotFinding::Level::kError;
    warnings += f.level == RobotFinding::Level::kWarning;
    out << "| " << f.check << " | " << core::to_string(f.level) << " | " << cell(f.message)
        << " |\n";
  }
  out << "\nLint: " << errors << (errors == 1 ? " error, " : " errors, ") << warnings
      << (warnings == 1 ? " warning" : " warnings") << ".\n";
  if (errors > 0) {
    out << "Fix the errors (file: key above) and run again; the programs were not run.\n";
    return kCheckRobotLintError;
  }
  if (!options.run) return 0;

  RunJobOptions run;
  // The default suite under the models' root, else the built-in one (a root that holds a
  // user's models alone): its scenarios run on the models of this root.
  const std::filesystem::path suite =
      std::filesystem::path("scenarios") / "suites" / "default.yaml";
  run.scenario_file = catalog.root() / suite;
  if (!std::filesystem::is_regular_file(run.scenario_file)) {
    run.scenario_file = ModelCatalog::built_in_root() / suite;
  }
  if (!std::filesystem::is_regular_file(run.scenario_file)) {
    throw core::InputError((catalog.root() / suite).string(), "",
                           "missing, and so is " + run.scenario_file.string() +
                               ": the quick run takes the twelve program scenarios from the "
                               "default suite (or pass --no-run)");
  }
  run.out = options.out.empty() ? catalog.root() / "results" / "runs" /
                                      ("check-robot-" + options.robot + "-" + environment)
                                : options.out;
  run.jobs = options.jobs;
  run.overrides.trials = 1;
  run.overrides.robots = {options.robot};
  run.overrides.environments = {environment};
  run.progress = RunJobOptions::Progress::kAuto;
  out << "\nThe twelve programs once in " << environment << " (" << run.scenario_file.string()
      << ", its first layout; the run is in " << run.out.string() << "):\n\n"
      << std::flush;
  std::ostringstream summary;  // the run's summary.md is in the run directory
  const RunJobResult result = run_job(catalog, registry, run, summary, err);

  // In the suite's order (the plan is not loaded again: the registry already holds its
  // inline machines).
  std::map<std::string, size_t> order;
  for (size_t i = 0; i < result.scenarios.size(); ++i) order[result.scenarios[i]] = i;
  std::vector<nlohmann::json> trials = read_trials_file(result.dir / "trials.jsonl").trials;
  std::stable_sort(trials.begin(), trials.end(), [&](const auto& a, const auto& b) {
    return order[a.value("scenario", "")] < order[b.value("scenario", "")];
  });
  out << "| program | status | simulated s | wall s | failure reason |\n|---|---|---|---|---|\n";
  int failed = 0;
  for (const nlohmann::json& t : trials) {
    const bool ok = t.value("success", false);
    failed += !ok;
    auto number = [&](const char* key) {
      return t.contains(key) && t[key].is_number() ? format_number("%.1f", t[key].get<double>())
                                                   : std::string("-");
    };
    out << "| " << t.value("scenario", "?") << " | " << t.value("status", "?") << " | "
        << number("duration_s") << " | " << number("wall_time_s") << " | "
        << cell(t.value("failure_reason", ""), 300) << " |\n";
  }
  out << "\nPrograms: " << result.successes << " of " << result.finished << " succeeded"
      << (result.interrupted ? " (interrupted)" : "") << ".\n";
  if (result.interrupted) return 130;
  return failed > 0 ? kCheckRobotProgramFailed : 0;
}

}  // namespace taskmatrix::harness
