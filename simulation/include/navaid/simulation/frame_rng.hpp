#pragma once
// Per-frame random engines for the image noise models. A frame's draws depend only on
// (seed, frame_index, stream), never on which frames were processed before, so a recording can be
// noised in any order or in parallel and still come out bit for bit the same. Distinct streams
// keep the models of one frame independent (e.g. depth noise and label confusion may share the
// scenario seed without their draws being correlated).
#include <cstdint>
#include <random>

namespace navaid::simulation {

/// Stream ids of the simulator's per-frame noise models (append only: changing one changes the
/// recordings every seed produces).
enum class FrameNoiseStream : std::uint64_t {
  kDepth = 1,
  kDepthDropout = 2,
  kIntensity = 3,
  kLabels = 4,
};

/// SplitMix64 finalizer: a bijective 64-bit mix whose outputs for consecutive inputs look
/// independent (Steele, Lea & Flood 2014), so neighbouring seeds or frames give unrelated engines.
constexpr std::uint64_t mix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

/// Seed of one frame's engine for one stream; chained mixing so that (a, b) and (b, a) differ.
constexpr std::uint64_t frame_seed(std::uint64_t seed, std::uint64_t frame_index, FrameNoiseStream stream) {
  return mix64(mix64(mix64(seed) ^ frame_index) ^ static_cast<std::uint64_t>(stream));
}

inline std::mt19937_64 frame_rng(std::uint64_t seed, std::uint64_t frame_index, FrameNoiseStream stream) {
  return std::mt19937_64(frame_seed(seed, frame_index, stream));
}

/// Uniform in [0, 1) from the top 53 bits of one draw: exact, and cheaper than
/// std::uniform_real_distribution in per-pixel loops.
inline double uniform01(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

}  // namespace navaid::simulation
