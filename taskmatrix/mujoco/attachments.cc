#include "taskmatrix/mujoco/attachments.h"

#include <algorithm>

namespace taskmatrix::mujoco {

std::vector<int> supports_of(const mjModel* m, const mjData* d, const Scene& scene, int body) {
  std::vector<int> out;
  for (int i = 0; i < d->ncon; ++i) {
    const mjContact& c = d->contact[i];
    const int r1 = m->body_rootid[m->geom_bodyid[c.geom1]];
    const int r2 = m->body_rootid[m->geom_bodyid[c.geom2]];
    const int other = r1 == body ? c.geom2 : (r2 == body ? c.geom1 : -1);
    if (other >= 0 && !scene.is_robot_geom(other) &&
        std::find(out.begin(), out.end(), other) == out.end()) {
      out.push_back(other);
    }
  }
  return out;
}

Attachment attachment_at(const Scene& scene, const mjModel* m, const mjData* d, int body,
                         int holder_body, std::string object, std::string side) {
  Attachment a;
  a.object = std::move(object);
  a.side = std::move(side);
  a.body = body;
  a.holder_body = holder_body;
  for (int b = a.holder_body; b < m->nbody; ++b) {
    int up = b;
    while (up > a.holder_body) up = m->body_parentid[up];
    if (up == a.holder_body) a.hand_bodies.push_back(b);
  }
  a.support_geoms = supports_of(m, d, scene, body);
  // Object frame in the holder frame, from the current poses.
  double inv_pos[3], inv_quat[4];
  mju_negPose(inv_pos, inv_quat, d->xpos + 3 * a.holder_body, d->xquat + 4 * a.holder_body);
  mju_mulPose(a.pos.data(), a.quat.data(), inv_pos, inv_quat, d->xpos + 3 * body,
              d->xquat + 4 * body);
  return a;
}

const Attachment* HeldObjects::find(std::string_view object) const {
  for (const Attachment& a : held_) {
    if (a.object == object) return &a;
  }
  return nullptr;
}

bool HeldObjects::holds_body(int body) const {
  return std::any_of(held_.begin(), held_.end(),
                     [&](const Attachment& a) { return a.body == body; });
}

int HeldObjects::remove(std::string_view object) {
  const auto it = std::find_if(held_.begin(), held_.end(),
                               [&](const Attachment& a) { return a.object == object; });
  if (it == held_.end()) return -1;
  const int body = it->body;
  held_.erase(it);
  return body;
}

std::vector<std::string> HeldObjects::objects() const {
  std::vector<std::string> names;
  for (const Attachment& a : held_) names.push_back(a.object);
  return names;
}

void HeldObjects::refresh_supports(const Scene& scene, const mjModel* m, const mjData* d) {
  for (Attachment& a : held_) {
    for (int g : supports_of(m, d, scene, a.body)) {
      if (std::find(a.support_geoms.begin(), a.support_geoms.end(), g) == a.support_geoms.end()) {
        a.support_geoms.push_back(g);
      }
    }
  }
}

}  // namespace taskmatrix::mujoco
