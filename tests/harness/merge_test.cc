// Sharded runs and their merge: shard specs from the command line and from a Slurm array
// task's environment, shards that partition the matrix, shard directories merged into the
// run one machine would have written (trials, summary, provenance, trajectories), and merges
// refused with the reason: missing or duplicated trials, another suite, build or matrix.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cstdlib>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "harness/compare/compare_job.h"
#include "harness/replay/trajectory_file.h"
#include "harness/results/trial_record.h"
#include "harness/run/merge_job.h"
#include "harness/run/run_job.h"
#include "harness/scenario/trial_matrix.h"
#include "taskmatrix/core/input_error.h"
#include "taskmatrix/programs/primitives.h"
#include "tests/test_support.h"

namespace taskmatrix::harness {
namespace {

namespace fs = std::filesystem;

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const core::InputError& e) {
    return e.what();
  }
  return "no InputError";
}

TEST(Shard, SpecsAreCheckedAndNameTheOption) {
  const Shard s = parse_shard("2/5", "--shard");
  EXPECT_EQ(s.index, 2);
  EXPECT_EQ(s.count, 5);
  EXPECT_EQ(s.from, "--shard");
  EXPECT_EQ(parse_shard("0/1", "--shard").count, 1);
  for (const char* bad : {"5/5", "-1/3", "1/0", "3", "", "a/b", "1/3/4", " 1/3", "1/2000000",
                          "99999999999/100000000000"}) {
    const std::string e = error_of([&] { parse_shard(bad, "--shard"); });
    EXPECT_NE(e.find("--shard"), std::string::npos) << bad << ": " << e;
    EXPECT_NE(e.find("0 <= I < N"), std::string::npos) << bad << ": " << e;
  }
}

TEST(Shard, ASlurmArrayTaskSelectsItsShard) {
  auto from = [](std::map<std::string, std::string> vars) {
    return slurm_array_shard([vars](const char* name) -> const char* {
      const auto it = vars.find(name);
      return it == vars.end() ? nullptr : it->second.c_str();
    });
  };
  EXPECT_FALSE(from({}).has_value());  // not an array task
  const auto plain = from({{"SLURM_ARRAY_TASK_ID", "2"}, {"SLURM_ARRAY_TASK_COUNT", "3"}});
  ASSERT_TRUE(plain.has_value());
  EXPECT_EQ(plain->index, 2);
  EXPECT_EQ(plain->count, 3);
  EXPECT_EQ(plain->from, "SLURM_ARRAY_TASK_ID");
  // --array=4-6 as Slurm describes it: task 5 is shard 1/3.
  const auto offset = from({{"SLURM_ARRAY_TASK_ID", "5"},
                            {"SLURM_ARRAY_TASK_COUNT", "3"},
                            {"SLURM_ARRAY_TASK_MIN", "4"},
                            {"SLURM_ARRAY_TASK_MAX", "6"},
                            {"SLURM_ARRAY_TASK_STEP", "1"}});
  ASSERT_TRUE(offset.has_value());
  EXPECT_EQ(offset->index, 1);
  EXPECT_EQ(offset->count, 3);
  // Arrays whose task count is not the shard count: a step, a sparse list, nonsense.
  for (const std::map<std::string, std::string>& bad :
       std::vector<std::map<std::string, std::string>>{
           {{"SLURM_ARRAY_TASK_ID", "2"},
            {"SLURM_ARRAY_TASK_COUNT", "3"},
            {"SLURM_ARRAY_TASK_MIN", "0"},
            {"SLURM_ARRAY_TASK_MAX", "4"},
            {"SLURM_ARRAY_TASK_STEP", "2"}},
           {{"SLURM_ARRAY_TASK_ID", "4"},
            {"SLURM_ARRAY_TASK_COUNT", "2"},
            {"SLURM_ARRAY_TASK_MIN", "1"},
            {"SLURM_ARRAY_TASK_MAX", "4"}},
           {{"SLURM_ARRAY_TASK_ID", "3"}, {"SLURM_ARRAY_TASK_COUNT", "3"}},
           {{"SLURM_ARRAY_TASK_ID", "x"}, {"SLURM_ARRAY_TASK_COUNT", "3"}},
           {{"SLURM_ARRAY_TASK_ID", "1"}}}) {
    const std::string e = error_of([&] { from(bad); });
    EXPECT_NE(e.find("SLURM_ARRAY_TASK_"), std::string::npos) << e;
  }
  EXPECT_NE(error_of([&] {
              from({{"SLURM_ARRAY_TASK_ID", "2"},
                    {"SLURM_ARRAY_TASK_COUNT", "3"},
                    {"SLURM_ARRAY_TASK_STEP", "2"},
                    {"SLURM_ARRAY_TASK_MIN", "0"},
                    {"SLURM_ARRAY_TASK_MAX", "4"}});
            }).find("pass --shard I/N"),
            std::string::npos);
}

TEST(Shard, ShardsPartitionTheMatrixByStride) {
  core::ProgramRegistry registry;
  programs::register_programs(registry);
  const RunPlan plan = load_run_plan(
      test::catalog().root() / "scenarios" / "suites" / "default.yaml", test::catalog(), registry);
  const std::vector<TrialSpec> matrix = trial_matrix(plan);
  ASSERT_GE(matrix.size(), 144u);
  for (int count : {1, 2, 5, static_cast<int>(matrix.size()), 300}) {
    std::multiset<std::string> all;
    for (int index = 0; index < count; ++index) {
      const std::vector<TrialSpec> shard = select_shard(matrix, {index, count, ""});
      EXPECT_LE(shard.size(),
                (matrix.size() + static_cast<size_t>(count) - 1) / static_cast<size_t>(count));
      for (size_t k = 0; k < shard.size(); ++k) {
        // Trial k of shard I is trial I + k N of the matrix.
        EXPECT_EQ(shard[k].id, matrix[static_cast<size_t>(index + static_cast<int>(k) * count)].id);
        all.insert(shard[k].id);
      }
    }
    EXPECT_EQ(all.size(), matrix.size()) << count << " shards";
    for (const TrialSpec& t : matrix) EXPECT_EQ(all.count(t.id), 1u) << t.id;
  }
}

// Four cheap trials (postural on both robots, two layouts), run as three shards.
class Merge : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    char tmpl[] = "/tmp/taskmatrix_merge_XXXXXX";
    dir_ = new fs::path(mkdtemp(tmpl));
    registry_ = new core::ProgramRegistry;
    programs::register_programs(*registry_);
    std::ofstream(*dir_ / "wave.yaml")
        << "program: postural\nparams: {posture: wave_start, side: as_named}\n"
           "robots: [minibot, tallbot]\nenvironments: [kitchen]\nobstacles: {count: 4}\n"
           "layout_seed: 7\ntrials: 2\nsuccess: postural(wave_start)\n";
  }
  // The three shards, run in-process (once per test process).
  static void need_shards() {
    if (fs::exists(*dir_ / "shard2")) return;
    for (int i = 0; i < 3; ++i) run_into("shard" + std::to_string(i), {i, 3, "--shard"}, 1);
  }
  static void TearDownTestSuite() {
    fs::remove_all(*dir_);
    delete dir_;
    delete registry_;
  }
  static RunJobResult run_into(const std::string& out, const Shard& shard, int jobs,
                               const RunOverrides& overrides = {}) {
    RunJobOptions o;
    o.scenario_file = *dir_ / "wave.yaml";
    o.out = *dir_ / out;
    o.jobs = jobs;
    o.shard = shard;
    o.overrides = overrides;
    o.progress = RunJobOptions::Progress::kOff;
    std::ostringstream sink;
    return run_job(test::catalog(), *registry_, o, sink, sink);
  }
  static MergeJobResult merge(const std::string& out, const std::vector<std::string>& shards,
                              bool allow_partial = false, std::string* err_text = nullptr) {
    MergeJobOptions o;
    o.out = *dir_ / out;
    for (const std::string& s : shards) o.shard_dirs.push_back(*dir_ / s);
    o.allow_partial = allow_partial;
    o.command_line = {"taskmatrix", "merge"};
    std::ostringstream sink, err;
    MergeJobResult r = run_merge_job(test::catalog(), *registry_, o, sink, err);
    if (err_text) *err_text = err.str();
    return r;
  }
  static nlohmann::json read_json(const fs::path& file) {
    return nlohmann::json::parse(std::ifstream(file));
  }
  static std::map<std::string, nlohmann::json> trials_of(const std::string& run) {
    std::map<std::string, nlohmann::json> out;
    for (nlohmann::json& t : read_trials_file(*dir_ / run / "trials.jsonl").trials) {
      EXPECT_EQ(out.count(t["trial_id"]), 0u) << "duplicate " << t["trial_id"];
      out[t["trial_id"]] = without_timing(t);
    }
    return out;
  }
  // A copy of a shard directory whose provenance.json `edit` changes.
  static std::string edited_copy(const std::string& shard, const std::string& name,
                                 const std::function<void(nlohmann::json&)>& edit) {
    fs::copy(*dir_ / shard, *dir_ / name, fs::copy_options::recursive);
    nlohmann::json p = read_json(*dir_ / name / "provenance.json");
    edit(p);
    std::ofstream(*dir_ / name / "provenance.json") << p.dump(2);
    return name;
  }
  static fs::path* dir_;
  static core::ProgramRegistry* registry_;
};
fs::path* Merge::dir_ = nullptr;
core::ProgramRegistry* Merge::registry_ = nullptr;

TEST_F(Merge, ShardsMergeIntoTheRunOneMachineWrites) {
  need_shards();
  run_into("whole", {0, 1, ""}, 2);
  const MergeJobResult r = merge("merged", {"shard0", "shard1", "shard2"});
  ASSERT_EQ(r.dir, *dir_ / "merged");
  EXPECT_EQ(r.planned, 4);
  EXPECT_EQ(r.merged, 4);
  EXPECT_TRUE(r.missing.empty());
  EXPECT_TRUE(r.duplicated.empty());
  // Trial for trial what the whole run holds (timings aside), in matrix order.
  const auto whole = trials_of("whole"), merged = trials_of("merged");
  ASSERT_EQ(merged.size(), 4u);
  for (const auto& [id, t] : whole) {
    ASSERT_TRUE(merged.count(id)) << id;
    EXPECT_EQ(merged.at(id), t) << id;
  }
  std::vector<std::string> order;
  for (const nlohmann::json& t : read_trials_file(*dir_ / "merged" / "trials.jsonl").trials) {
    order.push_back(t["trial_id"]);
  }
  std::vector<std::string> matrix_order;
  for (const nlohmann::json& t : read_trials_file(*dir_ / "whole" / "trials.jsonl").trials) {
    matrix_order.push_back(t["trial_id"]);
  }
  // jobs 2 may finish out of order; the matrix order is the shards' stride order.
  EXPECT_EQ(order[0], "wave.minibot.kitchen.RRTConnect.l7.s1");
  EXPECT_EQ(order[3], "wave.tallbot.kitchen.RRTConnect.l8.s2");
  EXPECT_EQ(std::set<std::string>(order.begin(), order.end()),
            std::set<std::string>(matrix_order.begin(), matrix_order.end()));
  // The summary is recomputed: the same groups, counts and ids as the whole run's.
  const nlohmann::json a = read_json(*dir_ / "whole" / "summary.json");
  const nlohmann::json b = read_json(*dir_ / "merged" / "summary.json");
  EXPECT_EQ(b["run"]["planned_trials"], 4);
  EXPECT_TRUE(b["run"]["complete"].get<bool>());
  EXPECT_EQ(b["run"]["jobs"], 3);  // one worker per shard
  EXPECT_EQ(b["overall"]["successes"], a["overall"]["successes"]);
  ASSERT_EQ(b["groups"].size(), a["groups"].size());
  for (size_t g = 0; g < a["groups"].size(); ++g) {
    for (const char* key : {"robot", "trials", "successes", "statuses", "success_ci95",
                            "collision_checks", "path_length_joint"}) {
      EXPECT_EQ(b["groups"][g][key], a["groups"][g][key]) << key;
    }
  }
  auto sorted_ids = [](nlohmann::json ids) {
    std::vector<std::string> v = ids.get<std::vector<std::string>>();
    std::sort(v.begin(), v.end());
    return v;
  };
  EXPECT_EQ(sorted_ids(b["trial_ids"]), sorted_ids(a["trial_ids"]));
  // One OMPL log with every trial.
  std::ifstream log(*dir_ / "merged" / "ompl.log");
  const std::string log_text((std::istreambuf_iterator<char>(log)),
                             std::istreambuf_iterator<char>());
  EXPECT_NE(log_text.find("4 runs"), std::string::npos);
  // Provenance: the shards' build, and each shard's directory, host and times.
  const nlohmann::json p = read_json(*dir_ / "merged" / "provenance.json");
  const nlohmann::json p0 = read_json(*dir_ / "shard0" / "provenance.json");
  EXPECT_EQ(p["executable_sha256"], p0["executable_sha256"]);
  EXPECT_EQ(p["executable_sha256"].get<std::string>().size(), 64u);
  EXPECT_EQ(p["scenario_hash"], p0["scenario_hash"]);
  EXPECT_EQ(p["shard"]["from"], "merge");
  EXPECT_EQ(p["trials"]["missing"], 0);
  ASSERT_EQ(p["shards"].size(), 3u);
  for (int i = 0; i < 3; ++i) {
    const nlohmann::json& s = p["shards"][static_cast<size_t>(i)];
    EXPECT_EQ(s["index"], i);
    EXPECT_EQ(s["count"], 3);
    EXPECT_EQ(s["dir"], (*dir_ / ("shard" + std::to_string(i))).string());
    EXPECT_FALSE(s["host"].get<std::string>().empty());
    EXPECT_FALSE(s["started_at"].get<std::string>().empty());
    EXPECT_TRUE(s["finished_at"].is_string());
    EXPECT_EQ(s["trials_merged"], i == 0 ? 2 : 1);  // 4 trials in strides of 3
  }
  EXPECT_LE(p["started_at"].get<std::string>(), p["shards"][1]["started_at"].get<std::string>());
  EXPECT_EQ(p["merge"]["trajectories"]["linked"], 4);
  // Trajectories are the shards' files, linked, and readable.
  for (const auto& [id, t] : merged) {
    const fs::path file = *dir_ / "merged" / t["trajectory"].get<std::string>();
    struct stat st {};
    ASSERT_EQ(stat(file.c_str(), &st), 0) << file;
    EXPECT_EQ(st.st_nlink, 2u) << file;
    EXPECT_GT(read_trajectory_file(file).recording.frames(), 10u) << file;
  }
  // compare takes the merged directory like any run: every pair, nothing changed.
  CompareJobOptions c;
  c.base_dir = *dir_ / "whole";
  c.new_dir = *dir_ / "merged";
  std::ostringstream sink;
  const CompareJobResult cr = run_compare_job(c, sink);
  EXPECT_EQ(cr.comparison.overall.pairs, 4);
  EXPECT_FALSE(cr.comparison.regression());
  // A merged directory is itself a run of the whole matrix: merging it again changes nothing.
  const MergeJobResult again = merge("merged_again", {"merged"});
  EXPECT_EQ(again.merged, 4);
  EXPECT_EQ(trials_of("merged_again"), merged);
}

TEST_F(Merge, MissingOrDuplicatedTrialsAreListedAndNothingIsWritten) {
  need_shards();
  std::string err;
  const MergeJobResult missing = merge("no_shard1", {"shard0", "shard2"}, false, &err);
  EXPECT_TRUE(missing.dir.empty());
  EXPECT_FALSE(fs::exists(*dir_ / "no_shard1"));
  EXPECT_EQ(missing.missing, std::vector<std::string>{"wave.minibot.kitchen.RRTConnect.l8.s2"});
  EXPECT_NE(err.find("missing wave.minibot.kitchen.RRTConnect.l8.s2 (shard 1/3)"),
            std::string::npos)
      << err;
  EXPECT_NE(err.find("1 of 4 trials missing, 0 duplicated; nothing written"), std::string::npos)
      << err;

  const MergeJobResult twice =
      merge("twice", {"shard0", "shard1", "shard2", "shard1"}, false, &err);
  EXPECT_TRUE(twice.dir.empty());
  EXPECT_EQ(twice.duplicated, std::vector<std::string>{"wave.minibot.kitchen.RRTConnect.l8.s2"});
  EXPECT_NE(err.find("duplicated wave.minibot.kitchen.RRTConnect.l8.s2"), std::string::npos) << err;

  // --allow-partial merges what is there and says what is not.
  const MergeJobResult partial = merge("partial", {"shard0", "shard2"}, true, &err);
  ASSERT_FALSE(partial.dir.empty());
  EXPECT_EQ(partial.merged, 3);
  const nlohmann::json s = read_json(*dir_ / "partial" / "summary.json");
  EXPECT_EQ(s["run"]["planned_trials"], 4);
  EXPECT_EQ(s["run"]["finished_trials"], 3);
  EXPECT_FALSE(s["run"]["complete"].get<bool>());
  const nlohmann::json p = read_json(*dir_ / "partial" / "provenance.json");
  EXPECT_EQ(p["merge"]["missing"],
            nlohmann::json::array({"wave.minibot.kitchen.RRTConnect.l8.s2"}));
  // ... and the missing shard completes it later.
  EXPECT_EQ(merge("completed", {"partial", "shard1"}).merged, 4);
}

TEST_F(Merge, ShardsOfAnotherSuiteBuildOrMatrixAreRefused) {
  need_shards();
  const std::string build = edited_copy("shard1", "other_build", [](nlohmann::json& p) {
    p["executable_sha256"] = std::string(64, '0');
  });
  std::string e = error_of([&] { merge("m", {"shard0", build, "shard2"}); });
  EXPECT_NE(e.find("other_build/provenance.json: executable_sha256: the shard ran another build"),
            std::string::npos)
      << e;
  const std::string suite = edited_copy("shard1", "other_suite", [](nlohmann::json& p) {
    p["scenario_hash"] = "sha256:" + std::string(64, '1');
  });
  e = error_of([&] { merge("m", {"shard0", suite}); });
  EXPECT_NE(e.find("scenario_hash: the shard ran other scenario files"), std::string::npos) << e;
  // Another --trials: another matrix (a shard of 2 trials out of 2 x 2).
  RunOverrides one_layout;
  one_layout.trials = 1;
  run_into("one_layout", {0, 1, "--shard"}, 1, one_layout);
  e = error_of([&] { merge("m", {"shard0", "one_layout"}); });
  EXPECT_NE(e.find("one_layout/provenance.json: matrix: the shard ran another matrix"),
            std::string::npos)
      << e;
  // The suite's files changed since the shards ran.
  fs::copy(*dir_ / "wave.yaml", *dir_ / "wave.yaml.orig");
  std::ofstream(*dir_ / "wave.yaml", std::ios::app) << "# edited\n";
  e = error_of([&] { merge("m", {"one_layout"}); });
  fs::rename(*dir_ / "wave.yaml.orig", *dir_ / "wave.yaml");
  EXPECT_NE(e.find("wave.yaml: its scenario files changed since the shards ran"), std::string::npos)
      << e;
  // Not a run directory; OUT is a shard.
  e = error_of([&] { merge("m", {"shard0", "nowhere"}); });
  EXPECT_NE(e.find("nowhere: no such shard directory"), std::string::npos) << e;
  e = error_of([&] { merge("shard0", {"shard0", "shard1", "shard2"}); });
  EXPECT_NE(e.find("is one of the shard directories"), std::string::npos) << e;
  EXPECT_FALSE(fs::exists(*dir_ / "m"));
}

// A run whose command line replaced the execution mode and the robots (as check-robot does)
// merges into the run one machine writes with them. Before, provenance.json kept neither, so
// the merge rebuilt the suite's own matrix (both robots) and refused the shards: `matrix.trials:
// the shards' matrix has 2 trials, but ...`.
TEST_F(Merge, ShardsOfARunWithAnotherExecutionModeAndRobotMerge) {
  RunOverrides overrides;
  overrides.execution = "kinematic";
  overrides.robots = {"tallbot"};
  run_into("kinematic0", {0, 2, "--shard"}, 1, overrides);
  run_into("kinematic1", {1, 2, "--shard"}, 1, overrides);
  run_into("kinematic_whole", {0, 1, ""}, 1, overrides);
  const MergeJobResult r = merge("kinematic_merged", {"kinematic0", "kinematic1"});
  EXPECT_EQ(r.planned, 2);
  EXPECT_EQ(r.merged, 2);
  const auto whole = trials_of("kinematic_whole"), merged = trials_of("kinematic_merged");
  ASSERT_EQ(merged.size(), 2u);
  for (const auto& [id, t] : whole) {
    EXPECT_NE(id.find(".tallbot."), std::string::npos) << id;
    ASSERT_TRUE(merged.count(id)) << id;
    EXPECT_EQ(merged.at(id), t) << id;
  }
  const nlohmann::json p = read_json(*dir_ / "kinematic_merged" / "provenance.json");
  EXPECT_EQ(p["matrix"]["overrides"]["execution"], "kinematic") << p["matrix"].dump();
  EXPECT_EQ(p["matrix"]["overrides"]["robots"], nlohmann::json::array({"tallbot"}));
}

TEST_F(Merge, TheCommandLineTakesTheShardFromTheFlagOrTheSlurmArrayTask) {
  const std::string wave = (*dir_ / "wave.yaml").string();
  const fs::path root = test::catalog().root();
  auto out = [&](const std::string& name) { return (*dir_ / name).string(); };
  // A bad spec, and --shard with --only: exit 2, nothing written.
  for (const char* args :
       {"--shard 3/3", "--shard 1/x", "--shard 0/2 --only wave.minibot.kitchen.RRTConnect.l7.s1"}) {
    const test::CommandResult r =
        test::run_cli("run " + wave + " --out " + out("bad") + " " + args, root);
    EXPECT_EQ(r.exit_code, 2) << args << ": " << r.err;
    EXPECT_NE(r.err.find("--shard"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out("bad"))) << args;
  }
  // In an array task the environment chooses; --shard wins over it.
  setenv("SLURM_ARRAY_TASK_ID", "1", 1);
  setenv("SLURM_ARRAY_TASK_COUNT", "3", 1);
  setenv("SLURM_ARRAY_TASK_MIN", "0", 1);
  const test::CommandResult env = test::run_cli("run " + wave + " --out " + out("env1"), root);
  const test::CommandResult flag =
      test::run_cli("run " + wave + " --out " + out("flag2") + " --shard 2/3", root);
  setenv("SLURM_ARRAY_TASK_MIN", "2", 1);  // task 1 of an array from 2: not one range
  const test::CommandResult odd = test::run_cli("run " + wave + " --out " + out("odd"), root);
  unsetenv("SLURM_ARRAY_TASK_ID");
  unsetenv("SLURM_ARRAY_TASK_COUNT");
  unsetenv("SLURM_ARRAY_TASK_MIN");
  EXPECT_EQ(env.exit_code, 0) << env.err;
  EXPECT_NE(env.err.find("shard 1/3 from SLURM_ARRAY_TASK_ID"), std::string::npos) << env.err;
  const nlohmann::json p = read_json(out("env1") + "/provenance.json");
  EXPECT_EQ(
      p["shard"],
      nlohmann::json({{"index", 1}, {"count", 3}, {"from", "SLURM_ARRAY_TASK_ID"}, {"trials", 1}}));
  EXPECT_EQ(p["matrix"]["trials"], 4);
  EXPECT_EQ(flag.exit_code, 0) << flag.err;
  EXPECT_EQ(read_json(out("flag2") + "/provenance.json")["shard"]["from"], "--shard");
  EXPECT_EQ(odd.exit_code, 2);
  EXPECT_NE(odd.err.find("SLURM_ARRAY_TASK_ID"), std::string::npos) << odd.err;
  EXPECT_FALSE(fs::exists(out("odd")));
  // merge: exit 0 with the summary; 1 with a shard missing (listed); 2 for bad input. (Shards
  // of one build: this binary's, not the test's.)
  const test::CommandResult zero =
      test::run_cli("run " + wave + " --out " + out("cli0") + " --shard 0/3", root);
  ASSERT_EQ(zero.exit_code, 0) << zero.err;
  const test::CommandResult ok = test::run_cli(
      "merge " + out("cli_merged") + " " + out("cli0") + " " + out("env1") + " " + out("flag2"),
      root);
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_NE(ok.out.find("4 of 4 trials finished"), std::string::npos) << ok.out;
  EXPECT_NE(ok.err.find("merged 3 shard directories: 4 of 4 trials"), std::string::npos) << ok.err;
  const test::CommandResult gap =
      test::run_cli("merge " + out("cli_gap") + " " + out("cli0") + " " + out("flag2"), root);
  EXPECT_EQ(gap.exit_code, 1);
  EXPECT_NE(gap.err.find("missing wave.minibot.kitchen.RRTConnect.l8.s2 (shard 1/3)"),
            std::string::npos)
      << gap.err;
  const test::CommandResult bad =
      test::run_cli("merge " + out("cli_bad") + " " + out("none"), root);
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_EQ(std::count(bad.err.begin(), bad.err.end(), '\n'), 1) << bad.err;
}

}  // namespace
}  // namespace taskmatrix::harness
