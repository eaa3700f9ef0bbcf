// Forward and inverse kinematics of named frames (sites or bodies) on a worker's data.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "taskmatrix/core/planning_types.h"
#include "taskmatrix/mujoco/scene.h"

namespace taskmatrix::mujoco {

// Pose of a frame after the last mj_kinematics on `d`.
core::Pose frame_pose(const mjData* d, FrameRef frame);

struct IkOptions {
  bool orientation = true;  // full pose, or position only
  double position_tolerance_m = 1e-3;
  double orientation_tolerance_rad = 0.0174533;  // 1 degree
  int max_iterations = 150;                      // per start
  int restarts = 30;                             // random starts after the current configuration
  int max_solutions = 1;                         // stop after this many distinct solutions
  double distinct_rad = 0.2;                     // joint-space (max-norm) separation of solutions
  bool collision_free = true;
  std::uint64_t seed = 1;
};

// Damped least squares on `joints` (hinge/slide joint ids), clamped to joint limits, from
// the worker's current configuration first and then from seeded random starts. Leaves the
// worker's qpos as it found it.
core::IkResult solve_ik(const Scene& scene, WorkerScene& worker, const std::vector<int>& joints,
                        const std::string& frame, const core::Pose& target,
                        const IkOptions& options);

}  // namespace taskmatrix::mujoco
