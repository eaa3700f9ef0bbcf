// The common skillset (paper section III-A): everything a task program may ask of a robot.
// Programs hold a Skillset& and never learn what robot or simulator is behind it; they
// discover chains, joints and limits at run time. No MuJoCo or OMPL type appears here.
//
// Conventions:
//   - A configuration of a list of chains is their joint values concatenated in the order
//     the chains are listed, each chain in its own joint order (ChainInfo::joints).
//   - Queries (FK, IK, validity, clearance, planning) never change the simulated robot; they
//     start from its current state, with every joint not being asked about where it is now.
//   - Inputs with NaN, wrong sizes, unknown names or values outside joint limits are
//     rejected: queries return a status (IkStatus/PlanStatus) naming the problem, commands
//     throw std::invalid_argument.
//   - Grasped objects that are attached move with the hand and are collision-checked as part
//     of the robot by every query and during execution, until detached.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "taskmatrix/core/planning_types.h"
#include "taskmatrix/core/robot_profile.h"
#include "taskmatrix/core/trajectory.h"

namespace taskmatrix::core {

struct ChainInfo {
  std::string name;
  std::vector<std::string> joints;  // kinematic order
  std::vector<double> lower, upper;
  SpeedLimit speed;
  std::string end_effector;  // frame at the tip; empty for chains without one
};

// A goal region for planning, given as a sampler of goal configurations of the planned
// chains. It may return nullopt for a draw that missed. The skillset draws up to
// `max_draws` samples with an RNG seeded from the plan's seed, keeps the valid ones (at most
// `max_goals`), and plans to whichever it reaches first.
struct GoalRegion {
  std::function<std::optional<std::vector<double>>(std::mt19937_64&)> sample;
  int max_draws = 200;
  int max_goals = 8;
};

// A contact that counts as a collision: a geom of a moving robot part or attached object
// against anything it is not allowed to touch.
struct Collision {
  std::string robot_part;  // robot body (or attached object) involved
  std::string other;       // the other body
  double depth_m = 0;      // penetration, positive
};

enum class ExecutionStatus {
  kCompleted,           // reached the end within tolerance
  kCollision,           // a moving part touched something it may not touch
  kTrackingError,       // did not settle within tolerance of the final waypoint
  kSimulationUnstable,  // the simulator diverged (NaN, bad accelerations)
  kInvalidInput,        // chains or trajectory do not fit together
};
const char* to_string(ExecutionStatus status);

struct ExecutionOptions {
  double position_tolerance = 0.02;  // rad or m, per joint, at the end
  double settle_time_s = 1.0;        // extra time allowed to settle after the trajectory ends
  bool stop_on_collision = true;
  // Objects the moving parts may touch without it counting as a collision (reach may brush
  // the object it is reaching for).
  std::vector<std::string> may_touch;
};

struct ExecutionReport {
  ExecutionStatus status = ExecutionStatus::kInvalidInput;
  double duration_s = 0;          // simulated time spent, settling included
  double max_tracking_error = 0;  // max over joints and control steps, rad or m
  double final_error = 0;         // max over joints at the end
  std::optional<Collision> collision;
  std::string message;
  bool success() const { return status == ExecutionStatus::kCompleted; }
};

// The head camera, for programs that point it (fixate) or reason about what it sees
// (in_view, explore). Convention: the camera looks along the -z axis of its frame, with +y up
// in the image (as MuJoCo and OpenGL cameras do).
struct CameraInfo {
  std::string frame;        // frame_pose(frame) is the camera's pose
  double fovy_rad = 0;      // vertical field of view
  double aspect = 4.0 / 3;  // image width / height of the head sensor
  double range_m = 0;       // depth range of the head sensor
};

// One depth capture of the head sensor: where its rays ended, in the world frame.
struct DepthScan {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();  // the camera's position
  std::vector<Eigen::Vector3d> hits;                 // rays that hit something within range
  int rays = 0;                                      // rays cast
};

// What one control period of simulation did.
struct StepReport {
  bool unstable = false;
  std::string message;  // why it is unstable
};

class Skillset {
 public:
  virtual ~Skillset() = default;

  // ---- The robot, as discovered at run time.
  virtual const RobotProfile& profile() const = 0;
  virtual const std::vector<ChainInfo>& chains() const = 0;
  // Throws std::invalid_argument naming an unknown chain.
  const ChainInfo& chain(std::string_view name) const;
  // Total number of joints of `chain_names`; throws for an unknown chain.
  size_t dof(const std::vector<std::string>& chain_names) const;
  // Current (simulated or measured) configuration of the chains.
  virtual std::vector<double> configuration(const std::vector<std::string>& chain_names) const = 0;
  // The same clamped to the chains' joint limits: a joint may rest a hair past a limit (soft
  // limits in simulation, noise on a robot), which a command may not ask for. What to command
  // to hold the chains where they are.
  std::vector<double> clamped_configuration(const std::vector<std::string>& chain_names) const;
  // A named posture of the profile restricted to the chains it names; throws
  // std::invalid_argument for an unknown posture.
  const Posture& posture(std::string_view name) const;

  // ---- Kinematics.
  // Current pose of a frame: a profile frame (palm, end effector), an object's frame, or any
  // named site or body. Throws std::invalid_argument for an unknown frame.
  virtual Pose frame_pose(const std::string& frame) const = 0;
  // Pose of a frame with `chain_names` at `values` and everything else as it is now.
  virtual Pose frame_pose_at(const std::vector<std::string>& chain_names,
                             const std::vector<double>& values, const std::string& frame) = 0;
  // Inverse kinematics of `chain_names` placing `frame` at `target` (position only when
  // options.orientation is false). Solutions are configurations of the chains.
  virtual IkResult solve_ik(const std::vector<std::string>& chain_names, const std::string& frame,
                            const Pose& target, const IkOptions& options) = 0;

  // ---- Collisions.
  // True if the chains at `values` are within limits and nothing of the robot (or what it
  // holds) touches anything. Throws std::invalid_argument for NaN or wrong sizes.
  virtual bool is_valid(const std::vector<std::string>& chain_names,
                        const std::vector<double>& values) = 0;
  // Smallest signed distance (m, negative when penetrating) between the parts the chains move
  // (and what they hold) and everything else, capped at `max_distance_m`.
  virtual double clearance(const std::vector<std::string>& chain_names,
                           const std::vector<double>& values, double max_distance_m) = 0;

  // ---- Planning (collision-free paths, start = current configuration).
  virtual PlanResult plan_to_configuration(const std::vector<std::string>& chain_names,
                                           const std::vector<double>& goal,
                                           const PlanOptions& options) = 0;
  // The paper's reach with several target hand configurations: each target pose in turn is
  // solved by IK (several solutions) and planned to; the first exact plan wins. All IK
  // failing gives kIkFailure; PlanResult::goal_index is the pose reached.
  virtual PlanResult plan_to_poses(const std::vector<std::string>& chain_names,
                                   const std::string& frame, const std::vector<Pose>& targets,
                                   const PlanOptions& options, const IkOptions& ik) = 0;
  virtual PlanResult plan_to_region(const std::vector<std::string>& chain_names,
                                    const GoalRegion& region, const PlanOptions& options) = 0;
  // The fastest synchronized trajectory through `path` under the chains' speed limits, scaled
  // by `speed_scale` in (0, 1].
  Trajectory time_parameterize(const std::vector<std::string>& chain_names,
                               const std::vector<std::vector<double>>& path,
                               double speed_scale = 1.0) const;

  // ---- Execution, in simulated time advanced one control period at a time.
  virtual double time() const = 0;            // simulated seconds
  virtual double control_period() const = 0;  // seconds per advance()
  // Position targets for the chains' joints, held until changed. Throws std::invalid_argument
  // for NaN, wrong sizes or values outside limits (beyond rounding: a value within 1e-6 of a
  // limit is clamped to it). The base moves only through these.
  virtual void command(const std::vector<std::string>& chain_names,
                       const std::vector<double>& positions,
                       const std::vector<double>& velocities = {},
                       const std::vector<double>& accelerations = {}) = 0;
  virtual StepReport advance() = 0;
  // Collisions, at the current state, of the parts the chains move and what they hold.
  virtual std::vector<Collision> collisions(const std::vector<std::string>& chain_names) const = 0;
  // Blocking helper: commands `trajectory` sample by sample, advancing at the control rate,
  // then lets the chains settle. Other chains keep their current targets.
  ExecutionReport execute(const std::vector<std::string>& chain_names, const Trajectory& trajectory,
                          const ExecutionOptions& options = {});

  // ---- The head sensor.
  virtual CameraInfo head_camera() const = 0;
  // Casts the head sensor's rays in the current simulated state.
  virtual DepthScan scan_depth() = 0;

  // ---- Attachment of grasped objects.
  // From now on `object` moves rigidly with the hand of `side` ("left"/"right") and is part
  // of the robot for collisions, except against that hand and the surfaces it rests on
  // (tolerating 5 mm): what it touches at the moment of attachment and when any later query or
  // plan starts. Throws std::invalid_argument for an unknown object or side, or an object
  // already attached.
  virtual void attach(const std::string& object, const std::string& side) = 0;
  // Returns the object to physics where it is. Throws for an object not attached.
  virtual void detach(const std::string& object) = 0;
  virtual std::vector<std::string> attached_objects() const = 0;
  // The side ("left"/"right") of the hand holding `object`, or "" if it is not held.
  virtual std::string holder_of(const std::string& object) const = 0;

  // ---- Contact sensing (the simulated state now).
  // What touches `part`, a robot body or an object's symbolic name: object names for task
  // objects, body names otherwise. Throws std::invalid_argument for an unknown name.
  virtual std::vector<std::string> touching(const std::string& part) const = 0;
};

}  // namespace taskmatrix::core
