// taskmatrix compare BASE_DIR NEW_DIR [--report DIR] [--fail-on-regression] ...
#include <cstdlib>
#include <filesystem>
#include <iostream>

#include "harness/cli/verb.h"
#include "harness/compare/compare_job.h"
#include "harness/replay/trial_video.h"

namespace taskmatrix::harness::cli {
namespace {

// How a command line that renders with this binary and these models starts:
// "[TASKMATRIX_ROOT=ROOT ]/absolute/path/of/taskmatrix" (shell-quoted where needed).
std::string render_command_prefix() {
  std::error_code ec;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
  std::string prefix = ec ? std::string("taskmatrix") : shell_word(self.string());
  if (const char* root = std::getenv("TASKMATRIX_ROOT"); root != nullptr && *root) {
    prefix = "TASKMATRIX_ROOT=" + shell_word(root) + " " + prefix;
  }
  return prefix;
}

class Compare final : public Verb {
 public:
  CLI::App* add_to(CLI::App& app) override {
    CLI::App* compare = app.add_subcommand(
        "compare",
        "Pair the trials of two run directories by id and test what changed (success, planning "
        "time, work counts)");
    CompareThresholds& t = options_.thresholds;
    compare->add_option("BASE_DIR", base_, "the baseline run directory")->required();
    compare->add_option("NEW_DIR", new_, "the run directory to judge")->required();
    compare->add_option("--report", report_,
                        "write compare.md, compare.json and report.html (with pictures of failed "
                        "trials) into this directory");
    compare->add_flag("--fail-on-regression", fail_,
                      "exit 1 when a change is a significant regression beyond the thresholds");
    compare->add_flag("--fail-on-model-change", fail_models_,
                      "exit 1 when the runs loaded model, profile or environment files with "
                      "different contents (or either run did not record their hashes)");
    compare->add_flag("--power", options_.print_power,
                      "also print, per group, the smallest success drop and planning-time ratio "
                      "the runs could detect (80% power) and the trials needed for the targets");
    compare
        ->add_option("--power-drop", t.power_success_target,
                     "the success drop (0..1) whose trials needed the power table gives")
        ->check(CLI::Range(0.001, 1.0))
        ->capture_default_str()
        ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
    compare
        ->add_option("--power-ratio", t.power_time_target,
                     "the planning-time ratio whose trials needed the power table gives "
                     "(default: --max-time-ratio)")
        ->check(CLI::Range(1.001, 1e6))
        ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
    compare->add_flag("--fail-on-unpaired", t.fail_on_unpaired,
                      "a trial without a partner is a regression (both ways, unless --subset)");
    compare->add_flag("--subset", t.new_is_subset,
                      "the new run holds only some of the base's trials (a fast form): base "
                      "trials without a partner are expected");
    compare->add_flag("--fail-on-nonreproducible", t.fail_on_nonreproducible,
                      "a pair where a clock bound decided a trial is a regression");
    compare->add_flag("--include-nonreproducible", t.include_nonreproducible,
                      "judge pairs where a clock bound decided a trial too (left out by default)");
    compare->add_flag("--exact-work", t.exact_work,
                      "any change of a trial's work counts or planned paths is a regression");
    compare->add_flag("--ignore-planner", options_.ignore_planner,
                      "pair trials whatever their planner label (one planner against another)");
    compare->add_option("--alpha", t.alpha, "significance level of McNemar's and Wilcoxon's tests")
        ->check(finite_range(1e-9, 0.5))
        ->capture_default_str()
        ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
    compare
        ->add_option("--max-success-drop", t.max_success_drop,
                     "success-rate drop (0..1) that fails when significant")
        ->check(finite_range(0.0, 1.0))
        ->capture_default_str()
        ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
    compare
        ->add_option("--max-time-ratio", t.max_time_ratio,
                     "planning-time ratio new/base that fails when its 95% interval lies above")
        ->check(finite_range(1.0, 1e6))
        ->capture_default_str()
        ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
    compare
        ->add_option("--max-work-ratio", t.max_work_ratio,
                     "ratio of total collision checks new/base above which a group fails")
        ->check(finite_range(1.0, 1e6))
        ->capture_default_str()
        ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
    compare
        ->add_option("--min-time-pairs", t.min_time_pairs,
                     "fewest pairs that both planned for a planning-time verdict")
        ->check(CLI::Range(2, 1000000))
        ->capture_default_str()
        ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
    compare
        ->add_option("--max-new-failures", t.max_new_failures,
                     "trials that succeeded in the base and now fail, beyond which the run "
                     "fails whatever the test says (-1: off)")
        ->check(CLI::Range(-1, 100000000))
        ->capture_default_str()
        ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
    compare
        ->add_option("--max-snapshots", options_.max_snapshots,
                     "failed trials pictured in report.html")
        ->check(CLI::Range(0, 10000))
        ->capture_default_str()
        ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
    return compare;
  }

  int run(VerbContext& context) override {
    const ModelCatalog& catalog = context.catalog();
    options_.base_dir = base_;
    options_.new_dir = new_;
    options_.report_dir = report_;
    options_.snapshot = [&catalog](const std::string& dir_and_trial, double time_s) {
      FrameOptions frame;
      frame.width = 480;
      frame.height = 360;
      return failure_pictures(catalog, dir_and_trial, time_s, frame);
    };
    options_.render_command = render_command_prefix();
    const CompareJobResult r = run_compare_job(options_, std::cout);
    if (fail_models_ && r.differences.models_changed()) {
      std::cerr << "taskmatrix: compare: the runs' model files differ "
                   "(--fail-on-model-change)\n";
      return 1;
    }
    return fail_ && r.comparison.regression() ? 1 : 0;
  }

 private:
  CompareJobOptions options_;
  std::string base_, new_, report_;
  bool fail_ = false, fail_models_ = false;
};

}  // namespace

std::unique_ptr<Verb> compare_verb() { return std::make_unique<Compare>(); }

}  // namespace taskmatrix::harness::cli
