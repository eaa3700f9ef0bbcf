#include "taskmatrix/mujoco/physics_contacts.h"

#include <algorithm>
#include <cmath>

#include "taskmatrix/mujoco/validity_checker.h"

namespace taskmatrix::mujoco {
namespace {

// mju_makeFrame of MuJoCo 2.2.2 (not in its public API): the contact frame from its normal.
void make_frame(mjtNum frame[9]) {
  mjtNum tmp[3];
  if (mju_normalize3(frame) < 0.5) mju_error("xaxis of contact frame undefined");
  if (mju_norm3(frame + 3) < 0.5) {
    mju_zero3(frame + 3);
    if (frame[1] < 0.5 && frame[1] > -0.5) {
      frame[4] = 1;
    } else {
      frame[5] = 1;
    }
  }
  mju_scl3(tmp, frame, mju_dot3(frame, frame + 3));
  mju_subFrom3(frame + 3, tmp);
  mju_normalize3(frame + 3);
  mju_cross(frame + 6, frame, frame + 3);
}

// Signed height of `point` over plane geom `plane` (along its normal, the geom's z axis).
mjtNum height_above_plane(const mjData* d, int plane, const mjtNum* point) {
  const mjtNum* mat = d->geom_xmat + 9 * plane;
  const mjtNum normal[3] = {mat[2], mat[5], mat[8]};
  mjtNum dif[3];
  mju_sub3(dif, point, d->geom_xpos + 3 * plane);
  return mju_dot3(dif, normal);
}

// Pairs MuJoCo's filter rejects whatever the state: one weld body, weld parent and child, an
// excluded body pair.
bool always_rejected(const mjModel* m, int g1, int g2) {
  const int b1 = m->geom_bodyid[g1], b2 = m->geom_bodyid[g2];
  const int w1 = m->body_weldid[b1], w2 = m->body_weldid[b2];
  if (w1 == w2) return true;
  if (!(m->opt.disableflags & mjDSBL_FILTERPARENT) && w1 && w2 &&
      (w1 == m->body_weldid[m->body_parentid[w2]] || w2 == m->body_weldid[m->body_parentid[w1]])) {
    return true;
  }
  if (m->nexclude) {
    const int signature = ((std::min(b1, b2) + 1) << 16) + (std::max(b1, b2) + 1);
    for (int k = 0; k < m->nexclude; ++k) {
      if (m->exclude_signature[k] == signature) return true;
    }
  }
  return false;
}

}  // namespace

PhysicsContacts::PhysicsContacts(const mjModel* m) {
  usable_ = m->npair == 0 && m->opt.collision == mjCOL_ALL;
  // A negative margin shrinks MuJoCo's broadphase boxes below what its pair test allows, so
  // MuJoCo misses contacts this pass would find.
  for (int g = 0; g < m->ngeom && usable_; ++g) usable_ = m->geom_margin[g] >= 0;
  if (!usable_) return;
  for (int g = 0; g < m->ngeom; ++g) {
    (m->body_weldid[m->geom_bodyid[g]] == 0 ? static_geoms_ : moving_geoms_).push_back(g);
  }
  // Moving bodies and their bounding spheres (geoms are numbered body by body).
  for (size_t i = 0; i < moving_geoms_.size(); ++i) {
    const int g = moving_geoms_[i];
    const int body = m->geom_bodyid[g];
    if (bodies_.empty() || bodies_.back().id != body) bodies_.push_back({body, {}});
    bodies_.back().geoms.push_back(static_cast<int>(i));
  }
  for (Body& b : bodies_) {
    for (const int i : b.geoms) {
      for (int k = 0; k < 3; ++k) b.local_center[k] += m->geom_pos[3 * moving_geoms_[i] + k];
    }
    for (double& c : b.local_center) c /= static_cast<double>(b.geoms.size());
    for (const int i : b.geoms) {
      const int g = moving_geoms_[i];
      if (!(m->geom_rbound[g] > 0)) {
        b.radius = INFINITY;
        break;
      }
      const double* p = m->geom_pos + 3 * g;
      const double r =
          std::hypot(p[0] - b.local_center[0], p[1] - b.local_center[1], p[2] - b.local_center[2]) +
          m->geom_rbound[g] + std::max(0.0, m->geom_margin[g]);
      b.radius = std::max(b.radius, r);
    }
  }
  for (size_t x = 0; x < bodies_.size(); ++x) {
    for (size_t y = x + 1; y < bodies_.size(); ++y) {
      BodyPair group{static_cast<int>(x), static_cast<int>(y), moving_pairs_.size(), 0};
      for (const int i : bodies_[x].geoms) {
        for (const int j : bodies_[y].geoms) {
          const int a = moving_geoms_[i], b = moving_geoms_[j];
          if (!always_rejected(m, a, b)) moving_pairs_.push_back({a, b});
        }
      }
      group.end = moving_pairs_.size();
      if (group.end > group.begin) body_pairs_.push_back(group);
    }
  }
  centers_.resize(3 * bodies_.size());
  with_static_.resize(moving_geoms_.size());
  for (size_t i = 0; i < moving_geoms_.size(); ++i) {
    with_static_[i].resize(static_geoms_.size());
    for (size_t j = 0; j < static_geoms_.size(); ++j) {
      with_static_[i][j] = !always_rejected(m, moving_geoms_[i], static_geoms_[j]);
    }
  }
  open_static_.reserve(static_geoms_.size());
}

void PhysicsContacts::collide_pair(const mjModel* m, mjData* d, int a, int b) const {
  // Ordered as mj_collision and mj_collideGeoms order them: the lower body's geom first (geoms
  // are numbered body by body), then by type if that is lower (a layout may change an
  // obstacle's type).
  const int lo = std::min(a, b), hi = std::max(a, b);
  const int g1 = m->geom_type[lo] <= m->geom_type[hi] ? lo : hi;
  const int g2 = g1 == lo ? hi : lo;
  const int type1 = m->geom_type[g1], type2 = m->geom_type[g2];
  // Margin, gap and contact dimension as mj_collideGeoms sets them for a dynamic pair (no
  // override here: collide() hands that to MuJoCo).
  const mjtNum margin = std::max(m->geom_margin[g1], m->geom_margin[g2]);
  const mjtNum gap = std::max(m->geom_gap[g1], m->geom_gap[g2]);
  const bool prioritised = m->geom_priority[g1] != m->geom_priority[g2];
  const int gp = m->geom_priority[g1] > m->geom_priority[g2] ? g1 : g2;
  const int condim =
      prioritised ? m->geom_condim[gp] : std::max(m->geom_condim[g1], m->geom_condim[g2]);
  // MuJoCo's plane test; then the validity checker's pair test: collision bits, bounding
  // spheres, a box against the other geom's sphere (the test MuJoCo does not make), the narrow
  // phase.
  const mjtNum r1 = m->geom_rbound[g1], r2 = m->geom_rbound[g2];
  if (type1 == mjGEOM_PLANE && r2 > 0 &&
      height_above_plane(d, g1, d->geom_xpos + 3 * g2) > margin + r2)
    return;
  if (type2 == mjGEOM_PLANE && r1 > 0 &&
      height_above_plane(d, g2, d->geom_xpos + 3 * g1) > margin + r1)
    return;
  mjContact con[mjMAXCONPAIR];
  int num = collide_geoms(m, d, GeomPair{g1, g2, margin}, margin, con);
  if (num <= 0) return;
  if (type1 == mjGEOM_BOX && type2 == mjGEOM_BOX) {  // repeated points of box-box
    for (int i = 0; i < num; ++i) con[i].dim = 0;
    for (int i = 0; i < num - 1; ++i) {
      for (int j = i + 1; j < num; ++j) {
        if (con[i].pos[0] == con[j].pos[0] && con[i].pos[1] == con[j].pos[1] &&
            con[i].pos[2] == con[j].pos[2]) {
          con[i].dim = -1;
          break;
        }
      }
    }
    int kept = 0;
    for (int j = 0; j < num; ++j) {
      if (con[j].dim == 0) {
        if (kept < j) con[kept] = con[j];
        ++kept;
      }
    }
    num = kept;
  }
  // Friction, solref and solimp: the prioritised geom's, else the larger friction and the mix.
  mjtNum friction[5], solref[mjNREF], solimp[mjNIMP];
  if (prioritised) {
    for (int i = 0; i < 3; ++i) friction[2 * i] = m->geom_friction[3 * gp + i];
    mju_copy(solref, m->geom_solref + mjNREF * gp, mjNREF);
    mju_copy(solimp, m->geom_solimp + mjNIMP * gp, mjNIMP);
  } else {
    for (int i = 0; i < 3; ++i) {
      friction[2 * i] = std::max(m->geom_friction[3 * g1 + i], m->geom_friction[3 * g2 + i]);
    }
    const mjtNum s1 = m->geom_solmix[g1], s2 = m->geom_solmix[g2];
    mjtNum mix;
    if (s1 >= mjMINVAL && s2 >= mjMINVAL) {
      mix = s1 / (s1 + s2);
    } else if (s1 < mjMINVAL && s2 < mjMINVAL) {
      mix = 0.5;
    } else if (s1 < mjMINVAL) {
      mix = 0.0;
    } else {
      mix = 1.0;
    }
    const mjtNum* ref1 = m->geom_solref + mjNREF * g1;
    const mjtNum* ref2 = m->geom_solref + mjNREF * g2;
    if (ref1[0] > 0 && ref2[0] > 0) {
      for (int i = 0; i < mjNREF; ++i) solref[i] = mix * ref1[i] + (1 - mix) * ref2[i];
    } else {
      for (int i = 0; i < mjNREF; ++i) solref[i] = std::min(ref1[i], ref2[i]);
    }
    mju_scl(solimp, m->geom_solimp + mjNIMP * g1, mix, mjNIMP);
    mju_addToScl(solimp, m->geom_solimp + mjNIMP * g2, 1 - mix, mjNIMP);
  }
  friction[1] = friction[0];
  friction[3] = friction[4];
  for (mjtNum& f : friction) f = std::max(mjMINMU, f);
  for (int i = 0; i < num; ++i) {
    mjContact& c = con[i];
    c.dim = condim;
    c.geom1 = g1;
    c.geom2 = g2;
    c.includemargin = margin - gap;
    mju_copy(c.friction, friction, 5);
    mju_copy(c.solref, solref, mjNREF);
    mju_copy(c.solimp, solimp, mjNIMP);
    c.exclude = c.dist < c.includemargin ? 0 : 1;
    make_frame(c.frame);
    c.efc_address = -1;
    c.mu = 0;
    mju_zero(c.H, 36);
    if (mj_addContact(m, d, &c)) return;  // full: MuJoCo warns, then tries the next pair
  }
}

void PhysicsContacts::collide(const mjModel* m, mjData* d) const {
  // MuJoCo's pipeline where this pass would not find what it finds: a user's contact filter,
  // the margin override (MuJoCo's broadphase keeps the geoms' own margins, its pair test the
  // override's).
  if (!usable_ || mjcb_contactfilter || (m->opt.enableflags & mjENBL_OVERRIDE)) {
    mj_collision(m, d);
    return;
  }
  const mjWarningStat full_before = d->warning[mjWARN_CONTACTFULL];
  find(m, d);
  if (d->ncon >= m->nconmax) {
    // The array filled up: which contacts it keeps depends on the order pairs are tried in, so
    // MuJoCo's own pass decides (and warns as it would).
    d->warning[mjWARN_CONTACTFULL] = full_before;
    mj_collision(m, d);
  }
}

void PhysicsContacts::find(const mjModel* m, mjData* d) const {
  d->ncon = 0;
  if ((m->opt.disableflags & (mjDSBL_CONSTRAINT | mjDSBL_CONTACT)) || m->nconmax == 0 ||
      m->nbody < 2) {
    return;
  }
  for (size_t b = 0; b < bodies_.size(); ++b) {
    const int id = bodies_[b].id;
    double* c = centers_.data() + 3 * b;
    mju_rotVecMat(c, bodies_[b].local_center, d->xmat + 9 * id);
    mju_addTo3(c, d->xpos + 3 * id);
  }
  auto apart = [&](const double* c1, double r1, const double* c2, double r2) {
    const double dx = c1[0] - c2[0], dy = c1[1] - c2[1], dz = c1[2] - c2[2];
    const double reach = r1 + r2;
    return dx * dx + dy * dy + dz * dz > reach * reach;
  };
  for (const BodyPair& group : body_pairs_) {
    const Body &x = bodies_[static_cast<size_t>(group.body1)],
               &y = bodies_[static_cast<size_t>(group.body2)];
    if (apart(centers_.data() + 3 * group.body1, x.radius, centers_.data() + 3 * group.body2,
              y.radius)) {
      continue;  // MuJoCo's bounding-sphere test would reject each of its pairs
    }
    for (size_t k = group.begin; k < group.end; ++k) {
      collide_pair(m, d, moving_pairs_[k].g1, moving_pairs_[k].g2);
    }
  }
  // Static geoms with collision bits now (pruning clears the bits of those nothing is near).
  open_static_.clear();
  for (size_t j = 0; j < static_geoms_.size(); ++j) {
    const int g = static_geoms_[j];
    if (m->geom_contype[g] || m->geom_conaffinity[g]) open_static_.push_back(static_cast<int>(j));
  }
  for (size_t b = 0; b < bodies_.size(); ++b) {
    const double* c = centers_.data() + 3 * b;
    const double r = bodies_[b].radius;
    for (const int j : open_static_) {
      const int s = static_geoms_[static_cast<size_t>(j)];
      const double margin = std::max(0.0, m->geom_margin[s]);
      if (m->geom_rbound[s] > 0) {
        if (apart(c, r, d->geom_xpos + 3 * s, m->geom_rbound[s] + margin)) continue;
      } else if (m->geom_type[s] == mjGEOM_PLANE && std::isfinite(r)) {
        if (height_above_plane(d, s, c) > r + margin) continue;
      }
      for (const int i : bodies_[b].geoms) {
        if (!with_static_[static_cast<size_t>(i)][static_cast<size_t>(j)]) continue;
        const int g = moving_geoms_[static_cast<size_t>(i)];
        if (!m->geom_contype[g] && !m->geom_conaffinity[g]) continue;
        collide_pair(m, d, g, s);
      }
    }
  }
}

void PhysicsContacts::step1(const mjModel* m, mjData* d) const {
  mj_checkPos(m, d);
  mj_checkVel(m, d);
  // mj_fwdPosition with collide() for mj_collision.
  mj_kinematics(m, d);
  mj_comPos(m, d);
  mj_camlight(m, d);
  mj_tendon(m, d);
  mj_crb(m, d);
  mj_factorM(m, d);
  collide(m, d);
  mj_makeConstraint(m, d);
  mj_transmission(m, d);
  mj_projectConstraint(m, d);
  mj_sensorPos(m, d);
  mj_energyPos(m, d);
  mj_fwdVelocity(m, d);
  mj_sensorVel(m, d);
  mj_energyVel(m, d);
  if (mjcb_control) mjcb_control(m, d);
}

}  // namespace taskmatrix::mujoco
