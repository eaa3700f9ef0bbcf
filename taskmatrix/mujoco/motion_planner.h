// Collision-free motion planning with OMPL's geometric planners over a set of robot joints,
// validity from ValidityChecker, motions checked at a configurable resolution, path
// simplification bounded by time, and a status in which only an exact solution succeeds.
//
// Determinism: OMPL seeds every RNG from one process-global generator. `plan` reseeds it
// with the request's seed and holds a process-wide lock while planning, so the same request
// and seed give the same path bit for bit whatever was planned before in the process.
// Planners that run until their time limit (RRTstar, PRM, BITstar, ...) are deterministic
// only when stopped by `max_iterations` rather than by the clock.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "taskmatrix/core/planning_types.h"
#include "taskmatrix/mujoco/scene.h"

namespace taskmatrix::mujoco {

struct PlannerSpec {
  std::string name = "RRTConnect";
  std::map<std::string, std::string> params;  // OMPL parameter names, e.g. range: "0.5"
};

struct PlanOptions {
  PlannerSpec planner;
  double time_limit_s = 5.0;
  unsigned max_iterations = 0;       // > 0: also stop after this many planner iterations
  double simplify_time_s = 0.25;     // bound on simplification; 0 skips it
  double motion_resolution = 0.005;  // fraction of the space's extent between checked states
  std::uint32_t seed = 1;            // > 0
};

// Planner names accepted by PlannerSpec, sorted.
std::vector<std::string> planner_names();

class MotionPlanner {
 public:
  // Plans for `joints` (robot hinge/slide joint ids); every other joint stays where the
  // worker's data has it.
  MotionPlanner(const Scene& scene, WorkerScene& worker, std::vector<int> joints);

  // From the worker's current configuration to one of `goals`, tried in the order given.
  core::PlanResult plan(const std::vector<std::vector<double>>& goals, const PlanOptions& options);

 private:
  const Scene& scene_;
  WorkerScene& worker_;
  std::vector<int> joints_;
};

}  // namespace taskmatrix::mujoco
