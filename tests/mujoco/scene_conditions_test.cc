// Conditions on the built-in scenes with ground-truth perception, for each robot: what the
// models themselves must give (the cup standing on the work surface, in the head camera's view
// at rest). The conditions' logic is tested on the fake skillset in tests/core/conditions_test.cc.
#include <cmath>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

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

// A table turned about the vertical in its room: ground truth gives its top as the table's own
// rectangle, turned with it, and the cup standing on it is above it.
TEST(GroundTruthOfATurnedTable, ItsTopIsItsOwnRectangleTurnedWithIt) {
  test::ScratchRoot root;
  test::add_turned_kitchen(root);
  mujoco::MujocoSkillset skills(
      mujoco::Scene::load(root.path() / "models" / "robots" / "atlas",
                          root.path() / "models" / "environments" / "kitchen_turned"));
  PerceptualModel percepts;
  mujoco::GroundTruthPerception(skills).update(0, percepts);
  const PerceivedObject* table = percepts.find("work_surface");
  ASSERT_NE(table, nullptr);
  EXPECT_LT((table->top.min() - Eigen::Vector2d(-0.35, -0.6)).norm(), 1e-9);
  EXPECT_LT((table->top.max() - Eigen::Vector2d(0.35, 0.6)).norm(), 1e-9);
  const SurfaceTop top = surface_top(*table);
  ASSERT_TRUE(top.turned());
  EXPECT_NEAR(std::atan2(top.sin, top.cos), 0.35, 1e-9);
  EXPECT_NEAR(top.height, 0.65, 1e-9);
  // The table's corner on its edge; the corner of its world-aligned box 10 cm and more off it.
  const Eigen::Vector2d corner =
      Eigen::Vector2d(0.75, 0) + Eigen::Rotation2Dd(0.35) * Eigen::Vector2d(0.35, 0.6);
  EXPECT_NEAR(top.signed_distance(corner), 0, 1e-9);
  EXPECT_GT(top.signed_distance(table->box.max().head<2>()), 0.1);
  EXPECT_TRUE(above("cup", "work_surface")->holds(World{skills, percepts}));
}

INSTANTIATE_TEST_SUITE_P(RobotsAndEnvironments, ConditionsTest,
                         ::testing::Values(test::RobotEnv{"tallbot", "kitchen"},
                                           test::RobotEnv{"minibot", "office"}),
                         [](const auto& p) { return test::pair_name(p.param); });

}  // namespace
}  // namespace taskmatrix::core
