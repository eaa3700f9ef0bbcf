// The harness's door to the simulator (core/backend.h, harness/backends/): backends by name,
// and a loaded scene's layout check and trial worlds as the runner uses them.
#include <gtest/gtest.h>

#include <regex>
#include <stdexcept>

#include "harness/backends/backends.h"
#include "taskmatrix/core/input_error.h"
#include "tests/test_support.h"

namespace taskmatrix::harness {
namespace {

TEST(Backends, AnUnknownNameIsAnErrorNamingTheKnownOnes) {
  EXPECT_EQ(backend_names(), std::vector<std::string>{"mujoco"});
  EXPECT_EQ(backend("mujoco").name(), "mujoco");
  EXPECT_TRUE(std::regex_match(backend().version(), std::regex(R"(\d+\.\d+\.\d+)")))
      << backend().version();
  try {
    backend("bullet");
    FAIL() << "no error";
  } catch (const core::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("unknown backend 'bullet' (known: mujoco)"),
              std::string::npos)
        << e.what();
  }
}

TEST(Backends, StartContactsNameTheRobotInTheWall) {
  const auto scene = backend().load(test::catalog().robot_dir("tallbot"),
                                    test::catalog().environment_dir("kitchen"));
  EXPECT_EQ(scene->robot().name, "tallbot");
  core::TrialLayout layout = scene->make_trial_layout({}, {}, 1);
  for (const core::StartContact& c : scene->start_contacts(layout)) {
    EXPECT_FALSE(c.robot) << c.first << " touches " << c.second;
    EXPECT_LE(c.depth_m, 0.001) << c.first << " in " << c.second;
  }
  // The robot's base drawn into the front wall (x = 3.55 m).
  layout.variation.robot_start = core::RobotStart{3.5, 0.0, 0.0};
  const std::vector<core::StartContact> contacts = scene->start_contacts(layout);
  bool pelvis_in_wall = false;
  for (const core::StartContact& c : contacts) {
    EXPECT_FALSE(c.obstacle);
    pelvis_in_wall |=
        c.robot && c.first == "pelvis" && c.second == "kitchen_wall_front" && c.depth_m > 0.05;
  }
  EXPECT_TRUE(pelvis_in_wall) << contacts.size() << " contacts";
}

TEST(Backends, ATrialWorldHasItsLayoutExecutionAndRecording) {
  const auto scene = backend().load(test::catalog().robot_dir("minibot"),
                                    test::catalog().environment_dir("kitchen"));
  const core::TrialLayout layout = scene->make_trial_layout({}, {}, 1);
  core::TrialWorldOptions options;
  options.execution = "kinematic";
  options.record_rate_hz = 50;
  const auto world = scene->make_trial_world(layout, options);
  core::Skillset& skills = world->skills();
  EXPECT_EQ(&world->skills(), &skills);
  EXPECT_TRUE(skills.recording_states());
  for (int k = 0; k < 10; ++k) skills.advance();
  EXPECT_EQ(skills.recording().frames(), 6u);  // the start, then every 2 control periods
  EXPECT_TRUE(world->removed_objects().empty());
  EXPECT_STREQ(world->make_perception("ground_truth")->mode(), "ground_truth");
  EXPECT_STREQ(world->make_perception("sensor")->mode(), "sensor");
  EXPECT_THROW(world->make_perception("lidar"), std::invalid_argument);
  options.execution = "teleport";
  EXPECT_THROW(scene->make_trial_world(layout, options), std::invalid_argument);
}

}  // namespace
}  // namespace taskmatrix::harness
