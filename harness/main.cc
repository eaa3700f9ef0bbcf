// The `taskmatrix` command line. Verbs: list, validate, run, render, scenes. Every failure is
// one line on stderr and a non-zero exit status (2 for bad input).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>

#include <CLI/CLI.hpp>

#include "harness/model_catalog.h"
#include "harness/replay.h"
#include "harness/run_job.h"
#include "harness/scenes_job.h"
#include "taskmatrix/core/input_error.h"
#include "taskmatrix/core/obstacle_layout.h"
#include "taskmatrix/mujoco/motion_planner.h"
#include "taskmatrix/mujoco/offscreen_renderer.h"
#include "taskmatrix/mujoco/scene.h"
#include "taskmatrix/programs/primitives.h"

namespace {

using taskmatrix::harness::ModelCatalog;

struct RenderOptions {
  std::string robot, environment, camera, posture = "rest", out;
  std::string trial;  // RUN_DIR:TRIAL_ID: a frame of a recorded trial
  double time = -1;   // of the trial's frame; < 0: the last frame
  long long seed = 1;
  int obstacles = 8;
  int width = 960, height = 720;
  bool depth = false;
};

taskmatrix::mujoco::CameraView camera_view(const taskmatrix::mujoco::Scene& scene,
                                           std::string& camera) {
  taskmatrix::mujoco::CameraView view;
  if (camera.empty())
    camera = scene.environment().cameras.empty() ? "free" : scene.environment().cameras[0];
  if (camera == "head") {
    view.fixed_camera = scene.head_camera();
  } else if (camera != "free") {
    view.fixed_camera = mj_name2id(scene.model(), mjOBJ_CAMERA, camera.c_str());
    if (view.fixed_camera < 0) {
      std::string known = "head, free";
      for (const std::string& c : scene.environment().cameras) known += ", " + c;
      throw taskmatrix::core::InputError("--camera", "",
                                         "unknown camera '" + camera + "' (known: " + known + ")");
    }
  }
  return view;
}

int run_render_trial(const ModelCatalog& catalog, const RenderOptions& o) {
  namespace mj = taskmatrix::mujoco;
  namespace h = taskmatrix::harness;
  const std::filesystem::path file = h::trajectory_of(o.trial);
  h::Replay replay(catalog, h::read_trajectory_file(file));
  if (replay.frames() == 0)
    throw taskmatrix::core::InputError(file.string(), "frames", "no frames");
  const size_t frame = o.time < 0 ? replay.frames() - 1 : replay.frame_at(o.time);
  replay.show(frame);
  std::string camera = o.camera;
  const mj::CameraView view = camera_view(replay.scene(), camera);
  mj::OffscreenRenderer renderer(replay.scene().model(), o.width, o.height);
  mj::write_png(o.out, renderer.render_rgb(replay.worker().model(), replay.worker().data(), view));
  std::printf("%s: trial %s at t = %.2f s (frame %zu of %zu), camera %s\n", o.out.c_str(),
              o.trial.c_str(), replay.time_of(frame), frame + 1, replay.frames(), camera.c_str());
  return 0;
}

int run_render(const ModelCatalog& catalog, const RenderOptions& o) {
  namespace mj = taskmatrix::mujoco;
  if (!o.trial.empty()) return run_render_trial(catalog, o);
  if (o.robot.empty() || o.environment.empty()) {
    throw taskmatrix::core::InputError("render", "", "needs --robot and --env, or --trial");
  }
  auto scene = mj::Scene::load(catalog.robot_dir(o.robot), catalog.environment_dir(o.environment));
  mj::WorkerScene worker(scene);
  worker.apply_layout(scene->make_layout(o.obstacles, static_cast<std::uint64_t>(o.seed)));
  std::vector<double> qpos = scene->start_qpos();
  try {
    scene->apply_posture(o.posture, qpos.data());
  } catch (const std::out_of_range& e) {
    throw taskmatrix::core::InputError("--posture", "", e.what());
  }
  std::copy(qpos.begin(), qpos.end(), worker.data()->qpos);
  mj_forward(worker.model(), worker.data());

  std::string camera = o.camera;
  const mj::CameraView view = camera_view(*scene, camera);
  mj::OffscreenRenderer renderer(scene->model(), o.width, o.height);
  if (o.depth) {
    const mj::DepthImage depth = renderer.render_depth(worker.model(), worker.data(), view);
    mj::write_depth_png(o.out, depth);
    float near = INFINITY, far = 0;
    for (float v : depth.metres) {
      if (std::isfinite(v)) {
        near = std::min(near, v);
        far = std::max(far, v);
      }
    }
    std::printf("depth %.3f..%.3f m (grey 255..40)\n", near, far);
  } else {
    mj::write_png(o.out, renderer.render_rgb(worker.model(), worker.data(), view));
  }
  std::printf("%s: %s in %s, seed %lld, %d obstacles, camera %s%s\n", o.out.c_str(),
              o.robot.c_str(), o.environment.c_str(), o.seed, o.obstacles, camera.c_str(),
              o.depth ? " (depth)" : "");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "taskmatrix: robot-independent humanoid task programs on MuJoCo, and a benchmark harness"};
  app.require_subcommand(1);

  std::string list_what;
  CLI::App* list = app.add_subcommand(
      "list", "List robots, environments, task programs or planners, one name per line");
  list->add_option("what", list_what, "robots | environments | programs | planners")
      ->required()
      ->check(CLI::IsMember({"robots", "environments", "programs", "planners"}));

  RenderOptions render_options;
  CLI::App* render =
      app.add_subcommand("render", "Render a robot in an environment to PNG (OSMesa)");
  render->add_option("--robot", render_options.robot, "robot name");
  render->add_option("--env", render_options.environment, "environment name");
  render->add_option("--trial", render_options.trial,
                     "RUN_DIR:TRIAL_ID: render a recorded trial's frame instead (no re-planning)");
  render->add_option("--time", render_options.time,
                     "simulated time of the trial's frame in seconds (default: its last frame)");
  render->add_option("--seed", render_options.seed, "obstacle layout seed")
      ->check(CLI::Validator(
          [](std::string& v) {
            return v.find('-') == std::string::npos ? "" : "must not be negative";
          },
          "SEED >= 0"))
      ->capture_default_str();
  render->add_option("--obstacles", render_options.obstacles, "number of random obstacles")
      ->check(CLI::Range(0, 200))
      ->capture_default_str();
  render->add_option("--camera", render_options.camera,
                     "an environment camera, 'head' (the robot's head camera) or 'free'");
  render->add_option("--posture", render_options.posture, "robot posture from its profile")
      ->capture_default_str();
  render->add_flag("--depth", render_options.depth,
                   "write metric depth as a grey image (near is bright)");
  render->add_option("--width", render_options.width)
      ->check(CLI::Range(16, 1280))
      ->capture_default_str();
  render->add_option("--height", render_options.height)
      ->check(CLI::Range(16, 960))
      ->capture_default_str();
  render->add_option("--out", render_options.out, "output PNG")->required();

  taskmatrix::harness::ScenesJobOptions scenes_options;
  std::string scenes_out = scenes_options.out.string();
  CLI::App* scenes = app.add_subcommand(
      "scenes", "Load every robot in every environment over layout seeds; render and tabulate");
  scenes->add_option("--seeds", scenes_options.seeds, "layout seeds 1..N")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  scenes->add_option("--obstacles", scenes_options.obstacles)
      ->check(CLI::Range(0, 200))
      ->capture_default_str();
  scenes->add_option("--out", scenes_out, "output folder")->capture_default_str();

  std::string validate_file;
  CLI::App* validate = app.add_subcommand(
      "validate", "Check a scenario or suite (files, models, planners, layouts) without running");
  validate->add_option("SCENARIO", validate_file, "scenario or suite YAML")->required();

  taskmatrix::harness::RunJobOptions run_options;
  std::string run_out, planners_list, progress = "auto";
  long long run_seed = 0;
  CLI::App* run = app.add_subcommand(
      "run", "Run a scenario or suite: trials in parallel workers, results in a run directory");
  run->add_option("SCENARIO", run_options.scenario_file, "scenario or suite YAML")->required();
  run->add_option("--out", run_out, "run directory (default: results/runs/<name>)");
  run->add_option("--jobs", run_options.jobs, "trials run at once (worker processes)")
      ->check(CLI::Range(1, 256))
      ->capture_default_str();
  run->add_option("--trials", run_options.overrides.trials,
                  "trials per (robot, environment, planner)")
      ->check(CLI::Range(1, 100000));
  run->add_option("--seed", run_seed, "planner seed base (trial k uses seed + k)")
      ->check(CLI::Range(1LL, 4294967295LL));
  run->add_option("--planners", planners_list,
                  "planners, comma separated (replaces the scenario's)");
  run->add_flag("--resume", run_options.resume,
                "keep the trials already in the run directory, run the rest");
  run->add_option("--only", run_options.only, "run one trial by its id and print its result line");
  run->add_option("--progress", progress, "progress line on stderr: auto (on a terminal), on, off")
      ->check(CLI::IsMember({"auto", "on", "off"}))
      ->capture_default_str();
  run->add_option("--record-hz", run_options.record_rate_hz,
                  "trajectory frames kept per simulated second (0: none)")
      ->check(CLI::Range(0.0, 1000.0))
      ->capture_default_str();

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::string what = e.what();
    std::replace(what.begin(), what.end(), '\n', ' ');
    std::cerr << "taskmatrix: error: " << what << " (see taskmatrix --help)\n";
    return 2;
  }

  try {
    if (*list && (list_what == "programs" || list_what == "planners")) {
      taskmatrix::core::ProgramRegistry registry;
      taskmatrix::programs::register_programs(registry);
      for (const std::string& name :
           list_what == "programs" ? registry.names() : taskmatrix::mujoco::planner_names()) {
        std::cout << name << "\n";
      }
      return 0;
    }
    const ModelCatalog catalog = ModelCatalog::from_environment();
    if (*list) {
      for (const std::string& name :
           list_what == "robots" ? catalog.robots() : catalog.environments()) {
        std::cout << name << "\n";
      }
      return 0;
    }
    if (*render) return run_render(catalog, render_options);
    if (*validate || *run) {
      taskmatrix::core::ProgramRegistry registry;
      taskmatrix::programs::register_programs(registry);
      if (*validate) {
        const int trials = taskmatrix::harness::validate_run_plan(catalog, registry, validate_file);
        std::cout << validate_file << ": ok, " << trials << " trials\n";
        return 0;
      }
      run_options.out = run_out;
      run_options.overrides.seed = static_cast<std::uint32_t>(run_seed);
      if (!planners_list.empty()) {
        std::stringstream in(planners_list);
        for (std::string name; std::getline(in, name, ',');) {
          if (!name.empty()) run_options.overrides.planners.push_back(name);
        }
      }
      run_options.progress = progress == "on" ? taskmatrix::harness::RunJobOptions::Progress::kOn
                             : progress == "off"
                                 ? taskmatrix::harness::RunJobOptions::Progress::kOff
                                 : taskmatrix::harness::RunJobOptions::Progress::kAuto;
      run_options.command_line.assign(argv, argv + argc);
      const taskmatrix::harness::RunJobResult r =
          taskmatrix::harness::run_job(catalog, registry, run_options, std::cout, std::cerr);
      if (!r.dir.empty()) {
        std::cerr << "taskmatrix: " << r.finished << " of " << r.planned << " trials in "
                  << r.dir.string() << " (" << r.ran << " run now, " << r.successes << " succeeded)"
                  << (r.interrupted ? "; interrupted: --resume runs the rest" : "") << "\n";
      }
      return r.interrupted ? 130 : 0;
    }
    if (*scenes) {
      scenes_options.out = scenes_out;
      return taskmatrix::harness::run_scenes_job(catalog, scenes_options, std::cout) == 0 ? 0 : 1;
    }
  } catch (const std::exception& e) {
    std::cerr << "taskmatrix: error: " << e.what() << "\n";
    return 2;
  }
  return 0;
}
