// The trial-record schema (harness/results/trial_schema.h) drives what the run's outputs hold: a
// field added to the table reaches summary.json and ompl.log with no change to those writers;
// compare judges its exact work counts; the reports' columns (summary.md, compare's per-group
// tables, the planners' tables, path quality) are the table's marked fields;
// docs/architecture.md shows the same table.
#include "harness/results/trial_schema.h"

#include <algorithm>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "harness/compare/compare.h"
#include "harness/compare/compare_sections.h"
#include "harness/compare/html_report.h"
#include "harness/compare/planner_comparison.h"
#include "harness/results/ompl_log.h"
#include "harness/results/summary.h"

namespace taskmatrix::harness {
namespace {

std::vector<nlohmann::json> trials_with_grip(int n) {
  std::vector<nlohmann::json> trials;
  for (int i = 0; i < n; ++i) {
    trials.push_back({{"trial_id", "t" + std::to_string(i)},
                      {"scenario", "s"},
                      {"program", "reach"},
                      {"robot", "r"},
                      {"environment", "e"},
                      {"planner", "p"},
                      {"seed", i + 1},
                      {"layout_seed", i + 1},
                      {"success", true},
                      {"status", "success"},
                      {"planning_time_s", 0.5},
                      {"grip_force_n", 10.0 + i}});
  }
  return trials;
}

TEST(TrialSchema, AFieldAddedToTheTableReachesTheSummaryAndTheOmplLog) {
  std::vector<TrialField> fields(kTrialFields.begin(), kTrialFields.end());
  fields.push_back({"grip_force_n", "N", FieldSource::kMeasured, false, FieldSummary::kMedian,
                    "grip force", OmplType::kReal, false, "the hands' grip force"});
  const std::vector<nlohmann::json> trials = trials_with_grip(3);

  const nlohmann::json with = make_summary({"run", "", 3, false, 1, 1}, trials, fields);
  EXPECT_EQ(with["overall"]["grip_force_n"]["median"], 11.0) << with["overall"].dump();
  EXPECT_EQ(with["groups"][0]["grip_force_n"]["median"], 11.0);
  const nlohmann::json without = make_summary({"run", "", 3, false, 1, 1}, trials);
  EXPECT_FALSE(without["overall"].contains("grip_force_n"));
  // The table's own summarised fields are there.
  for (const TrialField& f : kTrialFields) {
    EXPECT_EQ(without["overall"].contains(std::string(f.name)), f.summary != FieldSummary::kNone)
        << f.name;
  }
  EXPECT_EQ(without["overall"]["planning_time_s"]["p90"], 0.5);

  OmplLogInfo info;
  info.experiment = "run";
  info.planners.push_back({"p", "RRTConnect", {}});
  const std::string log = ompl_log_text(info, trials, fields);
  size_t properties = 0;
  for (const TrialField& f : fields) properties += f.ompl_type != OmplType::kNone;
  EXPECT_NE(log.find(std::to_string(properties) + " properties for each run\n"), std::string::npos)
      << log;
  EXPECT_NE(log.find("\ngrip force REAL\n"), std::string::npos) << log;
  // Each run's line ends with the new property's value.
  EXPECT_NE(log.find("; 12; \n"), std::string::npos) << log;
  const std::string plain = ompl_log_text(info, trials);
  EXPECT_EQ(plain.find("grip force"), std::string::npos);
  for (const TrialField& f : kTrialFields) {
    if (f.ompl_type == OmplType::kNone) continue;
    EXPECT_NE(plain.find("\n" + std::string(f.ompl_property) + " " + to_string(f.ompl_type) + "\n"),
              std::string::npos)
        << f.name;
  }
}

TEST(TrialSchema, CompareJudgesTheTablesExactWorkCounts) {
  const std::vector<std::string> work = exact_work_fields();
  EXPECT_EQ(work, (std::vector<std::string>{"collision_checks", "plan_calls", "planner_runs",
                                            "ik_calls"}));
  std::vector<nlohmann::json> base = trials_with_grip(2), fresh = base;
  for (nlohmann::json& t : base) {
    for (const std::string& f : work) t[f] = 10;
  }
  for (nlohmann::json& t : fresh) {
    for (const std::string& f : work) t[f] = 10;
  }
  fresh[0]["ik_calls"] = 11;
  CompareThresholds exact;
  exact.exact_work = true;
  const Comparison c = compare_trials(base, fresh, true, exact);
  ASSERT_EQ(c.overall.work.size(), work.size());
  for (size_t i = 0; i < work.size(); ++i) EXPECT_EQ(c.overall.work[i].field, work[i]);
  EXPECT_EQ(c.overall.work[3].changed_trials, 1);
  const std::vector<std::string>& r = c.overall.regressions;
  EXPECT_NE(
      std::find(r.begin(), r.end(), "1 trial changed ik_calls (20 -> 21; exact counts required)"),
      r.end())
      << (r.empty() ? "no regression" : r.front());
}

// The same trials under a second planner, with other measures (more checks, a firmer grip).
std::vector<nlohmann::json> with_second_planner(const std::vector<nlohmann::json>& trials) {
  std::vector<nlohmann::json> out = trials;
  for (nlohmann::json t : trials) {
    t["planner"] = "q";
    t["planning_time_s"] = 0.25;
    t["grip_force_n"] = t["grip_force_n"].get<double>() + 5;
    out.push_back(t);
  }
  return out;
}

// The heading cells of the Markdown table whose heading row starts with `first`.
std::vector<std::string> markdown_headings(const std::string& md, const std::string& first) {
  const size_t at = md.find("| " + first + " |");
  EXPECT_NE(at, std::string::npos) << md;
  if (at == std::string::npos) return {};
  std::vector<std::string> out;
  std::stringstream row(md.substr(at + 1, md.find('\n', at) - at - 1));
  for (std::string cell; std::getline(row, cell, '|');) {
    out.push_back(cell.substr(1, cell.size() - 2));
  }
  return out;
}

// The headings of the reports' tables, after their fixed columns, are the table's fields marked
// for them, in table order: a field marked in kTrialFields shows without a change to a report.
TEST(TrialSchema, TheReportsColumnsAreTheTablesMarkedFields) {
  std::vector<std::string> summary_md, compare_groups, planner_table, path_quality;
  for (const TrialField& f : kTrialFields) {
    const FieldDisplay& d = f.display;
    if (!d.summary_md.empty()) {
      summary_md.push_back(std::string(d.summary_md) +
                           (f.summary == FieldSummary::kMedianP90 ? " (median / p90)" : ""));
    }
    if (d.compare_groups) compare_groups.emplace_back(d.label);
    if (d.planner_table) {
      planner_table.push_back(std::string(d.label) +
                              (d.unit.empty() ? "" : " " + std::string(d.unit)) + " (median)");
    }
    if (d.path_quality != Better::kNone) path_quality.emplace_back(d.label);
  }
  // What the reports show today; a change to the table changes the reports with it.
  EXPECT_EQ(summary_md, (std::vector<std::string>{"planning s (median / p90)", "joint path",
                                                  "EE path m", "duration s"}));
  EXPECT_EQ(compare_groups, (std::vector<std::string>{"collision checks", "plan calls"}));
  EXPECT_EQ(path_quality, (std::vector<std::string>{"joint path", "end-effector path", "duration",
                                                    "smoothness (RMS jerk)", "minimum clearance"}));

  const std::vector<nlohmann::json> trials = with_second_planner(trials_with_grip(3));
  const std::vector<std::string> planners = {"p", "q"};
  const std::vector<Comparison> cs = compare_planners(trials, planners);
  ASSERT_EQ(cs.size(), 1u);

  // summary.md: six columns of the group, the marked fields, the failures.
  std::vector<std::string> expected = {"scenario", "robot",   "environment",
                                       "planner",  "success", "95% CI"};
  expected.insert(expected.end(), summary_md.begin(), summary_md.end());
  expected.push_back("failures");
  const std::string summary = summary_markdown(make_summary({"run", "", 6, false, 1, 1}, trials));
  EXPECT_EQ(markdown_headings(summary, "scenario"), expected);

  // compare.md and report.html per group: eight columns, the marked work counts, the verdict.
  expected = {"scenario",
              "robot",
              "environment",
              "planner",
              "success",
              "McNemar p",
              "planning time ratio (95% CI)",
              "Wilcoxon p"};
  expected.insert(expected.end(), compare_groups.begin(), compare_groups.end());
  expected.push_back("verdict");
  EXPECT_EQ(markdown_headings(comparison_markdown(cs[0]), "scenario"), expected);
  std::string html_row;
  for (const std::string& h : expected) html_row += "<th>" + h + "</th>";
  const std::string html = planners_html("run", trials, planners, cs);
  EXPECT_NE(html.find("<tr>" + html_row + "</tr>"), std::string::npos) << html_row;

  // The planners' tables: the planner's fixed columns, then the marked measures.
  expected = {"planner", "success", "95% CI", "planning s (median)"};
  expected.insert(expected.end(), planner_table.begin(), planner_table.end());
  const std::vector<std::string> md =
      markdown_headings(planner_table_markdown(trials, planners, cs), "planner");
  ASSERT_GE(md.size(), expected.size());
  EXPECT_EQ(std::vector<std::string>(md.begin(), md.begin() + static_cast<long>(expected.size())),
            expected);
  html_row = "<th>planning time per trial s (median / p90)</th>";
  for (const std::string& h : planner_table) html_row += "<th>" + h + "</th>";
  EXPECT_NE(html.find(html_row + "</tr>"), std::string::npos) << html_row;

  // Path quality: the marked measures, in table order.
  std::vector<std::string> measures;
  for (const PathQualityChange& q : cs[0].overall.path_quality) measures.push_back(q.name);
  EXPECT_EQ(measures, path_quality);
}

// A field marked for every report, added to the table, shows in each with its label, unit,
// format and words, and nothing else changes.
TEST(TrialSchema, AFieldMarkedForTheReportsShowsInThem) {
  std::vector<TrialField> fields(kTrialFields.begin(), kTrialFields.end());
  fields.push_back({"grip_force_n",
                    "N",
                    FieldSource::kMeasured,
                    false,
                    FieldSummary::kMedian,
                    "grip force",
                    OmplType::kReal,
                    false,
                    "the hands' grip force",
                    {.label = "grip force",
                     .unit = "N",
                     .format = "%.1f",
                     .summary_md = "grip N",
                     .planner_table = true,
                     .path_quality = Better::kHigher,
                     .better_word = "firmer",
                     .worse_word = "weaker"}});
  const std::vector<nlohmann::json> trials = with_second_planner(trials_with_grip(6));

  // summary.md: the group's median grip force (10..15 for p, 15..20 for q).
  const std::string summary =
      summary_markdown(make_summary({"run", "", 12, false, 1, 1}, trials, fields), fields);
  EXPECT_NE(summary.find(" | duration s | grip N | failures |\n"), std::string::npos) << summary;
  EXPECT_NE(summary.find(" | 12.5 | - |\n"), std::string::npos) << summary;
  EXPECT_NE(summary.find(" | 17.5 | - |\n"), std::string::npos) << summary;
  EXPECT_EQ(summary_markdown(make_summary({"run", "", 12, false, 1, 1}, trials)).find("grip"),
            std::string::npos);

  // The planners' tables.
  const std::vector<std::string> planners = {"p", "q"};
  const std::vector<Comparison> cs = compare_planners(trials, planners);
  ASSERT_EQ(cs.size(), 1u);
  const std::string md = planner_table_markdown(trials, planners, cs, fields);
  EXPECT_NE(md.find(" | joint path (median) | grip force N (median) | McNemar p |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| q | 6/6 | 61%..100% | 0.2500 | - | - | 17.5 | "), std::string::npos) << md;
  EXPECT_EQ(planner_table_markdown(trials, planners, cs).find("grip"), std::string::npos);
  const std::string html = planners_html("run", trials, planners, cs, fields);
  EXPECT_NE(html.find("<th>grip force N (median)</th></tr>"), std::string::npos);
  EXPECT_NE(html.find("<td>17.5</td></tr>"), std::string::npos);

  // Path quality: a firmer grip by 5 N in each of 6 pairs, higher being better.
  std::vector<TrialPair> pairs;
  for (size_t i = 0; i < 6; ++i) pairs.push_back({&trials[i], &trials[i + 6]});
  const std::vector<PathQualityChange> changes = compare_path_quality(pairs, fields);
  ASSERT_FALSE(changes.empty());
  const PathQualityChange& grip = changes.back();
  EXPECT_EQ(grip.field, "grip_force_n");
  EXPECT_EQ(grip.name, "grip force");
  EXPECT_EQ(grip.unit, "N");
  EXPECT_FALSE(grip.lower_is_better);
  EXPECT_EQ(grip.pairs, 6);
  EXPECT_DOUBLE_EQ(grip.mean_change, 5);
  EXPECT_TRUE(grip.better());
  const std::vector<std::string> findings = path_quality_findings(changes);
  ASSERT_EQ(findings.size(), 1u);
  EXPECT_EQ(findings[0].rfind("grip force 40% firmer (mean change +5.00", 0), 0u) << findings[0];
  EXPECT_EQ(compare_path_quality(pairs).size(), changes.size() - 1);
}

TEST(TrialSchema, TheArchitectureDocShowsTheTable) {
  const std::string path = std::string(TASKMATRIX_TEST_ROOT) + "/docs/architecture.md";
  std::ifstream in(path);
  ASSERT_TRUE(in) << path;
  std::stringstream text;
  text << in.rdbuf();
  const std::string doc = text.str();
  const std::string begin = "<!-- trial-fields: begin -->\n", end = "<!-- trial-fields: end -->";
  const size_t b = doc.find(begin), e = doc.find(end);
  ASSERT_NE(b, std::string::npos) << path << " lacks " << begin;
  ASSERT_NE(e, std::string::npos) << path << " lacks " << end;
  EXPECT_EQ(doc.substr(b + begin.size(), e - b - begin.size()), trial_fields_markdown())
      << "docs/architecture.md's trial record table differs from harness/results/trial_schema.h; "
         "replace it with:\n"
      << trial_fields_markdown();
}

}  // namespace
}  // namespace taskmatrix::harness
