#include "navaid/estimation/frontend/frontend_config.hpp"

#include <algorithm>
#include <cmath>

#include "navaid/core/errors.hpp"
#include "navaid/core/number_text.hpp"

namespace navaid::estimation {
namespace {

// Finite and inside [lo, hi] (open ends when the flags say so).
void check_range(const std::string& source, const char* key, double v, double lo, double hi, bool lo_open, bool hi_open,
                 const std::string& allowed) {
  const bool ok = std::isfinite(v) && (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
  if (!ok) throw ConfigError(source, key, "expected " + allowed + ", found " + number_text(v));
}

void check_int(const std::string& source, const char* key, int v, int lo, int hi, const std::string& allowed) {
  if (v < lo || v > hi) throw ConfigError(source, key, "expected " + allowed + ", found " + std::to_string(v));
}

constexpr double kUnbounded = HUGE_VAL;
constexpr int kIntUnbounded = 1 << 30;

}  // namespace

void validate(const FrontendConfig& c, const std::string& source) {
  check_int(source, "max_features", c.max_features, 1, kIntUnbounded, "an integer >= 1");
  check_int(source, "detect_min_missing", c.detect_min_missing, 1, std::max(1, c.max_features),
            "an integer in [1, max_features = " + std::to_string(c.max_features) + "]");
  check_range(source, "min_distance_px", c.min_distance_px, 0.0, kUnbounded, false, true, "a finite value >= 0 px");
  check_range(source, "quality_level", c.quality_level, 0.0, 1.0, true, true, "a value in (0, 1)");
  if (c.corner_block_size < 3 || c.corner_block_size % 2 == 0)
    throw ConfigError(source, "corner_block_size",
                      "expected an odd integer >= 3, found " + std::to_string(c.corner_block_size));
  check_int(source, "depth_edge_margin_px", c.depth_edge_margin_px, 0, kIntUnbounded, "an integer >= 0 px");
  check_range(source, "depth_edge_relative_jump", c.depth_edge_relative_jump, 0.0, kUnbounded, true, true, "a finite value > 0");
  if (c.klt_window_px < 5 || c.klt_window_px % 2 == 0)
    throw ConfigError(source, "klt_window_px", "expected an odd integer >= 5, found " + std::to_string(c.klt_window_px));
  check_int(source, "klt_max_level", c.klt_max_level, 0, 8, "an integer in [0, 8]");
  check_int(source, "klt_max_iterations", c.klt_max_iterations, 1, kIntUnbounded, "an integer >= 1");
  check_range(source, "klt_epsilon", c.klt_epsilon, 0.0, kUnbounded, true, true, "a finite value > 0 px");
  check_range(source, "fb_threshold_px", c.fb_threshold_px, 0.0, kUnbounded, true, true, "a finite value > 0 px");
  check_int(source, "fb_max_level", c.fb_max_level, 0, 8, "an integer in [0, 8]");
  check_int(source, "klt_threads", c.klt_threads, 1, 16, "an integer in [1, 16]");
  check_int(source, "drift_check_interval", c.drift_check_interval, 0, kIntUnbounded, "an integer >= 0 frames");
  check_range(source, "drift_max_px", c.drift_max_px, 0.0, kUnbounded, true, true, "a finite value > 0 px");
  check_range(source, "ransac_threshold_px", c.ransac_threshold_px, 0.0, kUnbounded, true, true, "a finite value > 0 px");
  check_range(source, "ransac_confidence", c.ransac_confidence, 0.0, 1.0, true, true, "a value in (0, 1)");
  check_range(source, "border_px", c.border_px, 0.0, kUnbounded, false, true, "a finite value >= 0 px");
  if (c.depth_patch_size != 3 && c.depth_patch_size != 5)
    throw ConfigError(source, "depth_patch_size", "expected 3 or 5, found " + std::to_string(c.depth_patch_size));
  check_range(source, "depth_max_relative_spread", c.depth_max_relative_spread, 0.0, kUnbounded, true, true,
              "a finite value > 0");
  check_int(source, "depth_min_valid", c.depth_min_valid, 1, c.depth_patch_size * c.depth_patch_size,
            "an integer in [1, depth_patch_size^2 = " + std::to_string(c.depth_patch_size * c.depth_patch_size) + "]");
  check_range(source, "keyframe_parallax_px", c.keyframe_parallax_px, 0.0, kUnbounded, true, true, "a finite value > 0 px");
  check_int(source, "keyframe_min_tracked", c.keyframe_min_tracked, 0, kIntUnbounded, "an integer >= 0");
}

}  // namespace navaid::estimation
