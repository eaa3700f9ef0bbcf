// The `taskmatrix` command line. Verbs: list, validate, run, merge, render, scenes, compare,
// bench-compare, check-robot (one file each in this folder). Every failure is one line on
// stderr and a non-zero exit status (2 for bad input; 1 for a regression when asked to fail on
// one).
#include <algorithm>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "harness/cli/verb.h"
#include "harness/scenario/planner_plugins.h"

int main(int argc, char** argv) {
  namespace cli = taskmatrix::harness::cli;
  CLI::App app{
      "taskmatrix: robot-independent humanoid task programs on MuJoCo, and a benchmark harness"};
  app.require_subcommand(1);

  // In the order `taskmatrix --help` lists them.
  std::vector<std::unique_ptr<cli::Verb>> verbs;
  verbs.push_back(cli::list_verb());
  verbs.push_back(cli::render_verb());
  verbs.push_back(cli::scenes_verb());
  verbs.push_back(cli::validate_verb());
  verbs.push_back(cli::run_verb());
  verbs.push_back(cli::merge_verb());
  verbs.push_back(cli::check_robot_verb());
  verbs.push_back(cli::bench_compare_verb());
  verbs.push_back(cli::compare_verb());
  std::vector<CLI::App*> subcommands;
  for (const auto& verb : verbs) subcommands.push_back(verb->add_to(app));

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::string what = e.what();
    std::replace(what.begin(), what.end(), '\n', ' ');
    std::cerr << "taskmatrix: error: " << what << " (see taskmatrix --help)\n";
    return 2;
  }

  try {
    taskmatrix::harness::register_builtin_planners();
    cli::VerbContext context(argc, argv);
    for (size_t i = 0; i < verbs.size(); ++i) {
      if (*subcommands[i]) return verbs[i]->run(context);
    }
  } catch (const std::exception& e) {
    std::cerr << "taskmatrix: error: " << e.what() << "\n";
    return 2;
  }
  return 0;
}
