// The parts of the comparison reports beyond the verdict: statistical power against textbook
// values, paired path quality against a hand computation, one table model rendered the same in
// Markdown and HTML, and the provenance difference naming what changed between two runs.
#include <gtest/gtest.h>

#include <cmath>

#include "harness/compare/path_quality.h"
#include "harness/compare/power.h"
#include "harness/compare/provenance_diff.h"
#include "harness/report/report_table.h"

namespace taskmatrix::harness {
namespace {

TEST(Power, ThreeTrialsCannotDetectAFiftyPointDrop) {
  // McNemar's exact test over 3 pairs can never reach p < 0.05 (2 / 2^3 = 0.25).
  EXPECT_EQ(mcnemar_power(3, 1.0, 0.5, 0.05), 0.0);
  EXPECT_EQ(mcnemar_power(3, 1.0, 0.0, 0.05), 0.0);
  const GroupPower p = group_power(3, 3, {}, 3, 0.05, 0.5, 1.25);
  EXPECT_TRUE(std::isnan(p.success_change));
  EXPECT_EQ(success_change_text(p), "none (3 pairs)");
  // A 50-point drop from 100% needs a handful of trials, not 3.
  const int needed = pairs_for_success_change(1.0, 0.5, 0.05);
  EXPECT_GT(needed, 3);
  EXPECT_LT(needed, 20);
  EXPECT_GE(mcnemar_power(needed, 1.0, 0.5, 0.05), kTargetPower);
}

// The textbook sample size of McNemar's test for outcomes independent at the two rates
// (Connor 1987, normal approximation): n = (z_.975 sqrt(psi) + z_.8 sqrt(psi - delta^2))^2 /
// delta^2 with psi = p1 q2 + p2 q1, delta = p1 - p2. Solved by hand for n = 100 (bisection): a
// drop of 19.58 points from 50%, 18.13 from 80%; a 10-point drop from 50% needs 390 trials.
// The exact test is discrete and a little more conservative.
TEST(Power, HundredTrialsGiveTheTextbookDetectableDropWithinAPoint) {
  EXPECT_NEAR(detectable_success_change(100, 0.5, 0.05), 0.1958, 0.01);
  EXPECT_NEAR(detectable_success_change(100, 0.8, 0.05), 0.1813, 0.01);
  const GroupPower p = group_power(100, 50, {}, 1, 0.05, 0.1, 1.25);
  EXPECT_EQ(success_change_text(p), "20 points");
  const int needed = pairs_for_success_change(0.5, 0.1, 0.05);
  EXPECT_GE(needed, 390);
  EXPECT_LE(needed, 410);
  EXPECT_GE(mcnemar_power(needed, 0.5, 0.4, 0.05), kTargetPower);
}

// A run's summary.md and summary.json say per group and for the whole run how small a change
// a repeat of the run could detect, and how many trials a 10-point change needs.
TEST(Power, TheRunSummaryGivesEachGroupsDetectableDropAndTheTrialsNeeded) {
  const nlohmann::json summary = {{"overall", {{"trials", 103}, {"successes", 53}}},
                                  {"groups",
                                   {{{"scenario", "pickup"},
                                     {"robot", "tallbot"},
                                     {"environment", "kitchen"},
                                     {"planner", "RRTConnect"},
                                     {"trials", 3},
                                     {"successes", 3}},
                                    {{"scenario", "reach"},
                                     {"robot", "minibot"},
                                     {"environment", "office"},
                                     {"planner", "BITstar"},
                                     {"trials", 100},
                                     {"successes", 50}},
                                    {{"scenario", "grasp"},
                                     {"robot", "atlas"},
                                     {"environment", "kitchen"},
                                     {"planner", "RRTConnect"},
                                     {"trials", 20},
                                     {"successes", 0}}}}};
  const nlohmann::json power = summary_power_json(summary);
  ASSERT_EQ(power["groups"].size(), 3u);
  const nlohmann::json& three = power["groups"][0];
  const nlohmann::json& hundred = power["groups"][1];
  const nlohmann::json& none = power["groups"][2];
  // 3 trials: no drop at all is detectable; a 10-point drop from 100% needs what the exact
  // test says.
  EXPECT_TRUE(three["detectable_success_change"].is_null());
  EXPECT_EQ(three["trials_for_target"], pairs_for_success_change(1.0, 0.1, 0.05));
  // 100 trials at 50%: the textbook 19.6 points within a point; 390 trials by the formula for
  // a 10-point drop, a few more by the exact test.
  EXPECT_NEAR(hundred["detectable_success_change"].get<double>(), 0.1958, 0.01);
  EXPECT_GE(hundred["trials_for_target"].get<int>(), 390);
  EXPECT_LE(hundred["trials_for_target"].get<int>(), 410);
  // Nothing succeeded: the smallest detectable rise.
  EXPECT_TRUE(none["success_change_is_rise"].get<bool>());
  EXPECT_GT(none["detectable_success_change"].get<double>(), 0.0);
  EXPECT_EQ(power["overall"]["trials"], 103);
  EXPECT_NEAR(power["overall"]["detectable_success_change"].get<double>(),
              detectable_success_change(103, 53.0 / 103, 0.05), 1e-9);

  const std::string md = summary_power_markdown(power);
  EXPECT_NE(md.find("## Statistical power"), std::string::npos) << md;
  EXPECT_NE(md.find("| pickup | tallbot | kitchen | RRTConnect | 3 | 3/3 | none (3 trials) | " +
                    std::to_string(pairs_for_success_change(1.0, 0.1, 0.05)) + " |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| reach | minibot | office | BITstar | 100 | 50/100 | 20 points | " +
                    hundred["trials_for_target"].dump() + " |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| all trials |  |  |  | 103 | 53/103 |"), std::string::npos) << md;
}

TEST(Power, PlanningTimeRatioFollowsTheWilcoxonEfficiency) {
  // Wilcoxon's exact test needs 6 non-zero pairs to reach p < 0.05 (2 / 2^6 = 0.031).
  EXPECT_EQ(wilcoxon_min_pairs(0.05), 6);
  EXPECT_TRUE(std::isnan(detectable_time_ratio(5, 0.3, 0.05)));
  // 100 pairs, sd of the log ratios 0.5: the t test of n' = 300 / pi pairs detects an effect of
  // about (z_.975 + z_.8) / sqrt(n') = 2.80 / 9.77 = 0.287 sd (a little more for t): a ratio
  // of exp(0.5 * 0.287) = 1.154.
  EXPECT_NEAR(detectable_time_ratio(100, 0.5, 0.05), 1.154, 0.01);
  // More spread, a larger ratio; more pairs, a smaller one.
  EXPECT_GT(detectable_time_ratio(100, 1.0, 0.05), detectable_time_ratio(100, 0.5, 0.05));
  EXPECT_LT(detectable_time_ratio(400, 0.5, 0.05), detectable_time_ratio(100, 0.5, 0.05));
  // The pairs needed for that ratio come back to about 100.
  EXPECT_NEAR(pairs_for_time_ratio(1.154, 0.5, 0.05), 100, 3);
}

nlohmann::json trial(bool success, double joint, double ee) {
  return {{"success", success}, {"path_length_joint", joint}, {"path_length_ee_m", ee}};
}

TEST(PathQuality, PairedIntervalMatchesAHandComputation) {
  // Joint path changes new - base: 0.5, 0.5, 0.2, 0.5 (the fifth pair failed in the new run and
  // is not compared). Mean 0.425, sd 0.15, t(0.975, 3) = 3.182446: 0.425 +- 0.238683.
  const std::vector<nlohmann::json> base = {trial(true, 1, 0.1), trial(true, 2, 0.2),
                                            trial(true, 3, 0.3), trial(true, 4, 0.4),
                                            trial(true, 5, 0.5)};
  const std::vector<nlohmann::json> fresh = {trial(true, 1.5, 0.1), trial(true, 2.5, 0.2),
                                             trial(true, 3.2, 0.3), trial(true, 4.5, 0.4),
                                             trial(false, 0.1, 0.01)};
  std::vector<TrialPair> pairs;
  for (size_t i = 0; i < base.size(); ++i) pairs.push_back({&base[i], &fresh[i]});
  const std::vector<PathQualityChange> changes = compare_path_quality(pairs);
  const auto joint = std::find_if(changes.begin(), changes.end(),
                                  [](const auto& c) { return c.field == "path_length_joint"; });
  ASSERT_NE(joint, changes.end());
  EXPECT_EQ(joint->pairs, 4);
  EXPECT_NEAR(joint->mean_change, 0.425, 1e-12);
  EXPECT_NEAR(joint->change_low, 0.425 - 0.238683, 1e-5);
  EXPECT_NEAR(joint->change_high, 0.425 + 0.238683, 1e-5);
  EXPECT_TRUE(joint->significant());
  EXPECT_FALSE(joint->better());  // longer
  EXPECT_NEAR(joint->percent(), 100 * 0.425 / 2.5, 1e-9);
  // The end-effector path did not change: no finding; the joint path is one.
  const std::vector<std::string> findings = path_quality_findings(changes);
  ASSERT_EQ(findings.size(), 1u);
  EXPECT_NE(findings[0].find("joint path"), std::string::npos) << findings[0];
  EXPECT_NE(findings[0].find("longer"), std::string::npos) << findings[0];
  // Measures no trial recorded have no pairs.
  const auto clearance = std::find_if(changes.begin(), changes.end(),
                                      [](const auto& c) { return c.field == "min_clearance_m"; });
  ASSERT_NE(clearance, changes.end());
  EXPECT_EQ(clearance->pairs, 0);
}

// A minimum clearance can be negative (a penetration) or about 0: no share of it is given.
TEST(PathQuality, NoPercentOfABaseMeanThatIsNotPositive) {
  std::vector<nlohmann::json> base, fresh;
  for (const double c : {-0.0004, 0.0001, 0.0002}) {
    base.push_back({{"success", true}, {"min_clearance_m", c}});
    fresh.push_back({{"success", true}, {"min_clearance_m", c + 0.0005}});
  }
  std::vector<TrialPair> pairs;
  for (size_t i = 0; i < base.size(); ++i) pairs.push_back({&base[i], &fresh[i]});
  const std::vector<PathQualityChange> changes = compare_path_quality(pairs);
  const auto clearance = std::find_if(changes.begin(), changes.end(),
                                      [](const auto& c) { return c.field == "min_clearance_m"; });
  ASSERT_NE(clearance, changes.end());
  EXPECT_EQ(clearance->pairs, 3);
  EXPECT_NEAR(clearance->mean_change, 0.0005, 1e-12);
  EXPECT_TRUE(std::isnan(clearance->percent()));
  const std::string text = path_change_text(*clearance);
  EXPECT_EQ(text.find('%'), std::string::npos) << text;
  EXPECT_NE(text.find("+0.0005"), std::string::npos) << text;
}

TEST(ReportTable, MarkdownAndHtmlHoldTheSameCellsEscapedForEach) {
  ReportTable t;
  t.columns = {"group", "reason"};
  t.rows.push_back({{"reach · tallbot", "a|b <c> & d"}, "bad"});
  t.rows.push_back({{"pickup", "line\nbreak"}, ""});
  EXPECT_EQ(markdown_table(t),
            "| group | reason |\n|---|---|\n| reach · tallbot | a\\|b <c> & d |\n"
            "| pickup | line break |\n");
  EXPECT_EQ(html_table(t),
            "<table><tr><th>group</th><th>reason</th></tr><tr class='bad'><td>reach · tallbot"
            "</td><td>a|b &lt;c&gt; &amp; d</td></tr><tr><td>pickup</td><td>line\nbreak</td>"
            "</tr></table>");
}

nlohmann::json provenance(const std::string& kitchen_sha, const std::string& commit) {
  return {{"git_commit", commit},
          {"git_dirty", false},
          {"mujoco_version", "2.2.2"},
          {"ompl_version", "1.5.2"},
          {"model_files",
           {{{"path", "models/environments/kitchen/kitchen.xml"},
             {"role", "environment model (MJCF)"},
             {"of", "kitchen"},
             {"sha256", kitchen_sha}},
            {{"path", "models/robots/minibot/minibot.xml"},
             {"role", "robot model (MJCF)"},
             {"of", "minibot"},
             {"sha256", "1111"}}}}};
}

TEST(ProvenanceDiff, NamesTheChangedModelFileAndBuildFields) {
  const nlohmann::json a = provenance("aaaaaaaaaaaaaaaa", "c1");
  EXPECT_FALSE(diff_provenance(a, a).models_changed());
  EXPECT_EQ(provenance_warning(diff_provenance(a, a)), "");
  EXPECT_TRUE(provenance_diff_table(diff_provenance(a, a)).rows.empty());

  const ProvenanceDiff d = diff_provenance(a, provenance("bbbbbbbbbbbbbbbb", "c2"));
  EXPECT_TRUE(d.models_changed());
  ASSERT_EQ(d.changed_models.size(), 1u);
  EXPECT_EQ(d.changed_models[0].path, "models/environments/kitchen/kitchen.xml");
  const std::string w = provenance_warning(d);
  EXPECT_NE(w.find("WARNING: the runs loaded different model files (1 changed)"), std::string::npos)
      << w;
  EXPECT_NE(w.find("models/environments/kitchen/kitchen.xml (environment model (MJCF) of "
                   "kitchen): sha256 aaaaaaaaaaaa -> bbbbbbbbbbbb"),
            std::string::npos)
      << w;
  const std::string md = markdown_table(provenance_diff_table(d));
  EXPECT_NE(md.find("| build commit |  | c1 | c2 |"), std::string::npos) << md;
  EXPECT_EQ(md.find("minibot.xml"), std::string::npos) << md;  // unchanged: not listed
  const nlohmann::json j = provenance_diff_json(d);
  EXPECT_TRUE(j["models_changed"].get<bool>());
  EXPECT_EQ(j["changed_model_files"][0]["new_sha256"], "bbbbbbbbbbbbbbbb");

  // A run from an older build recorded no model files: nothing can be said, and that counts as
  // a change for --fail-on-model-change.
  nlohmann::json old = a;
  old.erase("model_files");
  const ProvenanceDiff unknown = diff_provenance(old, a);
  EXPECT_TRUE(unknown.models_changed());
  EXPECT_NE(provenance_warning(unknown).find("the base recorded"), std::string::npos)
      << provenance_warning(unknown);

  // A kinematic run against a physics run: the same trial ids, paired all the same; said.
  nlohmann::json kinematic = a, physics = a;
  kinematic["matrix"] = {{"overrides", {{"execution", "kinematic"}}}};
  physics["matrix"] = {{"overrides", {{"execution", nullptr}}}};
  const ProvenanceDiff modes = diff_provenance(physics, kinematic);
  ASSERT_TRUE(modes.execution.has_value());
  EXPECT_NE(provenance_warning(modes).find("WARNING: the runs ran in different execution modes "
                                           "(base: the scenarios' own execution modes, new: "
                                           "--execution kinematic)"),
            std::string::npos)
      << provenance_warning(modes);
  EXPECT_EQ(provenance_diff_json(modes)["execution"]["new"], "--execution kinematic");
  EXPECT_FALSE(diff_provenance(kinematic, kinematic).execution.has_value());
  EXPECT_FALSE(diff_provenance(a, kinematic).execution.has_value()) << "a run that recorded none";
}

}  // namespace
}  // namespace taskmatrix::harness
