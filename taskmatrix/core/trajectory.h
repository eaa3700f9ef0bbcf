// Time parameterization of a joint-space path: straight segments between waypoints, each a
// synchronized trapezoidal (or triangular) velocity profile that starts and ends at rest,
// the fastest such profile under per-joint velocity and acceleration limits. Pure math: the
// backend executes the result at its control rate.
#pragma once

#include <vector>

#include <Eigen/Core>

namespace taskmatrix::core {

struct TrajectorySample {
  Eigen::VectorXd position, velocity, acceleration;
};

class Trajectory {
 public:
  // Throws std::invalid_argument for fewer than one waypoint, mismatched sizes, non-finite
  // values, or limits that are not positive.
  Trajectory(std::vector<Eigen::VectorXd> waypoints, const Eigen::VectorXd& max_velocity,
             const Eigen::VectorXd& max_acceleration);

  double duration() const {
    return segment_start_.empty() ? 0.0 : segment_start_.back() + segments_.back().duration;
  }
  // Clamped to [0, duration()].
  TrajectorySample sample(double t) const;
  const std::vector<Eigen::VectorXd>& waypoints() const { return waypoints_; }
  // Time at which waypoint k is reached.
  double waypoint_time(size_t k) const;

 private:
  struct Segment {
    double duration = 0;   // T
    double ramp = 0;       // acceleration phase length
    double peak_rate = 0;  // ds/dt at cruise, s in [0, 1]
  };
  std::vector<Eigen::VectorXd> waypoints_;
  std::vector<Segment> segments_;
  std::vector<double> segment_start_;
};

}  // namespace taskmatrix::core
