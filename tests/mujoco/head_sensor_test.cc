// The simulated head sensor and perception mode `sensor`, on every robot in the kitchen.
#include "taskmatrix/mujoco/head_sensor.h"

#include <gtest/gtest.h>

#include <cmath>

#include "taskmatrix/core/conditions.h"
#include "tests/test_support.h"

namespace taskmatrix::mujoco {
namespace {

class HeadSensorTest : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    skills_ = std::make_unique<MujocoSkillset>(test::scene(GetParam(), "kitchen"));
  }
  // Recognised things of the last capture, by id.
  std::map<std::string, Recognition> recognised(const HeadSensor& sensor) {
    std::map<std::string, Recognition> out;
    for (const Recognition& r : sensor.recognise()) out[sensor.things()[r.thing].id] = r;
    return out;
  }
  // One box obstacle centred at `centre`.
  void place_box(const Eigen::Vector3d& centre, double half) {
    core::ObstacleLayout layout;
    core::PlacedObstacle o;
    o.shape = core::ObstacleShape::kBox;
    o.position = centre;
    o.size = Eigen::Vector3d::Constant(half);
    layout.obstacles.push_back(o);
    skills_->apply_layout(layout);
  }
  std::unique_ptr<MujocoSkillset> skills_;
};

TEST_P(HeadSensorTest, SeesTheTableObjectsAndEveryHitLiesOnWhatItIsLabelled) {
  HeadSensor sensor(*skills_, {64, 48, 5.0, 3});
  const SensorImage& image = sensor.capture();
  const auto seen = recognised(sensor);
  for (const char* id : {"cup", "box", "work_surface"}) {
    ASSERT_TRUE(seen.count(id)) << id << " not recognised";
    EXPECT_GE(seen.at(id).pixels, 3);
    EXPECT_GT(seen.at(id).confidence(), 0.5) << id;
    EXPECT_LE(seen.at(id).confidence(), 1.0) << id;
  }
  int hits = 0;
  for (size_t i = 0; i < image.thing.size(); ++i) {
    const std::optional<Eigen::Vector3d> p = sensor.hit_point(i);
    EXPECT_EQ(p.has_value(), image.depth_m[i] > 0) << i;
    if (!p) continue;
    ++hits;
    EXPECT_LE(image.depth_m[i], 5.0f);
    const int t = image.thing[i];
    if (t < 0) continue;
    const auto o = perceive(*skills_, sensor.things()[t], 0.0);
    ASSERT_TRUE(o);
    const std::string& type = sensor.things()[t].type;
    if (type == "surface") continue;  // the table's legs are outside its top's box
    Eigen::AlignedBox3d grown = o->box;
    grown.extend(o->box.min() - Eigen::Vector3d::Constant(1e-3));
    grown.extend(o->box.max() + Eigen::Vector3d::Constant(1e-3));
    EXPECT_TRUE(grown.contains(*p)) << sensor.things()[t].id << " pixel " << i;
  }
  // The room's walls and floor are in range: nearly every ray hits something.
  EXPECT_GT(hits, static_cast<int>(image.thing.size() * 9 / 10));
}

TEST_P(HeadSensorTest, AnObstacleBetweenHeadAndCupHidesTheCup) {
  HeadSensor sensor(*skills_);
  sensor.capture();
  ASSERT_TRUE(recognised(sensor).count("cup"));
  const int cam = skills_->scene().head_camera();
  const Eigen::Vector3d eye(skills_->sim_data()->cam_xpos + 3 * cam);
  const Eigen::Vector3d cup = skills_->frame_pose("cup").position;
  place_box(eye + 0.45 * (cup - eye), 0.07);
  sensor.capture();
  const auto seen = recognised(sensor);
  EXPECT_FALSE(seen.count("cup"));
  ASSERT_TRUE(seen.count("obstacle_0"));
  EXPECT_GT(seen.at("obstacle_0").confidence(), 0.9);
}

TEST_P(HeadSensorTest, SensorModeKnowsOnlyWhatTheHeadHasSeen) {
  // An obstacle where the right hand goes when the arm is raised out to the side: beside the
  // robot, outside the head's view.
  const core::ChainInfo& arm = skills_->chain("right_arm");
  std::vector<double> out_to_side = skills_->configuration({"right_arm"});
  // Shoulder roll (second joint) towards its abduction limit.
  const double roll_limit =
      std::abs(arm.upper[1]) > std::abs(arm.lower[1]) ? arm.upper[1] : arm.lower[1];
  out_to_side[1] = std::copysign(std::min(0.9 * std::abs(roll_limit), 1.4), roll_limit);
  const Eigen::Vector3d hand =
      skills_
          ->frame_pose_at({"right_arm"}, out_to_side, skills_->profile().find_hand("right")->palm)
          .position;
  place_box(hand, 0.06);
  ASSERT_FALSE(skills_->is_valid({"right_arm"}, out_to_side)) << "ground truth sees it";

  SensorPerception perception(*skills_);
  core::PerceptualModel model;
  perception.update(0.0, model);
  EXPECT_TRUE(model.knows("cup"));
  EXPECT_FALSE(model.knows("obstacle_0"));
  EXPECT_FALSE(skills_->obstacle_known(0));
  EXPECT_TRUE(skills_->is_valid({"right_arm"}, out_to_side))
      << "the planner ignores what it has not seen";
  // The simulation still has it: moving the arm there collides.
  const core::Trajectory traj = skills_->time_parameterize(
      {"right_arm"}, {skills_->configuration({"right_arm"}), out_to_side});
  const core::ExecutionReport report = skills_->execute({"right_arm"}, traj);
  EXPECT_EQ(report.status, core::ExecutionStatus::kCollision) << report.message;
  ASSERT_TRUE(report.collision);
  EXPECT_EQ(report.collision->other, "obstacle_0");

  // Turn the head towards the obstacle (its first joint to the right, level; a neck that
  // cannot turn, the base): once seen, queries know it.
  skills_->reset();
  const std::vector<double> start_base = skills_->configuration({"base"});
  const core::ChainInfo& head = skills_->chain("head");
  std::vector<double> look(head.joints.size(), 0.0);
  look[0] = head.lower[0];
  skills_->set_configuration({"head"}, look);
  for (int turn = 1; turn <= 8 && !core::in_camera_view(*skills_, hand); ++turn) {
    for (int tilt = 0; tilt <= 4 && !core::in_camera_view(*skills_, hand); ++tilt) {
      std::vector<double> tilted(head.joints.size(), 0.0), turned = start_base;
      tilted[0] = head.lower[0] + (head.upper[0] - head.lower[0]) * tilt / 4;
      turned[2] -= 0.25 * turn;  // the base's yaw, to the right
      skills_->set_configuration({"head"}, tilted);
      skills_->set_configuration({"base"}, turned);
    }
  }
  if (!core::in_camera_view(*skills_, hand)) {
    GTEST_SKIP() << "no turn of the head or base (up to 2 rad) brings the raised hand's place "
                    "into the head camera's view";
  }
  perception.update(1.0, model);
  ASSERT_TRUE(model.knows("obstacle_0"));
  EXPECT_DOUBLE_EQ(model.find("obstacle_0")->last_seen, 1.0);
  EXPECT_TRUE(skills_->obstacle_known(0));
  skills_->set_configuration({"base"}, start_base);
  EXPECT_FALSE(skills_->is_valid({"right_arm"}, out_to_side));
  // A reset (a new trial) forgets what was seen.
  skills_->reset();
  EXPECT_FALSE(skills_->obstacle_known(0));
  EXPECT_TRUE(skills_->is_valid({"right_arm"}, out_to_side));
}

TEST_P(HeadSensorTest, TheImageIsUprightAndDepthIsAlongTheOpticalAxis) {
  HeadSensor sensor(*skills_, {64, 48, 5.0, 3});
  const SensorImage& image = sensor.capture();
  // Where the pinhole model puts the cup's centre: column 0 is the left, row 0 the top.
  const int cam = skills_->scene().head_camera();
  const double* R = skills_->sim_data()->cam_xmat + 9 * cam;
  const Eigen::Vector3d eye(skills_->sim_data()->cam_xpos + 3 * cam);
  const Eigen::Vector3d x(R[0], R[3], R[6]), y(R[1], R[4], R[7]), z(R[2], R[5], R[8]);
  const Eigen::Vector3d rel = skills_->frame_pose("cup").position - eye;
  const double tan_half = std::tan(skills_->model()->cam_fovy[cam] * M_PI / 360.0);
  const double u = rel.dot(x) / -rel.dot(z), v = rel.dot(y) / -rel.dot(z);
  const double col = (u / (tan_half * 64.0 / 48.0) + 1) / 2 * 64 - 0.5;
  const double row = (1 - v / tan_half) / 2 * 48 - 0.5;
  double sum_col = 0, sum_row = 0;
  int n = 0;
  int cup = -1;
  for (size_t t = 0; t < sensor.things().size(); ++t) {
    if (sensor.things()[t].id == "cup") cup = static_cast<int>(t);
  }
  for (int r = 0; r < 48; ++r) {
    for (int c = 0; c < 64; ++c) {
      if (image.thing[static_cast<size_t>(r * 64 + c)] != cup) continue;
      sum_col += c;
      sum_row += r;
      ++n;
    }
  }
  ASSERT_GT(n, 0);
  EXPECT_NEAR(sum_col / n, col, 2.5);
  EXPECT_NEAR(sum_row / n, row, 2.5);
  // Depth is the hit point's distance along the optical axis.
  for (size_t i : {size_t{0}, size_t{24 * 64 + 32}, size_t{47 * 64 + 63}}) {
    const std::optional<Eigen::Vector3d> p = sensor.hit_point(i);
    ASSERT_TRUE(p);
    EXPECT_NEAR(image.depth_m[i], (*p - eye).dot(-z), 1e-4);
  }
}

// Every robot of the models folder, so a user's robot gets these checks too (a head camera
// inside the robot's own geometry once left a robot's sensor seeing nothing but its torso).
INSTANTIATE_TEST_SUITE_P(Robots, HeadSensorTest, ::testing::ValuesIn(test::catalog().robots()),
                         [](const ::testing::TestParamInfo<std::string>& p) { return p.param; });

}  // namespace
}  // namespace taskmatrix::mujoco
