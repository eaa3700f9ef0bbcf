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
//
// A backend (a simulator, a robot) derives from Skillset and implements its protected hooks
// (do_*), the non-virtual interface that Drake's systems use: the public calls check their
// arguments once here (chain and hand names, sizes, NaN, joint limits), count the work in the
// WorkRecord, keep the state recording's cadence, and plan to poses and goal regions over the
// backend's IK, validity and planning hooks; a hook sees only checked arguments. What a hook
// may still reject (an unknown frame or object, planner options) it rejects as the public call
// documents.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "taskmatrix/core/joint_limits.h"
#include "taskmatrix/core/planning_types.h"
#include "taskmatrix/core/robot_profile.h"
#include "taskmatrix/core/state_recording.h"
#include "taskmatrix/core/trajectory.h"
#include "taskmatrix/core/work_record.h"

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
  const RobotProfile& profile() const { return do_profile(); }
  const std::vector<ChainInfo>& chains() const { return do_chains(); }
  // Throws std::invalid_argument naming an unknown chain.
  const ChainInfo& chain(std::string_view name) const;
  // Total number of joints of `chain_names`; throws for an unknown chain.
  size_t dof(const std::vector<std::string>& chain_names) const;
  // Current (simulated or measured) configuration of the chains.
  std::vector<double> configuration(const std::vector<std::string>& chain_names) const;
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
  Pose frame_pose(const std::string& frame) const { return do_frame_pose(frame); }
  // Pose of a frame with `chain_names` at `values` and everything else as it is now.
  Pose frame_pose_at(const std::vector<std::string>& chain_names, const std::vector<double>& values,
                     const std::string& frame);
  // Inverse kinematics of `chain_names` placing `frame` at `target` (position only when
  // options.orientation is false). Solutions are configurations of the chains. Unknown chains
  // or a non-finite target give kInvalidInput.
  IkResult solve_ik(const std::vector<std::string>& chain_names, const std::string& frame,
                    const Pose& target, const IkOptions& options);

  // ---- Collisions.
  // True if the chains at `values` are within limits and nothing of the robot (or what it
  // holds) touches anything but, up to the planner's touch depth, the objects or bodies in
  // `may_touch` (as PlanOptions::may_touch: what a motion starts against). Throws
  // std::invalid_argument for NaN, wrong sizes or a name in `may_touch` the world lacks.
  bool is_valid(const std::vector<std::string>& chain_names, const std::vector<double>& values,
                const std::vector<std::string>& may_touch = {});
  // Smallest signed distance (m, negative when penetrating) between the parts the chains move
  // (and what they hold) and everything else, capped at `max_distance_m`.
  double clearance(const std::vector<std::string>& chain_names, const std::vector<double>& values,
                   double max_distance_m);

  // ---- Planning (collision-free paths, start = current configuration). Bad arguments (unknown
  // chains, a goal of the wrong size, NaN or outside limits, unknown may_touch names) give
  // kInvalidInput naming the problem.
  PlanResult plan_to_configuration(const std::vector<std::string>& chain_names,
                                   const std::vector<double>& goal, const PlanOptions& options);
  // The paper's reach with several target hand configurations: each target pose in turn is
  // solved by IK (several solutions) and planned to; the first exact plan wins. All IK
  // failing gives kIkFailure; PlanResult::goal_index is the pose reached.
  PlanResult plan_to_poses(const std::vector<std::string>& chain_names, const std::string& frame,
                           const std::vector<Pose>& targets, const PlanOptions& options,
                           const IkOptions& ik);
  PlanResult plan_to_region(const std::vector<std::string>& chain_names, const GoalRegion& region,
                            const PlanOptions& options);
  // The fastest synchronized trajectory through `path` under the chains' speed limits, scaled
  // by `speed_scale` in (0, 1].
  Trajectory time_parameterize(const std::vector<std::string>& chain_names,
                               const std::vector<std::vector<double>>& path,
                               double speed_scale = 1.0) const;

  // ---- Execution, in simulated time advanced one control period at a time.
  double time() const { return do_time(); }                      // simulated seconds
  double control_period() const { return do_control_period(); }  // seconds per advance()
  // Position targets for the chains' joints, held until changed. Throws std::invalid_argument
  // for NaN, wrong sizes or values outside limits (beyond rounding: a value within
  // kCommandClampTolerance of a limit is clamped to it; core/joint_limits.h). The base moves only
  // through these.
  void command(const std::vector<std::string>& chain_names, const std::vector<double>& positions,
               const std::vector<double>& velocities = {},
               const std::vector<double>& accelerations = {});
  StepReport advance();
  // Collisions, at the current state, of the parts the chains move and what they hold.
  std::vector<Collision> collisions(const std::vector<std::string>& chain_names) const;
  // Blocking helper: commands `trajectory` sample by sample, advancing at the control rate,
  // then lets the chains settle. Other chains keep their current targets.
  ExecutionReport execute(const std::vector<std::string>& chain_names, const Trajectory& trajectory,
                          const ExecutionOptions& options = {});

  // How far (m) behind a hand's palm frame, against the hand's approach axis, the collision
  // geometry of the body the palm frame is on ends: where an object the hand closes on meets
  // the palm. 0 for a palm body without collision geometry. Throws std::invalid_argument for
  // a side the profile has no hand for.
  double palm_depth(const std::string& side) const;

  // ---- The head sensor.
  CameraInfo head_camera() const { return do_head_camera(); }
  // Casts the head sensor's rays in the current simulated state.
  DepthScan scan_depth() { return do_scan_depth(); }

  // ---- Attachment of grasped objects.
  // From now on `object` moves rigidly with the hand of `side` ("left"/"right") and is part
  // of the robot for collisions, except against that hand and the surfaces it rests on
  // (tolerating 5 mm): what it touches at the moment of attachment and when any later query or
  // plan starts. Throws std::invalid_argument for an unknown object or side, or an object
  // already attached.
  void attach(const std::string& object, const std::string& side);
  // Returns the object to physics where it is. Throws for an object not attached.
  void detach(const std::string& object);
  std::vector<std::string> attached_objects() const { return do_attached_objects(); }
  // The side ("left"/"right") of the hand holding `object`, or "" if it is not held.
  std::string holder_of(const std::string& object) const { return do_holder_of(object); }

  // ---- Contact sensing (the simulated state now).
  // What touches `part`, a robot body or an object's symbolic name: object names for task
  // objects, body names otherwise. Throws std::invalid_argument for an unknown name.
  std::vector<std::string> touching(const std::string& part) const { return do_touching(part); }

  // ---- What this skillset did, and the state over time.
  // The work since the skillset was made: plan calls, IK calls and checks counted here, the
  // executed motion measured by the backend.
  const WorkRecord& work() const { return work_; }
  // From now on, records the backend's state every `rate_hz`-th of a second of simulated time
  // (at the nearest whole number of control periods; 0 stops), starting with the current
  // state. Throws std::invalid_argument for a negative or non-finite rate.
  void record_states(double rate_hz);
  bool recording_states() const { return record_every_ > 0; }
  // The frames recorded since the last record_states() call (empty if never asked).
  const StateRecording& recording() const { return recording_; }
  // The name of joint `index` of the chains' concatenation; throws std::out_of_range past it.
  const std::string& joint_name(const std::vector<std::string>& chain_names, size_t index) const;

 protected:
  // ---- The backend's hooks. Chains are known, distinct and non-empty; value vectors have one
  // finite value per joint of the chains; commanded positions are within limits.
  virtual const RobotProfile& do_profile() const = 0;
  virtual const std::vector<ChainInfo>& do_chains() const = 0;
  virtual std::vector<double> do_configuration(
      const std::vector<std::string>& chain_names) const = 0;
  virtual Pose do_frame_pose(const std::string& frame) const = 0;
  virtual Pose do_frame_pose_at(const std::vector<std::string>& chain_names,
                                const std::vector<double>& values, const std::string& frame) = 0;
  virtual IkResult do_solve_ik(const std::vector<std::string>& chain_names,
                               const std::string& frame, const Pose& target,
                               const IkOptions& options) = 0;
  // Values within limits: whether nothing of the robot (or what it holds) touches anything
  // but `may_touch` (see is_valid).
  virtual bool do_is_valid(const std::vector<std::string>& chain_names,
                           const std::vector<double>& values,
                           const std::vector<std::string>& may_touch) = 0;
  virtual double do_clearance(const std::vector<std::string>& chain_names,
                              const std::vector<double>& values, double max_distance_m) = 0;
  // Why `options` cannot be planned with by this backend (e.g. an unknown may_touch name), or
  // "" when they can; called before any planning work.
  virtual std::string do_plan_options_error(const PlanOptions& options) const = 0;
  // A plan from the current configuration to whichever of `goals` (within limits, at least
  // one) it reaches first; PlanResult::goal_index is left to the caller.
  virtual PlanResult do_plan(const std::vector<std::string>& chain_names,
                             const std::vector<std::vector<double>>& goals,
                             const PlanOptions& options) = 0;
  virtual double do_time() const = 0;
  virtual double do_control_period() const = 0;
  virtual void do_command(const std::vector<std::string>& chain_names,
                          const std::vector<double>& positions,
                          const std::vector<double>& velocities,
                          const std::vector<double>& accelerations) = 0;
  // One control period; WorkRecord::control_periods already counts it.
  virtual StepReport do_advance() = 0;
  virtual std::vector<Collision> do_collisions(
      const std::vector<std::string>& chain_names) const = 0;
  virtual CameraInfo do_head_camera() const = 0;
  virtual DepthScan do_scan_depth() = 0;
  // `hand` is one of the profile's hands.
  virtual double do_palm_depth(const HandSpec& hand) const = 0;
  // `side` is a hand of the profile and `object` is not held.
  virtual void do_attach(const std::string& object, const std::string& side) = 0;
  // `object` is held.
  virtual void do_detach(const std::string& object) = 0;
  virtual std::vector<std::string> do_attached_objects() const = 0;
  virtual std::string do_holder_of(const std::string& object) const = 0;
  virtual std::vector<std::string> do_touching(const std::string& part) const = 0;
  // The state recording's frames: how many numbers the backend's state has, and the current
  // state appended to `frames` (exactly do_state_size() numbers).
  virtual int do_state_size() const = 0;
  virtual void do_append_state(std::vector<float>& frames) const = 0;

  // For the backend: its own counts and measures of executed motion.
  WorkRecord& mutable_work() { return work_; }
  // For the backend, while recording states: a frame of the current state now (after a change
  // that did not go through advance(), such as a placement), and a body it took out of the
  // world at the current time.
  void record_state_now();
  void note_removal(int body);
  // Whether a query of this skillset is running (a goal region's sampler may call back into
  // the skillset's queries, but must not change the world).
  bool in_query() const { return query_depth_ > 0; }

 private:
  // Throws std::invalid_argument unless the chains are known, distinct and not empty.
  void check_chains(const std::vector<std::string>& chain_names) const;
  // Throws std::invalid_argument unless IkOptions::start and joint_weights, where given, have
  // one finite value per joint of the chains, the weights none negative.
  void check_ik_options(const std::vector<std::string>& chain_names,
                        const IkOptions& options) const;
  // Throws std::invalid_argument unless `values` has a finite value per joint of the chains.
  void check_values(const std::vector<std::string>& chain_names, const std::vector<double>& values,
                    const char* what) const;
  // The index of the first value outside the chains' limits (beyond rounding), or -1.
  int outside_limits(const std::vector<std::string>& chain_names, const std::vector<double>& values,
                     double tolerance) const;
  // Checks of the planning calls' common arguments; a failure result when they are bad.
  std::optional<PlanResult> plan_input_error(const std::vector<std::string>& chain_names,
                                             const PlanOptions& options) const;
  PlanResult plan_to_poses_unrecorded(const std::vector<std::string>& chain_names,
                                      const std::string& frame, const std::vector<Pose>& targets,
                                      const PlanOptions& options, const IkOptions& ik);
  PlanResult plan_to_region_unrecorded(const std::vector<std::string>& chain_names,
                                       const GoalRegion& region, const PlanOptions& options);
  // Records a public plan call in the work record.
  PlanResult note_plan(const char* kind, PlanResult result);

  WorkRecord work_;
  StateRecording recording_;
  int record_every_ = 0;  // control periods per recorded frame; 0: not recording
  long record_from_ = 0;  // work_.control_periods when the recording began
  int query_depth_ = 0;
};

}  // namespace taskmatrix::core
