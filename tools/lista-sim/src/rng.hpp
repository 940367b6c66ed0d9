// Deterministic randomness for the simulator. Sequential choices (layout,
// changes, routes) use Rng streams derived from the seed; per-ray noise uses a
// counter-based hash so results do not depend on thread scheduling.
#pragma once

#include <cmath>
#include <cstdint>
#include <random>

namespace lista::sim {

inline uint64_t mix64(uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

// FNV-1a: a stable string hash (std::hash is not specified across libraries).
inline uint64_t hash_string(const char* s) {
  uint64_t h = 1469598103934665603ull;
  for (; *s; ++s) h = (h ^ uint64_t(uint8_t(*s))) * 1099511628211ull;
  return h;
}

inline uint64_t hash_combine(uint64_t a, uint64_t b) { return mix64(a ^ mix64(b)); }

// Uniform in [0, 1) from a 64-bit hash.
inline double hash_uniform(uint64_t h) { return double(h >> 11) * (1.0 / 9007199254740992.0); }

// Standard normal from two hashes (Box-Muller).
inline double hash_normal(uint64_t h) {
  const double u1 = std::max(hash_uniform(h), 1e-12);
  const double u2 = hash_uniform(mix64(h));
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(6.283185307179586 * u2);
}

// A named random stream: same seed and name, same sequence. std::mt19937_64 is
// specified exactly by the standard; the distributions below are written by
// hand because std:: distributions differ between library implementations.
class Rng {
 public:
  explicit Rng(uint64_t seed, uint64_t stream = 0) : engine_(hash_combine(seed, stream)) {}
  double uniform() { return double(engine_() >> 11) * (1.0 / 9007199254740992.0); }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  int integer(int lo, int hi) {  // inclusive
    return lo + int(engine_() % uint64_t(hi - lo + 1));
  }
  double normal() { return hash_normal(engine_()); }
  bool chance(double p) { return uniform() < p; }
  uint64_t next() { return engine_(); }

 private:
  std::mt19937_64 engine_;
};

}  // namespace lista::sim
