#include "taskmatrix/mujoco/validity_checker.h"

#include <algorithm>
#include <set>
#include <stdexcept>
#include <string>

namespace taskmatrix::mujoco {
namespace {

bool robot_contact(const Scene& scene, const mjData* d) {
  for (int i = 0; i < d->ncon; ++i) {
    if (scene.is_robot_geom(d->contact[i].geom1) || scene.is_robot_geom(d->contact[i].geom2))
      return true;
  }
  return false;
}

// MuJoCo's body-pair filter (engine_collision_driver): same weld body, or weld parent/child.
bool body_pair_filtered(const mjModel* m, int b1, int b2) {
  const int w1 = m->body_weldid[b1], w2 = m->body_weldid[b2];
  if (w1 == w2) return true;
  const int p1 = m->body_weldid[m->body_parentid[w1]], p2 = m->body_weldid[m->body_parentid[w2]];
  const bool filter_parent = !(m->opt.disableflags & mjDSBL_FILTERPARENT);
  return filter_parent && w1 != 0 && w2 != 0 && (w1 == p2 || w2 == p1);
}

bool excluded(const mjModel* m, int b1, int b2) {
  const int lo = std::min(b1, b2), hi = std::max(b1, b2);
  const int signature = ((lo + 1) << 16) + hi + 1;
  for (int i = 0; i < m->nexclude; ++i) {
    if (m->exclude_signature[i] == signature) return true;
  }
  return false;
}

}  // namespace

bool raw_robot_in_collision(const Scene& scene, const mjModel* m, mjData* d) {
  mj_kinematics(m, d);
  mj_collision(m, d);
  return robot_contact(scene, d);
}

ValidityChecker::ValidityChecker(const Scene& scene, const mjModel* m, mjData* d,
                                 const std::vector<int>& moving_joints)
    : scene_(scene), m_(m), d_(d), joints_(moving_joints) {
  if (m->npair > 0)
    throw std::invalid_argument("models with explicit <contact><pair> are not supported");
  std::vector<char> moving(m->nbody, 0);
  for (int j : joints_) {
    if (j < 0 || j >= m->njnt || (m->jnt_type[j] != mjJNT_HINGE && m->jnt_type[j] != mjJNT_SLIDE) ||
        !scene.is_robot_body(m->jnt_bodyid[j])) {
      throw std::invalid_argument("joint id " + std::to_string(j) +
                                  " is not a hinge or slide joint of the robot");
    }
    qpos_adr_.push_back(m->jnt_qposadr[j]);
    moving[m->jnt_bodyid[j]] = 1;
  }
  for (int b = 1; b < m->nbody; ++b) {  // parents precede children
    if (moving[m->body_parentid[b]]) moving[b] = 1;
    if (moving[b]) moving_bodies_.push_back(b);
  }
  // Any body with a joint that is not listed but lies below a moving body would need full
  // kinematics: reject rather than compute wrong poses.
  for (int b : moving_bodies_) {
    for (int k = 0; k < m->body_jntnum[b]; ++k) {
      const int j = m->body_jntadr[b] + k;
      if (m->jnt_type[j] != mjJNT_HINGE && m->jnt_type[j] != mjJNT_SLIDE) {
        throw std::invalid_argument("a moving body carries a free or ball joint");
      }
    }
  }
  for (int g = 0; g < m->ngeom; ++g) {
    if (moving[m->geom_bodyid[g]]) moving_geoms_.push_back(g);
  }

  mj_kinematics(m, d);
  // Candidate pairs: at least one robot geom, not filtered by bodies or excludes, and able to
  // collide now or later (obstacle slots change their contype per layout: test at query time).
  std::set<int> slot_geoms;
  for (const ObstacleSlot& s : scene.obstacle_slots())
    slot_geoms.insert(s.geoms.begin(), s.geoms.end());
  auto can_ever_collide = [&](int g) {
    return slot_geoms.count(g) || m->geom_contype[g] || m->geom_conaffinity[g];
  };
  for (int g1 = 0; g1 < m->ngeom; ++g1) {
    if (!can_ever_collide(g1)) continue;
    for (int g2 = g1 + 1; g2 < m->ngeom; ++g2) {
      if (!can_ever_collide(g2)) continue;
      if (!scene.is_robot_geom(g1) && !scene.is_robot_geom(g2)) continue;
      const int b1 = m->geom_bodyid[g1], b2 = m->geom_bodyid[g2];
      if (body_pair_filtered(m, b1, b2) || excluded(m, b1, b2)) continue;
      Pair p{g1, g2, std::max(m->geom_margin[g1], m->geom_margin[g2])};
      if (m->geom_type[p.g1] > m->geom_type[p.g2]) std::swap(p.g1, p.g2);
      if (moving[b1] || moving[b2]) {
        changing_pairs_.push_back(p);
      } else if (!static_collision_ && pair_in_contact(p)) {
        static_collision_ = true;
      }
    }
  }
}

bool ValidityChecker::pair_in_contact(const Pair& p) {
  const mjModel* m = m_;
  const int g1 = p.g1, g2 = p.g2;
  if (!((m->geom_contype[g1] & m->geom_conaffinity[g2]) ||
        (m->geom_contype[g2] & m->geom_conaffinity[g1]))) {
    return false;
  }
  // Bounding spheres, as mj_collideGeoms does (planes have rbound 0 and skip this).
  if (m->geom_rbound[g1] > 0 && m->geom_rbound[g2] > 0) {
    const double* a = d_->geom_xpos + 3 * g1;
    const double* b = d_->geom_xpos + 3 * g2;
    const double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
    const double bound = m->geom_rbound[g1] + m->geom_rbound[g2] + p.margin;
    if (dx * dx + dy * dy + dz * dz > bound * bound) return false;
  }
  mjfCollision collide = mjCOLLISIONFUNC[m->geom_type[g1]][m->geom_type[g2]];
  if (!collide) return false;
  ++narrow_calls_;
  return collide(m, d_, scratch_, g1, g2, p.margin) > 0;
}

void ValidityChecker::update_moving_kinematics() {
  const mjModel* m = m_;
  mjData* d = d_;
  for (int b : moving_bodies_) {
    const int parent = m->body_parentid[b];
    double* xpos = d->xpos + 3 * b;
    double* xquat = d->xquat + 4 * b;
    // Body frame in the parent.
    mju_rotVecMat(xpos, m->body_pos + 3 * b, d->xmat + 9 * parent);
    mju_addTo3(xpos, d->xpos + 3 * parent);
    mju_mulQuat(xquat, d->xquat + 4 * parent, m->body_quat + 4 * b);
    for (int k = 0; k < m->body_jntnum[b]; ++k) {
      const int j = m->body_jntadr[b] + k;
      const double q = d->qpos[m->jnt_qposadr[j]] - m->qpos0[m->jnt_qposadr[j]];
      double xmat[9], xaxis[3], xanchor[3];
      mju_quat2Mat(xmat, xquat);
      mju_rotVecMat(xanchor, m->jnt_pos + 3 * j, xmat);
      mju_addTo3(xanchor, xpos);
      mju_rotVecMat(xaxis, m->jnt_axis + 3 * j, xmat);
      if (m->jnt_type[j] == mjJNT_SLIDE) {
        mju_addToScl3(xpos, xaxis, q);
      } else {  // hinge: rotate about the anchor
        double qloc[4], vec[3];
        mju_axisAngle2Quat(qloc, m->jnt_axis + 3 * j, q);
        double tmp[4];
        mju_mulQuat(tmp, xquat, qloc);
        mju_copy4(xquat, tmp);
        mju_rotVecQuat(vec, m->jnt_pos + 3 * j, xquat);
        mju_sub3(xpos, xanchor, vec);
      }
    }
    mju_normalize4(xquat);
    mju_quat2Mat(d->xmat + 9 * b, xquat);
  }
  for (int g : moving_geoms_) {
    const int b = m->geom_bodyid[g];
    mju_rotVecMat(d->geom_xpos + 3 * g, m->geom_pos + 3 * g, d->xmat + 9 * b);
    mju_addTo3(d->geom_xpos + 3 * g, d->xpos + 3 * b);
    double q[4];
    mju_mulQuat(q, d->xquat + 4 * b, m->geom_quat + 4 * g);
    mju_quat2Mat(d->geom_xmat + 9 * g, q);
  }
}

bool ValidityChecker::in_collision(const double* values) {
  ++checks_;
  for (size_t i = 0; i < qpos_adr_.size(); ++i) d_->qpos[qpos_adr_[i]] = values[i];
  if (static_collision_) return true;
  update_moving_kinematics();
  for (const Pair& p : changing_pairs_) {
    if (pair_in_contact(p)) return true;
  }
  return false;
}

}  // namespace taskmatrix::mujoco
