// taskmatrix bench-compare BASE NEW
#include <iostream>

#include "harness/cli/verb.h"
#include "harness/compare/bench_compare.h"

namespace taskmatrix::harness::cli {
namespace {

class BenchCompare final : public Verb {
 public:
  CLI::App* add_to(CLI::App& app) override {
    CLI::App* bench_compare = app.add_subcommand(
        "bench-compare",
        "Compare two taskmatrix_bench JSON files: exact counters must match, times within noise");
    bench_compare->add_option("BASE", base_, "baseline JSON (--benchmark_out_format=json)")
        ->required();
    bench_compare->add_option("NEW", new_, "new JSON")->required();
    bench_compare
        ->add_option("--time-tolerance", options_.time_tolerance,
                     "relative slow-down allowed before a time is a regression (at least 3 cv)")
        ->check(finite_range(0.0, 100.0))
        ->capture_default_str();
    bench_compare->add_flag("--fail-on-regression", fail_, "exit 1 when anything regressed");
    return bench_compare;
  }

  int run(VerbContext&) override {
    return run_bench_compare(base_, new_, options_, fail_, std::cout);
  }

 private:
  BenchCompareOptions options_;
  std::string base_, new_;
  bool fail_ = false;
};

}  // namespace

std::unique_ptr<Verb> bench_compare_verb() { return std::make_unique<BenchCompare>(); }

}  // namespace taskmatrix::harness::cli
