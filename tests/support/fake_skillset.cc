#include "tests/support/fake_skillset.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace taskmatrix::test {

namespace {

using Eigen::Vector3d;

// Chains in joint order: name, joints, lower, upper.
struct ChainDef {
  const char* name;
  std::vector<std::string> joints;
  std::vector<double> lower, upper;
  const char* end_effector;
};

std::vector<ChainDef> chain_defs() {
  return {
      {"base", {"base_x", "base_y", "base_yaw"}, {-5, -5, -M_PI}, {5, 5, M_PI}, ""},
      {"torso", {"torso_lift"}, {0}, {0.3}, ""},
      {"head", {"head_pan", "head_tilt"}, {-1.5, -1.0}, {1.5, 1.0}, "head_camera"},
      {"left_arm", {"left_j1", "left_j2", "left_j3"}, {-2.5, -2.5, -2}, {2.5, 2.5, 2}, "left_palm"},
      {"right_arm",
       {"right_j1", "right_j2", "right_j3"},
       {-2.5, -2.5, -2},
       {2.5, 2.5, 2},
       "right_palm"},
      {"left_hand", {"left_finger"}, {0}, {1.5}, ""},
      {"right_hand", {"right_finger"}, {0}, {1.5}, ""},
  };
}

Eigen::Matrix3d rot_z(double a) {
  return Eigen::AngleAxisd(a, Vector3d::UnitZ()).toRotationMatrix();
}
Eigen::Matrix3d rot_y(double a) {
  return Eigen::AngleAxisd(a, Vector3d::UnitY()).toRotationMatrix();
}

double wrap(double a) { return std::remainder(a, 2 * M_PI); }

// The yaw of a rotation's x axis, and whether the rotation is a turn about the vertical.
double yaw_of(const Eigen::Quaterniond& q, bool* vertical_turn) {
  const Vector3d x = q.normalized() * Vector3d::UnitX();
  if (vertical_turn)
    *vertical_turn = std::abs(x.z()) < 1e-6 && (q.normalized() * Vector3d::UnitZ()).z() > 1 - 1e-9;
  return std::atan2(x.y(), x.x());
}

}  // namespace

FakeSkillset::FakeSkillset(std::vector<FakeBox> world) : world_(std::move(world)) {
  profile_.name = "fake_humanoid";
  profile_.height_m = 1.6;
  for (const ChainDef& c : chain_defs()) {
    core::ChainInfo info;
    info.name = c.name;
    info.joints = c.joints;
    info.lower = c.lower;
    info.upper = c.upper;
    info.speed = {1.0, 2.0};
    info.end_effector = c.end_effector;
    chains_.push_back(info);
    profile_.chains.push_back({c.name, c.joints, c.end_effector});
    profile_.speed_limits[c.name] = info.speed;
  }
  profile_.head_camera.name = "head_camera";
  for (const char* side : {"left", "right"}) {
    core::HandSpec hand;
    hand.side = side;
    hand.palm = std::string(side) + "_palm";
    hand.approach = {1, 0, 0};
    hand.closing = {0, 1, 0};
    profile_.hands.push_back(hand);
  }
  profile_.postures["rest"] = {{"base", {0, 0, 0}},
                               {"torso", {0}},
                               {"head", {0, 0}},
                               {"left_arm", {1.5, 0, 0}},
                               {"right_arm", {-1.5, 0, 0}},
                               {"left_hand", {0}},
                               {"right_hand", {0}}};
  profile_.postures["fist"] = {{"left_hand", {1.2}}, {"right_hand", {1.2}}};
  profile_.postures["wave_start"] = {{"right_arm", {-0.5, -1.0, 0.5}}};
  for (const core::ChainInfo& c : chains_) {
    const std::vector<double>& rest = profile_.postures["rest"].at(c.name);
    q_.insert(q_.end(), rest.begin(), rest.end());
  }
  target_ = q_;
}

size_t FakeSkillset::offset_of(const std::string& chain) const {
  size_t k = 0;
  for (const core::ChainInfo& c : chains_) {
    if (c.name == chain) return k;
    k += c.joints.size();
  }
  throw std::invalid_argument("no chain '" + chain + "'");
}

std::vector<double> FakeSkillset::with(const std::vector<std::string>& chain_names,
                                       const std::vector<double>& values) const {
  std::vector<double> q = q_;
  size_t i = 0;
  for (const std::string& name : chain_names) {
    const size_t at = offset_of(name);
    for (size_t k = 0; k < chain(name).joints.size(); ++k) q[at + k] = values[i++];
  }
  return q;
}

std::vector<double> FakeSkillset::do_configuration(
    const std::vector<std::string>& chain_names) const {
  std::vector<double> out;
  for (const std::string& name : chain_names) {
    const size_t at = offset_of(name);
    out.insert(out.end(), q_.begin() + static_cast<long>(at),
               q_.begin() + static_cast<long>(at + chain(name).joints.size()));
  }
  return out;
}

std::optional<core::Pose> FakeSkillset::robot_frame(const std::vector<double>& q,
                                                    const std::string& frame) const {
  const Vector3d base(q[0], q[1], 0);
  const double yaw = q[2], lift = q[3];
  core::Pose pose;
  if (frame == "head_camera") {
    pose.position = base + rot_z(yaw) * Vector3d(0.05, 0, kShoulderHeight + lift + 0.4);
    Eigen::Matrix3d r0;  // camera axes in a frame facing +x: looks along -z, +y up
    r0.col(0) = Vector3d(0, -1, 0);
    r0.col(1) = Vector3d(0, 0, 1);
    r0.col(2) = Vector3d(-1, 0, 0);
    pose.orientation = Eigen::Quaterniond(rot_z(yaw + q[4]) * rot_y(q[5]) * r0);
    return pose;
  }
  for (const char* side : {"left", "right"}) {
    if (frame != std::string(side) + "_palm") continue;
    const std::vector<Vector3d> points = arm_spheres(q, side);
    const size_t at = offset_of(std::string(side) + "_arm");
    pose.position = points.back();
    pose.orientation = Eigen::Quaterniond(rot_z(yaw + q[at] + q[at + 1] + q[at + 2]));
    return pose;
  }
  return std::nullopt;
}

std::vector<Vector3d> FakeSkillset::arm_spheres(const std::vector<double>& q,
                                                const std::string& side) const {
  const double yaw = q[2];
  const double y = side == "left" ? 0.2 : -0.2;
  Vector3d at = Vector3d(q[0], q[1], 0) + rot_z(yaw) * Vector3d(0, y, kShoulderHeight + q[3]);
  const size_t a = offset_of(side + "_arm");
  std::vector<Vector3d> points{at};
  double heading = yaw;
  for (size_t link = 0; link < kLinks.size(); ++link) {
    heading += q[a + link];
    const Vector3d dir(std::cos(heading), std::sin(heading), 0);
    const int steps = std::max(1, static_cast<int>(std::ceil(kLinks[link] / 0.05)));
    for (int s = 1; s <= steps; ++s) points.push_back(at + dir * (kLinks[link] * s / steps));
    at += dir * kLinks[link];
  }
  return points;  // the last is the palm
}

const FakeBox* FakeSkillset::find_box(const std::string& name) const {
  for (const FakeBox& b : world_) {
    if (b.name == name) return &b;
  }
  return nullptr;
}

std::vector<FakeBox> FakeSkillset::held_boxes(const std::vector<double>& q) const {
  std::vector<FakeBox> out;
  for (const Held& h : held_) {
    const core::Pose palm = *robot_frame(q, h.side + "_palm");
    FakeBox box = *find_box(h.object);
    const Vector3d half = box.box.sizes() / 2;
    const Vector3d centre = palm.position + palm.orientation * h.offset;
    box.box = Eigen::AlignedBox3d(centre - half, centre + half);
    out.push_back(box);
  }
  return out;
}

core::Pose FakeSkillset::do_frame_pose(const std::string& frame) const {
  if (std::optional<core::Pose> p = robot_frame(q_, frame)) return *p;
  if (frame == "world") return core::Pose{};
  for (const FakeBox& b : held_boxes(q_)) {
    if (b.name == frame) return core::Pose{b.box.center(), Eigen::Quaterniond::Identity()};
  }
  if (const FakeBox* b = find_box(frame)) {
    return core::Pose{b->box.center(), Eigen::Quaterniond::Identity()};
  }
  throw std::invalid_argument("no frame or object '" + frame + "' in robot " + profile_.name);
}

core::Pose FakeSkillset::do_frame_pose_at(const std::vector<std::string>& chain_names,
                                          const std::vector<double>& values,
                                          const std::string& frame) {
  if (std::optional<core::Pose> p = robot_frame(with(chain_names, values), frame)) return *p;
  return do_frame_pose(frame);
}

std::vector<core::Collision> FakeSkillset::collisions_at(
    const std::vector<double>& q, const std::vector<std::string>& chain_names,
    const std::vector<std::string>& may_touch) const {
  auto moves = [&](const std::string& side) {
    if (chain_names.empty()) return true;
    for (const std::string& c : chain_names) {
      if (c == "base" || c == "torso" || c == side + "_arm") return true;
    }
    return false;
  };
  auto ignored = [&](const std::string& name) {
    return std::find(may_touch.begin(), may_touch.end(), name) != may_touch.end() ||
           std::any_of(held_.begin(), held_.end(), [&](const Held& h) { return h.object == name; });
  };
  std::vector<core::Collision> out;
  const std::vector<FakeBox> held = held_boxes(q);
  for (const char* side : {"left", "right"}) {
    if (!moves(side)) continue;
    for (const Vector3d& p : arm_spheres(q, side)) {
      for (const FakeBox& b : world_) {
        if (ignored(b.name)) continue;
        const double d = b.box.exteriorDistance(p);
        if (d < kLinkRadius) out.push_back({std::string(side) + "_arm", b.name, kLinkRadius - d});
      }
    }
  }
  for (size_t k = 0; k < held_.size(); ++k) {
    if (!moves(held_[k].side)) continue;
    for (const FakeBox& b : world_) {
      if (ignored(b.name) || std::find(held_[k].supports.begin(), held_[k].supports.end(),
                                       b.name) != held_[k].supports.end()) {
        continue;
      }
      const Eigen::AlignedBox3d overlap = held[k].box.intersection(b.box);
      if (!overlap.isEmpty()) {
        out.push_back({held_[k].object, b.name, overlap.sizes().minCoeff()});
      }
    }
  }
  return out;
}

double FakeSkillset::distance_at(const std::vector<double>& q) const {
  double best = std::numeric_limits<double>::infinity();
  const std::vector<FakeBox> held = held_boxes(q);
  for (const char* side : {"left", "right"}) {
    for (const Vector3d& p : arm_spheres(q, side)) {
      for (const FakeBox& b : world_) {
        if (std::any_of(held_.begin(), held_.end(),
                        [&](const Held& h) { return h.object == b.name; })) {
          continue;
        }
        best = std::min(best, b.box.exteriorDistance(p) - kLinkRadius);
      }
    }
  }
  return best;
}

bool FakeSkillset::do_is_valid(const std::vector<std::string>& chain_names,
                               const std::vector<double>& values,
                               const std::vector<std::string>& may_touch) {
  return collisions_at(with(chain_names, values), {}, may_touch).empty();
}

double FakeSkillset::do_clearance(const std::vector<std::string>& chain_names,
                                  const std::vector<double>& values, double max_distance_m) {
  return std::min(max_distance_m, distance_at(with(chain_names, values)));
}

core::IkResult FakeSkillset::do_solve_ik(const std::vector<std::string>& chain_names,
                                         const std::string& frame, const core::Pose& target,
                                         const core::IkOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  core::IkResult result;
  if (chain_names.size() != 1 || (chain_names[0] != "left_arm" && chain_names[0] != "right_arm") ||
      frame != chain(chain_names[0]).end_effector) {
    result.reason = "the fake solves IK for one arm chain and its palm";
    return result;
  }
  const std::string side = chain_names[0] == "left_arm" ? "left" : "right";
  const core::ChainInfo& arm = chain(chain_names[0]);
  const size_t at = offset_of(chain_names[0]);
  const double yaw = q_[2];
  const Vector3d shoulder =
      Vector3d(q_[0], q_[1], 0) +
      rot_z(yaw) * Vector3d(0, side == "left" ? 0.2 : -0.2, kShoulderHeight + q_[3]);
  const Vector3d d = rot_z(-yaw) * (target.position - shoulder);
  bool vertical_turn = true;
  const double target_yaw = yaw_of(target.orientation, &vertical_turn) - yaw;
  std::vector<double> headings;
  if (options.orientation) {
    headings.push_back(target_yaw);
  } else {
    for (int k = 0; k < 16; ++k)
      headings.push_back(wrap(q_[at] + q_[at + 1] + q_[at + 2] + k * M_PI / 8));
  }
  const double l1 = kLinks[0], l2 = kLinks[1], l3 = kLinks[2];
  result.status = core::IkStatus::kUnreachable;
  result.position_error_m = std::numeric_limits<double>::infinity();
  bool any_within_limits = false;
  for (double psi : headings) {
    const Eigen::Vector2d w = d.head<2>() - l3 * Eigen::Vector2d(std::cos(psi), std::sin(psi));
    const double r = w.norm();
    const double miss = std::max({0.0, r - (l1 + l2), std::abs(l1 - l2) - r}) + std::abs(d.z());
    result.position_error_m = std::min(result.position_error_m, miss);
    ++result.iterations;
    if (miss > options.position_tolerance_m) continue;
    if (options.orientation && !vertical_turn) continue;
    const double c2 = std::clamp((r * r - l1 * l1 - l2 * l2) / (2 * l1 * l2), -1.0, 1.0);
    for (double sign : {1.0, -1.0}) {
      const double t2 = sign * std::acos(c2);
      const double t1 =
          wrap(std::atan2(w.y(), w.x()) - std::atan2(l2 * std::sin(t2), l1 + l2 * std::cos(t2)));
      const double t3 = wrap(psi - t1 - t2);
      const std::vector<double> sol{t1, t2, t3};
      bool inside = true;
      for (size_t i = 0; i < 3; ++i)
        inside = inside && sol[i] >= arm.lower[i] && sol[i] <= arm.upper[i];
      if (!inside) continue;
      any_within_limits = true;
      if (options.collision_free && !do_is_valid(chain_names, sol, {})) continue;
      const bool distinct = std::all_of(result.solutions.begin(), result.solutions.end(),
                                        [&](const std::vector<double>& s) {
                                          double far = 0;
                                          for (size_t i = 0; i < 3; ++i)
                                            far = std::max(far, std::abs(s[i] - sol[i]));
                                          return far > options.distinct_rad;
                                        });
      if (distinct && static_cast<int>(result.solutions.size()) < options.max_solutions) {
        result.solutions.push_back(sol);
      }
    }
  }
  if (!result.solutions.empty()) {
    result.status = core::IkStatus::kSolved;
    result.position_error_m = 0;
  } else if (any_within_limits) {
    result.status = core::IkStatus::kInCollision;
    result.reason = "every solution is in collision";
  } else {
    result.reason = options.orientation && !vertical_turn ? "the palm only turns about the vertical"
                                                          : "out of the arm's reach or limits";
  }
  result.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return result;
}

std::string FakeSkillset::do_plan_options_error(const core::PlanOptions& options) const {
  for (const std::string& name : options.may_touch) {
    if (!find_box(name)) return "may_touch: no object '" + name + "' in the fake world";
  }
  if (!(options.motion_resolution > 0 && options.motion_resolution < 1)) {
    return "motion resolution must be in (0, 1)";
  }
  return "";
}

core::PlanResult FakeSkillset::do_plan(const std::vector<std::string>& chain_names,
                                       const std::vector<std::vector<double>>& goals,
                                       const core::PlanOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  core::PlanResult result;
  result.plan_calls = 1;
  const std::vector<double> start = clamped_configuration(chain_names);
  double extent = 0;
  for (const std::string& name : chain_names) {
    const core::ChainInfo& c = chain(name);
    for (size_t i = 0; i < c.joints.size(); ++i) extent = std::max(extent, c.upper[i] - c.lower[i]);
  }
  auto free = [&](const std::vector<double>& q) {
    ++result.collision_checks;
    return collisions_at(with(chain_names, q), chain_names, options.may_touch).empty();
  };
  if (!free(start)) {
    result.status = core::PlanStatus::kInvalidStart;
    result.message = "the start is in collision";
    return result;
  }
  result.status = core::PlanStatus::kInvalidGoal;
  result.message = "every goal is in collision";
  for (size_t g = 0; g < goals.size(); ++g) {
    ++result.planner_iterations;
    if (!free(goals[g])) continue;
    double longest = 0;
    for (size_t i = 0; i < start.size(); ++i)
      longest = std::max(longest, std::abs(goals[g][i] - start[i]));
    const int steps =
        std::max(1, static_cast<int>(std::ceil(longest / (options.motion_resolution * extent))));
    bool clear = true;
    for (int s = 1; s < steps && clear; ++s) {
      std::vector<double> q = start;
      for (size_t i = 0; i < q.size(); ++i) q[i] += (goals[g][i] - start[i]) * s / steps;
      clear = free(q);
    }
    if (clear) {
      result.status = core::PlanStatus::kExactSolution;
      result.message.clear();
      result.path = {start, goals[g]};
      result.goal_index = static_cast<int>(g);
      break;
    }
    result.status = core::PlanStatus::kTimeout;
    result.message = "no straight line to a goal is free";
  }
  result.planning_time_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return result;
}

void FakeSkillset::do_command(const std::vector<std::string>& chain_names,
                              const std::vector<double>& positions, const std::vector<double>&,
                              const std::vector<double>&) {
  size_t i = 0;
  for (const std::string& name : chain_names) {
    const size_t at = offset_of(name);
    for (size_t k = 0; k < chain(name).joints.size(); ++k) target_[at + k] = positions[i++];
  }
}

core::StepReport FakeSkillset::do_advance() {
  q_ = target_;
  time_ += kControlPeriod;
  return {};
}

std::vector<core::Collision> FakeSkillset::do_collisions(
    const std::vector<std::string>& chain_names) const {
  return collisions_at(q_, chain_names, {});
}

// The fake's palm is a frame at the arm's tip: nothing of it lies behind the frame.
double FakeSkillset::do_palm_depth(const core::HandSpec&) const { return 0; }

core::CameraInfo FakeSkillset::do_head_camera() const {
  core::CameraInfo info;
  info.frame = "head_camera";
  info.fovy_rad = 1.0;
  info.aspect = 4.0 / 3;
  info.range_m = 4.0;
  return info;
}

core::DepthScan FakeSkillset::do_scan_depth() {
  const core::CameraInfo cam = do_head_camera();
  const core::Pose pose = do_frame_pose(cam.frame);
  core::DepthScan scan;
  scan.origin = pose.position;
  std::vector<FakeBox> boxes = world_;
  for (const FakeBox& h : held_boxes(q_)) {
    for (FakeBox& b : boxes) {
      if (b.name == h.name) b = h;
    }
  }
  const int cols = 16, rows = 12;
  const double half_h = std::tan(cam.fovy_rad / 2), half_w = half_h * cam.aspect;
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      ++scan.rays;
      const Vector3d dir = (pose.orientation * Vector3d(half_w * (2.0 * (c + 0.5) / cols - 1),
                                                        half_h * (1 - 2.0 * (r + 0.5) / rows), -1))
                               .normalized();
      double nearest = cam.range_m;
      for (const FakeBox& b : boxes) {  // slab test
        double lo = 0, hi = nearest;
        for (int k = 0; k < 3 && lo <= hi; ++k) {
          if (std::abs(dir[k]) < 1e-12) {
            if (scan.origin[k] < b.box.min()[k] || scan.origin[k] > b.box.max()[k]) hi = -1;
            continue;
          }
          double t1 = (b.box.min()[k] - scan.origin[k]) / dir[k];
          double t2 = (b.box.max()[k] - scan.origin[k]) / dir[k];
          if (t1 > t2) std::swap(t1, t2);
          lo = std::max(lo, t1);
          hi = std::min(hi, t2);
        }
        if (lo <= hi) nearest = lo;
      }
      if (nearest < cam.range_m) scan.hits.push_back(scan.origin + dir * nearest);
    }
  }
  return scan;
}

void FakeSkillset::do_attach(const std::string& object, const std::string& side) {
  const FakeBox* box = find_box(object);
  if (!box || (box->type != "graspable" && box->type != "tool")) {
    throw std::invalid_argument("'" + object + "' is not a graspable object or tool");
  }
  const core::Pose palm = *robot_frame(q_, side + "_palm");
  Held h{object, side, palm.orientation.inverse() * (box->box.center() - palm.position), {}};
  const Eigen::AlignedBox3d grown(box->box.min() - Vector3d::Constant(0.005),
                                  box->box.max() + Vector3d::Constant(0.005));
  for (const FakeBox& b : world_) {
    if (b.name != object && !grown.intersection(b.box).isEmpty()) h.supports.push_back(b.name);
  }
  held_.push_back(std::move(h));
}

void FakeSkillset::do_detach(const std::string& object) {
  const std::vector<FakeBox> placed = held_boxes(q_);
  for (size_t k = 0; k < held_.size(); ++k) {
    if (held_[k].object != object) continue;
    for (FakeBox& b : world_) {
      if (b.name == object) b.box = placed[k].box;  // left where the hand has it
    }
    held_.erase(held_.begin() + static_cast<long>(k));
    return;
  }
}

std::vector<std::string> FakeSkillset::do_attached_objects() const {
  std::vector<std::string> out;
  for (const Held& h : held_) out.push_back(h.object);
  return out;
}

std::string FakeSkillset::do_holder_of(const std::string& object) const {
  for (const Held& h : held_) {
    if (h.object == object) return h.side;
  }
  return "";
}

std::vector<std::string> FakeSkillset::do_touching(const std::string& part) const {
  std::vector<FakeBox> boxes = world_;
  for (const FakeBox& h : held_boxes(q_)) {
    for (FakeBox& b : boxes) {
      if (b.name == h.name) b = h;
    }
  }
  const auto self =
      std::find_if(boxes.begin(), boxes.end(), [&](const FakeBox& b) { return b.name == part; });
  if (self == boxes.end()) throw std::invalid_argument("no body or object '" + part + "'");
  const Eigen::AlignedBox3d grown(self->box.min() - Vector3d::Constant(0.001),
                                  self->box.max() + Vector3d::Constant(0.001));
  std::vector<std::string> out;
  for (const FakeBox& b : boxes) {
    if (b.name != part && !grown.intersection(b.box).isEmpty()) out.push_back(b.name);
  }
  for (const char* side : {"left", "right"}) {
    for (const Vector3d& p : arm_spheres(q_, side)) {
      if (grown.exteriorDistance(p) < kLinkRadius) {
        out.push_back(std::string(side) + "_arm");
        break;
      }
    }
  }
  return out;
}

void FakeSkillset::place(const std::vector<std::string>& chain_names,
                         const std::vector<double>& values) {
  q_ = with(chain_names, values);
  target_ = q_;
}

int FakeSkillset::do_state_size() const { return static_cast<int>(q_.size()); }

void FakeSkillset::do_append_state(std::vector<float>& frames) const {
  for (double q : q_) frames.push_back(static_cast<float>(q));
}

void FakeSkillset::perceive(core::PerceptualModel& model) const {
  std::vector<FakeBox> boxes = world_;
  for (const FakeBox& h : held_boxes(q_)) {
    for (FakeBox& b : boxes) {
      if (b.name == h.name) b = h;
    }
  }
  for (const FakeBox& b : boxes) {
    core::PerceivedObject o;
    o.id = b.name;
    o.type = b.type;
    o.pose.position = b.box.center();
    o.box = b.box;
    o.last_seen = time_;
    o.confidence = 1;
    model.observe(std::move(o));
  }
}

}  // namespace taskmatrix::test

namespace taskmatrix::test {

std::vector<FakeBox> fake_kitchen() {
  using Eigen::Vector3d;
  return {
      {"work_surface", "surface",
       Eigen::AlignedBox3d(Vector3d(0.35, -0.4, 0), Vector3d(0.9, 0.6, 0.9))},
      {"cup", "graspable",
       Eigen::AlignedBox3d(Vector3d(0.45, 0.3, 0.9), Vector3d(0.51, 0.36, 1.1))},
      {"shelf", "surface", Eigen::AlignedBox3d(Vector3d(-0.4, -1.2, 0), Vector3d(0.4, -0.9, 1.4))},
  };
}

}  // namespace taskmatrix::test
