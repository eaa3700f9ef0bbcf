// Forward and inverse kinematics of named frames (sites or bodies) on a worker's data.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "taskmatrix/core/planning_types.h"
#include "taskmatrix/mujoco/body_kinematics.h"
#include "taskmatrix/mujoco/scene.h"
#include "taskmatrix/mujoco/validity_checker.h"

namespace taskmatrix::mujoco {

// Pose of a frame after the last mj_kinematics on `d`.
core::Pose frame_pose(const mjData* d, FrameRef frame);

using core::IkOptions;

// A frame rigidly fixed to a body: the body's pose times `offset`. Sites, bodies and the
// frames of attached objects (fixed to their holder) are all expressed this way.
struct BodyFrame {
  int body = -1;
  core::Pose offset;
};
// Resolves a site or body name on the data's current poses; a frame on an attached object
// becomes a frame on its holder. Throws std::out_of_range for an unknown name.
BodyFrame resolve_frame(const Scene& scene, const mjData* d, const std::string& name,
                        const std::vector<Attachment>& attachments = {});
core::Pose frame_pose(const mjData* d, const BodyFrame& frame);

// The part of the body tree `joints` move on the way to a frame's body: its ancestors from the
// first one that carries one of the joints (from the world's first child with `from_world`),
// down to the frame's body. update() recomputes their poses from a qpos by mj_kinematics'
// formulas (body_pose_from_parent: the same numbers, bit for bit); everything above is read
// from the data as it was. IK and frame_pose_at use it.
class ChainPath {
 public:
  ChainPath(const mjModel* m, const std::vector<int>& joints, int frame_body,
            bool from_world = false);
  // Whether update() can pose every body of the path: hinge and slide joints only, no mocap.
  bool posable() const { return posable_; }
  // Whether joint j moves the frame; its world frame after the last update().
  bool on_path(int j) const { return frame_of_joint_[j] >= 0; }
  const JointFrame& joint(int j) const { return joint_frames_[frame_of_joint_[j]]; }
  // Poses of the path's bodies from `qpos` (null: d->qpos); the frame body's pose, its
  // orientation the body quaternion. Bodies are recomputed from the first whose inputs (the
  // pose above the path in `d`, its joints' values) differ, bit for bit, from the last call's.
  core::Pose update(const mjData* d, const mjtNum* qpos = nullptr);
  // After update(): the pose of a frame `offset` from the frame's body, as frame_pose(d, frame)
  // gives it after a whole mj_kinematics.
  core::Pose frame_pose(const core::Pose& offset) const;

 private:
  const mjModel* m_;
  std::vector<int> bodies_;
  int top_parent_ = 0;
  bool posable_ = true;
  std::vector<int> frame_of_joint_;  // per joint id: index into joint_frames_, -1 off the path
  std::vector<JointFrame> joint_frames_;
  std::vector<mjtNum> pos_, quat_, mat_;
  // The inputs of the last update(): the pose above the path (position, quaternion, matrix)
  // and the values of the path's joints, in path order.
  bool updated_ = false;
  mjtNum top_[16] = {};
  std::vector<mjtNum> inputs_;
  const mjtNum* frame_pos_ = nullptr;  // the frame body's, after update()
  const mjtNum* frame_mat_ = nullptr;
};

// Damped least squares on `joints` (hinge/slide joint ids), clamped to joint limits, from
// the data's current configuration first and then from seeded random starts. Solutions are
// collision-checked with `attachments` held. `d`'s kinematics must be current for its qpos
// (mj_kinematics since the last change); leaves the data as it found it.
core::IkResult solve_ik(const Scene& scene, const mjModel* m, mjData* d,
                        const std::vector<int>& joints, const std::string& frame,
                        const core::Pose& target, const IkOptions& options,
                        const std::vector<Attachment>& attachments = {});
// The same on a worker's model and data (its kinematics brought up to date first).
core::IkResult solve_ik(const Scene& scene, WorkerScene& worker, const std::vector<int>& joints,
                        const std::string& frame, const core::Pose& target,
                        const IkOptions& options);

}  // namespace taskmatrix::mujoco
