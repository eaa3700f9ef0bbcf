// taskmatrix merge OUT SHARD_DIR...
#include <iostream>

#include "harness/cli/verb.h"
#include "harness/run/merge_job.h"

namespace taskmatrix::harness::cli {
namespace {

class Merge final : public Verb {
 public:
  CLI::App* add_to(CLI::App& app) override {
    CLI::App* merge = app.add_subcommand(
        "merge", "Union the run directories of a sharded run (run --shard) into one run directory");
    merge->add_option("OUT", out_, "the merged run directory (its old results are replaced)")
        ->required();
    merge->add_option("SHARD_DIR", dirs_, "the shards' run directories")->required();
    merge->add_flag("--allow-partial", options_.allow_partial,
                    "merge even when trials are missing or duplicated (the first copy is kept)");
    merge->add_flag("--move", options_.move_trajectories,
                    "move trajectories out of the shards instead of hard-linking them");
    return merge;
  }

  int run(VerbContext& context) override {
    const ModelCatalog& catalog = context.catalog();
    options_.out = out_;
    options_.shard_dirs.assign(dirs_.begin(), dirs_.end());
    options_.command_line = context.command_line();
    const MergeJobResult r =
        run_merge_job(catalog, context.programs(), options_, std::cout, std::cerr);
    if (r.dir.empty()) return 1;
    std::cerr << "taskmatrix: merged " << dirs_.size() << " shard directories: " << r.merged
              << " of " << r.planned << " trials in " << r.dir.string() << " (" << r.successes
              << " succeeded)\n";
    return 0;
  }

 private:
  MergeJobOptions options_;
  std::string out_;
  std::vector<std::string> dirs_;
};

}  // namespace

std::unique_ptr<Verb> merge_verb() { return std::make_unique<Merge>(); }

}  // namespace taskmatrix::harness::cli
