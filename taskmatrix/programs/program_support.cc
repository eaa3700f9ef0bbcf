#include "taskmatrix/programs/program_support.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>
#include <utility>

namespace taskmatrix::programs {

std::string arm_of(const std::string& side) { return side + "_arm"; }
std::string hand_of(const std::string& side) { return side + "_hand"; }

std::vector<std::string> free_sides(const core::ClaimContext& ctx,
                                    const std::vector<std::string>& sides,
                                    std::string (*chain_of)(const std::string&)) {
  std::vector<std::string> out;
  for (const std::string& s : sides) {
    if (!ctx.busy(chain_of(s))) out.push_back(s);
  }
  return out;
}

std::string nearest_free_side(const core::ClaimContext& ctx, const std::string& object,
                              std::string (*chain_of)(const std::string&)) {
  const std::vector<std::string> free = free_sides(ctx, {"left", "right"}, chain_of);
  if (free.empty()) return "left";
  const core::PerceivedObject* o = ctx.percepts.find(object);
  if (!o) return free.front();
  std::string best = free.front();
  double best_distance = INFINITY;
  for (const std::string& side : free) {
    const core::HandSpec* hand = ctx.skills.profile().find_hand(side);
    const double d = (ctx.skills.frame_pose(hand->palm).position - o->grasp_point()).norm();
    if (d < best_distance) {
      best_distance = d;
      best = side;
    }
  }
  return best;
}

std::string single_side(const std::vector<std::string>& chains) {
  std::string side;
  for (const std::string& c : chains) {
    if (core::chain_kind(c).empty()) continue;
    const std::string s = c.substr(0, c.find('_'));
    if (!side.empty() && s != side) return "";
    side = s;
  }
  return side;
}

ChainValues mirrored(const core::Skillset& skills, const ChainValues& v) {
  ChainValues out;
  size_t offset = 0;
  for (const std::string& c : v.chains) {
    const size_t n = skills.chain(c).joints.size();
    const std::string other = core::mirror_chain(c);
    out.chains.push_back(other.empty() ? c : other);
    const std::vector<double>* signs = nullptr;
    if (!other.empty()) signs = &skills.profile().mirror_signs.at(core::chain_kind(c));
    for (size_t i = 0; i < n; ++i) {
      out.values.push_back(signs ? (*signs)[i] * v.values[offset + i] : v.values[offset + i]);
    }
    offset += n;
  }
  return out;
}

ChainValues posture_values(const core::Skillset& skills, const std::string& posture,
                           const std::vector<std::string>& only_chains) {
  const core::Posture& p = skills.posture(posture);
  // A chain a robot may lack (core::kOptionalChains: a rigid torso, a camera fixed to the
  // trunk) is left out when it lacks it; a list of nothing else asks for nothing.
  std::vector<std::string> only;
  for (const std::string& c : only_chains) {
    const bool optional = std::find(core::kOptionalChains.begin(), core::kOptionalChains.end(),
                                    c) != core::kOptionalChains.end();
    if (!optional || skills.profile().find_chain(c)) only.push_back(c);
  }
  if (!only_chains.empty() && only.empty()) return {};
  for (const std::string& c : only) {
    skills.chain(c);  // throws for an unknown chain
    if (!p.count(c)) {
      throw std::invalid_argument("posture '" + posture + "' does not name chain '" + c + "'");
    }
  }
  ChainValues out;
  for (const auto& [chain, values] : p) {
    if (!only.empty() && std::find(only.begin(), only.end(), chain) == only.end()) {
      continue;
    }
    out.chains.push_back(chain);
    out.values.insert(out.values.end(), values.begin(), values.end());
  }
  return out;
}

std::vector<double> clamped_configuration(const core::Skillset& skills,
                                          const std::vector<std::string>& chains) {
  return skills.clamped_configuration(chains);
}

double max_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double e = 0;
  for (size_t i = 0; i < a.size() && i < b.size(); ++i) e = std::max(e, std::abs(a[i] - b[i]));
  return e;
}

std::optional<double> heading_within_limits(const core::ChainInfo& base, double yaw) {
  if (yaw > base.upper[2] && yaw - 2 * M_PI >= base.lower[2]) yaw -= 2 * M_PI;
  if (yaw < base.lower[2] && yaw + 2 * M_PI <= base.upper[2]) yaw += 2 * M_PI;
  if (yaw < base.lower[2] || yaw > base.upper[2]) return std::nullopt;
  return yaw;
}

namespace {

// The objects the hand on `side` holds.
std::vector<std::string> held_by(const core::Skillset& skills, const std::string& side) {
  std::vector<std::string> held;
  for (const std::string& o : skills.attached_objects()) {
    if (skills.holder_of(o) == side) held.push_back(o);
  }
  return held;
}

}  // namespace

bool chain_taken(const core::ClaimContext& ctx, const std::string& chain) {
  if (ctx.busy(chain)) return true;
  for (const char* side : {"left", "right"}) {
    if ((chain == arm_of(side) || chain == hand_of(side)) && !held_by(ctx.skills, side).empty()) {
      return true;
    }
  }
  return false;
}

LimbChoice choose_limb(const core::ClaimContext& ctx, const ChainValues& named,
                       const std::string& side) {
  const std::string named_side = single_side(named.chains);
  if (side == "as_named" || named_side.empty()) return {false};
  if (side != "any") return {side != named_side};
  const ChainValues other = mirrored(ctx.skills, named);
  auto busy = [&](const ChainValues& v) {
    return std::any_of(v.chains.begin(), v.chains.end(),
                       [&](const std::string& c) { return chain_taken(ctx, c); });
  };
  const bool named_busy = busy(named), other_busy = busy(other);
  if (named_busy != other_busy) return {named_busy};
  auto there = [&](const ChainValues& v) {
    return max_difference(ctx.skills.configuration(v.chains), v.values) <= kAlreadyThere;
  };
  const bool named_there = there(named), other_there = there(other);
  if (named_there != other_there) return {other_there};
  // Beside furniture one arm's posture may reach into it where the other's is clear.
  if (ctx.clear) {
    const bool named_clear = ctx.clear(named.chains, named.values);
    if (named_clear != ctx.clear(other.chains, other.values)) return {!named_clear};
  }
  std::mt19937 rng(ctx.seed);
  return {std::bernoulli_distribution(0.5)(rng)};
}

core::Failure plan_failure(const core::PlanResult& plan) {
  return core::Failure(core::failure_code(plan.status), plan.message);
}

namespace {

constexpr double kEscapeMaxJointStep = 0.3;       // rad (or m) per escape step
constexpr double kEscapeMaxPalmDeviation = 0.01;  // m, halfway through an escape step
// How much deeper than at its start an escape step may press into what the start touches (m):
// what it touches is rigid, and physics holds the arm where it meets it.
constexpr double kEscapeDeeperM = 0.001;

}  // namespace

bool finger_under(core::ProgramContext& ctx, const std::string& side, const std::string& object,
                  double rise_m) {
  constexpr double kAcrossM = 0.01;  // a finger's half thickness, about
  core::Skillset& skills = ctx.skills();
  const core::HandSpec* hand = skills.profile().find_hand(side);
  const core::PerceivedObject* seen = ctx.percepts().find(object);
  if (!hand || !seen) return false;
  std::vector<Eigen::AlignedBox3d> parts;
  for (const core::Shape& s : seen->shapes) parts.push_back(s.bounds());
  if (parts.empty()) parts.push_back(seen->box);
  std::vector<Eigen::Vector3d> points;
  for (const core::FingerSpec& f : hand->fingers) {
    Eigen::Vector3d previous = Eigen::Vector3d::Zero(), last = Eigen::Vector3d::Zero();
    for (const std::string& body : f.bodies) {
      previous = last;
      last = skills.frame_pose(body).position;
      points.push_back(last);
    }
    if (f.bodies.size() >= 2) points.push_back(2 * last - previous);
  }
  for (const Eigen::Vector3d& p : points) {
    for (const Eigen::AlignedBox3d& b : parts) {
      const Eigen::AlignedBox2d across(b.min().head<2>(), b.max().head<2>());
      if (across.exteriorDistance(p.head<2>()) < kAcrossM && b.min().z() > p.z() - kAcrossM &&
          b.min().z() < p.z() + rise_m) {
        return true;
      }
    }
  }
  return false;
}

std::vector<std::string> touched_by_arm(core::ProgramContext& ctx, const std::string& side) {
  core::Skillset& skills = ctx.skills();
  const std::vector<std::string> held = held_by(skills, side);
  std::vector<std::string> touched;
  auto add = [&](const std::string& name) {
    if (std::find(held.begin(), held.end(), name) == held.end() &&
        std::find(touched.begin(), touched.end(), name) == touched.end()) {
      touched.push_back(name);
    }
  };
  for (const std::string& o : held) {
    for (const std::string& other : skills.touching(o)) {
      if (ctx.percepts().knows(other)) add(other);  // the world, not the hand
    }
  }
  for (const core::Collision& c : skills.collisions({arm_of(side)})) add(c.other);
  return touched;
}

namespace {

// escape_motion with `chains` (the arm, perhaps the torso before it).
std::optional<Escape> escape_with(core::ProgramContext& ctx, const core::HandSpec* hand,
                                  const std::vector<std::string>& chains,
                                  const std::vector<std::string>& held,
                                  const std::vector<std::string>& touched, double distance_m,
                                  bool lift) {
  core::Skillset& skills = ctx.skills();
  const core::Pose palm = skills.frame_pose(hand->palm);
  const Eigen::Vector3d approach(hand->approach[0], hand->approach[1], hand->approach[2]);
  const Eigen::Vector3d direction =
      held.empty() && !lift ? Eigen::Vector3d(-(palm.orientation * approach).normalized())
                            : Eigen::Vector3d::UnitZ();
  core::IkOptions ik;
  ik.restarts = 2;
  ik.collision_free = false;  // it starts in contact; execution checks the rest
  ik.position_tolerance_m = 0.003;
  ik.orientation_tolerance_rad = 0.03;
  // The lowest corner of what the hand holds (its perceived box), with the palm at `q`: a
  // held object must rise, not pivot about the grip into what it rests on.
  auto lowest_held_point = [&](const std::vector<double>& q) {
    const core::Pose at = skills.frame_pose_at(chains, q, hand->palm);
    const Eigen::Quaterniond turn = at.orientation * palm.orientation.conjugate();
    double lowest = INFINITY;
    for (const std::string& o : held) {
      const core::PerceivedObject* seen = ctx.percepts().find(o);
      if (!seen) continue;
      for (int c = 0; c < 8; ++c) {
        const Eigen::Vector3d corner =
            seen->box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(c));
        lowest = std::min(lowest, (at.position + turn * (corner - palm.position)).z());
      }
    }
    return lowest;
  };
  const std::vector<double> from = clamped_configuration(skills, chains);
  const double lowest_now = lowest_held_point(from);
  std::vector<std::vector<double>> path = {from};
  // IK does not keep the arm off the robot or the world: where the start touches nothing but
  // `touched`, a step (and the middle of the way to it) that touches anything else, the
  // robot's own body included (a forearm swung into the torso), is no escape; nor is one that
  // presses deeper into what the start touches (an upper arm resting on the torso, pushed
  // 2.5 mm further in by a lift: physics stops it there, 13 mrad short of the step).
  const bool judged = skills.is_valid(chains, from, touched);
  // (Signed distances capped at kEscapeDeeperM: only how deep matters.)
  const double deepest_allowed =
      judged ? std::min(0.0, skills.clearance(chains, from, kEscapeDeeperM)) - kEscapeDeeperM : 0.0;
  auto clear_at = [&](const std::vector<double>& q) {
    return skills.is_valid(chains, q, touched) &&
           skills.clearance(chains, q, kEscapeDeeperM) >= deepest_allowed;
  };
  auto clear_step = [&](const std::vector<double>& q) {
    if (!judged) return true;
    std::vector<double> middle(q.size());
    for (size_t i = 0; i < q.size(); ++i) middle[i] = 0.5 * (q[i] + path.back()[i]);
    return clear_at(middle) && clear_at(q);
  };
  // Each step moves the palm a few centimetres along `direction`: a solution that turns a joint
  // farther than kEscapeMaxJointStep, or whose straight motion from the step before carries the
  // palm off that line, is another posture of the arm, and moving straight to it would swing
  // the arm through what surrounds it. When the first step finds only such a posture, the
  // escape is a planned motion to a posture of the lifted hand clear of everything.
  Eigen::Vector3d palm_before = palm.position;
  bool other_posture = false;  // the step IK solved only as another posture of the arm
  auto stays_near = [&](const std::vector<double>& q, const Eigen::Vector3d& palm_target) {
    const std::vector<double>& before = path.back();
    std::vector<double> middle(q.size());
    for (size_t i = 0; i < q.size(); ++i) {
      if (std::abs(q[i] - before[i]) > kEscapeMaxJointStep) return false;
      middle[i] = 0.5 * (q[i] + before[i]);
    }
    const core::Pose at = skills.frame_pose_at(chains, middle, hand->palm);
    return (at.position - 0.5 * (palm_before + palm_target)).norm() <= kEscapeMaxPalmDeviation;
  };
  for (double share : {0.5, 1.0}) {
    core::Pose target = palm;
    target.position += share * distance_m * direction;
    ik.seed = ctx.next_seed();
    ik.orientation = true;
    ik.start = path.back();
    // A solution only another posture of the arm reaches is none.
    auto keep_near = [&](core::IkResult& r) {
      if (!r.solutions.empty() && !stays_near(r.solutions.front(), target.position)) {
        other_posture = true;
        r.solutions.clear();
      }
    };
    core::IkResult r = skills.solve_ik(chains, hand->palm, target, ik);
    keep_near(r);
    if (r.solutions.empty()) {
      // An arm that cannot keep the hand's orientation exactly (five joints) keeps it as
      // near as damped least squares from here does, unless that tips what it holds down.
      ik.orientation = false;
      r = skills.solve_ik(chains, hand->palm, target, ik);
      if (!r.solutions.empty() && !held.empty() && std::isfinite(lowest_now) &&
          lowest_held_point(r.solutions.front()) < lowest_now + 0.25 * share * distance_m) {
        r.solutions.clear();
      }
      keep_near(r);
    }
    if (r.solutions.empty()) break;
    if (!clear_step(r.solutions.front())) {
      other_posture = true;  // this way the arm meets something: a planned way, as below
      break;
    }
    other_posture = false;
    path.push_back(r.solutions.front());
    palm_before = target.position;
  }
  Escape e;
  e.chains = chains;
  if (path.size() < 2) {
    // No lift straight from here: to the other posture, planned (the planner may touch what
    // the start touches, near the start only).
    if (!other_posture) return std::nullopt;
    // One clear of everything (the one IK found may touch what the hand stands in).
    core::Pose target = palm;
    target.position += distance_m * direction;
    core::IkOptions clear = ik;
    clear.collision_free = true;
    clear.orientation = !held.empty();
    clear.restarts = 10;
    clear.seed = ctx.next_seed();
    const core::IkResult r = skills.solve_ik(chains, hand->palm, target, clear);
    if (r.solutions.empty()) return std::nullopt;
    core::PlanOptions options = ctx.plan_options();
    options.seed = ctx.next_seed();
    options.may_touch = touched;
    const core::PlanResult planned =
        skills.plan_to_configuration(e.chains, r.solutions.front(), options);
    if (!planned.success()) return std::nullopt;
    path = planned.path;
  }
  e.motion = core::timed(skills.time_parameterize(e.chains, path, 0.5));
  e.options.position_tolerance = 0.01;
  e.options.may_touch = touched;
  return e;
}

}  // namespace

std::optional<Escape> escape_motion(core::ProgramContext& ctx, const std::string& side,
                                    const std::vector<std::string>& touched, double distance_m,
                                    bool always, bool torso, bool lift) {
  core::Skillset& skills = ctx.skills();
  const core::HandSpec* hand = skills.profile().find_hand(side);
  if (!hand) return std::nullopt;
  if (touched.empty() && !always) return std::nullopt;
  const std::vector<std::string> held = held_by(skills, side);
  std::optional<Escape> e = escape_with(ctx, hand, {arm_of(side)}, held, touched, distance_m, lift);
  // An arm that cannot lift it alone (too few joints to keep the hand's orientation, or at the
  // edge of its reach): torso and arm together.
  if (!e && torso && skills.profile().find_chain("torso")) {
    e = escape_with(ctx, hand, {"torso", arm_of(side)}, held, touched, distance_m, lift);
  }
  return e;
}

std::optional<core::Failure> MotionStage::plan_to_configuration(
    core::ProgramContext& ctx, const std::vector<std::string>& chains,
    const std::vector<double>& goal) {
  for (const std::string& c : chains) {
    if (core::chain_kind(c) != "arm") continue;
    const std::string side = single_side({c});
    const std::vector<std::string> touched = touched_by_arm(ctx, side);
    std::optional<Escape> escape = escape_motion(ctx, side, touched, 0.05);
    if (!escape) {
      // An arm against something that cannot move straight off it: the planner starts from
      // the contact (it may touch what the start touches, near the start only).
      allow_touching(touched);
      continue;
    }
    pending_ctx_ = &ctx;
    pending_chains_ = chains;
    pending_goal_ = goal;
    allow_touching(touched);
    escape->options.may_touch = execution.may_touch;  // and what the planned motion may touch
    follow(ctx, escape->chains, std::move(escape->motion), escape->options);
    return std::nullopt;
  }
  return plan_now(ctx, chains, goal);
}

void MotionStage::allow_touching(const std::vector<std::string>& names) {
  for (const std::string& n : names) {
    if (std::find(execution.may_touch.begin(), execution.may_touch.end(), n) ==
        execution.may_touch.end()) {
      execution.may_touch.push_back(n);
    }
  }
}

std::optional<core::Failure> MotionStage::plan_now(core::ProgramContext& ctx,
                                                   const std::vector<std::string>& chains,
                                                   const std::vector<double>& goal) {
  core::PlanOptions options = ctx.plan_options();
  options.seed = ctx.next_seed();
  options.may_touch = execution.may_touch;
  ctx.emit(core::MessageType::kPlanningStarted);
  auto plan = std::make_shared<const core::PlanResult>(
      ctx.skills().plan_to_configuration(chains, goal, options));
  return start_following(ctx, chains, std::move(plan));
}

std::vector<std::vector<double>> ArmMotion::solve(core::ProgramContext& ctx,
                                                  const std::vector<std::string>& chains, size_t k,
                                                  std::string& why,
                                                  const core::IkOptions* options) {
  core::Skillset& skills = ctx.skills();
  const ArmTarget& t = targets_[k];
  core::IkOptions ik = options ? *options : ik_;
  ik.seed = ctx.next_seed();
  const bool free = t.free_axis.squaredNorm() > 0 && t.free_turn_rad > 0;
  if (free) ik.free_axis = (t.pose.orientation.conjugate() * t.free_axis).normalized();
  const core::IkResult r = skills.solve_ik(chains, frame_, t.pose, ik);
  if (r.solutions.empty()) {
    if (why.empty()) why = r.reason;
    if (r.position_error_m < best_miss_m_) {
      best_miss_m_ = r.position_error_m;
      best_miss_rad_ = r.orientation_error_rad;
      best_miss_tag_ = t.tag;
    }
    return {};
  }
  std::vector<std::vector<double>> out;
  for (const std::vector<double>& q : r.solutions) {
    const bool limited = free && t.free_turn_rad < M_PI;
    if (!limited && t.keep_above.empty()) {
      out.push_back(q);
      continue;
    }
    const core::Pose at = skills.frame_pose_at(chains, q, frame_);
    if (limited) {
      const double turn =
          Eigen::AngleAxisd(t.pose.orientation.conjugate() * at.orientation).angle();
      if (turn > t.free_turn_rad + 0.035) {
        if (why.empty()) why = "the turn the arm needs is outside what the target allows";
        continue;
      }
    }
    const bool above =
        std::all_of(t.keep_above.begin(), t.keep_above.end(), [&](const Eigen::Vector3d& p) {
          return (at.position + at.orientation * p).z() >= t.floor_z;
        });
    if (!above) {
      if (why.empty())
        why = "at the turn IK found, the closing fingers would reach the surface below";
      continue;
    }
    out.push_back(q);
  }
  return out;
}

std::optional<core::Failure> ArmMotion::reach_from_here(core::ProgramContext& ctx) {
  std::vector<std::vector<std::string>> levels = {{arm_}};
  if (torso_) levels.push_back({"torso", arm_});
  std::optional<core::Failure> last_plan_failure;
  std::string why;
  int timeouts = 0;
  for (const std::vector<std::string>& chains : levels) {
    for (size_t k = 0; k < targets_.size(); ++k) {
      for (const std::vector<double>& q : solve(ctx, chains, k, why)) {
        std::optional<core::Failure> failure = motion_.plan_now(ctx, chains, q);
        if (!failure) {
          reached_ = static_cast<int>(k);
          return std::nullopt;
        }
        if (failure->code == core::FailureCode::kInvalidStart ||
            failure->code == core::FailureCode::kInvalidInput) {
          return failure;
        }
        // A planner that ran out of time will not do better for the next pose of the same
        // region; one more try, then give up (bounded work).
        if (failure->code == core::FailureCode::kPlanningTimeout && ++timeouts >= 2) {
          return failure;
        }
        last_plan_failure = std::move(failure);
      }
    }
  }
  if (last_plan_failure) return last_plan_failure;
  std::string chains = arm_;
  if (torso_) chains += ", torso and " + arm_;
  char buf[200];
  std::snprintf(buf, sizeof buf, " (best: %.1f mm, %.1f deg off, %s)", best_miss_m_ * 1e3,
                best_miss_rad_ * 180 / M_PI, best_miss_tag_.c_str());
  return core::Failure(core::FailureCode::kIkFailure,
                       frame_ + " reaches none of " + std::to_string(targets_.size()) +
                           " targets with " + chains +
                           (std::isfinite(best_miss_m_) ? buf : " (" + why + ")"));
}

bool found_no_way(const core::Failure& failure) {
  switch (failure.code) {
    case core::FailureCode::kIkFailure:
    case core::FailureCode::kApproximateSolution:
    case core::FailureCode::kPlanningTimeout:
    case core::FailureCode::kPlanningFailed:
      return true;
    default:
      return false;
  }
}

std::optional<core::Failure> ArmMotion::start(core::ProgramContext& ctx, const std::string& arm,
                                              const std::string& frame,
                                              std::vector<ArmTarget> targets,
                                              const core::IkOptions& ik, bool torso, bool base) {
  arm_ = arm;
  frame_ = frame;
  targets_ = std::move(targets);
  ik_ = ik;
  torso_ = torso;
  base_ = base;
  reached_ = -1;
  best_miss_m_ = INFINITY;
  stances_left_.clear();
  lifted_ = false;
  if (targets_.empty()) {
    return core::Failure(core::FailureCode::kInvalidInput, "no target for " + frame_);
  }
  const std::string side = single_side({arm_});
  const bool holding = !held_by(ctx.skills(), side).empty();
  const std::vector<std::string> touched = touched_by_arm(ctx, side);
  if (std::optional<Escape> escape =
          escape_motion(ctx, side, touched, holding ? 0.04 : 0.05, false, torso_)) {
    motion_.allow_touching(touched);
    // Getting free may touch what the motion after it may (reach's object).
    escape->options.may_touch = motion_.execution.may_touch;
    motion_.follow(ctx, escape->chains, std::move(escape->motion), escape->options);
    phase_ = Phase::kEscaping;
    return std::nullopt;
  }
  // Against something it cannot move straight off: the planner starts from the contact (it
  // may touch what the start touches, near the start only).
  motion_.allow_touching(touched);
  phase_ = Phase::kReaching;
  std::optional<core::Failure> failure = reach_from_here(ctx);
  if (base_ && failure && found_no_way(*failure)) failure = step_over(ctx, std::move(*failure));
  if (failure && lift_first(ctx, *failure)) return std::nullopt;
  return failure;
}

bool ArmMotion::lift_first(core::ProgramContext& ctx, const core::Failure& failure) {
  // The planner found no way from here, with the hand (or what it holds) a hair off what it
  // stood on: it keeps its clearance everywhere but next to the start, and few of its random
  // motions lift a held object straight up. Once: lifted straight first, then reaching again.
  if (lifted_ || failure.code == core::FailureCode::kIkFailure || !found_no_way(failure)) {
    return false;
  }
  core::Skillset& skills = ctx.skills();
  const double clearance = ctx.plan_options().clearance_m;
  if (skills.clearance({arm_}, skills.configuration({arm_}), clearance) >= clearance) return false;
  const std::string side = single_side({arm_});
  const bool holding = !held_by(skills, side).empty();
  std::optional<Escape> escape = escape_motion(ctx, side, touched_by_arm(ctx, side),
                                               holding ? 0.04 : 0.05, /*always=*/true, torso_);
  if (!escape) return false;
  lifted_ = true;
  escape->options.may_touch = motion_.execution.may_touch;
  motion_.follow(ctx, escape->chains, std::move(escape->motion), escape->options);
  phase_ = Phase::kEscaping;
  stances_left_.clear();
  best_miss_m_ = INFINITY;
  return true;
}

std::optional<core::Failure> ArmMotion::step_over(core::ProgramContext& ctx,
                                                  core::Failure failure) {
  // A stance from which the arm reaches: first IK over the whole body from here; then a search
  // that places the base first (stance_candidates) and solves the torso and arm with the base
  // held there, each solution collision-checked with the body as it would stand; then IK over
  // the whole body again, started from the first of those base poses; then the nearest base
  // poses again with more IK starts.
  core::Skillset& skills = ctx.skills();
  std::vector<std::string> body{"base"};
  if (torso_) body.push_back("torso");
  body.push_back(arm_);
  std::string why;
  // A stance the planner cannot get to: the next one; the kMaxUnplannedStances-th such plan
  // failure is the program's.
  int unplanned = 0;
  std::optional<core::Failure> last_plan_failure;
  // Starts moving to a whole-body solution; false when the plan failed and another stance
  // may be tried, else true with `ended` the failure, if any.
  auto go = [&](size_t k, const std::vector<double>& solution,
                std::optional<core::Failure>& ended) {
    ended = go_to_stance(ctx, body, k, solution);
    if (ended && ended->code != core::FailureCode::kIkFailure && found_no_way(*ended) &&
        ++unplanned < kMaxUnplannedStances) {
      last_plan_failure = std::move(ended);
      ended.reset();
      return false;
    }
    return true;
  };
  std::optional<core::Failure> ended;
  // (Not after a stance failed: from there it would find that stance again.)
  for (size_t k = 0; k < targets_.size() && stances_left_.empty(); ++k) {
    const std::vector<std::vector<double>> solutions = solve(ctx, body, k, why);
    if (solutions.empty()) continue;
    if (go(k, solutions.front(), ended)) return ended;
    break;
  }
  const std::vector<std::vector<double>> stances = stance_candidates(ctx, body);
  // IK from each stance, the rest of the body starting where it is: first with the base's
  // joints held there (weight 0); then, from the first kMaxLooseStances stances, with the base
  // free (weight kLooseBaseWeight: its steps are shorter than the other joints', but IK's
  // restarts draw it like any joint, its heading anywhere and its position within the hand's
  // distance from the target plus 0.5 m): whole-body IK started from those poses, which finds
  // stances between the candidates; when neither pass found a solution (none, not one the
  // planner failed to get to), the nearest stances again, base held, with many more IK starts
  // (where the few starts above converged only into collision, or were dropped by the
  // target's checks, other starts may converge elsewhere).
  struct Pass {
    double base_weight;
    int stances, restarts;
    bool only_if_none_found;
  };
  const size_t nb = skills.chain("base").joints.size();
  core::IkOptions held = ik_;
  held.start = skills.configuration(body);
  held.joint_weights.assign(held.start.size(), 1.0);
  int tried = 0;
  for (const Pass& pass : {Pass{0.0, kMaxStances, kStanceRestarts, false},
                           Pass{kLooseBaseWeight, kMaxLooseStances, kStanceRestarts, false},
                           Pass{0.0, kMaxRefinedStances, kRefineRestarts, true}}) {
    if (pass.only_if_none_found && last_plan_failure) break;
    std::fill(held.joint_weights.begin(), held.joint_weights.begin() + static_cast<long>(nb),
              pass.base_weight);
    held.restarts = pass.restarts;
    int here = 0;
    for (const std::vector<double>& stance : stances) {
      if (left_before(stance)) continue;
      if (++here > pass.stances) break;
      ++tried;
      std::copy(stance.begin(), stance.end(), held.start.begin());
      for (size_t k = 0; k < targets_.size(); ++k) {
        const std::vector<std::vector<double>> solutions = solve(ctx, body, k, why, &held);
        if (solutions.empty()) continue;
        if (left_before(solutions.front())) break;  // the next stance
        if (go(k, solutions.front(), ended)) return ended;
        break;  // the next stance
      }
    }
  }
  if (last_plan_failure) return last_plan_failure;
  failure.detail += "; stepping: no stance found (" + why + "; " + std::to_string(tried) +
                    " searches from " + std::to_string(stances.size()) + " stances)";
  return failure;
}

bool ArmMotion::left_before(const std::vector<double>& base) const {
  return std::any_of(stances_left_.begin(), stances_left_.end(), [&](const std::vector<double>& s) {
    return std::hypot(s[0] - base[0], s[1] - base[1]) < kFailedStanceM &&
           std::abs(std::remainder(s[2] - base[2], 2 * M_PI)) < kFailedStanceRad;
  });
}

ReachEnvelope::ReachEnvelope(core::Skillset& skills, const std::vector<std::string>& body,
                             const std::string& frame) {
  // The base at the origin facing +x; every other joint of the body drawn uniformly within
  // its limits, then the farthest draws pushed outwards joint by joint with shrinking steps
  // (the farthest reach is a corner of the joint space that uniform draws rarely hit). The
  // draws are seeded by a constant: the result depends on the robot and on the frame (a held
  // tool's tip, on the grasp), never on the trial's seed.
  std::vector<double> q = skills.configuration(body);
  std::vector<double> lower, upper;
  for (const std::string& c : body) {
    const core::ChainInfo& info = skills.chain(c);
    lower.insert(lower.end(), info.lower.begin(), info.lower.end());
    upper.insert(upper.end(), info.upper.begin(), info.upper.end());
  }
  const size_t nb = skills.chain("base").joints.size();
  std::fill(q.begin(), q.begin() + static_cast<long>(nb), 0.0);
  // The base's vertical axis at base (0, 0): halfway between where the frame is with the base
  // turned by 0 and by pi (the axis need not be at the model's origin).
  const Eigen::Vector3d p0 = skills.frame_pose_at(body, q, frame).position;
  q[nb - 1] = M_PI;  // the base's joints are x, y and yaw (the profile's rule)
  const Eigen::Vector3d pi = skills.frame_pose_at(body, q, frame).position;
  q[nb - 1] = 0;
  axis_ = Eigen::Vector2d((p0.x() + pi.x()) / 2, (p0.y() + pi.y()) / 2);
  auto radius_of = [&](const std::vector<double>& v) {
    const Eigen::Vector3d p = skills.frame_pose_at(body, v, frame).position;
    return std::hypot(p.x() - axis_.x(), p.y() - axis_.y());
  };
  std::mt19937_64 rng(0x5eed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<std::pair<double, std::vector<double>>> draws;
  for (int n = 0; n < kDraws; ++n) {
    for (size_t j = nb; j < q.size(); ++j) q[j] = lower[j] + unit(rng) * (upper[j] - lower[j]);
    draws.emplace_back(radius_of(q), q);
  }
  std::partial_sort(draws.begin(), draws.begin() + kClimbs, draws.end(),
                    [](const auto& a, const auto& b) { return a.first > b.first; });
  radius_ = draws.front().first;
  for (int c = 0; c < kClimbs; ++c) {
    auto [best, v] = draws[static_cast<size_t>(c)];
    for (double step = 0.5; step > 0.01; step /= 2) {
      for (size_t j = nb; j < v.size(); ++j) {
        for (double sign : {1.0, -1.0}) {
          std::vector<double> w = v;
          w[j] = std::clamp(w[j] + sign * step * (upper[j] - lower[j]), lower[j], upper[j]);
          const double r = radius_of(w);
          if (r > best) {
            best = r;
            v = std::move(w);
          }
        }
      }
    }
    radius_ = std::max(radius_, best);
  }
}

std::vector<std::vector<double>> ArmMotion::stance_candidates(
    core::ProgramContext& ctx, const std::vector<std::string>& body) {
  // Base poses near the current one (forward and back along the heading, to either side,
  // turned towards the targets' centre or not), then on rings round the targets' centre
  // facing it (walking round what the target stands on), the nearest travel first. A pose
  // from which every target is beyond the frame's farthest horizontal reach (plus a slack for
  // what the search for it missed) is dropped, and so is a repeat of an earlier one.
  core::Skillset& skills = ctx.skills();
  const std::vector<double> now = skills.configuration(body);
  const double x0 = now[0], y0 = now[1], yaw0 = now[2];
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (const ArmTarget& t : targets_) centre += t.pose.position;
  centre /= static_cast<double>(targets_.size());
  const ReachEnvelope envelope(skills, body, frame_);
  struct Candidate {
    double cost;
    std::vector<double> base;
  };
  std::vector<Candidate> candidates;
  auto add = [&](double x, double y, double yaw) {
    const Eigen::Vector2d axis = envelope.axis_at_origin() + Eigen::Vector2d(x, y);
    const bool within = std::any_of(targets_.begin(), targets_.end(), [&](const ArmTarget& t) {
      return std::hypot(t.pose.position.x() - axis.x(), t.pose.position.y() - axis.y()) <=
             envelope.radius() + ReachEnvelope::kSlackM;
    });
    if (!within) return;
    const double turn = std::remainder(yaw - yaw0, 2 * M_PI);
    for (const Candidate& c : candidates) {
      if (std::hypot(c.base[0] - x, c.base[1] - y) < kSameStanceM &&
          std::abs(std::remainder(c.base[2] - yaw0 - turn, 2 * M_PI)) < kSameStanceRad) {
        return;
      }
    }
    candidates.push_back(
        {std::hypot(x - x0, y - y0) + kStanceTurnCostM * std::abs(turn), {x, y, yaw0 + turn}});
  };
  const double facing = std::atan2(centre.y() - y0, centre.x() - x0);
  const double turn = std::remainder(facing - yaw0, 2 * M_PI);
  const Eigen::Vector2d ahead(std::cos(yaw0), std::sin(yaw0)), left(-ahead.y(), ahead.x());
  for (double along : {0.1, 0.2, 0.3, -0.1, -0.2}) {
    for (double aside : {0.0, -0.15, 0.15}) {
      for (double share : {0.0, 0.5, 1.0}) {
        const Eigen::Vector2d at = Eigen::Vector2d(x0, y0) + along * ahead + aside * left;
        add(at.x(), at.y(), yaw0 + share * turn);
      }
    }
  }
  // Ring radii in proportion to the robot's height (a human's arm is about 0.35 of it).
  const double height = skills.profile().height_m;
  // The base's axis (not its joints' origin) on the ring.
  const Eigen::Vector2d& axis_offset = envelope.axis_at_origin();
  for (double share : {0.25, 0.35, 0.45}) {
    for (int k = 0; k < kStanceHeadings; ++k) {
      const double around = 2 * M_PI * k / kStanceHeadings;
      add(centre.x() + share * height * std::cos(around) - axis_offset.x(),
          centre.y() + share * height * std::sin(around) - axis_offset.y(), around + M_PI);
    }
  }
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const Candidate& a, const Candidate& b) { return a.cost < b.cost; });
  std::vector<std::vector<double>> out;
  for (Candidate& c : candidates) out.push_back(std::move(c.base));
  return out;
}

std::optional<core::Failure> ArmMotion::go_to_stance(core::ProgramContext& ctx,
                                                     const std::vector<std::string>& body, size_t k,
                                                     const std::vector<double>& solution) {
  // The base alone when the arm can stay as it is at the new stance; else, or when the base
  // alone finds no way there (the arm, or what its hand holds, over something the base must
  // pass), the whole body.
  core::Skillset& skills = ctx.skills();
  const size_t nb = skills.chain("base").joints.size();
  std::vector<double> stance_now = skills.configuration(body);
  std::copy(solution.begin(), solution.begin() + static_cast<long>(nb), stance_now.begin());
  if (skills.is_valid(body, stance_now)) {
    const std::vector<double> stance(solution.begin(), solution.begin() + static_cast<long>(nb));
    std::optional<core::Failure> moved = motion_.plan_now(ctx, {"base"}, stance);
    if (!moved) {
      phase_ = Phase::kStepping;
      stance_target_ = static_cast<int>(k);
      stance_rest_.assign(solution.begin() + static_cast<long>(nb), solution.end());
      stance_body_ = body;
      return std::nullopt;
    }
    if (moved->code != core::FailureCode::kPlanningTimeout &&
        moved->code != core::FailureCode::kApproximateSolution &&
        moved->code != core::FailureCode::kPlanningFailed) {
      return moved;
    }
  }
  std::optional<core::Failure> moved = motion_.plan_now(ctx, body, solution);
  if (!moved) {
    reached_ = static_cast<int>(k);
    return moved;
  }
  if (moved->code == core::FailureCode::kIkFailure || !found_no_way(*moved)) return moved;
  if (carry_to_stance(ctx, body, k, solution)) return std::nullopt;
  return moved;
}

bool ArmMotion::carry_to_stance(core::ProgramContext& ctx, const std::vector<std::string>& body,
                                size_t k, const std::vector<double>& solution) {
  // The whole body found no way there in one motion (the arm, or what its hand holds, out over
  // what the base must walk round): torso and arm drawn in first, to a posture clear of
  // everything both here and at the stance (the torso upright with the arm as it is, the rest
  // posture, or between the two), the base walked there with them so, and torso and arm
  // planned from there as after any step.
  core::Skillset& skills = ctx.skills();
  const size_t nb = skills.chain("base").joints.size();
  std::vector<std::string> upper = {arm_};
  if (torso_) upper.insert(upper.begin(), "torso");
  std::vector<double> rest;  // in `upper`'s order
  for (const std::string& c : upper) {
    const std::vector<double> v = posture_values(skills, "rest", {c}).values;
    rest.insert(rest.end(), v.begin(), v.end());
  }
  const std::vector<double> now = skills.configuration(upper);
  std::vector<double> upright = now;
  if (torso_) {
    const long nt = static_cast<long>(skills.chain("torso").joints.size());
    std::copy(rest.begin(), rest.begin() + nt, upright.begin());
  }
  std::vector<double> at_stance(solution.begin(), solution.begin() + static_cast<long>(nb));
  int plans = 0;
  for (const double share : {0.0, 1.0, 0.5, 0.25, 0.75}) {
    std::vector<double> carried(rest.size());
    for (size_t i = 0; i < rest.size(); ++i) {
      carried[i] = upright[i] + share * (rest[i] - upright[i]);
    }
    at_stance.resize(nb);
    at_stance.insert(at_stance.end(), carried.begin(), carried.end());
    // As it is now: the base alone was tried with it, or it collides at the stance.
    double from_now = 0;
    for (size_t i = 0; i < now.size(); ++i) {
      from_now = std::max(from_now, std::abs(carried[i] - now[i]));
    }
    if (from_now < kSameCarryRad) continue;
    if (!skills.is_valid(upper, carried) || !skills.is_valid(body, at_stance)) continue;
    if (plans++ == kMaxCarryPlans) break;
    if (motion_.plan_now(ctx, upper, carried)) continue;
    phase_ = Phase::kCarrying;
    stance_target_ = static_cast<int>(k);
    stance_base_.assign(solution.begin(), solution.begin() + static_cast<long>(nb));
    stance_rest_.assign(solution.begin() + static_cast<long>(nb), solution.end());
    stance_body_ = body;
    return true;
  }
  return false;
}

std::optional<Ended> ArmMotion::step(core::ProgramContext& ctx) {
  std::optional<Ended> result = motion_.step();
  if (!result) return result;
  if (phase_ == Phase::kEscaping) {
    phase_ = Phase::kReaching;
    if (*result) return result;
    std::optional<core::Failure> failure = reach_from_here(ctx);
    if (base_ && failure && found_no_way(*failure)) {
      failure = step_over(ctx, std::move(*failure));
    }
    if (failure) return Ended(std::move(failure));
    return std::nullopt;
  }
  if (phase_ == Phase::kCarrying && *result) phase_ = Phase::kReaching;
  if (phase_ == Phase::kCarrying) {
    // Drawn in: the base walks to the stance.
    phase_ = Phase::kStepping;
    std::optional<core::Failure> moved = motion_.plan_now(ctx, {"base"}, stance_base_);
    if (!moved) return std::nullopt;
    phase_ = Phase::kReaching;
    if (!found_no_way(*moved) || static_cast<int>(stances_left_.size()) >= kMaxFailedStances) {
      return Ended(std::move(moved));
    }
    // No way there: another stance, as when reaching from one failed.
    stances_left_.push_back(stance_base_);
    std::optional<core::Failure> failure = step_over(ctx, std::move(*moved));
    if (failure) return Ended(std::move(failure));
    return std::nullopt;
  }
  if (*result || phase_ != Phase::kStepping) return result;
  phase_ = Phase::kReaching;
  // At the stance: the rest of the body as the whole-body solution had it, if the base got
  // close enough for that to still place the frame; else search again from here.
  std::vector<std::string> rest = {arm_};
  if (torso_) rest.insert(rest.begin(), "torso");
  const ArmTarget& t = targets_[static_cast<size_t>(stance_target_)];
  const core::Pose at = ctx.skills().frame_pose_at(rest, stance_rest_, frame_);
  if ((at.position - t.pose.position).norm() <= 0.01 && ctx.skills().is_valid(rest, stance_rest_)) {
    if (!motion_.plan_now(ctx, rest, stance_rest_)) {
      reached_ = stance_target_;
      return std::nullopt;
    }
    // The arm cannot get there with the base standing where it is (it hangs below the edge of
    // what it reaches over): the whole body, which may step away and back.
    std::vector<double> whole = ctx.skills().configuration(stance_body_);
    std::copy(stance_rest_.begin(), stance_rest_.end(),
              whole.end() - static_cast<long>(stance_rest_.size()));
    if (!motion_.plan_now(ctx, stance_body_, whole)) {
      reached_ = stance_target_;
      return std::nullopt;
    }
  }
  std::optional<core::Failure> failure = reach_from_here(ctx);
  // Reaching from this stance failed where another stance may do (the planner connected to no
  // solution, the arm wedged between what it reaches over and what stands beside it; or no IK
  // solution from where the base stopped): another stance, a bounded number of times.
  if (failure && found_no_way(*failure) &&
      static_cast<int>(stances_left_.size()) < kMaxFailedStances) {
    stances_left_.push_back(ctx.skills().configuration({"base"}));
    failure = step_over(ctx, std::move(*failure));
  }
  if (failure) return Ended(std::move(failure));
  return std::nullopt;
}

std::vector<std::string> arm_claim(const core::ClaimContext& ctx, const std::string& arm,
                                   bool& torso, bool& base) {
  torso = torso && ctx.skills.profile().find_chain("torso") != nullptr && !ctx.busy("torso");
  base = base && !ctx.busy("base");
  std::vector<std::string> chains;
  if (base) chains.push_back("base");
  if (torso) chains.push_back("torso");
  chains.push_back(arm);
  return chains;
}

std::vector<std::string> head_chains(const core::Skillset& skills) {
  if (skills.profile().find_chain("head")) return {"head"};
  return {};
}

std::vector<std::string> head_claim(const core::ClaimContext& ctx, bool& base) {
  base = base && !ctx.busy("base");
  std::vector<std::string> chains = head_chains(ctx.skills);
  if (base) chains.push_back("base");
  return chains;
}

std::optional<core::Failure> MotionStage::start_following(
    core::ProgramContext& ctx, const std::vector<std::string>& chains,
    std::shared_ptr<const core::PlanResult> plan) {
  plan_ = plan;
  std::optional<core::Failure> failure;
  if (!plan->success()) failure = plan_failure(*plan);
  ctx.emit(core::MessageType::kPlanningEnded, failure, plan);
  if (failure) return failure;
  follow(ctx, chains, core::timed(ctx.skills().time_parameterize(chains, plan->path)), execution);
  return std::nullopt;
}

void MotionStage::follow(core::ProgramContext& ctx, const std::vector<std::string>& chains,
                         core::TimedMotion motion, const core::ExecutionOptions& options) {
  follower_.emplace(ctx.skills(), chains, std::move(motion), options);
}

std::optional<Ended> MotionStage::step() {
  if (!follower_)
    return Ended(core::Failure(core::FailureCode::kInvalidInput, "no motion to follow"));
  const std::optional<core::ExecutionReport> done = follower_->step();
  if (!done) return std::nullopt;
  follower_.reset();
  Ended outcome;
  if (!done->success()) outcome = core::Failure(core::failure_code(done->status), done->message);
  if (core::ProgramContext* ctx = std::exchange(pending_ctx_, nullptr)) {
    // The escape ended: plan from here.
    if (outcome) {
      outcome->detail += " (moving off what the arm touched)";
      return outcome;
    }
    if (std::optional<core::Failure> failure = plan_now(*ctx, pending_chains_, pending_goal_)) {
      return Ended(std::move(failure));
    }
    return std::nullopt;
  }
  return outcome;
}

}  // namespace taskmatrix::programs
