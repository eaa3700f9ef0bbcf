// fixate: keeps an object centred in the head camera (paper: "fixate"). Every control period
// it finds the head configuration that points the camera's optical axis at the object's box
// centre (damped least squares on the head joints, with a finite-difference Jacobian of the
// camera's view angles) and moves the head towards it within the head's speed limits. When
// the head alone cannot centre the object (the head is at a limit and the object is off to
// the side) and the base is free, the base turns about its yaw joint, the third joint of the
// planar base chain (x, y, yaw) as the skillset defines it, the other way round when the
// short way is past a limit of a yaw whose range spans a full turn; a turn that would bring the
// robot into collision (is_valid) is not taken, nor a head step to within 1 cm of anything, the
// robot's own body included (clearance).
//
// Records "tracking_error_rad" (the angle between the optical axis and the object) every
// control period. Ends when halted, after `duration` seconds if given (failing,
// `tracking_error`, if the object was never in view meanwhile), or, with
// `until_centered`, once the object has stayed centred for 0.3 s: within `tolerance`, or, for
// a head that cannot do better (a neck without pitch), in view with the head at its best
// configuration and no horizontal error left. A robot without a head chain (its camera fixed
// to the trunk) aims with the base's yaw alone; with the base not free either, nothing aims
// the camera and the object counts as centred while it is in view. With `until_centered`, it
// fails (`invalid_goal`) when every base turn it asked for has been refused for 2 s (the object
// will not be centred from where the robot stands), and (`tracking_error`) when it is not
// centred after 20 s.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "taskmatrix/programs/primitives.h"
#include "taskmatrix/programs/program_support.h"

namespace taskmatrix::programs {

namespace {

constexpr double kCenteredHold = 0.3;  // s the object must stay centred for until_centered
// With until_centered: s of refused base turns, the object not centred, before fixate fails.
constexpr double kBlockedS = 2.0;
// How far past a full-turn yaw's limit a heading may be and still be turned to the limit (the
// neck takes up the rest) rather than reached the other way round, rad.
constexpr double kAroundMargin = 0.15;
// With until_centered: s after which an object never centred fails fixate.
constexpr double kSeekLimitS = 20.0;
// Base turns smaller than this (rad, or a quarter of the tolerance) are not commanded (nor
// checked for collision).
constexpr double kMinTurnRad = 0.002;
// How far (rad, any joint) the head's goal moves before it is checked for collision again.
constexpr double kGoalRecheckRad = 0.02;
// How far (m) the head keeps from everything, the robot's own body included.
constexpr double kHeadClearanceM = 0.01;

// The object's direction in the camera's view: (horizontal, vertical) angles off the optical
// axis (the camera looks along its -z, with +x right and +y up).
Eigen::Vector2d view_angles(const core::Pose& camera, const Eigen::Vector3d& point) {
  const Eigen::Vector3d p = camera.orientation.conjugate() * (point - camera.position);
  return {std::atan2(p.x(), -p.z()), std::atan2(p.y(), -p.z())};
}

double off_axis(const core::Pose& camera, const Eigen::Vector3d& point) {
  const Eigen::Vector3d p = camera.orientation.conjugate() * (point - camera.position);
  return std::acos(std::clamp(-p.z() / std::max(p.norm(), 1e-9), -1.0, 1.0));
}

class Fixate final : public core::TaskProgram {
 public:
  explicit Fixate(const core::Params& p)
      : object_(p.text("object")),
        duration_(p.number("duration")),
        until_centered_(p.flag("until_centered")),
        tolerance_(p.number("tolerance")),
        use_base_(p.flag("base")) {
    if (!(std::isfinite(duration_) && duration_ >= 0)) {
      throw std::invalid_argument("parameter 'duration': must be >= 0 s (0: until halted)");
    }
    if (!(tolerance_ > 0 && tolerance_ < 1)) {
      throw std::invalid_argument("parameter 'tolerance': must be in (0, 1) rad");
    }
  }

  std::vector<std::string> chains(const core::Skillset& skills) const override {
    return head_chains(skills);
  }
  std::vector<std::string> claim(const core::ClaimContext& ctx) override {
    base_ = use_base_;
    return head_claim(ctx, base_);
  }

  void start(core::ProgramContext& ctx) override {
    core::Skillset& skills = ctx.skills();
    camera_ = skills.head_camera().frame;
    has_head_ = !head_chains(skills).empty();
    if (has_head_) head_ = skills.clamped_configuration({"head"});
    start_time_ = ctx.time();
    if (base_) {
      base_cmd_ = skills.clamped_configuration({"base"});
      if (base_cmd_.size() != 3) {
        failure_ = core::Failure(core::FailureCode::kInvalidInput,
                                 "the base chain is not planar (x, y, yaw)");
      }
    }
  }

  core::ProgramState step(core::ProgramContext& ctx) override {
    if (failure_) return fail(*failure_);
    const core::PerceivedObject* o = ctx.percepts().find(object_);
    if (!o)
      return fail(core::Failure(core::FailureCode::kPerceptionMiss,
                                "'" + object_ + "' is not in the perceptual model"));
    core::Skillset& skills = ctx.skills();
    const Eigen::Vector3d target = o->box.center();
    const double error = off_axis(skills.frame_pose(camera_), target);
    ctx.record("tracking_error_rad", error);

    const double dt = skills.control_period();
    std::vector<double> goal;  // the head's, if the robot has one
    if (has_head_) goal = step_head(skills, target, dt);

    // What the head cannot take up: the object's horizontal angle from the camera at the
    // head's goal (where the head stopped short of it, at the head as it is: an arm raised
    // beside the head, a chest below it). The base turns it away when it may.
    const double residual =
        view_angles(has_head_
                        ? skills.frame_pose_at({"head"}, head_blocked_ ? head_ : goal, camera_)
                        : skills.frame_pose(camera_),
                    target)
            .x();
    const bool head_there = max_difference(goal, head_) < 0.01;
    // Nothing aims the camera (no head chain, the base not free): keeping the object in view
    // is the best there is.
    const bool aims = has_head_ || base_;
    const bool best_possible = head_there && (std::abs(residual) <= tolerance_ || !aims) &&
                               core::in_camera_view(skills, o->box);
    if (base_) {
      const core::ChainInfo& base = skills.chain("base");
      const double step = base.speed.velocity * dt;
      // The heading that centres the object, from where the base stands (+x right: turn left
      // for -x). Not from its command: under physics the base lags its command, and a command
      // stepped on by what is still to turn runs ahead of the base and past the object, then
      // back past it (atlas, without a neck yaw, swung 0.1 rad either side of a walking
      // visitor and never held it centred). Turns smaller than kMinTurnRad are not commanded.
      const double measured = skills.clamped_configuration({"base"})[2];
      double heading = measured - residual;
      // A yaw joint whose range spans a full turn reaches a heading past one of its limits
      // the other way round (a robot that starts facing -x at the limit of a [-pi, pi] yaw).
      // A heading past the limit by no more than the neck (or the tolerance) takes up is
      // turned to the limit instead; once going round, it keeps going while the heading
      // is past the limit at all (a target just past it, moving or seen from a lagging
      // base, would otherwise flip the direction back and forth).
      const bool full_turn = base.upper[2] - base.lower[2] >= 2 * M_PI - 1e-3;
      const double past =
          full_turn ? std::max(heading - base.upper[2], base.lower[2] - heading) : 0.0;
      const double margin = has_head_ ? kAroundMargin : tolerance_ / 2;
      if (past > (going_round_ ? 0.0 : margin)) {
        going_round_ = true;
        heading += heading > base.upper[2] ? -2 * M_PI : 2 * M_PI;
      } else if (past <= 0) {
        going_round_ = false;
      }
      const double turn = std::clamp(heading - base_cmd_[2], -step, step);
      const bool wants_turn = std::abs(residual) > tolerance_ / 2;
      if (std::abs(turn) > std::min(kMinTurnRad, tolerance_ / 4)) {
        std::vector<double> turned = base_cmd_;
        turned[2] = std::clamp(base_cmd_[2] + turn, base.lower[2], base.upper[2]);
        // Nothing checks a commanded turn on the way: one that would sweep the robot (a hand
        // beside the table) into something is not taken, and the head alone tracks.
        if (skills.is_valid({"base"}, turned)) {
          base_cmd_ = turned;
          skills.command({"base"}, base_cmd_);
          blocked_since_ = -1;
        } else if (wants_turn && blocked_since_ < 0) {
          blocked_since_ = ctx.time();
        }
      }
      if (!wants_turn) blocked_since_ = -1;
      // Waiting to be centred while the base cannot turn (the robot close beside furniture, a
      // neck that cannot take up the angle): it never will be. A machine can make room and try
      // again; running on would only meet the scenario's time limit without a reason.
      if (until_centered_ && blocked_since_ >= 0 &&
          ctx.time() - blocked_since_ >= kBlockedS - 1e-9) {
        char buf[200];
        std::snprintf(buf, sizeof buf,
                      "the base cannot turn towards '%s' without touching something (%.0f degrees "
                      "still to turn, refused for %.1f s)",
                      object_.c_str(), std::abs(residual) * 180 / M_PI, kBlockedS);
        stop_base(skills);
        return fail(core::Failure(core::FailureCode::kInvalidGoal, buf));
      }
    }

    const double now = ctx.time();
    ever_in_view_ = ever_in_view_ || core::in_camera_view(skills, o->box);
    if (error <= tolerance_ || best_possible) {
      if (centered_since_ < 0) centered_since_ = now;
    } else {
      centered_since_ = -1;
    }
    best_error_ = std::min(best_error_, error);
    if (until_centered_ && now - start_time_ >= kSeekLimitS - 1e-9 && centered_since_ < 0) {
      char buf[200];
      std::snprintf(buf, sizeof buf, "'%s' not centred after %.0f s (at best %.2f rad off)",
                    object_.c_str(), kSeekLimitS, best_error_);
      stop_base(skills);
      return fail(core::Failure(core::FailureCode::kTrackingError, buf));
    }
    const bool done = (until_centered_ && centered_since_ >= 0 &&
                       now - centered_since_ >= kCenteredHold - 1e-9) ||
                      (duration_ > 0 && now - start_time_ >= duration_ - 1e-9);
    if (!done) return core::ProgramState::kRunning;
    stop_base(skills);
    if (!ever_in_view_) {
      // The duration ran out with the object never in view: nothing was tracked.
      char buf[240];
      std::snprintf(buf, sizeof buf, "'%s' never in view in %.1f s (at best %.2f rad off%s)",
                    object_.c_str(), now - start_time_, best_error_,
                    blocked_since_ >= 0
                        ? "; the base cannot turn towards it without touching something"
                        : "");
      return fail(core::Failure(core::FailureCode::kTrackingError, buf));
    }
    return core::ProgramState::kCompleted;
  }

 private:
  // The base, if fixate turns it, stops where it is: under physics it lags its command, and a
  // program that plans next (an arm raised beside the table) plans from where it stands.
  void stop_base(core::Skillset& skills) const {
    if (base_) skills.command({"base"}, skills.clamped_configuration({"base"}));
  }

  // One control period of the head towards the configuration that centres `target`, within
  // its speed limits; returns that goal.
  std::vector<double> step_head(core::Skillset& skills, const Eigen::Vector3d& target, double dt) {
    const core::ChainInfo& head = skills.chain("head");
    const std::vector<double> goal = look_at(skills, head, target);
    std::vector<double> next = head_;
    for (size_t i = 0; i < next.size(); ++i) {
      const double step = head.speed.velocity * dt;
      next[i] = std::clamp(next[i] + std::clamp(goal[i] - next[i], -step, step), head.lower[i],
                           head.upper[i]);
    }
    // Nor is a head step checked on the way: a step to within kHeadClearanceM of anything (the
    // head pitched down onto the robot's own chest, looking at an object close in front) is
    // not taken; the margin covers the servo's overshoot. The goal is checked when it has moved
    // kGoalRecheckRad since it last was; while it is clear the steps towards it go unchecked,
    // else each step is checked and the head stops short.
    auto clear = [&](const std::vector<double>& q) {
      return skills.clearance({"head"}, q, 2 * kHeadClearanceM) >= kHeadClearanceM;
    };
    if (checked_goal_.empty() || max_difference(goal, checked_goal_) > kGoalRecheckRad) {
      checked_goal_ = goal;
      goal_clear_ = clear(goal);
    }
    head_blocked_ = next != head_ && !(goal_clear_ || clear(next));
    if (next != head_ && !head_blocked_) head_ = next;
    skills.command({"head"}, head_);
    return goal;
  }

  // Head joints that point the camera at `target`, from the current goal: a few damped
  // Gauss-Newton steps on the view angles, within joint limits.
  std::vector<double> look_at(core::Skillset& skills, const core::ChainInfo& head,
                              const Eigen::Vector3d& target) {
    std::vector<double> q = goal_.empty() ? head_ : goal_;
    const size_t n = q.size();
    const double h = 1e-4;
    for (int iter = 0; iter < 3; ++iter) {
      const Eigen::Vector2d e = view_angles(skills.frame_pose_at({"head"}, q, camera_), target);
      if (e.norm() < 1e-4) break;
      Eigen::MatrixXd jac(2, n);
      for (size_t i = 0; i < n; ++i) {
        std::vector<double> qh = q;
        const bool down = qh[i] + h > head.upper[i];
        qh[i] += down ? -h : h;
        const Eigen::Vector2d eh = view_angles(skills.frame_pose_at({"head"}, qh, camera_), target);
        jac.col(static_cast<Eigen::Index>(i)) = (eh - e) / (down ? -h : h);
      }
      const Eigen::MatrixXd jjt = jac * jac.transpose() + 1e-4 * Eigen::Matrix2d::Identity();
      const Eigen::VectorXd dq = -jac.transpose() * jjt.ldlt().solve(e);
      for (size_t i = 0; i < n; ++i) {
        q[i] = std::clamp(q[i] + dq[static_cast<Eigen::Index>(i)], head.lower[i], head.upper[i]);
      }
    }
    goal_ = q;
    return q;
  }

  std::string object_;
  double duration_;
  bool until_centered_;
  double tolerance_;
  bool use_base_, base_ = false;
  bool has_head_ = false;  // a robot whose camera is fixed to its trunk has no head chain
  std::string camera_;
  std::vector<double> head_, goal_, base_cmd_;
  // The head goal last checked for collision, and whether it was clear.
  std::vector<double> checked_goal_;
  bool goal_clear_ = false;
  bool head_blocked_ = false;  // the last head step towards its goal was not taken
  double start_time_ = 0, centered_since_ = -1;
  double blocked_since_ = -1;     // since when each base turn asked for was refused
  bool going_round_ = false;      // turning the other way round past the yaw's limit
  double best_error_ = INFINITY;  // rad, the nearest the object came to the optical axis
  bool ever_in_view_ = false;     // the object has been in the camera's view
  std::optional<core::Failure> failure_;
};

}  // namespace

core::ProgramType fixate_program() {
  using core::ParamType;
  return {"fixate",
          "keeps an object centred in the head camera with the head (and the base's yaw when "
          "the head cannot); records the tracking error",
          {{"object",
            ParamType::kString,
            true,
            {},
            {},
            "object id in the perceptual model",
            core::NameKind::kObject},
           {"duration",
            ParamType::kNumber,
            false,
            0.0,
            {},
            "complete after this many seconds; 0: run until halted"},
           {"until_centered",
            ParamType::kBool,
            false,
            false,
            {},
            "complete once the object has stayed within `tolerance` for 0.3 s"},
           {"tolerance", ParamType::kNumber, false, 0.05, {}, "rad off the optical axis"},
           {"base",
            ParamType::kBool,
            false,
            true,
            {},
            "turn the base when the head cannot centre the object (if the base is free)"}},
          [](const core::Params& p) { return std::make_unique<Fixate>(p); }};
}

}  // namespace taskmatrix::programs
