// postural: collision-free motion of one or more chains to a named posture of the profile
// (paper: "postural"). A posture of a single limb (e.g. wave_start of the right arm) can be
// taken by either limb: with side "any" the program mirrors it to the other limb when the
// named one is busy or the other is already there, or when only the other's touches nothing,
// and otherwise picks one at random (from the run's seed sequence, so a run is reproducible). With
// `skip_busy`, chains of the posture that other programs hold, and the arm and hand of a hand
// holding an object, are left out (greet lowers the waving arm and leaves the arm carrying a
// cup as it is, its hand closed). Chains already at the posture are left out of the plan.
#include "taskmatrix/core/robot_profile.h"
#include "taskmatrix/programs/primitives.h"
#include "taskmatrix/programs/program_support.h"

namespace taskmatrix::programs {

namespace {

class Postural final : public core::TaskProgram {
 public:
  explicit Postural(const core::Params& p)
      : posture_(p.text("posture")),
        only_(p.list("chains")),
        side_(p.text("side")),
        skip_busy_(p.flag("skip_busy")) {}

  std::vector<std::string> chains(const core::Skillset& skills) const override {
    return target(skills).chains;
  }
  std::vector<std::string> claim(const core::ClaimContext& ctx) override {
    if (skip_busy_) {
      std::vector<std::string> free;
      for (const std::string& c : posture_values(ctx.skills, posture_, only_).chains) {
        if (!chain_taken(ctx, c)) free.push_back(c);
      }
      if (free.empty()) {
        throw std::invalid_argument("every chain of posture '" + posture_ + "' is busy");
      }
      only_ = free;
    }
    const ChainValues named = posture_values(ctx.skills, posture_, only_);
    choice_ = choose_limb(ctx, named, side_);
    return target(ctx.skills).chains;
  }

  void start(core::ProgramContext& ctx) override {
    const ChainValues goal = target(ctx.skills());
    // Nothing to move (the chains named are ones this robot lacks) or already there.
    if (goal.chains.empty() ||
        max_difference(ctx.skills().configuration(goal.chains), goal.values) <= kAlreadyThere) {
      done_ = true;
      return;
    }
    // Chains already at their posture stay where they are: they are left out of the plan
    // (every joint planned is a dimension the planner searches). An arm touching something
    // stays in it: the plan frees it from the contact (MotionStage) as the torso moves it.
    ChainValues moving;
    size_t at = 0;
    for (const std::string& c : goal.chains) {
      const std::vector<double> now = ctx.skills().configuration({c});
      if (at + now.size() > goal.values.size()) {
        failure_ =
            core::Failure(core::FailureCode::kInvalidInput,
                          "posture '" + posture_ + "' has too few values for chain '" + c + "'");
        return;
      }
      const std::vector<double> want(goal.values.begin() + at,
                                     goal.values.begin() + at + now.size());
      at += now.size();
      const bool touching =
          core::chain_kind(c) == "arm" && !touched_by_arm(ctx, single_side({c})).empty();
      if (max_difference(now, want) <= kAlreadyThere && !touching) continue;
      moving.chains.push_back(c);
      moving.values.insert(moving.values.end(), want.begin(), want.end());
    }
    failure_ = motion_.plan_to_configuration(ctx, moving.chains, moving.values);
  }

  core::ProgramState step(core::ProgramContext&) override {
    if (failure_) return fail(*failure_);
    if (done_) return core::ProgramState::kCompleted;
    const std::optional<Ended> result = motion_.step();
    if (!result) return core::ProgramState::kRunning;
    if (*result) return fail(**result);
    return core::ProgramState::kCompleted;
  }

 private:
  ChainValues target(const core::Skillset& skills) const {
    const ChainValues named = posture_values(skills, posture_, only_);
    return choice_.mirror ? mirrored(skills, named) : named;
  }

  std::string posture_;
  std::vector<std::string> only_;
  std::string side_;
  bool skip_busy_;
  LimbChoice choice_;
  MotionStage motion_;
  std::optional<core::Failure> failure_;
  bool done_ = false;
};

}  // namespace

core::ProgramType postural_program() {
  return {"postural",
          "collision-free motion of chains to a named posture of the robot's profile",
          {{"posture", core::ParamType::kString, true, {}, {}, "posture name in the profile"},
           {"chains",
            core::ParamType::kStringList,
            false,
            std::vector<std::string>{},
            {},
            "only these chains of the posture (default: every chain it names)"},
           {"side",
            core::ParamType::kString,
            false,
            std::string("any"),
            {"any", "left", "right", "as_named"},
            "for a single-limb posture: the limb to use; any: the free one, or at random"},
           {"skip_busy",
            core::ParamType::kBool,
            false,
            false,
            {},
            "leave out the chains other programs hold and the arm and hand holding an object"}},
          [](const core::Params& p) { return std::make_unique<Postural>(p); }};
}

}  // namespace taskmatrix::programs
