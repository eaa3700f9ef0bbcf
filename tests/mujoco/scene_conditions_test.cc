// Conditions on the built-in scenes with ground-truth perception, for each robot: what the
// models themselves must give (the cup standing on the work surface, in the head camera's view
// at rest). The conditions' logic is tested on the fake skillset in tests/core/conditions_test.cc.
#include <gtest/gtest.h>

#include "taskmatrix/core/conditions.h"
#include "taskmatrix/mujoco/ground_truth_perception.h"
#include "taskmatrix/mujoco/mujoco_skillset.h"
#include "tests/test_support.h"

namespace taskmatrix::core {
namespace {

class ConditionsTest : public ::testing::TestWithParam<test::RobotEnv> {
 protected:
  void SetUp() override {
    skills_ = std::make_unique<mujoco::MujocoSkillset>(
        test::scene(GetParam().robot, GetParam().environment));
    mujoco::GroundTruthPerception(*skills_).update(0, percepts_);
  }
  World world() { return World{*skills_, percepts_}; }
  std::unique_ptr<mujoco::MujocoSkillset> skills_;
  PerceptualModel percepts_;
};

TEST_P(ConditionsTest, TheCupStandsOnTheWorkSurfaceInViewAtTheStart) {
  ASSERT_TRUE(percepts_.knows("cup"));
  ASSERT_TRUE(percepts_.knows("work_surface"));
  const Eigen::AlignedBox3d cup = percepts_.find("cup")->box;
  const Eigen::AlignedBox3d top = percepts_.find("work_surface")->box;
  EXPECT_TRUE(above("cup", "work_surface")->holds(world()))
      << "cup " << cup.min().transpose() << " .. " << cup.max().transpose() << ", surface "
      << top.min().transpose() << " .. " << top.max().transpose();
  EXPECT_TRUE(near("cup", "work_surface")->holds(world()));
  EXPECT_FALSE(above("work_surface", "cup")->holds(world()));
  // At rest the head looks at the work surface.
  EXPECT_TRUE(parse_condition("in_view(cup)")->holds(world()));
}

INSTANTIATE_TEST_SUITE_P(RobotsAndEnvironments, ConditionsTest,
                         ::testing::Values(test::RobotEnv{"tallbot", "kitchen"},
                                           test::RobotEnv{"minibot", "office"}),
                         [](const auto& p) { return test::pair_name(p.param); });

}  // namespace
}  // namespace taskmatrix::core
