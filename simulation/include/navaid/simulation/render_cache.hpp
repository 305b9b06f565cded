#pragma once
// On-disk cache of noise-free renderings, so that Monte-Carlo runs of one scenario (same path,
// camera and world; different noise seeds) render once. A cache entry is a folder named by a
// 64-bit hash of a canonical key text that lists everything the rendering depends on (scenario,
// world seed, people, camera, mount, walker, frame times, render options, renderer version); the
// full key is stored beside the images and compared on every open, so a hash collision or a
// stale entry is detected instead of silently re-used.
//
// Per frame: depth as 16-bit PNG in units of depth_unit_m, labels and intensity as 8-bit PNG.
// The simulator quantizes depth to depth_unit_m whether or not a cache is used, so a recording is
// the same bit for bit with a cold cache, a warm cache or none.
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>

#include "navaid/simulation/rgbd_renderer.hpp"

namespace navaid::simulation {

/// Bump when the renderer's output changes for the same inputs: old cache entries stop matching.
constexpr int kRendererVersion = 2;  // 2: image-textured plane patches (AprilTag targets)

/// Depth quantum [m] of cached (and simulated) clean depth for a largest rendered depth.
double cache_depth_unit_m(double max_depth_m);

class RenderCache {
 public:
  /// Opens (creating when missing) the entry for `key` under `root`. Throws IoError when the
  /// folder holds an entry with another key (hash collision) or cannot be created.
  RenderCache(const std::filesystem::path& root, const std::string& key, double depth_unit_m);

  const std::filesystem::path& folder() const { return folder_; }
  /// True when frame `index` was stored (all three images present).
  bool has(std::size_t index) const;
  /// Loads frame `index` (IoError when missing or corrupt). Depth in metres.
  RenderedFrame load(std::size_t index) const;
  /// Stores frame `index` (depth must already be quantized to the unit; others as rendered).
  /// Written to temporary names and renamed, so a crash never leaves a half-written frame.
  void store(std::size_t index, const RenderedFrame& frame) const;

 private:
  std::filesystem::path path(std::size_t index, const char* kind) const;
  std::filesystem::path folder_;
  double depth_unit_m_;
};

/// FNV-1a 64-bit hash (stable across platforms and runs), as 16 hex digits.
std::string stable_hash_hex(const std::string& text);

}  // namespace navaid::simulation
