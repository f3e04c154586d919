// Deterministic random numbers for the simulator: one std::mt19937_64 per scenario, and
// per-ray streams derived from (seed, frame, column) with a splitmix64 hash, so results do not
// depend on how TBB schedules the columns.
#pragma once

#include <cstdint>
#include <random>

namespace dloam::sim {

using Rng = std::mt19937_64;

/// splitmix64 finaliser: a well-mixed 64-bit hash of `x`.
inline std::uint64_t mix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

/// Seed of an independent stream for (seed, a, b).
inline std::uint64_t stream_seed(std::uint64_t seed, std::uint64_t a, std::uint64_t b) {
  return mix64(mix64(mix64(seed) ^ a) ^ (b * 0xD6E8FEB86659FD93ull));
}

inline double uniform(Rng& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}
inline int uniform_int(Rng& rng, int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); }
inline bool chance(Rng& rng, double p) { return std::uniform_real_distribution<double>(0.0, 1.0)(rng) < p; }

}  // namespace dloam::sim
