// One trial of a scenario: a robot in an environment with one obstacle layout. Makes the
// trial's world from the shared loaded scene (core/backend.h) with the layout and the visitor's
// walk,
// runs the set-up programs (each must complete), then the scenario's program within its time
// limit, and judges success on the world as it is at the end (ground-truth perception, so a
// sensor's misses cannot fake a success).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "harness/results/trial_result.h"
#include "harness/scenario/scenario.h"
#include "taskmatrix/core/backend.h"
#include "taskmatrix/core/executive.h"

namespace taskmatrix::harness {

// Called after set-up and at the end, for looking at the trial (renders).
using TrialObserver = std::function<void(const std::string& moment, const core::TrialWorld& world)>;

struct TrialOptions {
  const PlannerConfig* planner = nullptr;  // default: the scenario's first planner
  double record_rate_hz = 0;               // > 0: record the simulated state for replay
  // The trial's drawn world, if already drawn (the runner draws every trial's before forking
  // workers); default: drawn here from the scenario and the layout seed.
  const core::TrialLayout* layout = nullptr;
};

// Draws a trial's world (task variation, then obstacles: LoadedScene::make_trial_layout) and
// checks it: at its start the robot touches nothing and no two bodies interpenetrate by more
// than 1 mm. Throws core::InputError naming the scenario file, the line and key at fault, and
// the trial.
core::TrialLayout draw_trial_layout(const Scenario& scenario, const core::LoadedScene& scene,
                                    std::uint64_t layout_seed, const std::string& trial_id);

TrialResult run_trial(const Scenario& scenario, const core::LoadedScene& scene,
                      std::uint64_t layout_seed, std::uint32_t seed,
                      const core::ProgramRegistry& registry, const TrialObserver& observe = nullptr,
                      const TrialOptions& options = {});

}  // namespace taskmatrix::harness
