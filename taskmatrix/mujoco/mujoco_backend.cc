#include "taskmatrix/mujoco/mujoco_backend.h"

#include <cstdio>
#include <optional>
#include <stdexcept>

#include "taskmatrix/mujoco/ground_truth_perception.h"
#include "taskmatrix/mujoco/head_sensor.h"
#include "taskmatrix/mujoco/mujoco_view.h"
#include "taskmatrix/mujoco/robot_check.h"

namespace taskmatrix::mujoco {

namespace {

SimulationOptions simulation_options(const std::string& execution) {
  SimulationOptions simulation;
  if (execution == "physics") {
    simulation.execution = ExecutionMode::kPhysics;
  } else if (execution == "kinematic") {
    simulation.execution = ExecutionMode::kKinematic;
  } else if (execution == "physics_unpruned") {
    simulation.execution = ExecutionMode::kPhysics;
    simulation.pruning = {false, false};
    simulation.sparse_jacobian = false;
    simulation.candidate_pairs = false;
  } else {
    throw std::invalid_argument("unknown execution mode '" + execution +
                                "' (physics, kinematic or physics_unpruned)");
  }
  return simulation;
}

}  // namespace

MujocoTrialWorld::MujocoTrialWorld(std::shared_ptr<const Scene> scene,
                                   const core::TrialLayout& layout,
                                   const core::TrialWorldOptions& options)
    : skills_(std::move(scene), simulation_options(options.execution)) {
  skills_.apply_layout(layout);
  if (options.record_rate_hz > 0) skills_.record_states(options.record_rate_hz);
  skills_.set_visitor_walk(options.visitor_speed_mps);
}

std::unique_ptr<core::Perception> MujocoTrialWorld::make_perception(const std::string& kind) {
  if (kind == "ground_truth") return std::make_unique<GroundTruthPerception>(skills_);
  if (kind == "sensor") return std::make_unique<SensorPerception>(skills_);
  throw std::invalid_argument("unknown perception '" + kind + "' (ground_truth or sensor)");
}

std::vector<std::string> MujocoTrialWorld::removed_objects() const {
  std::vector<std::string> names;
  for (int body : skills_.removed_debris()) {
    const char* name = mj_id2name(skills_.model(), mjOBJ_BODY, body);
    names.push_back(name ? name : "body " + std::to_string(body));
  }
  return names;
}

MujocoLoadedScene::MujocoLoadedScene(std::shared_ptr<const Scene> scene)
    : scene_(std::move(scene)) {
  if (!scene_) throw std::invalid_argument("MujocoLoadedScene: no scene");
}

core::TrialLayout MujocoLoadedScene::make_trial_layout(const core::ObstacleOptions& obstacles,
                                                       const core::VariationOptions& variation,
                                                       std::uint64_t seed) const {
  // A drawn start is clear when the robot, at rest there, touches nothing of the varied world
  // (the rule start_contacts applies to the whole layout).
  auto start_clear = [&](const core::TaskVariation& v) -> std::optional<std::string> {
    core::TrialLayout probe;
    probe.variation = v;
    const std::lock_guard<std::mutex> lock(probe_mutex_);
    const core::StartContact* deepest = nullptr;
    const std::vector<core::StartContact> contacts = contacts_at_start(probe);
    for (const core::StartContact& c : contacts) {
      if (c.robot && (!deepest || c.depth_m > deepest->depth_m)) deepest = &c;
    }
    if (!deepest) return std::nullopt;
    char depth[32];
    std::snprintf(depth, sizeof depth, "%.1f", deepest->depth_m * 1000);
    return deepest->first + " touches " + deepest->second + " (depth " + depth + " mm)";
  };
  return scene_->make_trial_layout(obstacles, variation, seed, start_clear);
}

std::vector<core::StartContact> MujocoLoadedScene::start_contacts(
    const core::TrialLayout& layout) const {
  const std::lock_guard<std::mutex> lock(probe_mutex_);
  return contacts_at_start(layout);
}

std::vector<core::StartContact> MujocoLoadedScene::contacts_at_start(
    const core::TrialLayout& layout) const {
  if (!probe_) probe_ = std::make_unique<WorkerScene>(scene_);
  WorkerScene& worker = *probe_;
  worker.apply(layout);
  worker.reset_to_start();
  const mjModel* m = worker.model();
  const mjData* d = worker.data();
  auto name = [&](int geom) {
    const char* n = mj_id2name(m, mjOBJ_GEOM, geom);
    return n ? std::string(n) : "geom " + std::to_string(geom);
  };
  auto is_obstacle = [&](int geom) {
    for (const ObstacleSlot& slot : scene_->obstacle_slots()) {
      if (m->geom_bodyid[geom] == slot.body) return true;
    }
    return false;
  };
  std::vector<core::StartContact> contacts;
  for (int i = 0; i < d->ncon; ++i) {
    const mjContact& c = d->contact[i];
    const bool robot = scene_->is_robot_geom(c.geom1) || scene_->is_robot_geom(c.geom2);
    if (!robot && c.dist >= -0.001) continue;
    contacts.push_back({name(c.geom1), name(c.geom2), -c.dist, robot,
                        is_obstacle(c.geom1) || is_obstacle(c.geom2)});
  }
  return contacts;
}

std::unique_ptr<core::TrialWorld> MujocoLoadedScene::make_trial_world(
    const core::TrialLayout& layout, const core::TrialWorldOptions& options) const {
  return std::make_unique<MujocoTrialWorld>(scene_, layout, options);
}

std::unique_ptr<core::SceneView> MujocoLoadedScene::make_view(
    const core::TrialLayout& layout) const {
  return std::make_unique<MujocoView>(scene_, layout);
}

std::string MujocoBackend::version() const {
  const int v = mj_version();
  return std::to_string(v / 100) + "." + std::to_string(v / 10 % 10) + "." + std::to_string(v % 10);
}

std::shared_ptr<const core::LoadedScene> MujocoBackend::load(
    const std::filesystem::path& robot_dir, const std::filesystem::path& environment_dir) const {
  return std::make_shared<MujocoLoadedScene>(Scene::load(robot_dir, environment_dir));
}

namespace {

void (*g_fatal_error_handler)(const char*) = nullptr;

void report_mujoco_error(const char* message) {
  g_fatal_error_handler((std::string("MuJoCo error: ") + message).c_str());
}

}  // namespace

void MujocoBackend::on_fatal_error(void (*handler)(const char* message)) const {
  g_fatal_error_handler = handler;
  mju_user_error = handler ? report_mujoco_error : nullptr;
}

std::vector<core::RobotFinding> MujocoBackend::check_robot(
    const core::LoadedScene& home,
    const std::vector<std::shared_ptr<const core::LoadedScene>>& everywhere) const {
  std::vector<std::shared_ptr<const Scene>> scenes;
  for (const auto& loaded : everywhere) scenes.push_back(scene_of(*loaded));
  std::vector<core::RobotFinding> findings = check_robot_kinematics(*scene_of(home));
  for (core::RobotFinding& f : check_reach_envelope(scenes)) findings.push_back(std::move(f));
  return findings;
}

const std::shared_ptr<const Scene>& scene_of(const core::LoadedScene& scene) {
  const auto* mujoco_scene = dynamic_cast<const MujocoLoadedScene*>(&scene);
  if (!mujoco_scene) throw std::invalid_argument("not a scene of the MuJoCo backend");
  return mujoco_scene->scene();
}

}  // namespace taskmatrix::mujoco
