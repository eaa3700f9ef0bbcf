// Pictures of a recorded trial (harness/replay/replay.h), without re-planning: a PNG snapshot in
// memory (for reports) and an H.264 MP4 of the whole trial, encoded by ffmpeg (the Debian
// package) from raw RGB frames drawn by the scene's backend (core/scene_view.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "harness/report/failure_pictures.h"
#include "harness/scenario/model_catalog.h"
#include "taskmatrix/core/scene_view.h"

namespace taskmatrix::harness {

// The view for a `--camera` value: "" is the environment's first camera ("free" when it has
// none), "head" the robot's head camera, "free" the default free camera (looking at
// (0.4, 0, 0.8) from 3.6 m, azimuth 210, elevation -22 degrees), "lookat:X,Y,Z[,D[,AZ[,EL]]]"
// a free camera looking at world point (X, Y, Z) from D metres (default 1.5) at azimuth AZ
// and elevation EL in degrees (defaults 210 and -25: from the robot's front, +x, a little
// above), anything else a camera of the model by name. Sets `camera` to the name used (for
// "": the camera chosen). Throws core::InputError("--camera") naming the known cameras for an
// unknown one, and for a malformed lookat.
core::Camera camera_view(const core::SceneView& view, std::string& camera);

// "lookat:X,Y,Z,D,AZ,EL" for a free camera, as camera_view reads it.
std::string lookat_camera_text(const core::Camera& camera);

struct FrameOptions {
  std::string camera;  // "" = the environment's first camera (as `render` does), "head", "free"
                       // or a camera name
  int width = 640, height = 480;
};

// PNG file bytes (lodepng encode to memory) of the recorded trial's frame nearest simulated
// time `time_s` (< 0: the last frame). `run_dir_and_trial` is "RUN_DIR:TRIAL_ID". Throws
// core::InputError for an unknown trial, a trial without a trajectory, an unknown camera or a
// size outside the model's offscreen buffer.
std::vector<std::uint8_t> trial_snapshot_png(const ModelCatalog& catalog,
                                             const std::string& run_dir_and_trial, double time_s,
                                             const FrameOptions& options);

// The recorded frame nearest `time_s` (< 0: the last), drawn twice: through options.camera and
// through a free camera 0.7 m from the focus, looking down 25 degrees from the far side of the
// focus as seen from the robot's base, turned 35 degrees; where that camera would not see the
// focus (a visible geom on the line of sight more than 15 cm short of it, the camera inside
// furniture or under the floor), turned further (-35, +-70, +-105, +-140, 180 degrees), then
// looking down 45 and 65 degrees; the first that sees it. The focus is a held or handled
// object (one that moved during the trial and is within 15 cm of a palm at that moment, at
// their midpoint), else the palm that moved most in the 2 s before (over the whole trial
// when none moved 1 cm). Throws as trial_snapshot_png.
FailurePictures failure_pictures(const ModelCatalog& catalog, const std::string& run_dir_and_trial,
                                 double time_s, const FrameOptions& options);

struct VideoOptions {
  FrameOptions frame;
  double fps = 25;     // output frame rate; frames are the recording's frames resampled to this
                       // rate in simulated time
  double speed = 1.0;  // simulated seconds per video second
};

struct VideoInfo {
  size_t frames = 0;      // frames in the video
  double duration_s = 0;  // of the video: frames / fps
  std::string camera;     // the camera used (the name chosen for "")
};

// Encodes the whole trial as H.264 MP4 (yuv420p, even width/height) by piping raw RGB frames
// to ffmpeg. Video frame k shows the recorded frame nearest simulated time
// t0 + k * speed / fps, for every such time up to the recording's last (t0: its first).
// Throws core::InputError naming the argument ("--video", "--fps", "--speed", "--width",
// "--height", "--camera", "--trial" or the run's trials.jsonl) when ffmpeg is missing from
// PATH, when the output directory does not exist, for bad options or an unknown trial, and
// when ffmpeg fails (with the last line of its stderr). Never leaves a partial `out` behind:
// the video is encoded to a temporary name in the same folder and renamed into place.
VideoInfo write_trial_video(const ModelCatalog& catalog, const std::string& run_dir_and_trial,
                            const std::filesystem::path& out, const VideoOptions& options);

}  // namespace taskmatrix::harness
