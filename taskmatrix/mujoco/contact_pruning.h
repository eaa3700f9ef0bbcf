// What the physics need not compute, on one worker's model: contacts that cannot occur, and
// contacts of objects that lie still while nothing comes near them.
//
//   - Large static boxes (a room's walls, a window: boxes on bodies welded to the world whose
//     bounding sphere has a radius of at least kLargeBoxRadiusM) pass MuJoCo's bounding-sphere
//     test against nearly every geom, and each pass costs a narrow-phase call. While no movable
//     geom's bounding sphere comes within the pair's margin plus kStepAllowanceM of the box
//     itself (its oriented box), the box's collision bits are cleared, so MuJoCo skips it.
//     Exact: MuJoCo's narrow phase finds no contact there either, as long as nothing moves more
//     than kStepAllowanceM in one timestep (25 m/s at a 2 ms timestep).
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
// validity, planning) always see the model as compiled.
#pragma once

#include <vector>

#include "taskmatrix/mujoco/scene.h"

namespace taskmatrix::mujoco {

inline constexpr double kLargeBoxRadiusM = 0.5;
inline constexpr double kStepAllowanceM = 0.05;
inline constexpr double kRestSpeed = 0.005;        // m/s
inline constexpr double kRestAngularSpeed = 0.05;  // rad/s
inline constexpr double kRestTimeS = 0.1;

struct ContactPruningOptions {
  bool gate_large_static_boxes = true;
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
  // wakes objects something movable approaches, and opens or closes the large static boxes.
  void before_collision(mjModel* m, const mjData* d);
  // After each integration (mj_step2): holds sleeping objects still, and puts objects that have
  // rested long enough with nothing near to sleep.
  void after_integration(mjModel* m, mjData* d);
  // Every object awake and every box open (after a reset, a teleport, an attachment). Call
  // outside begin()/end().
  void wake_all();
  // A held object moves with its holder: it never sleeps, and it does not collide with
  // `hand_bodies` (the bodies of the hand holding it) while held. Call outside begin()/end().
  void set_held(int body, bool held, const std::vector<int>& hand_bodies = {});

  int sleeping() const;
  int closed_boxes() const;

 private:
  struct Tree {  // a movable body tree: the robot, the visitor, a free object
    int root = -1;
    std::vector<int> geoms;  // collidable geoms
    bool free_object = false;
    int qpos = -1, dof = -1;  // free objects: their free joint's addresses
    bool held = false;
    bool asleep = false;
    int rest_steps = 0;
    double center[3] = {0, 0, 0}, radius = 0;  // bounding sphere of the collidable geoms
    double sleep_qpos[7] = {0, 0, 0, 0, 0, 0, 0};
  };
  struct Box {
    int geom;
    bool closed = false;
  };
  void bound(Tree& t, const mjData* d) const;
  // Whether any movable geom of an awake tree other than `except` comes within `extra` of the
  // sphere (c, r).
  bool something_near(const double* c, double r, const Tree* except, const mjData* d) const;
  bool box_needed(const mjModel* m, int box, const mjData* d) const;
  void set_bits(mjModel* m, int geom, bool on) const;
  void set_tree_bits(mjModel* m, const Tree& t, bool on) const;

  ContactPruningOptions options_;
  std::vector<Tree> trees_;
  std::vector<Box> boxes_;
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
  std::vector<int> open_contype_, open_conaffinity_;    // on: with the holds applied
  std::vector<int> saved_contype_, saved_conaffinity_;  // at begin(), while holding
  std::vector<double> margin_, rbound_;
  int rest_steps_needed_ = 1;
  bool active_ = false;  // between begin() and end()
};

}  // namespace taskmatrix::mujoco
