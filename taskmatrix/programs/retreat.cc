// retreat: makes room. With `part: base` the robot steps back from a surface (or object): the
// base moves `distance` horizontally away from the nearest point of its top (or box), keeping its
// heading, so that later arm motions (lowering the arms after a wave, a reach) are not made
// against the furniture; where that way is taken, it steps in a direction turned from it.
// Without `from` it steps away from every surface at once: in the direction that leaves the
// base and the hands (where they are, and where the arms' rest would put them) farthest from
// the nearest surface. A hand that touches an object (not a
// surface) first gets off it, as below. With `part: hand`
// the arm withdraws its hand `distance` straight back against the hand's approach axis (lifting
// what it holds straight up instead), as after a grasp that did not hold, before the next one is
// reached for; with `direction: up` the hand rises straight up, as off an object it has set down
// and let go of (its open fingers round the object's far side would drag it back with them),
// unless a finger lies under part of `from` (round a handle: rising would carry it), then back.
#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <string>

#include <Eigen/Geometry>

#include "taskmatrix/programs/primitives.h"
#include "taskmatrix/programs/program_support.h"

namespace taskmatrix::programs {

namespace {

class Retreat final : public core::TaskProgram {
 public:
  explicit Retreat(const core::Params& p)
      : part_(p.text("part")),
        from_(p.text("from")),
        side_(p.text("side")),
        up_(p.text("direction") == "up") {
    distance_ = p.number("distance");
    if (!(std::isfinite(distance_) && distance_ >= 0 && distance_ <= 2)) {
      throw std::invalid_argument("parameter 'distance': must be in [0, 2] m");
    }
  }

  std::vector<std::string> chains(const core::Skillset& skills) const override {
    // The base, and the arms a hand close to something withdraws first; the torso (if the
    // robot has one) and the arms when the base alone finds no way.
    if (part_ == "base") return body(skills);
    return {arm_of(side_ == "any" ? "left" : side_)};
  }
  std::vector<std::string> claim(const core::ClaimContext& ctx) override {
    if (part_ == "hand" && side_ == "any") side_ = nearest_free_side(ctx, from_, arm_of);
    return chains(ctx.skills);
  }

  void start(core::ProgramContext& ctx) override {
    if (distance_ <= 0) {
      done_ = true;
      return;
    }
    if (part_ == "hand") {
      // Up, unless a finger lies under part of what it let go of (round a handle): back.
      const bool lift = up_ && (from_.empty() || !finger_under(ctx, side_, from_, distance_));
      std::optional<Escape> escape =
          escape_motion(ctx, side_, touched_by_arm(ctx, side_), distance_,
                        /*always=*/true, /*torso=*/false, lift);
      if (!escape) {
        failure_ = core::Failure(core::FailureCode::kIkFailure,
                                 "the " + side_ + " arm cannot withdraw its hand " +
                                     std::to_string(distance_).substr(0, 4) + " m");
        return;
      }
      // Withdrawing from what it let go of may brush it, as stepping back from it may.
      if (!from_.empty() &&
          std::find(escape->options.may_touch.begin(), escape->options.may_touch.end(), from_) ==
              escape->options.may_touch.end()) {
        escape->options.may_touch.push_back(from_);
      }
      motion_.follow(ctx, escape->chains, std::move(escape->motion), escape->options);
      return;
    }
    failure_ = step_base(ctx);
  }

  core::ProgramState step(core::ProgramContext& ctx) override {
    if (failure_) return fail(*failure_);
    if (done_) return core::ProgramState::kCompleted;
    const std::optional<Ended> result = motion_.step();
    if (!result) return core::ProgramState::kRunning;
    if (withdrawing_) {
      // A hand has withdrawn (or stopped short, touching something on the way: it went as
      // far as it could): now the base.
      withdrawing_ = false;
      failure_ = step_base(ctx);
      return failure_ ? fail(*failure_) : core::ProgramState::kRunning;
    }
    if (*result && (*result)->code == core::FailureCode::kTrackingError && part_ == "base") {
      // Held back short of its goal (a hand dragging on what it rests against): room made is
      // room made, if the base got at least half the way.
      const std::vector<double> base = ctx.skills().configuration({"base"});
      const double moved = (Eigen::Vector2d(base[0], base[1]) - stepped_from_).norm();
      if (moved >= 0.5 * distance_) return core::ProgramState::kCompleted;
      core::Failure short_of = **result;
      short_of.detail += " (the base moved " + std::to_string(moved).substr(0, 5) + " m of " +
                         std::to_string(distance_).substr(0, 4) + ")";
      return fail(short_of);
    }
    if (*result) return fail(**result);
    return core::ProgramState::kCompleted;
  }

 private:
  // Starts the base's step away from `from`, or first a hand's withdrawal; why neither can.
  // Straight away first. Where that goal is taken or the way there blocked (a counter beside
  // the table it steps back from, the corner of another), directions turned from it in steps
  // of 30 degrees up to 90 either way, nearest first. The first direction whose straight step
  // is clear is planned to at once; where none is, or that plan finds no way, a hand close to
  // something (fingers round what a putdown has just let go of) withdraws first, each hand
  // once, and then the directions are planned to in turn, at most kPlans plans in all (each
  // plan's work is bounded by iterations); last, the base with the arms to the first direction.
  std::optional<core::Failure> step_base(core::ProgramContext& ctx) {
    core::Skillset& skills = ctx.skills();
    const std::vector<double> base = skills.configuration({"base"});
    const Eigen::Vector2d at(base[0], base[1]);
    stepped_from_ = at;
    // Without `from`: where the base and the hands are, what every surface is measured against.
    const std::vector<Eigen::Vector3d> points =
        from_.empty() ? base_and_hands(ctx, at) : std::vector<Eigen::Vector3d>{};
    const core::PerceivedObject* from = away_from(ctx, points);
    if (!from) {
      return from_.empty()
                 ? core::Failure(core::FailureCode::kPerceptionMiss, "no surface is known")
                 : core::Failure(core::FailureCode::kPerceptionMiss,
                                 "'" + from_ + "' is not in the perceptual model");
    }
    const core::SurfaceTop top = core::surface_top(*from);
    Eigen::Vector2d away = at - top.nearest(at);
    if (away.norm() < 1e-6) away = at - top.world(0.5 * (top.lo + top.hi));
    if (away.norm() < 1e-6) away = Eigen::Vector2d(-std::cos(base[2]), -std::sin(base[2]));
    away.normalize();
    // A hand that touches an object other than a surface (the open fingers round what a
    // putdown has just let go of) gets off it first: the base stepping back would drag the
    // object along with the hand, off its surface. Up, unless a finger lies under part of it
    // (round a handle): back.
    for (const char* side : {"left", "right"}) {
      if (withdrawn_.count(side)) continue;
      const std::vector<std::string> touched = touched_by_arm(ctx, side);
      bool on_object = false, under = false;
      for (const std::string& id : touched) {
        const core::PerceivedObject* o = ctx.percepts().find(id);
        if (!o || o->type == "surface") continue;
        on_object = true;
        under = under || finger_under(ctx, side, id, kWithdrawal);
      }
      if (on_object && withdraw(ctx, side, touched, /*lift=*/!under)) return std::nullopt;
    }
    // What it steps away from, and what a hand rests against (a surface), it may brush as it
    // leaves.
    motion_.execution.may_touch = {from->id};
    for (const char* side : {"left", "right"}) motion_.allow_touching(touched_by_arm(ctx, side));

    const core::ChainInfo& chain = skills.chain("base");
    const std::vector<Eigen::Vector2d> ways = directions(ctx, points, away);
    std::vector<std::vector<double>> goals;  // collision-free, in the order of `ways`
    for (const Eigen::Vector2d& way : ways) {
      std::vector<double> goal = base;
      goal[0] += distance_ * way.x();
      goal[1] += distance_ * way.y();
      for (size_t i = 0; i < goal.size(); ++i)
        goal[i] = std::clamp(goal[i], chain.lower[i], chain.upper[i]);
      if (skills.is_valid({"base"}, goal)) goals.push_back(std::move(goal));
    }
    const std::string where =
        " (stepping " + std::to_string(distance_).substr(0, 4) + " m away from '" + from->id +
        "', " + std::to_string(goals.size()) + " of " + std::to_string(ways.size()) +
        (from_.empty() ? " directions free, the farthest from every surface first"
                       : " directions within 90 degrees of straight away free");
    if (goals.empty()) {
      return core::Failure(core::FailureCode::kInvalidGoal,
                           "the goal configuration is in collision" + where + ")");
    }
    auto straight_clear = [&](const std::vector<double>& goal) {
      const int checks = std::max(1, static_cast<int>(std::ceil(distance_ / kStraightCheck)));
      std::vector<double> q = base;
      for (int k = 1; k < checks; ++k) {
        for (size_t i = 0; i < q.size(); ++i) q[i] = base[i] + k * (goal[i] - base[i]) / checks;
        if (!skills.is_valid({"base"}, q)) return false;
      }
      return true;
    };
    // The first failed plan: the program's failure if nothing after it does better.
    std::optional<core::Failure> first;
    int planned = 0;
    size_t tried = goals.size();  // the goal planned to below, if any
    for (size_t k = 0; k < goals.size(); ++k) {
      if (!straight_clear(goals[k])) continue;
      // Clear at every step, yet no way found within the clearance plans keep (a hand open
      // round a handle it has just let go of): the hands withdraw first, as below.
      std::optional<core::Failure> failure = motion_.plan_to_configuration(ctx, {"base"}, goals[k]);
      if (!failure || !found_no_way(*failure)) return failure;
      first = std::move(failure);
      ++planned;
      tried = k;
      break;
    }
    for (const char* side : {"left", "right"}) {
      const std::string arm = arm_of(side);
      if (withdrawn_.count(side)) continue;
      if (skills.clearance({arm}, skills.configuration({arm}), kNear) >= kNear) {
        withdrawn_.insert(side);
        continue;
      }
      if (withdraw(ctx, side, touched_by_arm(ctx, side), /*lift=*/false)) return std::nullopt;
    }
    for (size_t k = 0; k < goals.size() && planned < kPlans; ++k) {
      if (k == tried) continue;
      std::optional<core::Failure> failure = motion_.plan_to_configuration(ctx, {"base"}, goals[k]);
      if (!failure) return std::nullopt;  // following
      if (!first) first = std::move(failure);
      ++planned;
    }
    // The base alone found no way (a hand hovering a few millimetres over the table keeps that
    // height as the base moves, short of the clearance every plan keeps away from its ends):
    // the base with the torso and the arms, which may move on the way and end as they are.
    if (found_no_way(*first)) {
      const std::vector<std::string> chains = body(skills);
      std::vector<double> goal = clamped_configuration(skills, chains);
      std::copy(goals.front().begin(), goals.front().end(), goal.begin());
      std::optional<core::Failure> failure = motion_.plan_to_configuration(ctx, chains, goal);
      if (!failure) return std::nullopt;
      ++planned;
    }
    first->detail += where + ", " + std::to_string(planned) + " planned)";
    return first;
  }

  // Starts the hand on `side` withdrawing kWithdrawal before the base steps (once per side):
  // against its approach axis, or with `lift` straight up; false where it cannot.
  bool withdraw(core::ProgramContext& ctx, const std::string& side,
                const std::vector<std::string>& touched, bool lift) {
    withdrawn_.insert(side);
    std::optional<Escape> escape =
        escape_motion(ctx, side, touched, kWithdrawal, /*always=*/true, /*torso=*/false, lift);
    if (!escape) return false;
    withdrawing_ = true;
    motion_.follow(ctx, escape->chains, std::move(escape->motion), escape->options);
    return true;
  }

  // The base first, then the torso if the robot has one, and the arms.
  static std::vector<std::string> body(const core::Skillset& skills) {
    std::vector<std::string> chains = {"base"};
    if (skills.profile().find_chain("torso")) chains.push_back("torso");
    chains.push_back(arm_of("left"));
    chains.push_back(arm_of("right"));
    return chains;
  }

  // `from`, or the surface nearest to `points` (base_and_hands).
  const core::PerceivedObject* away_from(core::ProgramContext& ctx,
                                         const std::vector<Eigen::Vector3d>& points) {
    if (!from_.empty()) return ctx.percepts().find(from_);
    const core::PerceivedObject* best = nullptr;
    double best_d = std::numeric_limits<double>::infinity();
    for (const core::PerceivedObject* s : ctx.percepts().of_type("surface")) {
      const double d = distance_to(*s, points, Eigen::Vector2d::Zero());
      if (d < best_d) best_d = d, best = s;
    }
    return best;
  }

  // The base and the hands, the hands where they are and where the rest of the torso and the
  // arms would put them from here (what follows a step back: the arms lowered after a wave or
  // a putdown): a hand out over a surface is what the arms' later motions would meet. The
  // base counts at any height (its z is minus infinity).
  static std::vector<Eigen::Vector3d> base_and_hands(core::ProgramContext& ctx,
                                                     const Eigen::Vector2d& at) {
    core::Skillset& skills = ctx.skills();
    const ChainValues rest =
        posture_values(skills, "rest", {"torso", arm_of("left"), arm_of("right")});
    std::vector<Eigen::Vector3d> points = {
        Eigen::Vector3d(at.x(), at.y(), -std::numeric_limits<double>::infinity())};
    for (const core::HandSpec& hand : skills.profile().hands) {
      points.push_back(skills.frame_pose(hand.palm).position);
      points.push_back(skills.frame_pose_at(rest.chains, rest.values, hand.palm).position);
    }
    return points;
  }

  // The least distance, seen from above, from `points` moved by `step` to the top of
  // `surface`; negative inside it (how far in from its nearest edge). A hand higher than
  // kOverTop above the top (an arm raised to wave) does not count: it does not meet it.
  static double distance_to(const core::PerceivedObject& surface,
                            const std::vector<Eigen::Vector3d>& points,
                            const Eigen::Vector2d& step) {
    const core::SurfaceTop top = core::surface_top(surface);
    double least = std::numeric_limits<double>::infinity();
    for (const Eigen::Vector3d& point : points) {
      if (point.z() > top.height + kOverTop) continue;
      least = std::min(least, top.signed_distance(point.head<2>() + step));
    }
    return least;
  }

  // The directions to step in. Away from `from`: straight away, then turned from it in steps
  // of 30 degrees up to 90 either way, nearest first. Without `from`, every surface counts:
  // stepping from the nearest one alone can take the robot towards another (from the counter
  // it set a cup on towards the table beside it, whose top the arms' rest then meets). All
  // 12 directions 30 degrees apart, ordered by the clearance the step leaves, seen from above,
  // between the base and the hands and the nearest surface to them (to the millimetre; ties
  // nearest straight away from the nearest surface first).
  std::vector<Eigen::Vector2d> directions(core::ProgramContext& ctx,
                                          const std::vector<Eigen::Vector3d>& points,
                                          const Eigen::Vector2d& away) const {
    std::vector<Eigen::Vector2d> ways;
    for (const int turn : {0, 1, -1, 2, -2, 3, -3, 4, -4, 5, -5, 6}) {
      if (!from_.empty() && std::abs(turn) > 3) break;
      ways.push_back(Eigen::Rotation2Dd(turn * M_PI / 6) * away);
    }
    if (!from_.empty()) return ways;
    const std::vector<const core::PerceivedObject*> surfaces = ctx.percepts().of_type("surface");
    std::vector<std::pair<double, size_t>> order;  // (-clearance in mm, index)
    for (size_t i = 0; i < ways.size(); ++i) {
      double clearance = std::numeric_limits<double>::infinity();
      for (const core::PerceivedObject* s : surfaces) {
        clearance = std::min(clearance, distance_to(*s, points, distance_ * ways[i]));
      }
      order.emplace_back(-std::round(clearance * 1000), i);
    }
    std::sort(order.begin(), order.end());
    std::vector<Eigen::Vector2d> sorted;
    for (const auto& [clearance, i] : order) sorted.push_back(ways[i]);
    return sorted;
  }

  static constexpr int kPlans = 3;
  static constexpr double kStraightCheck = 0.01;  // m between the straight step's checks
  static constexpr double kNear = 0.02;           // m: a hand this close to something withdraws
  static constexpr double kWithdrawal = 0.08;     // m, how far a hand withdraws first
  static constexpr double kOverTop = 0.3;  // m over a top above which a hand does not meet it

  std::string part_, from_, side_;
  bool up_ = false;  // part hand: straight up rather than back
  double distance_ = 0.2;
  MotionStage motion_;
  std::optional<core::Failure> failure_;
  bool done_ = false;
  bool withdrawing_ = false;
  Eigen::Vector2d stepped_from_ = Eigen::Vector2d::Zero();  // the base where its step began
  std::set<std::string> withdrawn_;  // sides whose hand has had its chance to withdraw
};

}  // namespace

core::ProgramType retreat_program() {
  using core::ParamType;
  return {"retreat",
          "steps the base back from a surface, or withdraws a hand straight back, to make room",
          {{"part",
            ParamType::kString,
            false,
            std::string("base"),
            {"base", "hand"},
            "base: step away from `from`; hand: withdraw the hand against its approach axis"},
           {"from",
            ParamType::kString,
            false,
            std::string(),
            {},
            "the surface or object to step away from (base; default: every surface), or "
            "the object the hand withdraws from, which it may brush (hand; side any: the hand "
            "nearest it)",
            core::NameKind::kObject},
           {"distance", ParamType::kNumber, false, 0.2, {}, "how far, m"},
           {"side", ParamType::kString, false, std::string("any"), kSides,
            "hand: which; any: the free hand nearest `from`"},
           {"direction",
            ParamType::kString,
            false,
            std::string("back"),
            {"back", "up"},
            "hand: back against the hand's approach axis, or straight up (off what it let go "
            "of; back where a finger lies under part of `from`)"}},
          [](const core::Params& p) { return std::make_unique<Retreat>(p); }};
}

}  // namespace taskmatrix::programs
