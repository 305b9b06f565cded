#pragma once
// The obstacle pipeline's output (BYU augmented cane, thesis Ch. 2 "Nearest Point Laser Scan"): the
// nearest obstacle point per 1° of bearing in the ground-aligned user frame U, plus the nearest
// drop-off (ground below the fitted plane: a kerb or step down) per bearing and the counters of
// every pipeline stage. This is what the planning layer's FICF / CACF cost functions read.
//
// Frame U (DESIGN.md §4): ground-aligned, z up, x forward (the camera's heading projected on the
// ground, the thesis's "direction of the cane"), y left; origin on the ground plane directly below
// the camera, so z_U is the height above the ground plane and ranges are horizontal distances.
// Bearing = atan2(y_U, x_U): 0 straight ahead, positive to the left. The thesis measures
// phi = atan(p_z / p_x) in its levelled sensor frame (x right), 90° ahead, so bearing = phi - 90°.
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "navaid/core/geometry.hpp"
#include "navaid/core/time.hpp"

namespace navaid::mapping {

/// Where the ground plane of a frame came from (thesis "Ground Plane Filtering").
enum class GroundSource : std::uint8_t {
  kRansac,                   ///< RANSAC found a plane consistent with the running average
  kRunningAverageRejected,   ///< RANSAC's plane was off the running average by more than the
                             ///< allowed deviation (a table top): the running-average plane is used
  kRunningAverageNoPlane,    ///< RANSAC found no plane: the running-average plane is used
  kPrior,                    ///< no plane and no running average yet: the plane of the T_U_C prior
};

/// Ground plane n . p_C + offset = 0 in the camera frame C (Hessian normal form, thesis eq. 2.1).
/// `normal_C` is a unit vector pointing up (away from the ground), so `offset_m` is the height of
/// the camera above the plane and height_above(p) > 0 for points above the ground.
struct GroundPlane {
  Eigen::Vector3d normal_C = -Eigen::Vector3d::UnitY();
  double offset_m = 0.0;

  double height_above(const Eigen::Vector3d& p_C) const { return normal_C.dot(p_C) + offset_m; }
};

/// Point counts of each stage of one frame (every count refers to this frame only).
struct ObstacleScanCounters {
  std::size_t points_in = 0;            ///< points handed to the pipeline
  std::size_t non_finite = 0;           ///< of points_in: NaN / inf coordinates, skipped
  std::size_t after_voxel_grid = 0;     ///< finite points left by the approximate voxel grid
  std::size_t ground_inliers = 0;       ///< points removed as ground (within the threshold of the plane used)
  std::size_t above_head_removed = 0;   ///< points more than the above-head height over the ground
  std::size_t drop_off_points = 0;      ///< non-ground points below the ground plane (kerbs, steps down)
  std::size_t obstacle_points = 0;      ///< points left as obstacles (before binning)
  std::size_t outside_scan = 0;         ///< obstacle or drop-off points whose bearing has no bin
  bool ransac_succeeded = false;        ///< RANSAC returned a plane (even if it was then rejected)
  bool running_average_used = false;    ///< the frame used the running-average plane
  /// A second ground level (kerb, step) was found within the step height of the dominant one;
  /// the nearer of the two is the ground, the other is obstacle (above) or drop-off (below).
  bool second_level_found = false;
  bool second_level_chosen = false;     ///< the nearer level was RANSAC's second one
  GroundSource ground_source = GroundSource::kPrior;
};

/// Nearest obstacle and drop-off per bearing bin. Bin i covers bearings within half a bin width
/// of bearing(i) (the thesis rounds the angle to the nearest degree, eq. 2.9). A bin in which
/// nothing is seen has range +infinity (REP 117: "no return") and NaN points.
struct ObstacleScan {
  Timestamp t = 0;
  double min_bearing_rad = 0.0;        ///< centre of bin 0
  double bearing_increment_rad = 0.0;  ///< bin width (1° by default)

  /// Horizontal distance [m] from the U origin to the nearest obstacle point of each bin.
  std::vector<float> ranges;
  /// That nearest obstacle point in U [m]; NaN where ranges[i] is infinite.
  std::vector<Eigen::Vector3f> nearest_U;
  /// Horizontal distance [m] to the nearest drop-off point of each bin (+inf: none seen).
  std::vector<float> drop_off_ranges;
  /// That nearest drop-off point in U (z_U < 0: its depth below the ground); NaN where none.
  std::vector<Eigen::Vector3f> drop_off_nearest_U;

  GroundPlane ground;  ///< the plane used for this frame, in C
  SE3 T_U_C;           ///< the sensor-to-user alignment used for this frame
  ObstacleScanCounters counters;

  /// Empty bins (every range +inf) over [min_bearing, min_bearing + (bins - 1) increment].
  static ObstacleScan empty(std::size_t bins, double min_bearing_rad, double bearing_increment_rad);

  std::size_t size() const { return ranges.size(); }
  double bearing(std::size_t bin) const { return min_bearing_rad + static_cast<double>(bin) * bearing_increment_rad; }
  /// The bin whose centre is nearest to `bearing_rad`; nullopt when outside every bin.
  std::optional<std::size_t> bin_of(double bearing_rad) const;
  bool has_obstacle(std::size_t bin) const { return ranges[bin] < std::numeric_limits<float>::infinity(); }
  bool has_drop_off(std::size_t bin) const { return drop_off_ranges[bin] < std::numeric_limits<float>::infinity(); }
  /// Smallest obstacle range over all bins (+inf when the scan is clear).
  float min_range() const;
};

}  // namespace navaid::mapping
