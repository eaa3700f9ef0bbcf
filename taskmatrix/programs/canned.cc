// canned: plays a predetermined joint-space motion of the profile, such as wave or bow
// (paper: "canned"). The chains first move, collision-free, to the first keyframe; the
// keyframes are then followed at their own times (linear interpolation), checking for
// collisions as they go. A single-limb motion mirrors to the other limb as postural does.
#include <algorithm>

#include "taskmatrix/programs/primitives.h"
#include "taskmatrix/programs/program_support.h"

namespace taskmatrix::programs {

namespace {

const core::CannedMotion& canned_motion(const core::Skillset& skills, const std::string& name) {
  const auto& all = skills.profile().canned;
  const auto it = all.find(name);
  if (it == all.end()) {
    std::string names;
    for (const auto& [n, m] : all) names += (names.empty() ? "" : ", ") + n;
    throw std::invalid_argument("robot '" + skills.profile().name + "' has no canned motion '" +
                                name + "' (it has: " + names + ")");
  }
  return it->second;
}

class Canned final : public core::TaskProgram {
 public:
  explicit Canned(const core::Params& p) : motion_name_(p.text("motion")), side_(p.text("side")) {}

  std::vector<std::string> chains(const core::Skillset& skills) const override {
    return keyframe(skills, 0).chains;
  }
  std::vector<std::string> claim(const core::ClaimContext& ctx) override {
    choice_ = choose_limb(ctx, keyframe(ctx.skills, 0), side_);
    return chains(ctx.skills);
  }

  void start(core::ProgramContext& ctx) override {
    const ChainValues first = keyframe(ctx.skills(), 0);
    if (max_difference(ctx.skills().configuration(first.chains), first.values) <= kAlreadyThere) {
      play(ctx);
      return;
    }
    failure_ = stage_.plan_to_configuration(ctx, first.chains, first.values);
  }

  core::ProgramState step(core::ProgramContext& ctx) override {
    if (failure_) return fail(*failure_);
    const std::optional<Ended> result = stage_.step();
    if (!result) return core::ProgramState::kRunning;
    if (*result) return fail(**result);
    if (playing_) return core::ProgramState::kCompleted;
    play(ctx);  // at the first keyframe: start the motion itself
    return core::ProgramState::kRunning;
  }

 private:
  ChainValues keyframe(const core::Skillset& skills, size_t k) const {
    const core::CannedMotion& m = canned_motion(skills, motion_name_);
    const ChainValues named{m.chains, m.keyframes[k].values};
    return choice_.mirror ? mirrored(skills, named) : named;
  }

  void play(core::ProgramContext& ctx) {
    const core::CannedMotion& m = canned_motion(ctx.skills(), motion_name_);
    std::vector<double> times;
    std::vector<Eigen::VectorXd> rows;
    std::vector<std::string> chains;
    for (size_t k = 0; k < m.keyframes.size(); ++k) {
      const ChainValues v = keyframe(ctx.skills(), k);
      chains = v.chains;
      times.push_back(m.keyframes[k].time_s);
      rows.push_back(Eigen::Map<const Eigen::VectorXd>(v.values.data(),
                                                       static_cast<Eigen::Index>(v.values.size())));
    }
    stage_.follow(ctx, chains, core::piecewise_linear(times, rows));
    playing_ = true;
  }

  std::string motion_name_, side_;
  LimbChoice choice_;
  MotionStage stage_;
  std::optional<core::Failure> failure_;
  bool playing_ = false;
};

}  // namespace

core::ProgramType canned_program() {
  return {"canned",
          "plays a predetermined joint-space motion of the robot's profile (wave, bow, ...)",
          {{"motion", core::ParamType::kString, true, {}, {}, "canned motion name in the profile"},
           {"side",
            core::ParamType::kString,
            false,
            std::string("any"),
            {"any", "left", "right", "as_named"},
            "for a single-limb motion: the limb to use; any: the free one, or at random"}},
          [](const core::Params& p) { return std::make_unique<Canned>(p); }};
}

}  // namespace taskmatrix::programs
