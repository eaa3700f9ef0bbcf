// The common skillset's own logic (argument checks, planning to poses and goal regions over
// the backend's hooks, work counts) on the fake skillset: no simulator. The conditions on it:
// tests/core/conditions_test.cc.
#include <gtest/gtest.h>

#include "taskmatrix/core/perceptual_model.h"
#include "tests/support/fake_skillset.h"
#include "tests/support/skillset_conformance.h"

namespace taskmatrix::test {
namespace {

INSTANTIATE_TEST_SUITE_P(Fake, SkillsetConformance,
                         ::testing::Values(Backend{
                             "fake", [] { return std::make_unique<FakeSkillset>(fake_kitchen()); },
                             "cup"}),
                         backend_name);

}  // namespace
}  // namespace taskmatrix::test

namespace taskmatrix::core {
namespace {

using Chains = std::vector<std::string>;

class FakeSkillsetTest : public ::testing::Test {
 protected:
  void SetUp() override { skills_.perceive(percepts_); }
  // A palm pose at `position`, facing along the base's +x.
  static Pose palm_at(const Eigen::Vector3d& position) {
    Pose p;
    p.position = position;
    return p;
  }
  test::FakeSkillset skills_{test::fake_kitchen()};
  PerceptualModel percepts_;
};

TEST_F(FakeSkillsetTest, PlanningToPosesTriesEachPoseInTurnAndReachesTheFirstItCan) {
  const Chains arm = {"left_arm"};
  const Pose unreachable = palm_at({5, 5, 1});
  const Pose reachable = palm_at({-0.2, 0.6, 1.0});  // behind the shoulder, away from the cup
  IkOptions ik;
  ik.orientation = false;
  const int ik_before = skills_.work().ik_calls;
  PlanOptions options;
  const PlanResult r =
      skills_.plan_to_poses(arm, "left_palm", {unreachable, reachable}, options, ik);
  ASSERT_EQ(r.status, PlanStatus::kExactSolution) << r.message;
  EXPECT_EQ(r.goal_index, 1);
  EXPECT_EQ(r.plan_calls, 1);  // the unreachable pose was not planned to
  EXPECT_EQ(skills_.work().ik_calls, ik_before + 2);
  EXPECT_EQ(skills_.work().plans.back().kind, "poses");
  EXPECT_EQ(skills_.work().plans.back().status, "exact_solution");
  // The path ends where the palm is at the pose reached.
  const Pose reached = skills_.frame_pose_at(arm, r.path.back(), "left_palm");
  EXPECT_LT((reached.position - reachable.position).norm(), ik.position_tolerance_m);

  // Executing it brings the palm there.
  const ExecutionReport done = skills_.execute(arm, skills_.time_parameterize(arm, r.path));
  EXPECT_TRUE(done.success()) << done.message;
  EXPECT_LT((skills_.frame_pose("left_palm").position - reachable.position).norm(), 1e-3);
}

TEST_F(FakeSkillsetTest, PlanningToPosesExplainsEveryIkFailure) {
  IkOptions ik;
  ik.orientation = false;
  const PlanResult r = skills_.plan_to_poses({"left_arm"}, "left_palm",
                                             {palm_at({5, 5, 1}), palm_at({0, 0.2, 3})}, {}, ik);
  EXPECT_EQ(r.status, PlanStatus::kIkFailure);
  EXPECT_EQ(r.message.rfind("no target pose has an IK solution: 2 poses tried (2 unreachable, 0 "
                            "with every solution in collision); the closest, pose ",
                            0),
            0u)
      << r.message;
  EXPECT_NE(r.detail.find("pose 0: unreachable"), std::string::npos) << r.detail;
  EXPECT_NE(r.detail.find("pose 1: unreachable"), std::string::npos) << r.detail;
}

TEST_F(FakeSkillsetTest, AGoalRegionKeepsOnlyValidDrawsAndThoseCountAsThePlansWork) {
  const Chains arm = {"left_arm"};
  const std::vector<double> q = skills_.configuration(arm);
  // Every other draw puts the arm through the cup.
  std::vector<double> into_cup;
  IkOptions ik;
  ik.orientation = false;
  ik.collision_free = false;
  const IkResult at_cup =
      skills_.solve_ik(arm, "left_palm", palm_at(percepts_.find("cup")->box.center()), ik);
  ASSERT_EQ(at_cup.status, IkStatus::kSolved) << at_cup.reason;
  EXPECT_FALSE(skills_.is_valid(arm, at_cup.solutions.front()));
  std::vector<double> free_goal = q;
  free_goal[0] -= 0.3;
  int draws = 0;
  GoalRegion region;
  region.max_draws = 4;
  region.sample = [&](std::mt19937_64&) {
    return std::optional<std::vector<double>>(draws++ % 2 ? free_goal : at_cup.solutions.front());
  };
  const std::uint64_t checks = skills_.work().collision_checks;
  const PlanResult r = skills_.plan_to_region(arm, region, {});
  ASSERT_EQ(r.status, PlanStatus::kExactSolution) << r.message;
  EXPECT_EQ(draws, 4);
  EXPECT_EQ(r.path.back(), free_goal);
  // Checking the draws is part of planning, not is_valid calls of a program: only the
  // planner's own checks are added.
  EXPECT_EQ(skills_.work().collision_checks, checks + r.collision_checks);
}

}  // namespace
}  // namespace taskmatrix::core
