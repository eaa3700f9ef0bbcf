// Grasp candidates for every robot's hands in every environment: the fingers stay off the
// surface the object stands on, and a tool's handle sits where the closed fingers reach it.
#include "taskmatrix/programs/grasp_candidates.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "taskmatrix/mujoco/ground_truth_perception.h"
#include "taskmatrix/mujoco/mujoco_skillset.h"
#include "tests/test_support.h"

namespace taskmatrix::programs {
namespace {

class GraspCandidatesTest : public ::testing::TestWithParam<test::RobotEnv> {
 protected:
  void SetUp() override {
    skills_ = std::make_unique<mujoco::MujocoSkillset>(
        test::scene(GetParam().robot, GetParam().environment));
    mujoco::GroundTruthPerception(*skills_).update(0, model_);
  }
  const core::PerceivedObject& object(const std::string& id) const {
    const core::PerceivedObject* o = model_.find(id);
    if (!o) throw std::runtime_error("no '" + id + "' in " + GetParam().environment);
    return *o;
  }
  // The palm frame's lowest finger point over `support_z` at `pose`.
  static double finger_gap(const HandGeometry& hand, const core::Pose& pose, double support_z) {
    double lowest = INFINITY;
    for (const Eigen::Vector3d& f : hand.finger_points) {
      lowest = std::min(lowest, (pose.position + pose.orientation * f).z());
    }
    return lowest - support_z;
  }
  std::unique_ptr<mujoco::MujocoSkillset> skills_;
  core::PerceptualModel model_;
};

TEST_P(GraspCandidatesTest, FingersStayOverTheSurfaceTheCupStandsOn) {
  const core::PerceivedObject& cup = object("cup");
  const double table = cup.box.min().z();
  for (const core::HandSpec& spec : skills_->profile().hands) {
    const HandGeometry hand = measure_hand(*skills_, spec);
    ASSERT_FALSE(hand.finger_points.empty()) << spec.side;
    const std::vector<GraspCandidate> all =
        grasp_candidates(cup, hand, skills_->frame_pose(spec.palm).position);
    ASSERT_FALSE(all.empty()) << spec.side;
    // A hand coming down keeps every open finger point over the table, and the placement says
    // so; from above, it is held back over the cup.
    for (const GraspCandidate& c : all) {
      if (c.approach.z() >= -0.1 || c.score >= 20) continue;
      for (double clearance : {0.01, 0.025}) {
        const GraspCandidate::Placement at = c.place(hand, clearance);
        EXPECT_GE(at.support_gap_m, 0.0) << spec.side << " " << c.id;
        EXPECT_NEAR(at.support_gap_m, finger_gap(hand, at.pose, table), 1e-3) << c.id;
      }
    }
    for (const GraspCandidate& c : all) {
      if (c.family != "top") continue;
      const GraspCandidate::Placement at = c.place(hand, 0.01);
      EXPECT_GE(at.support_gap_m, 0.0) << spec.side << " " << c.id;
      // The palm frame stays over the cup, inside its box (where graspable() finds it).
      EXPECT_LE(at.pose.position.z(), cup.box.max().z()) << spec.side << " " << c.id;
      EXPECT_GE(at.pose.position.z(), cup.box.center().z()) << spec.side << " " << c.id;
    }
  }
}

TEST_P(GraspCandidatesTest, AHandleSitsWhereTheClosedFingersReachIt) {
  const core::PerceivedObject& tool = object("vacuum");
  ASSERT_TRUE(tool.frames.count("grip"));
  const Eigen::Vector3d grip = tool.frames.at("grip").position;
  for (const core::HandSpec& spec : skills_->profile().hands) {
    const HandGeometry hand = measure_hand(*skills_, spec);
    const std::vector<GraspCandidate> all =
        grasp_candidates(tool, hand, skills_->frame_pose(spec.palm).position);
    ASSERT_FALSE(all.empty()) << spec.side;
    for (const GraspCandidate& c : all) {
      ASSERT_EQ(c.family, "grip");
      const GraspCandidate::Placement at = c.place(hand, 0.01);
      // The handle's axis lies at least as far out as the closed fingers' last segments begin,
      // and the palm frame within graspable()'s 3 cm of the grip (less the arm's settling).
      const double depth = (grip - at.pose.position).dot(c.approach);
      EXPECT_GE(depth, hand.closed_reach_m - 1e-9) << spec.side << " " << c.id;
      EXPECT_LE((grip - at.pose.position).norm(), 0.027 + 1e-9) << spec.side << " " << c.id;
      if (c.approach.z() < -0.1 && c.score < 20) {
        EXPECT_GE(at.support_gap_m, 0.0) << spec.side << " " << c.id;
      }
    }
  }
}

// The closing sweep of every hand: each finger's points from open to fist, starting where
// finger_points has them; closing moves every fingertip; a finger closing on a bar stops no
// later than one closing on nothing.
TEST_P(GraspCandidatesTest, EveryFingersClosingSweepStartsOpenAndMovesItsTip) {
  const core::PerceivedObject& tool = object("vacuum");
  for (const core::HandSpec& spec : skills_->profile().hands) {
    const HandGeometry hand = measure_hand(*skills_, spec);
    ASSERT_EQ(hand.sweeps.size(), static_cast<size_t>(hand.fingers)) << spec.side;
    for (const auto& finger : hand.sweeps) {
      ASSERT_GE(finger.size(), 2u) << spec.side;
      for (const Eigen::Vector3d& p : finger.front()) {
        const bool listed =
            std::any_of(hand.finger_points.begin(), hand.finger_points.end(),
                        [&](const Eigen::Vector3d& f) { return (f - p).norm() < 1e-9; });
        EXPECT_TRUE(listed) << spec.side << ": " << p.transpose();
      }
      EXPECT_GT((finger.back().back() - finger.front().back()).norm(), 0.02) << spec.side;
    }
    const std::vector<GraspCandidate> all =
        grasp_candidates(tool, hand, skills_->frame_pose(spec.palm).position);
    ASSERT_FALSE(all.empty()) << spec.side;
    for (const GraspCandidate& c : all) {
      const GraspCandidate::Placement at = c.place(hand, 0.01);
      const Eigen::Quaterniond to_palm = at.pose.orientation.conjugate();
      const Eigen::Vector3d centre = to_palm * (c.centre - at.pose.position);
      const Eigen::Vector3d axis = to_palm * c.free_axis;
      EXPECT_LE(hand.swept_points(centre, axis, c.width_m / 2).size(),
                hand.swept_points(centre, axis, 0).size())
          << spec.side << " " << c.id;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(EveryRobot, GraspCandidatesTest,
                         ::testing::ValuesIn(test::all_robot_environment_pairs()),
                         [](const ::testing::TestParamInfo<test::RobotEnv>& p) {
                           return test::pair_name(p.param);
                         });

// tallbot's fingers are longer than the vacuum's handle is high over the table (8 cm). From
// above they close round the handle, stopping on it, and stay over the table; with the hand
// turned a quarter about the handle, fingers pointing down, the same closing reaches the table
// (under physics they stopped on it and the grasp held with one finger of three). After a
// grasp that did not hold, reach keeps poses whose closing reaches the table out.
TEST(GraspCandidatesOnTallbot, ClosingOnAHandleFromAboveStaysOffTheTableAndFingersDownDoNot) {
  mujoco::MujocoSkillset skills(test::scene("tallbot", "kitchen"));
  core::PerceptualModel model;
  mujoco::GroundTruthPerception(skills).update(0, model);
  const core::PerceivedObject* tool = model.find("vacuum");
  ASSERT_NE(tool, nullptr);
  for (const core::HandSpec& spec : skills.profile().hands) {
    const HandGeometry hand = measure_hand(skills, spec);
    const std::vector<GraspCandidate> all =
        grasp_candidates(*tool, hand, skills.frame_pose(spec.palm).position);
    ASSERT_FALSE(all.empty()) << spec.side;
    const GraspCandidate& above = all.front();
    ASSERT_LT(above.approach.z(), -0.99) << spec.side << " " << above.id;
    const GraspCandidate::Placement at = above.place(hand, 0.01);
    const Eigen::Quaterniond to_palm = at.pose.orientation.conjugate();
    const Eigen::Vector3d centre = to_palm * (above.centre - at.pose.position);
    const Eigen::Vector3d axis = to_palm * above.free_axis;
    const std::vector<Eigen::Vector3d> stopped = hand.swept_points(centre, axis, above.width_m / 2);
    EXPECT_LT(stopped.size(), hand.swept_points(centre, axis, 0).size())
        << spec.side << ": no finger stops on the handle";
    auto over_table = [&](const core::Pose& pose) {
      double z = INFINITY;
      for (const Eigen::Vector3d& p : stopped) {
        z = std::min(z, (pose.position + pose.orientation * p).z());
      }
      return z - above.support_z;
    };
    EXPECT_GT(over_table(at.pose), 0.005) << spec.side;
    double deepest = INFINITY;
    for (double turn : {M_PI / 2, -M_PI / 2}) {
      const Eigen::AngleAxisd r(turn, above.free_axis);
      core::Pose turned;
      turned.orientation = r * at.pose.orientation;
      turned.position = above.centre + r * (at.pose.position - above.centre);
      deepest = std::min(deepest, over_table(turned));
    }
    EXPECT_LT(deepest, 0.0) << spec.side;
  }
}

// Seen along the handle (x), two fingers from a palm below it whose tips meet above it ring it;
// the same fingers short of meeting, or all beside it, do not.
TEST(RingedHandle, OnlyPointsAllRoundTheHandleRingIt) {
  Handle handle;
  handle.centre = {0.3, 0.1, 0.8};
  handle.axis = Eigen::Vector3d::UnitX();
  auto at = [&](double y, double z) {
    return Eigen::Vector3d(handle.centre + Eigen::Vector3d(0.01, y, z));
  };
  // Finger bases either side of the palm, middle segments beside the handle, tips above it.
  const std::vector<Eigen::Vector3d> meeting = {at(-0.04, -0.03), at(-0.03, 0.01), at(-0.005, 0.03),
                                                at(0.04, -0.03),  at(0.03, 0.01),  at(0.005, 0.03)};
  EXPECT_TRUE(rings(handle, meeting));
  // The tips still beside the handle: the half-plane above it is open.
  const std::vector<Eigen::Vector3d> open = {at(-0.04, -0.03), at(-0.03, 0.0), at(0.04, -0.03),
                                             at(0.03, 0.0)};
  EXPECT_FALSE(rings(handle, open));
  // Closed, but with the handle outside the fingers (beside the second).
  std::vector<Eigen::Vector3d> beside = meeting;
  for (Eigen::Vector3d& p : beside) p.y() += 0.06;
  EXPECT_FALSE(rings(handle, beside));
  // Along the axis the points do not matter.
  std::vector<Eigen::Vector3d> along = meeting;
  for (Eigen::Vector3d& p : along) p.x() += 0.2;
  EXPECT_TRUE(rings(handle, along));
}

// An object of primitive shapes standing on a table at z = 0.7, at (0.5, 0.3).
core::PerceivedObject object_of(const std::vector<core::Shape>& shapes) {
  core::PerceivedObject o;
  o.id = "thing";
  o.type = "graspable";
  o.pose.position = {0.5, 0.3, 0.75};
  o.shapes = shapes;
  o.box.setEmpty();
  for (const core::Shape& s : shapes) o.box.extend(s.bounds());
  return o;
}

core::Shape shape(core::Shape::Type type, const Eigen::Vector3d& at, const Eigen::Vector3d& size) {
  core::Shape s;
  s.type = type;
  s.pose.position = at;
  s.size = size;
  return s;
}

// A mug 9 cm across, its handle sticking out 3 cm towards +x: tallbot's hand (80 mm between its
// fingers) spans no grasp of the whole mug (before: `not_graspable`) but closes round the handle,
// coming at it from outside towards the mug's middle (straight, or obliquely, 0.6 rad from
// either side), the fingers across its 12 mm: fallback grasps, the only ones here.
TEST(GraspCandidatesOfAMug, AHandTooSmallForTheMugHoldsItByTheHandle) {
  mujoco::MujocoSkillset skills(test::scene("tallbot", "kitchen"));
  const core::HandSpec& spec = skills.profile().hands.front();
  const HandGeometry hand = measure_hand(skills, spec);
  ASSERT_LT(hand.aperture_m, 0.09);
  const core::PerceivedObject mug =
      object_of({shape(core::Shape::Type::kCylinder, {0.5, 0.3, 0.75}, {0.045, 0.05, 0}),
                 shape(core::Shape::Type::kBox, {0.56, 0.3, 0.75}, {0.015, 0.006, 0.03})});
  const std::vector<GraspCandidate> all = grasp_candidates(mug, hand, {0.0, 0.3, 1.0});
  ASSERT_EQ(all.size(), 6u);
  for (const GraspCandidate& c : all) {
    EXPECT_EQ(c.family, "part") << c.id;
    EXPECT_TRUE(c.fallback) << c.id;
    EXPECT_LT((c.centre - Eigen::Vector3d(0.56, 0.3, 0.75)).norm(), 1e-9) << c.id;
    EXPECT_GT(c.approach.dot(-Eigen::Vector3d::UnitX()), std::cos(0.6) - 1e-9) << c.id;
    EXPECT_NEAR(c.approach.z(), 0, 1e-9) << c.id;
    EXPECT_LT(c.width_m, 0.03) << c.id;
  }
  EXPECT_NEAR(all.front().approach.x(), -1, 1e-9) << "straight in first";
  // A hand wide enough for the whole mug grasps the whole first, the handle after.
  HandGeometry wide = hand;
  wide.aperture_m = 0.2;
  const std::vector<GraspCandidate> wider = grasp_candidates(mug, wide, {0.0, 0.3, 1.0});
  ASSERT_GT(wider.size(), 6u);
  EXPECT_NE(wider.front().family, "part");
  // (The mug's body beside the handle is a part too: it sticks out the other way.)
  EXPECT_EQ(std::count_if(
                wider.begin(), wider.end(),
                [](const GraspCandidate& c) { return c.family == "part" && c.centre.x() > 0.55; }),
            6);
  // A juice box with its straw inside its outline has no part that sticks out.
  const core::PerceivedObject box =
      object_of({shape(core::Shape::Type::kBox, {0.5, 0.3, 0.76}, {0.025, 0.025, 0.06}),
                 shape(core::Shape::Type::kCapsule, {0.514, 0.311, 0.836}, {0.003, 0.02, 0})});
  for (const GraspCandidate& c : grasp_candidates(box, hand, {0.0, 0.3, 1.0})) {
    EXPECT_NE(c.family, "part") << c.id;
  }
}

// An 8 cm ball: side grasps at its middle put atlas's wrist on the table (`all in collision
// (first: l_wrist_mount touches table_top (depth 0.4 mm))`, every pickup failed; 1 cm higher
// they still did). The same side grasps 2 cm higher come after every other candidate; a 3 cm
// slab gets none (they would leave the middle half of its height).
TEST(GraspCandidatesOfABall, SideGraspsAlsoGoALittleHigherUpAfterEveryOther) {
  mujoco::MujocoSkillset skills(test::scene("tallbot", "kitchen"));
  HandGeometry hand = measure_hand(skills, skills.profile().hands.front());
  hand.aperture_m = 0.1;  // clear of the ball's width (tallbot's is 80 mm, the ball's own)
  const core::PerceivedObject ball =
      object_of({shape(core::Shape::Type::kSphere, {0.5, 0.3, 0.74}, {0.04, 0, 0})});
  const std::vector<GraspCandidate> all = grasp_candidates(ball, hand, {0.0, 0.3, 1.0});
  size_t first_raised = all.size();
  int raised = 0;
  for (size_t i = 0; i < all.size(); ++i) {
    const double up = all[i].centre.z() - 0.74;
    EXPECT_EQ(all[i].fallback, up > 1e-9) << all[i].id;
    if (up < 1e-9) {
      EXPECT_LT(i, first_raised) << all[i].id << " after a raised grasp";
      continue;
    }
    first_raised = std::min(first_raised, i);
    EXPECT_EQ(all[i].family, "side") << all[i].id;
    EXPECT_NEAR(all[i].approach.z(), 0, 1e-9) << all[i].id;
    EXPECT_NEAR(up, 0.02, 1e-9) << all[i].id;
    ++raised;
  }
  EXPECT_EQ(raised, 16);  // 8 directions round a round object, either closing sense
  const core::PerceivedObject slab =
      object_of({shape(core::Shape::Type::kBox, {0.5, 0.3, 0.715}, {0.03, 0.03, 0.015})});
  for (const GraspCandidate& c : grasp_candidates(slab, hand, {0.0, 0.3, 1.0})) {
    EXPECT_NEAR(c.centre.z(), 0.715, 1e-9) << c.id;
  }
}

// A hand like a person's, drawn in its palm frame (approach +z, closing +x): a thumb whose root
// sits 3 cm to one side of the palm frame and three fingers whose roots sit 3 cm to the other
// (an aperture of 60 mm), the roots 4 cm behind the frame; open, the fingers lie flat in the
// palm's plane, pointing away along the closing axis (the thumb the other way); closing, each
// joint turns the same angle towards the approach. `segment_m`: each finger's three segments.
HandGeometry curling_hand(double segment_m) {
  HandGeometry g;
  g.side = "right";
  g.approach = Eigen::Vector3d::UnitZ();
  g.closing = Eigen::Vector3d::UnitX();
  g.palm_depth_m = 0.04;
  g.aperture_m = 0.06;
  // One finger: its root at x = `root_x` (y across the hand), pointing along `sense` x.
  auto finger = [&](double root_x, double y, double sense) {
    std::vector<std::vector<Eigen::Vector3d>> sweep;
    for (int step = 0; step <= 8; ++step) {
      const double turn = 0.2 * step;
      std::vector<Eigen::Vector3d> points = {{root_x, y, -0.04}};
      for (int joint = 1; joint <= 3; ++joint) {
        const double angle = joint * turn;  // from the closing axis towards the approach
        points.push_back(points.back() +
                         segment_m * Eigen::Vector3d(sense * std::cos(angle), 0, std::sin(angle)));
      }
      sweep.push_back(std::move(points));
    }
    for (const Eigen::Vector3d& p : sweep.front()) g.finger_points.push_back(p);
    g.sweeps.push_back(std::move(sweep));
    ++g.fingers;
  };
  finger(-0.03, 0.0, -1.0);  // the thumb
  for (double y : {-0.02, 0.0, 0.02}) finger(0.03, y, 1.0);
  g.fingers_needed = g.fingers / 2 + 1;
  return g;
}

// A hand whose fingers' roots spread 60 mm round a 76 mm cup (a person's hand and a mug): the
// fingers curl round it from beside the palm, so the cup is graspable (before: `not_graspable:
// the right hand (aperture 60 mm) spans no grasp`). Those grasps come after any between the
// roots, in reach's second round, numbered on their own. Short fingers that meet the cup only
// on its near half would push it out of the hand: no wrap. An open finger across the cup's
// path: no wrap. (Closed round the cup from the side, the section's centre sits 8 mm ahead of
// the palm frame: its near side 1 cm off the palm, 4 cm behind the frame.)
TEST(GraspCandidatesOfACup, FingersThatCurlRoundItHoldACupWiderThanTheirRoots) {
  const HandGeometry hand = curling_hand(0.035);
  EXPECT_TRUE(hand.wraps(0.076, 0.1, 0.008));
  EXPECT_TRUE(hand.wraps(0.05, 0.1, 0.0));
  EXPECT_FALSE(hand.wraps(0.2, 0.1, 0.07)) << "wider than the curled fingers";
  const core::PerceivedObject cup =
      object_of({shape(core::Shape::Type::kCylinder, {0.5, 0.3, 0.75}, {0.038, 0.05, 0})});
  const std::vector<GraspCandidate> all = grasp_candidates(cup, hand, {0.0, 0.3, 1.0});
  ASSERT_FALSE(all.empty());
  int round_the_side = 0;  // closing horizontally round the cup's round section
  for (const GraspCandidate& c : all) {
    EXPECT_TRUE(c.fallback) << c.id;
    EXPECT_GT(c.wrap_length_m, 0) << c.id;
    EXPECT_NE(c.id.find(".w"), std::string::npos) << c.id;
    EXPECT_TRUE(c.wrapped_at(hand, 0.01)) << c.id;
    // Across the cup, or along its 10 cm height.
    EXPECT_NEAR(c.width_m, std::abs(c.closing.z()) > 0.5 ? 0.1 : 0.076, 1e-9) << c.id;
    round_the_side += c.family == "side" && std::abs(c.closing.z()) < 1e-9;
  }
  EXPECT_GT(round_the_side, 0);
  // A 50 mm cup fits between the roots: its grasps keep their ids, and as before only the side
  // grasps raised higher up are for the second round, with any wrapped ones (along its height).
  const core::PerceivedObject narrow =
      object_of({shape(core::Shape::Type::kCylinder, {0.5, 0.3, 0.75}, {0.025, 0.05, 0})});
  std::map<std::string, int> spanned;
  for (const GraspCandidate& c : grasp_candidates(narrow, hand, {0.0, 0.3, 1.0})) {
    if (c.wrap_length_m > 0) {
      EXPECT_TRUE(c.fallback) << c.id;
      continue;
    }
    EXPECT_EQ(c.fallback, c.centre.z() > 0.75 + 1e-9) << c.id;
    EXPECT_EQ(c.id, c.family + "." + std::to_string(spanned[c.family]++)) << "numbered in turn";
  }
  EXPECT_GT(spanned["side"], 0);
  // Fingers of three 15 mm segments meet the cup on its near half only.
  const HandGeometry stubby = curling_hand(0.015);
  EXPECT_FALSE(stubby.wraps(0.076, 0.1, 0.008));
  // The open thumb bent forward into where the cup goes.
  HandGeometry bent = hand;
  bent.sweeps.front().front().back() = {0.0, 0.0, 0.02};
  EXPECT_FALSE(bent.wraps(0.076, 0.1, 0.008));
}
}  // namespace
}  // namespace taskmatrix::programs
