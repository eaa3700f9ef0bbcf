#include "taskmatrix/core/skillset.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace taskmatrix::core {

const char* to_string(ExecutionStatus status) {
  switch (status) {
    case ExecutionStatus::kCompleted:
      return "completed";
    case ExecutionStatus::kCollision:
      return "collision";
    case ExecutionStatus::kTrackingError:
      return "tracking_error";
    case ExecutionStatus::kSimulationUnstable:
      return "sim_unstable";
    case ExecutionStatus::kInvalidInput:
      return "invalid_input";
  }
  return "unknown";
}

const ChainInfo& Skillset::chain(std::string_view name) const {
  for (const ChainInfo& c : chains()) {
    if (c.name == name) return c;
  }
  throw std::invalid_argument("unknown chain '" + std::string(name) + "'");
}

size_t Skillset::dof(const std::vector<std::string>& chain_names) const {
  size_t n = 0;
  for (const std::string& name : chain_names) n += chain(name).joints.size();
  return n;
}

const Posture& Skillset::posture(std::string_view name) const {
  const auto it = profile().postures.find(std::string(name));
  if (it == profile().postures.end()) {
    throw std::invalid_argument("robot '" + profile().name + "' has no posture '" +
                                std::string(name) + "'");
  }
  return it->second;
}

Trajectory Skillset::time_parameterize(const std::vector<std::string>& chain_names,
                                       const std::vector<std::vector<double>>& path,
                                       double speed_scale) const {
  if (!(speed_scale > 0 && speed_scale <= 1)) {
    throw std::invalid_argument("speed scale must be in (0, 1]");
  }
  const size_t n = dof(chain_names);
  Eigen::VectorXd vmax(n), amax(n);
  size_t i = 0;
  for (const std::string& name : chain_names) {
    const ChainInfo& c = chain(name);
    for (size_t k = 0; k < c.joints.size(); ++k, ++i) {
      vmax[i] = c.speed.velocity * speed_scale;
      amax[i] = c.speed.acceleration * speed_scale * speed_scale;
    }
  }
  std::vector<Eigen::VectorXd> waypoints;
  for (const auto& q : path) {
    if (q.size() != n) {
      throw std::invalid_argument("a path waypoint has " + std::to_string(q.size()) +
                                  " values for " + std::to_string(n) + " joints");
    }
    waypoints.push_back(Eigen::Map<const Eigen::VectorXd>(q.data(), static_cast<Eigen::Index>(n)));
  }
  return Trajectory(std::move(waypoints), vmax, amax);
}

namespace {

std::vector<double> to_std(const Eigen::VectorXd& v) { return {v.data(), v.data() + v.size()}; }

double max_abs_difference(const std::vector<double>& a, const Eigen::VectorXd& b) {
  double e = 0;
  for (size_t i = 0; i < a.size(); ++i)
    e = std::max(e, std::abs(a[i] - b[static_cast<Eigen::Index>(i)]));
  return e;
}

}  // namespace

ExecutionReport Skillset::execute(const std::vector<std::string>& chain_names,
                                  const Trajectory& trajectory, const ExecutionOptions& options) {
  ExecutionReport report;
  size_t n = 0;
  try {
    n = dof(chain_names);
  } catch (const std::invalid_argument& e) {
    report.message = e.what();
    return report;
  }
  if (trajectory.waypoints().empty() ||
      static_cast<size_t>(trajectory.waypoints().front().size()) != n) {
    report.message = "the trajectory does not have one value per joint of the chains";
    return report;
  }
  const double t0 = time();
  const double period = control_period();
  const double duration = trajectory.duration();
  auto fail_on_step = [&](const StepReport& step) {
    report.duration_s = time() - t0;
    report.status = ExecutionStatus::kSimulationUnstable;
    report.message = step.message;
    return report;
  };
  auto check_collision = [&]() {
    const std::vector<Collision> hits = collisions(chain_names);
    if (hits.empty()) return false;
    if (!report.collision) report.collision = hits.front();
    return options.stop_on_collision;
  };
  auto stop_for_collision = [&]() {
    command(chain_names, configuration(chain_names));  // hold where it is
    report.duration_s = time() - t0;
    report.status = ExecutionStatus::kCollision;
    report.message =
        "collision of " + report.collision->robot_part + " with " + report.collision->other;
    return report;
  };

  const int steps = static_cast<int>(std::ceil(duration / period - 1e-9));
  for (int k = 1; k <= steps; ++k) {
    const TrajectorySample s = trajectory.sample(std::min(k * period, duration));
    command(chain_names, to_std(s.position), to_std(s.velocity), to_std(s.acceleration));
    const StepReport step = advance();
    if (step.unstable) return fail_on_step(step);
    report.max_tracking_error = std::max(
        report.max_tracking_error, max_abs_difference(configuration(chain_names), s.position));
    if (check_collision()) return stop_for_collision();
  }
  const Eigen::VectorXd& goal = trajectory.waypoints().back();
  command(chain_names, to_std(goal));
  report.final_error = max_abs_difference(configuration(chain_names), goal);
  const double settle_until = time() + options.settle_time_s;
  while (report.final_error > options.position_tolerance && time() < settle_until - 1e-12) {
    const StepReport step = advance();
    if (step.unstable) return fail_on_step(step);
    if (check_collision()) return stop_for_collision();
    report.final_error = max_abs_difference(configuration(chain_names), goal);
  }
  report.duration_s = time() - t0;
  if (report.final_error > options.position_tolerance) {
    report.status = ExecutionStatus::kTrackingError;
    char buf[128];
    std::snprintf(buf, sizeof buf, "%.4f from the goal after %.2f s of settling",
                  report.final_error, options.settle_time_s);
    report.message = buf;
  } else {
    report.status = report.collision ? ExecutionStatus::kCollision : ExecutionStatus::kCompleted;
  }
  return report;
}

}  // namespace taskmatrix::core
