// The simulation backend as the harness sees it: one factory that loads a robot composed into
// an environment (a LoadedScene, shared read-only by every trial on it) and makes one trial's
// world from it (a TrialWorld: a skillset with the trial's layout applied, and its perception).
// Nothing here names a simulator; the MuJoCo backend implements it in
// taskmatrix/mujoco/mujoco_backend.h. A second backend implements these three classes.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "taskmatrix/core/environment_spec.h"
#include "taskmatrix/core/obstacle_layout.h"
#include "taskmatrix/core/perceptual_model.h"
#include "taskmatrix/core/robot_profile.h"
#include "taskmatrix/core/scene_view.h"
#include "taskmatrix/core/skillset.h"
#include "taskmatrix/core/task_variation.h"

namespace taskmatrix::core {

// How a trial's world executes motion and what it records.
struct TrialWorldOptions {
  // "physics" (dynamics, contact pruning), "kinematic" (configurations set along the
  // trajectory, collisions checked each control period) or "physics_unpruned" (dynamics
  // computing every contact, as MuJoCo does with the scene's own options: the reference that
  // pruning, the candidate-pair contact pass and sparse Jacobians are checked and measured
  // against).
  std::string execution = "physics";
  double visitor_speed_mps = 0;  // the visitor's walk (0: stands still)
  double record_rate_hz = 0;     // > 0: the skillset records its state (Skillset::recording)
};

// One trial's mutable world, owned by one worker.
class TrialWorld {
 public:
  virtual ~TrialWorld() = default;
  virtual Skillset& skills() = 0;
  virtual const Skillset& skills() const = 0;
  // A perception process over this world: "ground_truth" (the exact pose of every object) or
  // "sensor" (what the head sensor sees). Throws std::invalid_argument for another kind.
  virtual std::unique_ptr<Perception> make_perception(const std::string& kind) = 0;
  // The objects the world took away during the trial (debris collected by a tool), by name,
  // in the order they went.
  virtual std::vector<std::string> removed_objects() const = 0;
};

// A contact in a trial's start state, as the layout check reports it.
struct StartContact {
  std::string first, second;  // the two touching parts, by name
  double depth_m = 0;         // penetration; negative: apart, within the contact margin
  bool robot = false;         // the robot is one of them
  bool obstacle = false;      // a random obstacle is one of them
};

// One robot composed into one environment, loaded and checked once; immutable and shared by
// every trial on it (each trial gets its own TrialWorld).
class LoadedScene {
 public:
  virtual ~LoadedScene() = default;
  virtual const RobotProfile& robot() const = 0;
  virtual const EnvironmentSpec& environment() const = 0;
  // Draws a trial's world: the task variation, then the obstacles in the world it leaves.
  // Throws core::LayoutError with a key (of the variation or targeted obstacles at fault) or
  // core::InputError (the environment's regions cannot hold the random obstacles).
  virtual TrialLayout make_trial_layout(const ObstacleOptions& obstacles,
                                        const VariationOptions& variation,
                                        std::uint64_t seed) const = 0;
  // The contacts of the start state with `layout` applied: every one the robot takes part in,
  // and every other one deeper than 1 mm. Throws core::LayoutError or core::VariationError
  // when the layout cannot be applied.
  virtual std::vector<StartContact> start_contacts(const TrialLayout& layout) const = 0;
  // A trial's world with `layout` applied, at its start state. Throws std::invalid_argument
  // for an unknown execution mode.
  virtual std::unique_ptr<TrialWorld> make_trial_world(const TrialLayout& layout,
                                                       const TrialWorldOptions& options) const = 0;
  // A view for pictures of this scene with `layout` applied, showing its start state. Throws
  // as start_contacts, and std::runtime_error when the backend cannot draw here.
  virtual std::unique_ptr<SceneView> make_view(const TrialLayout& layout) const = 0;
};

// One finding of `taskmatrix check-robot`: what the loader cannot decide from names alone.
struct RobotFinding {
  enum class Level { kOk, kWarning, kError };
  Level level = Level::kOk;
  std::string check;    // what was checked: "chains", "mirror signs", "palm axes", ...
  std::string message;  // what was found, with the profile key at fault for an error
};
// "ok", "warning" or "ERROR".
inline const char* to_string(RobotFinding::Level level) {
  switch (level) {
    case RobotFinding::Level::kOk:
      return "ok";
    case RobotFinding::Level::kWarning:
      return "warning";
    case RobotFinding::Level::kError:
      return "ERROR";
  }
  return "?";
}

// The factory: what the harness calls to reach a backend.
class Backend {
 public:
  virtual ~Backend() = default;
  virtual std::string name() const = 0;     // "mujoco"
  virtual std::string version() const = 0;  // the simulator's, for a run's provenance
  // Loads a robot's folder (profile and model) into an environment's folder. Throws
  // core::InputError naming the file and key at fault.
  virtual std::shared_ptr<const LoadedScene> load(
      const std::filesystem::path& robot_dir,
      const std::filesystem::path& environment_dir) const = 0;
  // Routes the simulator's fatal errors (those it cannot return from, as MuJoCo's mju_error) to
  // `handler`, for the whole process; the message names the simulator. `handler` must not
  // return (a trial worker reports the error as its crash and ends).
  virtual void on_fatal_error(void (*handler)(const char* message)) const = 0;
  // What a robot must satisfy for the task programs to work, checked on its kinematics
  // (models/README.md, "What the programs need of a robot"): `home` is the robot loaded into
  // one environment, `everywhere` into each environment (for the reach envelope against every
  // surface). Both were loaded by this backend; throws std::invalid_argument otherwise.
  virtual std::vector<RobotFinding> check_robot(
      const LoadedScene& home,
      const std::vector<std::shared_ptr<const LoadedScene>>& everywhere) const = 0;
};

}  // namespace taskmatrix::core
