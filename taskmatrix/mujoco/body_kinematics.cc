#include "taskmatrix/mujoco/body_kinematics.h"

#include <algorithm>
#include <cmath>

namespace taskmatrix::mujoco {

void body_pose_from_parent(const mjModel* m, const mjtNum* qpos, int body, const mjtNum* parent_pos,
                           const mjtNum* parent_quat, const mjtNum* parent_mat, mjtNum* pos,
                           mjtNum* quat, mjtNum* mat, JointFrame* joints) {
  // Body frame in the parent.
  mju_rotVecMat(pos, m->body_pos + 3 * body, parent_mat);
  mju_addTo3(pos, parent_pos);
  mju_mulQuat(quat, parent_quat, m->body_quat + 4 * body);
  for (int k = 0; k < m->body_jntnum[body]; ++k) {
    const int j = m->body_jntadr[body] + k;
    const mjtNum q = qpos[m->jnt_qposadr[j]] - m->qpos0[m->jnt_qposadr[j]];
    mjtNum xmat[9], xaxis[3], xanchor[3];
    mju_quat2Mat(xmat, quat);
    mju_rotVecMat(xanchor, m->jnt_pos + 3 * j, xmat);
    mju_addTo3(xanchor, pos);
    mju_rotVecMat(xaxis, m->jnt_axis + 3 * j, xmat);
    if (joints) {
      mju_copy3(joints[k].anchor, xanchor);
      mju_copy3(joints[k].axis, xaxis);
    }
    if (m->jnt_type[j] == mjJNT_SLIDE) {
      mju_addToScl3(pos, xaxis, q);
    } else {  // hinge: rotate about the anchor
      mjtNum qloc[4], vec[3], tmp[4];
      mju_axisAngle2Quat(qloc, m->jnt_axis + 3 * j, q);
      mju_mulQuat(tmp, quat, qloc);
      mju_copy4(quat, tmp);
      mju_rotVecQuat(vec, m->jnt_pos + 3 * j, quat);
      mju_sub3(pos, xanchor, vec);
    }
  }
  mju_normalize4(quat);
  mju_quat2Mat(mat, quat);
}

void geom_pose_from_body(const mjModel* m, int geom, const mjtNum* body_pos,
                         const mjtNum* body_quat, const mjtNum* body_mat, mjtNum* pos,
                         mjtNum* mat) {
  mju_rotVecMat(pos, m->geom_pos + 3 * geom, body_mat);
  mju_addTo3(pos, body_pos);
  mjtNum q[4];
  mju_mulQuat(q, body_quat, m->geom_quat + 4 * geom);
  mju_quat2Mat(mat, q);
}

bool sphere_clear_of_box(const mjModel* m, const mjData* d, int box, const mjtNum* center,
                         mjtNum radius) {
  mjtNum rel[3], local[3];
  mju_sub3(rel, center, d->geom_xpos + 3 * box);
  mju_rotVecMatT(local, rel, d->geom_xmat + 9 * box);
  const mjtNum* half = m->geom_size + 3 * box;
  mjtNum outside = 0;
  for (int i = 0; i < 3; ++i) {
    const mjtNum beyond = std::abs(local[i]) - half[i];
    if (beyond > 0) outside += beyond * beyond;
  }
  return outside > radius * radius;
}

bool point_inside_geom(const mjModel* m, const mjData* d, int g, const mjtNum* point) {
  mjtNum rel[3], q[3];  // the point in the geom's frame
  mju_sub3(rel, point, d->geom_xpos + 3 * g);
  mju_rotVecMatT(q, rel, d->geom_xmat + 9 * g);
  const mjtNum* size = m->geom_size + 3 * g;
  switch (m->geom_type[g]) {
    case mjGEOM_SPHERE:
      return mju_norm3(q) < size[0];
    case mjGEOM_CAPSULE: {
      const mjtNum z = q[2] - std::clamp(q[2], -size[1], size[1]);
      return q[0] * q[0] + q[1] * q[1] + z * z < size[0] * size[0];
    }
    case mjGEOM_CYLINDER:
      return q[0] * q[0] + q[1] * q[1] < size[0] * size[0] && std::abs(q[2]) < size[1];
    case mjGEOM_ELLIPSOID: {
      mjtNum r = 0;
      for (int i = 0; i < 3; ++i) r += (q[i] / size[i]) * (q[i] / size[i]);
      return r < 1;
    }
    case mjGEOM_BOX:
      return std::abs(q[0]) < size[0] && std::abs(q[1]) < size[1] && std::abs(q[2]) < size[2];
    default:
      return false;
  }
}

double geom_support(const mjModel* m, const mjData* d, int g, const mjtNum* dir) {
  const mjtNum* c = d->geom_xpos + 3 * g;
  const mjtNum* r = d->geom_xmat + 9 * g;  // row-major: column k is the geom's axis k
  mjtNum local[3];                         // dir in the geom's frame
  for (int k = 0; k < 3; ++k) local[k] = r[k] * dir[0] + r[3 + k] * dir[1] + r[6 + k] * dir[2];
  const mjtNum* s = m->geom_size + 3 * g;
  double extent = 0;
  switch (m->geom_type[g]) {
    case mjGEOM_SPHERE:
      extent = s[0];
      break;
    case mjGEOM_CAPSULE:
      extent = s[1] * std::abs(local[2]) + s[0];
      break;
    case mjGEOM_CYLINDER:
      extent = s[1] * std::abs(local[2]) + s[0] * std::sqrt(std::max(0.0, 1 - local[2] * local[2]));
      break;
    case mjGEOM_BOX:
      extent = s[0] * std::abs(local[0]) + s[1] * std::abs(local[1]) + s[2] * std::abs(local[2]);
      break;
    case mjGEOM_ELLIPSOID:
      extent = std::sqrt(std::pow(s[0] * local[0], 2) + std::pow(s[1] * local[1], 2) +
                         std::pow(s[2] * local[2], 2));
      break;
    default:
      extent = m->geom_rbound[g];
  }
  return dir[0] * c[0] + dir[1] * c[1] + dir[2] * c[2] + extent;
}

}  // namespace taskmatrix::mujoco
