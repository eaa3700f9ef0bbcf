// taskmatrix validate SCENARIO
#include <iostream>
#include <string>
#include <vector>

#include "harness/cli/verb.h"
#include "harness/run/run_job.h"

namespace taskmatrix::harness::cli {
namespace {

class Validate final : public Verb {
 public:
  CLI::App* add_to(CLI::App& app) override {
    CLI::App* validate = app.add_subcommand(
        "validate", "Check a scenario or suite (files, models, planners, layouts) without running");
    validate->add_option("SCENARIO", file_, "scenario or suite YAML")->required();
    return validate;
  }

  int run(VerbContext& context) override {
    const ModelCatalog& catalog = context.catalog();
    std::vector<std::string> warnings;
    const int trials = validate_run_plan(catalog, context.programs(), file_, &warnings);
    for (const std::string& w : warnings) std::cerr << w << "\n";
    std::cout << file_ << ": ok, " << trials << " trials" << (warnings.empty() ? "" : ", ")
              << (warnings.empty() ? ""
                                   : std::to_string(warnings.size()) + " warning" +
                                         (warnings.size() == 1 ? "" : "s"))
              << "\n";
    return 0;
  }

 private:
  std::string file_;
};

}  // namespace

std::unique_ptr<Verb> validate_verb() { return std::make_unique<Validate>(); }

}  // namespace taskmatrix::harness::cli
