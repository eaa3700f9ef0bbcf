#include "taskmatrix/mujoco/world_script.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace taskmatrix::mujoco {

WorldScript::WorldScript(const Scene& scene, const mjModel* m) : scene_(scene) {
  for (int g = 0; g < m->ngeom; ++g) {
    if (scene_.is_robot_geom(g)) robot_geoms_.push_back(g);
  }
  for (const auto& [name, spec] : scene_.environment().objects) {
    for (const std::string& b : spec.bodies) {
      const int body = mj_name2id(m, mjOBJ_BODY, b.c_str());
      if (spec.kind == core::ObjectKind::kDebris) {
        debris_.push_back({body, Eigen::Vector3d(m->body_pos[3 * body], m->body_pos[3 * body + 1],
                                                 m->body_pos[3 * body + 2])});
      }
      if (spec.kind == core::ObjectKind::kTool && !spec.tip_site.empty()) {
        tool_tips_.push_back({body, mj_name2id(m, mjOBJ_SITE, spec.tip_site.c_str())});
      }
    }
  }
}

void WorldScript::set_visitor_walk(const mjModel* m, double speed_mps) {
  if (!(std::isfinite(speed_mps) && speed_mps >= 0)) {
    throw std::invalid_argument("visitor walking speed must be a non-negative number of m/s");
  }
  const core::VisitorSpec& v = scene_.environment().visitor;
  const std::string where = "environment " + scene_.environment().name + ": the visitor ";
  if (v.path.size() < 2) throw std::invalid_argument(where + "needs a path of two or more points");
  const int body = mj_name2id(m, mjOBJ_BODY, v.body.c_str());
  const int types[3] = {mjJNT_SLIDE, mjJNT_SLIDE, mjJNT_HINGE};
  if (body < 0 || m->body_jntnum[body] != 3) {
    throw std::invalid_argument(where + "body must have three joints (slide x, slide y, hinge z)");
  }
  for (int k = 0; k < 3; ++k) {
    const int j = m->body_jntadr[body] + k;
    if (m->jnt_type[j] != types[k] || m->jnt_axis[3 * j + (k == 1 ? 1 : k == 0 ? 0 : 2)] < 0.99) {
      throw std::invalid_argument(where +
                                  "body must have three joints (slide x, slide y, hinge z)");
    }
    visitor_qpos_[k] = m->jnt_qposadr[j];
    visitor_dof_[k] = m->jnt_dofadr[j];
  }
  restart_visitor_walk();
  visitor_arc_ = {0.0};
  for (size_t i = 1; i < v.path.size(); ++i) {
    visitor_arc_.push_back(visitor_arc_.back() + std::hypot(v.path[i][0] - v.path[i - 1][0],
                                                            v.path[i][1] - v.path[i - 1][1]));
  }
  visitor_speed_ = speed_mps;
}

Eigen::Vector2d WorldScript::visitor_at(double walked, Eigen::Vector2d* heading) const {
  const auto& path = scene_.environment().visitor.path;
  const std::vector<double>& at = visitor_arc_;  // arc length at each waypoint
  const double length = at.back();
  double s = std::fmod(walked, 2 * length);
  const bool back = s > length;
  if (back) s = 2 * length - s;
  size_t i = 1;
  while (i + 1 < at.size() && at[i] < s) ++i;
  const double seg = at[i] - at[i - 1];
  const double f = seg > 0 ? (s - at[i - 1]) / seg : 0;
  Eigen::Vector2d step(path[i][0] - path[i - 1][0], path[i][1] - path[i - 1][1]);
  const Eigen::Vector2d place = Eigen::Vector2d(path[i - 1][0], path[i - 1][1]) + f * step;
  if (back) step = -step;
  if (heading) *heading = step.normalized();
  return place;
}

double WorldScript::room_from_robot(const mjModel* m, const mjData* d, const Eigen::Vector2d& at,
                                    const HeldObjects& held) const {
  double room = INFINITY;
  auto measure = [&](int g) {
    // From the visitor's axis to the box round the geom, seen from above.
    const Eigen::Vector2d centre(d->geom_xpos[3 * g], d->geom_xpos[3 * g + 1]);
    const Eigen::Vector2d half = horizontal_half_extent(m, d, g);
    const Eigen::Vector2d outside = ((at - centre).cwiseAbs() - half).cwiseMax(0.0);
    room = std::min(room, outside.norm() - scene_.visitor_radius());
  };
  for (int g : robot_geoms_) measure(g);
  for (const Attachment& a : held.list()) {
    for (int g = 0; g < m->ngeom; ++g) {
      if (m->body_rootid[m->geom_bodyid[g]] == a.body) measure(g);
    }
  }
  return room;
}

void WorldScript::drive_visitor(const mjModel* m, mjData* d, double time, const HeldObjects& held) {
  if (visitor_speed_ <= 0 || visitor_arc_.back() <= 0) return;
  const double dt = std::max(0.0, time - visitor_time_);
  visitor_time_ = time;
  const Eigen::Vector2d origin(scene_.environment().visitor.path[0][0],
                               scene_.environment().visitor.path[0][1]);
  Eigen::Vector2d heading;
  const Eigen::Vector2d here = visitor_at(visitor_walked_, nullptr);
  const double step = visitor_speed_ * dt;
  Eigen::Vector2d place = visitor_at(visitor_walked_ + step, &heading);
  const double room_next = room_from_robot(m, d, place, held);
  if (room_next < kVisitorYieldM && room_next < room_from_robot(m, d, here, held)) {
    // The robot is in the way: it turns round (the same place on the path, walked the other
    // way) and walks back.
    const double length = visitor_arc_.back();
    visitor_walked_ = 2 * length - std::fmod(visitor_walked_, 2 * length);
    place = visitor_at(visitor_walked_ + step, &heading);
  }
  visitor_walked_ += step;
  // Joint values are offsets from the first waypoint; heading = pi + yaw (facing -x at 0).
  d->qpos[visitor_qpos_[0]] = place.x() - origin.x();
  d->qpos[visitor_qpos_[1]] = place.y() - origin.y();
  d->qpos[visitor_qpos_[2]] = std::remainder(std::atan2(heading.y(), heading.x()) - M_PI, 2 * M_PI);
  d->qvel[visitor_dof_[0]] = visitor_speed_ * heading.x();
  d->qvel[visitor_dof_[1]] = visitor_speed_ * heading.y();
  d->qvel[visitor_dof_[2]] = 0;
}

void WorldScript::note_debris_places(const mjModel* m) {
  for (Debris& flake : debris_) {
    flake.pos = Eigen::Vector3d(m->body_pos[3 * flake.body], m->body_pos[3 * flake.body + 1],
                                m->body_pos[3 * flake.body + 2]);
  }
}

void WorldScript::restore_debris(mjModel* m) {
  for (const Debris& flake : debris_) {
    for (int i = 0; i < 3; ++i) m->body_pos[3 * flake.body + i] = flake.pos[i];
  }
  removed_.clear();
}

bool WorldScript::removed(int body) const {
  return std::find(removed_.begin(), removed_.end(), body) != removed_.end();
}

std::vector<int> WorldScript::collect_debris(mjModel* m, const mjData* d, const HeldObjects& held) {
  std::vector<int> now;
  if (held.empty()) return now;
  for (const ToolTip& tool : tool_tips_) {
    if (!held.holds_body(tool.body)) continue;
    const Eigen::Vector3d p(d->site_xpos[3 * tool.site], d->site_xpos[3 * tool.site + 1],
                            d->site_xpos[3 * tool.site + 2]);
    for (const Debris& flake : debris_) {
      if (removed(flake.body)) continue;
      const double* c = d->xpos + 3 * flake.body;
      const double up = p.z() - c[2];
      if (std::hypot(p.x() - c[0], p.y() - c[1]) <= kDebrisPickupRadius && up >= -0.01 &&
          up <= kDebrisPickupHeight) {
        m->body_pos[3 * flake.body + 2] = flake.pos.z() - 10.0;  // out of the world
        removed_.push_back(flake.body);
        now.push_back(flake.body);
      }
    }
  }
  return now;
}

}  // namespace taskmatrix::mujoco
