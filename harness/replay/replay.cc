#include "harness/replay/replay.h"

#include <algorithm>
#include <span>
#include <stdexcept>

#include "harness/backends/backends.h"
#include "harness/results/trial_record.h"
#include "taskmatrix/core/input_error.h"

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
      scene_(backend().load(catalog.robot_dir(trajectory_.robot),
                            catalog.environment_dir(trajectory_.environment))),
      view_(scene_->make_view(core::TrialLayout{trajectory_.variation, trajectory_.layout})) {
  if (trajectory_.recording.nq != view_->state_size()) {
    throw core::InputError("trajectory", "nq",
                           "recorded with " + std::to_string(trajectory_.recording.nq) +
                               " positions but the model has " +
                               std::to_string(view_->state_size()) +
                               " (the robot or environment changed since)");
  }
  if (trajectory_.removed_bodies.size() != trajectory_.recording.removals.size()) {
    throw core::InputError("trajectory", "removals",
                           "names " + std::to_string(trajectory_.removed_bodies.size()) +
                               " removed bodies for " +
                               std::to_string(trajectory_.recording.removals.size()) +
                               " removals");
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
  std::vector<std::string> removed;
  for (size_t k = 0; k < r.removals.size(); ++k) {
    if (r.removals[k].time_s <= r.times[frame] + 1e-9) {
      removed.push_back(trajectory_.removed_bodies[k]);
    }
  }
  const size_t nq = static_cast<size_t>(r.nq);
  try {
    view_->show_state(std::span<const float>(r.qpos).subspan(frame * nq, nq), r.times[frame],
                      removed);
  } catch (const std::out_of_range& e) {
    throw core::InputError("trajectory", "removals", e.what());
  }
}

}  // namespace taskmatrix::harness
