// Collision-free motion planning with OMPL's geometric planners over a set of robot joints,
// validity from ValidityChecker, motions checked at a configurable resolution, path
// simplification bounded by work, paths within the joint limits, and a status in which only an
// exact solution succeeds.
//
// Determinism: OMPL seeds every RNG from one process-global generator. `plan` reseeds it
// with the request's seed and holds a process-wide lock while planning, so the same request
// and seed give the same path bit for bit whatever was planned before in the process. Under
// an iteration budget (PlanOptions::max_iterations) the result does not depend on the machine
// or its load either: simplification is bounded by rounds, PRM runs in one thread
// (OMPL's polls for solutions from a second thread), and the clock bounds are safety nets
// whose firing the result reports (planning_hit_time_limit, simplification_hit_time_limit).
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "taskmatrix/core/planning_types.h"
#include "taskmatrix/mujoco/scene.h"
#include "taskmatrix/mujoco/validity_checker.h"

namespace taskmatrix::mujoco {

using core::PlannerSpec;
using core::PlanOptions;

// Planner names accepted by PlannerSpec, sorted.
std::vector<std::string> planner_names();
// Whether OMPL's planner `name` optimizes its path (PlannerSpecs::optimizingPaths: RRTstar,
// PRM, BITstar, ...): with the default path-length objective, whose cost threshold no path
// meets, it plans until its time limit. False for an unknown name.
bool planner_optimizes_paths(const std::string& name);
// "" if `spec` names a known planner and every parameter exists and accepts its value (checked
// on a planner made for a small unit space); otherwise what is wrong.
std::string check_planner_spec(const PlannerSpec& spec);

class MotionPlanner {
 public:
  // Plans for `joints` (robot hinge/slide joint ids) on model `m` and data `d` (its qpos is
  // the start; every other joint stays where it is), with `attachments` held. The start, and
  // states within the endpoint radius of it, may touch `touch_geoms` up to kTouchDepth of
  // penetration (PlanOptions::may_touch): a plan may start against what a hand let go of.
  MotionPlanner(const Scene& scene, const mjModel* m, mjData* d, std::vector<int> joints,
                std::vector<Attachment> attachments = {}, std::vector<int> touch_geoms = {});
  static constexpr double kTouchDepth = 0.005;
  // The same on a worker's model and data.
  MotionPlanner(const Scene& scene, WorkerScene& worker, std::vector<int> joints);

  // From the worker's current configuration to one of `goals`, tried in the order given.
  core::PlanResult plan(const std::vector<std::vector<double>>& goals, const PlanOptions& options);

 private:
  const Scene& scene_;
  const mjModel* m_;
  mjData* d_;
  std::vector<int> joints_;
  std::vector<Attachment> attachments_;
  std::vector<int> touch_geoms_;
};

}  // namespace taskmatrix::mujoco
