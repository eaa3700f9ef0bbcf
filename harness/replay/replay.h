// Replaying a recorded trial (harness/replay/trajectory_file.h) without re-planning: the run
// directory's trials.jsonl says which trajectory file holds a trial; the file holds the
// layout and the simulated state at a fixed rate.
#pragma once

#include <filesystem>
#include <string>

#include "harness/replay/trajectory_file.h"
#include "harness/scenario/model_catalog.h"
#include "taskmatrix/mujoco/scene.h"

namespace taskmatrix::harness {

// "RUN_DIR:TRIAL_ID" -> the trial's trajectory file. Throws core::InputError naming the
// run directory's trials.jsonl when the trial or its trajectory is not there.
std::filesystem::path trajectory_of(const std::string& run_dir_and_trial);

// A replay of one recorded trial on its own worker copy of the scene.
class Replay {
 public:
  Replay(const ModelCatalog& catalog, TrajectoryFile trajectory);
  size_t frames() const { return trajectory_.recording.frames(); }
  double time_of(size_t frame) const { return trajectory_.recording.times.at(frame); }
  // The frame nearest simulated time t.
  size_t frame_at(double t) const;
  // Sets the worker's state to the frame (positions, removed debris), then mj_forward.
  void show(size_t frame);
  mujoco::WorkerScene& worker() { return worker_; }
  const mujoco::Scene& scene() const { return *scene_; }

 private:
  TrajectoryFile trajectory_;
  std::shared_ptr<const mujoco::Scene> scene_;
  mujoco::WorkerScene worker_;
  std::vector<int> removed_body_ids_;
  std::vector<double> removed_body_z_;  // as compiled
};

}  // namespace taskmatrix::harness
