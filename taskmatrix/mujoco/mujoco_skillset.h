// The skillset on MuJoCo + OMPL: one worker's simulated robot in one scene.
//
// Two mjData on the worker's model copy: `sim` is the world as simulated; `query` is scratch
// for FK, IK, validity, clearance and planning, synchronised from `sim` before each query,
// so a query never disturbs the simulation.
//
// Execution, in one of two modes (SimulationOptions::execution):
//   - physics: each joint has a position actuator; advance() runs the control period as
//     timestep substeps (mj_step2, then mj_step1 at the new state, so the state is current
//     for queries after every period without another mj_forward) with a computed-torque
//     feed-forward on the robot's joints (qfrc_applied = bias forces + M * commanded
//     acceleration + damping * commanded velocity), so tracking error reflects the trajectory
//     and the gains, not gravity. Held objects are moved kinematically with their holder
//     before every substep. Contacts that cannot matter are pruned (contact_pruning.h), and
//     mj_step1's contact pass finds MuJoCo's contacts from candidate pairs
//     (physics_contacts.h), with MuJoCo's sparse Jacobians where the model leaves the choice.
//   - kinematic: the paper's kinematically simulated robot. advance() sets the robot's joints
//     to the commanded positions (and velocities) at the end of the period, moves held objects
//     with their holders, and finds the contacts of the robot and what it holds with the
//     validity checker's pair test (collide_geoms: collision filters, bounding spheres,
//     oriented boxes, MuJoCo's narrow phase); nothing else moves unless scripted (the visitor).
//     Fingers (the profile's hands) do not pass through what they touch: a finger's motion in
//     a period stops where its segments would sink more than kFingerPenetrationM into anything
//     (deeper than they already were), and a segment that touches something holds the joints
//     between it and the palm from closing further (towards the profile's fist posture), as a
//     finger pressing on an object stops closing in physics.
//     A released object is dropped onto what lies below it by a short physics settle at the
//     moment of release (until it has touched something and rested for kRestTimeS, at most
//     kSettleMaxS; the robot and everything else held still, its contacts with the robot off):
//     simulated time does not advance during the settle. The free objects are settled the same
//     way after a reset or a new layout (the physics settles them in its first steps), so
//     they rest on their supports and what the robot picks up has a support to leave.
//   Both report the same measures (WorkRecord), and collisions() and touching() read the
//   same contact list.
//
// The world's own behaviour beyond physics (the visitor's walk, debris removal by a held tool)
// is scripted by WorldScript (world_script.h) and restarts with reset(). What queries know of
// obstacles is the ObstacleBelief (obstacle_belief.h): every obstacle of the layout in
// ground-truth perception, only the perceived ones in sensor perception. Held objects are
// HeldObjects (attachments.h); the joints' targets are a JointServo (joint_servo.h).
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "taskmatrix/core/skillset.h"
#include "taskmatrix/core/state_recording.h"
#include "taskmatrix/mujoco/attachments.h"
#include "taskmatrix/mujoco/contact_pruning.h"
#include "taskmatrix/mujoco/joint_servo.h"
#include "taskmatrix/mujoco/kinematics.h"
#include "taskmatrix/mujoco/obstacle_belief.h"
#include "taskmatrix/mujoco/physics_contacts.h"
#include "taskmatrix/mujoco/scene.h"
#include "taskmatrix/mujoco/validity_checker.h"
#include "taskmatrix/mujoco/world_script.h"

namespace taskmatrix::mujoco {

class HeadSensor;

enum class ExecutionMode { kPhysics, kKinematic };
const char* to_string(ExecutionMode mode);  // "physics", "kinematic"

// Upper bound on a kinematic release's settle (simulated seconds, not counted as trial time).
inline constexpr double kSettleMaxS = 1.0;
// How far a finger may sink into what it touches in kinematic mode (m).
inline constexpr double kFingerPenetrationM = 0.0005;

struct SimulationOptions {
  double control_rate_hz = 100.0;  // rounded to a whole number of model timesteps per period
  ExecutionMode execution = ExecutionMode::kPhysics;
  ContactPruningOptions pruning;  // physics mode
  // Physics mode: MuJoCo's sparse constraint Jacobians where the model leaves the choice to
  // MuJoCo (`jacobian="auto"`, which picks dense below 60 degrees of freedom: every built-in
  // scene). On these scenes the dense ones cost a third more per step in the constraint
  // solver, with few contacts touching few of the 40-60 degrees of freedom. The same
  // equations; sums in another order, so states differ at rounding level. A model that sets
  // `jacobian` keeps its choice.
  bool sparse_jacobian = true;
  // Physics mode: each step's contacts from the scene's candidate pairs (PhysicsContacts,
  // physics_contacts.h: MuJoCo's contacts without its broadphase, pairs a box keeps apart
  // skipped, and where it would differ otherwise mj_collision itself) instead of mj_collision.
  bool candidate_pairs = true;
  // Execution monitoring (WorkRecord): how often the moving chains' clearance is sampled
  // (0: never) and the distance it is capped at.
  double clearance_rate_hz = 10.0;
  double clearance_cap_m = 0.25;
};

class MujocoSkillset final : public core::Skillset {
 public:
  // Throws std::invalid_argument for a control rate that is not positive and finite.
  MujocoSkillset(std::shared_ptr<const Scene> scene, SimulationOptions options = {});
  ~MujocoSkillset() override;

  // Backend set-up, for the harness: obstacles of a layout, and the start state (robot at the
  // environment's start in the rest posture, targets there, time 0, nothing attached).
  void apply_layout(const core::ObstacleLayout& layout);
  // A trial's whole drawn world (task variation, then obstacles; WorkerScene::apply), then
  // reset() into its start state.
  void apply_layout(const core::TrialLayout& layout);
  void reset();
  // Whether obstacle slot `slot` holds an obstacle of the applied layout.
  bool obstacle_active(int slot) const { return belief_.active(slot); }
  // Sensor mode: from now on (and after every reset or layout) queries know an obstacle only
  // once it is marked perceived. Off by default: queries know every obstacle.
  void set_obstacles_need_perception(bool need);
  void mark_obstacle_perceived(int slot);
  // Whether queries take obstacle slot `slot` into account.
  bool obstacle_known(int slot) const;
  // Places the chains at `values` at once (and makes that the held target): set-up of a
  // trial's initial state, not motion. Throws std::invalid_argument like command().
  void set_configuration(const std::vector<std::string>& chain_names,
                         const std::vector<double>& values);
  // The visitor's walking speed along its path (m/s, >= 0); from the next control period.
  // Throws std::invalid_argument for a negative or non-finite speed, or an environment whose
  // visitor is not a (slide x, slide y, hinge) body with a path of two or more points.
  void set_visitor_walk(double speed_mps);
  // Debris bodies removed since the last reset, in order of removal.
  const std::vector<int>& removed_debris() const { return world_.removed_debris(); }
  bool removed(int body) const { return world_.removed(body); }

  ExecutionMode execution() const { return execution_; }
  const ContactPruning& pruning() const { return pruning_; }
  const Scene& scene() const { return *scene_; }
  const mjModel* model() const { return worker_.model(); }
  const mjData* sim_data() const { return worker_.data(); }
  const std::vector<Attachment>& attachments() const { return held_.list(); }

 protected:
  // core::Skillset's hooks.
  const core::RobotProfile& do_profile() const override { return scene_->robot(); }
  const std::vector<core::ChainInfo>& do_chains() const override { return chains_; }
  std::vector<double> do_configuration(const std::vector<std::string>& chain_names) const override;
  core::Pose do_frame_pose(const std::string& frame) const override;
  core::Pose do_frame_pose_at(const std::vector<std::string>& chain_names,
                              const std::vector<double>& values, const std::string& frame) override;
  core::IkResult do_solve_ik(const std::vector<std::string>& chain_names, const std::string& frame,
                             const core::Pose& target, const core::IkOptions& options) override;
  bool do_is_valid(const std::vector<std::string>& chain_names, const std::vector<double>& values,
                   const std::vector<std::string>& may_touch) override;
  double do_clearance(const std::vector<std::string>& chain_names,
                      const std::vector<double>& values, double max_distance_m) override;
  std::string do_plan_options_error(const core::PlanOptions& options) const override;
  core::PlanResult do_plan(const std::vector<std::string>& chain_names,
                           const std::vector<std::vector<double>>& goals,
                           const core::PlanOptions& options) override;
  double do_time() const override;
  double do_control_period() const override { return period_; }
  void do_command(const std::vector<std::string>& chain_names, const std::vector<double>& positions,
                  const std::vector<double>& velocities,
                  const std::vector<double>& accelerations) override;
  core::StepReport do_advance() override;
  std::vector<core::Collision> do_collisions(
      const std::vector<std::string>& chain_names) const override;
  void do_attach(const std::string& object, const std::string& side) override;
  void do_detach(const std::string& object) override;
  std::vector<std::string> do_attached_objects() const override;
  std::string do_holder_of(const std::string& object) const override;
  core::CameraInfo do_head_camera() const override;
  double do_palm_depth(const core::HandSpec& hand) const override;
  core::DepthScan do_scan_depth() override;
  std::vector<std::string> do_touching(const std::string& part) const override;
  // The state recording's frames: every generalized position.
  int do_state_size() const override;
  void do_append_state(std::vector<float>& frames) const override;

 private:
  // Joint ids of the chains, in order; throws std::invalid_argument for an unknown chain.
  std::vector<int> joints_of(const std::vector<std::string>& chain_names) const;
  void sync_query();
  // Debris under held tool tips (WorldScript), removed and recorded.
  void collect_debris();
  // One control period of each execution mode.
  void step_physics();
  void step_kinematic();
  // Kinematic mode: the contacts of the robot and what it holds, into the simulation's
  // contact list.
  void find_robot_contacts();
  // Kinematic mode: lets free objects (a released one; all of them at the start) fall onto
  // what lies below them and come to rest, with the robot and everything else held still and
  // the clock stopped.
  void settle_objects(const std::vector<int>& bodies);
  void settle_free_objects();
  // The layout's obstacles into the worker's model, then mj_forward (no settle, no reset).
  void apply_obstacles(const core::ObstacleLayout& layout);
  // Kinematic mode: holds back finger motions that would sink into what the fingers touch.
  // `before`: the robot's qpos before the period's commands were set. True if any was held.
  bool stop_fingers_at_contact(const std::vector<double>& before);
  // After each control period: the executed motion's measures.
  void monitor_period();
  // Throws std::logic_error when called from inside a query (a goal sampler's callback).
  void require_no_query(const char* what) const;
  int object_body(const std::string& object) const;  // -1 if not an object's body
  // Geoms of named objects (symbolic names or body names, with their subtrees); throws
  // std::invalid_argument for an unknown name.
  std::vector<int> object_geoms(const std::vector<std::string>& objects) const;
  // Held objects' supports, refreshed from the simulation (HeldObjects::refresh_supports).
  void refresh_supports();
  // The symbolic object name of a body's object, or the body's name.
  std::string name_of_body(int body) const;
  // The body of the random obstacle named "obstacle_N" (name_of_body's name for it), or -1.
  int obstacle_body(const std::string& name) const;
  // Robot bodies the chains' joints move, as a per-body mask.
  std::vector<char> moved_bodies(const std::vector<int>& joints) const;

  std::shared_ptr<const Scene> scene_;
  WorkerScene worker_;
  DataPtr query_;
  std::vector<core::ChainInfo> chains_;
  JointServo servo_;
  HeldObjects held_;
  ObstacleBelief belief_;
  WorldScript world_;
  ExecutionMode execution_ = ExecutionMode::kPhysics;
  ContactPruning pruning_;
  PhysicsContacts contacts_;   // the physics steps' contact pass
  bool own_contacts_ = false;  // step with contacts_ (physics, candidate_pairs, usable)
  // frame_pose_at's path from the world to the frame's body, for the last joints and body
  // asked (programs ask the same many times a period), and the qpos it poses.
  std::optional<ChainPath> fk_path_;
  std::vector<int> fk_path_joints_;
  int fk_path_body_ = -1;
  std::vector<double> fk_qpos_;
  std::vector<GeomPair> held_pairs_;  // kinematic: held objects' geoms against the world
  bool held_pairs_current_ = false;
  // Kinematic mode: each geom's pose and collision bits at the last contact pass, and what
  // each of the scene's robot pairs found then. A pair whose two geoms are as they were finds
  // what it found (most of the robot and the world stand still while an arm moves). Cleared
  // whenever the model's geometry may change (a layout, a reset).
  struct GeomSnapshot {
    std::array<double, 12> pose;  // geom_xpos, geom_xmat
    int contype, conaffinity;
    bool operator==(const GeomSnapshot&) const = default;
  };
  std::vector<GeomSnapshot> contact_pass_geoms_;
  std::vector<int> changed_geoms_;                           // this pass
  std::vector<std::vector<std::uint32_t>> pairs_of_geom_;    // robot pairs by geom
  std::vector<std::vector<mjContact>> robot_pair_contacts_;  // per robot pair
  std::vector<std::uint32_t> pairs_with_contacts_;           // ascending
  std::vector<std::uint32_t> pair_pass_;                     // the pass a pair was last tested
  std::uint32_t contact_pass_ = 0;
  struct Finger {                 // kinematic mode: a finger of the profile's hands
    std::vector<int> qpos_adr;    // its joints
    std::vector<double> fist;     // their values in the fist posture
    std::vector<int> segments;    // the body each joint moves, palm outwards
    std::vector<int> bodies;      // the bodies its joints move, parents first
    std::vector<int> geoms;       // their geoms
    std::vector<GeomPair> pairs;  // the scene's robot pairs with one of them
  };
  std::vector<Finger> fingers_;
  std::vector<double> robot_qpos_before_;  // scratch
  double period_ = 0.01;
  int substeps_ = 5;
  double period_start_ = 0;
  std::unique_ptr<HeadSensor> sensor_;  // made on the first scan_depth()
  // Monitoring.
  int clearance_every_ = 0;  // control periods per clearance sample; 0: never
  double clearance_cap_m_ = 0.25;
  std::vector<int> ee_sites_, ee_bodies_;                   // end effector frames of the chains
  std::vector<double> last_q_, last_v_, last_a_, last_ee_;  // the previous period's
  std::vector<double> cur_q_, cur_v_, cur_a_, cur_ee_;      // scratch for this period's
  std::vector<int> moving_;                                 // joints commanded to move
  bool have_last_ = false;
  bool have_accel_ = false;
};

}  // namespace taskmatrix::mujoco
