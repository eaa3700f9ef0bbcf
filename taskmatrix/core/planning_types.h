// Results of the skillset's kinematic and planning services, shared by the backend and the
// programs. Status enums, not bools: an approximate plan is not a success.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace taskmatrix::core {

struct Pose {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
};

struct IkOptions {
  bool orientation = true;  // full pose, or position only
  // With orientation: a unit axis of the frame (in the frame's own coordinates) about which
  // rotation is left free, so the orientation is matched up to a turn about it (a 5-D pose,
  // e.g. for arms with five joints). Zero: the full orientation.
  Eigen::Vector3d free_axis = Eigen::Vector3d::Zero();
  double position_tolerance_m = 1e-3;
  double orientation_tolerance_rad = 0.0174533;  // 1 degree
  int max_iterations = 150;                      // per start
  // A start stops early when its error (position in m plus orientation in rad) has not fallen
  // by 1% within this many iterations; 0: every start runs max_iterations.
  int stall_iterations = 15;
  int restarts = 30;          // random starts after the current configuration
  int max_solutions = 1;      // stop after this many distinct solutions
  double distinct_rad = 0.2;  // joint-space (max-norm) separation of solutions
  bool collision_free = true;
  std::uint64_t seed = 1;
  // The first start, as values of the chains' joints in chain order; empty: the current
  // configuration. Random restarts are drawn around it.
  std::vector<double> start;
  // Per joint in chain order, how freely damped least squares moves it (empty: all 1; the
  // weighted form of DLS). A zero holds the joint at its start value, e.g. a base placed by a
  // stance search while the torso and arm solve.
  std::vector<double> joint_weights;
};

// A registered planner by name (core::planner_registry(), motion_planning.h) with parameters
// by the planner's own names, e.g. {"range": "0.5"} for OMPL's RRTConnect.
struct PlannerSpec {
  std::string name = "RRTConnect";
  std::map<std::string, std::string> params;
};

// Work bounds make a plan repeat exactly (same request and seed, same path and counts, whatever
// the machine's load); clock bounds are safety nets, and a result says when one fired.
struct PlanOptions {
  PlannerSpec planner;
  // The planner's budget: > 0: at most this many iterations (evaluations of OMPL's termination
  // condition, about one sampling step each), with time_limit_s as a safety net; 0: the clock
  // alone (time_limit_s), which makes anytime planners (RRTstar, PRM, BITstar) depend on load.
  unsigned max_iterations = 10000;
  double time_limit_s = 60.0;  // in (0, 86400]
  // Path simplification: rounds of OMPL's shortcutting, B-spline smoothing and vertex
  // reduction, each with a fixed amount of work (0 skips it); simplify_time_s is its clock
  // safety net (when it fires, the path is the one simplified so far).
  int simplify_rounds = 3;
  double simplify_time_s = 30.0;
  double motion_resolution = 0.005;  // fraction of the space's extent between checked states
  // Distance paths keep from obstacles (not from the floor): room for the execution's tracking
  // error. Within 0.25 (rad or m, every joint) of the start or a goal the distance asked for
  // grows in proportion from nothing at the endpoint (a hand beside what it grasps) to this,
  // and motions there are checked five times more finely. 0: paths may touch.
  double clearance_m = 0.01;
  std::uint32_t seed = 1;  // > 0
  // Objects (symbolic names) the start may touch, a few millimetres deep: what a hand let go
  // of, what a reaching hand brushes. Paths leave them within the endpoint radius (where a
  // start that touches them needs no clearance at all, only no deeper contact).
  std::vector<std::string> may_touch;
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
  kTimeout,              // no path within the budget (iterations, or the clock)
  kPlanningFailed,       // the planner stopped without a path before its budget; see message
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
  // A clock safety net decided the result (the planner's time limit with an iteration budget,
  // or any stop by the clock without one; the simplification's): it may differ under load.
  bool planning_hit_time_limit = false;
  bool simplification_hit_time_limit = false;
  std::uint64_t planner_iterations = 0;  // evaluations of the termination condition
  double ik_time_s = 0;                  // inverse kinematics for pose goals
  std::uint64_t collision_checks = 0;
  unsigned graph_states = 0;
  int plan_calls = 0;   // planner runs behind this result (one per pose tried;
                        // two where the path was planned again)
  int goal_index = -1;  // which of several goals (poses, for plan_to_poses) was reached
  std::string message;  // bounded: a summary
  std::string detail;   // what the summary leaves out (every IK attempt); may be empty
  bool success() const { return status == PlanStatus::kExactSolution; }
};

}  // namespace taskmatrix::core
