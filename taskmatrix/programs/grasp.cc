// grasp: closes the hand on an object (paper: "grasp"). Each segment of each finger closes
// on its own, at half the hand's speed limit, until its body touches something or it reaches
// the profile's fist posture. The object is then held (attached to the hand) if at least two
// fingers touch it (every finger, for a hand with fewer).
#include <algorithm>
#include <cmath>

#include "taskmatrix/programs/primitives.h"
#include "taskmatrix/programs/program_support.h"

namespace taskmatrix::programs {

namespace {

constexpr double kTimeLimitS = 4.0;

class Grasp final : public core::TaskProgram {
 public:
  explicit Grasp(const core::Params& p) : object_(p.text("object")), side_(p.text("side")) {}

  std::vector<std::string> chains(const core::Skillset&) const override {
    return {hand_of(side_ == "any" ? "left" : side_)};
  }
  std::vector<std::string> claim(const core::ClaimContext& ctx) override {
    if (side_ == "any") side_ = nearest_free_side(ctx, object_, hand_of);
    return {hand_of(side_)};
  }
  core::ConditionPtr precondition() const override { return core::graspable(object_, side_); }

  void start(core::ProgramContext& ctx) override {
    core::Skillset& skills = ctx.skills();
    const std::string chain = hand_of(side_);
    const core::ChainInfo& info = skills.chain(chain);
    hand_ = skills.profile().find_hand(side_);
    fist_ = skills.posture("fist").at(chain);
    target_ = clamped_configuration(skills, {chain});
    segment_body_.assign(info.joints.size(), "");
    for (const core::FingerSpec& f : hand_->fingers) {
      for (size_t k = 0; k < f.joints.size(); ++k) {
        const auto it = std::find(info.joints.begin(), info.joints.end(), f.joints[k]);
        segment_body_[it - info.joints.begin()] = f.bodies[k];
      }
    }
    stopped_.assign(info.joints.size(), false);
    for (size_t i = 0; i < stopped_.size(); ++i) stopped_[i] = segment_body_[i].empty();
    speed_ = 0.5 * info.speed.velocity;
    t0_ = ctx.time();
  }

  core::ProgramState step(core::ProgramContext& ctx) override {
    core::Skillset& skills = ctx.skills();
    const std::string chain = hand_of(side_);
    const double dstep = speed_ * skills.control_period();
    bool moving = false;
    for (size_t i = 0; i < target_.size(); ++i) {
      if (stopped_[i]) continue;
      if (!skills.touching(segment_body_[i]).empty()) {
        stopped_[i] = true;  // hold the segment where it made contact
        continue;
      }
      const double gap = fist_[i] - target_[i];
      target_[i] += std::clamp(gap, -dstep, dstep);
      if (std::abs(fist_[i] - target_[i]) < 1e-9) {
        stopped_[i] = true;
        continue;
      }
      moving = true;
    }
    skills.command({chain}, target_);
    if (moving && ctx.time() - t0_ < kTimeLimitS) return core::ProgramState::kRunning;
    return finish(skills);
  }

 private:
  core::ProgramState finish(core::Skillset& skills) {
    int touching = 0;
    for (const core::FingerSpec& f : hand_->fingers) {
      bool touches = false;
      for (const std::string& body : f.bodies) {
        const std::vector<std::string> contacts = skills.touching(body);
        touches |= std::find(contacts.begin(), contacts.end(), object_) != contacts.end();
      }
      touching += touches;
    }
    const int needed = std::min<int>(2, static_cast<int>(hand_->fingers.size()));
    if (touching < needed) {
      return fail("grasp_failed: " + std::to_string(touching) + " of " +
                  std::to_string(hand_->fingers.size()) + " fingers of the " + side_ +
                  " hand touch '" + object_ + "' (need " + std::to_string(needed) + ")");
    }
    skills.attach(object_, side_);
    return core::ProgramState::kCompleted;
  }

  std::string object_, side_;
  const core::HandSpec* hand_ = nullptr;
  std::vector<double> fist_, target_;
  std::vector<std::string> segment_body_;  // per hand joint; "" if not a finger segment
  std::vector<bool> stopped_;
  double speed_ = 1.0;
  double t0_ = 0;
};

}  // namespace

core::ProgramType grasp_program() {
  return {"grasp",
          "closes each finger segment until contact and holds `object` if two fingers touch it",
          {{"object", core::ParamType::kString, true, {}, {}, "object id in the perceptual model"},
           {"side", core::ParamType::kString, false, std::string("any"), kSides,
            "hand to use; any: the free hand nearest the object"}},
          [](const core::Params& p) { return std::make_unique<Grasp>(p); }};
}

}  // namespace taskmatrix::programs
