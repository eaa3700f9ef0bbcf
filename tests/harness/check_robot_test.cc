// `taskmatrix check-robot`, run as a user adding a robot would: the built-in robots pass the
// lint; robots broken on purpose in a scratch models folder fail it with the profile key at
// fault and exit status 1; the quick run prints one line per program and exits 4 when one
// fails.
#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "tests/test_support.h"

namespace taskmatrix::test {
namespace {

// A copy of minibot named `name` in the scratch root's models, to be broken.
void copy_minibot(const ScratchRoot& root, const std::string& name) {
  const std::filesystem::path dir = root.path() / "models" / "robots" / name;
  std::filesystem::copy(root.path() / "models" / "robots" / "minibot", dir);
  root.replace("models/robots/" + name + "/profile.yaml", "name: minibot", "name: " + name);
}

// Removes each of `texts` (each must be there) from a file of the scratch root.
void remove_all(const ScratchRoot& root, const std::string& file,
                const std::vector<std::string>& texts) {
  for (const std::string& text : texts) root.replace(file, text, "");
}

// A default suite of program scenarios (file stem, text) in the scratch root: what
// check-robot's quick run runs.
void write_default_suite(const ScratchRoot& root,
                         const std::vector<std::pair<std::string, std::string>>& scenarios) {
  std::filesystem::create_directories(root.path() / "scenarios" / "suites");
  std::filesystem::create_directories(root.path() / "scenarios" / "programs");
  std::string list;
  for (const auto& [name, text] : scenarios) {
    root.write("scenarios/programs/" + name + ".yaml", text);
    list += (list.empty() ? "" : ", ") + std::string("../programs/") + name + ".yaml";
  }
  root.write("scenarios/suites/default.yaml", "suite: default\nscenarios: [" + list + "]\n");
}

TEST(CheckRobot, BuiltInRobotsPassTheLint) {
  for (const std::string robot : {"atlas", "tallbot", "minibot"}) {
    const CommandResult r = run_cli("check-robot " + robot + " --no-run", TASKMATRIX_TEST_ROOT);
    EXPECT_EQ(r.exit_code, 0) << robot << "\n" << r.out << r.err;
    EXPECT_NE(r.out.find("Lint: 0 errors"), std::string::npos) << r.out;
    // tallbot's thumb closes across its closing axis: a warning, not an error.
    for (const char* check :
         {"| load | ok |", "| mirror signs | ok |", "| palm axes | ", "| fingers | ok |",
          "| head camera | ok |", "| surface heights | ok |",
          "| canned | ok | bow, wave: the robot touches neither itself nor the floor"}) {
      EXPECT_NE(r.out.find(check), std::string::npos) << robot << ": " << check << "\n" << r.out;
    }
    // Every surface of both rooms is within reach.
    for (const char* surface : {"kitchen work_surface", "office side_surface"}) {
      EXPECT_NE(r.out.find(std::string("| reach envelope | ok | ") + surface), std::string::npos)
          << robot << ": " << surface << "\n"
          << r.out;
    }
    EXPECT_EQ(r.out.find("| ERROR |"), std::string::npos) << r.out;
  }
}

// The reach lint counts a palm only as a grasp holds it: approaching within 30 degrees of the
// horizontal or of down, and closing within 30 degrees of the horizontal (every grasp of an
// upright object but the last resort closes so). tallbot's fingers close along its forearm:
// with the waist it had until 2026-12-06 (pitch at most 0.8 rad) the forearm points down too
// steeply over a 0.55 m table, and the lint says so, as the generalization suite found (each of
// that tallbot's 72 cup and box trials on a table below 0.60 m failed, each of its 24 vacuum
// trials there succeeded: a tool's grip closes across its handle; counted with the approach
// alone, the lint found 0.22 m at 0.55 m). With its waist bending to 1.4 rad it serves 0.50 m.
TEST(CheckRobot, SurfaceHeightsCountPalmsThatCloseAsAGraspDoes) {
  const CommandResult r = run_cli("check-robot tallbot --no-run", TASKMATRIX_TEST_ROOT);
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("0.45: nowhere, 0.50: 0.32, 0.55: 0.32, 0.60: 0.34"), std::string::npos)
      << r.out;
  ScratchRoot root;
  test::stiffen_tallbot_waist(root);
  const CommandResult stiff = run_cli("check-robot tallbot --no-run", root.path());
  EXPECT_EQ(stiff.exit_code, 0) << stiff.out << stiff.err;
  EXPECT_NE(stiff.out.find("0.50: nowhere, 0.55: nowhere, 0.60: 0.34"), std::string::npos)
      << stiff.out;
  // A kitchen table lowered to 0.55 m: a warning naming it for the stiff waist (a tool's grip
  // closes across its handle in any direction, so the programs may still use it), not an
  // error; none for the waist that bends further.
  const auto lint_at_a_low_table = [](const ScratchRoot& at) {
    at.replace("models/environments/kitchen/kitchen.xml",
               R"(<body name="table" pos="0.65 0 0.65">)",
               R"(<body name="table" pos="0.65 0 0.55">)");
    const CommandResult low = run_cli("check-robot tallbot --no-run", at.path());
    EXPECT_EQ(low.exit_code, 0) << low.out << low.err;
    return low.out;
  };
  const std::string warning = "| reach envelope | warning | kitchen work_surface (top 0.550 m";
  const std::string stiff_low = lint_at_a_low_table(root);
  EXPECT_NE(stiff_low.find(warning), std::string::npos) << stiff_low;
  EXPECT_NE(stiff_low.find("as grasps of upright objects close them, nowhere (need 0.15 m): cups "
                           "and boxes there are out of reach"),
            std::string::npos)
      << stiff_low;
  const std::string supple_low = lint_at_a_low_table(ScratchRoot());
  EXPECT_EQ(supple_low.find(warning), std::string::npos) << supple_low;
}

// minibot's elbow bends to -2.1 rad, where the biceps already touches the forearm: the lint
// warns, naming the joint, the limit and the links (a plan may end a hair from that contact
// and physics then holds it). With the range ending where the links meet (-1.9), it is clean.
TEST(CheckRobot, AJointRangeThatFoldsALinkIntoAnotherIsAWarning) {
  const CommandResult built_in = run_cli("check-robot minibot --no-run", TASKMATRIX_TEST_ROOT);
  EXPECT_EQ(built_in.exit_code, 0) << built_in.out << built_in.err;
  EXPECT_NE(built_in.out.find("| joint ranges | warning | 2 joint limits fold a link of the chain "
                              "into another"),
            std::string::npos)
      << built_in.out;
  EXPECT_NE(built_in.out.find("left_arm joint 'LElbowRoll' at its lower limit -2.10: LBiceps "
                              "touches LForeArm"),
            std::string::npos)
      << built_in.out;
  ScratchRoot root;
  copy_minibot(root, "stops");
  const std::string model = "models/robots/stops/minibot.xml";
  for (const std::string side : {"L", "R"}) {
    root.replace(model,
                 "name=\"" + side + "ElbowRoll\" type=\"hinge\" axis=\"0 1 0\" range=\"-2.1 0\"",
                 "name=\"" + side + "ElbowRoll\" type=\"hinge\" axis=\"0 1 0\" range=\"-1.9 0\"");
    root.replace(model, "joint=\"" + side + "ElbowRoll\" kp=\"500\" ctrlrange=\"-2.1 0\"",
                 "joint=\"" + side + "ElbowRoll\" kp=\"500\" ctrlrange=\"-1.9 0\"");
  }
  const CommandResult stops = run_cli("check-robot stops --no-run", root.path());
  EXPECT_EQ(stops.exit_code, 0) << stops.out << stops.err;
  EXPECT_NE(stops.out.find("| joint ranges | ok |"), std::string::npos) << stops.out;
}

struct BrokenRobot {
  std::string name;
  std::function<void(const ScratchRoot&, const std::string& profile, const std::string& model)>
      corrupt;
  std::string expected;  // in the lint table
};
void PrintTo(const BrokenRobot& b, std::ostream* os) { *os << b.name; }

class CheckRobotBroken : public ::testing::TestWithParam<BrokenRobot> {};

TEST_P(CheckRobotBroken, FailsTheLintWithTheKeyAndExitsOne) {
  const BrokenRobot& b = GetParam();
  ScratchRoot root;
  copy_minibot(root, "broken");
  b.corrupt(root, "models/robots/broken/profile.yaml", "models/robots/broken/minibot.xml");
  const CommandResult r = run_cli("check-robot broken", root.path());
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_NE(r.out.find("| ERROR |"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(b.expected), std::string::npos) << "expected '" << b.expected << "' in:\n"
                                                       << r.out;
  EXPECT_NE(r.out.find("the programs were not run"), std::string::npos) << r.out;
  EXPECT_FALSE(std::filesystem::exists(root.path() / "results")) << "ran programs anyway";
}

INSTANTIATE_TEST_SUITE_P(
    Lint, CheckRobotBroken,
    ::testing::Values(
        // The approach axis points into the palm: the palm block lies in front of the origin.
        BrokenRobot{"ApproachIntoThePalm",
                    [](const ScratchRoot& r, const std::string& p, const std::string&) {
                      r.replace(p, "approach: [1, 0, 0]", "approach: [-1, 0, 0]");
                    },
                    "hands.left.approach: geom 'LPalmBlock' of the palm's body reaches"},
        // A mirror sign that keeps every posture within limits but mirrors the elbow wrongly.
        BrokenRobot{"MirrorSignWrong",
                    [](const ScratchRoot& r, const std::string& p, const std::string&) {
                      r.replace(p, "arm:        [1, -1, -1, 1, -1]",
                                "arm:        [1, -1, 1, 1, -1]");
                    },
                    "mirror_signs.arm: at left_arm ["},
        // The fist opens the hand: the fingertips move away from the palm.
        BrokenRobot{"FistOpensTheHand",
                    [](const ScratchRoot& r, const std::string& p, const std::string&) {
                      r.replace(p, "  fist:\n    left_hand:  [0.4, 0.45, 0.4, 0.45]",
                                "  fist:\n    left_hand:  [-0.4, 0, -0.4, 0]");
                    },
                    "hands.left.fingers: fingers[0]: its tip ends"},
        // The rest posture closes the fingers into each other.
        BrokenRobot{"RestFingersOverlap",
                    [](const ScratchRoot& r, const std::string& p, const std::string&) {
                      r.replace(p,
                                "    left_hand:  [-0.3, 0, -0.3, 0]\n    right_hand: [-0.3, 0, "
                                "-0.3, 0]\n  hand_open",
                                "    left_hand:  [0.8, 1, 0.8, 1]\n    right_hand: [-0.3, 0, -0.3, "
                                "0]\n  hand_open");
                    },
                    "postures.rest: at the start of kitchen, LFinger1"},
        // A wave within the speed limits that swings the elbow through the torso.
        BrokenRobot{"WaveSwingsTheElbowIntoTheTorso",
                    [](const ScratchRoot& r, const std::string& p, const std::string&) {
                      r.replace(p,
                                "      - [1.1, 0, -1.3, -1.5708, -1.9, 0]\n"
                                "      - [1.7, 0, -1.3, -1.5708, -1.25, 0]\n"
                                "      - [2.3, 0, -1.3, -1.5708, -1.9, 0]\n"
                                "      - [2.8, ",
                                "      - [2.5, 0, 0.3, -1.5708, -1.9, 0]\n"
                                "      - [4.5, 0, -1.3, -1.5708, -1.25, 0]\n"
                                "      - [5.1, 0, -1.3, -1.5708, -1.9, 0]\n"
                                "      - [5.6, ");
                    },
                    "| canned | ERROR | canned.wave: at 2.24 s RElbow touches Torso"},
        // A camera that looks backwards is refused when the robot loads.
        BrokenRobot{"CameraLooksBackwards",
                    [](const ScratchRoot& r, const std::string&, const std::string& m) {
                      r.replace(m, "xyaxes=\"0 -1 0 0.5 0 0.8660254037844386\"",
                                "xyaxes=\"0 1 0 -0.5 0 0.8660254037844386\"");
                    },
                    "| load | ERROR | in kitchen: "}),
    [](const auto& p) { return p.param.name; });

// check-robot NAME in the kitchen with a default suite of one pickup of the cup: a clean lint
// and the cup picked up.
void expect_clean_lint_and_cup_pickup(const ScratchRoot& root, const std::string& robot) {
  write_default_suite(root,
                      {{"pickup", "program: pickup\nparams: {object: cup}\nrobots: [" + robot +
                                      "]\nenvironments: [kitchen]\nobstacles: {count: 8}\n"
                                      "layout_seed: 3\nseed: 1\ntime_limit_s: 40\n"
                                      "success: grasping(cup)\n"}});
  const CommandResult r = run_cli("check-robot " + robot + " --env kitchen --jobs 1", root.path());
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("Lint: 0 errors"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("| pickup | success |"), std::string::npos) << r.out;
}

// The quick run goes through the scenario runner with the root's default suite: here a
// two-scenario suite in a scratch root, one that succeeds and one that cannot.
TEST(CheckRobot, QuickRunPrintsAProgramTableAndExitsFourOnAFailure) {
  ScratchRoot root;
  write_default_suite(root,
                      {{"postural",
                        "program: postural\nparams: {posture: wave_start, side: as_named}\n"
                        "robots: [minibot]\nenvironments: [kitchen]\nobstacles: {count: 2}\n"
                        "time_limit_s: 20\nsuccess: postural(wave_start)\n"},
                       {"unreachable",
                        "program: reach\nparams: {object: visitor, base: false, torso: false}\n"
                        "robots: [minibot]\nenvironments: [kitchen]\nobstacles: {count: 2}\n"
                        "time_limit_s: 20\n"}});
  const CommandResult r = run_cli("check-robot minibot --env office --jobs 1", root.path());
  EXPECT_EQ(r.exit_code, 4) << r.out << r.err;
  EXPECT_NE(r.out.find("Lint: 0 errors"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("| postural | success |"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("| unreachable | not_graspable |"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("Programs: 1 of 2 succeeded."), std::string::npos) << r.out;
  // The run stays for inspection, in its own directory.
  const std::filesystem::path run = root.path() / "results/runs/check-robot-minibot-office";
  EXPECT_TRUE(std::filesystem::exists(run / "summary.md"));
  // In the environment asked for, whatever the scenarios list.
  const std::string trials = root.read("results/runs/check-robot-minibot-office/trials.jsonl");
  EXPECT_NE(trials.find("\"trial_id\":\"postural.minibot.office."), std::string::npos) << trials;
  EXPECT_EQ(trials.find(".kitchen."), std::string::npos) << trials;
}

// A robot with a rigid torso (many small humanoids have no waist joint) has no `torso` chain:
// it loads, passes the lint, and reach goes from its arm straight to a stance.
TEST(CheckRobot, ARobotWithoutATorsoChainPassesTheLintAndPicksUpTheCup) {
  ScratchRoot root;
  copy_minibot(root, "rigid");
  const std::string profile = "models/robots/rigid/profile.yaml";
  const std::string model = "models/robots/rigid/minibot.xml";
  root.replace(profile, "  bow:\n    chains: [torso]\n", "  bow:\n    chains: [head]\n");
  remove_all(root, profile,
             {"  torso:      {joints: [TorsoPitch]}\n", "    torso:      [0]\n",
              "  torso:      {velocity: 0.8, acceleration: 2}\n", "  torso:      800\n"});
  remove_all(
      root, model,
      {R"(<joint name="TorsoPitch" type="hinge" axis="0 1 0" range="-0.2 0.6" damping="50"/>)",
       R"(<position name="TorsoPitch" joint="TorsoPitch" kp="800" ctrlrange="-0.2 0.6"/>)"});
  ASSERT_EQ(root.read(profile).find("torso:"), std::string::npos) << root.read(profile);
  expect_clean_lint_and_cup_pickup(root, "rigid");
}

// A robot whose head camera is fixed to its trunk (no neck joints) has no `head` chain: it
// loads, passes the lint, and fixate, explore and pickup aim the camera with the base; an
// explore told to keep the base still says why it stops after one look.
TEST(CheckRobot, ARobotWithAFixedHeadCameraTracksExploresAndPicksUpWithItsBase) {
  ScratchRoot root;
  copy_minibot(root, "fixedcam");
  const std::string profile = "models/robots/fixedcam/profile.yaml";
  const std::string model = "models/robots/fixedcam/minibot.xml";
  remove_all(root, profile,
             {"  head:       {joints: [HeadYaw]}\n", "    head:       [0]\n",
              "  head:       {velocity: 1.5, acceleration: 4}\n", "  head:       300\n"});
  remove_all(root, model,
             {R"(<joint name="HeadYaw" type="hinge" axis="0 0 1" range="-2 2" damping="5"/>)",
              R"(<position name="HeadYaw" joint="HeadYaw" kp="300" ctrlrange="-2 2"/>)"});
  ASSERT_EQ(root.read(profile).find("head:"), std::string::npos) << root.read(profile);
  const std::string common =
      "robots: [fixedcam]\nenvironments: [kitchen]\nobstacles: {count: 8}\nlayout_seed: 3\n"
      "seed: 1\n";
  write_default_suite(
      root,
      {{"fixate", "program: fixate\nparams: {object: visitor, duration: 6}\n" + common +
                      "visitor: {walk_speed: 0.4}\ntime_limit_s: 30\nsuccess: in_view(visitor)\n"},
       {"explore",
        "program: explore\nparams: {surface: side_surface, coverage: 0.9, cell_m: 0.05}\n" +
            common + "time_limit_s: 60\n"},
       {"pickup", "program: pickup\nparams: {object: cup}\n" + common +
                      "time_limit_s: 40\nsuccess: grasping(cup)\n"},
       // Neither a head nor the base to aim with: one look, and the reason it stops there.
       {"explore_in_place",
        "program: explore\nparams: {surface: side_surface, coverage: 0.9, cell_m: 0.05, "
        "base: false}\n" +
            common + "time_limit_s: 60\n"}});
  const CommandResult r = run_cli("check-robot fixedcam --env kitchen --jobs 1", root.path());
  EXPECT_EQ(r.exit_code, 4) << r.out << r.err;
  EXPECT_NE(r.out.find("Programs: 3 of 4 succeeded."), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("| explore_in_place | coverage_short |"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("nothing aims the camera (the robot has no head chain; base: false)"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("Lint: 0 errors"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("fixed to the trunk (no head chain)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("| fixate | success |"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("| explore | success |"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("| pickup | success |"), std::string::npos) << r.out;
}

// Replaces, in a file of the scratch root, the text from `start` up to and including the
// `closings`-th "</body>" after it.
void replace_bodies(const ScratchRoot& root, const std::string& file, const std::string& start,
                    int closings, const std::string& with) {
  std::string text = root.read(file);
  const size_t from = text.find(start);
  ASSERT_NE(from, std::string::npos) << start;
  size_t to = from;
  for (int i = 0; i < closings; ++i) {
    to = text.find("</body>", to);
    ASSERT_NE(to, std::string::npos);
    to += 7;
  }
  text.replace(from, to - from, with);
  root.write(file, text);
}

// A robot with parallel-jaw grippers (each finger one segment on a slide joint, its frame
// level with the palm frame): reach places the palm by the palm's geometry, not by where the
// jaws' frames sit, and pickup holds the cup.
TEST(CheckRobot, ARobotWithParallelJawGrippersPicksUpTheCup) {
  ScratchRoot root;
  copy_minibot(root, "jaws");
  const std::string profile = "models/robots/jaws/profile.yaml";
  const std::string model = "models/robots/jaws/minibot.xml";
  for (const std::string side : {"L", "R"}) {
    for (const auto& [finger, y, axis] :
         {std::tuple{"1", "0.06", "0 -1 0"}, std::tuple{"2", "-0.06", "0 1 0"}}) {
      const std::string jaw = side + "Jaw" + finger;
      replace_bodies(root, model, "<body name=\"" + side + "Finger" + finger + "ProxLink\"", 2,
                     "<body name=\"" + jaw + "\" pos=\"0 " + y + " 0\"><inertial pos=\"0 0 0\" " +
                         "mass=\"0.04\" diaginertia=\"1e-5 1e-5 1e-5\"/><joint name=\"" + jaw +
                         "\" type=\"slide\" axis=\"" + axis + "\" range=\"0 0.055\" " +
                         "damping=\"5\"/><geom name=\"" + jaw + "Pad\" type=\"box\" " +
                         "size=\"0.035 0.008 0.012\" pos=\"0.003 0 0\"/></body>");
      const std::string prox = side + "Finger" + finger + "Prox";
      const std::string dist = side + "Finger" + finger + "Dist";
      root.replace(
          model,
          "<position name=\"" + dist + "\" joint=\"" + dist + "\" kp=\"30\" ctrlrange=\"0 1\"/>",
          "");
      root.replace(model,
                   "<position name=\"" + prox + "\" joint=\"" + prox +
                       "\" kp=\"30\" ctrlrange=\"-0.4 0.8\"/>",
                   "<position name=\"" + jaw + "\" joint=\"" + jaw +
                       "\" kp=\"300\" ctrlrange=\"0 0.055\"/>");
      root.replace(
          profile,
          "{joints: [" + prox + ", " + dist + "], bodies: [" + prox + "Link, " + dist + "Link]}",
          "{joints: [" + jaw + "], bodies: [" + jaw + "]}");
    }
    root.replace(profile,
                 "[" + side + "Finger1Prox, " + side + "Finger1Dist, " + side + "Finger2Prox, " +
                     side + "Finger2Dist]",
                 "[" + side + "Jaw1, " + side + "Jaw2]");
  }
  root.replace(model, R"(size="0.022 0.062 0.016")", R"(size="0.022 0.075 0.016")");
  root.replace(model, R"(size="0.022 0.062 0.016")", R"(size="0.022 0.075 0.016")");
  for (int i = 0; i < 4; ++i) root.replace(profile, "[-0.3, 0, -0.3, 0]", "[0, 0]");
  for (int i = 0; i < 2; ++i) root.replace(profile, "[0.4, 0.45, 0.4, 0.45]", "[0.05, 0.05]");
  root.replace(profile, "hand:       [1, 1, 1, 1]", "hand:       [1, 1]");
  // Jaws close at 0.1 m/s, as a real parallel gripper does.
  root.replace(profile, "left_hand:  {velocity: 2, acceleration: 8}",
               "left_hand:  {velocity: 0.1, acceleration: 0.5}");
  root.replace(profile, "right_hand: {velocity: 2, acceleration: 8}",
               "right_hand: {velocity: 0.1, acceleration: 0.5}");
  ASSERT_EQ(root.read(model).find("Finger"), std::string::npos) << root.read(model);
  expect_clean_lint_and_cup_pickup(root, "jaws");
}

// A user's own models folder, holding their robot and one room (no built-in robot, no office,
// no scenarios): check-robot's quick run takes the built-in default suite, and a suite of the
// user's that lists built-in program scenarios runs on that robot in that room, though those
// scenarios' own `robots:` and `environments:` name models this root lacks (the suite's lists
// replace theirs). An unknown name in the suite's own lists is still an error naming its file
// and line.
TEST(CheckRobot, ARootWithTheUsersRobotAloneRunsTheBuiltInProgramScenarios) {
  ScratchRoot root;
  copy_minibot(root, "solo");
  for (const char* other : {"atlas", "tallbot", "minibot", "minibot_urdf"}) {
    std::filesystem::remove_all(root.path() / "models" / "robots" / other);
  }
  std::filesystem::remove_all(root.path() / "models" / "environments" / "office");
  const CommandResult check = run_cli("check-robot solo --env kitchen --jobs 2", root.path());
  EXPECT_EQ(check.exit_code, 0) << check.out << check.err;
  EXPECT_NE(check.out.find(std::string(TASKMATRIX_TEST_ROOT) + "/scenarios/suites/default.yaml"),
            std::string::npos)
      << check.out;
  EXPECT_NE(check.out.find("Programs: 12 of 12 succeeded."), std::string::npos) << check.out;

  const std::string programs = std::string(TASKMATRIX_TEST_ROOT) + "/scenarios/programs/";
  auto suite = [&](const std::string& robots, const std::string& environments = "kitchen") {
    return "suite: mine\nscenarios: [" + programs + "pickup.yaml, " + programs +
           "putdown.yaml]\nrobots: [" + robots + "]\nenvironments: [" + environments +
           "]\ntrials: 2\n";
  };
  root.write("mine.yaml", suite("solo"));
  const CommandResult ok = run_cli("validate " + root.file("mine.yaml").string(), root.path());
  EXPECT_EQ(ok.exit_code, 0) << ok.out << ok.err;
  EXPECT_NE(ok.out.find("mine.yaml: ok, 4 trials"), std::string::npos) << ok.out << ok.err;
  root.write("mine.yaml", suite("solo, tallbot"));
  const CommandResult bad = run_cli("validate " + root.file("mine.yaml").string(), root.path());
  EXPECT_EQ(bad.exit_code, 2) << bad.out << bad.err;
  EXPECT_NE(bad.err.find("mine.yaml:3: robots: unknown robot 'tallbot' (known: solo)"),
            std::string::npos)
      << bad.err;
  root.write("mine.yaml", suite("solo", "office"));
  const CommandResult room = run_cli("validate " + root.file("mine.yaml").string(), root.path());
  EXPECT_EQ(room.exit_code, 2) << room.out << room.err;
  EXPECT_NE(
      room.err.find("mine.yaml:4: environments: unknown environment 'office' (known: kitchen)"),
      std::string::npos)
      << room.err;
}

// A root whose default suite holds a machine written inline in its scenario: check-robot's
// quick run runs it and lists it. Before, check-robot loaded the suite a second time to order
// its table, and the machine, registered by the first load, was refused by the second: `a
// program named 'nod' already exists`.
TEST(CheckRobot, TheQuickRunTakesADefaultSuiteWithAnInlineMachine) {
  ScratchRoot root;
  std::filesystem::create_directories(root.path() / "scenarios" / "suites");
  root.write("scenarios/nod.yaml",
             "machine:\n  name: nod\n  initial: up\n  states:\n"
             "    up: {program: postural, params: {posture: wave_start}}\n"
             "    down: {program: postural, params: {posture: rest}}\n"
             "    done: {final: success}\n"
             "  transitions:\n    - {from: up, on: completed, to: down}\n"
             "    - {from: down, on: completed, to: done}\n"
             "robots: [minibot]\nenvironments: [kitchen]\ntrials: 1\n");
  root.write("scenarios/suites/default.yaml", "suite: quick\nscenarios: [../nod.yaml]\n");
  const CommandResult check = run_cli("check-robot minibot --env kitchen --jobs 1", root.path());
  EXPECT_EQ(check.exit_code, 0) << check.out << check.err;
  EXPECT_NE(check.out.find("| nod | success |"), std::string::npos) << check.out;
  EXPECT_NE(check.out.find("Programs: 1 of 1 succeeded."), std::string::npos) << check.out;
}

TEST(CheckRobot, UnknownNamesAreBadInput) {
  CommandResult r = run_cli("check-robot nobody --no-run", TASKMATRIX_TEST_ROOT);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("unknown robot 'nobody' (known: "), std::string::npos) << r.err;
  r = run_cli("check-robot minibot --env attic", TASKMATRIX_TEST_ROOT);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("unknown environment 'attic'"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace taskmatrix::test
