// taskmatrix list robots | environments | programs | planners
#include <iostream>

#include "harness/cli/verb.h"
#include "taskmatrix/core/motion_planning.h"

namespace taskmatrix::harness::cli {
namespace {

class List final : public Verb {
 public:
  CLI::App* add_to(CLI::App& app) override {
    CLI::App* list = app.add_subcommand(
        "list", "List robots, environments, task programs or planners, one name per line");
    list->add_option("what", what_, "robots | environments | programs | planners")
        ->required()
        ->check(CLI::IsMember({"robots", "environments", "programs", "planners"}));
    return list;
  }

  int run(VerbContext& context) override {
    // Programs and planners need no models.
    const std::vector<std::string> names = what_ == "programs"   ? context.programs().names()
                                           : what_ == "planners" ? core::planner_registry().names()
                                           : what_ == "robots"   ? context.catalog().robots()
                                                                 : context.catalog().environments();
    for (const std::string& name : names) std::cout << name << "\n";
    return 0;
  }

 private:
  std::string what_;
};

}  // namespace

std::unique_ptr<Verb> list_verb() { return std::make_unique<List>(); }

}  // namespace taskmatrix::harness::cli
