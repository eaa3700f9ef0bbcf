// Bad model files reach the user as one clear line naming the file (and the element or key),
// a non-zero exit status, and never a crash or a hang. Each case corrupts one file in a
// scratch copy of models/ and runs the CLI as a user would.
#include <gtest/gtest.h>

#include <algorithm>

#include "tests/test_support.h"

namespace taskmatrix::test {
namespace {

struct BadInputCase {
  std::string name;
  std::string robot;
  std::function<void(const ScratchRoot&)> corrupt;
  std::vector<std::string> expected;  // substrings of the one error line
};

void PrintTo(const BadInputCase& c, std::ostream* os) { *os << c.name; }

class BadInput : public ::testing::TestWithParam<BadInputCase> {};

TEST_P(BadInput, OneClearLineAndANonZeroExit) {
  const BadInputCase& c = GetParam();
  ScratchRoot root;
  c.corrupt(root);
  const CommandResult r = run_cli(
      "render --robot " + c.robot + " --env kitchen --out " + (root.path() / "x.png").string(),
      root.path());
  EXPECT_EQ(r.exit_code, 2) << "stderr: " << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "stderr: " << r.err;
  EXPECT_EQ(r.err.rfind("taskmatrix: error: ", 0), 0u) << r.err;
  for (const std::string& s : c.expected) {
    EXPECT_NE(r.err.find(s), std::string::npos) << "expected '" << s << "' in: " << r.err;
  }
  EXPECT_FALSE(std::filesystem::exists(root.path() / "x.png"))
      << "wrote an image despite the error";
}

const std::string kProfile = "models/robots/minibot/profile.yaml";
const std::string kMjcf = "models/robots/minibot/minibot.xml";
const std::string kUrdf = "models/robots/minibot/minibot.urdf";
const std::string kEnvSpec = "models/environments/kitchen/environment.yaml";
const std::string kEnvMjcf = "models/environments/kitchen/kitchen.xml";

std::vector<BadInputCase> cases() {
  return {
      // A base yaw narrower than a full turn is not re-centred on the room's start heading.
      {"StartHeadingOutsideANarrowBaseYaw",
       "minibot",
       [](const ScratchRoot& r) {
         r.replace(kMjcf, "range=\"-3.14159 3.14159\" damping=\"100\"",
                   "range=\"-1 1\" damping=\"100\"");
         r.replace(kMjcf, "ctrlrange=\"-3.14159 3.14159\"", "ctrlrange=\"-1 1\"");
         r.replace(kEnvSpec, "yaw: 0.0}", "yaw: 2.0}");
       },
       {"environment.yaml", "robot_start.yaw", "2.0", "outside minibot's base yaw range"}},
      {"MjcfTruncated",
       "minibot",
       [](const ScratchRoot& r) {
         const std::string t = r.read(kMjcf);
         r.write(kMjcf, t.substr(0, t.size() / 2));
       },
       {"minibot.xml", "MuJoCo"}},
      {"MjcfActuatorOnUnknownJoint",
       "minibot",
       [](const ScratchRoot& r) {
         r.replace(kMjcf, "</actuator>", "<position joint=\"NoSuchJoint\"/></actuator>");
       },
       {"minibot.xml", "NoSuchJoint"}},
      {"MjcfNotXml",
       "minibot",
       [](const ScratchRoot& r) { r.write(kMjcf, "this is not xml"); },
       {"minibot.xml"}},
      {"UrdfMalformed",
       "minibot_urdf",
       [](const ScratchRoot& r) { r.replace(kUrdf, "</robot>", ""); },
       {"minibot.urdf", "urdfdom"}},
      {"UrdfJointWithoutLimits",
       "minibot_urdf",
       [](const ScratchRoot& r) {
         r.replace(kUrdf, "<joint name=\"LElbowRoll\" type=\"revolute\">",
                   "<joint name=\"LElbowRoll\" type=\"continuous\">");
       },
       {"minibot.urdf", "joint[LElbowRoll]"}},
      // A model taken with its floating base: the free joint named as the base chain.
      {"ProfileFloatingBase",
       "minibot",
       [](const ScratchRoot& r) {
         r.replace(kProfile, "base:       {joints: [BaseX, BaseY, BaseYaw]}",
                   "base:       {joints: [Root]}");
       },
       {"profile.yaml", "chains.base.joints", "free joint", "a slide along x"}},
      {"MjcfFreeJointInAChain",
       "minibot",
       [](const ScratchRoot& r) {
         r.replace(kMjcf,
                   R"(<joint name="BaseX" type="slide" axis="1 0 0" range="-5 5" damping="300"/>)",
                   "");
         r.replace(kMjcf, R"(<position name="BaseX" joint="BaseX" kp="1000" ctrlrange="-5 5"/>)",
                   "");
         r.replace(kMjcf, R"(<body name="BaseRoot" pos="0 0 0">)",
                   R"(<body name="BaseRoot" pos="0 0 0"><freejoint name="Root"/>)");
         r.replace(kProfile, "base:       {joints: [BaseX, BaseY, BaseYaw]}",
                   "base:       {joints: [Root, BaseY, BaseYaw]}");
       },
       {"profile.yaml", "chains.base.joints", "joint 'Root' is a free joint", "planar base"}},
      {"ProfileUnknownKey",
       "minibot",
       [](const ScratchRoot& r) { r.write(kProfile, r.read(kProfile) + "colour: red\n"); },
       {"profile.yaml:", "colour: unknown key"}},
      {"ProfileNanHeight",
       "minibot",
       [](const ScratchRoot& r) { r.replace(kProfile, "height_m: 1.105", "height_m: .nan"); },
       {"profile.yaml:", "height_m: must be a finite number"}},
      {"ProfilePostureOutsideLimits",
       "minibot",
       [](const ScratchRoot& r) {
         r.replace(kProfile, "    torso:      [0]", "    torso:      [2.5]");
       },
       {"profile.yaml", "postures.rest.torso", "TorsoPitch", "outside"}},
      {"ProfileJointNotInModel",
       "minibot",
       [](const ScratchRoot& r) {
         r.replace(kProfile, "{joints: [HeadYaw]}", "{joints: [HeadRoll]}");
       },
       {"profile.yaml", "chains.head.joints", "HeadRoll"}},
      {"ProfileChainsOverlap",
       "minibot",
       [](const ScratchRoot& r) {
         r.replace(kProfile, "{joints: [HeadYaw]}", "{joints: [TorsoPitch]}");
       },
       {"profile.yaml", "already in chain"}},
      {"ProfileWithoutTheWave",
       "minibot",
       [](const ScratchRoot& r) { r.replace(kProfile, "  wave:\n", "  waving:\n"); },
       {"profile.yaml", "canned: missing required canned motion 'wave'"}},
      {"ProfileWaveNotFromWaveStart",
       "minibot",
       [](const ScratchRoot& r) {
         r.replace(kProfile, "      - [0, 0, -1.3, -1.5708, -1.6, 0]",
                   "      - [0, 0, -1.3, -1.5708, -1.5, 0]");
       },
       {"profile.yaml", "canned.wave.keyframes[0]: must equal postures.wave_start"}},
      {"HeadCameraLooksBackwards",
       "minibot",
       [](const ScratchRoot& r) {
         r.replace(kMjcf, "xyaxes=\"0 -1 0 0.5 0 0.8660254037844386\"",
                   "xyaxes=\"0 1 0 -0.5 0 0.8660254037844386\"");
       },
       {"profile.yaml", "head_camera",
        "'HeadCam' looks 150 degrees away from the robot's forward"}},
      {"HeadCameraUpsideDown",
       "minibot",
       [](const ScratchRoot& r) {
         r.replace(kMjcf, "xyaxes=\"0 -1 0 0.5 0 0.8660254037844386\"",
                   "xyaxes=\"0 1 0 0.5 0 -0.8660254037844386\"");
       },
       {"profile.yaml", "head_camera", "is not upright"}},
      {"ProfileNotYaml",
       "minibot",
       [](const ScratchRoot& r) { r.write(kProfile, "chains: [unclosed\n"); },
       {"profile.yaml", "not valid YAML"}},
      {"EnvironmentModelMissing",
       "minibot",
       [](const ScratchRoot& r) {
         r.replace(kEnvSpec, "model: kitchen.xml", "model: nothere.xml");
       },
       {"environment.yaml", "model", "nothere.xml"}},
      {"EnvironmentMjcfBroken",
       "minibot",
       [](const ScratchRoot& r) { r.write(kEnvMjcf, "<mujoco><worldbody><body></mujoco>"); },
       {"kitchen.xml"}},
      {"EnvironmentObjectBodyMissing",
       "minibot",
       [](const ScratchRoot& r) { r.replace(kEnvSpec, "body: cup", "body: mug"); },
       {"environment.yaml", "objects.cup", "mug"}},
      {"ProfileChainJointNotOnTheRobot",
       "minibot",
       [](const ScratchRoot& r) {
         r.replace(kProfile, "{joints: [HeadYaw]}", "{joints: [HeadYaw, visitor_x]}");
         r.replace(kProfile, "    head:       [0]", "    head:       [0, 0.5]");
       },
       {"profile.yaml", "chains.head.joints", "visitor_x", "not on the robot"}},
      {"ProfileDuplicateKey",
       "minibot",
       [](const ScratchRoot& r) { r.write(kProfile, r.read(kProfile) + "name: other\n"); },
       {"profile.yaml:", "name: appears twice"}},
      {"ProfileNonScalarKey",
       "minibot",
       [](const ScratchRoot& r) { r.write(kProfile, r.read(kProfile) + "? [a, b]\n: 1\n"); },
       {"profile.yaml:", "keys must be plain names"}},
      {"ProfileWithoutRightHand",
       "minibot",
       [](const ScratchRoot& r) {
         r.replace(kProfile, "  right:\n    palm: RPalm", "  other:\n    palm: RPalm");
       },
       {"profile.yaml", "hands"}},
      {"EnvironmentKeepOutNamesNoRegion",
       "minibot",
       [](const ScratchRoot& r) { r.replace(kEnvSpec, "regions: [floor]", "regions: [ceiling]"); },
       {"environment.yaml:", "keep_out[1].regions[0]: names no obstacle region"}},
      {"EnvironmentRegionsTooSmallForTheObstacles",
       "minibot",
       [](const ScratchRoot& r) {
         r.replace(kEnvSpec, "{name: floor, x: [1.15, 3.1], y: [-2.0, 2.0], z: 0.0}",
                   "{name: floor, x: [1.15, 1.4], y: [-2.0, -1.8], z: 0.0}");
         r.replace(kEnvSpec, "{name: table_top, x: [0.36, 0.94], y: [-0.54, 0.54], z: 0.65}",
                   "{name: table_top, x: [0.36, 0.40], y: [-0.54, -0.50], z: 0.65}");
       },
       {"environment.yaml", "obstacle_regions", "could place only"}},
      {"EnvironmentAngleUnitUnknown",
       "minibot",
       [](const ScratchRoot& r) { r.replace(kEnvMjcf, "angle=\"radian\"", "angle=\"grad\""); },
       {"kitchen.xml", "'grad'", "compiler"}},
  };
}

INSTANTIATE_TEST_SUITE_P(Files, BadInput, ::testing::ValuesIn(cases()),
                         [](const auto& p) { return p.param.name; });

TEST(BadInput, UnknownRobotListsTheKnownOnes) {
  const CommandResult r =
      run_cli("render --robot nobody --env kitchen --out /tmp/never.png", TASKMATRIX_TEST_ROOT);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("unknown robot 'nobody' (known: atlas, minibot, minibot_urdf, tallbot)"),
            std::string::npos)
      << r.err;
}

TEST(BadInput, CommandLineMistakesAreOneLineToo) {
  for (const char* args :
       {"list", "list planets", "render --robot minibot --env kitchen --seed -3 --out /tmp/n.png",
        "render --robot minibot --env kitchen --obstacles 500 --out /tmp/n.png", "frobnicate"}) {
    const CommandResult r = run_cli(args, TASKMATRIX_TEST_ROOT);
    EXPECT_EQ(r.exit_code, 2) << args << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << ": " << r.err;
    EXPECT_EQ(r.err.rfind("taskmatrix: error: ", 0), 0u) << args << ": " << r.err;
  }
}

TEST(Cli, ListPrintsOneNamePerLine) {
  const CommandResult robots = run_cli("list robots", TASKMATRIX_TEST_ROOT);
  EXPECT_EQ(robots.exit_code, 0);
  EXPECT_EQ(robots.out, "atlas\nminibot\nminibot_urdf\ntallbot\n");
  const CommandResult envs = run_cli("list environments", TASKMATRIX_TEST_ROOT);
  EXPECT_EQ(envs.exit_code, 0);
  EXPECT_EQ(envs.out, "kitchen\noffice\n");
}

TEST(Cli, RenderWritesAPng) {
  ScratchRoot root;
  const auto out = root.path() / "head.png";
  const CommandResult r = run_cli(
      "render --robot minibot --env office --seed 4 --camera head --width 64 --height 48 --out " +
          out.string(),
      TASKMATRIX_TEST_ROOT);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  ASSERT_TRUE(std::filesystem::exists(out));
  EXPECT_GT(std::filesystem::file_size(out), 200u);
}

}  // namespace
}  // namespace taskmatrix::test
