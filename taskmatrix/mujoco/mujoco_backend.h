// The MuJoCo backend behind the harness's factory interface (core/backend.h): a LoadedScene is
// a compiled Scene, a TrialWorld a MujocoSkillset on its own worker copy of the model, a
// SceneView a MujocoView (mujoco_view.h).
#pragma once

#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "taskmatrix/core/backend.h"
#include "taskmatrix/mujoco/mujoco_skillset.h"
#include "taskmatrix/mujoco/scene.h"

namespace taskmatrix::mujoco {

class MujocoTrialWorld final : public core::TrialWorld {
 public:
  MujocoTrialWorld(std::shared_ptr<const Scene> scene, const core::TrialLayout& layout,
                   const core::TrialWorldOptions& options);
  core::Skillset& skills() override { return skills_; }
  const core::Skillset& skills() const override { return skills_; }
  std::unique_ptr<core::Perception> make_perception(const std::string& kind) override;
  std::vector<std::string> removed_objects() const override;
  // The backend's own view, for its renderers and tests.
  MujocoSkillset& mujoco_skills() { return skills_; }
  const MujocoSkillset& mujoco_skills() const { return skills_; }

 private:
  MujocoSkillset skills_;
};

class MujocoLoadedScene final : public core::LoadedScene {
 public:
  explicit MujocoLoadedScene(std::shared_ptr<const Scene> scene);
  const core::RobotProfile& robot() const override { return scene_->robot(); }
  const core::EnvironmentSpec& environment() const override { return scene_->environment(); }
  core::TrialLayout make_trial_layout(const core::ObstacleOptions& obstacles,
                                      const core::VariationOptions& variation,
                                      std::uint64_t seed) const override;
  std::vector<core::StartContact> start_contacts(const core::TrialLayout& layout) const override;
  std::unique_ptr<core::TrialWorld> make_trial_world(
      const core::TrialLayout& layout, const core::TrialWorldOptions& options) const override;
  std::unique_ptr<core::SceneView> make_view(const core::TrialLayout& layout) const override;
  const std::shared_ptr<const Scene>& scene() const { return scene_; }

 private:
  // start_contacts without the lock.
  std::vector<core::StartContact> contacts_at_start(const core::TrialLayout& layout) const;

  std::shared_ptr<const Scene> scene_;
  // One worker copy of the model for start_contacts and make_trial_layout's check of a drawn
  // start, made at the first call and reused (a layout applies from the compiled model each
  // time), as a run checks every trial's layout.
  mutable std::mutex probe_mutex_;
  mutable std::unique_ptr<WorkerScene> probe_;
};

class MujocoBackend final : public core::Backend {
 public:
  std::string name() const override { return "mujoco"; }
  std::string version() const override;  // "2.2.2"
  std::shared_ptr<const core::LoadedScene> load(
      const std::filesystem::path& robot_dir,
      const std::filesystem::path& environment_dir) const override;
  void on_fatal_error(void (*handler)(const char* message)) const override;
  std::vector<core::RobotFinding> check_robot(
      const core::LoadedScene& home,
      const std::vector<std::shared_ptr<const core::LoadedScene>>& everywhere) const override;
};

// The MuJoCo Scene behind a scene this backend loaded. Throws std::invalid_argument for a
// scene of another backend.
const std::shared_ptr<const Scene>& scene_of(const core::LoadedScene& scene);

}  // namespace taskmatrix::mujoco
