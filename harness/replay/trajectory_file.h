// The executed trajectory of a trial, kept in the run directory for replay and rendering
// without re-planning: `trajectories/<trial id>.traj.gz`.
//
// Format (gzip): a text line "taskmatrix-trajectory 1", a line of JSON (robot, environment,
// the obstacle layout as placed, the task variation (moved surfaces, placed objects, the
// robot's start; absent in files from before variations), nq, frame period, frame count, frame
// times, debris removals), then the frames: nq little-endian float32 values each, every frame but
// the first stored as the XOR of its bit patterns with the previous frame's (what does not move
// compresses to nothing). A 20 s trial of tallbot in the kitchen takes a few tens of kilobytes.
#pragma once

#include <filesystem>
#include <string>

#include "taskmatrix/core/obstacle_layout.h"
#include "taskmatrix/core/state_recording.h"
#include "taskmatrix/core/task_variation.h"

namespace taskmatrix::harness {

struct TrajectoryFile {
  std::string robot, environment;
  core::ObstacleLayout layout;
  core::StateRecording recording;
  std::vector<std::string> removed_bodies;  // body names, parallel to recording.removals
  core::TaskVariation variation{};          // empty: nothing varied
};

// Writes atomically (a temporary file renamed into place). Throws std::runtime_error.
void write_trajectory_file(const std::filesystem::path& file, const TrajectoryFile& trajectory);
// Throws core::InputError naming the file for a missing, truncated or malformed file.
TrajectoryFile read_trajectory_file(const std::filesystem::path& file);

}  // namespace taskmatrix::harness
