#include "taskmatrix/mujoco/mujoco_skillset.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "taskmatrix/core/joint_limits.h"
#include "taskmatrix/mujoco/body_kinematics.h"
#include "taskmatrix/mujoco/head_sensor.h"
#include "taskmatrix/mujoco/kinematics.h"
#include "taskmatrix/mujoco/mjcf_compose.h"
#include "taskmatrix/mujoco/motion_planner.h"

namespace taskmatrix::mujoco {

namespace {

std::string body_name(const mjModel* m, int body) {
  const char* name = mj_id2name(m, mjOBJ_BODY, body);
  return name ? name : "body " + std::to_string(body);
}

}  // namespace

const char* to_string(ExecutionMode mode) {
  return mode == ExecutionMode::kKinematic ? "kinematic" : "physics";
}

MujocoSkillset::MujocoSkillset(std::shared_ptr<const Scene> scene, SimulationOptions options)
    : scene_(std::move(scene)),
      worker_(scene_),
      servo_(*scene_, worker_.model()),
      belief_(*scene_),
      world_(*scene_, worker_.model()),
      execution_(options.execution),
      pruning_(*scene_, worker_.model(), options.pruning),
      contacts_(worker_.model()) {
  if (execution_ == ExecutionMode::kPhysics && options.sparse_jacobian &&
      worker_.model()->opt.jacobian == mjJAC_AUTO) {
    worker_.model()->opt.jacobian = mjJAC_SPARSE;
  }
  own_contacts_ =
      execution_ == ExecutionMode::kPhysics && options.candidate_pairs && contacts_.usable();
  const mjModel* m = worker_.model();
  if (!(std::isfinite(options.control_rate_hz) && options.control_rate_hz > 0)) {
    throw std::invalid_argument("control rate must be a positive number of Hz");
  }
  substeps_ =
      std::max(1, static_cast<int>(std::lround(1.0 / (options.control_rate_hz * m->opt.timestep))));
  period_ = substeps_ * m->opt.timestep;
  query_ = make_data(m);
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
    chains_.push_back(std::move(info));
  }
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
  reset();
}

MujocoSkillset::~MujocoSkillset() = default;

void MujocoSkillset::set_visitor_walk(double speed_mps) {
  world_.set_visitor_walk(worker_.model(), speed_mps);
}

void MujocoSkillset::collect_debris() {
  const std::vector<int> removed = world_.collect_debris(worker_.model(), worker_.data(), held_);
  if (removed.empty()) return;
  for (int body : removed) note_removal(body);
  mj_forward(worker_.model(), worker_.data());
}

core::CameraInfo MujocoSkillset::do_head_camera() const {
  const HeadSensorOptions sensor;
  core::CameraInfo info;
  info.frame = profile().head_camera.name;
  info.fovy_rad = worker_.model()->cam_fovy[scene_->head_camera()] * M_PI / 180.0;
  info.aspect = static_cast<double>(sensor.width) / sensor.height;
  info.range_m = sensor.range_m;
  return info;
}

double MujocoSkillset::do_palm_depth(const core::HandSpec& hand) const {
  const mjModel* m = worker_.model();
  const mjData* d = worker_.data();
  const BodyFrame palm = resolve_frame(*scene_, d, hand.palm);
  const core::Pose at = mujoco::frame_pose(d, palm);
  const Eigen::Vector3d approach =
      at.orientation *
      Eigen::Vector3d(hand.approach[0], hand.approach[1], hand.approach[2]).normalized();
  const mjtNum dir[3] = {approach.x(), approach.y(), approach.z()};
  double front = -INFINITY;  // the palm geometry's furthest point along approach
  for (int g = 0; g < m->ngeom; ++g) {
    if (m->geom_bodyid[g] != palm.body || !(m->geom_contype[g] || m->geom_conaffinity[g])) continue;
    front = std::max(front, geom_support(m, d, g, dir));
  }
  if (!std::isfinite(front)) return 0;
  return std::max(0.0, approach.dot(at.position) - front);
}

core::DepthScan MujocoSkillset::do_scan_depth() {
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

void MujocoSkillset::apply_obstacles(const core::ObstacleLayout& layout) {
  contact_pass_geoms_.clear();
  worker_.apply_layout(layout);
  belief_.set_active(static_cast<int>(layout.obstacles.size()));
  mj_forward(worker_.model(), worker_.data());
}

void MujocoSkillset::apply_layout(const core::ObstacleLayout& layout) {
  require_no_query("apply_layout");
  apply_obstacles(layout);
  if (execution_ == ExecutionMode::kKinematic) settle_free_objects();
}

void MujocoSkillset::apply_layout(const core::TrialLayout& layout) {
  require_no_query("apply_layout");
  worker_.apply_variation(layout.variation);
  // The variation may have changed the geoms of moving bodies under a surface it moved.
  contacts_ = PhysicsContacts(worker_.model());
  world_.note_debris_places(worker_.model());  // where the variation put them
  // No settle here: reset() starts from the start state again and settles once.
  apply_obstacles(layout.obstacles);
  reset();
}

void MujocoSkillset::set_obstacles_need_perception(bool need) {
  require_no_query("set_obstacles_need_perception");
  belief_.set_need_perception(need);
}

void MujocoSkillset::mark_obstacle_perceived(int slot) { belief_.mark_perceived(slot); }

bool MujocoSkillset::obstacle_known(int slot) const { return belief_.known(slot); }

void MujocoSkillset::require_no_query(const char* what) const {
  if (belief_.in_scope() || in_query()) {
    throw std::logic_error(std::string(what) + " while a query is running (from a callback)");
  }
}

void MujocoSkillset::reset() {
  require_no_query("reset");
  world_.restore_debris(worker_.model());
  world_.restart_visitor_walk();
  have_last_ = false;
  have_accel_ = false;
  pruning_.wake_all();
  held_pairs_current_ = false;
  contact_pass_geoms_.clear();
  worker_.reset_to_start();
  belief_.forget();
  held_.clear();
  mjData* d = worker_.data();
  servo_.hold_current(d);
  mj_forward(worker_.model(), d);
  if (execution_ == ExecutionMode::kKinematic) settle_free_objects();
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
    } else if (const int o = obstacle_body(name); o > 0) {
      bodies.push_back(o);  // as name_of_body and the perceptual model name it
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
  held_.refresh_supports(*scene_, worker_.model(), worker_.data());
}

std::vector<char> MujocoSkillset::moved_bodies(const std::vector<int>& joints) const {
  const mjModel* m = worker_.model();
  std::vector<char> moved(m->nbody, 0);
  for (int j : joints) moved[m->jnt_bodyid[j]] = 1;
  for (int b = 1; b < m->nbody; ++b) {
    if (moved[m->body_parentid[b]]) moved[b] = 1;
  }
  for (const Attachment& a : held_.list()) {  // held objects move with their holders
    if (!moved[a.holder_body]) continue;
    for (int b = a.body; b < m->nbody && m->body_rootid[b] == a.body; ++b) moved[b] = 1;
  }
  return moved;
}

std::vector<double> MujocoSkillset::do_configuration(
    const std::vector<std::string>& chain_names) const {
  std::vector<double> values;
  for (int j : joints_of(chain_names))
    values.push_back(worker_.data()->qpos[servo_.joint(j).qpos_adr]);
  return values;
}

core::Pose MujocoSkillset::do_frame_pose(const std::string& frame) const {
  try {
    return mujoco::frame_pose(worker_.data(), resolve_frame(*scene_, worker_.data(), frame));
  } catch (const std::out_of_range&) {
    throw std::invalid_argument("no frame or object '" + frame + "' in robot " + profile().name +
                                " or environment " + scene_->environment().name);
  }
}

core::Pose MujocoSkillset::do_frame_pose_at(const std::vector<std::string>& chain_names,
                                            const std::vector<double>& values,
                                            const std::string& frame) {
  const std::vector<int> joints = joints_of(chain_names);
  const mjModel* m = worker_.model();
  BodyFrame resolved;
  try {
    resolved = resolve_frame(*scene_, worker_.data(), frame);
  } catch (const std::out_of_range&) {
    throw std::invalid_argument("no frame or object '" + frame + "'");
  }
  // Without held objects (which follow their holders), the bodies between the world and the
  // frame's body alone: the same numbers as the whole model's kinematics, bit for bit.
  if (held_.empty()) {
    if (!fk_path_ || fk_path_joints_ != joints || fk_path_body_ != resolved.body) {
      fk_path_.emplace(m, joints, resolved.body, true);
      fk_path_joints_ = joints;
      fk_path_body_ = resolved.body;
    }
    if (fk_path_->posable()) {
      fk_qpos_.assign(worker_.data()->qpos, worker_.data()->qpos + m->nq);
      for (size_t i = 0; i < joints.size(); ++i) {
        fk_qpos_[static_cast<size_t>(servo_.joint(joints[i]).qpos_adr)] = values[i];
      }
      fk_path_->update(worker_.data(), fk_qpos_.data());
      return fk_path_->frame_pose(resolved.offset);
    }
  }
  mjData* q = query_.get();
  sync_query();
  for (size_t i = 0; i < joints.size(); ++i) q->qpos[servo_.joint(joints[i]).qpos_adr] = values[i];
  mj_kinematics(m, q);
  if (!held_.empty()) {
    place_attachments(m, q, held_.list());
    mj_kinematics(m, q);
  }
  return mujoco::frame_pose(q, resolve_frame(*scene_, q, frame));
}

core::IkResult MujocoSkillset::do_solve_ik(const std::vector<std::string>& chain_names,
                                           const std::string& frame, const core::Pose& target,
                                           const core::IkOptions& options) {
  const std::vector<int> joints = joints_of(chain_names);
  const ObstacleBelief::Scope belief(belief_, worker_.model());
  refresh_supports();
  sync_query();
  return mujoco::solve_ik(*scene_, worker_.model(), query_.get(), joints, frame, target, options,
                          held_.list());
}

bool MujocoSkillset::do_is_valid(const std::vector<std::string>& chain_names,
                                 const std::vector<double>& values,
                                 const std::vector<std::string>& may_touch) {
  const std::vector<int> joints = joints_of(chain_names);
  // Resolved only when asked: object_geoms walks every geom, and is_valid runs per turning
  // period in fixate and per candidate elsewhere.
  const std::vector<int> touch = may_touch.empty() ? std::vector<int>{} : object_geoms(may_touch);
  const ObstacleBelief::Scope belief(belief_, worker_.model());
  refresh_supports();
  sync_query();
  ValidityChecker checker(*scene_, worker_.model(), query_.get(), joints, held_.list(), touch,
                          MotionPlanner::kTouchDepth);
  checker.keep_off_visitor_route();
  return !checker.in_collision(values.data());
}

double MujocoSkillset::do_clearance(const std::vector<std::string>& chain_names,
                                    const std::vector<double>& values, double max_distance_m) {
  const std::vector<int> joints = joints_of(chain_names);
  const ObstacleBelief::Scope belief(belief_, worker_.model());
  refresh_supports();
  sync_query();
  ValidityChecker checker(*scene_, worker_.model(), query_.get(), joints, held_.list());
  return checker.distance(values.data(), max_distance_m);
}

std::string MujocoSkillset::do_plan_options_error(const core::PlanOptions& options) const {
  try {
    object_geoms(options.may_touch);
  } catch (const std::invalid_argument& e) {
    return std::string("may_touch: ") + e.what();
  }
  return "";
}

core::PlanResult MujocoSkillset::do_plan(const std::vector<std::string>& chain_names,
                                         const std::vector<std::vector<double>>& goals,
                                         const core::PlanOptions& options) {
  const std::vector<int> joints = joints_of(chain_names);
  const ObstacleBelief::Scope belief(belief_, worker_.model());
  refresh_supports();
  sync_query();
  MotionPlanner planner(*scene_, worker_.model(), query_.get(), joints, held_.list(),
                        object_geoms(options.may_touch));
  return planner.plan(goals, options);
}

double MujocoSkillset::do_time() const { return worker_.data()->time; }

void MujocoSkillset::do_command(const std::vector<std::string>& chain_names,
                                const std::vector<double>& positions,
                                const std::vector<double>& velocities,
                                const std::vector<double>& accelerations) {
  const std::vector<int> joints = joints_of(chain_names);
  const mjModel* m = worker_.model();
  mjData* d = worker_.data();
  for (size_t i = 0; i < joints.size(); ++i) {
    const int j = joints[i];
    servo_.set_target(j, std::clamp(positions[i], m->jnt_range[2 * j], m->jnt_range[2 * j + 1]),
                      velocities.empty() ? 0.0 : velocities[i],
                      accelerations.empty() ? 0.0 : accelerations[i], d);
  }
}

void MujocoSkillset::set_configuration(const std::vector<std::string>& chain_names,
                                       const std::vector<double>& values) {
  command(chain_names, values);
  const std::vector<int> joints = joints_of(chain_names);
  mjData* d = worker_.data();
  for (size_t i = 0; i < joints.size(); ++i) {
    const ServoJoint& s = servo_.joint(joints[i]);
    d->qpos[s.qpos_adr] = s.target_pos;
    d->qvel[s.dof_adr] = 0;
  }
  const mjModel* m = worker_.model();
  if (!held_.empty()) {
    mj_kinematics(m, d);
    place_attachments(m, d, held_.list());
  }
  mj_forward(m, d);
  have_last_ = false;  // a placement, not motion
  have_accel_ = false;
  record_state_now();
}

int MujocoSkillset::do_state_size() const { return worker_.model()->nq; }

void MujocoSkillset::do_append_state(std::vector<float>& frames) const {
  const mjData* d = worker_.data();
  frames.insert(frames.end(), d->qpos, d->qpos + worker_.model()->nq);
}

void MujocoSkillset::monitor_period() {
  const mjModel* m = worker_.model();
  const mjData* d = worker_.data();
  core::WorkRecord& work = mutable_work();
  // Robot joints: positions, velocities, accelerations; end effectors: positions. The
  // buffers are members: no allocation per period once sized.
  cur_q_.clear();
  cur_v_.clear();
  cur_ee_.clear();
  moving_.clear();
  for (const ServoJoint& js : servo_.joints()) {
    cur_q_.push_back(d->qpos[js.qpos_adr]);
    cur_v_.push_back(d->qvel[js.dof_adr]);
    if (js.target_vel != 0) moving_.push_back(js.joint);
  }
  for (int s : ee_sites_)
    cur_ee_.insert(cur_ee_.end(), d->site_xpos + 3 * s, d->site_xpos + 3 * s + 3);
  for (int b : ee_bodies_) cur_ee_.insert(cur_ee_.end(), d->xpos + 3 * b, d->xpos + 3 * b + 3);
  if (have_last_) {
    double dq = 0;
    for (size_t i = 0; i < cur_q_.size(); ++i) {
      dq += (cur_q_[i] - last_q_[i]) * (cur_q_[i] - last_q_[i]);
    }
    work.path_length_joint += std::sqrt(dq);
    for (size_t i = 0; i + 2 < cur_ee_.size(); i += 3) {
      work.path_length_ee_m +=
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
      work.jerk_squared_sum += jerk_sq;
      ++work.jerk_samples;
    }
    std::swap(last_a_, cur_a_);
    have_accel_ = true;
  }
  std::swap(last_q_, cur_q_);
  std::swap(last_v_, cur_v_);
  std::swap(last_ee_, cur_ee_);
  have_last_ = true;
  if (clearance_every_ > 0 && !moving_.empty() && work.control_periods % clearance_every_ == 0) {
    // Against the world as it is (every obstacle, seen or not), not the robot's belief.
    sync_query();
    ValidityChecker checker(*scene_, m, query_.get(), moving_, held_.list());
    cur_q_.clear();
    for (int j : moving_) cur_q_.push_back(d->qpos[m->jnt_qposadr[j]]);
    work.min_clearance_m =
        std::min(work.min_clearance_m, checker.distance_to_world(cur_q_.data(), clearance_cap_m_));
    ++work.clearance_samples;
  }
}

void MujocoSkillset::step_physics() {
  mjModel* m = worker_.model();
  mjData* d = worker_.data();
  // Entered with the state current (mj_step1 or mj_forward ran at it): bias forces, mass
  // matrix and contacts are those of the present configuration.
  const double t_end = d->time + period_;
  pruning_.begin(m);
  for (int s = 0; s < substeps_; ++s) {
    // Targets are samples for the end of the period: run along the commanded velocity.
    servo_.actuate(m, d, t_end - (d->time + m->opt.timestep));
    mj_step2(m, d);  // actuation, accelerations, contact forces, integration
    pruning_.after_integration(m, d);
    world_.drive_visitor(m, d, d->time, held_);
    if (!held_.empty()) {
      mj_kinematics(m, d);
      place_attachments(m, d, held_.list());
    }
    pruning_.before_collision(m, d);
    // Kinematics, contacts, bias forces at the new state.
    if (own_contacts_) {
      contacts_.step1(m, d);
    } else {
      mj_step1(m, d);
    }
    ++mutable_work().contact_passes;
    mutable_work().contacts += d->ncon;
  }
  pruning_.end(m);
  servo_.hold_targets(d);
}

void MujocoSkillset::step_kinematic() {
  const mjModel* m = worker_.model();
  mjData* d = worker_.data();
  // The same clock as the physics (mj_step adds one timestep at a time).
  for (int s = 0; s < substeps_; ++s) d->time += m->opt.timestep;
  robot_qpos_before_.assign(d->qpos, d->qpos + m->nq);
  servo_.place_at_targets(d);
  world_.drive_visitor(m, d, d->time, held_);
  mj_kinematics(m, d);
  if (!held_.empty()) {
    place_attachments(m, d, held_.list());
    mj_kinematics(m, d);
  }
  if (stop_fingers_at_contact(robot_qpos_before_)) {
    mj_kinematics(m, d);
    if (!held_.empty()) {
      place_attachments(m, d, held_.list());
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
    for (const Attachment& a : held_.list()) {
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
  // Which geoms changed pose or collision bits since the last pass (all, with nothing cached).
  const int ngeom = m->ngeom;
  const bool cached = contact_pass_geoms_.size() == static_cast<size_t>(ngeom);
  contact_pass_geoms_.resize(static_cast<size_t>(ngeom));
  changed_geoms_.clear();
  for (int g = 0; g < ngeom; ++g) {
    GeomSnapshot now;
    std::copy(d->geom_xpos + 3 * g, d->geom_xpos + 3 * g + 3, now.pose.begin());
    std::copy(d->geom_xmat + 9 * g, d->geom_xmat + 9 * g + 9, now.pose.begin() + 3);
    now.contype = m->geom_contype[g];
    now.conaffinity = m->geom_conaffinity[g];
    GeomSnapshot& before = contact_pass_geoms_[static_cast<size_t>(g)];
    if (!cached || !(now == before)) changed_geoms_.push_back(g);
    before = now;
  }
  const std::vector<GeomPair>& robot_pairs = scene_->robot_geom_pairs();
  if (pairs_of_geom_.size() != static_cast<size_t>(ngeom)) {
    pairs_of_geom_.assign(static_cast<size_t>(ngeom), {});
    for (size_t k = 0; k < robot_pairs.size(); ++k) {
      pairs_of_geom_[static_cast<size_t>(robot_pairs[k].g1)].push_back(
          static_cast<std::uint32_t>(k));
      pairs_of_geom_[static_cast<size_t>(robot_pairs[k].g2)].push_back(
          static_cast<std::uint32_t>(k));
    }
  }
  if (!cached) {
    robot_pair_contacts_.assign(robot_pairs.size(), {});
    pairs_with_contacts_.clear();
    pair_pass_.assign(robot_pairs.size(), 0);
  }
  // The pairs with a changed geom are tested again; every other pair finds what it found.
  ++contact_pass_;
  mjContact found[mjMAXCONPAIR];
  for (const int g : changed_geoms_) {
    for (const std::uint32_t k : pairs_of_geom_[static_cast<size_t>(g)]) {
      if (pair_pass_[k] == contact_pass_) continue;
      pair_pass_[k] = contact_pass_;
      const GeomPair& p = robot_pairs[k];
      const int n = collide_geoms(m, d, p, p.margin, found);
      std::vector<mjContact>& last = robot_pair_contacts_[k];
      if (n == 0 && last.empty()) continue;
      last.assign(found, found + n);
      const auto at = std::lower_bound(pairs_with_contacts_.begin(), pairs_with_contacts_.end(), k);
      const bool listed = at != pairs_with_contacts_.end() && *at == k;
      if (n > 0 && !listed) pairs_with_contacts_.insert(at, k);
      if (n == 0 && listed) pairs_with_contacts_.erase(at);
    }
  }
  // In the order of the scene's pairs, then the held objects' pairs.
  d->ncon = 0;
  auto append = [&](const mjContact* contacts, size_t n) {
    for (size_t i = 0; i < n && d->ncon < m->nconmax; ++i) d->contact[d->ncon++] = contacts[i];
  };
  for (const std::uint32_t k : pairs_with_contacts_) {
    append(robot_pair_contacts_[k].data(), robot_pair_contacts_[k].size());
  }
  for (const GeomPair& p : held_pairs_) {
    const int n = collide_geoms(m, d, p, p.margin, found);
    append(found, static_cast<size_t>(n));
  }
  ++mutable_work().contact_passes;
  mutable_work().contacts += d->ncon;
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
  // Static geoms nothing movable comes near are closed, as in physics execution (exact; the
  // robot counts as movable though it cannot touch anything here).
  pruning_.begin(m);
  for (int s = 0; s < steps && !settled(); ++s) {
    pruning_.before_collision(m, d);
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
  pruning_.end(m);
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
    if (!held_.holds_body(body)) bodies.push_back(body);
  }
  if (!bodies.empty()) settle_objects(bodies);
}

core::StepReport MujocoSkillset::do_advance() {
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
  mutable_work().stepping_wall_s += std::chrono::duration<double>(t_monitor - t_step).count();
  monitor_period();
  mutable_work().monitoring_wall_s +=
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

std::vector<core::Collision> MujocoSkillset::do_collisions(
    const std::vector<std::string>& chain_names) const {
  const std::vector<char> moved = moved_bodies(joints_of(chain_names));
  const mjModel* m = worker_.model();
  const mjData* d = worker_.data();
  std::vector<core::Collision> out;
  auto part_name = [&](int body) {
    for (const Attachment& a : held_.list()) {
      if (m->body_rootid[body] == a.body) return a.object;
    }
    return body_name(m, body);
  };
  for (int i = 0; i < d->ncon; ++i) {
    const mjContact& c = d->contact[i];
    const int b1 = m->geom_bodyid[c.geom1], b2 = m->geom_bodyid[c.geom2];
    if (!moved[b1] && !moved[b2]) continue;
    if (!counts_as_robot_collision(*scene_, m, c, held_.list())) continue;
    const int mine = moved[b1] ? b1 : b2, other = moved[b1] ? b2 : b1;
    out.push_back({part_name(mine), name_of_body(other), -c.dist});
  }
  return out;
}

void MujocoSkillset::do_attach(const std::string& object, const std::string& side) {
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
  const core::HandSpec* hand = profile().find_hand(side);
  mjData* d = worker_.data();
  mj_forward(m, d);
  held_.add(
      attachment_at(*scene_, m, d, body, resolve_frame(*scene_, d, hand->palm).body, object, side));
  const Attachment& held = *held_.find(object);
  pruning_.set_held(body, true, held.hand_bodies);
  held_pairs_current_ = false;
  if (execution_ == ExecutionMode::kPhysics) {
    // The object no longer pushes back on the fingers (ContactPruning): they hold where they
    // closed rather than close on through it. (The palm body's own joint is the arm's.)
    for (const ServoJoint& s : servo_.joints()) {
      const int b = m->jnt_bodyid[s.joint];
      if (b != held.holder_body && std::find(held.hand_bodies.begin(), held.hand_bodies.end(), b) !=
                                       held.hand_bodies.end()) {
        servo_.set_target(s.joint, d->qpos[s.qpos_adr], 0, 0, d);
      }
    }
  }
  place_attachments(m, d, held_.list());
  mj_forward(m, d);
  if (execution_ == ExecutionMode::kKinematic) find_robot_contacts();
}

void MujocoSkillset::do_detach(const std::string& object) {
  const int body = held_.remove(object);
  if (body < 0) throw std::invalid_argument("object '" + object + "' is not attached");
  pruning_.set_held(body, false);
  held_pairs_current_ = false;
  if (execution_ == ExecutionMode::kKinematic) settle_objects({body});
  mj_forward(worker_.model(), worker_.data());
  if (execution_ == ExecutionMode::kKinematic) find_robot_contacts();
}

std::vector<std::string> MujocoSkillset::do_attached_objects() const { return held_.objects(); }

std::string MujocoSkillset::do_holder_of(const std::string& object) const {
  const Attachment* a = held_.find(object);
  return a ? a->side : "";
}

int MujocoSkillset::obstacle_body(const std::string& name) const {
  const int slot = obstacle_slot_named(name);
  const std::vector<ObstacleSlot>& slots = scene_->obstacle_slots();
  return slot >= 0 && static_cast<size_t>(slot) < slots.size()
             ? slots[static_cast<size_t>(slot)].body
             : -1;
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
    if (slots[s].body == body) return obstacle_name(static_cast<int>(s));
  }
  return body_name(m, body);
}

std::vector<std::string> MujocoSkillset::do_touching(const std::string& part) const {
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
