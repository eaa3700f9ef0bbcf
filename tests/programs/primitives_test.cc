// The primitive task programs on both robots in both environments: each succeeds in a fixed
// layout, with the world showing it, and fails with the right reason when it cannot.
#include "taskmatrix/programs/primitives.h"
#include "taskmatrix/programs/program_support.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "taskmatrix/core/executive.h"
#include "taskmatrix/mujoco/ground_truth_perception.h"
#include "taskmatrix/mujoco/head_sensor.h"
#include "taskmatrix/mujoco/mujoco_skillset.h"
#include "tests/test_support.h"

namespace taskmatrix::programs {
namespace {

using core::MessageType;

// Holds chains where they are until halted.
class Hold final : public core::TaskProgram {
 public:
  explicit Hold(std::vector<std::string> chains) : chains_(std::move(chains)) {}
  std::vector<std::string> chains(const core::Skillset&) const override { return chains_; }
  void start(core::ProgramContext&) override {}
  core::ProgramState step(core::ProgramContext&) override { return core::ProgramState::kRunning; }

 private:
  std::vector<std::string> chains_;
};

class PrimitivesTest : public ::testing::TestWithParam<test::RobotEnv> {
 protected:
  void SetUp() override {
    register_primitives(registry_);
    skills_ = std::make_unique<mujoco::MujocoSkillset>(
        test::scene(GetParam().robot, GetParam().environment));
    perception_ = std::make_unique<mujoco::GroundTruthPerception>(*skills_);
    make_executive(1);
  }
  void make_executive(std::uint32_t seed) {
    core::ExecutiveOptions options;
    options.seed = seed;
    options.plan.time_limit_s = 5.0;
    executive_ = std::make_unique<core::Executive>(*skills_, registry_, perception_.get(), options);
  }
  // Runs one program to its end; returns its final message.
  core::Message run(const std::string& program, const core::RawParams& params,
                    double max_time_s = 30.0) {
    const int id = executive_->start(program, params);
    executive_->run(max_time_s);
    EXPECT_FALSE(executive_->running(id)) << program << " still running after " << max_time_s;
    const core::Message* outcome = executive_->outcome(id);
    return outcome ? *outcome : core::Message{};
  }
  std::vector<core::Message> messages_of(const std::string& program) const {
    std::vector<core::Message> out;
    for (const core::Message& m : executive_->log()) {
      if (m.program == program) out.push_back(m);
    }
    return out;
  }
  bool holds(const core::ConditionPtr& c) {
    executive_->perceive();
    return c->holds(core::World{*skills_, executive_->percepts()});
  }

  core::ProgramRegistry registry_;
  std::unique_ptr<mujoco::MujocoSkillset> skills_;
  std::unique_ptr<core::Perception> perception_;
  std::unique_ptr<core::Executive> executive_;
};

TEST_P(PrimitivesTest, ReachGraspReleaseTheCup) {
  ASSERT_FALSE(holds(core::graspable("cup")));
  const core::Message reach = run("reach", {{"object", "cup"}});
  ASSERT_EQ(reach.type, MessageType::kCompleted) << reach.reason;
  EXPECT_TRUE(holds(core::graspable("cup")));
  // The planning messages carry the plan; the last one is the plan executed.
  const std::vector<core::Message> msgs = messages_of("reach");
  const auto ended = std::find_if(msgs.rbegin(), msgs.rend(), [](const core::Message& m) {
    return m.type == MessageType::kPlanningEnded;
  });
  ASSERT_NE(ended, msgs.rend());
  ASSERT_TRUE(ended->plan);
  EXPECT_TRUE(ended->plan->success());
  EXPECT_GT(ended->plan->collision_checks, 0);

  const core::Message grasp = run("grasp", {{"object", "cup"}});
  ASSERT_EQ(grasp.type, MessageType::kCompleted) << grasp.reason;
  EXPECT_TRUE(holds(core::grasping("cup")));
  const std::string hand = skills_->holder_of("cup");
  ASSERT_FALSE(hand.empty());

  const core::Message release = run("release", {{"object", "cup"}});
  ASSERT_EQ(release.type, MessageType::kCompleted) << release.reason;
  EXPECT_TRUE(skills_->holder_of("cup").empty());
  const std::vector<double> rest = skills_->posture("rest").at(hand + "_hand");
  EXPECT_LE(max_difference(skills_->configuration({hand + "_hand"}), rest), 0.05);
}

TEST_P(PrimitivesTest, PosturalAndCannedMotions) {
  const core::Message wave_start = run("postural", {{"posture", "wave_start"}});
  ASSERT_EQ(wave_start.type, MessageType::kCompleted) << wave_start.reason;
  const core::Message wave = run("canned", {{"motion", "wave"}});
  ASSERT_EQ(wave.type, MessageType::kCompleted) << wave.reason;
  const core::Message rest = run("postural", {{"posture", "rest"}});
  ASSERT_EQ(rest.type, MessageType::kCompleted) << rest.reason;
  EXPECT_TRUE(holds(core::postural("rest")));
  const core::Message bow = run("canned", {{"motion", "bow"}});
  ASSERT_EQ(bow.type, MessageType::kCompleted) << bow.reason;
}

TEST_P(PrimitivesTest, FailuresNameTheirReason) {
  auto reason = [&](const std::string& program, const core::RawParams& params) {
    const core::Message m = run(program, params);
    EXPECT_EQ(m.type, MessageType::kFailed) << program;
    return m.reason;
  };
  EXPECT_EQ(reason("reach", {{"object", "teapot"}}),
            "perception_miss: 'teapot' is not in the perceptual model");
  EXPECT_EQ(reason("reach", {{"object", "visitor"}}).rfind("ik_failure: ", 0), 0u);
  EXPECT_EQ(reason("grasp", {{"object", "cup"}, {"side", "left"}}),
            "precondition_false: graspable(cup, left)");
  EXPECT_EQ(reason("release", {{"object", "cup"}}), "precondition_false: grasping(cup)");
  EXPECT_EQ(reason("postural", {{"posture", "cartwheel"}}),
            "invalid_input: robot '" + skills_->profile().name + "' has no posture 'cartwheel'");
  EXPECT_EQ(reason("canned", {{"motion", "moonwalk"}}),
            "invalid_input: robot '" + skills_->profile().name +
                "' has no canned motion 'moonwalk' (it has: bow, wave)");
  EXPECT_FALSE(executive_->any_running());
}

INSTANTIATE_TEST_SUITE_P(
    Pairs, PrimitivesTest,
    ::testing::Values(test::RobotEnv{"tallbot", "kitchen"}, test::RobotEnv{"tallbot", "office"},
                      test::RobotEnv{"minibot", "kitchen"}, test::RobotEnv{"minibot", "office"}),
    [](const ::testing::TestParamInfo<test::RobotEnv>& p) { return test::pair_name(p.param); });

}  // namespace
}  // namespace taskmatrix::programs
