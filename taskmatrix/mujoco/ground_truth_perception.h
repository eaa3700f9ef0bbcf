// Perception mode `ground_truth`: every task object, surface, debris flake, active obstacle
// and the visitor, with exact poses and bounding boxes from the simulation, confidence 1.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "taskmatrix/core/perceptual_model.h"
#include "taskmatrix/mujoco/mujoco_skillset.h"

namespace taskmatrix::mujoco {

// World-aligned bounding box of one geom, from the data's current poses (planes: empty).
Eigen::AlignedBox3d geom_box(const mjModel* m, const mjData* d, int geom);

// World-aligned bounding box of a body's geoms (of the body only, or of its whole subtree),
// from the data's current poses. Empty (isEmpty()) if the body has no geoms.
Eigen::AlignedBox3d body_box(const mjModel* m, const mjData* d, int body, bool subtree);

// A surface's box: its geoms whose top is the body origin's height (the environment
// convention: a surface body's origin is the centre of its top face), so a monitor on a desk
// is not part of the desk's top.
Eigen::AlignedBox3d surface_box(const mjModel* m, const mjData* d, int body);

// The extent of those geoms in the body's own frame, seen from above, from its origin
// (core::PerceivedObject::top; empty where no geom is at the origin's height).
Eigen::AlignedBox2d surface_top_extent(const mjModel* m, const mjData* d, int body);

class GroundTruthPerception final : public core::Perception {
 public:
  explicit GroundTruthPerception(const MujocoSkillset& skills) : skills_(skills) {}
  const char* mode() const override { return "ground_truth"; }
  void update(double time, core::PerceptualModel& model) override;

 private:
  const MujocoSkillset& skills_;
};

// A perceivable thing of the scene: its id and type, and the body it is (with its subtree,
// except for surfaces, which are their body's own geoms).
struct SceneThing {
  std::string id, type;
  int body = -1;
  bool subtree = true;
  int grip_site = -1, tip_site = -1;  // tools
  int obstacle_slot = -1;             // obstacles
};
// Every perceivable thing: task objects, surfaces, debris, the visitor, active obstacles.
std::vector<SceneThing> scene_things(const MujocoSkillset& skills);
// What exact perception of `thing` in the simulation now gives (confidence 1, seen at
// `time`); nullopt if it has no visible geom.
std::optional<core::PerceivedObject> perceive(const MujocoSkillset& skills, const SceneThing& thing,
                                              double time);

// Every perceivable thing of the scene as it is now (what the sensor may recognise).
std::vector<core::PerceivedObject> scene_objects(const MujocoSkillset& skills, double time);

}  // namespace taskmatrix::mujoco
