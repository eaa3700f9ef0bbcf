// Offscreen rendering on the CPU through OSMesa: RGB images and metric depth from a scene
// camera, the robot's head camera or a free camera. One renderer per thread (the OSMesa
// context is made current on each call).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include <mujoco/mujoco.h>

#include "taskmatrix/core/scene_view.h"

namespace taskmatrix::mujoco {

using core::DepthImage;
using core::RgbImage;

// Which camera to look through. A free camera looks at `lookat` from `distance` metres,
// with azimuth and elevation in degrees (MuJoCo's conventions).
struct CameraView {
  int fixed_camera = -1;  // >= 0: a model camera id; -1: the free camera below
  double lookat[3] = {0.4, 0.0, 0.8};
  double distance = 3.6;
  double azimuth = 210;
  double elevation = -22;
};

class OffscreenRenderer {
 public:
  // Throws std::runtime_error if no OSMesa context can be made or the size exceeds the
  // model's offscreen buffer (visual/global offwidth, offheight).
  OffscreenRenderer(const mjModel* model, int width, int height);
  ~OffscreenRenderer();
  OffscreenRenderer(const OffscreenRenderer&) = delete;
  OffscreenRenderer& operator=(const OffscreenRenderer&) = delete;

  // `model` and `data` may be a worker's copy of the model the renderer was made with.
  RgbImage render_rgb(const mjModel* model, mjData* data, const CameraView& view);
  DepthImage render_depth(const mjModel* model, mjData* data, const CameraView& view);

  int width() const { return width_; }
  int height() const { return height_; }

 private:
  void draw(const mjModel* model, mjData* data, const CameraView& view);

  struct Impl;
  std::unique_ptr<Impl> impl_;
  int width_, height_;
};

}  // namespace taskmatrix::mujoco
