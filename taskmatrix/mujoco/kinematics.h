// Forward and inverse kinematics of named frames (sites or bodies) on a worker's data.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "taskmatrix/core/planning_types.h"
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

// Damped least squares on `joints` (hinge/slide joint ids), clamped to joint limits, from
// the data's current configuration first and then from seeded random starts. Solutions are
// collision-checked with `attachments` held. Leaves the data's qpos as it found it.
core::IkResult solve_ik(const Scene& scene, const mjModel* m, mjData* d,
                        const std::vector<int>& joints, const std::string& frame,
                        const core::Pose& target, const IkOptions& options,
                        const std::vector<Attachment>& attachments = {});
// The same on a worker's model and data.
core::IkResult solve_ik(const Scene& scene, WorkerScene& worker, const std::vector<int>& joints,
                        const std::string& frame, const core::Pose& target,
                        const IkOptions& options);

}  // namespace taskmatrix::mujoco
