#include "taskmatrix/mujoco/motion_planner.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <optional>
#include <stdexcept>

#include "taskmatrix/core/joint_limits.h"
#include "taskmatrix/core/motion_planning.h"
#include "taskmatrix/mujoco/validity_checker.h"

namespace taskmatrix::mujoco {

namespace {

constexpr double kEndpointRadius = 0.25;  // rad or m
// Below this (m), the clearance near an endpoint is left to the contact check itself.
constexpr double kMinRampClearance = 1e-4;
// The share of the start's own clearance from the world that the states near it keep.
constexpr double kStartFloorShare = 0.5;
// How many times closer the checks along a motion are near an endpoint.
constexpr double kFineChecks = 5;
constexpr double kMaxTimeLimitS = 86400;  // beyond it, planners' deadline arithmetic overflows
// Certifying a path: distances are measured up to this far (m), and a piece of a motion that
// moves no point farther than kCertifyFloor (m) between two contact-free states is accepted.
constexpr double kCertifyCap = 0.05;
constexpr double kCertifyFloor = 1e-4;

// Certifies a path contact-free along its straight segments by conservative advancement: the
// first state found in contact (empty if none). `clearances_at(v, wanted, out)` measures, per
// group of pairs (ValidityChecker::clearance_groups), how far the group `wanted` names is from
// contact at `v`, false when a pair is in contact; a motion changing joint i by dq_i moves a
// group's pairs at most sum(reach[i] |dq_i|) over its joints (ValidityChecker::joint_reach). A
// piece of a segment is safe for a group when that motion is within the sum of its ends'
// clearances (or below kCertifyFloor); else it is halved.
core::Configuration first_contact_along(
    const std::vector<core::Configuration>& path, const std::vector<std::vector<char>>& groups,
    const std::vector<double>& reach,
    const std::function<bool(const double*, const std::vector<char>&, std::vector<double>&)>&
        clearances_at) {
  const size_t n = reach.size();
  const size_t ng = groups.size();
  std::vector<double> motion(ng);  // per group: the most its pairs' distances change
  std::vector<char> wanted(ng);
  std::vector<double> c0, c1, cm;
  std::vector<double> q(n);
  // A piece of a segment, its ends' clearances, and the groups it has still to certify
  // (a group certified over a piece is certified over its halves: those are not measured).
  struct Piece {
    double t0, t1;
    std::vector<double> c0, c1;
    std::vector<char> open;
  };
  std::vector<Piece> pieces;
  // Waypoints are measured for every group a motion can change, once each (the end of one
  // segment is the start of the next); states inside a segment for the groups it changes.
  std::vector<char> movable(ng);
  for (size_t g = 0; g < ng; ++g) {
    movable[g] = std::any_of(groups[g].begin(), groups[g].end(), [](char c) { return c != 0; });
  }
  if (path.size() >= 2 && !clearances_at(path[0].data(), movable, c1)) return path[0];
  for (size_t k = 0; k + 1 < path.size(); ++k) {
    const core::Configuration& a = path[k];
    const core::Configuration& b = path[k + 1];
    c0 = c1;
    if (!clearances_at(b.data(), movable, c1)) return b;
    bool moves = false;
    for (size_t g = 0; g < ng; ++g) {
      motion[g] = 0;
      for (size_t i = 0; i < n; ++i) {
        if (groups[g][i]) motion[g] += reach[i] * std::abs(b[i] - a[i]);
      }
      wanted[g] = motion[g] > 0;
      moves = moves || wanted[g];
    }
    if (!moves) continue;
    pieces.assign(1, Piece{0, 1, c0, c1, wanted});
    while (!pieces.empty()) {
      Piece p = std::move(pieces.back());
      pieces.pop_back();
      bool safe = true;
      for (size_t g = 0; g < ng; ++g) {
        if (!p.open[g]) continue;
        const double moved = motion[g] * (p.t1 - p.t0);
        if (moved <= p.c0[g] + p.c1[g] || moved <= kCertifyFloor) {
          p.open[g] = 0;
        } else {
          safe = false;
        }
      }
      if (safe) continue;
      const double tm = 0.5 * (p.t0 + p.t1);
      for (size_t i = 0; i < n; ++i) q[i] = a[i] + tm * (b[i] - a[i]);
      if (!clearances_at(q.data(), p.open, cm)) return core::Configuration(q);
      pieces.push_back(Piece{tm, p.t1, cm, std::move(p.c1), p.open});
      pieces.push_back(Piece{p.t0, tm, std::move(p.c0), cm, std::move(p.open)});
    }
  }
  return core::Configuration{};
}

}  // namespace

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
  const core::PlannerRegistry& planners = core::planner_registry();
  if (planners.find(o.planner.name) == nullptr)
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
    // plan from the limit. Beyond core::kStartPastLimit the start is invalid.
    if (start[i] < lo[i] && start[i] >= lo[i] - core::kStartPastLimit) start[i] = lo[i];
    if (start[i] > hi[i] && start[i] <= hi[i] + core::kStartPastLimit) start[i] = hi[i];
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
      if (g[i] < lo[i] - core::kLimitRounding || g[i] > hi[i] + core::kLimitRounding) {
        char buf[200];
        std::snprintf(buf, sizeof buf,
                      "goal value %.6g for joint '%s' is outside its limits [%.6g, %.6g]", g[i],
                      joint, lo[i], hi[i]);
        return fail(core::PlanStatus::kInvalidInput, buf);
      }
    }
  }

  const std::vector<double> saved(d->qpos, d->qpos + m->nq);
  for (size_t i = 0; i < n; ++i) d->qpos[m->jnt_qposadr[joints_[i]]] = start[i];
  mj_kinematics(m, d);
  ValidityChecker checker(scene_, m, d, joints_, attachments_);
  checker.keep_off_visitor_route();
  // Near the start, contact with what the start may touch is allowed (shallow).
  std::optional<ValidityChecker> touching;
  if (!touch_geoms_.empty()) {
    touching.emplace(scene_, m, d, joints_, attachments_, touch_geoms_, kTouchDepth);
    touching->keep_off_visitor_route();
  }
  // Contacts the planned joints cannot change (the other hand resting against what it set
  // down) stay as they are along any path: shallow ones are left out of every check, as
  // execution leaves them out; deeper ones make the start invalid.
  if (checker.static_collision() && checker.static_depth_m() <= kStaticContactDepth) {
    checker.accept_static_contacts();
    if (touching) touching->accept_static_contacts();
  }
  auto restore = [&] {
    std::copy(saved.begin(), saved.end(), d->qpos);
    mj_kinematics(m, d);
  };

  auto within = [&](const std::vector<double>& q) {
    for (size_t i = 0; i < n; ++i) {
      if (q[i] < lo[i] - core::kLimitRounding || q[i] > hi[i] + core::kLimitRounding) return false;
    }
    return true;
  };
  for (size_t i = 0; i < n; ++i) {
    if (start[i] >= lo[i] - core::kLimitRounding && start[i] <= hi[i] + core::kLimitRounding)
      continue;
    restore();
    char buf[200];
    std::snprintf(buf, sizeof buf, "joint '%s' starts at %.6g, outside its limits [%.6g, %.6g]",
                  mj_id2name(m, mjOBJ_JOINT, joints_[i]), start[i], lo[i], hi[i]);
    return fail(core::PlanStatus::kInvalidStart, buf);
  }
  // A start in contact may be left through contact with what it may touch; a start clear of
  // everything is left as any other (the clearance below).
  const bool start_in_contact = checker.static_collision() || checker.in_collision(start.data());
  const bool start_touches_allowed = start_in_contact && touching &&
                                     !touching->static_collision() &&
                                     !touching->in_collision(start.data());
  if (start_in_contact && !start_touches_allowed) {
    const std::string contacts = describe_robot_contacts(scene_, m, d, attachments_);
    restore();
    return fail(core::PlanStatus::kInvalidStart,
                (checker.static_collision()
                     ? "the robot is in collision where the planned joints cannot move it: "
                     : "the start configuration is in collision: ") +
                    contacts);
  }

  // Clearance: states keep o.clearance_m from obstacles, except within kEndpointRadius (joint
  // space, max-norm) of the start or a goal, which may be closer (a hand next to what it will
  // grasp): there the clearance asked for grows from the endpoint's floor to o.clearance_m
  // at the radius, so a path leaves an endpoint's surroundings instead of sliding along them.
  // A goal's floor is nothing; the start's is half its own clearance from the world (at most
  // o.clearance_m): a path from a start clear of everything does not dive towards what is
  // near it on the way out (a hand a centimetre above the table, fingers beside what it has
  // just let go of). Without the ramp, simplified paths graze obstacles and execution, which
  // tracks the path only to within a few millimetres (physics: the arm's lag, the fingers
  // swinging as it accelerates), touches them.
  auto distance_from = [&](const double* v, const std::vector<double>& e) {
    double dist = 0;
    for (size_t i = 0; i < n; ++i) dist = std::max(dist, std::abs(v[i] - e[i]));
    return dist;
  };
  auto near = [&](const double* v, const std::vector<double>& e) {
    return distance_from(v, e) <= kEndpointRadius;
  };
  core::PlanningProblem problem;
  const double clearance = o.clearance_m;
  // The start's own clearance from the world, as the clearance test below measures it (a held
  // object keeps none from the robot holding it, as the robot's links keep none from each
  // other): the largest margin, to a twentieth of o.clearance_m, with nothing within it.
  double start_clear = 0;
  if (clearance > 0 && !start_touches_allowed) {
    double clear = 0, blocked = clearance;
    if (!checker.within_margin(start.data(), blocked, /*count=*/false)) clear = blocked;
    while (blocked - clear > clearance / 20) {
      const double mid = 0.5 * (clear + blocked);
      (checker.within_margin(start.data(), mid, /*count=*/false) ? blocked : clear) = mid;
    }
    start_clear = clear;
  }
  const double start_floor = kStartFloorShare * start_clear;
  // The clearance asked for at `v` near an endpoint (see above): the smallest the endpoints'
  // ramps ask.
  auto ramp_clearance = [&](const double* v) {
    auto ramp = [&](double floor, double from_end) {
      return floor + (clearance - floor) * std::min(1.0, from_end / kEndpointRadius);
    };
    double needed = ramp(start_floor, distance_from(v, start));
    // The goals planned to (problem.goals, filled below), not those dropped as invalid.
    for (const auto& g : problem.goals) needed = std::min(needed, ramp(0.0, distance_from(v, g)));
    return needed;
  };
  for (size_t i = 0; i < n; ++i) {
    const char* joint = mj_id2name(m, mjOBJ_JOINT, joints_[i]);
    problem.joint_names.push_back(joint ? joint : "");
  }
  problem.lower = lo;
  problem.upper = hi;
  problem.start = start;
  problem.is_valid = [&, clearance](const double* v) {
    if (start_touches_allowed && near(v, start)) return !touching->in_collision(v);
    if (clearance > 0) {
      if (!checker.within_margin(v, clearance)) return true;
      // Nothing within `needed` means no contact either.
      const double needed = ramp_clearance(v);
      if (needed >= clearance) return false;
      if (needed > kMinRampClearance) return !checker.within_margin(v, needed, /*count=*/false);
    }
    return !checker.in_collision(v, /*count=*/clearance <= 0);
  };
  problem.motion_resolution = o.motion_resolution;
  if (clearance > 0) {
    // Where the clearance asked for falls below o.clearance_m, the checks along a motion
    // are closer together: elsewhere the centimetre every checked state keeps makes a graze
    // between two checks unlikely, but two states a hair off the table say little about the
    // straight line between them (the arm's far end moves centimetres between checks).
    problem.fine_radius = kEndpointRadius;
    problem.fine_resolution = o.motion_resolution / kFineChecks;
  }
  problem.max_iterations = o.max_iterations;
  problem.time_limit_s = o.time_limit_s;
  problem.simplify_rounds = o.simplify_rounds;
  problem.simplify_time_s = o.simplify_time_s;
  problem.seed = o.seed;
  std::vector<int> goal_index_of_state;
  for (size_t k = 0; k < goals.size(); ++k) {
    if (!within(goals[k]) || checker.in_collision(goals[k].data())) continue;
    problem.goals.push_back(goals[k]);
    goal_index_of_state.push_back(static_cast<int>(k));
  }
  if (goal_index_of_state.empty()) {
    // What the (first) goal touches, as for a start in collision; a goal outside the limits
    // says so instead.
    std::string what = "outside the joint limits";
    if (within(goals.front())) {
      checker.in_collision(goals.front().data(), /*count=*/false);
      what = checker.visitor_route_hit();
      if (what.empty()) what = describe_robot_contacts(scene_, m, d, attachments_);
    }
    restore();
    return fail(core::PlanStatus::kInvalidGoal,
                (goals.size() == 1 ? "the goal configuration is in collision: "
                                   : "every goal configuration is in collision (the first: ") +
                    what + (goals.size() == 1 ? "" : ")"));
  }

  const std::uint64_t checks_before = checker.checks() + (touching ? touching->checks() : 0);
  // Runs the planner on `problem`; "" or why its result cannot be used.
  core::PlannerResult planned;
  auto solve = [&]() -> std::string {
    std::unique_ptr<core::Planner> planner;
    try {
      planner = planners.make(o.planner.name, o.planner.params);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    try {
      planned = planner->solve(problem);
    } catch (const std::exception& e) {
      return "planner " + o.planner.name + " failed: " + e.what();
    }
    if (planned.status == core::PlannerStatus::kExactSolution ||
        planned.status == core::PlannerStatus::kApproximateSolution) {
      const bool malformed =
          planned.path.empty() ||
          std::any_of(planned.path.begin(), planned.path.end(), [n](const core::Configuration& q) {
            return q.size() != n ||
                   !std::all_of(q.begin(), q.end(), [](double v) { return std::isfinite(v); });
          });
      if (malformed) {
        return "planner " + o.planner.name +
               " returned a path that is empty or has a waypoint of the wrong size or not finite";
      }
      for (core::Configuration& q : planned.path) {
        // Within the joint limits exactly (goals may lie up to core::kLimitRounding outside).
        for (size_t i = 0; i < n; ++i) q[i] = std::clamp(q[i], lo[i], hi[i]);
      }
    }
    result.planning_time_s += planned.planning_time_s;
    result.simplification_time_s += planned.simplification_time_s;
    result.plan_calls += 1;
    result.planner_iterations += planned.iterations;
    result.planning_hit_time_limit |= planned.hit_time_limit;
    result.simplification_hit_time_limit |= planned.simplification_hit_time_limit;
    if (const auto g = planned.statistics.find("graph_states"); g != planned.statistics.end()) {
      result.graph_states += static_cast<unsigned>(g->second);
    }
    return "";
  };

  // The planner checks states along its motions a resolution apart; between two checked states
  // the robot may still graze something (a hand's far end moves centimetres per check). The
  // path it returns is certified contact-free along every straight segment
  // (first_contact_along). Where a contact is found, the problem is planned again with checks
  // close enough for the clearance every checked state keeps to certify the space between
  // them, and that path is certified in turn.
  const std::vector<double>& reach = checker.joint_reach();
  const std::vector<std::vector<char>>& groups = checker.clearance_groups();
  // `touching` (when there is one) was built for the same joints and attachments: the same
  // groups, indexed alike.
  // The clearances of the groups `wanted` names at `v`; false if a pair is in contact.
  auto clearances_at = [&](const double* v, const std::vector<char>& wanted,
                           std::vector<double>& out) {
    ValidityChecker& c = start_touches_allowed && near(v, start) ? *touching : checker;
    if (!c.clearances_to_contact(v, kCertifyCap, wanted, out)) return false;
    return std::all_of(out.begin(), out.end(), [](double x) { return x >= 0; });
  };
  auto describe_contact_at = [&](const core::Configuration& q) {
    for (size_t i = 0; i < n; ++i) d->qpos[m->jnt_qposadr[joints_[i]]] = q[i];
    return describe_robot_contacts(scene_, m, d, attachments_);
  };

  std::string unusable = solve();
  std::string grazed;
  auto has_path = [&] {
    return unusable.empty() && (planned.status == core::PlannerStatus::kExactSolution ||
                                planned.status == core::PlannerStatus::kApproximateSolution);
  };
  if (has_path()) {
    core::Configuration contact = first_contact_along(planned.path, groups, reach, clearances_at);
    if (!contact.empty()) {
      grazed = describe_contact_at(contact);
      // Checks close enough that two states with the clearance asked for certify the motion
      // between them (as far as joint_reach bounds it), and at least twice as close as before.
      double reach_norm = 0;
      for (double r : reach) reach_norm += r * r;
      reach_norm = std::sqrt(reach_norm);
      const double extent = core::space_extent(problem);
      const double spacing = 2 * std::max(clearance, kCertifyFloor) / reach_norm;
      problem.motion_resolution = std::min(o.motion_resolution / 2, spacing / extent);
      if (problem.fine_resolution > 0)
        problem.fine_resolution = problem.motion_resolution / kFineChecks;
      unusable = solve();
      if (has_path()) {
        contact = first_contact_along(planned.path, groups, reach, clearances_at);
        if (!contact.empty()) {
          char buf[160];
          std::snprintf(buf, sizeof buf,
                        "; planned again with checks every %.3g of the joint space's extent, "
                        "it touches: ",
                        problem.motion_resolution);
          const std::string message =
              "the path found touches something between the states the planner checked: " + grazed +
              buf + describe_contact_at(contact);
          restore();
          return fail(core::PlanStatus::kPlanningFailed, message);
        }
      }
    }
  }
  if (!unusable.empty()) {
    restore();
    return fail(core::PlanStatus::kInvalidInput, unusable);
  }
  result.message = planned.message;
  switch (planned.status) {
    case core::PlannerStatus::kExactSolution:
      result.status = core::PlanStatus::kExactSolution;
      break;
    case core::PlannerStatus::kApproximateSolution:
      result.status = core::PlanStatus::kApproximateSolution;
      break;
    case core::PlannerStatus::kTimeout: {
      result.status = core::PlanStatus::kTimeout;
      char buf[120];
      if (planned.hit_iteration_limit) {
        std::snprintf(buf, sizeof buf, "no path within %u iterations", o.max_iterations);
      } else {
        std::snprintf(buf, sizeof buf, "no path within %g s", o.time_limit_s);
      }
      result.message = buf;
      break;
    }
    case core::PlannerStatus::kInvalidStart:
      result.status = core::PlanStatus::kInvalidStart;
      break;
    case core::PlannerStatus::kInvalidGoal:
      result.status = core::PlanStatus::kInvalidGoal;
      break;
    case core::PlannerStatus::kFailed:
      // Stopped without a path for a reason of its own (OMPL's abort, crash or infeasible):
      // not a timeout, whose budget was spent.
      result.status = core::PlanStatus::kPlanningFailed;
      if (result.message.empty()) {
        result.message = "planner " + o.planner.name + " stopped without a path";
      }
      break;
  }

  if (result.status == core::PlanStatus::kExactSolution ||
      result.status == core::PlanStatus::kApproximateSolution) {
    result.path = std::move(planned.path);
    // Which goal the path ends at.
    for (size_t k = 0; k < goal_index_of_state.size(); ++k) {
      const std::vector<double>& g = problem.goals[k];
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
