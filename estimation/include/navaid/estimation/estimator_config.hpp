#pragma once
// Settings of the sliding-window estimator, read from a navaid::Config under the `estimator.`
// prefix. Every key, its default and its range is documented in docs/estimator.md ("Sliding
// window"); every switch is an ablation. Values that come from the rig (focal length, depth
// baseline and disparity noise) are taken from the calibration unless a key overrides them.
#include <cmath>
#include <string>

#include "navaid/core/config.hpp"
#include "navaid/core/geometry.hpp"
#include "navaid/estimation/factors/depth_3d_covariance.hpp"

namespace navaid::estimation {

enum class LossKind { kCauchy, kHuber, kNone };
enum class LinearSolverKind { kDenseSchur, kSparseSchur, kSparseNormalCholesky };
/// What happens to the inverse depth of a far feature (anchor depth > far_threshold_m).
enum class FarFeaturePolicy { kFree, kFixed };
/// A track whose anchor keyframe leaves the window: its factors go into the marginalization prior
/// and it is re-anchored at its next observation, whose factors then count a second time
/// (VINS-Mono, "reuse"); its factors go into the prior and it is restarted at its next new
/// observation ("restart"); or its factors stay out of the prior and it is re-anchored, so every
/// observation counts once and the leaving anchor's bearing is given up ("reanchor").
enum class LeavingAnchorPolicy { kReuse, kRestart, kReanchor, kHandOver };
/// The bearing of a feature in its anchor keyframe: the anchor's measurement, held exact (VINS-Mono,
/// DSO), or estimated with the inverse depth, the anchor observation then being a factor
/// (factors/landmark_factors.hpp says why).
enum class AnchorBearing { kFixed, kEstimated };
/// How the newest state's covariance is computed: Schur complement of the window's information
/// (fast), ceres::Covariance (SPARSE_QR; reference, slower), or not at all.
enum class CovarianceMethod { kSchur, kCeres, kOff };
/// How the visual residuals are weighted in the covariance: as the robust loss weights them in the
/// solve (Triggs-corrected, as ceres::Covariance), or at full Gaussian weight unless beyond the
/// outlier gate (then not at all).
enum class CovarianceWeights { kRobust, kInliers };
/// What a frame that will not be kept (a non-keyframe) solves: the whole window with it, as a
/// keyframe does ("window"), or its own state alone against the window held where the last solve
/// left it ("newest": motion-only, the window's keyframes and landmarks are refined at keyframes).
enum class NonKeyframeSolve { kWindow, kNewest };
/// Which blocks a Schur solver eliminates: the landmarks, Ceres' own independent set, or (auto)
/// the landmarks where that gives Ceres' fixed-size kernels (VIO), Ceres' set otherwise.
enum class SchurOrdering { kAuto, kLandmarks, kCeres };
/// How GPS enters (factors.gps): T_ENU_W and GPS factors in the window ("joint"), or the VIO window
/// alone with T_ENU_W re-registered over the fixes at every fix (eLabrador, "decoupled").
enum class GpsMode { kJoint, kDecoupled };
/// How the window starts: from a still start (gravity from the mean accelerometer), or by the
/// visual-inertial initialization (window SfM + alignment, docs/initialization.md) whose pose change
/// is HPnP (W-ROMA RGBD-VIO) or 3D-2D PnP (VINS-RGBD).
enum class InitializationMethod { kStill, kHybridPnp, kPnp };

/// What a solve must not produce (VINS-Mono's failure detection, with a pedestrian's limits).
struct FailureThresholds {
  double max_accel_bias = 2.5;  ///< |b_a| [m/s^2] (VINS-Mono 2.5)
  double max_gyro_bias = 1.0;   ///< |b_g| [rad/s] (VINS-Mono 1.0)
  /// Position change between consecutive estimates beyond the previous velocity times the time
  /// between them [m] (a walker at 30 Hz moves 5 cm a frame).
  double max_position_jump_m = 1.0;
  double max_rotation_jump_rad = 50.0 * M_PI / 180.0;  ///< between consecutive estimates (VINS-Mono 50 deg)
  double max_speed_mps = 10.0;                         ///< |v| (walking: ~1.5 m/s)
  /// Share of the newest frame's visual residual blocks inside the inlier gate (|r|^2 <= 16)
  /// below which vision and the IMU disagree: the solve followed one and rejected the other.
  double min_inlier_fraction = 0.5;
  /// Checked when the newest frame has at least this many visual residual blocks.
  int min_visual_residuals = 16;
  /// ... and only after the median share of the last second was at least this.
  double collapse_from = 0.8;
};

struct EstimatorConfig {
  int window_size = 10;  ///< keyframes in the window
  /// Multipliers of the calibration's IMU white-noise densities and random walks (a datasheet's
  /// values hold for a still, quiet IMU; rotor or gait vibration adds noise the model must cover).
  double imu_noise_scale = 1.0;
  double imu_random_walk_scale = 1.0;
  /// A gap in the IMU stream longer than this is bridged with the walker's motion as noise
  /// (ImuNoise::max_sample_gap_s; 0 = never): a dropped USB packet or a stalled driver then
  /// widens the covariance instead of stopping the run.
  double imu_max_sample_gap_s = 0.05;
  double imu_gap_gyro_density = 0.5;   ///< [rad/s/sqrt(Hz)]
  double imu_gap_accel_density = 2.0;  ///< [m/s^2/sqrt(Hz)]

  // Factor switches.
  bool use_imu = true;
  bool use_reprojection = true;
  bool use_inverse_depth = true;
  bool use_depth_3d = true;
  bool use_gps = false;
  bool use_mag = false;
  /// Zero-velocity update (zero_velocity_factor.hpp) on frames whose tracks stood still.
  bool use_zero_velocity = true;
  /// false: ignore every depth measurement (VIO): no depth factors, inverse depths triangulated.
  bool use_depth = true;

  // Features.
  double far_threshold_m = 3.0;
  FarFeaturePolicy far_policy = FarFeaturePolicy::kFree;
  /// A free far feature keeps a weak prior on its inverse depth: the anchor's measured depth with
  /// sigma_lambda x this. Without it (0, the paper as written) nothing constrains a far inverse
  /// depth while the camera only turns (a user standing and scanning with the head or cane): the
  /// window then drifts like dead reckoning (1.6-1.8 m in 30 s, docs/estimator.md). Large enough
  /// that parallax, whenever there is some, decides the depth.
  double far_depth_sigma_scale = 10.0;
  double pixel_sigma_px = 1.5;
  /// Below this many features with usable visual factors the frame is IMU-only.
  int min_visual_features = 8;
  /// What happens to a track whose anchor keyframe is marginalized (docs/estimator.md, "Features").
  LeavingAnchorPolicy leaving_anchor = LeavingAnchorPolicy::kReuse;
  AnchorBearing anchor_bearing = AnchorBearing::kEstimated;
  /// Depth noise: 0 = the calibration's depth_disparity_sigma_px / depth_baseline_m.
  double disparity_sigma_px = 0;
  double depth_baseline_m = 0;
  /// Covariance of the depth-augmented 3D factor's measured point (depth_3d_factor.hpp).
  Depth3dCovariance depth_3d_covariance = Depth3dCovariance::kFull;

  // Keyframes.
  double keyframe_parallax_px = 10.0;  ///< mean parallax to the last keyframe
  int keyframe_min_tracked = 30;       ///< fewer common tracks than this: keyframe (track loss)
  double keyframe_max_interval_s = 1.0;

  // Robust loss on visual factors (scale in standard deviations).
  LossKind loss = LossKind::kCauchy;
  double loss_scale = 1.0;

  // Solver.
  LinearSolverKind linear_solver = LinearSolverKind::kDenseSchur;
  int max_iterations = 8;
  double max_solver_time_s = 0;  ///< 0: no limit (a limit makes results depend on the machine)
  NonKeyframeSolve non_keyframe_solve = NonKeyframeSolve::kNewest;
  SchurOrdering schur_ordering = SchurOrdering::kAuto;

  bool marginalization = true;
  /// First-estimate Jacobians for the factors on blocks the prior holds (first_estimates.hpp).
  bool first_estimates = false;
  /// Accumulate whitened residual statistics per factor type after every solve (costs one more
  /// evaluation of the window per frame).
  bool residual_diagnostics = false;
  CovarianceMethod covariance_method = CovarianceMethod::kSchur;
  CovarianceWeights covariance_weights = CovarianceWeights::kInliers;
  /// Weights of the visual factors in the marginalization prior (inliers: the covariance's gate).
  CovarianceWeights prior_weights = CovarianceWeights::kInliers;

  // Initialization.
  InitializationMethod init_method = InitializationMethod::kStill;
  double still_duration_s = 0.5;  ///< still: IMU data averaged for gravity
  double init_sigma_roll_pitch_rad = 0.01;
  double init_sigma_velocity = 0.02;   ///< [m/s]
  double init_sigma_gyro_bias = 0.01;  ///< [rad/s]
  double init_sigma_accel_bias = 0.1;  ///< [m/s^2]
  /// still: when the camera confirms the still window (its tracks moved at most
  /// still_max_motion_px, median), the mean gyro over it is the gyro bias, with the standard error
  /// of that mean; otherwise the bias starts at 0 +- init_sigma_gyro_bias. A still start also
  /// serves a re-initialization when the camera and the accelerometer say the user stands still.
  bool still_gyro_bias = true;
  double still_max_motion_px = 2.0;

  // Zero-velocity update: the newest frame's tracks moved at most zero_velocity_max_motion_px
  // (median) since the frame zero_velocity_lookback_s before it and the predicted speed is below
  // zero_velocity_max_speed_mps: v = 0 +- zero_velocity_sigma_mps.
  double zero_velocity_sigma_mps = 0.01;
  double zero_velocity_max_motion_px = 2.0;
  double zero_velocity_lookback_s = 0.25;
  double zero_velocity_max_speed_mps = 0.3;

  // GPS (factors.gps): a fix joins the frame within this time of it; Huber threshold [sigma].
  double gps_max_time_offset_s = 0.02;
  double gps_huber_threshold = 2.0;
  /// Correlation time of the fix errors (multipath) for the registration's covariance [s].
  double gps_correlation_time_s = 30.0;
  GpsMode gps_mode = GpsMode::kJoint;
  /// Joint: share of each fix's reported covariance that is multipath, a bias per fix estimated as
  /// a Gauss-Markov process (time constant gps_correlation_time_s); 0: independent fixes.
  double gps_multipath_fraction = 0.0;
  /// Decoupled: register over the newest this many fixes (0: every fix so far).
  int gps_registration_fixes = 0;
  /// Innovation gate (gps.outlier_gate): once W is registered, a fix whose squared Mahalanobis
  /// distance from the antenna position the state predicts (under the fix's covariance, plus the
  /// multipath share) exceeds this is not used (0: off; 16.27 = chi2(3) at 99.9 %): a jump, not a
  /// walk. Fixes that keep disagreeing for longer than gps_max_outlier_s are used again (the
  /// state, not the fixes, has drifted).
  double gps_outlier_gate = 16.27;
  double gps_max_outlier_s = 20.0;

  // Magnetometer (factors.mag). The field of a sample, calibrated as soft_iron^-1 (m - hard_iron),
  // is compared in heading with the reference field (ENU, declination included) [T].
  Vec3 mag_reference_field_enu = Vec3(0.0, 20e-6, -45e-6);
  Vec3 mag_hard_iron = Vec3::Zero();
  Mat3 mag_soft_iron = Mat3::Identity();
  double mag_sigma = 0.2e-6;  ///< white noise per axis of one sample [T]
  /// A state gets the samples bracketing it interpolated when both lie within this time of it,
  /// else the nearest one within it, else no magnetometer factor [s].
  double mag_max_time_offset_s = 0.03;
  /// A disturbed field (steel, a passing car, a motor) is not used: its strength off the
  /// reference's by more than this fraction, or its inclination (in the state's gravity-aligned
  /// frame) off by more than this angle [deg]. 0 switches a test off.
  double mag_max_norm_deviation = 0.15;
  double mag_max_inclination_deviation_deg = 10.0;
  /// Once W has a magnetic heading: a field whose heading disagrees with the state's by more than
  /// this [deg] is disturbed too, unless it has disagreed for longer than
  /// mag_max_disturbance_s (then the state's yaw drifted, and the field is trusted again).
  double mag_max_heading_deviation_deg = 20.0;
  double mag_max_disturbance_s = 10.0;

  /// IMU-only for longer than this: mode "lost".
  double lost_after_s = 2.0;

  // Failure detection after every solve (failure_detection.hpp) and recovery: a restart of the
  // window from the last good estimate (the map frame kept), or, without one, a new
  // initialization (hpnp when the method is still: the user is walking).
  bool failure_detection = true;
  FailureThresholds failure;
  /// A restart starts from the newest estimate that vision confirmed (this share of its frame's
  /// visual residual blocks inside the gate) within restart_max_gap_s before the failed frame,
  /// carried to the frame at constant velocity with the gyro's rotation.
  double confirmed_inlier_fraction = 0.9;
  double restart_max_gap_s = 1.0;
  /// Uncertainty added to the good estimate's velocity [m/s], and the
  /// walker's acceleration over the gap as white noise of this density [m/s^2/sqrt(s)].
  double restart_sigma_velocity = 0.5;
  double restart_accel_density = 2.0;

  // Camera-IMU calibration estimated online (VINS-Mono style), starting from the rig calibration
  // with a Gaussian prior of these sigmas around it.
  bool estimate_extrinsic = false;
  double extrinsic_sigma_rotation_rad = 0.05;
  double extrinsic_sigma_translation_m = 0.05;
  bool estimate_time_offset = false;
  double time_offset_sigma_s = 0.02;
};

/// Reads `estimator.*` (defaults above for absent keys); ConfigError names the key and its range.
EstimatorConfig read_estimator_config(const Config& config);

/// A magnetometer sample calibrated with the config's iron model: soft_iron^-1 (raw - hard_iron) [T].
Vec3 calibrated_mag_field(const EstimatorConfig& config, const Vec3& raw);

std::string to_string(LossKind kind);
std::string to_string(LinearSolverKind kind);
std::string to_string(FarFeaturePolicy policy);
std::string to_string(Depth3dCovariance model);
std::string to_string(LeavingAnchorPolicy policy);
std::string to_string(AnchorBearing bearing);
std::string to_string(GpsMode mode);
std::string to_string(InitializationMethod method);
std::string to_string(NonKeyframeSolve solve);
std::string to_string(SchurOrdering ordering);

}  // namespace navaid::estimation
