// The twelve task programs, each from its scenarios/programs/<program>.yaml, on both robots
// in both environments in the scenario's default layout: each succeeds, judged on the world
// (the scenario's success condition on ground truth). Plus what the issue singles out: greet
// with the visitor walking, vacuum leaving no debris, and a pickup out of reach failing with
// its reason instead of hanging.
#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <iterator>
#include <regex>
#include <sstream>
#include <stdexcept>

#include "harness/run/trial.h"
#include "harness/scenario/scenario.h"
#include "taskmatrix/core/state_machine.h"
#include "taskmatrix/io/png.h"
#include "taskmatrix/mujoco/offscreen_renderer.h"
#include "taskmatrix/programs/grasp_candidates.h"
#include "taskmatrix/programs/primitives.h"
#include "tests/test_support.h"

namespace taskmatrix::harness {
namespace {

const std::vector<std::string> kPrograms = {"reach",  "position", "grasp",    "release",
                                            "fixate", "explore",  "postural", "canned",
                                            "pickup", "putdown",  "greet",    "vacuum"};

core::ProgramRegistry& registry() {
  static core::ProgramRegistry r = [] {
    core::ProgramRegistry out;
    programs::register_programs(out);
    return out;
  }();
  return r;
}

Scenario program_scenario(const std::string& program) {
  return load_scenario(test::catalog().root() / "scenarios" / "programs" / (program + ".yaml"),
                       test::catalog(), registry());
}

// The trial's events of `program` with `type` ("started", "completed", "failed", ...).
std::vector<TrialEvent> events_of(const TrialResult& r, const std::string& program,
                                  const std::string& type) {
  std::vector<TrialEvent> out;
  std::copy_if(r.events.begin(), r.events.end(), std::back_inserter(out),
               [&](const TrialEvent& e) { return e.program == program && e.type == type; });
  return out;
}

// A scenario of the generalization suite (objects placed, surface heights and start poses
// drawn per layout), by name.
Scenario generalization_scenario(const std::string& name) {
  const RunPlan plan =
      load_run_plan(test::catalog().root() / "scenarios" / "suites" / "generalization.yaml",
                    test::catalog(), registry());
  const auto it = std::find_if(plan.scenarios.begin(), plan.scenarios.end(),
                               [&](const Scenario& s) { return s.name == name; });
  if (it == plan.scenarios.end()) throw std::runtime_error("no scenario " + name);
  return *it;
}

// Runs the generalization suite's scenario `name` on `robot` in `environment` (that layout and
// seed) and expects it to succeed.
TrialResult expect_success(const std::string& name, const std::string& robot,
                           const std::string& environment, std::uint32_t layout,
                           std::uint32_t seed) {
  TrialResult r = run_trial(generalization_scenario(name), *test::loaded_scene(robot, environment),
                            layout, seed, registry());
  EXPECT_TRUE(r.success) << trial_status(r) << ": " << trial_failure_reason(r);
  return r;
}

// Runs the trial (layout, seed) of `s` in `scene` under kinematic execution and expects it to
// succeed with the base ending more than `min_travel_m` (in the plane) from where it stood at
// set-up: the robot stepped.
void expect_success_stepping(Scenario s, const core::LoadedScene& scene, std::uint32_t layout,
                             std::uint32_t seed, double min_travel_m) {
  s.execution = "kinematic";
  std::vector<double> start, end;
  const TrialResult r = run_trial(s, scene, layout, seed, registry(),
                                  [&](const std::string& moment, const core::TrialWorld& world) {
                                    if (moment == "setup")
                                      start = world.skills().configuration({"base"});
                                    if (moment == "end")
                                      end = world.skills().configuration({"base"});
                                  });
  ASSERT_TRUE(r.success) << trial_status(r) << ": " << trial_failure_reason(r);
  ASSERT_EQ(start.size(), 3u);
  ASSERT_EQ(end.size(), 3u);
  EXPECT_GT(std::hypot(end[0] - start[0], end[1] - start[1]), min_travel_m)
      << "the base did not step far enough";
}

// With TASKMATRIX_RENDER_DIR set, writes DIR/<label>_<moment>.png of the trial.
TrialObserver renders(const std::string& label) {
  const char* dir = std::getenv("TASKMATRIX_RENDER_DIR");
  if (!dir) return nullptr;
  return [dir, label](const std::string& moment, const core::TrialWorld& world) {
    const mujoco::MujocoSkillset& skills = test::mujoco_skills(world);
    mujoco::OffscreenRenderer renderer(skills.model(), 640, 480);
    mujoco::CameraView view;
    view.lookat[0] = 0.4;
    view.lookat[1] = -0.1;
    view.lookat[2] = 0.8;
    view.distance = 1.9;
    view.azimuth = 150;
    view.elevation = -30;
    io::write_png(
        std::string(dir) + "/" + label + "_" + moment + ".png",
        renderer.render_rgb(skills.model(), const_cast<mjData*>(skills.sim_data()), view));
  };
}

struct Case {
  std::string program;
  test::RobotEnv pair;
};
void PrintTo(const Case& c, std::ostream* os) {
  *os << c.program << " on " << c.pair.robot << " in " << c.pair.environment;
}

// The two humanoids of the program scenarios (minibot_urdf, minibot's URDF twin, is covered
// by the primitives' tests).
std::vector<test::RobotEnv> scenario_pairs() {
  std::vector<test::RobotEnv> out;
  for (const test::RobotEnv& p : test::all_robot_environment_pairs()) {
    if (p.robot == "tallbot" || p.robot == "minibot") out.push_back(p);
  }
  return out;
}

std::string case_name(const ::testing::TestParamInfo<Case>& info) {
  return info.param.program + "_" + test::pair_name(info.param.pair);
}

std::vector<Case> all_cases() {
  std::vector<Case> out;
  for (const std::string& p : kPrograms) {
    for (const test::RobotEnv& pair : scenario_pairs()) out.push_back({p, pair});
  }
  return out;
}

class ProgramScenarioTest : public ::testing::TestWithParam<Case> {};

TEST_P(ProgramScenarioTest, SucceedsInTheDefaultLayout) {
  const Case& c = GetParam();
  const Scenario s = program_scenario(c.program);
  EXPECT_EQ(s.run.program, c.program);
  // The scenario covers this robot and environment.
  ASSERT_NE(std::find(s.robots.begin(), s.robots.end(), c.pair.robot), s.robots.end());
  ASSERT_NE(std::find(s.environments.begin(), s.environments.end(), c.pair.environment),
            s.environments.end());
  const TrialResult r =
      run_trial(s, *test::loaded_scene(c.pair.robot, c.pair.environment), s.layout_seed, s.seed,
                registry(), renders(c.program + "_" + test::pair_name(c.pair)));
  EXPECT_TRUE(r.success) << trial_status(r) << ": " << trial_failure_reason(r);
  EXPECT_EQ(trial_status(r), "success");
  EXPECT_GT(r.duration_s, 0.0);
}

INSTANTIATE_TEST_SUITE_P(AllPrograms, ProgramScenarioTest, ::testing::ValuesIn(all_cases()),
                         case_name);

class ProgramBehaviourTest : public ::testing::TestWithParam<test::RobotEnv> {};

TEST_P(ProgramBehaviourTest, GreetsAWalkingVisitorWhileTrackingThem) {
  const Scenario s = program_scenario("greet");
  ASSERT_GT(s.visitor_speed_mps, 0.0);
  double visitor_y_at_end = 0;
  const TrialResult r =
      run_trial(s, *test::loaded_scene(GetParam().robot, GetParam().environment), s.layout_seed,
                s.seed, registry(), [&](const std::string& moment, const core::TrialWorld& world) {
                  if (moment == "end")
                    visitor_y_at_end = world.skills().frame_pose("visitor").position.y();
                });
  ASSERT_TRUE(r.success) << trial_failure_reason(r);
  // The visitor walked (it starts at y = -1.0 on its path), and the wave was played.
  EXPECT_GT(std::abs(visitor_y_at_end + 1.0), 0.5);
  EXPECT_TRUE(std::any_of(r.log.begin(), r.log.end(), [](const core::Message& m) {
    return m.program == "canned" && m.type == core::MessageType::kCompleted;
  }));
  // The tracking fixate (the longest of greet's fixates: finding the visitor and looking at
  // them again after the wave are short) recorded its error throughout, and kept the visitor
  // near the centre of the view (a neck without pitch leaves a vertical offset: under 0.5 rad
  // either way).
  auto track = r.series.end();
  for (auto it = r.series.begin(); it != r.series.end(); ++it) {
    if (it->name == "tracking_error_rad" &&
        (track == r.series.end() || it->samples.size() > track->samples.size())) {
      track = it;
    }
  }
  ASSERT_NE(track, r.series.end());
  // Greet's last state looked at the visitor again with the arms down.
  EXPECT_GE(std::count_if(r.series.begin(), r.series.end(),
                          [](const auto& series) { return series.name == "tracking_error_rad"; }),
            3);
  ASSERT_GT(track->samples.size(), 300u);
  for (const auto& [t, e] : track->samples) ASSERT_LT(e, 0.5) << "at t = " << t;
}

TEST_P(ProgramBehaviourTest, VacuumRemovesEveryFlakeOfDebris) {
  const Scenario s = program_scenario("vacuum");
  size_t removed = 0;
  const TrialResult r =
      run_trial(s, *test::loaded_scene(GetParam().robot, GetParam().environment), s.layout_seed,
                s.seed, registry(), [&](const std::string& moment, const core::TrialWorld& world) {
                  if (moment == "end") removed = world.removed_objects().size();
                });
  ASSERT_TRUE(r.success) << trial_failure_reason(r);
  EXPECT_EQ(removed, 5u);
  // One position per flake at most (a pass may take two flakes at once).
  const auto positions = std::count_if(r.log.begin(), r.log.end(), [](const core::Message& m) {
    return m.program == "position" && m.type == core::MessageType::kCompleted;
  });
  EXPECT_GE(positions, 2);
  EXPECT_LE(positions, 6);  // five flakes, and the putdown's placement
}

TEST_P(ProgramBehaviourTest, PickupOutOfReachFailsWithTheReason) {
  Scenario s = program_scenario("pickup");
  // The robot steps 1.2 m back from the work surface; without stepping, no arm reaches the cup.
  s.setup = {{"retreat", {{"part", "base"}, {"from", "work_surface"}, {"distance", "1.2"}}}};
  s.run.params = {{"object", "cup"}, {"step", "false"}};
  s.success.clear();
  const TrialResult r = run_trial(s, *test::loaded_scene(GetParam().robot, GetParam().environment),
                                  s.layout_seed, s.seed, registry());
  EXPECT_FALSE(r.success);
  ASSERT_TRUE(r.failure.has_value());
  EXPECT_EQ(r.failure->code, core::FailureCode::kIkFailure) << trial_failure_reason(r);
  EXPECT_NE(trial_failure_reason(r).find("reaches none of"), std::string::npos)
      << trial_failure_reason(r);
  EXPECT_LT(r.duration_s, 1.0);  // it gave up at once, and nothing was left running
}

TEST_P(ProgramBehaviourTest, AFailureInsideAMachineNamesTheStatesItFailedIn) {
  core::ProgramRegistry programs = registry();
  core::MachineSpec fetch;
  fetch.name = "fetch";
  fetch.states = {
      {"approach", "pickup", {{"object", "visitor"}, {"step", "false"}}, false, true, ""},
      {"done", "", {}, true, true, ""}};
  fetch.initial = "approach";
  fetch.transitions = {{"approach", core::MessageType::kCompleted, "done", {}, {}, ""}};
  core::register_machine(fetch, programs);
  Scenario s = program_scenario("pickup");
  s.run.program = "fetch";
  s.run.params.clear();
  s.success.clear();
  const TrialResult r = run_trial(s, *test::loaded_scene(GetParam().robot, GetParam().environment),
                                  s.layout_seed, s.seed, programs);
  // A person is no grasp for a hand: reach refuses it before any IK.
  ASSERT_TRUE(r.failure.has_value());
  EXPECT_EQ(r.failure->code, core::FailureCode::kNotGraspable) << trial_failure_reason(r);
  EXPECT_EQ(trial_failure_reason(r).rfind("fetch > pickup(approach) > reach: not_graspable: ", 0),
            0u)
      << trial_failure_reason(r);
  // The machine's failed event carries the same path.
  const auto failed = std::find_if(r.events.begin(), r.events.end(), [](const TrialEvent& e) {
    return e.program == "fetch" && e.type == "failed";
  });
  ASSERT_NE(failed, r.events.end());
  EXPECT_EQ(failed->path, "pickup(approach) > reach");
}

INSTANTIATE_TEST_SUITE_P(BothRobots, ProgramBehaviourTest, ::testing::ValuesIn(scenario_pairs()),
                         [](const auto& p) { return test::pair_name(p.param); });

// atlas stands with its hands beside the table: every base turn that would show the side
// surface sweeps a hand into the table, and its head camera sits inside its shoulders box.
// explore takes those viewpoints from a base moved away, and the sensor sees past the box.
TEST(ExploreOnAtlas, ViewpointsInCollisionAreTakenFromAMovedBase) {
  if (!std::filesystem::exists(test::catalog().robot_dir("atlas"))) {
    GTEST_SKIP() << "no atlas in " << test::catalog().root();
  }
  Scenario s = program_scenario("explore");
  s.execution = "kinematic";
  std::vector<double> base_at_end;
  const TrialResult r =
      run_trial(s, *test::loaded_scene("atlas", "kitchen"), s.layout_seed, s.seed, registry(),
                [&](const std::string& moment, const core::TrialWorld& world) {
                  if (moment == "end") base_at_end = world.skills().configuration({"base"});
                });
  ASSERT_TRUE(r.success) << trial_status(r) << ": " << trial_failure_reason(r);
  ASSERT_EQ(base_at_end.size(), 3u);
  EXPECT_GT(std::hypot(base_at_end[0], base_at_end[1]), 0.05) << "the base did not move away";
  double coverage = 0;
  for (const core::RecordedSeries& series : r.series) {
    if (series.name == "coverage" && !series.samples.empty())
      coverage = series.samples.back().second;
  }
  EXPECT_GE(coverage, 0.9);
}

// greet's tracking turns the base towards the visitor; the arms' plan down to rest assumes
// the base stays put. With tracking still running while atlas lowered its arms, a base turn
// swept its fingers into the side surface (office, layout 4).
TEST(GreetOnAtlas, TrackingStopsBeforeTheArmsAreLowered) {
  if (!std::filesystem::exists(test::catalog().robot_dir("atlas"))) {
    GTEST_SKIP() << "no atlas in " << test::catalog().root();
  }
  Scenario s = program_scenario("greet");
  s.execution = "kinematic";
  const TrialResult r = run_trial(s, *test::loaded_scene("atlas", "office"), s.layout_seed + 1,
                                  s.seed + 1, registry());
  EXPECT_TRUE(r.success) << trial_status(r) << ": " << trial_failure_reason(r);
}

// The same while raising the arm and at the rest posture it ends in: on the generalization
// suite's layouts (the table's height and the robot's start drawn), a base turn swept atlas's
// fingers into the table while finding the visitor (fixate commanded turns unchecked), while
// raising the arm (tracking turned the base), or left the rest posture in collision (kitchen,
// layout 101 shows all three). fixate now takes no turn into collision, and greet tracks with
// the head alone once the visitor is found.
TEST(GreetOnAtlas, TheBaseTurnsOnlyWhereNothingIsSweptIntoTheTable) {
  if (!std::filesystem::exists(test::catalog().robot_dir("atlas"))) {
    GTEST_SKIP() << "no atlas in " << test::catalog().root();
  }
  Scenario s = generalization_scenario("greet");
  s.execution = "kinematic";
  const TrialResult r = run_trial(s, *test::loaded_scene("atlas", "kitchen"), 101, 2, registry());
  EXPECT_TRUE(r.success) << trial_status(r) << ": " << trial_failure_reason(r);
}

// Runs the scenario file `file` of `root` (all its trials, or `only`); its trials.jsonl.
std::string run_in_root(const test::ScratchRoot& root, const std::string& file,
                        const std::string& only = "") {
  const test::CommandResult r = test::run_cli(
      "run " + (root.path() / file).string() + (only.empty() ? "" : " --only " + only) +
          " --jobs 1 --progress off --out " + (root.path() / "run").string(),
      root.path());
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  return root.read("run/trials.jsonl");
}

// Runs one trial of a task of scenarios/tasks/ (tidy.yaml, chores.yaml) for `robot` in
// `environment` (the task file's own robots and environments replaced), in a scratch root to
// which `add_room` (if given) first adds a room; its trials.jsonl.
std::string run_task_trial(const std::string& task, const std::string& robot,
                           const std::string& environment, const std::string& trial_id,
                           const std::function<void(const test::ScratchRoot&)>& add_room = {}) {
  test::ScratchRoot root;
  if (add_room) add_room(root);
  std::ifstream in(std::filesystem::path(TASKMATRIX_TEST_ROOT) / "scenarios" / "tasks" / task);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_FALSE(text.empty()) << task;
  text = std::regex_replace(text, std::regex("\n(robots|environments): [^\n]*"), "");
  root.write(task, text + "robots: [" + robot + "]\nenvironments: [" + environment + "]\n");
  return run_in_root(root, task, trial_id);
}

// The trial `trial_id` of the tidy task with each putdown written out as its position and
// release, without the withdrawal and rest that end a putdown: the robot greets with the hand
// that set the juice box down still round it, out over the side surface, as putdown left it
// until 2026-12-05. The situations greet's recovery is for (the base cannot turn, the arms
// cannot come down) arise here; a putdown now avoids most of them.
std::string unstowed_tidy_trial(const std::string& robot, const std::string& environment,
                                const std::string& trial_id) {
  test::ScratchRoot root;
  std::ifstream in(std::filesystem::path(TASKMATRIX_TEST_ROOT) / "scenarios" / "tasks" /
                   "tidy.yaml");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  text = std::regex_replace(text, std::regex("\n(robots|environments): [^\n]*"), "");
  for (const std::string object : {"cup", "box"}) {
    const std::string place = "place_" + object, let_go = "let_go_" + object;
    const std::string putdown = "    " + place + ": {program: putdown, params: {object: " + object +
                                ", surface: $surface}}\n";
    const size_t at = text.find(putdown);
    EXPECT_NE(at, std::string::npos) << putdown;
    if (at == std::string::npos) return "";
    text.replace(at, putdown.size(),
                 "    " + place + ": {program: position, params: {object: " + object +
                     ", frame: origin, on: $surface, height: 0.01}}\n    " + let_go +
                     ": {program: release, params: {object: " + object + "}}\n");
    text = std::regex_replace(text, std::regex("\\{from: " + place + ", on: completed, to: "),
                              "{from: " + place + ", on: completed, to: " + let_go +
                                  "}\n    - {from: " + let_go + ", on: completed, to: ");
  }
  root.write("tidy.yaml", text + "robots: [" + robot + "]\nenvironments: [" + environment + "]\n");
  return run_in_root(root, "tidy.yaml", trial_id);
}

// The trial succeeded, and `program` ran in it (the case the test describes).
void expect_success_running(const std::string& trials, const std::string& program) {
  EXPECT_NE(trials.find("\"status\":\"success\""), std::string::npos) << trials.substr(0, 2000);
  EXPECT_NE(trials.find("\"program\":\"" + program + "\",\"t\""), std::string::npos)
      << "not the case described: " << trials.substr(0, 2000);
}

// Another task the programs were not written for: carry the juice box and the cup from the
// side surface to the work surface, then look the work surface over. The trial `trial_id` of
// it for `robot` in `environment`; its trials.jsonl.
std::string restock_trial(const std::string& robot, const std::string& environment,
                          const std::string& trial_id) {
  test::ScratchRoot root;
  root.write("restock.yaml", R"(machine:
  name: restock
  initial: take_box
  states:
    take_box: {program: pickup, params: {object: box}}
    place_box: {program: putdown, params: {object: box, surface: work_surface}}
    take_cup: {program: pickup, params: {object: cup}}
    place_cup: {program: putdown, params: {object: cup, surface: work_surface}}
    look: {program: explore, params: {surface: work_surface, coverage: 0.8}}
    done: {final: success}
  transitions:
    - {from: take_box, on: completed, to: place_box}
    - {from: place_box, on: completed, to: take_cup}
    - {from: take_cup, on: completed, to: place_cup}
    - {from: place_cup, on: completed, to: look}
    - {from: look, on: completed, to: done}
params: {}
robots: [)" + robot + R"(]
environments: [)" + environment + R"(]
perception: ground_truth
obstacles: {count: 8}
objects:
  box: {on: side_surface, yaw: [-3.14159, 3.14159]}
  cup: {on: side_surface, yaw: [-3.14159, 3.14159]}
robot_start: {x: [-0.05, 0.05], y: [-0.10, 0.10], yaw: [-0.15, 0.15]}
layout_seed: 900
seed: 1
trials: 4
visitor: {walk_speed: 0.4}
time_limit_s: 200
success: all_of(above(cup, work_surface), above(box, work_surface))
)");
  return run_in_root(root, "restock.yaml", trial_id);
}

// A robot wedged under furniture (a wheeled robot that lowered its torso to set something
// down under a table's edge) found the visitor but could not raise its arm: greet went to find
// the visitor again and raised the same arm from the same place, and failed
// (`greet > postural(raise_again): planning_timeout`). Constructed: a shelf board 3 cm above
// tallbot's head, over its front, so that either arm's wave_start puts the hand in it. The
// raise fails with the visitor in view; greet now steps back from the nearest surface (the
// shelf), brings the arms to rest, finds the visitor and raises and waves from there. Before:
// 0 of 4 (`postural(raise_again): invalid_goal: ... touches shelf_board`).
TEST(GreetUnderAShelf, AnArmThatCannotRiseWithTheTargetInViewStepsBackAndWaves) {
  test::ScratchRoot root;
  root.replace("models/environments/kitchen/kitchen.xml", "    <body name=\"counter\"",
               "    <body name=\"shelf\" pos=\"0.3 0 1.765\"><geom name=\"shelf_board\" "
               "type=\"box\" size=\"0.3 0.8 0.015\"/></body>\n    <body name=\"counter\"");
  root.replace("models/environments/kitchen/environment.yaml",
               "  side_surface:", "  overhead: {body: shelf, kind: surface}\n  side_surface:");
  root.write("greet.yaml", R"(program: greet
params: {target: visitor}
robots: [tallbot]
environments: [kitchen]
perception: ground_truth
layout_seed: 1
seed: 1
trials: 4
time_limit_s: 40
visitor: {walk_speed: 0.0}
success: in_view(visitor)
)");
  const std::string trials = run_in_root(root, "greet.yaml");
  size_t lines = 0;
  std::istringstream in(trials);
  for (std::string line; std::getline(in, line);) {
    if (line.empty()) continue;
    ++lines;
    EXPECT_NE(line.find("\"success\":true"), std::string::npos) << line.substr(0, 2000);
    // The case described: the first raise failed against the shelf, then the step back.
    EXPECT_NE(line.find("touches shelf_board"), std::string::npos) << line.substr(0, 2000);
    EXPECT_NE(line.find("\"program\":\"retreat\""), std::string::npos) << line.substr(0, 2000);
  }
  EXPECT_EQ(lines, 4u) << trials.substr(0, 2000);
}

// After setting the cup down beside the box, tallbot's thumb rested 0.3 mm against the box,
// and every viewpoint's plan (the base and torso carrying the arm) started in collision:
// `coverage_short: observed 15 of 336 cells ...; the viewpoints that would show more cannot
// be reached (invalid_start: ... l_thumb_dist touches box_body ...)`. explore's plans may now
// leave what a hand touches at their start, as retreat's may.
TEST(ExploreAfterAPutdown, AHandLeftAgainstWhatItSetDownDoesNotPinTheRobot) {
  const std::string trials =
      restock_trial("tallbot", "kitchen", "restock.tallbot.kitchen.RRTConnect.l900.s1");
  expect_success_running(trials, "explore");
  EXPECT_EQ(trials.find("invalid_start"), std::string::npos) << trials.substr(0, 2000);
}

// atlas's first look over the desk showed 90% of it, more than the 80% asked for, and explore
// still sought a viewpoint; none could be reached, and it failed with `coverage_short:
// observed 351 of 390 cells (coverage 0.9, target 0.8)` (restock, office, layout 903). A
// region seen whole at the first look failed the same way: no viewpoint showed anything new.
// A first look that is enough now completes explore.
TEST(ExploreAFewCellsInView, AFirstLookThatIsEnoughCompletes) {
  test::ScratchRoot root;
  root.write("look.yaml", R"(program: explore
params: {bounds: ["0.45", "0.55", "-0.05", "0.05", "0.65"], cell_m: 0.05, coverage: 0.9}
robots: [tallbot]
environments: [kitchen]
obstacles: {count: 0}
layout_seed: 1
seed: 1
trials: 1
time_limit_s: 30
)");
  const std::string trials = run_in_root(root, "look.yaml");
  EXPECT_NE(trials.find("\"status\":\"success\""), std::string::npos) << trials.substr(0, 2000);
}

// A task the programs were not written for, as a user writes it: carry the cup and the juice
// box to the side surface, then greet. After the putdown atlas stands against the counter,
// its torso bent: finding the visitor, every base turn was refused (a hand would sweep into the
// counter), and fixate waited until the scenario's time limit; the arms' rest was in collision
// with the torso still bent. Now fixate fails after 2 s of refused turns, greet steps back from
// the counter and finds the visitor again, and lowering, refused, steps back and brings the
// torso upright with the arms (kitchen, layout 207). Since putdown brings the arms to rest,
// the task's own trials rarely meet this: the case is built with the putdowns written out as
// position and release (office, layout 218).
TEST(GreetAfterAPutdown, StepsBackWhenTheBaseCannotTurnOrTheArmsCannotComeDown) {
  if (!std::filesystem::exists(test::catalog().robot_dir("atlas"))) {
    GTEST_SKIP() << "no atlas in " << test::catalog().root();
  }
  const std::string trials =
      unstowed_tidy_trial("atlas", "office", "tidy.atlas.office.RRTConnect.l218.s19");
  EXPECT_NE(trials.find("\"status\":\"success\""), std::string::npos) << trials.substr(0, 2000);
  EXPECT_NE(trials.find("the base cannot turn towards 'visitor'"), std::string::npos)
      << "not the case described: " << trials.substr(0, 2000);
  EXPECT_NE(trials.find("\"program\":\"postural\",\"reason\":"), std::string::npos)
      << "not the case described (the arms' rest refused): " << trials.substr(0, 2000);
  EXPECT_NE(trials.find("\"program\":\"retreat\""), std::string::npos);
}

// Stepping straight back from the counter, atlas's right hand, still round the juice box it
// had set down, was blocked, and every plan ran out of iterations (office, layout 202). Now
// a hand close to something withdraws first, and where the straight step is still taken the
// step goes in a direction turned from it. (The putdowns written out as position and release,
// as putdown was then.)
TEST(GreetAfterAPutdown, AHandRoundWhatItSetDownWithdrawsBeforeTheRobotStepsBack) {
  if (!std::filesystem::exists(test::catalog().robot_dir("atlas"))) {
    GTEST_SKIP() << "no atlas in " << test::catalog().root();
  }
  const std::string trials =
      unstowed_tidy_trial("atlas", "office", "tidy.atlas.office.RRTConnect.l202.s3");
  expect_success_running(trials, "retreat");
}

// atlas put the juice box down next to the cup it had just set on the counter: the six nearest
// placements drawn all lay round the cup, and every IK solution had the box in the cup (`box
// reaches none of 36 targets ... all in collision (first: cup_shell touches box_body)`, kitchen
// 204). Placements at least 1 cm clear of other objects' boxes now come first.
TEST(TidyTheTable, TheJuiceBoxGoesBesideTheCupNotIntoIt) {
  if (!std::filesystem::exists(test::catalog().robot_dir("atlas"))) {
    GTEST_SKIP() << "no atlas in " << test::catalog().root();
  }
  const std::string trials =
      run_task_trial("tidy.yaml", "atlas", "kitchen", "tidy.atlas.kitchen.RRTConnect.l204.s5");
  EXPECT_NE(trials.find("\"status\":\"success\""), std::string::npos) << trials.substr(0, 2000);
}

// After stepping back, minibot's arm still lay out over the counter where it had set the juice
// box down, and each base turn towards the visitor swept it into the counter: not centred
// after 20 s (kitchen, layout 201). greet now brings the arms down before finding again.
// (The putdowns written out as position and release, as putdown was then.)
TEST(GreetAfterAPutdown, TheArmsComeDownBeforeTheBaseTurnsToTheVisitorAgain) {
  const std::string trials =
      unstowed_tidy_trial("minibot", "kitchen", "tidy.minibot.kitchen.RRTConnect.l201.s2");
  expect_success_running(trials, "retreat");
}

// The walking visitor left minibot's view while it waved (office, layout 204): the wave's
// invariant in_view(visitor) stopped it. greet finds the visitor again, base and head, and
// raises the arm and waves once more. (Since putdown's placements keep clear of other objects
// the box goes elsewhere in that world and the visitor stays in view. Since placed objects
// start 0.1 mm above their surface, office 200 no longer has the visitor leave the view;
// kitchen 218, a world beyond the task's eight, did; since putdown brings the arms to rest,
// kitchen 209 with the putdowns written out as position and release does.)
TEST(GreetAfterAPutdown, FindsAVisitorWhoWalkedOutOfViewAndWavesAgain) {
  const std::string trials =
      unstowed_tidy_trial("minibot", "kitchen", "tidy.minibot.kitchen.RRTConnect.l209.s10");
  EXPECT_NE(trials.find("\"status\":\"success\""), std::string::npos) << trials.substr(0, 2000);
  const std::regex halted("\"program\":\"canned\",\"t\":[-0-9.e+]+,\"type\":\"halted\"");
  const std::regex completed("\"program\":\"canned\",\"t\":[-0-9.e+]+,\"type\":\"completed\"");
  auto count = [&](const std::regex& re) {
    return std::distance(std::sregex_iterator(trials.begin(), trials.end(), re),
                         std::sregex_iterator());
  };
  EXPECT_EQ(count(halted), 1) << "not the case described: " << trials.substr(0, 2000);
  EXPECT_EQ(count(completed), 1);
}

// After the juice box went onto the counter, atlas stood between the counter and the table:
// the base could not turn to the visitor, nor after one step back from the counter (`the base
// cannot turn towards 'visitor' without touching something (107 degrees still to turn)`,
// kitchen 202). greet steps back once more, from whatever is nearest then, and looks again.
// (The putdowns written out as position and release, as putdown was then.)
TEST(GreetAfterAPutdown, StepsBackOnceMoreWhenOneStepLeavesItWedged) {
  if (!std::filesystem::exists(test::catalog().robot_dir("atlas"))) {
    GTEST_SKIP() << "no atlas in " << test::catalog().root();
  }
  const std::string trials =
      unstowed_tidy_trial("atlas", "kitchen", "tidy.atlas.kitchen.RRTConnect.l202.s3");
  EXPECT_NE(trials.find("\"status\":\"success\""), std::string::npos) << trials.substr(0, 2000);
  auto count = [&](const std::string& program, const std::string& type) {
    const std::regex re("\"program\":\"" + program +
                        "\",(\"reason\":\"[^\"]*\",)?\"t\":[-0-9.e+]+,\"type\":\"" + type + "\"");
    return std::distance(std::sregex_iterator(trials.begin(), trials.end(), re),
                         std::sregex_iterator());
  };
  EXPECT_EQ(count("fixate", "failed"), 2) << "not the case described: " << trials.substr(0, 2000);
  EXPECT_EQ(count("retreat", "completed"), 2);
}

// A task written as a user writes one: pick the cup up, greet the visitor holding it, then set
// it on the side surface. greet's rest posture took every limb, the arm carrying the cup too:
// that arm came down to the robot's side with its hand opened to rest, and putdown then found
// no stance (`putdown(place) > position(place): ik_failure: cup reaches none of 36 targets`;
// minibot 0 of 12 in three rooms, 22 of 48 over four robots). An arm whose hand holds
// something is taken: greet waves the other and leaves it as it is.
TEST(GreetHoldingACup, WavesTheFreeArmAndKeepsTheCupForThePutdown) {
  test::ScratchRoot root;
  root.write("serve.yaml", R"(machine:
  name: serve
  initial: take_cup
  states:
    take_cup: {program: pickup, params: {object: cup}}
    show: {program: greet, params: {target: visitor}}
    place: {program: putdown, params: {object: cup, surface: side_surface}}
    done: {final: success}
  transitions:
    - {from: take_cup, on: completed, to: show}
    - {from: show, on: completed, to: place}
    - {from: place, on: completed, to: done}
params: {}
robots: [minibot]
environments: [kitchen]
perception: ground_truth
obstacles: {count: 8}
objects:
  cup: {on: work_surface, yaw: [-3.14159, 3.14159]}
  box: {on: work_surface, yaw: [-3.14159, 3.14159]}
surfaces:
  work_surface: {height_m: [0.62, 0.80]}
robot_start: {x: [-0.05, 0.05], y: [-0.10, 0.10], yaw: [-0.15, 0.15]}
layout_seed: 1300
seed: 1
trials: 2
visitor: {walk_speed: 0.3}
time_limit_s: 200
success: all_of(above(cup, side_surface), near(cup, side_surface))
)");
  const std::string trials = run_in_root(root, "serve.yaml");
  size_t lines = 0;
  std::istringstream in(trials);
  for (std::string line; std::getline(in, line);) {
    if (line.empty()) continue;
    ++lines;
    EXPECT_NE(line.find("\"success\":true"), std::string::npos) << line.substr(0, 2000);
    EXPECT_NE(line.find("\"program\":\"canned\",\"t\""), std::string::npos)
        << "not the case described (no wave): " << line.substr(0, 2000);
  }
  EXPECT_EQ(lines, 2u) << trials.substr(0, 2000);
}

// The cup stood beyond the middle of the table, and minibot's reach planned the base round the
// table and on, 2 m out, into the route the visitor walks (the visitor was at its other end
// then): a finger met the visitor (`restock > pickup(take_cup) > reach: collision: collision of
// LFinger2ProxLink with visitor (depth 0.6 mm)`, kitchen 900; atlas's upper arm the same in
// chores, kitchen 503). Plans, IK and is_valid now keep off the visitor's route.
TEST(RestockBesideAWalkingVisitor, ThePlansKeepOffTheVisitorsRoute) {
  const std::string trials = run_task_trial("restock.yaml", "minibot", "kitchen",
                                            "restock.minibot.kitchen.RRTConnect.l900.s1");
  EXPECT_NE(trials.find("\"status\":\"success\""), std::string::npos) << trials.substr(0, 2000);
  EXPECT_EQ(trials.find("with visitor"), std::string::npos) << trials.substr(0, 2000);
}

// atlas picked the juice box up from the side table, the cup standing beside it (office,
// layout 902); lifting the box off the table before carrying it to the desk, the straight
// escape IK solved swung its hand into the cup (`restock > putdown(place_box) >
// position(place): collision: collision of l_hand with cup (depth 0.0 mm)`): IK keeps no
// clearance. An escape step that touches anything the start did not is no longer taken (a
// planned way to a clear posture instead).
TEST(RestockOnAtlas, TheEscapeThatLiftsTheBoxDoesNotSwingTheHandIntoTheCup) {
  const std::string trials =
      run_task_trial("restock.yaml", "atlas", "office", "restock.atlas.office.RRTConnect.l902.s3");
  EXPECT_NE(trials.find("\"status\":\"success\""), std::string::npos) << trials.substr(0, 2000);
}

// Another: park the juice box on the side surface, vacuum the work surface, then step back
// from it (retreat) and look it over. After the vacuum was set down minibot's hand lay open
// round its handle a few millimetres over the table: the straight step back was clear at every
// checked state, yet its plan (the base alone) ran out of iterations, and retreat failed at
// once, the hand never withdrawn (kitchen, layout 1503); where the hand had withdrawn and every
// base-only plan still failed (layout 1501: the hand keeps its height over the table as the
// base moves, short of the clearance plans keep away from their ends), nothing else was tried.
// A straight step whose plan fails now goes on to the withdrawal and the other directions, and
// last the base moves with the torso and the arms, which may rise on the way.
TEST(RetreatAfterTheVacuum, AHandOpenRoundTheHandleWithdrawsAndTheBodyStepsBack) {
  test::ScratchRoot root;
  root.write("sweep.yaml", R"(machine:
  name: sweep
  initial: take_box
  states:
    take_box: {program: pickup, params: {object: box}}
    park_box: {program: putdown, params: {object: box, surface: side_surface}}
    clean: {program: vacuum, params: {}}
    step_back: {program: retreat, params: {part: base}}
    done: {final: success}
  transitions:
    - {from: take_box, on: completed, to: park_box}
    - {from: park_box, on: completed, to: clean}
    - {from: clean, on: completed, to: step_back}
    - {from: step_back, on: completed, to: done}
params: {}
robots: [minibot]
environments: [kitchen]
perception: ground_truth
obstacles: {count: 8}
objects:
  vacuum: {on: work_surface, yaw: [-0.5, 0.5]}
  box: {on: work_surface, yaw: [-3.14159, 3.14159]}
surfaces:
  work_surface: {height_m: [0.62, 0.78]}
robot_start: {x: [-0.05, 0.05], y: [-0.10, 0.10], yaw: [-0.15, 0.15]}
layout_seed: 1500
seed: 1
trials: 4
visitor: {walk_speed: 0.3}
time_limit_s: 200
success: all_of(above(box, side_surface), not(exists(debris)))
)");
  for (const char* id :
       {"sweep.minibot.kitchen.RRTConnect.l1501.s2", "sweep.minibot.kitchen.RRTConnect.l1503.s4"}) {
    const std::string trials = run_in_root(root, "sweep.yaml", id);
    EXPECT_NE(trials.find("\"success\":true"), std::string::npos)
        << id << ": " << trials.substr(0, 2000);
    std::filesystem::remove_all(root.path() / "run");
  }
}

// Runs the scenario `text` (written as `file`) in a scratch copy of the kitchen whose robot
// starts at `start` (the environment file's robot_start line); expects it to succeed.
void expect_success_in_kitchen_starting_at(const std::string& start, const std::string& file,
                                           const std::string& text,
                                           const std::string& floor_region = "") {
  test::ScratchRoot root;
  const std::string env = "models/environments/kitchen/environment.yaml";
  root.replace(env, "robot_start: {x: 0.0, y: 0.0, yaw: 0.0}", "robot_start: " + start);
  if (!floor_region.empty()) {
    root.replace(env, "- {name: floor, x: [1.15, 3.1]", "- {name: floor, x: " + floor_region);
  }
  root.write(file, text);
  const std::string trials = run_in_root(root, file);
  EXPECT_NE(trials.find("\"status\":\"success\""), std::string::npos) << trials.substr(0, 2000);
}

// A scratch root whose kitchen also holds a mug (9 cm across, a handle sticking out 3 cm) and
// an 8 cm ball on its table: objects the programs were never written for.
void add_mug_and_ball_to_the_kitchen(const test::ScratchRoot& root) {
  root.replace("models/environments/kitchen/kitchen.xml", "    <body name=\"box\"",
               R"(    <body name="mug" pos="0.5 0.35 0.7">
      <freejoint name="mug_free"/>
      <geom name="mug_shell" type="cylinder" size="0.045 0.05" mass="0.3" friction="1 0.01 0.001"/>
      <geom name="mug_handle" type="box" pos="0.06 0 0" size="0.015 0.006 0.03" mass="0.02" friction="1 0.01 0.001"/>
    </body>
    <body name="ball" pos="0.75 0.3 0.69">
      <freejoint name="ball_free"/>
      <geom name="ball_body" type="sphere" size="0.04" mass="0.15" friction="1 0.01 0.001"/>
    </body>
    <body name="box")");
  root.replace(
      "models/environments/kitchen/environment.yaml", "  box: ",
      "  mug: {body: mug, kind: graspable}\n  ball: {body: ball, kind: graspable}\n  box: ");
}

// Pickup of `object` by `robot` in that kitchen, both objects placed at random on the table
// (layout `layout`, seed `seed`); the trial's record.
std::string pick_up_in_a_kitchen_with_a_mug_and_a_ball(const std::string& object,
                                                       const std::string& robot, int layout,
                                                       int seed) {
  test::ScratchRoot root;
  add_mug_and_ball_to_the_kitchen(root);
  root.write("pickup.yaml", "program: pickup\nparams: {object: " + object + "}\nrobots: [" + robot +
                                R"(]
environments: [kitchen]
obstacles: {count: 8}
objects:
  mug: {on: work_surface, yaw: [-3.14159, 3.14159]}
  ball: {on: work_surface}
layout_seed: )" + std::to_string(layout) +
                                "\nseed: " + std::to_string(seed) + R"(
trials: 1
time_limit_s: 60
success: grasping()" + object + ")\n");
  return run_in_root(root, "pickup.yaml");
}

// Every side grasp of the ball's middle put atlas's wrist on the table (`8 solutions found, all
// in collision (first: l_wrist_mount touches table_top (depth 0.4 mm))`) and every grasp from
// above its fingers: 0 of 8 layouts. Side grasps 2 cm higher up come last: 8 of 8.
TEST(ObjectsNeverSeen, AtlasPicksUpABallFromTheTable) {
  if (!std::filesystem::exists(test::catalog().robot_dir("atlas"))) {
    GTEST_SKIP() << "no atlas in " << test::catalog().root();
  }
  const std::string trials = pick_up_in_a_kitchen_with_a_mug_and_a_ball("ball", "atlas", 900, 1);
  EXPECT_NE(trials.find("\"status\":\"success\""), std::string::npos) << trials.substr(0, 2000);
}

// minibot's palm ended beside the mug's handle, outside the 3 cm round the mug's centre and
// outside its box (`the left palm reached its target but 'mug' is not graspable from there`).
// A hand is now taken to the handle on its own, and graspable() finds a palm within 3 cm of
// one of an object's parts.
TEST(ObjectsNeverSeen, MinibotPicksUpAMugByItsHandle) {
  const std::string trials = pick_up_in_a_kitchen_with_a_mug_and_a_ball("mug", "minibot", 903, 4);
  EXPECT_NE(trials.find("\"status\":\"success\""), std::string::npos) << trials.substr(0, 2000);
}

// A jar 104 mm across, wider than the spread of tallbot's fingers' roots (80 mm): before,
// `not_graspable: the left hand (aperture 80 mm) spans no grasp of 'jar'` in each of 4 layouts.
// Its fingers curl round the jar (HandGeometry::wraps), and it picks it up in each of those 4
// (this is the first).
TEST(ObjectsNeverSeen, TallbotWrapsAJarWiderThanItsFingersSpread) {
  test::ScratchRoot root;
  root.replace("models/environments/kitchen/kitchen.xml", "    <body name=\"box\"",
               R"(    <body name="jar" pos="0.5 0.35 0.8">
      <freejoint name="jar_free"/>
      <geom name="jar_shell" type="cylinder" size="0.052 0.06" mass="0.3" friction="1 0.01 0.001"/>
    </body>
    <body name="box")");
  root.replace("models/environments/kitchen/environment.yaml",
               "  box: ", "  jar: {body: jar, kind: graspable}\n  box: ");
  root.write("pickup.yaml", R"(program: pickup
params: {object: jar}
robots: [tallbot]
environments: [kitchen]
obstacles: {count: 8}
objects:
  jar: {on: work_surface, yaw: [-3.14159, 3.14159]}
layout_seed: 900
seed: 1
trials: 1
time_limit_s: 60
success: grasping(jar)
)");
  const std::string trials = run_in_root(root, "pickup.yaml");
  EXPECT_NE(trials.find("\"status\":\"success\""), std::string::npos) << trials.substr(0, 2000);
}

// The generalization suite's drawn world, as scenario text: ground-truth perception, 8 random
// obstacles, the vacuum, cup and juice box placed at random on the work surface; and its start
// drawn round the environment's.
constexpr const char* kDrawnWorld = R"(perception: ground_truth
obstacles: {count: 8}
objects:
  vacuum: {on: work_surface, yaw: [-0.5, 0.5]}
  cup: {on: work_surface, yaw: [-3.14159, 3.14159]}
  box: {on: work_surface, yaw: [-3.14159, 3.14159]}
)";
constexpr const char* kDrawnStart =
    "robot_start: {x: [-0.05, 0.05], y: [-0.10, 0.10], yaw: [-0.15, 0.15]}\n";

// The robot `robot` of tests/data/robots (copied into a scratch root) reaching for the cup in
// the kitchen as the generalization suite draws it, the table's top drawn from `heights`
// ("min, max", m); the trials.jsonl of layout `layout_seed` (seed: layout_seed - 99, as the
// suite numbers its trials).
std::string never_seen_robot_reach_trial(const std::string& robot, const std::string& heights,
                                         int layout_seed) {
  test::ScratchRoot root;
  const std::filesystem::path data =
      std::filesystem::path(TASKMATRIX_TEST_ROOT) / "tests" / "data" / "robots" / robot;
  std::filesystem::copy(data, root.path() / "models" / "robots" / robot);
  root.write("reach.yaml", "program: reach\nparams: {object: cup}\nrobots: [" + robot +
                               "]\nenvironments: [kitchen]\n" + kDrawnWorld +
                               "surfaces:\n  work_surface: {height_m: [" + heights + "]}\n" +
                               kDrawnStart + "layout_seed: " + std::to_string(layout_seed) +
                               "\nseed: " + std::to_string(layout_seed - 99) + R"(
trials: 1
time_limit_s: 30
success: graspable(cup)
)");
  return run_in_root(root, "reach.yaml");
}

// valbot (tests/data/robots/valbot: NASA Valkyrie's public kinematics, a robot the programs
// were not written for) reaching for the cup on a 0.77 m table (kitchen, layout 101 of the
// generalization suite's draws with tables of 0.76-0.80 m): the stance search's two passes
// found IK solutions only into collision, a hair from the grasp poses, at the stances nearest
// the table (`ik_failure ... stepping: no stance found`). A third pass, the nearest stances
// again with more IK starts, finds one that is clear.
TEST(RobotsNeverSeen, ValbotReachesACupOnAHighTableFromAStanceSearchedAgain) {
  const std::string trials = never_seen_robot_reach_trial("valbot", "0.76, 0.80", 101);
  EXPECT_NE(trials.find("\"status\":\"success\""), std::string::npos) << trials.substr(0, 2000);
}

// g1bot (tests/data/robots/g1bot: the Unitree G1's public kinematics, 1.32 m, a waist of three
// joints, no neck, hands of a thumb and two fingers; a robot the programs were not written
// for) reaching for the cup in the kitchen as the generalization suite draws it; the trials.jsonl
// of layout `layout_seed`.
std::string g1bot_reach_trial(int layout_seed) {
  return never_seen_robot_reach_trial("g1bot", "0.55, 0.80", layout_seed);
}

// The cup 0.85 m ahead on a 0.56 m table: the stance search put the base where the thighs pass
// through the table's top, which MuJoCo 2.2.2's capsule-box function reports as no contact, so
// every such stance passed as valid and the planner spent its 10,000 iterations on each
// (`approximate_solution`). Now a capsule whose axis is inside a box touches it
// (collide_geoms), and the robot reaches from a stance clear of the table.
TEST(RobotsNeverSeen, G1ReachesACupAcrossALowTableFromAStanceClearOfIt) {
  const std::string trials = g1bot_reach_trial(119);
  EXPECT_NE(trials.find("\"status\":\"success\""), std::string::npos) << trials.substr(0, 2000);
}

// The G1's hands, at rest, reach forward of its base at the table's height: from the start
// drawn first in layout 116 its fingers touched the table's top, and the whole run stopped
// (`cannot lay out trial ...: at the start left_index_0 touches table_top`). Now the start is
// drawn again (its own stream; the table and the objects stay) and the record says which draw
// it is.
TEST(RobotsNeverSeen, AStartAtWhichTheG1TouchesTheTableIsDrawnAgain) {
  const std::string trials = g1bot_reach_trial(116);
  EXPECT_NE(trials.find("\"status\":\"success\""), std::string::npos) << trials.substr(0, 2000);
  EXPECT_NE(trials.find("\"robot_start\":{\"draw\":1,"), std::string::npos)
      << trials.substr(0, 2000);
}

// The trial `trial_id` of the tidy task for atlas in a room the programs were not written for
// (tests/data/environments/workshop: a 0.74 m bench with a shelf over its back, a steel cart to
// the robot's right as the side surface, a mug with a handle), the bench's top drawn from
// 0.65-0.80 m; its trials.jsonl.
std::string workshop_tidy_trial(const std::string& trial_id) {
  test::ScratchRoot root;
  const std::filesystem::path data =
      std::filesystem::path(TASKMATRIX_TEST_ROOT) / "tests" / "data" / "environments" / "workshop";
  std::filesystem::copy(data, root.path() / "models" / "environments" / "workshop");
  std::ifstream in(std::filesystem::path(TASKMATRIX_TEST_ROOT) / "scenarios" / "tasks" /
                   "tidy.yaml");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  text = std::regex_replace(text, std::regex("\n(robots|environments|trials|layout_seed): [^\n]*"),
                            "");
  text = std::regex_replace(text, std::regex("\nsurfaces:\n  work_surface: [^\n]*"), "");
  root.write("tidy.yaml", text + R"(robots: [atlas]
environments: [workshop]
surfaces: {work_surface: {height_m: [0.65, 0.80]}}
layout_seed: 200
trials: 6
)");
  return run_in_root(root, "tidy.yaml", trial_id);
}

// atlas set the juice box down on the cart beside the mug; the rest posture from there put its
// wrist into the bench, and its open hand, drawn back against its approach and carried back as
// the base stepped away, dragged the box, which knocked the mug off the cart
// (`criterion_false: above(cup, side_surface)`). Now putdown lifts the hand straight off what
// it let go of before the arms come to rest, and a base stepping back first lifts a hand off
// any object (not a surface) it touches.
TEST(RoomsNeverSeen, TheBoxSetDownOnTheCartStaysThereWhenTheRobotStepsBack) {
  const std::string trials = workshop_tidy_trial("tidy.atlas.workshop.RRTConnect.l203.s4");
  EXPECT_NE(trials.find("\"status\":\"success\""), std::string::npos) << trials.substr(0, 3000);
}

// minibot took the cup for the tidy task (layout 202) with its left upper arm resting on its
// torso; in the kitchen with the counter behind it (test::add_kitchen_counter_behind), putdown's
// first step lifted the cup, and the lift's IK, which may touch what the start touches, pressed
// the upper arm 2.5 mm further into the torso. Physics stopped it there: `tidy >
// putdown(place_cup) > position(place): tracking_error: 0.0128 from the goal after 1.00 s of
// settling (joint 'LShoulderRoll' at -0.1890, sent to -0.2018)`. An escape step no longer
// presses deeper than 1 mm into what its start touches.
TEST(RoomsNeverSeen, ALiftDoesNotPressTheUpperArmIntoTheTorsoItRestsOn) {
  const std::string trials = run_task_trial("tidy.yaml", "minibot", "kitchen_behind",
                                            "tidy.minibot.kitchen_behind.RRTConnect.l202.s3",
                                            test::add_kitchen_counter_behind);
  EXPECT_NE(trials.find("\"status\":\"success\""), std::string::npos) << trials.substr(0, 3000);
}

// The trial `trial_id` of the vacuum program for atlas in a room the programs were not
// written for: the kitchen with its table turned 20 degrees (test::add_turned_kitchen), the
// vacuum, cup and juice box drawn on the table, its height drawn from 0.62-0.78 m; its
// trials.jsonl. Expects every object drawn on the table itself (its origin inside the table's
// turned rectangle), not in the corners of the table's world-aligned box.
std::string turned_kitchen_vacuum_trial(const std::string& trial_id) {
  test::ScratchRoot root;
  test::add_turned_kitchen(root);
  root.write("vacuum.yaml", std::string(R"(program: vacuum
params: {tool: vacuum, surface: work_surface}
robots: [atlas]
environments: [kitchen_turned]
)") + kDrawnWorld + "surfaces: {work_surface: {height_m: [0.62, 0.78]}}\n" +
                                kDrawnStart +
                                R"(layout_seed: 500
seed: 1
trials: 6
time_limit_s: 90
success: all_of(not(exists(debris)), not(grasping(vacuum)), above(vacuum, work_surface))
)");
  const std::string trials = run_in_root(root, "vacuum.yaml", trial_id);
  const std::regex drawn(
      "\"(box|cup|vacuum)\":\\{\"on\":\"work_surface\",\"x\":([-0-9.e]+),\"y\":([-0-9.e]+)");
  int objects = 0;
  for (std::sregex_iterator it(trials.begin(), trials.end(), drawn), end; it != end; ++it) {
    const Eigen::Vector2d at =
        Eigen::Rotation2Dd(-0.35) *
        (Eigen::Vector2d(std::stod((*it)[2].str()), std::stod((*it)[3].str())) -
         Eigen::Vector2d(0.75, 0));
    EXPECT_LT(std::abs(at.x()), 0.35) << (*it)[1] << " drawn off the table";
    EXPECT_LT(std::abs(at.y()), 0.6) << (*it)[1] << " drawn off the table";
    ++objects;
  }
  EXPECT_EQ(objects, 3) << trials.substr(0, 3000);
  return trials;
}

// On the kitchen's table turned 20 degrees, objects drawn in the corners of the table's
// world-aligned box, and placements chosen there, fell to the floor (atlas's vacuum, layout
// 504: `criterion_false: above(vacuum, work_surface): vacuum's bottom is 17.0 cm below`; 163 of
// 234 trials of the twelve programs on the three robots succeeded in that room). The
// scenario's objects are now drawn on the table itself and the vacuum is set back on it.
TEST(RoomsNeverSeen, OnATableTurnedInTheRoomTheVacuumIsDrawnAndSetBackOnIt) {
  const std::string trials =
      turned_kitchen_vacuum_trial("vacuum.atlas.kitchen_turned.RRTConnect.l504.s5");
  EXPECT_NE(trials.find("\"status\":\"success\""), std::string::npos) << trials.substr(0, 3000);
}

// The vacuum drawn on the turned table, resting, was thrown into the air at the first step:
// MuJoCo 2.2.2's box-box function reported its battery 0.29-1.09 m deep in the table's top
// (layout 503, every robot: `not_graspable: ... (did it move?)`). A box-box contact now gets
// no more depth than the two boxes overlap along its normal.
TEST(RoomsNeverSeen, AVacuumRestingOnATurnedTableStaysWhereItWasDrawn) {
  const std::string trials =
      turned_kitchen_vacuum_trial("vacuum.atlas.kitchen_turned.RRTConnect.l503.s4");
  EXPECT_NE(trials.find("\"status\":\"success\""), std::string::npos) << trials.substr(0, 3000);
}

// Over a 0.45 m table the palm of tallbot with the stiffer waist it had until 2026-12-06 (pitch
// at most 0.8 rad) gets nowhere (models/README.md): the first round of grasps finds no way, the
// second (side grasps 2 cm higher) neither, and the reason says both. tallbot as it is, its
// waist bending to 1.4 rad, picks that cup up.
TEST(ObjectsNeverSeen, AReachWhoseBothRoundsFailSaysWhatEachFound) {
  const auto pickup_from_a_low_table = [](const test::ScratchRoot& root) {
    root.write("pickup.yaml", R"(program: pickup
params: {object: cup}
robots: [tallbot]
environments: [kitchen]
obstacles: {count: 8}
surfaces: {work_surface: {height_m: 0.45}}
layout_seed: 1
seed: 1
trials: 1
time_limit_s: 60
success: grasping(cup)
)");
    return run_in_root(root, "pickup.yaml");
  };
  test::ScratchRoot stiff;
  test::stiffen_tallbot_waist(stiff);
  const std::string trials = pickup_from_a_low_table(stiff);
  EXPECT_TRUE(std::regex_search(
      trials, std::regex("\"failure_reason\":\"pickup > reach: ik_failure: [^\"]* reaches none of "
                         "[0-9]+ targets[^\"]*; then 16 grasps higher up, wrapping or of a part: "
                         "ik_failure: [^\"]* reaches none of 32 targets")))
      << trials.substr(0, 3000);
  const std::string supple = pickup_from_a_low_table(test::ScratchRoot());
  EXPECT_NE(supple.find("\"status\":\"success\""), std::string::npos) << supple.substr(0, 3000);
}

// A room whose robot starts on the far side of the table, facing -x, and start headings drawn
// round that: past pi the robot stood outside its [-pi, pi] base yaw (`invalid_start: joint
// 'base_yaw' starts at 3.28, outside its limits`), and every arm program failed (tallbot,
// minibot and atlas: 38 of 156 trials of the twelve programs succeeded in such a kitchen). A
// base yaw whose range spans a full turn is now centred on the room's start heading (the
// slides on its start position).
TEST(ARoomFacingMinusX, TheRobotPicksUpTheCupFromTheFarSideOfTheTable) {
  // Obstacles on the floor keep off the robot's side of the table.
  expect_success_in_kitchen_starting_at("{x: 1.32, y: 0.0, yaw: 3.14159}", "pickup.yaml",
                                        R"(program: pickup
params: {object: cup}
robots: [tallbot]
environments: [kitchen]
obstacles: {count: 8}
objects: {cup: {on: work_surface, yaw: [-3.14, 3.14]}}
robot_start: {x: [-0.05, 0.05], y: [-0.1, 0.1], yaw: [0.1, 0.15]}
layout_seed: 601
seed: 2
trials: 1
time_limit_s: 60
success: grasping(cup)
)",
                                        "[1.95, 3.1]");
}

// A room whose robot stands at the long side of the table, the side surface across it: from
// there minibot's camera (no head pitch) saw 65-82% of the side surface (`coverage_short ...
// no viewpoint shows a cell not yet observed`) and explore gave up. When nothing from where it
// stands shows more, explore walks round the region.
TEST(ExploreAcrossTheTable, WalksRoundTheRegionWhenNothingFromHereShowsMore) {
  expect_success_in_kitchen_starting_at("{x: 0.65, y: -0.97, yaw: 1.5708}", "explore.yaml",
                                        R"(program: explore
params: {surface: side_surface, coverage: 0.9, cell_m: 0.05}
robots: [minibot]
environments: [kitchen]
obstacles: {count: 8}
layout_seed: 700
seed: 1
trials: 1
time_limit_s: 60
)");
}

// A room whose robot starts facing -x, the visitor behind it: fixate turns the base round to
// the visitor (the base yaw's range is centred on the start heading; before that, the start
// sat at the limit of a [-pi, pi] yaw and fixate had to turn the other way round).
TEST(FixateFacingAway, TurnsTheBaseTheOtherWayWhenTheShortWayIsPastItsYawLimit) {
  expect_success_in_kitchen_starting_at("{x: 0.0, y: 0.0, yaw: 3.14159}", "fixate.yaml",
                                        R"(program: fixate
params: {object: visitor, until_centered: true}
robots: [minibot]
environments: [kitchen]
obstacles: {count: 8}
layout_seed: 3
seed: 1
trials: 1
time_limit_s: 40
success: in_view(visitor)
)");
}

// fixate for a duration, with the base held, facing away from the cup on the table: the neck
// cannot turn the camera round to it. It completed all the same after its duration, though
// nothing was ever tracked (a task's "look at what was set down" then read as done; the swap
// task of the README, atlas with its base turn refused beside the desk). Now it fails
// and says so.
TEST(FixateForADuration, AnObjectNeverInViewIsAFailureThatSaysSo) {
  test::ScratchRoot root;
  root.replace("models/environments/kitchen/environment.yaml",
               "robot_start: {x: 0.0, y: 0.0, yaw: 0.0}",
               "robot_start: {x: 0.0, y: 0.0, yaw: 3.14159}");
  root.write("look.yaml", R"(program: fixate
params: {object: cup, duration: 1, base: false}
robots: [tallbot]
environments: [kitchen]
obstacles: {count: 0}
layout_seed: 1
seed: 1
trials: 1
time_limit_s: 10
)");
  const std::string trials = run_in_root(root, "look.yaml");
  EXPECT_NE(trials.find("\"status\":\"tracking_error\""), std::string::npos)
      << trials.substr(0, 2000);
  EXPECT_NE(trials.find("'cup' never in view in 1.0 s"), std::string::npos)
      << trials.substr(0, 2000);
}

// atlas has no neck yaw: only its base turns its camera towards the visitor walking behind it.
// fixate stepped the base's command on by what was still to turn, measured from a base that
// lags its command under physics, so the command ran ahead and the base swung 0.1 rad either
// side of the visitor, never centred for 0.3 s: each look ended `not centred after 20 s` and
// greet met its time limit (it greeted in 2 of 12 such layouts; now in 10). The base is now
// turned towards the heading that centres the visitor from where it stands.
TEST(GreetFacingAway, ABaseOnlyYawCentresTheVisitorWithoutSwingingPastIt) {
  if (!std::filesystem::exists(test::catalog().robot_dir("atlas"))) {
    GTEST_SKIP() << "no atlas in " << test::catalog().root();
  }
  expect_success_in_kitchen_starting_at("{x: 1.32, y: 0.0, yaw: 3.14159}", "greet.yaml",
                                        R"(program: greet
params: {target: visitor}
robots: [atlas]
environments: [kitchen]
perception: ground_truth
obstacles: {count: 8}
objects: {cup: {on: work_surface, yaw: [-3.14, 3.14]}}
surfaces: {work_surface: {height_m: [0.55, 0.80]}}
robot_start: {x: [-0.05, 0.05], y: [-0.10, 0.10], yaw: [-0.15, 0.15]}
layout_seed: 602
seed: 3
trials: 1
visitor: {walk_speed: 0.4}
time_limit_s: 40
success: in_view(visitor)
)",
                                        "[1.95, 3.1]");
}

// explore looked only within a radian of where the base faced and never moved the torso: a
// robot facing away from the surface, its torso left bent (after a putdown elsewhere in a
// task), saw at most a quarter of it (atlas: `coverage_short ... no viewpoint shows a cell not
// yet observed`). Viewpoints now also face the region's centre, and bring a bent torso back
// to its rest posture.
TEST(ExploreBehindTheRobot, TurnsToTheSurfaceAndStraightensABentTorso) {
  if (!std::filesystem::exists(test::catalog().robot_dir("atlas"))) {
    GTEST_SKIP() << "no atlas in " << test::catalog().root();
  }
  test::ScratchRoot root;
  root.write("explore.yaml", R"(doc: explore the work surface behind the robot, its torso bent
setup:
  - {program: postural, params: {posture: bow}}
program: explore
params: {surface: work_surface, coverage: 0.8}
robots: [atlas]
environments: [kitchen, office]
obstacles: {count: 8}
robot_start: {x: 0.0, y: 0.0, yaw: 2.8}
layout_seed: 3
seed: 1
trials: 1
time_limit_s: 60
)");
  const std::string trials = run_in_root(root, "explore.yaml");
  std::size_t successes = 0;
  for (std::size_t at = trials.find("\"status\":\"success\""); at != std::string::npos;
       at = trials.find("\"status\":\"success\"", at + 1)) {
    ++successes;
  }
  EXPECT_EQ(successes, 2u) << trials.substr(0, 3000);
}

// The chores task (scenarios/tasks/chores.yaml): after looking the work surface over, tallbot
// turned to find the visitor behind it with its right arm folded up beside its head, so its
// neck could not turn; fixate went on counting on the neck's goal, and the visitor's heading,
// just past the base yaw's limit, sent the base the other way round and back every few
// seconds: not centred after 20 s (kitchen, layout 503). A blocked neck now leaves the whole
// turn to the base, and once going round the base keeps going.
TEST(FixateWithABlockedNeck, TheBaseTakesUpTheWholeTurnAndKeepsItsDirection) {
  const std::string trials = run_task_trial("chores.yaml", "tallbot", "kitchen",
                                            "chores.tallbot.kitchen.RRTConnect.l503.s4");
  expect_success_running(trials, "explore");
}

// Lowering its arms after the wave, tallbot's left hand came down into the desk it had just
// looked over (office, layout 501: `invalid_goal: the goal configuration is in collision:
// desk_top touches l_palm ...`): greet had stepped back from the side table, the surface
// nearest its base, so the rest posture stayed in collision. retreat now steps away from the
// surface nearest the base or a hand.
TEST(GreetAfterLookingTheDeskOver, StepsBackFromTheSurfaceItsHandIsOver) {
  const std::string trials = run_task_trial("chores.yaml", "tallbot", "office",
                                            "chores.tallbot.office.RRTConnect.l501.s2");
  expect_success_running(trials, "retreat");
}

// After setting the cup on the counter, atlas stood between the counter and the table, its left
// side towards the table: the arms' rest put its left palm into the table's top. greet's step
// back went straight away from the surface nearest a hand (the counter), along the table, and
// the rest met the table again, deeper (chores, kitchen 503: `invalid_goal: ... table_top
// touches l_palm (depth 26.5 mm)`). Without `from` retreat steps away from every surface.
TEST(GreetBetweenTheCounterAndTheTable, StepsAwayFromBoth) {
  const std::string trials =
      run_task_trial("chores.yaml", "atlas", "kitchen", "chores.atlas.kitchen.RRTConnect.l503.s4");
  expect_success_running(trials, "retreat");
  // The case: the rest after the wave met the table before the step back.
  EXPECT_TRUE(std::regex_search(
      trials, std::regex("\"program\":\"postural\",\"reason\":\"invalid_goal: [^\"]*table_top")))
      << "not the case described: " << trials.substr(0, 2000);
}

// Lifting a held tool off the table before a plan: atlas's arm could not keep the hand's
// orientation exactly, and the nearest solution tipped the vacuum about the grip, pushing its
// battery 6 mm into the table, so the next plan started in collision.
TEST(PositionOnAtlas, AHeldToolIsLiftedWithoutTippingIntoTheTable) {
  if (!std::filesystem::exists(test::catalog().robot_dir("atlas"))) {
    GTEST_SKIP() << "no atlas in " << test::catalog().root();
  }
  Scenario s = program_scenario("position");
  s.execution = "kinematic";
  const TrialResult r =
      run_trial(s, *test::loaded_scene("atlas", "kitchen"), s.layout_seed, s.seed, registry());
  EXPECT_TRUE(r.success) << trial_status(r) << ": " << trial_failure_reason(r);
}

// atlas sets the cup down with its long fingers close to the desk: opening them, a finger
// stops against the desk 0.09 rad short of rest (office, layout 3). The cup stands released;
// release ends there instead of failing with a tracking error.
TEST(PutdownOnAtlas, AFingerStoppedByTheSurfaceEndsTheRelease) {
  if (!std::filesystem::exists(test::catalog().robot_dir("atlas"))) {
    GTEST_SKIP() << "no atlas in " << test::catalog().root();
  }
  Scenario s = program_scenario("putdown");
  s.execution = "kinematic";
  const TrialResult r = run_trial(s, *test::loaded_scene("atlas", "office"), 3, 1, registry());
  EXPECT_TRUE(r.success) << trial_status(r) << ": " << trial_failure_reason(r);
}

// The trials of one scenario written to a scratch root, each of which must succeed.
// Returns the trials' lines.
std::string expect_every_trial_succeeds(const std::string& file, const std::string& yaml,
                                        size_t expected_trials) {
  test::ScratchRoot root;
  root.write(file, yaml);
  const std::string trials = run_in_root(root, file);
  size_t lines = 0;
  std::istringstream in(trials);
  for (std::string line; std::getline(in, line);) {
    if (line.empty()) continue;
    ++lines;
    EXPECT_NE(line.find("\"success\":true"), std::string::npos) << line.substr(0, 3000);
  }
  EXPECT_EQ(lines, expected_trials) << trials.substr(0, 2000);
  return trials;
}

// putdown let go and left the arm where it was: the open hand round what it had set down, out
// over the furniture, and a bent torso bent. The next program met it there (a base turn swept
// the hand into the desk; the hand hid the object from the head camera). The arms now come to
// rest after the release, the torso upright: the success condition asks for the rest posture
// of both arms (before: `postural(rest, left_arm, right_arm): joint r_shoulder_pitch is
// 0.267059 from the posture` on tallbot, `RShoulderPitch is 0.738066` on minibot).
TEST(PutdownOnEveryRobot, TheArmsEndAtRestAfterTheRelease) {
  expect_every_trial_succeeds("putdown.yaml", R"(setup:
  - {program: pickup, params: {object: cup}}
program: putdown
params: {object: cup, surface: work_surface}
robots: [tallbot, minibot]
environments: [kitchen]
perception: ground_truth
obstacles: {count: 8}
layout_seed: 3
seed: 1
trials: 1
time_limit_s: 40
success: all_of(above(cup, work_surface), not(grasping(cup)), postural(rest, left_arm, right_arm))
)",
                              2);
}

// putdown from a held object touching its surface: pickup takes the cup without lifting it, so
// at putdown's start the held cup still stands on the table (MuJoCo reports their contact);
// putdown lifts it off along the table's normal, then plans and places it (each robot, the
// putdown scenario's first world). Before a held object's supports were refreshed, a cup that
// was a hair off the table when it was taken made every such start an `invalid_start: ...
// cup_shell touches desk_top` once it settled back onto it.
TEST(PutdownOnEveryRobot, StartsWithTheHeldCupStillTouchingTheTableItStoodOn) {
  for (const std::string& robot : test::catalog().robots()) {
    if (robot != "tallbot" && robot != "minibot" && robot != "atlas") continue;
    int cup_on_table = -1;
    bool held = false;
    Scenario s = program_scenario("putdown");
    s.execution = "physics";
    const TrialResult r =
        run_trial(s, *test::loaded_scene(robot, "kitchen"), s.layout_seed, s.seed, registry(),
                  [&](const std::string& moment, const core::TrialWorld& world) {
                    if (moment != "setup") return;
                    const mujoco::MujocoSkillset& skills = test::mujoco_skills(world);
                    const mjModel* m = skills.model();
                    const mjData* d = skills.sim_data();
                    const int cup = mj_name2id(m, mjOBJ_BODY, "cup");
                    const int table = mj_name2id(m, mjOBJ_BODY, "table");
                    cup_on_table = 0;
                    for (int i = 0; i < d->ncon; ++i) {
                      const int b1 = m->geom_bodyid[d->contact[i].geom1];
                      const int b2 = m->geom_bodyid[d->contact[i].geom2];
                      if ((b1 == cup && b2 == table) || (b1 == table && b2 == cup)) {
                        cup_on_table += d->contact[i].dist <= 0 ? 1 : 0;
                      }
                    }
                    held = !world.skills().holder_of("cup").empty();
                  });
    EXPECT_TRUE(held) << robot << ": the set-up pickup left the cup unheld";
    EXPECT_GT(cup_on_table, 0) << robot << ": the held cup no longer touches the table";
    EXPECT_TRUE(r.success) << robot << ": " << trial_status(r) << ": " << trial_failure_reason(r);
  }
}

// atlas set the vacuum down with its right hand round the handle, over the table; the rest of
// its torso and both arms found no way there in 10,000 iterations (`planning_timeout`, 3.7 s
// of the trial's 4.1; kitchen, layout 5, seed 3 of the default suite), and the arm stayed out
// over the table. The left arm was at rest already: planned all the same, its six joints made
// the search fifteen-dimensional. postural now plans only the chains not yet at the posture
// (161 iterations here).
TEST(VacuumOnAtlas, TheArmComesToRestFromTheHandleItSetDown) {
  if (!std::filesystem::exists(test::catalog().robot_dir("atlas"))) {
    GTEST_SKIP() << "no atlas in " << test::catalog().root();
  }
  const std::string trials = expect_every_trial_succeeds("vacuum.yaml", R"(program: vacuum
params: {tool: vacuum, surface: work_surface}
robots: [atlas]
environments: [kitchen]
perception: ground_truth
obstacles: {count: 8}
execution: kinematic
layout_seed: 5
seed: 3
trials: 1
time_limit_s: 90
success: all_of(not(exists(debris)), not(grasping(vacuum)), above(vacuum, work_surface), postural(rest, left_arm, right_arm))
)",
                                                         1);
  // At rest from where it set the vacuum down, not after putdown's step back: one retreat, the
  // hand's withdrawal off the handle.
  const std::regex retreat("\"program\":\"retreat\",\"t\":[-0-9.e+]+,\"type\":\"started\"");
  EXPECT_EQ(std::distance(std::sregex_iterator(trials.begin(), trials.end(), retreat),
                          std::sregex_iterator()),
            1)
      << trials.substr(0, 3000);
}

// minibot set the vacuum down standing against the desk, where its rest posture puts the
// right elbow into the desk's top (office, layout 3, seed 1: `invalid_goal: the goal
// configuration is in collision: RElbowBall touches desk_top (depth 9.8 mm)`), and the arm
// stayed over the desk. putdown now steps back from the nearest surface and tries once more.
TEST(VacuumOnMinibot, StepsBackWhereTheRestPutsAnElbowIntoTheDesk) {
  const std::string trials = expect_every_trial_succeeds("vacuum.yaml", R"(program: vacuum
params: {tool: vacuum, surface: work_surface}
robots: [minibot]
environments: [office]
perception: ground_truth
obstacles: {count: 8}
execution: kinematic
layout_seed: 3
seed: 1
trials: 1
time_limit_s: 90
success: all_of(not(exists(debris)), not(grasping(vacuum)), above(vacuum, work_surface), postural(rest, left_arm, right_arm))
)",
                                                         1);
  EXPECT_NE(trials.find("\"program\":\"retreat\""), std::string::npos) << trials.substr(0, 3000);
}

// A task written as a user writes one: the cup to the side surface, the juice box from there to
// the desk, then watch the box for 3 s. atlas set the box down at the desk's corner with its
// hand still round it: every base turn towards the box swept that hand into the desk, and the
// box never came into view (`swap > fixate(watch): tracking_error: 'box' never in view in 3.0
// s (at best 0.81 rad off; the base cannot turn towards it without touching something)`,
// office, layout 1400; 7 of 48 such trials over four robots and three rooms). putdown now
// brings the arms to rest after letting go.
TEST(SwapOnAtlas, TheBoxJustSetDownComesIntoView) {
  if (!std::filesystem::exists(test::catalog().robot_dir("atlas"))) {
    GTEST_SKIP() << "no atlas in " << test::catalog().root();
  }
  test::ScratchRoot root;
  root.write("swap.yaml", R"(machine:
  name: swap
  initial: take_cup
  states:
    take_cup: {program: pickup, params: {object: cup}}
    place_cup: {program: putdown, params: {object: cup, surface: side_surface}}
    take_box: {program: pickup, params: {object: box}}
    place_box: {program: putdown, params: {object: box, surface: work_surface}}
    watch: {program: fixate, params: {object: box, duration: 3}}
    done: {final: success}
  transitions:
    - {from: take_cup, on: completed, to: place_cup}
    - {from: place_cup, on: completed, to: take_box}
    - {from: take_box, on: completed, to: place_box}
    - {from: place_box, on: completed, to: watch}
    - {from: watch, on: completed, to: done}
params: {}
robots: [atlas]
environments: [office]
perception: ground_truth
obstacles: {count: 8}
objects:
  cup: {on: work_surface, yaw: [-3.14159, 3.14159]}
  box: {on: side_surface, yaw: [-3.14159, 3.14159]}
surfaces:
  work_surface: {height_m: [0.62, 0.80]}
robot_start: {x: [-0.05, 0.05], y: [-0.10, 0.10], yaw: [-0.15, 0.15]}
layout_seed: 1400
seed: 1
trials: 1
time_limit_s: 240
success: all_of(above(cup, side_surface), above(box, work_surface), near(box, work_surface), in_view(box))
)");
  const std::string trials = run_in_root(root, "swap.yaml");
  EXPECT_NE(trials.find("\"status\":\"success\""), std::string::npos) << trials.substr(0, 2000);
}

// Under physics atlas held the vacuum's handle in a firm grip, and the grip's contact forces on
// the kinematically held vacuum pushed the arm 0.012-0.025 rad off its path, so passing the
// nozzle 8 mm over the table drove it 5 mm into it (the
// generalization suite's vacuum, office, layout 102, on the third flake: `collision of vacuum
// with work_surface (depth 5.0 mm)`). A held object no longer collides with the hand holding it.
TEST(VacuumOnAtlas, AHeldToolFollowsItsPathOverTheTableUnderPhysics) {
  if (!std::filesystem::exists(test::catalog().robot_dir("atlas"))) {
    GTEST_SKIP() << "no atlas in " << test::catalog().root();
  }
  const Scenario s = generalization_scenario("vacuum");
  ASSERT_EQ(s.execution, "physics");
  const TrialResult r = run_trial(s, *test::loaded_scene("atlas", "office"), 102, 3, registry());
  EXPECT_TRUE(r.success) << trial_status(r) << ": " << trial_failure_reason(r);
}

// After a grasp of the vacuum that did not hold and a retreat that stopped short, the next
// reach first frees the hand, which brushed the vacuum it was reaching for and stopped as a
// collision (generalization vacuum, office, layout 100 until reach kept the closing fingers
// over the table after a failed grasp; now layout 104, which fails the same way without the
// fix: `collision of l_finger_middle_link_1 with vacuum`). Getting free may touch what the
// motion after it may.
TEST(VacuumOnAtlas, FreeingTheHandMayTouchTheObjectReachedFor) {
  if (!std::filesystem::exists(test::catalog().robot_dir("atlas"))) {
    GTEST_SKIP() << "no atlas in " << test::catalog().root();
  }
  const Scenario s = generalization_scenario("vacuum");
  const TrialResult r = run_trial(s, *test::loaded_scene("atlas", "office"), 104, 5, registry());
  // What the case is about: the reach after the grasp that did not hold gets the hand free and
  // completes, and pickup holds the vacuum (what the cleaning does after that is not).
  auto count = [&](const std::string& program, const std::string& type) {
    return static_cast<int>(events_of(r, program, type).size());
  };
  ASSERT_GE(count("grasp", "failed"), 1) << "the first grasp held: nothing to get free from";
  EXPECT_EQ(count("reach", "failed"), 0) << trial_failure_reason(r);
  EXPECT_EQ(count("reach", "completed"), count("grasp", "failed") + 1);
  EXPECT_EQ(count("pickup", "completed"), 1) << trial_failure_reason(r);
}

// minibot stepped up to the table to reach the vacuum's handle and the arm, hanging at its
// side below the table's edge, could not be planned up to the solution found for that stance
// with the base standing still (`approximate_solution`, generalization vacuum, kitchen, layout
// 111). The whole body is then planned to it, free to step away and back.
TEST(VacuumOnMinibot, AnArmThatCannotRiseAtItsStanceIsPlannedThereWithTheWholeBody) {
  const Scenario s = generalization_scenario("vacuum");
  const TrialResult r =
      run_trial(s, *test::loaded_scene("minibot", "kitchen"), 111, 12, registry());
  EXPECT_TRUE(r.success) << trial_status(r) << ": " << trial_failure_reason(r);
}

// atlas's first grasp of the vacuum's handle closed one finger of three on it; pickup let go
// and withdrew the hand, whose finger brushed the handle it had just let go of, and retreat
// stopped as a collision (generalization position, office, layout 100). Withdrawing from what
// it let go of may brush it.
TEST(PickupOnAtlas, WithdrawingFromAGraspThatDidNotHoldMayBrushTheObject) {
  if (!std::filesystem::exists(test::catalog().robot_dir("atlas"))) {
    GTEST_SKIP() << "no atlas in " << test::catalog().root();
  }
  const Scenario s = generalization_scenario("position");
  const TrialResult r = run_trial(s, *test::loaded_scene("atlas", "office"), 100, 1, registry());
  auto count = [&](const std::string& program, const std::string& type) {
    return static_cast<int>(events_of(r, program, type).size());
  };
  ASSERT_GE(count("grasp", "failed"), 1) << "the first grasp held: nothing to withdraw from";
  EXPECT_EQ(count("retreat", "failed"), 0);
  EXPECT_EQ(count("retreat", "completed"), count("grasp", "failed"));
}

// atlas's hand, at rest beside a 0.56 m table, swung up past its edge (the generalization
// suite's reach, kitchen, layout 115): the plan could pass the edge a hair off it anywhere
// within 0.25 rad of the start, and under physics the fingers, a few millimetres off the
// path while the arm sped up, touched it (`collision of r_finger_2_link_3 with work_surface
// (depth 0.8 mm)`). Near the start and the goal the clearance asked for now grows from nothing
// to the centimetre kept elsewhere, and motions there are checked five times more finely;
// the finer checks alone also keep this path off the edge
// (`PlanOnBothRobots.PathsLeaveAStartAHairOffTheWorldWithClearanceGrowingAway` needs the ramp).
TEST(ReachOnAtlas, AHandStartingBesideTheTableLeavesItsEdgeWithRoomToSpare) {
  if (!std::filesystem::exists(test::catalog().robot_dir("atlas"))) {
    GTEST_SKIP() << "no atlas in " << test::catalog().root();
  }
  const Scenario s = generalization_scenario("reach");
  ASSERT_EQ(s.execution, "physics");
  const TrialResult r = run_trial(s, *test::loaded_scene("atlas", "kitchen"), 115, 16, registry());
  EXPECT_TRUE(r.success) << trial_status(r) << ": " << trial_failure_reason(r);
}

// The same reach from another start beside the table (layout 119), kinematically executed: the
// planner checked states 3.6 cm of joint motion apart, two of them a hair off the table, and
// the straight line between them took a finger 0.7 mm into it (`collision of
// r_finger_2_link_3 with work_surface`). Near the start and the goal the checks along a motion
// are five times closer together.
TEST(ReachOnAtlas, APathLeavingTheTableIsCheckedFinelyNearItsStart) {
  if (!std::filesystem::exists(test::catalog().robot_dir("atlas"))) {
    GTEST_SKIP() << "no atlas in " << test::catalog().root();
  }
  Scenario s = generalization_scenario("reach");
  s.execution = "kinematic";
  const TrialResult r = run_trial(s, *test::loaded_scene("atlas", "kitchen"), 119, 20, registry());
  EXPECT_TRUE(r.success) << trial_status(r) << ": " << trial_failure_reason(r);
}

// A cup 0.81 m ahead on a 0.72 m table (the generalization suite's reach, kitchen, layout
// 117): the arm and torso of tallbot with the stiffer waist it had until 2026-12-06 (pitch at
// most 0.8 rad) miss every grasp pose by 5 cm or more, and IK over the whole body from where
// it stands found no stance. The stance search places the base first, nearer the table, and
// solves the torso and arm with the base held there. (tallbot as it is bends over the table
// far enough to reach that cup from where it stands.)
TEST(ReachOnTallbot, ACupBeyondArmAndTorsoIsReachedFromAStanceFoundBaseFirst) {
  test::ScratchRoot root;
  test::stiffen_tallbot_waist(root);
  const mujoco::MujocoLoadedScene stiff(mujoco::Scene::load(
      root.path() / "models" / "robots" / "tallbot", test::catalog().environment_dir("kitchen")));
  expect_success_stepping(generalization_scenario("reach"), stiff, 117, 18, 0.05);
}

// The vacuum's handle on the table (the default suite's vacuum, kitchen, layout 5): minibot's
// arm and torso reach it only with solutions the planner cannot connect to
// (`approximate_solution`), IK over the whole body from where it stands finds no stance, and
// the stance search tried its first 48 base poses, 45 of them within 0.34 m of the start,
// among them the same pose three times over and poses behind the start from which nothing
// on the table is within the arm's reach, and never got to the poses round the table.
// Repeats and base poses out of the arm's reach are dropped.
TEST(VacuumOnMinibot, TheStanceSearchGetsPastPosesFromWhichTheHandleIsOutOfReach) {
  expect_success_stepping(program_scenario("vacuum"), *test::loaded_scene("minibot", "kitchen"), 5,
                          3, 0.3);
}

// The vacuum's handle on a 0.66 m table, 0.76 m ahead (the generalization suite's vacuum,
// kitchen, layout 107): from none of the stance candidates, the base held there, do torso and
// arm get minibot's hand round it (`the turn the arm needs is outside what the target
// allows`). A second pass lets the base move a little from each of the first candidates.
TEST(VacuumOnMinibot, AStanceBetweenTheCandidatesIsFoundWithTheBaseFreeToMove) {
  expect_success("vacuum", "minibot", "kitchen", 107, 8);
}

// minibot's two fingers closing on the vacuum's handle (office, layout 100 of the
// generalization suite), the hand turned about it so that the handle sat 8 mm to one side of
// the fingers' middle: the first finger stopped on it, the second closed on past it and met
// the first's tip over it. Each of three grasps "held with 1 of 2 fingers" was let go of and
// the vacuum never picked up. Fingers that meet round a handle, one of them on it, hold it.
TEST(VacuumOnMinibot, FingersThatMeetRoundTheHandleHoldIt) {
  const TrialResult r = expect_success("vacuum", "minibot", "office", 100, 1);
  EXPECT_TRUE(events_of(r, "grasp", "failed").empty());
}

// tallbot's fingers are longer than the vacuum's handle is high over the table, and the hand
// may turn all round the handle: in the kitchen (layout 104 of the generalization suite) IK
// turned it with the fingers pointing down past the handle, closing they stopped on the table,
// and three grasps held with one finger of three (`3 grasps of 'vacuum' ... did not hold`).
// After a grasp that did not hold because something other than the object stopped a finger,
// reach now keeps out poses from which the closing fingers would reach the surface under the
// object. (Since a capsule through a box touches it, layout 104's first grasp holds; since
// tallbot's waist bends to 1.4 rad, layout 103's first grasp holds too; layout 101's first
// grasp is the case.)
TEST(PositionOnTallbot, AfterAGraspThatDidNotHoldTheFingersCloseOverTheTable) {
  const TrialResult r = expect_success("position", "tallbot", "kitchen", 101, 2);
  const std::vector<TrialEvent> failed = events_of(r, "grasp", "failed");
  EXPECT_GE(failed.size(), 1u) << "the first grasp held: the case is not the one described";
  for (const TrialEvent& e : failed) {  // each failure says what stopped the fingers
    EXPECT_NE(e.reason.find("fingers stopped by 'work_surface'"), std::string::npos) << e.reason;
  }
}

// fixate alongside reach: looking down at a cup close in front with the neck turned (office,
// layout 117 of the generalization suite), tallbot's neck pitched to its limit, where the
// head touches its own shoulders, and reach stopped with `collision of torso with head`.
// fixate now takes no head step to within 1 cm of anything, its own body included.
TEST(PickupOnTallbot, FixateKeepsTheHeadOffTheRobotsOwnBody) {
  expect_success("pickup", "tallbot", "office", 117, 18);
}

// atlas holds the vacuum on the kitchen's table beside the cup (layout 112 of the
// generalization suite): position first lifts the tool off the table (an escape motion, which
// execution checks and the planner does not), and IK's second lift step came from a random
// restart, another posture of the arm (an elbow turned 2.6 rad): moving to it swung the vacuum
// through the cup. An escape step now takes only a solution a short straight motion reaches.
TEST(PositionOnAtlas, TheHeldToolIsLiftedOffTheTableWithoutSwingingTheArm) {
  expect_success("position", "atlas", "kitchen", 112, 13);
}

// minibot takes the vacuum to a stance beside the kitchen's counter (layout 105 of the
// generalization suite): the base's path, checked every 7.7 cm of joint space, ran a finger of
// the idle hand 0.7 mm into the counter between two checked states. The planner's path is now
// certified between its checked states and planned again, with closer checks, where it
// touches. Kinematic execution: the plan, not physics, decides. (Since plans keep off the
// visitor's route that world's paths differ; in layout 103 the first plan's path touches
// something between its checked states and is planned again.)
TEST(VacuumOnMinibot, APathThatGrazesTheCounterBetweenChecksIsPlannedAgain) {
  Scenario s = generalization_scenario("vacuum");
  s.execution = "kinematic";
  const TrialResult r = run_trial(s, *test::loaded_scene("minibot", "kitchen"), 103, 4, registry());
  EXPECT_TRUE(r.success) << trial_status(r) << ": " << trial_failure_reason(r);
  EXPECT_TRUE(std::any_of(r.work.plans.begin(), r.work.plans.end(),
                          [](const core::PlanCallRecord& p) { return p.planner_runs > 1; }))
      << "no plan was planned again: the case is not the one described";
}

// minibot fetches the vacuum for position (the generalization suite's kitchen, layout 102): the
// stance search stepped to the table's end, between the table and the counter, and from there
// the planner connected to none of the arm's grasp solutions (`approximate_solution` for each,
// with torso and arm and with the whole body). A stance from which reaching fails that way is
// now left for another (at most two such stances).
TEST(PositionOnMinibot, AStanceFromWhichTheArmsPlanFailsIsLeftForAnother) {
  const TrialResult r = expect_success("position", "minibot", "kitchen", 102, 3);
  EXPECT_TRUE(std::any_of(r.work.plans.begin(), r.work.plans.end(),
                          [](const core::PlanCallRecord& p) {
                            return p.status ==
                                   core::to_string(core::PlanStatus::kApproximateSolution);
                          }))
      << "no plan ended approximate: the case is not the one described";
}

// The stance search finds whole-body solutions at stances the arm could keep its posture at
// and plans the base alone there. minibot fetching the vacuum (the generalization suite's
// kitchen, layout 109) once found no way for the base alone to three stances in turn
// (`planning_timeout`) and the set-up's pickup failed. When the base alone finds no way to a
// stance, the whole body is planned there: here (kitchen, layout 114) 15 s in, the base
// alone runs out of iterations. (The case first written here, office layout 118 with the
// vacuum held over the table, no longer arises: the base alone failed there only because
// the held vacuum kept a planning margin from the arm holding it, which moved with it.)
TEST(VacuumOnMinibot, WhenTheBaseAloneFindsNoWayToAStanceTheWholeBodyGoes) {
  const TrialResult r = expect_success("vacuum", "minibot", "kitchen", 114, 15);
  const std::vector<core::PlanCallRecord>& plans = r.work.plans;
  bool recovered = false;  // a plan out of iterations, at once followed by one that succeeded
  for (size_t i = 0; i + 1 < plans.size(); ++i) {
    recovered =
        recovered || (plans[i].status == core::to_string(core::PlanStatus::kTimeout) &&
                      plans[i + 1].status == core::to_string(core::PlanStatus::kExactSolution) &&
                      plans[i + 1].time_s == plans[i].time_s);
  }
  EXPECT_TRUE(recovered) << "no plan succeeded right after one ran out of iterations: the case "
                            "is not the one described";
}

// True if some plan of `r` ran out of iterations.
bool a_plan_ran_out(const TrialResult& r) {
  return std::any_of(r.work.plans.begin(), r.work.plans.end(), [](const core::PlanCallRecord& p) {
    return p.status == core::to_string(core::PlanStatus::kTimeout);
  });
}

// minibot picks the vacuum up from the table and positions it over the debris (the
// generalization suite's kitchen, layout 114). The vacuum lay a hair above the table, touching
// nothing, so reaching planned from there at once, and every plan, to each of three stances
// round the table, ran out of iterations: the planner keeps its clearance everywhere but next
// to the start, and few of its random motions lift a lying tool straight up. Where every plan
// from such a start fails, the hand now lifts what it holds straight off first, then plans
// again.
TEST(PositionOnMinibot, AToolAHairOffTheTableIsPlacedThoughEveryPlanFromBesideItRanOut) {
  const TrialResult r = expect_success("position", "minibot", "kitchen", 114, 15);
  EXPECT_TRUE(a_plan_ran_out(r)) << "no plan ran out of iterations: the case is not the one "
                                    "described";
}

// After putting the vacuum down, putdown lifts the open hand straight off what it let go of
// (a hand drawn back against its approach dragged a box set down on a cart). minibot's fingers
// ring the vacuum's handle, one under it: rising, the hand carried the vacuum up and dropped
// it off the table (generalization suite, kitchen 108: `criterion_false: above(vacuum,
// work_surface): vacuum's bottom is 76.6 cm below work_surface's top`). A hand with a finger
// under part of what it let go of draws back instead.
TEST(PutdownOnMinibot, TheHandDrawsBackOffTheVacuumsHandleRatherThanLiftingTheVacuum) {
  const TrialResult r = expect_success("vacuum", "minibot", "kitchen", 108, 9);
  EXPECT_FALSE(events_of(r, "retreat", "completed").empty()) << "the hand did not withdraw";
}

// The same in the office (layout 114): lifted, the vacuum is still out over the desk, and
// planning the whole body round the desk's end to a stance on its far side ran out of
// iterations for each stance found. The torso now straightens first, the arm as it is (or
// the arm comes to rest), where that posture is clear both here and at the stance; the base
// walks there with it, and torso and arm are planned from there.
TEST(PositionOnMinibot, TheToolReachesTheFarSideOfTheDeskThoughEveryWholeBodyPlanRanOut) {
  Scenario s = generalization_scenario("position");
  std::vector<double> start, end;
  const TrialResult r = run_trial(s, *test::loaded_scene("minibot", "office"), 114, 15, registry(),
                                  [&](const std::string& moment, const core::TrialWorld& world) {
                                    if (moment == "setup")
                                      start = world.skills().configuration({"base"});
                                    if (moment == "end")
                                      end = world.skills().configuration({"base"});
                                  });
  ASSERT_TRUE(r.success) << trial_status(r) << ": " << trial_failure_reason(r);
  EXPECT_TRUE(a_plan_ran_out(r)) << "no plan ran out of iterations: the case is not the one "
                                    "described";
  ASSERT_EQ(start.size(), 3u);
  ASSERT_EQ(end.size(), 3u);
  EXPECT_GT(std::hypot(end[0] - start[0], end[1] - start[1]), 0.5)
      << "the base did not walk round the desk";
}

// minibot's two fingers close round the cup under physics (kitchen, layout 108 of the
// generalization suite): each stops on the cup, but the first one's contact flickers off at
// the instant the second stops, and grasp counted 1 of 2 fingers. A finger that stopped on
// the object now holds it.
TEST(GraspOnMinibot, AFingerThatStoppedOnTheCupHoldsItThoughItsContactFlickers) {
  expect_success("grasp", "minibot", "kitchen", 108, 9);
}

// The paper's retry loop (pickup: reach, grasp; a grasp that does not hold: let go, back off,
// reach for the next grasp), constructed: the first grasp of a run closes with too few
// fingers (it fails as grasp does, noting the candidate reach moved to as failed), later ones
// are the real grasp. pickup must let go, back off, reach a different candidate, and hold it.
class FirstGraspFails final : public core::TaskProgram {
 public:
  FirstGraspFails(std::unique_ptr<core::TaskProgram> real, core::Params params, int& runs,
                  std::vector<std::string>& reached)
      : real_(std::move(real)), params_(std::move(params)), runs_(runs), reached_(reached) {}
  std::vector<std::string> chains(const core::Skillset& skills) const override {
    return real_->chains(skills);
  }
  std::vector<std::string> claim(const core::ClaimContext& ctx) override {
    return real_->claim(ctx);
  }
  core::ConditionPtr precondition() const override { return real_->precondition(); }
  void start(core::ProgramContext& ctx) override {
    first_ = runs_++ == 0;
    const std::string object = params_.text("object");
    for (const char* side : {"left", "right"}) {
      const std::vector<std::string>& note = ctx.notes(programs::reached_grasp_note(object, side));
      if (!note.empty()) {
        side_ = side;
        reached_.push_back(note.front());
      }
    }
    if (!first_) real_->start(ctx);
  }
  core::ProgramState step(core::ProgramContext& ctx) override {
    if (first_) {
      ctx.notes(programs::failed_grasps_note(params_.text("object"), side_))
          .push_back(reached_.back());
      return fail(core::FailureCode::kGraspFailed, "1 of 3 fingers touch it (constructed)");
    }
    const core::ProgramState state = real_->step(ctx);
    if (state == core::ProgramState::kFailed) return fail(real_->failure());
    return state;
  }
  void halt(core::ProgramContext& ctx) override { real_->halt(ctx); }

 private:
  std::unique_ptr<core::TaskProgram> real_;
  core::Params params_;
  int& runs_;
  std::vector<std::string>& reached_;
  bool first_ = false;
  std::string side_;
};

TEST(PickupOnTallbot, AGraspThatDoesNotHoldIsLetGoOfAndTheNextCandidateReachedFor) {
  int runs = 0;
  std::vector<std::string> reached;  // the candidate reach moved to, at each grasp
  core::ProgramRegistry primitives;
  programs::register_primitives(primitives);
  core::ProgramRegistry programs;
  for (const std::string& name : primitives.names()) {
    core::ProgramType type = *primitives.find(name);
    if (name == "grasp") {
      const auto real = type.make;
      type.make = [real, &runs, &reached](const core::Params& p) {
        return std::make_unique<FirstGraspFails>(real(p), p, runs, reached);
      };
    }
    programs.add(std::move(type));
  }
  programs::register_complex(programs);
  Scenario s = program_scenario("pickup");
  s.execution = "kinematic";
  const TrialResult r =
      run_trial(s, *test::loaded_scene("tallbot", "kitchen"), s.layout_seed, s.seed, programs);
  ASSERT_TRUE(r.success) << trial_status(r) << ": " << trial_failure_reason(r);
  EXPECT_EQ(runs, 2);
  ASSERT_EQ(reached.size(), 2u);
  EXPECT_NE(reached[0], reached[1]) << "the second reach went back to the grasp that failed";
  auto count = [&](const std::string& program, const std::string& type) {
    return static_cast<int>(events_of(r, program, type).size());
  };
  EXPECT_EQ(count("grasp", "failed"), 1);
  EXPECT_EQ(count("release", "completed"), 1);
  EXPECT_EQ(count("retreat", "completed"), 1);
  EXPECT_EQ(count("reach", "completed"), 2);
  EXPECT_EQ(count("grasp", "completed"), 1);
}

}  // namespace
}  // namespace taskmatrix::harness
