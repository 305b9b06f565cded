#pragma once
// The BYU augmented-cane obstacle pipeline (thesis Ch. 2.2.2, docs/mapping.md ("Obstacle pipeline")):
// points in the camera frame C  ->  approximate voxel grid  ->  RANSAC perpendicular-plane ground
// fit (checked against a running average of the plane offset, which replaces it when RANSAC fails
// or finds a table)  ->  ground removal  ->  above-head removal  ->  sensor-to-user alignment
// (rotate the ground normal onto the user's up axis)  ->  nearest point per 1° of bearing.
// Points below the ground plane are drop-offs (a kerb or step down), never obstacles; the scan
// reports them separately.
//
// PCL (thirdparty-notes/pcl.md) stays inside the implementation: this header speaks Eigen and core.
// Thread safety: a pipeline keeps the running average between frames, so one instance serves one
// camera stream from one thread; process() is deterministic (RANSAC is seeded by PCL).
#include <cstddef>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "navaid/core/calibration.hpp"
#include "navaid/core/config.hpp"
#include "navaid/core/geometry.hpp"
#include "navaid/core/messages.hpp"
#include "navaid/core/time.hpp"
#include "navaid/mapping/obstacle_scan.hpp"

namespace navaid::mapping {

/// Every parameter of the pipeline; defaults are the thesis's values (section and page of
/// "Augmented Cane ... Point Cloud Obstacle Avoidance", BYU) or, where it gives none, ours with
/// the reason. Config keys (read_obstacle_pipeline_config) are under `mapping.obstacles.`.
struct ObstaclePipelineConfig {
  static constexpr double kDeg = 3.14159265358979323846 / 180.0;  ///< radians per degree

  /// Edge of the approximate voxel grid cubes [m]. Thesis App. D.2 (`leaf_size = 0.01`); the text
  /// says only that the grid removes 10-50 % of the points. Key `voxel_leaf_size`.
  double voxel_leaf_size_m = 0.01;

  /// RANSAC iterations at most ("The maximum iterations used within the RANSAC method is 1000").
  /// Key `ransac.max_iterations`.
  int ransac_max_iterations = 1000;
  /// Inlier distance of the ground plane [m] ("The maximum distance threshold for points to be
  /// included in the model is 0.1 meters"). It is also the step boundary: what lies more than
  /// this above the plane is an obstacle (a 15 cm step up), more than this below it a drop-off (a
  /// kerb stepped down). Key `ransac.distance_threshold`.
  double ransac_distance_threshold_m = 0.1;
  /// Largest angle between the plane normal and the expected up axis [rad] ("The normal of the
  /// perpendicular plane can deviate at most 15° from the Xtion Pro Live y-axis"; App. D.2 uses
  /// 20°). The axis is the up direction of the T_U_C prior: the camera's -y for a level camera,
  /// as in the thesis. Key `ransac.eps_angle` [deg].
  double ransac_eps_angle_rad = 15.0 * kDeg;
  /// Fewest inliers for a RANSAC plane to count as found. The thesis asks for "a minimum number
  /// of points" without a number; 300 voxels is ~ 0.03 m² of floor at 1 cm leaf. Key
  /// `ransac.min_inliers`.
  int ransac_min_inliers = 300;
  /// RANSAC fits on at most this many points, spread evenly over the voxel cloud (ours, for the
  /// 30 frames/s budget: RANSAC's cost is iterations x points, and the thesis's 1 cm voxels leave
  /// 100k+ points of a 640x480 frame). Inliers are then selected among all points. Key
  /// `ransac.max_points`.
  int ransac_max_points = 5000;
  /// Least-squares refit of the RANSAC plane on its inliers (App. D.2 `setOptimizeCoefficients
  /// (true)`). Key `ransac.optimize_coefficients`.
  bool ransac_optimize_coefficients = true;

  /// A RANSAC plane whose offset D differs from the running average D_avg by more than this [m]
  /// is a false ground detection, e.g. a table top ("When a calculated D value differs from D_avg
  /// by more than 0.2 meters, it is considered a false ground plane detection"). The frame then
  /// uses the running-average plane (normal and D_avg: the thesis keeps the false plane's normal,
  /// which may be tilted by up to the angle tolerance).
  /// Key `running_average.max_deviation`.
  double running_average_max_deviation_m = 0.2;
  /// Length of the running average [frames]: the cumulative mean of the first N accepted planes,
  /// then an exponential average of weight 1/N. The thesis does not say which average; 30 frames
  /// are 1 s of the Xtion's 30 Hz stream. Key `running_average.frames`.
  int running_average_frames = 30;
  /// Inlier distance [m] used with the running-average plane ("the maximum distance threshold is
  /// increased to improve the probability of extracting the points comprising the ground plane";
  /// no value given: 1.5 x the RANSAC threshold). Key `running_average.distance_threshold`.
  double fallback_distance_threshold_m = 0.15;

  /// Level refinement and two-level ground (ours; the thesis assumes one flat floor). The
  /// thesis's 0.1 m band lets wall bases pull the least-squares plane by 1-2° (which turns into
  /// bearing errors along walls), and with a kerb RANSAC prefers a slightly tilted plane through
  /// both levels, leaving the near pavement or the far road outside the band: a wall at the
  /// user's feet. So after the thesis's fit the dominant flat level is refitted with
  /// `level_fit_threshold_m`, and a second level parallel to it is searched among the points
  /// outside its ground band: more than the band and at most `max_step_height_m` above or below,
  /// covering an area (not a band through a wall). If there is one, the ground is the level nearer
  /// to the user (the one under the user's feet). The removal band stays the thesis's.
  /// Key `level_refinement`.
  bool level_refinement = true;
  /// Inlier distance of the level search [m]: depth noise of a structured-light sensor at a few
  /// metres (Kinect / Xtion: ~1.5 cm at 3 m), well below a kerb. Key `level_fit_threshold`.
  double level_fit_threshold_m = 0.03;
  /// Largest angle [rad] between the thesis's plane and the refined level, and between the two
  /// levels (ours): the tilt of a plane fitted through both levels of a kerb is 2-4°, and a road
  /// is parallel to its pavement within its camber (<= 2.5 %, 1.4°). Key `level_eps_angle` [deg].
  double level_eps_angle_rad = 5.0 * kDeg;
  /// Largest offset between the two ground levels [m]: kerbs and low steps are <= 0.15-0.2 m
  /// (docs/scenarios.md, ClearanceBand); beyond this the other level is a table or a hole and
  /// is left to the obstacle / drop-off rule. Key `max_step_height`.
  double max_step_height_m = 0.3;

  /// Points more than this above the ground plane are removed [m] ("the fourth Hessian
  /// component is increased by a value of 2.0 meters"; App. D.2 uses 1.65). Key `above_head_height`.
  double above_head_height_m = 2.0;

  /// Rotate the ground normal onto the user's up axis (thesis "Sensor to User Frame
  /// Transformation", eq. 2.5-2.8). false: use the T_U_C prior as given. Key `align_to_ground`.
  bool align_to_ground_plane = true;

  /// Bearing of the first and last bin centre [rad] and the bin width. Thesis App. D.2: 61 bins
  /// from -30° to 30° in 1° steps (the Xtion's 58° view: eq. 2.9, 61°..119° in its angle).
  /// Keys `scan.min_bearing`, `scan.max_bearing`, `scan.bin_width` [deg].
  double scan_min_bearing_rad = -30.0 * kDeg;
  double scan_max_bearing_rad = 30.0 * kDeg;
  double scan_bin_width_rad = 1.0 * kDeg;

  /// Number of bins: round((max - min) / width) + 1.
  std::size_t scan_bins() const;
};

/// Reads `mapping.obstacles.*` (every key optional, defaults above, angles in degrees); each value
/// is range-checked and the scan limits must be ordered, else ConfigError naming the key.
ObstaclePipelineConfig read_obstacle_pipeline_config(const Config& config);
/// Throws ConfigError (file "<obstacle pipeline>") when a value is out of range.
void validate(const ObstaclePipelineConfig& config);

/// T_U_C of a camera at `height_m` above the ground, pitched down by `pitch_down_rad` about its x
/// axis, with no roll: the optical axis projects on U's x axis. Pitch 0 is the thesis's set-up
/// (RANSAC axis = camera y).
SE3 level_camera_T_U_C(double height_m, double pitch_down_rad = 0.0);

/// The ground plane that a T_U_C implies (z_U = 0, up = U's z axis), in C.
GroundPlane ground_plane_of(const SE3& T_U_C);

/// Sensor-to-user alignment from a ground plane (thesis eq. 2.5-2.8): the prior's rotation
/// corrected by the smallest rotation that takes the plane's normal onto U's z axis (axis
/// n x z_U, angle acos(n . z_U)), then turned about z_U so that the optical axis keeps the
/// heading the prior gives it (the smallest rotation alone shifts bearings by ~ roll error x
/// sin(pitch)). Translation (prior x, prior y, plane offset), so z_U is the height above the
/// plane. With a level-camera prior and no roll this is exactly the thesis's
/// Eigen::AngleAxis(acos(-B), (C, 0, -A) / |(C, 0, -A)|) followed by the optical-to-user axes.
SE3 user_frame_from_ground(const GroundPlane& plane, const SE3& T_U_C_prior);

/// Back-projects a metric depth image (RgbdFrame::depth, z along the optical axis, 0 = invalid)
/// through `camera` (distortion honoured), taking every `stride`-th pixel in x and y. Row-major,
/// ceil(width / stride) x ceil(height / stride) points in C; invalid pixels give NaN points, which
/// the pipeline counts as non-finite. Throws navaid::Error when the frame has no depth pixels
/// loaded, its size differs from the calibration, or stride < 1.
std::vector<Eigen::Vector3f> camera_points_from_depth(const RgbdFrame& frame, const CameraCalibration& camera,
                                                      int stride = 1);

class ObstaclePipeline {
 public:
  /// Validates the configuration (ConfigError).
  explicit ObstaclePipeline(const ObstaclePipelineConfig& config = {});
  ~ObstaclePipeline();
  ObstaclePipeline(ObstaclePipeline&&) noexcept;
  ObstaclePipeline& operator=(ObstaclePipeline&&) noexcept;
  ObstaclePipeline(const ObstaclePipeline&) = delete;
  ObstaclePipeline& operator=(const ObstaclePipeline&) = delete;

  /// One frame: `points_C` in the camera optical frame (non-finite points are skipped and
  /// counted), `T_U_C_prior` the sensor-to-user alignment known before looking at the cloud
  /// (IMU gravity and the mount height, or level_camera_T_U_C). Its up axis is the RANSAC axis,
  /// its plane the fallback before any running average exists, and its heading the heading of U.
  /// Updates the running average when RANSAC's plane is accepted. An empty cloud gives an empty
  /// scan (every bin +inf) with the fallback plane.
  ObstacleScan process(const std::vector<Eigen::Vector3f>& points_C, const SE3& T_U_C_prior, Timestamp t = 0);

  /// Forgets the running average (a new recording).
  void reset();
  /// Accepted RANSAC planes in the running average so far.
  std::size_t running_average_count() const;
  /// The running-average plane; only meaningful when running_average_count() > 0.
  GroundPlane running_average_plane() const;

  const ObstaclePipelineConfig& config() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace navaid::mapping
