// Failure codes: one name each, read back to the same code, and the texts users read.
#include "taskmatrix/core/failure.h"

#include <set>
#include <string>

#include <gtest/gtest.h>

namespace taskmatrix::core {
namespace {

TEST(Failure, EveryCodeHasOneNameThatReadsBackToIt) {
  std::set<std::string> names;
  for (FailureCode code : all_failure_codes()) {
    const std::string name = to_string(code);
    EXPECT_TRUE(names.insert(name).second) << name << " names two codes";
    EXPECT_EQ(failure_code_from_string(name), code) << name;
    // Names are one token of lower-case words, as trial records and ompl.log need them.
    EXPECT_EQ(name.find_first_not_of("abcdefghijklmnopqrstuvwxyz_"), std::string::npos) << name;
  }
  EXPECT_GE(names.size(), 25u);
  EXPECT_EQ(failure_code_from_string("success"), std::nullopt);
  EXPECT_EQ(failure_code_from_string("ik_failure: no pose"), std::nullopt);
  EXPECT_EQ(failure_code_from_string(""), std::nullopt);
  EXPECT_EQ(failure_code_from_string("IK_FAILURE"), std::nullopt);
}

TEST(Failure, TheTrialStatusesKeepTheirPlaceInThePlannerArenaEnum) {
  // ompl.log's trial_status enum lists the codes in this order after "success": a database
  // that keeps the first log's enum reads later logs' statuses at the same indices.
  const std::vector<std::string> first = {"crash",
                                          "timeout",
                                          "sim_unstable",
                                          "setup_failed",
                                          "time_limit",
                                          "criterion_false",
                                          "planning_timeout",
                                          "ik_failure",
                                          "collision",
                                          "grasp_failed",
                                          "invalid_start",
                                          "invalid_goal",
                                          "invalid_input",
                                          "precondition_false",
                                          "invariant_false",
                                          "no_transition",
                                          "perception_miss",
                                          "not_graspable",
                                          "coverage_short",
                                          "chains_busy",
                                          "approximate_solution"};
  for (size_t i = 0; i < first.size(); ++i) {
    EXPECT_EQ(to_string(all_failure_codes().at(i)), first[i]) << i;
  }
}

TEST(Failure, PlanAndExecutionStatusesReadAsTheFailureTheyCause) {
  for (PlanStatus s :
       {PlanStatus::kApproximateSolution, PlanStatus::kTimeout, PlanStatus::kPlanningFailed,
        PlanStatus::kInvalidStart, PlanStatus::kInvalidGoal, PlanStatus::kIkFailure,
        PlanStatus::kInvalidInput}) {
    EXPECT_STREQ(to_string(s), to_string(failure_code(s)));
  }
  EXPECT_EQ(failure_code(PlanStatus::kTimeout), FailureCode::kPlanningTimeout);
  EXPECT_EQ(failure_code(PlanStatus::kPlanningFailed), FailureCode::kPlanningFailed);
  EXPECT_STREQ(to_string(PlanStatus::kExactSolution), "exact_solution");
  EXPECT_EQ(failure_code(ExecutionStatus::kCollision), FailureCode::kCollision);
  EXPECT_EQ(failure_code(ExecutionStatus::kTrackingError), FailureCode::kTrackingError);
  EXPECT_EQ(failure_code(ExecutionStatus::kSimulationUnstable), FailureCode::kSimUnstable);
  EXPECT_STREQ(to_string(failure_code(ExecutionStatus::kSimulationUnstable)),
               to_string(ExecutionStatus::kSimulationUnstable));
}

TEST(Failure, TextsNameThePathThenTheCodeThenTheDetail) {
  const Failure own(FailureCode::kIkFailure, "palm reaches none of 3 targets");
  EXPECT_EQ(own.reason(), "ik_failure: palm reaches none of 3 targets");
  EXPECT_EQ(own.text(), own.reason());
  // Reported by the program that ran it: a failure of its own has no path to extend.
  EXPECT_EQ(reported_by("reach", own).text(), "ik_failure: palm reaches none of 3 targets");
  const Failure nested(FailureCode::kNotGraspable, "the left palm ...", "pickup(approach) > reach");
  const Failure reported = reported_by("fetch", nested);
  EXPECT_EQ(reported.path, "fetch > pickup(approach) > reach");
  EXPECT_EQ(reported.code, FailureCode::kNotGraspable);
  EXPECT_EQ(reported.text(), "fetch > pickup(approach) > reach: not_graspable: the left palm ...");
}

}  // namespace
}  // namespace taskmatrix::core
