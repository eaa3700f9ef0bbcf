#include "fuzz/fuzz_targets.h"

#include <zlib.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "harness/compare/bench_compare.h"
#include "harness/compare/compare.h"
#include "harness/compare/compare_job.h"
#include "harness/compare/html_report.h"
#include "harness/replay/replay.h"
#include "harness/replay/trajectory_file.h"
#include "harness/results/json_input.h"
#include "harness/results/ompl_log.h"
#include "harness/results/summary.h"
#include "harness/results/trial_record.h"
#include "harness/run/run_job.h"
#include "harness/scenario/model_catalog.h"
#include "taskmatrix/core/input_error.h"
#include "taskmatrix/mujoco/scene.h"
#include "taskmatrix/programs/primitives.h"

namespace taskmatrix::fuzz {

namespace {

namespace fs = std::filesystem;

fs::path g_root;                            // the project
std::map<std::string, fs::path> g_scratch;  // per target: a copy of models/ and scenarios/

std::string slurp(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void write(const fs::path& file, const std::string& bytes) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out << bytes;
  if (!out) throw std::runtime_error(file.string() + ": cannot write the fuzz input");
}

// A fresh copy of the project's models and scenarios for one target, made once: targets
// overwrite files in it and must not disturb each other or the project.
const fs::path& scratch(const std::string& target) {
  auto& dir = g_scratch[target];
  if (dir.empty()) {
    std::string tmpl =
        (fs::temp_directory_path() / ("taskmatrix_fuzz_" + target + "_XXXXXX")).string();
    if (!mkdtemp(tmpl.data())) throw std::runtime_error("cannot make a scratch directory");
    dir = tmpl;
    fs::copy(g_root / "models", dir / "models", fs::copy_options::recursive);
    fs::copy(g_root / "scenarios", dir / "scenarios", fs::copy_options::recursive);
    fs::create_directories(dir / "run" / "trajectories");
  }
  return dir;
}

// The folder a profile or environment file belongs in: the one its `name:` names, if the
// scratch copy has it (a name must match its folder), else `fallback`.
std::string folder_for(const std::string& text, const fs::path& parent,
                       const std::string& fallback) {
  size_t at = text.rfind("name: ", 0) == 0 ? 0 : text.find("\nname: ");
  if (at == std::string::npos) return fallback;
  at = text.find("name: ", at) + 6;
  const std::string name = text.substr(at, text.find_first_of("\r\n #", at) - at);
  std::error_code ec;
  return harness::is_safe_name(name) && fs::is_directory(parent / name, ec) ? name : fallback;
}

core::ProgramRegistry fresh_registry() {
  core::ProgramRegistry registry;
  programs::register_programs(registry);
  return registry;
}

void validate(const fs::path& root, const fs::path& file) {
  const harness::ModelCatalog catalog(root);
  core::ProgramRegistry registry = fresh_registry();
  harness::validate_run_plan(catalog, registry, file);
}

void scene_of(const fs::path& root, const std::string& robot, const std::string& environment) {
  const harness::ModelCatalog catalog(root);
  mujoco::Scene::load(catalog.robot_dir(robot), catalog.environment_dir(environment));
}

void run_scenario(const std::string& input) {
  const fs::path& root = scratch("scenario");
  const fs::path file = root / "scenarios" / "programs" / "fuzz_input.yaml";
  write(file, input);
  validate(root, file);
}

void run_suite(const std::string& input) {
  const fs::path& root = scratch("suite");
  const fs::path file = root / "scenarios" / "suites" / "fuzz_input.yaml";
  write(file, input);
  validate(root, file);
}

void run_profile(const std::string& input) {
  const fs::path& root = scratch("profile");
  const fs::path robots = root / "models" / "robots";
  const std::string robot = folder_for(input, robots, "minibot");
  write(robots / robot / "profile.yaml", input);
  scene_of(root, robot, "kitchen");
}

void run_environment(const std::string& input) {
  const fs::path& root = scratch("environment");
  const fs::path environments = root / "models" / "environments";
  const std::string environment = folder_for(input, environments, "kitchen");
  write(environments / environment / "environment.yaml", input);
  scene_of(root, "minibot", environment);
}

void run_mjcf(const std::string& input) {
  const fs::path& root = scratch("mjcf");
  write(root / "models" / "robots" / "minibot" / "minibot.xml", input);
  scene_of(root, "minibot", "kitchen");
}

void run_urdf(const std::string& input) {
  const fs::path& root = scratch("urdf");
  write(root / "models" / "robots" / "minibot" / "minibot.urdf", input);
  scene_of(root, "minibot_urdf", "kitchen");
}

// A run directory holding the input as trials.jsonl, read as `compare` and `--resume` read
// it, then summarised, logged and compared with itself as `run` and `compare` would.
void run_trials(const std::string& input) {
  const fs::path dir = scratch("trials") / "run";
  write(dir / "trials.jsonl", input);
  const harness::TrialsFile file = harness::read_trials_file(dir / "trials.jsonl");
  std::vector<nlohmann::json> trials = harness::read_run_trials(dir);
  const nlohmann::json summary = harness::make_summary({"fuzz", "", 1, false, 0, 1}, trials);
  harness::summary_markdown(summary);
  harness::OmplLogInfo info;
  info.experiment = "fuzz";
  harness::ompl_log_text(info, trials);
  try {
    const harness::Comparison c = harness::compare_trials(trials, trials, true, {});
    harness::comparison_markdown(c);
    harness::json_text(harness::comparison_json(c));
    harness::compare_html(c, trials, trials, nullptr, nullptr, {}, 0);
  } catch (const std::invalid_argument&) {
    // Two trials with one identity: compare refuses them (run_compare_job names the files).
  }
  (void)file;
}

// The input is the unpacked content of a trajectory file; it is packed as `run` packs it.
void run_trajectory(const std::string& input) {
  const fs::path& root = scratch("trajectory");
  const fs::path file = root / "run" / "trajectories" / "fuzz.traj.gz";
  {
    gzFile gz = gzopen(file.c_str(), "wb1");
    if (!gz) throw std::runtime_error("cannot write the fuzz trajectory");
    gzwrite(gz, input.data(), static_cast<unsigned>(input.size()));
    gzclose(gz);
  }
  harness::TrajectoryFile t = harness::read_trajectory_file(file);
  harness::Replay replay(harness::ModelCatalog(root), std::move(t));
  if (replay.frames() > 0) {
    replay.show(replay.frames() - 1);
    replay.show(replay.frame_at(replay.time_of(0) + 0.5));
  }
}

void run_bench(const std::string& input) {
  const fs::path& root = scratch("bench");
  const fs::path file = root / "run" / "bench.json";
  write(file, input);
  const harness::BenchFile now = harness::read_bench_file(file);
  const harness::BenchFile base =
      harness::read_bench_file(g_root / "results" / "baselines" / "bench.json");
  std::ostringstream out;
  harness::run_bench_compare(g_root / "results" / "baselines" / "bench.json", file, {}, true, out);
  (void)now;
  (void)base;
}

}  // namespace

const std::vector<Target>& targets() {
  static const std::vector<Target> all = {
      {"scenario",
       "a scenario file (taskmatrix validate)",
       {"scenarios/programs/reach.yaml", "scenarios/programs/putdown.yaml",
        "scenarios/programs/explore.yaml", "fuzz/seeds/scenario/machine.yaml",
        "fuzz/seeds/scenario/everything.yaml"},
       4},
      {"suite",
       "a suite file (taskmatrix validate)",
       {"scenarios/suites/planners.yaml", "fuzz/seeds/suite/small.yaml"},
       6},
      {"profile",
       "a robot profile (scene load)",
       {"models/robots/minibot/profile.yaml", "models/robots/tallbot/profile.yaml",
        "models/robots/minibot_urdf/profile.yaml"},
       4},
      {"environment",
       "an environment.yaml (scene load)",
       {"models/environments/kitchen/environment.yaml",
        "models/environments/office/environment.yaml"},
       4},
      {"mjcf", "a robot's MJCF model (scene load)", {"models/robots/minibot/minibot.xml"}, 4},
      {"urdf", "a robot's URDF model (scene load)", {"models/robots/minibot/minibot.urdf"}, 4},
      {"trials",
       "a run directory's trials.jsonl (compare, --resume, summaries, OMPL log)",
       {"fuzz/seeds/trials/trials.jsonl"},
       1},
      {"trajectory",
       "a recorded trajectory file, unpacked (render --trial, --video)",
       {"fuzz/seeds/trajectory/reach.traj"},
       4},
      {"bench", "a Google Benchmark JSON file (bench-compare)", {"fuzz/seeds/bench/small.json"}, 1},
  };
  return all;
}

const Target* find_target(const std::string& name) {
  for (const Target& t : targets()) {
    if (t.name == name) return &t;
  }
  return nullptr;
}

void set_up(const fs::path& root) {
  g_root = root;
  for (const Target& t : targets()) scratch(t.name);  // before any fork: children share them
}

void tear_down() {
  std::error_code ec;
  for (const auto& [name, dir] : g_scratch) fs::remove_all(dir, ec);
  g_scratch.clear();
}

bool run(const Target& target, const std::uint8_t* data, std::size_t size) {
  const std::string input(reinterpret_cast<const char*>(data), size);
  static const std::map<std::string, void (*)(const std::string&)> kRunners = {
      {"scenario", run_scenario}, {"suite", run_suite},
      {"profile", run_profile},   {"environment", run_environment},
      {"mjcf", run_mjcf},         {"urdf", run_urdf},
      {"trials", run_trials},     {"trajectory", run_trajectory},
      {"bench", run_bench}};
  try {
    kRunners.at(target.name)(input);
    return true;
  } catch (const core::InputError&) {
    return false;
  }
}

std::vector<std::string> seed_inputs(const Target& target, const fs::path& root) {
  std::vector<std::string> out;
  for (const std::string& rel : target.seeds) {
    if (!fs::is_regular_file(root / rel)) {
      throw std::runtime_error("missing seed input " + (root / rel).string());
    }
    out.push_back(slurp(root / rel));
  }
  return out;
}

}  // namespace taskmatrix::fuzz
