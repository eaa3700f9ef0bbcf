// Comparing runs: the paired statistics against published values, the verdicts against the
// thresholds, `taskmatrix compare` on run directories (exit status, report files, bad input)
// and on real runs, and the planner comparison of a run with several planners.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "harness/compare/compare.h"
#include "harness/compare/compare_job.h"
#include "harness/compare/html_report.h"
#include "harness/compare/paired_stats.h"
#include "harness/compare/planner_comparison.h"
#include "harness/results/trial_record.h"
#include "harness/run/run_job.h"
#include "taskmatrix/core/input_error.h"
#include "taskmatrix/programs/primitives.h"
#include "tests/test_support.h"

namespace taskmatrix::harness {
namespace {

TEST(PairedStats, McNemarExactMatchesTheBinomialTail) {
  EXPECT_DOUBLE_EQ(mcnemar_exact_p(0, 0), 1.0);
  EXPECT_DOUBLE_EQ(mcnemar_exact_p(3, 3), 1.0);
  EXPECT_NEAR(mcnemar_exact_p(0, 5), 2.0 / 32, 1e-15);  // 0.0625: 5 flips cannot be significant
  EXPECT_NEAR(mcnemar_exact_p(9, 1), 2.0 * 11 / 1024, 1e-15);  // 0.0215
  EXPECT_NEAR(mcnemar_exact_p(0, 8), 2.0 / 256, 1e-15);
  EXPECT_NEAR(mcnemar_exact_p(200, 150), 0.00872, 2e-5);  // large n: summed in logs
}

TEST(PairedStats, WilcoxonSignedRankMatchesR) {
  // R: wilcox.test(x, y, paired = TRUE) on its documentation's depression data: V = 40,
  // p-value = 0.03906 (exact).
  const std::vector<double> x = {1.83, 0.50, 1.62, 2.48, 1.68, 1.88, 1.55, 3.06, 1.30};
  const std::vector<double> y = {0.878, 0.647, 0.598, 2.05, 1.06, 1.29, 1.06, 3.14, 1.29};
  std::vector<double> d;
  for (size_t i = 0; i < x.size(); ++i) d.push_back(x[i] - y[i]);
  EXPECT_NEAR(wilcoxon_signed_rank_p(d), 0.0390625, 1e-9);
  EXPECT_NEAR(wilcoxon_signed_rank_p({1, 2, 3, 4, 5}), 0.0625, 1e-12);
  EXPECT_DOUBLE_EQ(wilcoxon_signed_rank_p({0, 0, 0}), 1.0);
  // Ties: the normal approximation with R's tie and continuity corrections. R:
  // wilcox.test(c(1, 1, 2, 2, 3, 3, 4, -1, 5, 6), exact = FALSE): V = 53, p-value = 0.01052.
  EXPECT_NEAR(wilcoxon_signed_rank_p({1, 1, 2, 2, 3, 3, 4, -1, 5, 6}), 0.010521, 2e-6);
}

TEST(PairedStats, BootstrapIntervalIsDeterministicAndHoldsTheMean) {
  const std::vector<double> v = {0.1, 0.3, -0.2, 0.5, 0.05, 0.2, 0.15, -0.1};
  const MeanInterval a = bootstrap_mean_interval(v), b = bootstrap_mean_interval(v);
  EXPECT_DOUBLE_EQ(a.low, b.low);
  EXPECT_DOUBLE_EQ(a.high, b.high);
  EXPECT_NEAR(a.mean, 0.125, 1e-12);
  EXPECT_LT(a.low, a.mean);
  EXPECT_GT(a.high, a.mean);
  EXPECT_GT(a.low, -0.1);  // the mean of 8 values is far narrower than their range
  EXPECT_LT(a.high, 0.35);
  const MeanInterval c = bootstrap_mean_interval({0.7, 0.7, 0.7});
  EXPECT_DOUBLE_EQ(c.low, 0.7);
  EXPECT_DOUBLE_EQ(c.high, 0.7);
}

// A trial line with the fields compare reads.
nlohmann::json trial(const std::string& program, const std::string& robot, int seed, bool success,
                     double planning_s, int checks, const std::string& planner = "RRTConnect") {
  const std::string id =
      program + "." + robot + ".kitchen." + planner + ".l3.s" + std::to_string(seed);
  return {{"trial_id", id},
          {"scenario", program},
          {"program", program},
          {"robot", robot},
          {"environment", "kitchen"},
          {"planner", planner},
          {"seed", seed},
          {"layout_seed", 3},
          {"success", success},
          {"status", success ? "success" : "collision"},
          {"failure_reason", ""},
          {"planning_time_s", planning_s},
          {"collision_checks", checks},
          {"plan_calls", 2},
          {"planner_runs", 1},
          {"ik_calls", 1}};
}

std::vector<nlohmann::json> run_of(int n, const std::function<nlohmann::json(int)>& make) {
  std::vector<nlohmann::json> out;
  for (int i = 1; i <= n; ++i) out.push_back(make(i));
  return out;
}

TEST(CompareTrials, EqualRunsAreNoRegression) {
  const auto base =
      run_of(12, [](int i) { return trial("reach", "tallbot", i, i % 4 != 0, 0.01 * i, 100 * i); });
  const Comparison c = compare_trials(base, base, true, {});
  EXPECT_FALSE(c.regression());
  EXPECT_EQ(c.overall.pairs, 12);
  EXPECT_EQ(c.overall.base_successes, 9);
  EXPECT_DOUBLE_EQ(c.overall.mcnemar_p, 1.0);
  EXPECT_DOUBLE_EQ(c.overall.time_ratio, 1.0);
  EXPECT_EQ(c.overall.work[0].changed_trials, 0);
  EXPECT_TRUE(c.flips.empty());
  ASSERT_EQ(c.groups.size(), 1u);
}

TEST(CompareTrials, SignificantSuccessDropIsARegressionAndSmallOnesAreNot) {
  const auto base =
      run_of(20, [](int i) { return trial("pickup", "tallbot", i, true, 0.02, 500); });
  // 8 of 20 now fail: McNemar p = 2/256.
  const auto worse =
      run_of(20, [](int i) { return trial("pickup", "tallbot", i, i > 8, 0.02, 500); });
  const Comparison c = compare_trials(base, worse, true, {});
  EXPECT_TRUE(c.regression());
  EXPECT_NEAR(c.overall.mcnemar_p, 2.0 / 256, 1e-12);
  ASSERT_EQ(c.overall.regressions.size(), 1u);
  EXPECT_NE(c.overall.regressions[0].find("success 100% -> 60%"), std::string::npos)
      << c.overall.regressions[0];
  EXPECT_EQ(c.flips.size(), 8u);
  EXPECT_FALSE(c.flips[0].now_succeeds);
  // 4 of 20: p = 0.125, not significant at 0.05, so not a regression (but listed as flips).
  const auto slightly =
      run_of(20, [](int i) { return trial("pickup", "tallbot", i, i > 4, 0.02, 500); });
  const Comparison d = compare_trials(base, slightly, true, {});
  EXPECT_FALSE(d.regression());
  EXPECT_EQ(d.flips.size(), 4u);
  // The reverse direction is an improvement.
  const Comparison e = compare_trials(worse, base, true, {});
  EXPECT_FALSE(e.regression());
  EXPECT_EQ(e.overall.improvements.size(), 1u);
  // Trials repeat exactly, so a user may fail on any trial that now fails.
  CompareThresholds strict;
  strict.max_new_failures = 3;
  const Comparison f = compare_trials(base, slightly, true, strict);
  EXPECT_TRUE(f.regression());
  EXPECT_NE(f.overall.regressions.at(0).find("4 trials now fail (at most 3 allowed)"),
            std::string::npos);
  strict.max_new_failures = 4;
  EXPECT_FALSE(compare_trials(base, slightly, true, strict).regression());
  // A user who tolerates a 50-point drop passes the first.
  CompareThresholds lenient;
  lenient.max_success_drop = 0.5;
  EXPECT_FALSE(compare_trials(base, worse, true, lenient).regression());
}

TEST(CompareTrials, PlanningTimeRatioAndItsInterval) {
  const auto base =
      run_of(10, [](int i) { return trial("reach", "minibot", i, true, 0.01 * i, 100); });
  // Every trial twice as slow: the interval is the point, and (all ranks tied) Wilcoxon's
  // normal approximation gives p = 0.0019.
  const auto twice =
      run_of(10, [](int i) { return trial("reach", "minibot", i, true, 0.02 * i, 100); });
  const Comparison c = compare_trials(base, twice, true, {});
  EXPECT_NEAR(c.overall.time_ratio, 2.0, 1e-9);
  EXPECT_NEAR(c.overall.time_ratio_low, 2.0, 1e-9);
  EXPECT_NEAR(c.overall.time_ratio_high, 2.0, 1e-9);
  EXPECT_NEAR(c.overall.wilcoxon_p, 0.001904, 1e-6);
  EXPECT_TRUE(c.regression());
  EXPECT_NE(c.overall.regressions.at(0).find("planning time x2.00"), std::string::npos);
  // 1.9x to 2.35x, all different: exact p = 2/1024, interval inside the range.
  const auto slower = run_of(10, [](int i) {
    return trial("reach", "minibot", i, true, 0.01 * i * (1.9 + 0.05 * i), 100);
  });
  const Comparison e = compare_trials(base, slower, true, {});
  EXPECT_NEAR(e.overall.wilcoxon_p, 2.0 / 1024, 1e-12);
  EXPECT_GT(e.overall.time_ratio_low, 1.95);
  EXPECT_LT(e.overall.time_ratio_high, 2.3);
  EXPECT_TRUE(e.regression());
  // 10% slower with noise: below the 1.25 threshold, no verdict.
  const auto noisy = run_of(10, [](int i) {
    return trial("reach", "minibot", i, true, 0.01 * i * (i % 2 ? 1.2 : 1.0), 100);
  });
  const Comparison d = compare_trials(base, noisy, true, {});
  EXPECT_FALSE(d.regression());
  EXPECT_GT(d.overall.time_ratio, 1.05);
  EXPECT_LT(d.overall.time_ratio, 1.15);
  EXPECT_LE(d.overall.time_ratio_low, d.overall.time_ratio);
  EXPECT_GE(d.overall.time_ratio_high, d.overall.time_ratio);
  // Too few pairs for a time verdict, however slow.
  const auto few_base =
      run_of(3, [](int i) { return trial("reach", "minibot", i, true, 0.01, 100); });
  const auto few_slow =
      run_of(3, [](int i) { return trial("reach", "minibot", i, true, 0.05, 100); });
  EXPECT_FALSE(compare_trials(few_base, few_slow, true, {}).regression());
}

TEST(CompareTrials, AnAnytimePlannerSpendingItsBudgetIsSlowerByDesignNotARegression) {
  const auto base = run_of(10, [](int i) {
    nlohmann::json t = trial("reach", "minibot", i, true, 0.01 * i, 100, "RRTConnect");
    t["planner_name"] = "RRTConnect";
    return t;
  });
  // BITstar uses its whole 0.5 s per plan call: 10x to 50x slower, 5x the checks.
  const auto optimizing = run_of(10, [](int i) {
    nlohmann::json t = trial("reach", "minibot", i, true, 0.5, 500, "BITstar");
    t["planner_name"] = "BITstar";
    // The second call tried three goal poses: three planner runs of up to 0.5 s each.
    t["plans"] = {{{"planning_time_s", 0.5}, {"planner_runs", 1}},
                  {{"planning_time_s", 1.49}, {"planner_runs", 3}}};
    return t;
  });
  PlannerBudgets budgets;
  budgets.anytime_planners = {"BITstar"};
  budgets.plan_time_limit_s = {{"reach", 0.5}};
  const Comparison c = compare_trials(base, optimizing, false, {}, budgets);
  EXPECT_FALSE(c.regression());
  ASSERT_EQ(c.overall.by_design.size(), 2u);  // planning time and collision checks
  EXPECT_NE(c.overall.by_design[0].find("planning time x"), std::string::npos);
  EXPECT_NE(c.overall.by_design[1].find("collision checks x5.00"), std::string::npos);
  const std::string md = comparison_markdown(c);
  EXPECT_NE(md.find(kByDesign), std::string::npos) << md;
  // Without the budgets, or past its limit, the same numbers are regressions; for an anytime
  // planner the verdict says why they are not its design.
  EXPECT_TRUE(compare_trials(base, optimizing, false, {}).regression());
  PlannerBudgets tight = budgets;
  tight.plan_time_limit_s = {{"reach", 0.2}};
  const Comparison over = compare_trials(base, optimizing, false, {}, tight);
  EXPECT_TRUE(over.regression());
  ASSERT_FALSE(over.overall.regressions.empty());
  EXPECT_NE(over.overall.regressions[0].find("(not by design: a plan call of reach.minibot."
                                             "kitchen.BITstar.l3.s1 planned 0.50 s, over its "
                                             "0.20 s limit)"),
            std::string::npos)
      << over.overall.regressions[0];
  // Within its limit but asking for more plans than the base (a call that found no path in
  // its budget, then another): a regression, saying so.
  auto more_calls = optimizing;
  more_calls[0]["plan_calls"] = 3;
  const Comparison more = compare_trials(base, more_calls, false, {}, budgets);
  EXPECT_TRUE(more.regression());
  EXPECT_NE(comparison_markdown(more).find("(not by design: 21 plan calls against the base's 20)"),
            std::string::npos);
}

// RRTstar under an iteration budget too large for the machine: every plan call ran into the
// clock's safety net, so no pair can be judged. The run's planner table says so instead of
// leaving the planner out.
TEST(CompareTrials, APlannerWhosePairsAClockBoundDecidedIsNotJudgedAndSaysWhy) {
  std::vector<nlohmann::json> trials = run_of(
      4, [](int i) { return trial("reach", "tallbot", i, true, 0.01 * i, 100, "RRTConnect"); });
  for (const nlohmann::json& t : run_of(4, [](int i) {
         nlohmann::json t = trial("reach", "tallbot", i, true, 60, 150000, "RRTstar");
         t["clock_bound_hit"] = {"plan_time_limit"};
         return t;
       })) {
    trials.push_back(t);
  }
  const std::vector<std::string> planners = {"RRTConnect", "RRTstar"};
  const std::vector<Comparison> cs = compare_planners(trials, planners, {});
  ASSERT_EQ(cs.size(), 1u);
  EXPECT_EQ(cs[0].overall.pairs, 0);
  EXPECT_EQ(cs[0].nonreproducible.size(), 4u);
  const std::string table = planner_table_markdown(trials, planners, cs);
  EXPECT_NE(table.find("| RRTstar | 4/4 |"), std::string::npos) << table;
  EXPECT_NE(table.find("not judged: a clock bound decided all 4 pairs"), std::string::npos)
      << table;
  EXPECT_NE(comparison_markdown(cs[0]).find("**Verdict: not judged: no pair left to judge.**"),
            std::string::npos);
}

TEST(CompareTrials, NoChangeOnAGroupTooSmallToDetectOneSaysSo) {
  const auto three = run_of(3, [](int i) { return trial("reach", "minibot", i, true, 0.01, 100); });
  const Comparison c = compare_trials(three, three, true, {});
  ASSERT_EQ(c.groups.size(), 1u);
  EXPECT_EQ(no_change_text(c.groups[0], {}),
            "no significant change (underpowered: no success change is detectable with 3 "
            "pairs)");
  EXPECT_NE(comparison_markdown(c).find("underpowered"), std::string::npos);
  // 30 pairs at 100% detect a drop of about 25 points, more than the 10-point threshold.
  const auto thirty =
      run_of(30, [](int i) { return trial("reach", "minibot", i, true, 0.01, 100); });
  const std::string text = no_change_text(compare_trials(thirty, thirty, true, {}).groups[0], {});
  EXPECT_NE(text.find("underpowered: only a success drop of "), std::string::npos) << text;
}

TEST(CompareTrials, FailureLocationIsThePathOfTheFailingPrograms) {
  nlohmann::json t = {{"failure_reason", "tidy > greet > postural(rest): invalid_goal: far"}};
  EXPECT_EQ(failure_location(t), "tidy > greet > postural(rest)");
  // From the failed events, innermost first in the log: outermost first in the path.
  t = {{"failure_reason", "ik_failure: unreachable"},
       {"events",
        {{{"type", "started"}, {"program", "pickup"}},
         {{"type", "failed"}, {"program", "grasp"}, {"reason", "ik_failure: unreachable"}},
         {{"type", "failed"},
          {"program", "pickup"},
          {"reason", "grasp: ik_failure: unreachable"}}}}};
  EXPECT_EQ(failure_location(t), "pickup > grasp");
  EXPECT_EQ(failure_location({{"status", "timeout"}}), "");
}

TEST(CompareTrials, TheHtmlReportListsTheTrialsWhoseOutcomeChanged) {
  const auto base = run_of(4, [](int i) { return trial("pickup", "tallbot", i, true, 0.02, 50); });
  auto fresh = base;
  fresh[1]["success"] = false;
  fresh[1]["status"] = "ik_failure";
  fresh[1]["failure_reason"] = "pickup > grasp: ik_failure: the cup is out of reach";
  const Comparison c = compare_trials(base, fresh, true, {});
  ASSERT_EQ(c.flips.size(), 1u);
  EXPECT_EQ(c.flips[0].where, "pickup > grasp");
  const std::string html = compare_html(c, base, fresh, nullptr, nullptr, {}, 0);
  const size_t table = html.find("Trials whose outcome changed");
  ASSERT_NE(table, std::string::npos);
  EXPECT_NE(html.find("pickup.tallbot.kitchen.RRTConnect.l3.s2", table), std::string::npos);
  EXPECT_NE(html.find("pickup &gt; grasp", table), std::string::npos);
  // The Markdown holds the same table.
  const std::string md = comparison_markdown(c);
  EXPECT_NE(md.find("## Trials whose outcome changed"), std::string::npos);
  EXPECT_NE(md.find("pickup > grasp"), std::string::npos);
}

TEST(CompareTrials, TwoPlannersRunsPairedWithoutThePlannerShowNoEmptyRows) {
  const auto base = run_of(4, [](int i) { return trial("reach", "tallbot", i, true, 0.02, 50); });
  const auto fresh =
      run_of(4, [](int i) { return trial("reach", "tallbot", i, true, 0.5, 400, "BITstar"); });
  const Comparison c = compare_trials(base, fresh, false, {});
  EXPECT_EQ(c.overall.pairs, 4);
  const std::string html = compare_html(c, base, fresh, nullptr, nullptr, {}, 0);
  EXPECT_NE(html.find("RRTConnect · base (4)"), std::string::npos);
  EXPECT_NE(html.find("BITstar · new (4)"), std::string::npos);
  EXPECT_EQ(html.find("(0)"), std::string::npos);
}

TEST(CompareTrials, WorkCountsAreExactAndMoreChecksFail) {
  const auto base = run_of(6, [](int i) { return trial("reach", "tallbot", i, true, 0.01, 1000); });
  const auto more = run_of(
      6, [](int i) { return trial("reach", "tallbot", i, true, 0.01, i <= 3 ? 2000 : 1000); });
  const Comparison c = compare_trials(base, more, true, {});
  const WorkCountChange& checks = c.overall.work.at(0);
  EXPECT_EQ(checks.field, "collision_checks");
  EXPECT_DOUBLE_EQ(checks.base_total, 6000);
  EXPECT_DOUBLE_EQ(checks.new_total, 9000);
  EXPECT_EQ(checks.changed_trials, 3);
  EXPECT_TRUE(c.regression());
  EXPECT_NE(c.overall.regressions.at(0).find("collision checks x1.50 (6000 -> 9000; 3 trials"),
            std::string::npos)
      << c.overall.regressions.at(0);
}

TEST(CompareTrials, PairsByIdentityAndListsTheRest) {
  auto base = run_of(4, [](int i) { return trial("reach", "tallbot", i, true, 0.01, 100); });
  auto fresh = run_of(5, [](int i) { return trial("reach", "tallbot", i + 1, true, 0.01, 100); });
  const Comparison c = compare_trials(base, fresh, true, {});
  EXPECT_EQ(c.overall.pairs, 3);
  EXPECT_EQ(c.only_in_base, std::vector<std::string>{"reach.tallbot.kitchen.RRTConnect.l3.s1"});
  EXPECT_EQ(c.only_in_new.size(), 2u);
  // Another planner pairs only when planners are ignored.
  const auto prm =
      run_of(4, [](int i) { return trial("reach", "tallbot", i, true, 0.01, 100, "PRM"); });
  EXPECT_EQ(compare_trials(base, prm, true, {}).overall.pairs, 0);
  const Comparison q = compare_trials(base, prm, false, {});
  EXPECT_EQ(q.overall.pairs, 4);
  ASSERT_EQ(q.groups.size(), 1u);
  EXPECT_EQ(q.groups[0].new_planner, "PRM");
  base.push_back(base[0]);
  EXPECT_THROW(compare_trials(base, fresh, true, {}), std::invalid_argument);
}

TEST(CompareTrials, UnpairedTrialsFailOnlyWhenAsked) {
  const auto base = run_of(4, [](int i) { return trial("reach", "tallbot", i, true, 0.01, 100); });
  const auto half = run_of(2, [](int i) { return trial("reach", "tallbot", i, true, 0.01, 100); });
  EXPECT_FALSE(compare_trials(base, half, true, {}).regression());
  CompareThresholds t;
  t.fail_on_unpaired = true;
  const Comparison c = compare_trials(base, half, true, t);
  EXPECT_TRUE(c.regression());
  EXPECT_EQ(c.overall.regressions.at(0), "2 trials of the base are missing");
  t.new_is_subset = true;  // the fast form: fewer trials, all with partners
  EXPECT_FALSE(compare_trials(base, half, true, t).regression());
  auto extra = half;
  extra.push_back(trial("reach", "tallbot", 9, true, 0.01, 100));
  const Comparison d = compare_trials(base, extra, true, t);
  EXPECT_TRUE(d.regression());
  EXPECT_EQ(d.overall.regressions.at(0), "1 trials of the new run have no partner in the base");
}

TEST(CompareTrials, ChecksFromNothingAndMissingCountsAreRegressions) {
  // A group that did not plan now does.
  const auto none = run_of(3, [](int i) { return trial("postural", "tallbot", i, true, 0, 0); });
  const auto some =
      run_of(3, [](int i) { return trial("postural", "tallbot", i, true, 0.01, 500); });
  const Comparison c = compare_trials(none, some, true, {});
  EXPECT_TRUE(c.regression());
  EXPECT_EQ(c.overall.regressions.at(0), "collision checks 0 -> 1500 (3 trials changed)");
  // A successful new trial without its counts is a broken writer, not a pass.
  auto blank = run_of(3, [](int i) { return trial("reach", "tallbot", i, true, 0.01, 500); });
  const auto full = blank;
  blank[1]["collision_checks"] = nullptr;
  const Comparison d = compare_trials(full, blank, true, {});
  EXPECT_TRUE(d.regression());
  EXPECT_EQ(d.overall.work.at(0).missing, 1);
  EXPECT_EQ(d.overall.regressions.at(0), "1 successful new trials lack collision_checks");
  // A crashed trial's null counts are not that: its failure is judged as a failure.
  blank[1]["success"] = false;
  const Comparison e = compare_trials(full, blank, true, {});
  EXPECT_FALSE(e.regression());  // one flip of three: not significant
  EXPECT_EQ(e.overall.work.at(0).missing, 1);
}

// ---- `taskmatrix compare` on run directories.
class CompareCli : public ::testing::Test {
 protected:
  void SetUp() override {
    char tmpl[] = "/tmp/taskmatrix_compare_XXXXXX";
    dir_ = mkdtemp(tmpl);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path write_run(const std::string& name, const std::vector<nlohmann::json>& t) {
    const auto d = dir_ / name;
    std::filesystem::create_directories(d);
    std::ofstream out(d / "trials.jsonl");
    for (const nlohmann::json& j : t) out << j.dump() << "\n";
    return d;
  }
  test::CommandResult compare(const std::string& args) {
    return test::run_cli("compare " + args, test::catalog().root());
  }
  std::filesystem::path dir_;
};

std::string slurp(const std::filesystem::path& f) {
  std::ifstream in(f);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST_F(CompareCli, ExitStatusFollowsTheVerdictOnlyWhenAsked) {
  const auto base =
      write_run("base", run_of(20, [](int i) {
                  return trial(i % 2 ? "reach" : "grasp", i % 4 < 2 ? "tallbot" : "minibot", i,
                               true, 0.01 * i, 300);
                }));
  const auto worse =
      write_run("worse", run_of(20, [](int i) {
                  return trial(i % 2 ? "reach" : "grasp", i % 4 < 2 ? "tallbot" : "minibot", i,
                               i > 9, 0.01 * i, 300);
                }));
  const test::CommandResult same =
      compare("'" + base.string() + "' '" + base.string() + "' --fail-on-regression");
  EXPECT_EQ(same.exit_code, 0) << same.err;
  EXPECT_NE(same.out.find("**Verdict: no regression.**"), std::string::npos) << same.out;
  const test::CommandResult report_only =
      compare("'" + base.string() + "' '" + worse.string() + "'");
  EXPECT_EQ(report_only.exit_code, 0) << report_only.err;
  const auto report = dir_ / "report";
  const test::CommandResult gate =
      compare("'" + base.string() + "' '" + worse.string() + "' --fail-on-regression --report '" +
              report.string() + "'");
  EXPECT_EQ(gate.exit_code, 1) << gate.err;
  EXPECT_NE(gate.out.find("**Verdict: regression.**"), std::string::npos) << gate.out;
  EXPECT_NE(gate.out.find("9 now fail"), std::string::npos) << gate.out;
  // The last value of a threshold wins, so scripts' defaults can be overridden.
  EXPECT_EQ(compare("'" + base.string() + "' '" + worse.string() +
                    "' --fail-on-regression --max-success-drop 0.05 --max-success-drop 0.5")
                .exit_code,
            0);
  // Without pictures the failures are still counted.
  const auto bare = dir_ / "bare";
  EXPECT_EQ(compare("'" + base.string() + "' '" + worse.string() +
                    "' --max-snapshots 0 --report '" + bare.string() + "'")
                .exit_code,
            0);
  const std::string bare_html = slurp(bare / "report.html");
  EXPECT_EQ(bare_html.find("No trial failed"), std::string::npos);
  EXPECT_NE(bare_html.find("9 more failed trials not pictured"), std::string::npos);
  // The thresholds are the user's: a 50-point drop is tolerated.
  EXPECT_EQ(compare("'" + base.string() + "' '" + worse.string() +
                    "' --fail-on-regression --max-success-drop 0.5")
                .exit_code,
            0);
  // The report: Markdown, JSON, and HTML that needs nothing from outside.
  const std::string md = slurp(report / "compare.md");
  EXPECT_NE(md.find("## Trials whose outcome changed"), std::string::npos);
  const nlohmann::json j = nlohmann::json::parse(slurp(report / "compare.json"));
  EXPECT_TRUE(j["regression"].get<bool>());
  EXPECT_EQ(j["overall"]["success"]["only_base"], 9);
  const std::string html = slurp(report / "report.html");
  EXPECT_NE(html.find("Regression</p>"), std::string::npos);
  EXPECT_GE(std::count(html.begin(), html.end(), '<'), 100);
  size_t svgs = 0;
  for (size_t at = html.find("<svg"); at != std::string::npos; at = html.find("<svg", at + 1))
    ++svgs;
  EXPECT_EQ(svgs, 3u);  // distributions, success rates, scatter
  EXPECT_EQ(html.find("<script"), std::string::npos);
  EXPECT_EQ(html.find("src='http"), std::string::npos);
  EXPECT_EQ(html.find("href="), std::string::npos);
  // These trials have no recordings: the failed ones are listed with the reason.
  EXPECT_NE(html.find("no picture:"), std::string::npos);
}

TEST_F(CompareCli, OnlyTheRunsOwnTrialsArePairedAfterAResume) {
  // trials.jsonl holds a trial of another matrix (left by --resume with other --trials);
  // summary.json names the run's own.
  const auto base = write_run(
      "base", run_of(2, [](int i) { return trial("reach", "tallbot", i, true, 0.01, 1); }));
  auto lines = run_of(3, [](int i) { return trial("reach", "tallbot", i, i < 3, 0.01, 1); });
  const auto fresh = write_run("fresh", lines);
  EXPECT_EQ(compare("'" + base.string() + "' '" + fresh.string() +
                    "' --fail-on-regression --fail-on-unpaired")
                .exit_code,
            1);
  std::ofstream(fresh / "summary.json")
      << nlohmann::json{{"trial_ids", {lines[0]["trial_id"], lines[1]["trial_id"]}}}.dump();
  const test::CommandResult r = compare("'" + base.string() + "' '" + fresh.string() +
                                        "' --fail-on-regression --fail-on-unpaired");
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("2 trials paired."), std::string::npos) << r.out;
}

TEST_F(CompareCli, BadInputIsOneClearLine) {
  const auto base = write_run(
      "base", run_of(2, [](int i) { return trial("reach", "tallbot", i, true, 0.01, 1); }));
  const test::CommandResult missing =
      compare("'" + base.string() + "' '" + (dir_ / "nope").string() + "'");
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("nope: no such run directory"), std::string::npos) << missing.err;

  std::filesystem::create_directories(dir_ / "empty");
  const test::CommandResult empty =
      compare("'" + base.string() + "' '" + (dir_ / "empty").string() + "'");
  EXPECT_EQ(empty.exit_code, 2);
  EXPECT_NE(empty.err.find("empty/trials.jsonl: missing"), std::string::npos) << empty.err;

  auto broken = run_of(2, [](int i) { return trial("reach", "tallbot", i, true, 0.01, 1); });
  broken[0].erase("success");
  const auto bad = write_run("bad", broken);
  const test::CommandResult no_success = compare("'" + base.string() + "' '" + bad.string() + "'");
  EXPECT_EQ(no_success.exit_code, 2);
  EXPECT_NE(no_success.err.find("bad/trials.jsonl:1: success: is required but missing"),
            std::string::npos)
      << no_success.err;

  const auto other = write_run(
      "other", run_of(2, [](int i) { return trial("reach", "tallbot", i, true, 0.01, 1, "PRM"); }));
  const test::CommandResult unpaired = compare("'" + base.string() + "' '" + other.string() + "'");
  EXPECT_EQ(unpaired.exit_code, 2);
  EXPECT_NE(unpaired.err.find("no trial has a partner"), std::string::npos) << unpaired.err;
  EXPECT_NE(unpaired.err.find("--ignore-planner"), std::string::npos) << unpaired.err;
  EXPECT_EQ(compare("'" + base.string() + "' '" + other.string() + "' --ignore-planner").exit_code,
            0);
}

// ---- Real runs.
class CompareRuns : public ::testing::Test {
 protected:
  void SetUp() override {
    char tmpl[] = "/tmp/taskmatrix_compare_runs_XXXXXX";
    dir_ = mkdtemp(tmpl);
    programs::register_programs(registry_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  RunJobResult run(const std::string& scenario_text, const std::string& out,
                   RunOverrides overrides = {}) {
    std::ofstream(dir_ / "s.yaml") << scenario_text;
    RunJobOptions options;
    options.scenario_file = dir_ / "s.yaml";
    options.out = dir_ / out;
    options.jobs = 2;
    options.progress = RunJobOptions::Progress::kOff;
    options.overrides = std::move(overrides);
    std::ostringstream o, e;
    return run_job(test::catalog(), registry_, options, o, e);
  }
  std::filesystem::path dir_;
  core::ProgramRegistry registry_;
};

TEST_F(CompareRuns, ARunAgainstItsRepeatIsNoRegressionAndFailuresArePictured) {
  // Reach on both robots, plus a pickup of a visitor out of reach (fails with ik_failure at
  // once).
  const std::string suite =
      "name: mixed\nprogram: reach\nparams: {object: cup}\nrobots: [minibot, tallbot]\n"
      "environments: [kitchen]\nobstacles: {count: 4}\nlayout_seed: 5\ntrials: 2\n"
      "time_limit_s: 30\nsuccess: graspable(cup)\n";
  const RunJobResult a = run(suite, "a");
  const RunJobResult b = run(suite, "b");
  std::ofstream(dir_ / "far.yaml")
      << "name: far\nprogram: pickup\nparams: {object: visitor, step: false}\nrobots: [minibot]\n"
         "environments: [office]\ntrials: 1\ntime_limit_s: 10\n";
  RunJobOptions options;
  options.scenario_file = dir_ / "far.yaml";
  options.out = dir_ / "far";
  options.progress = RunJobOptions::Progress::kOff;
  std::ostringstream o, e;
  run_job(test::catalog(), registry_, options, o, e);
  // Two run directories holding the same far trial (a copy), so a failure is in both.
  const nlohmann::json far = nlohmann::json::parse(slurp(dir_ / "far" / "trials.jsonl"));
  for (const auto& d : {a.dir, b.dir}) {
    std::ofstream(d / "trials.jsonl", std::ios::app) << slurp(dir_ / "far" / "trials.jsonl");
    nlohmann::json summary = nlohmann::json::parse(slurp(d / "summary.json"));
    ASSERT_EQ(summary["trial_ids"].size(), 4u);  // the run's own, for compare
    summary["trial_ids"].push_back(far["trial_id"]);
    std::ofstream(d / "summary.json") << summary.dump();
    std::filesystem::copy(
        dir_ / "far" / "trajectories", d / "trajectories",
        std::filesystem::copy_options::update_existing | std::filesystem::copy_options::recursive);
  }
  const auto report = dir_ / "report";
  const test::CommandResult r =
      test::run_cli("compare '" + a.dir.string() + "' '" + b.dir.string() +
                        "' --fail-on-regression --report '" + report.string() + "'",
                    test::catalog().root());
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("5 trials paired"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("0 now fail, 0 now succeed"), std::string::npos) << r.out;
  // Work counts are deterministic: no trial's collision checks changed between the runs.
  const nlohmann::json j = nlohmann::json::parse(slurp(report / "compare.json"));
  EXPECT_EQ(j["overall"]["work"]["collision_checks"]["changed_trials"], 0);
  EXPECT_EQ(j["overall"]["work"]["plan_calls"]["changed_trials"], 0);
  EXPECT_GT(j["overall"]["work"]["collision_checks"]["base"].get<double>(), 100);
  EXPECT_NE(r.out.find("(1 failed trials pictured)"), std::string::npos) << r.out;
  const std::string html = slurp(report / "report.html");
  // The failed trial at the moment it failed: the overview and a close-up, and the commands
  // that render its video with this binary.
  EXPECT_NE(html.find("<img alt='overview of far.minibot.office"), std::string::npos);
  EXPECT_NE(html.find("<img alt='close-up of far.minibot.office"), std::string::npos);
  EXPECT_NE(html.find("src='data:image/png;base64,iVBORw0KGgo"), std::string::npos);
  EXPECT_NE(html.find("not_graspable"), std::string::npos);
  EXPECT_NE(html.find(" render --trial "), std::string::npos);
  EXPECT_NE(html.find("--camera lookat:"), std::string::npos);
  // The same build loaded the same models: no warning, and the report says so.
  EXPECT_EQ(r.out.find("WARNING"), std::string::npos) << r.out;
  EXPECT_NE(slurp(report / "compare.md").find("The same build loaded the same model"),
            std::string::npos);
  EXPECT_FALSE(j["provenance_differences"]["models_changed"].get<bool>());
}

TEST_F(CompareRuns, AModelFileEditedBetweenTwoRunsIsNamedByCompare) {
  // A copy of the models, one run, an edit to the kitchen's MJCF (a comment: same scene,
  // other bytes), another run.
  const std::filesystem::path root = dir_ / "root";
  std::filesystem::create_directories(root);
  std::filesystem::copy(test::catalog().root() / "models", root / "models",
                        std::filesystem::copy_options::recursive);
  std::ofstream(dir_ / "s.yaml") << "name: one\nprogram: reach\nparams: {object: cup}\n"
                                    "robots: [minibot]\nenvironments: [kitchen]\ntrials: 1\n"
                                    "time_limit_s: 30\n";
  const auto run_in = [&](const std::string& out) {
    const ModelCatalog catalog(root);
    RunJobOptions options;
    options.scenario_file = dir_ / "s.yaml";
    options.out = dir_ / out;
    options.progress = RunJobOptions::Progress::kOff;
    std::ostringstream o, e;
    return run_job(catalog, registry_, options, o, e).dir;
  };
  const std::filesystem::path a = run_in("a");
  const nlohmann::json provenance = nlohmann::json::parse(slurp(a / "provenance.json"));
  std::vector<std::string> recorded;
  for (const auto& f : provenance["model_files"]) {
    recorded.push_back(f["path"].get<std::string>());
    EXPECT_EQ(f["sha256"].get<std::string>().size(), 64u) << f;
  }
  EXPECT_EQ(recorded, (std::vector<std::string>{"models/environments/kitchen/environment.yaml",
                                                "models/environments/kitchen/kitchen.xml",
                                                "models/robots/minibot/minibot.xml",
                                                "models/robots/minibot/profile.yaml"}));
  EXPECT_EQ(provenance["build"]["commit"].get<std::string>().size(), 40u) << provenance["build"];

  std::ofstream(root / "models/environments/kitchen/kitchen.xml", std::ios::app)
      << "<!-- edited -->\n";
  const std::filesystem::path b = run_in("b");
  CompareJobOptions options;
  options.base_dir = a;
  options.new_dir = b;
  options.report_dir = dir_ / "report";
  std::ostringstream out;
  const CompareJobResult r = run_compare_job(options, out);
  EXPECT_TRUE(r.differences.models_changed());
  ASSERT_EQ(r.differences.changed_models.size(), 1u);
  EXPECT_EQ(r.differences.changed_models[0].path, "models/environments/kitchen/kitchen.xml");
  EXPECT_NE(out.str().find("WARNING: the runs loaded different model files (1 changed):\n"
                           "  models/environments/kitchen/kitchen.xml"),
            std::string::npos)
      << out.str();
  EXPECT_NE(slurp(dir_ / "report" / "compare.md").find("models/environments/kitchen/kitchen.xml"),
            std::string::npos);
  EXPECT_NE(slurp(dir_ / "report" / "report.html").find("models/environments/kitchen/kitchen.xml"),
            std::string::npos);
  // The command line fails on it only when asked.
  const std::string args = "compare '" + a.string() + "' '" + b.string() + "'";
  EXPECT_EQ(test::run_cli(args, root).exit_code, 0);
  const test::CommandResult failed = test::run_cli(args + " --fail-on-model-change", root);
  EXPECT_EQ(failed.exit_code, 1) << failed.out << failed.err;
  EXPECT_NE(failed.err.find("--fail-on-model-change"), std::string::npos) << failed.err;
}

TEST_F(CompareRuns, SeveralPlannersAreComparedOnTheSameTrials) {
  RunOverrides o;
  o.planners = {"RRTConnect", "RRT"};
  const RunJobResult r =
      run("name: planners\nprogram: reach\nparams: {object: cup}\nrobots: [tallbot]\n"
          "environments: [kitchen]\nobstacles: {count: 4}\nlayout_seed: 5\ntrials: 3\n"
          // Bounded by work, never by the clock: an RRT plan that needs more iterations fails
          // as a result (and stays a pair) instead of meeting the 60 s clock bound on a loaded
          // machine (which compare leaves out).
          "plan_iterations: 3000\nexecution: kinematic\n"
          "time_limit_s: 30\nsuccess: graspable(cup)\n",
          "planners", o);
  ASSERT_EQ(r.finished, 6);
  const std::string md = slurp(r.dir / "summary.md");
  EXPECT_NE(md.find("## Planners, each against RRTConnect on the same trials"), std::string::npos)
      << md;
  EXPECT_NE(md.find("| RRTConnect | "), std::string::npos);
  EXPECT_NE(md.find("| RRT | "), std::string::npos);
  const nlohmann::json s = nlohmann::json::parse(slurp(r.dir / "summary.json"));
  const nlohmann::json& c = s["planner_comparison"]["comparisons"].at(0);
  EXPECT_EQ(s["planner_comparison"]["reference"], "RRTConnect");
  EXPECT_EQ(c["new"], "RRT");
  EXPECT_EQ(c["overall"]["pairs"], 3);
  EXPECT_GT(c["overall"]["planning_time"]["pairs"].get<int>(), 0);
  const std::string html = slurp(r.dir / "planners.html");
  EXPECT_NE(html.find("RRT against RRTConnect"), std::string::npos);
  EXPECT_NE(html.find("<svg"), std::string::npos);
  EXPECT_TRUE(std::filesystem::exists(r.dir / "planners.md"));
}

}  // namespace
}  // namespace taskmatrix::harness
