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
#include <ompl/tools/config/MagicConstants.h>
#include <ompl/util/Console.h>
#include <ompl/util/RandomNumbers.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <optional>

#include "taskmatrix/mujoco/validity_checker.h"

namespace taskmatrix::mujoco {

namespace ob = ompl::base;
namespace og = ompl::geometric;

namespace {

constexpr double kLimitSlack = 0.02;      // rad or m
constexpr double kEndpointRadius = 0.25;  // rad or m
constexpr double kMaxTimeLimitS = 86400;  // beyond it, OMPL's deadline arithmetic overflows

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

// The planner's termination condition: an iteration budget (when given) checked before a
// clock bound, latched, so that the result says which of the two stopped the planner.
class Budget {
 public:
  Budget(std::uint64_t max_iterations, double time_limit_s)
      : max_iterations_(max_iterations),
        deadline_(std::chrono::steady_clock::now() +
                  std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                      std::chrono::duration<double>(time_limit_s))) {}
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
                             std::vector<int> joints, std::vector<Attachment> attachments,
                             std::vector<int> touch_geoms)
    : scene_(scene),
      m_(m),
      d_(d),
      joints_(std::move(joints)),
      attachments_(std::move(attachments)),
      touch_geoms_(std::move(touch_geoms)) {}

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
  if (!(o.time_limit_s > 0 && o.time_limit_s <= kMaxTimeLimitS) ||
      !(o.simplify_time_s > 0 && o.simplify_time_s <= kMaxTimeLimitS) ||
      !(o.motion_resolution > 0 && o.motion_resolution < 1) || o.seed == 0 ||
      o.simplify_rounds < 0 || !(o.clearance_m >= 0 && o.clearance_m < 1)) {
    return fail(core::PlanStatus::kInvalidInput,
                "time limits must be in (0, 86400] s, resolution in (0, 1), seed positive, "
                "simplification rounds 0 or more, clearance in [0, 1) m");
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
  // Near the start, contact with what the start may touch is allowed (shallow).
  std::optional<ValidityChecker> touching;
  if (!touch_geoms_.empty()) {
    touching.emplace(scene_, m, d, joints_, attachments_, touch_geoms_, kTouchDepth);
  }
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
  const bool start_touches_allowed =
      touching && !touching->static_collision() && !touching->in_collision(start.data());
  if (!start_touches_allowed &&
      (checker.static_collision() || checker.in_collision(start.data()))) {
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
  auto near = [&](const double* v, const std::vector<double>& e) {
    for (size_t i = 0; i < n; ++i) {
      if (std::abs(v[i] - e[i]) > kEndpointRadius) return false;
    }
    return true;
  };
  auto near_endpoint = [&](const double* v) {
    if (near(v, start)) return true;
    for (const auto& g : goals) {
      if (near(v, g)) return true;
    }
    return false;
  };
  const double clearance = o.clearance_m;
  si->setStateValidityChecker([&, clearance](const ob::State* s) {
    const auto* v = s->as<ob::RealVectorStateSpace::StateType>()->values;
    if (start_touches_allowed && near(v, start)) return !touching->in_collision(v);
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

  const std::uint64_t checks_before = checker.checks() + (touching ? touching->checks() : 0);
  Budget budget(o.max_iterations, o.time_limit_s);
  const ob::PlannerTerminationCondition ptc([&budget] { return budget(); });
  const auto t_plan = std::chrono::steady_clock::now();
  const ob::PlannerStatus status = planner->solve(ptc);
  result.planning_time_s = seconds_since(t_plan);
  result.plan_calls = 1;
  result.planner_iterations = budget.evaluations();
  // The clock decided when it stopped the planner: always for a planner that runs to its limit,
  // and for one that stops at a solution when it had none yet.
  result.planning_hit_time_limit = budget.clock_out();
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
    char buf[120];
    if (budget.iterations_out()) {
      std::snprintf(buf, sizeof buf, "no path within %u iterations", o.max_iterations);
    } else {
      std::snprintf(buf, sizeof buf, "no path within %g s", o.time_limit_s);
    }
    result.message = buf;
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
    if (o.simplify_rounds > 0 && result.status == core::PlanStatus::kExactSolution) {
      const auto t_simplify = std::chrono::steady_clock::now();
      const og::PathGeometric planned(*path);
      og::PathSimplifier simplifier(si, pdef->getGoal());
      Budget safety(0, o.simplify_time_s);
      simplify_path(simplifier, *path, o.simplify_rounds, [&safety] { return safety(); });
      result.simplification_hit_time_limit = safety.clock_out();
      // A repair pass may leave a path that still touches an obstacle: keep the planner's.
      if (!path->check()) *path = planned;
      result.simplification_time_s = seconds_since(t_simplify);
    }
    for (size_t k = 0; k < path->getStateCount(); ++k) {
      const auto* v = path->getState(k)->as<ob::RealVectorStateSpace::StateType>()->values;
      std::vector<double> q(v, v + n);
      // Within the joint limits exactly (goals may lie up to 1e-9 outside).
      for (size_t i = 0; i < n; ++i) q[i] = std::clamp(q[i], lo[i], hi[i]);
      result.path.push_back(std::move(q));
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
  result.collision_checks = checker.checks() + (touching ? touching->checks() : 0) - checks_before;
  restore();
  return result;
}

}  // namespace taskmatrix::mujoco
