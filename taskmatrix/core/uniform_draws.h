// Reproducible uniform draws for layouts and task variations: the same seed gives the same
// numbers on every platform and standard library (own mapping of std::mt19937_64's bits, no
// std distributions), and independent streams derived from one seed.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <random>

namespace taskmatrix::core {

class UniformDraws {
 public:
  explicit UniformDraws(std::uint64_t seed) : engine_(seed) {}
  // Uniform in [0, 1) from the top 53 bits.
  double next() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  double in(double lo, double hi) { return lo + (hi - lo) * next(); }
  std::size_t index(std::size_t n) {
    return std::min(n - 1, static_cast<std::size_t>(next() * static_cast<double>(n)));
  }

 private:
  std::mt19937_64 engine_;
};

// The seed of stream `stream` (>= 1) of `seed` (splitmix64): streams of one seed are
// unrelated, so adding a stream changes no other stream's draws.
inline std::uint64_t stream_seed(std::uint64_t seed, std::uint64_t stream) {
  std::uint64_t z = seed + 0x9e3779b97f4a7c15ULL * stream;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

}  // namespace taskmatrix::core
