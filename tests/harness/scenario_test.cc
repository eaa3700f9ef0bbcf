// Scenario and suite files, the trial matrix and its ids, and the statistics of summaries.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>

#include "harness/results/summary.h"
#include "harness/run/run_job.h"
#include "harness/run/trial.h"
#include "harness/scenario/scenario.h"
#include "harness/scenario/trial_matrix.h"
#include "taskmatrix/core/input_error.h"
#include "taskmatrix/programs/primitives.h"
#include "tests/test_support.h"

namespace taskmatrix::harness {
namespace {

class ScenarioFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    char tmpl[] = "/tmp/taskmatrix_scenarios_XXXXXX";
    dir_ = mkdtemp(tmpl);
    programs::register_programs(registry_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name) << text;
    return dir_ / name;
  }
  // The message of the InputError that loading `text` throws ("" if none).
  std::string error_of(const std::string& text) {
    const auto file = write("bad.yaml", text);
    try {
      load_run_plan(file, test::catalog(), registry_);
    } catch (const core::InputError& e) {
      return e.what();
    }
    return "";
  }
  std::filesystem::path dir_;
  core::ProgramRegistry registry_;
};

constexpr const char* kReach =
    "program: reach\nparams: {object: cup}\nrobots: [minibot]\nenvironments: [kitchen]\n";

TEST_F(ScenarioFiles, ReadsPlannersObstaclesAndLimits) {
  const auto file =
      write("s.yaml", std::string(kReach) +
                          "planners:\n"
                          "  - RRTConnect\n"
                          "  - {name: RRTConnect, label: short_range, params: {range: 0.3}}\n"
                          "obstacles: {count: 5, regions: [floor], shapes: [box, sphere],\n"
                          "            footprint_m: [0.05, 0.08], half_height_m: [0.1, 0.2]}\n"
                          "trials: 3\nlayout_seed: 10\nseed: 7\nwall_limit_s: 30\n");
  const RunPlan plan = load_run_plan(file, test::catalog(), registry_);
  ASSERT_EQ(plan.scenarios.size(), 1u);
  const Scenario& s = plan.scenarios[0];
  EXPECT_EQ(s.name, "s");
  ASSERT_EQ(s.planners.size(), 2u);
  EXPECT_EQ(s.planners[1].label, "short_range");
  EXPECT_EQ(s.planners[1].spec.params.at("range"), "0.3");
  EXPECT_EQ(s.obstacles.count, 5);
  EXPECT_EQ(s.obstacles.regions, std::vector<std::string>{"floor"});
  EXPECT_EQ(s.obstacles.shapes.size(), 2u);
  EXPECT_DOUBLE_EQ(s.obstacles.footprint_max_m, 0.08);
  EXPECT_DOUBLE_EQ(s.wall_limit_s, 30.0);
  // The matrix: 1 robot x 1 environment x 2 planners x 3 trials, seeds counting up.
  const std::vector<TrialSpec> m = trial_matrix(plan);
  ASSERT_EQ(m.size(), 6u);
  EXPECT_EQ(m[0].id, "s.minibot.kitchen.RRTConnect.l10.s7");
  EXPECT_EQ(m[2].id, "s.minibot.kitchen.RRTConnect.l12.s9");
  EXPECT_EQ(m[5].id, "s.minibot.kitchen.short_range.l12.s9");
  // Each id names its trial, and any seeds may be asked for.
  const TrialSpec t = parse_trial_id(plan, "s.minibot.kitchen.short_range.l99.s5");
  EXPECT_EQ(t.planner, 1);
  EXPECT_EQ(t.layout_seed, 99u);
  EXPECT_EQ(t.seed, 5u);
  // The obstacle options reach the layout: 5 obstacles, all on the floor, boxes and spheres.
  const core::ObstacleLayout layout =
      test::scene("minibot", "kitchen")->make_layout(s.obstacles, 10);
  ASSERT_EQ(layout.obstacles.size(), 5u);
  for (const core::PlacedObstacle& o : layout.obstacles) {
    EXPECT_NE(o.shape, core::ObstacleShape::kCylinder);
    EXPECT_LT(o.position.z(), 0.5);  // on the floor, not a table top
  }
}

TEST_F(ScenarioFiles, BadTrialIdsAreExplained) {
  const RunPlan plan = load_run_plan(write("s.yaml", kReach), test::catalog(), registry_);
  auto error = [&](const std::string& id) {
    try {
      parse_trial_id(plan, id);
    } catch (const core::InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(error("s.minibot.kitchen").find("expected <scenario>"), std::string::npos);
  EXPECT_NE(error("s.tallbot.kitchen.RRTConnect.l1.s1").find("no robot 'tallbot'"),
            std::string::npos);
  EXPECT_NE(error("s.minibot.kitchen.PRM.l1.s1").find("no planner 'PRM'"), std::string::npos);
  EXPECT_NE(error("s.minibot.kitchen.RRTConnect.1.s1").find("expected l<number>"),
            std::string::npos);
  EXPECT_NE(error("s.minibot.kitchen.RRTConnect.l1.s0").find("1..4294967295"), std::string::npos);
}

TEST_F(ScenarioFiles, MistakesNameFileLineAndKey) {
  const std::string r(kReach);
  EXPECT_NE(error_of(r + "trails: 3\n").find("bad.yaml:5: trails: unknown key"), std::string::npos)
      << error_of(r + "trails: 3\n");
  EXPECT_NE(error_of(r + "time_limit_s: .nan\n").find("time_limit_s"), std::string::npos);
  EXPECT_NE(error_of(r + "time_limit_s: .nan\n").find("finite"), std::string::npos)
      << error_of(r + "time_limit_s: .nan\n");
  EXPECT_NE(error_of(r + "planners: [RRTFast]\n").find("unknown planner 'RRTFast'"),
            std::string::npos);
  const std::string bad_param = r + "planners: [{name: RRTConnect, params: {rnage: 0.3}}]\n";
  EXPECT_NE(
      error_of(bad_param).find("params: planner RRTConnect: parameter 'rnage' is unknown (known: "),
      std::string::npos)
      << error_of(bad_param);
  EXPECT_NE(error_of(r + "planners: [{name: RRTConnect, params: {range: fast}}]\n")
                .find("rejects 'fast'"),
            std::string::npos);
  EXPECT_NE(error_of(r + "obstacles: {count: 2, shapes: [cube]}\n").find("unknown shape 'cube'"),
            std::string::npos);
  EXPECT_NE(error_of(r + "obstacles: {count: 2, footprint_m: [0.2, 0.1]}\n").find("min <= max"),
            std::string::npos);
  EXPECT_NE(error_of(r + "trials: 0\n").find("trials: must be in 1..100000"), std::string::npos);
  EXPECT_NE(error_of("suite: s\nscenarios: [missing.yaml]\n").find("no scenario file"),
            std::string::npos);
  write("a.yaml", kReach);
  EXPECT_NE(error_of("suite: s\nscenarios: [a.yaml, a.yaml]\n").find("two scenarios are named 'a'"),
            std::string::npos);
}

TEST_F(ScenarioFiles, SuitesOverrideEveryScenario) {
  write("a.yaml", kReach);
  write("b.yaml",
        "program: grasp\nparams: {object: cup}\nsetup: [{program: reach, params: {object: cup}}]\n"
        "robots: [tallbot]\nenvironments: [office]\n");
  const auto file = write("suite.yaml",
                          "suite: both\nscenarios: [a.yaml, b.yaml]\ntrials: 2\n"
                          "planners: [RRTConnect, BiEST]\n");
  RunPlan plan = load_run_plan(file, test::catalog(), registry_);
  EXPECT_TRUE(plan.suite);
  EXPECT_EQ(plan.name, "both");
  ASSERT_EQ(plan.scenarios.size(), 2u);
  EXPECT_EQ(trial_matrix(plan).size(), 2u * 2u * 2u);
  RunOverrides o;
  o.trials = 1;
  o.planners = {"PRM"};
  apply_overrides(plan, o);
  EXPECT_EQ(trial_matrix(plan).size(), 2u);
  EXPECT_EQ(trial_matrix(plan)[1].id, "b.tallbot.office.PRM.l1.s1");
  o.planners = {"Nope"};
  EXPECT_THROW(apply_overrides(plan, o), core::InputError);
}

TEST_F(ScenarioFiles, ExecutionModeIsCheckedAndOverridden) {
  const std::string r(kReach);
  EXPECT_EQ(load_run_plan(write("p.yaml", r), test::catalog(), registry_).scenarios[0].execution,
            "physics");
  write("k.yaml", r + "execution: kinematic\n");
  EXPECT_EQ(load_run_plan(dir_ / "k.yaml", test::catalog(), registry_).scenarios[0].execution,
            "kinematic");
  const std::string bad = error_of(r + "execution: kinetic\n");
  EXPECT_NE(bad.find("bad.yaml:5: execution: must be physics, kinematic or physics_unpruned, "
                     "not 'kinetic'"),
            std::string::npos)
      << bad;
  write("u.yaml", r + "execution: physics_unpruned\n");
  EXPECT_EQ(load_run_plan(dir_ / "u.yaml", test::catalog(), registry_).scenarios[0].execution,
            "physics_unpruned");
  // A suite's key replaces every scenario's; the command line's replaces the suite's.
  RunPlan plan = load_run_plan(write("suite.yaml",
                                     "suite: s\nscenarios: [p.yaml, k.yaml]\n"
                                     "execution: physics\n"),
                               test::catalog(), registry_);
  EXPECT_EQ(plan.scenarios[1].execution, "physics");
  RunOverrides o;
  o.execution = "kinematic";
  apply_overrides(plan, o);
  EXPECT_EQ(plan.scenarios[0].execution, "kinematic");
  EXPECT_EQ(plan.scenarios[1].execution, "kinematic");
  o.execution = "fast";
  EXPECT_THROW(apply_overrides(plan, o), core::InputError);
}

TEST_F(ScenarioFiles, InlineMachinesBecomePrograms) {
  const auto file = write("m.yaml", R"(machine:
  name: reach_and_grasp
  parameters: {object: {type: string}}
  initial: reach
  states:
    reach: {program: reach, params: {object: $object}}
    grasp: {program: grasp, params: {object: $object}}
    done: {final: success}
  transitions:
    - {from: reach, on: completed, to: grasp}
    - {from: grasp, on: completed, to: done}
params: {object: cup}
robots: [minibot]
environments: [kitchen]
)");
  const RunPlan plan = load_run_plan(file, test::catalog(), registry_);
  EXPECT_EQ(plan.scenarios[0].run.program, "reach_and_grasp");
  EXPECT_NE(registry_.find("reach_and_grasp"), nullptr);
  // A machine whose state names an unknown program is refused with its line.
  const std::string bad = error_of(R"(machine:
  name: broken
  initial: a
  states:
    a: {program: teleport}
    done: {final: success}
  transitions:
    - {from: a, on: completed, to: done}
robots: [minibot]
environments: [kitchen]
)");
  EXPECT_NE(bad.find("bad.yaml:5"), std::string::npos) << bad;
  EXPECT_NE(bad.find("teleport"), std::string::npos) << bad;
}

TEST_F(ScenarioFiles, ValidateChecksLayoutsBeforeAnything) {
  // The region exists in neither environment: caught by validation, naming the scenario.
  const auto file =
      write("s.yaml", std::string(kReach) + "obstacles: {count: 3, regions: [roof]}\n");
  try {
    validate_run_plan(test::catalog(), registry_, file);
    FAIL() << "no error";
  } catch (const core::InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("s.yaml: obstacles"), std::string::npos) << what;
    EXPECT_NE(what.find("no region 'roof' (known: floor, table_top)"), std::string::npos) << what;
  }
  // Too many obstacles for the room: the same.
  const auto crowded = write("c.yaml", std::string(kReach) + "obstacles: {count: 400}\n");
  EXPECT_THROW(validate_run_plan(test::catalog(), registry_, crowded), core::InputError);
  EXPECT_EQ(validate_run_plan(test::catalog(), registry_, write("ok.yaml", kReach)), 1);
}

// A misspelled name of something in the world is refused before anything runs, with the file,
// line and key where it is written and which program would have used it: a program's
// parameter (followed into the machines pickup and putdown run), a state of an inline machine,
// a machine's default, a guard and the success condition; every environment the scenario
// lists is asked. Before, each of these validated and the trials failed as they ran
// (`perception_miss: 'cupp' is not in the perceptual model`).
TEST_F(ScenarioFiles, ValidateRefusesANameNoEnvironmentKnowsWithWhereItIsWritten) {
  auto refusal = [&](const std::string& text) {
    const auto file = write("names.yaml", text);
    core::ProgramRegistry fresh;  // an inline machine registers its name
    programs::register_programs(fresh);
    try {
      validate_run_plan(test::catalog(), fresh, file);
    } catch (const core::InputError& e) {
      return std::string(e.what());
    }
    return std::string("validated");
  };
  const std::string file = (dir_ / "names.yaml").string();
  const std::string where = "robots: [minibot]\nenvironments: [kitchen, office]\n";
  const std::string cupp = refusal("program: pickup\nparams: {object: cupp}\n" + where);
  EXPECT_EQ(cupp.rfind(file + ":2: params.object: no object 'cupp' in environment 'kitchen' "
                              "(used by pickup > ",
                       0),
            0u)
      << cupp;
  EXPECT_NE(cupp.find("it knows: box, cup, "), std::string::npos) << cupp;
  const std::string surface =
      refusal("program: putdown\nparams: {object: cup, surface: side_surfac}\n" + where +
              "setup:\n  - {program: pickup, params: {object: cup}}\n");
  EXPECT_EQ(surface.rfind(file + ":2: params.surface: no object 'side_surfac' in environment "
                                 "'kitchen' (used by putdown > position(place): parameter 'on'; "
                                 "it knows: box, cup, ",
                          0),
            0u)
      << surface;
  const std::string setup =
      refusal("program: putdown\nparams: {object: cup}\n" + where +
              "setup:\n  - {program: pickup, params: {object: cup}}\n  - {program: reach, params: "
              "{object: mug}}\n");
  EXPECT_EQ(setup.rfind(file + ":7: setup[1].params.object: no object 'mug'", 0), 0u) << setup;
  const std::string machine = R"yaml(machine:
  name: carry
  parameters: {to: {type: string, default: counter}}
  initial: take
  states:
    take: {program: pickup, params: {object: cup}}
    place: {program: putdown, params: {object: cup, surface: $to}}
    wave: {program: greet, params: {target: visiter}}
    done: {final: success}
  transitions:
    - {from: take, on: completed, to: place}
    - {from: place, on: completed, to: wave, when: "near(cup, side_surface)"}
    - {from: wave, on: completed, to: done}
)yaml";
  const std::string by_default = refusal(machine + where);
  EXPECT_EQ(by_default.rfind(file + ":3: machine.parameters.to: no object 'counter'", 0), 0u)
      << by_default;
  EXPECT_NE(by_default.find("(used by carry > putdown(place) > position(place): parameter 'on' "
                            "(the default of 'to');"),
            std::string::npos)
      << by_default;
  const std::string in_state = refusal(machine + "params: {to: side_surface}\n" + where);
  EXPECT_EQ(in_state.rfind(file + ":8: machine.states.wave: no object 'visiter'", 0), 0u)
      << in_state;
  std::string guarded = machine + "params: {to: side_surface}\n" + where;
  guarded.replace(guarded.find("visiter"), 7, "visitor");
  guarded.replace(guarded.find("near(cup, side_surface)"), 23, "near(cupp, side_surface)");
  const std::string guard = refusal(guarded);
  EXPECT_EQ(guard.rfind(file + ":12: machine.transitions[1]: no object 'cupp'", 0), 0u) << guard;
  EXPECT_NE(guard.find("used by carry, transition 1 (from place) guard"), std::string::npos)
      << guard;
  const std::string success =
      refusal(std::string(kReach) + "success: all_of(graspable(cup), not(in_view(vistor)))\n");
  EXPECT_EQ(success.rfind(file + ":5: success: no object 'vistor'", 0), 0u) << success;
  // What every environment has: the debris flakes, the visitor, the obstacle slots.
  EXPECT_EQ(refusal("program: fixate\nparams: {object: debris_4}\n" + where), "validated");
  EXPECT_EQ(refusal("program: fixate\nparams: {object: obstacle_3}\n" + where), "validated");
  EXPECT_EQ(refusal("program: fixate\nparams: {object: visitor}\n" + where), "validated");
  for (const char* slot : {"obstacle_400", "obstacle_007"}) {
    const std::string refused =
        refusal("program: fixate\nparams: {object: " + std::string(slot) + "}\n" + where);
    EXPECT_NE(refused.find("no object '" + std::string(slot) + "'"), std::string::npos) << refused;
  }
  // A guard's word with a parameter inside it is checked as the machine makes it.
  const std::string numbered = R"yaml(machine:
  name: watch
  parameters: {n: {type: string, default: "3"}}
  initial: look
  states:
    look: {program: fixate, params: {object: cup}}
    done: {final: success}
  transitions:
    - {from: look, on: completed, to: done, when: "in_view(obstacle_$n)"}
)yaml";
  EXPECT_EQ(refusal(numbered + where), "validated");
  const std::string padded = refusal(numbered + "params: {n: \"007\"}\n" + where);
  EXPECT_NE(padded.find("no object 'obstacle_007'"), std::string::npos) << padded;
  // Every environment listed is asked: one without a visitor, listed second.
  test::ScratchRoot root;
  const std::filesystem::path environments = root.path() / "models" / "environments";
  std::filesystem::copy(environments / "kitchen", environments / "bare",
                        std::filesystem::copy_options::recursive);
  root.replace("models/environments/bare/environment.yaml", "name: kitchen\n", "name: bare\n");
  root.replace("models/environments/bare/environment.yaml",
               "visitor: {body: visitor, path: [[2.5, -1.0], [2.5, 1.0]]}\n", "");
  core::ProgramRegistry fresh;
  programs::register_programs(fresh);
  const auto greet = write("greet.yaml",
                           "program: greet\nrobots: [minibot]\nenvironments: "
                           "[kitchen, bare]\n");
  try {
    validate_run_plan(ModelCatalog(root.path()), fresh, greet);
    ADD_FAILURE() << "validated";
  } catch (const core::InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(greet.string() +
                                              ":1: params.target: no object "
                                              "'visitor' in environment 'bare' (used by greet",
                                          0),
              0u)
        << e.what();
  }
}

// validate warns, and still validates, where a machine leaves a state no transition leads to
// or reaches no final state with success.
TEST_F(ScenarioFiles, ValidateWarnsOfAMachineStateNeverReachedAndOfNoWayToSucceed) {
  const std::string machine = R"(machine:
  name: fetch_cup
  initial: take
  states:
    take: {program: pickup, params: {object: cup}}
    spare: {program: reach, params: {object: box}}
    done: {final: success}
    gave_up: {final: failure}
  transitions:
    - {from: take, on: completed, to: done}
    - {from: take, on: failed, to: gave_up}
    - {from: spare, on: completed, to: done}
robots: [minibot]
environments: [kitchen]
)";
  std::vector<std::string> warnings;
  EXPECT_EQ(validate_run_plan(test::catalog(), registry_, write("w.yaml", machine), &warnings), 1);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0], (dir_ / "w.yaml").string() +
                             ": warning: machine 'fetch_cup': state 'spare' is never reached: no "
                             "transition leads to it from 'take'");
  std::string failing = machine;
  failing.replace(failing.find("{from: take, on: completed, to: done}"), 37,
                  "{from: take, on: completed, to: gave_up}");
  failing.replace(failing.find("name: fetch_cup"), 15, "name: fetch_cup2");
  warnings.clear();
  EXPECT_EQ(validate_run_plan(test::catalog(), registry_, write("f.yaml", failing), &warnings), 1);
  ASSERT_EQ(warnings.size(), 3u);
  EXPECT_NE(warnings[1].find("state 'done' is never reached"), std::string::npos) << warnings[1];
  EXPECT_NE(warnings[2].find("machine 'fetch_cup2': no final state with success is reached, so "
                             "the machine can only fail"),
            std::string::npos)
      << warnings[2];
  // A concurrent program never started fires no transition: the success it alone leads to
  // is never reached.
  const std::string idle = R"(machine:
  name: idle_watch
  concurrent:
    watch: {program: fixate, params: {object: cup}, at_start: false}
  initial: take
  states:
    take: {program: pickup, params: {object: cup}}
    done: {final: success}
    gave_up: {final: failure}
  transitions:
    - {from: take, on: completed, to: gave_up}
    - {from: watch, on: completed, to: done}
robots: [minibot]
environments: [kitchen]
)";
  warnings.clear();
  validate_run_plan(test::catalog(), registry_, write("i.yaml", idle), &warnings);
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_NE(warnings[0].find("state 'done' is never reached"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[1].find("no final state with success"), std::string::npos) << warnings[1];
  // The built-in machines (pickup, putdown, greet, vacuum) and the task files: none.
  for (const char* task : {"tidy.yaml", "chores.yaml", "restock.yaml"}) {
    core::ProgramRegistry fresh;
    programs::register_programs(fresh);
    warnings.clear();
    validate_run_plan(test::catalog(), fresh,
                      std::filesystem::path(TASKMATRIX_TEST_ROOT) / "scenarios" / "tasks" / task,
                      &warnings);
    EXPECT_TRUE(warnings.empty()) << task << ": " << (warnings.empty() ? "" : warnings[0]);
  }
}

// The obstacle density suite (scenarios/suites/obstacle_density.yaml) puts its obstacles where
// they interfere with the task: in every one of its 720 trials' worlds a density of n holds n
// obstacles, three quarters of them on the table within 0.35 m of the cup.
TEST_F(ScenarioFiles, ObstacleDensitySuitePlacesItsObstaclesAroundTheCup) {
  const ModelCatalog catalog(TASKMATRIX_TEST_ROOT);
  const RunPlan plan = load_run_plan(
      catalog.root() / "scenarios" / "suites" / "obstacle_density.yaml", catalog, registry_);
  const std::vector<TrialSpec> trials = trial_matrix(plan);
  ASSERT_EQ(trials.size(), 720U);
  std::map<int, int> trials_per_density;
  std::map<std::string, std::shared_ptr<const mujoco::Scene>> scenes;  // one room: the kitchen
  for (const TrialSpec& t : trials) {
    const Scenario& scenario = plan.scenarios[static_cast<size_t>(t.scenario)];
    const int n = std::stoi(scenario.name.substr(scenario.name.rfind("_n") + 2));
    ++trials_per_density[n];
    std::shared_ptr<const mujoco::Scene>& scene = scenes[t.robot];
    if (!scene) {
      scene =
          mujoco::Scene::load(catalog.robot_dir(t.robot), catalog.environment_dir(t.environment));
    }
    const core::TrialLayout layout =
        draw_trial_layout(scenario, mujoco::MujocoLoadedScene(scene), t.layout_seed, t.id);
    mujoco::WorkerScene worker(scene);
    worker.apply(layout);
    worker.reset_to_start();
    const int cup = mj_name2id(worker.model(), mjOBJ_BODY, "cup");
    ASSERT_GE(cup, 0);
    const double* c = worker.data()->xpos + 3 * cup;
    ASSERT_EQ(static_cast<int>(layout.obstacles.obstacles.size()), n) << t.id;
    int near = 0;
    for (const core::PlacedObstacle& o : layout.obstacles.obstacles) {
      if (o.group < 0 ||
          layout.obstacles.groups[static_cast<size_t>(o.group)] != "obstacles near cup") {
        continue;
      }
      ++near;
      EXPECT_LE(std::hypot(o.position.x() - c[0], o.position.y() - c[1]), 0.35 + 1e-9) << t.id;
      EXPECT_GT(o.position.z(), c[2] - 0.1) << t.id << ": not on the table";
    }
    EXPECT_EQ(near, 3 * n / 4) << t.id;
  }
  EXPECT_EQ(trials_per_density, (std::map<int, int>{{0, 180}, {4, 180}, {8, 180}, {12, 180}}));
}

TEST(Statistics, WilsonIntervalMatchesPublishedValues) {
  // Reference values from the Wilson score formula (e.g. Newcombe 1998, table I: 81/263).
  const Interval a = wilson_interval(81, 263);
  EXPECT_NEAR(a.low, 0.2553, 5e-4);
  EXPECT_NEAR(a.high, 0.3662, 5e-4);
  const Interval none = wilson_interval(0, 10);
  EXPECT_DOUBLE_EQ(none.low, 0.0);
  EXPECT_NEAR(none.high, 0.2775, 5e-4);
  const Interval all = wilson_interval(4, 4);
  EXPECT_NEAR(all.low, 0.5101, 5e-4);
  EXPECT_DOUBLE_EQ(all.high, 1.0);
  EXPECT_DOUBLE_EQ(wilson_interval(0, 0).high, 1.0);
}

TEST(Statistics, QuantilesInterpolateBetweenRanks) {
  EXPECT_DOUBLE_EQ(quantile({3, 1, 2}, 0.5), 2.0);
  EXPECT_DOUBLE_EQ(quantile({1, 2, 3, 4}, 0.5), 2.5);
  EXPECT_NEAR(quantile({1, 2, 3, 4, 5, 6, 7, 8, 9, 10}, 0.9), 9.1, 1e-12);
  EXPECT_TRUE(std::isnan(quantile({}, 0.5)));
}

}  // namespace
}  // namespace taskmatrix::harness
