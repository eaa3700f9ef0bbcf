// What a skillset did, for the harness's metrics and replays: every plan call, the IK and
// collision-check work (counted by the common skillset, whatever the backend), and the
// executed motion measured each control period (by the backend, which steps it).
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace taskmatrix::core {

// One public planning call (plan_to_configuration, plan_to_poses or plan_to_region).
struct PlanCallRecord {
  double time_s = 0;           // simulated time of the call
  std::string kind;            // "configuration", "poses", "region"
  std::string status;          // core::to_string(PlanStatus)
  int planner_runs = 0;        // planner solves behind the call (one per pose tried;
                               // two where the path was planned again)
  double planning_time_s = 0;  // planner solve, wall clock
  double simplification_time_s = 0;
  // A clock safety net decided the plan (core::PlanResult): it may differ under load.
  bool planning_hit_time_limit = false;
  bool simplification_hit_time_limit = false;
  std::uint64_t planner_iterations = 0;
  double ik_time_s = 0;  // inverse kinematics for pose goals
  std::uint64_t collision_checks = 0;
  double path_length = 0;  // of the returned path, in joint space (rad and m)
  int path_states = 0;
  // FNV-1a (64 bit, hex) of the returned path's waypoints as IEEE doubles: equal digests,
  // the same path bit for bit.
  std::string path_digest;
};

std::string path_digest(const std::vector<std::vector<double>>& path);

struct WorkRecord {
  std::vector<PlanCallRecord> plans;
  // Every IK solve: the programs' solve_ik calls and one per target pose plan_to_poses tried.
  int ik_calls = 0;
  double ik_time_s = 0;  // of the programs' solve_ik calls (plan_to_poses' IK is in `plans`)
  // Validity checks: the planners' (states and motion steps) plus is_valid calls.
  std::uint64_t collision_checks = 0;
  // Execution: control periods simulated and the wall time spent stepping them (physics,
  // feed-forward, the visitor and attachments), and the wall time spent measuring below.
  long control_periods = 0;
  double stepping_wall_s = 0;
  double monitoring_wall_s = 0;
  // Contact detection while stepping: passes (one per timestep in physics, one per control
  // period in kinematic mode) and the contacts they found, summed.
  long contact_passes = 0;
  long contacts = 0;
  // The executed motion of the robot's joints (all chains, base included).
  double path_length_joint = 0;  // sum over periods of |q(t) - q(t - T)| (rad and m mixed)
  double path_length_ee_m = 0;   // sum over end effectors of their Cartesian path length
  double jerk_squared_sum = 0;   // of |dddq| by finite differences of joint velocities
  long jerk_samples = 0;
  // Smallest distance between the moving chains (and what they hold) and the world (furniture,
  // objects, obstacles; not the floor, not the robot itself), sampled while any chain is
  // commanded to move; infinity when never sampled. Capped at the monitor's cap. Touching a
  // grasped or placed object counts as 0.
  double min_clearance_m = std::numeric_limits<double>::infinity();
  long clearance_samples = 0;

  double planning_time_s() const;
  double simplification_time_s() const;
  double plan_ik_time_s() const;
  int planner_runs() const;
  double jerk_rms() const;  // NaN without samples
};

}  // namespace taskmatrix::core
