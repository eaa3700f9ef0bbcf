// The simulated head sensor (paper section III-B): a depth camera with object recognition at
// the robot's head camera. Each capture casts one ray per pixel (mj_ray) from the camera
// through a pinhole image plane of the camera's vertical field of view, up to a range.
// Recognition: a thing is recognised when at least `min_pixels` rays end on it (so it is in
// view, in range and not occluded); its confidence is the share of the rays pointing into its
// bounding box that reach it (1: fully visible, lower: partly occluded). Recognised things get
// their true pose and box; the sensor adds no noise.
//
// SensorPerception is perception mode `sensor`: only what the head has recognised is in the
// perceptual model (kept with the time it was last seen), and the skillset's queries know an
// obstacle only once it has been recognised.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "taskmatrix/core/perceptual_model.h"
#include "taskmatrix/mujoco/ground_truth_perception.h"
#include "taskmatrix/mujoco/mujoco_skillset.h"

namespace taskmatrix::mujoco {

struct HeadSensorOptions {
  int width = 64;  // rays per row
  int height = 48;
  double range_m = 5.0;
  int min_pixels = 3;
};

// One capture. Pixels are row-major from the top-left.
struct SensorImage {
  int width = 0, height = 0;
  std::vector<float> depth_m;  // along the optical axis; 0 where nothing is hit within range
  std::vector<int> thing;      // index into HeadSensor::things(), or -1
};

struct Recognition {
  int thing = -1;                // index into HeadSensor::things()
  int pixels = 0;                // rays ending on it
  int in_box = 0;                // rays pointing into its bounding box within range
  core::PerceivedObject object;  // its true pose, box and frames (last_seen, confidence unset)
  double confidence() const { return in_box > 0 ? static_cast<double>(pixels) / in_box : 0.0; }
};

class HeadSensor {
 public:
  // Throws std::invalid_argument for a non-positive size, range or pixel count.
  HeadSensor(const MujocoSkillset& skills, HeadSensorOptions options = {});

  // Casts the rays in the simulation's current state (after the layout is applied: the
  // things include the active obstacles as they are at the first capture after a layout).
  const SensorImage& capture();
  // What the last capture recognised.
  std::vector<Recognition> recognise() const;
  const std::vector<SceneThing>& things() const { return things_; }
  // World point where pixel `i`'s ray ended in the last capture; nullopt for no hit.
  std::optional<Eigen::Vector3d> hit_point(size_t i) const;
  const HeadSensorOptions& options() const { return options_; }
  // mj_ray from `from` along `dir` as the sensor's rays go (the camera's body excluded, and
  // the robot geoms the camera sat inside at the last capture passed through): the distance
  // in multiples of |dir| and the geom hit, or -1 and geom -1 for none.
  double ray(const Eigen::Vector3d& from, const Eigen::Vector3d& dir, int* geom) const;

 private:
  void map_geoms();

  const MujocoSkillset& skills_;
  HeadSensorOptions options_;
  std::vector<SceneThing> things_;
  std::vector<int> geom_thing_;  // geom -> thing index or -1
  SensorImage image_;
  std::vector<Eigen::Vector3d> rays_;  // world directions of the last capture (unit)
  std::vector<double> distance_;       // along each ray; -1 for no hit
  Eigen::Vector3d origin_;
  std::vector<int> enclosing_;  // robot geoms holding the camera at the last capture
};

class SensorPerception final : public core::Perception {
 public:
  // Switches the skillset to sensor mode (queries know only perceived obstacles).
  SensorPerception(MujocoSkillset& skills, HeadSensorOptions options = {});
  const char* mode() const override { return "sensor"; }
  void update(double time, core::PerceptualModel& model) override;
  const HeadSensor& sensor() const { return sensor_; }

 private:
  MujocoSkillset& skills_;
  HeadSensor sensor_;
};

}  // namespace taskmatrix::mujoco
