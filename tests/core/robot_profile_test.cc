#include "taskmatrix/core/robot_profile.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "taskmatrix/core/input_error.h"

namespace taskmatrix::core {
namespace {

RobotProfile valid_profile() {
  RobotProfile p;
  p.name = "toy";
  p.profile_file = "models/robots/toy/profile.yaml";
  p.height_m = 1.0;
  p.chains = {{"base", {"x", "y", "yaw"}, ""},
              {"torso", {"t"}, ""},
              {"head", {"h"}, ""},
              {"left_arm", {"la1", "la2"}, "lp"},
              {"right_arm", {"ra1", "ra2"}, "rp"},
              {"left_hand", {"lf1", "lf2"}, ""},
              {"right_hand", {"rf1", "rf2"}, ""}};
  p.hands = {{"left", "lp", {0, 0, 1}, {1, 0, 0}, {{{"lf1", "lf2"}, {"lf1b", "lf2b"}}}},
             {"right", "rp", {0, 0, 1}, {1, 0, 0}, {{{"rf1", "rf2"}, {"rf1b", "rf2b"}}}}};
  p.mirror_signs = {{"arm", {1, -1}}, {"hand", {1, 1}}};
  p.canned["wave"] = {{"left_arm"}, {{0.0, {0, 0}}, {1.0, {0.5, -0.5}}}};
  p.postures = {{"rest",
                 {{"torso", {0}},
                  {"head", {0}},
                  {"left_arm", {0, 0}},
                  {"right_arm", {0, 0}},
                  {"left_hand", {0, 0}},
                  {"right_hand", {0, 0}}}},
                {"fist", {{"left_hand", {1, 1}}, {"right_hand", {1, 1}}}},
                {"wave_start", {{"left_arm", {0, 0}}, {"left_hand", {0, 0}}}}};
  for (const ChainSpec& c : p.chains) p.speed_limits[c.name] = {1.0, 2.0};
  return p;
}

std::string error_of(const RobotProfile& p) {
  try {
    validate_profile_structure(p);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(RobotProfile, AValidProfilePasses) { EXPECT_EQ(error_of(valid_profile()), ""); }

TEST(RobotProfile, HandsNeedAUnitApproachAxis) {
  RobotProfile p = valid_profile();
  p.hands[1].approach = {0, 0, 2};
  EXPECT_NE(error_of(p).find("hands.right.approach: must be a unit vector"), std::string::npos)
      << error_of(p);
  p = valid_profile();
  p.hands[0].closing = {0, 0, 1};
  EXPECT_NE(error_of(p).find("hands.left.closing: must be a unit vector perpendicular"),
            std::string::npos)
      << error_of(p);
}

TEST(RobotProfile, MirrorSignsMustFitTheLimbChains) {
  RobotProfile p = valid_profile();
  p.mirror_signs.erase("hand");
  EXPECT_NE(error_of(p).find("mirror_signs: has no entry 'hand' for chain 'left_hand'"),
            std::string::npos)
      << error_of(p);
  p = valid_profile();
  p.mirror_signs["arm"] = {1};
  EXPECT_NE(error_of(p).find("mirror_signs.arm: has 1 signs but chain 'left_arm' has 2 joints"),
            std::string::npos)
      << error_of(p);
  p = valid_profile();
  p.mirror_signs["arm"] = {1, 0.5};
  EXPECT_NE(error_of(p).find("mirror_signs.arm: signs must be 1 or -1"), std::string::npos);
}

TEST(RobotProfile, CannedMotionsAreCheckedAgainstTheSpeedLimits) {
  RobotProfile p = valid_profile();
  p.canned["wave"].keyframes[1].time_s = 0.25;  // 0.5 rad in 0.25 s: 2 rad/s > 1 rad/s
  EXPECT_NE(error_of(p).find("canned.wave.keyframes[1]: joint 0 moves at 2.0"), std::string::npos)
      << error_of(p);
  p = valid_profile();
  p.canned["wave"].keyframes[1].values.pop_back();
  EXPECT_NE(error_of(p).find("canned.wave.keyframes[1]: has 1 joint values but the chains have 2"),
            std::string::npos)
      << error_of(p);
  p = valid_profile();
  p.canned["wave"].keyframes[0].time_s = 0.5;
  EXPECT_NE(error_of(p).find("keyframes[0]: must start at time 0"), std::string::npos);
  p = valid_profile();
  p.canned["wave"].keyframes.pop_back();
  EXPECT_NE(error_of(p).find("canned.wave.keyframes: needs at least two keyframes"),
            std::string::npos);
  p = valid_profile();
  p.canned["wave"].chains = {"tail"};
  EXPECT_NE(error_of(p).find("canned.wave.chains: names unknown chain 'tail'"), std::string::npos);
}

TEST(RobotProfile, ChainsMustBeDisjoint) {
  RobotProfile p = valid_profile();
  p.chains[1].joints.push_back("la1");
  const std::string e = error_of(p);
  EXPECT_NE(e.find("models/robots/toy/profile.yaml"), std::string::npos) << e;
  EXPECT_NE(e.find("chains.left_arm.joints"), std::string::npos) << e;
  EXPECT_NE(e.find("already in chain 'torso'"), std::string::npos) << e;
}

TEST(RobotProfile, RequiredChainsAndPosturesMustExist) {
  RobotProfile p = valid_profile();
  p.chains.erase(p.chains.begin() + 3);
  EXPECT_NE(error_of(p).find("missing required chain 'left_arm'"), std::string::npos);
  p = valid_profile();
  p.postures.erase("fist");
  EXPECT_NE(error_of(p).find("missing required posture 'fist'"), std::string::npos);
  p = valid_profile();
  p.postures.erase("wave_start");
  EXPECT_NE(error_of(p).find("postures: missing required posture 'wave_start'"), std::string::npos)
      << error_of(p);
  p = valid_profile();
  p.canned.erase("wave");
  EXPECT_NE(error_of(p).find("canned: missing required canned motion 'wave'"), std::string::npos)
      << error_of(p);
}

// A robot with a rigid torso or a camera fixed to its trunk leaves those chains out (and
// their rest values, which would name a chain it does not have).
TEST(RobotProfile, TorsoAndHeadChainsAreOptional) {
  RobotProfile p = valid_profile();
  for (const char* chain : {"torso", "head"}) {
    p.chains.erase(std::find_if(p.chains.begin(), p.chains.end(),
                                [&](const ChainSpec& c) { return c.name == chain; }));
    p.postures["rest"].erase(chain);
    p.speed_limits.erase(chain);
  }
  EXPECT_EQ(error_of(p), "");
}

// No program opens a hand to `hand_open`: a profile without it is complete.
TEST(RobotProfile, HandOpenIsNotRequired) {
  RobotProfile p = valid_profile();
  ASSERT_FALSE(p.postures.count("hand_open"));
  EXPECT_EQ(error_of(p), "");
}

TEST(RobotProfile, PosturesTheProgramsUseNameWhatTheyNeed) {
  RobotProfile p = valid_profile();
  p.postures["rest"].erase("right_hand");
  EXPECT_NE(error_of(p).find("postures.rest: must name chain 'right_hand'"), std::string::npos)
      << error_of(p);
  p = valid_profile();
  p.postures["fist"].erase("left_hand");
  EXPECT_NE(error_of(p).find("postures.fist: must name chain 'left_hand'"), std::string::npos)
      << error_of(p);
  p = valid_profile();
  p.postures["wave_start"]["right_arm"] = {0, 0};
  EXPECT_NE(error_of(p).find("postures.wave_start: must name one side's arm"), std::string::npos)
      << error_of(p);
  p = valid_profile();
  p.postures["wave_start"] = {{"left_hand", {0, 0}}};
  EXPECT_NE(error_of(p).find("postures.wave_start: must name one side's arm"), std::string::npos)
      << error_of(p);
}

TEST(RobotProfile, TheWaveStartsAtWaveStartOnTheSameSide) {
  RobotProfile p = valid_profile();
  p.canned["wave"].chains = {"right_arm"};
  EXPECT_NE(error_of(p).find("canned.wave.chains: must include 'left_arm'"), std::string::npos)
      << error_of(p);
  p = valid_profile();
  p.canned["wave"].keyframes[0].values = {0.1, 0.0};
  EXPECT_NE(error_of(p).find("canned.wave.keyframes[0]: must equal postures.wave_start for "
                             "chain 'left_arm'"),
            std::string::npos)
      << error_of(p);
}

TEST(RobotProfile, PosturesNeedOneFiniteValuePerJoint) {
  RobotProfile p = valid_profile();
  p.postures["rest"]["left_arm"] = {0.1};
  EXPECT_NE(error_of(p).find("has 1 values but chain 'left_arm' has 2 joints"), std::string::npos);
  p = valid_profile();
  p.postures["rest"]["left_arm"] = {0.1, std::nan("")};
  EXPECT_NE(error_of(p).find("postures.rest.left_arm: holds a non-finite value"),
            std::string::npos);
  p = valid_profile();
  p.postures["rest"]["tail"] = {0.1};
  EXPECT_NE(error_of(p).find("unknown chain 'tail'"), std::string::npos);
}

TEST(RobotProfile, FingersMustBelongToTheirHandChain) {
  RobotProfile p = valid_profile();
  p.hands[0].fingers[0].joints = {"rf1", "lf2"};
  EXPECT_NE(error_of(p).find("joint 'rf1' is not in chain 'left_hand'"), std::string::npos);
  p = valid_profile();
  p.hands[0].fingers[0].bodies = {"only_one"};
  EXPECT_NE(error_of(p).find("needs one body per joint"), std::string::npos);
}

TEST(RobotProfile, EveryChainNeedsPositiveSpeedLimits) {
  RobotProfile p = valid_profile();
  p.speed_limits.erase("head");
  EXPECT_NE(error_of(p).find("speed_limits: has no entry for chain 'head'"), std::string::npos)
      << error_of(p);
  p = valid_profile();
  p.speed_limits["left_arm"].acceleration = NAN;
  EXPECT_NE(error_of(p).find("speed_limits.left_arm: velocity and acceleration must be positive"),
            std::string::npos)
      << error_of(p);
  p = valid_profile();
  p.speed_limits["tail"] = {1, 1};
  EXPECT_NE(error_of(p).find("speed_limits.tail: names unknown chain"), std::string::npos);
}

TEST(RobotProfile, BaseHasThreeJointsAndHeightIsPositive) {
  RobotProfile p = valid_profile();
  p.chains[0].joints = {"x", "y"};
  EXPECT_NE(error_of(p).find("exactly three joints"), std::string::npos);
  p = valid_profile();
  p.height_m = -1;
  EXPECT_NE(error_of(p).find("height_m"), std::string::npos);
}

}  // namespace
}  // namespace taskmatrix::core
