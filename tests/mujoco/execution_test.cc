// The two execution modes of the skillset and the physics' contact pruning: what a user of
// the simulation would notice (poses, contacts, where a released object ends up), on both
// robots in the kitchen.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <random>
#include <string>
#include <tuple>

#include "taskmatrix/mujoco/attachments.h"
#include "taskmatrix/mujoco/contact_pruning.h"
#include "taskmatrix/mujoco/kinematics.h"
#include "taskmatrix/mujoco/mujoco_skillset.h"
#include "taskmatrix/mujoco/physics_contacts.h"
#include "tests/test_support.h"

namespace taskmatrix::mujoco {
namespace {

using Chains = std::vector<std::string>;

std::unique_ptr<MujocoSkillset> make_skills(const std::string& robot, SimulationOptions options) {
  auto skills = std::make_unique<MujocoSkillset>(test::scene(robot, "kitchen"), options);
  skills->apply_layout(skills->scene().make_layout(8, 5));
  skills->reset();
  return skills;
}

// A collision-free configuration of the side's arm and the torso that brings the palm to
// `position` (its orientation free).
std::vector<double> palm_at(MujocoSkillset& skills, const std::string& side,
                            const Eigen::Vector3d& position) {
  const std::string palm = skills.profile().find_hand(side)->palm;
  core::Pose target = skills.frame_pose(palm);
  target.position = position;
  core::IkOptions ik;
  ik.orientation = false;
  const core::IkResult r = skills.solve_ik({side + "_arm", "torso"}, palm, target, ik);
  EXPECT_EQ(r.status, core::IkStatus::kSolved) << r.reason;
  return r.solutions.empty() ? std::vector<double>{} : r.solutions.front();
}

// The palm 18 cm above the cup.
std::vector<double> arm_over_the_cup(MujocoSkillset& skills, const std::string& side) {
  return palm_at(skills, side, skills.frame_pose("cup").position + Eigen::Vector3d(0, 0, 0.18));
}

// A planned, timed motion of the right arm and the torso to 18 cm over the cup; none (the
// failure reported) when IK or the planner fails.
const Chains kRightArmAndTorso = {"right_arm", "torso"};
std::optional<core::Trajectory> motion_over_the_cup(MujocoSkillset& skills) {
  const std::vector<double> goal = arm_over_the_cup(skills, "right");
  if (goal.empty()) return std::nullopt;
  core::PlanOptions options;
  options.time_limit_s = 10;
  const core::PlanResult plan = skills.plan_to_configuration(kRightArmAndTorso, goal, options);
  EXPECT_TRUE(plan.success()) << plan.message;
  if (!plan.success()) return std::nullopt;
  return skills.time_parameterize(kRightArmAndTorso, plan.path);
}

// The base's slide joints move the robot's root body: the base configuration that puts the
// head just short of the counter's centre, facing the way it faces now.
std::vector<double> base_against_the_counter(const MujocoSkillset& skills) {
  const core::Pose counter = skills.frame_pose("side_surface");
  const double* at = skills.sim_data()->cam_xpos + 3 * skills.scene().head_camera();
  std::vector<double> base = skills.configuration({"base"});
  base[0] += counter.position.x() - at[0];
  base[1] += counter.position.y() - 0.3 - at[1];
  return base;
}

// Plans and executes a motion of the chains to `goal`.
void move_to(MujocoSkillset& skills, const Chains& chains, const std::vector<double>& goal) {
  core::PlanOptions options;
  options.time_limit_s = 10;
  const core::PlanResult plan = skills.plan_to_configuration(chains, goal, options);
  ASSERT_TRUE(plan.success()) << plan.message;
  const core::ExecutionReport report =
      skills.execute(chains, skills.time_parameterize(chains, plan.path));
  ASSERT_TRUE(report.success()) << report.message;
}

class ExecutionOnBothRobots : public ::testing::TestWithParam<std::string> {};

TEST_P(ExecutionOnBothRobots, ClosingStaticGeomsNothingComesNearChangesNothing) {
  // The same motions with and without the static geoms' gate: bit-identical states and the same
  // contacts every period (resting objects stay awake in both, so only the gate differs). The
  // world as trials draw it: 12 obstacles from a layout and the table lowered to 0.6 m (its top
  // moves, its legs shrink), so the gate sees the layout's and the variation's geoms.
  SimulationOptions gated, plain;
  gated.pruning = {true, false};
  plain.pruning = {false, false};
  auto a = make_skills(GetParam(), gated);
  auto b = make_skills(GetParam(), plain);
  const core::SurfaceGeometry& table = *a->scene().world_geometry().surface("work_surface");
  core::TrialLayout layout;
  layout.obstacles = a->scene().make_layout(12, 5);
  layout.variation.surfaces = {{"work_surface", 0.6, 0.6 - table.height}};
  a->apply_layout(layout);
  b->apply_layout(layout);
  int slots_on = 0;
  for (const ObstacleSlot& slot : a->scene().obstacle_slots()) {
    for (int g : slot.geoms) slots_on += a->model()->geom_contype[g] != 0;
  }
  ASSERT_GT(slots_on, 0) << "the layout switched no obstacle on";
  a->set_visitor_walk(1.0);
  b->set_visitor_walk(1.0);
  const Chains& chains = kRightArmAndTorso;
  const std::optional<core::Trajectory> planned = motion_over_the_cup(*a);
  ASSERT_TRUE(planned);
  const core::Trajectory& motion = *planned;
  int fewest_closed = 1 << 30;
  long contacts = 0;
  for (int k = 0; k * a->control_period() < motion.duration() + 0.5; ++k) {
    const core::TrajectorySample s = motion.sample(k * a->control_period());
    const std::vector<double> q(s.position.data(), s.position.data() + s.position.size());
    const std::vector<double> v(s.velocity.data(), s.velocity.data() + s.velocity.size());
    a->command(chains, q, v);
    b->command(chains, q, v);
    a->advance();
    b->advance();
    fewest_closed = std::min(fewest_closed, a->pruning().closed_static_geoms());
    const mjModel* m = a->model();
    for (int i = 0; i < m->nq; ++i) {
      ASSERT_EQ(a->sim_data()->qpos[i], b->sim_data()->qpos[i]) << "qpos " << i << " period " << k;
    }
    ASSERT_EQ(a->sim_data()->ncon, b->sim_data()->ncon) << "period " << k;
    for (int c = 0; c < a->sim_data()->ncon; ++c) {
      ASSERT_EQ(a->sim_data()->contact[c].geom1, b->sim_data()->contact[c].geom1);
      ASSERT_EQ(a->sim_data()->contact[c].geom2, b->sim_data()->contact[c].geom2);
    }
    contacts += a->sim_data()->ncon;
    // Between periods the model's bits are the layout's again (queries see every obstacle).
    for (int g = 0; g < m->ngeom; ++g) {
      ASSERT_EQ(m->geom_contype[g], b->model()->geom_contype[g]) << "geom " << g;
      ASSERT_EQ(m->geom_conaffinity[g], b->model()->geom_conaffinity[g]) << "geom " << g;
    }
  }
  EXPECT_GT(contacts, 0) << "the objects rest on the table: contacts every step";
  // Far from everything movable the static geoms are closed (the walls, the window, the
  // counter, the fridge, obstacles on the floor); the table the objects rest on stays open
  // (the contacts above are the same as without the gate).
  EXPECT_GT(fewest_closed, 20);
  EXPECT_EQ(b->pruning().closed_static_geoms(), 0);
}

TEST_P(ExecutionOnBothRobots, AStaticGeomClosedBeforeTheRobotWasSetBesideItCollidesAtOnce) {
  // Three steps per period, so the static geoms' 10 ms checks fall in the middle of periods;
  // the robot is set between periods from the middle of the room to a stance pressed against
  // the counter, which nothing came near before. Gated and ungated physics must stay equal.
  SimulationOptions gated, plain;
  gated.control_rate_hz = plain.control_rate_hz = 1.0 / 0.006;
  gated.pruning = {true, false};
  plain.pruning = {false, false};
  auto a = make_skills(GetParam(), gated);
  auto b = make_skills(GetParam(), plain);
  ASSERT_EQ(std::lround(a->control_period() / a->model()->opt.timestep), 3);
  for (int k = 0; k < 7; ++k) {
    a->advance();
    b->advance();
  }
  ASSERT_GT(a->pruning().closed_static_geoms(), 20);
  const std::vector<double> base = base_against_the_counter(*a);
  a->set_configuration({"base"}, base);
  b->set_configuration({"base"}, base);
  for (int k = 0; k < 4; ++k) {
    a->advance();
    b->advance();
    ASSERT_EQ(a->sim_data()->ncon, b->sim_data()->ncon) << "period " << k;
    for (int i = 0; i < a->model()->nq; ++i) {
      ASSERT_EQ(a->sim_data()->qpos[i], b->sim_data()->qpos[i]) << "qpos " << i << " period " << k;
    }
  }
  bool touching_counter = false;
  const int counter_body = mj_name2id(a->model(), mjOBJ_BODY, "counter");
  for (int c = 0; c < a->sim_data()->ncon; ++c) {
    const mjContact& con = a->sim_data()->contact[c];
    touching_counter = touching_counter || a->model()->geom_bodyid[con.geom1] == counter_body ||
                       a->model()->geom_bodyid[con.geom2] == counter_body;
  }
  EXPECT_TRUE(touching_counter) << "the robot was not set against the counter";
}

// Every contact field mj_collision sets, compared exactly; contacts ordered by what they are.
void expect_same_contacts(const mjData* a, const mjData* b, const std::string& where) {
  ASSERT_EQ(a->ncon, b->ncon) << where;
  auto sorted = [](const mjData* d) {
    std::vector<const mjContact*> c;
    for (int i = 0; i < d->ncon; ++i) c.push_back(d->contact + i);
    std::sort(c.begin(), c.end(), [](const mjContact* x, const mjContact* y) {
      return std::tie(x->geom1, x->geom2, x->pos[0], x->pos[1], x->pos[2]) <
             std::tie(y->geom1, y->geom2, y->pos[0], y->pos[1], y->pos[2]);
    });
    return c;
  };
  const std::vector<const mjContact*> x = sorted(a), y = sorted(b);
  for (size_t i = 0; i < x.size(); ++i) {
    const mjContact &p = *x[i], &q = *y[i];
    const std::string at =
        where + ", contact of geoms " + std::to_string(p.geom1) + " and " + std::to_string(p.geom2);
    ASSERT_EQ(p.geom1, q.geom1) << at;
    ASSERT_EQ(p.geom2, q.geom2) << at;
    EXPECT_EQ(p.dist, q.dist) << at;
    EXPECT_EQ(p.dim, q.dim) << at;
    EXPECT_EQ(p.exclude, q.exclude) << at;
    EXPECT_EQ(p.includemargin, q.includemargin) << at;
    EXPECT_EQ(p.efc_address, q.efc_address) << at;
    for (int k = 0; k < 3; ++k) EXPECT_EQ(p.pos[k], q.pos[k]) << at;
    for (int k = 0; k < 9; ++k) EXPECT_EQ(p.frame[k], q.frame[k]) << at;
    for (int k = 0; k < 5; ++k) EXPECT_EQ(p.friction[k], q.friction[k]) << at;
    for (int k = 0; k < mjNREF; ++k) EXPECT_EQ(p.solref[k], q.solref[k]) << at;
    for (int k = 0; k < mjNIMP; ++k) EXPECT_EQ(p.solimp[k], q.solimp[k]) << at;
  }
}

TEST_P(ExecutionOnBothRobots, TheCandidatePairsFindTheContactsMuJoCoFinds) {
  // Along the arm's motion over the cup (objects resting on the table, the vacuum's debris on
  // the floor), then with the robot set against the counter: the physics mode's contact pass
  // finds every contact mj_collision finds, field for field, and no other (these states have
  // nothing on the floor at its plane's centre, where MuJoCo 2.2.2 doubles contacts;
  // physics_contacts_test.cc).
  auto skills = make_skills(GetParam(), SimulationOptions{});
  const mjModel* m = skills->model();
  const PhysicsContacts contacts(m);
  ASSERT_TRUE(contacts.usable());
  DataPtr mine = make_data(m), theirs = make_data(m);
  long compared = 0, with_robot = 0;
  auto compare = [&](const std::string& where) {
    mj_copyData(mine.get(), m, skills->sim_data());
    mj_copyData(theirs.get(), m, skills->sim_data());
    mj_kinematics(m, mine.get());
    mj_kinematics(m, theirs.get());
    contacts.collide(m, mine.get());
    mj_collision(m, theirs.get());
    expect_same_contacts(mine.get(), theirs.get(), where);
    compared += theirs->ncon;
    for (int c = 0; c < theirs->ncon; ++c) {
      with_robot += skills->scene().is_robot_body(m->geom_bodyid[theirs->contact[c].geom1]) ||
                    skills->scene().is_robot_body(m->geom_bodyid[theirs->contact[c].geom2]);
    }
  };
  const Chains& chains = kRightArmAndTorso;
  const std::optional<core::Trajectory> planned = motion_over_the_cup(*skills);
  ASSERT_TRUE(planned);
  const core::Trajectory& motion = *planned;
  for (int k = 0; k * skills->control_period() < motion.duration(); ++k) {
    const core::TrajectorySample s = motion.sample(k * skills->control_period());
    skills->command(chains,
                    std::vector<double>(s.position.data(), s.position.data() + s.position.size()));
    skills->advance();
    compare("period " + std::to_string(k));
  }
  // Against the counter: the robot's own contacts.
  skills->set_configuration({"base"}, base_against_the_counter(*skills));
  compare("against the counter");
  EXPECT_GT(compared, 20) << "nothing touched";
  EXPECT_GT(with_robot, 0) << "the robot touched nothing";
}

TEST_P(ExecutionOnBothRobots, RestingObjectsSleepUntilSomethingComesNear) {
  SimulationOptions options;  // physics, every pruning on
  auto skills = make_skills(GetParam(), options);
  // Standing still: the objects settle and fall asleep; contacts per step drop to the robot's
  // own (standing on nothing: none at all).
  for (int k = 0; k < 50; ++k) skills->advance();
  EXPECT_EQ(skills->pruning().sleeping(), 3) << "cup, box and vacuum";
  const long passes = skills->work().contact_passes, contacts = skills->work().contacts;
  for (int k = 0; k < 20; ++k) skills->advance();
  EXPECT_EQ(skills->work().contacts - contacts, 0)
      << "over " << skills->work().contact_passes - passes;
  const Eigen::Vector3d cup = skills->frame_pose("cup").position;
  // Reaching over the cup wakes it (and it has not moved while it slept).
  const std::vector<double> goal = arm_over_the_cup(*skills, "right");
  ASSERT_FALSE(goal.empty());
  int fewest = 3;
  core::PlanOptions plan_options;
  plan_options.time_limit_s = 10;
  const Chains chains = {"right_arm", "torso"};
  const core::PlanResult plan = skills->plan_to_configuration(chains, goal, plan_options);
  ASSERT_TRUE(plan.success()) << plan.message;
  const core::Trajectory motion = skills->time_parameterize(chains, plan.path);
  for (int k = 0; k * skills->control_period() < motion.duration(); ++k) {
    const core::TrajectorySample s = motion.sample(k * skills->control_period());
    skills->command(chains, {s.position.data(), s.position.data() + s.position.size()},
                    {s.velocity.data(), s.velocity.data() + s.velocity.size()});
    skills->advance();
    fewest = std::min(fewest, skills->pruning().sleeping());
  }
  EXPECT_LT(fewest, 3) << "nothing woke";
  EXPECT_LT((skills->frame_pose("cup").position - cup).norm(), 1e-3);
}

TEST_P(ExecutionOnBothRobots, KinematicModeSetsTheCommandedConfiguration) {
  SimulationOptions options;
  options.execution = ExecutionMode::kKinematic;
  auto skills = make_skills(GetParam(), options);
  EXPECT_EQ(skills->execution(), ExecutionMode::kKinematic);
  const Chains chains = {"right_arm", "torso"};
  const std::vector<double> goal = arm_over_the_cup(*skills, "right");
  ASSERT_FALSE(goal.empty());
  core::PlanOptions plan_options;
  plan_options.time_limit_s = 10;
  const core::PlanResult plan = skills->plan_to_configuration(chains, goal, plan_options);
  ASSERT_TRUE(plan.success()) << plan.message;
  const core::Trajectory motion = skills->time_parameterize(chains, plan.path);
  const Eigen::Vector3d cup = skills->frame_pose("cup").position;
  const double t0 = skills->time();
  for (int k = 1; k * skills->control_period() <= motion.duration() + 1e-9; ++k) {
    const core::TrajectorySample s = motion.sample(k * skills->control_period());
    const std::vector<double> q(s.position.data(), s.position.data() + s.position.size());
    skills->command(chains, q, {s.velocity.data(), s.velocity.data() + s.velocity.size()});
    skills->advance();
    ASSERT_EQ(skills->configuration(chains), q) << "period " << k;
    ASSERT_NEAR(skills->time() - t0, k * skills->control_period(), 1e-9);
  }
  // Nothing else moved; the tracking is exact; the measures are those of the physics.
  EXPECT_EQ(skills->frame_pose("cup").position, cup);
  EXPECT_GT(skills->work().path_length_joint, 0.1);
  EXPECT_GT(skills->work().path_length_ee_m, 0.05);
  EXPECT_TRUE(std::isfinite(skills->work().jerk_rms()));
  EXPECT_GT(skills->work().clearance_samples, 0);
  EXPECT_GT(skills->work().contact_passes, 0);

  // A straight, unplanned motion into the table is stopped as a collision naming both.
  std::mt19937_64 rng(12);
  const Chains arm = {"right_arm"};
  std::vector<double> into;
  std::uniform_real_distribution<double> u(0, 1);
  const core::ChainInfo& c = skills->chain("right_arm");
  for (int k = 0; k < 5000 && into.empty(); ++k) {
    std::vector<double> q;
    for (size_t i = 0; i < c.joints.size(); ++i)
      q.push_back(c.lower[i] + (c.upper[i] - c.lower[i]) * u(rng));
    if (!skills->is_valid(arm, q)) into = q;
  }
  ASSERT_FALSE(into.empty());
  const core::ExecutionReport report =
      skills->execute(arm, skills->time_parameterize(arm, {skills->configuration(arm), into}));
  EXPECT_EQ(report.status, core::ExecutionStatus::kCollision) << report.message;
  ASSERT_TRUE(report.collision.has_value());
  EXPECT_FALSE(report.collision->other.empty());
}

TEST_P(ExecutionOnBothRobots, KinematicReleaseDropsTheObjectOntoWhatIsBelow) {
  SimulationOptions options;
  options.execution = ExecutionMode::kKinematic;
  auto skills = make_skills(GetParam(), options);
  const double z_rest = skills->frame_pose("cup").position.z();
  const Chains chains = {"right_arm", "torso"};
  const std::vector<double> over = arm_over_the_cup(*skills, "right");
  ASSERT_FALSE(over.empty());
  move_to(*skills, chains, over);
  // Held 18 cm below the palm, lifted by 8 cm.
  skills->attach("cup", "right");
  const std::string palm = skills->profile().find_hand("right")->palm;
  const std::vector<double> lifted =
      palm_at(*skills, "right", skills->frame_pose(palm).position + Eigen::Vector3d(0, 0, 0.08));
  ASSERT_FALSE(lifted.empty());
  move_to(*skills, chains, lifted);
  const Eigen::Vector3d held = skills->frame_pose("cup").position;
  ASSERT_GT(held.z(), z_rest + 0.02) << "the cup was lifted";
  const std::vector<double> robot = skills->configuration(chains);
  const double t = skills->time();
  skills->detach("cup");
  // On the table again, below where it was let go, upright; the robot and the clock unchanged.
  const core::Pose cup = skills->frame_pose("cup");
  EXPECT_NEAR(cup.position.z(), z_rest, 0.01);
  EXPECT_LT(std::hypot(cup.position.x() - held.x(), cup.position.y() - held.y()), 0.05);
  EXPECT_LT((cup.orientation * Eigen::Vector3d::UnitZ()).z(), 1.0 + 1e-9);
  EXPECT_GT((cup.orientation * Eigen::Vector3d::UnitZ()).z(), 0.95);
  EXPECT_EQ(skills->configuration(chains), robot);
  EXPECT_EQ(skills->time(), t);
  // And it stays there.
  for (int k = 0; k < 20; ++k) skills->advance();
  EXPECT_LT((skills->frame_pose("cup").position - cup.position).norm(), 1e-12);
}

TEST_P(ExecutionOnBothRobots, AHeldObjectCollidesWithEverythingButTheHandHoldingIt) {
  // The cup inside the right palm and the box pushed into the cup: the physics sees the cup
  // touch the hand and the box. Held by the right hand, it touches the box only, and the right
  // hand nothing of it; after the physics step every bit is as it was before.
  const std::shared_ptr<const Scene> scene = test::scene(GetParam(), "kitchen");
  ModelPtr model(mj_copyModel(nullptr, scene->model()));
  mjModel* m = model.get();
  DataPtr data(mj_makeData(m));
  mjData* d = data.get();
  mj_forward(m, d);
  const int cup = mj_name2id(m, mjOBJ_BODY, "cup");
  const int box = mj_name2id(m, mjOBJ_BODY, "box");
  ASSERT_GT(cup, 0);
  ASSERT_GT(box, 0);
  const BodyFrame palm = resolve_frame(*scene, d, scene->robot().find_hand("right")->palm);
  double* cup_q = d->qpos + m->jnt_qposadr[m->body_jntadr[cup]];
  double* box_q = d->qpos + m->jnt_qposadr[m->body_jntadr[box]];
  mju_copy3(cup_q, d->xpos + 3 * palm.body);
  mju_copy3(box_q, cup_q);
  box_q[0] += 0.05;
  mj_forward(m, d);
  const Attachment held = attachment_at(*scene, m, d, cup, palm.body, "cup", "right");
  auto cup_contacts = [&](bool with_hand) {
    int n = 0;
    for (int i = 0; i < d->ncon; ++i) {
      const int b[2] = {m->geom_bodyid[d->contact[i].geom1], m->geom_bodyid[d->contact[i].geom2]};
      for (int s = 0; s < 2; ++s) {
        if (m->body_rootid[b[s]] != cup) continue;
        const bool hand = std::find(held.hand_bodies.begin(), held.hand_bodies.end(), b[1 - s]) !=
                          held.hand_bodies.end();
        n += hand == with_hand;
      }
    }
    return n;
  };
  ASSERT_GT(cup_contacts(true), 0) << "the cup is not in the hand";
  const int with_box = cup_contacts(false);
  ASSERT_GT(with_box, 0) << "the box does not touch the cup";

  ContactPruningOptions nothing_pruned;
  nothing_pruned.gate_static_geoms = false;
  nothing_pruned.sleep_resting_objects = false;
  ContactPruning pruning(*scene, m, nothing_pruned);
  // A layout switches an obstacle slot off after the model was compiled: it stays off.
  ASSERT_FALSE(scene->obstacle_slots().empty());
  for (int g : scene->obstacle_slots().front().geoms) {
    m->geom_contype[g] = 0;
    m->geom_conaffinity[g] = 0;
  }
  const std::vector<int> contype(m->geom_contype, m->geom_contype + m->ngeom);
  const std::vector<int> conaffinity(m->geom_conaffinity, m->geom_conaffinity + m->ngeom);
  pruning.set_held(cup, true, held.hand_bodies);
  pruning.begin(m);
  mj_forward(m, d);
  EXPECT_EQ(cup_contacts(true), 0) << "the hand still pushes on what it holds";
  EXPECT_EQ(cup_contacts(false), with_box);
  pruning.end(m);
  EXPECT_EQ(std::vector<int>(m->geom_contype, m->geom_contype + m->ngeom), contype);
  EXPECT_EQ(std::vector<int>(m->geom_conaffinity, m->geom_conaffinity + m->ngeom), conaffinity);
  // Let go: the hand touches it again.
  pruning.set_held(cup, false);
  pruning.begin(m);
  mj_forward(m, d);
  EXPECT_GT(cup_contacts(true), 0);
  pruning.end(m);
  // A model whose bits keep the box off the cup keeps it off while the cup is held.
  auto cup_box_contacts = [&] {
    int n = 0;
    for (int i = 0; i < d->ncon; ++i) {
      const int r1 = m->body_rootid[m->geom_bodyid[d->contact[i].geom1]];
      const int r2 = m->body_rootid[m->geom_bodyid[d->contact[i].geom2]];
      n += (r1 == cup && r2 == box) || (r1 == box && r2 == cup);
    }
    return n;
  };
  for (int g = 0; g < m->ngeom; ++g) {
    if (m->body_rootid[m->geom_bodyid[g]] == box && m->geom_contype[g]) {
      m->geom_contype[g] = 2;
      m->geom_conaffinity[g] = 2;
    }
  }
  mj_forward(m, d);
  ASSERT_EQ(cup_box_contacts(), 0);
  pruning.set_held(cup, true, held.hand_bodies);
  pruning.begin(m);
  mj_forward(m, d);
  EXPECT_EQ(cup_box_contacts(), 0) << "the hold let the box collide with the cup";
  EXPECT_EQ(cup_contacts(true), 0);
  pruning.end(m);
}

TEST_P(ExecutionOnBothRobots, TheVisitorTurnsRoundRatherThanWalkIntoARobotInItsWay) {
  // The robot stands on the visitor's path (x = 2.5 from y = -1 to 1 in the kitchen), the
  // visitor walks towards it at 1 m/s: it turns round short of the robot and walks back,
  // touching nothing, in both execution modes.
  for (const ExecutionMode mode : {ExecutionMode::kKinematic, ExecutionMode::kPhysics}) {
    SimulationOptions options;
    options.execution = mode;
    auto skills = std::make_unique<MujocoSkillset>(test::scene(GetParam(), "kitchen"), options);
    const double robot_y = 0.3;
    core::TrialLayout layout;
    layout.variation.robot_start = core::RobotStart{2.5, robot_y, M_PI / 2};
    skills->apply_layout(layout);
    skills->reset();
    const mjModel* m = skills->model();
    const int visitor_y = m->jnt_qposadr[mj_name2id(m, mjOBJ_JOINT, "visitor_y")];
    const std::vector<double> base = skills->configuration({"base"});
    ASSERT_NEAR(base[0], 2.5, 0.01) << to_string(mode);
    ASSERT_NEAR(base[1], robot_y, 0.01) << to_string(mode);
    skills->set_visitor_walk(1.0);
    // Where it got to, and how far back it walked after that.
    double farthest = -INFINITY, back_after = INFINITY;
    int touching = 0;
    auto walk = [&] {
      farthest = -INFINITY, back_after = INFINITY, touching = 0;
      for (int k = 0; k * skills->control_period() < 4.0; ++k) {
        skills->advance();
        const double y = -1.0 + skills->sim_data()->qpos[visitor_y];
        if (y > farthest) farthest = y, back_after = y;
        back_after = std::min(back_after, y);
        for (const core::Collision& c : skills->collisions({"base"}))
          touching += c.other == "visitor";
      }
    };
    walk();
    EXPECT_EQ(touching, 0) << to_string(mode);
    EXPECT_LT(farthest, robot_y - 0.3) << to_string(mode) << ": it walked into the robot";
    EXPECT_GT(farthest, robot_y - 1.0) << to_string(mode) << ": it turned round far away";
    EXPECT_LT(back_after, farthest - 0.3) << to_string(mode) << ": it did not walk back";
    // After a reset it walks its path from the start again, exactly as the first time.
    const double first_farthest = farthest, first_back_after = back_after;
    skills->reset();
    walk();
    EXPECT_EQ(farthest, first_farthest) << to_string(mode) << " after a reset";
    EXPECT_EQ(back_after, first_back_after) << to_string(mode) << " after a reset";
    EXPECT_EQ(touching, 0) << to_string(mode) << " after a reset";
  }
}

INSTANTIATE_TEST_SUITE_P(Robots, ExecutionOnBothRobots, ::testing::Values("tallbot", "minibot"));

}  // namespace
}  // namespace taskmatrix::mujoco
