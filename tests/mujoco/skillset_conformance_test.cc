// The skillset conformance suite (tests/support/skillset_conformance.h) on the MuJoCo backend,
// in both execution modes.
#include <gtest/gtest.h>

#include "taskmatrix/mujoco/mujoco_skillset.h"
#include "tests/support/skillset_conformance.h"
#include "tests/test_support.h"

namespace taskmatrix::test {
namespace {

std::unique_ptr<core::Skillset> mujoco_skillset(const std::string& robot,
                                                mujoco::ExecutionMode mode) {
  mujoco::SimulationOptions options;
  options.execution = mode;
  return std::make_unique<mujoco::MujocoSkillset>(scene(robot, "kitchen"), options);
}

INSTANTIATE_TEST_SUITE_P(
    Mujoco, SkillsetConformance,
    ::testing::Values(
        Backend{"tallbot_physics",
                [] { return mujoco_skillset("tallbot", mujoco::ExecutionMode::kPhysics); }, "cup"},
        Backend{"minibot_kinematic",
                [] { return mujoco_skillset("minibot", mujoco::ExecutionMode::kKinematic); },
                "cup"}),
    backend_name);

}  // namespace
}  // namespace taskmatrix::test
