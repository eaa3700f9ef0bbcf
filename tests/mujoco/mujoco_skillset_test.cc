// The skillset as a task program sees it: every call goes through core::Skillset, on both
// robots, and is checked against raw MuJoCo where a reference exists.
#include "taskmatrix/mujoco/mujoco_skillset.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <thread>

#include "taskmatrix/mujoco/kinematics.h"
#include "taskmatrix/mujoco/validity_checker.h"
#include "tests/test_support.h"

namespace taskmatrix::mujoco {
namespace {

using Chains = std::vector<std::string>;

std::vector<double> random_configuration(const core::Skillset& s, const Chains& chains,
                                         std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<double> q;
  for (const std::string& name : chains) {
    const core::ChainInfo& c = s.chain(name);
    for (size_t i = 0; i < c.joints.size(); ++i)
      q.push_back(c.lower[i] + (c.upper[i] - c.lower[i]) * u(rng));
  }
  return q;
}

std::vector<double> valid_configuration(core::Skillset& s, const Chains& chains,
                                        std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  for (int attempt = 0; attempt < 5000; ++attempt) {
    std::vector<double> q = random_configuration(s, chains, rng);
    if (s.is_valid(chains, q)) return q;
  }
  ADD_FAILURE() << "no valid configuration found";
  return {};
}

std::vector<double> colliding_configuration(core::Skillset& s, const Chains& chains,
                                            std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  for (int attempt = 0; attempt < 5000; ++attempt) {
    std::vector<double> q = random_configuration(s, chains, rng);
    if (!s.is_valid(chains, q)) return q;
  }
  ADD_FAILURE() << "no configuration in collision found";
  return {};
}

double max_abs_diff(const std::vector<double>& a, const std::vector<double>& b) {
  double e = 0;
  for (size_t i = 0; i < a.size(); ++i) e = std::max(e, std::abs(a[i] - b[i]));
  return e;
}

double angle_between(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  return a.angularDistance(b);
}

class SkillsetOnBothRobots : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    skills_ = std::make_unique<MujocoSkillset>(test::scene(GetParam(), "kitchen"));
    skills_->apply_layout(skills_->scene().make_layout(8, 5));
    skills_->reset();
  }
  core::Skillset& skills() { return *skills_; }
  std::unique_ptr<MujocoSkillset> skills_;
};

TEST_P(SkillsetOnBothRobots, ChainsJointsLimitsAndPosturesComeFromTheProfile) {
  const core::RobotProfile& profile = skills().profile();
  ASSERT_EQ(skills().chains().size(), profile.chains.size());
  for (const core::ChainSpec& spec : profile.chains) {
    const core::ChainInfo& c = skills().chain(spec.name);
    EXPECT_EQ(c.joints, spec.joints);
    EXPECT_EQ(c.end_effector, spec.end_effector);
    ASSERT_EQ(c.lower.size(), c.joints.size());
    for (size_t i = 0; i < c.joints.size(); ++i) EXPECT_LT(c.lower[i], c.upper[i]);
    EXPECT_EQ(c.speed.velocity, profile.speed_limits.at(spec.name).velocity);
  }
  EXPECT_THROW(skills().chain("tail"), std::invalid_argument);
  // At reset the arm is in the rest posture.
  const std::vector<double> rest = skills().posture("rest").at("left_arm");
  EXPECT_LT(max_abs_diff(skills().configuration({"left_arm"}), rest), 1e-12);
  EXPECT_THROW(skills().posture("moonwalk"), std::invalid_argument);
}

TEST_P(SkillsetOnBothRobots, ForwardKinematicsMatchesMujocoSitePoses) {
  const mjModel* m = skills_->model();
  DataPtr ref = make_data(m);
  const Chains chains = {"torso", "left_arm"};
  const std::string palm = skills().profile().find_hand("left")->palm;
  const int site = mj_name2id(m, mjOBJ_SITE, palm.c_str());
  ASSERT_GE(site, 0);
  std::mt19937_64 rng(11);
  for (int k = 0; k < 100; ++k) {
    const std::vector<double> q = random_configuration(skills(), chains, rng);
    const core::Pose pose = skills().frame_pose_at(chains, q, palm);
    // Reference: the simulation's state with the chains' qpos replaced, raw mj_kinematics.
    mju_copy(ref->qpos, skills_->sim_data()->qpos, m->nq);
    size_t i = 0;
    for (const std::string& name : chains) {
      for (int j : skills_->scene().chain(name).joints) ref->qpos[m->jnt_qposadr[j]] = q[i++];
    }
    mj_kinematics(m, ref.get());
    const double* p = ref->site_xpos + 3 * site;
    EXPECT_LT((pose.position - Eigen::Vector3d(p[0], p[1], p[2])).norm(), 1e-9);
    const double* r = ref->site_xmat + 9 * site;
    Eigen::Matrix3d rot;
    rot << r[0], r[1], r[2], r[3], r[4], r[5], r[6], r[7], r[8];
    EXPECT_LT(angle_between(pose.orientation, Eigen::Quaterniond(rot)), 1e-9);
    // Bit for bit the whole model's kinematics composed with the site's offset (frame_pose_at
    // computes only the bodies between the world and the palm).
    const core::Pose whole =
        frame_pose(ref.get(), resolve_frame(skills_->scene(), ref.get(), palm));
    EXPECT_EQ(pose.position, whole.position);
    EXPECT_EQ(pose.orientation.coeffs(), whole.orientation.coeffs());
  }
  // The current pose is the simulation's.
  const double* p = skills_->sim_data()->site_xpos + 3 * site;
  EXPECT_LT((skills().frame_pose(palm).position - Eigen::Vector3d(p[0], p[1], p[2])).norm(), 1e-12);
  EXPECT_THROW(skills().frame_pose("no_such_frame"), std::invalid_argument);
}

TEST_P(SkillsetOnBothRobots, IkReachesSampledPosesAndReportsUnreachableOnes) {
  const Chains chains = {"right_arm"};
  const std::string palm = skills().profile().find_hand("right")->palm;
  int solved = 0;
  const int trials = 20;
  for (int k = 0; k < trials; ++k) {
    const std::vector<double> q = valid_configuration(skills(), chains, 300 + k);
    const core::Pose target = skills().frame_pose_at(chains, q, palm);
    core::IkOptions options;
    options.seed = static_cast<std::uint64_t>(k + 1);
    const core::IkResult r = skills().solve_ik(chains, palm, target, options);
    if (r.status != core::IkStatus::kSolved) continue;
    ++solved;
    const core::Pose reached = skills().frame_pose_at(chains, r.solutions.front(), palm);
    EXPECT_LT((reached.position - target.position).norm(), 1e-3);
    EXPECT_LT(angle_between(reached.orientation, target.orientation), 0.0175);
    EXPECT_TRUE(skills().is_valid(chains, r.solutions.front()));
  }
  EXPECT_GE(solved, trials * 8 / 10);

  core::Pose far = skills().frame_pose(palm);
  far.position += Eigen::Vector3d(3.0, 0, 0);
  core::IkOptions quick;
  quick.restarts = 5;
  const core::IkResult r = skills().solve_ik(chains, palm, far, quick);
  EXPECT_EQ(r.status, core::IkStatus::kUnreachable) << r.reason;
  EXPECT_TRUE(r.solutions.empty());
  core::PlanOptions plan;
  plan.time_limit_s = 1;
  const core::PlanResult p = skills().plan_to_poses(chains, palm, {far}, plan, quick);
  EXPECT_EQ(p.status, core::PlanStatus::kIkFailure) << p.message;
  EXPECT_NE(p.message.find("no target pose has an IK solution"), std::string::npos);
  // A summary (how many poses, how close the best came); every attempt is in the detail.
  EXPECT_NE(p.message.find("1 pose tried (1 unreachable, 0 with every solution in collision)"),
            std::string::npos)
      << p.message;
  EXPECT_NE(p.message.find("the closest, pose 0, ended "), std::string::npos) << p.message;
  EXPECT_EQ(p.detail.rfind("pose 0: unreachable (", 0), 0u) << p.detail;
  EXPECT_EQ(p.plan_calls, 0);
  EXPECT_GT(p.ik_time_s, 0);
}

TEST_P(SkillsetOnBothRobots, IkStopsEarlyAndCountsEveryCall) {
  const Chains chains = {"right_arm"};
  const std::string palm = skills().profile().find_hand("right")->palm;
  // Beyond the arm's reach from its first joint: answered without iterating.
  core::Pose far = skills().frame_pose(palm);
  far.position += Eigen::Vector3d(2.0, 0, 0);
  const core::IkResult out = skills().solve_ik(chains, palm, far, {});
  EXPECT_EQ(out.status, core::IkStatus::kUnreachable);
  EXPECT_EQ(out.iterations, 0);
  EXPECT_NE(out.reason.find("out of reach"), std::string::npos) << out.reason;
  // Where the palm is, turned upside down: within reach, and (unless the arm can turn it)
  // starts stop when their error stalls, long before their 150 iterations.
  core::Pose behind = skills().frame_pose(palm);
  behind.orientation =
      Eigen::Quaterniond(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitY())) * behind.orientation;
  core::IkOptions stalling, patient;
  patient.stall_iterations = 0;
  const core::IkResult quick = skills().solve_ik(chains, palm, behind, stalling);
  const core::IkResult slow = skills().solve_ik(chains, palm, behind, patient);
  EXPECT_EQ(quick.status, slow.status) << quick.reason << " / " << slow.reason;
  if (slow.status != core::IkStatus::kSolved) {
    EXPECT_EQ(slow.iterations, (patient.restarts + 1) * patient.max_iterations);
    EXPECT_LT(quick.iterations * 3, slow.iterations);
  }
  // Reachable targets are solved either way, from the start nearest the current configuration.
  for (int k = 0; k < 5; ++k) {
    const std::vector<double> q = valid_configuration(skills(), chains, 500 + k);
    const core::Pose target = skills().frame_pose_at(chains, q, palm);
    const core::IkResult a = skills().solve_ik(chains, palm, target, stalling);
    ASSERT_EQ(a.status, core::IkStatus::kSolved) << a.reason;
  }
  // Every IK solve is counted, the ones inside plan_to_poses too.
  const int before = skills_->work().ik_calls;
  core::PlanOptions plan;
  plan.time_limit_s = 5;
  skills().plan_to_poses(chains, palm, {far, far, far}, plan, {});
  EXPECT_EQ(skills_->work().ik_calls, before + 3);
}

// The stance search's IK: the base placed at a start of its own and held there (weight 0)
// while the torso and arm solve; a reachable target is reached with the base exactly where it
// was put, and bad starts and weights are refused naming the joint.
TEST_P(SkillsetOnBothRobots, IkHoldsWeightlessJointsAtTheirStart) {
  const Chains chains = {"base", "torso", "right_arm"};
  const std::string palm = skills().profile().find_hand("right")->palm;
  std::vector<double> q = valid_configuration(skills(), {"torso", "right_arm"}, 700);
  q.insert(q.begin(), {-0.8, 0.4, 1.0});  // a base pose 0.9 m behind the current one
  const core::Pose target = skills().frame_pose_at(chains, q, palm);
  core::IkOptions held;
  held.collision_free = false;
  held.start = skills().configuration(chains);
  std::copy(q.begin(), q.begin() + 3, held.start.begin());
  held.joint_weights.assign(q.size(), 1.0);
  std::fill(held.joint_weights.begin(), held.joint_weights.begin() + 3, 0.0);
  const core::IkResult r = skills().solve_ik(chains, palm, target, held);
  ASSERT_EQ(r.status, core::IkStatus::kSolved) << r.reason;
  for (int i = 0; i < 3; ++i) EXPECT_EQ(r.solutions.front()[i], q[i]) << "base joint " << i;
  const core::Pose reached = skills().frame_pose_at(chains, r.solutions.front(), palm);
  EXPECT_LT((reached.position - target.position).norm(), 1e-3);
  // Without the start the base stays where it is, and the arm cannot get there.
  core::IkOptions from_here = held;
  from_here.start.clear();
  from_here.restarts = 3;
  const core::IkResult stuck = skills().solve_ik(chains, palm, target, from_here);
  EXPECT_NE(stuck.status, core::IkStatus::kSolved)
      << "the target was meant to need the base where the start puts it";

  core::IkOptions bad = held;
  bad.joint_weights[4] = -1;
  core::IkResult refused = skills().solve_ik(chains, palm, target, bad);
  EXPECT_EQ(refused.status, core::IkStatus::kInvalidInput);
  EXPECT_NE(refused.reason.find("is negative"), std::string::npos) << refused.reason;
  bad = held;
  bad.start.pop_back();
  refused = skills().solve_ik(chains, palm, target, bad);
  EXPECT_EQ(refused.status, core::IkStatus::kInvalidInput);
  EXPECT_NE(refused.reason.find("IK start has"), std::string::npos) << refused.reason;
  bad = held;
  bad.start[0] = NAN;
  refused = skills().solve_ik(chains, palm, target, bad);
  EXPECT_NE(refused.reason.find("not finite"), std::string::npos) << refused.reason;
}

TEST_P(SkillsetOnBothRobots, SeveralTargetPosesAreTriedInTurn) {
  const Chains chains = {"left_arm"};
  const std::string palm = skills().profile().find_hand("left")->palm;
  const std::vector<double> q = valid_configuration(skills(), chains, 77);
  const core::Pose reachable = skills().frame_pose_at(chains, q, palm);
  core::Pose unreachable = reachable;
  unreachable.position.z() += 3.0;
  core::IkOptions ik;
  ik.restarts = 10;
  ik.max_solutions = 3;
  core::PlanOptions options;
  options.time_limit_s = 10;
  const core::PlanResult r =
      skills().plan_to_poses(chains, palm, {unreachable, reachable}, options, ik);
  ASSERT_TRUE(r.success()) << core::to_string(r.status) << ": " << r.message;
  EXPECT_EQ(r.goal_index, 1);
  EXPECT_EQ(r.plan_calls, 1);
  const core::Pose end = skills().frame_pose_at(chains, r.path.back(), palm);
  EXPECT_LT((end.position - reachable.position).norm(), 1e-3);
}

TEST_P(SkillsetOnBothRobots, StartInCollisionIsInvalidStartNeverTimeoutOrSuccess) {
  auto* backend = skills_.get();
  const Chains chains = {"left_arm"};
  const std::vector<double> colliding = colliding_configuration(skills(), chains, 5);
  ASSERT_FALSE(colliding.empty());
  const std::vector<double> goal = valid_configuration(skills(), chains, 8);
  backend->set_configuration(chains, colliding);
  core::PlanOptions options;
  options.time_limit_s = 2;
  const core::PlanResult r = skills().plan_to_configuration(chains, goal, options);
  EXPECT_EQ(r.status, core::PlanStatus::kInvalidStart) << r.message;
  EXPECT_TRUE(r.path.empty());
}

TEST_P(SkillsetOnBothRobots, GoalInCollisionIsInvalidGoal) {
  const Chains chains = {"right_arm"};
  const std::vector<double> colliding = colliding_configuration(skills(), chains, 6);
  core::PlanOptions options;
  options.time_limit_s = 2;
  const core::PlanResult r = skills().plan_to_configuration(chains, colliding, options);
  EXPECT_EQ(r.status, core::PlanStatus::kInvalidGoal) << r.message;
  // It says what the goal touches, as a start in collision does: "A touches B (depth ...)".
  EXPECT_NE(r.message.find("the goal configuration is in collision: "), std::string::npos)
      << r.message;
  EXPECT_NE(r.message.find(" touches "), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("mm)"), std::string::npos) << r.message;
}

// IK that converges only into collision says what the first such solution touches.
TEST_P(SkillsetOnBothRobots, IkSolutionsOnlyInCollisionNameTheFirstContact) {
  const Chains chains = {"right_arm"};
  const std::string palm = skills().profile().find_hand("right")->palm;
  const std::vector<double> colliding = colliding_configuration(skills(), chains, 6);
  ASSERT_FALSE(colliding.empty());
  core::IkOptions options;
  options.start = colliding;  // converges at once, there
  options.restarts = 0;
  const core::IkResult r =
      skills().solve_ik(chains, palm, skills().frame_pose_at(chains, colliding, palm), options);
  EXPECT_EQ(r.status, core::IkStatus::kInCollision) << r.reason;
  EXPECT_NE(r.reason.find("1 solutions found, all in collision (first: "), std::string::npos)
      << r.reason;
  EXPECT_NE(r.reason.find(" touches "), std::string::npos) << r.reason;
  EXPECT_NE(r.reason.find("mm))"), std::string::npos) << r.reason;
  EXPECT_EQ(r.reason.find(';'), std::string::npos) << r.reason;  // one contact
}

TEST_P(SkillsetOnBothRobots, NanAndOutOfLimitInputsAreRejectedWithTheJointNamed) {
  const Chains chains = {"left_arm"};
  const core::ChainInfo& arm = skills().chain("left_arm");
  std::vector<double> q = skills().configuration(chains);
  std::vector<double> nan_q = q;
  nan_q[1] = NAN;
  try {
    skills().is_valid(chains, nan_q);
    ADD_FAILURE() << "NaN accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'" + arm.joints[1] + "' is not finite"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(skills().command(chains, nan_q), std::invalid_argument);
  EXPECT_THROW(skills().is_valid(chains, {0.0}), std::invalid_argument);
  EXPECT_THROW(skills().is_valid({"tail"}, q), std::invalid_argument);

  std::vector<double> beyond = q;
  beyond[2] = arm.upper[2] + 0.5;
  EXPECT_FALSE(skills().is_valid(chains, beyond));
  try {
    skills().command(chains, beyond);
    ADD_FAILURE() << "out-of-limit command accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("joint '" + arm.joints[2] + "' is outside its limits"),
              std::string::npos)
        << e.what();
  }
  core::PlanOptions options;
  core::PlanResult r = skills().plan_to_configuration(chains, beyond, options);
  EXPECT_EQ(r.status, core::PlanStatus::kInvalidInput);
  EXPECT_NE(r.message.find(arm.joints[2]), std::string::npos) << r.message;
  r = skills().plan_to_configuration(chains, nan_q, options);
  EXPECT_EQ(r.status, core::PlanStatus::kInvalidInput);
  EXPECT_NE(r.message.find("not finite"), std::string::npos) << r.message;

  core::Pose bad;
  bad.position.x() = NAN;
  const std::string palm = skills().profile().find_hand("left")->palm;
  EXPECT_EQ(skills().solve_ik(chains, palm, bad, {}).status, core::IkStatus::kInvalidInput);
  EXPECT_EQ(skills().plan_to_poses(chains, palm, {bad}, options, {}).status,
            core::PlanStatus::kInvalidInput);
  // Nothing moved.
  EXPECT_EQ(skills().configuration(chains), q);
}

TEST_P(SkillsetOnBothRobots, AJointAHairPastItsLimitIsHeldAtTheLimitNeverRejected) {
  const Chains chains = {"left_arm"};
  const core::ChainInfo& arm = skills().chain("left_arm");
  std::vector<double> q = skills().configuration(chains);
  // Rounding on a limit's value is clamped; anything further is the caller's error.
  q[2] = arm.upper[2] + 1e-7;
  EXPECT_NO_THROW(skills().command(chains, q));
  q[2] = arm.upper[2] + 1e-4;
  EXPECT_THROW(skills().command(chains, q), std::invalid_argument);

  // The joint settled 0.1 mrad past its limit (a soft limit): holding it where it is commands
  // the limit.
  const mjModel* m = skills_->model();
  mjData* d = const_cast<mjData*>(skills_->sim_data());
  const int joint = mj_name2id(m, mjOBJ_JOINT, arm.joints[2].c_str());
  d->qpos[m->jnt_qposadr[joint]] = arm.upper[2] + 1e-4;
  mj_forward(m, d);
  EXPECT_GT(skills().configuration(chains)[2], arm.upper[2]);
  const std::vector<double> hold = skills().clamped_configuration(chains);
  EXPECT_EQ(hold[2], arm.upper[2]);
  EXPECT_THROW(skills().command(chains, skills().configuration(chains)), std::invalid_argument);
  EXPECT_NO_THROW(skills().command(chains, hold));
}

TEST_P(SkillsetOnBothRobots, QueriesNeverDisturbTheSimulation) {
  const mjModel* m = skills_->model();
  const std::vector<double> qpos(skills_->sim_data()->qpos, skills_->sim_data()->qpos + m->nq);
  const double t = skills().time();
  const Chains chains = {"torso", "right_arm"};
  const std::vector<double> goal = valid_configuration(skills(), chains, 21);
  skills().plan_to_configuration(chains, goal, {});
  skills().solve_ik({"right_arm"}, skills().profile().find_hand("right")->palm,
                    skills().frame_pose("cup"), {});
  skills().clearance(chains, goal, 0.5);
  skills().frame_pose_at(chains, goal, "cup");
  EXPECT_EQ(std::vector<double>(skills_->sim_data()->qpos, skills_->sim_data()->qpos + m->nq),
            qpos);
  EXPECT_EQ(skills().time(), t);
}

// The left hand sent 1.5 cm down into the table (touching it allowed, no stop on contact): the
// table stops the arm short of its goal, and the tracking error names the joint furthest from
// where it was sent, where it is and where it was sent.
TEST_P(SkillsetOnBothRobots, ATrackingErrorNamesTheJointThatFellShort) {
  const Chains chains = {"torso", "left_arm"};
  const std::string palm = skills().profile().find_hand("left")->palm;
  core::Pose target = skills().frame_pose("cup");
  target.orientation = skills().frame_pose(palm).orientation;
  target.position.z() -= 0.065;  // the cup's centre is 5 cm above the top
  core::IkOptions ik;
  ik.collision_free = false;
  ik.orientation = false;
  ik.restarts = 60;
  const core::IkResult r = skills().solve_ik(chains, palm, target, ik);
  ASSERT_FALSE(r.solutions.empty()) << r.reason;
  const core::Trajectory trajectory = skills().time_parameterize(
      chains, {skills().configuration(chains), r.solutions.front()}, 0.5);
  core::ExecutionOptions options;
  options.stop_on_collision = false;
  options.may_touch = {"work_surface", "cup"};
  const core::ExecutionReport report = skills().execute(chains, trajectory, options);
  ASSERT_EQ(report.status, core::ExecutionStatus::kTrackingError) << report.message;
  const std::vector<std::string>& torso = skills().chain("torso").joints;
  const std::vector<std::string>& arm = skills().chain("left_arm").joints;
  bool named = false;
  for (const std::vector<std::string>* joints : {&torso, &arm}) {
    for (const std::string& j : *joints) {
      named = named || report.message.find("(joint '" + j + "' at ") != std::string::npos;
    }
  }
  EXPECT_TRUE(named) << report.message;
  EXPECT_NE(report.message.find(", sent to "), std::string::npos) << report.message;
}

TEST_P(SkillsetOnBothRobots, PlannedArmMotionExecutesWithinSpeedLimitsAndTracks) {
  const Chains chains = {"left_arm"};
  const std::vector<double> goal = valid_configuration(skills(), chains, 31);
  core::PlanOptions options;
  options.time_limit_s = 10;
  const core::PlanResult plan = skills().plan_to_configuration(chains, goal, options);
  ASSERT_TRUE(plan.success()) << plan.message;
  const core::Trajectory trajectory = skills().time_parameterize(chains, plan.path);
  const double t0 = skills().time();
  const core::ExecutionReport report = skills().execute(chains, trajectory);
  ASSERT_EQ(report.status, core::ExecutionStatus::kCompleted) << report.message;
  EXPECT_LT(report.final_error, 0.02);
  EXPECT_LT(report.max_tracking_error, 0.05);
  EXPECT_GE(report.duration_s, trajectory.duration() - 1e-9);
  EXPECT_NEAR(skills().time() - t0, report.duration_s, 1e-9);
  EXPECT_LT(max_abs_diff(skills().configuration(chains), goal), 0.02);
  // Other chains held still.
  EXPECT_LT(
      max_abs_diff(skills().configuration({"right_arm"}), skills().posture("rest").at("right_arm")),
      0.02);
}

TEST_P(SkillsetOnBothRobots, ExecutedJointVelocitiesStayNearTheirLimits) {
  const Chains chains = {"right_arm"};
  const std::vector<double> start = skills().configuration(chains);
  const core::ChainInfo& arm = skills().chain("right_arm");
  std::vector<double> goal;
  for (double step : {-0.8, 0.8}) {  // swing the shoulder's first joint whichever way is free
    std::vector<double> q = start;
    q[0] = std::clamp(start[0] + step, arm.lower[0], arm.upper[0]);
    if (goal.empty() && std::abs(q[0] - start[0]) > 0.7 && skills().is_valid(chains, q)) goal = q;
  }
  ASSERT_FALSE(goal.empty());
  const core::Trajectory trajectory = skills().time_parameterize(chains, {start, goal});
  const int dof = skills_->model()->jnt_dofadr[skills_->scene().chain("right_arm").joints[0]];
  double peak = 0;
  const double period = skills().control_period();
  for (double t = period; t <= trajectory.duration() + 0.3; t += period) {
    const core::TrajectorySample s = trajectory.sample(t);
    skills().command(chains, {s.position.data(), s.position.data() + s.position.size()},
                     {s.velocity.data(), s.velocity.data() + s.velocity.size()});
    ASSERT_FALSE(skills().advance().unstable);
    peak = std::max(peak, std::abs(skills_->sim_data()->qvel[dof]));
  }
  EXPECT_GT(peak, 0.5 * arm.speed.velocity);
  EXPECT_LT(peak, 1.15 * arm.speed.velocity);
}

TEST_P(SkillsetOnBothRobots, LocomotionMovesTheRobotOnlyThroughTheBaseJoints) {
  const Chains base = {"base"};
  const std::vector<double> start = skills().configuration(base);
  const std::string palm = skills().profile().find_hand("left")->palm;
  const core::Pose palm_before = skills().frame_pose(palm);
  // Turn in place and step sideways, a goal the planner has to check against the room.
  std::vector<double> goal = {start[0] - 0.15, start[1] + 0.2, start[2] + 0.4};
  ASSERT_TRUE(skills().is_valid(base, goal));
  core::PlanOptions options;
  options.time_limit_s = 10;
  const core::PlanResult plan = skills().plan_to_configuration(base, goal, options);
  ASSERT_TRUE(plan.success()) << plan.message;
  const core::ExecutionReport report =
      skills().execute(base, skills().time_parameterize(base, plan.path));
  ASSERT_TRUE(report.success()) << report.message;
  EXPECT_LT(max_abs_diff(skills().configuration(base), goal), 0.02);
  // The palm moved rigidly with the base: its pose relative to the base frame is unchanged.
  const core::Pose palm_after = skills().frame_pose(palm);
  auto to_base = [](const std::vector<double>& b, const Eigen::Vector3d& p) {
    const Eigen::Vector2d d(p.x() - b[0], p.y() - b[1]);
    return Eigen::Vector3d(std::cos(b[2]) * d.x() + std::sin(b[2]) * d.y(),
                           -std::sin(b[2]) * d.x() + std::cos(b[2]) * d.y(), p.z());
  };
  EXPECT_LT((to_base(start, palm_before.position) -
             to_base(skills().configuration(base), palm_after.position))
                .norm(),
            0.01);
}

// Stopped at the first contact of an unplanned motion, the arm is invalid, but valid where
// `may_touch` names what it touches (as a plan may start against it); a name the world lacks
// is refused.
TEST_P(SkillsetOnBothRobots, IsValidLetsTheArmTouchWhatMayTouchNames) {
  const Chains chains = {"right_arm"};
  const std::vector<double> into = colliding_configuration(skills(), chains, 12);
  ASSERT_FALSE(into.empty());
  const core::ExecutionReport report = skills().execute(
      chains, skills().time_parameterize(chains, {skills().configuration(chains), into}));
  ASSERT_EQ(report.status, core::ExecutionStatus::kCollision) << report.message;
  ASSERT_TRUE(report.collision.has_value());
  const std::vector<double> at = skills().clamped_configuration(chains);
  EXPECT_FALSE(skills().is_valid(chains, at)) << report.message;
  EXPECT_TRUE(skills().is_valid(chains, at, {report.collision->other})) << report.message;
  EXPECT_THROW(skills().is_valid(chains, at, {"no_such_object"}), std::invalid_argument);
}

TEST_P(SkillsetOnBothRobots, ExecutingAnUnplannedMotionIntoContactIsACollision) {
  const Chains chains = {"right_arm"};
  // A straight line to a configuration in collision, not planned: execution must stop and
  // name what touched.
  std::mt19937_64 rng(12);
  std::vector<double> into;
  for (int k = 0; k < 5000 && into.empty(); ++k) {
    std::vector<double> q = random_configuration(skills(), chains, rng);
    if (!skills().is_valid(chains, q)) into = q;
  }
  ASSERT_FALSE(into.empty());
  const core::Trajectory straight =
      skills().time_parameterize(chains, {skills().configuration(chains), into});
  const core::ExecutionReport report = skills().execute(chains, straight);
  EXPECT_EQ(report.status, core::ExecutionStatus::kCollision) << report.message;
  ASSERT_TRUE(report.collision.has_value());
  EXPECT_FALSE(report.collision->robot_part.empty());
  EXPECT_FALSE(report.collision->other.empty());
  EXPECT_NE(report.message.find(report.collision->robot_part), std::string::npos);
}

TEST_P(SkillsetOnBothRobots, AHeldObjectMovesWithTheHandAndIsCheckedAsPartOfTheRobot) {
  const std::string palm = skills().profile().find_hand("left")->palm;
  skills().attach("cup", "left");
  EXPECT_EQ(skills().attached_objects(), std::vector<std::string>{"cup"});
  EXPECT_THROW(skills().attach("cup", "right"), std::invalid_argument);
  EXPECT_THROW(skills().attach("work_surface", "right"), std::invalid_argument);

  // Verdicts with the cup held agree with raw MuJoCo (cup moved to the hand, contacts with the
  // hand and, within 5 mm, with the surface it stood on ignored), and differ from verdicts
  // without it: the cup matters.
  const Chains chains = {"torso", "left_arm"};
  const mjModel* m = skills_->model();
  DataPtr ref = make_data(m);
  std::vector<int> joints;
  for (const std::string& c : chains)
    for (int j : skills_->scene().chain(c).joints) joints.push_back(j);
  std::mt19937_64 rng(3);
  int differ = 0, invalid = 0;
  const int samples = 2000;
  for (int k = 0; k < samples; ++k) {
    const std::vector<double> q = random_configuration(skills(), chains, rng);
    const bool valid = skills().is_valid(chains, q);
    mju_copy(ref->qpos, skills_->sim_data()->qpos, m->nq);
    for (size_t i = 0; i < joints.size(); ++i) ref->qpos[m->jnt_qposadr[joints[i]]] = q[i];
    ASSERT_EQ(valid,
              !raw_robot_in_collision(skills_->scene(), m, ref.get(), skills_->attachments()))
        << "sample " << k;
    ValidityChecker bare(skills_->scene(), m, ref.get(), joints);
    const bool valid_without = !bare.in_collision(q.data());
    differ += valid != valid_without;
    invalid += !valid;
  }
  EXPECT_GT(differ, samples / 100) << "the held cup never changed a verdict";
  EXPECT_LT(invalid, samples);

  // Executing an arm motion carries the cup: its pose relative to the palm is unchanged.
  const auto relative = [&]() {
    const core::Pose p = skills().frame_pose(palm), c = skills().frame_pose("cup");
    return std::make_pair(p.orientation.conjugate() * (c.position - p.position),
                          p.orientation.conjugate() * c.orientation);
  };
  const auto before = relative();
  const Chains arm = {"left_arm"};
  const std::vector<double> goal = valid_configuration(skills(), arm, 41);
  core::PlanOptions options;
  options.time_limit_s = 10;
  const core::PlanResult plan = skills().plan_to_configuration(arm, goal, options);
  ASSERT_TRUE(plan.success()) << plan.message;
  const core::ExecutionReport report =
      skills().execute(arm, skills().time_parameterize(arm, plan.path));
  ASSERT_TRUE(report.success()) << report.message;
  const auto after = relative();
  EXPECT_LT((after.first - before.first).norm(), 1e-6);
  EXPECT_LT(after.second.angularDistance(before.second), 1e-6);

  // Released, the cup is back under physics: it falls and comes to rest lower down.
  const double z_held = skills().frame_pose("cup").position.z();
  skills().detach("cup");
  EXPECT_TRUE(skills().attached_objects().empty());
  EXPECT_THROW(skills().detach("cup"), std::invalid_argument);
  for (int k = 0; k < 150; ++k) ASSERT_FALSE(skills().advance().unstable);
  EXPECT_LT(skills().frame_pose("cup").position.z(), z_held - 0.01);
}

// Minimum contact distance MuJoCo's full pipeline reports over pairs with a moved body, with
// every geom margin set to `margin` (INFINITY if none). Contacts within one hand (a finger on
// a finger) are the hand's own and do not count.
double raw_min_contact_distance(const Scene& scene, const std::vector<char>& moved,
                                const std::vector<double>& qpos, double margin) {
  const mjModel* m = scene.model();
  ModelPtr wide = copy_model(m);
  for (int g = 0; g < wide->ngeom; ++g) wide->geom_margin[g] = margin;
  wide->nconmax = 20000;
  DataPtr d = make_data(wide.get());
  mju_copy(d->qpos, qpos.data(), m->nq);
  mj_kinematics(wide.get(), d.get());
  mj_collision(wide.get(), d.get());
  double dist = INFINITY;
  for (int c = 0; c < d->ncon; ++c) {
    const int b1 = m->geom_bodyid[d->contact[c].geom1], b2 = m->geom_bodyid[d->contact[c].geom2];
    if ((moved[b1] || moved[b2]) && !scene.same_hand(b1, b2)) {
      dist = std::min(dist, d->contact[c].dist);
    }
  }
  return dist;
}

TEST_P(SkillsetOnBothRobots, ClearanceAgreesWithMujocoContactsAndIsNegativeInCollision) {
  const Chains chains = {"base",      "torso",     "head",      "left_arm",
                         "right_arm", "left_hand", "right_hand"};
  const double cap = 0.3;
  const mjModel* m = skills_->model();
  std::vector<int> joints;
  for (const std::string& c : chains)
    for (int j : skills_->scene().chain(c).joints) joints.push_back(j);
  std::vector<char> moved(m->nbody, 0);  // bodies the chains move (not a fixed robot root)
  for (int j : joints) moved[m->jnt_bodyid[j]] = 1;
  for (int b = 1; b < m->nbody; ++b) moved[b] = moved[b] || moved[m->body_parentid[b]];
  std::mt19937_64 rng(9);
  int negative = 0, positive = 0;
  const int samples = 60;
  for (int k = 0; k < samples; ++k) {
    std::vector<double> q = skills().configuration(chains);
    // Perturb arms, hands, head and torso around the start: near and penetrating states.
    std::uniform_real_distribution<double> u(-0.6, 0.6);
    for (size_t i = 3; i < q.size(); ++i) {
      q[i] =
          std::clamp(q[i] + u(rng), m->jnt_range[2 * joints[i]], m->jnt_range[2 * joints[i] + 1]);
    }
    const double clearance = skills().clearance(chains, q, cap);
    ASSERT_EQ(clearance < 0, !skills().is_valid(chains, q)) << "sample " << k;
    std::vector<double> qpos(skills_->sim_data()->qpos, skills_->sim_data()->qpos + m->nq);
    for (size_t i = 0; i < joints.size(); ++i) qpos[m->jnt_qposadr[joints[i]]] = q[i];
    if (clearance < 0) {
      // Penetration: MuJoCo's own deepest contact.
      EXPECT_NEAR(clearance, raw_min_contact_distance(skills_->scene(), moved, qpos, 0.0), 1e-9)
          << k;
      ++negative;
    } else if (clearance < cap) {
      // Apart: MuJoCo finds a contact with margins just above the clearance, none just below.
      EXPECT_LT(raw_min_contact_distance(skills_->scene(), moved, qpos, clearance + 1e-4), INFINITY)
          << k;
      EXPECT_EQ(
          raw_min_contact_distance(skills_->scene(), moved, qpos, std::max(0.0, clearance - 1e-4)),
          INFINITY)
          << k;
      ++positive;
    }
  }
  EXPECT_GT(negative, 0);
  EXPECT_GT(positive, 0);
}

TEST_P(SkillsetOnBothRobots, PlanningToAGoalRegionEndsInsideIt) {
  const Chains chains = {"left_arm"};
  const std::vector<double> centre = valid_configuration(skills(), chains, 51);
  core::GoalRegion region;
  region.sample = [&](std::mt19937_64& rng) -> std::optional<std::vector<double>> {
    std::uniform_real_distribution<double> u(-0.1, 0.1);
    std::vector<double> q = centre;
    for (double& v : q) v += u(rng);
    return q;
  };
  core::PlanOptions options;
  options.time_limit_s = 10;
  const core::PlanResult r = skills().plan_to_region(chains, region, options);
  ASSERT_TRUE(r.success()) << r.message;
  EXPECT_LE(max_abs_diff(r.path.back(), centre), 0.1 + 1e-12);

  core::GoalRegion nowhere;
  nowhere.sample = [](std::mt19937_64&) -> std::optional<std::vector<double>> {
    return std::nullopt;
  };
  EXPECT_EQ(skills().plan_to_region(chains, nowhere, options).status,
            core::PlanStatus::kInvalidGoal);
}

TEST_P(SkillsetOnBothRobots, SameSeedSamePathWhenOtherWorkersPlanAtTheSameTime) {
  const Chains chains = {"torso", "left_arm"};
  const std::vector<double> goal = valid_configuration(skills(), chains, 61);
  core::PlanOptions options;
  options.seed = 17;
  options.time_limit_s = 20;
  const core::PlanResult alone = skills().plan_to_configuration(chains, goal, options);
  ASSERT_TRUE(alone.success()) << alone.message;
  // Three workers of the same scene plan side by side: two different problems and this one.
  std::vector<core::PlanResult> results(3);
  std::vector<std::thread> threads;
  for (int w = 0; w < 3; ++w) {
    threads.emplace_back([&, w] {
      MujocoSkillset worker(test::scene(GetParam(), "kitchen"));
      worker.apply_layout(worker.scene().make_layout(8, 5));
      worker.reset();
      core::PlanOptions o = options;
      std::vector<double> g = goal;
      if (w != 1) {
        o.seed = static_cast<std::uint32_t>(100 + w);
        g = valid_configuration(worker, chains, 70 + w);
      }
      results[w] = worker.plan_to_configuration(chains, g, o);
    });
  }
  for (std::thread& t : threads) t.join();
  EXPECT_EQ(results[1].path, alone.path);
  EXPECT_EQ(results[1].collision_checks, alone.collision_checks);
}

INSTANTIATE_TEST_SUITE_P(Robots, SkillsetOnBothRobots, ::testing::Values("tallbot", "minibot"));

// Where an object the hand closes on meets the palm: minibot's palm block (half depth 22 mm,
// its centre 50 mm behind the palm frame) ends 28 mm behind the frame on both hands.
TEST(SkillsetPalmDepth, IsWhereThePalmBodysGeometryEndsAlongApproach) {
  MujocoSkillset minibot(test::scene("minibot", "kitchen"));
  EXPECT_NEAR(minibot.palm_depth("left"), 0.028, 1e-9);
  EXPECT_NEAR(minibot.palm_depth("right"), 0.028, 1e-9);
  EXPECT_THROW(minibot.palm_depth("middle"), std::invalid_argument);
}

}  // namespace
}  // namespace taskmatrix::mujoco
