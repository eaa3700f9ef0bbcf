// WorkerScene::apply_layout: obstacle layouts written into the reserved slots of a worker's
// model copy. Only pose, size, bounding radius, collision bits, group and colour change;
// the model is never recompiled.
#include <cmath>
#include <string>

#include "taskmatrix/mujoco/scene.h"

namespace taskmatrix::mujoco {
namespace {

constexpr int kHiddenGroup = 3;  // not drawn by default visualisation options
constexpr float kShapeColour[3][4] = {
    {0.80f, 0.42f, 0.20f, 1.0f},  // box
    {0.25f, 0.55f, 0.80f, 1.0f},  // cylinder
    {0.55f, 0.75f, 0.30f, 1.0f},  // sphere
};

double bounding_radius(core::ObstacleShape shape, const Eigen::Vector3d& size) {
  switch (shape) {
    case core::ObstacleShape::kBox:
      return size.norm();
    case core::ObstacleShape::kCylinder:
      return std::hypot(size.x(), size.y());
    case core::ObstacleShape::kSphere:
      return size.x();
  }
  return 0;
}

}  // namespace

void WorkerScene::apply_layout(const core::ObstacleLayout& layout) {
  const auto& slots = scene_->obstacle_slots();
  if (layout.obstacles.size() > slots.size()) {
    throw core::LayoutError("layout has " + std::to_string(layout.obstacles.size()) +
                            " obstacles but " + scene_->environment().spec_file.string() +
                            " reserves obstacle_slots: " + std::to_string(slots.size()));
  }
  mjModel* m = model_.get();
  for (size_t s = 0; s < slots.size(); ++s) {
    const ObstacleSlot& slot = slots[s];
    const core::PlacedObstacle* o = s < layout.obstacles.size() ? &layout.obstacles[s] : nullptr;
    for (int k = 0; k < 3; ++k) {
      const int g = slot.geoms[k];
      const bool active = o && static_cast<int>(o->shape) == k;
      // All bits: an obstacle collides with whatever collision bits a robot uses.
      m->geom_contype[g] = active ? -1 : 0;
      m->geom_conaffinity[g] = active ? -1 : 0;
      m->geom_group[g] = active ? 0 : kHiddenGroup;
      if (!active) continue;
      for (int i = 0; i < 3; ++i) {
        m->geom_size[3 * g + i] = o->size[i] > 0 ? o->size[i] : m->geom_size[3 * g + i];
        m->geom_rgba[4 * g + i] = kShapeColour[k][i];
      }
      m->geom_rgba[4 * g + 3] = kShapeColour[k][3];
      m->geom_rbound[g] = bounding_radius(o->shape, o->size);
    }
    double* pos = m->body_pos + 3 * slot.body;
    double* quat = m->body_quat + 4 * slot.body;
    if (o) {
      pos[0] = o->position.x();
      pos[1] = o->position.y();
      pos[2] = o->position.z();
      quat[0] = std::cos(o->yaw / 2);
      quat[1] = 0;
      quat[2] = 0;
      quat[3] = std::sin(o->yaw / 2);
    } else {
      pos[0] = 0;
      pos[1] = 0;
      pos[2] = -5;
      quat[0] = 1;
      quat[1] = quat[2] = quat[3] = 0;
    }
  }
}

}  // namespace taskmatrix::mujoco
