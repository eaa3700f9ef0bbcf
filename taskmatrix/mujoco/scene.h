// A Scene is one robot composed into one environment and compiled once, with every name the
// profile and environment spec use resolved to MuJoCo ids and checked. It is immutable and
// shared read-only by all workers. A WorkerScene is one worker's mutable state: its own copy
// of the model (so obstacle slots can be written without recompiling) and its mjData.
#pragma once

#include <array>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "taskmatrix/core/environment_spec.h"
#include "taskmatrix/core/obstacle_layout.h"
#include "taskmatrix/core/robot_profile.h"
#include "taskmatrix/core/task_variation.h"
#include "taskmatrix/mujoco/mujoco_handles.h"

namespace taskmatrix::mujoco {

struct ChainIndex {
  std::string name;
  std::vector<int> joints;    // MuJoCo joint ids, chain order
  std::vector<int> qpos_adr;  // one per joint (hinge and slide joints only)
  std::vector<double> lower, upper;
};

// A named frame: a site, a body or a camera of the model.
struct FrameRef {
  enum class Kind { kSite, kBody, kCamera } kind = Kind::kSite;
  int id = -1;
};

struct ObstacleSlot {
  int body = -1;
  std::array<int, 3> geoms{-1, -1, -1};  // indexed by core::ObstacleShape
};

// A geom pair that MuJoCo's collision filters let through and that involves the robot.
struct GeomPair {
  int g1, g2;  // geom_type[g1] <= geom_type[g2], as MuJoCo's function table wants
  double margin;
};

struct RobotContact {
  std::string geom1, body1, geom2, body2;
  double distance = 0;  // negative: penetration
};

// Half the extent of geom `g` (as posed in `d`) along the world's x and y: its box, or the box
// round its primitive shape, turned into the world (a mesh or anything else: its bounding
// sphere).
Eigen::Vector2d horizontal_half_extent(const mjModel* m, const mjData* d, int g);

class Scene {
 public:
  // Loads models/robots/<robot>/profile.yaml and models/environments/<env>/environment.yaml,
  // composes and compiles them and checks every name. Throws core::InputError naming the
  // file and key at fault.
  static std::shared_ptr<const Scene> load(const std::filesystem::path& robot_dir,
                                           const std::filesystem::path& environment_dir);

  const mjModel* model() const { return model_.get(); }
  const core::RobotProfile& robot() const { return robot_; }
  const core::EnvironmentSpec& environment() const { return environment_; }
  const std::string& composed_mjcf() const { return composed_mjcf_; }

  const std::vector<ChainIndex>& chains() const { return chains_; }
  const ChainIndex& chain(std::string_view name) const;  // throws std::out_of_range
  // A site, body or camera by name; an object by its symbolic name ("cup": its body) or one of
  // its frames ("vacuum.tip", "vacuum.grip"). Throws std::out_of_range.
  FrameRef frame(std::string_view name) const;
  int head_camera() const { return head_camera_; }
  bool is_robot_body(int body) const;
  bool is_robot_geom(int geom) const;
  // The hand (index into robot().hands) that robot body `body` belongs to: the palm frame's
  // body and every body below it; -1 for any other body. Contacts within one hand (a finger
  // on a finger, a finger on the palm) are the hand's own business, never collisions.
  int hand_of_body(int body) const;
  bool same_hand(int body1, int body2) const;
  const std::vector<ObstacleSlot>& obstacle_slots() const { return obstacle_slots_; }
  // The farthest the visitor's geoms reach from its vertical axis as it stands in the model (a
  // geom's reach: its centre's distance plus the larger of its half extents along x and y);
  // 0 for an environment without a visitor.
  double visitor_radius() const { return visitor_radius_; }
  // Every geom pair with a robot geom that can ever produce a contact: not filtered by
  // MuJoCo's weld/parent rule or an <exclude>, and with collision bits set, or an obstacle
  // slot (whose bits change per layout). Computed once, at load.
  const std::vector<GeomPair>& robot_geom_pairs() const { return robot_geom_pairs_; }
  // The pair (g1, g2) in MuJoCo's argument order, if the two geoms can ever touch: both with
  // collision bits (or an obstacle slot), not filtered by weld/parent rules or an <exclude>.
  std::optional<GeomPair> collidable_pair(int g1, int g2) const;

  // Full qpos with the robot at the environment's start pose in posture `rest`; everything
  // else at the model's qpos0.
  const std::vector<double>& start_qpos() const { return start_qpos_; }
  // Writes a profile posture into qpos. Throws std::out_of_range for an unknown posture.
  void apply_posture(std::string_view posture, double* qpos) const;

  // Obstacle request for `count` obstacles: the environment's regions, the robot's start
  // disk, keep-out rectangles and the footprints of task objects and the visitor protected.
  // Throws core::InputError when `count` exceeds the environment's obstacle_slots.
  core::LayoutRequest layout_request(int count) const;
  // generate_layout(layout_request(count), seed), with a failure reported as an InputError
  // naming the environment file's obstacle_regions.
  core::ObstacleLayout make_layout(int count, std::uint64_t seed) const;
  // The same with a scenario's options: regions by name (an unknown name throws
  // core::InputError naming the environment file's obstacle_regions), shapes and sizes.
  core::LayoutRequest layout_request(const core::ObstacleOptions& options) const;
  core::ObstacleLayout make_layout(const core::ObstacleOptions& options, std::uint64_t seed) const;

  // Task variations (core/task_variation.h). What the generator knows of this scene: every
  // surface (top, height, placement area: the environment's obstacle region on it, or its top
  // less 3 cm, fixtures on it kept out), every task object (debris flakes by body name) and the
  // robot's start, as compiled.
  const core::WorldGeometry& world_geometry() const { return world_; }
  // The robot's footprint radius at its start (horizontal reach of its geoms from the base
  // origin), counting only geoms whose lowest point is below `below_z`.
  double robot_footprint_radius(double below_z) const;
  // The obstacle request in the world a variation leaves: regions on moved surfaces at their
  // new heights, the drawn start disk, objects protected where they now are, and the
  // scenario's targeted obstacles as groups. Without variation and targeted obstacles it is
  // layout_request(options).
  core::LayoutRequest layout_request(const core::ObstacleOptions& options,
                                     const core::TaskVariation& variation) const;
  // Draws the variation, then the obstacles in the world it leaves. Throws
  // core::LayoutError with a key (of the scenario's variation or targeted obstacles at fault)
  // or core::InputError (the environment's regions cannot hold the random obstacles).
  // `start_clear` redraws a varied start the robot would begin in contact at
  // (core::draw_world).
  core::TrialLayout make_trial_layout(const core::ObstacleOptions& obstacles,
                                      const core::VariationOptions& variation, std::uint64_t seed,
                                      const core::StartCheck& start_clear = {}) const;

 private:
  Scene() = default;
  void index_and_validate();
  // Shifts the base joints' ranges (and their actuators' control ranges) to centre on the
  // environment's start pose; a yaw only if its range spans a full turn (within
  // kFullTurnSlackRad).
  void centre_base_on_start();
  static constexpr double kFullTurnSlackRad = 1e-3;

  ModelPtr model_;
  core::RobotProfile robot_;
  core::EnvironmentSpec environment_;
  std::string composed_mjcf_;
  std::vector<ChainIndex> chains_;
  int head_camera_ = -1;
  int robot_root_ = -1;
  double visitor_radius_ = 0;
  std::vector<ObstacleSlot> obstacle_slots_;
  std::vector<GeomPair> robot_geom_pairs_;
  std::vector<char> ever_collides_;
  std::vector<int> hand_of_body_;
  std::vector<double> start_qpos_;
  std::vector<core::Rect2> object_footprints_;

  // Task variations: made at load by index_variations() (variation_apply.cc).
  friend class WorkerScene;
  void index_variations();
  // A surface that can move up and down: its body subtree and how each geom stretches.
  struct SurfaceRig {
    std::string name;
    int body = -1;
    double height = 0;  // of the top face, as compiled
    double cut = 0;     // below this, geoms stretch with the height; above, they move rigidly
    std::vector<int> geoms;
    std::vector<double> bottom, top;  // each geom's world z extent, as compiled
    std::vector<char> stretches;      // an upright box, cylinder or capsule
  };
  // A free body or static debris flake resting on a surface, moving with it.
  struct RestingBody {
    size_t surface = 0;  // index into surface_rigs_
    int body = -1;
    int qpos_adr = -1;  // a free joint's position; -1: a body without joints (body_pos moves)
  };
  core::WorldGeometry world_;
  std::vector<SurfaceRig> surface_rigs_;
  std::vector<RestingBody> resting_;
  std::vector<std::pair<double, double>> robot_geom_reach_;  // (horizontal reach, lowest z)
  std::vector<int> object_footprint_bodies_;                 // parallel to object_footprints_
};

class WorkerScene {
 public:
  explicit WorkerScene(std::shared_ptr<const Scene> scene);

  const Scene& scene() const { return *scene_; }
  mjModel* model() { return model_.get(); }
  mjData* data() { return data_.get(); }
  const mjModel* model() const { return model_.get(); }
  const mjData* data() const { return data_.get(); }

  // Writes the layout into the obstacle slots of this worker's model copy: the slot's geom
  // of the obstacle's shape is given size, pose, collision and visibility; every other slot
  // geom is disabled. Throws core::LayoutError if there are more obstacles than slots.
  void apply_layout(const core::ObstacleLayout& layout);
  // Writes a task variation into this worker's model copy and start state, starting from the
  // compiled model each time (an empty variation restores it). A surface's body moves by its
  // height change; its geoms map heights z in [0, cut] (the floor to the bottom of its top
  // slab) to z (cut + shift) / cut and move rigidly above the cut, so legs and cabinets keep
  // standing on the floor; what rests on it (free bodies, debris) moves with it. Placed objects
  // and the robot's base get their drawn poses in the start state. Takes effect on the next
  // reset_to_start(). Throws core::VariationError for a height the surface cannot take.
  void apply_variation(const core::TaskVariation& variation);
  // Both, the variation first.
  void apply(const core::TrialLayout& layout);
  // The start state: scene().start_qpos() as the applied variation changes it.
  const std::vector<double>& start_qpos() const { return start_qpos_; }
  // qpos = start_qpos(), zero velocities, then mj_forward.
  void reset_to_start();
  // Contacts after the last mj_forward/mj_collision in which a robot geom takes part.
  std::vector<RobotContact> robot_contacts() const;

 private:
  std::shared_ptr<const Scene> scene_;
  ModelPtr model_;
  DataPtr data_;
  std::vector<double> start_qpos_;
};

}  // namespace taskmatrix::mujoco
