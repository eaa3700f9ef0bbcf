// taskmatrix render: a robot in an environment, a scenario's world, or a recorded trial's frame
// or video.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "harness/backends/backends.h"
#include "harness/cli/verb.h"
#include "harness/replay/replay.h"
#include "harness/replay/trial_video.h"
#include "harness/run/trial.h"
#include "harness/scenario/scenario.h"
#include "taskmatrix/core/input_error.h"
#include "taskmatrix/io/png.h"

namespace taskmatrix::harness::cli {
namespace {

struct RenderOptions {
  std::string robot, environment, camera, posture = "rest", out;
  std::string trial;     // RUN_DIR:TRIAL_ID: a frame of a recorded trial
  std::string scenario;  // draw the world of this scenario's layout seed --seed
  double time = -1;      // of the trial's frame; < 0: the last frame
  std::string video;     // with --trial: the whole trial as MP4 instead of one frame
  double fps = 25, speed = 1.0;
  long long seed = 1;
  int obstacles = 8;
  int width = 960, height = 720;
  bool depth = false;
};

// draw(): the view's image at the options' size; a size the backend cannot draw is an input
// error naming --width.
template <class Draw>
auto sized(const Draw& draw) {
  try {
    return draw();
  } catch (const std::invalid_argument& e) {
    throw core::InputError("--width", "", e.what());
  }
}

int render_trial(const ModelCatalog& catalog, const RenderOptions& o) {
  if (o.out.empty() == o.video.empty()) {
    throw core::InputError(
        "render", "", "--trial needs one of --out F.png (a frame) and --video F.mp4 (the trial)");
  }
  if (!o.video.empty()) {
    VideoOptions options;
    options.frame.camera = o.camera;
    options.frame.width = o.width;
    options.frame.height = o.height;
    options.fps = o.fps;
    options.speed = o.speed;
    const VideoInfo info = write_trial_video(catalog, o.trial, o.video, options);
    std::printf("%s: trial %s, %zu frames at %g fps (%.2f s), camera %s\n", o.video.c_str(),
                o.trial.c_str(), info.frames, o.fps, info.duration_s, info.camera.c_str());
    return 0;
  }
  const std::filesystem::path file = trajectory_of(o.trial);
  Replay replay(catalog, read_trajectory_file(file));
  if (replay.frames() == 0) throw core::InputError(file.string(), "frames", "no frames");
  const size_t frame = o.time < 0 ? replay.frames() - 1 : replay.frame_at(o.time);
  replay.show(frame);
  std::string camera = o.camera;
  const core::Camera view = camera_view(replay.view(), camera);
  io::write_png(o.out, sized([&] { return replay.view().render(view, o.width, o.height); }));
  std::printf("%s: trial %s at t = %.2f s (frame %zu of %zu), camera %s\n", o.out.c_str(),
              o.trial.c_str(), replay.time_of(frame), frame + 1, replay.frames(), camera.c_str());
  return 0;
}

int render(const ModelCatalog& catalog, core::ProgramRegistry& programs, const RenderOptions& o) {
  if (!o.trial.empty()) return render_trial(catalog, o);
  if (o.robot.empty() || o.environment.empty()) {
    throw core::InputError("render", "", "needs --robot and --env, or --trial");
  }
  if (o.out.empty()) throw core::InputError("render", "", "needs --out F.png");
  const std::shared_ptr<const core::LoadedScene> loaded =
      backend().load(catalog.robot_dir(o.robot), catalog.environment_dir(o.environment));
  core::TrialLayout layout;
  if (o.scenario.empty()) {
    core::ObstacleOptions obstacles;
    obstacles.count = o.obstacles;
    layout = loaded->make_trial_layout(obstacles, {}, static_cast<std::uint64_t>(o.seed));
  } else {
    // The robot and the environment are --robot's and --env's, whatever the scenario lists.
    const Scenario s = load_run_plan(o.scenario, catalog, programs, {true, true}).scenarios.at(0);
    layout = draw_trial_layout(s, *loaded, static_cast<std::uint64_t>(o.seed),
                               "--seed " + std::to_string(o.seed));
  }
  const std::unique_ptr<core::SceneView> view = loaded->make_view(layout);
  try {
    view->show_posture(o.posture);
  } catch (const std::out_of_range& e) {
    throw core::InputError("--posture", "", e.what());
  }

  std::string camera = o.camera;
  const core::Camera through = camera_view(*view, camera);
  if (o.depth) {
    const core::DepthImage depth =
        sized([&] { return view->render_depth(through, o.width, o.height); });
    io::write_depth_png(o.out, depth);
    float near = INFINITY, far = 0;
    for (float v : depth.metres) {
      if (std::isfinite(v)) {
        near = std::min(near, v);
        far = std::max(far, v);
      }
    }
    std::printf("depth %.3f..%.3f m (grey 255..40)\n", near, far);
  } else {
    io::write_png(o.out, sized([&] { return view->render(through, o.width, o.height); }));
  }
  std::printf("%s: %s in %s, seed %lld, %s, camera %s%s\n", o.out.c_str(), o.robot.c_str(),
              o.environment.c_str(), o.seed,
              o.scenario.empty() ? (std::to_string(o.obstacles) + " obstacles").c_str()
                                 : ("the world of " + o.scenario).c_str(),
              camera.c_str(), o.depth ? " (depth)" : "");
  return 0;
}

class Render final : public Verb {
 public:
  CLI::App* add_to(CLI::App& app) override {
    RenderOptions& o = options_;
    CLI::App* render =
        app.add_subcommand("render", "Render a robot in an environment to PNG (OSMesa)");
    render->add_option("--robot", o.robot, "robot name");
    render->add_option("--env", o.environment, "environment name");
    render->add_option(
        "--trial", o.trial,
        "RUN_DIR:TRIAL_ID: render a recorded trial's frame instead (no re-planning)");
    render
        ->add_option("--time", o.time,
                     "simulated time of the trial's frame in seconds (default: its last frame)")
        ->check(finite_range(0.0, 1e9));
    render->add_option(
        "--scenario", o.scenario,
        "draw the world of this scenario (or a suite's first) for layout seed --seed");
    render->add_option("--seed", o.seed, "obstacle layout seed")
        ->check(CLI::Validator(
            [](std::string& v) {
              return v.find('-') == std::string::npos ? "" : "must not be negative";
            },
            "SEED >= 0"))
        ->capture_default_str();
    render->add_option("--obstacles", o.obstacles, "number of random obstacles")
        ->check(CLI::Range(0, 200))
        ->capture_default_str();
    render->add_option("--camera", o.camera,
                       "an environment camera, 'head' (the robot's head camera), 'free', or "
                       "lookat:X,Y,Z[,DISTANCE[,AZIMUTH[,ELEVATION]]] (a free camera aimed at a "
                       "world point; metres and degrees; defaults 1.5, 210, -25)");
    render->add_option("--posture", o.posture, "robot posture from its profile")
        ->capture_default_str();
    render->add_flag("--depth", o.depth, "write metric depth as a grey image (near is bright)");
    render->add_option("--width", o.width)->check(CLI::Range(16, 1280))->capture_default_str();
    render->add_option("--height", o.height)->check(CLI::Range(16, 960))->capture_default_str();
    render->add_option("--out", o.out, "output PNG (needed unless --video)");
    CLI::Option* video =
        render
            ->add_option("--video", o.video,
                         "with --trial: the whole trial as H.264 MP4 (ffmpeg) instead of a frame")
            ->needs(render->get_option("--trial"))
            ->excludes(render->get_option("--out"))
            ->excludes(render->get_option("--time"))
            ->excludes(render->get_option("--depth"));
    render->add_option("--fps", o.fps, "video frames per second")
        ->check(finite_range(1.0, 240.0))
        ->capture_default_str()
        ->needs(video);
    render->add_option("--speed", o.speed, "simulated seconds per video second")
        ->check(finite_range(0.01, 100.0))
        ->capture_default_str()
        ->needs(video);
    return render;
  }

  int run(VerbContext& context) override {
    const ModelCatalog& catalog = context.catalog();
    return render(catalog, context.programs(), options_);
  }

 private:
  RenderOptions options_;
};

}  // namespace

std::unique_ptr<Verb> render_verb() { return std::make_unique<Render>(); }

}  // namespace taskmatrix::harness::cli
