// A skillset with no simulator behind it, for tests of the core (executive, state machines,
// conditions) and for the skillset conformance suite: pure core, no MuJoCo or OMPL.
//
// The robot: a humanoid reduced to analytic kinematics, with the chains every profile has.
//   base        x, y (m) and yaw (rad) of the robot on the floor
//   torso       a lift (m): the shoulders are at kShoulderHeight + lift
//   head        pan and tilt (rad); the camera "head_camera" looks along the base's +x at 0
//   left_arm,   three joints turning about the vertical, links kLinks long, in the horizontal
//   right_arm   plane of the shoulder (0.2 m left/right of the base); the palm frame
//               ("left_palm", "right_palm") at the tip faces along the last link
//   left_hand,  one finger joint each, which moves nothing in the world
//   right_hand
// The world: world-aligned boxes by name (objects, surfaces, obstacles); frame_pose knows the
// robot's frames, the boxes (their centres) and "world".
// Collisions: each arm link is a row of spheres (kLinkRadius) against every box; a held box
// moves with its palm and collides with every box but the ones it rested on when grasped.
// Planning: the straight line from the current configuration to each goal in turn, checked at
// the plan's motion resolution (of the largest joint range) by the validity test; the first
// free line is the exact solution. Execution: kinematic, the joints are at their targets at
// the end of each control period.
#pragma once

#include <array>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "taskmatrix/core/perceptual_model.h"
#include "taskmatrix/core/skillset.h"

namespace taskmatrix::test {

struct FakeBox {
  std::string name;
  std::string type;  // "graspable", "surface", "obstacle", ... (PerceivedObject::type)
  Eigen::AlignedBox3d box;
};

class FakeSkillset final : public core::Skillset {
 public:
  static constexpr double kShoulderHeight = 1.0;
  static constexpr std::array<double, 3> kLinks{0.3, 0.25, 0.1};
  static constexpr double kLinkRadius = 0.03;
  static constexpr double kControlPeriod = 0.01;

  // The robot at the origin in its rest posture, with `world` around it.
  explicit FakeSkillset(std::vector<FakeBox> world = {});

  // Puts the chains at `values` at once, unchecked (a simulator's soft limits may leave a joint
  // a hair past its limit), and holds them there.
  void place(const std::vector<std::string>& chain_names, const std::vector<double>& values);
  // The world, for a perception of it: every box as a perceived object (held boxes where
  // their palms carry them).
  void perceive(core::PerceptualModel& model) const;
  const std::vector<FakeBox>& world() const { return world_; }

 protected:
  const core::RobotProfile& do_profile() const override { return profile_; }
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
  double do_time() const override { return time_; }
  double do_control_period() const override { return kControlPeriod; }
  void do_command(const std::vector<std::string>& chain_names, const std::vector<double>& positions,
                  const std::vector<double>& velocities,
                  const std::vector<double>& accelerations) override;
  core::StepReport do_advance() override;
  std::vector<core::Collision> do_collisions(
      const std::vector<std::string>& chain_names) const override;
  core::CameraInfo do_head_camera() const override;
  double do_palm_depth(const core::HandSpec& hand) const override;
  core::DepthScan do_scan_depth() override;
  void do_attach(const std::string& object, const std::string& side) override;
  void do_detach(const std::string& object) override;
  std::vector<std::string> do_attached_objects() const override;
  std::string do_holder_of(const std::string& object) const override;
  std::vector<std::string> do_touching(const std::string& part) const override;
  int do_state_size() const override;
  void do_append_state(std::vector<float>& frames) const override;

 private:
  struct Held {
    std::string object, side;
    Eigen::Vector3d offset;             // box centre from the palm, in the palm's frame
    std::vector<std::string> supports;  // boxes it rested on when grasped
  };
  // Joint values of every joint (all chains, in chain order) with `chain_names` at `values`.
  std::vector<double> with(const std::vector<std::string>& chain_names,
                           const std::vector<double>& values) const;
  size_t offset_of(const std::string& chain) const;  // first joint of `chain` in q_
  // Frames of the robot at full configuration `q`; throws std::invalid_argument if unknown.
  std::optional<core::Pose> robot_frame(const std::vector<double>& q,
                                        const std::string& frame) const;
  const FakeBox* find_box(const std::string& name) const;
  // The held boxes placed for configuration `q`.
  std::vector<FakeBox> held_boxes(const std::vector<double>& q) const;
  // Collisions at `q` of the parts `chain_names` move (all parts when empty) and what they hold,
  // ignoring boxes named in `may_touch`.
  std::vector<core::Collision> collisions_at(const std::vector<double>& q,
                                             const std::vector<std::string>& chain_names,
                                             const std::vector<std::string>& may_touch) const;
  // Smallest distance at `q` between the arms' spheres (and held boxes) and the world.
  double distance_at(const std::vector<double>& q) const;
  // Sphere centres along the arm of `side` at `q`.
  std::vector<Eigen::Vector3d> arm_spheres(const std::vector<double>& q,
                                           const std::string& side) const;

  core::RobotProfile profile_;
  std::vector<core::ChainInfo> chains_;
  std::vector<FakeBox> world_;
  std::vector<double> q_, target_;
  double time_ = 0;
  std::vector<Held> held_;
};

}  // namespace taskmatrix::test

namespace taskmatrix::test {

// Ground truth of a FakeSkillset's world, for the executive.
class FakePerception final : public core::Perception {
 public:
  explicit FakePerception(const FakeSkillset& skills) : skills_(skills) {}
  const char* mode() const override { return "ground_truth"; }
  void update(double, core::PerceptualModel& model) override { skills_.perceive(model); }

 private:
  const FakeSkillset& skills_;
};

// A kitchen-like world for the fake: a table ("work_surface") in front of the robot with a
// "cup" on it within the left arm's reach, and a "shelf" to its right.
std::vector<FakeBox> fake_kitchen();

}  // namespace taskmatrix::test
