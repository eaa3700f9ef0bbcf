// Task variations on the MuJoCo backend (core/task_variation.h): the scene summarised for the
// generator at load, obstacle requests in a varied world, and a variation written into a
// worker's model copy and start state. Only body and geom poses, geom sizes and bounding radii
// change; the model is never recompiled.
#include <algorithm>
#include <cmath>
#include <limits>

#include "taskmatrix/core/input_error.h"
#include "taskmatrix/mujoco/ground_truth_perception.h"
#include "taskmatrix/mujoco/scene.h"

namespace taskmatrix::mujoco {

using core::InputError;

namespace {

constexpr double kOnTop = 0.005;       // m: a geom's top this near a surface's height is its top
constexpr double kAreaMargin = 0.03;   // m: a surface's placement area inside its top face
constexpr double kMinSlabLift = 0.05;  // m: the cut must stay at least this high
constexpr double kUpright = 1 - 1e-9;  // z axis of a frame this close to vertical

bool upright(const double* xmat) { return std::abs(xmat[8]) >= kUpright; }

bool in_subtree(const mjModel* m, int body, int root) {
  while (body > 0 && body != root) body = m->body_parentid[body];
  return body == root;
}

// The geom's extent along its own z axis, centre to top, for geoms that stretch.
double stretch_half(const mjModel* m, int g) {
  const double* s = m->geom_size + 3 * g;
  switch (m->geom_type[g]) {
    case mjGEOM_BOX:
      return s[2];
    case mjGEOM_CYLINDER:
      return s[1];
    case mjGEOM_CAPSULE:
      return s[1] + s[0];
    default:
      return -1;
  }
}

double bounding_radius(const mjModel* m, int g) {
  const double* s = m->geom_size + 3 * g;
  switch (m->geom_type[g]) {
    case mjGEOM_BOX:
      return std::sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
    case mjGEOM_CYLINDER:
      return std::hypot(s[0], s[1]);
    case mjGEOM_CAPSULE:
      return s[0] + s[1];
    default:
      return m->geom_rbound[g];
  }
}

}  // namespace

void Scene::index_variations() {
  const mjModel* m = model_.get();
  const std::string efile = environment_.spec_file.string();
  DataPtr data = make_data(m);
  mjData* d = data.get();
  std::copy(start_qpos_.begin(), start_qpos_.end(), d->qpos);
  mj_forward(m, d);

  world_.start = environment_.robot_start;
  // Surfaces.
  for (const auto& [name, obj] : environment_.objects) {
    if (obj.kind != core::ObjectKind::kSurface || obj.bodies.size() != 1) continue;
    const int body = mj_name2id(m, mjOBJ_BODY, obj.bodies[0].c_str());
    SurfaceRig rig;
    rig.name = name;
    rig.body = body;
    rig.height = d->xpos[3 * body + 2];
    rig.cut = rig.height;
    const Eigen::AlignedBox3d top = surface_box(m, d, body);
    core::SurfaceGeometry s;
    s.name = name;
    s.top = {top.min().x(), top.max().x(), top.min().y(), top.max().y()};
    s.height = rig.height;
    std::vector<core::Rect2> fixtures;  // what stands on the top (a monitor on a desk)
    bool movable = true;
    for (int g = 0; g < m->ngeom; ++g) {
      if (!in_subtree(m, m->geom_bodyid[g], body) || m->geom_type[g] == mjGEOM_PLANE) continue;
      const Eigen::AlignedBox3d box = geom_box(m, d, g);
      rig.geoms.push_back(g);
      rig.bottom.push_back(box.min().z());
      rig.top.push_back(box.max().z());
      rig.stretches.push_back(upright(d->geom_xmat + 9 * g) && stretch_half(m, g) > 0);
      if (std::abs(box.max().z() - rig.height) <= kOnTop)
        rig.cut = std::min(rig.cut, box.min().z());
      if (box.min().z() >= rig.height - kOnTop && (m->geom_contype[g] || m->geom_conaffinity[g])) {
        fixtures.push_back({box.min().x(), box.max().x(), box.min().y(), box.max().y()});
      }
      movable = movable && upright(d->xmat + 9 * m->geom_bodyid[g]);
    }
    // The environment's obstacle region on this surface, if there is one; else the top face.
    const auto region =
        std::find_if(environment_.obstacle_regions.begin(), environment_.obstacle_regions.end(),
                     [&](const core::ObstacleRegion& r) {
                       return std::abs(r.z - rig.height) <= 1e-3 && r.x_min >= s.top.x_min - 0.01 &&
                              r.x_max <= s.top.x_max + 0.01 && r.y_min >= s.top.y_min - 0.01 &&
                              r.y_max <= s.top.y_max + 0.01;
                     });
    if (region != environment_.obstacle_regions.end()) {
      s.area = *region;
    } else {
      // A top turned about the vertical (the corners of its world-aligned box lie beside it):
      // objects go within its own rectangle, obstacles within the largest world-aligned
      // rectangle inside it.
      core::Pose frame;
      frame.position = Eigen::Vector3d(d->xpos[3 * body], d->xpos[3 * body + 1], rig.height);
      frame.orientation = Eigen::Quaterniond(d->xquat[4 * body], d->xquat[4 * body + 1],
                                             d->xquat[4 * body + 2], d->xquat[4 * body + 3]);
      const core::SurfaceTop turned = core::surface_top(top, frame, surface_top_extent(m, d, body));
      const Eigen::AlignedBox2d inside = turned.inscribed();
      if (turned.turned()) {
        s.turned =
            core::TurnedArea{turned.cos, turned.sin,
                             core::Rect2{turned.lo.x() + kAreaMargin, turned.hi.x() - kAreaMargin,
                                         turned.lo.y() + kAreaMargin, turned.hi.y() - kAreaMargin}};
      }
      s.area.name = name;
      s.area.x_min = inside.min().x() + kAreaMargin;
      s.area.x_max = inside.max().x() - kAreaMargin;
      s.area.y_min = inside.min().y() + kAreaMargin;
      s.area.y_max = inside.max().y() - kAreaMargin;
      s.area.z = rig.height;
      s.area.keep_out = fixtures;
    }
    world_.surfaces.push_back(s);
    // A surface whose frames are tilted keeps its height (apply_variation refuses to move it).
    if (!movable) rig.cut = -1;
    surface_rigs_.push_back(std::move(rig));
  }

  // Task objects, debris flakes one by one, and what rests on which surface.
  auto resting_surface = [&](double x, double y, double lowest) -> int {
    for (size_t i = 0; i < world_.surfaces.size(); ++i) {
      const core::SurfaceGeometry& s = world_.surfaces[i];
      if (std::abs(lowest - s.height) <= kOnTop && core::distance_to_rect(x, y, s.top) == 0)
        return static_cast<int>(i);
    }
    return -1;
  };
  for (const auto& [name, obj] : environment_.objects) {
    if (obj.kind == core::ObjectKind::kSurface) continue;
    for (const std::string& body_name : obj.bodies) {
      const int body = mj_name2id(m, mjOBJ_BODY, body_name.c_str());
      core::ObjectGeometry o;
      o.name = obj.bodies.size() == 1 ? name : body_name;
      o.kind = obj.kind;
      o.x = d->xpos[3 * body];
      o.y = d->xpos[3 * body + 1];
      o.z = d->xpos[3 * body + 2];
      double lowest = std::numeric_limits<double>::infinity(), highest = -lowest;
      for (int g = 0; g < m->ngeom; ++g) {
        if (!in_subtree(m, m->geom_bodyid[g], body)) continue;
        const Eigen::AlignedBox3d box = geom_box(m, d, g);
        if (box.isEmpty()) continue;
        lowest = std::min(lowest, box.min().z());
        highest = std::max(highest, box.max().z());
        for (int corner = 0; corner < 4; ++corner) {
          const double cx = corner & 1 ? box.max().x() : box.min().x();
          const double cy = corner & 2 ? box.max().y() : box.min().y();
          o.radius = std::max(o.radius, std::hypot(cx - o.x, cy - o.y));
        }
      }
      o.below = o.z - lowest;
      o.above = highest - o.z;
      const auto fp =
          std::find(object_footprint_bodies_.begin(), object_footprint_bodies_.end(), body);
      o.footprint = object_footprints_[static_cast<size_t>(fp - object_footprint_bodies_.begin())];
      o.footprint.z_top = highest;
      const int on = resting_surface(o.x, o.y, lowest);
      if (on >= 0) o.rests_on = world_.surfaces[static_cast<size_t>(on)].name;
      world_.objects.push_back(o);
    }
  }
  // Every free body and every jointless task object on a surface moves with it.
  for (int body = 1; body < m->nbody; ++body) {
    if (is_robot_body(body) || m->body_parentid[body] != 0) continue;
    const bool free = m->body_jntnum[body] == 1 && m->jnt_type[m->body_jntadr[body]] == mjJNT_FREE;
    const bool task_object =
        std::find(object_footprint_bodies_.begin(), object_footprint_bodies_.end(), body) !=
        object_footprint_bodies_.end();
    if (!free && !(task_object && m->body_jntnum[body] == 0)) continue;
    double lowest = std::numeric_limits<double>::infinity();
    for (int g = 0; g < m->ngeom; ++g) {
      if (!in_subtree(m, m->geom_bodyid[g], body)) continue;
      const Eigen::AlignedBox3d box = geom_box(m, d, g);
      if (!box.isEmpty()) lowest = std::min(lowest, box.min().z());
    }
    const int on = resting_surface(d->xpos[3 * body], d->xpos[3 * body + 1], lowest);
    if (on < 0) continue;
    resting_.push_back(
        {static_cast<size_t>(on), body, free ? m->jnt_qposadr[m->body_jntadr[body]] : -1});
  }
  // The robot's reach on the floor.
  const ChainIndex& base = chain("base");
  const double bx = start_qpos_[base.qpos_adr[0]], by = start_qpos_[base.qpos_adr[1]];
  for (int g = 0; g < m->ngeom; ++g) {
    if (!is_robot_geom(g)) continue;
    const Eigen::AlignedBox3d box = geom_box(m, d, g);
    if (box.isEmpty()) continue;
    double reach = 0;
    for (int corner = 0; corner < 4; ++corner) {
      const double cx = corner & 1 ? box.max().x() : box.min().x();
      const double cy = corner & 2 ? box.max().y() : box.min().y();
      reach = std::max(reach, std::hypot(cx - bx, cy - by));
    }
    robot_geom_reach_.emplace_back(reach, box.min().z());
  }
}

double Scene::robot_footprint_radius(double below_z) const {
  double r = 0;
  for (const auto& [reach, lowest] : robot_geom_reach_) {
    if (lowest < below_z) r = std::max(r, reach);
  }
  return r;
}

core::LayoutRequest Scene::layout_request(const core::ObstacleOptions& options,
                                          const core::TaskVariation& variation) const {
  core::LayoutRequest req = layout_request(options);
  if (variation.empty() && options.targeted.empty()) return req;
  if (options.total() > environment_.obstacle_slots) {
    throw InputError(environment_.spec_file.string(), "obstacle_slots",
                     std::to_string(options.total()) +
                         " obstacles requested but the environment reserves " +
                         std::to_string(environment_.obstacle_slots) + " slots");
  }
  const core::WorldGeometry world = core::varied(world_, variation);
  for (core::ObstacleRegion& r : req.regions) {
    for (const core::SurfaceGeometry& s : world.surfaces) {
      if (s.area.name == r.name) r.z = s.height;
    }
  }
  req.protected_disks = {{world.start.x, world.start.y, environment_.start_clearance_m}};
  req.protected_rects = environment_.keep_out;
  for (const core::ObjectGeometry& o : world.objects) req.protected_rects.push_back(o.footprint);
  if (!environment_.visitor.body.empty()) req.protected_rects.push_back(object_footprints_.back());
  std::vector<core::Rect2> floor_keep_out;
  double floor_height = 0;
  for (const core::ObstacleRegion& r : environment_.obstacle_regions) {
    if (r.z == 0) floor_keep_out.insert(floor_keep_out.end(), r.keep_out.begin(), r.keep_out.end());
  }
  for (const core::TargetedObstacles& t : options.targeted) {
    if (t.kind == core::TargetedObstacles::Kind::kFloor)
      floor_height = std::max(floor_height, 2 * t.half_height_max_m);
  }
  req.groups =
      core::targeted_groups(options.targeted, world, floor_keep_out,
                            robot_footprint_radius(std::numeric_limits<double>::infinity()),
                            robot_footprint_radius(floor_height + req.clearance_m));
  return req;
}

core::TrialLayout Scene::make_trial_layout(const core::ObstacleOptions& obstacles,
                                           const core::VariationOptions& variation,
                                           std::uint64_t seed,
                                           const core::StartCheck& start_clear) const {
  // A height the surface cannot take is an input error whatever the draw.
  for (const core::SurfaceHeightOptions& s : variation.surfaces) {
    const auto rig = std::find_if(surface_rigs_.begin(), surface_rigs_.end(),
                                  [&](const SurfaceRig& r) { return r.name == s.surface; });
    if (rig == surface_rigs_.end()) continue;  // draw_variation names it
    if (rig->cut < 0) {
      throw core::VariationError("surfaces." + s.surface,
                                 "'" + s.surface + "' is tilted: only upright surfaces move");
    }
    if (rig->cut + s.height_m.min - rig->height < kMinSlabLift) {
      throw core::VariationError(
          "surfaces." + s.surface + ".height_m",
          "height " + std::to_string(s.height_m.min) + " m leaves no room under the top of '" +
              s.surface + "' (its top slab is " + std::to_string(rig->height - rig->cut) +
              " m thick; the lowest height is " +
              std::to_string(rig->height - rig->cut + kMinSlabLift) + " m)");
    }
  }
  try {
    return core::draw_world(
        variation, world_,
        [&](const core::TaskVariation& v) { return layout_request(obstacles, v); }, seed,
        start_clear);
  } catch (const core::LayoutError& e) {
    if (!e.key().empty()) throw;  // a scenario key's (a variation's, a group's)
    throw InputError(environment_.spec_file.string(), "obstacle_regions", e.what());
  }
}

void WorkerScene::apply_variation(const core::TaskVariation& variation) {
  mjModel* m = model_.get();
  const mjModel* m0 = scene_->model();
  const Scene& scene = *scene_;
  std::vector<double> shifts(scene.surface_rigs_.size(), 0.0);
  for (size_t i = 0; i < scene.surface_rigs_.size(); ++i) {
    const Scene::SurfaceRig& rig = scene.surface_rigs_[i];
    if (const core::SurfaceDraw* s = variation.surface(rig.name)) shifts[i] = s->shift_m;
    const double shift = shifts[i];
    if (shift != 0 && (rig.cut < 0 || rig.cut + shift < kMinSlabLift)) {
      throw core::VariationError(
          "surfaces." + rig.name,
          "'" + rig.name + "' cannot take the height " + std::to_string(rig.height + shift) + " m");
    }
    m->body_pos[3 * rig.body + 2] = m0->body_pos[3 * rig.body + 2] + shift;
    // Height map: the floor stays, the cut rises with the top, above it all moves rigidly.
    auto lift = [&](double z) {
      return z >= rig.cut ? z + shift : z <= 0 ? z : z * (rig.cut + shift) / rig.cut;
    };
    for (size_t k = 0; k < rig.geoms.size(); ++k) {
      const int g = rig.geoms[k];
      std::copy(m0->geom_pos + 3 * g, m0->geom_pos + 3 * g + 3, m->geom_pos + 3 * g);
      std::copy(m0->geom_size + 3 * g, m0->geom_size + 3 * g + 3, m->geom_size + 3 * g);
      m->geom_rbound[g] = m0->geom_rbound[g];
      m->geom_sameframe[g] = m0->geom_sameframe[g];
      if (shift == 0) continue;
      const double bottom = lift(rig.bottom[k]), top = lift(rig.top[k]);
      const double centre = (rig.bottom[k] + rig.top[k]) / 2;
      // The geom's new world centre height, relative to where its body now is (every body of
      // the subtree moved up by `shift`).
      double dz = (bottom + top) / 2 - centre - shift;
      if (rig.stretches[k]) {
        const double half = (top - bottom) / 2;
        const double extra = half - (rig.top[k] - rig.bottom[k]) / 2;
        const int axis = m->geom_type[g] == mjGEOM_BOX ? 2 : 1;
        m->geom_size[3 * g + axis] = std::max(1e-4, m0->geom_size[3 * g + axis] + extra);
        m->geom_rbound[g] = bounding_radius(m, g);
      } else {
        dz = lift(centre) - centre - shift;
      }
      if (dz != 0) {
        // The body frame is upright: a world height change is a change of the local z, along
        // the body's own z axis (up or, turned over, down).
        const int b = m->geom_bodyid[g];
        double xmat_zz = 1;
        {  // the body's world z axis from its compiled pose chain
          double q[4] = {1, 0, 0, 0};
          for (int up = b; up > 0; up = m0->body_parentid[up]) {
            double r[4];
            mju_mulQuat(r, m0->body_quat + 4 * up, q);
            std::copy(r, r + 4, q);
          }
          double mat[9];
          mju_quat2Mat(mat, q);
          xmat_zz = mat[8];
        }
        m->geom_pos[3 * g + 2] += dz * (xmat_zz < 0 ? -1 : 1);
        m->geom_sameframe[g] = 0;
      }
    }
  }
  start_qpos_ = scene.start_qpos_;
  for (const Scene::RestingBody& r : scene.resting_) {
    const double shift = shifts[r.surface];
    if (r.qpos_adr >= 0) {
      start_qpos_[static_cast<size_t>(r.qpos_adr) + 2] += shift;
    } else {
      m->body_pos[3 * r.body + 2] = m0->body_pos[3 * r.body + 2] + shift;
    }
  }
  for (const core::ObjectDraw& o : variation.objects) {
    const auto spec = scene.environment_.objects.find(o.object);
    const int body = spec == scene.environment_.objects.end()
                         ? -1
                         : mj_name2id(m, mjOBJ_BODY, spec->second.bodies.front().c_str());
    if (body < 0 || m->body_jntnum[body] != 1 || m->jnt_type[m->body_jntadr[body]] != mjJNT_FREE) {
      throw core::VariationError("objects." + o.object,
                                 "'" + o.object + "' is not a free body: it cannot be placed");
    }
    const size_t adr = static_cast<size_t>(m->jnt_qposadr[m->body_jntadr[body]]);
    start_qpos_[adr] = o.x;
    start_qpos_[adr + 1] = o.y;
    start_qpos_[adr + 2] = o.z;
    const double turn[4] = {std::cos(o.yaw_rad / 2), 0, 0, std::sin(o.yaw_rad / 2)};
    double q[4];
    mju_mulQuat(q, turn, scene.start_qpos_.data() + adr + 3);
    std::copy(q, q + 4, start_qpos_.begin() + static_cast<std::ptrdiff_t>(adr) + 3);
  }
  if (variation.robot_start) {
    const ChainIndex& base = scene.chain("base");
    start_qpos_[base.qpos_adr[0]] = variation.robot_start->x;
    start_qpos_[base.qpos_adr[1]] = variation.robot_start->y;
    start_qpos_[base.qpos_adr[2]] = variation.robot_start->yaw;
  }
}

void WorkerScene::apply(const core::TrialLayout& layout) {
  apply_variation(layout.variation);
  apply_layout(layout.obstacles);
}

}  // namespace taskmatrix::mujoco
