// reach: moves an arm so that its hand can grasp an object (paper: "reach"). The target hand
// configurations come from the object's geometry (grasp_candidates.h): grasps around a tool's
// grip, from above and from the side, ranked for this hand; those a grasp of this object by
// this hand already failed with (ProgramContext::notes) are left out. Each is tried in turn
// (IK, then planning), at two clearances of the palm, with the arm, then torso and arm, then by
// stepping (ArmMotion); the first plan found is executed and its candidate noted for grasp.
// The fallback candidates (a part of the object on its own, side grasps higher up, grasps the
// fingers wrap) get a second round of the same only when the first found no way to any of the
// others (or first, when there are no others). The
// hand may turn about the candidate's free axis (round objects, handles) as far as the grasp
// allows, whatever the arm; after a grasp that did not hold because something else stopped a
// finger, only as far as the closing fingers stay over the surface under the object. Exits at
// once when the object is already graspable by that hand.
#include <algorithm>
#include <cmath>

#include "taskmatrix/programs/grasp_candidates.h"
#include "taskmatrix/programs/primitives.h"
#include "taskmatrix/programs/program_support.h"

namespace taskmatrix::programs {

namespace {

// Clearances of the palm from the object's near side, along the approach: close, then with
// more room.
constexpr double kClearances[] = {0.01, 0.025};
// A free axis with a larger vertical component turns the hand about the vertical, which
// keeps the fingers' heights.
constexpr double kVerticalAxis = 0.9;
// How far the axes of the closing fingers stay over the support.
constexpr double kSweepClearance = 0.005;
// How much of one round's failure reason follows the other's.
constexpr size_t kMaxSecondReason = 160;

class Reach final : public core::TaskProgram {
 public:
  explicit Reach(const core::Params& p)
      : object_(p.text("object")),
        side_(p.text("side")),
        use_torso_(p.flag("torso")),
        use_base_(p.flag("base")),
        max_failures_(static_cast<int>(p.integer("attempts"))) {
    if (max_failures_ < 1) throw std::invalid_argument("parameter 'attempts': must be at least 1");
  }

  std::vector<std::string> chains(const core::Skillset&) const override {
    return {arm_of(side_ == "any" ? "left" : side_)};
  }
  std::vector<std::string> claim(const core::ClaimContext& ctx) override {
    if (side_ == "any") side_ = nearest_free_side(ctx, object_, arm_of);
    torso_ = use_torso_;
    base_ = use_base_;
    return arm_claim(ctx, arm_of(side_), torso_, base_);
  }

  void start(core::ProgramContext& ctx) override {
    const core::PerceivedObject* o = ctx.percepts().find(object_);
    if (!o) {
      failure_ = core::Failure(core::FailureCode::kPerceptionMiss,
                               "'" + object_ + "' is not in the perceptual model");
      return;
    }
    const std::vector<std::string>& failed = ctx.notes(failed_grasps_note(object_, side_));
    if (static_cast<int>(failed.size()) >= max_failures_) {
      failure_ =
          core::Failure(core::FailureCode::kGraspFailed,
                        std::to_string(failed.size()) + " grasps of '" + object_ + "' with the " +
                            side_ + " hand did not hold (" + join(failed) + ")");
      return;
    }
    // Already graspable: done, unless the grasp there is one that did not hold.
    const std::vector<std::string>& reached = ctx.notes(reached_grasp_note(object_, side_));
    const bool failed_here = !reached.empty() && std::find(failed.begin(), failed.end(),
                                                           reached.front()) != failed.end();
    if (!failed_here && core::graspable(object_, side_)->holds(ctx.world())) {
      done_ = true;
      return;
    }
    core::Skillset& skills = ctx.skills();
    palm_ = skills.profile().find_hand(side_)->palm;
    geometry_ = measure_hand(skills, *skills.profile().find_hand(side_));
    const HandGeometry& geometry = geometry_;
    std::vector<GraspCandidate> all =
        grasp_candidates(*o, geometry, skills.frame_pose(palm_).position);
    if (all.empty()) {
      failure_ = core::Failure(
          core::FailureCode::kNotGraspable,
          "the " + side_ + " hand (aperture " +
              std::to_string(static_cast<int>(std::lround(geometry.aperture_m * 1000))) +
              " mm) spans no grasp of '" + object_ + "' and its fingers wrap none");
      return;
    }
    for (const GraspCandidate& c : all) {
      if (std::find(failed.begin(), failed.end(), c.id) != failed.end()) continue;
      (c.fallback ? fallback_ : candidates_).push_back(c);
    }
    if (candidates_.empty()) candidates_.swap(fallback_);
    if (candidates_.empty()) {
      failure_ =
          core::Failure(core::FailureCode::kGraspFailed,
                        std::to_string(failed.size()) + " grasps of '" + object_ + "' with the " +
                            side_ + " hand did not hold (" + join(failed) + ")");
      return;
    }
    failure_ = start_round(ctx);
    if (failure_) failure_ = next_round(ctx, std::move(*failure_));
  }

  // Moves to one of candidates_: their targets to ArmMotion.
  std::optional<core::Failure> start_round(core::ProgramContext& ctx) {
    const HandGeometry& geometry = geometry_;
    std::vector<ArmTarget> targets;
    const bool blocked = !ctx.notes(blocked_fingers_note(object_, side_)).empty();
    for (const GraspCandidate& c : candidates_) {
      for (double clearance : kClearances) {
        const GraspCandidate::Placement at = c.place(geometry, clearance);
        ArmTarget t;
        t.pose = at.pose;
        t.free_axis = c.free_axis;
        t.free_turn_rad = at.free_turn_rad;
        t.tag = c.id;
        // Turning about an axis that is not vertical (a handle's), IK decides how low the
        // fingers go. After a grasp that did not hold because something other than the object
        // stopped a finger, their closing sweep must stay over the support. The sweep errs low
        // (fingertips as long as the segment before them, each finger stopping only when its
        // axis reaches the handle's radius), so it is not asked of every grasp: asked of the
        // first, it kept out grasps that hold (tallbot over a low table).
        if (blocked && std::abs(c.free_axis.z()) < kVerticalAxis && at.free_turn_rad > 0) {
          // The handle in the palm frame, the same however the hand turns about it.
          const Eigen::Quaterniond to_palm = at.pose.orientation.conjugate();
          t.keep_above = geometry.swept_points(to_palm * (c.centre - at.pose.position),
                                               to_palm * c.free_axis, c.width_m / 2);
          t.floor_z = c.support_z + kSweepClearance;
        }
        targets.push_back(std::move(t));
      }
    }
    core::IkOptions ik;
    ik.restarts = 8;
    // Settle close to the planned hand pose: the graspable test allows 3 cm.
    arm_motion_.stage().execution.position_tolerance = 0.003;
    // The fingers may brush the object on the last centimetres; anything else stops the arm.
    arm_motion_.stage().execution.may_touch = {object_};
    return arm_motion_.start(ctx, arm_of(side_), palm_, targets, ik, torso_, base_);
  }

  // After `failure` of a round that found no way to its candidates (found_no_way): the
  // fallback candidates (GraspCandidate::fallback) get their own round, started here (nullopt).
  // Without one, the failure; after a second round, what both found: the first round's code
  // and reason followed by the second's when that too found no way, else the second's (a
  // collision while moving there) followed by the first's reason.
  std::optional<core::Failure> next_round(core::ProgramContext& ctx, core::Failure failure) {
    if (!first_round_failure_ && found_no_way(failure) && !fallback_.empty()) {
      first_round_failure_ = std::move(failure);
      candidates_ = std::move(fallback_);
      fallback_.clear();
      std::optional<core::Failure> second = start_round(ctx);
      if (!second) return std::nullopt;
      failure = std::move(*second);
    }
    if (!first_round_failure_) return failure;
    auto cut = [](std::string text) {
      return text.size() > kMaxSecondReason ? text.substr(0, kMaxSecondReason) + "..." : text;
    };
    const std::string second_round =
        std::to_string(candidates_.size()) + " grasps higher up, wrapping or of a part";
    if (!found_no_way(failure)) {
      failure.detail += " (reaching for " + second_round + ", after the first round's " +
                        cut(first_round_failure_->reason()) + ")";
      return failure;
    }
    core::Failure out = *first_round_failure_;
    out.detail += "; then " + second_round + ": " + cut(failure.reason());
    return out;
  }

  core::ProgramState step(core::ProgramContext& ctx) override {
    if (failure_) return fail(*failure_);
    if (done_) return core::ProgramState::kCompleted;
    const std::optional<Ended> result = arm_motion_.step(ctx);
    if (!result) return core::ProgramState::kRunning;
    if (*result) {
      std::optional<core::Failure> failure = next_round(ctx, std::move(**result));
      return failure ? fail(*failure) : core::ProgramState::kRunning;
    }
    const int k = arm_motion_.target_index();
    if (k >= 0) {
      ctx.notes(reached_grasp_note(object_, side_)) = {
          candidates_[static_cast<size_t>(k) / std::size(kClearances)].id};
    }
    if (!core::graspable(object_, side_)->holds(ctx.world())) {
      return fail(core::Failure(core::FailureCode::kNotGraspable,
                                "the " + side_ + " palm reached its target but '" + object_ +
                                    "' is not graspable from there (did it move?)"));
    }
    return core::ProgramState::kCompleted;
  }

 private:
  static std::string join(const std::vector<std::string>& items) {
    std::string out;
    for (const std::string& i : items) out += (out.empty() ? "" : ", ") + i;
    return out;
  }

  std::string object_, side_;
  bool use_torso_ = true, torso_ = false, use_base_ = true, base_ = false;
  int max_failures_ = 3;
  // The candidates of the round under way, and those for a second round (GraspCandidate::
  // fallback) after a first that found no way to its own.
  std::vector<GraspCandidate> candidates_, fallback_;
  std::optional<core::Failure> first_round_failure_;
  std::string palm_;
  HandGeometry geometry_;
  ArmMotion arm_motion_;
  std::optional<core::Failure> failure_;
  bool done_ = false;
};

}  // namespace

core::ProgramType reach_program() {
  return {"reach",
          "collision-free arm motion to a hand pose from which `object` can be grasped",
          {{"object",
            core::ParamType::kString,
            true,
            {},
            {},
            "object id in the perceptual model",
            core::NameKind::kObject},
           {"side", core::ParamType::kString, false, std::string("any"), kSides,
            "arm to use; any: the free arm nearest the object"},
           {"torso",
            core::ParamType::kBool,
            false,
            true,
            {},
            "bend the torso too when the arm alone cannot reach (if the torso is free)"},
           {"base",
            core::ParamType::kBool,
            false,
            true,
            {},
            "step the base too when arm and torso cannot reach (if the base is free)"},
           {"attempts",
            core::ParamType::kInteger,
            false,
            std::int64_t{3},
            {},
            "fail once this many grasps of the object by this hand did not hold"}},
          [](const core::Params& p) { return std::make_unique<Reach>(p); }};
}

}  // namespace taskmatrix::programs
