// The scenario runner end to end: worker processes, result files, reproducibility for any
// number of jobs and from a trial id alone, failures contained as statuses, interrupted runs
// resumed, the OMPL benchmark log read by OMPL's own script, recorded trajectories replayed.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <thread>

#include <mujoco/mujoco.h>

#include "harness/replay/replay.h"
#include "harness/replay/trajectory_file.h"
#include "harness/results/trial_record.h"
#include "harness/results/trial_schema.h"
#include "harness/run/run_job.h"
#include "harness/run/trial.h"
#include "taskmatrix/core/input_error.h"
#include "taskmatrix/mujoco/mujoco_view.h"
#include "taskmatrix/programs/primitives.h"
#include "tests/test_support.h"

namespace taskmatrix::harness {
namespace {

// ---- Programs that misbehave, for the runner's containment.
class Misbehaving : public core::TaskProgram {
 public:
  explicit Misbehaving(std::string how) : how_(std::move(how)) {}
  std::vector<std::string> chains(const core::Skillset& skills) const override {
    return {skills.chains().front().name};
  }
  void start(core::ProgramContext&) override {}
  core::ProgramState step(core::ProgramContext& ctx) override {
    if (how_ == "segfault") std::raise(SIGSEGV);
    if (how_ == "mju_error") mju_error("injected by the test");
    if (how_ == "hang") std::this_thread::sleep_for(std::chrono::hours(1));
    if (how_ == "throw") throw std::runtime_error("thrown by the test");
    if (how_ == "diverge") {
      // Accelerations no physics can follow: MuJoCo flags bad accelerations.
      const std::vector<std::string> chain = chains(ctx.skills());
      const std::vector<double> q = ctx.skills().configuration(chain);
      ctx.skills().command(chain, q, std::vector<double>(q.size(), 0.0),
                           std::vector<double>(q.size(), 1e14));
    }
    return core::ProgramState::kRunning;
  }

 private:
  std::string how_;
};

void register_misbehaving(core::ProgramRegistry& registry) {
  for (const char* how : {"segfault", "mju_error", "hang", "diverge", "throw"}) {
    registry.add({std::string("test_") + how, "misbehaves", {}, [how](const core::Params&) {
                    return std::make_unique<Misbehaving>(how);
                  }});
  }
}

class Runner : public ::testing::Test {
 protected:
  void SetUp() override {
    char tmpl[] = "/tmp/taskmatrix_runner_XXXXXX";
    dir_ = mkdtemp(tmpl);
    programs::register_programs(registry_);
    register_misbehaving(registry_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name) << text;
    return dir_ / name;
  }
  RunJobResult run(const std::filesystem::path& scenario, const std::string& out, int jobs,
                   std::string* err_text = nullptr, RunJobOptions options = {}) {
    options.scenario_file = scenario;
    if (!out.empty()) options.out = dir_ / out;
    options.jobs = jobs;
    if (options.progress == RunJobOptions::Progress::kAuto) {
      options.progress = RunJobOptions::Progress::kOff;
    }
    std::ostringstream o, e;
    RunJobResult r = run_job(test::catalog(), registry_, options, o, e);
    if (err_text) *err_text = e.str();
    last_out_ = o.str();
    return r;
  }
  static std::map<std::string, nlohmann::json> by_id(const std::filesystem::path& run_dir) {
    std::map<std::string, nlohmann::json> out;
    for (const nlohmann::json& t : read_trials_file(run_dir / "trials.jsonl").trials) {
      EXPECT_EQ(out.count(t["trial_id"]), 0u) << "duplicate " << t["trial_id"];
      out[t["trial_id"]] = t;
    }
    return out;
  }
  std::filesystem::path dir_;
  core::ProgramRegistry registry_;
  std::string last_out_;
};

// Four quick trials: reach on both robots in the kitchen, two layouts each.
constexpr const char* kReachScenario =
    "name: quick_reach\nprogram: reach\nparams: {object: cup}\nrobots: [minibot, tallbot]\n"
    "environments: [kitchen]\nobstacles: {count: 6}\nlayout_seed: 20\ntrials: 2\n"
    "time_limit_s: 30\nsuccess: graspable(cup)\n";

nlohmann::json comparable(nlohmann::json t) {
  t = without_timing(std::move(t));
  t.erase("trajectory");  // where it was written, and whether
  t.erase("trajectory_frames");
  return t;
}

TEST_F(Runner, ResultsAreTheSameForAnyNumberOfJobsAndFromATrialIdAlone) {
  const auto scenario = write("quick_reach.yaml", kReachScenario);
  const RunJobResult one = run(scenario, "one", 1);
  const RunJobResult two = run(scenario, "two", 2);
  EXPECT_EQ(one.planned, 4);
  EXPECT_EQ(one.finished, 4);
  EXPECT_EQ(two.finished, 4);
  EXPECT_FALSE(two.interrupted);
  const auto a = by_id(one.dir), b = by_id(two.dir);
  ASSERT_EQ(a.size(), 4u);
  ASSERT_EQ(b.size(), 4u);
  int successes = 0;
  for (const auto& [id, t] : a) {
    ASSERT_TRUE(b.count(id)) << id;
    EXPECT_EQ(comparable(t), comparable(b.at(id))) << id;
    successes += t["success"].get<bool>();
    // The contract's fields are all there, and measured.
    for (const char* key : {"trial_id",
                            "scenario",
                            "robot",
                            "environment",
                            "program",
                            "planner",
                            "seed",
                            "layout_seed",
                            "success",
                            "status",
                            "failure_reason",
                            "planning_time_s",
                            "simplification_time_s",
                            "plan_calls",
                            "collision_checks",
                            "ik_time_s",
                            "path_length_joint",
                            "path_length_ee_m",
                            "duration_s",
                            "smoothness",
                            "min_clearance_m",
                            "wall_time_s",
                            "events",
                            "peak_memory_mb",
                            "trajectory"}) {
      EXPECT_TRUE(t.contains(key)) << id << " lacks " << key;
    }
    // The record holds the schema's fields (harness/results/trial_schema.h), and no other.
    for (const TrialField& f : kTrialFields) {
      EXPECT_TRUE(t.contains(std::string(f.name))) << id << " lacks schema field " << f.name;
    }
    for (const auto& [key, value] : t.items()) {
      EXPECT_TRUE(std::any_of(kTrialFields.begin(), kTrialFields.end(),
                              [&](const TrialField& f) { return f.name == key; }))
          << id << ": field " << key << " is not in the trial schema";
    }
    if (t["success"].get<bool>()) {
      EXPECT_GT(t["plan_calls"].get<int>(), 0);
      EXPECT_GT(t["collision_checks"].get<int>(), 100);
      EXPECT_GT(t["path_length_ee_m"].get<double>(), 0.1);
      EXPECT_GT(t["wall_time_s"].get<double>(), t["planning_time_s"].get<double>());
      EXPECT_GT(t["peak_memory_mb"].get<double>(), 10.0);
      EXPECT_GE(t["min_clearance_m"].get<double>(), 0.0);
      EXPECT_EQ(t["events"].front()["type"], "started");
      EXPECT_EQ(t["events"].back()["type"], "completed");
    }
  }
  EXPECT_GE(successes, 2);  // reach succeeds on most layouts; the runner's figures say which
  // The summaries agree on every count and rate.
  auto groups = [](const std::filesystem::path& d) {
    nlohmann::json s = nlohmann::json::parse(std::ifstream(d / "summary.json"));
    nlohmann::json out = nlohmann::json::array();
    for (nlohmann::json g : s["groups"]) {
      out.push_back({g["scenario"], g["robot"], g["planner"], g["trials"], g["successes"],
                     g["success_ci95"], g["statuses"], g["path_length_joint"]});
    }
    return out;
  };
  EXPECT_EQ(groups(one.dir), groups(two.dir));
  const nlohmann::json summary = nlohmann::json::parse(std::ifstream(two.dir / "summary.json"));
  EXPECT_EQ(summary["overall"]["trials"], 4);
  EXPECT_EQ(summary["overall"]["successes"], successes);
  EXPECT_TRUE(summary["run"]["complete"].get<bool>());
  std::ifstream md(two.dir / "summary.md");
  const std::string md_text((std::istreambuf_iterator<char>(md)), std::istreambuf_iterator<char>());
  EXPECT_NE(md_text.find("| quick_reach | tallbot | kitchen | RRTConnect |"), std::string::npos);
  // Statistical power: with 2 trials a group (4 in all) no change is detectable, and the
  // summary says how many trials a 10-point change needs.
  ASSERT_EQ(summary["power"]["groups"].size(), 2u);
  for (const nlohmann::json& g : summary["power"]["groups"]) {
    EXPECT_TRUE(g["detectable_success_change"].is_null()) << g;
    EXPECT_GT(g["trials_for_target"].get<int>(), 10) << g;
  }
  EXPECT_TRUE(summary["power"]["overall"]["detectable_success_change"].is_null());
  EXPECT_NE(md_text.find("## Statistical power"), std::string::npos);
  EXPECT_NE(md_text.find("| quick_reach | tallbot | kitchen | RRTConnect | 2 |"),
            std::string::npos);
  EXPECT_NE(md_text.find("none (2 trials)"), std::string::npos);
  EXPECT_NE(md_text.find("| all trials |  |  |  | 4 |"), std::string::npos);
  const nlohmann::json prov = nlohmann::json::parse(std::ifstream(two.dir / "provenance.json"));
  EXPECT_EQ(prov["mujoco_version"], "2.2.2");
  EXPECT_EQ(prov["ompl_version"], "1.5.2");
  EXPECT_EQ(prov["scenario_hash"].get<std::string>().size(), 7u + 64u);
  EXPECT_EQ(prov["trials"]["finished"], 4);

  // One trial again from its id alone: the same line, bit for bit (timings aside).
  const std::string id = a.rbegin()->first;
  RunJobOptions only;
  only.only = id;
  const RunJobResult r = run(scenario, "", 1, nullptr, only);
  EXPECT_TRUE(r.dir.empty());  // nothing written without --out
  const nlohmann::json again = nlohmann::json::parse(last_out_);
  EXPECT_EQ(comparable(again), comparable(a.at(id)));
}

TEST_F(Runner, OmplBenchmarkStatisticsReadsTheLogWithoutComplaint) {
  const auto file = write("two_planners.yaml",
                          "program: reach\nparams: {object: cup}\nrobots: [minibot]\n"
                          "environments: [kitchen]\nobstacles: {count: 4}\ntrials: 2\n"
                          "planners: [RRTConnect, {name: RRTConnect, label: RRTConnect_r02, "
                          "params: {range: 0.2}}]\n");
  const RunJobResult r = run(file, "arena", 2);
  ASSERT_EQ(r.finished, 4);
  const std::string db = (dir_ / "arena.db").string();
  const std::string command = "ompl_benchmark_statistics '" + (r.dir / "ompl.log").string() +
                              "' -d '" + db + "' >'" + (dir_ / "stats.out").string() + "' 2>'" +
                              (dir_ / "stats.err").string() + "'";
  ASSERT_EQ(std::system(command.c_str()), 0) << "see " << command;
  std::ifstream err(dir_ / "stats.err");
  const std::string err_text((std::istreambuf_iterator<char>(err)),
                             std::istreambuf_iterator<char>());
  EXPECT_EQ(err_text, "");  // no warnings, no errors
  // The database holds both planners, two runs each, with the trials' figures.
  const std::string query =
      "python3 -c \"import sqlite3; c = sqlite3.connect('" + db +
      "'); print(c.execute('select count(*), count(distinct plannerid), sum(solved), "
      "min(collision_checks) > 0 from runs').fetchone()); print(c.execute('select count(*) from "
      "enums where name = \\\"robot\\\"').fetchone())\" > '" +
      (dir_ / "q.out").string() + "'";
  ASSERT_EQ(std::system(query.c_str()), 0);
  std::ifstream q(dir_ / "q.out");
  const std::string q_text((std::istreambuf_iterator<char>(q)), std::istreambuf_iterator<char>());
  const auto trials = by_id(r.dir);
  int solved = 0;
  for (const auto& [id, t] : trials) solved += t["success"].get<bool>();
  EXPECT_EQ(q_text, "(4, 2, " + std::to_string(solved) + ", 1)\n(1,)\n");
}

TEST_F(Runner, CrashesHangsAndDivergenceAreStatusesAndTheRunGoesOn) {
  const std::string tail = "robots: [minibot]\nenvironments: [kitchen]\nwall_limit_s: 3\n";
  write("segfault.yaml", "program: test_segfault\n" + tail);
  write("mju_error.yaml", "program: test_mju_error\n" + tail);
  write("hang.yaml", "program: test_hang\n" + tail);
  write("diverge.yaml", "program: test_diverge\n" + tail);
  write("throw.yaml", "program: test_throw\n" + tail);
  write("fine.yaml", "program: postural\nparams: {posture: rest}\n" + tail);
  const auto suite = write("faults.yaml",
                           "suite: faults\nscenarios: [segfault.yaml, "
                           "mju_error.yaml, hang.yaml, diverge.yaml, throw.yaml, fine.yaml]\n");
  const RunJobResult r = run(suite, "faults", 2);
  EXPECT_EQ(r.finished, 6);
  const auto t = by_id(r.dir);
  auto get = [&](const std::string& scenario) {
    return t.at(scenario + ".minibot.kitchen.RRTConnect.l1.s1");
  };
  EXPECT_EQ(get("segfault")["status"], "crash");
  EXPECT_NE(get("segfault")["failure_reason"].get<std::string>().find("signal 11"),
            std::string::npos);
  EXPECT_EQ(get("mju_error")["status"], "crash");
  EXPECT_NE(get("mju_error")["failure_reason"].get<std::string>().find("injected by the test"),
            std::string::npos);
  EXPECT_EQ(get("hang")["status"], "timeout");
  EXPECT_GE(get("hang")["wall_time_s"].get<double>(), 3.0);
  EXPECT_LT(get("hang")["wall_time_s"].get<double>(), 10.0);
  EXPECT_EQ(get("diverge")["status"], "sim_unstable") << get("diverge")["failure_reason"];
  // A program that throws fails its own trial with the exception's text; the worker lives on.
  EXPECT_EQ(get("throw")["status"], "program_error") << get("throw")["failure_reason"];
  EXPECT_NE(get("throw")["failure_reason"].get<std::string>().find("thrown by the test"),
            std::string::npos)
      << get("throw")["failure_reason"];
  EXPECT_EQ(get("fine")["status"], "success") << get("fine")["failure_reason"];
  // What was not measured is null, not zero.
  EXPECT_TRUE(get("segfault")["planning_time_s"].is_null());
  const nlohmann::json summary = nlohmann::json::parse(std::ifstream(r.dir / "summary.json"));
  EXPECT_EQ(summary["overall"]["statuses"]["crash"], 2);
  EXPECT_EQ(summary["overall"]["statuses"]["timeout"], 1);
}

TEST_F(Runner, BadInputWritesNothing) {
  const auto bad = write("bad.yaml", std::string(kReachScenario) + "planners: [Nope]\n");
  RunJobOptions options;
  EXPECT_THROW(run(bad, "never", 1, nullptr, options), core::InputError);
  EXPECT_FALSE(std::filesystem::exists(dir_ / "never"));
  // From the command line: one line naming the file and key, exit status 2, no directory.
  const test::CommandResult cli =
      test::run_cli("run '" + bad.string() + "' --out '" + (dir_ / "never").string() + "'",
                    test::catalog().root());
  EXPECT_EQ(cli.exit_code, 2);
  EXPECT_NE(cli.err.find("bad.yaml:11: planners"), std::string::npos) << cli.err;
  EXPECT_EQ(std::count(cli.err.begin(), cli.err.end(), '\n'), 1) << cli.err;
  EXPECT_FALSE(std::filesystem::exists(dir_ / "never"));
  const test::CommandResult v =
      test::run_cli("validate '" + bad.string() + "'", test::catalog().root());
  EXPECT_EQ(v.exit_code, 2);
  EXPECT_NE(v.err.find("unknown planner 'Nope'"), std::string::npos) << v.err;
}

// A trial's id does not name its execution mode: resuming a kinematic run in physics would have
// kept the kinematic trials as this run's. Refused, naming both modes; the directory is left
// as it was.
TEST_F(Runner, AResumeInAnotherExecutionModeIsRefused) {
  const auto file = write("modes.yaml",
                          "program: postural\nparams: {posture: rest}\n"
                          "robots: [minibot]\nenvironments: [kitchen]\n");
  RunJobOptions kinematic;
  kinematic.overrides.execution = "kinematic";
  run(file, "modes", 1, nullptr, kinematic);
  auto trials_text = [&] {
    std::ostringstream text;
    text << std::ifstream(dir_ / "modes" / "trials.jsonl").rdbuf();
    return text.str();
  };
  const std::string before = trials_text();
  RunJobOptions physics;
  physics.resume = true;
  try {
    run(file, "modes", 1, nullptr, physics);
    ADD_FAILURE() << "resumed";
  } catch (const core::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--resume: the run there ran with --execution "
                                         "kinematic, now the scenarios' own execution modes"),
              std::string::npos)
        << e.what();
  }
  EXPECT_EQ(trials_text(), before);
  kinematic.resume = true;
  EXPECT_EQ(run(file, "modes", 1, nullptr, kinematic).finished, 1);
}

TEST_F(Runner, ProgressLineOnlyWhenAsked) {
  const auto file = write("one.yaml",
                          "program: postural\nparams: {posture: rest}\n"
                          "robots: [minibot]\nenvironments: [kitchen, office]\n");
  std::string err;
  RunJobOptions on;
  on.progress = RunJobOptions::Progress::kOn;
  run(file, "on", 1, &err, on);
  EXPECT_NE(err.find("\r[1/2] success 1/1 (100%)"), std::string::npos) << err;
  EXPECT_NE(err.find("\r[2/2] success 2/2 (100%)"), std::string::npos) << err;
  EXPECT_NE(err.find("ETA"), std::string::npos);
  RunJobOptions off;
  off.progress = RunJobOptions::Progress::kOff;
  run(file, "off", 1, &err, off);
  EXPECT_EQ(err, "");
}

// Starts `taskmatrix run` in the background and returns its pid once `lines` trials are in.
pid_t start_cli_until(const std::vector<std::string>& args, const std::filesystem::path& trials,
                      size_t lines) {
  const pid_t pid = fork();
  if (pid == 0) {
    std::vector<char*> argv;
    std::string cli = TASKMATRIX_CLI;
    argv.push_back(cli.data());
    std::vector<std::string> copy = args;
    for (std::string& a : copy) argv.push_back(a.data());
    argv.push_back(nullptr);
    const int devnull = open("/dev/null", O_WRONLY);
    dup2(devnull, 1);
    dup2(devnull, 2);
    execv(cli.c_str(), argv.data());
    _exit(127);
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (std::chrono::steady_clock::now() < deadline) {
    if (read_trials_file(trials).trials.size() >= lines) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return pid;
}

TEST_F(Runner, AKilledRunLosesNoTrialAndResumesWithoutDuplicates) {
  const auto file = write("quick_reach.yaml", kReachScenario);
  const std::filesystem::path out = dir_ / "killed";
  const pid_t pid = start_cli_until({"run", file.string(), "--out", out.string(), "--jobs", "1"},
                                    out / "trials.jsonl", 1);
  kill(pid, SIGKILL);
  int status = 0;
  waitpid(pid, &status, 0);
  const size_t before = read_trials_file(out / "trials.jsonl").trials.size();
  ASSERT_GE(before, 1u);
  ASSERT_LT(before, 4u) << "the run finished before it could be killed";
  // A line torn by the kill.
  std::ofstream(out / "trials.jsonl", std::ios::app) << "{\"trial_id\": \"quick_reach.mini";
  std::string err;
  RunJobOptions resume;
  resume.resume = true;
  const RunJobResult r = run(file, "killed", 2, &err, resume);
  EXPECT_NE(err.find("dropped a torn last line"), std::string::npos) << err;
  EXPECT_EQ(r.ran, static_cast<int>(4 - before));
  EXPECT_EQ(r.finished, 4);
  const auto t = by_id(out);  // checks for duplicates
  EXPECT_EQ(t.size(), 4u);
  // Resuming a finished run runs nothing.
  const RunJobResult again = run(file, "killed", 2, &err, resume);
  EXPECT_EQ(again.ran, 0);
  EXPECT_EQ(by_id(out).size(), 4u);
  // A run directory of other scenario files is not resumed into.
  const auto other = write("other.yaml", std::string(kReachScenario) + "seed: 5\n");
  RunJobOptions wrong = resume;
  EXPECT_THROW(run(other, "killed", 1, nullptr, wrong), core::InputError);
}

TEST_F(Runner, InterruptStopsCleanlyAndSaysSo) {
  const auto file = write("quick_reach.yaml", kReachScenario);
  const std::filesystem::path out = dir_ / "interrupted";
  const pid_t pid = start_cli_until({"run", file.string(), "--out", out.string(), "--jobs", "1"},
                                    out / "trials.jsonl", 1);
  kill(pid, SIGINT);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  const int finished = static_cast<int>(read_trials_file(out / "trials.jsonl").trials.size());
  ASSERT_LT(finished, 4) << "the run finished before it could be interrupted";
  EXPECT_EQ(WEXITSTATUS(status), 130);
  const nlohmann::json s = nlohmann::json::parse(std::ifstream(out / "summary.json"));
  EXPECT_TRUE(s["run"]["interrupted"].get<bool>());
  EXPECT_EQ(s["run"]["finished_trials"], finished);
  EXPECT_FALSE(s["run"]["complete"].get<bool>());
  // No trial was recorded as failed because of the interrupt.
  for (const nlohmann::json& t : read_trials_file(out / "trials.jsonl").trials) {
    EXPECT_NE(t["status"], "crash") << t["failure_reason"];
  }
}

TEST_F(Runner, RecordedTrajectoriesReplayTheTrial) {
  Scenario s = load_run_plan(test::catalog().root() / "scenarios" / "programs" / "vacuum.yaml",
                             test::catalog(), registry_)
                   .scenarios[0];
  std::vector<double> final_qpos;
  TrialOptions options;
  options.record_rate_hz = 25;
  const auto scene = test::scene("tallbot", "kitchen");
  const TrialResult r = run_trial(
      s, *test::loaded_scene("tallbot", "kitchen"), s.layout_seed, s.seed, registry_,
      [&](const std::string& moment, const core::TrialWorld& world) {
        if (moment == "end") {
          const mujoco::MujocoSkillset& skills = test::mujoco_skills(world);
          final_qpos.assign(skills.sim_data()->qpos, skills.sim_data()->qpos + skills.model()->nq);
        }
      },
      options);
  ASSERT_TRUE(r.success) << trial_failure_reason(r);
  ASSERT_EQ(r.removed_debris.size(), 5u);
  // 25 frames per simulated second, the last at the end of the trial.
  EXPECT_NEAR(static_cast<double>(r.recording.frames()), r.sim_time_s * 25, 3.0);
  TrajectoryFile file{"tallbot", "kitchen", scene->make_layout(s.obstacles, s.layout_seed),
                      r.recording, r.removed_debris};
  const auto path = dir_ / "vacuum.traj.gz";
  write_trajectory_file(path, file);
  EXPECT_LT(std::filesystem::file_size(path), 200u * 1024u);
  Replay replay(test::catalog(), read_trajectory_file(path));
  ASSERT_EQ(replay.frames(), r.recording.frames());
  replay.show(replay.frames() - 1);
  EXPECT_NEAR(replay.time_of(replay.frames() - 1), r.sim_time_s, 0.05);
  // The replayed end state is the trial's own (float precision), with every flake gone.
  const mujoco::WorkerScene& worker =
      dynamic_cast<const mujoco::MujocoView&>(replay.view()).worker();
  for (size_t i = 0; i < final_qpos.size(); ++i) {
    EXPECT_NEAR(worker.data()->qpos[i], final_qpos[i], 1e-3) << "qpos " << i;
  }
  for (const std::string& flake : r.removed_debris) {
    EXPECT_LT(replay.view().position(flake).z(), -5.0) << flake;
  }
  replay.show(0);
  for (const std::string& flake : r.removed_debris) {
    EXPECT_GT(replay.view().position(flake).z(), 0.5) << flake << " at the start";
  }
  // A truncated file is refused with its name.
  std::filesystem::resize_file(path, std::filesystem::file_size(path) / 2);
  try {
    read_trajectory_file(path);
    FAIL() << "a truncated file was read";
  } catch (const core::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("vacuum.traj.gz"), std::string::npos) << e.what();
  }
}

TEST_F(Runner, RenderReplaysATrialFromTheRunDirectory) {
  const auto file = write("one.yaml",
                          "program: reach\nparams: {object: cup}\n"
                          "robots: [minibot]\nenvironments: [kitchen]\n");
  const RunJobResult r = run(file, "render", 1);
  const auto trials = by_id(r.dir);
  ASSERT_EQ(trials.size(), 1u);
  const std::string id = trials.begin()->first;
  const auto png = dir_ / "frame.png";
  const test::CommandResult cli =
      test::run_cli("render --trial '" + r.dir.string() + ":" + id +
                        "' --time 1.0 --width 320 --height 240 --out '" + png.string() + "'",
                    test::catalog().root());
  EXPECT_EQ(cli.exit_code, 0) << cli.err;
  EXPECT_NE(cli.out.find("at t = 1.00 s"), std::string::npos) << cli.out;
  EXPECT_GT(std::filesystem::file_size(png), 10000u);
  const test::CommandResult missing =
      test::run_cli("render --trial '" + r.dir.string() + ":nope' --out '" + png.string() + "'",
                    test::catalog().root());
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("trials.jsonl: nope: no trial with this id"), std::string::npos)
      << missing.err;
}

}  // namespace
}  // namespace taskmatrix::harness
