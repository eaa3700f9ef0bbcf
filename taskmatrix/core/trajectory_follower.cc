#include "taskmatrix/core/trajectory_follower.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace taskmatrix::core {

namespace {

std::vector<double> to_std(const Eigen::VectorXd& v) { return {v.data(), v.data() + v.size()}; }

double max_abs_difference(const std::vector<double>& a, const Eigen::VectorXd& b) {
  double e = 0;
  for (size_t i = 0; i < a.size(); ++i)
    e = std::max(e, std::abs(a[i] - b[static_cast<Eigen::Index>(i)]));
  return e;
}

}  // namespace

TimedMotion timed(const Trajectory& trajectory) {
  TimedMotion m;
  m.duration = trajectory.duration();
  m.sample = [trajectory](double t) { return trajectory.sample(t); };
  m.goal = trajectory.waypoints().back();
  return m;
}

TimedMotion piecewise_linear(const std::vector<double>& times,
                             const std::vector<Eigen::VectorXd>& positions) {
  if (times.size() < 2 || times.size() != positions.size()) {
    throw std::invalid_argument("a piecewise-linear motion needs two or more keyframes");
  }
  for (size_t k = 1; k < times.size(); ++k) {
    if (!(times[k] > times[k - 1]) || positions[k].size() != positions[0].size()) {
      throw std::invalid_argument("keyframe times must increase and rows must have one size");
    }
  }
  TimedMotion m;
  m.duration = times.back() - times.front();
  m.goal = positions.back();
  m.sample = [times, positions](double t) {
    t = std::clamp(t + times.front(), times.front(), times.back());
    size_t k = 1;
    while (k + 1 < times.size() && t > times[k]) ++k;
    const double dt = times[k] - times[k - 1];
    const double s = (t - times[k - 1]) / dt;
    TrajectorySample out;
    out.position = positions[k - 1] + s * (positions[k] - positions[k - 1]);
    out.velocity = (positions[k] - positions[k - 1]) / dt;
    out.acceleration = Eigen::VectorXd::Zero(out.position.size());
    if (t >= times.back()) out.velocity.setZero();
    return out;
  };
  return m;
}

TrajectoryFollower::TrajectoryFollower(Skillset& skills, std::vector<std::string> chains,
                                       TimedMotion motion, ExecutionOptions options)
    : skills_(skills),
      chains_(std::move(chains)),
      motion_(std::move(motion)),
      options_(options),
      t0_(skills.time()) {
  if (static_cast<size_t>(motion_.goal.size()) != skills_.dof(chains_)) {
    throw std::invalid_argument("the trajectory does not have one value per joint of the chains");
  }
  steps_ = static_cast<int>(std::ceil(motion_.duration / skills_.control_period() - 1e-9));
}

std::string TrajectoryFollower::collision_pair() const {
  char depth[48];
  std::snprintf(depth, sizeof depth, " (depth %.1f mm)", report_.collision->depth_m * 1000);
  return report_.collision->robot_part + " with " + report_.collision->other + depth;
}

ExecutionReport TrajectoryFollower::finish(ExecutionStatus status, std::string message) {
  report_.status = status;
  report_.message = std::move(message);
  report_.duration_s = skills_.time() - t0_;
  return report_;
}

std::optional<ExecutionReport> TrajectoryFollower::step() {
  const double period = skills_.control_period();
  if (k_ > 0) {
    const std::vector<double> q = skills_.configuration(chains_);
    if (k_ <= steps_ && settle_until_ < 0) {
      report_.max_tracking_error =
          std::max(report_.max_tracking_error, max_abs_difference(q, last_commanded_));
    }
    std::vector<Collision> hits = skills_.collisions(chains_);
    hits.erase(std::remove_if(hits.begin(), hits.end(),
                              [&](const Collision& c) {
                                return std::find(options_.may_touch.begin(),
                                                 options_.may_touch.end(),
                                                 c.other) != options_.may_touch.end();
                              }),
               hits.end());
    if (!hits.empty()) {
      if (!report_.collision) report_.collision = hits.front();
      if (options_.stop_on_collision) {
        skills_.command(chains_, skills_.clamped_configuration(chains_));  // hold where it is
        return finish(ExecutionStatus::kCollision, "collision of " + collision_pair());
      }
    }
  }
  if (k_ < steps_) {
    ++k_;
    const TrajectorySample s = motion_.sample(std::min(k_ * period, motion_.duration));
    skills_.command(chains_, to_std(s.position), to_std(s.velocity), to_std(s.acceleration));
    last_commanded_ = s.position;
    return std::nullopt;
  }
  if (settle_until_ < 0) {
    skills_.command(chains_, to_std(motion_.goal));
    settle_until_ = skills_.time() + options_.settle_time_s;
    k_ = steps_ + 1;
  }
  report_.final_error = max_abs_difference(skills_.configuration(chains_), motion_.goal);
  if (report_.final_error <= options_.position_tolerance) {
    return finish(report_.collision ? ExecutionStatus::kCollision : ExecutionStatus::kCompleted,
                  report_.collision ? "touched on the way: " + collision_pair() : "");
  }
  if (skills_.time() >= settle_until_ - 1e-12) {
    // The joint furthest from its goal, by name, with where it is and where it was sent.
    const std::vector<double> q = skills_.configuration(chains_);
    size_t worst = 0;
    for (size_t i = 0; i < q.size(); ++i) {
      const double e = std::abs(q[i] - motion_.goal[static_cast<Eigen::Index>(i)]);
      if (e > std::abs(q[worst] - motion_.goal[static_cast<Eigen::Index>(worst)])) worst = i;
    }
    const std::string joint = q.empty() ? std::string() : skills_.joint_name(chains_, worst);
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "%.4f from the goal after %.2f s of settling (joint '%s' at %.4f, sent to %.4f)",
                  report_.final_error, options_.settle_time_s, joint.c_str(),
                  q.empty() ? 0.0 : q[worst],
                  q.empty() ? 0.0 : motion_.goal[static_cast<Eigen::Index>(worst)]);
    return finish(ExecutionStatus::kTrackingError, buf);
  }
  return std::nullopt;
}

}  // namespace taskmatrix::core
