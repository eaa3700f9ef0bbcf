#include "taskmatrix/planners/line_connect.h"

#include <algorithm>
#include <limits>
#include <random>

namespace taskmatrix::planners {

namespace {

struct Node {
  core::Configuration q;
  int parent = -1;
};

using Tree = std::vector<Node>;

enum class Growth { kTrapped, kAdvanced, kReached };

class LineConnect : public core::Planner {
 public:
  LineConnect(double range, bool straight_line_first, int shortcuts)
      : range_(range), straight_line_first_(straight_line_first), shortcuts_(shortcuts) {}

  core::PlannerResult solve(const core::PlanningProblem& p) override {
    core::PlannerResult result;
    const size_t n = p.lower.size();
    std::mt19937_64 rng(p.seed);
    core::PlanningBudget budget(p.max_iterations, p.time_limit_s);
    const double range = range_ > 0 ? range_ : 0.2 * core::space_extent(p);
    const auto t_plan = std::chrono::steady_clock::now();
    std::vector<core::Configuration> path;
    double straight = 0;

    if (straight_line_first_) {
      for (const core::Configuration& goal : p.goals) {
        if (budget()) break;
        if (core::motion_valid(p, p.start.data(), goal.data())) {
          path = {p.start, goal};
          straight = 1;
          break;
        }
      }
    }
    Tree from_start{{p.start, -1}};
    Tree from_goals;
    for (const core::Configuration& goal : p.goals) from_goals.push_back({goal, -1});
    Tree* a = &from_start;
    Tree* b = &from_goals;
    std::vector<double> sample(n);
    while (path.empty() && !budget()) {
      for (size_t i = 0; i < n; ++i) {
        sample[i] = std::uniform_real_distribution<double>(p.lower[i], p.upper[i])(rng);
      }
      if (extend(p, *a, sample, range) != Growth::kTrapped) {
        const core::Configuration target = a->back().q;
        Growth g = Growth::kAdvanced;
        while (g == Growth::kAdvanced) g = extend(p, *b, target, range);
        if (g == Growth::kReached) path = join(from_start, from_goals);
      }
      std::swap(a, b);
    }
    result.planning_time_s = core::seconds_since(t_plan);
    result.iterations = budget.evaluations();
    result.hit_iteration_limit = budget.iterations_out();
    result.hit_time_limit = budget.clock_out();
    result.statistics["graph_states"] = static_cast<double>(from_start.size() + from_goals.size());
    result.statistics["straight_line"] = straight;
    if (path.empty()) {
      result.status = core::PlannerStatus::kTimeout;
      return result;
    }
    result.status = core::PlannerStatus::kExactSolution;
    if (p.simplify_rounds > 0 && path.size() > 2) {
      const auto t_simplify = std::chrono::steady_clock::now();
      core::PlanningBudget safety(0, p.simplify_time_s);
      result.statistics["shortcuts"] = shortcut(p, path, rng, safety);
      result.simplification_hit_time_limit = safety.clock_out();
      result.simplification_time_s = core::seconds_since(t_simplify);
    }
    result.path = std::move(path);
    return result;
  }

 private:
  static size_t nearest(const Tree& tree, const core::Configuration& q) {
    size_t best = 0;
    double best_d = std::numeric_limits<double>::infinity();
    for (size_t k = 0; k < tree.size(); ++k) {
      const double d = core::configuration_distance(tree[k].q.data(), q.data(), q.size());
      if (d < best_d) {
        best_d = d;
        best = k;
      }
    }
    return best;
  }

  // One step of at most `range` from the nearest node of `tree` towards `target`.
  static Growth extend(const core::PlanningProblem& p, Tree& tree,
                       const core::Configuration& target, double range) {
    const size_t from = nearest(tree, target);
    const core::Configuration& q = tree[from].q;
    const double d = core::configuration_distance(q.data(), target.data(), q.size());
    core::Configuration next = target;
    const bool reaches = d <= range;
    if (!reaches) {
      for (size_t i = 0; i < q.size(); ++i) next[i] = q[i] + (target[i] - q[i]) * range / d;
    }
    if (!core::motion_valid(p, q.data(), next.data())) return Growth::kTrapped;
    tree.push_back({std::move(next), static_cast<int>(from)});
    return reaches ? Growth::kReached : Growth::kAdvanced;
  }

  // The path from the start tree's root to the goal tree's root through the two trees' last
  // nodes (which hold the same configuration).
  static std::vector<core::Configuration> join(const Tree& from_start, const Tree& from_goals) {
    std::vector<core::Configuration> path;
    for (int k = static_cast<int>(from_start.size()) - 1; k >= 0; k = from_start[k].parent) {
      path.push_back(from_start[k].q);
    }
    std::reverse(path.begin(), path.end());
    for (int k = from_goals[from_goals.size() - 1].parent; k >= 0; k = from_goals[k].parent) {
      path.push_back(from_goals[k].q);
    }
    return path;
  }

  // Random shortcuts (two waypoints joined by a valid straight motion drop those between),
  // `shortcuts_` attempts per round; returns how many were taken.
  double shortcut(const core::PlanningProblem& p, std::vector<core::Configuration>& path,
                  std::mt19937_64& rng, core::PlanningBudget& safety) const {
    double taken = 0;
    for (int round = 0; round < p.simplify_rounds; ++round) {
      for (int k = 0; k < shortcuts_ && path.size() > 2; ++k) {
        if (safety()) return taken;
        const size_t last = path.size() - 1;
        size_t i = std::uniform_int_distribution<size_t>(0, last)(rng);
        size_t j = std::uniform_int_distribution<size_t>(0, last)(rng);
        if (i > j) std::swap(i, j);
        if (j < i + 2) continue;
        if (core::motion_valid(p, path[i].data(), path[j].data())) {
          path.erase(path.begin() + static_cast<std::ptrdiff_t>(i) + 1,
                     path.begin() + static_cast<std::ptrdiff_t>(j));
          ++taken;
        }
      }
    }
    return taken;
  }

  double range_;
  bool straight_line_first_;
  int shortcuts_;
};

}  // namespace

void register_planners(core::PlannerRegistrar& registrar) {
  core::PlannerType type;
  type.name = "LineConnect";
  type.doc =
      "the straight line to each goal first, then bidirectional RRT-Connect, then "
      "random shortcuts (taskmatrix/planners)";
  type.params = {
      {"range",
       core::ParamType::kNumber,
       false,
       0.0,
       {},
       "longest extension step (rad or m); 0: a fifth of the space's extent"},
      {"straight_line_first",
       core::ParamType::kBool,
       false,
       true,
       {},
       "try the straight line to each goal before sampling"},
      {"shortcuts",
       core::ParamType::kInteger,
       false,
       std::int64_t{20},
       {},
       "random shortcut attempts per simplification round"},
  };
  type.check = [](const core::PlannerParams& params) -> std::string {
    if (std::get<double>(params.at("range")) < 0) return "parameter 'range' must be 0 or more";
    const std::int64_t s = std::get<std::int64_t>(params.at("shortcuts"));
    if (s < 0 || s > 100000) return "parameter 'shortcuts' must be in 0..100000";
    return "";
  };
  type.make = [](const core::PlannerParams& params) {
    return std::make_unique<LineConnect>(
        std::get<double>(params.at("range")), std::get<bool>(params.at("straight_line_first")),
        static_cast<int>(std::get<std::int64_t>(params.at("shortcuts"))));
  };
  registrar.add(std::move(type));
}

}  // namespace taskmatrix::planners
