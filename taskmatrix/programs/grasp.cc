// grasp: closes the hand on an object (paper: "grasp"). Each segment of each finger closes on
// its own, at half the hand's speed limit, until it touches something other than the hand
// itself or reaches the profile's fist posture. A segment that touches stops, and so do the
// segments between it and the palm: once a fingertip holds the object, closing the finger's
// inner joints would only drag and tilt it. The object is then held (attached to the hand) if
// a majority of the hand's fingers touch it or stopped on it (HandGeometry::fingers_needed), or,
// for a tool, if the closed fingers ring its handle: one of them on the handle, the others
// closed on the hand's own fingers, and the grip point inside the ring they make seen along
// the handle (a small hand's fingertips meet round a thick handle before both reach it). A
// grasp that does not hold is noted against the candidate reach moved to, so the next reach
// tries another.
#include <algorithm>
#include <cmath>
#include <optional>

#include "taskmatrix/programs/grasp_candidates.h"
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
    geometry_ = measure_hand(skills, *hand_);
    needed_ = geometry_.fingers_needed;
    fist_ = skills.posture("fist").at(chain);
    target_ = clamped_configuration(skills, {chain});
    segments_.clear();
    for (size_t f = 0; f < hand_->fingers.size(); ++f) {
      const core::FingerSpec& finger = hand_->fingers[f];
      for (size_t k = 0; k < finger.joints.size(); ++k) {
        const auto it = std::find(info.joints.begin(), info.joints.end(), finger.joints[k]);
        segments_.push_back(
            {static_cast<size_t>(it - info.joints.begin()), f, k, finger.bodies[k]});
        own_bodies_.push_back(finger.bodies[k]);
      }
    }
    stopped_.assign(info.joints.size(), true);  // joints that are no finger segment stay put
    for (const Segment& seg : segments_) stopped_[seg.joint] = false;
    stopped_on_object_.assign(hand_->fingers.size(), false);
    blocked_by_.clear();
    speed_ = 0.5 * info.speed.velocity;
    t0_ = ctx.time();
  }

  core::ProgramState step(core::ProgramContext& ctx) override {
    core::Skillset& skills = ctx.skills();
    const std::string chain = hand_of(side_);
    // A segment touching something stops, with every segment nearer the palm on its finger.
    for (const Segment& seg : segments_) {
      if (stopped_[seg.joint]) continue;
      const std::vector<std::string> touched = skills.touching(seg.body);
      if (!touches_world(touched)) continue;
      if (std::find(touched.begin(), touched.end(), object_) != touched.end()) {
        stopped_on_object_[seg.finger] = true;
      } else {
        for (const std::string& other : touched) {
          if (std::find(own_bodies_.begin(), own_bodies_.end(), other) == own_bodies_.end() &&
              std::find(blocked_by_.begin(), blocked_by_.end(), other) == blocked_by_.end()) {
            blocked_by_.push_back(other);
          }
        }
      }
      for (const Segment& inner : segments_) {
        if (inner.finger == seg.finger && inner.index <= seg.index) stopped_[inner.joint] = true;
      }
    }
    const double dstep = speed_ * skills.control_period();
    bool moving = false;
    for (const Segment& seg : segments_) {
      const size_t i = seg.joint;
      if (stopped_[i]) continue;
      target_[i] += std::clamp(fist_[i] - target_[i], -dstep, dstep);
      if (std::abs(fist_[i] - target_[i]) < 1e-9) {
        stopped_[i] = true;
        continue;
      }
      moving = true;
    }
    skills.command({chain}, target_);
    if (moving && ctx.time() - t0_ < kTimeLimitS) return core::ProgramState::kRunning;
    return finish(ctx);
  }

 private:
  struct Segment {
    size_t joint;   // in the hand chain
    size_t finger;  // in the profile's hand
    size_t index;   // from the palm outwards
    std::string body;
  };

  // Whether what a segment touches (Skillset::touching) includes anything but the hand's own
  // fingers.
  bool touches_world(const std::vector<std::string>& touched) const {
    for (const std::string& other : touched) {
      if (std::find(own_bodies_.begin(), own_bodies_.end(), other) == own_bodies_.end()) {
        return true;
      }
    }
    return false;
  }

  // Whether the object is a tool whose handle the hand's fingers ring (rings(): seen along the
  // handle, the grip point inside the fingers' segments and tips).
  bool rings_handle(core::ProgramContext& ctx) const {
    const core::PerceivedObject* o = ctx.percepts().find(object_);
    const std::optional<Handle> handle = o ? tool_handle(*o) : std::nullopt;
    if (!handle) return false;
    core::Skillset& skills = ctx.skills();
    std::vector<Eigen::Vector3d> points;
    for (size_t k = 0; k < hand_->fingers.size() && k < geometry_.tips_in_last.size(); ++k) {
      core::Pose last;
      for (const std::string& body : hand_->fingers[k].bodies) {
        last = skills.frame_pose(body);
        points.push_back(last.position);
      }
      points.push_back(last.position + last.orientation * geometry_.tips_in_last[k]);
    }
    return rings(*handle, points);
  }

  core::ProgramState finish(core::ProgramContext& ctx) {
    core::Skillset& skills = ctx.skills();
    int touching = 0;
    bool others_on_fingers = true;  // every finger off the object closed on another finger
    for (size_t k = 0; k < hand_->fingers.size(); ++k) {
      const core::FingerSpec& f = hand_->fingers[k];
      // A finger that stopped on the object holds it, though under physics its contact may
      // flicker off at the instant the last finger stops.
      bool touches = stopped_on_object_[k], on_finger = false;
      for (const std::string& body : f.bodies) {
        const std::vector<std::string> contacts = skills.touching(body);
        touches |= std::find(contacts.begin(), contacts.end(), object_) != contacts.end();
        for (const std::string& other : contacts) {
          on_finger |=
              std::find(f.bodies.begin(), f.bodies.end(), other) == f.bodies.end() &&
              std::find(own_bodies_.begin(), own_bodies_.end(), other) != own_bodies_.end();
        }
      }
      touching += touches;
      others_on_fingers = others_on_fingers && (touches || on_finger);
    }
    if (touching < needed_ && touching >= 1 && others_on_fingers && rings_handle(ctx)) {
      touching = needed_;
    }
    if (touching < needed_) {
      // The grasp reach moved to did not hold: the next reach leaves it out.
      const std::vector<std::string>& reached = ctx.notes(reached_grasp_note(object_, side_));
      std::vector<std::string>& failed = ctx.notes(failed_grasps_note(object_, side_));
      failed.push_back(reached.empty() ? "unknown" : reached.front());
      std::vector<std::string>& blocked = ctx.notes(blocked_fingers_note(object_, side_));
      std::string stopped_by;
      for (const std::string& other : blocked_by_) {
        stopped_by += (stopped_by.empty() ? "; fingers stopped by '" : ", '") + other + "'";
        if (std::find(blocked.begin(), blocked.end(), other) == blocked.end()) {
          blocked.push_back(other);
        }
      }
      return fail(core::Failure(core::FailureCode::kGraspFailed,
                                std::to_string(touching) + " of " +
                                    std::to_string(hand_->fingers.size()) + " fingers of the " +
                                    side_ + " hand touch '" + object_ + "' (need " +
                                    std::to_string(needed_) + ")" + stopped_by));
    }
    skills.attach(object_, side_);
    return core::ProgramState::kCompleted;
  }

  std::string object_, side_;
  const core::HandSpec* hand_ = nullptr;
  HandGeometry geometry_;
  int needed_ = 1;
  std::vector<double> fist_, target_;
  std::vector<Segment> segments_;
  std::vector<std::string> own_bodies_;  // the hand's finger segments
  std::vector<bool> stopped_;            // per hand joint
  std::vector<bool> stopped_on_object_;  // per finger: a segment stopped touching the object
  std::vector<std::string> blocked_by_;  // what else stopped a segment
  double speed_ = 1.0;
  double t0_ = 0;
};

}  // namespace

core::ProgramType grasp_program() {
  return {"grasp",
          "closes each finger segment until contact and holds `object` if most fingers touch it",
          {{"object",
            core::ParamType::kString,
            true,
            {},
            {},
            "object id in the perceptual model",
            core::NameKind::kObject},
           {"side", core::ParamType::kString, false, std::string("any"), kSides,
            "hand to use; any: the free hand nearest the object"}},
          [](const core::Params& p) { return std::make_unique<Grasp>(p); }};
}

}  // namespace taskmatrix::programs
