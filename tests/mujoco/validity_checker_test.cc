#include "taskmatrix/mujoco/validity_checker.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "taskmatrix/mujoco/attachments.h"
#include "taskmatrix/mujoco/kinematics.h"
#include "taskmatrix/mujoco/mujoco_handles.h"
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
    const bool expected = reference_robot_in_collision(*scene, raw.model(), raw.data());
    ASSERT_EQ(checker.in_collision(q.data()), expected)
        << robot << " in " << env << ", sample " << s;
    collisions += expected;
  }
  // Both verdicts occur often enough for the comparison to mean something.
  EXPECT_GT(collisions, samples / 20);
  EXPECT_LT(collisions, samples - samples / 20);
}

TEST(ValidityChecker, SameVerdictsAsTheReferenceOn100kConfigurationsOfTheTallRobot) {
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

// The kitchen's visitor walks x = 2.5 from y = -1 to y = 1 and stands at its first point. A
// plan made while the visitor is at one end must not put the robot where they walk next: with
// the route kept, the robot may not stand beside any part of it; where it already stands that
// close, it may stay (a start is never made invalid).
TEST(ValidityChecker, KeepsTheRobotOffTheVisitorsRouteNotOnlyOffWhereTheVisitorStands) {
  auto scene = test::scene("minibot", "kitchen");
  WorkerScene worker(scene);
  worker.reset_to_start();
  const ChainIndex& base = scene->chain("base");
  EXPECT_GT(scene->visitor_radius(), 0.2);  // shoulders and arms round its axis
  EXPECT_LT(scene->visitor_radius(), 0.4);
  ValidityChecker plain(*scene, worker.model(), worker.data(), base.joints);
  ValidityChecker kept(*scene, worker.model(), worker.data(), base.joints);
  kept.keep_off_visitor_route();
  // 0.35 m from the route near its far end, 1.8 m from the visitor: no contact, but on it.
  const std::vector<double> beside = {2.15, 0.8, 0.0};
  EXPECT_FALSE(plain.in_collision(beside.data()));
  EXPECT_TRUE(kept.in_collision(beside.data()));
  EXPECT_NE(kept.visitor_route_hit().find("of the visitor's route"), std::string::npos)
      << kept.visitor_route_hit();
  EXPECT_TRUE(kept.within_margin(beside.data(), 0.01));
  // 1.3 m from it: free. The hit is forgotten after a clear check.
  const std::vector<double> away = {1.2, 0.8, 0.0};
  EXPECT_FALSE(kept.in_collision(away.data()));
  EXPECT_TRUE(kept.visitor_route_hit().empty());
  // Bound where the robot stands beside the route, it may stay and move along it.
  for (int i = 0; i < 3; ++i) worker.data()->qpos[base.qpos_adr[i]] = beside[i];
  ValidityChecker from_beside(*scene, worker.model(), worker.data(), base.joints);
  from_beside.keep_off_visitor_route();
  const std::vector<double> along = {2.15, 0.5, 0.3};
  EXPECT_FALSE(from_beside.in_collision(beside.data()));
  EXPECT_FALSE(from_beside.in_collision(along.data()));
}

// The clearances and per-joint reach a planned path is certified with (MotionPlanner): on both
// robots, moving base, torso and arm, holding the cup in the left hand.
class ClearanceOnBothRobots : public ::testing::TestWithParam<std::string> {};

TEST_P(ClearanceOnBothRobots, BoundHowFarTheRobotAndWhatItHoldsCanMoveWithoutTouching) {
  auto scene = test::scene(GetParam(), "kitchen");
  WorkerScene worker(scene), probe(scene);
  const core::ObstacleLayout layout = core::generate_layout(scene->layout_request(8), 5);
  worker.apply_layout(layout);
  probe.apply_layout(layout);
  worker.reset_to_start();
  probe.reset_to_start();
  const mjModel* m = worker.model();
  mjData* d = worker.data();
  // The cup in the left hand, 25 cm out from the palm along the hand's approach axis (as a
  // long tool would be: beyond the fingers).
  const int cup = mj_name2id(m, mjOBJ_BODY, "cup");
  ASSERT_GT(cup, 0);
  const core::HandSpec* hand = scene->robot().find_hand("left");
  const BodyFrame palm = resolve_frame(*scene, d, hand->palm);
  const core::Pose at = frame_pose(d, palm);
  const Eigen::Vector3d cup_at =
      at.position + at.orientation *
                        Eigen::Vector3d(hand->approach[0], hand->approach[1], hand->approach[2]) *
                        0.25;
  mju_copy3(d->qpos + m->jnt_qposadr[m->body_jntadr[cup]], cup_at.data());
  mj_forward(m, d);
  const std::vector<Attachment> held = {attachment_at(*scene, m, d, cup, palm.body, "cup", "left")};
  const Sampler sampler(*scene, {"base", "torso", "left_arm"});
  ValidityChecker checker(*scene, m, d, sampler.joints, held);
  ASSERT_FALSE(checker.static_collision());
  ASSERT_EQ(describe_robot_contacts(*scene, m, d, held), "no contact");
  const std::vector<double> reach = checker.joint_reach();
  const std::vector<std::vector<char>> groups = checker.clearance_groups();
  ASSERT_EQ(reach.size(), sampler.joints.size());
  const std::vector<char> all(groups.size(), 1);
  // Per geom, its centre and the six points where its local axes leave its bounding sphere,
  // as the probe poses them (the checker poses only what moves).
  auto sphere_points = [&](const std::vector<double>& q) {
    for (size_t i = 0; i < q.size(); ++i)
      probe.data()->qpos[probe.model()->jnt_qposadr[sampler.joints[i]]] = q[i];
    mj_kinematics(probe.model(), probe.data());
    place_attachments(probe.model(), probe.data(), held);
    mj_kinematics(probe.model(), probe.data());
    std::vector<Eigen::Vector3d> points;
    for (int g = 0; g < m->ngeom; ++g) {
      const Eigen::Vector3d c(probe.data()->geom_xpos + 3 * g);
      const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> rot(
          probe.data()->geom_xmat + 9 * g);
      points.push_back(c);
      for (int axis = 0; axis < 3; ++axis) {
        points.push_back(c + m->geom_rbound[g] * rot.col(axis));
        points.push_back(c - m->geom_rbound[g] * rot.col(axis));
      }
    }
    return points;
  };
  std::mt19937_64 rng(99);
  std::normal_distribution<double> gauss(0, 1);
  int touching = 0, advanced = 0, jumps = 0;
  for (int s = 0; s < 3000; ++s) {
    const std::vector<double> q = sampler.draw(rng);
    std::vector<double> clearances;
    ASSERT_TRUE(checker.clearances_to_contact(q.data(), 0.05, all, clearances));
    const bool in_contact =
        std::any_of(clearances.begin(), clearances.end(), [](double c) { return c < 0; });
    ASSERT_EQ(in_contact, checker.in_collision(q.data())) << GetParam() << ", sample " << s;
    touching += in_contact;
    // A step in a random direction (every other sample along one joint, so that no joint's
    // reach hides behind another's), as long as every group's clearance allows (90% of it).
    std::vector<double> dq(q.size(), 0.0);
    if (s % 2 == 0) {
      dq[static_cast<size_t>(s / 2) % dq.size()] = gauss(rng);
    } else {
      for (double& v : dq) v = gauss(rng);
    }
    double scale = 0.2;  // at most this far (rad or m) along any joint
    for (double v : dq) {
      if (v != 0) scale = std::min(scale, 0.2 / std::abs(v));
    }
    for (size_t g = 0; g < groups.size() && !in_contact; ++g) {
      double per_unit = 0;
      for (size_t i = 0; i < q.size(); ++i) per_unit += groups[g][i] * reach[i] * std::abs(dq[i]);
      if (per_unit > 0) scale = std::min(scale, 0.9 * clearances[g] / per_unit);
    }
    std::vector<double> q2(q.size());
    double bound = 0;
    for (size_t i = 0; i < q.size(); ++i) {
      q2[i] = q[i] + scale * dq[i];
      bound += reach[i] * std::abs(q2[i] - q[i]);
    }
    // No point of what moves goes farther than joint_reach says.
    const std::vector<Eigen::Vector3d> a = sphere_points(q), b = sphere_points(q2);
    for (size_t k = 0; k < a.size(); ++k) {
      ASSERT_LE((a[k] - b[k]).norm(), bound + 1e-9) << "geom " << k / 7 << ", sample " << s;
    }
    if (in_contact) continue;
    // Within its clearances the robot touches nothing, unless MuJoCo's own narrow phase jumps:
    // 2.2.2's capsule-box function reports a capsule beside a box's edge 1 cm away, then 6 cm
    // deep 0.3 mm further (a thigh under a table top), a contact deeper than the step could
    // make it.
    if (checker.in_collision(q2.data())) {
      sphere_points(q2);
      mj_collision(probe.model(), probe.data());
      double deepest = 0;
      for (int i = 0; i < probe.data()->ncon; ++i) {
        const mjContact& c = probe.data()->contact[i];
        if (counts_as_robot_collision(*scene, probe.model(), c, held))
          deepest = std::max(deepest, -c.dist);
      }
      EXPECT_GT(deepest, bound) << GetParam() << ", sample " << s << ": "
                                << describe_robot_contacts(*scene, m, d, held);
      ++jumps;
      continue;
    }
    advanced += scale > 0;
  }
  // Both cases occur often enough to mean something.
  EXPECT_GT(touching, 300);
  EXPECT_GT(advanced, 300);
  EXPECT_LE(jumps, 3);
}

TEST_P(ClearanceOnBothRobots, PairsMovedTogetherByTheBaseAreNotInTheBasesGroups) {
  auto scene = test::scene(GetParam(), "office");
  WorkerScene worker(scene);
  worker.reset_to_start();
  const Sampler sampler(*scene, {"base", "left_arm"});
  ValidityChecker checker(*scene, worker.model(), worker.data(), sampler.joints);
  const auto base_joints = static_cast<long>(scene->chain("base").joints.size());
  bool arm_only = false, with_base = false;
  for (const std::vector<char>& g : checker.clearance_groups()) {
    auto any = [](auto first, auto last) {
      return std::any_of(first, last, [](char c) { return c != 0; });
    };
    const bool base = any(g.begin(), g.begin() + base_joints);
    const bool arm = any(g.begin() + base_joints, g.end());
    arm_only = arm_only || (arm && !base);  // the arm against the rest of the robot
    with_base = with_base || base;          // the robot against the world
    // A base joint moves both geoms of a pair on the robot: only world pairs have one, and
    // then all of them.
    if (base) {
      EXPECT_TRUE(std::all_of(g.begin(), g.begin() + base_joints, [](char c) { return c != 0; }));
    }
  }
  EXPECT_TRUE(arm_only);
  EXPECT_TRUE(with_base);
}

INSTANTIATE_TEST_SUITE_P(Robots, ClearanceOnBothRobots, ::testing::Values("tallbot", "minibot"));

// A capsule (a thigh, 0.055 m radius, 0.258 m between its caps' centres) on a slide along x, a
// slide along z and a hinge about y, against a table top 4 cm thick, over a grid of poses:
// wherever the capsule overlaps the top by more than 0.1 mm (its axis measured against the top
// at 2001 points), the pair has a penetrating contact. MuJoCo 2.2.2's own
// capsule-box function reports none for 400 of these poses, every one with the axis inside the
// top (a leg through a table passed as valid, and the planner searched its iterations for a way
// to such a stance). The normal points from the capsule to the top, as MuJoCo's contacts do.
TEST(CollideGeoms, ACapsuleThroughAThinBoxTouchesItAtEveryPose) {
  const ModelPtr model = compile_mjcf_text(
      "<mujoco><worldbody>"
      "<geom name=\"top\" type=\"box\" pos=\"0 0 0.543\" size=\"0.35 0.6 0.02\"/>"
      "<body name=\"leg\"><joint type=\"slide\" axis=\"1 0 0\"/>"
      "<joint type=\"slide\" axis=\"0 0 1\"/><joint type=\"hinge\" axis=\"0 1 0\"/>"
      "<geom name=\"thigh\" type=\"capsule\" fromto=\"0 0 0.129 0 0 -0.129\" size=\"0.055\"/>"
      "</body></worldbody></mujoco>",
      "capsule_through_box");
  const mjModel* m = model.get();
  const DataPtr data = make_data(m);
  mjData* d = data.get();
  const int capsule = mj_name2id(m, mjOBJ_GEOM, "thigh"), box = mj_name2id(m, mjOBJ_GEOM, "top");
  const GeomPair pair{capsule, box, 0.0};
  int overlapping = 0, axis_inside = 0;
  for (int iz = 0; iz <= 50; ++iz) {
    for (int ix = 0; ix <= 20; ++ix) {
      for (int ip = 0; ip < 8; ++ip) {
        const double x = -0.5 + 0.05 * ix, z = 0.30 + 0.01 * iz, pitch = 0.2 * ip;
        d->qpos[0] = x;
        d->qpos[1] = z;
        d->qpos[2] = pitch;
        mj_kinematics(m, d);
        double gap = INFINITY;  // the axis's distance from the top
        for (int k = 0; k <= 2000; ++k) {
          const double t = -0.129 + 0.258 * k / 2000.0;
          const double dx = std::max(std::abs(x + t * std::sin(pitch)) - 0.35, 0.0);
          const double dz = std::max(std::abs(z + t * std::cos(pitch) - 0.543) - 0.02, 0.0);
          gap = std::min(gap, std::hypot(dx, dz));
        }
        if (gap >= 0.055 - 1e-4) continue;
        ++overlapping;
        mjContact contacts[mjMAXCONPAIR];
        const int n = collide_geoms(m, d, pair, 0.0, contacts);
        ASSERT_GT(n, 0) << "x " << x << " z " << z << " pitch " << pitch;
        double deepest = 0;
        for (int i = 0; i < n; ++i) deepest = std::min(deepest, contacts[i].dist);
        EXPECT_LT(deepest, 0.0) << "x " << x << " z " << z << " pitch " << pitch;
        axis_inside += gap == 0;
      }
    }
  }
  EXPECT_GT(overlapping, 4000);
  EXPECT_GT(axis_inside, 1000);
  // Upright through the top, its axis's upper end 5.6 cm above the top's upper face (9.6 cm
  // above its underside) and its lower end 20 cm below the upper face: it leaves the top
  // soonest downwards, so the top lies above it, 9.6 cm plus its radius deep.
  d->qpos[0] = 0;
  d->qpos[1] = 0.49;
  d->qpos[2] = 0;
  mj_kinematics(m, d);
  mjContact contacts[mjMAXCONPAIR];
  ASSERT_GT(collide_geoms(m, d, pair, 0.0, contacts), 0);
  EXPECT_GT(contacts[0].frame[2], 0.99);
  EXPECT_LT(contacts[0].dist, -0.1);
}

}  // namespace
}  // namespace taskmatrix::mujoco
