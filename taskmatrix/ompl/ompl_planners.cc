#include "taskmatrix/ompl/ompl_planners.h"

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
#include <ompl/tools/config/MagicConstants.h>
#include <ompl/util/Console.h>
#include <ompl/util/RandomNumbers.h>

#include <algorithm>
#include <cstdio>
#include <mutex>

namespace taskmatrix::ompl_planners {

namespace ob = ompl::base;
namespace og = ompl::geometric;

namespace {

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

// OMPL's PRM checks for a solution in a second thread that polls every millisecond and grows
// its roadmap in phases bounded by the clock (ROADMAP_BUILD_TIME), so where it stops depends
// on the machine even under an iteration budget. This PRM runs in one thread: it alternates
// growing (kPhaseIterations x 2) and expanding (kPhaseIterations), OMPL's 2:1 ratio counted in
// iterations, and looks for a solution after every phase.
class SingleThreadPRM : public og::PRM {
 public:
  using og::PRM::PRM;

  ob::PlannerStatus solve(const ob::PlannerTerminationCondition& ptc) override {
    checkValidity();
    auto* goal = dynamic_cast<ob::GoalSampleableRegion*>(pdef_->getGoal().get());
    if (goal == nullptr) return ob::PlannerStatus::UNRECOGNIZED_GOAL_TYPE;
    while (const ob::State* st = pis_.nextStart())
      startM_.push_back(addMilestone(si_->cloneState(st)));
    if (startM_.empty()) return ob::PlannerStatus::INVALID_START;
    if (!goal->couldSample()) return ob::PlannerStatus::INVALID_GOAL;
    while (goal->maxSampleCount() > goalM_.size()) {
      const ob::State* st = pis_.nextGoal();
      if (st == nullptr) break;
      goalM_.push_back(addMilestone(si_->cloneState(st)));
    }
    if (goalM_.empty()) return ob::PlannerStatus::INVALID_GOAL;
    if (!sampler_) sampler_ = si_->allocValidStateSampler();
    if (!simpleSampler_) simpleSampler_ = si_->allocStateSampler();
    std::vector<ob::State*> work(kRandomBounceSteps);
    si_->allocStates(work);
    bestCost_ = opt_->infiniteCost();
    ob::PathPtr solution;
    bool satisfied = false, grow = true;
    while (!satisfied && !ptc) {
      ob::IterationTerminationCondition phase(grow ? 2 * kPhaseIterations : kPhaseIterations);
      const ob::PlannerTerminationCondition bounded = ob::plannerOrTerminationCondition(ptc, phase);
      if (grow) {
        growRoadmap(bounded, work[0]);
      } else {
        expandRoadmap(bounded, work);
      }
      grow = !grow;
      satisfied = maybeConstructSolution(startM_, goalM_, solution);
    }
    si_->freeStates(work);
    if (solution) {
      ob::PlannerSolution psol(solution);
      psol.setPlannerName(getName());
      psol.setOptimized(opt_, bestCost_, satisfied);
      pdef_->addSolutionPath(psol);
      return ob::PlannerStatus::EXACT_SOLUTION;
    }
    const ob::Cost diff = constructApproximateSolution(startM_, goalM_, solution);
    if (!opt_->isFinite(diff)) return ob::PlannerStatus::TIMEOUT;
    pdef_->addSolutionPath(solution, true, diff.value(), getName());
    return ob::PlannerStatus::APPROXIMATE_SOLUTION;
  }

 private:
  static constexpr unsigned kPhaseIterations = 50;
  static constexpr unsigned kRandomBounceSteps = 5;  // PRM.cpp's own
};

// OMPL's PathSimplifier::simplify, with each step's work fixed instead of bounded by the clock:
// per round, shortcutting and connecting to a better goal (up to 5 times while they improve),
// B-spline smoothing (3 subdivisions), a repair pass, vertex reduction and collapsing of close
// vertices (reduction repeated up to 5 times while it helps), a repair pass; rounds stop early
// when vertex reduction no longer helps. The same path and seed give the same result; `safety`
// (the clock) is checked between steps. Returns the rounds run.
int simplify_path(og::PathSimplifier& simplifier, og::PathGeometric& path, int rounds,
                  const std::function<bool()>& safety) {
  const ob::PlannerTerminationCondition never = ob::plannerNonTerminatingCondition();
  int done = 0;
  for (; done < rounds && path.getStateCount() >= 3; ++done) {
    for (int k = 0; k < 5; ++k) {
      const bool shortcut = simplifier.shortcutPath(path);
      const bool better_goal = simplifier.findBetterGoal(path, never);
      if (!(shortcut || better_goal) || safety()) break;
    }
    if (safety()) break;
    simplifier.smoothBSpline(path, 3, path.length() / 100.0);
    path.checkAndRepair(ompl::magic::MAX_VALID_SAMPLE_ATTEMPTS);
    if (safety()) break;
    bool more = simplifier.reduceVertices(path);
    simplifier.collapseCloseVertices(path);
    for (int k = 0; k < 5 && more && !safety(); ++k) more = simplifier.reduceVertices(path);
    path.checkAndRepair(ompl::magic::MAX_VALID_SAMPLE_ATTEMPTS);
    if (!more) {
      ++done;
      break;
    }
  }
  return done;
}

using Factory = std::function<ob::PlannerPtr(const ob::SpaceInformationPtr&)>;

const std::map<std::string, Factory>& factories() {
  static const std::map<std::string, Factory> f = {
      {"BiEST", [](auto si) { return std::make_shared<og::BiEST>(si); }},
      {"BITstar", [](auto si) { return std::make_shared<og::BITstar>(si); }},
      {"BKPIECE1", [](auto si) { return std::make_shared<og::BKPIECE1>(si); }},
      {"EST", [](auto si) { return std::make_shared<og::EST>(si); }},
      {"KPIECE1", [](auto si) { return std::make_shared<og::KPIECE1>(si); }},
      {"LazyPRM", [](auto si) { return std::make_shared<og::LazyPRM>(si); }},
      {"PRM", [](auto si) { return std::make_shared<SingleThreadPRM>(si); }},
      {"RRT", [](auto si) { return std::make_shared<og::RRT>(si); }},
      {"RRTConnect", [](auto si) { return std::make_shared<og::RRTConnect>(si); }},
      {"RRTstar", [](auto si) { return std::make_shared<og::RRTstar>(si); }},
      {"SBL", [](auto si) { return std::make_shared<og::SBL>(si); }},
  };
  return f;
}

// A free 2-D unit square, to make a planner for asking about it (call with the planning lock).
ob::SpaceInformationPtr unit_space_info() {
  auto space = std::make_shared<ob::RealVectorStateSpace>(2);
  space->setBounds(0.0, 1.0);
  auto si = std::make_shared<ob::SpaceInformation>(space);
  si->setStateValidityChecker([](const ob::State*) { return true; });
  si->setup();
  return si;
}

// The parameters the scenario gave (a declared OMPL parameter left at "" keeps OMPL's value).
std::vector<std::pair<std::string, std::string>> given(const core::PlannerParams& params) {
  std::vector<std::pair<std::string, std::string>> out;
  for (const auto& [key, value] : params) {
    const std::string& text = std::get<std::string>(value);
    if (!text.empty()) out.emplace_back(key, text);
  }
  return out;
}

// "" if every given parameter accepts its value on a planner made for the unit space.
std::string check_values(const Factory& factory, const core::PlannerParams& params) {
  std::lock_guard<std::mutex> lock(planning_mutex());
  use_quiet_output();
  ob::PlannerPtr planner = factory(unit_space_info());
  for (const auto& [key, value] : given(params)) {
    if (!set_param(*planner, key, value)) return "parameter " + key + " rejects '" + value + "'";
  }
  return "";
}

// OMPL's discrete motion validator with the problem's finer checks near its endpoints
// (core::motion_check_points), in the same order.
class FineMotionValidator : public ob::MotionValidator {
 public:
  FineMotionValidator(ob::SpaceInformation* si, const core::PlanningProblem& p)
      : ob::MotionValidator(si), p_(p) {}

  bool checkMotion(const ob::State* s1, const ob::State* s2) const override {
    const bool ok = core::motion_valid_bisecting(p_, values(s1), values(s2));
    (ok ? valid_ : invalid_)++;
    return ok;
  }
  bool checkMotion(const ob::State* s1, const ob::State* s2,
                   std::pair<ob::State*, double>& last_valid) const override {
    const double t = core::motion_valid_fraction(p_, values(s1), values(s2));
    if (t >= 1.0) {
      valid_++;
      return true;
    }
    if (last_valid.first != nullptr) si_->getStateSpace()->interpolate(s1, s2, t, last_valid.first);
    last_valid.second = t;
    invalid_++;
    return false;
  }

 private:
  static const double* values(const ob::State* s) {
    return s->as<ob::RealVectorStateSpace::StateType>()->values;
  }
  const core::PlanningProblem& p_;
};

class OmplPlanner : public core::Planner {
 public:
  OmplPlanner(std::string name, Factory factory, core::PlannerParams params)
      : name_(std::move(name)), factory_(std::move(factory)), params_(std::move(params)) {}

  core::PlannerResult solve(const core::PlanningProblem& p) override;

 private:
  std::string name_;
  Factory factory_;
  core::PlannerParams params_;
};

core::PlannerResult OmplPlanner::solve(const core::PlanningProblem& p) {
  core::PlannerResult result;
  const size_t n = p.lower.size();
  std::lock_guard<std::mutex> lock(planning_mutex());
  use_quiet_output();
  ompl::RNG::setSeed(p.seed);

  auto space = std::make_shared<ob::RealVectorStateSpace>(static_cast<unsigned>(n));
  ob::RealVectorBounds bounds(static_cast<unsigned>(n));
  for (size_t i = 0; i < n; ++i) {
    bounds.setLow(static_cast<unsigned>(i), p.lower[i]);
    bounds.setHigh(static_cast<unsigned>(i), p.upper[i]);
  }
  space->setBounds(bounds);
  auto si = std::make_shared<ob::SpaceInformation>(space);
  si->setStateValidityChecker([&p](const ob::State* s) {
    return p.is_valid(s->as<ob::RealVectorStateSpace::StateType>()->values);
  });
  si->setStateValidityCheckingResolution(p.motion_resolution);
  if (p.fine_resolution > 0 && p.fine_resolution < p.motion_resolution) {
    si->setMotionValidator(std::make_shared<FineMotionValidator>(si.get(), p));
  }
  si->setup();

  auto pdef = std::make_shared<ob::ProblemDefinition>(si);
  ob::ScopedState<> s(space);
  for (size_t i = 0; i < n; ++i) s[i] = p.start[i];
  pdef->addStartState(s);
  auto goal_states = std::make_shared<ob::GoalStates>(si);
  for (const core::Configuration& goal : p.goals) {
    ob::ScopedState<> g(space);
    for (size_t i = 0; i < n; ++i) g[i] = goal[i];
    goal_states->addState(g);
  }
  pdef->setGoal(goal_states);

  ob::PlannerPtr planner = factory_(si);
  for (const auto& [key, value] : given(params_)) {
    if (!set_param(*planner, key, value)) {
      result.message = "planner " + name_ + " parameter " + key + " rejects '" + value + "'";
      return result;
    }
  }
  planner->setProblemDefinition(pdef);
  planner->setup();

  core::PlanningBudget budget(p.max_iterations, p.time_limit_s);
  const ob::PlannerTerminationCondition ptc([&budget] { return budget(); });
  const auto t_plan = std::chrono::steady_clock::now();
  const ob::PlannerStatus status = planner->solve(ptc);
  result.planning_time_s = core::seconds_since(t_plan);
  result.iterations = budget.evaluations();
  // The clock decided when it stopped the planner: always for a planner that runs to its limit,
  // and for one that stops at a solution when it had none yet.
  result.hit_time_limit = budget.clock_out();
  result.hit_iteration_limit = budget.iterations_out();
  ob::PlannerData data(si);
  planner->getPlannerData(data);
  result.statistics["graph_states"] = data.numVertices();

  if (status == ob::PlannerStatus::APPROXIMATE_SOLUTION) {
    result.status = core::PlannerStatus::kApproximateSolution;
    // How near it came: the joint-space distance (rad, and m for slide joints) from the end of
    // its best path to the nearest goal.
    char buf[96];
    std::snprintf(buf, sizeof buf, " (its path ends %.3f from the nearest of %zu goals)",
                  pdef->getSolutionDifference(), p.goals.size());
    result.message = std::string("OMPL found only an approximate solution") + buf;
  } else if (status == ob::PlannerStatus::EXACT_SOLUTION) {
    result.status = core::PlannerStatus::kExactSolution;
  } else if (status == ob::PlannerStatus::TIMEOUT || status == ob::PlannerStatus::UNKNOWN) {
    result.status = core::PlannerStatus::kTimeout;
  } else if (status == ob::PlannerStatus::INVALID_START) {
    result.status = core::PlannerStatus::kInvalidStart;
  } else if (status == ob::PlannerStatus::INVALID_GOAL ||
             status == ob::PlannerStatus::UNRECOGNIZED_GOAL_TYPE) {
    result.status = core::PlannerStatus::kInvalidGoal;
  } else {
    result.status = core::PlannerStatus::kFailed;
    result.message = std::string("OMPL: ") + status.asString();
  }

  if (result.status == core::PlannerStatus::kExactSolution ||
      result.status == core::PlannerStatus::kApproximateSolution) {
    auto path = pdef->getSolutionPath()->as<og::PathGeometric>();
    if (p.simplify_rounds > 0 && result.status == core::PlannerStatus::kExactSolution) {
      const auto t_simplify = std::chrono::steady_clock::now();
      const og::PathGeometric planned(*path);
      og::PathSimplifier simplifier(si, pdef->getGoal());
      core::PlanningBudget safety(0, p.simplify_time_s);
      simplify_path(simplifier, *path, p.simplify_rounds, [&safety] { return safety(); });
      result.simplification_hit_time_limit = safety.clock_out();
      // A repair pass may leave a path that still touches an obstacle: keep the planner's.
      if (!path->check()) *path = planned;
      result.simplification_time_s = core::seconds_since(t_simplify);
    }
    for (size_t k = 0; k < path->getStateCount(); ++k) {
      const auto* v = path->getState(k)->as<ob::RealVectorStateSpace::StateType>()->values;
      result.path.emplace_back(v, v + n);
    }
  }
  return result;
}

core::PlannerType planner_type(const std::string& name, const Factory& factory) {
  core::PlannerType type;
  type.name = name;
  type.doc = "OMPL's " + name;
  std::lock_guard<std::mutex> lock(planning_mutex());
  use_quiet_output();
  ob::PlannerPtr planner = factory(unit_space_info());
  type.optimizes_paths = planner->getSpecs().optimizingPaths;
  std::vector<std::string> names;
  planner->params().getParamNames(names);
  for (const std::string& key : names) {
    core::ParamSpec spec;
    spec.name = key;
    spec.required = false;
    spec.default_value = std::string();  // OMPL's own
    spec.doc = "OMPL parameter; range " + planner->params()[key].getRangeSuggestion();
    type.params.push_back(std::move(spec));
  }
  type.check = [factory](const core::PlannerParams& params) {
    return check_values(factory, params);
  };
  type.make = [name, factory](const core::PlannerParams& params) {
    return std::make_unique<OmplPlanner>(name, factory, params);
  };
  return type;
}

}  // namespace

void register_planners(core::PlannerRegistrar& registrar) {
  for (const auto& [name, factory] : factories()) registrar.add(planner_type(name, factory));
}

}  // namespace taskmatrix::ompl_planners
