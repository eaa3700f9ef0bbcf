// What a robot must satisfy for the task programs to work, checked by forward kinematics
// on its compiled scene (models/README.md, "What the programs need of a robot"): the rules
// the loader cannot decide from names alone. `taskmatrix check-robot` prints these findings;
// the loader's own checks (names, limits, the head camera) come first, as load errors.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "taskmatrix/core/backend.h"
#include "taskmatrix/mujoco/scene.h"

namespace taskmatrix::mujoco {

using core::RobotFinding;

// The robot of `scene`, at its start pose in the scene's environment with the base turned to
// face +x (positions below are in that base frame):
//   chains:       degrees of freedom per chain; a warning for posture values within 1e-3 of
//                 a joint limit (a servo settles a hair past it);
//   postures:     every posture touches nothing (robot or environment); in `fist` the
//                 fingers and palm of one hand may touch each other (a warning: grasp stops a
//                 segment that touches anything, another finger included);
//   head camera:  where it looks at rest (the loader has checked the convention);
//   mirror signs: left-arm configurations and their mirror images (mirror_signs) give palm
//                 poses mirrored in the robot's sagittal plane (y = 0), within 5 mm and 3
//                 degrees of the approach axis; the same for the fingertips of `fist`;
//   palm axes:    no geometry of the palm's body reaches past the palm origin along
//                 `approach`; the fingertips close (rest to fist) more along `closing` than
//                 across it: an error when fewer fingers do than grasp needs touching (two,
//                 or every finger of a hand with fewer), a warning for any other finger;
//   fingers:      each fingertip ends at least 5 mm nearer the palm origin in `fist` than at
//                 rest.
std::vector<RobotFinding> check_robot_kinematics(const Scene& scene);

// The reach envelope against the surfaces of every environment: for each surface (objects
// of kind surface) of each scene's environment, the furthest the palm gets beyond the
// robot's front (the furthest forward of what no limb moves and reaches below the surface's
// top, the surface being taken as solid down to the floor; a surface's top is its body's
// origin), with
// the palm 2 to 15 cm above the surface's top, within 0.35 m of the robot's midline, held as
// a grasp holds it (its approach axis within 30 degrees of the horizontal or of straight
// down), and the robot touching nothing of itself, over seeded random configurations of an arm and
// the torso (the base stays; stepping can bring the front no nearer). An error below
// `min_reach_m` (task objects stand up to 0.15 m in from a surface's edge). One more
// finding, "surface heights", does the same for solid surfaces of every top from 0.40 to
// 1.00 m (every 5 cm) and says how far beyond the front the palm gets over each (a
// warning when it gets `min_reach_m` over none).
std::vector<RobotFinding> check_reach_envelope(
    const std::vector<std::shared_ptr<const Scene>>& scenes, double min_reach_m = 0.15);

}  // namespace taskmatrix::mujoco
