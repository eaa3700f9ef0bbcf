// The core planning interface without a simulator: a 2-D square with a wall, solved by the
// registered planners (OMPL's through taskmatrix/ompl, the project's LineConnect).
#include "taskmatrix/core/motion_planning.h"

#include <gtest/gtest.h>

#include "taskmatrix/ompl/ompl_planners.h"
#include "taskmatrix/planners/line_connect.h"

namespace taskmatrix::core {
namespace {

// The unit square with a wall x in [0.45, 0.55], y < 0.8: from the left to the right side a
// path must go over the wall's top.
struct WallProblem {
  PlanningProblem problem;
  int checks = 0;
  WallProblem() {
    problem.joint_names = {"x", "y"};
    problem.lower = {0, 0};
    problem.upper = {1, 1};
    problem.start = {0.1, 0.1};
    problem.goals = {{0.9, 0.1}};
    problem.is_valid = [this](const double* q) {
      ++checks;
      return !(q[0] >= 0.45 && q[0] <= 0.55 && q[1] < 0.8);
    };
    problem.max_iterations = 5000;
    problem.seed = 7;
  }
};

PlannerRegistry registry_with_builtins() {
  PlannerRegistry r;
  ompl_planners::register_planners(r);
  planners::register_planners(r);
  return r;
}

void expect_valid_path(const PlanningProblem& p, const PlannerResult& r) {
  ASSERT_EQ(r.status, PlannerStatus::kExactSolution) << r.message;
  ASSERT_GE(r.path.size(), 2u);
  EXPECT_EQ(r.path.front(), p.start);
  EXPECT_EQ(r.path.back(), p.goals[0]);
  for (size_t k = 1; k < r.path.size(); ++k) {
    EXPECT_TRUE(motion_valid(p, r.path[k - 1].data(), r.path[k].data())) << "segment " << k;
  }
}

TEST(PlannerRegistry, ChecksNamesAndParameters) {
  const PlannerRegistry r = registry_with_builtins();
  const std::vector<std::string> names = r.names();
  EXPECT_NE(std::find(names.begin(), names.end(), "RRTConnect"), names.end());
  EXPECT_NE(std::find(names.begin(), names.end(), "LineConnect"), names.end());
  EXPECT_EQ(r.check("RRTConnect", {{"range", "0.3"}}), "");
  EXPECT_EQ(r.check("LineConnect", {{"range", "0.3"}, {"straight_line_first", "false"}}), "");
  EXPECT_NE(r.check("Nope", {}).find("unknown planner 'Nope' (known: BITstar"), std::string::npos);
  EXPECT_NE(r.check("RRTConnect", {{"rnge", "1"}}).find("parameter 'rnge' is unknown"),
            std::string::npos);
  EXPECT_NE(r.check("RRTConnect", {{"range", "far"}}).find("range rejects 'far'"),
            std::string::npos);
  EXPECT_NE(r.check("LineConnect", {{"range", "far"}}).find("is not a finite number"),
            std::string::npos);
  EXPECT_NE(r.check("LineConnect", {{"range", "-1"}}).find("must be 0 or more"), std::string::npos);
  EXPECT_THROW(r.make("LineConnect", {{"shortcuts", "x"}}), std::invalid_argument);
  EXPECT_TRUE(r.find("BITstar")->optimizes_paths);
  EXPECT_FALSE(r.find("RRTConnect")->optimizes_paths);
  EXPECT_FALSE(r.find("LineConnect")->optimizes_paths);
}

TEST(PlannerRegistry, RefusesTakenAndMalformedNames) {
  PlannerRegistry r = registry_with_builtins();
  PlannerType t;
  t.name = "RRTConnect";
  t.make = [](const PlannerParams&) -> std::unique_ptr<Planner> { return nullptr; };
  EXPECT_THROW(r.add(t), std::invalid_argument);
  t.name = "has space";
  EXPECT_THROW(r.add(t), std::invalid_argument);
  t.name = "NoMake";
  t.make = nullptr;
  EXPECT_THROW(r.add(t), std::invalid_argument);
}

TEST(MotionPlanning, EveryBuiltinPlannerGoesOverTheWall) {
  const PlannerRegistry r = registry_with_builtins();
  for (const std::string name : {"RRTConnect", "LineConnect"}) {
    WallProblem w;
    const PlannerResult result = r.make(name, {})->solve(w.problem);
    expect_valid_path(w.problem, result);
    EXPECT_GT(w.checks, 0) << name;
    EXPECT_GT(result.iterations, 0u) << name;
    EXPECT_GT(result.statistics.at("graph_states"), 1) << name;
    // Over the wall's top.
    double highest = 0;
    for (const Configuration& q : result.path) highest = std::max(highest, q[1]);
    EXPECT_GE(highest, 0.8) << name;
  }
}

TEST(MotionPlanning, LineConnectRepeatsBySeed) {
  const PlannerRegistry r = registry_with_builtins();
  WallProblem a, b, c;
  c.problem.seed = 8;
  const PlannerResult ra = r.make("LineConnect", {})->solve(a.problem);
  const PlannerResult rb = r.make("LineConnect", {})->solve(b.problem);
  const PlannerResult rc = r.make("LineConnect", {})->solve(c.problem);
  EXPECT_EQ(ra.path, rb.path);
  EXPECT_EQ(ra.iterations, rb.iterations);
  EXPECT_EQ(a.checks, b.checks);
  EXPECT_NE(ra.path, rc.path);
}

TEST(MotionPlanning, LineConnectTakesTheStraightLineWhenFree) {
  const PlannerRegistry r = registry_with_builtins();
  WallProblem w;
  w.problem.goals = {{0.3, 0.9}};
  const PlannerResult result = r.make("LineConnect", {})->solve(w.problem);
  expect_valid_path(w.problem, result);
  EXPECT_EQ(result.path.size(), 2u);
  EXPECT_EQ(result.statistics.at("straight_line"), 1);
  EXPECT_EQ(result.iterations, 1u);
  // Without it, the trees find a path of their own.
  WallProblem w2;
  w2.problem.goals = {{0.3, 0.9}};
  const PlannerResult sampled =
      r.make("LineConnect", {{"straight_line_first", "false"}})->solve(w2.problem);
  expect_valid_path(w2.problem, sampled);
  EXPECT_EQ(sampled.statistics.at("straight_line"), 0);
}

TEST(MotionPlanning, LineConnectStopsAtItsIterationBudget) {
  const PlannerRegistry r = registry_with_builtins();
  WallProblem w;
  // The goal is walled in: no path.
  w.problem.is_valid = [](const double* q) { return !(q[0] >= 0.45 && q[0] <= 0.55); };
  w.problem.max_iterations = 300;
  const PlannerResult result = r.make("LineConnect", {})->solve(w.problem);
  EXPECT_EQ(result.status, PlannerStatus::kTimeout);
  EXPECT_TRUE(result.hit_iteration_limit);
  EXPECT_FALSE(result.hit_time_limit);
  EXPECT_EQ(result.iterations, 301u);
  EXPECT_TRUE(result.path.empty());
}

TEST(MotionPlanning, MotionCheckSpacing) {
  WallProblem w;
  w.problem.motion_resolution = 0.01;  // of the diagonal, sqrt(2)
  const double a[2] = {0.1, 0.5}, b[2] = {0.4, 0.5};
  EXPECT_TRUE(motion_valid(w.problem, a, b));
  // b, then the states between at most 0.01 * sqrt(2) apart: ceil(0.3 / 0.01414) = 22 segments.
  EXPECT_EQ(w.checks, 22);
  const double c[2] = {0.9, 0.5};
  EXPECT_FALSE(motion_valid(w.problem, a, c));
}

// A wall 1 cm thick 3 cm from the start and 14 cm long, which checks 7 cm apart step over. Near an
// endpoint the checks come closer together: there a backend lets states come close to obstacles (a
// hand beside a table), and the line between two checked states may cross one.
struct ThinWallNearTheStart {
  PlanningProblem problem;
  int checks = 0;
  ThinWallNearTheStart() {
    problem.joint_names = {"x", "y"};
    problem.lower = {0, 0};
    problem.upper = {1, 1};
    problem.start = {0.1, 0.5};
    problem.goals = {{0.9, 0.5}};
    problem.is_valid = [this](const double* q) {
      ++checks;
      return !(q[0] >= 0.125 && q[0] <= 0.135 && q[1] > 0.43 && q[1] < 0.57);
    };
    problem.motion_resolution = 0.05;  // 7.1 cm
    problem.max_iterations = 5000;
    problem.seed = 3;
  }
};

TEST(MotionPlanning, MotionsNearAnEndpointAreCheckedMoreFinely) {
  ThinWallNearTheStart w;
  const double* a = w.problem.start.data();
  const double* b = w.problem.goals[0].data();
  // At the coarse spacing alone the checks step over the wall: 0.1, 0.171, ...
  EXPECT_TRUE(motion_valid(w.problem, a, b));
  EXPECT_EQ(motion_check_points(w.problem, a, b).size(), 11u);  // ceil(0.8 / 0.0707) - 1
  w.problem.fine_radius = 0.1;
  w.problem.fine_resolution = 0.005;  // 7 mm
  EXPECT_FALSE(motion_valid(w.problem, a, b));
  EXPECT_FALSE(motion_valid_bisecting(w.problem, a, b));
  EXPECT_LT(motion_valid_fraction(w.problem, a, b), 0.04 / 0.8);
  // Fine only on the steps that begin or end within 0.1 of the start or the goal: the first two
  // and the last two of 12, each cut into 10; the 8 in the middle stay whole.
  const std::vector<double> points = motion_check_points(w.problem, a, b);
  EXPECT_EQ(points.size(), 11u + 4 * 9u);
  EXPECT_TRUE(std::is_sorted(points.begin(), points.end()));
  // Away from the ends, nothing changes.
  const double c[2] = {0.3, 0.5}, d[2] = {0.7, 0.5};
  w.problem.fine_resolution = 0;
  const size_t coarse = motion_check_points(w.problem, c, d).size();
  w.problem.fine_resolution = 0.005;
  EXPECT_EQ(motion_check_points(w.problem, c, d).size(), coarse);
}

TEST(MotionPlanning, PlannersFindTheThinWallWithFinerChecksNearTheEnds) {
  const PlannerRegistry r = registry_with_builtins();
  for (const std::string name : {"RRTConnect", "LineConnect"}) {
    // What the planner gets: both run the same check.
    ThinWallNearTheStart coarse;
    const PlannerResult through = r.make(name, {})->solve(coarse.problem);
    ASSERT_EQ(through.status, PlannerStatus::kExactSolution) << name;
    ThinWallNearTheStart fine;
    fine.problem.fine_radius = 0.1;
    fine.problem.fine_resolution = 0.005;
    const PlannerResult around = r.make(name, {})->solve(fine.problem);
    ASSERT_EQ(around.status, PlannerStatus::kExactSolution) << name;
    // Checked at 0.7 mm everywhere: the path found with fine checks goes round the wall, the
    // one found without goes through it.
    PlanningProblem dense = fine.problem;
    dense.fine_resolution = 0;
    dense.motion_resolution = 0.0005;
    auto path_valid = [&](const PlannerResult& result) {
      for (size_t k = 1; k < result.path.size(); ++k) {
        if (!motion_valid(dense, result.path[k - 1].data(), result.path[k].data())) return false;
      }
      return true;
    };
    EXPECT_FALSE(path_valid(through)) << name;
    EXPECT_TRUE(path_valid(around)) << name;
  }
}

}  // namespace
}  // namespace taskmatrix::core
