// The MuJoCo backend's pictures (core/scene_view.h): a worker copy of the scene with a layout
// applied, drawn through the OSMesa offscreen renderer.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "taskmatrix/core/scene_view.h"
#include "taskmatrix/mujoco/offscreen_renderer.h"
#include "taskmatrix/mujoco/scene.h"

namespace taskmatrix::mujoco {

class MujocoView final : public core::SceneView {
 public:
  MujocoView(std::shared_ptr<const Scene> scene, const core::TrialLayout& layout);

  std::vector<std::string> cameras() const override;
  int max_width() const override;
  int max_height() const override;
  int state_size() const override;
  void show_posture(const std::string& posture) override;
  void show_state(std::span<const float> state, double time_s,
                  const std::vector<std::string>& removed_objects) override;
  Eigen::Vector3d position(const std::string& frame) const override;
  Eigen::Vector3d base_position() const override;
  double first_hit(const Eigen::Vector3d& from, const Eigen::Vector3d& along) const override;
  core::RgbImage render(const core::Camera& camera, int width, int height) override;
  core::DepthImage render_depth(const core::Camera& camera, int width, int height) override;

  // The renderer's camera for `camera`. Throws std::out_of_range for an unknown name.
  CameraView camera_view(const core::Camera& camera) const;
  // The worker copy it shows, for the backend's own tests.
  const WorkerScene& worker() const { return worker_; }

 private:
  OffscreenRenderer& renderer(int width, int height);
  // Moves a body out of the world (10 m down) or back to where the layout put it.
  void set_removed(const std::string& body_name, bool removed);

  std::shared_ptr<const Scene> scene_;
  WorkerScene worker_;
  std::unique_ptr<OffscreenRenderer> renderer_;
  std::map<std::string, std::pair<int, double>> removable_;  // name -> body, z as laid out
  std::vector<std::string> removed_;
};

}  // namespace taskmatrix::mujoco
