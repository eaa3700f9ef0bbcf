#include "taskmatrix/core/trajectory.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace taskmatrix::core {
namespace {

Eigen::VectorXd vec(std::initializer_list<double> v) {
  Eigen::VectorXd out(static_cast<Eigen::Index>(v.size()));
  Eigen::Index i = 0;
  for (double x : v) out[i++] = x;
  return out;
}

TEST(Trajectory, RespectsLimitsPassesWaypointsAndStopsAtEach) {
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> u(-2, 2);
  for (int trial = 0; trial < 50; ++trial) {
    std::vector<Eigen::VectorXd> path;
    for (int k = 0; k < 5; ++k) path.push_back(vec({u(rng), u(rng), u(rng)}));
    const Eigen::VectorXd vmax = vec({1.0, 0.5, 2.0}), amax = vec({2.0, 1.0, 0.5});
    const Trajectory traj(path, vmax, amax);
    for (size_t k = 0; k < path.size(); ++k) {
      const TrajectorySample s = traj.sample(traj.waypoint_time(k));
      EXPECT_LT((s.position - path[k]).norm(), 1e-9);
      EXPECT_LT(s.velocity.norm(), 1e-9);
    }
    for (double t = 0; t <= traj.duration(); t += traj.duration() / 2000) {
      const TrajectorySample s = traj.sample(t);
      EXPECT_TRUE(((s.velocity.array().abs() - vmax.array()) <= 1e-9).all()) << t;
      EXPECT_TRUE(((s.acceleration.array().abs() - amax.array()) <= 1e-9).all()) << t;
    }
  }
}

TEST(Trajectory, IsTheFastestRestToRestProfileForOneJoint) {
  // 2 rad at 1 rad/s and 2 rad/s^2: 0.5 s ramps, 1.5 s cruise: 2.5 s.
  const Trajectory trapezoid({vec({0}), vec({2})}, vec({1}), vec({2}));
  EXPECT_NEAR(trapezoid.duration(), 2.5, 1e-12);
  // 0.5 rad never reaches 1 rad/s: a triangle of 2 * sqrt(0.5 / 2) = 1 s.
  const Trajectory triangle({vec({0}), vec({0.5})}, vec({1}), vec({2}));
  EXPECT_NEAR(triangle.duration(), 1.0, 1e-12);
  EXPECT_NEAR(triangle.sample(0.5).position[0], 0.25, 1e-12);
}

TEST(Trajectory, RepeatedWaypointsAndSinglePointsTakeNoTime) {
  EXPECT_EQ(Trajectory({vec({1, 2})}, vec({1, 1}), vec({1, 1})).duration(), 0.0);
  EXPECT_EQ(Trajectory({vec({1, 2}), vec({1, 2})}, vec({1, 1}), vec({1, 1})).duration(), 0.0);
}

TEST(Trajectory, RejectsBadInput) {
  EXPECT_THROW(Trajectory({}, vec({1}), vec({1})), std::invalid_argument);
  EXPECT_THROW(Trajectory({vec({0}), vec({NAN})}, vec({1}), vec({1})), std::invalid_argument);
  EXPECT_THROW(Trajectory({vec({0}), vec({1})}, vec({0}), vec({1})), std::invalid_argument);
  EXPECT_THROW(Trajectory({vec({0}), vec({1, 2})}, vec({1}), vec({1})), std::invalid_argument);
}

}  // namespace
}  // namespace taskmatrix::core
