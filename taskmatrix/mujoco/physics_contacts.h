// The physics mode's contact pass: the contacts MuJoCo 2.2.2's mj_collision would find, found
// from a list of candidate geom pairs built once per model instead of MuJoCo's broadphase.
//
// Why: after contact pruning (contact_pruning.h) about half of a physics step was collision
// detection, and most of that MuJoCo's broadphase rather than its narrow phase: every step it
// bounds every body (the closed static ones too), sorts them, pairs the floor's body with every
// body (a plane pairs with all) and calls the pair filter for each geom pair of each body pair.
//
// What it computes: the candidate pairs are every pair of a geom on a moving body (a body not
// welded to the world) with any other geom, less the pairs MuJoCo's filter always rejects (one
// weld body, weld parent and child unless the model disables that filter, a body pair the
// model excludes). Each step, a candidate is tested as MuJoCo's mj_collideGeoms tests it: a
// collision function for the two types (a layout may change an obstacle's type), collision
// bits as they are now (pruning and holds change them), the pair's margin, gap and contact
// dimension, the bounding spheres, a plane against the other geom's sphere, then one more
// rejection MuJoCo lacks: the other geom's bounding sphere wholly outside a box's oriented box
// (a table top's bounding sphere reaches far past it); all but the plane test are the
// validity checker's pair test (collide_geoms, validity_checker.h). A pair that passes goes to
// MuJoCo's narrow-phase function, and its contacts get friction, solref and solimp as
// mj_collideGeoms gives them (priority or mix), repeated box-box points dropped, the contact frame
// completed.
//
// The same contacts as mj_collision (a test compares them field for field on both robots'
// states along a motion over the table, objects resting, and against the counter), but for
// the phantom depths MuJoCo's box-box function reports (collide_geoms gives a box-box contact
// no more depth than the boxes overlap along its normal), listed in
// another order (candidate order, not MuJoCo's body-pair order), so the constraint solver's
// sums run in another order and states differ from MuJoCo's own pipeline at rounding level.
// With one exception, a defect of MuJoCo 2.2.2 (fixed in 2.3.2): its broadphase pairs a static
// body holding a plane or height field with every body and then again with the bodies its
// sweep finds overlapping it (a plane's box is its centre point), so a body touching the floor
// near the plane's centre gets each contact twice; this pass lists it once. Within rounding at
// exact tangency (MuJoCo sweeps its boxes in single precision) the two may also disagree on a
// pair touching at exactly its margin.
// mj_collision runs instead where this pass would differ otherwise: predefined <pair>s,
// `collision` other than "all", a negative geom margin, the margin override, a user's contact
// filter callback, or a contact array that fills up (which contacts it keeps depends on order).
// The candidate pairs and the moving bodies' spheres come from the model as it is at
// construction: build it again after the model's geoms change (a task variation).
#pragma once

#include <mujoco/mujoco.h>

#include <vector>

namespace taskmatrix::mujoco {

class PhysicsContacts {
 public:
  explicit PhysicsContacts(const mjModel* m);

  bool usable() const { return usable_; }
  // Fills d->contact and d->ncon as mj_collision would (the geoms posed in d).
  void collide(const mjModel* m, mjData* d) const;
  // mj_step1 with collide() in place of mj_collision (MuJoCo's timers are not kept).
  void step1(const mjModel* m, mjData* d) const;

 private:
  struct Pair {
    int g1, g2;
  };
  // A moving body's geoms, bounded by one sphere (in the body's frame: centre and radius over
  // its geoms' bounding spheres grown by their margins).
  struct Body {
    int id;
    std::vector<int> geoms;  // indices into moving_geoms_
    double local_center[3] = {0, 0, 0};
    double radius = 0;  // infinite with a plane or height field
  };
  // The candidate pairs of two moving bodies.
  struct BodyPair {
    int body1, body2;   // indices into bodies_
    size_t begin, end;  // range in moving_pairs_
  };
  // The candidate pairs' contacts.
  void find(const mjModel* m, mjData* d) const;
  // Tests one pair and adds its contacts (as far as the contact array holds them).
  void collide_pair(const mjModel* m, mjData* d, int a, int b) const;

  bool usable_ = false;
  std::vector<Pair> moving_pairs_;  // two geoms of moving bodies, grouped by body pair
  std::vector<BodyPair> body_pairs_;
  std::vector<Body> bodies_;       // moving bodies with geoms
  std::vector<int> moving_geoms_;  // geoms of moving bodies
  std::vector<int> static_geoms_;  // geoms welded to the world
  // Per moving geom (index into moving_geoms_), whether each static geom may be tested with it.
  std::vector<std::vector<char>> with_static_;
  mutable std::vector<int> open_static_;  // per step: static geoms with collision bits
  mutable std::vector<double> centers_;   // per step: bodies_' sphere centres in the world
};

}  // namespace taskmatrix::mujoco
