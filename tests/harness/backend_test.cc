// The harness's door to the simulator (core/backend.h, harness/backends/): backends by name,
// and a loaded scene's layout check, trial worlds and pictures as the harness uses them.
#include <gtest/gtest.h>

#include <cmath>
#include <regex>
#include <set>
#include <span>
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

// What a chain touches is reported by name (Skillset::collisions, the perceptual model): a
// random obstacle as "obstacle_N". A program that lets a plan leave what a hand touches passes
// those names back as may_touch; an obstacle's name was not resolved there, and every plan
// failed `invalid_input: may_touch: no object or body 'obstacle_0'`.
TEST(Backends, APlanMayTouchAnObstacleByTheNameItIsReportedBy) {
  const auto scene = backend().load(test::catalog().robot_dir("minibot"),
                                    test::catalog().environment_dir("kitchen"));
  core::ObstacleOptions obstacles;
  obstacles.count = 3;
  const core::TrialLayout layout = scene->make_trial_layout(obstacles, {}, 1);
  core::TrialWorldOptions options;
  options.execution = "kinematic";
  const auto world = scene->make_trial_world(layout, options);
  core::Skillset& skills = world->skills();
  core::PlanOptions plan;
  plan.seed = 1;
  plan.may_touch = {"obstacle_0", "obstacle_2"};
  const std::vector<double> here = skills.configuration({"left_arm"});
  core::PlanResult r = skills.plan_to_configuration({"left_arm"}, here, plan);
  EXPECT_EQ(r.status, core::PlanStatus::kExactSolution) << r.message;
  plan.may_touch = {"obstacle_99"};  // no such slot (the kitchen has 24)
  r = skills.plan_to_configuration({"left_arm"}, here, plan);
  EXPECT_EQ(r.status, core::PlanStatus::kInvalidInput);
  EXPECT_NE(r.message.find("obstacle_99"), std::string::npos) << r.message;
}

TEST(Backends, AViewShowsPosturesAndRecordedStatesAndDrawsThem) {
  const auto scene = backend().load(test::catalog().robot_dir("tallbot"),
                                    test::catalog().environment_dir("kitchen"));
  const core::TrialLayout layout = scene->make_trial_layout({}, {}, 1);
  const std::unique_ptr<core::SceneView> view = scene->make_view(layout);
  std::string palm;
  for (const core::HandSpec& hand : scene->robot().hands) {
    if (hand.side == "right") palm = hand.palm;
  }
  ASSERT_FALSE(palm.empty());

  // Postures move the hand; names the view does not know are errors.
  view->show_posture("rest");
  const Eigen::Vector3d rest = view->position(palm);
  EXPECT_LT((rest - view->base_position()).head<2>().norm(), 1.0);
  view->show_posture("fist");  // fingers only
  EXPECT_LT((view->position(palm) - rest).norm(), 1e-9);
  view->show_posture("wave_start");  // the right arm out to the side, the forearm up
  EXPECT_GT(view->position(palm).z() - rest.z(), 0.2);
  view->show_posture("rest");
  EXPECT_THROW(view->show_posture("moonwalk"), std::out_of_range);
  EXPECT_THROW(view->position("no_such_frame"), std::out_of_range);

  // Lines of sight: down onto the cup (0.10 m tall, its origin at its centre or foot) from a
  // metre above its origin; nothing above it.
  const Eigen::Vector3d cup = view->position("cup");
  const Eigen::Vector3d above = cup + Eigen::Vector3d(0, 0, 1);
  EXPECT_GT(view->first_hit(above, -Eigen::Vector3d::UnitZ()), 0.85);
  EXPECT_LT(view->first_hit(above, -Eigen::Vector3d::UnitZ()), 1.0);
  EXPECT_TRUE(std::isinf(view->first_hit(above, Eigen::Vector3d::UnitZ())));

  // Images through the head camera: the right size, not one flat colour; depth in metres.
  core::Camera head;
  head.name = "head";
  const core::RgbImage image = view->render(head, 64, 48);
  ASSERT_EQ(image.pixels.size(), 64u * 48u * 3u);
  std::set<std::uint32_t> colours;
  for (size_t i = 0; i + 2 < image.pixels.size(); i += 3) {
    colours.insert(image.pixels[i] << 16 | image.pixels[i + 1] << 8 | image.pixels[i + 2]);
  }
  EXPECT_GT(colours.size(), 20u);
  const core::DepthImage depth = view->render_depth(head, 64, 48);
  float nearest = INFINITY;
  for (float d : depth.metres) nearest = std::min(nearest, d);
  EXPECT_GT(nearest, 0.05f);
  EXPECT_LT(nearest, 3.0f);
  core::Camera nowhere;
  nowhere.name = "nowhere";
  EXPECT_THROW(view->render(nowhere, 64, 48), std::out_of_range);
  EXPECT_THROW(view->render(head, view->max_width() + 2, 48), std::invalid_argument);
  const std::vector<std::string> cameras = view->cameras();
  ASSERT_FALSE(cameras.empty());
  EXPECT_EQ(cameras.front(), scene->environment().cameras.front());

  // A recorded state shows as recorded, with removed objects out of the world and back.
  core::TrialWorldOptions options;
  options.record_rate_hz = 50;
  const auto world = scene->make_trial_world(layout, options);
  const core::StateRecording& recording = world->skills().recording();
  ASSERT_EQ(recording.nq, view->state_size());
  ASSERT_GE(recording.frames(), 1u);
  const std::span<const float> first(recording.qpos.data(), static_cast<size_t>(recording.nq));
  view->show_state(first, 0, {});
  const Eigen::Vector3d debris = view->position("debris_0");
  view->show_state(first, 0, {"debris_0"});
  EXPECT_NEAR(view->position("debris_0").z(), debris.z() - 10, 1e-9);
  view->show_state(first, 0, {});
  EXPECT_NEAR(view->position("debris_0").z(), debris.z(), 1e-9);
  EXPECT_THROW(view->show_state(first, 0, {"no_such_body"}), std::out_of_range);
  EXPECT_THROW(view->show_state(first.first(3), 0, {}), std::invalid_argument);
}

TEST(Backends, RobotChecksRunOnLoadedScenes) {
  const auto kitchen = backend().load(test::catalog().robot_dir("minibot"),
                                      test::catalog().environment_dir("kitchen"));
  const std::vector<core::RobotFinding> findings = backend().check_robot(*kitchen, {kitchen});
  std::set<std::string> checks;
  for (const core::RobotFinding& f : findings) {
    checks.insert(f.check);
    EXPECT_NE(f.level, core::RobotFinding::Level::kError) << f.check << ": " << f.message;
  }
  for (const char* check : {"chains", "postures", "mirror signs", "palm axes", "fingers", "reach envelope"}) {
    EXPECT_TRUE(checks.count(check)) << check;
  }
}

}  // namespace
}  // namespace taskmatrix::harness
