#include "taskmatrix/mujoco/head_sensor.h"

#include "taskmatrix/core/conditions.h"
#include "taskmatrix/mujoco/body_kinematics.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace taskmatrix::mujoco {

namespace {

// Distance along a unit ray from `o` at which it enters `box`, or -1 if it misses.
double ray_box_entry(const Eigen::Vector3d& o, const Eigen::Vector3d& dir,
                     const Eigen::AlignedBox3d& box) {
  double lo = 0, hi = INFINITY;
  for (int i = 0; i < 3; ++i) {
    if (std::abs(dir[i]) < 1e-12) {
      if (o[i] < box.min()[i] || o[i] > box.max()[i]) return -1;
      continue;
    }
    double t1 = (box.min()[i] - o[i]) / dir[i], t2 = (box.max()[i] - o[i]) / dir[i];
    if (t1 > t2) std::swap(t1, t2);
    lo = std::max(lo, t1);
    hi = std::min(hi, t2);
    if (lo > hi) return -1;
  }
  return lo;
}

}  // namespace

HeadSensor::HeadSensor(const MujocoSkillset& skills, HeadSensorOptions options)
    : skills_(skills), options_(options) {
  if (options_.width <= 0 || options_.height <= 0 || options_.min_pixels <= 0 ||
      !(std::isfinite(options_.range_m) && options_.range_m > 0)) {
    throw std::invalid_argument(
        "head sensor: width, height, min_pixels and range_m must be positive");
  }
  image_.width = options_.width;
  image_.height = options_.height;
  image_.depth_m.assign(static_cast<size_t>(options_.width) * options_.height, 0.0f);
  image_.thing.assign(image_.depth_m.size(), -1);
  rays_.resize(image_.depth_m.size());
  distance_.assign(image_.depth_m.size(), -1.0);
}

std::optional<Eigen::Vector3d> HeadSensor::hit_point(size_t i) const {
  if (i >= distance_.size() || distance_[i] < 0) return std::nullopt;
  return origin_ + distance_[i] * rays_[i];
}

void HeadSensor::map_geoms() {
  const mjModel* m = skills_.model();
  things_ = scene_things(skills_);
  geom_thing_.assign(m->ngeom, -1);
  std::vector<int> body_thing(m->nbody, -1);
  for (size_t t = 0; t < things_.size(); ++t) body_thing[things_[t].body] = static_cast<int>(t);
  for (int g = 0; g < m->ngeom; ++g) {
    const int own = m->geom_bodyid[g];
    for (int b = own; b > 0; b = m->body_parentid[b]) {
      const int t = body_thing[b];
      if (t >= 0 && (b == own || things_[t].subtree)) {
        geom_thing_[g] = t;
        break;
      }
    }
  }
}

const SensorImage& HeadSensor::capture() {
  map_geoms();
  const mjModel* m = skills_.model();
  const mjData* d = skills_.sim_data();
  const int cam = skills_.scene().head_camera();
  const double* xmat = d->cam_xmat + 9 * cam;  // row-major; columns are the camera axes
  const Eigen::Vector3d x(xmat[0], xmat[3], xmat[6]), y(xmat[1], xmat[4], xmat[7]),
      z(xmat[2], xmat[5], xmat[8]);
  origin_ =
      Eigen::Vector3d(d->cam_xpos[3 * cam], d->cam_xpos[3 * cam + 1], d->cam_xpos[3 * cam + 2]);
  const double tan_half = std::tan(m->cam_fovy[cam] * M_PI / 360.0);
  const double aspect = static_cast<double>(options_.width) / options_.height;
  // The robot's own geoms the camera sits inside (a housing of the body the head hangs from):
  // a camera cannot see them, so rays pass through them.
  enclosing_.clear();
  for (int g = 0; g < m->ngeom; ++g) {
    if (m->geom_bodyid[g] != m->cam_bodyid[cam] && m->geom_group[g] <= 2 &&
        skills_.scene().is_robot_geom(g) && point_inside_geom(m, d, g, origin_.data())) {
      enclosing_.push_back(g);
    }
  }
  for (int r = 0; r < options_.height; ++r) {
    for (int c = 0; c < options_.width; ++c) {
      const size_t i = static_cast<size_t>(r) * options_.width + c;
      const double u = (2.0 * (c + 0.5) / options_.width - 1.0) * tan_half * aspect;
      const double v = (1.0 - 2.0 * (r + 0.5) / options_.height) * tan_half;
      const Eigen::Vector3d dir = (u * x + v * y - z).normalized();
      rays_[i] = dir;
      int geom = -1;
      const double dist = ray(origin_, dir, &geom);
      if (geom < 0 || dist < 0 || dist > options_.range_m) {
        image_.depth_m[i] = 0.0f;
        image_.thing[i] = -1;
        distance_[i] = -1;
        continue;
      }
      distance_[i] = dist;
      image_.depth_m[i] = static_cast<float>(dist * dir.dot(-z));
      image_.thing[i] = geom_thing_[geom];
    }
  }
  return image_;
}

double HeadSensor::ray(const Eigen::Vector3d& from, const Eigen::Vector3d& dir, int* geom) const {
  const mjModel* m = skills_.model();
  const mjData* d = skills_.sim_data();
  // Groups 0-2: what the renderer shows by default (unused obstacle slots are in group 3).
  const mjtByte groups[mjNGROUP] = {1, 1, 1, 0, 0, 0};
  const int head_body = m->cam_bodyid[skills_.scene().head_camera()];
  const Eigen::Vector3d unit = dir.normalized();
  const double scale = dir.norm();  // mj_ray measures in multiples of |dir|
  double travelled = 0;             // metres, past enclosing geoms
  for (size_t k = 0;; ++k) {
    const Eigen::Vector3d start = from + travelled * unit;
    const double dist = mj_ray(m, d, start.data(), dir.data(), groups, 1, head_body, geom);
    if (*geom < 0 || dist < 0) return dist;
    if (k == enclosing_.size() ||
        std::find(enclosing_.begin(), enclosing_.end(), *geom) == enclosing_.end()) {
      return dist + travelled / scale;
    }
    travelled += dist * scale + 1e-6;  // out of the enclosing geom, on
  }
}

std::vector<Recognition> HeadSensor::recognise() const {
  std::vector<int> pixels(things_.size(), 0);
  for (int t : image_.thing) {
    if (t >= 0) ++pixels[t];
  }
  std::vector<Recognition> out;
  for (size_t t = 0; t < things_.size(); ++t) {
    if (pixels[t] < options_.min_pixels) continue;
    Recognition rec;
    rec.thing = static_cast<int>(t);
    rec.pixels = pixels[t];
    std::optional<core::PerceivedObject> o = perceive(skills_, things_[t], 0.0);
    if (!o) continue;
    const Eigen::AlignedBox3d& box = o->box;
    for (const Eigen::Vector3d& dir : rays_) {
      const double entry = ray_box_entry(origin_, dir, box);
      if (entry >= 0 && entry <= options_.range_m) ++rec.in_box;
    }
    rec.in_box = std::max(rec.in_box, rec.pixels);  // surfaces: legs hit outside the top's box
    rec.object = std::move(*o);
    out.push_back(std::move(rec));
  }
  return out;
}

SensorPerception::SensorPerception(MujocoSkillset& skills, HeadSensorOptions options)
    : skills_(skills), sensor_(skills, options) {
  skills_.set_obstacles_need_perception(true);
}

void SensorPerception::update(double time, core::PerceptualModel& model) {
  sensor_.capture();
  std::vector<Recognition> seen = sensor_.recognise();
  // An object the model places in plain view that the sensor did not recognise is gone (a
  // vacuumed flake, a moved object): forgotten. "In plain view": its box centre is inside
  // the field of view and range, and the centre's ray reaches the box unblocked.
  std::vector<std::string> gone;
  const Eigen::Vector3d eye = skills_.frame_pose(skills_.head_camera().frame).position;
  for (const auto& [id, o] : model.objects()) {
    if (std::any_of(seen.begin(), seen.end(),
                    [&](const Recognition& r) { return sensor_.things()[r.thing].id == id; })) {
      continue;
    }
    const Eigen::Vector3d centre = o.box.center();
    if (!core::in_camera_view(skills_, centre)) continue;
    const Eigen::Vector3d to = centre - eye;
    int geom = -1;
    const double hit = sensor_.ray(eye, to, &geom);  // as the sensor's rays
    const double entry = ray_box_entry(eye, to.normalized(), o.box) / to.norm();
    if (hit < 0 || hit >= entry - 1e-6) gone.push_back(id);
  }
  for (const std::string& id : gone) model.forget(id);
  for (Recognition& rec : seen) {
    const SceneThing& thing = sensor_.things()[rec.thing];
    rec.object.last_seen = time;
    rec.object.confidence = rec.confidence();
    if (thing.obstacle_slot >= 0) skills_.mark_obstacle_perceived(thing.obstacle_slot);
    model.observe(std::move(rec.object));
  }
}

}  // namespace taskmatrix::mujoco
