#include "harness/replay/replay.h"

#include <algorithm>

#include "harness/backends/backends.h"
#include "harness/results/trial_record.h"
#include "taskmatrix/core/input_error.h"
#include "taskmatrix/mujoco/mujoco_backend.h"

namespace taskmatrix::harness {

std::filesystem::path trajectory_of(const std::string& run_dir_and_trial) {
  const size_t colon = run_dir_and_trial.rfind(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == run_dir_and_trial.size()) {
    throw core::InputError("--trial", "",
                           "expected RUN_DIR:TRIAL_ID, not '" + run_dir_and_trial + "'");
  }
  const std::filesystem::path dir = run_dir_and_trial.substr(0, colon);
  const std::string id = run_dir_and_trial.substr(colon + 1);
  const std::filesystem::path trials = dir / "trials.jsonl";
  std::error_code ec;
  if (!std::filesystem::exists(trials, ec)) {
    throw core::InputError(trials.string(), "", "no such file: not a run directory");
  }
  for (const nlohmann::json& t : read_trials_file(trials).trials) {
    if (t.value("trial_id", std::string()) != id) continue;
    const auto rel = t.find("trajectory");
    if (rel == t.end() || !rel->is_string()) {
      throw core::InputError(trials.string(), id,
                             "the trial has no recorded trajectory (status " +
                                 t.value("status", std::string("?")) + ")");
    }
    return dir / rel->get<std::string>();
  }
  throw core::InputError(trials.string(), id, "no trial with this id");
}

Replay::Replay(const ModelCatalog& catalog, TrajectoryFile trajectory)
    : trajectory_(std::move(trajectory)),
      scene_(mujoco::scene_of(*backend().load(catalog.robot_dir(trajectory_.robot),
                                              catalog.environment_dir(trajectory_.environment)))),
      worker_(scene_) {
  if (trajectory_.recording.nq != worker_.model()->nq) {
    throw core::InputError("trajectory", "nq",
                           "recorded with " + std::to_string(trajectory_.recording.nq) +
                               " positions but the model has " +
                               std::to_string(worker_.model()->nq) +
                               " (the robot or environment changed since)");
  }
  worker_.apply(core::TrialLayout{trajectory_.variation, trajectory_.layout});
  for (const std::string& name : trajectory_.removed_bodies) {
    const int body = mj_name2id(worker_.model(), mjOBJ_BODY, name.c_str());
    if (body < 0) throw core::InputError("trajectory", "removals", "no body '" + name + "'");
    removed_body_ids_.push_back(body);
    removed_body_z_.push_back(worker_.model()->body_pos[3 * body + 2]);
  }
}

size_t Replay::frame_at(double t) const {
  const std::vector<double>& times = trajectory_.recording.times;
  if (times.empty()) return 0;
  const auto it = std::lower_bound(times.begin(), times.end(), t);
  if (it == times.end()) return times.size() - 1;
  const size_t k = static_cast<size_t>(it - times.begin());
  return k > 0 && t - times[k - 1] < *it - t ? k - 1 : k;
}

void Replay::show(size_t frame) {
  const core::StateRecording& r = trajectory_.recording;
  if (frame >= r.frames()) throw std::out_of_range("replay frame out of range");
  mjModel* m = worker_.model();
  mjData* d = worker_.data();
  for (int i = 0; i < r.nq; ++i) {
    d->qpos[i] = r.qpos[frame * static_cast<size_t>(r.nq) + static_cast<size_t>(i)];
  }
  // Quaternions lost precision as float: normalise them for rendering.
  mj_normalizeQuat(m, d->qpos);
  for (size_t k = 0; k < removed_body_ids_.size(); ++k) {
    const bool gone = r.removals[k].time_s <= r.times[frame] + 1e-9;
    m->body_pos[3 * removed_body_ids_[k] + 2] = removed_body_z_[k] - (gone ? 10.0 : 0.0);
  }
  d->time = r.times[frame];
  mj_forward(m, d);
}

}  // namespace taskmatrix::harness
