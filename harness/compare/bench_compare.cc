#include "harness/compare/bench_compare.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <ostream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "harness/results/json_input.h"
#include "harness/results/summary.h"
#include "taskmatrix/core/input_error.h"

namespace taskmatrix::harness {

namespace {

using nlohmann::json;

constexpr double kCounterRelativeTolerance = 1e-9;

// Google Benchmark writes NaN and Infinity as bare words, which JSON does not allow: they
// become the strings "NaN", "Infinity", "-Infinity" (outside strings only), so a file parses
// and a value that is used can be reported as what it is.
std::string quote_non_finite(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  bool in_string = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      out += c;
      if (c == '\\' && i + 1 < text.size()) {
        out += text[++i];
      } else if (c == '"') {
        in_string = false;
      }
      continue;
    }
    if (c == '"') {
      in_string = true;
      out += c;
      continue;
    }
    bool replaced = false;
    for (const char* word : {"-Infinity", "Infinity", "-NaN", "NaN"}) {
      const size_t n = std::char_traits<char>::length(word);
      if (text.compare(i, n, word) == 0) {
        out += std::string("\"") + (std::string(word) == "-NaN" ? "NaN" : word) + "\"";
        i += n - 1;
        replaced = true;
        break;
      }
    }
    if (!replaced) out += c;
  }
  return out;
}

double ns_per_unit(const std::string& unit) {
  if (unit == "ns") return 1;
  if (unit == "us") return 1e3;
  if (unit == "ms") return 1e6;
  if (unit == "s") return 1e9;
  return 0;
}

// The raw fields of one "benchmarks" element, with its key for messages.
struct Run {
  std::string key;  // benchmarks[i]
  const json* j = nullptr;
};

class Reader {
 public:
  explicit Reader(std::filesystem::path file) : file_(std::move(file)) {}

  [[noreturn]] void fail(const std::string& key, const std::string& message) const {
    throw core::InputError(file_.string(), key, message);
  }

  std::string string_field(const Run& r, const char* field, bool required) const {
    const auto it = r.j->find(field);
    if (it == r.j->end()) {
      if (required) fail(r.key + "." + field, "missing");
      return "";
    }
    if (!it->is_string()) fail(r.key + "." + field, "must be a string");
    return it->get<std::string>();
  }

  // A number that is used: present, numeric and finite.
  double number_field(const Run& r, const std::string& field) const {
    const auto it = r.j->find(field);
    if (it == r.j->end()) fail(r.key + "." + field, "missing");
    if (it->is_string()) {
      const std::string s = it->get<std::string>();
      if (s == "NaN") fail(r.key + "." + field, "is NaN");
      if (s == "Infinity" || s == "-Infinity") fail(r.key + "." + field, "is " + s);
    }
    if (!it->is_number()) fail(r.key + "." + field, "must be a number");
    return it->get<double>();
  }

  double time_ns(const Run& r) const {
    const std::string unit = string_field(r, "time_unit", true);
    const double scale = ns_per_unit(unit);
    if (scale == 0) fail(r.key + ".time_unit", "unknown time unit '" + unit + "' (ns, us, ms, s)");
    const double t = number_field(r, "real_time");
    if (t < 0) fail(r.key + ".real_time", "must not be negative");
    if (!std::isfinite(t * scale)) fail(r.key + ".real_time", "is too large to be a time");
    return t * scale;
  }

 private:
  std::filesystem::path file_;
};

// Fields of a benchmark entry that are not user counters.
bool is_builtin_field(const std::string& key) {
  static const char* const kFields[] = {"name",
                                        "family_index",
                                        "per_family_instance_index",
                                        "run_name",
                                        "run_type",
                                        "repetitions",
                                        "repetition_index",
                                        "threads",
                                        "aggregate_name",
                                        "aggregate_unit",
                                        "iterations",
                                        "real_time",
                                        "cpu_time",
                                        "time_unit",
                                        "error_occurred",
                                        "error_message",
                                        "label",
                                        "big_o",
                                        "rms"};
  return std::find(std::begin(kFields), std::end(kFields), key) != std::end(kFields);
}

std::string format_time(double ns) {
  const char* unit = "ns";
  double v = ns;
  if (ns >= 1e9) {
    v = ns / 1e9;
    unit = "s";
  } else if (ns >= 1e6) {
    v = ns / 1e6;
    unit = "ms";
  } else if (ns >= 1e3) {
    v = ns / 1e3;
    unit = "us";
  }
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.4g %s", v, unit);
  return buf;
}

std::string format_ratio(double r) { return format_number("%.3g", r); }

std::string percent(double fraction) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.0f%%", fraction * 100);
  return buf;
}

bool counters_equal(double a, double b) {
  return a == b ||
         std::abs(a - b) <= kCounterRelativeTolerance * std::max(std::abs(a), std::abs(b));
}

// "BM_Name_Skillset/arg:1/iterations:16" -> {"BM_Name_Skillset", "arg:1"}: the family and
// the benchmark's own arguments, without Google Benchmark's run settings.
std::pair<std::string, std::string> split_name(const std::string& name) {
  const size_t slash = name.find('/');
  if (slash == std::string::npos) return {name, ""};
  std::string args;
  std::stringstream parts(name.substr(slash + 1));
  for (std::string part; std::getline(parts, part, '/');) {
    bool setting = part == "real_time" || part == "process_time" || part == "manual_time";
    for (const char* prefix :
         {"iterations:", "repeats:", "min_time:", "min_warmup_time:", "threads:"}) {
      setting = setting || part.rfind(prefix, 0) == 0;
    }
    if (!setting) args += (args.empty() ? "" : "/") + part;
  }
  return {name.substr(0, slash), args};
}

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// The raw partner of a `_Skillset` benchmark in the same file, or null.
const BenchEntry* raw_partner(const BenchFile& file, const std::string& name) {
  const auto [family, args] = split_name(name);
  const std::string suffix = "_Skillset";
  if (!ends_with(family, suffix)) return nullptr;
  const std::string stem = family.substr(0, family.size() - suffix.size());
  const BenchEntry* exact = nullptr;
  const BenchEntry* with_args = nullptr;
  const BenchEntry* without_args = nullptr;
  for (const BenchEntry& e : file.entries) {
    const auto [other_family, other_args] = split_name(e.name);
    if (other_family == stem + "_Raw" && other_args == args && !exact) exact = &e;
    if (other_family.rfind(stem + "_", 0) != 0) continue;
    if (other_family.find("Raw", stem.size() + 1) == std::string::npos) continue;
    if (other_args == args && !with_args) with_args = &e;
    if (other_args.empty() && !without_args) without_args = &e;
  }
  return exact ? exact : with_args ? with_args : without_args;
}

const char* verdict_text(BenchVerdict v) {
  switch (v) {
    case BenchVerdict::kOk:
      return "ok";
    case BenchVerdict::kFaster:
      return "faster";
    case BenchVerdict::kSlower:
      return "REGRESSION: slower";
    case BenchVerdict::kCounterChanged:
      return "REGRESSION: exact counter changed";
    case BenchVerdict::kErrorInNew:
      return "REGRESSION: error in new";
    case BenchVerdict::kErrorInBase:
      return "error in base";
    case BenchVerdict::kOnlyInBase:
      return "only in base";
    case BenchVerdict::kOnlyInNew:
      return "only in new";
  }
  return "?";
}

}  // namespace

const BenchEntry* BenchFile::find(const std::string& name) const {
  for (const BenchEntry& e : entries) {
    if (e.name == name) return &e;
  }
  return nullptr;
}

BenchFile read_bench_file(const std::filesystem::path& path) {
  const std::string file = path.string();
  std::ifstream in(path, std::ios::binary);
  std::error_code ec;
  if (!in || std::filesystem::is_directory(path, ec)) {
    throw core::InputError(file, "", "cannot read the file (missing or not a regular file)");
  }
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const json doc = parse_json_text(quote_non_finite(text), file);
  const Reader reader(path);
  if (!doc.is_object()) reader.fail("", "not a Google Benchmark JSON file (not an object)");
  const auto benchmarks = doc.find("benchmarks");
  if (benchmarks == doc.end() || !benchmarks->is_array()) {
    reader.fail("benchmarks", "missing or not an array (not a Google Benchmark JSON file)");
  }

  BenchFile out;
  out.path = path;
  const auto context = doc.find("context");
  if (context != doc.end() && context->is_object()) {
    const auto exact = context->find("taskmatrix_exact_counters");
    if (exact != context->end()) {
      if (!exact->is_string()) {
        reader.fail("context.taskmatrix_exact_counters", "must be a comma-separated string");
      }
      std::stringstream list(exact->get<std::string>());
      for (std::string name; std::getline(list, name, ',');) {
        name.erase(0, name.find_first_not_of(" \t"));
        name.erase(name.find_last_not_of(" \t") + 1);
        if (!name.empty()) out.exact_counters.push_back(name);
      }
    }
  }

  // Group the runs by run_name, in file order.
  std::vector<std::string> order;
  std::map<std::string, std::vector<Run>> iterations;
  std::map<std::string, std::map<std::string, Run>> aggregates;
  for (size_t i = 0; i < benchmarks->size(); ++i) {
    const Run r{"benchmarks[" + std::to_string(i) + "]", &(*benchmarks)[i]};
    if (!r.j->is_object()) reader.fail(r.key, "must be an object");
    const std::string name = reader.string_field(r, "name", true);
    std::string run_name = reader.string_field(r, "run_name", false);
    if (run_name.empty()) run_name = name;
    const std::string run_type = reader.string_field(r, "run_type", false);
    if (!iterations.count(run_name) && !aggregates.count(run_name)) order.push_back(run_name);
    if (run_type == "aggregate") {
      const std::string agg = reader.string_field(r, "aggregate_name", true);
      aggregates[run_name].emplace(agg, r);
    } else {
      iterations[run_name].push_back(r);
    }
  }

  for (const std::string& name : order) {
    BenchEntry e;
    e.name = name;
    const auto agg = aggregates.find(name);
    const auto runs = iterations.find(name);
    std::vector<Run> chosen;  // the runs whose fields make the entry (median of several)
    if (agg != aggregates.end() && agg->second.count("median")) {
      chosen.push_back(agg->second.at("median"));
    } else if (runs != iterations.end()) {
      chosen = runs->second;
    } else {
      continue;  // aggregates without a median (only mean, stddev, ...): nothing to compare
    }
    for (const Run& r : chosen) {
      const auto err = r.j->find("error_occurred");
      if (err != r.j->end() && err->is_boolean() && err->get<bool>()) {
        e.error = true;
        e.error_message = reader.string_field(r, "error_message", false);
      }
    }
    if (!e.error) {
      std::vector<double> times;
      std::map<std::string, std::vector<double>> counters;
      for (const Run& r : chosen) {
        times.push_back(reader.time_ns(r));
        for (auto it = r.j->begin(); it != r.j->end(); ++it) {
          if (is_builtin_field(it.key())) continue;
          const bool exact = std::find(out.exact_counters.begin(), out.exact_counters.end(),
                                       it.key()) != out.exact_counters.end();
          if (exact) {
            counters[it.key()].push_back(reader.number_field(r, it.key()));
          } else if (it->is_number()) {
            counters[it.key()].push_back(it->get<double>());
          }
        }
      }
      e.real_time_ns = quantile(times, 0.5);
      for (const auto& [key, values] : counters) {
        if (values.size() == chosen.size()) e.counters[key] = quantile(values, 0.5);
      }
      // The spread of the real time: the cv aggregate, else stddev over mean (or median).
      if (agg != aggregates.end()) {
        const auto& a = agg->second;
        if (a.count("cv")) {
          const Run& r = a.at("cv");
          const std::string unit = reader.string_field(r, "aggregate_unit", false);
          e.cv = unit == "percentage" || unit.empty()
                     ? reader.number_field(r, "real_time")
                     : reader.time_ns(r) / std::max(e.real_time_ns, 1e-300);
        } else if (a.count("stddev")) {
          const double sd = reader.time_ns(a.at("stddev"));
          const double mean = a.count("mean") ? reader.time_ns(a.at("mean")) : e.real_time_ns;
          e.cv = mean > 0 ? sd / mean : 0;
        }
        if (e.cv < 0) reader.fail(a.count("cv") ? a.at("cv").key : name, "negative spread");
      }
    }
    out.entries.push_back(std::move(e));
  }
  return out;
}

bool is_regression(BenchVerdict verdict) {
  return verdict == BenchVerdict::kSlower || verdict == BenchVerdict::kCounterChanged ||
         verdict == BenchVerdict::kErrorInNew;
}

BenchComparison compare_bench(const BenchFile& base, const BenchFile& now,
                              const BenchCompareOptions& options) {
  BenchComparison c;
  for (const BenchEntry& b : base.entries) {
    const BenchEntry* n = now.find(b.name);
    BenchRow row;
    row.benchmark = b.name;
    if (!b.error) row.base = b.real_time_ns;
    if (!n) {
      row.verdict = BenchVerdict::kOnlyInBase;
      ++c.only_in_base;
      c.rows.push_back(row);
      continue;
    }
    ++c.compared;
    if (!n->error) row.now = n->real_time_ns;
    bool regressed = false;
    if (n->error) {
      row.verdict = BenchVerdict::kErrorInNew;
      row.note = n->error_message;
      ++c.errors;
      regressed = true;
    } else if (b.error) {
      row.verdict = BenchVerdict::kErrorInBase;
      row.note = b.error_message;
    } else {
      row.tolerance = std::max(options.time_tolerance, 3 * std::max(b.cv, n->cv));
      if (n->real_time_ns > b.real_time_ns * (1 + row.tolerance)) {
        row.verdict = BenchVerdict::kSlower;
        ++c.slower;
        regressed = true;
      } else if (n->real_time_ns * (1 + row.tolerance) < b.real_time_ns) {
        row.verdict = BenchVerdict::kFaster;
        ++c.faster;
      } else {
        row.verdict = BenchVerdict::kOk;
        ++c.ok;
      }
    }
    c.rows.push_back(row);
    if (!b.error && !n->error) {
      for (const std::string& counter : base.exact_counters) {
        const auto bc = b.counters.find(counter);
        if (bc == b.counters.end()) continue;
        const auto nc = n->counters.find(counter);
        if (nc != n->counters.end() && counters_equal(bc->second, nc->second)) continue;
        BenchRow changed;
        changed.benchmark = b.name;
        changed.counter = counter;
        changed.base = bc->second;
        if (nc != n->counters.end()) changed.now = nc->second;
        changed.verdict = BenchVerdict::kCounterChanged;
        if (nc == n->counters.end()) changed.note = "missing in new";
        c.rows.push_back(changed);
        ++c.counters_changed;
        regressed = true;
      }
    }
    c.regressed += regressed;
  }
  for (const BenchEntry& n : now.entries) {
    if (base.find(n.name)) continue;
    BenchRow row;
    row.benchmark = n.name;
    if (!n.error) row.now = n.real_time_ns;
    row.verdict = BenchVerdict::kOnlyInNew;
    c.rows.push_back(row);
    ++c.only_in_new;
  }
  for (const BenchEntry& n : now.entries) {
    const BenchEntry* raw = raw_partner(now, n.name);
    if (!raw || n.error || raw->error || !(raw->real_time_ns > 0)) continue;
    RawRatio r;
    r.benchmark = n.name;
    r.raw = raw->name;
    r.ratio = n.real_time_ns / raw->real_time_ns;
    const BenchEntry* bn = base.find(n.name);
    const BenchEntry* br = base.find(raw->name);
    if (bn && br && !bn->error && !br->error && br->real_time_ns > 0)
      r.base_ratio = bn->real_time_ns / br->real_time_ns;
    c.raw_ratios.push_back(r);
  }
  return c;
}

void write_bench_comparison(const BenchFile& base, const BenchFile& now, const BenchComparison& c,
                            std::ostream& out) {
  out << "Benchmarks: " << base.path.string() << " (base) against " << now.path.string()
      << " (new)\n\n";
  out << "| benchmark | base | new | ratio | verdict |\n|---|---|---|---|---|\n";
  for (const BenchRow& row : c.rows) {
    const bool time = row.counter.empty();
    auto value = [&](const std::optional<double>& v) {
      if (!v) return std::string("-");
      return time ? format_time(*v) : format_number("%.10g", *v);
    };
    std::string ratio;
    if (row.base && row.now && *row.base > 0) ratio = format_ratio(*row.now / *row.base);
    std::string verdict = verdict_text(row.verdict);
    if (time && (row.verdict == BenchVerdict::kOk || row.verdict == BenchVerdict::kFaster ||
                 row.verdict == BenchVerdict::kSlower)) {
      verdict += " (tolerance " + percent(row.tolerance) + ")";
    }
    if (!row.note.empty()) verdict += ": " + row.note;
    out << "| " << row.benchmark << (time ? "" : " [" + row.counter + "]") << " | "
        << value(row.base) << " | " << value(row.now) << " | " << ratio << " | " << verdict
        << " |\n";
  }
  if (!c.raw_ratios.empty()) {
    out << "\nRatios to raw within the new run (the machine-independent figure; < 1: faster "
           "than raw):\n\n";
    out << "| benchmark | raw | new ratio | base ratio |\n|---|---|---|---|\n";
    for (const RawRatio& r : c.raw_ratios) {
      const std::string how =
          r.ratio < 1 ? format_ratio(1 / r.ratio) + "x faster" : format_ratio(r.ratio) + "x slower";
      out << "| " << r.benchmark << " | " << r.raw << " | " << format_ratio(r.ratio) << " (" << how
          << ") | " << (r.base_ratio ? format_ratio(*r.base_ratio) : std::string("-")) << " |\n";
    }
  }
  out << "\nbench-compare: " << c.compared << " benchmarks compared: " << c.regressed
      << " regressed (" << c.slower << " slower, " << c.counters_changed
      << " exact counters changed, " << c.errors << " errors), " << c.faster << " faster, " << c.ok
      << " ok; " << c.only_in_base << " only in base, " << c.only_in_new << " only in new\n";
}

int run_bench_compare(const std::filesystem::path& base, const std::filesystem::path& now,
                      const BenchCompareOptions& options, bool fail_on_regression,
                      std::ostream& out) {
  const BenchFile base_file = read_bench_file(base);
  const BenchFile new_file = read_bench_file(now);
  const BenchComparison c = compare_bench(base_file, new_file, options);
  write_bench_comparison(base_file, new_file, c, out);
  // A benchmark of the baseline missing from the new run is a failure too: compare like
  // with like (the same filter), or a broken benchmark would pass by vanishing.
  return fail_on_regression && (c.regressed > 0 || c.only_in_base > 0) ? 1 : 0;
}

}  // namespace taskmatrix::harness
