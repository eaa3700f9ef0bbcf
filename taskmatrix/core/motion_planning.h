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

// Whether the straight motion from `a` (assumed valid) to `b` is valid: `b` first, then the
// states between them at most motion_resolution * space_extent apart (OMPL's discrete motion
// validator's order and spacing).
inline bool motion_valid(const PlanningProblem& p, const double* a, const double* b) {
  const size_t n = p.lower.size();
  if (!p.is_valid(b)) return false;
  const double step = p.motion_resolution * space_extent(p);
  const double d = configuration_distance(a, b, n);
  const int segments = step > 0 ? static_cast<int>(std::ceil(d / step)) : 1;
  std::vector<double> q(n);
  for (int k = 1; k < segments; ++k) {
    const double t = static_cast<double>(k) / segments;
    for (size_t i = 0; i < n; ++i) q[i] = a[i] + t * (b[i] - a[i]);
    if (!p.is_valid(q.data())) return false;
  }
  return true;
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
inline constexpr int kPlannerPluginApi = 1;

}  // namespace taskmatrix::core

// Exported whatever the plugin's default symbol visibility.
#define TASKMATRIX_PLANNER_PLUGIN(registrar)                                              \
  extern "C" __attribute__((visibility("default"))) int taskmatrix_planner_plugin_api() { \
    return ::taskmatrix::core::kPlannerPluginApi;                                         \
  }                                                                                       \
  extern "C" __attribute__((visibility("default"))) void taskmatrix_register_planners(    \
      ::taskmatrix::core::PlannerRegistrar& registrar)
