// URDF robots: validated with urdfdom, compiled by MuJoCo's URDF importer, completed from the
// robot profile (a position actuator on every joint, the head camera) and returned as MJCF
// text, ready to be composed with an environment like any MJCF robot.
#pragma once

#include <string>

#include "taskmatrix/core/robot_profile.h"

namespace taskmatrix::mujoco {

// Throws core::InputError naming the URDF (or the profile key) at fault: not a URDF, not a
// tree, a chain joint missing, fixed, continuous or without limits, a camera body missing.
std::string import_urdf_as_mjcf(const core::RobotProfile& profile);

// Default position-actuator gains when the profile's actuator_kp does not name the chain.
inline constexpr double kDefaultArmKp = 400.0;
inline constexpr double kDefaultHandKp = 20.0;

}  // namespace taskmatrix::mujoco
