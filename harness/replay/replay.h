// Replaying a recorded trial (harness/replay/trajectory_file.h) without re-planning: the run
// directory's trials.jsonl says which trajectory file holds a trial; the file holds the
// layout and the simulated state at a fixed rate.
#pragma once

#include <filesystem>
#include <memory>
#include <string>

#include "harness/replay/trajectory_file.h"
#include "harness/scenario/model_catalog.h"
#include "taskmatrix/core/backend.h"

namespace taskmatrix::harness {

// "RUN_DIR:TRIAL_ID" -> the trial's trajectory file. Throws core::InputError naming the
// run directory's trials.jsonl when the trial or its trajectory is not there.
std::filesystem::path trajectory_of(const std::string& run_dir_and_trial);

// A replay of one recorded trial through a view of its scene (core/scene_view.h), from the
// backend that recorded it.
class Replay {
 public:
  Replay(const ModelCatalog& catalog, TrajectoryFile trajectory);
  size_t frames() const { return trajectory_.recording.frames(); }
  double time_of(size_t frame) const { return trajectory_.recording.times.at(frame); }
  // The frame nearest simulated time t.
  size_t frame_at(double t) const;
  // Shows the frame's state in the view (positions, debris removed by then). Throws
  // core::InputError("trajectory", "removals") for a removed object the scene lacks.
  void show(size_t frame);
  core::SceneView& view() { return *view_; }
  const core::LoadedScene& scene() const { return *scene_; }

 private:
  TrajectoryFile trajectory_;
  std::shared_ptr<const core::LoadedScene> scene_;
  std::unique_ptr<core::SceneView> view_;
};

}  // namespace taskmatrix::harness
