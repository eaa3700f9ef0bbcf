// taskmatrix_fuzz: a deterministic mutation fuzzer over the fuzz targets (fuzz/fuzz_targets.h),
// for machines without clang's libFuzzer and for CI. From a fixed seed it derives every input
// from the target's seed files by a few mutations each (byte and bit changes, insertions and
// deletions, duplicated or dropped lines and chunks, splices of two seeds, and tokens that have
// broken parsers: NaN, infinities, numbers out of range, bytes that are not UTF-8, carriage
// returns, deep nesting, very long names, Markdown and HTML). Each input runs in a forked child
// with a time limit, so a crash or a hang is caught, counted and its input kept.
//
//   taskmatrix_fuzz [--root DIR] [--runs N] [--seed S] [--timeout SECONDS] [--out DIR]
//                   [--budget UNITS] [--write-seeds DIR] TARGET...|all
//
// --runs: inputs per target (the seeds themselves come first); --budget: instead, about this
// many units of work per target (a target's cost per input: 1 for parsers, 4 and more when
// scenes are compiled). Prints per target: inputs tried, accepted, refused with an error,
// crashes, hangs, other errors. Exit 0 when there were no crashes, hangs or other errors; 1
// otherwise, with each such input written to --out (default fuzz-findings/).
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "fuzz/fuzz_targets.h"

namespace {

namespace fs = std::filesystem;
using taskmatrix::fuzz::Target;

const std::vector<std::string>& tokens() {
  static const std::vector<std::string> t = {".nan",
                                             "nan",
                                             "NaN",
                                             ".inf",
                                             "-.inf",
                                             "inf",
                                             "-inf",
                                             "Infinity",
                                             "-Infinity",
                                             "1e999",
                                             "-1e999",
                                             "1e308",
                                             "1e10",
                                             "4294967296",
                                             "18446744073709551616",
                                             "99999999999999999999",
                                             "-1",
                                             "0",
                                             "-0",
                                             "0.0",
                                             "1e-320",
                                             "2147483648",
                                             "-2147483649",
                                             "0x10",
                                             "\xff",
                                             "\xc3\x28",
                                             "\xed\xa0\x80",
                                             "\xf4\x90\x80\x80",
                                             "\r",
                                             "\r\n",
                                             "\t",
                                             "\0",
                                             "|",
                                             "<img src=x onerror=1>",
                                             "a;b|c",
                                             "../../x",
                                             "/etc/passwd",
                                             "$x",
                                             "null",
                                             "~",
                                             "true",
                                             "[]",
                                             "{}",
                                             "\"",
                                             "'",
                                             ":",
                                             "- ",
                                             "&a",
                                             "*a",
                                             "!!binary",
                                             "%",
                                             "#",
                                             "@",
                                             "`",
                                             "{{",
                                             "]]",
                                             "\\u0000",
                                             "\\ud800"};
  return t;
}

std::string deep(size_t depth, const std::string& open, const std::string& leaf,
                 const std::string& close) {
  std::string s;
  for (size_t i = 0; i < depth; ++i) s += open;
  s += leaf;
  for (size_t i = 0; i < depth; ++i) s += close;
  return s;
}

class Mutator {
 public:
  Mutator(std::uint64_t seed, const std::vector<std::string>& seeds) : rng_(seed), seeds_(seeds) {}

  std::string next() {
    std::string s = seeds_[pick(seeds_.size())];
    const int steps = 1 + static_cast<int>(pick(4));
    for (int k = 0; k < steps; ++k) mutate(s);
    if (s.size() > kMaxSize) s.resize(kMaxSize);
    return s;
  }

 private:
  static constexpr size_t kMaxSize = 1 << 20;

  size_t pick(size_t n) { return n == 0 ? 0 : static_cast<size_t>(rng_() % n); }

  // A position at the start of a number in `s`, if there is one (a quarter of the tries).
  size_t number_at(const std::string& s) {
    for (int tries = 0; tries < 8; ++tries) {
      const size_t at = pick(s.size());
      if (at < s.size() && ((s[at] >= '0' && s[at] <= '9') || s[at] == '-') &&
          (at == 0 || !std::isalnum(static_cast<unsigned char>(s[at - 1])))) {
        return at;
      }
    }
    return std::string::npos;
  }

  std::vector<std::pair<size_t, size_t>> lines(const std::string& s) {
    std::vector<std::pair<size_t, size_t>> out;
    size_t start = 0;
    while (start < s.size()) {
      const size_t eol = s.find('\n', start);
      const size_t end = eol == std::string::npos ? s.size() : eol + 1;
      out.push_back({start, end - start});
      start = end;
    }
    return out;
  }

  void mutate(std::string& s) {
    const size_t at = pick(s.size() + 1);
    switch (pick(14)) {
      case 0:  // flip a bit
        if (!s.empty()) s[pick(s.size())] ^= static_cast<char>(1 << pick(8));
        break;
      case 1:  // set a byte
        if (!s.empty()) s[pick(s.size())] = static_cast<char>(rng_());
        break;
      case 2:  // delete a range
        if (!s.empty()) s.erase(pick(s.size()), 1 + pick(std::min<size_t>(s.size(), 64)));
        break;
      case 3:  // insert random bytes
        s.insert(at, std::string(1 + pick(8), static_cast<char>(rng_())));
        break;
      case 4:
      case 5: {  // insert a token
        s.insert(at, tokens()[pick(tokens().size())]);
        break;
      }
      case 6:
      case 7: {  // replace a number with a token
        const size_t n = number_at(s);
        if (n == std::string::npos) break;
        size_t end = n + 1;
        while (end < s.size() && (std::isalnum(static_cast<unsigned char>(s[end])) ||
                                  s[end] == '.' || s[end] == '-' || s[end] == '+')) {
          ++end;
        }
        s.replace(n, end - n, tokens()[pick(20)]);
        break;
      }
      case 8: {  // duplicate a line
        const auto l = lines(s);
        if (l.empty()) break;
        const auto [from, len] = l[pick(l.size())];
        s.insert(l[pick(l.size())].first, s.substr(from, len));
        break;
      }
      case 9: {  // drop a line
        const auto l = lines(s);
        if (l.empty()) break;
        const auto [from, len] = l[pick(l.size())];
        s.erase(from, len);
        break;
      }
      case 10: {  // splice with another seed
        const std::string& other = seeds_[pick(seeds_.size())];
        if (other.empty()) break;
        const size_t from = pick(other.size());
        s = s.substr(0, at) + other.substr(from, pick(other.size() - from + 1));
        break;
      }
      case 11: {  // deep nesting: conditions, YAML and JSON lists, XML elements
        const size_t depth = 100 + pick(20000);
        static const char* const kinds[][3] = {
            {"not(", "exists(x)", ")"}, {"[", "1", "]"}, {"{a: ", "1", "}"}, {"<a>", "", "</a>"}};
        const auto& k = kinds[pick(4)];
        s.insert(at, deep(depth, k[0], k[1], k[2]));
        break;
      }
      case 12:  // a very long name
        s.insert(at, std::string(200 + pick(400), static_cast<char>('a' + pick(26))));
        break;
      default: {  // repeat a chunk
        if (s.empty()) break;
        const size_t from = pick(s.size());
        const std::string chunk = s.substr(from, 1 + pick(32));
        const size_t times = 1 + pick(64);
        std::string rep;
        for (size_t i = 0; i < times; ++i) rep += chunk;
        s.insert(at, rep);
        break;
      }
    }
  }

  std::mt19937_64 rng_;
  const std::vector<std::string>& seeds_;
};

enum class Outcome { kAccepted, kRefused, kCrash, kHang, kOtherError };

// Runs the input in a child: exit 0 accepted, 10 refused (InputError), 11 another exception
// (its message on stderr); a signal is a crash; past the timeout it is a hang.
Outcome run_child(const Target& target, const std::string& input, double timeout_s) {
  std::fflush(nullptr);
  const pid_t pid = fork();
  if (pid < 0) {
    std::perror("fork");
    std::exit(2);
  }
  if (pid == 0) {
#if !defined(__SANITIZE_ADDRESS__)
    // 4 GiB of address space is far more than any input needs: an allocation that asks for
    // more fails (a finding) instead of bringing the machine to its knees. (AddressSanitizer
    // reserves terabytes of address space and has its own allocation limit.)
    const rlimit limit{rlim_t{4} << 30, rlim_t{4} << 30};
    setrlimit(RLIMIT_AS, &limit);
#endif
    int code = 0;
    try {
      code = taskmatrix::fuzz::run(target, reinterpret_cast<const std::uint8_t*>(input.data()),
                                   input.size())
                 ? 0
                 : 10;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "taskmatrix_fuzz: %s: other exception: %s\n", target.name.c_str(),
                   e.what());
      code = 11;
    }
    std::fflush(nullptr);
    std::_Exit(code);
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  int status = 0;
  for (;;) {
    const pid_t r = waitpid(pid, &status, WNOHANG);
    if (r == pid) break;
    if (std::chrono::steady_clock::now() > deadline) {
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
      return Outcome::kHang;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  if (WIFSIGNALED(status)) return Outcome::kCrash;
  switch (WEXITSTATUS(status)) {
    case 0:
      return Outcome::kAccepted;
    case 10:
      return Outcome::kRefused;
    case 11:
      return Outcome::kOtherError;
    default:
      return Outcome::kCrash;  // mju_error exits, sanitizer reports
  }
}

int usage() {
  std::cerr << "usage: taskmatrix_fuzz [--root DIR] [--runs N | --budget UNITS] [--seed S] "
               "[--timeout SECONDS] [--out DIR] TARGET...|all\ntargets:";
  for (const Target& t : taskmatrix::fuzz::targets()) std::cerr << " " << t.name;
  std::cerr << "\n";
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  fs::path root = TASKMATRIX_FUZZ_ROOT;
  fs::path out = "fuzz-findings";
  long runs = 200, budget = 0;
  std::uint64_t seed = 1;
  double timeout_s = 20;
  std::vector<const Target*> chosen;
  fs::path write_seeds;  // --write-seeds DIR: write each target's seeds to DIR/<target>/, run none
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::cerr << "taskmatrix_fuzz: " << a << " needs a value\n";
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--root") {
      root = value();
    } else if (a == "--runs") {
      runs = std::strtol(value().c_str(), nullptr, 10);
    } else if (a == "--budget") {
      budget = std::strtol(value().c_str(), nullptr, 10);
    } else if (a == "--seed") {
      seed = std::strtoull(value().c_str(), nullptr, 10);
    } else if (a == "--timeout") {
      timeout_s = std::strtod(value().c_str(), nullptr);
    } else if (a == "--out") {
      out = value();
    } else if (a == "--write-seeds") {
      write_seeds = value();
    } else if (a == "all") {
      for (const Target& t : taskmatrix::fuzz::targets()) chosen.push_back(&t);
    } else if (const Target* t = taskmatrix::fuzz::find_target(a)) {
      chosen.push_back(t);
    } else {
      return usage();
    }
  }
  if (chosen.empty() || runs < 1 || !(timeout_s > 0)) return usage();
  if (!write_seeds.empty()) {
    for (const Target* t : chosen) {
      const std::vector<std::string> seeds = taskmatrix::fuzz::seed_inputs(*t, root);
      fs::create_directories(write_seeds / t->name);
      for (size_t k = 0; k < seeds.size(); ++k) {
        std::ofstream(write_seeds / t->name / ("seed-" + std::to_string(k)), std::ios::binary)
            << seeds[k];
      }
    }
    return 0;
  }
  taskmatrix::fuzz::set_up(root);
  int findings = 0;
  long total = 0;
  for (const Target* t : chosen) {
    const std::vector<std::string> seeds = taskmatrix::fuzz::seed_inputs(*t, root);
    const long n =
        budget > 0 ? std::max<long>(static_cast<long>(seeds.size()), budget / t->cost) : runs;
    Mutator mutator(seed ^ std::hash<std::string>{}(t->name), seeds);
    long counts[5] = {0, 0, 0, 0, 0};
    const auto t0 = std::chrono::steady_clock::now();
    for (long k = 0; k < n; ++k) {
      const std::string input =
          k < static_cast<long>(seeds.size()) ? seeds[static_cast<size_t>(k)] : mutator.next();
      const Outcome o = run_child(*t, input, timeout_s);
      ++counts[static_cast<int>(o)];
      if (k < static_cast<long>(seeds.size()) && o != Outcome::kAccepted) {
        std::cerr << "taskmatrix_fuzz: " << t->name << ": seed " << k
                  << " is not accepted: the seeds are stale\n";
        ++findings;
      }
      if (o == Outcome::kCrash || o == Outcome::kHang || o == Outcome::kOtherError) {
        ++findings;
        fs::create_directories(out);
        const char* kind = o == Outcome::kCrash ? "crash" : o == Outcome::kHang ? "hang" : "error";
        const fs::path file = out / (t->name + "-" + kind + "-" + std::to_string(k));
        std::ofstream(file, std::ios::binary) << input;
        std::cerr << "taskmatrix_fuzz: " << t->name << ": input " << k << ": " << kind
                  << ", kept in " << file.string() << "\n";
      }
    }
    total += n;
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf(
        "%-12s %6ld inputs: %6ld accepted, %6ld refused with an error, %ld crashes, "
        "%ld hangs, %ld other errors (%.1f s)\n",
        t->name.c_str(), n, counts[0], counts[1], counts[2], counts[3], counts[4], s);
  }
  taskmatrix::fuzz::tear_down();
  std::printf("total %ld inputs, %d findings\n", total, findings);
  return findings == 0 ? 0 : 1;
}
