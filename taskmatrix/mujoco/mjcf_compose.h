// Composes one robot MJCF and one environment MJCF into a single scene MJCF, plus the
// reserved obstacle slots whose pose and size are written per layout into a model copy
// (never recompiled). Section by section:
//   compiler   attributes merged; a conflicting value is an error. A file in degrees
//              (MJCF's default unit) is first rewritten in radians as MuJoCo's compiler
//              would convert it (orientations, hinge and ball ranges, hinge ref and
//              springref, also where they come from class defaults)
//   option, size, visual, statistic
//              attributes merged recursively, the environment's value wins a conflict
//   default    nested classes appended; both files setting the same top-level default
//              element (<default><geom .../>) is an error (use a named class)
//   asset, worldbody, actuator, sensor, contact, equality, tendon, custom
//              children appended, robot first
//   include    replaced by the named file's children first, as MuJoCo does (relative to
//              the including file's folder)
//   keyframe   dropped: qpos sizes do not survive composition (a trial starts from the
//              profile's rest posture)
// Asset files (mesh, hfield, skin, texture) named relative to a source's folder and its
// compiler's meshdir/texturedir/assetdir become absolute paths, and those attributes go:
// each file's assets load as they would from the file alone.
#pragma once

#include <string>

#include "taskmatrix/core/obstacle_layout.h"

namespace taskmatrix::mujoco {

struct MjcfSource {
  std::string text;
  std::string file;  // names the source in errors
};

struct CompositionOptions {
  std::string model_name = "scene";
  int obstacle_slots = 0;
  int offscreen_width = 1280;  // at least this offscreen buffer for rendering
  int offscreen_height = 960;
};

// Throws core::InputError naming the file (and element) at fault.
std::string compose_scene_mjcf(const MjcfSource& robot, const MjcfSource& environment,
                               const CompositionOptions& options);

std::string obstacle_body_name(int slot);
// "obstacle_N": how the skillset and the perceptual model name the obstacle in slot N; and
// the slot such a name names (-1 for any other name).
std::string obstacle_name(int slot);
int obstacle_slot_named(const std::string& name);
std::string obstacle_geom_name(int slot, core::ObstacleShape shape);

}  // namespace taskmatrix::mujoco
