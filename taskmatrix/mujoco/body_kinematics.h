// Poses of single bodies from their parents' poses and the joint positions, by the formulas of
// MuJoCo's mj_kinematics for hinge and slide joints: for code that moves a few bodies of a
// model (the validity checker, IK on one chain) and needs their poses without recomputing the
// whole tree. And a bound tighter than MuJoCo's bounding spheres for box geoms.
#pragma once

#include <mujoco/mujoco.h>

namespace taskmatrix::mujoco {

// A joint's axis and anchor in world coordinates, as mj_kinematics writes xaxis and xanchor.
struct JointFrame {
  mjtNum anchor[3];
  mjtNum axis[3];
};

// Writes `body`'s world position, unit quaternion and rotation matrix from its parent's and
// qpos. Its joints must be hinges or slides. With `joints`, also each of the body's joints'
// world frame (body_jntnum entries, in order). The outputs may be the body's own entries in an
// mjData (xpos, xquat, xmat); they must not alias the parent's.
void body_pose_from_parent(const mjModel* m, const mjtNum* qpos, int body, const mjtNum* parent_pos,
                           const mjtNum* parent_quat, const mjtNum* parent_mat, mjtNum* pos,
                           mjtNum* quat, mjtNum* mat, JointFrame* joints = nullptr);

// Writes a geom's world position and rotation matrix from its body's pose.
void geom_pose_from_body(const mjModel* m, int geom, const mjtNum* body_pos,
                         const mjtNum* body_quat, const mjtNum* body_mat, mjtNum* pos, mjtNum* mat);

// Whether the sphere (`center`, `radius`) lies wholly outside box geom `box` as posed in `d`
// (its oriented box, not its bounding sphere).
bool sphere_clear_of_box(const mjModel* m, const mjData* d, int box, const mjtNum* center,
                         mjtNum radius);

// Whether `point` lies inside geom `g` as posed in `d`: spheres, capsules, cylinders,
// ellipsoids and boxes; never a plane or a mesh.
bool point_inside_geom(const mjModel* m, const mjData* d, int g, const mjtNum* point);

// The furthest point of geom `g` as posed in `d` along the unit direction `dir`, as dir . p:
// exact for spheres, capsules, cylinders, boxes and ellipsoids; other shapes by their bounding
// sphere.
double geom_support(const mjModel* m, const mjData* d, int g, const mjtNum* dir);

}  // namespace taskmatrix::mujoco
