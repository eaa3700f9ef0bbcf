// The trial-record schema (harness/results/trial_schema.h) drives what the run's outputs hold: a
// field added to the table reaches summary.json and ompl.log with no change to those writers;
// compare judges its exact work counts; docs/architecture.md shows the same table.
#include "harness/results/trial_schema.h"

#include <algorithm>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "harness/compare/compare.h"
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
