// Following a timed joint-space motion one control period at a time, for task programs,
// which are stepped by the executive and must not block. Skillset::execute is the blocking
// form of the same loop.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "taskmatrix/core/skillset.h"

namespace taskmatrix::core {

// A timed motion: a sample for every t in [0, duration], ending at rest at `goal`.
struct TimedMotion {
  double duration = 0;
  std::function<TrajectorySample(double)> sample;
  Eigen::VectorXd goal;
};
TimedMotion timed(const Trajectory& trajectory);
// Linear interpolation between keyframes at their times (velocity = slope, no acceleration
// feed-forward). Throws std::invalid_argument for fewer than two keyframes, times that do not
// increase, or rows of different sizes.
TimedMotion piecewise_linear(const std::vector<double>& times,
                             const std::vector<Eigen::VectorXd>& positions);

class TrajectoryFollower {
 public:
  // Starts at the skillset's current time. Throws std::invalid_argument if the motion does not
  // have one value per joint of the chains.
  TrajectoryFollower(Skillset& skills, std::vector<std::string> chains, TimedMotion motion,
                     ExecutionOptions options = {});
  // Call once per control period, before the simulation advances: checks what the last
  // period did (tracking, collisions) and commands the next sample. Returns the report once
  // the motion has ended (completed, collision or tracking error); nullopt while it runs.
  std::optional<ExecutionReport> step();
  const std::vector<std::string>& chains() const { return chains_; }
  // What the motion has done so far (tracking error, collision seen).
  const ExecutionReport& report() const { return report_; }

 private:
  ExecutionReport finish(ExecutionStatus status, std::string message);
  // "<robot part> with <other> (depth d mm)" of the first collision seen.
  std::string collision_pair() const;

  Skillset& skills_;
  std::vector<std::string> chains_;
  TimedMotion motion_;
  ExecutionOptions options_;
  double t0_ = 0;
  int steps_ = 0;  // control periods the motion lasts
  int k_ = 0;      // samples commanded
  Eigen::VectorXd last_commanded_;
  double settle_until_ = -1;  // set when the last sample has been tracked
  ExecutionReport report_;
};

}  // namespace taskmatrix::core
