// Videos and snapshots of a recorded trial: what a user gets from `taskmatrix render --trial
// RUN:ID --video F.mp4` (checked with ffprobe) and what a report gets in memory (a PNG), and
// the errors: an unknown trial, a missing output folder, ffmpeg missing or failing.
#include <gtest/gtest.h>
#include <lodepng.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <numbers>
#include <regex>
#include <set>

#include <nlohmann/json.hpp>

#include "harness/replay/replay.h"
#include "harness/replay/trajectory_file.h"
#include "harness/replay/trial_video.h"
#include "harness/results/trial_record.h"
#include "taskmatrix/core/input_error.h"
#include "taskmatrix/mujoco/ground_truth_perception.h"
#include "taskmatrix/mujoco/mujoco_view.h"
#include "taskmatrix/mujoco/offscreen_renderer.h"
#include "tests/test_support.h"

namespace taskmatrix::harness {
namespace {

// $PATH replaced while alive.
class PathSetting {
 public:
  explicit PathSetting(const std::string& path) {
    const char* old = std::getenv("PATH");
    had_ = old != nullptr;
    if (had_) old_ = old;
    setenv("PATH", path.c_str(), 1);
  }
  ~PathSetting() {
    if (had_) {
      setenv("PATH", old_.c_str(), 1);
    } else {
      unsetenv("PATH");
    }
  }
  PathSetting(const PathSetting&) = delete;
  PathSetting& operator=(const PathSetting&) = delete;

 private:
  bool had_ = false;
  std::string old_;
};

std::string shell_arg(const std::filesystem::path& p) { return "'" + p.string() + "'"; }

// ffprobe's view of the first video stream (frames counted by decoding).
nlohmann::json probe(const std::filesystem::path& video) {
  const std::string command =
      "ffprobe -v error -select_streams v:0 -count_frames -show_entries "
      "stream=codec_name,width,height,pix_fmt,nb_read_frames -of json " +
      shell_arg(video);
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return {};
  std::string text;
  char buffer[4096];
  for (size_t n; (n = fread(buffer, 1, sizeof buffer, pipe)) > 0;) text.append(buffer, n);
  pclose(pipe);
  const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
  if (j.is_discarded() || !j.contains("streams") || j["streams"].empty()) return {};
  return j["streams"][0];
}

long long read_frames(const nlohmann::json& stream) {
  return std::stoll(stream.value("nb_read_frames", std::string("-1")));
}

// Files in a folder (hidden ones included: a left-over partial video would show).
std::set<std::string> files_in(const std::filesystem::path& dir) {
  std::set<std::string> out;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    out.insert(e.path().filename().string());
  }
  return out;
}

// One short recorded trial (minibot raises its arm in the kitchen), run once through the CLI
// for the whole suite.
class TrialVideo : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    char tmpl[] = "/tmp/taskmatrix_video_XXXXXX";
    dir_ = new std::filesystem::path(mkdtemp(tmpl));
    std::ofstream(*dir_ / "wave.yaml")
        << "program: postural\nparams: {posture: wave_start, side: as_named}\n"
           "robots: [minibot]\nenvironments: [kitchen]\nobstacles: {count: 2}\n"
           "time_limit_s: 20\n";
    const test::CommandResult r =
        test::run_cli("run " + shell_arg(*dir_ / "wave.yaml") + " --out " +
                          shell_arg(*dir_ / "run") + " --progress off",
                      test::catalog().root());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto trials = read_trials_file(*dir_ / "run" / "trials.jsonl").trials;
    ASSERT_EQ(trials.size(), 1u);
    id_ = new std::string(trials[0]["trial_id"].get<std::string>());
  }
  static void TearDownTestSuite() {
    std::filesystem::remove_all(*dir_);
    delete dir_;
    delete id_;
  }
  void SetUp() override {
    ASSERT_NE(id_, nullptr) << "the trial was not recorded";
    out_ = *dir_ / ::testing::UnitTest::GetInstance()->current_test_info()->name();
    std::filesystem::create_directories(out_);
  }
  static std::string trial() { return (*dir_ / "run").string() + ":" + *id_; }
  // Simulated seconds from the first recorded frame to the last.
  static double recorded_duration() {
    const TrajectoryFile t = read_trajectory_file(trajectory_of(trial()));
    return t.recording.times.back() - t.recording.times.front();
  }

  static std::filesystem::path* dir_;
  static std::string* id_;
  std::filesystem::path out_;  // this test's own output folder
};
std::filesystem::path* TrialVideo::dir_ = nullptr;
std::string* TrialVideo::id_ = nullptr;

TEST_F(TrialVideo, VideoHasTheAskedSizeAndOneFramePerTickOfSimulatedTime) {
  const double duration = recorded_duration();
  ASSERT_GT(duration, 1.0);
  const auto video = out_ / "wave it.mp4";  // a space: no shell between us and ffmpeg
  const test::CommandResult cli =
      test::run_cli("render --trial " + shell_arg(trial()) + " --video " + shell_arg(video) +
                        " --width 320 --height 240 --fps 25",
                    test::catalog().root());
  ASSERT_EQ(cli.exit_code, 0) << cli.err;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(
      cli.out, m,
      std::regex(R"(wave it\.mp4: trial .+, (\d+) frames at 25 fps \(([0-9.]+) s\), )"
                 R"(camera (\w+)\n$)")))
      << cli.out;
  const nlohmann::json s = probe(video);
  EXPECT_EQ(s.value("codec_name", ""), "h264") << s;
  EXPECT_EQ(s.value("pix_fmt", ""), "yuv420p") << s;
  EXPECT_EQ(s.value("width", 0), 320) << s;
  EXPECT_EQ(s.value("height", 0), 240) << s;
  EXPECT_NEAR(static_cast<double>(read_frames(s)), duration * 25, 1.0) << s;
  EXPECT_EQ(std::to_string(read_frames(s)), m[1].str());
  EXPECT_NEAR(std::stod(m[2].str()), static_cast<double>(read_frames(s)) / 25, 0.006);
  EXPECT_EQ(m[3].str(), "overview") << "the kitchen's first camera";

  // In-process, twice as fast at 10 fps through the head camera.
  VideoOptions options;
  options.frame = {"head", 160, 120};
  options.fps = 10;
  options.speed = 2;
  const VideoInfo info = write_trial_video(test::catalog(), trial(), out_ / "fast.mp4", options);
  EXPECT_EQ(info.camera, "head");
  EXPECT_NEAR(static_cast<double>(info.frames), duration / 2 * 10, 1.0);
  EXPECT_DOUBLE_EQ(info.duration_s, static_cast<double>(info.frames) / 10);
  const nlohmann::json fast = probe(out_ / "fast.mp4");
  EXPECT_EQ(read_frames(fast), static_cast<long long>(info.frames)) << fast;
  EXPECT_EQ(fast.value("width", 0), 160) << fast;
  // Nothing else was left in the folder.
  EXPECT_EQ(files_in(out_), (std::set<std::string>{"wave it.mp4", "fast.mp4"}));
}

TEST_F(TrialVideo, SnapshotIsAPngOfTheAskedSizeShowingTheScene) {
  const FrameOptions options{"", 321, 241};  // a PNG may have odd sides
  const std::vector<std::uint8_t> last = trial_snapshot_png(test::catalog(), trial(), -1, options);
  const std::uint8_t signature[] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  ASSERT_GT(last.size(), sizeof signature);
  EXPECT_TRUE(std::equal(signature, signature + sizeof signature, last.begin()));
  std::vector<unsigned char> rgb;
  unsigned width = 0, height = 0;
  ASSERT_EQ(lodepng::decode(rgb, width, height, last, LCT_RGB, 8), 0u);
  EXPECT_EQ(width, 321u);
  EXPECT_EQ(height, 241u);
  std::set<std::uint32_t> colours;
  for (size_t i = 0; i + 2 < rgb.size(); i += 3) {
    colours.insert(static_cast<std::uint32_t>(rgb[i] << 16 | rgb[i + 1] << 8 | rgb[i + 2]));
  }
  EXPECT_GT(colours.size(), 100u) << "a picture of the scene, not a blank";
  // The arm moved: the first frame is another picture.
  EXPECT_NE(trial_snapshot_png(test::catalog(), trial(), 0.0, options), last);
  // An unknown camera is named.
  try {
    trial_snapshot_png(test::catalog(), trial(), -1, {"nope", 64, 48});
    FAIL() << "an unknown camera was accepted";
  } catch (const core::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--camera: unknown camera 'nope'"), std::string::npos)
        << e.what();
  }
}

TEST_F(TrialVideo, FailurePicturesAddACloseUpThatALookatCameraReproduces) {
  const FrameOptions options{"", 160, 120};
  const FailurePictures p = failure_pictures(test::catalog(), trial(), -1, options);
  EXPECT_EQ(p.overview, trial_snapshot_png(test::catalog(), trial(), -1, options));
  ASSERT_FALSE(p.close_up.empty());
  EXPECT_NE(p.close_up, p.overview);
  EXPECT_GT(p.time_s, 0);
  EXPECT_FALSE(p.focus.empty());
  // The close-up is a --camera value: rendering through it gives the same picture.
  ASSERT_EQ(p.close_up_camera.rfind("lookat:", 0), 0u) << p.close_up_camera;
  EXPECT_EQ(p.close_up,
            trial_snapshot_png(test::catalog(), trial(), -1, {p.close_up_camera, 160, 120}));
  // A malformed lookat names the option and the expected form.
  for (const std::string bad : {"lookat:1,2", "lookat:1,x,3", "lookat:0,0,1,-1"}) {
    try {
      trial_snapshot_png(test::catalog(), trial(), -1, {bad, 64, 48});
      FAIL() << bad << " was accepted";
    } catch (const core::InputError& e) {
      EXPECT_NE(std::string(e.what()).find("--camera: '" + bad + "'"), std::string::npos)
          << e.what();
    }
  }
}

// minibot fails its reach at once (no plan within 1 iteration): the close-up aims at its left
// palm at rest, beside the kitchen counter. The first camera tried (turned 35 degrees) would
// sit inside the counter's top slab, with its handle across the view; the one chosen is in no
// geom and sees the palm.
TEST(FailureCloseUp, TheCameraIsInNothingAndSeesItsFocus) {
  char tmpl[] = "/tmp/taskmatrix_closeup_XXXXXX";
  const std::filesystem::path dir = mkdtemp(tmpl);
  std::ofstream(dir / "stuck.yaml")
      << "program: reach\nparams: {object: cup}\nrobots: [minibot]\nenvironments: [kitchen]\n"
         "execution: kinematic\nobstacles: {count: 0}\nplan_iterations: 1\ntime_limit_s: 10\n";
  const test::CommandResult r = test::run_cli("run " + shell_arg(dir / "stuck.yaml") + " --out " +
                                                  shell_arg(dir / "run") + " --progress off",
                                              test::catalog().root());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto trials = read_trials_file(dir / "run" / "trials.jsonl").trials;
  ASSERT_EQ(trials.size(), 1u);
  // No plan within 1 iteration: OMPL reports a timeout or its approximate solution.
  const std::string status = trials[0]["status"];
  ASSERT_TRUE(status == "planning_timeout" || status == "approximate_solution")
      << trials[0]["failure_reason"];
  const std::string trial = (dir / "run").string() + ":" + trials[0]["trial_id"].get<std::string>();

  const FailurePictures p = failure_pictures(test::catalog(), trial, -1, {"", 160, 120});
  EXPECT_NE(p.focus.find("left hand"), std::string::npos) << p.focus;
  Replay replay(test::catalog(), read_trajectory_file(trajectory_of(trial)));
  replay.show(replay.frames() - 1);
  std::string camera = p.close_up_camera;
  const core::Camera view = camera_view(replay.view(), camera);
  const double az = view.azimuth * std::numbers::pi / 180;
  const double el = view.elevation * std::numbers::pi / 180;
  const Eigen::Vector3d eye =
      view.lookat - view.distance * Eigen::Vector3d(std::cos(el) * std::cos(az),
                                                    std::cos(el) * std::sin(az), std::sin(el));
  // Not inside the bounding box of any geom drawn (the counter's slab among them).
  const mujoco::WorkerScene& worker =
      dynamic_cast<const mujoco::MujocoView&>(replay.view()).worker();
  const mjModel* m = worker.model();
  for (int g = 0; g < m->ngeom; ++g) {
    if (m->geom_group[g] > 2 || m->geom_type[g] == mjGEOM_PLANE) continue;
    const Eigen::AlignedBox3d box = mujoco::geom_box(m, worker.data(), g);
    EXPECT_FALSE(box.contains(eye))
        << p.close_up_camera << " is inside geom " << mj_id2name(m, mjOBJ_GEOM, g);
  }
  EXPECT_GT(eye.z(), 0.05);
  // Its centre pixel sees the palm: nothing nearer than 15 cm short of it.
  const core::DepthImage depth = replay.view().render_depth(view, 64, 48);
  const float centre = depth.metres[24 * 64 + 32];
  EXPECT_GT(centre, view.distance - 0.15) << p.close_up_camera;
  std::filesystem::remove_all(dir);
}

TEST_F(TrialVideo, UnknownTrialAndMissingFolderAreInputErrorsAndWriteNothing) {
  const auto video = out_ / "v.mp4";
  const test::CommandResult unknown =
      test::run_cli("render --trial " + shell_arg((*dir_ / "run").string() + ":nope") +
                        " --video " + shell_arg(video),
                    test::catalog().root());
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_NE(unknown.err.find("trials.jsonl: nope: no trial with this id"), std::string::npos)
      << unknown.err;
  EXPECT_THROW(trial_snapshot_png(test::catalog(), (*dir_ / "run").string() + ":nope", -1, {}),
               core::InputError);

  const auto nowhere = out_ / "missing" / "v.mp4";
  const test::CommandResult missing =
      test::run_cli("render --trial " + shell_arg(trial()) + " --video " + shell_arg(nowhere),
                    test::catalog().root());
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("--video: the output folder '" + (out_ / "missing").string() +
                             "' does not exist"),
            std::string::npos)
      << missing.err;
  EXPECT_EQ(std::count(missing.err.begin(), missing.err.end(), '\n'), 1) << missing.err;
  EXPECT_TRUE(files_in(out_).empty());
}

TEST_F(TrialVideo, FfmpegMissingFromPathIsAnInputError) {
  // A PATH with `timeout` (which test::run_cli calls) but no ffmpeg.
  const auto bin = out_ / "bin";
  std::filesystem::create_directories(bin);
  std::filesystem::create_symlink("/usr/bin/timeout", bin / "timeout");
  const auto video = out_ / "v.mp4";
  test::CommandResult cli;
  {
    const PathSetting path(bin.string());
    cli = test::run_cli("render --trial " + shell_arg(trial()) + " --video " + shell_arg(video),
                        test::catalog().root());
    try {
      write_trial_video(test::catalog(), trial(), video, {});
      ADD_FAILURE() << "no error without ffmpeg";
    } catch (const core::InputError& e) {
      EXPECT_EQ(e.file(), "--video");
      EXPECT_NE(e.message().find("ffmpeg is not on PATH"), std::string::npos) << e.what();
    }
  }
  EXPECT_EQ(cli.exit_code, 2);
  EXPECT_NE(cli.err.find("--video: ffmpeg is not on PATH"), std::string::npos) << cli.err;
  EXPECT_EQ(files_in(out_), std::set<std::string>{"bin"});
}

TEST_F(TrialVideo, FfmpegFailureIsReportedWithItsLastLineAndLeavesNoFile) {
  // An "ffmpeg" that refuses at once, without reading its input (the writer sees EPIPE).
  const auto bin = out_ / "bin";
  std::filesystem::create_directories(bin);
  std::ofstream(bin / "ffmpeg") << "#!/bin/sh\necho 'some chatter' >&2\n"
                                   "echo \"Unknown encoder 'libx264'\" >&2\nexit 1\n";
  std::filesystem::permissions(bin / "ffmpeg", std::filesystem::perms::owner_all);
  const auto video = out_ / "v.mp4";
  std::ofstream(video) << "an older video";  // kept as it was
  const PathSetting path(bin.string() + ":" + std::getenv("PATH"));
  VideoOptions options;
  options.frame = {"", 320, 240};  // more than a pipe holds: writing meets the closed pipe
  try {
    write_trial_video(test::catalog(), trial(), video, options);
    FAIL() << "ffmpeg's failure was not reported";
  } catch (const core::InputError& e) {
    EXPECT_EQ(e.file(), "--video");
    EXPECT_EQ(e.message(), "ffmpeg failed (exit status 1): Unknown encoder 'libx264'");
  }
  EXPECT_EQ(files_in(out_), (std::set<std::string>{"bin", "v.mp4"}));
  std::ifstream in(video);
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), "an older video");
}

TEST_F(TrialVideo, RenderArgumentsNeedExactlyOneOutput) {
  const std::string t = " --trial " + shell_arg(trial());
  const auto video = " --video " + shell_arg(out_ / "v.mp4");
  const auto png = " --out " + shell_arg(out_ / "f.png");
  struct Case {
    std::string args, error;
  };
  for (const Case& c : std::vector<Case>{
           {"render --robot minibot --env kitchen" + video, "--video requires --trial"},
           {"render" + t + video + png, "--out excludes --video"},
           {"render" + t, "--trial needs one of --out F.png (a frame) and --video F.mp4"},
           {"render" + t + png + " --fps 10", "--fps requires --video"},
           {"render" + t + video + " --width 321", "--width: 321 is odd"},
           {"render --robot minibot --env kitchen", "render: needs --out F.png"},
       }) {
    const test::CommandResult r = test::run_cli(c.args, test::catalog().root());
    EXPECT_EQ(r.exit_code, 2) << c.args;
    EXPECT_NE(r.err.find(c.error), std::string::npos) << c.args << "\n" << r.err;
  }
  EXPECT_TRUE(files_in(out_).empty());
}

}  // namespace
}  // namespace taskmatrix::harness
