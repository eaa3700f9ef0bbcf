#include "harness/run/trial.h"

#include <chrono>
#include <cstdio>

#include "taskmatrix/core/conditions.h"
#include "taskmatrix/core/input_error.h"
#include "taskmatrix/core/motion_planning.h"

namespace taskmatrix::harness {

namespace {

// Runs one program to its end or the limit; nullopt on completion, else its failure (with
// the path through nested machines beginning with the program). An exception that escapes
// the executive (the world's, not a program's) fails the program too.
std::optional<core::Failure> run_program(core::Executive& executive, const ProgramCall& call,
                                         double limit_s) {
  int id = -1;
  try {
    id = executive.start(call.program, call.params);
  } catch (const std::invalid_argument& e) {
    return core::Failure(core::FailureCode::kInvalidInput, e.what());
  }
  try {
    executive.run(limit_s);
  } catch (const std::exception& e) {
    return core::Failure(core::FailureCode::kProgramError, call.program + ": " + e.what());
  }
  const core::Message* outcome = executive.outcome(id);
  if (!outcome) {
    executive.halt(id);
    return core::Failure(core::FailureCode::kTimeLimit,
                         call.program + " still running after " + std::to_string(limit_s) + " s");
  }
  if (outcome->type == core::MessageType::kCompleted) return std::nullopt;
  if (!outcome->failure) {
    return core::Failure(core::FailureCode::kProgramError,
                         call.program + " " + core::to_string(outcome->type));
  }
  return core::reported_by(call.program, *outcome->failure);
}

}  // namespace

core::TrialLayout draw_trial_layout(const Scenario& scenario, const core::LoadedScene& scene,
                                    std::uint64_t layout_seed, const std::string& trial_id) {
  auto fail = [&](const std::string& key, const std::string& why) -> core::InputError {
    const bool varied = key.rfind("obstacles", 0) != 0;
    const std::filesystem::path& file = varied ? scenario.variation_file : scenario.file;
    return core::InputError(file.string(), key, "cannot lay out trial " + trial_id + ": " + why,
                            line_of(scenario.key_lines, key));
  };
  core::TrialLayout layout;
  std::vector<core::StartContact> contacts;
  try {
    layout = scene.make_trial_layout(scenario.obstacles, scenario.variation, layout_seed);
    contacts = scene.start_contacts(layout);
  } catch (const core::LayoutError& e) {
    throw fail(e.key().empty() ? "obstacles" : e.key(), e.what());
  } catch (const core::InputError& e) {
    throw fail("obstacles", e.what());
  }
  const core::VariationOptions& v = scenario.variation;
  for (const core::StartContact& c : contacts) {
    const std::string key = c.obstacle                       ? "obstacles"
                            : c.robot && v.robot_start       ? "robot_start"
                            : !c.robot && !v.objects.empty() ? "objects"
                            : !v.surfaces.empty()            ? "surfaces"
                                                             : "obstacles";
    char depth[32];
    std::snprintf(depth, sizeof depth, "%.1f", c.depth_m * 1000);
    throw fail(key, "at the start " + c.first + " touches " + c.second + " (depth " + depth +
                        " mm)" + (c.robot ? ": the robot must start clear of everything" : ""));
  }
  return layout;
}

TrialResult run_trial(const Scenario& scenario, const core::LoadedScene& scene,
                      std::uint64_t layout_seed, std::uint32_t seed,
                      const core::ProgramRegistry& registry, const TrialObserver& observe,
                      const TrialOptions& trial_options) {
  const auto t0 = std::chrono::steady_clock::now();
  TrialResult result;
  result.layout = trial_options.layout ? *trial_options.layout
                                       : scene.make_trial_layout(scenario.obstacles,
                                                                 scenario.variation, layout_seed);
  core::TrialWorldOptions world_options;
  world_options.execution = scenario.execution;
  world_options.visitor_speed_mps = scenario.visitor_speed_mps;
  world_options.record_rate_hz = trial_options.record_rate_hz;
  const std::unique_ptr<core::TrialWorld> trial_world =
      scene.make_trial_world(result.layout, world_options);
  core::Skillset& skills = trial_world->skills();
  const std::unique_ptr<core::Perception> perception =
      trial_world->make_perception(scenario.perception);
  core::ExecutiveOptions options;
  options.plan.time_limit_s = scenario.plan_time_limit_s;
  options.plan.max_iterations =
      scenario.planner_budget == "iterations" ? scenario.plan_iterations : 0;
  options.seed = seed;
  const PlannerConfig* planner =
      trial_options.planner ? trial_options.planner
                            : (scenario.planners.empty() ? nullptr : &scenario.planners[0]);
  if (planner) options.plan.planner = planner->spec;
  core::Executive executive(skills, registry, perception.get(), options);

  auto finish = [&](std::optional<core::Failure> failure) {
    result.success = !failure;
    result.failure = std::move(failure);
    result.log = executive.log();
    result.series = executive.series();
    for (const core::Message& m : result.log) {
      if (m.type == core::MessageType::kPlanningStarted) continue;
      if (m.type == core::MessageType::kPlanningEnded) {
        // Only plans whose failure has more to say than its summary (every IK attempt).
        if (!m.plan || m.plan->detail.empty()) continue;
        result.events.push_back(
            {m.time, m.sender, m.program, core::to_string(m.type),
             std::string(core::to_string(m.plan->status)) + ": " + m.plan->detail, ""});
        continue;
      }
      result.events.push_back({m.time, m.sender, m.program, core::to_string(m.type), m.reason(),
                               m.failure ? m.failure->path : ""});
    }
    result.work = skills.work();
    result.sim_time_s = skills.time();
    result.removed_debris = trial_world->removed_objects();
    if (trial_options.record_rate_hz > 0) result.recording = skills.recording();
    if (observe) observe("end", *trial_world);
    result.trial_wall_s = core::seconds_since(t0);
    return result;
  };
  // Wall time inside the executive (programs, planning, IK, simulation); the rest of the
  // trial is the harness's own overhead.
  auto timed_run = [&](const ProgramCall& call) {
    const auto t = std::chrono::steady_clock::now();
    std::optional<core::Failure> failed = run_program(executive, call, scenario.time_limit_s);
    result.executive_wall_s += core::seconds_since(t);
    return failed;
  };
  for (const ProgramCall& step : scenario.setup) {
    if (const std::optional<core::Failure> failed = timed_run(step)) {
      // The set-up program's failure as a user reads it, naming the program.
      const bool names_program = !failed->path.empty();
      return finish(core::Failure(core::FailureCode::kSetupFailed,
                                  (names_program ? "" : step.program + ": ") + failed->text()));
    }
  }
  if (observe) observe("setup", *trial_world);
  const double start = skills.time();
  std::optional<core::Failure> failed = timed_run(scenario.run);
  result.duration_s = skills.time() - start;
  if (failed) return finish(std::move(failed));
  if (!scenario.success.empty()) {
    // Judged on the world: exact perception of the final state.
    core::PerceptualModel truth;
    trial_world->make_perception("ground_truth")->update(skills.time(), truth);
    const core::ConditionPtr criterion = core::parse_condition(scenario.success);
    const core::World world{skills, truth};
    if (!criterion->holds(world)) {
      const std::string why = criterion->explain(world);
      const bool whole = why.rfind(criterion->describe(), 0) == 0;
      return finish(
          core::Failure(core::FailureCode::kCriterionFalse,
                        why + (whole ? "" : " (success condition " + criterion->describe() + ")")));
    }
  }
  return finish(std::nullopt);
}

}  // namespace taskmatrix::harness
