// Task variations through the harness: the scenario keys are checked when the file is read
// (file:line: key errors), every drawn value is in the trial's record, the same layout seed
// gives the same values, and a recorded trial replays in its varied world.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "harness/replay/replay.h"
#include "harness/replay/trajectory_file.h"
#include "harness/results/trial_record.h"
#include "harness/run/run_job.h"
#include "harness/run/trial.h"
#include "harness/scenario/scenario.h"
#include "taskmatrix/core/input_error.h"
#include "taskmatrix/mujoco/ground_truth_perception.h"
#include "taskmatrix/mujoco/mujoco_view.h"
#include "taskmatrix/programs/primitives.h"
#include "tests/test_support.h"

namespace taskmatrix::harness {
namespace {

class Variations : public ::testing::Test {
 protected:
  void SetUp() override {
    char tmpl[] = "/tmp/taskmatrix_variations_XXXXXX";
    dir_ = mkdtemp(tmpl);
    programs::register_programs(registry_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name) << text;
    return dir_ / name;
  }
  // Runs `scenario` into run/ with two workers.
  RunJobResult run(const std::filesystem::path& scenario) {
    RunJobOptions options;
    options.scenario_file = scenario;
    options.out = dir_ / "run";
    options.jobs = 2;
    options.progress = RunJobOptions::Progress::kOff;
    std::ostringstream out, err;
    return run_job(test::catalog(), registry_, options, out, err);
  }
  // "file:line: key: message" of the InputError that validating `text` throws ("" if none).
  std::string error_of(const std::string& text) {
    const auto file = write("bad.yaml", text);
    try {
      validate_run_plan(test::catalog(), registry_, file);
    } catch (const core::InputError& e) {
      return e.what();
    }
    return "";
  }
  std::filesystem::path dir_;
  core::ProgramRegistry registry_;
};

constexpr const char* kFixate =
    "program: fixate\nparams: {object: cup, duration: 0.2}\nrobots: [minibot]\n"
    "environments: [kitchen]\n";

// A varied world: objects placed, the table's height drawn, the start moved, obstacles near
// the cup.
constexpr const char* kVaried =
    "objects:\n"
    "  cup: {on: work_surface, area: {x: [0, 0.6]}, yaw: [-3.14, 3.14]}\n"
    "  box: {on: work_surface, yaw: 0.5}\n"
    "surfaces:\n"
    "  work_surface: {height_m: [0.55, 0.80]}\n"
    "robot_start: {x: [-0.05, 0.05], y: [-0.1, 0.1], yaw: [-0.2, 0.2]}\n"
    "obstacles: {count: 2, near: {object: cup, radius_m: 0.3, count: 3}}\n";

TEST_F(Variations, BadValuesAreRejectedWithFileLineAndKey) {
  const std::string base = kFixate;
  const std::string file = (dir_ / "bad.yaml").string();
  EXPECT_EQ(
      error_of(base + "surfaces:\n  work_surface: {height_m: [0.9, 0.5]}\n")
          .rfind(file + ":6: surfaces.work_surface.height_m: must be a number or [min, max]", 0),
      0u)
      << error_of(base + "surfaces:\n  work_surface: {height_m: [0.9, 0.5]}\n");
  EXPECT_EQ(error_of(base + "objects:\n  cup: {on: work_surface, area: {x: [0.5, 0.2]}}\n")
                .rfind(file + ":6: objects.cup.area.x: must be [min, max] fractions", 0),
            0u);
  EXPECT_EQ(error_of(base + "objects:\n  cup: {on: work_surface, spin: 1}\n")
                .rfind(file + ":6: objects.cup.spin: unknown key", 0),
            0u)
      << error_of(base + "objects:\n  cup: {on: work_surface, spin: 1}\n");
  EXPECT_EQ(error_of(base + "robot_start: {x: [-5, 5]}\n")
                .rfind(file + ":5: robot_start.x: must stay within", 0),
            0u)
      << error_of(base + "robot_start: {x: [-5, 5]}\n");
  EXPECT_EQ(error_of(base + "obstacles: {near: {object: cup, count: -1}}\n")
                .rfind(file + ":5: obstacles.near.count: must be in 0..200", 0),
            0u)
      << error_of(base + "obstacles: {near: {object: cup, count: -1}}\n");
  // Names are checked against the environment: a misspelled object, an unknown surface.
  const std::string cupp = error_of(base + "objects:\n  cupp: {on: work_surface}\n");
  EXPECT_EQ(cupp.rfind(file + ":6: objects.cupp: ", 0), 0u) << cupp;
  EXPECT_NE(cupp.find("no graspable object or tool 'cupp'"), std::string::npos) << cupp;
  const std::string floor = error_of(base + "objects:\n  cup: {on: floor}\n");
  EXPECT_EQ(floor.rfind(file + ":6: objects.cup.on: ", 0), 0u) << floor;
  const std::string mug = error_of(base + "obstacles: {near: {object: mug, count: 2}}\n");
  EXPECT_EQ(mug.rfind(file + ":5: obstacles.near.object: ", 0), 0u) << mug;
  // A height the table cannot take, and more near obstacles than fit.
  const std::string low = error_of(base + "surfaces:\n  work_surface: {height_m: 0.04}\n");
  EXPECT_EQ(low.rfind(file + ":6: surfaces.work_surface.height_m: ", 0), 0u) << low;
  const std::string crowded =
      error_of(base + "obstacles: {near: {object: cup, radius_m: 0.05, count: 20}}\n");
  EXPECT_EQ(crowded.rfind(file + ":5: obstacles.near: ", 0), 0u) << crowded;
  EXPECT_NE(crowded.find("too crowded"), std::string::npos) << crowded;
}

// Objects placed on the office's side table, turned at random: a cup turned 0.4 rad (layout
// 903) stood exactly on the table top, and MuJoCo's box-box test reported its base pad 322 mm
// deep in the top (`cannot lay out trial ...: at the start side_table_top touches cup_base`),
// refusing the whole run. Placed objects now start a tenth of a millimetre above their surface
// and settle onto it: every layout starts without a contact, and the objects come to rest on
// the table, neither in it nor thrown off it.
TEST_F(Variations, ObjectsTurnedOnASurfaceStartClearOfItAndSettleOnIt) {
  const auto scenario = write("side.yaml",
                              "program: fixate\nparams: {object: work_surface, duration: 0.5}\n"
                              "robots: [tallbot]\nenvironments: [office]\n"
                              "objects:\n"
                              "  box: {on: side_surface, yaw: [-3.14159, 3.14159]}\n"
                              "  cup: {on: side_surface, yaw: [-3.14159, 3.14159]}\n"
                              "obstacles: {count: 8}\nlayout_seed: 900\ntrials: 4\n");
  const RunPlan plan = load_run_plan(scenario, test::catalog(), registry_);
  auto scene = test::loaded_scene("tallbot", "office");
  for (std::uint64_t seed = 900; seed < 904; ++seed) {
    SCOPED_TRACE(seed);
    const core::TrialLayout layout = draw_trial_layout(plan.scenarios[0], *scene, seed, "side");
    EXPECT_TRUE(scene->start_contacts(layout).empty());
  }
  const RunJobResult r = run(scenario);
  ASSERT_EQ(r.finished, 4);
  for (const nlohmann::json& t : read_trials_file(dir_ / "run" / "trials.jsonl").trials) {
    SCOPED_TRACE(t["trial_id"].get<std::string>());
    EXPECT_TRUE(t["success"].get<bool>()) << t["failure_reason"];
    // At the end the cup stands on the side table's top (0.64 m; the cup 0.1 m tall).
    Replay replay(test::catalog(),
                  read_trajectory_file(trajectory_of((dir_ / "run").string() + ":" +
                                                     t["trial_id"].get<std::string>())));
    replay.show(replay.frames() - 1);
    const mujoco::WorkerScene& worker =
        dynamic_cast<const mujoco::MujocoView&>(replay.view()).worker();
    const int cup = mj_name2id(worker.model(), mjOBJ_BODY, "cup");
    EXPECT_NEAR(worker.data()->xpos[3 * cup + 2], 0.64 + 0.05, 1e-3);
  }
}

TEST_F(Variations, EveryDrawnValueIsRecordedTheSameSeedGivesTheSameAndReplaysShowIt) {
  const auto scenario =
      write("varied.yaml", std::string(kFixate) + kVaried + "layout_seed: 40\ntrials: 2\n");
  const RunJobResult r = run(scenario);
  ASSERT_EQ(r.finished, 2);
  const RunPlan plan = load_run_plan(scenario, test::catalog(), registry_);
  auto scene = test::scene("minibot", "kitchen");
  for (const nlohmann::json& t : read_trials_file(dir_ / "run" / "trials.jsonl").trials) {
    SCOPED_TRACE(t["trial_id"].get<std::string>());
    EXPECT_TRUE(t["success"].get<bool>()) << t["failure_reason"];
    const nlohmann::json& l = t.at("layout");
    const double h = l.at("surfaces").at("work_surface").at("height_m").get<double>();
    EXPECT_GE(h, 0.55);
    EXPECT_LE(h, 0.80);
    EXPECT_EQ(l.at("objects").at("box").at("yaw").get<double>(), 0.5);
    EXPECT_EQ(l.at("obstacles").size(), 5u);
    EXPECT_EQ(l.at("obstacles")[0].at("group").get<std::string>(), "obstacles near cup");
    EXPECT_FALSE(l.at("obstacles")[4].contains("group"));
    // The record is what the scene draws for the seed, to the last bit.
    const core::TrialLayout again =
        scene->make_trial_layout(plan.scenarios[0].obstacles, plan.scenarios[0].variation,
                                 t["layout_seed"].get<std::uint64_t>());
    EXPECT_EQ(l.at("objects").at("cup").at("x").get<double>(), again.variation.object("cup")->x);
    EXPECT_EQ(h, again.variation.surface("work_surface")->height_m);
    EXPECT_EQ(l.at("robot_start").at("yaw").get<double>(), again.variation.robot_start->yaw);
    EXPECT_EQ(l.at("obstacles")[1].at("position")[0].get<double>(),
              again.obstacles.obstacles[1].position.x());
    // The recorded trial replays in its varied world: the table at its drawn height.
    Replay replay(test::catalog(),
                  read_trajectory_file(trajectory_of((dir_ / "run").string() + ":" +
                                                     t["trial_id"].get<std::string>())));
    replay.show(0);
    const mujoco::WorkerScene& worker =
        dynamic_cast<const mujoco::MujocoView&>(replay.view()).worker();
    const int table = mj_name2id(worker.model(), mjOBJ_BODY, "table");
    EXPECT_NEAR(mujoco::surface_box(worker.model(), worker.data(), table).max().z(), h, 1e-9);
  }
}

TEST_F(Variations, ASuiteVariesEveryScenarioAndNamesItsOwnLines) {
  write("a.yaml", std::string(kFixate) + "name: a\n");
  write("b.yaml", std::string(kFixate) + "name: b\nsurfaces:\n  side_surface: {height_m: 0.7}\n");
  const auto suite = write("suite.yaml",
                           "suite: s\nscenarios: [a.yaml, b.yaml]\n"
                           "surfaces:\n  work_surface: {height_m: [0.6, 0.7]}\n");
  const RunPlan plan = load_run_plan(suite, test::catalog(), registry_);
  for (const Scenario& s : plan.scenarios) {
    ASSERT_EQ(s.variation.surfaces.size(), 1u);
    EXPECT_EQ(s.variation.surfaces[0].surface, "work_surface");
    EXPECT_EQ(s.variation_file, suite);
  }
  write("bad_suite.yaml",
        "suite: s\nscenarios: [a.yaml]\nsurfaces:\n  work_surface: {height_m: 0.03}\n");
  try {
    validate_run_plan(test::catalog(), registry_, dir_ / "bad_suite.yaml");
    FAIL();
  } catch (const core::InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(
                  (dir_ / "bad_suite.yaml").string() + ":4: surfaces.work_surface.height_m:", 0),
              0u)
        << e.what();
  }
}

}  // namespace
}  // namespace taskmatrix::harness
