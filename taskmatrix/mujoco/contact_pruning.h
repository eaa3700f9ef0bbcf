// What the physics need not compute, on one worker's model: contacts that cannot occur, and
// contacts of objects that lie still while nothing comes near them.
//
//   - Static geoms (on bodies welded to the world: a room's walls and window, furniture,
//     obstacles; not planes or height fields, which have no bounding sphere) that no movable
//     geom comes near cost every step: MuJoCo's broadphase pairs every body whose bounding box
//     overlaps another's (furniture with the obstacles standing by it, the world's own geoms
//     with every body) and visits each pair of their geoms. While no movable geom's bounding
//     sphere comes within the pair's margins plus kStaticAllowanceM of a static geom (of its
//     oriented box for boxes, of its bounding sphere otherwise), the static geom's collision
//     bits are cleared, so MuJoCo skips it, and a body left with no collidable geom leaves the
//     broadphase. Checked at the first step of every control period (the state may have been
//     set between periods), then every kStaticCheckS of simulated time, and at once when an
//     object wakes. Exact: MuJoCo's own bounding-sphere test rejects every such pair, as long as
//     nothing moves more than kStaticAllowanceM in kStaticCheckS (10 m/s) while the
//     simulation steps (the visitor's walk is set before stepping, as trials do; a speed
//     changed mid-run jumps it). Not used under MuJoCo's margin override.
//     Static geoms are tested against each other by nobody (MuJoCo filters pairs on one weld
//     body), so only movable geoms count; a scripted body (the visitor, whose heading is set
//     and turns about its root at the ends of its walk) counts by its bounding sphere.
//   - Free objects at rest (under kRestSpeed and kRestAngularSpeed for kRestTimeS) that nothing
//     movable comes near (bounding spheres within kStepAllowanceM plus margins) are put to
//     sleep: their collision bits are cleared and they are held exactly where they are. They
//     wake when something movable comes that near. Not exact: a sleeping object no longer creeps
//     by the contact solver's micrometres.
//
//   - A held object does not collide with the hand that holds it: the attachment fixes where it
//     is in the hand, so the grip's contact forces would only push the arm off its path (atlas's
//     arm joints lagged 0.012-0.025 rad with the vacuum in hand, 0.004 rad at most before; the
//     vacuum sank 5 mm into the table it passed 8 mm over). While held, its geoms and every geom
//     that could collide with one of them (by their bits), but that hand's, share a bit of their
//     own (one per hand, from the bits no compiled geom uses; with none free, nothing changes), so
//     it still collides with everything else, the other hand and a second held object
//     included. Exact for every other pair.
//
// Bits are cleared only between begin() and end(), while the simulation steps: queries (IK,
// validity, planning) always see the model as it was before begin() (as compiled, with the
// layout's obstacle slots and the variation's furniture applied).
#pragma once

#include <vector>

#include "taskmatrix/mujoco/scene.h"

namespace taskmatrix::mujoco {

inline constexpr double kStepAllowanceM = 0.05;    // per timestep (resting objects)
inline constexpr double kStaticAllowanceM = 0.1;   // per kStaticCheckS (static geoms)
inline constexpr double kStaticCheckS = 0.01;
inline constexpr double kRestSpeed = 0.005;        // m/s
inline constexpr double kRestAngularSpeed = 0.05;  // rad/s
inline constexpr double kRestTimeS = 0.1;

struct ContactPruningOptions {
  bool gate_static_geoms = true;
  bool sleep_resting_objects = true;
};

class ContactPruning {
 public:
  // `m` is the worker's model as compiled (its collision bits are the ones restored).
  ContactPruning(const Scene& scene, const mjModel* m, ContactPruningOptions options);

  // Applies the cleared bits to the worker's model; end() restores every bit.
  void begin(mjModel* m);
  void end(mjModel* m);
  // Before each collision detection (mj_step1), with the geom poses of the previous step:
  // wakes objects something movable approaches, and opens or closes the static geoms.
  void before_collision(mjModel* m, const mjData* d);
  // After each integration (mj_step2): holds sleeping objects still, and puts objects that have
  // rested long enough with nothing near to sleep.
  void after_integration(mjModel* m, mjData* d);
  // Every object awake and every static geom open (after a reset, a teleport, an attachment,
  // a new layout). Call
  // outside begin()/end().
  void wake_all();
  // A held object moves with its holder: it never sleeps, and it does not collide with
  // `hand_bodies` (the bodies of the hand holding it) while held. Call outside begin()/end().
  void set_held(int body, bool held, const std::vector<int>& hand_bodies = {});

  int sleeping() const;
  int closed_static_geoms() const;

 private:
  struct Tree {  // a movable body tree: the robot, the visitor, a free object
    int root = -1;
    std::vector<int> geoms;  // collidable geoms
    bool free_object = false;
    int qpos = -1, dof = -1;  // free objects: their free joint's addresses
    bool held = false;
    bool asleep = false;
    // Scripted (the visitor): its pose is set, not integrated, and may turn about its root in
    // one step, so static geoms test its bounding sphere, never its geoms.
    bool scripted = false;
    int rest_steps = 0;
    double center[3] = {0, 0, 0}, radius = 0;  // bounding sphere of the collidable geoms
    double sleep_qpos[7] = {0, 0, 0, 0, 0, 0, 0};
  };
  struct StaticGeom {
    int geom;
    bool closed = false;
  };
  void bound(Tree& t, const mjData* d) const;
  // Whether any movable geom of an awake tree other than `except` comes within `extra` of the
  // sphere (c, r).
  // `coarse`: a scripted tree's bounding sphere alone decides.
  bool something_near(const double* c, double r, const Tree* except, const mjData* d,
                      double allowance = kStepAllowanceM, bool coarse = false) const;
  // Whether a movable geom of an awake tree comes near the static geom (the model's size,
  // bounding radius and pose as they are: layouts and variations change them).
  bool static_geom_needed(const mjModel* m, int geom, const mjData* d) const;
  void set_bits(mjModel* m, int geom, bool on) const;
  void set_tree_bits(mjModel* m, const Tree& t, bool on) const;

  ContactPruningOptions options_;
  std::vector<Tree> trees_;
  std::vector<StaticGeom> statics_;
  // Saves the model's bits and computes open_contype_ and open_conaffinity_ from them and the
  // holds.
  void apply_holds(const mjModel* m);

  struct Hold {
    int body;
    std::vector<int> hand_bodies;
  };
  std::vector<Hold> holds_;
  bool holds_applied_ = false;              // between begin() and end()
  std::vector<int> hold_bits_;              // free collision bits, one per simultaneous hold
  std::vector<int> contype_, conaffinity_;  // as compiled, per geom
  // on: with the holds applied; a static geom's are its bits at begin()
  std::vector<int> open_contype_, open_conaffinity_;
  std::vector<int> saved_contype_, saved_conaffinity_;  // at begin(), while holding
  std::vector<double> margin_, rbound_;
  int rest_steps_needed_ = 1;
  int static_check_steps_ = 1;  // kStaticCheckS in timesteps
  int static_countdown_ = 0;    // steps to the next check of the static geoms (0: now)
  bool active_ = false;  // between begin() and end()
};

}  // namespace taskmatrix::mujoco
