// One trial of a scenario: a robot in an environment with one obstacle layout. Builds a
// worker skillset on the shared compiled scene, applies the layout and the visitor's walk,
// runs the set-up programs (each must complete), then the scenario's program within its time
// limit, and judges success on the world as it is at the end (ground-truth perception, so a
// sensor's misses cannot fake a success).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "harness/scenario.h"
#include "taskmatrix/core/executive.h"
#include "taskmatrix/mujoco/mujoco_skillset.h"

namespace taskmatrix::harness {

// A message of the trial's executive other than planning (started, completed, failed,
// halted), i.e. the programs' and state machines' events, with simulated time.
struct TrialEvent {
  double time_s = 0;
  int sender = -1;
  std::string program;
  std::string type;
  std::string reason;
  std::string path;  // of a state machine's failure (core::Failure::path)
};

struct TrialResult {
  bool success = false;
  // Why the trial failed (nullopt when it succeeded): the program's failure, its path beginning
  // with the program when it happened inside state machines ("fetch > pickup(approach) >
  // reach"); kSetupFailed, kTimeLimit (still running at the limit), kCriterionFalse (the
  // program completed but the success condition does not hold: the detail says which clause
  // and what was measured), kInvalidInput, kProgramError (a program threw; the trial goes on,
  // the worker lives).
  std::optional<core::Failure> failure;
  double duration_s = 0;    // simulated seconds of the scenario's program
  double sim_time_s = 0;    // simulated seconds of the whole trial, set-up included
  double trial_wall_s = 0;  // wall clock inside run_trial, set-up of the skillset included
  // Wall clock inside the executive: set-up programs and the program (their planning, IK,
  // queries, logic and the simulation). trial_wall_s minus this is the trial's set-up.
  double executive_wall_s = 0;
  mujoco::WorkRecord work;  // every plan call, IK, checks, the executed motion
  std::vector<TrialEvent> events;
  std::vector<core::Message> log;  // every message, set-up included
  std::vector<core::RecordedSeries> series;
  mujoco::StateRecording recording;  // empty unless asked for
  std::vector<std::string> removed_debris;
  core::TrialLayout layout;  // the drawn world: task variation and obstacles
};

// The trial record's texts: "success" or the failure's code ("ik_failure"); the failure as a
// user reads it ("fetch > pickup(approach) > reach: ik_failure: ..."), cut at 600 characters
// (the events hold the whole text), "" on success.
std::string trial_status(const TrialResult& result);
std::string trial_failure_reason(const TrialResult& result);

// Called after set-up and at the end, for looking at the trial (renders).
using TrialObserver =
    std::function<void(const std::string& moment, const mujoco::MujocoSkillset& skills)>;

struct TrialOptions {
  const PlannerConfig* planner = nullptr;  // default: the scenario's first planner
  double record_rate_hz = 0;               // > 0: record the simulated state for replay
  // The trial's drawn world, if already drawn (the runner draws every trial's before forking
  // workers); default: drawn here from the scenario and the layout seed.
  const core::TrialLayout* layout = nullptr;
};

// Draws a trial's world (task variation, then obstacles: Scene::make_trial_layout) and checks
// it in `worker` (a copy of the scene): at its start the robot touches nothing and no two
// bodies interpenetrate by more than 1 mm. Throws core::InputError naming the scenario file,
// the line and key at fault, and the trial. Leaves the layout applied to `worker`.
core::TrialLayout draw_trial_layout(const Scenario& scenario, mujoco::WorkerScene& worker,
                                    std::uint64_t layout_seed, const std::string& trial_id);

TrialResult run_trial(const Scenario& scenario, std::shared_ptr<const mujoco::Scene> scene,
                      std::uint64_t layout_seed, std::uint32_t seed,
                      const core::ProgramRegistry& registry, const TrialObserver& observe = nullptr,
                      const TrialOptions& options = {});

}  // namespace taskmatrix::harness
