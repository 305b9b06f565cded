// Configuration of the obstacle pipeline: keys under mapping.obstacles.*, one allowed range per key
// shared by the YAML reader and validate() so that both reject the same values.
#include <cmath>
#include <string>

#include <fmt/format.h>

#include "navaid/core/errors.hpp"
#include "navaid/mapping/obstacle_pipeline.hpp"

namespace navaid::mapping {
namespace {

constexpr double kDeg = ObstaclePipelineConfig::kDeg;
const std::string kPrefix = "mapping.obstacles.";
const std::string kOrigin = "<obstacle pipeline>";

// Allowed ranges (SI, angles in degrees as in the config files).
constexpr Range kLeaf{0.001, 1.0};
constexpr Range kIterations{1, 1e6};
constexpr Range kDistance{0.001, 1.0};
constexpr Range kEpsAngleDeg{0.1, 89.0};
constexpr Range kMinInliers{3, 1e8};
constexpr Range kMaxPoints{100, 1e8};
constexpr Range kDeviation{0.001, 5.0};
constexpr Range kFrames{1, 1e6};
constexpr Range kAboveHead{0.1, 10.0};
constexpr Range kStep{0.01, 2.0};
constexpr Range kBearingDeg{-180.0, 180.0};
constexpr Range kBinWidthDeg{0.01, 90.0};

void check(const std::string& key, double value, Range r) {
  if (!(value >= r.min && value <= r.max))
    throw ConfigError(kOrigin, kPrefix + key, fmt::format("{} is outside the allowed range [{}, {}]", value, r.min, r.max));
}

long long get_count(const Config& c, const std::string& key, int fallback, Range r) {
  return c.get_int(kPrefix + key, fallback, static_cast<long long>(r.min), static_cast<long long>(r.max));
}

}  // namespace

std::size_t ObstaclePipelineConfig::scan_bins() const {
  return static_cast<std::size_t>(std::lround((scan_max_bearing_rad - scan_min_bearing_rad) / scan_bin_width_rad)) + 1;
}

void validate(const ObstaclePipelineConfig& c) {
  check("voxel_leaf_size", c.voxel_leaf_size_m, kLeaf);
  check("ransac.max_iterations", c.ransac_max_iterations, kIterations);
  check("ransac.distance_threshold", c.ransac_distance_threshold_m, kDistance);
  check("ransac.eps_angle", c.ransac_eps_angle_rad / kDeg, kEpsAngleDeg);
  check("ransac.min_inliers", c.ransac_min_inliers, kMinInliers);
  check("ransac.max_points", c.ransac_max_points, kMaxPoints);
  check("running_average.max_deviation", c.running_average_max_deviation_m, kDeviation);
  check("running_average.frames", c.running_average_frames, kFrames);
  check("running_average.distance_threshold", c.fallback_distance_threshold_m, kDistance);
  check("max_step_height", c.max_step_height_m, kStep);
  check("level_fit_threshold", c.level_fit_threshold_m, kDistance);
  check("level_eps_angle", c.level_eps_angle_rad / kDeg, kEpsAngleDeg);
  check("above_head_height", c.above_head_height_m, kAboveHead);
  check("scan.min_bearing", c.scan_min_bearing_rad / kDeg, kBearingDeg);
  check("scan.max_bearing", c.scan_max_bearing_rad / kDeg, kBearingDeg);
  check("scan.bin_width", c.scan_bin_width_rad / kDeg, kBinWidthDeg);
  if (!(c.scan_max_bearing_rad >= c.scan_min_bearing_rad))
    throw ConfigError(kOrigin, kPrefix + "scan.max_bearing",
                      fmt::format("{}° must not be below scan.min_bearing {}°", c.scan_max_bearing_rad / kDeg,
                                  c.scan_min_bearing_rad / kDeg));
}

ObstaclePipelineConfig read_obstacle_pipeline_config(const Config& c) {
  ObstaclePipelineConfig o;
  auto get = [&](const std::string& key, double fallback, Range r) { return c.get_double(kPrefix + key, fallback, r); };
  o.voxel_leaf_size_m = get("voxel_leaf_size", o.voxel_leaf_size_m, kLeaf);
  o.ransac_max_iterations = static_cast<int>(get_count(c, "ransac.max_iterations", o.ransac_max_iterations, kIterations));
  o.ransac_distance_threshold_m = get("ransac.distance_threshold", o.ransac_distance_threshold_m, kDistance);
  o.ransac_eps_angle_rad = kDeg * get("ransac.eps_angle", o.ransac_eps_angle_rad / kDeg, kEpsAngleDeg);
  o.ransac_min_inliers = static_cast<int>(get_count(c, "ransac.min_inliers", o.ransac_min_inliers, kMinInliers));
  o.ransac_max_points = static_cast<int>(get_count(c, "ransac.max_points", o.ransac_max_points, kMaxPoints));
  o.ransac_optimize_coefficients = c.get_bool(kPrefix + "ransac.optimize_coefficients", o.ransac_optimize_coefficients);
  o.running_average_max_deviation_m =
      get("running_average.max_deviation", o.running_average_max_deviation_m, kDeviation);
  o.running_average_frames = static_cast<int>(get_count(c, "running_average.frames", o.running_average_frames, kFrames));
  o.fallback_distance_threshold_m =
      get("running_average.distance_threshold", o.fallback_distance_threshold_m, kDistance);
  o.level_refinement = c.get_bool(kPrefix + "level_refinement", o.level_refinement);
  o.max_step_height_m = get("max_step_height", o.max_step_height_m, kStep);
  o.level_fit_threshold_m = get("level_fit_threshold", o.level_fit_threshold_m, kDistance);
  o.level_eps_angle_rad = kDeg * get("level_eps_angle", o.level_eps_angle_rad / kDeg, kEpsAngleDeg);
  o.above_head_height_m = get("above_head_height", o.above_head_height_m, kAboveHead);
  o.align_to_ground_plane = c.get_bool(kPrefix + "align_to_ground", o.align_to_ground_plane);
  o.scan_min_bearing_rad = kDeg * get("scan.min_bearing", o.scan_min_bearing_rad / kDeg, kBearingDeg);
  o.scan_max_bearing_rad = kDeg * get("scan.max_bearing", o.scan_max_bearing_rad / kDeg, kBearingDeg);
  o.scan_bin_width_rad = kDeg * get("scan.bin_width", o.scan_bin_width_rad / kDeg, kBinWidthDeg);
  if (!(o.scan_max_bearing_rad >= o.scan_min_bearing_rad)) {
    const std::string key = kPrefix + (c.has(kPrefix + "scan.max_bearing") ? "scan.max_bearing" : "scan.min_bearing");
    throw ConfigError(c.origin(key), key,
                      fmt::format("{}° must not be below scan.min_bearing {}°", o.scan_max_bearing_rad / kDeg,
                                  o.scan_min_bearing_rad / kDeg));
  }
  return o;
}

}  // namespace navaid::mapping
