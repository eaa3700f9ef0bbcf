// position: like reach, with a held object as the end effector (paper: "position"). The
// controlled frame is one of the held object's frames from its model ("tip", "grip") or the
// object itself ("origin"). Targets:
//   - `target`: a point `height` above the top of that object's box (a tool's tip over a
//     flake of debris);
//   - `target_type`: the same, for the nearest known object of that type;
//   - `on`: a resting placement for the held object on that surface, drawn from
//     above(object, surface) and near(object, surface) (putdown), `height` above its rest;
//     those 1 cm clear of other known objects' boxes (not surfaces', not the visitor's) first,
//     then nearest the object.
// Candidate orientations stand the held object up as it stood before the grasp and turn it
// about the vertical; the turn is also left to IK, for any arm. Each candidate is tried in turn
// (IK, then planning), with the arm, then torso and arm, then base, torso and arm (ArmMotion).
// A held object that rests on a surface is lifted off it first.
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "taskmatrix/programs/primitives.h"
#include "taskmatrix/programs/program_support.h"

namespace taskmatrix::programs {

namespace {

// How far a placement keeps from another object's box, across.
constexpr double kPlacementGapM = 0.01;

class Position final : public core::TaskProgram {
 public:
  explicit Position(const core::Params& p)
      : object_(p.text("object")),
        frame_(p.text("frame")),
        target_(p.text("target")),
        target_type_(p.text("target_type")),
        on_(p.text("on")),
        height_(p.number("height")),
        use_torso_(p.flag("torso")),
        use_base_(p.flag("base")) {
    const int given = !target_.empty() + !target_type_.empty() + !on_.empty();
    if (given != 1) {
      throw std::invalid_argument("position needs exactly one of target, target_type and on");
    }
    if (!(std::isfinite(height_) && height_ >= 0 && height_ <= 0.5)) {
      throw std::invalid_argument("parameter 'height': must be in [0, 0.5] m");
    }
  }

  std::vector<std::string> chains(const core::Skillset& skills) const override {
    const std::string side = skills.holder_of(object_);
    return {arm_of(side.empty() ? "left" : side)};
  }
  std::vector<std::string> claim(const core::ClaimContext& ctx) override {
    side_ = ctx.skills.holder_of(object_);
    if (side_.empty()) side_ = "left";  // the precondition fails it before it moves
    torso_ = use_torso_;
    base_ = use_base_;
    return arm_claim(ctx, arm_of(side_), torso_, base_);
  }
  core::ConditionPtr precondition() const override { return core::grasping(object_); }

  void start(core::ProgramContext& ctx) override {
    const core::PerceivedObject* held = ctx.percepts().find(object_);
    if (!held) {
      failure_ = core::Failure(core::FailureCode::kPerceptionMiss,
                               "'" + object_ + "' is not in the perceptual model");
      return;
    }
    if (frame_ != "origin" && !held->frames.count(frame_)) {
      failure_ = core::Failure(core::FailureCode::kInvalidInput,
                               "'" + object_ + "' has no frame '" + frame_ + "'");
      return;
    }
    const std::string frame = frame_ == "origin" ? object_ : object_ + "." + frame_;
    core::Skillset& skills = ctx.skills();
    const core::Pose now = skills.frame_pose(frame);
    std::vector<Eigen::Vector3d> points;
    if (!on_.empty()) {
      failure_ = placements(ctx, *held, now, points);
    } else {
      const core::PerceivedObject* goal = target_object(ctx, now.position);
      if (!goal) {
        failure_ = target_.empty()
                       ? core::Failure(core::FailureCode::kPerceptionMiss,
                                       "no object of type '" + target_type_ + "' is known")
                       : core::Failure(core::FailureCode::kPerceptionMiss,
                                       "'" + target_ + "' is not in the perceptual model");
        return;
      }
      goal_ = goal->id;
      Eigen::Vector3d p = goal->box.center();
      p.z() = goal->box.max().z() + height_;
      points.push_back(p);
    }
    if (failure_) return;

    // The held object upright, as it stood before it was grasped (a grasp that tilted it a
    // little does not carry the tilt to where it goes), at several turns about the vertical,
    // which the task leaves free for any arm.
    const Eigen::Quaterniond upright = (uprighting(*held) * now.orientation).normalized();
    std::vector<ArmTarget> targets;
    for (const Eigen::Vector3d& p : points) {
      for (double yaw : {0.0, -0.8, 0.8, -1.6, 1.6, M_PI}) {
        ArmTarget t;
        t.pose.position = p;
        t.pose.orientation =
            (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * upright).normalized();
        t.free_axis = Eigen::Vector3d::UnitZ();
        t.free_turn_rad = M_PI;
        t.tag = "yaw " + std::to_string(yaw).substr(0, 4);
        targets.push_back(t);
      }
    }
    core::IkOptions ik;
    ik.restarts = 6;
    ik.position_tolerance_m = 0.002;
    ik.orientation_tolerance_rad = 0.035;
    // A held tool loads the arm: settle to 0.01 rad (under a centimetre at the tip).
    arm_motion_.stage().execution.position_tolerance = 0.01;
    // Setting an object down may touch the surface it goes onto.
    if (!on_.empty()) arm_motion_.stage().execution.may_touch = {on_};
    failure_ = arm_motion_.start(ctx, arm_of(side_), frame, targets, ik, torso_, base_);
  }

  core::ProgramState step(core::ProgramContext& ctx) override {
    if (failure_) return fail(*failure_);
    const std::optional<Ended> result = arm_motion_.step(ctx);
    if (!result) return core::ProgramState::kRunning;
    if (*result) return fail(**result);
    return core::ProgramState::kCompleted;
  }

 private:
  const core::PerceivedObject* target_object(core::ProgramContext& ctx,
                                             const Eigen::Vector3d& from) const {
    if (!target_.empty()) return ctx.percepts().find(target_);
    const core::PerceivedObject* best = nullptr;
    double best_d = std::numeric_limits<double>::infinity();
    for (const core::PerceivedObject* o : ctx.percepts().of_type(target_type_)) {
      const Eigen::Vector3d c = o->box.center();
      const double d = std::hypot(c.x() - from.x(), c.y() - from.y());
      if (d < best_d) best_d = d, best = o;
    }
    return best;
  }

  // The rotation that stands `held` up again: its axis nearest the vertical onto the vertical.
  static Eigen::Quaterniond uprighting(const core::PerceivedObject& held) {
    const Eigen::Matrix3d r = held.pose.orientation.toRotationMatrix();
    Eigen::Vector3d axis = r.col(0);
    for (int i = 1; i < 3; ++i) {
      if (std::abs(r(2, i)) > std::abs(axis.z())) axis = r.col(i);
    }
    if (axis.z() < 0) axis = -axis;
    return Eigen::Quaterniond::FromTwoVectors(axis, Eigen::Vector3d::UnitZ());
  }

  // Placements on `on_`: the object's frame where its box would rest on a drawn placement,
  // nearest the object's current position first.
  std::optional<core::Failure> placements(core::ProgramContext& ctx,
                                          const core::PerceivedObject& held, const core::Pose& now,
                                          std::vector<Eigen::Vector3d>& points) const {
    if (!ctx.percepts().knows(on_)) {
      return core::Failure(core::FailureCode::kPerceptionMiss,
                           "surface '" + on_ + "' is not in the perceptual model");
    }
    const core::ConditionPtr resting =
        core::all_of({core::above(object_, on_), core::near(object_, on_)});
    std::mt19937_64 rng(ctx.next_seed());
    std::vector<Eigen::AlignedBox3d> boxes =
        core::sample_placements(*resting, ctx.world(), object_, rng, 40);
    if (boxes.empty()) {
      return core::Failure(core::FailureCode::kInvalidGoal,
                           "no placement satisfies " + resting->describe());
    }
    const Eigen::Vector3d offset = now.position - held.box.center();
    std::sort(boxes.begin(), boxes.end(), [&](const auto& a, const auto& b) {
      return (a.center() - held.box.center()).squaredNorm() <
             (b.center() - held.box.center()).squaredNorm();
    });
    // Those clear of what else stands there (another object's box within kPlacementGapM across:
    // the cup put down a moment ago) first, each group nearest the object first.
    const Eigen::Vector3d gap(kPlacementGapM, kPlacementGapM, 0);
    std::stable_partition(boxes.begin(), boxes.end(), [&](const Eigen::AlignedBox3d& box) {
      const Eigen::AlignedBox3d grown(box.min() - gap, box.max() + gap);
      for (const auto& [id, o] : ctx.percepts().objects()) {
        if (id == object_ || o.type == "surface" || o.type == "humanoid") continue;
        if (grown.intersects(o.box)) return false;
      }
      return true;
    });
    boxes.resize(std::min<size_t>(boxes.size(), 6));
    for (const Eigen::AlignedBox3d& box : boxes) {
      points.push_back(box.center() + offset + Eigen::Vector3d(0, 0, height_));
    }
    return std::nullopt;
  }

  std::string object_, frame_, target_, target_type_, on_;
  double height_;
  bool use_torso_ = true, torso_ = false, use_base_ = true, base_ = false;
  std::string side_, goal_;
  ArmMotion arm_motion_;
  std::optional<core::Failure> failure_;
};

}  // namespace

core::ProgramType position_program() {
  using core::ParamType;
  return {"position",
          "moves a held object (or its tip or grip frame) over a target object or onto a "
          "placement on a surface",
          {{"object",
            ParamType::kString,
            true,
            {},
            {},
            "the held object (the end effector)",
            core::NameKind::kObject},
           {"frame",
            ParamType::kString,
            false,
            std::string("tip"),
            {"tip", "grip", "origin"},
            "which frame of the held object is placed: a frame of its model, or the object"},
           {"target",
            ParamType::kString,
            false,
            std::string(),
            {},
            "object to position over",
            core::NameKind::kObject},
           {"target_type",
            ParamType::kString,
            false,
            std::string(),
            {},
            "position over the nearest known object of this type (e.g. debris)"},
           {"on",
            ParamType::kString,
            false,
            std::string(),
            {},
            "a surface: place the held object resting on it (above and near)",
            core::NameKind::kObject},
           {"height",
            ParamType::kNumber,
            false,
            0.02,
            {},
            "m above the target's top (target) or above the resting pose (on)"},
           {"torso",
            ParamType::kBool,
            false,
            true,
            {},
            "bend the torso too when the arm alone cannot reach (if the torso is free)"},
           {"base",
            ParamType::kBool,
            false,
            true,
            {},
            "step the base too when arm and torso cannot reach (if the base is free)"}},
          [](const core::Params& p) { return std::make_unique<Position>(p); }};
}

}  // namespace taskmatrix::programs
