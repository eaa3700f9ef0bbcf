// Bad input and hostile conditions, one class per test, each reproduced as a user meets it:
// run directories that are not ours, two runs at once, duplicated and malformed result files,
// names that break Markdown and the OMPL log, nesting, NaN and infinity, numbers out of range,
// over-long names, write errors, interrupted reports, endless videos, huge regions, 64-bit
// seeds, unsafe names. Every case ends in one clear error (or a correct result), never a crash.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <sstream>
#include <thread>

#include "harness/compare/compare.h"
#include "harness/replay/trajectory_file.h"
#include "harness/replay/trial_video.h"
#include "harness/results/ompl_log.h"
#include "harness/results/run_directory.h"
#include "harness/results/summary.h"
#include "harness/results/trial_record.h"
#include "harness/run/run_job.h"
#include "harness/run/trial.h"
#include "harness/scenario/scenario.h"
#include "taskmatrix/core/conditions.h"
#include "taskmatrix/core/input_error.h"
#include "taskmatrix/core/utf8.h"
#include "taskmatrix/io/yaml_reader.h"
#include "taskmatrix/programs/primitives.h"
#include "tests/test_support.h"

namespace taskmatrix::harness {
namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& f) {
  std::ifstream in(f, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// A quick scenario: postural rest on minibot in the kitchen, two trials (a second each).
constexpr const char* kQuick =
    "name: quick\nprogram: postural\nparams: {posture: rest}\nrobots: [minibot]\n"
    "environments: [kitchen]\ntrials: 2\ntime_limit_s: 5\n";

class Robustness : public ::testing::Test {
 protected:
  void SetUp() override {
    char tmpl[] = "/tmp/taskmatrix_robust_XXXXXX";
    dir_ = mkdtemp(tmpl);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  fs::path write(const std::string& name, const std::string& text) {
    fs::create_directories((dir_ / name).parent_path());
    std::ofstream(dir_ / name, std::ios::binary) << text;
    return dir_ / name;
  }
  test::CommandResult cli(const std::string& args) {
    return test::run_cli(args, test::catalog().root());
  }
  test::CommandResult run_quick(const std::string& out, const std::string& extra = "") {
    const fs::path s = write("quick.yaml", kQuick);
    return cli("run '" + s.string() + "' --progress off --out '" + (dir_ / out).string() + "' " +
               extra);
  }
  fs::path dir_;
};

// ---- Run directories.

TEST_F(Robustness, ARunRefusesAFolderItDidNotWriteAndLeavesItAlone) {
  write("user/summary.md", "my notes\n");
  write("user/trajectories/a.csv", "1,2\n");
  const test::CommandResult r = run_quick("user");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("not a run directory"), std::string::npos) << r.err;
  EXPECT_EQ(slurp(dir_ / "user/summary.md"), "my notes\n");
  EXPECT_EQ(slurp(dir_ / "user/trajectories/a.csv"), "1,2\n");
  EXPECT_FALSE(fs::exists(dir_ / "user" / kRunDirectoryMarker));
  // An empty folder is fine, and a run directory can be run into again: the earlier results
  // are replaced, files the run did not write stay.
  fs::create_directories(dir_ / "empty");
  ASSERT_EQ(run_quick("empty").exit_code, 0);
  write("empty/notes.txt", "keep me\n");
  write("empty/trajectories/mine.csv", "keep me too\n");
  ASSERT_EQ(run_quick("empty").exit_code, 0);
  EXPECT_EQ(slurp(dir_ / "empty/notes.txt"), "keep me\n");
  EXPECT_EQ(slurp(dir_ / "empty/trajectories/mine.csv"), "keep me too\n");
  EXPECT_EQ(read_trials_file(dir_ / "empty/trials.jsonl").trials.size(), 2u);
}

TEST_F(Robustness, ASecondRunIntoALockedDirectoryFailsAtOnceNamingTheHolder) {
  ASSERT_EQ(run_quick("held").exit_code, 0);
  const std::string before = slurp(dir_ / "held/trials.jsonl");
  {
    const RunDirectoryLock lock(dir_ / "held", {"taskmatrix", "run", "other.yaml"});
    const auto t0 = std::chrono::steady_clock::now();
    const test::CommandResult r = run_quick("held");
    EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(20));
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("in use by another run (PID " + std::to_string(getpid()) +
                         ": taskmatrix run other.yaml)"),
              std::string::npos)
        << r.err;
    EXPECT_NE(run_quick("held", "--resume").err.find("in use"), std::string::npos);
  }
  EXPECT_EQ(slurp(dir_ / "held/trials.jsonl"), before);   // nothing lost
  EXPECT_EQ(run_quick("held", "--resume").exit_code, 0);  // free again
}

TEST_F(Robustness, DuplicatedTrialLinesAreDroppedWithAWarningOnResume) {
  ASSERT_EQ(run_quick("dup").exit_code, 0);
  const std::string lines = slurp(dir_ / "dup/trials.jsonl");
  write("dup/trials.jsonl", lines + lines.substr(0, lines.find('\n') + 1));
  const test::CommandResult r = run_quick("dup", "--resume");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("1 duplicated trial line ignored (line 3 repeats trial"), std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("2 of 2 trials"), std::string::npos) << r.err;
  const nlohmann::json summary = nlohmann::json::parse(slurp(dir_ / "dup/summary.json"));
  EXPECT_EQ(summary["run"]["finished_trials"], 2);
}

TEST_F(Robustness, MalformedRunDirectoryFilesNameTheFileLineAndKeyAndChangeNothing) {
  ASSERT_EQ(run_quick("runs/a").exit_code, 0);
  const fs::path a = dir_ / "runs/a";
  const std::string trials = slurp(a / "trials.jsonl");
  auto expect_error = [&](const std::string& file, const std::string& text, const std::string& args,
                          const std::string& wanted) {
    write("runs/a/" + file, text);
    const auto listing = [&] {
      std::string l;
      for (const auto& e : fs::recursive_directory_iterator(a)) {
        l += e.path().string() + " " +
             std::to_string(fs::last_write_time(e.path()).time_since_epoch().count()) + "\n";
      }
      return l;
    };
    const std::string before = listing();
    const test::CommandResult r = cli(args);
    EXPECT_EQ(r.exit_code, 2) << args << ": " << r.err;
    EXPECT_NE(r.err.find(wanted), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("json.exception"), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_EQ(listing(), before) << "the rejected input changed the run directory";
  };
  const std::string resume = "run '" + (dir_ / "quick.yaml").string() +
                             "' --progress off --resume --out '" + a.string() + "'";
  const std::string compare = "compare '" + a.string() + "' '" + a.string() + "'";
  expect_error("provenance.json", "[1, 2]", resume, "provenance.json: must be a JSON object");
  expect_error("provenance.json", "{\"scenario_hash\": 5}", resume,
               "provenance.json: scenario_hash: must be a string");
  expect_error("provenance.json", "{\"x\": 1e999}", compare, "provenance.json:1: not JSON");
  fs::remove(a / "provenance.json");
  std::string bad = trials;
  bad.replace(bad.find("\"success\":true"), 14, "\"success\":\"yes\"");
  expect_error("trials.jsonl", bad, resume, "trials.jsonl:1: success: must be true or false");
  expect_error("trials.jsonl", bad, compare, "trials.jsonl:1: success: must be true or false");
  bad = trials;
  bad.replace(bad.find("\"trial_id\":\""), 12, "\"trial_id\":7,\"x\":\"");
  expect_error("trials.jsonl", bad, compare, "trials.jsonl:1: trial_id: must be a string");
  bad = trials;
  bad.replace(bad.find("\"duration_s\":"), 13, "\"duration_s\":1e999,\"y\":");
  expect_error("trials.jsonl", bad, compare, "trials.jsonl:1: not JSON");
  bad = trials;
  bad.replace(bad.find("\"trajectory\":\""), 14, "\"trajectory\":\"../../../etc/passwd\",\"z\":\"");
  expect_error("trials.jsonl", bad, compare, "trials.jsonl:1: trajectory: must be a path inside");
  write("runs/a/trials.jsonl", trials);
  expect_error("summary.json", "{\"trial_ids\": [1]}", compare,
               "summary.json: trial_ids[0]: must be a string");
  expect_error("summary.json", "{\"trial_ids\": \"\xff\"}", compare, "summary.json:1: not JSON");
}

TEST_F(Robustness, BenchmarkFilesWithNumbersOutOfRangeAreOneClearError) {
  const std::string good = slurp(fs::path(TASKMATRIX_TEST_ROOT) / "fuzz/seeds/bench/small.json");
  // The value of `key` replaced by `value`: the first one, or every one.
  auto with = [](std::string text, const std::string& key, const std::string& value,
                 bool every = false) {
    for (size_t at = text.find("\"" + key + "\": "); at != std::string::npos;
         at = every ? text.find("\"" + key + "\": ", at + 1) : std::string::npos) {
      const size_t from = at + key.size() + 4;
      text.replace(from, text.find_first_of(",}", from) - from, value);
    }
    return text;
  };
  const std::string huge = with(good, "real_time", "1e999");
  const fs::path h = write("huge.json", huge);
  test::CommandResult r = cli("bench-compare '" + h.string() + "' '" + h.string() + "'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("huge.json:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("number overflow"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("json.exception"), std::string::npos) << r.err;
  // Finite, but no time in seconds.
  const std::string big = with(with(good, "time_unit", "\"s\"", true), "real_time", "1e308", true);
  const fs::path b = write("big.json", big);
  r = cli("bench-compare '" + b.string() + "' '" + b.string() + "'");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("real_time: is too large"), std::string::npos) << r.err;
}

TEST_F(Robustness, TextThatIsNotUtf8IsRefusedWhereItIsReadAndNeverBreaksOutput) {
  const fs::path s = write("latin1.yaml", std::string(kQuick) + "doc: caf\xe9 au lait\n");
  const test::CommandResult r = cli("validate '" + s.string() + "'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("latin1.yaml:8: not UTF-8 text (byte 0xe9)"), std::string::npos) << r.err;
  // A run directory is left alone when the input is refused.
  ASSERT_EQ(run_quick("kept").exit_code, 0);
  const std::string before = slurp(dir_ / "kept/trials.jsonl");
  EXPECT_EQ(cli("run '" + s.string() + "' --out '" + (dir_ / "kept").string() + "'").exit_code, 2);
  EXPECT_EQ(slurp(dir_ / "kept/trials.jsonl"), before);
  // Written anyway where it comes from a model (a body name): replaced, never an exception.
  EXPECT_EQ(json_text(nlohmann::json{{"reason", "touched caf\xe9"}}),
            "{\"reason\":\"touched caf\xef\xbf\xbd\"}");
  EXPECT_EQ(core::invalid_utf8_at("ok \xc3\xa9 \xed\xa0\x80"), 6u);  // a surrogate
  EXPECT_EQ(core::invalid_utf8_at("\xf0\x9f\x98\x80"), std::nullopt);
}

// ---- Names in reports.

TEST_F(Robustness, NamesAreEscapedInMarkdownAndTheOmplLog) {
  const std::string name = "<img src=x onerror=alert(1)> a;b|c\r\nd\xff";
  EXPECT_EQ(markdown_cell(name), "&lt;img src=x onerror=alert(1)&gt; a;b\\|c  d\xef\xbf\xbd");
  EXPECT_EQ(markdown_cell("a_b*c`[d]"), "a_b\\*c\\`\\[d\\]");
  // A summary table keeps its columns whatever the names and reasons hold.
  std::vector<nlohmann::json> trials;
  for (int i = 0; i < 40; ++i) {
    trials.push_back({{"trial_id", "t" + std::to_string(i)},
                      {"scenario", name},
                      {"program", "reach"},
                      {"robot", "r|1"},
                      {"environment", "e"},
                      {"planner", "p"},
                      {"success", false},
                      {"status", "status_number_" + std::to_string(i) + "|x"}});
  }
  const std::string md = summary_markdown(
      make_summary({name, "a doc with <b>html</b> | pipes", 40, false, 1, 1}, trials));
  const std::string row = md.substr(md.find("| &lt;img"));
  const std::string first_row = row.substr(0, row.find('\n'));
  EXPECT_GT(first_row.size(), 511u);  // nothing cut
  EXPECT_EQ(first_row.substr(first_row.size() - 2), " |");
  EXPECT_NE(first_row.find("status_number_39\\|x 1"), std::string::npos);
  // 11 columns: 12 unescaped pipes.
  int pipes = 0;
  for (size_t i = 0; i < first_row.size(); ++i)
    pipes += first_row[i] == '|' && (i == 0 || first_row[i - 1] != '\\');
  EXPECT_EQ(pipes, 12);
  EXPECT_EQ(md.find("<b>"), std::string::npos);
  // The OMPL log: one token per name, UTF-8, no carriage return.
  OmplLogInfo info;
  info.experiment = name;
  info.setup = "scenario text\r\nwith a carriage return and caf\xe9\n|>>>\n";
  info.planners.push_back({"p", "RRTConnect", {}});
  const std::string log = ompl_log_text(info, trials);
  EXPECT_EQ(log.find('\r'), std::string::npos);
  EXPECT_EQ(core::invalid_utf8_at(log), std::nullopt);
  EXPECT_NE(log.find("Experiment <img_src=x_onerror=alert(1)>_a_b_c__d\xef\xbf\xbd\n"),
            std::string::npos)
      << log.substr(0, 200);
}

// ---- Conditions, numbers and names in scenario files.

TEST_F(Robustness, DeeplyNestedConditionsAreRefusedNotAStackOverflow) {
  auto nested = [](int depth) {
    std::string s;
    for (int i = 0; i < depth; ++i) s += "not(";
    s += "exists(debris)";
    for (int i = 0; i < depth; ++i) s += ")";
    return s;
  };
  EXPECT_NO_THROW(core::parse_condition(nested(core::kMaxConditionDepth - 1)));
  try {
    core::parse_condition(nested(100000));
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("nested more than 64 levels deep"), std::string::npos);
    EXPECT_LT(std::string(e.what()).size(), 300u);
  }
  const fs::path s = write("deep.yaml", std::string(kQuick) + "success: " + nested(5000) + "\n");
  const test::CommandResult r = cli("validate '" + s.string() + "'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("deep.yaml:8: success:"), std::string::npos) << r.err.substr(0, 300);
}

TEST_F(Robustness, NumbersOutOfRangeAndNonFiniteAreRefusedWithTheKey) {
  auto error_of = [&](const std::string& extra) {
    return cli("validate '" + write("n.yaml", std::string(kQuick) + extra).string() + "'").err;
  };
  EXPECT_NE(error_of("plan_time_limit_s: 1e10\n").find("plan_time_limit_s: must be at most 86400"),
            std::string::npos);
  EXPECT_NE(error_of("plan_time_limit_s: .nan\n").find("must be a finite number"),
            std::string::npos);
  EXPECT_NE(error_of("planner_budget: clock\n").find("planner_budget: must be iterations or time"),
            std::string::npos);
  EXPECT_NE(error_of("plan_iterations: 0\n").find("plan_iterations: must be in 1..100000000"),
            std::string::npos);
  // 64-bit layout seeds: read whole, and their last trial must stay within 2^64 - 1.
  EXPECT_EQ(
      cli("validate '" +
          write("l.yaml", std::string(kQuick) + "layout_seed: 18446744073709551000\n").string() +
          "'")
          .exit_code,
      0);
  EXPECT_NE(error_of("layout_seed: 18446744073709551615\n").find("layout_seed + trials - 1"),
            std::string::npos);
  EXPECT_NE(error_of("layout_seed: 18446744073709551616\n").find("layout_seed: must be an integer"),
            std::string::npos);
  // The CLI's thresholds: NaN is not in any range.
  const test::CommandResult alpha = cli("compare a b --alpha nan");
  EXPECT_EQ(alpha.exit_code, 2);
  EXPECT_NE(alpha.err.find("must be a finite number"), std::string::npos) << alpha.err;
  const test::CommandResult tolerance = cli("bench-compare a b --time-tolerance nan");
  EXPECT_EQ(tolerance.exit_code, 2);
  EXPECT_NE(tolerance.err.find("must be a finite number"), std::string::npos) << tolerance.err;
  EXPECT_EQ(cli("render --trial x:y --out y.png --time inf").exit_code, 2);
}

TEST_F(Robustness, NamesThatBecomeFileNamesAreCheckedAndIdsStayShortEnough) {
  const std::string unnamed = std::string(kQuick).substr(std::string(kQuick).find('\n') + 1);
  const std::string long_name(65, 'a');
  EXPECT_NE(
      cli("validate '" + write("x.yaml", unnamed + "name: " + long_name + "\n").string() + "'")
          .err.find("must be 1 to 64 of A-Z a-z 0-9 _ -"),
      std::string::npos);
  // 64-character robot, scenario and planner names: valid names, but an id too long for a file
  // name.
  test::ScratchRoot root;
  const std::string name64(64, 'b');
  fs::copy(root.file("models/robots/minibot"), root.file("models/robots/" + name64),
           fs::copy_options::recursive);
  root.replace("models/robots/" + name64 + "/profile.yaml", "name: minibot", "name: " + name64);
  const std::string long_ids =
      "name: " + name64 + "\nprogram: postural\nparams: {posture: rest}\nrobots: [" + name64 +
      "]\nenvironments: [kitchen]\nplanners: [{name: RRTConnect, label: " + name64 +
      "}]\nlayout_seed: 18446744073709551000\n";
  const test::CommandResult r =
      test::run_cli("validate '" + write("y.yaml", long_ids).string() + "'", root.path());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("characters (at most 200)"), std::string::npos) << r.err;
  // A robot folder whose name cannot be part of a file name.
  fs::copy(root.file("models/robots/minibot"), root.file("models/robots/bad name"),
           fs::copy_options::recursive);
  try {
    ModelCatalog(root.path()).robot_dir("bad name");
    FAIL() << "no error";
  } catch (const core::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("robot name 'bad name' must be"), std::string::npos);
  }
}

// ---- Writes that fail, interruptions.

TEST_F(Robustness, AFullDiskIsAnErrorNeverAnEmptyFile) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  fs::create_directories(dir_ / "full");
  write("full/summary.md", "the old summary\n");
  fs::create_symlink("/dev/full", dir_ / "full/summary.md.tmp");
  try {
    write_file_atomically(dir_ / "full/summary.md", "a new summary that cannot be written\n");
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("No space left on device"), std::string::npos) << e.what();
  }
  EXPECT_EQ(slurp(dir_ / "full/summary.md"), "the old summary\n");
  fs::create_symlink("/dev/full", dir_ / "full/scene.png.tmp");
  const test::CommandResult r =
      cli("render --robot minibot --env kitchen --width 64 --height 48 --out '" +
          (dir_ / "full/scene.png").string() + "'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("No space left on device"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "full/scene.png"));
}

TEST_F(Robustness, CtrlCDuringACompareReportLeavesTheOldReportOrTheNewOneNeverAMix) {
  // Two small runs and two comparisons whose reports differ: a -> b, then b -> a.
  std::vector<nlohmann::json> ta, tb;
  for (int i = 1; i <= 30; ++i) {
    nlohmann::json t = {{"trial_id", "s.r.e.p.l3.s" + std::to_string(i)},
                        {"scenario", "s"},
                        {"program", "s"},
                        {"robot", "r"},
                        {"environment", "e"},
                        {"planner", "p"},
                        {"seed", i},
                        {"layout_seed", 3},
                        {"success", i % 3 != 0},
                        {"status", i % 3 ? "success" : "collision"},
                        {"planning_time_s", 0.01 * i},
                        {"collision_checks", 100 + i}};
    ta.push_back(t);
    t["planning_time_s"] = 0.02 * i;
    tb.push_back(t);
  }
  for (const auto& [name, trials] : {std::pair{"a", ta}, std::pair{"b", tb}}) {
    std::string lines;
    for (const nlohmann::json& t : trials) lines += t.dump() + "\n";
    write(std::string(name) + "/trials.jsonl", lines);
  }
  const fs::path report = dir_ / "report";
  auto compare_args = [&](const char* from, const char* to) {
    return std::vector<std::string>{TASKMATRIX_CLI,       "compare",  (dir_ / from).string(),
                                    (dir_ / to).string(), "--report", report.string(),
                                    "--max-snapshots",    "0"};
  };
  ASSERT_EQ(cli("compare '" + (dir_ / "a").string() + "' '" + (dir_ / "b").string() +
                "' --report '" + report.string() + "'")
                .exit_code,
            0);
  auto consistent = [&] {
    const std::string md = slurp(report / "compare.md");
    const nlohmann::json j = nlohmann::json::parse(slurp(report / "compare.json"));
    const std::string html = slurp(report / "report.html");
    const std::string to = j["new"].get<std::string>();
    const bool md_same = md.find("-> " + to + "\n") != std::string::npos;
    const bool html_same = html.find("→ " + to + "</title>") != std::string::npos;
    return md_same && html_same;
  };
  ASSERT_TRUE(consistent());
  int interrupted = 0;
  for (int k = 0; k < 12; ++k) {
    const auto args = compare_args(k % 2 ? "a" : "b", k % 2 ? "b" : "a");
    const pid_t pid = fork();
    if (pid == 0) {
      const int null = open("/dev/null", O_WRONLY);
      dup2(null, 1);
      dup2(null, 2);
      std::vector<char*> argv;
      for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
      argv.push_back(nullptr);
      setenv("TASKMATRIX_ROOT", TASKMATRIX_TEST_ROOT, 1);
      execv(argv[0], argv.data());
      _exit(127);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20 + 25 * k));
    kill(pid, SIGINT);
    int status = 0;
    waitpid(pid, &status, 0);
    interrupted += WIFSIGNALED(status);
    ASSERT_TRUE(consistent()) << "after an interrupt at " << 20 + 25 * k << " ms";
  }
  EXPECT_GT(interrupted, 0);  // some interrupts came while it worked
}

// ---- Replays, videos, program parameters.

TEST_F(Robustness, TrajectoryTimesAreCheckedAndVideosAreBounded) {
  auto scene = test::scene("minibot", "kitchen");
  TrajectoryFile t;
  t.robot = "minibot";
  t.environment = "kitchen";
  t.recording.nq = scene->model()->nq;
  t.recording.frame_period_s = 0.04;
  t.recording.times = {0.0, 1e12};
  t.recording.qpos.assign(2 * static_cast<size_t>(t.recording.nq), 0.0f);
  write_trajectory_file(dir_ / "endless.traj.gz", t);
  try {
    read_trajectory_file(dir_ / "endless.traj.gz");
    FAIL() << "no error";
  } catch (const core::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("times[1]: must be a time in [0, 1e6] s"),
              std::string::npos)
        << e.what();
  }
  // A valid but long trial: a video of it would have millions of frames.
  t.recording.times = {0.0, 5e5};
  fs::create_directories(dir_ / "run/trajectories");
  write_trajectory_file(dir_ / "run/trajectories/long.traj.gz", t);
  write("run/trials.jsonl",
        "{\"trial_id\":\"long\",\"scenario\":\"s\",\"program\":\"p\",\"robot\":\"minibot\","
        "\"environment\":\"kitchen\",\"planner\":\"RRTConnect\",\"status\":\"success\","
        "\"success\":true,\"seed\":1,\"layout_seed\":1,\"trajectory\":\"trajectories/"
        "long.traj.gz\"}\n");
  VideoOptions video;
  try {
    write_trial_video(test::catalog(), (dir_ / "run").string() + ":long", dir_ / "long.mp4", video);
    FAIL() << "no error";
  } catch (const core::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("video frames (at most 90000"), std::string::npos)
        << e.what();
  }
}

TEST_F(Robustness, AHugeExploreRegionFailsItsTrialInsteadOfExhaustingMemory) {
  core::ProgramRegistry registry;
  programs::register_programs(registry);
  for (const char* bounds :
       {"[-1e300, 1e300, -1e300, 1e300, 0.7]", "[-900, 900, -900, 900, 0.7]"}) {
    const fs::path s =
        write("explore.yaml", std::string("program: explore\nparams: {bounds: ") + bounds +
                                  ", cell_m: 0.01}\nrobots: [minibot]\nenvironments: "
                                  "[kitchen]\ntime_limit_s: 5\n");
    const Scenario scenario = load_scenario(s, test::catalog(), registry);
    const TrialResult r =
        run_trial(scenario, *test::loaded_scene("minibot", "kitchen"), 1, 1, registry);
    ASSERT_TRUE(r.failure.has_value());
    EXPECT_EQ(r.failure->code, core::FailureCode::kInvalidInput) << trial_failure_reason(r);
  }
}

}  // namespace
}  // namespace taskmatrix::harness
