#include "taskmatrix/mujoco/contact_pruning.h"

#include <algorithm>
#include <cmath>

#include "taskmatrix/mujoco/body_kinematics.h"

namespace taskmatrix::mujoco {

ContactPruning::ContactPruning(const Scene& scene, const mjModel* m, ContactPruningOptions options)
    : options_(options) {
  contype_.assign(m->geom_contype, m->geom_contype + m->ngeom);
  conaffinity_.assign(m->geom_conaffinity, m->geom_conaffinity + m->ngeom);
  open_contype_ = contype_;
  open_conaffinity_ = conaffinity_;
  int used = 0;
  for (int g = 0; g < m->ngeom; ++g) used |= contype_[g] | conaffinity_[g];
  for (int bit = 30; bit >= 0 && hold_bits_.size() < 2; --bit) {
    if (!(used & (1 << bit))) hold_bits_.push_back(1 << bit);
  }
  // MuJoCo's bounding-sphere test adds the larger of two margins; the sum of the margins
  // clamped at zero is never smaller.
  margin_.resize(m->ngeom);
  for (int g = 0; g < m->ngeom; ++g) margin_[g] = std::max(0.0, m->geom_margin[g]);
  rbound_.assign(m->geom_rbound, m->geom_rbound + m->ngeom);
  std::vector<char> slot_geom(m->ngeom, 0);
  for (const ObstacleSlot& s : scene.obstacle_slots()) {
    for (int g : s.geoms) slot_geom[g] = 1;
  }
  std::vector<int> tree_of_root(m->nbody, -1);
  for (int g = 0; g < m->ngeom; ++g) {
    const int body = m->geom_bodyid[g];
    if (m->body_weldid[body] == 0) {  // static
      // Obstacle slots are gated whatever their compiled bits: a layout switches them on.
      const bool collides = contype_[g] || conaffinity_[g] || slot_geom[g];
      const bool bounded = m->geom_type[g] != mjGEOM_PLANE && m->geom_type[g] != mjGEOM_HFIELD &&
                           m->geom_rbound[g] > 0;
      if (options_.gate_static_geoms && collides && bounded) statics_.push_back({g});
      continue;
    }
    if (!contype_[g] && !conaffinity_[g]) continue;
    const int root = m->body_rootid[body];
    if (tree_of_root[root] < 0) {
      tree_of_root[root] = static_cast<int>(trees_.size());
      Tree t;
      t.root = root;
      if (m->body_jntnum[root] == 1 && m->jnt_type[m->body_jntadr[root]] == mjJNT_FREE &&
          !scene.is_robot_body(root)) {
        t.free_object = true;
        t.qpos = m->jnt_qposadr[m->body_jntadr[root]];
        t.dof = m->jnt_dofadr[m->body_jntadr[root]];
      }
      t.scripted = !t.free_object && !scene.is_robot_body(root);
      trees_.push_back(t);
    }
    trees_[tree_of_root[root]].geoms.push_back(g);
  }
  rest_steps_needed_ = std::max(1, static_cast<int>(std::lround(kRestTimeS / m->opt.timestep)));
  static_check_steps_ =
      std::max(1, static_cast<int>(std::floor(kStaticCheckS / m->opt.timestep + 1e-9)));
}

void ContactPruning::set_bits(mjModel* m, int geom, bool on) const {
  m->geom_contype[geom] = on ? open_contype_[geom] : 0;
  m->geom_conaffinity[geom] = on ? open_conaffinity_[geom] : 0;
}

void ContactPruning::apply_holds(const mjModel* m) {
  // From the bits as they are (a layout may have switched obstacle slots on or off).
  saved_contype_.assign(m->geom_contype, m->geom_contype + m->ngeom);
  saved_conaffinity_.assign(m->geom_conaffinity, m->geom_conaffinity + m->ngeom);
  open_contype_ = saved_contype_;
  open_conaffinity_ = saved_conaffinity_;
  for (size_t k = 0; k < holds_.size() && k < hold_bits_.size(); ++k) {
    const Hold& h = holds_[k];
    const int bit = hold_bits_[k];
    std::vector<int> held;
    for (int g = 0; g < m->ngeom; ++g) {
      if (m->body_rootid[m->geom_bodyid[g]] == h.body) held.push_back(g);
    }
    // Whether geom `g` collides with any of the held object's geoms by their bits as they are.
    auto pairs_with_held = [&](int g) {
      return std::any_of(held.begin(), held.end(), [&](int o) {
        return (saved_contype_[g] & saved_conaffinity_[o]) ||
               (saved_contype_[o] & saved_conaffinity_[g]);
      });
    };
    for (int g = 0; g < m->ngeom; ++g) {
      const int b = m->geom_bodyid[g];
      if (m->body_rootid[b] == h.body) continue;
      if (std::find(h.hand_bodies.begin(), h.hand_bodies.end(), b) == h.hand_bodies.end() &&
          pairs_with_held(g)) {
        open_conaffinity_[g] |= bit;
      }
    }
    for (int o : held) {
      if (!saved_contype_[o] && !saved_conaffinity_[o]) continue;
      open_contype_[o] = bit;  // collides only through the hold's bit
      open_conaffinity_[o] = bit;
    }
  }
}

void ContactPruning::set_tree_bits(mjModel* m, const Tree& t, bool on) const {
  for (int g : t.geoms) set_bits(m, g, on);
}

void ContactPruning::begin(mjModel* m) {
  active_ = true;
  // The state may have jumped since the last period (a configuration set, a layout, a hold):
  // the first step decides every static geom afresh.
  static_countdown_ = 0;
  holds_applied_ = !holds_.empty() && !hold_bits_.empty();
  if (holds_applied_) {
    apply_holds(m);
    for (int g = 0; g < m->ngeom; ++g) set_bits(m, g, true);
  } else {
    for (const StaticGeom& s : statics_) {  // as the layout left them
      open_contype_[s.geom] = m->geom_contype[s.geom];
      open_conaffinity_[s.geom] = m->geom_conaffinity[s.geom];
    }
  }
  for (const Tree& t : trees_) {
    if (t.asleep) set_tree_bits(m, t, false);
  }
  for (const StaticGeom& s : statics_) {
    if (s.closed) set_bits(m, s.geom, false);
  }
}

void ContactPruning::end(mjModel* m) {
  active_ = false;
  if (holds_applied_) {  // every bit as it was at begin(); `on` is as compiled again
    std::copy(saved_contype_.begin(), saved_contype_.end(), m->geom_contype);
    std::copy(saved_conaffinity_.begin(), saved_conaffinity_.end(), m->geom_conaffinity);
    open_contype_ = contype_;
    open_conaffinity_ = conaffinity_;
    return;
  }
  for (const Tree& t : trees_) {
    if (t.asleep) set_tree_bits(m, t, true);
  }
  for (const StaticGeom& s : statics_) set_bits(m, s.geom, true);
}

void ContactPruning::wake_all() {
  for (Tree& t : trees_) {
    t.asleep = false;
    t.rest_steps = 0;
  }
  for (StaticGeom& s : statics_) s.closed = false;
  static_countdown_ = 0;
}

void ContactPruning::set_held(int body, bool held, const std::vector<int>& hand_bodies) {
  for (Tree& t : trees_) {
    if (t.root != body) continue;
    t.held = held;
    t.asleep = false;
    t.rest_steps = 0;
  }
  holds_.erase(
      std::remove_if(holds_.begin(), holds_.end(), [&](const Hold& h) { return h.body == body; }),
      holds_.end());
  if (held) holds_.push_back({body, hand_bodies});
}

int ContactPruning::sleeping() const {
  return static_cast<int>(
      std::count_if(trees_.begin(), trees_.end(), [](const Tree& t) { return t.asleep; }));
}

int ContactPruning::closed_static_geoms() const {
  return static_cast<int>(std::count_if(statics_.begin(), statics_.end(),
                                        [](const StaticGeom& s) { return s.closed; }));
}

void ContactPruning::bound(Tree& t, const mjData* d) const {
  const double* c = d->xpos + 3 * t.root;
  mju_copy3(t.center, c);
  t.radius = 0;
  for (int g : t.geoms) {
    t.radius = std::max(t.radius, mju_dist3(d->geom_xpos + 3 * g, c) + rbound_[g] + margin_[g]);
  }
}

bool ContactPruning::something_near(const double* c, double r, const Tree* except, const mjData* d,
                                    double allowance, bool coarse) const {
  for (const Tree& t : trees_) {
    if (&t == except || t.asleep) continue;
    if (mju_dist3(t.center, c) > t.radius + r + allowance) continue;
    if (coarse && t.scripted) return true;
    for (int g : t.geoms) {
      if (mju_dist3(d->geom_xpos + 3 * g, c) <= rbound_[g] + margin_[g] + r + allowance) {
        return true;
      }
    }
  }
  return false;
}

bool ContactPruning::static_geom_needed(const mjModel* m, int geom, const mjData* d) const {
  // MuJoCo's margin override replaces every margin: nothing here bounds it.
  if (m->opt.enableflags & mjENBL_OVERRIDE) return true;
  const double margin = margin_[geom];
  if (m->geom_type[geom] != mjGEOM_BOX) {
    return something_near(d->geom_xpos + 3 * geom, m->geom_rbound[geom] + margin, nullptr, d,
                          kStaticAllowanceM, true);
  }
  for (const Tree& t : trees_) {
    if (t.asleep) continue;
    if (sphere_clear_of_box(m, d, geom, t.center, t.radius + margin + kStaticAllowanceM)) {
      continue;
    }
    if (t.scripted) return true;
    for (int g : t.geoms) {
      const double reach = rbound_[g] + std::max(margin_[g], margin) + kStaticAllowanceM;
      if (!sphere_clear_of_box(m, d, geom, d->geom_xpos + 3 * g, reach)) return true;
    }
  }
  return false;
}

void ContactPruning::before_collision(mjModel* m, const mjData* d) {
  for (Tree& t : trees_) {
    if (!t.asleep) bound(t, d);
  }
  bool woke = false;
  for (Tree& t : trees_) {
    if (!t.asleep || !something_near(t.center, t.radius, &t, d)) continue;
    t.asleep = false;
    t.rest_steps = 0;
    if (active_) set_tree_bits(m, t, true);
    bound(t, d);
    woke = true;
  }
  // What was decided at the last check holds while nothing has moved kStaticAllowanceM since:
  // again after kStaticCheckS, or at once when an object wakes (it may rest on a closed geom).
  if (--static_countdown_ > 0 && !woke) return;
  static_countdown_ = static_check_steps_;
  for (StaticGeom& s : statics_) {
    if (!open_contype_[s.geom] && !open_conaffinity_[s.geom]) {  // an unused slot
      s.closed = false;
      continue;
    }
    const bool closed = !static_geom_needed(m, s.geom, d);
    if (closed != s.closed && active_) set_bits(m, s.geom, !closed);
    s.closed = closed;
  }
}

void ContactPruning::after_integration(mjModel* m, mjData* d) {
  for (Tree& t : trees_) {
    if (!t.free_object) continue;
    double* qvel = d->qvel + t.dof;
    if (t.asleep) {  // held exactly where it fell asleep
      mju_copy(d->qpos + t.qpos, t.sleep_qpos, 7);
      mju_zero(qvel, 6);
      continue;
    }
    if (!options_.sleep_resting_objects || t.held) continue;
    const bool resting = mju_norm3(qvel) < kRestSpeed && mju_norm3(qvel + 3) < kRestAngularSpeed;
    t.rest_steps = resting ? t.rest_steps + 1 : 0;
    if (t.rest_steps < rest_steps_needed_ || something_near(t.center, t.radius, &t, d)) continue;
    t.asleep = true;
    mju_copy(t.sleep_qpos, d->qpos + t.qpos, 7);
    mju_zero(qvel, 6);
    if (active_) set_tree_bits(m, t, false);
  }
}

}  // namespace taskmatrix::mujoco
