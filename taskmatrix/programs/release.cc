// release: opens a hand to the profile's rest posture (paper: "release"), first letting go of
// what it holds; a finger stopped short by what it touches (the surface under the object)
// ends the opening without failing it. With side "any" it opens the hand holding `object`; else,
// given `near`, the free hand nearest that object (a hand whose grasp did not hold); else every
// hand holding something, or both hands if none does.
#include <algorithm>

#include "taskmatrix/programs/primitives.h"
#include "taskmatrix/programs/program_support.h"

namespace taskmatrix::programs {

namespace {

class Release final : public core::TaskProgram {
 public:
  explicit Release(const core::Params& p)
      : object_(p.text("object")), near_(p.text("near")), side_(p.text("side")) {}

  std::vector<std::string> chains(const core::Skillset&) const override {
    std::vector<std::string> out;
    for (const std::string& s : sides_) out.push_back(hand_of(s));
    return out;
  }
  std::vector<std::string> claim(const core::ClaimContext& ctx) override {
    sides_.clear();
    if (side_ != "any") {
      sides_ = {side_};
    } else if (!object_.empty() && !ctx.skills.holder_of(object_).empty()) {
      sides_ = {ctx.skills.holder_of(object_)};
    } else if (!near_.empty()) {
      sides_ = {nearest_free_side(ctx, near_, hand_of)};
    } else {
      for (const std::string& o : ctx.skills.attached_objects()) {
        const std::string s = ctx.skills.holder_of(o);
        if (std::find(sides_.begin(), sides_.end(), s) == sides_.end()) sides_.push_back(s);
      }
      if (sides_.empty()) sides_ = {"left", "right"};
    }
    return chains(ctx.skills);
  }
  core::ConditionPtr precondition() const override {
    return object_.empty() ? nullptr : core::grasping(object_);
  }

  void start(core::ProgramContext& ctx) override {
    core::Skillset& skills = ctx.skills();
    for (const std::string& o : skills.attached_objects()) {
      if (std::find(sides_.begin(), sides_.end(), skills.holder_of(o)) != sides_.end()) {
        skills.detach(o);
      }
    }
    const std::vector<std::string> hands = chains(skills);
    const ChainValues rest = posture_values(skills, "rest", hands);
    const core::Trajectory open = skills.time_parameterize(
        rest.chains, {clamped_configuration(skills, rest.chains), rest.values});
    core::ExecutionOptions options;
    options.stop_on_collision = false;  // the fingers leave what they were touching
    motion_.follow(ctx, rest.chains, core::timed(open), options);
  }

  core::ProgramState step(core::ProgramContext& ctx) override {
    const std::optional<Ended> result = motion_.step();
    if (!result) return core::ProgramState::kRunning;
    // Touching what was let go is expected; only tracking matters.
    if (*result && (*result)->code != core::FailureCode::kCollision) {
      // A finger that stopped against something (the surface the object was set on, the
      // object) has opened as far as the world lets it: the hand has let go. Any other
      // shortfall (nothing touched) is a failure of the hand.
      const bool blocked = (*result)->code == core::FailureCode::kTrackingError &&
                           !ctx.skills().collisions(chains(ctx.skills())).empty();
      if (!blocked) return fail(**result);
    }
    return core::ProgramState::kCompleted;
  }

 private:
  std::string object_, near_, side_;
  std::vector<std::string> sides_ = {"left"};
  MotionStage motion_;
};

}  // namespace

core::ProgramType release_program() {
  return {"release",
          "lets go of what a hand holds and opens it to the rest posture",
          {{"side", core::ParamType::kString, false, std::string("any"), kSides,
            "hand to open; any: the hand holding `object`, or every hand holding something"},
           {"object",
            core::ParamType::kString,
            false,
            std::string(),
            {},
            "if given, the hand must be holding it (precondition grasping(object))",
            core::NameKind::kObject},
           {"near",
            core::ParamType::kString,
            false,
            std::string(),
            {},
            "with side any and no `object`: open the free hand nearest this object",
            core::NameKind::kObject}},
          [](const core::Params& p) { return std::make_unique<Release>(p); }};
}

}  // namespace taskmatrix::programs
