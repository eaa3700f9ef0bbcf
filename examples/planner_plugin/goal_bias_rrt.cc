// An example planner plugin: RRT with goal bias (LaValle's RRT, every goal_bias-th sample is a
// goal), written against taskmatrix/core/motion_planning.h only. Deterministic by the
// problem's seed and bounded by its iterations (one iteration per sample).
#include <cstdint>
#include <limits>
#include <random>

#include "taskmatrix/core/motion_planning.h"

namespace {

using taskmatrix::core::Configuration;
using taskmatrix::core::PlannerResult;
using taskmatrix::core::PlannerStatus;
using taskmatrix::core::PlanningBudget;
using taskmatrix::core::PlanningProblem;

class GoalBiasRRT : public taskmatrix::core::Planner {
 public:
  GoalBiasRRT(double range, double goal_bias) : range_(range), goal_bias_(goal_bias) {}

  PlannerResult solve(const PlanningProblem& p) override {
    PlannerResult result;
    const size_t n = p.lower.size();
    std::mt19937_64 rng(p.seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    PlanningBudget budget(p.max_iterations, p.time_limit_s);
    const double range = range_ > 0 ? range_ : 0.2 * taskmatrix::core::space_extent(p);
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<Configuration> nodes{p.start};
    std::vector<int> parent{-1};
    int reached = -1;
    Configuration sample(n);
    while (reached < 0 && !budget()) {
      const bool to_goal = unit(rng) < goal_bias_;
      if (to_goal) {
        sample = p.goals[std::uniform_int_distribution<size_t>(0, p.goals.size() - 1)(rng)];
      } else {
        for (size_t i = 0; i < n; ++i)
          sample[i] = p.lower[i] + unit(rng) * (p.upper[i] - p.lower[i]);
      }
      size_t near = 0;
      double best = std::numeric_limits<double>::infinity();
      for (size_t k = 0; k < nodes.size(); ++k) {
        const double d =
            taskmatrix::core::configuration_distance(nodes[k].data(), sample.data(), n);
        if (d < best) best = d, near = k;
      }
      Configuration next = sample;
      if (best > range) {
        for (size_t i = 0; i < n; ++i)
          next[i] = nodes[near][i] + (sample[i] - nodes[near][i]) * range / best;
      }
      if (!taskmatrix::core::motion_valid(p, nodes[near].data(), next.data())) continue;
      nodes.push_back(next);
      parent.push_back(static_cast<int>(near));
      for (const Configuration& goal : p.goals) {
        if (next == goal) reached = static_cast<int>(nodes.size()) - 1;
      }
    }
    result.planning_time_s = taskmatrix::core::seconds_since(t0);
    result.iterations = budget.evaluations();
    result.hit_iteration_limit = budget.iterations_out();
    result.hit_time_limit = budget.clock_out();
    result.statistics["graph_states"] = static_cast<double>(nodes.size());
    if (reached < 0) {
      result.status = PlannerStatus::kTimeout;
      return result;
    }
    for (int k = reached; k >= 0; k = parent[static_cast<size_t>(k)]) {
      result.path.insert(result.path.begin(), nodes[static_cast<size_t>(k)]);
    }
    result.status = PlannerStatus::kExactSolution;
    return result;
  }

 private:
  double range_;
  double goal_bias_;
};

}  // namespace

TASKMATRIX_PLANNER_PLUGIN(registrar) {
  taskmatrix::core::PlannerType type;
  type.name = "GoalBiasRRT";
  type.doc = "RRT towards a goal every goal_bias of its samples (an example plugin)";
  type.params = {
      {"range",
       taskmatrix::core::ParamType::kNumber,
       false,
       0.0,
       {},
       "longest step (rad or m); 0: a fifth of the space's extent"},
      {"goal_bias",
       taskmatrix::core::ParamType::kNumber,
       false,
       0.05,
       {},
       "fraction of samples that are a goal, in [0, 1]"},
  };
  type.check = [](const taskmatrix::core::PlannerParams& params) -> std::string {
    const double bias = std::get<double>(params.at("goal_bias"));
    if (bias < 0 || bias > 1) return "parameter 'goal_bias' must be in [0, 1]";
    if (std::get<double>(params.at("range")) < 0) return "parameter 'range' must be 0 or more";
    return "";
  };
  type.make = [](const taskmatrix::core::PlannerParams& params) {
    return std::make_unique<GoalBiasRRT>(std::get<double>(params.at("range")),
                                         std::get<double>(params.at("goal_bias")));
  };
  registrar.add(std::move(type));
}
