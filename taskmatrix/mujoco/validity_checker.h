// Collision verdicts for robot configurations: is the robot touching anything (itself, the
// world, obstacles, objects) at this configuration?
//
// `raw_robot_in_collision` is the reference: mj_kinematics + mj_collision on the whole model,
// then "any contact with a robot geom". `ValidityChecker` gives the same verdicts faster:
//   - it knows which joints a query may move (the planned chains) and recomputes the poses
//     of only the bodies those joints move (hinge and slide joints, MuJoCo's own formulas);
//   - it tests only geom pairs that can change: at least one geom moved by those joints, the
//     pair allowed by MuJoCo's filters (contype/conaffinity, weld and parent, exclude);
//     pairs that cannot change are checked once, when the checker is bound to a state;
//   - a bounding-sphere test first, MuJoCo's narrow-phase function second, and it stops at
//     the first contact.
// Verdicts are identical to the raw check; a test compares them on 100,000 configurations.
#pragma once

#include <cstdint>
#include <vector>

#include "taskmatrix/mujoco/scene.h"

namespace taskmatrix::mujoco {

// Reference check on the worker's full model and data: runs mj_kinematics and
// mj_collision with data->qpos as it is.
bool raw_robot_in_collision(const Scene& scene, const mjModel* m, mjData* d);

class ValidityChecker {
 public:
  // `moving_joints`: MuJoCo joint ids the queries may change (hinge or slide robot joints).
  // Binds to the worker's current state (data->qpos): pairs that no moving joint can change
  // are evaluated once here, and the poses of bodies that do not move are taken from it.
  ValidityChecker(const Scene& scene, const mjModel* m, mjData* d,
                  const std::vector<int>& moving_joints);

  // True if the pairs that cannot change are already in contact at the bound state: then
  // every configuration is invalid (a start in collision with itself or the world).
  bool static_collision() const { return static_collision_; }

  // Sets the moving joints' qpos to `values` (same order as moving_joints), updates the
  // moving bodies and geoms in `d`, and returns true if any robot geom is in contact.
  bool in_collision(const double* values);

  std::uint64_t checks() const { return checks_; }
  size_t changing_pair_count() const { return changing_pairs_.size(); }
  std::uint64_t narrow_phase_calls() const { return narrow_calls_; }

 private:
  void update_moving_kinematics();
  bool pair_in_contact(const GeomPair& p);

  const Scene& scene_;
  const mjModel* m_;
  mjData* d_;
  std::vector<int> joints_;
  std::vector<int> qpos_adr_;
  std::vector<int> moving_bodies_;  // in increasing id order: parents first
  std::vector<int> moving_geoms_;
  std::vector<GeomPair> changing_pairs_;
  bool static_collision_ = false;
  std::uint64_t checks_ = 0;
  std::uint64_t narrow_calls_ = 0;
  mjContact scratch_[mjMAXCONPAIR];
};

}  // namespace taskmatrix::mujoco
