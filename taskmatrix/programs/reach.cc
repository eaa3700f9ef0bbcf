// reach: moves an arm so that its hand can grasp an object (paper: "reach"). The target hand
// configurations are palm poses around the object's grasp point: the hand comes in along its
// approach axis, horizontally from several directions around the robot-object line (closing
// axis horizontal, then vertical) and from above, at two stand-off distances. Each is tried
// in turn (IK, then planning) and the first plan found is executed. When the arm alone
// cannot reach any of them (IK fails) and the torso is free, the torso and arm are planned
// together (a tall robot bends over a table); failing that, base, torso and arm (the robot
// steps over). Exits at once when the object is already
// graspable by that hand.
#include <cmath>

#include "taskmatrix/programs/primitives.h"
#include "taskmatrix/programs/program_support.h"

namespace taskmatrix::programs {

namespace {

Eigen::Vector3d vec(const std::array<double, 3>& a) { return {a[0], a[1], a[2]}; }

// The palm orientation that points `approach` (palm frame) along `direction` (world) and
// `closing` (palm frame) along `closing_world` (world, perpendicular to `direction`).
Eigen::Quaterniond palm_orientation(const Eigen::Vector3d& approach, const Eigen::Vector3d& closing,
                                    const Eigen::Vector3d& direction,
                                    const Eigen::Vector3d& closing_world) {
  Eigen::Matrix3d palm, world;
  palm << approach, closing, approach.cross(closing);
  world << direction, closing_world, direction.cross(closing_world);
  return Eigen::Quaterniond(world * palm.transpose()).normalized();
}

class Reach final : public core::TaskProgram {
 public:
  explicit Reach(const core::Params& p)
      : object_(p.text("object")),
        side_(p.text("side")),
        use_torso_(p.flag("torso")),
        use_base_(p.flag("base")) {}

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
      failure_ = "perception_miss: '" + object_ + "' is not in the perceptual model";
      return;
    }
    if (core::graspable(object_, side_)->holds(ctx.world())) {
      done_ = true;
      return;
    }
    core::Skillset& skills = ctx.skills();
    const core::HandSpec* hand = skills.profile().find_hand(side_);
    const std::vector<core::Pose> poses = candidate_poses(skills, *hand, *o);
    core::IkOptions ik;
    ik.restarts = 8;
    // An arm with fewer than six joints cannot reach every hand pose: leave the hand's turn
    // about its palm normal free (the approach direction may swing in the palm's plane).
    if (skills.chain(arm_of(side_)).joints.size() < 6) {
      ik.free_axis = vec(hand->approach).cross(vec(hand->closing));
    }
    // Settle close to the planned hand pose: the graspable test allows 3 cm and the second
    // stand-off uses 2.8 cm of it.
    arm_motion_.stage().execution.position_tolerance = 0.003;
    // The fingers may brush the object on the last centimetres; anything else stops the arm.
    arm_motion_.stage().execution.may_touch = {object_};
    failure_ = arm_motion_.start(ctx, arm_of(side_), hand->palm, poses, ik, torso_, base_);
  }

  core::ProgramState step(core::ProgramContext& ctx) override {
    if (!failure_.empty()) return fail(failure_);
    if (done_) return core::ProgramState::kCompleted;
    const std::optional<std::string> result = arm_motion_.step(ctx);
    if (!result) return core::ProgramState::kRunning;
    if (!result->empty()) return fail(*result);
    if (!core::graspable(object_, side_)->holds(ctx.world())) {
      return fail("not_graspable: the " + side_ + " palm reached its target but '" + object_ +
                  "' is not graspable from there (did it move?)");
    }
    return core::ProgramState::kCompleted;
  }

 private:
  std::vector<core::Pose> candidate_poses(core::Skillset& skills, const core::HandSpec& hand,
                                          const core::PerceivedObject& o) const {
    const Eigen::Vector3d target = o.grasp_point();
    const Eigen::Vector3d approach = vec(hand.approach), closing = vec(hand.closing);
    // Horizontal direction from the arm's shoulder side of the robot towards the object.
    const Eigen::Vector3d palm_now = skills.frame_pose(hand.palm).position;
    Eigen::Vector3d toward = target - palm_now;
    toward.z() = 0;
    if (toward.norm() < 1e-6) toward = Eigen::Vector3d::UnitX();
    toward.normalize();
    const double base_yaw = std::atan2(toward.y(), toward.x());
    const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
    std::vector<core::Pose> poses;
    auto add = [&](const Eigen::Vector3d& direction, const Eigen::Vector3d& closing_world,
                   double standoff) {
      core::Pose p;
      p.position = target - standoff * direction;
      p.orientation = palm_orientation(approach, closing, direction, closing_world);
      poses.push_back(p);
    };
    const double yaws[] = {0.0, -0.5, 0.5, -1.0, 1.0};
    for (double standoff : {0.015, 0.028}) {
      // From the side, fingers closing horizontally (both ways round).
      for (double dyaw : yaws) {
        const Eigen::Vector3d d(std::cos(base_yaw + dyaw), std::sin(base_yaw + dyaw), 0);
        const Eigen::Vector3d across = up.cross(d);
        add(d, across, standoff);
        add(d, -across, standoff);
      }
      // From above, closing across and along the robot-object line.
      add(-up, up.cross(toward), standoff);
      add(-up, toward, standoff);
      // From the side, fingers closing vertically.
      for (double dyaw : {0.0, -0.5, 0.5}) {
        const Eigen::Vector3d d(std::cos(base_yaw + dyaw), std::sin(base_yaw + dyaw), 0);
        add(d, up, standoff);
        add(d, -up, standoff);
      }
    }
    return poses;
  }

  std::string object_, side_;
  bool use_torso_ = true, torso_ = false, use_base_ = true, base_ = false;
  ArmMotion arm_motion_;
  std::string failure_;
  bool done_ = false;
};

}  // namespace

core::ProgramType reach_program() {
  return {"reach",
          "collision-free arm motion to a hand pose from which `object` can be grasped",
          {{"object", core::ParamType::kString, true, {}, {}, "object id in the perceptual model"},
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
            "step the base too when arm and torso cannot reach (if the base is free)"}},
          [](const core::Params& p) { return std::make_unique<Reach>(p); }};
}

}  // namespace taskmatrix::programs
