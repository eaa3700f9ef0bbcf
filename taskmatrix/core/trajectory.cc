#include "taskmatrix/core/trajectory.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace taskmatrix::core {

Trajectory::Trajectory(std::vector<Eigen::VectorXd> waypoints, const Eigen::VectorXd& vmax,
                       const Eigen::VectorXd& amax)
    : waypoints_(std::move(waypoints)) {
  if (waypoints_.empty()) throw std::invalid_argument("a trajectory needs at least one waypoint");
  const Eigen::Index n = waypoints_.front().size();
  if (vmax.size() != n || amax.size() != n) {
    throw std::invalid_argument("velocity and acceleration limits need one value per joint");
  }
  if (!(vmax.array() > 0).all() || !(amax.array() > 0).all() || !vmax.allFinite() ||
      !amax.allFinite()) {
    throw std::invalid_argument("velocity and acceleration limits must be positive and finite");
  }
  for (const Eigen::VectorXd& w : waypoints_) {
    if (w.size() != n) throw std::invalid_argument("waypoints differ in size");
    if (!w.allFinite()) throw std::invalid_argument("a waypoint holds NaN or infinity");
  }
  double start = 0;
  for (size_t k = 0; k + 1 < waypoints_.size(); ++k) {
    const Eigen::VectorXd delta = waypoints_[k + 1] - waypoints_[k];
    // Limits on the normalized path parameter s in [0, 1].
    double rate_limit = std::numeric_limits<double>::infinity();
    double accel_limit = std::numeric_limits<double>::infinity();
    for (Eigen::Index i = 0; i < n; ++i) {
      const double d = std::abs(delta[i]);
      if (d == 0) continue;
      rate_limit = std::min(rate_limit, vmax[i] / d);
      accel_limit = std::min(accel_limit, amax[i] / d);
    }
    Segment seg;
    if (std::isfinite(rate_limit)) {
      if (rate_limit * rate_limit / accel_limit <= 1.0) {  // trapezoid: reaches the rate limit
        seg.ramp = rate_limit / accel_limit;
        seg.peak_rate = rate_limit;
        seg.duration = 1.0 / rate_limit + seg.ramp;
      } else {  // triangle
        seg.ramp = std::sqrt(1.0 / accel_limit);
        seg.peak_rate = accel_limit * seg.ramp;
        seg.duration = 2 * seg.ramp;
      }
    }
    segments_.push_back(seg);
    segment_start_.push_back(start);
    start += seg.duration;
  }
}

double Trajectory::waypoint_time(size_t k) const {
  if (k == 0) return 0;
  return segment_start_[k - 1] + segments_[k - 1].duration;
}

TrajectorySample Trajectory::sample(double t) const {
  TrajectorySample out;
  const Eigen::Index n = waypoints_.front().size();
  out.velocity = Eigen::VectorXd::Zero(n);
  out.acceleration = Eigen::VectorXd::Zero(n);
  if (segments_.empty() || t >= duration()) {
    out.position = waypoints_.back();
    return out;
  }
  t = std::max(t, 0.0);
  size_t k = static_cast<size_t>(std::upper_bound(segment_start_.begin(), segment_start_.end(), t) -
                                 segment_start_.begin()) -
             1;
  const Segment& seg = segments_[k];
  const double tau = t - segment_start_[k];
  double s = 0, ds = 0, dds = 0;
  if (seg.duration > 0) {
    const double accel = seg.peak_rate / seg.ramp;
    if (tau < seg.ramp) {
      s = 0.5 * accel * tau * tau;
      ds = accel * tau;
      dds = accel;
    } else if (tau <= seg.duration - seg.ramp) {
      s = 0.5 * accel * seg.ramp * seg.ramp + seg.peak_rate * (tau - seg.ramp);
      ds = seg.peak_rate;
    } else {
      const double left = seg.duration - tau;
      s = 1.0 - 0.5 * accel * left * left;
      ds = accel * left;
      dds = -accel;
    }
  }
  const Eigen::VectorXd delta = waypoints_[k + 1] - waypoints_[k];
  out.position = waypoints_[k] + s * delta;
  out.velocity = ds * delta;
  out.acceleration = dds * delta;
  return out;
}

}  // namespace taskmatrix::core
