// A verb of the `taskmatrix` command line: it adds its subcommand, options and flags to the
// CLI11 app, and runs when the command line names it. One file per verb (harness/cli/*.cc);
// main.cc lists them in the order `taskmatrix --help` shows them.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "harness/scenario/model_catalog.h"
#include "taskmatrix/core/task_program.h"

namespace taskmatrix::harness::cli {

// What a verb may use when it runs: the command line, and the models and programs, made when a
// verb first asks for them (a missing models folder is an error only for a verb that needs it).
class VerbContext {
 public:
  VerbContext(int argc, char** argv) : argc_(argc), argv_(argv) {}
  int argc() const { return argc_; }
  char** argv() const { return argv_; }
  std::vector<std::string> command_line() const { return {argv_, argv_ + argc_}; }
  // ModelCatalog::from_environment(); throws what it throws.
  const ModelCatalog& catalog();
  // Every program of taskmatrix/programs, registered (a run adds its scenarios' machines).
  core::ProgramRegistry& programs();

 private:
  int argc_;
  char** argv_;
  std::optional<ModelCatalog> catalog_;
  std::optional<core::ProgramRegistry> programs_;
};

class Verb {
 public:
  virtual ~Verb() = default;
  // Adds the subcommand to `app` (options bound to this verb's members) and returns it.
  virtual CLI::App* add_to(CLI::App& app) = 0;
  // The exit status; a thrown std::exception is one line on stderr and status 2.
  virtual int run(VerbContext& context) = 0;
};

std::unique_ptr<Verb> list_verb();
std::unique_ptr<Verb> render_verb();
std::unique_ptr<Verb> scenes_verb();
std::unique_ptr<Verb> validate_verb();
std::unique_ptr<Verb> run_verb();
std::unique_ptr<Verb> merge_verb();
std::unique_ptr<Verb> check_robot_verb();
std::unique_ptr<Verb> bench_compare_verb();
std::unique_ptr<Verb> compare_verb();

// CLI::Range lets NaN through (every comparison with it is false): numbers must be finite and
// within [lo, hi].
CLI::Validator finite_range(double lo, double hi);

}  // namespace taskmatrix::harness::cli
