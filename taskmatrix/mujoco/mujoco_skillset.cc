#include "taskmatrix/mujoco/mujoco_skillset.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "taskmatrix/core/joint_limits.h"
#include "taskmatrix/mujoco/body_kinematics.h"
#include "taskmatrix/mujoco/head_sensor.h"
#include "taskmatrix/mujoco/kinematics.h"
#include "taskmatrix/mujoco/motion_planner.h"

namespace taskmatrix::mujoco {

namespace {

std::string body_name(const mjModel* m, int body) {
  const char* name = mj_id2name(m, mjOBJ_BODY, body);
  return name ? name : "body " + std::to_string(body);
}

// The geoms that are not the robot's and touch object `body` (a root body) in `d`'s contacts.
std::vector<int> supports_of(const mjModel* m, const mjData* d, const Scene& scene, int body) {
  std::vector<int> out;
  for (int i = 0; i < d->ncon; ++i) {
    const mjContact& c = d->contact[i];
    const int r1 = m->body_rootid[m->geom_bodyid[c.geom1]];
    const int r2 = m->body_rootid[m->geom_bodyid[c.geom2]];
    const int other = r1 == body ? c.geom2 : (r2 == body ? c.geom1 : -1);
    if (other >= 0 && !scene.is_robot_geom(other) &&
        std::find(out.begin(), out.end(), other) == out.end()) {
      out.push_back(other);
    }
  }
  return out;
}

core::PlanResult plan_failure(core::PlanStatus status, std::string message) {
  core::PlanResult r;
  r.status = status;
  r.message = std::move(message);
  return r;
}

}  // namespace

const char* to_string(ExecutionMode mode) {
  return mode == ExecutionMode::kKinematic ? "kinematic" : "physics";
}

MujocoSkillset::MujocoSkillset(std::shared_ptr<const Scene> scene, SimulationOptions options)
    : scene_(std::move(scene)),
      worker_(scene_),
      execution_(options.execution),
      pruning_(*scene_, worker_.model(), options.pruning) {
  const mjModel* m = worker_.model();
  if (!(std::isfinite(options.control_rate_hz) && options.control_rate_hz > 0)) {
    throw std::invalid_argument("control rate must be a positive number of Hz");
  }
  substeps_ =
      std::max(1, static_cast<int>(std::lround(1.0 / (options.control_rate_hz * m->opt.timestep))));
  period_ = substeps_ * m->opt.timestep;
  query_ = make_data(m);
  joint_state_.assign(m->njnt, JointState{-1, -1, -1, -1});
  const core::RobotProfile& robot = scene_->robot();
  for (const ChainIndex& c : scene_->chains()) {
    core::ChainInfo info;
    info.name = c.name;
    info.lower = c.lower;
    info.upper = c.upper;
    info.speed = robot.speed_limits.at(c.name);
    if (const core::ChainSpec* spec = robot.find_chain(c.name)) {
      info.joints = spec->joints;
      info.end_effector = spec->end_effector;
    }
    for (int j : c.joints) {
      JointState js{j, m->jnt_qposadr[j], m->jnt_dofadr[j], -1};
      for (int a = 0; a < m->nu; ++a) {
        if (m->actuator_trntype[a] == mjTRN_JOINT && m->actuator_trnid[2 * a] == j) js.actuator = a;
      }
      joint_state_[j] = js;  // Scene::load checked that every chain joint has an actuator
    }
    chains_.push_back(std::move(info));
  }
  target_pos_.assign(m->njnt, 0.0);
  target_vel_.assign(m->njnt, 0.0);
  target_acc_.assign(m->njnt, 0.0);
  acc_full_.assign(m->nv, 0.0);
  mass_times_acc_.assign(m->nv, 0.0);
  if (!(std::isfinite(options.clearance_rate_hz) && options.clearance_rate_hz >= 0) ||
      !(std::isfinite(options.clearance_cap_m) && options.clearance_cap_m > 0)) {
    throw std::invalid_argument("clearance rate must be >= 0 Hz and its cap > 0 m");
  }
  if (options.clearance_rate_hz > 0) {
    clearance_every_ =
        std::max(1, static_cast<int>(std::lround(1.0 / (options.clearance_rate_hz * period_))));
  }
  clearance_cap_m_ = options.clearance_cap_m;
  for (const core::ChainInfo& chain : chains_) {
    if (chain.end_effector.empty()) continue;
    const FrameRef f = scene_->frame(chain.end_effector);
    if (f.kind == FrameRef::Kind::kSite) ee_sites_.push_back(f.id);
    if (f.kind == FrameRef::Kind::kBody) ee_bodies_.push_back(f.id);
  }
  for (const core::HandSpec& hand : robot.hands) {
    const std::string hand_chain = hand.side + "_hand";
    const core::ChainSpec* chain = robot.find_chain(hand_chain);
    const auto fist = robot.postures.at("fist").find(hand_chain);
    for (const core::FingerSpec& f : hand.fingers) {
      Finger finger;
      std::vector<char> moved(m->nbody, 0);
      for (const std::string& j : f.joints) {
        const int id = mj_name2id(m, mjOBJ_JOINT, j.c_str());
        if (id < 0 || !chain || fist == robot.postures.at("fist").end()) continue;
        const auto at = std::find(chain->joints.begin(), chain->joints.end(), j);
        if (at == chain->joints.end()) continue;
        finger.qpos_adr.push_back(m->jnt_qposadr[id]);
        finger.fist.push_back(fist->second.at(static_cast<size_t>(at - chain->joints.begin())));
        finger.segments.push_back(m->jnt_bodyid[id]);
        moved[m->jnt_bodyid[id]] = 1;
      }
      for (int b = 1; b < m->nbody; ++b) {
        if (moved[m->body_parentid[b]]) moved[b] = 1;
        if (moved[b]) finger.bodies.push_back(b);
      }
      for (int g = 0; g < m->ngeom; ++g) {
        if (moved[m->geom_bodyid[g]]) finger.geoms.push_back(g);
      }
      for (const GeomPair& p : scene_->robot_geom_pairs()) {
        if (moved[m->geom_bodyid[p.g1]] || moved[m->geom_bodyid[p.g2]]) finger.pairs.push_back(p);
      }
      if (!finger.qpos_adr.empty()) fingers_.push_back(std::move(finger));
    }
  }
  for (const auto& [name, spec] : scene_->environment().objects) {
    for (const std::string& b : spec.bodies) {
      const int body = mj_name2id(m, mjOBJ_BODY, b.c_str());
      if (spec.kind == core::ObjectKind::kDebris) {
        debris_.push_back({body, Eigen::Vector3d(m->body_pos[3 * body], m->body_pos[3 * body + 1],
                                                 m->body_pos[3 * body + 2])});
      }
      if (spec.kind == core::ObjectKind::kTool && !spec.tip_site.empty()) {
        tool_tips_.push_back(body);
        tool_tips_.push_back(mj_name2id(m, mjOBJ_SITE, spec.tip_site.c_str()));
      }
    }
  }
  reset();
}

MujocoSkillset::~MujocoSkillset() = default;

void MujocoSkillset::set_visitor_walk(double speed_mps) {
  if (!(std::isfinite(speed_mps) && speed_mps >= 0)) {
    throw std::invalid_argument("visitor walking speed must be a non-negative number of m/s");
  }
  const mjModel* m = worker_.model();
  const core::VisitorSpec& v = scene_->environment().visitor;
  const std::string where = "environment " + scene_->environment().name + ": the visitor ";
  if (v.path.size() < 2) throw std::invalid_argument(where + "needs a path of two or more points");
  const int body = mj_name2id(m, mjOBJ_BODY, v.body.c_str());
  const int types[3] = {mjJNT_SLIDE, mjJNT_SLIDE, mjJNT_HINGE};
  if (body < 0 || m->body_jntnum[body] != 3) {
    throw std::invalid_argument(where + "body must have three joints (slide x, slide y, hinge z)");
  }
  for (int k = 0; k < 3; ++k) {
    const int j = m->body_jntadr[body] + k;
    if (m->jnt_type[j] != types[k] || m->jnt_axis[3 * j + (k == 1 ? 1 : k == 0 ? 0 : 2)] < 0.99) {
      throw std::invalid_argument(where +
                                  "body must have three joints (slide x, slide y, hinge z)");
    }
    visitor_qpos_[k] = m->jnt_qposadr[j];
    visitor_dof_[k] = m->jnt_dofadr[j];
  }
  visitor_arc_ = {0.0};
  for (size_t i = 1; i < v.path.size(); ++i) {
    visitor_arc_.push_back(visitor_arc_.back() + std::hypot(v.path[i][0] - v.path[i - 1][0],
                                                            v.path[i][1] - v.path[i - 1][1]));
  }
  visitor_speed_ = speed_mps;
}

void MujocoSkillset::drive_visitor(mjData* d, double time) const {
  if (visitor_speed_ <= 0) return;
  const auto& path = scene_->environment().visitor.path;
  const std::vector<double>& at = visitor_arc_;  // arc length at each waypoint
  const double length = at.back();
  if (length <= 0) return;
  double s = std::fmod(visitor_speed_ * time, 2 * length);
  const bool back = s > length;
  if (back) s = 2 * length - s;
  size_t i = 1;
  while (i + 1 < at.size() && at[i] < s) ++i;
  const double seg = at[i] - at[i - 1];
  const double f = seg > 0 ? (s - at[i - 1]) / seg : 0;
  double dx = path[i][0] - path[i - 1][0], dy = path[i][1] - path[i - 1][1];
  const double x = path[i - 1][0] + f * dx, y = path[i - 1][1] + f * dy;
  if (back) dx = -dx, dy = -dy;
  const double norm = std::hypot(dx, dy);
  // Joint values are offsets from the first waypoint; heading = pi + yaw (facing -x at 0).
  d->qpos[visitor_qpos_[0]] = x - path[0][0];
  d->qpos[visitor_qpos_[1]] = y - path[0][1];
  d->qpos[visitor_qpos_[2]] = std::remainder(std::atan2(dy, dx) - M_PI, 2 * M_PI);
  d->qvel[visitor_dof_[0]] = visitor_speed_ * dx / norm;
  d->qvel[visitor_dof_[1]] = visitor_speed_ * dy / norm;
  d->qvel[visitor_dof_[2]] = 0;
}

bool MujocoSkillset::removed(int body) const {
  return std::find(removed_debris_.begin(), removed_debris_.end(), body) != removed_debris_.end();
}

void MujocoSkillset::collect_debris() {
  if (attachments_.empty()) return;
  mjModel* m = worker_.model();
  const mjData* d = worker_.data();
  bool any = false;
  for (size_t k = 0; k < tool_tips_.size(); k += 2) {
    const int tool = tool_tips_[k], tip = tool_tips_[k + 1];
    if (std::none_of(attachments_.begin(), attachments_.end(),
                     [&](const Attachment& a) { return a.body == tool; })) {
      continue;
    }
    const Eigen::Vector3d p(d->site_xpos[3 * tip], d->site_xpos[3 * tip + 1],
                            d->site_xpos[3 * tip + 2]);
    for (const Debris& flake : debris_) {
      if (removed(flake.body)) continue;
      const double* c = d->xpos + 3 * flake.body;
      const double up = p.z() - c[2];
      if (std::hypot(p.x() - c[0], p.y() - c[1]) <= kDebrisPickupRadius && up >= -0.01 &&
          up <= kDebrisPickupHeight) {
        m->body_pos[3 * flake.body + 2] = flake.pos.z() - 10.0;  // out of the world
        removed_debris_.push_back(flake.body);
        if (record_every_ > 0) recording_.removals.push_back({worker_.data()->time, flake.body});
        any = true;
      }
    }
  }
  if (any) mj_forward(m, worker_.data());
}

core::CameraInfo MujocoSkillset::head_camera() const {
  const HeadSensorOptions sensor;
  core::CameraInfo info;
  info.frame = profile().head_camera.name;
  info.fovy_rad = worker_.model()->cam_fovy[scene_->head_camera()] * M_PI / 180.0;
  info.aspect = static_cast<double>(sensor.width) / sensor.height;
  info.range_m = sensor.range_m;
  return info;
}

core::DepthScan MujocoSkillset::scan_depth() {
  if (!sensor_) sensor_ = std::make_unique<HeadSensor>(*this);
  const SensorImage& image = sensor_->capture();
  core::DepthScan scan;
  scan.origin = frame_pose(profile().head_camera.name).position;
  scan.rays = image.width * image.height;
  for (size_t i = 0; i < image.depth_m.size(); ++i) {
    if (auto p = sensor_->hit_point(i)) scan.hits.push_back(*p);
  }
  return scan;
}

void MujocoSkillset::apply_layout(const core::ObstacleLayout& layout) {
  require_no_query("apply_layout");
  worker_.apply_layout(layout);
  obstacle_count_ = static_cast<int>(layout.obstacles.size());
  forget_obstacles();
  mj_forward(worker_.model(), worker_.data());
  if (execution_ == ExecutionMode::kKinematic) settle_free_objects();
}

void MujocoSkillset::apply_layout(const core::TrialLayout& layout) {
  require_no_query("apply_layout");
  worker_.apply_variation(layout.variation);
  const mjModel* m = worker_.model();
  for (Debris& flake : debris_) {  // where the variation put them
    flake.pos = Eigen::Vector3d(m->body_pos[3 * flake.body], m->body_pos[3 * flake.body + 1],
                                m->body_pos[3 * flake.body + 2]);
  }
  apply_layout(layout.obstacles);
  reset();
}

void MujocoSkillset::set_obstacles_need_perception(bool need) {
  require_no_query("set_obstacles_need_perception");
  obstacles_need_perception_ = need;
  forget_obstacles();
}

void MujocoSkillset::forget_obstacles() {
  obstacle_perceived_.assign(scene_->obstacle_slots().size(), 0);
}

void MujocoSkillset::mark_obstacle_perceived(int slot) {
  if (slot < 0 || slot >= static_cast<int>(obstacle_perceived_.size())) {
    throw std::invalid_argument("no obstacle slot " + std::to_string(slot));
  }
  obstacle_perceived_[slot] = 1;
}

bool MujocoSkillset::obstacle_known(int slot) const {
  return obstacle_active(slot) && (!obstacles_need_perception_ || obstacle_perceived_[slot]);
}

MujocoSkillset::BeliefScope::BeliefScope(MujocoSkillset& s) : s_(s) {
  if (s_.belief_depth_ == 0 && s_.obstacles_need_perception_) {
    mjModel* m = s_.worker_.model();
    const std::vector<ObstacleSlot>& slots = s_.scene_->obstacle_slots();
    s_.hidden_bits_.clear();
    for (int slot = 0; slot < s_.obstacle_count_; ++slot) {
      if (s_.obstacle_perceived_[slot]) continue;
      for (int g : slots[slot].geoms) {
        s_.hidden_bits_.push_back({g, m->geom_contype[g], m->geom_conaffinity[g]});
        m->geom_contype[g] = 0;
        m->geom_conaffinity[g] = 0;
      }
    }
  }
  ++s_.belief_depth_;
}

MujocoSkillset::BeliefScope::~BeliefScope() {
  if (--s_.belief_depth_ > 0) return;
  mjModel* m = s_.worker_.model();
  for (const HiddenGeom& h : s_.hidden_bits_) {
    m->geom_contype[h.geom] = h.contype;
    m->geom_conaffinity[h.geom] = h.conaffinity;
  }
  s_.hidden_bits_.clear();
}

void MujocoSkillset::require_no_query(const char* what) const {
  if (belief_depth_ > 0) {
    throw std::logic_error(std::string(what) + " while a query is running (from a callback)");
  }
}

void MujocoSkillset::reset() {
  require_no_query("reset");
  for (const Debris& flake : debris_) {
    for (int i = 0; i < 3; ++i) worker_.model()->body_pos[3 * flake.body + i] = flake.pos[i];
  }
  removed_debris_.clear();
  have_last_ = false;
  have_accel_ = false;
  pruning_.wake_all();
  held_pairs_current_ = false;
  worker_.reset_to_start();
  forget_obstacles();
  attachments_.clear();
  attachment_names_.clear();
  attachment_sides_.clear();
  mjData* d = worker_.data();
  for (const JointState& js : joint_state_) {
    if (js.joint < 0) continue;
    target_pos_[js.joint] = d->qpos[js.qpos_adr];
    target_vel_[js.joint] = 0;
    target_acc_[js.joint] = 0;
    d->ctrl[js.actuator] = target_pos_[js.joint];
  }
  mj_forward(worker_.model(), d);
  if (execution_ == ExecutionMode::kKinematic) settle_free_objects();
}

std::optional<core::PlanResult> MujocoSkillset::plan_joints(
    const std::vector<std::string>& chain_names, std::vector<int>& joints) const {
  try {
    joints = joints_of(chain_names);
  } catch (const std::invalid_argument& e) {
    return plan_failure(core::PlanStatus::kInvalidInput, e.what());
  }
  return std::nullopt;
}

std::optional<core::PlanResult> MujocoSkillset::touch_geoms(const core::PlanOptions& options,
                                                            std::vector<int>& geoms) const {
  try {
    geoms = object_geoms(options.may_touch);
  } catch (const std::invalid_argument& e) {
    return plan_failure(core::PlanStatus::kInvalidInput, std::string("may_touch: ") + e.what());
  }
  return std::nullopt;
}

std::vector<int> MujocoSkillset::joints_of(const std::vector<std::string>& chain_names) const {
  if (chain_names.empty()) throw std::invalid_argument("no chains given");
  std::vector<int> joints;
  for (const std::string& name : chain_names) {
    const ChainIndex* found = nullptr;
    for (const ChainIndex& c : scene_->chains()) {
      if (c.name == name) found = &c;
    }
    if (!found) {
      throw std::invalid_argument("robot '" + profile().name + "' has no chain '" + name + "'");
    }
    for (int j : found->joints) {
      if (std::find(joints.begin(), joints.end(), j) != joints.end()) {
        throw std::invalid_argument("chain '" + name + "' is listed twice");
      }
      joints.push_back(j);
    }
  }
  return joints;
}

void MujocoSkillset::check_values(const std::vector<std::string>& chain_names,
                                  const std::vector<int>& joints, const std::vector<double>& values,
                                  const char* what) const {
  if (values.size() != joints.size()) {
    std::string chains;
    for (const std::string& c : chain_names) chains += (chains.empty() ? "" : ",") + c;
    throw std::invalid_argument(std::string(what) + " has " + std::to_string(values.size()) +
                                " values but chains [" + chains + "] have " +
                                std::to_string(joints.size()) + " joints");
  }
  for (size_t i = 0; i < values.size(); ++i) {
    if (!std::isfinite(values[i])) {
      throw std::invalid_argument(std::string(what) + " value for joint '" +
                                  mj_id2name(worker_.model(), mjOBJ_JOINT, joints[i]) +
                                  "' is not finite");
    }
  }
}

bool MujocoSkillset::within_limits(const std::vector<int>& joints,
                                   const std::vector<double>& values) const {
  const mjModel* m = worker_.model();
  for (size_t i = 0; i < joints.size(); ++i) {
    if (values[i] < m->jnt_range[2 * joints[i]] - core::kLimitRounding ||
        values[i] > m->jnt_range[2 * joints[i] + 1] + core::kLimitRounding) {
      return false;
    }
  }
  return true;
}

void MujocoSkillset::sync_query() {
  const mjModel* m = worker_.model();
  const mjData* sim = worker_.data();
  mjData* q = query_.get();
  mju_copy(q->qpos, sim->qpos, m->nq);
  mju_copy(q->mocap_pos, sim->mocap_pos, 3 * m->nmocap);
  mju_copy(q->mocap_quat, sim->mocap_quat, 4 * m->nmocap);
  mj_kinematics(m, q);
}

int MujocoSkillset::object_body(const std::string& object) const {
  const auto it = scene_->environment().objects.find(object);
  if (it == scene_->environment().objects.end() || it->second.bodies.empty()) return -1;
  return mj_name2id(worker_.model(), mjOBJ_BODY, it->second.bodies.front().c_str());
}

std::vector<int> MujocoSkillset::object_geoms(const std::vector<std::string>& objects) const {
  const mjModel* m = worker_.model();
  std::vector<int> bodies;
  for (const std::string& name : objects) {
    const auto spec = scene_->environment().objects.find(name);
    if (spec != scene_->environment().objects.end()) {
      for (const std::string& b : spec->second.bodies) {
        bodies.push_back(mj_name2id(m, mjOBJ_BODY, b.c_str()));
      }
    } else if (const int b = mj_name2id(m, mjOBJ_BODY, name.c_str()); b > 0) {
      bodies.push_back(b);
    } else {
      throw std::invalid_argument("no object or body '" + name + "' in environment " +
                                  scene_->environment().name);
    }
  }
  std::vector<int> geoms;
  for (int g = 0; g < m->ngeom; ++g) {
    for (int up = m->geom_bodyid[g]; up > 0; up = m->body_parentid[up]) {
      if (std::find(bodies.begin(), bodies.end(), up) != bodies.end()) {
        geoms.push_back(g);
        break;
      }
    }
  }
  return geoms;
}

void MujocoSkillset::refresh_supports() {
  const mjModel* m = worker_.model();
  const mjData* d = worker_.data();
  for (Attachment& a : attachments_) {
    for (int g : supports_of(m, d, *scene_, a.body)) {
      if (std::find(a.support_geoms.begin(), a.support_geoms.end(), g) == a.support_geoms.end()) {
        a.support_geoms.push_back(g);
      }
    }
  }
}

std::vector<char> MujocoSkillset::moved_bodies(const std::vector<int>& joints) const {
  const mjModel* m = worker_.model();
  std::vector<char> moved(m->nbody, 0);
  for (int j : joints) moved[m->jnt_bodyid[j]] = 1;
  for (int b = 1; b < m->nbody; ++b) {
    if (moved[m->body_parentid[b]]) moved[b] = 1;
  }
  for (const Attachment& a : attachments_) {  // held objects move with their holders
    if (!moved[a.holder_body]) continue;
    for (int b = a.body; b < m->nbody && m->body_rootid[b] == a.body; ++b) moved[b] = 1;
  }
  return moved;
}

std::vector<double> MujocoSkillset::configuration(
    const std::vector<std::string>& chain_names) const {
  std::vector<double> values;
  for (int j : joints_of(chain_names))
    values.push_back(worker_.data()->qpos[joint_state_[j].qpos_adr]);
  return values;
}

core::Pose MujocoSkillset::frame_pose(const std::string& frame) const {
  try {
    return mujoco::frame_pose(worker_.data(), resolve_frame(*scene_, worker_.data(), frame));
  } catch (const std::out_of_range&) {
    throw std::invalid_argument("no frame or object '" + frame + "' in robot " + profile().name +
                                " or environment " + scene_->environment().name);
  }
}

core::Pose MujocoSkillset::frame_pose_at(const std::vector<std::string>& chain_names,
                                         const std::vector<double>& values,
                                         const std::string& frame) {
  const std::vector<int> joints = joints_of(chain_names);
  check_values(chain_names, joints, values, "configuration");
  const mjModel* m = worker_.model();
  mjData* q = query_.get();
  sync_query();
  for (size_t i = 0; i < joints.size(); ++i) q->qpos[joint_state_[joints[i]].qpos_adr] = values[i];
  mj_kinematics(m, q);
  if (!attachments_.empty()) {
    place_attachments(m, q, attachments_);
    mj_kinematics(m, q);
  }
  try {
    return mujoco::frame_pose(q, resolve_frame(*scene_, q, frame));
  } catch (const std::out_of_range&) {
    throw std::invalid_argument("no frame or object '" + frame + "'");
  }
}

core::IkResult MujocoSkillset::solve_ik(const std::vector<std::string>& chain_names,
                                        const std::string& frame, const core::Pose& target,
                                        const core::IkOptions& options) {
  std::vector<int> joints;
  try {
    joints = joints_of(chain_names);
  } catch (const std::invalid_argument& e) {
    core::IkResult r;
    r.reason = e.what();
    return r;
  }
  const BeliefScope belief(*this);
  refresh_supports();
  sync_query();
  core::IkResult result = mujoco::solve_ik(*scene_, worker_.model(), query_.get(), joints, frame,
                                           target, options, attachments_);
  ++work_.ik_calls;
  work_.ik_time_s += result.time_s;
  return result;
}

bool MujocoSkillset::is_valid(const std::vector<std::string>& chain_names,
                              const std::vector<double>& values) {
  const std::vector<int> joints = joints_of(chain_names);
  check_values(chain_names, joints, values, "configuration");
  if (!within_limits(joints, values)) return false;
  const BeliefScope belief(*this);
  refresh_supports();
  sync_query();
  ValidityChecker checker(*scene_, worker_.model(), query_.get(), joints, attachments_);
  ++work_.collision_checks;
  return !checker.in_collision(values.data());
}

double MujocoSkillset::clearance(const std::vector<std::string>& chain_names,
                                 const std::vector<double>& values, double max_distance_m) {
  const std::vector<int> joints = joints_of(chain_names);
  check_values(chain_names, joints, values, "configuration");
  if (!(std::isfinite(max_distance_m) && max_distance_m > 0)) {
    throw std::invalid_argument("clearance cap must be a positive number of metres");
  }
  const BeliefScope belief(*this);
  refresh_supports();
  sync_query();
  ValidityChecker checker(*scene_, worker_.model(), query_.get(), joints, attachments_);
  return checker.distance(values.data(), max_distance_m);
}

core::PlanResult MujocoSkillset::plan_to_configuration(const std::vector<std::string>& chain_names,
                                                       const std::vector<double>& goal,
                                                       const core::PlanOptions& options) {
  std::vector<int> joints, touch;
  if (auto bad = plan_joints(chain_names, joints)) return *bad;
  if (auto bad = touch_geoms(options, touch)) return *bad;
  const BeliefScope belief(*this);
  refresh_supports();
  sync_query();
  MotionPlanner planner(*scene_, worker_.model(), query_.get(), joints, attachments_, touch);
  return note_plan("configuration", planner.plan({goal}, options));
}

core::PlanResult MujocoSkillset::plan_to_poses(const std::vector<std::string>& chain_names,
                                               const std::string& frame,
                                               const std::vector<core::Pose>& targets,
                                               const core::PlanOptions& options,
                                               const core::IkOptions& ik) {
  return note_plan("poses", plan_to_poses_unrecorded(chain_names, frame, targets, options, ik));
}

core::PlanResult MujocoSkillset::plan_to_poses_unrecorded(
    const std::vector<std::string>& chain_names, const std::string& frame,
    const std::vector<core::Pose>& targets, const core::PlanOptions& options,
    const core::IkOptions& ik) {
  std::vector<int> joints, touch;
  if (auto bad = plan_joints(chain_names, joints)) return *bad;
  if (auto bad = touch_geoms(options, touch)) return *bad;
  if (targets.empty()) return plan_failure(core::PlanStatus::kInvalidInput, "no target poses");
  const BeliefScope belief(*this);
  refresh_supports();
  core::PlanResult total;
  total.status = core::PlanStatus::kIkFailure;
  std::string ik_reasons;  // every pose's IK failure: the detail
  int unreachable = 0, in_collision = 0, best_pose = -1;
  double best_position = 0, best_angle = 0;
  bool any_planned = false;
  for (size_t k = 0; k < targets.size(); ++k) {
    sync_query();
    const core::IkResult solved = mujoco::solve_ik(*scene_, worker_.model(), query_.get(), joints,
                                                   frame, targets[k], ik, attachments_);
    total.ik_time_s += solved.time_s;
    ++work_.ik_calls;
    if (solved.status == core::IkStatus::kInvalidInput) {
      total.status = core::PlanStatus::kInvalidInput;
      total.message = "target pose " + std::to_string(k) + ": " + solved.reason;
      return total;
    }
    if (solved.status != core::IkStatus::kSolved) {
      ik_reasons += (ik_reasons.empty() ? "" : "; ") + std::string("pose ") + std::to_string(k) +
                    ": " + core::to_string(solved.status) + " (" + solved.reason + ")";
      (solved.status == core::IkStatus::kInCollision ? in_collision : unreachable) += 1;
      const bool better =
          best_pose < 0 || solved.position_error_m < best_position ||
          (solved.position_error_m == best_position && solved.orientation_error_rad < best_angle);
      if (better) {
        best_pose = static_cast<int>(k);
        best_position = solved.position_error_m;
        best_angle = solved.orientation_error_rad;
      }
      continue;
    }
    MotionPlanner planner(*scene_, worker_.model(), query_.get(), joints, attachments_, touch);
    const core::PlanResult r = planner.plan(solved.solutions, options);
    any_planned = true;
    total.planning_time_s += r.planning_time_s;
    total.simplification_time_s += r.simplification_time_s;
    total.planning_hit_time_limit |= r.planning_hit_time_limit;
    total.simplification_hit_time_limit |= r.simplification_hit_time_limit;
    total.planner_iterations += r.planner_iterations;
    total.collision_checks += r.collision_checks;
    total.graph_states += r.graph_states;
    total.plan_calls += r.plan_calls;
    total.status = r.status;
    total.message = "pose " + std::to_string(k) + ": " + r.message;
    if (r.status == core::PlanStatus::kInvalidStart || r.status == core::PlanStatus::kInvalidInput)
      return total;  // no other pose can do better
    if (r.success()) {
      total.path = r.path;
      total.goal_index = static_cast<int>(k);
      total.message.clear();
      return total;
    }
  }
  if (!any_planned) {
    // A summary of bounded length; every attempt is in `detail`.
    char best[160];
    std::snprintf(best, sizeof best, "; the closest, pose %d, ended %.1f cm and %.1f deg off",
                  best_pose, best_position * 100, best_angle * 180 / M_PI);
    total.message = "no target pose has an IK solution: " + std::to_string(targets.size()) +
                    (targets.size() == 1 ? " pose" : " poses") + " tried (" +
                    std::to_string(unreachable) + " unreachable, " + std::to_string(in_collision) +
                    " with every solution in collision)" + (best_pose >= 0 ? best : "");
    total.detail = ik_reasons;
  }
  return total;
}

core::PlanResult MujocoSkillset::plan_to_region(const std::vector<std::string>& chain_names,
                                                const core::GoalRegion& region,
                                                const core::PlanOptions& options) {
  return note_plan("region", plan_to_region_unrecorded(chain_names, region, options));
}

core::PlanResult MujocoSkillset::plan_to_region_unrecorded(
    const std::vector<std::string>& chain_names, const core::GoalRegion& region,
    const core::PlanOptions& options) {
  std::vector<int> joints, touch;
  if (auto bad = plan_joints(chain_names, joints)) return *bad;
  if (auto bad = touch_geoms(options, touch)) return *bad;
  if (!region.sample || region.max_draws <= 0 || region.max_goals <= 0) {
    return plan_failure(core::PlanStatus::kInvalidInput,
                        "a goal region needs a sampler and positive draw and goal counts");
  }
  const BeliefScope belief(*this);
  refresh_supports();
  sync_query();
  std::vector<std::vector<double>> goals;
  {
    ValidityChecker checker(*scene_, worker_.model(), query_.get(), joints, attachments_);
    std::mt19937_64 rng(options.seed);
    for (int draw = 0; draw < region.max_draws && static_cast<int>(goals.size()) < region.max_goals;
         ++draw) {
      std::optional<std::vector<double>> q = region.sample(rng);
      if (!q) continue;
      if (q->size() != joints.size() ||
          !std::all_of(q->begin(), q->end(), [](double v) { return std::isfinite(v); })) {
        return plan_failure(core::PlanStatus::kInvalidInput,
                            "the goal region sampler returned a configuration of the wrong size "
                            "or with NaN");
      }
      if (within_limits(joints, *q) && !checker.in_collision(q->data())) goals.push_back(*q);
    }
  }
  if (goals.empty()) {
    return plan_failure(
        core::PlanStatus::kInvalidGoal,
        "none of " + std::to_string(region.max_draws) + " draws from the goal region is valid");
  }
  sync_query();
  MotionPlanner planner(*scene_, worker_.model(), query_.get(), joints, attachments_, touch);
  return planner.plan(goals, options);
}

double MujocoSkillset::time() const { return worker_.data()->time; }

void MujocoSkillset::command(const std::vector<std::string>& chain_names,
                             const std::vector<double>& positions,
                             const std::vector<double>& velocities,
                             const std::vector<double>& accelerations) {
  const std::vector<int> joints = joints_of(chain_names);
  check_values(chain_names, joints, positions, "command");
  if (!velocities.empty()) check_values(chain_names, joints, velocities, "command velocity");
  if (!accelerations.empty())
    check_values(chain_names, joints, accelerations, "command acceleration");
  const mjModel* m = worker_.model();
  for (size_t i = 0; i < joints.size(); ++i) {
    const double lo = m->jnt_range[2 * joints[i]], hi = m->jnt_range[2 * joints[i] + 1];
    if (positions[i] < lo - core::kCommandClampTolerance ||
        positions[i] > hi + core::kCommandClampTolerance) {
      char buf[200];
      std::snprintf(buf, sizeof buf,
                    "command %.6g for joint '%s' is outside its limits [%.6g, %.6g]", positions[i],
                    mj_id2name(m, mjOBJ_JOINT, joints[i]), lo, hi);
      throw std::invalid_argument(buf);
    }
  }
  mjData* d = worker_.data();
  for (size_t i = 0; i < joints.size(); ++i) {
    const int j = joints[i];
    target_pos_[j] = std::clamp(positions[i], m->jnt_range[2 * j], m->jnt_range[2 * j + 1]);
    target_vel_[j] = velocities.empty() ? 0.0 : velocities[i];
    target_acc_[j] = accelerations.empty() ? 0.0 : accelerations[i];
    d->ctrl[joint_state_[j].actuator] = target_pos_[j];
  }
}

void MujocoSkillset::set_configuration(const std::vector<std::string>& chain_names,
                                       const std::vector<double>& values) {
  command(chain_names, values);
  const std::vector<int> joints = joints_of(chain_names);
  mjData* d = worker_.data();
  for (size_t i = 0; i < joints.size(); ++i) {
    d->qpos[joint_state_[joints[i]].qpos_adr] = target_pos_[joints[i]];
    d->qvel[joint_state_[joints[i]].dof_adr] = 0;
  }
  const mjModel* m = worker_.model();
  if (!attachments_.empty()) {
    mj_kinematics(m, d);
    place_attachments(m, d, attachments_);
  }
  mj_forward(m, d);
  have_last_ = false;  // a placement, not motion
  have_accel_ = false;
  if (record_every_ > 0) record_frame();
}

core::PlanResult MujocoSkillset::note_plan(const char* kind, core::PlanResult result) {
  PlanCallRecord r;
  r.time_s = worker_.data()->time;
  r.kind = kind;
  r.status = core::to_string(result.status);
  r.planner_runs = result.plan_calls;
  r.planning_time_s = result.planning_time_s;
  r.simplification_time_s = result.simplification_time_s;
  r.planning_hit_time_limit = result.planning_hit_time_limit;
  r.simplification_hit_time_limit = result.simplification_hit_time_limit;
  r.planner_iterations = result.planner_iterations;
  r.path_digest = path_digest(result.path);
  r.ik_time_s = result.ik_time_s;
  r.collision_checks = result.collision_checks;
  r.path_states = static_cast<int>(result.path.size());
  for (size_t k = 1; k < result.path.size(); ++k) {
    double sq = 0;
    for (size_t i = 0; i < result.path[k].size(); ++i) {
      const double dq = result.path[k][i] - result.path[k - 1][i];
      sq += dq * dq;
    }
    r.path_length += std::sqrt(sq);
  }
  work_.collision_checks += result.collision_checks;
  work_.plans.push_back(std::move(r));
  return result;
}

void MujocoSkillset::record_states(double rate_hz) {
  if (!(std::isfinite(rate_hz) && rate_hz >= 0)) {
    throw std::invalid_argument("recording rate must be a non-negative number of Hz");
  }
  if (rate_hz == 0) {
    record_every_ = 0;
    return;
  }
  record_every_ = std::max(1, static_cast<int>(std::lround(1.0 / (rate_hz * period_))));
  recording_ = StateRecording{};
  recording_.nq = worker_.model()->nq;
  recording_.frame_period_s = record_every_ * period_;
  record_frame();
}

void MujocoSkillset::record_frame() {
  const mjData* d = worker_.data();
  recording_.times.push_back(d->time);
  recording_.qpos.insert(recording_.qpos.end(), d->qpos, d->qpos + worker_.model()->nq);
}

void MujocoSkillset::monitor_period() {
  const mjModel* m = worker_.model();
  const mjData* d = worker_.data();
  ++work_.control_periods;
  if (record_every_ > 0 && work_.control_periods % record_every_ == 0) record_frame();
  // Robot joints: positions, velocities, accelerations; end effectors: positions. The
  // buffers are members: no allocation per period once sized.
  cur_q_.clear();
  cur_v_.clear();
  cur_ee_.clear();
  moving_.clear();
  for (const JointState& js : joint_state_) {
    if (js.joint < 0) continue;
    cur_q_.push_back(d->qpos[js.qpos_adr]);
    cur_v_.push_back(d->qvel[js.dof_adr]);
    if (target_vel_[js.joint] != 0) moving_.push_back(js.joint);
  }
  for (int s : ee_sites_)
    cur_ee_.insert(cur_ee_.end(), d->site_xpos + 3 * s, d->site_xpos + 3 * s + 3);
  for (int b : ee_bodies_) cur_ee_.insert(cur_ee_.end(), d->xpos + 3 * b, d->xpos + 3 * b + 3);
  if (have_last_) {
    double dq = 0;
    for (size_t i = 0; i < cur_q_.size(); ++i) {
      dq += (cur_q_[i] - last_q_[i]) * (cur_q_[i] - last_q_[i]);
    }
    work_.path_length_joint += std::sqrt(dq);
    for (size_t i = 0; i + 2 < cur_ee_.size(); i += 3) {
      work_.path_length_ee_m +=
          std::hypot(cur_ee_[i] - last_ee_[i], cur_ee_[i + 1] - last_ee_[i + 1],
                     cur_ee_[i + 2] - last_ee_[i + 2]);
    }
    cur_a_.resize(cur_v_.size());
    for (size_t i = 0; i < cur_v_.size(); ++i) cur_a_[i] = (cur_v_[i] - last_v_[i]) / period_;
    if (have_accel_) {
      double jerk_sq = 0;
      for (size_t i = 0; i < cur_a_.size(); ++i) {
        const double j = (cur_a_[i] - last_a_[i]) / period_;
        jerk_sq += j * j;
      }
      work_.jerk_squared_sum += jerk_sq;
      ++work_.jerk_samples;
    }
    std::swap(last_a_, cur_a_);
    have_accel_ = true;
  }
  std::swap(last_q_, cur_q_);
  std::swap(last_v_, cur_v_);
  std::swap(last_ee_, cur_ee_);
  have_last_ = true;
  if (clearance_every_ > 0 && !moving_.empty() && work_.control_periods % clearance_every_ == 0) {
    // Against the world as it is (every obstacle, seen or not), not the robot's belief.
    sync_query();
    ValidityChecker checker(*scene_, m, query_.get(), moving_, attachments_);
    cur_q_.clear();
    for (int j : moving_) cur_q_.push_back(d->qpos[m->jnt_qposadr[j]]);
    work_.min_clearance_m =
        std::min(work_.min_clearance_m, checker.distance_to_world(cur_q_.data(), clearance_cap_m_));
    ++work_.clearance_samples;
  }
}

void MujocoSkillset::step_physics() {
  mjModel* m = worker_.model();
  mjData* d = worker_.data();
  // Entered with the state current (mj_step1 or mj_forward ran at it): bias forces, mass
  // matrix and contacts are those of the present configuration.
  const double t_end = d->time + period_;
  bool accelerating = false;
  for (const JointState& js : joint_state_) {
    if (js.joint >= 0 && target_acc_[js.joint] != 0) accelerating = true;
  }
  pruning_.begin(m);
  for (int s = 0; s < substeps_; ++s) {
    // Targets are samples for the end of the period: run along the commanded velocity.
    const double lead = t_end - (d->time + m->opt.timestep);
    if (accelerating) {
      std::fill(acc_full_.begin(), acc_full_.end(), 0.0);
      for (const JointState& js : joint_state_) {
        if (js.joint >= 0) acc_full_[js.dof_adr] = target_acc_[js.joint];
      }
      mj_mulM(m, d, mass_times_acc_.data(), acc_full_.data());
    }
    for (const JointState& js : joint_state_) {
      if (js.joint < 0) continue;
      const int v = js.dof_adr;
      d->ctrl[js.actuator] = target_pos_[js.joint] - target_vel_[js.joint] * lead;
      d->qfrc_applied[v] = d->qfrc_bias[v] + (accelerating ? mass_times_acc_[v] : 0.0) +
                           m->dof_damping[v] * target_vel_[js.joint];
    }
    mj_step2(m, d);  // actuation, accelerations, contact forces, integration
    pruning_.after_integration(m, d);
    drive_visitor(d, d->time);
    if (!attachments_.empty()) {
      mj_kinematics(m, d);
      place_attachments(m, d, attachments_);
    }
    pruning_.before_collision(m, d);
    mj_step1(m, d);  // kinematics, contacts, bias forces at the new state
    ++work_.contact_passes;
    work_.contacts += d->ncon;
  }
  pruning_.end(m);
  for (const JointState& js : joint_state_) {
    if (js.joint >= 0) d->ctrl[js.actuator] = target_pos_[js.joint];
  }
}

void MujocoSkillset::step_kinematic() {
  const mjModel* m = worker_.model();
  mjData* d = worker_.data();
  // The same clock as the physics (mj_step adds one timestep at a time).
  for (int s = 0; s < substeps_; ++s) d->time += m->opt.timestep;
  robot_qpos_before_.assign(d->qpos, d->qpos + m->nq);
  for (const JointState& js : joint_state_) {
    if (js.joint < 0) continue;
    d->qpos[js.qpos_adr] = target_pos_[js.joint];
    d->qvel[js.dof_adr] = target_vel_[js.joint];
    d->ctrl[js.actuator] = target_pos_[js.joint];
  }
  drive_visitor(d, d->time);
  mj_kinematics(m, d);
  if (!attachments_.empty()) {
    place_attachments(m, d, attachments_);
    mj_kinematics(m, d);
  }
  if (stop_fingers_at_contact(robot_qpos_before_)) {
    mj_kinematics(m, d);
    if (!attachments_.empty()) {
      place_attachments(m, d, attachments_);
      mj_kinematics(m, d);
    }
  }
  mj_camlight(m, d);
  find_robot_contacts();
}

bool MujocoSkillset::stop_fingers_at_contact(const std::vector<double>& before) {
  const mjModel* m = worker_.model();
  mjData* d = worker_.data();
  bool held_back = false;
  mjContact found[mjMAXCONPAIR];
  // The deepest penetration of the finger's geoms into anything, as posed in d.
  auto depth = [&](const Finger& f) {
    double deepest = 0;
    for (const GeomPair& p : f.pairs) {
      const int n = collide_geoms(m, d, p, p.margin, found);
      for (int i = 0; i < n; ++i) deepest = std::max(deepest, -found[i].dist);
    }
    return deepest;
  };
  // Poses the finger's bodies and geoms with its joints a fraction s of the way from `before`
  // to their targets (the palm's pose is current).
  auto pose = [&](const Finger& f, const std::vector<double>& target, double s) {
    for (size_t i = 0; i < f.qpos_adr.size(); ++i) {
      const int a = f.qpos_adr[i];
      d->qpos[a] = before[a] + s * (target[i] - before[a]);
    }
    for (int b : f.bodies) {
      const int parent = m->body_parentid[b];
      body_pose_from_parent(m, d->qpos, b, d->xpos + 3 * parent, d->xquat + 4 * parent,
                            d->xmat + 9 * parent, d->xpos + 3 * b, d->xquat + 4 * b,
                            d->xmat + 9 * b);
    }
    for (int g : f.geoms) {
      const int b = m->geom_bodyid[g];
      geom_pose_from_body(m, g, d->xpos + 3 * b, d->xquat + 4 * b, d->xmat + 9 * b,
                          d->geom_xpos + 3 * g, d->geom_xmat + 9 * g);
    }
  };
  // Whether a body touched anything at the start of the period (d->contact is still the last
  // period's).
  auto touched = [&](int body) {
    for (int i = 0; i < d->ncon; ++i) {
      if (m->geom_bodyid[d->contact[i].geom1] == body ||
          m->geom_bodyid[d->contact[i].geom2] == body) {
        return true;
      }
    }
    return false;
  };
  for (const Finger& f : fingers_) {
    // A touching segment holds the joints nearer the palm from closing.
    for (size_t k = f.segments.size(); k-- > 1;) {
      if (!touched(f.segments[k])) continue;
      for (size_t i = 0; i < k; ++i) {
        const int a = f.qpos_adr[i];
        if (std::abs(d->qpos[a] - f.fist[i]) < std::abs(before[a] - f.fist[i])) {
          d->qpos[a] = before[a];
          held_back = true;
        }
      }
      break;
    }
    std::vector<double> target;
    bool moved = false;
    for (int a : f.qpos_adr) {
      target.push_back(d->qpos[a]);
      moved = moved || d->qpos[a] != before[a];
    }
    if (!moved) continue;
    pose(f, target, 1.0);
    const double reached = depth(f);
    if (reached <= kFingerPenetrationM) continue;
    pose(f, target, 0.0);
    const double allowed = std::max(kFingerPenetrationM, depth(f));
    if (reached <= allowed) {
      pose(f, target, 1.0);
      continue;
    }
    // The furthest fraction of the motion that sinks no deeper than allowed.
    double lo = 0, hi = 1;
    for (int k = 0; k < 12; ++k) {
      const double mid = 0.5 * (lo + hi);
      pose(f, target, mid);
      (depth(f) <= allowed ? lo : hi) = mid;
    }
    pose(f, target, lo);
    held_back = true;
  }
  return held_back;
}

void MujocoSkillset::find_robot_contacts() {
  const mjModel* m = worker_.model();
  mjData* d = worker_.data();
  if (!held_pairs_current_) {
    // Held objects against everything that is neither the robot (those pairs are among the
    // scene's robot pairs) nor the object itself.
    held_pairs_.clear();
    for (const Attachment& a : attachments_) {
      for (int g1 = 0; g1 < m->ngeom; ++g1) {
        if (m->body_rootid[m->geom_bodyid[g1]] != a.body) continue;
        for (int g2 = 0; g2 < m->ngeom; ++g2) {
          if (scene_->is_robot_geom(g2) || m->body_rootid[m->geom_bodyid[g2]] == a.body) continue;
          if (const std::optional<GeomPair> p = scene_->collidable_pair(g1, g2)) {
            held_pairs_.push_back(*p);
          }
        }
      }
    }
    held_pairs_current_ = true;
  }
  d->ncon = 0;
  auto add = [&](const GeomPair& p) {
    mjContact found[mjMAXCONPAIR];
    const int n = collide_geoms(m, d, p, p.margin, found);
    for (int i = 0; i < n && d->ncon < m->nconmax; ++i) d->contact[d->ncon++] = found[i];
  };
  for (const GeomPair& p : scene_->robot_geom_pairs()) add(p);
  for (const GeomPair& p : held_pairs_) add(p);
  ++work_.contact_passes;
  work_.contacts += d->ncon;
}

void MujocoSkillset::settle_objects(const std::vector<int>& bodies) {
  mjModel* m = worker_.model();
  mjData* d = worker_.data();
  std::vector<char> free_dof(m->nv, 0), free_qpos(m->nq, 0);
  for (int body : bodies) {
    const int joint = m->body_jntadr[body];
    for (int k = 0; k < 7; ++k) free_qpos[m->jnt_qposadr[joint] + k] = 1;
    for (int k = 0; k < 6; ++k) free_dof[m->jnt_dofadr[joint] + k] = 1;
  }
  const std::vector<double> qpos(d->qpos, d->qpos + m->nq), qvel(d->qvel, d->qvel + m->nv);
  const double time = d->time;
  // The robot holds still and lets go: no contacts with it while the objects settle.
  std::vector<std::array<int, 3>> robot_bits;
  for (int g = 0; g < m->ngeom; ++g) {
    if (!scene_->is_robot_geom(g)) continue;
    robot_bits.push_back({g, m->geom_contype[g], m->geom_conaffinity[g]});
    m->geom_contype[g] = 0;
    m->geom_conaffinity[g] = 0;
  }
  mju_zero(d->qfrc_applied, m->nv);
  mju_zero(d->qvel, m->nv);
  // Until each has been touching something and at rest for kRestTimeS (or kSettleMaxS).
  const int steps = static_cast<int>(std::lround(kSettleMaxS / m->opt.timestep));
  const int rest_needed = std::max(1, static_cast<int>(std::lround(kRestTimeS / m->opt.timestep)));
  std::vector<int> at_rest(bodies.size(), 0);
  auto settled = [&] {
    return std::all_of(at_rest.begin(), at_rest.end(), [&](int n) { return n >= rest_needed; });
  };
  for (int s = 0; s < steps && !settled(); ++s) {
    mj_step(m, d);
    for (int i = 0; i < m->nq; ++i) {
      if (!free_qpos[i]) d->qpos[i] = qpos[i];
    }
    for (int i = 0; i < m->nv; ++i) {
      if (!free_dof[i]) d->qvel[i] = 0;
    }
    for (size_t k = 0; k < bodies.size(); ++k) {
      bool touching = false;
      for (int c = 0; c < d->ncon && !touching; ++c) {
        touching = m->body_rootid[m->geom_bodyid[d->contact[c].geom1]] == bodies[k] ||
                   m->body_rootid[m->geom_bodyid[d->contact[c].geom2]] == bodies[k];
      }
      const double* v = d->qvel + m->jnt_dofadr[m->body_jntadr[bodies[k]]];
      const bool slow = mju_norm3(v) < kRestSpeed && mju_norm3(v + 3) < kRestAngularSpeed;
      at_rest[k] = touching && slow ? at_rest[k] + 1 : 0;
    }
  }
  for (const auto& [g, contype, conaffinity] : robot_bits) {
    m->geom_contype[g] = contype;
    m->geom_conaffinity[g] = conaffinity;
  }
  for (int i = 0; i < m->nv; ++i) d->qvel[i] = free_dof[i] ? 0 : qvel[i];
  d->time = time;
  mj_forward(m, d);
}

void MujocoSkillset::settle_free_objects() {
  const mjModel* m = worker_.model();
  std::vector<int> bodies;
  for (const auto& [name, spec] : scene_->environment().objects) {
    const int body = object_body(name);
    if (body <= 0 || m->body_parentid[body] != 0 || m->body_jntnum[body] != 1 ||
        m->jnt_type[m->body_jntadr[body]] != mjJNT_FREE) {
      continue;
    }
    if (std::none_of(attachments_.begin(), attachments_.end(),
                     [&](const Attachment& a) { return a.body == body; })) {
      bodies.push_back(body);
    }
  }
  if (!bodies.empty()) settle_objects(bodies);
}

core::StepReport MujocoSkillset::advance() {
  const mjModel* m = worker_.model();
  mjData* d = worker_.data();
  const auto t_step = std::chrono::steady_clock::now();
  core::StepReport report;
  const int bad_before = d->warning[mjWARN_BADQACC].number + d->warning[mjWARN_BADQVEL].number +
                         d->warning[mjWARN_BADQPOS].number;
  if (execution_ == ExecutionMode::kKinematic) {
    step_kinematic();
  } else {
    step_physics();
  }
  collect_debris();
  const auto t_monitor = std::chrono::steady_clock::now();
  work_.stepping_wall_s += std::chrono::duration<double>(t_monitor - t_step).count();
  monitor_period();
  work_.monitoring_wall_s +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_monitor).count();
  const int bad_after = d->warning[mjWARN_BADQACC].number + d->warning[mjWARN_BADQVEL].number +
                        d->warning[mjWARN_BADQPOS].number;
  bool finite = true;
  for (int i = 0; i < m->nq; ++i) finite = finite && std::isfinite(d->qpos[i]);
  if (!finite || bad_after > bad_before) {
    report.unstable = true;
    char buf[160];
    std::snprintf(
        buf, sizeof buf, "simulation diverged near t = %.3f s (%s)", d->time,
        finite ? "MuJoCo reported bad accelerations and reset the state" : "non-finite positions");
    report.message = buf;
  }
  return report;
}

std::vector<core::Collision> MujocoSkillset::collisions(
    const std::vector<std::string>& chain_names) const {
  const std::vector<char> moved = moved_bodies(joints_of(chain_names));
  const mjModel* m = worker_.model();
  const mjData* d = worker_.data();
  std::vector<core::Collision> out;
  auto part_name = [&](int body) {
    for (size_t k = 0; k < attachments_.size(); ++k) {
      if (m->body_rootid[body] == attachments_[k].body) return attachment_names_[k];
    }
    return body_name(m, body);
  };
  for (int i = 0; i < d->ncon; ++i) {
    const mjContact& c = d->contact[i];
    const int b1 = m->geom_bodyid[c.geom1], b2 = m->geom_bodyid[c.geom2];
    if (!moved[b1] && !moved[b2]) continue;
    if (!counts_as_robot_collision(*scene_, m, c, attachments_)) continue;
    const int mine = moved[b1] ? b1 : b2, other = moved[b1] ? b2 : b1;
    out.push_back({part_name(mine), name_of_body(other), -c.dist});
  }
  return out;
}

void MujocoSkillset::attach(const std::string& object, const std::string& side) {
  const mjModel* m = worker_.model();
  const int body = object_body(object);
  const auto spec = scene_->environment().objects.find(object);
  if (body < 0 || (spec->second.kind != core::ObjectKind::kGraspable &&
                   spec->second.kind != core::ObjectKind::kTool)) {
    throw std::invalid_argument("'" + object + "' is not a graspable object or tool of " +
                                scene_->environment().name);
  }
  if (m->body_parentid[body] != 0 || m->body_jntnum[body] != 1 ||
      m->jnt_type[m->body_jntadr[body]] != mjJNT_FREE) {
    throw std::invalid_argument("object '" + object + "' is not a free body and cannot be held");
  }
  if (std::find(attachment_names_.begin(), attachment_names_.end(), object) !=
      attachment_names_.end()) {
    throw std::invalid_argument("object '" + object + "' is already attached");
  }
  const core::HandSpec* hand = profile().find_hand(side);
  if (!hand) throw std::invalid_argument("no hand on side '" + side + "'");
  mjData* d = worker_.data();
  mj_forward(m, d);
  Attachment a;
  a.body = body;
  a.holder_body = resolve_frame(*scene_, d, hand->palm).body;
  for (int b = a.holder_body; b < m->nbody; ++b) {
    int up = b;
    while (up > a.holder_body) up = m->body_parentid[up];
    if (up == a.holder_body) a.hand_bodies.push_back(b);
  }
  a.support_geoms = supports_of(m, d, *scene_, body);
  // Object frame in the holder frame, from the current poses.
  double inv_pos[3], inv_quat[4];
  mju_negPose(inv_pos, inv_quat, d->xpos + 3 * a.holder_body, d->xquat + 4 * a.holder_body);
  mju_mulPose(a.pos.data(), a.quat.data(), inv_pos, inv_quat, d->xpos + 3 * body,
              d->xquat + 4 * body);
  attachments_.push_back(std::move(a));
  attachment_names_.push_back(object);
  attachment_sides_.push_back(side);
  pruning_.set_held(body, true);
  held_pairs_current_ = false;
  place_attachments(m, d, attachments_);
  mj_forward(m, d);
  if (execution_ == ExecutionMode::kKinematic) find_robot_contacts();
}

void MujocoSkillset::detach(const std::string& object) {
  const auto it = std::find(attachment_names_.begin(), attachment_names_.end(), object);
  if (it == attachment_names_.end()) {
    throw std::invalid_argument("object '" + object + "' is not attached");
  }
  const size_t k = static_cast<size_t>(it - attachment_names_.begin());
  const int body = attachments_[k].body;
  attachments_.erase(attachments_.begin() + static_cast<long>(k));
  attachment_sides_.erase(attachment_sides_.begin() + static_cast<long>(k));
  attachment_names_.erase(it);
  pruning_.set_held(body, false);
  held_pairs_current_ = false;
  if (execution_ == ExecutionMode::kKinematic) settle_objects({body});
  mj_forward(worker_.model(), worker_.data());
  if (execution_ == ExecutionMode::kKinematic) find_robot_contacts();
}

std::vector<std::string> MujocoSkillset::attached_objects() const { return attachment_names_; }

std::string MujocoSkillset::holder_of(const std::string& object) const {
  for (size_t k = 0; k < attachment_names_.size(); ++k) {
    if (attachment_names_[k] == object) return attachment_sides_[k];
  }
  return "";
}

std::string MujocoSkillset::name_of_body(int body) const {
  const mjModel* m = worker_.model();
  for (const auto& [name, spec] : scene_->environment().objects) {
    for (const std::string& b : spec.bodies) {
      const int id = mj_name2id(m, mjOBJ_BODY, b.c_str());
      if (id >= 0 && (id == body || m->body_rootid[body] == id)) {
        return spec.bodies.size() == 1 ? name : b;
      }
    }
  }
  const std::vector<ObstacleSlot>& slots = scene_->obstacle_slots();
  for (size_t s = 0; s < slots.size(); ++s) {
    if (slots[s].body == body) return "obstacle_" + std::to_string(s);
  }
  return body_name(m, body);
}

std::vector<std::string> MujocoSkillset::touching(const std::string& part) const {
  const mjModel* m = worker_.model();
  const mjData* d = worker_.data();
  int body = object_body(part);
  if (body < 0) body = mj_name2id(m, mjOBJ_BODY, part.c_str());
  if (body <= 0) throw std::invalid_argument("no body or object '" + part + "'");
  const bool whole_object = object_body(part) >= 0;
  auto is_part = [&](int b) { return whole_object ? m->body_rootid[b] == body : b == body; };
  std::vector<std::string> out;
  for (int i = 0; i < d->ncon; ++i) {
    const int b1 = m->geom_bodyid[d->contact[i].geom1], b2 = m->geom_bodyid[d->contact[i].geom2];
    int other = -1;
    if (is_part(b1) && !is_part(b2)) other = b2;
    if (is_part(b2) && !is_part(b1)) other = b1;
    if (other < 0) continue;
    std::string name = name_of_body(other);
    if (std::find(out.begin(), out.end(), name) == out.end()) out.push_back(std::move(name));
  }
  return out;
}

}  // namespace taskmatrix::mujoco
