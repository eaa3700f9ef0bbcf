// The primitive task programs of the paper (section III-D) that this library provides, and
// their registration. Each is robot-independent: chains, hands, postures and motions come
// from the skillset and its profile; objects come from the perceptual model.
//
//   reach     object, side        arm to a hand pose from which the object can be grasped
//   position  object, frame, target | target_type | on
//                                 a held object's frame over a target, or onto a surface
//   fixate    object, duration    head (and base yaw) keep the object centred in the camera
//   explore   surface | bounds    head (and base yaw) until the sensor has seen the region
//   grasp     object, side        each finger segment closes until contact (or the fist)
//   release   side, object        open the hand to its rest posture, letting go of the object
//   postural  posture, chains, side   collision-free motion to a named posture
//   canned    motion, side        a predetermined joint-space motion from the profile
//   retreat   part, from, distance  the base steps back from a surface, or a hand withdraws
//
// The complex programs (pickup, putdown, greet, vacuum) are state machines over these; see
// complex.cc.
//
// Programs fail with a core::Failure (taskmatrix/core/failure.h): a code (perception_miss,
// ik_failure, planning_timeout, invalid_start, invalid_goal, collision, tracking_error,
// grasp_failed, not_graspable, invalid_input, coverage_short, ...) and a detail.
#pragma once

#include "taskmatrix/core/task_program.h"

namespace taskmatrix::programs {

core::ProgramType reach_program();
core::ProgramType grasp_program();
core::ProgramType release_program();
core::ProgramType postural_program();
core::ProgramType canned_program();
core::ProgramType position_program();
core::ProgramType fixate_program();
core::ProgramType explore_program();
core::ProgramType retreat_program();

// Adds the primitives above to `registry`.
void register_primitives(core::ProgramRegistry& registry);
// Adds pickup, putdown, greet and vacuum (the primitives must be registered).
void register_complex(core::ProgramRegistry& registry);
// All of them.
void register_programs(core::ProgramRegistry& registry);

}  // namespace taskmatrix::programs
