// taskmatrix scenes [--seeds N] [--obstacles K] [--out DIR]
#include <iostream>

#include "harness/cli/verb.h"
#include "harness/run/scenes_job.h"

namespace taskmatrix::harness::cli {
namespace {

class Scenes final : public Verb {
 public:
  CLI::App* add_to(CLI::App& app) override {
    CLI::App* scenes = app.add_subcommand(
        "scenes", "Load every robot in every environment over layout seeds; render and tabulate");
    scenes->add_option("--seeds", options_.seeds, "layout seeds 1..N")
        ->check(CLI::Range(1, 1000))
        ->capture_default_str();
    scenes->add_option("--obstacles", options_.obstacles)
        ->check(CLI::Range(0, 200))
        ->capture_default_str();
    scenes->add_option("--out", out_, "output folder")->capture_default_str();
    return scenes;
  }

  int run(VerbContext& context) override {
    const ModelCatalog& catalog = context.catalog();
    options_.out = out_;
    return run_scenes_job(catalog, options_, std::cout) == 0 ? 0 : 1;
  }

 private:
  ScenesJobOptions options_;
  std::string out_ = options_.out.string();
};

}  // namespace

std::unique_ptr<Verb> scenes_verb() { return std::make_unique<Scenes>(); }

}  // namespace taskmatrix::harness::cli
