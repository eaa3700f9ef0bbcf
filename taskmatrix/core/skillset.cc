#include "taskmatrix/core/skillset.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "taskmatrix/core/trajectory_follower.h"

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

std::vector<double> Skillset::clamped_configuration(
    const std::vector<std::string>& chain_names) const {
  std::vector<double> q = configuration(chain_names);
  size_t k = 0;
  for (const std::string& name : chain_names) {
    const ChainInfo& c = chain(name);
    for (size_t i = 0; i < c.lower.size() && k < q.size(); ++i, ++k) {
      q[k] = std::clamp(q[k], c.lower[i], c.upper[i]);
    }
  }
  return q;
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

ExecutionReport Skillset::execute(const std::vector<std::string>& chain_names,
                                  const Trajectory& trajectory, const ExecutionOptions& options) {
  ExecutionReport report;
  std::optional<TrajectoryFollower> follower;
  try {
    follower.emplace(*this, chain_names, timed(trajectory), options);
  } catch (const std::invalid_argument& e) {
    report.message = e.what();
    return report;
  }
  const double t0 = time();
  while (true) {
    if (std::optional<ExecutionReport> done = follower->step()) return *done;
    const StepReport step = advance();
    if (step.unstable) {
      report = follower->report();
      report.duration_s = time() - t0;
      report.status = ExecutionStatus::kSimulationUnstable;
      report.message = step.message;
      return report;
    }
  }
}

}  // namespace taskmatrix::core
