#include "taskmatrix/mujoco/motion_planner.h"

#include <ompl/base/PlannerTerminationCondition.h>
#include <ompl/base/ProblemDefinition.h>
#include <ompl/base/SpaceInformation.h>
#include <ompl/base/goals/GoalStates.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/base/terminationconditions/IterationTerminationCondition.h>
#include <ompl/geometric/PathGeometric.h>
#include <ompl/geometric/PathSimplifier.h>
#include <ompl/geometric/planners/est/BiEST.h>
#include <ompl/geometric/planners/est/EST.h>
#include <ompl/geometric/planners/informedtrees/BITstar.h>
#include <ompl/geometric/planners/kpiece/BKPIECE1.h>
#include <ompl/geometric/planners/kpiece/KPIECE1.h>
#include <ompl/geometric/planners/prm/LazyPRM.h>
#include <ompl/geometric/planners/prm/PRM.h>
#include <ompl/geometric/planners/rrt/RRT.h>
#include <ompl/geometric/planners/rrt/RRTConnect.h>
#include <ompl/geometric/planners/rrt/RRTstar.h>
#include <ompl/geometric/planners/sbl/SBL.h>
#include <ompl/util/Console.h>
#include <ompl/util/RandomNumbers.h>

#include <chrono>
#include <cmath>
#include <mutex>

#include "taskmatrix/mujoco/validity_checker.h"

namespace taskmatrix::mujoco {

namespace ob = ompl::base;
namespace og = ompl::geometric;

namespace {

constexpr double kLimitSlack = 0.02;      // rad or m
constexpr double kEndpointRadius = 0.25;  // rad or m

using Factory = std::function<ob::PlannerPtr(const ob::SpaceInformationPtr&)>;

const std::map<std::string, Factory>& factories() {
  static const std::map<std::string, Factory> f = {
      {"BiEST", [](auto si) { return std::make_shared<og::BiEST>(si); }},
      {"BITstar", [](auto si) { return std::make_shared<og::BITstar>(si); }},
      {"BKPIECE1", [](auto si) { return std::make_shared<og::BKPIECE1>(si); }},
      {"EST", [](auto si) { return std::make_shared<og::EST>(si); }},
      {"KPIECE1", [](auto si) { return std::make_shared<og::KPIECE1>(si); }},
      {"LazyPRM", [](auto si) { return std::make_shared<og::LazyPRM>(si); }},
      {"PRM", [](auto si) { return std::make_shared<og::PRM>(si); }},
      {"RRT", [](auto si) { return std::make_shared<og::RRT>(si); }},
      {"RRTConnect", [](auto si) { return std::make_shared<og::RRTConnect>(si); }},
      {"RRTstar", [](auto si) { return std::make_shared<og::RRTstar>(si); }},
      {"SBL", [](auto si) { return std::make_shared<og::SBL>(si); }},
  };
  return f;
}

// OMPL reports reseeding after RNGs exist as an error; reseeding is deliberate here.
class QuietOmplOutput : public ompl::msg::OutputHandler {
 public:
  void log(const std::string& text, ompl::msg::LogLevel level, const char*, int) override {
    if (level >= ompl::msg::LOG_ERROR &&
        text.find("Random number generation already started") == std::string::npos) {
      std::fprintf(stderr, "taskmatrix: OMPL: %s\n", text.c_str());
    }
  }
};

std::mutex& planning_mutex() {
  static std::mutex m;
  return m;
}

void use_quiet_output() {
  static QuietOmplOutput quiet;
  ompl::msg::useOutputHandler(&quiet);
}

// OMPL's setParam returns false for some bad values and throws for others.
bool set_param(ob::Planner& planner, const std::string& key, const std::string& value) {
  try {
    return planner.params().setParam(key, value);
  } catch (const std::exception&) {
    return false;
  }
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

std::vector<std::string> planner_names() {
  std::vector<std::string> names;
  for (const auto& [name, f] : factories()) names.push_back(name);
  return names;
}

namespace {

// A free 2-D unit square, to make a planner for asking about it (call with the planning lock).
ob::SpaceInformationPtr unit_space_info() {
  auto space = std::make_shared<ob::RealVectorStateSpace>(2);
  space->setBounds(0.0, 1.0);
  auto si = std::make_shared<ob::SpaceInformation>(space);
  si->setStateValidityChecker([](const ob::State*) { return true; });
  si->setup();
  return si;
}

}  // namespace

bool planner_optimizes_paths(const std::string& name) {
  const auto factory = factories().find(name);
  if (factory == factories().end()) return false;
  std::lock_guard<std::mutex> lock(planning_mutex());
  use_quiet_output();
  return factory->second(unit_space_info())->getSpecs().optimizingPaths;
}

std::string check_planner_spec(const PlannerSpec& spec) {
  const auto factory = factories().find(spec.name);
  if (factory == factories().end()) {
    std::string known;
    for (const auto& [name, f] : factories()) known += (known.empty() ? "" : ", ") + name;
    return "unknown planner '" + spec.name + "' (known: " + known + ")";
  }
  std::lock_guard<std::mutex> lock(planning_mutex());
  use_quiet_output();
  ob::PlannerPtr planner = factory->second(unit_space_info());
  for (const auto& [key, value] : spec.params) {
    if (!planner->params().hasParam(key)) {
      std::vector<std::string> names;
      planner->params().getParamNames(names);
      std::string known;
      for (const std::string& n : names) known += (known.empty() ? "" : ", ") + n;
      return "planner " + spec.name + " has no parameter '" + key + "' (known: " + known + ")";
    }
    if (!set_param(*planner, key, value)) {
      return "planner " + spec.name + " parameter " + key + " rejects '" + value + "'";
    }
  }
  return "";
}

MotionPlanner::MotionPlanner(const Scene& scene, const mjModel* m, mjData* d,
                             std::vector<int> joints, std::vector<Attachment> attachments)
    : scene_(scene),
      m_(m),
      d_(d),
      joints_(std::move(joints)),
      attachments_(std::move(attachments)) {}

MotionPlanner::MotionPlanner(const Scene& scene, WorkerScene& worker, std::vector<int> joints)
    : MotionPlanner(scene, worker.model(), worker.data(), std::move(joints)) {}

core::PlanResult MotionPlanner::plan(const std::vector<std::vector<double>>& goals,
                                     const PlanOptions& o) {
  core::PlanResult result;
  const mjModel* m = m_;
  mjData* d = d_;
  const size_t n = joints_.size();
  auto fail = [&](core::PlanStatus status, std::string message) {
    result.status = status;
    result.message = std::move(message);
    return result;
  };
  const auto factory = factories().find(o.planner.name);
  if (factory == factories().end())
    return fail(core::PlanStatus::kInvalidInput, "unknown planner '" + o.planner.name + "'");
  if (n == 0 || goals.empty()) return fail(core::PlanStatus::kInvalidInput, "no joints or no goal");
  if (!(o.time_limit_s > 0) || !(o.motion_resolution > 0 && o.motion_resolution < 1) ||
      o.seed == 0 || !(o.simplify_time_s >= 0) || !(o.clearance_m >= 0 && o.clearance_m < 1)) {
    return fail(core::PlanStatus::kInvalidInput,
                "time limit, resolution and seed must be positive, clearance in [0, 1) m");
  }
  std::vector<double> lo(n), hi(n), start(n);
  for (size_t i = 0; i < n; ++i) {
    lo[i] = m->jnt_range[2 * joints_[i]];
    hi[i] = m->jnt_range[2 * joints_[i] + 1];
    start[i] = d->qpos[m->jnt_qposadr[joints_[i]]];
    // Simulated joints rest slightly past a limit they are held at (soft limit constraints):
    // plan from the limit. Beyond kLimitSlack the start is invalid.
    if (start[i] < lo[i] && start[i] >= lo[i] - kLimitSlack) start[i] = lo[i];
    if (start[i] > hi[i] && start[i] <= hi[i] + kLimitSlack) start[i] = hi[i];
  }
  for (const auto& g : goals) {
    if (g.size() != n)
      return fail(core::PlanStatus::kInvalidInput, "a goal has the wrong number of values");
    for (size_t i = 0; i < n; ++i) {
      const char* joint = mj_id2name(m, mjOBJ_JOINT, joints_[i]);
      if (!std::isfinite(g[i])) {
        return fail(core::PlanStatus::kInvalidInput,
                    std::string("goal value for joint '") + joint + "' is not finite");
      }
      if (g[i] < lo[i] - 1e-9 || g[i] > hi[i] + 1e-9) {
        char buf[200];
        std::snprintf(buf, sizeof buf,
                      "goal value %.6g for joint '%s' is outside its limits [%.6g, %.6g]", g[i],
                      joint, lo[i], hi[i]);
        return fail(core::PlanStatus::kInvalidInput, buf);
      }
    }
  }

  std::lock_guard<std::mutex> lock(planning_mutex());
  use_quiet_output();
  ompl::RNG::setSeed(o.seed);

  const std::vector<double> saved(d->qpos, d->qpos + m->nq);
  for (size_t i = 0; i < n; ++i) d->qpos[m->jnt_qposadr[joints_[i]]] = start[i];
  mj_kinematics(m, d);
  ValidityChecker checker(scene_, m, d, joints_, attachments_);
  auto restore = [&] {
    std::copy(saved.begin(), saved.end(), d->qpos);
    mj_kinematics(m, d);
  };

  auto within = [&](const std::vector<double>& q) {
    for (size_t i = 0; i < n; ++i) {
      if (q[i] < lo[i] - 1e-9 || q[i] > hi[i] + 1e-9) return false;
    }
    return true;
  };
  for (size_t i = 0; i < n; ++i) {
    if (start[i] >= lo[i] - 1e-9 && start[i] <= hi[i] + 1e-9) continue;
    restore();
    char buf[200];
    std::snprintf(buf, sizeof buf, "joint '%s' starts at %.6g, outside its limits [%.6g, %.6g]",
                  mj_id2name(m, mjOBJ_JOINT, joints_[i]), start[i], lo[i], hi[i]);
    return fail(core::PlanStatus::kInvalidStart, buf);
  }
  if (checker.static_collision() || checker.in_collision(start.data())) {
    const std::string contacts = describe_robot_contacts(scene_, m, d, attachments_);
    restore();
    return fail(core::PlanStatus::kInvalidStart,
                (checker.static_collision()
                     ? "the robot is in collision where the planned joints cannot move it: "
                     : "the start configuration is in collision: ") +
                    contacts);
  }

  auto space = std::make_shared<ob::RealVectorStateSpace>(static_cast<unsigned>(n));
  ob::RealVectorBounds bounds(static_cast<unsigned>(n));
  for (size_t i = 0; i < n; ++i) {
    bounds.setLow(static_cast<unsigned>(i), lo[i]);
    bounds.setHigh(static_cast<unsigned>(i), hi[i]);
  }
  space->setBounds(bounds);
  auto si = std::make_shared<ob::SpaceInformation>(space);
  // Clearance: states keep o.clearance_m from obstacles, except within kEndpointRadius (joint
  // space, max-norm) of the start or a goal, which may be closer (a hand next to what it will
  // grasp). Without it, simplified paths graze obstacles and execution, which tracks the
  // path only to within a few millimetres, touches them.
  auto near_endpoint = [&](const double* v) {
    auto near = [&](const std::vector<double>& e) {
      for (size_t i = 0; i < n; ++i) {
        if (std::abs(v[i] - e[i]) > kEndpointRadius) return false;
      }
      return true;
    };
    if (near(start)) return true;
    for (const auto& g : goals) {
      if (near(g)) return true;
    }
    return false;
  };
  const double clearance = o.clearance_m;
  si->setStateValidityChecker([&checker, clearance, near_endpoint](const ob::State* s) {
    const auto* v = s->as<ob::RealVectorStateSpace::StateType>()->values;
    if (clearance > 0) {
      if (!checker.within_margin(v, clearance)) return true;
      if (!near_endpoint(v)) return false;
    }
    return !checker.in_collision(v, /*count=*/clearance <= 0);
  });
  si->setStateValidityCheckingResolution(o.motion_resolution);
  si->setup();

  auto pdef = std::make_shared<ob::ProblemDefinition>(si);
  ob::ScopedState<> s(space);
  for (size_t i = 0; i < n; ++i) s[i] = start[i];
  pdef->addStartState(s);
  auto goal_states = std::make_shared<ob::GoalStates>(si);
  std::vector<int> goal_index_of_state;
  for (size_t k = 0; k < goals.size(); ++k) {
    if (!within(goals[k]) || checker.in_collision(goals[k].data())) continue;
    ob::ScopedState<> g(space);
    for (size_t i = 0; i < n; ++i) g[i] = goals[k][i];
    goal_states->addState(g);
    goal_index_of_state.push_back(static_cast<int>(k));
  }
  if (goal_index_of_state.empty()) {
    restore();
    return fail(core::PlanStatus::kInvalidGoal, goals.size() == 1
                                                    ? "the goal configuration is in collision"
                                                    : "every goal configuration is in collision");
  }
  pdef->setGoal(goal_states);

  ob::PlannerPtr planner = factory->second(si);
  for (const auto& [key, value] : o.planner.params) {
    if (!planner->params().hasParam(key)) {
      restore();
      return fail(core::PlanStatus::kInvalidInput,
                  "planner " + o.planner.name + " has no parameter '" + key + "'");
    }
    if (!set_param(*planner, key, value)) {
      restore();
      return fail(core::PlanStatus::kInvalidInput,
                  "planner parameter " + key + " rejects '" + value + "'");
    }
  }
  planner->setProblemDefinition(pdef);
  planner->setup();

  const std::uint64_t checks_before = checker.checks();
  ob::PlannerTerminationCondition ptc = ob::timedPlannerTerminationCondition(o.time_limit_s);
  std::unique_ptr<ob::IterationTerminationCondition> iterations;
  if (o.max_iterations > 0) {
    iterations = std::make_unique<ob::IterationTerminationCondition>(o.max_iterations);
    ptc = ob::plannerOrTerminationCondition(ptc, *iterations);
  }
  const auto t_plan = std::chrono::steady_clock::now();
  const ob::PlannerStatus status = planner->solve(ptc);
  result.planning_time_s = seconds_since(t_plan);
  result.plan_calls = 1;
  ob::PlannerData data(si);
  planner->getPlannerData(data);
  result.graph_states = data.numVertices();

  if (status == ob::PlannerStatus::APPROXIMATE_SOLUTION) {
    result.status = core::PlanStatus::kApproximateSolution;
    result.message = "OMPL found only an approximate solution";
  } else if (status == ob::PlannerStatus::EXACT_SOLUTION) {
    result.status = core::PlanStatus::kExactSolution;
  } else if (status == ob::PlannerStatus::TIMEOUT || status == ob::PlannerStatus::UNKNOWN) {
    result.status = core::PlanStatus::kTimeout;
    result.message = "no path within " + std::to_string(o.time_limit_s) + " s";
  } else if (status == ob::PlannerStatus::INVALID_START) {
    result.status = core::PlanStatus::kInvalidStart;
  } else if (status == ob::PlannerStatus::INVALID_GOAL ||
             status == ob::PlannerStatus::UNRECOGNIZED_GOAL_TYPE) {
    result.status = core::PlanStatus::kInvalidGoal;
  } else {
    result.status = core::PlanStatus::kTimeout;
    result.message = std::string("OMPL: ") + status.asString();
  }

  if (result.status == core::PlanStatus::kExactSolution ||
      result.status == core::PlanStatus::kApproximateSolution) {
    auto path = pdef->getSolutionPath()->as<og::PathGeometric>();
    if (o.simplify_time_s > 0 && result.status == core::PlanStatus::kExactSolution) {
      const auto t_simplify = std::chrono::steady_clock::now();
      og::PathSimplifier simplifier(si, pdef->getGoal());
      const bool converged = simplifier.simplify(*path, o.simplify_time_s);
      result.simplification_time_s = seconds_since(t_simplify);
      result.simplification_hit_time_limit =
          !converged && result.simplification_time_s >= o.simplify_time_s;
    }
    for (size_t k = 0; k < path->getStateCount(); ++k) {
      const auto* v = path->getState(k)->as<ob::RealVectorStateSpace::StateType>()->values;
      result.path.emplace_back(v, v + n);
    }
    // Which goal the path ends at.
    for (size_t k = 0; k < goal_index_of_state.size(); ++k) {
      const auto* g = goal_states->getState(static_cast<unsigned>(k))
                          ->as<ob::RealVectorStateSpace::StateType>()
                          ->values;
      double dmax = 0;
      for (size_t i = 0; i < n; ++i) dmax = std::max(dmax, std::abs(g[i] - result.path.back()[i]));
      if (dmax < 1e-9) result.goal_index = goal_index_of_state[k];
    }
  }
  result.collision_checks = checker.checks() - checks_before;
  restore();
  return result;
}

}  // namespace taskmatrix::mujoco
