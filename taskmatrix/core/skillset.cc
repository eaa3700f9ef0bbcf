#include "taskmatrix/core/skillset.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "taskmatrix/core/trajectory_follower.h"

namespace taskmatrix::core {

namespace {

PlanResult plan_failure(PlanStatus status, std::string message) {
  PlanResult r;
  r.status = status;
  r.message = std::move(message);
  return r;
}

bool all_finite(const Pose& pose) {
  return pose.position.allFinite() && pose.orientation.coeffs().allFinite();
}

// While alive, the skillset counts a query as running.
class QueryScope {
 public:
  explicit QueryScope(int& depth) : depth_(depth) { ++depth_; }
  ~QueryScope() { --depth_; }
  QueryScope(const QueryScope&) = delete;
  QueryScope& operator=(const QueryScope&) = delete;

 private:
  int& depth_;
};

}  // namespace

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

double Skillset::palm_depth(const std::string& side) const {
  const HandSpec* hand = profile().find_hand(side);
  if (!hand) throw std::invalid_argument("robot " + profile().name + " has no " + side + " hand");
  return do_palm_depth(*hand);
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

void Skillset::check_chains(const std::vector<std::string>& chain_names) const {
  if (chain_names.empty()) throw std::invalid_argument("no chains given");
  for (size_t i = 0; i < chain_names.size(); ++i) {
    const std::string& name = chain_names[i];
    if (std::none_of(chains().begin(), chains().end(),
                     [&](const ChainInfo& c) { return c.name == name; })) {
      throw std::invalid_argument("robot '" + profile().name + "' has no chain '" + name + "'");
    }
    if (std::find(chain_names.begin(), chain_names.begin() + static_cast<long>(i), name) !=
        chain_names.begin() + static_cast<long>(i)) {
      throw std::invalid_argument("chain '" + name + "' is listed twice");
    }
  }
}

const std::string& Skillset::joint_name(const std::vector<std::string>& chain_names,
                                        size_t index) const {
  for (const std::string& name : chain_names) {
    const ChainInfo& c = chain(name);
    if (index < c.joints.size()) return c.joints[index];
    index -= c.joints.size();
  }
  throw std::out_of_range("joint index past the chains' joints");
}

void Skillset::check_values(const std::vector<std::string>& chain_names,
                            const std::vector<double>& values, const char* what) const {
  const size_t n = dof(chain_names);
  if (values.size() != n) {
    std::string names;
    for (const std::string& c : chain_names) names += (names.empty() ? "" : ",") + c;
    throw std::invalid_argument(std::string(what) + " has " + std::to_string(values.size()) +
                                " values but chains [" + names + "] have " + std::to_string(n) +
                                " joints");
  }
  for (size_t i = 0; i < values.size(); ++i) {
    if (!std::isfinite(values[i])) {
      throw std::invalid_argument(std::string(what) + " value for joint '" +
                                  joint_name(chain_names, i) + "' is not finite");
    }
  }
}

void Skillset::check_ik_options(const std::vector<std::string>& chain_names,
                                const IkOptions& options) const {
  if (!options.start.empty()) check_values(chain_names, options.start, "IK start");
  if (!options.joint_weights.empty()) {
    check_values(chain_names, options.joint_weights, "IK joint weights");
    for (size_t i = 0; i < options.joint_weights.size(); ++i) {
      if (options.joint_weights[i] < 0) {
        throw std::invalid_argument("IK joint weight for joint '" + joint_name(chain_names, i) +
                                    "' is negative");
      }
    }
  }
}

int Skillset::outside_limits(const std::vector<std::string>& chain_names,
                             const std::vector<double>& values, double tolerance) const {
  size_t k = 0;
  for (const std::string& name : chain_names) {
    const ChainInfo& c = chain(name);
    for (size_t i = 0; i < c.joints.size(); ++i, ++k) {
      if (values[k] < c.lower[i] - tolerance || values[k] > c.upper[i] + tolerance) {
        return static_cast<int>(k);
      }
    }
  }
  return -1;
}

std::vector<double> Skillset::configuration(const std::vector<std::string>& chain_names) const {
  check_chains(chain_names);
  return do_configuration(chain_names);
}

Pose Skillset::frame_pose_at(const std::vector<std::string>& chain_names,
                             const std::vector<double>& values, const std::string& frame) {
  check_chains(chain_names);
  check_values(chain_names, values, "configuration");
  return do_frame_pose_at(chain_names, values, frame);
}

IkResult Skillset::solve_ik(const std::vector<std::string>& chain_names, const std::string& frame,
                            const Pose& target, const IkOptions& options) {
  IkResult result;
  try {
    check_chains(chain_names);
    check_ik_options(chain_names, options);
  } catch (const std::invalid_argument& e) {
    result.reason = e.what();
    return result;
  }
  if (all_finite(target)) {
    result = do_solve_ik(chain_names, frame, target, options);
  } else {
    result.reason = "the target pose is not finite";
  }
  ++work_.ik_calls;
  work_.ik_time_s += result.time_s;
  return result;
}

bool Skillset::is_valid(const std::vector<std::string>& chain_names,
                        const std::vector<double>& values,
                        const std::vector<std::string>& may_touch) {
  check_chains(chain_names);
  check_values(chain_names, values, "configuration");
  if (!may_touch.empty()) {
    PlanOptions named;
    named.may_touch = may_touch;
    const std::string error = do_plan_options_error(named);
    if (!error.empty()) throw std::invalid_argument(error);
  }
  if (outside_limits(chain_names, values, kLimitRounding) >= 0) return false;
  const bool valid = do_is_valid(chain_names, values, may_touch);
  ++work_.collision_checks;
  return valid;
}

double Skillset::clearance(const std::vector<std::string>& chain_names,
                           const std::vector<double>& values, double max_distance_m) {
  check_chains(chain_names);
  check_values(chain_names, values, "configuration");
  if (!(std::isfinite(max_distance_m) && max_distance_m > 0)) {
    throw std::invalid_argument("clearance cap must be a positive number of metres");
  }
  return do_clearance(chain_names, values, max_distance_m);
}

std::optional<PlanResult> Skillset::plan_input_error(const std::vector<std::string>& chain_names,
                                                     const PlanOptions& options) const {
  try {
    check_chains(chain_names);
  } catch (const std::invalid_argument& e) {
    return plan_failure(PlanStatus::kInvalidInput, e.what());
  }
  if (std::string why = do_plan_options_error(options); !why.empty()) {
    return plan_failure(PlanStatus::kInvalidInput, std::move(why));
  }
  return std::nullopt;
}

PlanResult Skillset::plan_to_configuration(const std::vector<std::string>& chain_names,
                                           const std::vector<double>& goal,
                                           const PlanOptions& options) {
  PlanResult result;
  if (std::optional<PlanResult> bad = plan_input_error(chain_names, options)) {
    result = std::move(*bad);
  } else {
    try {
      check_values(chain_names, goal, "goal");
      if (const int i = outside_limits(chain_names, goal, kLimitRounding); i >= 0) {
        const ChainInfo* c = nullptr;
        size_t k = static_cast<size_t>(i);
        for (const std::string& name : chain_names) {
          c = &chain(name);
          if (k < c->joints.size()) break;
          k -= c->joints.size();
        }
        char buf[200];
        std::snprintf(buf, sizeof buf,
                      "goal value %.6g for joint '%s' is outside its limits [%.6g, %.6g]",
                      goal[static_cast<size_t>(i)], c->joints[k].c_str(), c->lower[k], c->upper[k]);
        result = plan_failure(PlanStatus::kInvalidInput, buf);
      } else {
        const QueryScope query(query_depth_);
        result = do_plan(chain_names, {goal}, options);
      }
    } catch (const std::invalid_argument& e) {
      result = plan_failure(PlanStatus::kInvalidInput, e.what());
    }
  }
  return note_plan("configuration", std::move(result));
}

PlanResult Skillset::plan_to_poses(const std::vector<std::string>& chain_names,
                                   const std::string& frame, const std::vector<Pose>& targets,
                                   const PlanOptions& options, const IkOptions& ik) {
  return note_plan("poses", plan_to_poses_unrecorded(chain_names, frame, targets, options, ik));
}

PlanResult Skillset::plan_to_poses_unrecorded(const std::vector<std::string>& chain_names,
                                              const std::string& frame,
                                              const std::vector<Pose>& targets,
                                              const PlanOptions& options, const IkOptions& ik) {
  if (std::optional<PlanResult> bad = plan_input_error(chain_names, options)) return *bad;
  if (targets.empty()) return plan_failure(PlanStatus::kInvalidInput, "no target poses");
  try {
    check_ik_options(chain_names, ik);
  } catch (const std::invalid_argument& e) {
    return plan_failure(PlanStatus::kInvalidInput, e.what());
  }
  const QueryScope query(query_depth_);
  PlanResult total;
  total.status = PlanStatus::kIkFailure;
  std::string ik_reasons;  // every pose's IK failure: the detail
  int unreachable = 0, in_collision = 0, best_pose = -1;
  double best_position = 0, best_angle = 0;
  bool any_planned = false;
  for (size_t k = 0; k < targets.size(); ++k) {
    IkResult solved;
    if (all_finite(targets[k])) {
      solved = do_solve_ik(chain_names, frame, targets[k], ik);
    } else {
      solved.reason = "the target pose is not finite";
    }
    total.ik_time_s += solved.time_s;
    ++work_.ik_calls;
    if (solved.status == IkStatus::kInvalidInput) {
      total.status = PlanStatus::kInvalidInput;
      total.message = "target pose " + std::to_string(k) + ": " + solved.reason;
      return total;
    }
    if (solved.status != IkStatus::kSolved) {
      ik_reasons += (ik_reasons.empty() ? "" : "; ") + std::string("pose ") + std::to_string(k) +
                    ": " + to_string(solved.status) + " (" + solved.reason + ")";
      (solved.status == IkStatus::kInCollision ? in_collision : unreachable) += 1;
      const bool better =
          best_pose < 0 || solved.position_error_m < best_position ||
          (solved.position_error_m == best_position && solved.orientation_error_rad < best_angle);
      if (better) {
        best_pose = static_cast<int>(k);
        best_position = solved.position_error_m;
        best_angle = solved.orientation_error_rad;
      }
      continue;
    }
    const PlanResult r = do_plan(chain_names, solved.solutions, options);
    any_planned = true;
    total.planning_time_s += r.planning_time_s;
    total.simplification_time_s += r.simplification_time_s;
    total.planning_hit_time_limit |= r.planning_hit_time_limit;
    total.simplification_hit_time_limit |= r.simplification_hit_time_limit;
    total.planner_iterations += r.planner_iterations;
    total.collision_checks += r.collision_checks;
    total.graph_states += r.graph_states;
    total.plan_calls += r.plan_calls;
    total.status = r.status;
    total.message = "pose " + std::to_string(k) + ": " + r.message;
    if (r.status == PlanStatus::kInvalidStart || r.status == PlanStatus::kInvalidInput)
      return total;  // no other pose can do better
    if (r.success()) {
      total.path = r.path;
      total.goal_index = static_cast<int>(k);
      total.message.clear();
      return total;
    }
  }
  if (!any_planned) {
    // A summary of bounded length; every attempt is in `detail`.
    char best[160];
    std::snprintf(best, sizeof best, "; the closest, pose %d, ended %.1f cm and %.1f deg off",
                  best_pose, best_position * 100, best_angle * 180 / M_PI);
    total.message = "no target pose has an IK solution: " + std::to_string(targets.size()) +
                    (targets.size() == 1 ? " pose" : " poses") + " tried (" +
                    std::to_string(unreachable) + " unreachable, " + std::to_string(in_collision) +
                    " with every solution in collision)" + (best_pose >= 0 ? best : "");
    total.detail = ik_reasons;
  }
  return total;
}

PlanResult Skillset::plan_to_region(const std::vector<std::string>& chain_names,
                                    const GoalRegion& region, const PlanOptions& options) {
  return note_plan("region", plan_to_region_unrecorded(chain_names, region, options));
}

PlanResult Skillset::plan_to_region_unrecorded(const std::vector<std::string>& chain_names,
                                               const GoalRegion& region,
                                               const PlanOptions& options) {
  if (std::optional<PlanResult> bad = plan_input_error(chain_names, options)) return *bad;
  if (!region.sample || region.max_draws <= 0 || region.max_goals <= 0) {
    return plan_failure(PlanStatus::kInvalidInput,
                        "a goal region needs a sampler and positive draw and goal counts");
  }
  const QueryScope query(query_depth_);
  const size_t n = dof(chain_names);
  std::vector<std::vector<double>> goals;
  std::mt19937_64 rng(options.seed);
  for (int draw = 0; draw < region.max_draws && static_cast<int>(goals.size()) < region.max_goals;
       ++draw) {
    std::optional<std::vector<double>> q = region.sample(rng);
    if (!q) continue;
    if (q->size() != n ||
        !std::all_of(q->begin(), q->end(), [](double v) { return std::isfinite(v); })) {
      return plan_failure(PlanStatus::kInvalidInput,
                          "the goal region sampler returned a configuration of the wrong size "
                          "or with NaN");
    }
    // A goal's check is part of the plan's work, not an is_valid call of the program's.
    if (outside_limits(chain_names, *q, kLimitRounding) < 0 && do_is_valid(chain_names, *q, {})) {
      goals.push_back(*q);
    }
  }
  if (goals.empty()) {
    return plan_failure(PlanStatus::kInvalidGoal, "none of " + std::to_string(region.max_draws) +
                                                      " draws from the goal region is valid");
  }
  return do_plan(chain_names, goals, options);
}

PlanResult Skillset::note_plan(const char* kind, PlanResult result) {
  PlanCallRecord r;
  r.time_s = time();
  r.kind = kind;
  r.status = to_string(result.status);
  r.planner_runs = result.plan_calls;
  r.planning_time_s = result.planning_time_s;
  r.simplification_time_s = result.simplification_time_s;
  r.planning_hit_time_limit = result.planning_hit_time_limit;
  r.simplification_hit_time_limit = result.simplification_hit_time_limit;
  r.planner_iterations = result.planner_iterations;
  r.path_digest = path_digest(result.path);
  r.ik_time_s = result.ik_time_s;
  r.collision_checks = result.collision_checks;
  r.path_states = static_cast<int>(result.path.size());
  for (size_t k = 1; k < result.path.size(); ++k) {
    double sq = 0;
    for (size_t i = 0; i < result.path[k].size(); ++i) {
      const double dq = result.path[k][i] - result.path[k - 1][i];
      sq += dq * dq;
    }
    r.path_length += std::sqrt(sq);
  }
  work_.collision_checks += result.collision_checks;
  work_.plans.push_back(std::move(r));
  return result;
}

void Skillset::command(const std::vector<std::string>& chain_names,
                       const std::vector<double>& positions, const std::vector<double>& velocities,
                       const std::vector<double>& accelerations) {
  check_chains(chain_names);
  check_values(chain_names, positions, "command");
  if (!velocities.empty()) check_values(chain_names, velocities, "command velocity");
  if (!accelerations.empty()) check_values(chain_names, accelerations, "command acceleration");
  std::vector<double> clamped = positions;
  size_t k = 0;
  for (const std::string& name : chain_names) {
    const ChainInfo& c = chain(name);
    for (size_t i = 0; i < c.joints.size(); ++i, ++k) {
      const double lo = c.lower[i], hi = c.upper[i];
      if (positions[k] < lo - kCommandClampTolerance ||
          positions[k] > hi + kCommandClampTolerance) {
        char buf[200];
        std::snprintf(buf, sizeof buf,
                      "command %.6g for joint '%s' is outside its limits [%.6g, %.6g]",
                      positions[k], c.joints[i].c_str(), lo, hi);
        throw std::invalid_argument(buf);
      }
      clamped[k] = std::clamp(positions[k], lo, hi);
    }
  }
  do_command(chain_names, clamped, velocities, accelerations);
}

StepReport Skillset::advance() {
  ++work_.control_periods;
  StepReport report = do_advance();
  if (record_every_ > 0 && (work_.control_periods - record_from_) % record_every_ == 0) {
    record_state_now();
  }
  return report;
}

std::vector<Collision> Skillset::collisions(const std::vector<std::string>& chain_names) const {
  check_chains(chain_names);
  return do_collisions(chain_names);
}

void Skillset::attach(const std::string& object, const std::string& side) {
  if (!do_holder_of(object).empty()) {
    throw std::invalid_argument("object '" + object + "' is already attached");
  }
  if (!profile().find_hand(side)) throw std::invalid_argument("no hand on side '" + side + "'");
  do_attach(object, side);
}

void Skillset::detach(const std::string& object) {
  if (do_holder_of(object).empty()) {
    throw std::invalid_argument("object '" + object + "' is not attached");
  }
  do_detach(object);
}

void Skillset::record_states(double rate_hz) {
  if (!(std::isfinite(rate_hz) && rate_hz >= 0)) {
    throw std::invalid_argument("recording rate must be a non-negative number of Hz");
  }
  if (rate_hz == 0) {
    record_every_ = 0;
    return;
  }
  record_every_ = std::max(1, static_cast<int>(std::lround(1.0 / (rate_hz * control_period()))));
  record_from_ = work_.control_periods;
  recording_ = StateRecording{};
  recording_.nq = do_state_size();
  recording_.frame_period_s = record_every_ * control_period();
  record_state_now();
}

void Skillset::record_state_now() {
  if (record_every_ == 0) return;
  const size_t before = recording_.qpos.size();
  do_append_state(recording_.qpos);
  if (recording_.qpos.size() != before + static_cast<size_t>(recording_.nq)) {
    throw std::logic_error("the backend's state frame has " +
                           std::to_string(recording_.qpos.size() - before) + " numbers, not " +
                           std::to_string(recording_.nq));
  }
  recording_.times.push_back(time());
}

void Skillset::note_removal(int body) {
  if (record_every_ > 0) recording_.removals.push_back({time(), body});
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
