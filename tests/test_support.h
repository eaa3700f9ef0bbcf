// Shared helpers for the test suite: the project's models, cached compiled scenes, and a
// way to run the CLI as a user would.
#pragma once

#include <filesystem>
#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "harness/scenario/model_catalog.h"
#include "taskmatrix/mujoco/mujoco_backend.h"
#include "taskmatrix/mujoco/scene.h"

namespace taskmatrix::test {

// The models the tests run on: $TASKMATRIX_ROOT if set (a checkout or any folder holding
// models/robots and models/environments), else this source tree. Tests over "every robot"
// and "every environment" take theirs from it, so a user's robot gets the model tests:
//   TASKMATRIX_ROOT=/my/root ctest -R Models   (tests are listed when ctest starts)
const harness::ModelCatalog& catalog();
// Compiled once per process and shared, as workers share them.
std::shared_ptr<const mujoco::Scene> scene(const std::string& robot,
                                           const std::string& environment);
// The same scene behind the harness's backend interface (core/backend.h), for run_trial.
std::shared_ptr<const core::LoadedScene> loaded_scene(const std::string& robot,
                                                      const std::string& environment);
// The MuJoCo skillset of a trial's world (a trial observer's argument).
const mujoco::MujocoSkillset& mujoco_skills(const core::TrialWorld& world);

struct RobotEnv {
  std::string robot, environment;
};
std::vector<RobotEnv> all_robot_environment_pairs();
inline void PrintTo(const RobotEnv& p, std::ostream* os) {
  *os << p.robot << " in " << p.environment;
}
std::string pair_name(const RobotEnv& p);  // for parameterised test names

struct CommandResult {
  int exit_code = -1;
  std::string out, err;
};
// Runs the taskmatrix CLI with `args` and TASKMATRIX_ROOT=`root` (with a time limit).
CommandResult run_cli(const std::string& args, const std::filesystem::path& root);

// A program whose default layout (kitchen) is known to plan differently under physics and
// kinematic execution on a built-in robot, with why; none: nullopt. Both must still succeed;
// the execution-modes test, which requires the same plan calls, skips it and says why, so the
// difference stays visible in every test run (README, "Known failures"). Remove an entry when
// the two plan alike again: the test then requires it.
std::optional<std::string> known_mode_difference(const std::string& program,
                                                 const std::string& robot);

// A throw-away copy of models/ under a fresh temporary root, for corrupting files.
class ScratchRoot {
 public:
  ScratchRoot();
  ~ScratchRoot();
  const std::filesystem::path& path() const { return root_; }
  std::filesystem::path file(const std::string& relative) const { return root_ / relative; }
  std::string read(const std::string& relative) const;
  void write(const std::string& relative, const std::string& text) const;
  // Replaces the first occurrence of `from` (which must exist) in a file.
  void replace(const std::string& relative, const std::string& from, const std::string& to) const;

 private:
  std::filesystem::path root_;
};

// Adds to `root` a room the programs were not written for: the kitchen with its table turned
// 0.35 rad (20 degrees) about the vertical and moved to x 0.75, the objects on it moved along
// with it by 0.1 m in x, as models/environments/kitchen_turned. The table's world-aligned box
// reaches 10-20 cm beyond the table at its corners; the environment names no obstacle region
// on the table, so objects and obstacles go where its own rectangle says.
void add_turned_kitchen(const ScratchRoot& root);

// Adds to `root` another room the programs were not written for: the kitchen with its counter
// (side_surface) behind the robot instead of to its left, its front facing the robot's back
// (centre at x -1.0, y 0.2), as models/environments/kitchen_behind. What is put down there
// needs the robot to turn round and walk to it.
void add_kitchen_counter_behind(const ScratchRoot& root);

// Gives tallbot in `root` the waist it had until 2026-12-06: its torso pitches forward at most
// 0.8 rad (46 degrees) instead of 1.4. With it, its palm gets nowhere over a table below
// 0.50-0.60 m as a grasp of an upright object holds it (its fingers close along its forearm,
// which then points down too steeply): a robot that cannot serve a low table.
void stiffen_tallbot_waist(const ScratchRoot& root);

}  // namespace taskmatrix::test
