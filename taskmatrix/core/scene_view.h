// Pictures of a loaded scene, backend-neutral: a SceneView shows one state of a robot in an
// environment (a layout's start, a posture, or a recorded trial's frame), answers where named
// frames are and what a line of sight meets, and draws it through a camera. The harness's
// `render`, `scenes`, replays, videos and failure pictures use only this; a backend implements
// it (the MuJoCo one in taskmatrix/mujoco/mujoco_view.h) and LoadedScene::make_view makes one.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace taskmatrix::core {

struct RgbImage {
  int width = 0, height = 0;
  std::vector<std::uint8_t> pixels;  // row-major, top row first, 3 bytes per pixel
};

struct DepthImage {
  int width = 0, height = 0;
  std::vector<float> metres;  // row-major, top row first; +inf where nothing was hit
};

// What to look through: a camera of the scene by name ("head": the robot's head camera), or,
// with `name` empty, a free camera looking at `lookat` from `distance` metres at `azimuth` and
// `elevation` degrees: it looks along (cos el cos az, cos el sin az, sin el).
struct Camera {
  std::string name;
  Eigen::Vector3d lookat{0.4, 0.0, 0.8};
  double distance = 3.6;
  double azimuth = 210;
  double elevation = -22;
};

class SceneView {
 public:
  virtual ~SceneView() = default;

  // The scene's own cameras by name: the environment's (its spec's list first), then any other
  // named camera of the models. The robot's head camera is not listed: "head" always names it.
  virtual std::vector<std::string> cameras() const = 0;
  // The largest image the view can draw.
  virtual int max_width() const = 0;
  virtual int max_height() const = 0;
  // Numbers in one recorded state (core::StateRecording::nq of this backend's recordings).
  virtual int state_size() const = 0;

  // Shows the layout's start state with the robot in one of its profile's postures. Throws
  // std::out_of_range naming the known postures for an unknown one.
  virtual void show_posture(const std::string& posture) = 0;
  // Shows a recorded state (state_size() numbers) at simulated time `time_s`, with the named
  // objects taken out of the world.
  virtual void show_state(std::span<const float> state, double time_s,
                          const std::vector<std::string>& removed_objects) = 0;

  // In the shown state: the world position of a named frame (a palm or fingertip of the
  // profile, an object of the environment), and of the robot's base. Throws
  // std::out_of_range for an unknown name.
  virtual Eigen::Vector3d position(const std::string& frame) const = 0;
  virtual Eigen::Vector3d base_position() const = 0;
  // The distance along the unit direction `along` from `from` to the first surface that is
  // drawn by default (+inf when there is none).
  virtual double first_hit(const Eigen::Vector3d& from, const Eigen::Vector3d& along) const = 0;

  // The shown state through `camera`. Throw std::out_of_range for an unknown camera name and
  // std::invalid_argument for a size outside 1..max_width() x 1..max_height().
  virtual RgbImage render(const Camera& camera, int width, int height) = 0;
  virtual DepthImage render_depth(const Camera& camera, int width, int height) = 0;
};

}  // namespace taskmatrix::core
