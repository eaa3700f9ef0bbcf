#include "taskmatrix/mujoco/scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "tests/test_support.h"

namespace taskmatrix::mujoco {
namespace {

using test::RobotEnv;

TEST(ModelCatalog, HasTwoHumanoidsAndTwoEnvironments) {
  const auto robots = test::catalog().robots();
  const auto envs = test::catalog().environments();
  EXPECT_GE(robots.size(), 2u);
  EXPECT_GE(envs.size(), 2u);
  for (const char* name : {"tallbot", "minibot", "minibot_urdf"}) {
    EXPECT_NE(std::find(robots.begin(), robots.end(), name), robots.end()) << name;
  }
  for (const char* name : {"kitchen", "office"}) {
    EXPECT_NE(std::find(envs.begin(), envs.end(), name), envs.end()) << name;
  }
}

class EveryRobotInEveryEnvironment : public ::testing::TestWithParam<RobotEnv> {};

TEST_P(EveryRobotInEveryEnvironment, LoadsAndTouchesNothingAtRest) {
  auto scene = test::scene(GetParam().robot, GetParam().environment);
  WorkerScene worker(scene);
  const auto contacts = worker.robot_contacts();
  for (const RobotContact& c : contacts) {
    ADD_FAILURE() << c.body1 << "/" << c.geom1 << " touches " << c.body2 << "/" << c.geom2
                  << " at distance " << c.distance;
  }
  // Standing where the environment says, upright: the head camera is above the floor and the
  // robot's top is near its declared height.
  const mjModel* m = worker.model();
  const mjData* d = worker.data();
  double top = 0;
  for (int g = 0; g < m->ngeom; ++g) {
    if (scene->is_robot_geom(g)) top = std::max(top, d->geom_xpos[3 * g + 2] + m->geom_rbound[g]);
  }
  EXPECT_NEAR(top, scene->robot().height_m, 0.08) << "top of the robot's bounding spheres";
  EXPECT_GT(d->cam_xpos[3 * scene->head_camera() + 2], 0.6 * scene->robot().height_m);
}

TEST_P(EveryRobotInEveryEnvironment, NamedPosturesOtherThanFistAreCollisionFree) {
  auto scene = test::scene(GetParam().robot, GetParam().environment);
  WorkerScene worker(scene);
  for (const auto& [name, posture] : scene->robot().postures) {
    if (name == "fist") continue;  // fingers closing on nothing may touch each other
    std::vector<double> q = scene->start_qpos();
    scene->apply_posture(name, q.data());
    std::copy(q.begin(), q.end(), worker.data()->qpos);
    mj_forward(worker.model(), worker.data());
    for (const RobotContact& c : worker.robot_contacts()) {
      ADD_FAILURE() << "posture " << name << ": " << c.body1 << " touches " << c.body2;
    }
  }
}

TEST_P(EveryRobotInEveryEnvironment, ProfileMatchesTheModel) {
  auto scene = test::scene(GetParam().robot, GetParam().environment);
  const mjModel* m = scene->model();
  std::set<int> seen;
  int robot_joints = 0;
  for (int j = 0; j < m->njnt; ++j) robot_joints += scene->is_robot_body(m->jnt_bodyid[j]);
  for (const ChainIndex& c : scene->chains()) {
    for (size_t i = 0; i < c.joints.size(); ++i) {
      EXPECT_TRUE(seen.insert(c.joints[i]).second) << "joint in two chains: " << c.name;
      EXPECT_TRUE(std::isfinite(c.lower[i]) && std::isfinite(c.upper[i]));
      EXPECT_LT(c.lower[i], c.upper[i]);
      EXPECT_TRUE(scene->is_robot_body(m->jnt_bodyid[c.joints[i]]));
    }
  }
  EXPECT_EQ(static_cast<int>(seen.size()), robot_joints)
      << "every robot joint is in exactly one chain";
  // Arms as the issue asks: tall 7 DOF, compact 5 or 6; fingers with two segments each.
  const size_t arm_dof = scene->chain("left_arm").joints.size();
  EXPECT_EQ(arm_dof, scene->chain("right_arm").joints.size());
  if (scene->robot().height_m > 1.5) {
    EXPECT_EQ(arm_dof, 7u);
  } else {
    EXPECT_TRUE(arm_dof == 5u || arm_dof == 6u);
  }
  for (const core::HandSpec& hand : scene->robot().hands) {
    for (const core::FingerSpec& f : hand.fingers) EXPECT_EQ(f.joints.size(), 2u);
  }
  // Environment objects the twelve programs need.
  const auto& objects = scene->environment().objects;
  for (const char* name : {"cup", "box", "vacuum", "debris"}) {
    EXPECT_TRUE(objects.count(name)) << name;
  }
  EXPECT_FALSE(scene->environment().visitor.body.empty());
  EXPECT_GE(scene->environment().visitor.path.size(), 2u);
}

INSTANTIATE_TEST_SUITE_P(Models, EveryRobotInEveryEnvironment,
                         ::testing::ValuesIn(test::all_robot_environment_pairs()),
                         [](const auto& p) { return test::pair_name(p.param); });

TEST(Robots, TheTwoHumanoidsDifferAsInThePaper) {
  auto tall = test::scene("tallbot", "kitchen");
  auto compact = test::scene("minibot", "kitchen");
  EXPECT_GE(tall->robot().height_m, 1.6);
  EXPECT_LE(tall->robot().height_m, 1.8);
  EXPECT_GE(compact->robot().height_m, 1.0);
  EXPECT_LE(compact->robot().height_m, 1.2);
  EXPECT_EQ(tall->robot().find_hand("left")->fingers.size(), 3u);
  EXPECT_EQ(compact->robot().find_hand("left")->fingers.size(), 2u);
  EXPECT_EQ(tall->chain("head").joints.size(), 2u);
  EXPECT_GE(compact->chain("head").joints.size(), 1u);
  // Different names: no joint name is shared.
  for (const ChainIndex& c : tall->chains()) {
    for (int j : c.joints) {
      EXPECT_LT(
          mj_name2id(compact->model(), mjOBJ_JOINT, mj_id2name(tall->model(), mjOBJ_JOINT, j)), 0);
    }
  }
}

TEST(Robots, EveryJointHasAPositionActuatorWithItsRange) {
  for (const std::string& robot : test::catalog().robots()) {
    auto scene = test::scene(robot, "kitchen");
    const mjModel* m = scene->model();
    for (const ChainIndex& c : scene->chains()) {
      for (size_t i = 0; i < c.joints.size(); ++i) {
        int found = 0;
        for (int a = 0; a < m->nu; ++a) {
          if (m->actuator_trnid[2 * a] != c.joints[i] || m->actuator_trntype[a] != mjTRN_JOINT)
            continue;
          ++found;
          EXPECT_EQ(m->actuator_biastype[a], mjBIAS_AFFINE) << robot << " position servo";
          EXPECT_GT(m->actuator_gainprm[a * mjNGAIN], 0) << robot;
          EXPECT_NEAR(m->actuator_ctrlrange[2 * a], c.lower[i], 1e-6) << robot;
          EXPECT_NEAR(m->actuator_ctrlrange[2 * a + 1], c.upper[i], 1e-6) << robot;
        }
        EXPECT_EQ(found, 1) << robot << " joint " << mj_id2name(m, mjOBJ_JOINT, c.joints[i]);
      }
    }
  }
}

}  // namespace
}  // namespace taskmatrix::mujoco
