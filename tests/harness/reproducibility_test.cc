// A trial's result depends on its id alone, whatever the machine's load and whatever else the
// process did before: the same trials run twice through the CLI, the second time with two busy
// loops competing for the cores and another heap (glibc's thread cache off, allocations
// filled with a byte pattern, so code that reads memory it does not own sees other bytes), give
// the same outcomes, statuses, failure reasons, planned paths (bit for bit), work counts
// (collision checks, planner iterations, IK calls, control periods) and executed trajectories,
// and no clock bound decides any of them. The trials: pickup, putdown and vacuum on every robot
// of the catalog in the kitchen (RRTConnect, whose paths are simplified), and a reach with PRM
// (its roadmap grown under the iteration budget), each on every robot, executed kinematically
// (README, Reliability: a physics trial was seen once to diverge on a rerun). One trial run
// alone (`--only`, a fresh process) gives its line of the suite run. In its own test program:
// it takes minutes.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <iterator>
#include <map>

#include "harness/replay/trajectory_file.h"
#include "harness/results/trial_record.h"
#include "tests/test_support.h"

namespace taskmatrix::harness {
namespace {

namespace fs = std::filesystem;

// Processes that spin until destroyed.
class BusyLoops {
 public:
  explicit BusyLoops(int n) {
    for (int i = 0; i < n; ++i) {
      const pid_t pid = fork();
      if (pid == 0) {
        volatile unsigned long x = 0;
        for (;;) x = x + 1;
      }
      pids_.push_back(pid);
    }
  }
  ~BusyLoops() {
    for (pid_t pid : pids_) {
      kill(pid, SIGKILL);
      waitpid(pid, nullptr, 0);
    }
  }
  BusyLoops(const BusyLoops&) = delete;
  BusyLoops& operator=(const BusyLoops&) = delete;

 private:
  std::vector<pid_t> pids_;
};

std::map<std::string, nlohmann::json> trials_of(const fs::path& dir) {
  std::map<std::string, nlohmann::json> out;
  TrialsFile file = read_trials_file(dir / "trials.jsonl");
  for (nlohmann::json& t : file.trials) {
    const std::string id = t["trial_id"].get<std::string>();
    out[id] = std::move(t);
  }
  return out;
}

// The CLI as a user runs it (exit status; its stderr is in DIR.err).
int run_cli(const std::string& args, const fs::path& err, const std::string& environment = "") {
  const std::string command = environment + " TASKMATRIX_ROOT='" +
                              std::string(TASKMATRIX_TEST_ROOT) + "' timeout 280 " +
                              TASKMATRIX_CLI + " " + args + " >/dev/null 2>'" + err.string() + "'";
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

std::string slurp(const fs::path& file) {
  std::ifstream in(file);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::string robots_list() {
  std::string list;
  for (const std::string& r : test::catalog().robots()) list += (list.empty() ? "" : ", ") + r;
  return "[" + list + "]";
}

TEST(Reproducibility, TrialsRepeatBitForBitWithTwoBusyLoopsCompetingForTheCores) {
  char tmpl[] = "/tmp/taskmatrix_repro_XXXXXX";
  const fs::path dir = mkdtemp(tmpl);
  const fs::path programs = fs::path(TASKMATRIX_TEST_ROOT) / "scenarios" / "programs";
  std::ofstream(dir / "reach_prm.yaml")
      << "name: reach_prm\nprogram: reach\nparams: {object: cup}\nrobots: [minibot]\n"
         "environments: [kitchen]\nobstacles: {count: 8}\nplanners: [PRM]\n"
         "planner_budget: iterations\nplan_iterations: 3000\nlayout_seed: 3\ntime_limit_s: 30\n"
         "success: graspable(cup)\n";
  std::ofstream(dir / "suite.yaml")
      << "suite: repro\nscenarios: [" << (programs / "pickup.yaml").string() << ", "
      << (programs / "putdown.yaml").string() << ", " << (programs / "vacuum.yaml").string()
      << ", reach_prm.yaml]\nrobots: " << robots_list()
      << "\nenvironments: [kitchen]\ntrials: 1\nexecution: kinematic\n"
      // The wall-clock safety net far above any trial's time on a loaded machine: this test
      // is about what decides a trial, not how long it may take.
      << "wall_limit_s: 1200\n";
  const std::string run =
      "run " + (dir / "suite.yaml").string() + " --jobs 2 --progress off --out ";
  ASSERT_EQ(run_cli(run + (dir / "quiet").string(), dir / "quiet.err"), 0)
      << slurp(dir / "quiet.err");
  int busy = 0;
  {
    const BusyLoops loops(2);
    busy = run_cli(run + (dir / "busy").string(), dir / "busy.err",
                   "GLIBC_TUNABLES=glibc.malloc.tcache_count=0 MALLOC_PERTURB_=85");
  }
  ASSERT_EQ(busy, 0) << slurp(dir / "busy.err");

  const auto a = trials_of(dir / "quiet"), b = trials_of(dir / "busy");
  ASSERT_EQ(a.size(), b.size());
  // The suite's robots replace each scenario's: reach_prm runs on every robot too.
  ASSERT_EQ(a.size(), 4 * test::catalog().robots().size());
  int successes = 0, plans = 0;
  for (const auto& [id, ta] : a) {
    ASSERT_TRUE(b.count(id)) << id;
    const nlohmann::json& tb = b.at(id);
    for (const nlohmann::json* t : {&ta, &tb}) {
      EXPECT_TRUE(clock_bounds_hit(*t).empty())
          << id << ": a clock bound decided the trial: " << (*t)["clock_bound_hit"].dump();
    }
    // Everything but the machine's own measurements, the plans' path digests included.
    nlohmann::json ca = without_timing(ta), cb = without_timing(tb);
    for (nlohmann::json* c : {&ca, &cb}) c->erase("trajectory");
    EXPECT_EQ(ca.dump(), cb.dump()) << id;
    successes += ta["success"].get<bool>();
    for (const nlohmann::json& p : ta["plans"]) {
      // A plan that found a path names it by its digest (null: no path).
      const auto digest = p.find("path_digest");
      if (digest == p.end() || digest->is_null()) continue;
      ASSERT_TRUE(digest->is_string()) << id;
      EXPECT_FALSE(digest->get<std::string>().empty()) << id;
      ++plans;
    }
    // The executed motion: every recorded position, bit for bit.
    ASSERT_TRUE(ta["trajectory"].is_string() && tb["trajectory"].is_string())
        << id << ": " << ta["failure_reason"].dump() << " / " << tb["failure_reason"].dump();
    const TrajectoryFile ra =
        read_trajectory_file(dir / "quiet" / ta["trajectory"].get<std::string>());
    const TrajectoryFile rb =
        read_trajectory_file(dir / "busy" / tb["trajectory"].get<std::string>());
    EXPECT_EQ(ra.recording.times, rb.recording.times) << id;
    EXPECT_EQ(ra.recording.qpos, rb.recording.qpos) << id;
  }
  // One carrying trial alone in a fresh process (the first putdown that succeeded): its line
  // of the suite run.
  std::string alone_id;
  for (const auto& [id, t] : a) {
    if (alone_id.empty() && id.rfind("putdown.", 0) == 0 && t["success"].get<bool>()) alone_id = id;
  }
  ASSERT_FALSE(alone_id.empty()) << "no putdown succeeded";
  ASSERT_EQ(run_cli("run " + (dir / "suite.yaml").string() + " --progress off --only " + alone_id +
                        " --out " + (dir / "alone").string(),
                    dir / "alone.err"),
            0)
      << slurp(dir / "alone.err");
  const auto alone = trials_of(dir / "alone");
  ASSERT_EQ(alone.size(), 1u);
  nlohmann::json ca = without_timing(a.at(alone_id)), cb = without_timing(alone.begin()->second);
  for (nlohmann::json* c : {&ca, &cb}) c->erase("trajectory");
  EXPECT_EQ(ca.dump(), cb.dump()) << alone_id << " alone";

  // The trials did real work: most succeed, and they planned.
  EXPECT_GE(successes, static_cast<int>(a.size()) / 2);
  EXPECT_GE(plans, static_cast<int>(a.size()) * 2);
  std::error_code ec;
  fs::remove_all(dir, ec);
}

}  // namespace
}  // namespace taskmatrix::harness
