#include "taskmatrix/mujoco/validity_checker.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>

#include "taskmatrix/mujoco/body_kinematics.h"

namespace taskmatrix::mujoco {
namespace {

// Index of the attachment whose object contains `body`, or -1.
int attachment_of(const mjModel* m, int body, const std::vector<Attachment>& attachments) {
  const int root = m->body_rootid[body];
  for (size_t k = 0; k < attachments.size(); ++k) {
    if (attachments[k].body == root) return static_cast<int>(k);
  }
  return -1;
}

bool contains(const std::vector<int>& v, int x) {
  return std::find(v.begin(), v.end(), x) != v.end();
}

// Pose of the attached object from its holder's pose in `d`.
void attached_pose(const mjData* d, const Attachment& a, double pos[3], double quat[4]) {
  mju_rotVecMat(pos, a.pos.data(), d->xmat + 9 * a.holder_body);
  mju_addTo3(pos, d->xpos + 3 * a.holder_body);
  mju_mulQuat(quat, d->xquat + 4 * a.holder_body, a.quat.data());
  mju_normalize4(quat);
}

}  // namespace

void place_attachments(const mjModel* m, mjData* d, const std::vector<Attachment>& attachments) {
  for (const Attachment& a : attachments) {
    const int j = m->body_jntadr[a.body];
    double* q = d->qpos + m->jnt_qposadr[j];
    attached_pose(d, a, q, q + 3);
    mju_zero(d->qvel + m->jnt_dofadr[j], 6);
  }
}

bool counts_as_robot_collision(const Scene& scene, const mjModel* m, const mjContact& c,
                               const std::vector<Attachment>& attachments) {
  const int g[2] = {c.geom1, c.geom2};
  const int b[2] = {m->geom_bodyid[c.geom1], m->geom_bodyid[c.geom2]};
  const int k[2] = {attachments.empty() ? -1 : attachment_of(m, b[0], attachments),
                    attachments.empty() ? -1 : attachment_of(m, b[1], attachments)};
  if (!scene.is_robot_body(b[0]) && !scene.is_robot_body(b[1]) && k[0] < 0 && k[1] < 0) {
    return false;
  }
  if (scene.same_hand(b[0], b[1])) return false;  // a finger on a finger of the same hand
  for (int s = 0; s < 2; ++s) {
    if (k[s] < 0) continue;
    const Attachment& a = attachments[k[s]];
    const int other = 1 - s;
    if (contains(a.hand_bodies, b[other])) return false;
    if (contains(a.support_geoms, g[other])) return c.dist < -a.support_tolerance_m;
  }
  return true;
}

namespace {

// The contact of capsule `gc` with box `gb` (as posed in `d`) when the capsule's axis segment
// passes into the box, or false when it does not. MuJoCo 2.2.2's capsule-box function reports
// no contact for many such poses (a thigh through a table top 4 cm thick: 400 of 4779 poses of
// a capsule overlapping the top on a grid, every one with its segment inside the top), so a
// configuration with a leg through the table passed as valid and the planner, given it as a
// goal, searched its iterations for a way there. The depth is the least the capsule must move
// along one of the box's axes for its segment to leave the box, plus its radius; the normal
// points from the capsule to the box (MuJoCo's convention, geom1 to geom2); the point is the
// middle of the segment's part inside the box.
bool capsule_through_box(const mjModel* m, const mjData* d, int gc, int gb, mjContact* out) {
  const mjtNum* rb = d->geom_xmat + 9 * gb;  // row-major: column k is the box's axis k
  const mjtNum* rc = d->geom_xmat + 9 * gc;
  const mjtNum* half = m->geom_size + 3 * gb;
  const double radius = m->geom_size[3 * gc], length = m->geom_size[3 * gc + 1];
  double rel[3], p[3], a[3];  // the capsule's centre and axis in the box's frame
  for (int k = 0; k < 3; ++k) rel[k] = d->geom_xpos[3 * gc + k] - d->geom_xpos[3 * gb + k];
  for (int k = 0; k < 3; ++k) {
    p[k] = rb[k] * rel[0] + rb[3 + k] * rel[1] + rb[6 + k] * rel[2];
    a[k] = rb[k] * rc[2] + rb[3 + k] * rc[5] + rb[6 + k] * rc[8];
  }
  // The segment p + t a, t in [-length, length], clipped to the box's slabs.
  double t0 = -length, t1 = length;
  for (int k = 0; k < 3; ++k) {
    if (std::abs(a[k]) < 1e-12) {
      if (std::abs(p[k]) > half[k]) return false;
      continue;
    }
    double ta = (-half[k] - p[k]) / a[k], tb = (half[k] - p[k]) / a[k];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  double depth = INFINITY;
  int axis = 0;
  double sign = 1;
  for (int k = 0; k < 3; ++k) {
    const double extent = length * std::abs(a[k]);
    const double up = half[k] - (p[k] - extent), down = (p[k] + extent) + half[k];
    if (up < depth) depth = up, axis = k, sign = 1;
    if (down < depth) depth = down, axis = k, sign = -1;
  }
  *out = mjContact{};
  out->dist = -(depth + radius);
  const double t = 0.5 * (t0 + t1);
  for (int k = 0; k < 3; ++k) {
    double local[3] = {p[0] + t * a[0], p[1] + t * a[1], p[2] + t * a[2]};
    out->pos[k] = d->geom_xpos[3 * gb + k] + rb[3 * k] * local[0] + rb[3 * k + 1] * local[1] +
                  rb[3 * k + 2] * local[2];
    // The capsule leaves along `sign` times the box's axis: the box lies the other way.
    out->frame[k] = -sign * rb[3 * k + axis];
  }
  return true;
}

// Full MuJoCo pipeline at the state in `d`: kinematics, held objects placed, contacts; with
// `complete`, then the contacts MuJoCo's capsule-box function misses (capsule_through_box) of
// the robot's capsule-box pairs its collision bits allow, appended while the contact array has
// room.
void collide_whole_model(const Scene& scene, const mjModel* m, mjData* d,
                         const std::vector<Attachment>& attachments, bool complete) {
  mj_kinematics(m, d);
  if (!attachments.empty()) {
    place_attachments(m, d, attachments);
    mj_kinematics(m, d);
  }
  mj_collision(m, d);
  if (!complete) return;
  for (const GeomPair& p : scene.robot_geom_pairs()) {
    if (m->geom_type[p.g1] != mjGEOM_CAPSULE || m->geom_type[p.g2] != mjGEOM_BOX) continue;
    if (!((m->geom_contype[p.g1] & m->geom_conaffinity[p.g2]) ||
          (m->geom_contype[p.g2] & m->geom_conaffinity[p.g1]))) {
      continue;
    }
    if (mju_dist3(d->geom_xpos + 3 * p.g1, d->geom_xpos + 3 * p.g2) >
        m->geom_rbound[p.g1] + m->geom_rbound[p.g2]) {
      continue;
    }
    mjContact c;
    if (d->ncon >= m->nconmax || !capsule_through_box(m, d, p.g1, p.g2, &c)) continue;
    bool found = false;
    for (int i = 0; i < d->ncon && !found; ++i) {
      const mjContact& o = d->contact[i];
      found = (o.geom1 == p.g1 && o.geom2 == p.g2) || (o.geom1 == p.g2 && o.geom2 == p.g1);
    }
    if (found) continue;
    c.geom1 = p.g1;
    c.geom2 = p.g2;
    d->contact[d->ncon++] = c;
  }
}

// A contact the narrow phase reports counts unless the pair may touch (`tolerance` > 0) and it
// is no deeper than that.
bool counts_as_contact(double dist, double tolerance) {
  return tolerance <= 0 || dist < -tolerance;
}

// Half the extent of box `g` along the unit direction `n` (world).
double box_half_along(const mjModel* m, const mjData* d, int g, const mjtNum* n) {
  const mjtNum* r = d->geom_xmat + 9 * g;  // row-major: column k is the box's axis k
  const mjtNum* size = m->geom_size + 3 * g;
  double half = 0;
  for (int k = 0; k < 3; ++k) {
    half += size[k] * std::abs(r[k] * n[0] + r[3 + k] * n[1] + r[6 + k] * n[2]);
  }
  return half;
}

// Corrects the contacts of a box-box pair (as posed in `d`, found within `margin`) that are
// deeper along their normal than the two boxes' projections on it overlap: two boxes cannot
// interpenetrate along a direction further than that, and where the projections are apart
// the boxes are apart. MuJoCo 2.2.2's box-box function reports such contacts: a point as deep
// as a box is wide added to a resting contact (a vacuum's battery resting on a table turned 20
// degrees in its room reported 0.29-1.09 m into the top, and the solver threw the vacuum into
// the air), and penetrations of centimetres for boxes a few millimetres to centimetres apart
// (a palm beside the juice box: 3-12 cm deep with the boxes 0.4-2 cm apart, every axis of the
// separating-axis test checked). Such a contact is given the depth (or distance) the overlap
// allows, and dropped where that lies beyond the margin (the pair would have no contact).
// Returns the contacts kept, in order.
int correct_box_box_contacts(const mjModel* m, const mjData* d, int g1, int g2, double margin,
                             mjContact* con, int n) {
  constexpr double kTolerance = 0.001;  // m: MuJoCo's points are not exact
  const mjtNum* a = d->geom_xpos + 3 * g1;
  const mjtNum* b = d->geom_xpos + 3 * g2;
  int kept = 0;
  for (int i = 0; i < n; ++i) {
    const mjtNum* normal = con[i].frame;
    const double apart =
        std::abs((b[0] - a[0]) * normal[0] + (b[1] - a[1]) * normal[1] + (b[2] - a[2]) * normal[2]);
    // The least signed distance along the normal the two boxes allow.
    const double least =
        apart - box_half_along(m, d, g1, normal) - box_half_along(m, d, g2, normal);
    if (con[i].dist < least - kTolerance) {
      if (least > margin) continue;
      con[i].dist = least;
    }
    if (kept != i) con[kept] = con[i];
    ++kept;
  }
  return kept;
}

}  // namespace

int collide_geoms(const mjModel* m, mjData* d, const GeomPair& p, double margin, mjContact* out,
                  std::uint64_t* narrow_calls) {
  const int g1 = p.g1, g2 = p.g2;
  if (!((m->geom_contype[g1] & m->geom_conaffinity[g2]) ||
        (m->geom_contype[g2] & m->geom_conaffinity[g1]))) {
    return 0;
  }
  // Bounding spheres, as mj_collideGeoms does (planes have rbound 0 and skip this).
  const mjtNum r1 = m->geom_rbound[g1], r2 = m->geom_rbound[g2];
  if (r1 > 0 && r2 > 0) {
    const double* a = d->geom_xpos + 3 * g1;
    const double* b = d->geom_xpos + 3 * g2;
    const double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
    const double bound = r1 + r2 + margin;
    if (dx * dx + dy * dy + dz * dz > bound * bound) return 0;
    // A box's bounding sphere is loose (a wall's reaches metres past it): the other geom's
    // sphere against the box itself.
    if (m->geom_type[g1] == mjGEOM_BOX &&
        sphere_clear_of_box(m, d, g1, d->geom_xpos + 3 * g2, r2 + margin)) {
      return 0;
    }
    if (m->geom_type[g2] == mjGEOM_BOX &&
        sphere_clear_of_box(m, d, g2, d->geom_xpos + 3 * g1, r1 + margin)) {
      return 0;
    }
  }
  mjfCollision fn = mjCOLLISIONFUNC[m->geom_type[g1]][m->geom_type[g2]];
  if (!fn) return 0;
  if (narrow_calls) ++*narrow_calls;
  int n = fn(m, d, out, g1, g2, margin);
  if (m->geom_type[g1] == mjGEOM_BOX && m->geom_type[g2] == mjGEOM_BOX) {
    n = correct_box_box_contacts(m, d, g1, g2, margin, out, n);
  } else if (n == 0 && m->geom_type[g1] == mjGEOM_CAPSULE && m->geom_type[g2] == mjGEOM_BOX) {
    n = capsule_through_box(m, d, g1, g2, out) ? 1 : 0;
  }
  for (int i = 0; i < n; ++i) {
    out[i].geom1 = g1;
    out[i].geom2 = g2;
  }
  return n;
}

bool raw_robot_in_collision(const Scene& scene, const mjModel* m, mjData* d,
                            const std::vector<Attachment>& attachments) {
  collide_whole_model(scene, m, d, attachments, /*complete=*/false);
  for (int i = 0; i < d->ncon; ++i) {
    if (counts_as_robot_collision(scene, m, d->contact[i], attachments)) return true;
  }
  return false;
}

bool reference_robot_in_collision(const Scene& scene, const mjModel* m, mjData* d,
                                  const std::vector<Attachment>& attachments) {
  collide_whole_model(scene, m, d, attachments, /*complete=*/true);
  for (int i = 0; i < d->ncon; ++i) {
    if (counts_as_robot_collision(scene, m, d->contact[i], attachments)) return true;
  }
  return false;
}

ValidityChecker::ValidityChecker(const Scene& scene, const mjModel* m, mjData* d,
                                 const std::vector<int>& moving_joints,
                                 const std::vector<Attachment>& attachments,
                                 const std::vector<int>& touch_geoms, double touch_depth_m)
    : scene_(scene), m_(m), d_(d), joints_(moving_joints), attachments_(attachments) {
  auto touch_tolerance = [&](const GeomPair& p) {
    return contains(touch_geoms, p.g1) || contains(touch_geoms, p.g2) ? touch_depth_m : 0.0;
  };
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

  // Attached objects: a free body under the world whose subtree has no other joint.
  std::vector<int> object_of(m->nbody, -1);
  for (size_t k = 0; k < attachments_.size(); ++k) {
    const Attachment& a = attachments_[k];
    if (a.body <= 0 || a.body >= m->nbody || m->body_parentid[a.body] != 0 ||
        m->body_jntnum[a.body] != 1 || m->jnt_type[m->body_jntadr[a.body]] != mjJNT_FREE ||
        !scene.is_robot_body(a.holder_body)) {
      throw std::invalid_argument(
          "an attached object must be a free body under the world, "
          "held by a robot body");
    }
    object_of[a.body] = static_cast<int>(k);
    if (moving[a.holder_body]) moving_attachments_.push_back(k);
  }
  for (int b = 1; b < m->nbody; ++b) {
    const int parent_object = object_of[m->body_parentid[b]];
    if (parent_object < 0) continue;
    if (m->body_jntnum[b] > 0) {
      throw std::invalid_argument("an attached object has a joint below its root body");
    }
    object_of[b] = parent_object;
  }

  for (int adr : qpos_adr_) bound_values_.push_back(d->qpos[adr]);
  mj_kinematics(m, d);
  for (const Attachment& a : attachments_) place_attached(a);
  // The nearest body at or above each body that a moving joint turns or slides (0: none).
  // Two of the robot's bodies with the same one are carried alike by the moving joints (an arm
  // left as it is while the base turns; both still, too): no moving joint lies between them,
  // and their pair never changes.
  std::vector<int> carried_by(m->nbody, 0);
  for (int j : joints_) carried_by[m->jnt_bodyid[j]] = m->jnt_bodyid[j];
  for (int b = 1; b < m->nbody; ++b) {  // parents precede children
    if (carried_by[b] != b) carried_by[b] = carried_by[m->body_parentid[b]];
  }
  // Pairs the moving joints can change are tested per query; the rest once, here. A pair of
  // the robot's own links carried alike is left out: what it is at the start (touching or
  // not) it stays, whatever the plan.
  for (const GeomPair& p : scene.robot_geom_pairs()) {
    const int b1 = m->geom_bodyid[p.g1], b2 = m->geom_bodyid[p.g2];
    if (object_of[b1] >= 0 || object_of[b2] >= 0) continue;
    if (carried_by[b1] == carried_by[b2] && scene.is_robot_body(b1) && scene.is_robot_body(b2)) {
      continue;
    }
    if (moving[b1] || moving[b2]) {
      changing_pairs_.push_back(p);
      // Robot-world pairs keep the planning margin, except against the floor, which the
      // base's lowest geoms always stay a few millimetres above as the base moves.
      const bool with_world =
          !scene.is_robot_body(m->geom_bodyid[p.g1]) || !scene.is_robot_body(m->geom_bodyid[p.g2]);
      const bool floor = m->geom_type[p.g1] == mjGEOM_PLANE || m->geom_type[p.g2] == mjGEOM_PLANE;
      changing_pair_with_world_.push_back(with_world && !floor);
      changing_pair_tolerance_.push_back(touch_tolerance(p));
    } else {
      note_static_contact(p, touch_tolerance(p));
    }
  }
  for (size_t k = 0; k < attachments_.size(); ++k) {
    const Attachment& a = attachments_[k];
    const bool object_moves = moving[a.holder_body];
    for (int g1 = 0; g1 < m->ngeom; ++g1) {
      if (object_of[m->geom_bodyid[g1]] != static_cast<int>(k)) continue;
      for (int g2 = 0; g2 < m->ngeom; ++g2) {
        const int b2 = m->geom_bodyid[g2];
        if (object_of[b2] == static_cast<int>(k) || contains(a.hand_bodies, b2)) continue;
        // Two held objects: keep the pair once, under the first.
        if (object_of[b2] >= 0 && object_of[b2] < static_cast<int>(k)) continue;
        const std::optional<GeomPair> p = scene.collidable_pair(g1, g2);
        if (!p) continue;
        const double tolerance =
            std::max(contains(a.support_geoms, g2) ? a.support_tolerance_m : 0.0,
                     contains(touch_geoms, g2) ? touch_depth_m : 0.0);
        const bool other_moves =
            moving[b2] || (object_of[b2] >= 0 && moving[attachments_[object_of[b2]].holder_body]);
        if (object_moves || other_moves) {
          attached_pairs_.push_back({*p, tolerance, !scene.is_robot_body(b2) && object_of[b2] < 0});
        } else {
          note_static_contact(*p, tolerance);
        }
      }
    }
  }
  moving_ = std::move(moving);
  object_of_ = std::move(object_of);
}

std::vector<double> ValidityChecker::subtree_reach() const {
  const mjModel* m = m_;
  const std::vector<char>& moving = moving_;
  const std::vector<int>& object_of = object_of_;
  auto norm3 = [](const mjtNum* v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); };
  // How far body b's origin can be from its parent's: its offset, plus twice each hinge's
  // anchor offset (the origin turns about the anchor), plus each slide's farthest travel.
  auto origin_offset = [&](int b) {
    double offset = norm3(m->body_pos + 3 * b);
    for (int k = 0; k < m->body_jntnum[b]; ++k) {
      const int j = m->body_jntadr[b] + k;
      if (m->jnt_type[j] == mjJNT_HINGE) offset += 2 * norm3(m->jnt_pos + 3 * j);
      if (m->jnt_type[j] == mjJNT_SLIDE) {
        offset += std::max(std::abs(m->jnt_range[2 * j]), std::abs(m->jnt_range[2 * j + 1]));
      }
    }
    return offset;
  };
  // Children follow their parents in MuJoCo's body order: visit in reverse, held objects first
  // (their pose in the holder's frame is fixed; no joints inside them).
  std::vector<double> reach(m->nbody, 0.0);
  auto add_geoms = [&](int b) {
    for (int k = 0; k < m->body_geomnum[b]; ++k) {
      const int g = m->body_geomadr[b] + k;
      reach[b] = std::max(reach[b], norm3(m->geom_pos + 3 * g) + m->geom_rbound[g]);
    }
  };
  for (int b = m->nbody - 1; b > 0; --b) {
    if (object_of[b] < 0) continue;
    add_geoms(b);
    const int parent = m->body_parentid[b];
    if (object_of[parent] >= 0)
      reach[parent] = std::max(reach[parent], origin_offset(b) + reach[b]);
  }
  for (int b = m->nbody - 1; b > 0; --b) {
    if (!moving[b]) continue;
    add_geoms(b);
    for (const Attachment& a : attachments_) {
      if (a.holder_body == b) reach[b] = std::max(reach[b], norm3(a.pos.data()) + reach[a.body]);
    }
    const int parent = m->body_parentid[b];
    if (moving[parent]) reach[parent] = std::max(reach[parent], origin_offset(b) + reach[b]);
  }
  return reach;
}

void ValidityChecker::compute_clearance_groups() {
  if (joint_reach_.size() == joints_.size()) return;
  const mjModel* m = m_;
  const std::vector<char>& moving = moving_;
  const std::vector<int>& object_of = object_of_;
  auto norm3 = [](const mjtNum* v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); };
  const std::vector<double> reach = subtree_reach();
  joint_reach_.clear();
  for (int j : joints_) {
    joint_reach_.push_back(
        m->jnt_type[j] == mjJNT_SLIDE ? 1.0 : norm3(m->jnt_pos + 3 * j) + reach[m->jnt_bodyid[j]]);
  }

  // The moving joints at or above each body (a held object's: its holder's); parents first.
  const size_t nj = joints_.size();
  std::vector<std::vector<char>> above(m->nbody, std::vector<char>(nj, 0));
  for (int b = 1; b < m->nbody; ++b) {
    if (!moving[b]) continue;
    above[b] = above[m->body_parentid[b]];
    for (size_t i = 0; i < nj; ++i) {
      if (m->jnt_bodyid[joints_[i]] == b) above[b][i] = 1;
    }
  }
  auto joints_above = [&](int b) -> const std::vector<char>& {
    return above[object_of[b] >= 0 ? attachments_[static_cast<size_t>(object_of[b])].holder_body
                                   : b];
  };
  std::map<std::vector<char>, int> index;
  auto group_of = [&](const GeomPair& p) {
    std::vector<char> mask = joints_above(m->geom_bodyid[p.g1]);
    const std::vector<char>& other = joints_above(m->geom_bodyid[p.g2]);
    for (size_t i = 0; i < nj; ++i) mask[i] = mask[i] != other[i];
    const auto [it, added] = index.emplace(mask, static_cast<int>(clearance_groups_.size()));
    if (added) clearance_groups_.push_back(std::move(mask));
    return it->second;
  };
  changing_pair_group_.clear();
  for (const GeomPair& p : changing_pairs_) changing_pair_group_.push_back(group_of(p));
  for (AttachedPair& p : attached_pairs_) p.group = group_of(p.pair);
}

bool ValidityChecker::clearances_to_contact(const double* values, double cap_m,
                                            const std::vector<char>& wanted,
                                            std::vector<double>& clearances) {
  compute_clearance_groups();
  clearances.assign(clearance_groups_.size(), cap_m);
  if (!begin_check(values)) return false;
  // Each pair is measured only up to its group's smallest clearance so far.
  auto visit = [&](const GeomPair& p, double tolerance, int group) {
    if (!wanted[static_cast<size_t>(group)]) return;
    double& clearance = clearances[static_cast<size_t>(group)];
    // MuJoCo's distance below which the pair counts as in contact.
    const double contact_at = tolerance > 0 ? -tolerance : p.margin;
    const double dist = pair_distance(p, std::max(contact_at + clearance, 1e-9));
    clearance = std::min(clearance, dist - contact_at);
  };
  // Groups of pairs whose bounding spheres are farther apart than the cap are skipped whole.
  any_changing_pair(
      cap_m,
      [&](size_t k) {
        visit(changing_pairs_[k], changing_pair_tolerance_[k], changing_pair_group_[k]);
        return false;
      },
      /*extra_for_all=*/true);
  for (const AttachedPair& p : attached_pairs_) visit(p.pair, p.tolerance, p.group);
  return true;
}

void ValidityChecker::group_changing_pairs() {
  const mjModel* m = m_;
  const mjData* d = d_;
  std::vector<int> local(m->nbody, -1);  // moving body -> its index among moving_bodies_
  for (size_t i = 0; i < moving_bodies_.size(); ++i) local[moving_bodies_[i]] = static_cast<int>(i);
  // (moving body, fixed body) -> group
  std::vector<int> group_of(moving_bodies_.size() * static_cast<size_t>(m->nbody), -1);
  struct Box {
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  };
  std::vector<Box> fixed_box;  // per group: the fixed geoms' spheres' bounding box
  auto sides = [&](const GeomPair& p, int& gm, int& gf) {
    const bool first_moves = local[m->geom_bodyid[p.g1]] >= 0;
    gm = first_moves ? p.g1 : p.g2;
    gf = first_moves ? p.g2 : p.g1;
  };
  std::vector<int> group_of_pair(changing_pairs_.size(), -1);
  for (size_t k = 0; k < changing_pairs_.size(); ++k) {
    const GeomPair& p = changing_pairs_[k];
    const bool bounded = m->geom_rbound[p.g1] > 0 && m->geom_rbound[p.g2] > 0;
    const bool both_move = local[m->geom_bodyid[p.g1]] >= 0 && local[m->geom_bodyid[p.g2]] >= 0;
    if (!bounded || both_move) {
      ungrouped_pairs_.push_back(static_cast<int>(k));
      continue;
    }
    int gm, gf;
    sides(p, gm, gf);
    const int bm = m->geom_bodyid[gm];
    int& gi = group_of[static_cast<size_t>(local[bm]) * m->nbody + m->geom_bodyid[gf]];
    if (gi < 0) {
      gi = static_cast<int>(pair_groups_.size());
      pair_groups_.emplace_back().moving_body = bm;
      fixed_box.emplace_back();
    }
    group_of_pair[k] = gi;
    PairGroup& g = pair_groups_[gi];
    g.pairs.push_back(static_cast<int>(k));
    g.margin = std::max(g.margin, p.margin);
    g.with_world = g.with_world || changing_pair_with_world_[k];
    // The moving side's radius about its body's origin (rigid: the same at every check).
    g.radius =
        std::max(g.radius, mju_dist3(d->geom_xpos + 3 * gm, d->xpos + 3 * bm) + m->geom_rbound[gm]);
    Box& b = fixed_box[gi];
    for (int a = 0; a < 3; ++a) {
      b.lo[a] = std::min(b.lo[a], d->geom_xpos[3 * gf + a] - m->geom_rbound[gf]);
      b.hi[a] = std::max(b.hi[a], d->geom_xpos[3 * gf + a] + m->geom_rbound[gf]);
    }
  }
  // The fixed side's sphere: centred on that box, holding every fixed geom's sphere.
  for (size_t i = 0; i < pair_groups_.size(); ++i) {
    for (int a = 0; a < 3; ++a) {
      pair_groups_[i].fixed_center[a] = 0.5 * (fixed_box[i].lo[a] + fixed_box[i].hi[a]);
    }
  }
  std::vector<double> fixed_radius(pair_groups_.size(), 0.0);
  for (size_t k = 0; k < changing_pairs_.size(); ++k) {
    const int gi = group_of_pair[k];
    if (gi < 0) continue;
    int gm, gf;
    sides(changing_pairs_[k], gm, gf);
    fixed_radius[gi] =
        std::max(fixed_radius[gi], mju_dist3(d->geom_xpos + 3 * gf, pair_groups_[gi].fixed_center) +
                                       m->geom_rbound[gf]);
  }
  for (size_t i = 0; i < pair_groups_.size(); ++i) pair_groups_[i].radius += fixed_radius[i];
}

bool ValidityChecker::group_near(const PairGroup& g, double extra, bool extra_for_all) const {
  const double* c = d_->xpos + 3 * g.moving_body;
  const double dx = c[0] - g.fixed_center[0], dy = c[1] - g.fixed_center[1],
               dz = c[2] - g.fixed_center[2];
  const double bound = g.radius + g.margin + (g.with_world || extra_for_all ? extra : 0.0);
  return dx * dx + dy * dy + dz * dz <= bound * bound;
}

template <class Hit>
bool ValidityChecker::any_changing_pair(double extra, Hit hit, bool extra_for_all) {
  // Grouping costs about as much as a few checks: a checker used once visits every pair.
  if (pair_visits_ < 2 && ++pair_visits_ == 2) group_changing_pairs();
  if (pair_visits_ < 2) {
    for (size_t k = 0; k < changing_pairs_.size(); ++k) {
      if (hit(k)) return true;
    }
    return false;
  }
  for (int k : ungrouped_pairs_) {
    if (hit(static_cast<size_t>(k))) return true;
  }
  for (const PairGroup& g : pair_groups_) {
    if (!group_near(g, extra, extra_for_all)) continue;
    for (int k : g.pairs) {
      if (hit(static_cast<size_t>(k))) return true;
    }
  }
  return false;
}

void ValidityChecker::place_attached(const Attachment& a) {
  const mjModel* m = m_;
  mjData* d = d_;
  attached_pose(d, a, d->xpos + 3 * a.body, d->xquat + 4 * a.body);
  mju_quat2Mat(d->xmat + 9 * a.body, d->xquat + 4 * a.body);
  for (int b = a.body + 1; b < m->nbody && m->body_rootid[b] == a.body; ++b) {
    const int parent = m->body_parentid[b];
    mju_rotVecMat(d->xpos + 3 * b, m->body_pos + 3 * b, d->xmat + 9 * parent);
    mju_addTo3(d->xpos + 3 * b, d->xpos + 3 * parent);
    mju_mulQuat(d->xquat + 4 * b, d->xquat + 4 * parent, m->body_quat + 4 * b);
    mju_quat2Mat(d->xmat + 9 * b, d->xquat + 4 * b);
  }
  for (int g = 0; g < m->ngeom; ++g) {
    const int b = m->geom_bodyid[g];
    if (m->body_rootid[b] != a.body) continue;
    geom_pose_from_body(m, g, d->xpos + 3 * b, d->xquat + 4 * b, d->xmat + 9 * b,
                        d->geom_xpos + 3 * g, d->geom_xmat + 9 * g);
  }
}

int ValidityChecker::collide(const GeomPair& p, double margin) {
  return collide_geoms(m_, d_, p, margin, scratch_, &narrow_calls_);
}

void ValidityChecker::note_static_contact(const GeomPair& p, double tolerance) {
  // In contact as pair_in_contact judges it, keeping the deepest penetration.
  const int n = collide(p, p.margin);
  for (int i = 0; i < n; ++i) {
    if (!counts_as_contact(scratch_[i].dist, tolerance)) continue;
    static_collision_ = true;
    static_depth_m_ = std::max(static_depth_m_, -scratch_[i].dist);
  }
}

void ValidityChecker::accept_static_contacts() { static_collision_ = false; }

bool ValidityChecker::pair_in_contact(const GeomPair& p, double tolerance) {
  const int n = collide(p, p.margin);
  if (tolerance <= 0) return n > 0;
  for (int i = 0; i < n; ++i) {
    if (counts_as_contact(scratch_[i].dist, tolerance)) return true;
  }
  return false;
}

double ValidityChecker::pair_distance(const GeomPair& p, double cap) {
  auto min_dist = [&](int n) {
    double dist = INFINITY;
    for (int i = 0; i < n; ++i) dist = std::min(dist, scratch_[i].dist);
    return dist;
  };
  // Touching: MuJoCo's own contact distance (negative when penetrating).
  if (const int n = collide(p, p.margin); n > 0) return std::min(cap, min_dist(n));
  const int n_cap = collide(p, cap);
  if (n_cap == 0) return cap;
  // Apart but closer than the cap. With a margin, MuJoCo's box and cylinder (libccd) functions
  // detect the pair reliably but can misreport its distance, so the distance is the smallest
  // margin at which a contact appears: accept the reported distance if it brackets that
  // margin, else bisect.
  const double reported = min_dist(n_cap);
  constexpr double kResolution = 1e-5;
  if (reported >= 0 && reported < cap && collide(p, reported + kResolution) > 0 &&
      (reported <= kResolution || collide(p, reported - kResolution) == 0)) {
    return reported;
  }
  double lo = 0, hi = cap;  // no contact at lo, contact at hi
  while (hi - lo > kResolution) {
    const double mid = 0.5 * (lo + hi);
    (collide(p, mid) > 0 ? hi : lo) = mid;
  }
  return 0.5 * (lo + hi);
}

void ValidityChecker::update_moving_kinematics() {
  const mjModel* m = m_;
  mjData* d = d_;
  for (int b : moving_bodies_) {
    const int parent = m->body_parentid[b];
    body_pose_from_parent(m, d->qpos, b, d->xpos + 3 * parent, d->xquat + 4 * parent,
                          d->xmat + 9 * parent, d->xpos + 3 * b, d->xquat + 4 * b, d->xmat + 9 * b);
  }
  for (int g : moving_geoms_) {
    const int b = m->geom_bodyid[g];
    geom_pose_from_body(m, g, d->xpos + 3 * b, d->xquat + 4 * b, d->xmat + 9 * b,
                        d->geom_xpos + 3 * g, d->geom_xmat + 9 * g);
  }
}

void ValidityChecker::set_values(const double* values) {
  for (size_t i = 0; i < qpos_adr_.size(); ++i) d_->qpos[qpos_adr_[i]] = values[i];
  update_moving_kinematics();
  for (size_t k : moving_attachments_) place_attached(attachments_[k]);
}

bool ValidityChecker::begin_check(const double* values, bool count) {
  if (count) ++checks_;
  route_hit_ = -1;
  if (static_collision_) {
    for (size_t i = 0; i < qpos_adr_.size(); ++i) d_->qpos[qpos_adr_[i]] = values[i];
    return false;
  }
  set_values(values);
  return true;
}

void ValidityChecker::keep_off_visitor_route(double berth_m) {
  route_.clear();
  route_groups_.clear();
  const core::VisitorSpec& visitor = scene_.environment().visitor;
  if (visitor.body.empty() || visitor.path.empty()) return;
  for (const auto& p : visitor.path) route_.emplace_back(p[0], p[1]);
  route_radius_ = scene_.visitor_radius() + std::max(0.0, berth_m);
  const std::vector<double> reach = subtree_reach();
  // Measured at the bound state: geoms already on the route are left out.
  set_values(bound_values_.data());
  for (int g = 0; g < m_->ngeom; ++g) {
    if (m_->geom_contype[g] == 0 && m_->geom_conaffinity[g] == 0) continue;
    int b = m_->geom_bodyid[g];
    if (object_of_[b] >= 0) b = attachments_[static_cast<size_t>(object_of_[b])].holder_body;
    if (!moving_[b] || !scene_.is_robot_body(b)) continue;
    if (geom_on_route(g)) continue;
    while (moving_[m_->body_parentid[b]]) b = m_->body_parentid[b];
    auto group = std::find_if(route_groups_.begin(), route_groups_.end(),
                              [&](const RouteGroup& r) { return r.root == b; });
    if (group == route_groups_.end()) {
      route_groups_.push_back({b, reach[b], {}});
      group = route_groups_.end() - 1;
    }
    group->geoms.push_back(g);
  }
  route_hit_ = -1;
}

double ValidityChecker::distance_to_route(const Eigen::Vector2d& c, Eigen::Vector2d* away) const {
  Eigen::Vector2d nearest = route_.front();
  for (size_t i = 1; i < route_.size(); ++i) {
    const Eigen::Vector2d a = route_[i - 1], ab = route_[i] - a;
    const double len2 = ab.squaredNorm();
    const double t = len2 > 0 ? std::clamp((c - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
    if ((c - (a + t * ab)).squaredNorm() < (c - nearest).squaredNorm()) nearest = a + t * ab;
  }
  if (away) *away = c - nearest;
  return (c - nearest).norm();
}

bool ValidityChecker::geom_on_route(int g) const {
  Eigen::Vector2d away;
  const double dist =
      distance_to_route(Eigen::Vector2d(d_->geom_xpos[3 * g], d_->geom_xpos[3 * g + 1]), &away);
  const double rbound = m_->geom_rbound[g];
  if (dist >= route_radius_ + rbound) return false;
  // How far the geom reaches from its centre towards the route: the box round it, seen along
  // that direction (within its bounding sphere).
  const Eigen::Vector2d half = horizontal_half_extent(m_, d_, g);
  const double towards = dist > 0 ? (away.cwiseAbs() / dist).dot(half) : half.maxCoeff();
  return dist < route_radius_ + std::min(rbound, towards);
}

bool ValidityChecker::on_visitor_route() {
  route_hit_ = -1;
  for (const RouteGroup& group : route_groups_) {
    const double* root = d_->xpos + 3 * group.root;
    if (distance_to_route(Eigen::Vector2d(root[0], root[1])) >= route_radius_ + group.reach) {
      continue;
    }
    for (int g : group.geoms) {
      if (geom_on_route(g)) {
        route_hit_ = g;
        return true;
      }
    }
  }
  return false;
}

std::string ValidityChecker::visitor_route_hit() const {
  if (route_hit_ < 0) return "";
  const char* name = mj_id2name(m_, mjOBJ_GEOM, route_hit_);
  char buf[160];
  std::snprintf(buf, sizeof buf, "'%s' within %.2f m of the visitor's route", name ? name : "?",
                route_radius_);
  return buf;
}

bool ValidityChecker::in_collision(const double* values, bool count) {
  if (!begin_check(values, count)) return true;
  if (on_visitor_route()) return true;
  const bool hit = any_changing_pair(0.0, [&](size_t k) {
    return pair_in_contact(changing_pairs_[k], changing_pair_tolerance_[k]);
  });
  if (hit) return true;
  for (const AttachedPair& p : attached_pairs_) {
    if (pair_in_contact(p.pair, p.tolerance)) return true;
  }
  return false;
}

bool ValidityChecker::within_margin(const double* values, double margin_m, bool count) {
  if (!begin_check(values, count)) return true;
  if (on_visitor_route()) return true;
  const bool hit = any_changing_pair(std::max(0.0, margin_m), [&](size_t k) {
    const GeomPair& p = changing_pairs_[k];
    if (changing_pair_tolerance_[k] > 0) return pair_in_contact(p, changing_pair_tolerance_[k]);
    return collide(p, changing_pair_with_world_[k] ? p.margin + margin_m : p.margin) > 0;
  });
  if (hit) return true;
  for (const AttachedPair& p : attached_pairs_) {
    if (p.tolerance > 0
            ? pair_in_contact(p.pair, p.tolerance)
            : collide(p.pair, p.with_world ? p.pair.margin + margin_m : p.pair.margin) > 0) {
      return true;
    }
  }
  return false;
}

double ValidityChecker::distance(const double* values, double cap_m) {
  set_values(values);
  double dist = cap_m;
  // Each pair is measured only up to the smallest distance so far: farther pairs cost a
  // bounding-sphere test or one narrow-phase call.
  for (const GeomPair& p : changing_pairs_) {
    dist = std::min(dist, pair_distance(p, std::max(dist, 1e-9)));
  }
  for (const AttachedPair& p : attached_pairs_) {
    double pd = pair_distance(p.pair, std::max(dist, 1e-9));
    if (pd < 0 && pd >= -p.tolerance) pd = 0;
    dist = std::min(dist, pd);
  }
  return dist;
}

double ValidityChecker::distance_to_world(const double* values, double cap_m) {
  set_values(values);
  double dist = cap_m;
  for (size_t k = 0; k < changing_pairs_.size(); ++k) {
    if (changing_pair_with_world_[k]) {
      dist = std::min(dist, pair_distance(changing_pairs_[k], std::max(dist, 1e-9)));
    }
  }
  auto self_or_floor = [&](int g) {
    return scene_.is_robot_geom(g) || m_->geom_type[g] == mjGEOM_PLANE;
  };
  for (const AttachedPair& p : attached_pairs_) {
    if (self_or_floor(p.pair.g1) || self_or_floor(p.pair.g2)) continue;
    double pd = pair_distance(p.pair, std::max(dist, 1e-9));
    if (pd < 0 && pd >= -p.tolerance) pd = 0;
    dist = std::min(dist, pd);
  }
  return dist;
}

std::string describe_robot_contacts(const Scene& scene, const mjModel* m, mjData* d,
                                    const std::vector<Attachment>& attachments) {
  collide_whole_model(scene, m, d, attachments, /*complete=*/true);
  std::string out;
  int shown = 0;
  for (int i = 0; i < d->ncon; ++i) {
    const mjContact& c = d->contact[i];
    if (!counts_as_robot_collision(scene, m, c, attachments)) continue;
    if (++shown > 3) {
      out += "; ...";
      break;
    }
    auto name = [&](int g) {
      const char* geom = mj_id2name(m, mjOBJ_GEOM, g);
      const char* body = mj_id2name(m, mjOBJ_BODY, m->geom_bodyid[g]);
      return std::string(geom ? geom : body ? body : "?");
    };
    char depth[48];
    std::snprintf(depth, sizeof depth, " (depth %.1f mm)", -c.dist * 1e3);
    out += (out.empty() ? "" : "; ") + name(c.geom1) + " touches " + name(c.geom2) + depth;
  }
  return out.empty() ? "no contact" : out;
}

}  // namespace taskmatrix::mujoco
