// Comparing two Google Benchmark JSON files (taskmatrix_bench --benchmark_out_format=json), a
// baseline and a new run: `taskmatrix bench-compare BASE.json NEW.json`.
//
//   - Benchmarks are paired by name (the file's run_name): the "median" aggregate when the file
//     has repetitions, else the iteration run (the per-field median of several). Benchmarks
//     found on one side only are reported, not counted as regressions.
//   - Exact counters, the ones BASE's context lists under "taskmatrix_exact_counters" (work
//     counts: collision checks, solved targets, ...): any change (beyond 1e-9 relative, for
//     the formatting of floats) is a regression, and so is an exact counter missing in NEW.
//   - Times (real_time in the entry's time_unit): NEW is slower when new > base * (1 + t) with
//     t = max(time tolerance, 3 x the larger coefficient of variation of either side, from
//     its "cv" aggregate or stddev / mean), faster when new < base / (1 + t); slower is a
//     regression, faster is not. A benchmark that reports an error in NEW is a regression.
//   - The machine-independent figure: each `<Name>_Skillset...` benchmark of NEW over its raw
//     partner measured in the same run (`<Name>_Raw` with the same arguments, else a benchmark
//     `<Name>_...Raw...` with the same or with no arguments; run settings such as
//     `iterations:16` are not arguments), beside the same ratio in BASE.
#pragma once

#include <filesystem>
#include <iosfwd>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace taskmatrix::harness {

// One benchmark of a file, as compared.
struct BenchEntry {
  std::string name;         // run_name: "BM_ValidityCheck_Raw/arm_only:1"
  double real_time_ns = 0;  // the median's (or the run's) real time
  double cv = 0;            // coefficient of variation of real_time; 0 when not reported
  bool error = false;       // the benchmark reported an error (error_occurred)
  std::string error_message;
  std::map<std::string, double> counters;  // finite numeric counters
};

struct BenchFile {
  std::filesystem::path path;
  std::vector<BenchEntry> entries;          // in the order of the file
  std::vector<std::string> exact_counters;  // from context.taskmatrix_exact_counters
  const BenchEntry* find(const std::string& name) const;
};

// Reads a Google Benchmark JSON file (NaN and Infinity as Google Benchmark writes them are
// accepted where they are not used). Throws core::InputError naming the file and key: missing
// or unreadable file, not JSON, no "benchmarks" array, a missing, NaN or infinite value that
// is compared, an unknown time unit.
BenchFile read_bench_file(const std::filesystem::path& file);

struct BenchCompareOptions {
  double time_tolerance = 0.25;  // relative; the floor of each benchmark's tolerance
};

enum class BenchVerdict {
  kOk,              // within the time tolerance (or an exact counter unchanged)
  kFaster,          // beyond the tolerance, faster: reported, not a failure
  kSlower,          // beyond the tolerance, slower: a regression
  kCounterChanged,  // an exact counter differs or is missing in NEW: a regression
  kErrorInNew,      // NEW reports an error for the benchmark: a regression
  kErrorInBase,     // BASE reports an error: nothing to compare
  kOnlyInBase,
  kOnlyInNew,
};
bool is_regression(BenchVerdict verdict);

struct BenchRow {
  std::string benchmark;
  std::string counter;              // empty for the time row
  std::optional<double> base, now;  // ns for times
  double tolerance = 0;             // of a time row
  BenchVerdict verdict = BenchVerdict::kOk;
  std::string note;
};

// A `_Skillset` benchmark over its raw partner, within one file.
struct RawRatio {
  std::string benchmark, raw;
  double ratio = 0;                  // in NEW
  std::optional<double> base_ratio;  // the same pair in BASE
};

struct BenchComparison {
  std::vector<BenchRow> rows;  // a time row per benchmark, then its changed exact counters
  std::vector<RawRatio> raw_ratios;
  int compared = 0;  // benchmarks in both files
  int ok = 0, faster = 0, slower = 0, counters_changed = 0, errors = 0;
  int only_in_base = 0, only_in_new = 0;
  // Benchmarks with at least one regression (slower, a changed exact counter, an error).
  int regressed = 0;
};

BenchComparison compare_bench(const BenchFile& base, const BenchFile& now,
                              const BenchCompareOptions& options);

// The table (benchmark, base, new, ratio, verdict), the ratios to raw, and a last line with
// the counts.
void write_bench_comparison(const BenchFile& base, const BenchFile& now,
                            const BenchComparison& comparison, std::ostream& out);

// `taskmatrix bench-compare`: reads both files, writes the comparison to `out`, returns 1 when
// something regressed and `fail_on_regression` is set, else 0. Throws core::InputError.
int run_bench_compare(const std::filesystem::path& base, const std::filesystem::path& now,
                      const BenchCompareOptions& options, bool fail_on_regression,
                      std::ostream& out);

}  // namespace taskmatrix::harness
