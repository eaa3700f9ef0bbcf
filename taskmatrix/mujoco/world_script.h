// The world's own behaviour beyond physics, for one worker's model:
//   - The visitor walks its environment path back and forth at set_visitor_walk's speed,
//     facing where it goes (driven kinematically; 0, the default, leaves it standing). As a
//     person does, it does not walk into the robot: where a step would bring it within
//     kVisitorYieldM of the robot or what it holds (seen from above: the box round every geom
//     against the visitor's own radius round its axis), and closer than it is, it turns
//     round and walks back the way it came. Nothing stops a robot coming to it.
//   - A debris flake is removed (moved out of the world) when the tip of a held tool passes
//     over it: tip within kDebrisPickupRadius of its centre horizontally and at most
//     kDebrisPickupHeight above it.
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

#include "taskmatrix/mujoco/attachments.h"
#include "taskmatrix/mujoco/scene.h"

namespace taskmatrix::mujoco {

inline constexpr double kDebrisPickupRadius = 0.035;  // m, horizontal, tip to flake centre
inline constexpr double kDebrisPickupHeight = 0.06;   // m, tip above the flake's centre
inline constexpr double kVisitorYieldM = 0.10;        // m, the room the visitor leaves the robot

class WorldScript {
 public:
  // The scene's debris flakes (where `m` has them) and tools with tip sites.
  WorldScript(const Scene& scene, const mjModel* m);

  // The visitor's walking speed along its path (m/s, >= 0). Throws std::invalid_argument for a
  // negative or non-finite speed, or an environment whose visitor is not a (slide x, slide y,
  // hinge) body with a path of two or more points.
  void set_visitor_walk(const mjModel* m, double speed_mps);
  // Walks the visitor on to simulated `time` (the first call after set_visitor_walk walks from
  // time 0), in `d`, with the robot and what `held` holds where `d`'s geom poses have them.
  void drive_visitor(const mjModel* m, mjData* d, double time, const HeldObjects& held);
  // The visitor starts its walk again from the path's first point at time 0 (after a reset).
  void restart_visitor_walk() { visitor_walked_ = visitor_time_ = 0; }

  // The flakes' places are where `m` has them now (after a task variation moved them).
  void note_debris_places(const mjModel* m);
  // Puts every removed flake back in `m`; none removed.
  void restore_debris(mjModel* m);
  // Removes the flakes under the tips of held tools (poses in `d`), in `m`; the removed
  // bodies, in order (empty if none).
  std::vector<int> collect_debris(mjModel* m, const mjData* d, const HeldObjects& held);
  // Debris bodies removed since the last restore, in order of removal.
  const std::vector<int>& removed_debris() const { return removed_; }
  bool removed(int body) const;

 private:
  const Scene& scene_;
  // The visitor's place on its path after walking `walked` metres (there and back again).
  Eigen::Vector2d visitor_at(double walked, Eigen::Vector2d* heading) const;
  // Horizontal room between the visitor standing at `at` and the robot or what it holds.
  double room_from_robot(const mjModel* m, const mjData* d, const Eigen::Vector2d& at,
                         const HeldObjects& held) const;

  double visitor_speed_ = 0;
  double visitor_walked_ = 0;  // m along the path (there and back again)
  double visitor_time_ = 0;    // s: the simulated time it has walked to
  std::vector<int> robot_geoms_;
  std::vector<double> visitor_arc_;              // arc length along the path at each waypoint
  std::array<int, 3> visitor_qpos_{-1, -1, -1};  // x, y, yaw
  std::array<int, 3> visitor_dof_{-1, -1, -1};
  struct Debris {
    int body;
    Eigen::Vector3d pos;  // body_pos in place
  };
  std::vector<Debris> debris_;
  struct ToolTip {
    int body, site;
  };
  std::vector<ToolTip> tool_tips_;
  std::vector<int> removed_;
};

}  // namespace taskmatrix::mujoco
