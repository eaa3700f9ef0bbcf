// Results of the skillset's kinematic and planning services, shared by the backend and the
// programs. Status enums, not bools: an approximate plan is not a success.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace taskmatrix::core {

struct Pose {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
};

enum class IkStatus {
  kSolved,        // within tolerance, within limits (and collision-free when asked)
  kUnreachable,   // no start converged within tolerance and limits
  kInCollision,   // converged, but every solution is in collision
  kInvalidInput,  // NaN target, unknown frame, empty chain
};
const char* to_string(IkStatus status);

struct IkResult {
  IkStatus status = IkStatus::kInvalidInput;
  std::vector<std::vector<double>> solutions;  // distinct, in the requested joints' order
  double position_error_m = 0;                 // of the best attempt
  double orientation_error_rad = 0;
  int iterations = 0;
  double time_s = 0;
  std::string reason;
};

enum class PlanStatus {
  kExactSolution,        // the only success
  kApproximateSolution,  // OMPL found a path ending near, not at, the goal
  kTimeout,              // no path within the time limit
  kInvalidStart,         // the start is in collision or outside limits
  kInvalidGoal,          // every goal is in collision or outside limits
  kIkFailure,            // no goal configuration for the requested pose
  kInvalidInput,         // NaN, wrong sizes, unknown planner or parameter
};
const char* to_string(PlanStatus status);

struct PlanResult {
  PlanStatus status = PlanStatus::kInvalidInput;
  std::vector<std::vector<double>> path;  // waypoints, start first
  double planning_time_s = 0;
  double simplification_time_s = 0;
  bool simplification_hit_time_limit = false;
  std::uint64_t collision_checks = 0;
  unsigned graph_states = 0;
  int goal_index = -1;  // which of several goals was reached
  std::string message;
  bool success() const { return status == PlanStatus::kExactSolution; }
};

}  // namespace taskmatrix::core
