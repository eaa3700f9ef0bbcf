// `taskmatrix bench-compare BASE.json NEW.json`, run as a user runs it, on small synthetic
// Google Benchmark JSON files: exact counters must match, times may move within the noise
// tolerance, missing benchmarks are reported, bad input is one line naming the file (exit 2).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "tests/test_support.h"

namespace taskmatrix::harness {
namespace {

struct Bench {
  std::string name;
  double real_time = 0;
  std::string unit = "ms";
  std::map<std::string, double> counters;
  std::optional<double> cv;  // set: written as repetitions (median, stddev and cv aggregates)
};

std::string number(double v) {
  std::ostringstream out;
  out.precision(17);
  out << v;
  return out.str();
}

std::string entry(const Bench& b, const std::string& aggregate, double real_time,
                  const std::string& aggregate_unit, const std::string& counter_value) {
  std::string s = "{\"name\": \"" + b.name + (aggregate.empty() ? "" : "_" + aggregate) +
                  "\", \"run_name\": \"" + b.name + "\", \"run_type\": \"" +
                  (aggregate.empty() ? "iteration" : "aggregate") + "\", ";
  if (!aggregate.empty()) {
    s += "\"repetitions\": 3, \"aggregate_name\": \"" + aggregate + "\", \"aggregate_unit\": \"" +
         aggregate_unit + "\", ";
  }
  s += "\"iterations\": 10, \"real_time\": " + number(real_time) +
       ", \"cpu_time\": " + number(real_time) + ", \"time_unit\": \"" + b.unit + "\"";
  for (const auto& [key, value] : b.counters)
    s += ", \"" + key + "\": " + (counter_value.empty() ? number(value) : counter_value);
  return s + "}";
}

// A file as taskmatrix_bench writes it, declaring collision_checks and solved exact.
std::string bench_json(const std::vector<Bench>& benches) {
  std::string s =
      "{\"context\": {\"date\": \"2026-11-22\", \"num_cpus\": 2, "
      "\"taskmatrix_exact_counters\": \"collision_checks,solved\"},\n\"benchmarks\": [\n";
  bool first = true;
  for (const Bench& b : benches) {
    std::vector<std::string> entries;
    if (b.cv) {
      entries.push_back(entry(b, "mean", b.real_time, "time", ""));
      entries.push_back(entry(b, "median", b.real_time, "time", ""));
      entries.push_back(entry(b, "stddev", *b.cv * b.real_time, "time", "0"));
      // As Google Benchmark writes it: a counter that is 0 in every repetition has cv NaN.
      entries.push_back(entry(b, "cv", *b.cv, "percentage", "NaN"));
    } else {
      entries.push_back(entry(b, "", b.real_time, "", ""));
    }
    for (const std::string& e : entries) {
      s += (first ? "  " : ",\n  ") + e;
      first = false;
    }
  }
  return s + "\n]}\n";
}

class BenchCompareTest : public ::testing::Test {
 protected:
  void SetUp() override {
    char tmpl[] = "/tmp/taskmatrix_bench_compare_XXXXXX";
    dir_ = mkdtemp(tmpl);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::string write(const std::string& name, const std::string& text) const {
    const std::filesystem::path p = dir_ / name;
    std::ofstream(p) << text;
    return p.string();
  }

  test::CommandResult compare(const std::vector<Bench>& base, const std::vector<Bench>& now,
                              const std::string& options = "--fail-on-regression") const {
    return test::run_cli("bench-compare " + write("base.json", bench_json(base)) + " " +
                             write("new.json", bench_json(now)) + " " + options,
                         test::catalog().root());
  }

  std::filesystem::path dir_;
};

const std::vector<Bench> kBase = {
    {"BM_Check_Raw", 2.0, "ms", {{"collision_checks", 102.9375}}, std::nullopt},
    {"BM_Check_Skillset", 0.5, "ms", {{"collision_checks", 108.8125}, {"rate", 3.5}}, std::nullopt},
    {"BM_IK_Raw", 10.0, "ms", {{"solved", 14}}, std::nullopt},
};

// The row of the table for `benchmark` (its first line starting "| benchmark |").
std::string row(const std::string& out, const std::string& benchmark) {
  const size_t at = out.find("| " + benchmark + " |");
  if (at == std::string::npos) return "";
  return out.substr(at, out.find('\n', at) - at);
}

std::string last_line(const std::string& out) {
  std::string s = out;
  while (!s.empty() && s.back() == '\n') s.pop_back();
  return s.substr(s.rfind('\n') + 1);
}

TEST_F(BenchCompareTest, IdenticalFilesPass) {
  const test::CommandResult r = compare(kBase, kBase);
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_EQ(last_line(r.out),
            "bench-compare: 3 benchmarks compared: 0 regressed (0 slower, 0 exact counters "
            "changed, 0 errors), 0 faster, 3 ok; 0 only in base, 0 only in new");
  EXPECT_NE(row(r.out, "BM_Check_Raw").find("| 2 ms | 2 ms | 1 | ok (tolerance 25%)"),
            std::string::npos)
      << r.out;
  // The skillset benchmark against its raw partner within the new file: 0.5 / 2.
  EXPECT_NE(r.out.find("| BM_Check_Skillset | BM_Check_Raw | 0.25 (4x faster) | 0.25 |"),
            std::string::npos)
      << r.out;
}

TEST_F(BenchCompareTest, SkillsetBenchmarksAreRatedAgainstTheirRawPartnerOfTheSameRun) {
  const std::vector<Bench> base = {
      {"BM_V_Raw/arm_only:0", 100, "us", {}, std::nullopt},
      {"BM_V_Raw/arm_only:1", 200, "us", {}, std::nullopt},
      {"BM_V_Skillset/arm_only:1", 20, "us", {}, std::nullopt},
      {"BM_Plan_OMPLRaw/iterations:16", 10, "ms", {}, std::nullopt},
      {"BM_Plan_Skillset/clearance_mm:0/iterations:16", 2, "ms", {}, std::nullopt},
      {"BM_Lone_Skillset", 1, "ms", {}, std::nullopt},
  };
  std::vector<Bench> now = base;
  for (Bench& b : now) b.real_time *= 2;  // a slower machine: the ratios stay
  now[2].real_time = 80;                  // but not this one's
  const test::CommandResult r = compare(base, now, "");
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("| BM_V_Skillset/arm_only:1 | BM_V_Raw/arm_only:1 | 0.2 (5x faster) | "
                       "0.1 |"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("| BM_Plan_Skillset/clearance_mm:0/iterations:16 | "
                       "BM_Plan_OMPLRaw/iterations:16 | 0.2 (5x faster) | 0.2 |"),
            std::string::npos)
      << r.out;
  EXPECT_EQ(r.out.find("| BM_Lone_Skillset | BM_"), std::string::npos) << r.out;
}

TEST_F(BenchCompareTest, AChangedExactCounterIsARegressionNamedWithBothValues) {
  std::vector<Bench> now = kBase;
  now[1].counters["collision_checks"] = 109.0;
  now[1].counters["rate"] = 7.0;  // not declared exact: may change
  const test::CommandResult r = compare(kBase, now);
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_NE(r.out.find("| BM_Check_Skillset [collision_checks] | 108.8125 | 109 | 1 | "
                       "REGRESSION: exact counter changed |"),
            std::string::npos)
      << r.out;
  EXPECT_EQ(r.out.find("[rate]"), std::string::npos) << r.out;
  EXPECT_NE(last_line(r.out).find("1 regressed (0 slower, 1 exact counters changed"),
            std::string::npos)
      << r.out;
  // Without --fail-on-regression the regression is reported and the exit status is 0.
  EXPECT_EQ(compare(kBase, now, "").exit_code, 0);
}

TEST_F(BenchCompareTest, AnExactCounterMissingInNewIsARegression) {
  std::vector<Bench> now = kBase;
  now[2].counters.clear();
  const test::CommandResult r = compare(kBase, now);
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_NE(row(r.out, "BM_IK_Raw [solved]").find("| 14 | - |"), std::string::npos) << r.out;
  EXPECT_NE(row(r.out, "BM_IK_Raw [solved]").find("missing in new"), std::string::npos) << r.out;
}

TEST_F(BenchCompareTest, TenPercentSlowerIsWithinTheDefaultTolerance) {
  std::vector<Bench> now = kBase;
  now[2].real_time = 11.0;
  const test::CommandResult r = compare(kBase, now);
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(row(r.out, "BM_IK_Raw").find("| 10 ms | 11 ms | 1.1 | ok (tolerance 25%) |"),
            std::string::npos)
      << r.out;
}

TEST_F(BenchCompareTest, SixtyPercentSlowerIsARegression) {
  std::vector<Bench> now = kBase;
  now[2].real_time = 16.0;
  const test::CommandResult r = compare(kBase, now);
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_NE(row(r.out, "BM_IK_Raw").find("| 1.6 | REGRESSION: slower (tolerance 25%) |"),
            std::string::npos)
      << r.out;
  EXPECT_NE(last_line(r.out).find("1 regressed (1 slower, 0 exact"), std::string::npos) << r.out;
  // A wider tolerance from the command line lets it pass.
  EXPECT_EQ(compare(kBase, now, "--fail-on-regression --time-tolerance 0.7").exit_code, 0);
}

TEST_F(BenchCompareTest, FasterBeyondTheToleranceIsReportedNotAFailure) {
  std::vector<Bench> now = kBase;
  now[0].real_time = 1.0;
  const test::CommandResult r = compare(kBase, now);
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(row(r.out, "BM_Check_Raw").find("| faster (tolerance 25%) |"), std::string::npos)
      << r.out;
  EXPECT_NE(last_line(r.out).find("0 regressed (0 slower, 0 exact counters changed, 0 errors), "
                                  "1 faster"),
            std::string::npos)
      << r.out;
}

TEST_F(BenchCompareTest, ANoisyBenchmarkFortyPercentSlowerIsNotARegression) {
  std::vector<Bench> base = kBase, now = kBase;
  base[2].cv = 0.2;  // tolerance max(0.25, 3 x 0.2) = 60%
  now[2].cv = 0.05;
  now[2].real_time = 14.0;
  const test::CommandResult r = compare(base, now);
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(row(r.out, "BM_IK_Raw").find("| 1.4 | ok (tolerance 60%) |"), std::string::npos)
      << r.out;
  // The same slow-down without the spread is a regression.
  base[2].cv = now[2].cv = 0.01;
  EXPECT_EQ(compare(base, now).exit_code, 1);
}

TEST_F(BenchCompareTest, TimesAreComparedInTheirUnits) {
  std::vector<Bench> now = kBase;
  now[2].real_time = 10000;  // us: the same 10 ms
  now[2].unit = "us";
  const test::CommandResult r = compare(kBase, now);
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(row(r.out, "BM_IK_Raw").find("| 10 ms | 10 ms | 1 | ok"), std::string::npos) << r.out;
}

TEST_F(BenchCompareTest, MissingBenchmarksAreReportedOnEitherSide) {
  std::vector<Bench> now = {kBase[0], kBase[1]};
  now.push_back({"BM_Trial/reach", 300, "ms", {}, std::nullopt});
  // A baseline benchmark missing from the new run fails the gate; one only in the new run
  // does not.
  EXPECT_EQ(compare(kBase, now).exit_code, 1);
  std::vector<Bench> more = kBase;
  more.push_back({"BM_Trial/reach", 300, "ms", {}, std::nullopt});
  EXPECT_EQ(compare(kBase, more).exit_code, 0);
  const test::CommandResult r = compare(kBase, now, "");
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(row(r.out, "BM_IK_Raw").find("| 10 ms | - |  | only in base |"), std::string::npos)
      << r.out;
  EXPECT_NE(row(r.out, "BM_Trial/reach").find("| - | 300 ms |  | only in new |"), std::string::npos)
      << r.out;
  EXPECT_NE(last_line(r.out).find("2 benchmarks compared"), std::string::npos) << r.out;
  EXPECT_NE(last_line(r.out).find("1 only in base, 1 only in new"), std::string::npos) << r.out;
}

TEST_F(BenchCompareTest, BadInputIsOneLineNamingTheFile) {
  const std::string good = write("good.json", bench_json(kBase));
  const std::string root = test::catalog().root().string();
  struct Case {
    std::string label, text, expected;  // expected: in the message after the file name
  };
  const std::vector<Case> cases = {
      {"malformed", "{\"benchmarks\": [", ":1: not JSON: "},
      {"no_array", "{\"context\": {}}", ": benchmarks: missing or not an array"},
      {"nan_time",
       "{\"benchmarks\": [{\"name\": \"BM_A\", \"run_type\": \"iteration\", \"real_time\": NaN, "
       "\"time_unit\": \"ns\"}]}",
       ": benchmarks[0].real_time: is NaN"},
      {"bad_unit",
       "{\"benchmarks\": [{\"name\": \"BM_A\", \"real_time\": 1, \"time_unit\": \"h\"}]}",
       ": benchmarks[0].time_unit: unknown time unit 'h'"},
  };
  for (const Case& c : cases) {
    const std::string bad = write(c.label + ".json", c.text);
    for (const std::string& args : {good + " " + bad, bad + " " + good}) {
      const test::CommandResult r = test::run_cli("bench-compare " + args, root);
      EXPECT_EQ(r.exit_code, 2) << c.label << ": " << r.out << r.err;
      EXPECT_EQ(r.err.rfind("taskmatrix: error: " + bad + c.expected, 0), 0u)
          << c.label << ": " << r.err;
      EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    }
  }
  const std::string missing = (dir_ / "no_such.json").string();
  const test::CommandResult r = test::run_cli("bench-compare " + good + " " + missing, root);
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_EQ(r.err, "taskmatrix: error: " + missing +
                       ": cannot read the file (missing or not a regular file)\n");
}

}  // namespace
}  // namespace taskmatrix::harness
