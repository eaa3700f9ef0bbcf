// Position servoing of the robot's chain joints: the commanded targets (position, velocity,
// acceleration), held until changed, and how each execution mode applies them.
//   - physics: the position actuators track the target run along the commanded velocity to the
//     end of the period, with a computed-torque feed-forward (qfrc_applied = bias forces +
//     M * commanded acceleration + damping * commanded velocity), so tracking error reflects
//     the trajectory and the gains, not gravity.
//   - kinematic: the joints are set to the targets.
#pragma once

#include <vector>

#include "taskmatrix/mujoco/scene.h"

namespace taskmatrix::mujoco {

struct ServoJoint {
  int joint = -1, qpos_adr = -1, dof_adr = -1, actuator = -1;
  double target_pos = 0, target_vel = 0, target_acc = 0;
};

class JointServo {
 public:
  // The scene's chain joints and their position actuators (Scene::load checked that every chain
  // joint has one).
  JointServo(const Scene& scene, const mjModel* m);

  // The servoed joints, in order of joint id.
  const std::vector<ServoJoint>& joints() const { return joints_; }
  const ServoJoint& joint(int id) const { return joints_[slot_[id]]; }
  // Targets where the joints are in `d`, at rest; the actuators hold them.
  void hold_current(mjData* d);
  // A new target for joint `id` (position within its limits).
  void set_target(int id, double pos, double vel, double acc, mjData* d);
  // Physics: one substep's actuation in `d`, the targets led `lead_s` back along the commanded
  // velocity. `d` must be current (bias forces and mass matrix of its configuration).
  void actuate(const mjModel* m, mjData* d, double lead_s);
  // The actuators' controls at the targets.
  void hold_targets(mjData* d) const;
  // Kinematic: joints at their targets (positions and velocities), controls with them.
  void place_at_targets(mjData* d) const;

 private:
  std::vector<ServoJoint> joints_;
  std::vector<int> slot_;                          // by joint id; -1 if not servoed
  std::vector<double> acc_full_, mass_times_acc_;  // nv scratch
};

}  // namespace taskmatrix::mujoco
