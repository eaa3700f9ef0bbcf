#include "taskmatrix/mujoco/motion_planner.h"

#include "taskmatrix/core/motion_planning.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

#include "taskmatrix/mujoco/kinematics.h"
#include "taskmatrix/mujoco/validity_checker.h"
#include "tests/test_support.h"

namespace taskmatrix::mujoco {
namespace {

// A collision-free configuration of `chain`, drawn with `seed`.
std::vector<double> valid_sample(const Scene& scene, WorkerScene& worker, const ChainIndex& chain,
                                 std::uint64_t seed) {
  ValidityChecker checker(scene, worker.model(), worker.data(), chain.joints);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<double> q(chain.joints.size());
  for (int attempt = 0; attempt < 10000; ++attempt) {
    for (size_t i = 0; i < q.size(); ++i)
      q[i] = chain.lower[i] + (chain.upper[i] - chain.lower[i]) * u(rng);
    if (!checker.in_collision(q.data())) break;
  }
  worker.reset_to_start();
  return q;
}

// Re-checks a path with the raw MuJoCo check at `per_segment` interpolated states.
bool path_collision_free(const Scene& scene, WorkerScene& worker, const std::vector<int>& joints,
                         const std::vector<std::vector<double>>& path, int per_segment) {
  for (size_t k = 0; k + 1 < path.size(); ++k) {
    for (int s = 0; s <= per_segment; ++s) {
      const double t = static_cast<double>(s) / per_segment;
      for (size_t i = 0; i < joints.size(); ++i) {
        worker.data()->qpos[worker.model()->jnt_qposadr[joints[i]]] =
            path[k][i] + t * (path[k + 1][i] - path[k][i]);
      }
      if (raw_robot_in_collision(scene, worker.model(), worker.data())) return false;
    }
  }
  return true;
}

class PlanOnBothRobots : public ::testing::TestWithParam<std::string> {};

TEST_P(PlanOnBothRobots, ArmPathsAreCollisionFreeAtTenTimesThePlanningResolution) {
  auto scene = test::scene(GetParam(), "kitchen");
  WorkerScene worker(scene);
  worker.apply_layout(scene->make_layout(12, 3));
  worker.reset_to_start();
  const ChainIndex& arm = scene->chain("left_arm");
  MotionPlanner planner(*scene, worker, arm.joints);
  PlanOptions options;
  options.time_limit_s = 10;
  int solved = 0;
  for (std::uint64_t k = 0; k < 5; ++k) {
    const std::vector<double> goal = valid_sample(*scene, worker, arm, 100 + k);
    options.seed = static_cast<std::uint32_t>(k + 1);
    const core::PlanResult r = planner.plan({goal}, options);
    ASSERT_NE(r.status, core::PlanStatus::kInvalidStart) << r.message;
    if (!r.success()) continue;
    ++solved;
    EXPECT_GT(r.collision_checks, 0u);
    EXPECT_GE(r.path.size(), 2u);
    for (size_t i = 0; i < goal.size(); ++i) EXPECT_NEAR(r.path.back()[i], goal[i], 1e-9);
    // The planner checks motions at 0.005 of the space's extent; re-check ten times finer.
    double extent = 0;
    for (size_t i = 0; i < arm.joints.size(); ++i)
      extent += std::pow(arm.upper[i] - arm.lower[i], 2);
    extent = std::sqrt(extent);
    int per_segment_max = 1;
    for (size_t s = 0; s + 1 < r.path.size(); ++s) {
      double len = 0;
      for (size_t i = 0; i < goal.size(); ++i) len += std::pow(r.path[s + 1][i] - r.path[s][i], 2);
      per_segment_max = std::max(per_segment_max,
                                 static_cast<int>(std::ceil(std::sqrt(len) / (0.0005 * extent))));
    }
    EXPECT_TRUE(path_collision_free(*scene, worker, arm.joints, r.path, per_segment_max));
  }
  EXPECT_GE(solved, 4) << "RRTConnect should solve nearly all arm problems within 10 s";
}

TEST_P(PlanOnBothRobots, PathsTouchNothingBetweenCheckedStatesEvenWhenChecksAreFarApart) {
  // Base motions checked at 0.2 of the space's extent (40 times coarser than the default, 3 m
  // apart in the kitchen): the planner's straight motions skip through furniture between
  // checks. Every path returned is
  // certified along its segments (replanned with finer checks where it touched), so it is
  // collision-free however finely it is re-checked.
  auto scene = test::scene(GetParam(), "kitchen");
  WorkerScene worker(scene);
  worker.apply_layout(scene->make_layout(12, 3));
  worker.reset_to_start();
  PlanOptions options;
  options.motion_resolution = 0.2;
  int solved = 0, replanned = 0;
  for (const char* name : {"base"}) {
    const ChainIndex& chain = scene->chain(name);
    std::vector<double> lower = chain.lower, upper = chain.upper;
    if (std::string(name) == "base") {  // around the start, where the furniture is
      for (size_t i = 0; i < 2; ++i) {
        const double at = scene->start_qpos()[chain.qpos_adr[i]];
        lower[i] = at - 2.5;
        upper[i] = at + 2.5;
      }
    }
    ValidityChecker checker(*scene, worker.model(), worker.data(), chain.joints);
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(0, 1);
    for (int k = 0; k < 10; ++k) {
      std::vector<double> goal(chain.joints.size());
      do {
        for (size_t i = 0; i < goal.size(); ++i)
          goal[i] = lower[i] + (upper[i] - lower[i]) * u(rng);
      } while (checker.in_collision(goal.data()));
      worker.reset_to_start();
      MotionPlanner planner(*scene, worker, chain.joints);
      options.seed = static_cast<std::uint32_t>(k + 1);
      const core::PlanResult r = planner.plan({goal}, options);
      if (!r.success()) continue;
      ++solved;
      replanned += r.plan_calls > 1;
      EXPECT_TRUE(path_collision_free(*scene, worker, chain.joints, r.path, 1000))
          << name << ", goal " << k;
      worker.reset_to_start();
    }
  }
  EXPECT_GE(solved, 8);
  // The certification found something to replan: without it, those paths would touch.
  EXPECT_GE(replanned, 1);
}

TEST_P(PlanOnBothRobots, SameSeedSamePathBitForBitWhateverRanBefore) {
  auto scene = test::scene(GetParam(), "office");
  WorkerScene worker(scene);
  worker.apply_layout(scene->make_layout(10, 8));
  worker.reset_to_start();
  const ChainIndex& arm = scene->chain("right_arm");
  const std::vector<double> goal = valid_sample(*scene, worker, arm, 7);
  MotionPlanner planner(*scene, worker, arm.joints);
  PlanOptions options;
  options.seed = 42;
  const core::PlanResult first = planner.plan({goal}, options);
  options.seed = 43;
  planner.plan({goal}, options);  // something else in between
  options.planner.name = "KPIECE1";
  planner.plan({goal}, options);
  options.planner.name = "RRTConnect";
  options.seed = 42;
  const core::PlanResult again = planner.plan({goal}, options);
  ASSERT_TRUE(first.success()) << first.message;
  ASSERT_EQ(first.path, again.path);
  EXPECT_EQ(first.collision_checks, again.collision_checks);
}

TEST_P(PlanOnBothRobots, InvalidStartInvalidGoalAndBadInputAreNamedAsSuch) {
  auto scene = test::scene(GetParam(), "kitchen");
  WorkerScene worker(scene);
  const ChainIndex& arm = scene->chain("left_arm");
  MotionPlanner planner(*scene, worker, arm.joints);
  PlanOptions options;
  options.time_limit_s = 1;
  const std::vector<double> goal = valid_sample(*scene, worker, arm, 5);

  // Goal in collision: the arm folded into the table is found by sampling colliding states.
  ValidityChecker checker(*scene, worker.model(), worker.data(), arm.joints);
  std::vector<double> colliding(arm.joints.size());
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  do {
    for (size_t i = 0; i < colliding.size(); ++i)
      colliding[i] = arm.lower[i] + (arm.upper[i] - arm.lower[i]) * u(rng);
  } while (!checker.in_collision(colliding.data()));
  worker.reset_to_start();
  EXPECT_EQ(planner.plan({colliding}, options).status, core::PlanStatus::kInvalidGoal);

  std::vector<double> outside = goal;
  outside[0] = arm.upper[0] + 0.5;
  const core::PlanResult beyond = planner.plan({outside}, options);
  EXPECT_EQ(beyond.status, core::PlanStatus::kInvalidInput);  // rejected, not planned for
  EXPECT_NE(beyond.message.find("outside its limits"), std::string::npos) << beyond.message;

  std::vector<double> nan_goal = goal;
  nan_goal[1] = std::nan("");
  EXPECT_EQ(planner.plan({nan_goal}, options).status, core::PlanStatus::kInvalidInput);
  EXPECT_EQ(planner.plan({std::vector<double>(2, 0.0)}, options).status,
            core::PlanStatus::kInvalidInput);
  options.planner.name = "NoSuchPlanner";
  EXPECT_EQ(planner.plan({goal}, options).status, core::PlanStatus::kInvalidInput);
  options.planner = {"RRTConnect", {{"no_such_param", "1"}}};
  EXPECT_EQ(planner.plan({goal}, options).status, core::PlanStatus::kInvalidInput);

  // Start in collision: the robot walked into the table.
  options.planner = {};
  worker.data()->qpos[scene->chain("base").qpos_adr[0]] = 0.4;
  const core::PlanResult r = planner.plan({goal}, options);
  EXPECT_EQ(r.status, core::PlanStatus::kInvalidStart) << r.message;
}

// A contact the planned joints cannot change (the other hand resting against what it set
// down) stays as it is along any path, and execution, which checks what the moving chains
// touch, ignores it: a shallow one is left out of the plan's checks; a deep one is still an
// invalid start.
TEST_P(PlanOnBothRobots, AShallowContactThePlannedJointsCannotChangeIsLeftAsItIs) {
  auto scene = test::scene(GetParam(), "kitchen");
  WorkerScene worker(scene);
  const ChainIndex& arm = scene->chain("left_arm");
  const std::vector<double> goal = valid_sample(*scene, worker, arm, 5);
  PlanOptions options;
  options.time_limit_s = 5;
  // The base stepped forward until the robot first touches the table, millimetre by millimetre.
  const int base_x = scene->chain("base").qpos_adr[0];
  double x = 0;
  for (; x < 0.6; x += 0.001) {
    worker.data()->qpos[base_x] = x;
    mj_kinematics(worker.model(), worker.data());
    if (raw_robot_in_collision(*scene, worker.model(), worker.data())) break;
  }
  ASSERT_LT(x, 0.6) << "the robot never reached the table";
  {
    ValidityChecker checker(*scene, worker.model(), worker.data(), arm.joints);
    ASSERT_TRUE(checker.static_collision());
    ASSERT_LE(checker.static_depth_m(), MotionPlanner::kStaticContactDepth);
  }
  MotionPlanner planner(*scene, worker, arm.joints);
  const core::PlanResult touching = planner.plan({goal}, options);
  EXPECT_EQ(touching.status, core::PlanStatus::kExactSolution) << touching.message;
  // 5 cm further in: the start stays invalid, and says the planned joints cannot move it.
  worker.data()->qpos[base_x] = x + 0.05;
  const core::PlanResult deep = planner.plan({goal}, options);
  EXPECT_EQ(deep.status, core::PlanStatus::kInvalidStart) << deep.message;
  EXPECT_NE(deep.message.find("cannot move it"), std::string::npos) << deep.message;
}

TEST_P(PlanOnBothRobots, EveryPlannerByNameSolvesAnOpenArmProblem) {
  auto scene = test::scene(GetParam(), "kitchen");
  WorkerScene worker(scene);
  const ChainIndex& arm = scene->chain("left_arm");
  // A goal near the rest posture: the shoulder lifted a little.
  std::vector<double> goal(arm.joints.size());
  for (size_t i = 0; i < goal.size(); ++i) goal[i] = worker.data()->qpos[arm.qpos_adr[i]];
  goal[0] = std::clamp(goal[0] + 0.4 * (arm.upper[0] > 0.5 ? 1 : -1), arm.lower[0], arm.upper[0]);
  MotionPlanner planner(*scene, worker, arm.joints);
  for (const std::string& name : core::planner_registry().names()) {
    PlanOptions options;
    options.planner.name = name;
    options.time_limit_s = 2;
    const core::PlanResult r = planner.plan({goal}, options);
    EXPECT_TRUE(r.success()) << name << ": " << core::to_string(r.status) << " " << r.message;
    EXPECT_LE(r.planning_time_s, 2.5) << name;
  }
}

TEST_P(PlanOnBothRobots, SimplifiedPathsAreBoundedByWorkAndStayWithinTheJointLimits) {
  auto scene = test::scene(GetParam(), "kitchen");
  WorkerScene worker(scene);
  worker.apply_layout(scene->make_layout(12, 5));
  worker.reset_to_start();
  const ChainIndex& arm = scene->chain("right_arm");
  MotionPlanner planner(*scene, worker, arm.joints);
  int solved = 0;
  for (std::uint64_t k = 0; k < 6; ++k) {
    const std::vector<double> goal = valid_sample(*scene, worker, arm, 300 + k);
    PlanOptions options;
    options.seed = static_cast<std::uint32_t>(7 + k);
    const core::PlanResult r = planner.plan({goal}, options);
    if (!r.success()) continue;
    ++solved;
    EXPECT_FALSE(r.simplification_hit_time_limit);
    EXPECT_FALSE(r.planning_hit_time_limit);
    for (const std::vector<double>& q : r.path) {
      for (size_t i = 0; i < q.size(); ++i) {
        EXPECT_GE(q[i], arm.lower[i]) << "waypoint below joint " << i << "'s limit";
        EXPECT_LE(q[i], arm.upper[i]) << "waypoint above joint " << i << "'s limit";
      }
    }
    // However long the simplification took, the same request gives the same path.
    const core::PlanResult again = planner.plan({goal}, options);
    EXPECT_EQ(r.path, again.path);
    EXPECT_EQ(r.collision_checks, again.collision_checks);
    // Without simplification the path is the planner's own: simplification shortened it.
    PlanOptions raw = options;
    raw.simplify_rounds = 0;
    const core::PlanResult unsimplified = planner.plan({goal}, raw);
    ASSERT_TRUE(unsimplified.success());
    auto length = [](const std::vector<std::vector<double>>& path) {
      double total = 0;
      for (size_t w = 1; w < path.size(); ++w) {
        double sq = 0;
        for (size_t i = 0; i < path[w].size(); ++i) sq += std::pow(path[w][i] - path[w - 1][i], 2);
        total += std::sqrt(sq);
      }
      return total;
    };
    EXPECT_LE(length(r.path), length(unsimplified.path) * 1.001);
  }
  EXPECT_GE(solved, 4);
  // A clock safety net that fires is reported, and the path is still valid.
  const std::vector<double> goal = valid_sample(*scene, worker, arm, 300);
  PlanOptions rushed;
  rushed.simplify_time_s = 1e-9;
  const core::PlanResult r = planner.plan({goal}, rushed);
  if (r.success() && r.path.size() > 2) {
    EXPECT_TRUE(r.simplification_hit_time_limit);
  }
}

TEST_P(PlanOnBothRobots, AnytimePlannersRepeatUnderAnIterationBudgetAndReportTheClock) {
  auto scene = test::scene(GetParam(), "kitchen");
  WorkerScene worker(scene);
  worker.apply_layout(scene->make_layout(8, 3));
  worker.reset_to_start();
  const ChainIndex& arm = scene->chain("left_arm");
  const std::vector<double> goal = valid_sample(*scene, worker, arm, 11);
  MotionPlanner planner(*scene, worker, arm.joints);
  for (const char* name : {"PRM", "RRTstar", "BITstar"}) {
    PlanOptions options;
    options.planner.name = name;
    options.max_iterations = 1500;
    options.time_limit_s = 60;  // a safety net only
    options.seed = 5;
    const core::PlanResult a = planner.plan({goal}, options);
    const core::PlanResult b = planner.plan({goal}, options);
    EXPECT_EQ(a.status, b.status) << name;
    EXPECT_EQ(a.path, b.path) << name;
    EXPECT_EQ(a.collision_checks, b.collision_checks) << name;
    EXPECT_EQ(a.planner_iterations, b.planner_iterations) << name;
    EXPECT_FALSE(a.planning_hit_time_limit) << name;
    // The budget stops them (the evaluation that stopped it counted), unless they are done
    // earlier: OMPL's PRM (without PRM*'s objective) at its first path, looked for after every
    // roadmap phase; BITstar when its path cannot be improved (a straight line).
    EXPECT_LE(a.planner_iterations, 1501u) << name;
    if (std::string(name) == "RRTstar") {
      EXPECT_EQ(a.planner_iterations, 1501u);  // never done
    }
    if (a.planner_iterations < 1501u) continue;
    // By the clock alone an anytime planner stops when time is up, and says so.
    options.max_iterations = 0;
    options.time_limit_s = 0.05;
    EXPECT_TRUE(planner.plan({goal}, options).planning_hit_time_limit) << name;
  }
  // An iteration budget too small for RRTConnect: a timeout that names the budget.
  PlanOptions tiny;
  tiny.max_iterations = 1;
  const core::PlanResult r = planner.plan({goal}, tiny);
  if (!r.success()) {
    EXPECT_EQ(r.status, core::PlanStatus::kTimeout);
    EXPECT_EQ(r.message, "no path within 1 iterations");
    EXPECT_FALSE(r.planning_hit_time_limit);
  }
  // Time limits beyond a day overflow OMPL's deadline: refused.
  PlanOptions huge;
  huge.time_limit_s = 1e10;
  EXPECT_EQ(planner.plan({goal}, huge).status, core::PlanStatus::kInvalidInput);
}

// The torso and the left arm of a robot (bending, every robot's hand gets near the table) as
// the clearance tests plan them: the joints, draws within their limits, and the states the
// planner checks along each motion of a path (core::motion_check_points with the planner's
// spacing for `options`, finer within `radius` of the start and goal).
class TorsoAndLeftArm {
 public:
  TorsoAndLeftArm(const Scene& scene, const PlanOptions& options, double radius, std::uint64_t seed)
      : rng_(seed) {
    for (const char* name : {"torso", "left_arm"}) {
      const ChainIndex& c = scene.chain(name);
      joints.insert(joints.end(), c.joints.begin(), c.joints.end());
      spacing_.lower.insert(spacing_.lower.end(), c.lower.begin(), c.lower.end());
      spacing_.upper.insert(spacing_.upper.end(), c.upper.begin(), c.upper.end());
    }
    spacing_.motion_resolution = options.motion_resolution;
    spacing_.fine_radius = radius;
    spacing_.fine_resolution = options.motion_resolution / 5;
  }
  std::vector<double> draw() {
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<double> q(joints.size());
    for (size_t i = 0; i < q.size(); ++i) {
      q[i] = spacing_.lower[i] + (spacing_.upper[i] - spacing_.lower[i]) * u(rng_);
    }
    return q;
  }
  void set(WorkerScene& worker, const std::vector<double>& q) const {
    for (size_t i = 0; i < q.size(); ++i)
      worker.data()->qpos[worker.model()->jnt_qposadr[joints[i]]] = q[i];
  }
  std::vector<std::vector<double>> checked_states(const core::PlanResult& r,
                                                  const std::vector<double>& start,
                                                  const std::vector<double>& goal) {
    spacing_.start = start;
    spacing_.goals = {goal};
    std::vector<std::vector<double>> out;
    for (size_t w = 0; w + 1 < r.path.size(); ++w) {
      const std::vector<double>& a = r.path[w];
      const std::vector<double>& b = r.path[w + 1];
      std::vector<double> ts = core::motion_check_points(spacing_, a.data(), b.data());
      ts.push_back(1);
      for (double t : ts) {
        std::vector<double> q(a.size());
        for (size_t i = 0; i < q.size(); ++i) q[i] = a[i] + t * (b[i] - a[i]);
        out.push_back(std::move(q));
      }
    }
    return out;
  }

  std::vector<int> joints;

 private:
  core::PlanningProblem spacing_;
  std::mt19937_64 rng_;
};

double max_abs_diff(const std::vector<double>& a, const std::vector<double>& b) {
  double e = 0;
  for (size_t i = 0; i < a.size(); ++i) e = std::max(e, std::abs(a[i] - b[i]));
  return e;
}

// A path keeps 1 cm from the world except near its start and goal (a hand beside what it
// grasps), and there only in proportion: the clearance asked for grows from nothing at the
// endpoint to the full centimetre 0.25 rad (every joint) away from it, so a path leaves a start
// a hair off the table instead of sliding along it. Checked at exactly the states the planner
// checks along each motion (core::motion_check_points with the planner's spacing).
TEST_P(PlanOnBothRobots, PathsLeaveAStartAHairOffTheWorldWithClearanceGrowingAway) {
  auto scene = test::scene(GetParam(), "kitchen");
  WorkerScene worker(scene);
  worker.apply_layout(scene->make_layout(8, 5));
  worker.reset_to_start();
  const double radius = 0.25;
  PlanOptions options;
  options.time_limit_s = 10;
  const double wanted = options.clearance_m;
  TorsoAndLeftArm body(*scene, options, radius, 21);
  const std::vector<int>& joints = body.joints;
  int problems = 0, checked = 0, short_of = 0, ramp_states = 0;
  std::string worst;
  double worst_ratio = INFINITY;
  for (int k = 0; k < 40000 && problems < 8; ++k) {
    const std::vector<double> start = body.draw();
    const std::vector<double> goal = body.draw();
    {
      ValidityChecker checker(*scene, worker.model(), worker.data(), joints);
      if (checker.in_collision(start.data()) || checker.in_collision(goal.data())) continue;
      // A start within 2 mm of the world, a goal a centimetre or more off it.
      if (checker.distance_to_world(start.data(), wanted) > 0.002) continue;
      if (checker.distance_to_world(goal.data(), wanted) < wanted) continue;
    }
    worker.reset_to_start();
    body.set(worker, start);
    MotionPlanner planner(*scene, worker, joints);
    options.seed = static_cast<std::uint32_t>(problems + 1);
    const core::PlanResult r = planner.plan({goal}, options);
    if (r.status != core::PlanStatus::kExactSolution) continue;
    ++problems;
    ValidityChecker checker(*scene, worker.model(), worker.data(), joints);
    for (const std::vector<double>& q : body.checked_states(r, start, goal)) {
      const double from_end = std::min(max_abs_diff(q, start), max_abs_diff(q, goal));
      const double needed = wanted * std::min(from_end, radius) / radius;
      const double have = checker.distance_to_world(q.data(), wanted);
      ++checked;
      if (from_end < radius) ++ramp_states;
      if (have < needed - 1e-4) ++short_of;
      if (needed > 1e-3 && have / needed < worst_ratio) {
        worst_ratio = have / needed;
        worst =
            std::to_string(have * 1000) + " mm at " + std::to_string(from_end) + " rad from an end";
      }
    }
    worker.reset_to_start();
  }
  ASSERT_EQ(problems, 8);
  EXPECT_GT(ramp_states, 100);
  EXPECT_EQ(short_of, 0) << "of " << checked << " checked states; least clearance for what was "
                         << "asked: " << worst;
}

// A start a few millimetres clear of the world keeps half that clearance on the way out, and
// the clearance asked for grows from there to the full centimetre 0.25 rad away: a path does
// not dive towards the table a hand is just above (execution lags the plan by millimetres and
// touches it). The same when the plan may touch an object (reach's may_touch): that allowance
// is for a start in contact only.
TEST_P(PlanOnBothRobots, PathsFromAStartClearOfTheWorldKeepHalfItsClearanceOnTheWayOut) {
  auto scene = test::scene(GetParam(), "kitchen");
  WorkerScene worker(scene);
  worker.apply_layout(scene->make_layout(8, 5));
  worker.reset_to_start();
  const int cup = mj_name2id(worker.model(), mjOBJ_BODY, "cup");
  ASSERT_GE(cup, 0);
  std::vector<int> cup_geoms;
  for (int g = 0; g < worker.model()->ngeom; ++g) {
    if (worker.model()->geom_bodyid[g] == cup) cup_geoms.push_back(g);
  }
  const double radius = 0.25;
  PlanOptions options;
  options.time_limit_s = 10;
  const double wanted = options.clearance_m;
  TorsoAndLeftArm body(*scene, options, radius, 23);
  const std::vector<int>& joints = body.joints;
  int problems = 0, short_of = 0, near_start = 0;
  std::string worst;
  for (int k = 0; k < 40000 && problems < 8; ++k) {
    const std::vector<double> start = body.draw();
    const std::vector<double> goal = body.draw();
    double start_clearance = 0;
    {
      ValidityChecker checker(*scene, worker.model(), worker.data(), joints);
      if (checker.in_collision(start.data()) || checker.in_collision(goal.data())) continue;
      // A start 3 to 8 mm off the world, a goal a centimetre or more off it.
      start_clearance = checker.distance_to_world(start.data(), wanted);
      if (start_clearance < 0.003 || start_clearance > 0.008) continue;
      if (checker.distance_to_world(goal.data(), wanted) < wanted) continue;
    }
    worker.reset_to_start();
    body.set(worker, start);
    MotionPlanner planner(*scene, worker.model(), worker.data(), joints, {}, cup_geoms);
    options.seed = static_cast<std::uint32_t>(problems + 1);
    const core::PlanResult r = planner.plan({goal}, options);
    if (r.status != core::PlanStatus::kExactSolution) continue;
    ++problems;
    ValidityChecker checker(*scene, worker.model(), worker.data(), joints);
    const double floor = 0.5 * start_clearance;
    for (const std::vector<double>& q : body.checked_states(r, start, goal)) {
      const double from_start = max_abs_diff(q, start);
      if (from_start >= radius || max_abs_diff(q, goal) < radius) continue;
      ++near_start;
      const double needed = floor + (wanted - floor) * from_start / radius;
      const double have = checker.distance_to_world(q.data(), wanted);
      if (have < needed - 1e-4) {
        ++short_of;
        worst = std::to_string(have * 1000) + " mm where " + std::to_string(needed * 1000) +
                " mm were asked, " + std::to_string(from_start) + " rad from a start " +
                std::to_string(start_clearance * 1000) + " mm clear";
      }
    }
    worker.reset_to_start();
  }
  ASSERT_EQ(problems, 8);
  EXPECT_GT(near_start, 50);
  EXPECT_EQ(short_of, 0) << "of " << near_start << " states near the start; last: " << worst;
}

// A held object a few millimetres from a link of the arm holding it that the plan does not
// move relative to the hand (tallbot's wrist sphere beside a cup grasped from above): the two
// stay as they are along any path, as the arm's own links do, so the object keeps no planning
// margin from the robot. Before: every state away from the start was within the centimetre
// and the plan met its iteration budget.
TEST_P(PlanOnBothRobots, AHeldObjectBesideTheArmHoldingItKeepsNoMarginFromIt) {
  auto scene = test::scene(GetParam(), "kitchen");
  WorkerScene worker(scene);
  worker.reset_to_start();
  const mjModel* m = worker.model();
  mjData* d = worker.data();
  const core::HandSpec* hand = scene->robot().find_hand("left");
  const BodyFrame palm = resolve_frame(*scene, d, hand->palm);
  // The nearest link above the palm's body with a collidable geom: the forearm or the wrist.
  int link_geom = -1;
  for (int b = m->body_parentid[palm.body]; b > 0 && link_geom < 0; b = m->body_parentid[b]) {
    for (int k = 0; k < m->body_geomnum[b] && link_geom < 0; ++k) {
      const int g = m->body_geomadr[b] + k;
      if (m->geom_contype[g] || m->geom_conaffinity[g]) link_geom = g;
    }
  }
  ASSERT_GE(link_geom, 0);
  const int cup = mj_name2id(m, mjOBJ_BODY, "cup");
  const int cup_shell = mj_name2id(m, mjOBJ_GEOM, "cup_shell");
  ASSERT_GT(cup, 0);
  ASSERT_GT(cup_shell, 0);
  const std::optional<GeomPair> pair = scene->collidable_pair(cup_shell, link_geom);
  ASSERT_TRUE(pair.has_value());
  // The cup out to the robot's left of that link, 4 mm from it.
  const Eigen::Vector3d link_at(d->geom_xpos + 3 * link_geom);
  const int cup_adr = m->jnt_qposadr[m->body_jntadr[cup]];
  mjContact contacts[mjMAXCONPAIR];
  auto cup_within = [&](double offset, double margin) {
    const Eigen::Vector3d at = link_at + Eigen::Vector3d(0, offset, 0);
    mju_copy3(d->qpos + cup_adr, at.data());
    mj_fwdPosition(m, d);  // contacts too: the attachment records what the cup rests on
    return collide_geoms(m, d, *pair, margin, contacts) > 0;
  };
  double offset = 0;
  while (offset < 0.5 && cup_within(offset, 0.004)) offset += 0.0005;
  ASSERT_LT(offset, 0.5);
  ASSERT_TRUE(cup_within(offset, 0.009)) << "the cup is a centimetre or more from the link";
  const std::vector<Attachment> held = {attachment_at(*scene, m, d, cup, palm.body, "cup", "left")};
  ASSERT_EQ(describe_robot_contacts(*scene, m, d, held), "no contact");
  // The base backs away 30 cm, arm and hand still: the cup and the link move together.
  const ChainIndex& base = scene->chain("base");
  std::vector<double> goal;
  for (size_t i = 0; i < base.joints.size(); ++i) goal.push_back(d->qpos[base.qpos_adr[i]]);
  goal[0] -= 0.3;
  MotionPlanner planner(*scene, m, d, base.joints, held);
  PlanOptions options;
  options.max_iterations = 2000;
  const core::PlanResult r = planner.plan({goal}, options);
  EXPECT_EQ(r.status, core::PlanStatus::kExactSolution) << r.message;
  // Against the world a held object keeps its centimetre: the same cup held 4 mm above the
  // table is within the planning margin, though it touches nothing.
  const int table_top = mj_name2id(m, mjOBJ_GEOM, "table_top");
  ASSERT_GE(table_top, 0);
  const std::optional<GeomPair> on_table = scene->collidable_pair(cup_shell, table_top);
  ASSERT_TRUE(on_table.has_value());
  const Eigen::Vector3d above_table(0.6, 0.0, 0.65 + 0.05 + 0.004);
  mju_copy3(d->qpos + cup_adr, above_table.data());
  mj_fwdPosition(m, d);
  ASSERT_FALSE(collide_geoms(m, d, *on_table, 0.003, contacts) > 0);
  const std::vector<Attachment> over_table = {
      attachment_at(*scene, m, d, cup, palm.body, "cup", "left")};
  ValidityChecker checker(*scene, m, d, base.joints, over_table);
  std::vector<double> q;
  for (size_t i = 0; i < base.joints.size(); ++i) q.push_back(d->qpos[base.qpos_adr[i]]);
  EXPECT_FALSE(checker.in_collision(q.data()));
  EXPECT_TRUE(checker.within_margin(q.data(), 0.01));
  // And the cup beside the link, checked the same way, is not.
  ValidityChecker beside_link(*scene, m, d, base.joints, held);
  EXPECT_FALSE(beside_link.within_margin(q.data(), 0.01));
}

// An arm left folded into the robot's own body (as physics may leave one that settled past
// a plan's goal) stays as it is while the base moves: the pair cannot change, so it does not
// make every state of the base's plan invalid; planning that arm itself, it still counts.
TEST_P(PlanOnBothRobots, ALinkPairThePlanCarriesAlikeDoesNotBlockIt) {
  auto scene = test::scene(GetParam(), "kitchen");
  WorkerScene worker(scene);
  worker.reset_to_start();
  const mjModel* m = worker.model();
  mjData* d = worker.data();
  const ChainIndex& arm = scene->chain("left_arm");
  // Seeded draws of the left arm until one touches the robot itself and nothing else.
  std::mt19937 rng(7);
  bool folded = false;
  for (int draw = 0; draw < 5000 && !folded; ++draw) {
    for (size_t i = 0; i < arm.joints.size(); ++i) {
      std::uniform_real_distribution<double> u(arm.lower[i], arm.upper[i]);
      d->qpos[arm.qpos_adr[i]] = u(rng);
    }
    mj_fwdPosition(m, d);
    int self = 0, other = 0;
    for (int c = 0; c < d->ncon; ++c) {
      const int b1 = m->geom_bodyid[d->contact[c].geom1], b2 = m->geom_bodyid[d->contact[c].geom2];
      const bool r1 = scene->is_robot_body(b1), r2 = scene->is_robot_body(b2);
      if (r1 && r2 && !scene->same_hand(b1, b2) && d->contact[c].dist < -0.001)
        ++self;
      else if (r1 || r2)
        ++other;
    }
    folded = self > 0 && other == 0;
  }
  ASSERT_TRUE(folded) << "no draw of the left arm touches only the robot itself";
  const ChainIndex& base = scene->chain("base");
  std::vector<double> start, goal;
  for (size_t i = 0; i < base.joints.size(); ++i) start.push_back(d->qpos[base.qpos_adr[i]]);
  goal = start;
  goal[0] -= 0.3;
  MotionPlanner planner(*scene, m, d, base.joints, {});
  PlanOptions options;
  options.max_iterations = 2000;
  const core::PlanResult r = planner.plan({goal}, options);
  EXPECT_EQ(r.status, core::PlanStatus::kExactSolution) << r.message;
  ValidityChecker base_checker(*scene, m, d, base.joints, {});
  EXPECT_FALSE(base_checker.in_collision(start.data()));
  std::vector<double> folded_arm;
  for (size_t i = 0; i < arm.joints.size(); ++i) folded_arm.push_back(d->qpos[arm.qpos_adr[i]]);
  ValidityChecker arm_checker(*scene, m, d, arm.joints, {});
  EXPECT_TRUE(arm_checker.in_collision(folded_arm.data()));
}

INSTANTIATE_TEST_SUITE_P(Robots, PlanOnBothRobots, ::testing::Values("tallbot", "minibot"));

class IkOnBothRobots : public ::testing::TestWithParam<std::string> {};

TEST_P(IkOnBothRobots, ReachesSampledPalmPosesWithinOneMillimetreAndOneDegree) {
  auto scene = test::scene(GetParam(), "kitchen");
  WorkerScene worker(scene);
  const ChainIndex& arm = scene->chain("right_arm");
  const std::string palm = scene->robot().find_hand("right")->palm;
  const FrameRef frame = scene->frame(palm);
  int solved = 0;
  const int trials = 20;
  for (int k = 0; k < trials; ++k) {
    const std::vector<double> q = valid_sample(*scene, worker, arm, 500 + k);
    for (size_t i = 0; i < q.size(); ++i) worker.data()->qpos[arm.qpos_adr[i]] = q[i];
    mj_kinematics(worker.model(), worker.data());
    const core::Pose target = frame_pose(worker.data(), frame);
    worker.reset_to_start();
    IkOptions options;
    options.seed = 10 + k;
    const core::IkResult r = solve_ik(*scene, worker, arm.joints, palm, target, options);
    if (r.status != core::IkStatus::kSolved) continue;
    ++solved;
    for (size_t i = 0; i < q.size(); ++i) worker.data()->qpos[arm.qpos_adr[i]] = r.solutions[0][i];
    mj_kinematics(worker.model(), worker.data());
    const core::Pose reached = frame_pose(worker.data(), frame);
    EXPECT_LE((reached.position - target.position).norm(), 1e-3);
    EXPECT_LE(reached.orientation.angularDistance(target.orientation), 0.0174533);
    worker.reset_to_start();
  }
  // The sampled poses are reachable by construction; a 5-DOF arm has no redundancy to
  // spare, so a few may need more restarts than the default.
  EXPECT_GE(solved, trials * 8 / 10) << GetParam();
}

TEST_P(IkOnBothRobots, UnreachableAndInvalidTargetsAreReportedAsSuch) {
  auto scene = test::scene(GetParam(), "kitchen");
  WorkerScene worker(scene);
  const ChainIndex& arm = scene->chain("left_arm");
  const std::string palm = scene->robot().find_hand("left")->palm;
  core::Pose far;
  far.position = {3.0, 0.0, 1.0};
  IkOptions options;
  options.restarts = 5;
  const core::IkResult r = solve_ik(*scene, worker, arm.joints, palm, far, options);
  EXPECT_EQ(r.status, core::IkStatus::kUnreachable);
  EXPECT_GT(r.position_error_m, 1.0);
  EXPECT_NE(r.reason.find("out of reach"), std::string::npos) << r.reason;
  core::Pose nan_pose;
  nan_pose.position = {std::nan(""), 0, 1};
  EXPECT_EQ(solve_ik(*scene, worker, arm.joints, palm, nan_pose, options).status,
            core::IkStatus::kInvalidInput);
  EXPECT_EQ(solve_ik(*scene, worker, arm.joints, "no_such_frame", far, options).status,
            core::IkStatus::kInvalidInput);
}

// IK reuses one ChainPath over its iterations, which recomputes only the bodies below the
// first whose inputs changed: after any change (the arm's last joint, the base, nothing, all;
// the pose above an arm-only path moved) it must pose the frame's body exactly as MuJoCo's
// whole-model kinematics does.
TEST_P(IkOnBothRobots, AReusedChainPathPosesTheFramesBodyBitForBitAsMujoco) {
  auto scene = test::scene(GetParam(), "kitchen");
  WorkerScene worker(scene);
  const mjModel* m = worker.model();
  mjData* d = worker.data();
  DataPtr ref = make_data(m);
  const ChainIndex& base = scene->chain("base");
  const ChainIndex& arm = scene->chain("right_arm");
  const int body = resolve_frame(*scene, d, scene->robot().find_hand("right")->palm).body;
  std::vector<int> joints = base.joints;
  joints.insert(joints.end(), arm.joints.begin(), arm.joints.end());
  std::vector<ChainIndex> chains = {base, arm};
  mj_kinematics(m, d);
  ChainPath whole(m, joints, body);
  ChainPath arm_only(m, arm.joints, body);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  auto draw = [&](const ChainIndex& c, size_t i) {
    const double lo = std::max(c.lower[i], -2.0), hi = std::min(c.upper[i], 2.0);
    d->qpos[c.qpos_adr[i]] = lo + (hi - lo) * u(rng);
  };
  auto expect_as_mujoco = [&](const core::Pose& pose, int step) {
    mju_copy(ref->qpos, d->qpos, m->nq);
    mj_kinematics(m, ref.get());
    const mjtNum* p = ref->xpos + 3 * body;
    const mjtNum* q = ref->xquat + 4 * body;
    EXPECT_EQ(pose.position, Eigen::Vector3d(p[0], p[1], p[2])) << "step " << step;
    EXPECT_EQ(pose.orientation.coeffs(), Eigen::Quaterniond(q[0], q[1], q[2], q[3]).coeffs())
        << "step " << step;
  };
  int changed_above = 0;
  for (int step = 0; step < 200; ++step) {
    switch (step % 4) {
      case 0:
        draw(arm, arm.joints.size() - 1);
        break;
      case 1:
        for (size_t i = 0; i < base.joints.size(); ++i) draw(base, i);
        break;
      case 2:
        break;
      default:
        for (const ChainIndex& c : chains)
          for (size_t i = 0; i < c.joints.size(); ++i) draw(c, i);
    }
    expect_as_mujoco(whole.update(d), step);
    // The arm-only path reads the pose above it from d: bring d's kinematics up to date when
    // the base moved, as IK's caller does.
    if (step % 4 == 1 || step % 4 == 3) {
      mj_kinematics(m, d);
      ++changed_above;
    }
    expect_as_mujoco(arm_only.update(d), step);
  }
  EXPECT_EQ(changed_above, 100);
}

// IK writes only the chain's qpos while it iterates and restores it; whether it solved (the
// collision checker posed the arm in the data), missed, or found the target out of reach, the
// data's configuration and poses are as they were, bit for bit.
TEST_P(IkOnBothRobots, LeavesTheDataAsItFoundItWhateverTheOutcome) {
  auto scene = test::scene(GetParam(), "kitchen");
  WorkerScene worker(scene);
  const mjModel* m = worker.model();
  mjData* d = worker.data();
  const ChainIndex& arm = scene->chain("right_arm");
  const std::string palm = scene->robot().find_hand("right")->palm;
  const std::vector<double> q = valid_sample(*scene, worker, arm, 77);
  for (size_t i = 0; i < q.size(); ++i) d->qpos[arm.qpos_adr[i]] = q[i];
  mj_kinematics(m, d);
  const core::Pose reachable = frame_pose(d, scene->frame(palm));
  worker.reset_to_start();
  mj_kinematics(m, d);
  auto snapshot = [&] {
    std::vector<mjtNum> s(d->qpos, d->qpos + m->nq);
    s.insert(s.end(), d->xpos, d->xpos + 3 * m->nbody);
    s.insert(s.end(), d->xquat, d->xquat + 4 * m->nbody);
    s.insert(s.end(), d->xmat, d->xmat + 9 * m->nbody);
    s.insert(s.end(), d->geom_xpos, d->geom_xpos + 3 * m->ngeom);
    s.insert(s.end(), d->geom_xmat, d->geom_xmat + 9 * m->ngeom);
    s.insert(s.end(), d->site_xpos, d->site_xpos + 3 * m->nsite);
    return s;
  };
  const std::vector<mjtNum> before = snapshot();
  core::Pose twisted = reachable;  // in reach, at an orientation the wrist cannot take
  twisted.orientation = reachable.orientation * Eigen::Quaterniond(0, 0, 1, 0);
  core::Pose far;
  far.position = {3.0, 0.0, 1.0};
  std::set<core::IkStatus> seen;
  for (const core::Pose& target : {reachable, twisted, far}) {
    const core::IkResult r = solve_ik(*scene, m, d, arm.joints, palm, target, IkOptions{});
    seen.insert(r.status);
    EXPECT_TRUE(before == snapshot()) << core::to_string(r.status) << ": " << r.reason;
  }
  EXPECT_EQ(seen.count(core::IkStatus::kSolved), 1u);
  EXPECT_EQ(seen.count(core::IkStatus::kUnreachable), 1u);
}

INSTANTIATE_TEST_SUITE_P(Robots, IkOnBothRobots, ::testing::Values("tallbot", "minibot"));

}  // namespace
}  // namespace taskmatrix::mujoco
