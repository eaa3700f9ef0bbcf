// The primitive task programs on both robots in both environments: each succeeds in a fixed
// layout, with the world showing it, and fails with the right reason when it cannot.
#include "taskmatrix/programs/primitives.h"
#include "taskmatrix/programs/program_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <random>
#include <set>

#include "taskmatrix/core/executive.h"
#include "taskmatrix/io/png.h"
#include "taskmatrix/mujoco/ground_truth_perception.h"
#include "taskmatrix/mujoco/head_sensor.h"
#include "taskmatrix/mujoco/mujoco_skillset.h"
#include "taskmatrix/mujoco/offscreen_renderer.h"
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
    register_programs(registry_);
    skills_ = std::make_unique<mujoco::MujocoSkillset>(
        test::scene(GetParam().robot, GetParam().environment));
    // A fixed layout: eight obstacles of layout seed 3 (on the floor and the work surface).
    skills_->apply_layout(skills_->scene().make_layout(8, 3));
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
  // With TASKMATRIX_RENDER_DIR set, writes the scene now to DIR/<test>_<pair>_<label>.png, for
  // looking at what the programs did.
  void snapshot(const std::string& label) {
    const char* dir = std::getenv("TASKMATRIX_RENDER_DIR");
    if (!dir) return;
    mujoco::OffscreenRenderer renderer(skills_->model(), 640, 480);
    mujoco::CameraView view;
    view.lookat[0] = 0.35;
    view.lookat[2] = 0.85;
    view.distance = 1.7;
    view.azimuth = 145;
    view.elevation = -28;
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = std::string(info->name());
    std::replace(name.begin(), name.end(), '/', '_');
    io::write_png(
        std::string(dir) + "/" + name + "_" + label + ".png",
        renderer.render_rgb(skills_->model(), const_cast<mjData*>(skills_->sim_data()), view));
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
  ASSERT_EQ(reach.type, MessageType::kCompleted) << reach.reason();
  EXPECT_TRUE(holds(core::graspable("cup")));
  snapshot("reached");
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
  ASSERT_EQ(grasp.type, MessageType::kCompleted) << grasp.reason();
  EXPECT_TRUE(holds(core::grasping("cup")));
  snapshot("grasped");
  const std::string hand = skills_->holder_of("cup");
  ASSERT_FALSE(hand.empty());

  const core::Message release = run("release", {{"object", "cup"}});
  ASSERT_EQ(release.type, MessageType::kCompleted) << release.reason();
  EXPECT_TRUE(skills_->holder_of("cup").empty());
  const std::vector<double> rest = skills_->posture("rest").at(hand + "_hand");
  EXPECT_LE(max_difference(skills_->configuration({hand + "_hand"}), rest), 0.05);
}

TEST_P(PrimitivesTest, PosturalAndCannedMotions) {
  const core::Message wave_start = run("postural", {{"posture", "wave_start"}});
  ASSERT_EQ(wave_start.type, MessageType::kCompleted) << wave_start.reason();
  snapshot("wave_start");
  const core::Message wave = run("canned", {{"motion", "wave"}});
  ASSERT_EQ(wave.type, MessageType::kCompleted) << wave.reason();
  const core::Message rest = run("postural", {{"posture", "rest"}});
  ASSERT_EQ(rest.type, MessageType::kCompleted) << rest.reason();
  EXPECT_TRUE(holds(core::postural("rest")));
  const core::Message bow = run("canned", {{"motion", "bow"}});
  ASSERT_EQ(bow.type, MessageType::kCompleted) << bow.reason();
}

TEST_P(PrimitivesTest, FailuresNameTheirReason) {
  auto reason = [&](const std::string& program, const core::RawParams& params) {
    const core::Message m = run(program, params);
    EXPECT_EQ(m.type, MessageType::kFailed) << program;
    return m.reason();
  };
  EXPECT_EQ(reason("reach", {{"object", "teapot"}}),
            "perception_miss: 'teapot' is not in the perceptual model");
  // A person is no grasp for a hand: wider than its fingers span.
  const std::string visitor = reason("reach", {{"object", "visitor"}});
  EXPECT_EQ(visitor.rfind("not_graspable: ", 0), 0u) << visitor;
  EXPECT_NE(visitor.find("aperture"), std::string::npos) << visitor;
  // A false precondition says what was measured.
  const std::string not_graspable = reason("grasp", {{"object", "cup"}, {"side", "left"}});
  EXPECT_EQ(
      not_graspable.rfind("precondition_false: graspable(cup, left): the nearest palm is ", 0), 0u)
      << not_graspable;
  EXPECT_NE(not_graspable.find(" from cup's grasp point (at most 3.0 cm)"), std::string::npos)
      << not_graspable;
  EXPECT_EQ(reason("release", {{"object", "cup"}}),
            "precondition_false: grasping(cup): no hand holds cup");
  EXPECT_EQ(reason("postural", {{"posture", "cartwheel"}}),
            "invalid_input: robot '" + skills_->profile().name + "' has no posture 'cartwheel'");
  EXPECT_EQ(reason("canned", {{"motion", "moonwalk"}}),
            "invalid_input: robot '" + skills_->profile().name +
                "' has no canned motion 'moonwalk' (it has: bow, wave)");
  EXPECT_FALSE(executive_->any_running());
}

TEST_P(PrimitivesTest, FixateFromAHeadAHairPastItsLimitsRunsAndHalts) {
  // Every head joint settled 0.1 mrad past its upper limit, as on a soft limit.
  const mjModel* m = skills_->model();
  mjData* d = const_cast<mjData*>(skills_->sim_data());
  const core::ChainInfo& head = skills_->chain("head");
  auto push_past_limits = [&] {
    for (size_t i = 0; i < head.joints.size(); ++i) {
      const int j = mj_name2id(m, mjOBJ_JOINT, head.joints[i].c_str());
      d->qpos[m->jnt_qposadr[j]] = head.upper[i] + 1e-4;
      d->qvel[m->jnt_dofadr[j]] = 0;
    }
    mj_forward(m, d);
  };
  push_past_limits();
  const core::Message timed = run("fixate", {{"object", "cup"}, {"duration", "2"}});
  EXPECT_EQ(timed.type, MessageType::kCompleted) << timed.reason();
  // Halted while the head sits past its limits: it holds at them, nothing fails.
  const int id = executive_->start("fixate", {{"object", "cup"}});
  for (int k = 0; k < 3; ++k) executive_->tick();
  push_past_limits();
  executive_->halt(id);
  ASSERT_NE(executive_->outcome(id), nullptr);
  EXPECT_EQ(executive_->outcome(id)->type, MessageType::kHalted)
      << executive_->outcome(id)->reason();
}

TEST_P(PrimitivesTest, APostureOrMotionInsideAnObstacleIsAnInvalidGoal) {
  // A box where wave_start puts the hand.
  const ChainValues goal = posture_values(*skills_, "wave_start", {});
  const std::string arm =
      *std::find_if(goal.chains.begin(), goal.chains.end(),
                    [](const std::string& c) { return c.find("_arm") != std::string::npos; });
  const std::string side = arm.substr(0, arm.find('_'));
  size_t offset = 0;
  for (const std::string& c : goal.chains) {
    if (c == arm) break;
    offset += skills_->chain(c).joints.size();
  }
  const std::vector<double> arm_goal(goal.values.begin() + static_cast<long>(offset),
                                     goal.values.begin() + static_cast<long>(offset) +
                                         static_cast<long>(skills_->chain(arm).joints.size()));
  core::ObstacleLayout layout;
  core::PlacedObstacle o;
  o.position =
      skills_->frame_pose_at({arm}, arm_goal, skills_->profile().find_hand(side)->palm).position;
  o.size = Eigen::Vector3d::Constant(0.05);
  layout.obstacles.push_back(o);
  skills_->apply_layout(layout);
  make_executive(1);
  const core::Message postural = run("postural", {{"posture", "wave_start"}, {"side", "as_named"}});
  EXPECT_EQ(postural.reason().rfind("invalid_goal: ", 0), 0u) << postural.reason();
  const core::Message canned = run("canned", {{"motion", "wave"}, {"side", "as_named"}});
  EXPECT_EQ(canned.reason().rfind("invalid_goal: ", 0), 0u) << canned.reason();
  // The other arm is free to take the mirrored posture.
  const core::Message mirrored_ok =
      run("postural", {{"posture", "wave_start"}, {"side", side == "left" ? "right" : "left"}});
  EXPECT_EQ(mirrored_ok.type, MessageType::kCompleted) << mirrored_ok.reason();
  // With `side: any` and both arms free, the arm whose posture touches nothing is taken,
  // whatever the seed (before: one at random, and half the seeds failed invalid_goal).
  const std::string other = core::mirror_chain(arm);
  for (std::uint32_t seed = 1; seed <= 6; ++seed) {
    skills_->reset();
    skills_->apply_layout(layout);
    make_executive(seed);
    const int p = executive_->start("postural", {{"posture", "wave_start"}});
    EXPECT_EQ(executive_->holder_of_chain(other), p) << "seed " << seed;
    executive_->run(20.0);
    ASSERT_TRUE(executive_->outcome(p));
    EXPECT_EQ(executive_->outcome(p)->type, MessageType::kCompleted)
        << "seed " << seed << ": " << executive_->outcome(p)->reason();
  }
}

TEST_P(PrimitivesTest, ReachExitsEarlyWhenTheObjectIsAlreadyGraspable) {
  ASSERT_EQ(run("reach", {{"object", "box"}}).type, MessageType::kCompleted);
  const size_t before = messages_of("reach").size();
  const core::Message again = run("reach", {{"object", "box"}});
  EXPECT_EQ(again.type, MessageType::kCompleted) << again.reason();
  const std::vector<core::Message> msgs = messages_of("reach");
  ASSERT_EQ(msgs.size(), before + 2) << "started and completed only, no planning";
  EXPECT_EQ(msgs[before].type, MessageType::kStarted);
}

TEST_P(PrimitivesTest, SingleLimbPosturesMirrorByTheDocumentedRule) {
  // wave_start names one arm; find which.
  const std::vector<std::string> named = posture_values(*skills_, "wave_start", {}).chains;
  const std::string arm = *std::find_if(named.begin(), named.end(), [](const std::string& c) {
    return core::chain_kind(c) == "arm";
  });
  const std::string other = core::mirror_chain(arm);
  // Busy: the named arm is held by another program, so the posture goes to the other arm,
  // whatever the seed.
  for (std::uint32_t seed = 1; seed <= 6; ++seed) {
    make_executive(seed);
    executive_->start(std::make_unique<Hold>(std::vector<std::string>{arm}), "hold");
    const int p = executive_->start("postural", {{"posture", "wave_start"}});
    EXPECT_EQ(executive_->holder_of_chain(other), p) << "seed " << seed;
  }
  make_executive(1);
  const int hold = executive_->start(std::make_unique<Hold>(std::vector<std::string>{arm}), "hold");
  const int id = executive_->start("postural", {{"posture", "wave_start"}});
  EXPECT_EQ(executive_->holder_of_chain(other), id);
  executive_->run(20.0);
  ASSERT_EQ(executive_->outcome(id)->type, MessageType::kCompleted)
      << executive_->outcome(id)->reason();
  const ChainValues mirrored_goal = mirrored(*skills_, posture_values(*skills_, "wave_start", {}));
  EXPECT_LE(max_difference(skills_->configuration(mirrored_goal.chains), mirrored_goal.values),
            0.05);
  executive_->halt(hold);
  // Already there: the other arm holds the mirrored posture, so it is chosen (whatever the
  // seed) and nothing moves.
  for (std::uint32_t seed = 1; seed <= 6; ++seed) {
    make_executive(seed);
    const int p = executive_->start("postural", {{"posture", "wave_start"}});
    EXPECT_EQ(executive_->holder_of_chain(other), p) << "seed " << seed;
    executive_->run(1.0);
    ASSERT_TRUE(executive_->outcome(p));
    EXPECT_EQ(executive_->outcome(p)->type, MessageType::kCompleted);
    for (const core::Message& m : executive_->log()) {
      EXPECT_NE(m.type, MessageType::kPlanningStarted) << "seed " << seed;
    }
  }
  // Both free and neither there: a random choice, reproducible from the run seed; over eight
  // seeds both arms are chosen.
  std::set<std::string> chosen;
  for (std::uint32_t seed = 1; seed <= 8; ++seed) {
    skills_->reset();
    make_executive(seed);
    const int p = executive_->start("postural", {{"posture", "wave_start"}});
    chosen.insert(executive_->holder_of_chain(arm) == p ? arm : other);
    executive_->halt(p);
  }
  EXPECT_EQ(chosen.size(), 2u);
  // side=as_named never mirrors.
  skills_->reset();
  make_executive(1);
  const int named_id =
      executive_->start("postural", {{"posture", "wave_start"}, {"side", "as_named"}});
  EXPECT_EQ(executive_->holder_of_chain(arm), named_id);
}

TEST_P(PrimitivesTest, InSensorModeAnObjectNeverSeenIsUnknownToPrograms) {
  // An obstacle behind the robot, where the head cannot see it.
  core::ObstacleLayout layout;
  core::PlacedObstacle o;
  o.position = Eigen::Vector3d(-1.0, 0.0, 0.3);
  o.size = Eigen::Vector3d::Constant(0.1);
  layout.obstacles.push_back(o);
  skills_->apply_layout(layout);
  executive_.reset();
  perception_ = std::make_unique<mujoco::SensorPerception>(*skills_);
  make_executive(1);
  EXPECT_FALSE(executive_->percepts().knows("obstacle_0"));
  EXPECT_TRUE(executive_->percepts().knows("cup"));
  EXPECT_EQ(run("reach", {{"object", "obstacle_0"}}).reason(),
            "perception_miss: 'obstacle_0' is not in the perceptual model");
  // The cup, which the head sees, is reached as in ground truth.
  EXPECT_EQ(run("reach", {{"object", "cup"}}).type, MessageType::kCompleted);
}

// The stance search drops base poses from which every target lies beyond the arm's farthest
// horizontal reach, so that estimate must not fall short of where the arm can get: none of
// 3000 random postures of torso and arm (more than the estimate's own 400 draws) takes the
// palm farther from the base's vertical axis than it says, the farthest comes within a tenth
// of it, and the axis it found is the one the base turns about (turning the base leaves every
// palm's distance from it as it was).
TEST_P(PrimitivesTest, TheReachEnvelopeIsNoShorterThanAnyPostureReaches) {
  std::vector<std::string> body = {"base"};
  if (skills_->profile().find_chain("torso")) body.push_back("torso");
  body.push_back("left_arm");
  const std::string palm = skills_->profile().find_hand("left")->palm;
  const ReachEnvelope envelope(*skills_, body, palm);
  std::vector<double> lower, upper;
  for (const std::string& c : body) {
    const core::ChainInfo& info = skills_->chain(c);
    lower.insert(lower.end(), info.lower.begin(), info.lower.end());
    upper.insert(upper.end(), info.upper.begin(), info.upper.end());
  }
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  auto from_axis = [&](const std::vector<double>& q) {
    const Eigen::Vector3d p = skills_->frame_pose_at(body, q, palm).position;
    const Eigen::Vector2d axis = envelope.axis_at_origin() + Eigen::Vector2d(q[0], q[1]);
    return std::hypot(p.x() - axis.x(), p.y() - axis.y());
  };
  double farthest = 0;
  for (int n = 0; n < 3000; ++n) {
    std::vector<double> q(lower.size());
    for (size_t j = 0; j < q.size(); ++j) q[j] = lower[j] + unit(rng) * (upper[j] - lower[j]);
    q[0] = 0.3 * (unit(rng) - 0.5);  // the base anywhere near the origin, turned any way
    q[1] = 0.3 * (unit(rng) - 0.5);
    const double r = from_axis(q);
    farthest = std::max(farthest, r);
    ASSERT_LE(r, envelope.radius() + 0.001);
    std::vector<double> turned = q;
    turned[2] = std::remainder(q[2] + 1.3, 2 * M_PI);
    ASSERT_NEAR(from_axis(turned), r, 1e-9) << "the axis is not the one the base turns about";
  }
  EXPECT_GT(farthest, 0.9 * envelope.radius());
  EXPECT_GT(envelope.radius(), 0.2 * skills_->profile().height_m);
}

INSTANTIATE_TEST_SUITE_P(
    Pairs, PrimitivesTest,
    ::testing::Values(test::RobotEnv{"tallbot", "kitchen"}, test::RobotEnv{"tallbot", "office"},
                      test::RobotEnv{"minibot", "kitchen"}, test::RobotEnv{"minibot", "office"}),
    [](const ::testing::TestParamInfo<test::RobotEnv>& p) { return test::pair_name(p.param); });

}  // namespace
}  // namespace taskmatrix::programs
