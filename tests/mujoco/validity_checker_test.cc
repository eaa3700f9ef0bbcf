#include "taskmatrix/mujoco/validity_checker.h"

#include <gtest/gtest.h>

#include <random>

#include "tests/test_support.h"

namespace taskmatrix::mujoco {
namespace {

// All robot joints of the named chains, with the base limited to +-0.4 m and +-0.6 rad
// around the start (further and the robot walks through furniture, which teaches nothing).
struct Sampler {
  std::vector<int> joints;
  std::vector<double> lower, upper;
  Sampler(const Scene& scene, const std::vector<std::string>& chains) {
    for (const std::string& name : chains) {
      const ChainIndex& c = scene.chain(name);
      for (size_t i = 0; i < c.joints.size(); ++i) {
        joints.push_back(c.joints[i]);
        double lo = c.lower[i], hi = c.upper[i];
        if (name == "base") {
          const double centre = scene.start_qpos()[c.qpos_adr[i]];
          const double half = i < 2 ? 0.4 : 0.6;
          lo = std::max(lo, centre - half);
          hi = std::min(hi, centre + half);
        }
        lower.push_back(lo);
        upper.push_back(hi);
      }
    }
  }
  std::vector<double> draw(std::mt19937_64& rng) const {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<double> q(joints.size());
    for (size_t i = 0; i < q.size(); ++i) q[i] = lower[i] + (upper[i] - lower[i]) * u(rng);
    return q;
  }
};

void expect_identical_verdicts(const std::string& robot, const std::string& env, int obstacles,
                               int samples, const std::vector<std::string>& chains) {
  auto scene = test::scene(robot, env);
  WorkerScene fast(scene), raw(scene);
  const core::ObstacleLayout layout = core::generate_layout(scene->layout_request(obstacles), 5);
  fast.apply_layout(layout);
  raw.apply_layout(layout);
  fast.reset_to_start();
  raw.reset_to_start();
  const Sampler sampler(*scene, chains);
  ValidityChecker checker(*scene, fast.model(), fast.data(), sampler.joints);
  ASSERT_FALSE(checker.static_collision());
  std::mt19937_64 rng(1234);
  int collisions = 0;
  for (int s = 0; s < samples; ++s) {
    const std::vector<double> q = sampler.draw(rng);
    for (size_t i = 0; i < q.size(); ++i)
      raw.data()->qpos[raw.model()->jnt_qposadr[sampler.joints[i]]] = q[i];
    const bool expected = raw_robot_in_collision(*scene, raw.model(), raw.data());
    ASSERT_EQ(checker.in_collision(q.data()), expected)
        << robot << " in " << env << ", sample " << s;
    collisions += expected;
  }
  // Both verdicts occur often enough for the comparison to mean something.
  EXPECT_GT(collisions, samples / 20);
  EXPECT_LT(collisions, samples - samples / 20);
}

TEST(ValidityChecker, SameVerdictsAsRawMuJoCoOn100kConfigurationsOfTheTallRobot) {
  expect_identical_verdicts(
      "tallbot", "kitchen", 20, 100000,
      {"base", "torso", "head", "left_arm", "right_arm", "left_hand", "right_hand"});
}

TEST(ValidityChecker, SameVerdictsOnTheCompactRobotsAndTheOffice) {
  for (const char* robot : {"minibot", "minibot_urdf", "tallbot"}) {
    expect_identical_verdicts(robot, "office", 20, 10000,
                              {"torso", "left_arm", "right_arm", "left_hand"});
  }
}

// A checker visits its pairs one by one at its first check and skips a far body's geoms in
// one test from its second (validity_checker.h): both must give the same verdicts, with and
// without a planning margin, here against a fresh checker's first check of each state.
TEST(ValidityChecker, AFarBodysGeomsSkippedTogetherGiveTheSameVerdicts) {
  for (const char* robot : {"tallbot", "minibot"}) {
    auto scene = test::scene(robot, "kitchen");
    WorkerScene worker(scene);
    worker.apply_layout(core::generate_layout(scene->layout_request(20), 7));
    worker.reset_to_start();
    const Sampler sampler(*scene, {"base", "torso", "left_arm", "right_arm"});
    ValidityChecker warm(*scene, worker.model(), worker.data(), sampler.joints);
    std::mt19937_64 rng(99);
    int hits[4] = {0, 0, 0, 0};
    const double margins[4] = {0.0, 0.005, 0.02, 0.1};
    for (int s = 0; s < 1500; ++s) {
      const std::vector<double> q = sampler.draw(rng);
      for (int k = 0; k < 4; ++k) {
        ValidityChecker fresh(*scene, worker.model(), worker.data(), sampler.joints);
        const bool expected = fresh.within_margin(q.data(), margins[k]);
        ASSERT_EQ(warm.within_margin(q.data(), margins[k]), expected)
            << robot << ", sample " << s << ", margin " << margins[k];
        hits[k] += expected;
      }
      ValidityChecker fresh(*scene, worker.model(), worker.data(), sampler.joints);
      ASSERT_EQ(warm.in_collision(q.data()), fresh.in_collision(q.data()))
          << robot << ", sample " << s;
    }
    // The margins change verdicts: states near something are among the samples.
    EXPECT_GT(hits[3], hits[0] + 30) << robot;
    EXPECT_LT(hits[0], 1500 - 100) << robot;
  }
}

TEST(ValidityChecker, ArmOnlyChecksSkipPairsThatCannotChange) {
  auto scene = test::scene("tallbot", "kitchen");
  WorkerScene worker(scene);
  const ChainIndex& arm = scene->chain("left_arm");
  ValidityChecker arm_checker(*scene, worker.model(), worker.data(), arm.joints);
  std::vector<int> all;
  for (const ChainIndex& c : scene->chains())
    all.insert(all.end(), c.joints.begin(), c.joints.end());
  ValidityChecker all_checker(*scene, worker.model(), worker.data(), all);
  std::vector<double> q(arm.joints.size()), q_all(all.size());
  for (size_t i = 0; i < q.size(); ++i) q[i] = worker.data()->qpos[arm.qpos_adr[i]];
  for (size_t i = 0; i < all.size(); ++i)
    q_all[i] = worker.data()->qpos[worker.model()->jnt_qposadr[all[i]]];
  EXPECT_FALSE(arm_checker.in_collision(q.data()));
  EXPECT_FALSE(all_checker.in_collision(q_all.data()));
  EXPECT_EQ(arm_checker.checks(), 1u);
  // One arm moves far fewer geoms than the whole robot: most pairs are settled once.
  EXPECT_GT(arm_checker.changing_pair_count(), 0u);
  EXPECT_LT(arm_checker.changing_pair_count() * 3, all_checker.changing_pair_count());
}

TEST(ValidityChecker, AStartInCollisionIsReportedAsStaticCollision) {
  auto scene = test::scene("minibot", "kitchen");
  WorkerScene worker(scene);
  // Walk the robot into the table: base x forward by 0.35 m.
  const ChainIndex& base = scene->chain("base");
  worker.data()->qpos[base.qpos_adr[0]] = 0.35;
  ValidityChecker arm_checker(*scene, worker.model(), worker.data(),
                              scene->chain("left_arm").joints);
  EXPECT_TRUE(arm_checker.static_collision());
  EXPECT_TRUE(raw_robot_in_collision(*scene, worker.model(), worker.data()));
}

}  // namespace
}  // namespace taskmatrix::mujoco
