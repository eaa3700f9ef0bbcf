// taskmatrix check-robot NAME [--env ENV] [--no-run]
#include <iostream>

#include "harness/cli/verb.h"
#include "harness/run/check_robot.h"

namespace taskmatrix::harness::cli {
namespace {

class CheckRobot final : public Verb {
 public:
  CLI::App* add_to(CLI::App& app) override {
    CLI::App* check_robot = app.add_subcommand(
        "check-robot",
        "Lint a robot's profile against its model, then run the twelve programs once in one "
        "environment (exit 0 clean, 1 lint error, 4 a program failed)");
    check_robot->add_option("NAME", options_.robot, "robot name")->required();
    check_robot->add_option("--env", options_.environment,
                            "environment of the program run (default: kitchen, else the first)");
    check_robot->add_flag("--no-run", no_run_, "the lint only");
    check_robot->add_option("--out", out_,
                            "run directory (default: results/runs/check-robot-NAME-ENV)");
    check_robot->add_option("--jobs", options_.jobs, "trials run at once")
        ->check(CLI::Range(1, 256))
        ->capture_default_str();
    return check_robot;
  }

  int run(VerbContext& context) override {
    const ModelCatalog& catalog = context.catalog();
    options_.run = !no_run_;
    options_.out = out_;
    return run_check_robot(catalog, context.programs(), options_, std::cout, std::cerr);
  }

 private:
  CheckRobotOptions options_;
  std::string out_;
  bool no_run_ = false;
};

}  // namespace

std::unique_ptr<Verb> check_robot_verb() { return std::make_unique<CheckRobot>(); }

}  // namespace taskmatrix::harness::cli
