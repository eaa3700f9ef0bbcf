// Fuzz targets: one per kind of input a user hands the harness. Each takes the bytes of one
// file, puts them where the harness reads that kind of file (a scratch copy of the project's
// models, a scratch run directory) and runs the reader and what consumes its result, as the
// CLI would. A target returns normally for every input: accepted, or refused with
// core::InputError (a clear error naming the file). Anything else is a finding: a crash, a hang
// (the drivers time each input), or another exception (the target rethrows it).
//
// Built two ways (fuzz/CMakeLists.txt): with libFuzzer when the compiler is clang
// (-DTASKMATRIX_LIBFUZZER=ON), and always as `taskmatrix_fuzz`, a deterministic mutation
// driver that runs in CI (fuzz/mutation_driver.cc).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace taskmatrix::fuzz {

struct Target {
  std::string name;  // scenario, suite, profile, environment, mjcf, urdf, trials, trajectory, bench
  std::string what;  // the file it stands for
  // Seed inputs: files of the project (relative to its root) and of fuzz/seeds/<name>/.
  std::vector<std::string> seeds;
  // Per-input work: +1 light (pure parsing), +4 and more when scenes are compiled.
  int cost = 1;
};

const std::vector<Target>& targets();
const Target* find_target(const std::string& name);

// Prepares what the targets need once per process (a scratch root with the project's models
// and scenarios; compiled scenes shared by the trajectory target). `root` is the project.
void set_up(const std::filesystem::path& root);
void tear_down();

// Runs one input. Returns true when the harness accepted it, false when it refused it with a
// core::InputError; rethrows any other exception.
bool run(const Target& target, const std::uint8_t* data, std::size_t size);

// The seed inputs of a target: their bytes, read from the project and fuzz/seeds/.
std::vector<std::string> seed_inputs(const Target& target, const std::filesystem::path& root);

}  // namespace taskmatrix::fuzz
