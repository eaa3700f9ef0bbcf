#include "taskmatrix/mujoco/mujoco_view.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "taskmatrix/mujoco/kinematics.h"

namespace taskmatrix::mujoco {

MujocoView::MujocoView(std::shared_ptr<const Scene> scene, const core::TrialLayout& layout)
    : scene_(std::move(scene)), worker_(scene_) {
  worker_.apply(layout);
  worker_.reset_to_start();
}

std::vector<std::string> MujocoView::cameras() const {
  std::vector<std::string> names = scene_->environment().cameras;
  const mjModel* m = worker_.model();
  for (int c = 0; c < m->ncam; ++c) {
    const char* name = mj_id2name(m, mjOBJ_CAMERA, c);
    if (c == scene_->head_camera() || name == nullptr) continue;
    if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
  }
  return names;
}

int MujocoView::max_width() const { return worker_.model()->vis.global.offwidth; }
int MujocoView::max_height() const { return worker_.model()->vis.global.offheight; }
int MujocoView::state_size() const { return worker_.model()->nq; }

void MujocoView::show_posture(const std::string& posture) {
  std::vector<double> qpos = worker_.start_qpos();
  scene_->apply_posture(posture, qpos.data());  // throws std::out_of_range
  worker_.reset_to_start();
  std::copy(qpos.begin(), qpos.end(), worker_.data()->qpos);
  mj_forward(worker_.model(), worker_.data());
}

void MujocoView::set_removed(const std::string& body_name, bool removed) {
  mjModel* m = worker_.model();
  auto it = removable_.find(body_name);
  if (it == removable_.end()) {
    const int body = mj_name2id(m, mjOBJ_BODY, body_name.c_str());
    if (body <= 0) throw std::out_of_range("no body '" + body_name + "' in the scene");
    it = removable_.emplace(body_name, std::make_pair(body, m->body_pos[3 * body + 2])).first;
  }
  const auto [body, z] = it->second;
  m->body_pos[3 * body + 2] = z - (removed ? 10.0 : 0.0);
}

void MujocoView::show_state(std::span<const float> state, double time_s,
                            const std::vector<std::string>& removed_objects) {
  mjModel* m = worker_.model();
  mjData* d = worker_.data();
  if (state.size() != static_cast<size_t>(m->nq)) {
    throw std::invalid_argument("a state of " + std::to_string(state.size()) +
                                " numbers for a model with " + std::to_string(m->nq) +
                                " positions");
  }
  for (const std::string& name : removed_) set_removed(name, false);
  for (const std::string& name : removed_objects) set_removed(name, true);
  removed_ = removed_objects;
  for (int i = 0; i < m->nq; ++i) d->qpos[i] = state[static_cast<size_t>(i)];
  // Quaternions lost precision as float: normalise them for rendering.
  mj_normalizeQuat(m, d->qpos);
  d->time = time_s;
  mj_forward(m, d);
}

Eigen::Vector3d MujocoView::position(const std::string& frame) const {
  return frame_pose(worker_.data(), scene_->frame(frame)).position;
}

Eigen::Vector3d MujocoView::base_position() const {
  const int body = worker_.model()->jnt_bodyid[scene_->chain("base").joints.at(0)];
  const mjtNum* x = worker_.data()->xpos + 3 * body;
  return {x[0], x[1], x[2]};
}

double MujocoView::first_hit(const Eigen::Vector3d& from, const Eigen::Vector3d& along) const {
  const mjtNum p[3] = {from.x(), from.y(), from.z()};
  const mjtNum v[3] = {along.x(), along.y(), along.z()};
  const mjtByte groups[mjNGROUP] = {1, 1, 1, 0, 0, 0};  // what the renderer draws by default
  int geom = -1;
  const double hit = mj_ray(worker_.model(), worker_.data(), p, v, groups, 1, -1, &geom);
  return geom < 0 || hit < 0 ? std::numeric_limits<double>::infinity() : hit;
}

CameraView MujocoView::camera_view(const core::Camera& camera) const {
  CameraView view;
  if (camera.name.empty()) {
    for (int i = 0; i < 3; ++i) view.lookat[i] = camera.lookat[i];
    view.distance = camera.distance;
    view.azimuth = camera.azimuth;
    view.elevation = camera.elevation;
  } else if (camera.name == "head") {
    view.fixed_camera = scene_->head_camera();
  } else {
    view.fixed_camera = mj_name2id(worker_.model(), mjOBJ_CAMERA, camera.name.c_str());
    if (view.fixed_camera < 0) {
      std::string known = "head";
      for (const std::string& c : cameras()) known += ", " + c;
      throw std::out_of_range("unknown camera '" + camera.name + "' (known: " + known + ")");
    }
  }
  return view;
}

OffscreenRenderer& MujocoView::renderer(int width, int height) {
  if (width < 1 || height < 1 || width > max_width() || height > max_height()) {
    throw std::invalid_argument("image size " + std::to_string(width) + "x" +
                                std::to_string(height) + " is outside 1x1.." +
                                std::to_string(max_width()) + "x" + std::to_string(max_height()) +
                                " (the model's offscreen buffer)");
  }
  if (!renderer_ || renderer_->width() != width || renderer_->height() != height) {
    renderer_.reset();
    renderer_ = std::make_unique<OffscreenRenderer>(scene_->model(), width, height);
  }
  return *renderer_;
}

core::RgbImage MujocoView::render(const core::Camera& camera, int width, int height) {
  const CameraView view = camera_view(camera);
  return renderer(width, height).render_rgb(worker_.model(), worker_.data(), view);
}

core::DepthImage MujocoView::render_depth(const core::Camera& camera, int width, int height) {
  const CameraView view = camera_view(camera);
  return renderer(width, height).render_depth(worker_.model(), worker_.data(), view);
}

}  // namespace taskmatrix::mujoco
