// The `taskmatrix` command line. Verbs: list, validate, run, merge, render, scenes, compare,
// bench-compare, check-robot. Every failure is one line on stderr and a non-zero exit status (2
// for bad input; 1 for a regression when asked to fail on one).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>

#include <CLI/CLI.hpp>

#include "harness/bench_compare.h"
#include "harness/check_robot.h"
#include "harness/compare_job.h"
#include "harness/merge_job.h"
#include "harness/model_catalog.h"
#include "harness/planner_plugins.h"
#include "harness/replay.h"
#include "harness/run_job.h"
#include "harness/scenario.h"
#include "harness/scenes_job.h"
#include "harness/trial.h"
#include "harness/trial_video.h"
#include "taskmatrix/core/input_error.h"
#include "taskmatrix/core/motion_planning.h"
#include "taskmatrix/core/obstacle_layout.h"
#include "taskmatrix/mujoco/offscreen_renderer.h"
#include "taskmatrix/mujoco/scene.h"
#include "taskmatrix/programs/primitives.h"

namespace {

using taskmatrix::harness::camera_view;
using taskmatrix::harness::ModelCatalog;

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

// CLI::Range lets NaN through (every comparison with it is false): numbers must be finite and
// within [lo, hi].
CLI::Validator finite_range(double lo, double hi) {
  auto number = [](double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return std::string(buf);
  };
  const std::string range = "[" + number(lo) + ", " + number(hi) + "]";
  return CLI::Validator(
      [lo, hi, range](std::string& text) -> std::string {
        char* end = nullptr;
        const double v = std::strtod(text.c_str(), &end);
        if (text.empty() || *end != '\0' || !std::isfinite(v)) return "must be a finite number";
        return v < lo || v > hi ? "must be in " + range : "";
      },
      "NUMBER in " + range);
}

int run_render_trial(const ModelCatalog& catalog, const RenderOptions& o) {
  namespace mj = taskmatrix::mujoco;
  namespace h = taskmatrix::harness;
  if (o.out.empty() == o.video.empty()) {
    throw taskmatrix::core::InputError(
        "render", "", "--trial needs one of --out F.png (a frame) and --video F.mp4 (the trial)");
  }
  if (!o.video.empty()) {
    h::VideoOptions options;
    options.frame.camera = o.camera;
    options.frame.width = o.width;
    options.frame.height = o.height;
    options.fps = o.fps;
    options.speed = o.speed;
    const h::VideoInfo info = h::write_trial_video(catalog, o.trial, o.video, options);
    std::printf("%s: trial %s, %zu frames at %g fps (%.2f s), camera %s\n", o.video.c_str(),
                o.trial.c_str(), info.frames, o.fps, info.duration_s, info.camera.c_str());
    return 0;
  }
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

// How a command line that renders with this binary and these models starts:
// "[TASKMATRIX_ROOT=ROOT ]/absolute/path/of/taskmatrix" (shell-quoted where needed).
std::string render_command_prefix() {
  std::error_code ec;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
  std::string prefix =
      ec ? std::string("taskmatrix") : taskmatrix::harness::shell_word(self.string());
  if (const char* root = std::getenv("TASKMATRIX_ROOT"); root != nullptr && *root) {
    prefix = "TASKMATRIX_ROOT=" + taskmatrix::harness::shell_word(root) + " " + prefix;
  }
  return prefix;
}

int run_render(const ModelCatalog& catalog, const RenderOptions& o) {
  namespace mj = taskmatrix::mujoco;
  if (!o.trial.empty()) return run_render_trial(catalog, o);
  if (o.robot.empty() || o.environment.empty()) {
    throw taskmatrix::core::InputError("render", "", "needs --robot and --env, or --trial");
  }
  if (o.out.empty()) throw taskmatrix::core::InputError("render", "", "needs --out F.png");
  auto scene = mj::Scene::load(catalog.robot_dir(o.robot), catalog.environment_dir(o.environment));
  mj::WorkerScene worker(scene);
  if (o.scenario.empty()) {
    worker.apply_layout(scene->make_layout(o.obstacles, static_cast<std::uint64_t>(o.seed)));
  } else {
    taskmatrix::core::ProgramRegistry registry;
    taskmatrix::programs::register_programs(registry);
    const taskmatrix::harness::Scenario s =
        taskmatrix::harness::load_run_plan(o.scenario, catalog, registry).scenarios.at(0);
    taskmatrix::harness::draw_trial_layout(s, worker, static_cast<std::uint64_t>(o.seed),
                                           "--seed " + std::to_string(o.seed));
  }
  std::vector<double> qpos = worker.start_qpos();
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
  std::printf("%s: %s in %s, seed %lld, %s, camera %s%s\n", o.out.c_str(), o.robot.c_str(),
              o.environment.c_str(), o.seed,
              o.scenario.empty() ? (std::to_string(o.obstacles) + " obstacles").c_str()
                                 : ("the world of " + o.scenario).c_str(),
              camera.c_str(), o.depth ? " (depth)" : "");
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
  render
      ->add_option("--time", render_options.time,
                   "simulated time of the trial's frame in seconds (default: its last frame)")
      ->check(finite_range(0.0, 1e9));
  render->add_option("--scenario", render_options.scenario,
                     "draw the world of this scenario (or a suite's first) for layout seed --seed");
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
                     "an environment camera, 'head' (the robot's head camera), 'free', or "
                     "lookat:X,Y,Z[,DISTANCE[,AZIMUTH[,ELEVATION]]] (a free camera aimed at a "
                     "world point; metres and degrees; defaults 1.5, 210, -25)");
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
  render->add_option("--out", render_options.out, "output PNG (needed unless --video)");
  CLI::Option* video =
      render
          ->add_option("--video", render_options.video,
                       "with --trial: the whole trial as H.264 MP4 (ffmpeg) instead of a frame")
          ->needs(render->get_option("--trial"))
          ->excludes(render->get_option("--out"))
          ->excludes(render->get_option("--time"))
          ->excludes(render->get_option("--depth"));
  render->add_option("--fps", render_options.fps, "video frames per second")
      ->check(finite_range(1.0, 240.0))
      ->capture_default_str()
      ->needs(video);
  render->add_option("--speed", render_options.speed, "simulated seconds per video second")
      ->check(finite_range(0.01, 100.0))
      ->capture_default_str()
      ->needs(video);

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
  std::string run_out, planners_list, progress = "auto", shard_spec;
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
  run->add_option("--execution", run_options.overrides.execution,
                  "physics, kinematic or physics_unpruned (replaces the scenario's)")
      ->check(CLI::IsMember({"physics", "kinematic", "physics_unpruned"}));
  run->add_flag("--resume", run_options.resume,
                "keep the trials already in the run directory, run the rest");
  CLI::Option* only_option = run->add_option("--only", run_options.only,
                                             "run one trial by its id and print its result line");
  run->add_option("--shard", shard_spec,
                  "I/N: run only the trials whose matrix index is I mod N (default in a Slurm "
                  "array task: SLURM_ARRAY_TASK_ID - SLURM_ARRAY_TASK_MIN of "
                  "SLURM_ARRAY_TASK_COUNT)")
      ->excludes(only_option);
  run->add_option("--progress", progress, "progress line on stderr: auto (on a terminal), on, off")
      ->check(CLI::IsMember({"auto", "on", "off"}))
      ->capture_default_str();
  run->add_option("--record-hz", run_options.record_rate_hz,
                  "trajectory frames kept per simulated second (0: none)")
      ->check(finite_range(0.0, 1000.0))
      ->capture_default_str();

  taskmatrix::harness::MergeJobOptions merge_options;
  std::string merge_out;
  std::vector<std::string> merge_dirs;
  CLI::App* merge = app.add_subcommand(
      "merge", "Union the run directories of a sharded run (run --shard) into one run directory");
  merge->add_option("OUT", merge_out, "the merged run directory (its old results are replaced)")
      ->required();
  merge->add_option("SHARD_DIR", merge_dirs, "the shards' run directories")->required();
  merge->add_flag("--allow-partial", merge_options.allow_partial,
                  "merge even when trials are missing or duplicated (the first copy is kept)");
  merge->add_flag("--move", merge_options.move_trajectories,
                  "move trajectories out of the shards instead of hard-linking them");

  taskmatrix::harness::CheckRobotOptions check_options;
  std::string check_out;
  bool check_no_run = false;
  CLI::App* check_robot = app.add_subcommand(
      "check-robot",
      "Lint a robot's profile against its model, then run the twelve programs once in one "
      "environment (exit 0 clean, 1 lint error, 4 a program failed)");
  check_robot->add_option("NAME", check_options.robot, "robot name")->required();
  check_robot->add_option("--env", check_options.environment,
                          "environment of the program run (default: kitchen, else the first)");
  check_robot->add_flag("--no-run", check_no_run, "the lint only");
  check_robot->add_option("--out", check_out,
                          "run directory (default: results/runs/check-robot-NAME-ENV)");
  check_robot->add_option("--jobs", check_options.jobs, "trials run at once")
      ->check(CLI::Range(1, 256))
      ->capture_default_str();

  taskmatrix::harness::BenchCompareOptions bench_options;
  std::string bench_base, bench_new;
  bool bench_fail = false;
  CLI::App* bench_compare = app.add_subcommand(
      "bench-compare",
      "Compare two taskmatrix_bench JSON files: exact counters must match, times within noise");
  bench_compare->add_option("BASE", bench_base, "baseline JSON (--benchmark_out_format=json)")
      ->required();
  bench_compare->add_option("NEW", bench_new, "new JSON")->required();
  bench_compare
      ->add_option("--time-tolerance", bench_options.time_tolerance,
                   "relative slow-down allowed before a time is a regression (at least 3 cv)")
      ->check(finite_range(0.0, 100.0))
      ->capture_default_str();
  bench_compare->add_flag("--fail-on-regression", bench_fail, "exit 1 when anything regressed");

  taskmatrix::harness::CompareJobOptions compare_options;
  std::string compare_base, compare_new, compare_report;
  bool compare_fail = false, compare_fail_models = false;
  CLI::App* compare = app.add_subcommand(
      "compare",
      "Pair the trials of two run directories by id and test what changed (success, planning "
      "time, work counts)");
  compare->add_option("BASE_DIR", compare_base, "the baseline run directory")->required();
  compare->add_option("NEW_DIR", compare_new, "the run directory to judge")->required();
  compare->add_option("--report", compare_report,
                      "write compare.md, compare.json and report.html (with pictures of failed "
                      "trials) into this directory");
  compare->add_flag("--fail-on-regression", compare_fail,
                    "exit 1 when a change is a significant regression beyond the thresholds");
  compare->add_flag("--fail-on-model-change", compare_fail_models,
                    "exit 1 when the runs loaded model, profile or environment files with "
                    "different contents (or either run did not record their hashes)");
  compare->add_flag("--power", compare_options.print_power,
                    "also print, per group, the smallest success drop and planning-time ratio "
                    "the runs could detect (80% power) and the trials needed for the targets");
  compare
      ->add_option("--power-drop", compare_options.thresholds.power_success_target,
                   "the success drop (0..1) whose trials needed the power table gives")
      ->check(CLI::Range(0.001, 1.0))
      ->capture_default_str()
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  compare
      ->add_option("--power-ratio", compare_options.thresholds.power_time_target,
                   "the planning-time ratio whose trials needed the power table gives "
                   "(default: --max-time-ratio)")
      ->check(CLI::Range(1.001, 1e6))
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  compare->add_flag("--fail-on-unpaired", compare_options.thresholds.fail_on_unpaired,
                    "a trial without a partner is a regression (both ways, unless --subset)");
  compare->add_flag("--subset", compare_options.thresholds.new_is_subset,
                    "the new run holds only some of the base's trials (a fast form): base "
                    "trials without a partner are expected");
  compare->add_flag("--fail-on-nonreproducible", compare_options.thresholds.fail_on_nonreproducible,
                    "a pair where a clock bound decided a trial is a regression");
  compare->add_flag("--include-nonreproducible", compare_options.thresholds.include_nonreproducible,
                    "judge pairs where a clock bound decided a trial too (left out by default)");
  compare->add_flag("--exact-work", compare_options.thresholds.exact_work,
                    "any change of a trial's work counts or planned paths is a regression");
  compare->add_flag("--ignore-planner", compare_options.ignore_planner,
                    "pair trials whatever their planner label (one planner against another)");
  compare
      ->add_option("--alpha", compare_options.thresholds.alpha,
                   "significance level of McNemar's and Wilcoxon's tests")
      ->check(finite_range(1e-9, 0.5))
      ->capture_default_str()
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  compare
      ->add_option("--max-success-drop", compare_options.thresholds.max_success_drop,
                   "success-rate drop (0..1) that fails when significant")
      ->check(finite_range(0.0, 1.0))
      ->capture_default_str()
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  compare
      ->add_option("--max-time-ratio", compare_options.thresholds.max_time_ratio,
                   "planning-time ratio new/base that fails when its 95% interval lies above")
      ->check(finite_range(1.0, 1e6))
      ->capture_default_str()
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  compare
      ->add_option("--max-work-ratio", compare_options.thresholds.max_work_ratio,
                   "ratio of total collision checks new/base above which a group fails")
      ->check(finite_range(1.0, 1e6))
      ->capture_default_str()
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  compare
      ->add_option("--min-time-pairs", compare_options.thresholds.min_time_pairs,
                   "fewest pairs that both planned for a planning-time verdict")
      ->check(CLI::Range(2, 1000000))
      ->capture_default_str()
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  compare
      ->add_option("--max-new-failures", compare_options.thresholds.max_new_failures,
                   "trials that succeeded in the base and now fail, beyond which the run "
                   "fails whatever the test says (-1: off)")
      ->check(CLI::Range(-1, 100000000))
      ->capture_default_str()
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  compare
      ->add_option("--max-snapshots", compare_options.max_snapshots,
                   "failed trials pictured in report.html")
      ->check(CLI::Range(0, 10000))
      ->capture_default_str()
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);

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
    taskmatrix::harness::register_builtin_planners();
    if (*bench_compare) {
      return taskmatrix::harness::run_bench_compare(bench_base, bench_new, bench_options,
                                                    bench_fail, std::cout);
    }
    if (*list && (list_what == "programs" || list_what == "planners")) {
      taskmatrix::core::ProgramRegistry registry;
      taskmatrix::programs::register_programs(registry);
      for (const std::string& name : list_what == "programs"
                                         ? registry.names()
                                         : taskmatrix::core::planner_registry().names()) {
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
    if (*check_robot) {
      taskmatrix::core::ProgramRegistry registry;
      taskmatrix::programs::register_programs(registry);
      check_options.run = !check_no_run;
      check_options.out = check_out;
      return taskmatrix::harness::run_check_robot(catalog, registry, check_options, std::cout,
                                                  std::cerr);
    }
    if (*compare) {
      compare_options.base_dir = compare_base;
      compare_options.new_dir = compare_new;
      compare_options.report_dir = compare_report;
      compare_options.snapshot = [&catalog](const std::string& dir_and_trial, double time_s) {
        taskmatrix::harness::FrameOptions frame;
        frame.width = 480;
        frame.height = 360;
        return taskmatrix::harness::failure_pictures(catalog, dir_and_trial, time_s, frame);
      };
      compare_options.render_command = render_command_prefix();
      const taskmatrix::harness::CompareJobResult r =
          taskmatrix::harness::run_compare_job(compare_options, std::cout);
      if (compare_fail_models && r.differences.models_changed()) {
        std::cerr << "taskmatrix: compare: the runs' model files differ "
                     "(--fail-on-model-change)\n";
        return 1;
      }
      return compare_fail && r.comparison.regression() ? 1 : 0;
    }
    if (*validate || *run || *merge) {
      taskmatrix::core::ProgramRegistry registry;
      taskmatrix::programs::register_programs(registry);
      if (*validate) {
        const int trials = taskmatrix::harness::validate_run_plan(catalog, registry, validate_file);
        std::cout << validate_file << ": ok, " << trials << " trials\n";
        return 0;
      }
      if (*merge) {
        merge_options.out = merge_out;
        merge_options.shard_dirs.assign(merge_dirs.begin(), merge_dirs.end());
        merge_options.command_line.assign(argv, argv + argc);
        const taskmatrix::harness::MergeJobResult r = taskmatrix::harness::run_merge_job(
            catalog, registry, merge_options, std::cout, std::cerr);
        if (r.dir.empty()) return 1;
        std::cerr << "taskmatrix: merged " << merge_dirs.size()
                  << " shard directories: " << r.merged << " of " << r.planned << " trials in "
                  << r.dir.string() << " (" << r.successes << " succeeded)\n";
        return 0;
      }
      if (!shard_spec.empty()) {
        run_options.shard = taskmatrix::harness::parse_shard(shard_spec, "--shard");
      } else if (run_options.only.empty()) {
        if (const auto shard = taskmatrix::harness::slurm_array_shard(std::getenv)) {
          run_options.shard = *shard;
          std::cerr << "taskmatrix: shard " << shard->index << "/" << shard->count
                    << " from SLURM_ARRAY_TASK_ID (--shard I/N overrides it)\n";
        }
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
