#include "tests/support/skillset_conformance.h"

#include <cmath>
#include <stdexcept>

namespace taskmatrix::test {
namespace {

using Chains = std::vector<std::string>;

// The message of the std::invalid_argument `call` throws; "" if it throws none.
template <typename F>
std::string rejection(F&& call) {
  try {
    call();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// `q` with joint `i` moved `step` towards the middle of its range.
std::vector<double> nudged(const core::ChainInfo& chain, std::vector<double> q, size_t i,
                           double step) {
  q[i] += 0.5 * (chain.lower[i] + chain.upper[i]) > q[i] ? step : -step;
  return q;
}

core::PlanOptions quick_plan() {
  core::PlanOptions options;
  options.time_limit_s = 2;
  return options;
}

TEST_P(SkillsetConformance, ArgumentsAreCheckedBeforeTheBackendSeesThem) {
  const Chains arm = {"left_arm"};
  const core::ChainInfo& chain = skills().chain("left_arm");
  const std::vector<double> q = skills().clamped_configuration(arm);
  EXPECT_TRUE(
      contains(rejection([&] { skills().configuration({"tail"}); }), "has no chain 'tail'"));
  EXPECT_TRUE(contains(rejection([&] { skills().configuration({}); }), "no chains given"));
  EXPECT_TRUE(contains(rejection([&] {
                         skills().configuration({"left_arm", "left_arm"});
                       }),
                       "chain 'left_arm' is listed twice"));
  EXPECT_TRUE(contains(rejection([&] { skills().is_valid(arm, {0.0}); }),
                       "configuration has 1 values but chains [left_arm] have"));
  EXPECT_TRUE(
      contains(rejection([&] { skills().is_valid(arm, q, {"no_such_object"}); }), "may_touch: "));
  std::vector<double> nan_q = q;
  nan_q[1] = NAN;
  EXPECT_TRUE(contains(rejection([&] { skills().is_valid(arm, nan_q); }),
                       "'" + chain.joints[1] + "' is not finite"));
  EXPECT_TRUE(contains(rejection([&] { skills().command(arm, nan_q); }), "is not finite"));
  EXPECT_TRUE(contains(rejection([&] { skills().frame_pose_at(arm, nan_q, chain.joints[0]); }),
                       "is not finite"));
  std::vector<double> beyond = q;
  beyond[2] = chain.upper[2] + 0.5;
  const std::uint64_t checks = skills().work().collision_checks;
  EXPECT_FALSE(skills().is_valid(arm, beyond));
  EXPECT_EQ(skills().work().collision_checks, checks);  // decided without a check
  EXPECT_TRUE(contains(rejection([&] { skills().command(arm, beyond); }),
                       "joint '" + chain.joints[2] + "' is outside its limits"));
  std::vector<double> hair = q;
  hair[2] = chain.upper[2] + 1e-7;  // rounding: clamped to the limit
  EXPECT_EQ(rejection([&] { skills().command(arm, hair); }), "");
  EXPECT_TRUE(contains(rejection([&] { skills().clearance(arm, q, 0); }), "clearance cap"));
  EXPECT_TRUE(contains(rejection([&] { skills().frame_pose("no_such_frame"); }), "no_such_frame"));

  core::PlanResult r = skills().plan_to_configuration(arm, beyond, quick_plan());
  EXPECT_EQ(r.status, core::PlanStatus::kInvalidInput);
  EXPECT_TRUE(contains(r.message, chain.joints[2])) << r.message;
  r = skills().plan_to_configuration(arm, nan_q, quick_plan());
  EXPECT_EQ(r.status, core::PlanStatus::kInvalidInput);
  EXPECT_TRUE(contains(r.message, "not finite")) << r.message;
  r = skills().plan_to_configuration({"tail"}, q, quick_plan());
  EXPECT_EQ(r.status, core::PlanStatus::kInvalidInput);
  core::PlanOptions touching = quick_plan();
  touching.may_touch = {"no_such_object"};
  r = skills().plan_to_configuration(arm, q, touching);
  EXPECT_EQ(r.status, core::PlanStatus::kInvalidInput);
  EXPECT_EQ(r.message.rfind("may_touch: ", 0), 0u) << r.message;

  const std::string palm = skills().profile().find_hand("left")->palm;
  core::Pose bad;
  bad.position.x() = NAN;
  EXPECT_EQ(skills().solve_ik({"tail"}, palm, bad, {}).status, core::IkStatus::kInvalidInput);
  EXPECT_EQ(skills().solve_ik(arm, palm, bad, {}).status, core::IkStatus::kInvalidInput);
  EXPECT_EQ(skills().plan_to_poses(arm, palm, {bad}, quick_plan(), {}).status,
            core::PlanStatus::kInvalidInput);
  EXPECT_EQ(skills().plan_to_poses(arm, palm, {}, quick_plan(), {}).status,
            core::PlanStatus::kInvalidInput);
  core::GoalRegion region;
  EXPECT_EQ(skills().plan_to_region(arm, region, quick_plan()).status,
            core::PlanStatus::kInvalidInput);  // no sampler
  region.sample = [](std::mt19937_64&) {
    return std::optional<std::vector<double>>(std::vector<double>{0.0});
  };
  EXPECT_EQ(skills().plan_to_region(arm, region, quick_plan()).status,
            core::PlanStatus::kInvalidInput);  // wrong size
}

TEST_P(SkillsetConformance, AttachDetachAndHolderOfKeepOneRecordPerObject) {
  const std::string object = GetParam().object;
  EXPECT_EQ(skills().holder_of(object), "");
  EXPECT_TRUE(contains(rejection([&] { skills().attach(object, "middle"); }), "no hand on side"));
  EXPECT_TRUE(contains(rejection([&] { skills().detach(object); }), "is not attached"));
  EXPECT_NE(rejection([&] { skills().attach("no_such_object", "left"); }), "");
  skills().attach(object, "left");
  EXPECT_EQ(skills().holder_of(object), "left");
  EXPECT_EQ(skills().attached_objects(), std::vector<std::string>{object});
  EXPECT_TRUE(contains(rejection([&] { skills().attach(object, "right"); }), "already attached"));
  EXPECT_EQ(skills().holder_of(object), "left");
  skills().detach(object);
  EXPECT_EQ(skills().holder_of(object), "");
  EXPECT_TRUE(skills().attached_objects().empty());
  EXPECT_TRUE(contains(rejection([&] { skills().detach(object); }), "is not attached"));
  skills().attach(object, "right");
  EXPECT_EQ(skills().holder_of(object), "right");
}

TEST_P(SkillsetConformance, ACommandIsReachedAndReadBack) {
  const Chains head = {"head"};
  const std::vector<double> q0 = skills().clamped_configuration(head);
  const std::vector<double> target = nudged(skills().chain("head"), q0, 0, 0.1);
  skills().command(head, target);
  const double t0 = skills().time();
  const int periods = static_cast<int>(std::lround(1.0 / skills().control_period()));
  for (int k = 0; k < periods; ++k) EXPECT_FALSE(skills().advance().unstable);
  EXPECT_NEAR(skills().time() - t0, periods * skills().control_period(), 1e-9);
  const std::vector<double> q = skills().configuration(head);
  ASSERT_EQ(q.size(), target.size());
  for (size_t i = 0; i < q.size(); ++i) EXPECT_NEAR(q[i], target[i], 0.02) << i;
}

TEST_P(SkillsetConformance, PlansEndWithTheStatusThatSaysWhy) {
  const Chains arm = {"left_arm"};
  const core::ChainInfo& chain = skills().chain("left_arm");
  const std::vector<double> goal = nudged(chain, skills().clamped_configuration(arm), 0, 0.05);
  core::PlanResult r = skills().plan_to_configuration(arm, goal, quick_plan());
  EXPECT_EQ(r.status, core::PlanStatus::kExactSolution) << r.message;
  ASSERT_GE(r.path.size(), 2u);
  for (size_t i = 0; i < goal.size(); ++i) EXPECT_NEAR(r.path.back()[i], goal[i], 1e-6);

  const std::string palm = skills().profile().find_hand("left")->palm;
  core::Pose far = skills().frame_pose(palm);
  far.position.x() += 100;
  core::IkOptions ik;
  ik.restarts = 2;
  r = skills().plan_to_poses(arm, palm, {far, far}, quick_plan(), ik);
  EXPECT_EQ(r.status, core::PlanStatus::kIkFailure);
  EXPECT_EQ(r.message.rfind("no target pose has an IK solution: 2 poses tried", 0), 0u)
      << r.message;
  EXPECT_EQ(r.goal_index, -1);

  core::GoalRegion nowhere;
  nowhere.sample = [](std::mt19937_64&) { return std::optional<std::vector<double>>(); };
  r = skills().plan_to_region(arm, nowhere, quick_plan());
  EXPECT_EQ(r.status, core::PlanStatus::kInvalidGoal);
  core::GoalRegion near_here;
  near_here.sample = [&](std::mt19937_64&) { return std::optional<std::vector<double>>(goal); };
  r = skills().plan_to_region(arm, near_here, quick_plan());
  EXPECT_EQ(r.status, core::PlanStatus::kExactSolution) << r.message;
}

TEST_P(SkillsetConformance, WorkIsCountedForEveryCall) {
  const Chains arm = {"left_arm"};
  const std::string palm = skills().profile().find_hand("left")->palm;
  const core::WorkRecord before = skills().work();
  core::Pose far = skills().frame_pose(palm);
  far.position.x() += 100;
  core::IkOptions ik;
  ik.restarts = 2;
  skills().solve_ik(arm, palm, far, ik);
  EXPECT_EQ(skills().work().ik_calls, before.ik_calls + 1);
  // Every IK call inside planning to poses counts, one per pose tried.
  skills().plan_to_poses(arm, palm, {far, far, far}, quick_plan(), ik);
  EXPECT_EQ(skills().work().ik_calls, before.ik_calls + 4);
  ASSERT_EQ(skills().work().plans.size(), before.plans.size() + 1);
  EXPECT_EQ(skills().work().plans.back().kind, "poses");
  EXPECT_EQ(skills().work().plans.back().status, "ik_failure");

  const std::vector<double> q = skills().clamped_configuration(arm);
  skills().is_valid(arm, q);
  EXPECT_EQ(skills().work().collision_checks, before.collision_checks + 1);
  const core::PlanResult r = skills().plan_to_configuration(
      arm, nudged(skills().chain("left_arm"), q, 0, 0.05), quick_plan());
  ASSERT_EQ(skills().work().plans.size(), before.plans.size() + 2);
  const core::PlanCallRecord& call = skills().work().plans.back();
  EXPECT_EQ(call.kind, "configuration");
  EXPECT_EQ(call.status, core::to_string(r.status));
  EXPECT_EQ(call.collision_checks, r.collision_checks);
  EXPECT_EQ(call.path_states, static_cast<int>(r.path.size()));
  EXPECT_EQ(call.path_digest, core::path_digest(r.path));
  EXPECT_EQ(skills().work().collision_checks, before.collision_checks + 1 + r.collision_checks);

  skills().record_states(1.0 / (2 * skills().control_period()));  // a frame every 2 periods
  EXPECT_TRUE(skills().recording_states());
  const double t0 = skills().time();
  for (int k = 0; k < 4; ++k) skills().advance();
  EXPECT_EQ(skills().work().control_periods, before.control_periods + 4);
  // The recording (kept by core): the start, then a frame every 2 periods, each with the
  // backend's whole state.
  const core::StateRecording& rec = skills().recording();
  EXPECT_NEAR(rec.frame_period_s, 2 * skills().control_period(), 1e-12);
  ASSERT_EQ(rec.frames(), 3u);
  EXPECT_GT(rec.nq, 0);
  EXPECT_EQ(rec.qpos.size(), rec.frames() * static_cast<size_t>(rec.nq));
  EXPECT_DOUBLE_EQ(rec.times.front(), t0);
  EXPECT_NEAR(rec.times.back() - rec.times.front(), 4 * skills().control_period(), 1e-9);
  EXPECT_THROW(skills().record_states(-1), std::invalid_argument);
  skills().record_states(0);
  EXPECT_FALSE(skills().recording_states());
}

}  // namespace
}  // namespace taskmatrix::test
