// Configuration of the obstacle pipeline: keys under mapping.obstacles.*, one allowed range per key
// shared by the YAML reader and validate() so that both reject the same values.
#include <cmath>
#include <string>

#include <fmt/format.h>

#include "navaid/core/errors.hpp"
#include "navaid/mapping/config_schema.hpp"
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

namespace {
// Angles are in degrees in the file, radians in the struct.
const ObstaclePipelineConfig kObstaclePipelineConfigDefaults;
const ConfigKey<double> kVoxelLeaf{kPrefix + "voxel_leaf_size", kObstaclePipelineConfigDefaults.voxel_leaf_size_m, kLeaf,
                                   "edge of the approximate voxel grid cubes [m]"};
const ConfigKey<int> kRansacIterations{kPrefix + "ransac.max_iterations", kObstaclePipelineConfigDefaults.ransac_max_iterations,
                                       static_cast<int>(kIterations.min), static_cast<int>(kIterations.max),
                                       "RANSAC iterations at most"};
const ConfigKey<double> kRansacDistance{kPrefix + "ransac.distance_threshold", kObstaclePipelineConfigDefaults.ransac_distance_threshold_m,
                                        kDistance, "ground-plane inlier distance, also the step boundary [m]"};
const ConfigKey<double> kRansacEpsAngle{kPrefix + "ransac.eps_angle", kObstaclePipelineConfigDefaults.ransac_eps_angle_rad / kDeg,
                                        kEpsAngleDeg, "largest angle between the plane normal and up [deg]"};
const ConfigKey<int> kRansacMinInliers{kPrefix + "ransac.min_inliers", kObstaclePipelineConfigDefaults.ransac_min_inliers,
                                       static_cast<int>(kMinInliers.min), static_cast<int>(kMinInliers.max),
                                       "fewest inliers for a RANSAC plane to count as found"};
const ConfigKey<int> kRansacMaxPoints{kPrefix + "ransac.max_points", kObstaclePipelineConfigDefaults.ransac_max_points,
                                      static_cast<int>(kMaxPoints.min), static_cast<int>(kMaxPoints.max),
                                      "RANSAC fits on at most this many points, spread over the cloud"};
const ConfigKey<bool> kRansacOptimize{kPrefix + "ransac.optimize_coefficients", kObstaclePipelineConfigDefaults.ransac_optimize_coefficients,
                                      "least-squares refit of the RANSAC plane on its inliers"};
const ConfigKey<double> kAverageDeviation{kPrefix + "running_average.max_deviation",
                                          kObstaclePipelineConfigDefaults.running_average_max_deviation_m, kDeviation,
                                          "a plane whose offset differs this much from the average is false [m]"};
const ConfigKey<int> kAverageFrames{kPrefix + "running_average.frames", kObstaclePipelineConfigDefaults.running_average_frames,
                                    static_cast<int>(kFrames.min), static_cast<int>(kFrames.max),
                                    "length of the ground plane's running average [frames]"};
const ConfigKey<double> kFallbackDistance{kPrefix + "running_average.distance_threshold",
                                          kObstaclePipelineConfigDefaults.fallback_distance_threshold_m, kDistance,
                                          "inlier distance to the running-average plane [m]"};
const ConfigKey<bool> kLevelRefinement{kPrefix + "level_refinement", kObstaclePipelineConfigDefaults.level_refinement,
                                       "of two ground levels a step apart, take the one under the user's feet"};
const ConfigKey<double> kMaxStep{kPrefix + "max_step_height", kObstaclePipelineConfigDefaults.max_step_height_m, kStep,
                                 "highest step between two levels of ground [m]"};
const ConfigKey<double> kLevelFit{kPrefix + "level_fit_threshold", kObstaclePipelineConfigDefaults.level_fit_threshold_m, kDistance,
                                  "inlier distance of the level refit [m]"};
const ConfigKey<double> kLevelEpsAngle{kPrefix + "level_eps_angle", kObstaclePipelineConfigDefaults.level_eps_angle_rad / kDeg, kEpsAngleDeg,
                                       "angle tolerance of the level refit [deg]"};
const ConfigKey<double> kAboveHeadHeight{kPrefix + "above_head_height", kObstaclePipelineConfigDefaults.above_head_height_m, kAboveHead,
                                   "points higher than this above the ground are ignored [m]"};
const ConfigKey<bool> kAlignToGround{kPrefix + "align_to_ground", kObstaclePipelineConfigDefaults.align_to_ground_plane,
                                     "rotate the ground normal onto the user's up axis (false: the T_U_C prior as given)"};
const ConfigKey<double> kScanMinBearing{kPrefix + "scan.min_bearing", kObstaclePipelineConfigDefaults.scan_min_bearing_rad / kDeg,
                                        kBearingDeg, "first bearing of the obstacle scan [deg]"};
const ConfigKey<double> kScanMaxBearing{kPrefix + "scan.max_bearing", kObstaclePipelineConfigDefaults.scan_max_bearing_rad / kDeg,
                                        kBearingDeg, "last bearing of the obstacle scan [deg] (>= min_bearing)"};
const ConfigKey<double> kScanBinWidth{kPrefix + "scan.bin_width", kObstaclePipelineConfigDefaults.scan_bin_width_rad / kDeg, kBinWidthDeg,
                                      "bearing bin width of the obstacle scan [deg]"};
}  // namespace

ConfigSchema obstacle_pipeline_config_schema() {
  return ConfigSchema()
      .add(kVoxelLeaf)
      .add(kRansacIterations)
      .add(kRansacDistance)
      .add(kRansacEpsAngle)
      .add(kRansacMinInliers)
      .add(kRansacMaxPoints)
      .add(kRansacOptimize)
      .add(kAverageDeviation)
      .add(kAverageFrames)
      .add(kFallbackDistance)
      .add(kLevelRefinement)
      .add(kMaxStep)
      .add(kLevelFit)
      .add(kLevelEpsAngle)
      .add(kAboveHeadHeight)
      .add(kAlignToGround)
      .add(kScanMinBearing)
      .add(kScanMaxBearing)
      .add(kScanBinWidth);
}

ObstaclePipelineConfig read_obstacle_pipeline_config(const Config& c) {
  ObstaclePipelineConfig o;
  o.voxel_leaf_size_m = get(c, kVoxelLeaf);
  o.ransac_max_iterations = get(c, kRansacIterations);
  o.ransac_distance_threshold_m = get(c, kRansacDistance);
  o.ransac_eps_angle_rad = kDeg * get(c, kRansacEpsAngle);
  o.ransac_min_inliers = get(c, kRansacMinInliers);
  o.ransac_max_points = get(c, kRansacMaxPoints);
  o.ransac_optimize_coefficients = get(c, kRansacOptimize);
  o.running_average_max_deviation_m = get(c, kAverageDeviation);
  o.running_average_frames = get(c, kAverageFrames);
  o.fallback_distance_threshold_m = get(c, kFallbackDistance);
  o.level_refinement = get(c, kLevelRefinement);
  o.max_step_height_m = get(c, kMaxStep);
  o.level_fit_threshold_m = get(c, kLevelFit);
  o.level_eps_angle_rad = kDeg * get(c, kLevelEpsAngle);
  o.above_head_height_m = get(c, kAboveHeadHeight);
  o.align_to_ground_plane = get(c, kAlignToGround);
  o.scan_min_bearing_rad = kDeg * get(c, kScanMinBearing);
  o.scan_max_bearing_rad = kDeg * get(c, kScanMaxBearing);
  o.scan_bin_width_rad = kDeg * get(c, kScanBinWidth);
  if (!(o.scan_max_bearing_rad >= o.scan_min_bearing_rad)) {
    const std::string key = kPrefix + (c.has(kPrefix + "scan.max_bearing") ? "scan.max_bearing" : "scan.min_bearing");
    throw ConfigError(c.origin(key), key,
                      fmt::format("{}° must not be below scan.min_bearing {}°", o.scan_max_bearing_rad / kDeg,
                                  o.scan_min_bearing_rad / kDeg));
  }
  return o;
}

}  // namespace navaid::mapping
