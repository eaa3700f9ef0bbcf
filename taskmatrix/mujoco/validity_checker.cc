#include "taskmatrix/mujoco/validity_checker.h"

#include <algorithm>
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

}  // namespace

bool raw_robot_in_collision(const Scene& scene, const mjModel* m, mjData* d) {
  mj_kinematics(m, d);
  mj_collision(m, d);
  return robot_contact(scene, d);
}

ValidityChecker::ValidityChecker(const Scene& scene, const mjModel* m, mjData* d,
                                 const std::vector<int>& moving_joints)
    : scene_(scene), m_(m), d_(d), joints_(moving_joints) {
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
  // Pairs the moving joints can change are tested per query; the rest once, here.
  for (const GeomPair& p : scene.robot_geom_pairs()) {
    if (moving[m->geom_bodyid[p.g1]] || moving[m->geom_bodyid[p.g2]]) {
      changing_pairs_.push_back(p);
    } else if (!static_collision_ && pair_in_contact(p)) {
      static_collision_ = true;
    }
  }
}

bool ValidityChecker::pair_in_contact(const GeomPair& p) {
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
  for (const GeomPair& p : changing_pairs_) {
    if (pair_in_contact(p)) return true;
  }
  return false;
}

}  // namespace taskmatrix::mujoco
