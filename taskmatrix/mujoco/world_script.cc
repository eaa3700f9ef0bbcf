#include "taskmatrix/mujoco/world_script.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace taskmatrix::mujoco {

WorldScript::WorldScript(const Scene& scene, const mjModel* m) : scene_(scene) {
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
  visitor_arc_ = {0.0};
  for (size_t i = 1; i < v.path.size(); ++i) {
    visitor_arc_.push_back(visitor_arc_.back() + std::hypot(v.path[i][0] - v.path[i - 1][0],
                                                            v.path[i][1] - v.path[i - 1][1]));
  }
  visitor_speed_ = speed_mps;
}

void WorldScript::drive_visitor(mjData* d, double time) const {
  if (visitor_speed_ <= 0) return;
  const auto& path = scene_.environment().visitor.path;
  const std::vector<double>& at = visitor_arc_;  // arc length at each waypoint
  const double length = at.back();
  if (length <= 0) return;
  double s = std::fmod(visitor_speed_ * time, 2 * length);
  const bool back = s > length;
  if (back) s = 2 * length - s;
  size_t i = 1;
  while (i + 1 < at.size() && at[i] < s) ++i;
  const double seg = at[i] - at[i - 1];
  const double f = seg > 0 ? (s - at[i - 1]) / seg : 0;
  double dx = path[i][0] - path[i - 1][0], dy = path[i][1] - path[i - 1][1];
  const double x = path[i - 1][0] + f * dx, y = path[i - 1][1] + f * dy;
  if (back) dx = -dx, dy = -dy;
  const double norm = std::hypot(dx, dy);
  // Joint values are offsets from the first waypoint; heading = pi + yaw (facing -x at 0).
  d->qpos[visitor_qpos_[0]] = x - path[0][0];
  d->qpos[visitor_qpos_[1]] = y - path[0][1];
  d->qpos[visitor_qpos_[2]] = std::remainder(std::atan2(dy, dx) - M_PI, 2 * M_PI);
  d->qvel[visitor_dof_[0]] = visitor_speed_ * dx / norm;
  d->qvel[visitor_dof_[1]] = visitor_speed_ * dy / norm;
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
