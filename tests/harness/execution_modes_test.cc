// Every task program in both execution modes, on both robots, in the kitchen and the
// scenario's default layout: the same success, the same plan calls, and planned paths that
// differ only where the simulated state at the plan differs: the physics ends a motion within
// its tolerance of the goal, the kinematic robot exactly at it, objects the physics pushed or
// let fall lie elsewhere, and the kinematic mode starts with the objects settled on their
// supports (the physics settles them in its first steps).
#include <gtest/gtest.h>

#include <cmath>

#include "harness/run/trial.h"
#include "harness/scenario/scenario.h"
#include "taskmatrix/programs/primitives.h"
#include "tests/test_support.h"

namespace taskmatrix::harness {
namespace {

core::ProgramRegistry& registry() {
  static core::ProgramRegistry r = [] {
    core::ProgramRegistry out;
    programs::register_programs(out);
    return out;
  }();
  return r;
}

struct Case {
  std::string program, robot;
};
void PrintTo(const Case& c, std::ostream* os) { *os << c.program << " on " << c.robot; }

std::vector<Case> all_cases() {
  std::vector<Case> out;
  for (const char* p : {"reach", "position", "grasp", "release", "fixate", "explore", "postural",
                        "canned", "pickup", "putdown", "greet", "vacuum"}) {
    for (const char* robot : {"tallbot", "minibot"}) out.push_back({p, robot});
  }
  return out;
}

// The plans of a trial in order, with the robot's joint positions and the whole simulated
// state (robot, objects, visitor) when each was made.
struct PlanAt {
  double time = 0;
  std::shared_ptr<const core::PlanResult> plan;
  std::vector<float> robot, world;
};

std::vector<PlanAt> plans_of(const TrialResult& r, const mujoco::Scene& scene) {
  std::vector<int> robot_qpos;
  for (const mujoco::ChainIndex& c : scene.chains()) {
    robot_qpos.insert(robot_qpos.end(), c.qpos_adr.begin(), c.qpos_adr.end());
  }
  const core::StateRecording& rec = r.recording;
  std::vector<PlanAt> out;
  for (const core::Message& m : r.log) {
    if (m.type != core::MessageType::kPlanningEnded || !m.plan) continue;
    PlanAt p;
    p.time = m.time;
    p.plan = m.plan;
    for (size_t f = 0; f < rec.frames(); ++f) {
      if (std::abs(rec.times[f] - m.time) > 1e-9) continue;
      const float* frame = rec.qpos.data() + f * static_cast<size_t>(rec.nq);
      for (int a : robot_qpos) p.robot.push_back(frame[a]);
      p.world.assign(frame, frame + rec.nq);
    }
    out.push_back(std::move(p));
  }
  return out;
}

class ExecutionModes : public ::testing::TestWithParam<Case> {};

TEST_P(ExecutionModes, SameSuccessAndPathsThatDifferOnlyWithTheirStart) {
  const Case& c = GetParam();
  Scenario s =
      load_scenario(test::catalog().root() / "scenarios" / "programs" / (c.program + ".yaml"),
                    test::catalog(), registry());
  const auto scene = test::loaded_scene(c.robot, "kitchen");
  TrialOptions options;
  options.record_rate_hz = 100;  // every control period: the state at each plan
  s.execution = "physics";
  const TrialResult physics =
      run_trial(s, *scene, s.layout_seed, s.seed, registry(), nullptr, options);
  s.execution = "kinematic";
  const TrialResult kinematic =
      run_trial(s, *scene, s.layout_seed, s.seed, registry(), nullptr, options);
  EXPECT_TRUE(physics.success) << trial_status(physics) << ": " << trial_failure_reason(physics);
  EXPECT_TRUE(kinematic.success) << trial_status(kinematic) << ": "
                                 << trial_failure_reason(kinematic);
  EXPECT_EQ(trial_status(physics), trial_status(kinematic));

  // The same measures, all measured.
  for (const TrialResult* r : {&physics, &kinematic}) {
    EXPECT_GT(r->duration_s, 0);
    EXPECT_GT(r->work.control_periods, 0);
    EXPECT_GT(r->work.contact_passes, 0);
  }

  const mujoco::Scene& mujoco_scene = *mujoco::scene_of(*scene);
  const std::vector<PlanAt> a = plans_of(physics, mujoco_scene),
                            b = plans_of(kinematic, mujoco_scene);
  // A known difference still succeeds in both modes (above); its plans are not compared.
  if (const auto why = test::known_mode_difference(c.program, c.robot)) {
    GTEST_SKIP() << *why << " (here " << a.size() << " plans under physics, " << b.size()
                 << " under kinematic execution)";
  }
  ASSERT_EQ(a.size(), b.size()) << "plan calls differ";
  int unexplained = 0, same = 0, robot_differs = 0;
  for (size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].plan->status, b[k].plan->status) << "plan " << k;
    ASSERT_FALSE(a[k].robot.empty()) << "no recorded state at plan " << k;
    if (a[k].plan->path == b[k].plan->path) {
      ++same;
      continue;
    }
    if (a[k].world == b[k].world) {
      ++unexplained;
      ADD_FAILURE() << "plan " << k << " differs from the same simulated state";
    }
    robot_differs += a[k].robot != b[k].robot;
  }
  EXPECT_EQ(unexplained, 0);
  RecordProperty("plans", static_cast<int>(a.size()));
  RecordProperty("identical_plans", same);
  RecordProperty("plans_from_another_robot_configuration", robot_differs);
}

// physics_unpruned computes every contact: the reference that contact pruning is checked and
// timed against (the runner benchmark). On a trial whose hand touches nothing it keeps the
// outcome and the plans, with more contacts per pass than pruned physics.
TEST(UnprunedPhysics, KeepsTheOutcomeAndComputesMoreContacts) {
  Scenario s = load_scenario(test::catalog().root() / "scenarios" / "programs" / "reach.yaml",
                             test::catalog(), registry());
  const auto scene = test::loaded_scene("minibot", "kitchen");
  s.execution = "physics";
  const TrialResult pruned = run_trial(s, *scene, s.layout_seed, s.seed, registry(), nullptr, {});
  s.execution = "physics_unpruned";
  const TrialResult unpruned = run_trial(s, *scene, s.layout_seed, s.seed, registry(), nullptr, {});
  EXPECT_TRUE(pruned.success) << trial_failure_reason(pruned);
  EXPECT_EQ(trial_status(pruned), trial_status(unpruned)) << trial_failure_reason(unpruned);
  EXPECT_EQ(pruned.work.plans.size(), unpruned.work.plans.size());
  ASSERT_GT(pruned.work.contact_passes, 0);
  ASSERT_GT(unpruned.work.contact_passes, 0);
  const double per_pass_pruned =
      static_cast<double>(pruned.work.contacts) / static_cast<double>(pruned.work.contact_passes);
  const double per_pass_unpruned = static_cast<double>(unpruned.work.contacts) /
                                   static_cast<double>(unpruned.work.contact_passes);
  EXPECT_GT(per_pass_unpruned, 1.5 * per_pass_pruned)
      << per_pass_unpruned << " against " << per_pass_pruned << " contacts per step";
}

std::string case_name(const ::testing::TestParamInfo<Case>& info) {
  return info.param.program + "_" + info.param.robot;
}

INSTANTIATE_TEST_SUITE_P(AllPrograms, ExecutionModes, ::testing::ValuesIn(all_cases()), case_name);

}  // namespace
}  // namespace taskmatrix::harness
