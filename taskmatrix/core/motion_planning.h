// Motion planning as a service any planner provides, whatever its library: a problem (joint
// bounds, a start, goals, a validity callback and the resolution at which motions are checked,
// work and clock bounds, a seed), a result (a status, a path, work counts and named
// statistics), a planner interface, and a registry of planner types by name with declared
// parameters. Nothing here names a simulator or a planning library: the backend (for example
// taskmatrix/mujoco/motion_planner.h) poses the problem, a planner library (taskmatrix/ompl,
// taskmatrix/planners, or a plugin) solves it.
//
// Everything a planner needs is header-only (the standard library alone), so a plugin built
// outside the project against these headers links nothing of the project's: see
// TASKMATRIX_PLANNER_PLUGIN at the end and examples/planner_plugin/.
//
// Determinism: a planner must give the same result for the same problem (same seed) whatever
// the machine's load when max_iterations > 0 bounds its work; the clock (time_limit_s) is a
// safety net whose firing the result reports (PlannerResult::hit_time_limit).
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "taskmatrix/core/parameters.h"

namespace taskmatrix::core {

// One value per planned joint (rad or m), in the problem's joint order.
using Configuration = std::vector<double>;

struct PlanningProblem {
  std::vector<std::string> joint_names;  // for messages
  std::vector<double> lower, upper;      // joint bounds; lower[i] <= upper[i]
  Configuration start;                   // valid and within bounds
  // Valid and within bounds; an exact solution ends exactly at one of them.
  std::vector<Configuration> goals;
  // True if the configuration (joint_names.size() values) is valid: collision-free, with the
  // clearance the backend asks for. Every call is work the backend counts.
  std::function<bool(const double* q)> is_valid;
  // Motions are valid when states at most this fraction of the space's extent (the diagonal
  // of the bounds box, OMPL's convention) apart along the straight line are: motion_valid().
  double motion_resolution = 0.005;
  // Where is_valid lets states come closer to obstacles (near the start and the goals, where a
  // hand starts beside or ends next to something), motions are checked more finely: the
  // steps of a motion (motion_resolution apart) that begin or end within fine_radius (rad or
  // m, every joint) of the start or a goal have states at most fine_resolution x the extent
  // apart (at most 2^20 per step). fine_resolution 0 (or not below motion_resolution): no
  // finer checks.
  double fine_radius = 0;
  double fine_resolution = 0;
  // The planner's budget: > 0: at most this many iterations (evaluations of the termination
  // condition, about one sampling step each), time_limit_s being a safety net; 0: the clock.
  unsigned max_iterations = 10000;
  double time_limit_s = 60;  // in (0, 86400]
  // Path simplification after an exact solution: rounds of fixed work (0: none), with a clock
  // safety net. A planner without simplification ignores them.
  int simplify_rounds = 3;
  double simplify_time_s = 30;
  std::uint32_t seed = 1;  // > 0
};

enum class PlannerStatus {
  kExactSolution,        // path from the start to a goal: the only success
  kApproximateSolution,  // path ending near, not at, a goal
  kTimeout,              // no path within the budget
  kInvalidStart,
  kInvalidGoal,
  kFailed,  // anything else; the message says what
};

struct PlannerResult {
  PlannerStatus status = PlannerStatus::kFailed;
  std::vector<Configuration> path;  // start first; every motion between waypoints valid
  std::string message;              // for a status other than exact: why
  std::uint64_t iterations = 0;     // evaluations of the termination condition
  bool hit_iteration_limit = false;
  // The clock stopped planning (or simplifying): the result may differ under load.
  bool hit_time_limit = false;
  bool simplification_hit_time_limit = false;
  double planning_time_s = 0;
  double simplification_time_s = 0;
  // Further counts by name, e.g. "graph_states" (states in the planner's graph or trees).
  std::map<std::string, double> statistics;
};

// ---- Helpers for planners written against this interface.

// Euclidean distance between two configurations of n values.
inline double configuration_distance(const double* a, const double* b, size_t n) {
  double s = 0;
  for (size_t i = 0; i < n; ++i) s += (a[i] - b[i]) * (a[i] - b[i]);
  return std::sqrt(s);
}

// The diagonal of the bounds box.
inline double space_extent(const PlanningProblem& p) {
  double s = 0;
  for (size_t i = 0; i < p.lower.size(); ++i)
    s += (p.upper[i] - p.lower[i]) * (p.upper[i] - p.lower[i]);
  return std::sqrt(s);
}

// Whether `q` lies within the problem's fine_radius of its start or a goal (every joint).
inline bool near_endpoint(const PlanningProblem& p, const double* q) {
  auto near = [&](const Configuration& e) {
    for (size_t i = 0; i < e.size(); ++i) {
      if (std::abs(q[i] - e[i]) > p.fine_radius) return false;
    }
    return true;
  };
  if (near(p.start)) return true;
  for (const Configuration& g : p.goals) {
    if (near(g)) return true;
  }
  return false;
}

// The states checked along the straight motion from `a` to `b`, as fractions of the way in
// (0, 1), in order: at most motion_resolution x the extent apart, and at most fine_resolution
// x the extent apart on the steps that begin or end near an endpoint (near_endpoint).
inline std::vector<double> motion_check_points(const PlanningProblem& p, const double* a,
                                               const double* b) {
  const size_t n = p.lower.size();
  const double extent = space_extent(p);
  const double step = p.motion_resolution * extent;
  const double fine_step = p.fine_resolution > 0 && p.fine_resolution < p.motion_resolution
                               ? p.fine_resolution * extent
                               : 0;
  const double d = configuration_distance(a, b, n);
  const int segments = step > 0 ? static_cast<int>(std::ceil(d / step)) : 1;
  std::vector<double> q(n), points;
  auto near_at = [&](double t) {
    for (size_t i = 0; i < n; ++i) q[i] = a[i] + t * (b[i] - a[i]);
    return near_endpoint(p, q.data());
  };
  // Whether each step's ends are near an endpoint, each state tested once.
  bool near0 = fine_step > 0 && near_at(0);
  for (int k = 1; k <= segments; ++k) {
    const double t0 = static_cast<double>(k - 1) / segments;
    const double t1 = static_cast<double>(k) / segments;
    const bool near1 = fine_step > 0 && near_at(t1);
    if (near0 || near1) {
      const int sub = static_cast<int>(std::min(std::ceil(d / segments / fine_step), 1048576.0));
      for (int j = 1; j < sub; ++j) points.push_back(t0 + (t1 - t0) * j / sub);
    }
    if (k < segments) points.push_back(t1);
    near0 = near1;
  }
  return points;
}

// Whether the straight motion from `a` (assumed valid) to `b` is valid: `b` first, then the
// states motion_check_points() names, in order (OMPL's discrete motion validator's spacing;
// taskmatrix/ompl gives OMPL planners this same check).
inline bool motion_valid(const PlanningProblem& p, const double* a, const double* b) {
  const size_t n = p.lower.size();
  if (!p.is_valid(b)) return false;
  std::vector<double> q(n);
  for (double t : motion_check_points(p, a, b)) {
    for (size_t i = 0; i < n; ++i) q[i] = a[i] + t * (b[i] - a[i]);
    if (!p.is_valid(q.data())) return false;
  }
  return true;
}

// The same check in OMPL's discrete motion validator's order: `b`, then the middle of the
// states between and the middles of the halves on either side of it, breadth first (a
// collision in the middle of a long motion is found after few checks).
inline bool motion_valid_bisecting(const PlanningProblem& p, const double* a, const double* b) {
  const size_t n = p.lower.size();
  if (!p.is_valid(b)) return false;
  const std::vector<double> points = motion_check_points(p, a, b);
  if (points.empty()) return true;
  std::vector<double> q(n);
  std::vector<std::pair<int, int>> ranges{{0, static_cast<int>(points.size()) - 1}};
  for (size_t next = 0; next < ranges.size(); ++next) {
    const auto [first, last] = ranges[next];
    const int mid = (first + last) / 2;
    for (size_t i = 0; i < n; ++i) q[i] = a[i] + points[mid] * (b[i] - a[i]);
    if (!p.is_valid(q.data())) return false;
    if (first < mid) ranges.emplace_back(first, mid - 1);
    if (last > mid) ranges.emplace_back(mid + 1, last);
  }
  return true;
}

// The same motion checked from `a` on, in order, `b` last: the fraction of the way to the last
// valid state before the first invalid one (0: `a`), or 1 when the motion is valid.
inline double motion_valid_fraction(const PlanningProblem& p, const double* a, const double* b) {
  const size_t n = p.lower.size();
  std::vector<double> q(n);
  double last = 0;
  std::vector<double> points = motion_check_points(p, a, b);
  points.push_back(1.0);
  for (double t : points) {
    for (size_t i = 0; i < n; ++i) q[i] = a[i] + t * (b[i] - a[i]);
    if (!p.is_valid(q.data())) return last;
    last = t;
  }
  return 1.0;
}

// The termination condition of PlanningProblem: an iteration budget (when given) checked
// before the clock, latched, so that the result says which of the two stopped the planner.
class PlanningBudget {
 public:
  PlanningBudget(std::uint64_t max_iterations, double time_limit_s)
      : max_iterations_(max_iterations),
        deadline_(std::chrono::steady_clock::now() +
                  std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                      std::chrono::duration<double>(time_limit_s))) {}
  // True when the planner must stop; each call is one iteration.
  bool operator()() {
    if (iterations_out_ || clock_out_) return true;
    ++evaluations_;
    if (max_iterations_ > 0 && evaluations_ > max_iterations_) return iterations_out_ = true;
    if (std::chrono::steady_clock::now() > deadline_) return clock_out_ = true;
    return false;
  }
  bool clock_out() const { return clock_out_; }
  bool iterations_out() const { return iterations_out_; }
  std::uint64_t evaluations() const { return evaluations_; }

 private:
  std::uint64_t max_iterations_;
  std::chrono::steady_clock::time_point deadline_;
  std::uint64_t evaluations_ = 0;
  bool iterations_out_ = false, clock_out_ = false;
};

inline double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// ---- Planners and their registry.

class Planner {
 public:
  virtual ~Planner() = default;
  // Plans for `problem`; never throws for a problem it cannot solve (a status says so).
  virtual PlannerResult solve(const PlanningProblem& problem) = 0;
};

// Checked parameter values by name: every declared parameter, given or its default.
using PlannerParams = std::map<std::string, ParamValue>;

struct PlannerType {
  std::string name;  // 1 to 64 of [A-Za-z0-9_-]
  std::string doc;
  // Whether it optimizes its path until its budget is spent (an anytime planner).
  bool optimizes_paths = false;
  std::vector<ParamSpec> params;  // checked by the registry before make
  std::function<std::unique_ptr<Planner>(const PlannerParams&)> make;
  // Optional: a further check of the values (beyond their declared types); "" when fine.
  std::function<std::string(const PlannerParams&)> check;
};

// What a planner library registers its planner types with.
class PlannerRegistrar {
 public:
  virtual ~PlannerRegistrar() = default;
  // Throws std::invalid_argument for a taken or malformed name, or a type without make.
  virtual void add(PlannerType type) = 0;
};

class PlannerRegistry : public PlannerRegistrar {
 public:
  void add(PlannerType type) override;
  const PlannerType* find(const std::string& name) const;
  std::vector<std::string> names() const;  // sorted
  // "" if `name` is registered and `raw` passes its parameter specs and check; otherwise what
  // is wrong ("unknown planner 'X' (known: ...)", "planner X: parameter 'k': ...").
  std::string check(const std::string& name, const RawParams& raw) const;
  // A planner with checked parameters; throws std::invalid_argument with check's message.
  std::unique_ptr<Planner> make(const std::string& name, const RawParams& raw) const;

 private:
  std::map<std::string, PlannerType> types_;
};

// The process's registry: built-in planners are registered by whoever assembles the program
// (the harness), plugins by the plugin loader.
PlannerRegistry& planner_registry();

// ---- Plugins: a shared library defines its entry point with this macro, e.g.
//   TASKMATRIX_PLANNER_PLUGIN(registrar) { registrar.add({...}); }
// The loader checks taskmatrix_planner_plugin_api() against its own kPlannerPluginApi before
// calling taskmatrix_register_planners. Change the number when anything above changes layout.
inline constexpr int kPlannerPluginApi = 2;

}  // namespace taskmatrix::core

// Exported whatever the plugin's default symbol visibility.
#define TASKMATRIX_PLANNER_PLUGIN(registrar)                                              \
  extern "C" __attribute__((visibility("default"))) int taskmatrix_planner_plugin_api() { \
    return ::taskmatrix::core::kPlannerPluginApi;                                         \
  }                                                                                       \
  extern "C" __attribute__((visibility("default"))) void taskmatrix_register_planners(    \
      ::taskmatrix::core::PlannerRegistrar& registrar)
