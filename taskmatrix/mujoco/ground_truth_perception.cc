#include "taskmatrix/mujoco/ground_truth_perception.h"

#include <algorithm>

#include <cmath>

#include "taskmatrix/mujoco/kinematics.h"
#include "taskmatrix/mujoco/mjcf_compose.h"

namespace taskmatrix::mujoco {

namespace {

const char* type_name(core::ObjectKind kind) {
  switch (kind) {
    case core::ObjectKind::kGraspable:
      return "graspable";
    case core::ObjectKind::kTool:
      return "tool";
    case core::ObjectKind::kSurface:
      return "surface";
    case core::ObjectKind::kDebris:
      return "debris";
  }
  return "object";
}

// Half extents of geom `g` along the axes of a frame in which its rotation is `r` (row-major:
// r[3 * i + j] = R(i, j)).
Eigen::Vector3d geom_half(const mjModel* m, int g, const double* r) {
  const double* s = m->geom_size + 3 * g;
  Eigen::Vector3d half;
  for (int i = 0; i < 3; ++i) {
    const double rx = std::abs(r[3 * i]), ry = std::abs(r[3 * i + 1]), rz = std::abs(r[3 * i + 2]);
    switch (m->geom_type[g]) {
      case mjGEOM_BOX:
        half[i] = rx * s[0] + ry * s[1] + rz * s[2];
        break;
      case mjGEOM_SPHERE:
        half[i] = s[0];
        break;
      case mjGEOM_CAPSULE:
        half[i] = s[0] + rz * s[1];
        break;
      case mjGEOM_CYLINDER:
        half[i] = s[0] * std::sqrt(std::max(0.0, 1 - rz * rz)) + rz * s[1];
        break;
      case mjGEOM_ELLIPSOID:
        half[i] = rx * s[0] + ry * s[1] + rz * s[2];
        break;
      default:
        half[i] = m->geom_rbound[g];
        break;
    }
  }
  return half;
}

void add_geom(const mjModel* m, const mjData* d, int g, Eigen::AlignedBox3d& box) {
  const double* p = d->geom_xpos + 3 * g;
  const Eigen::Vector3d half = geom_half(m, g, d->geom_xmat + 9 * g);
  const Eigen::Vector3d c(p[0], p[1], p[2]);
  box.extend(c - half);
  box.extend(c + half);
}

// Whether geom `g` of a surface's body is part of its top slab: its top within 5 mm of the
// body origin's height.
bool in_top_slab(const mjModel* m, const mjData* d, int body, int g) {
  if (m->geom_bodyid[g] != body || m->geom_type[g] == mjGEOM_PLANE) return false;
  Eigen::AlignedBox3d one;
  one.setEmpty();
  add_geom(m, d, g, one);
  return std::abs(one.max().z() - d->xpos[3 * body + 2]) <= 0.005;
}

// The collision geoms of `body` (and, for a subtree, its descendants) as shapes.
std::vector<core::Shape> collision_shapes(const mjModel* m, const mjData* d, int body,
                                          bool subtree) {
  std::vector<core::Shape> out;
  for (int g = 0; g < m->ngeom; ++g) {
    if (m->geom_contype[g] == 0 && m->geom_conaffinity[g] == 0) continue;
    bool mine = false;
    for (int up = m->geom_bodyid[g]; !mine && up > 0; up = subtree ? m->body_parentid[up] : 0) {
      mine = up == body;
    }
    if (!mine) continue;
    core::Shape s;
    switch (m->geom_type[g]) {
      case mjGEOM_BOX:
        s.type = core::Shape::Type::kBox;
        break;
      case mjGEOM_SPHERE:
        s.type = core::Shape::Type::kSphere;
        break;
      case mjGEOM_CAPSULE:
        s.type = core::Shape::Type::kCapsule;
        break;
      case mjGEOM_CYLINDER:
        s.type = core::Shape::Type::kCylinder;
        break;
      case mjGEOM_ELLIPSOID:
        s.type = core::Shape::Type::kEllipsoid;
        break;
      default:
        continue;  // planes and meshes are not graspable primitives
    }
    const double* p = d->geom_xpos + 3 * g;
    const double* r = d->geom_xmat + 9 * g;
    Eigen::Matrix3d rot;
    rot << r[0], r[1], r[2], r[3], r[4], r[5], r[6], r[7], r[8];
    s.pose.position = Eigen::Vector3d(p[0], p[1], p[2]);
    s.pose.orientation = Eigen::Quaterniond(rot).normalized();
    s.size = Eigen::Vector3d(m->geom_size[3 * g], m->geom_size[3 * g + 1], m->geom_size[3 * g + 2]);
    out.push_back(s);
  }
  return out;
}

core::Pose body_pose(const mjData* d, int body) {
  return frame_pose(d, FrameRef{FrameRef::Kind::kBody, body});
}

}  // namespace

Eigen::AlignedBox3d geom_box(const mjModel* m, const mjData* d, int geom) {
  Eigen::AlignedBox3d box;
  box.setEmpty();
  if (m->geom_type[geom] != mjGEOM_PLANE) add_geom(m, d, geom, box);
  return box;
}

Eigen::AlignedBox3d surface_box(const mjModel* m, const mjData* d, int body) {
  Eigen::AlignedBox3d box;
  box.setEmpty();
  for (int g = 0; g < m->ngeom; ++g) {
    if (in_top_slab(m, d, body, g)) add_geom(m, d, g, box);
  }
  return box.isEmpty() ? body_box(m, d, body, false) : box;
}

Eigen::AlignedBox2d surface_top_extent(const mjModel* m, const mjData* d, int body) {
  Eigen::AlignedBox2d extent;  // empty unless some geom is in the top slab
  const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> rb(d->xmat + 9 * body);
  const Eigen::Vector3d pb(d->xpos[3 * body], d->xpos[3 * body + 1], d->xpos[3 * body + 2]);
  for (int g = 0; g < m->ngeom; ++g) {
    if (!in_top_slab(m, d, body, g)) continue;
    const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> rg(d->geom_xmat + 9 * g);
    const Eigen::Matrix<double, 3, 3, Eigen::RowMajor> rel = rb.transpose() * rg;
    const Eigen::Vector3d at =
        rb.transpose() *
        (Eigen::Vector3d(d->geom_xpos[3 * g], d->geom_xpos[3 * g + 1], d->geom_xpos[3 * g + 2]) -
         pb);
    const Eigen::Vector3d half = geom_half(m, g, rel.data());
    extent.extend((at - half).head<2>());
    extent.extend((at + half).head<2>());
  }
  return extent;
}

Eigen::AlignedBox3d body_box(const mjModel* m, const mjData* d, int body, bool subtree) {
  Eigen::AlignedBox3d box;
  box.setEmpty();
  for (int g = 0; g < m->ngeom; ++g) {
    const int b = m->geom_bodyid[g];
    if (m->geom_type[g] == mjGEOM_PLANE || m->geom_rgba[4 * g + 3] == 0) continue;
    bool mine = b == body;
    for (int up = b; subtree && !mine && up > 0; up = m->body_parentid[up]) mine = up == body;
    if (mine) add_geom(m, d, g, box);
  }
  return box;
}

std::vector<SceneThing> scene_things(const MujocoSkillset& skills) {
  const mjModel* m = skills.model();
  const Scene& scene = skills.scene();
  std::vector<SceneThing> out;
  auto body_id = [&](const std::string& name) { return mj_name2id(m, mjOBJ_BODY, name.c_str()); };
  for (const auto& [name, spec] : scene.environment().objects) {
    for (const std::string& b : spec.bodies) {
      if (skills.removed(body_id(b))) continue;  // vacuumed up
      SceneThing t;
      t.id = core::perceived_id(name, spec, b);
      t.type = type_name(spec.kind);
      t.body = body_id(b);
      t.subtree = spec.kind != core::ObjectKind::kSurface;
      if (!spec.grip_site.empty()) t.grip_site = mj_name2id(m, mjOBJ_SITE, spec.grip_site.c_str());
      if (!spec.tip_site.empty()) t.tip_site = mj_name2id(m, mjOBJ_SITE, spec.tip_site.c_str());
      out.push_back(std::move(t));
    }
  }
  if (!scene.environment().visitor.body.empty()) {
    out.push_back({core::kVisitorId, "humanoid", body_id(scene.environment().visitor.body), true});
  }
  const std::vector<ObstacleSlot>& slots = scene.obstacle_slots();
  for (size_t s = 0; s < slots.size(); ++s) {
    if (!skills.obstacle_active(static_cast<int>(s))) continue;
    SceneThing t{obstacle_name(static_cast<int>(s)), "obstacle", slots[s].body, true};
    t.obstacle_slot = static_cast<int>(s);
    out.push_back(std::move(t));
  }
  return out;
}

std::optional<core::PerceivedObject> perceive(const MujocoSkillset& skills, const SceneThing& thing,
                                              double time) {
  const mjModel* m = skills.model();
  const mjData* d = skills.sim_data();
  core::PerceivedObject o;
  o.id = thing.id;
  o.type = thing.type;
  o.pose = body_pose(d, thing.body);
  o.box = thing.type == "surface" ? surface_box(m, d, thing.body)
                                  : body_box(m, d, thing.body, thing.subtree);
  if (o.box.isEmpty()) return std::nullopt;
  if (thing.type == "graspable" || thing.type == "tool")
    o.shapes = collision_shapes(m, d, thing.body, thing.subtree);
  if (thing.type == "surface") o.top = surface_top_extent(m, d, thing.body);
  o.last_seen = time;
  o.confidence = 1.0;
  if (thing.grip_site >= 0) {
    o.frames["grip"] = frame_pose(d, FrameRef{FrameRef::Kind::kSite, thing.grip_site});
  }
  if (thing.tip_site >= 0) {
    o.frames["tip"] = frame_pose(d, FrameRef{FrameRef::Kind::kSite, thing.tip_site});
  }
  return o;
}

std::vector<core::PerceivedObject> scene_objects(const MujocoSkillset& skills, double time) {
  std::vector<core::PerceivedObject> out;
  for (const SceneThing& t : scene_things(skills)) {
    if (auto o = perceive(skills, t, time)) out.push_back(std::move(*o));
  }
  return out;
}

void GroundTruthPerception::update(double time, core::PerceptualModel& model) {
  std::vector<core::PerceivedObject> now = scene_objects(skills_, time);
  // What is no longer in the world (vacuumed debris, obstacles of an old layout) is forgotten.
  std::vector<std::string> gone;
  for (const auto& [id, o] : model.objects()) {
    if (std::none_of(now.begin(), now.end(), [&](const auto& n) { return n.id == id; }))
      gone.push_back(id);
  }
  for (const std::string& id : gone) model.forget(id);
  for (core::PerceivedObject& o : now) model.observe(std::move(o));
}

}  // namespace taskmatrix::mujoco
