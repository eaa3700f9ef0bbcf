#include "taskmatrix/mujoco/joint_servo.h"

#include <algorithm>

namespace taskmatrix::mujoco {

JointServo::JointServo(const Scene& scene, const mjModel* m)
    : slot_(m->njnt, -1), acc_full_(m->nv, 0.0), mass_times_acc_(m->nv, 0.0) {
  std::vector<char> servoed(m->njnt, 0);
  for (const ChainIndex& c : scene.chains()) {
    for (int j : c.joints) servoed[j] = 1;
  }
  for (int j = 0; j < m->njnt; ++j) {
    if (!servoed[j]) continue;
    ServoJoint s;
    s.joint = j;
    s.qpos_adr = m->jnt_qposadr[j];
    s.dof_adr = m->jnt_dofadr[j];
    for (int a = 0; a < m->nu; ++a) {
      if (m->actuator_trntype[a] == mjTRN_JOINT && m->actuator_trnid[2 * a] == j) s.actuator = a;
    }
    slot_[j] = static_cast<int>(joints_.size());
    joints_.push_back(s);
  }
}

void JointServo::hold_current(mjData* d) {
  for (ServoJoint& s : joints_) {
    s.target_pos = d->qpos[s.qpos_adr];
    s.target_vel = 0;
    s.target_acc = 0;
    d->ctrl[s.actuator] = s.target_pos;
  }
}

void JointServo::set_target(int id, double pos, double vel, double acc, mjData* d) {
  ServoJoint& s = joints_[slot_[id]];
  s.target_pos = pos;
  s.target_vel = vel;
  s.target_acc = acc;
  d->ctrl[s.actuator] = pos;
}

void JointServo::actuate(const mjModel* m, mjData* d, double lead_s) {
  const bool accelerating = std::any_of(joints_.begin(), joints_.end(),
                                        [](const ServoJoint& s) { return s.target_acc != 0; });
  if (accelerating) {
    std::fill(acc_full_.begin(), acc_full_.end(), 0.0);
    for (const ServoJoint& s : joints_) acc_full_[s.dof_adr] = s.target_acc;
    mj_mulM(m, d, mass_times_acc_.data(), acc_full_.data());
  }
  for (const ServoJoint& s : joints_) {
    const int v = s.dof_adr;
    d->ctrl[s.actuator] = s.target_pos - s.target_vel * lead_s;
    d->qfrc_applied[v] = d->qfrc_bias[v] + (accelerating ? mass_times_acc_[v] : 0.0) +
                         m->dof_damping[v] * s.target_vel;
  }
}

void JointServo::hold_targets(mjData* d) const {
  for (const ServoJoint& s : joints_) d->ctrl[s.actuator] = s.target_pos;
}

void JointServo::place_at_targets(mjData* d) const {
  for (const ServoJoint& s : joints_) {
    d->qpos[s.qpos_adr] = s.target_pos;
    d->qvel[s.dof_adr] = s.target_vel;
    d->ctrl[s.actuator] = s.target_pos;
  }
}

}  // namespace taskmatrix::mujoco
