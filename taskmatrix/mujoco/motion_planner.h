// Collision-free motion planning over a set of robot joints with any registered planner
// (taskmatrix/core/motion_planning.h; built-in: OMPL's, taskmatrix/ompl, and the project's,
// taskmatrix/planners): this backend checks the request (sizes, NaN, limits, a start in
// collision), poses the problem with ValidityChecker's verdicts and the clearance it asks
// for, counts the collision checks, keeps paths within the joint limits, certifies the path
// returned between the states the planner checked (planning again with closer checks where it
// touches something there), and gives a status in which only an exact solution succeeds.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "taskmatrix/core/planning_types.h"
#include "taskmatrix/mujoco/scene.h"
#include "taskmatrix/mujoco/validity_checker.h"

namespace taskmatrix::mujoco {

using core::PlannerSpec;
using core::PlanOptions;

class MotionPlanner {
 public:
  // Plans for `joints` (robot hinge/slide joint ids) on model `m` and data `d` (its qpos is
  // the start; every other joint stays where it is), with `attachments` held. A start in
  // contact, and states within the endpoint radius of it, may touch `touch_geoms` up to
  // kTouchDepth of penetration (PlanOptions::may_touch): a plan may start against what a hand
  // let go of. A start clear of everything is left as any other, `touch_geoms` or not.
  MotionPlanner(const Scene& scene, const mjModel* m, mjData* d, std::vector<int> joints,
                std::vector<Attachment> attachments = {}, std::vector<int> touch_geoms = {});
  static constexpr double kTouchDepth = 0.005;
  // Contacts the planned joints cannot change, up to this deep, are left as they are (a hand
  // resting against what it set down while the other arm plans); deeper: invalid_start.
  static constexpr double kStaticContactDepth = 0.002;
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
