#include "navaid/estimation/estimator_config.hpp"

#include <limits>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include "navaid/core/enum_names.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/estimation/config_schema.hpp"

namespace navaid::estimation {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// One table per enum: the config key's allowed values, the value read, and to_string.
constexpr NameTable<GpsMode, 2> kGpsModeNames{{
    {GpsMode::kJoint, "joint"},
    {GpsMode::kDecoupled, "decoupled"},
}};
constexpr NameTable<FarFeaturePolicy, 2> kFarPolicyNames{{
    {FarFeaturePolicy::kFree, "free"},
    {FarFeaturePolicy::kFixed, "fixed"},
}};
constexpr NameTable<AnchorBearing, 2> kAnchorBearingNames{{
    {AnchorBearing::kFixed, "fixed"},
    {AnchorBearing::kEstimated, "estimated"},
}};
constexpr NameTable<LeavingAnchorPolicy, 4> kLeavingAnchorNames{{
    {LeavingAnchorPolicy::kReuse, "reuse"},
    {LeavingAnchorPolicy::kRestart, "restart"},
    {LeavingAnchorPolicy::kReanchor, "reanchor"},
    {LeavingAnchorPolicy::kHandOver, "hand_over"},
}};
constexpr NameTable<Depth3dCovariance, 2> kDepth3dCovarianceNames{{
    {Depth3dCovariance::kFull, "full"},
    {Depth3dCovariance::kPaper, "paper"},
}};
constexpr NameTable<LossKind, 3> kLossNames{{
    {LossKind::kCauchy, "cauchy"},
    {LossKind::kHuber, "huber"},
    {LossKind::kNone, "none"},
}};
constexpr NameTable<LinearSolverKind, 3> kLinearSolverNames{{
    {LinearSolverKind::kDenseSchur, "dense_schur"},
    {LinearSolverKind::kSparseSchur, "sparse_schur"},
    {LinearSolverKind::kSparseNormalCholesky, "sparse_normal_cholesky"},
}};
constexpr NameTable<NonKeyframeSolve, 2> kNonKeyframeSolveNames{{
    {NonKeyframeSolve::kWindow, "window"},
    {NonKeyframeSolve::kNewest, "newest"},
}};
constexpr NameTable<SchurOrdering, 3> kSchurOrderingNames{{
    {SchurOrdering::kAuto, "auto"},
    {SchurOrdering::kLandmarks, "landmarks"},
    {SchurOrdering::kCeres, "ceres"},
}};
constexpr NameTable<CovarianceMethod, 3> kCovarianceMethodNames{{
    {CovarianceMethod::kSchur, "schur"},
    {CovarianceMethod::kCeres, "ceres"},
    {CovarianceMethod::kOff, "off"},
}};
constexpr NameTable<CovarianceWeights, 2> kCovarianceWeightsNames{{
    {CovarianceWeights::kRobust, "robust"},
    {CovarianceWeights::kInliers, "inliers"},
}};
constexpr NameTable<InitializationMethod, 3> kInitializationNames{{
    {InitializationMethod::kStill, "still"},
    {InitializationMethod::kHybridPnp, "hpnp"},
    {InitializationMethod::kPnp, "pnp"},
}};

/// An enum key: get() checks the name against the table's names (its error lists them), the
/// table gives the value.
template <class Enum, std::size_t N>
ConfigKey<std::string> enum_key(const char* key, const std::string& fallback, const NameTable<Enum, N>& table,
                                const char* doc) {
  return ConfigKey<std::string>{key, fallback, enum_names(table), doc};
}

template <class Enum, std::size_t N>
Enum get_enum(const Config& c, const ConfigKey<std::string>& key, const NameTable<Enum, N>& table) {
  const std::string name = get(c, key);
  if (const std::optional<Enum> value = enum_value(table, name)) return *value;
  throw Error("unreachable: get() validated '" + name + "'");
}

Vec3 get_vec3(const Config& c, const ConfigKey<std::vector<double>>& key) {
  const auto v = get(c, key);
  return Vec3(v[0], v[1], v[2]);
}

std::vector<double> items(const Vec3& v) { return {v.x(), v.y(), v.z()}; }

const EstimatorConfig kDefaults;
const FailureThresholds& kFailure = kDefaults.failure;

// Window, IMU and factor switches.
const ConfigKey<int> kWindowSize{"estimator.window_size", kDefaults.window_size, 2, 100, "keyframes in the window"};
const ConfigKey<bool> kUseImu{"estimator.factors.imu", kDefaults.use_imu, "IMU preintegration factors"};
const ConfigKey<double> kImuNoiseScale{"estimator.imu.noise_scale", kDefaults.imu_noise_scale, {1e-3, 1e3},
                                       "multiplier of the calibration's IMU white-noise densities"};
const ConfigKey<double> kImuRandomWalkScale{"estimator.imu.random_walk_scale", kDefaults.imu_random_walk_scale,
                                            {1e-3, 1e3}, "multiplier of the calibration's IMU random walks"};
const ConfigKey<double> kImuMaxSampleGap{"estimator.imu.max_sample_gap", kDefaults.imu_max_sample_gap_s, {0, 10},
                                         "IMU gaps longer than this are bridged with the walker's motion as noise [s]; "
                                         "0 = never"};
const ConfigKey<double> kImuGapGyroDensity{"estimator.imu.gap_gyro_density", kDefaults.imu_gap_gyro_density, {1e-4, 100},
                                           "gyro noise density over a bridged IMU gap [rad/s/sqrt(Hz)]"};
const ConfigKey<double> kImuGapAccelDensity{"estimator.imu.gap_accel_density", kDefaults.imu_gap_accel_density,
                                            {1e-3, 1000}, "accelerometer noise density over a bridged IMU gap "
                                                          "[m/s^2/sqrt(Hz)]"};
const ConfigKey<bool> kUseReprojection{"estimator.factors.reprojection", kDefaults.use_reprojection,
                                       "reprojection factors"};
const ConfigKey<bool> kUseInverseDepth{"estimator.factors.inverse_depth", kDefaults.use_inverse_depth,
                                       "inverse-depth factors"};
const ConfigKey<bool> kUseDepth3d{"estimator.factors.depth_3d", kDefaults.use_depth_3d, "depth-augmented 3D factors"};
const ConfigKey<bool> kUseGps{"estimator.factors.gps", kDefaults.use_gps, "GPS factors"};
const ConfigKey<bool> kUseMag{"estimator.factors.mag", kDefaults.use_mag, "magnetometer factors"};
const ConfigKey<bool> kUseZeroVelocity{"estimator.factors.zero_velocity", kDefaults.use_zero_velocity,
                                       "zero-velocity updates on frames whose tracks stood still"};
const ConfigKey<double> kZeroVelocitySigma{"estimator.zero_velocity.sigma", kDefaults.zero_velocity_sigma_mps,
                                           {1e-6, 10}, "sigma of a zero-velocity update [m/s]"};
const ConfigKey<double> kZeroVelocityMaxMotion{"estimator.zero_velocity.max_motion_px",
                                               kDefaults.zero_velocity_max_motion_px, {0, 100},
                                               "tracks moving at most this (median) count as still [px]"};
const ConfigKey<double> kZeroVelocityLookback{"estimator.zero_velocity.lookback", kDefaults.zero_velocity_lookback_s,
                                              {0.01, 10}, "track motion is measured against the frame this much "
                                                          "earlier [s]"};
const ConfigKey<double> kZeroVelocityMaxSpeed{"estimator.zero_velocity.max_speed", kDefaults.zero_velocity_max_speed_mps,
                                              {0, 10}, "no zero-velocity update above this predicted speed [m/s]"};
const ConfigKey<bool> kUseDepth{"estimator.depth.enabled", kDefaults.use_depth,
                                "false: ignore every depth measurement (VIO)"};

// GPS.
const ConfigKey<double> kGpsMaxTimeOffset{"estimator.gps.max_time_offset", kDefaults.gps_max_time_offset_s, {0, 1},
                                          "a fix joins the frame within this time of it [s]"};
const ConfigKey<double> kGpsHuber{"estimator.gps.huber_threshold", kDefaults.gps_huber_threshold, {0.1, 100},
                                  "Huber threshold of the GPS factors [sigma]"};
const ConfigKey<double> kGpsCorrelationTime{"estimator.gps.correlation_time", kDefaults.gps_correlation_time_s, {0, 1e4},
                                            "correlation time of the fix errors (multipath) [s]"};
const ConfigKey<std::string> kGpsMode =
    enum_key("estimator.gps.mode", "joint", kGpsModeNames, "GPS in the window (joint) or registered apart (decoupled)");
const ConfigKey<double> kGpsMultipathFraction{"estimator.gps.multipath_fraction", kDefaults.gps_multipath_fraction,
                                              {0, 0.95}, "joint: share of a fix's covariance that is multipath "
                                                         "(a Gauss-Markov bias); 0: independent fixes"};
const ConfigKey<double> kGpsOutlierGate{"estimator.gps.outlier_gate", kDefaults.gps_outlier_gate, {0, 1e6},
                                        "fixes beyond this squared Mahalanobis distance are not used; 0: off"};
const ConfigKey<double> kGpsMaxOutlier{"estimator.gps.max_outlier", kDefaults.gps_max_outlier_s, {0, 1e4},
                                       "fixes that disagree for longer than this are used again [s]"};
const ConfigKey<int> kGpsRegistrationFixes{"estimator.gps.registration_fixes", kDefaults.gps_registration_fixes, 0,
                                           1000000, "decoupled: register over the newest this many fixes (0: all)"};

// Magnetometer.
const ConfigKey<std::vector<double>> kMagReference{"estimator.mag.reference_field", items(kDefaults.mag_reference_field_enu),
                                                   3, {-1e-3, 1e-3}, "reference magnetic field [east, north, up] [T] "
                                                                     "(with a horizontal part)"};
const ConfigKey<std::vector<double>> kMagHardIron{"estimator.mag.hard_iron", items(kDefaults.mag_hard_iron), 3,
                                                  {-1e-3, 1e-3}, "magnetometer hard-iron offset [T]"};
const ConfigKey<std::vector<double>> kMagSoftIron{"estimator.mag.soft_iron",
                                                  std::vector<double>{1, 0, 0, 0, 1, 0, 0, 0, 1}, 9, {-100, 100},
                                                  "magnetometer soft-iron matrix, row by row (near symmetric positive "
                                                  "definite)"};
const ConfigKey<double> kMagSigma{"estimator.mag.sigma", kDefaults.mag_sigma, {1e-10, 1e-4},
                                  "white noise per axis of one magnetometer sample [T]"};
const ConfigKey<double> kMagMaxTimeOffset{"estimator.mag.max_time_offset", kDefaults.mag_max_time_offset_s, {0, 1},
                                          "samples within this time of a state are used for it [s]"};
const ConfigKey<double> kMagMaxNormDeviation{"estimator.mag.max_norm_deviation", kDefaults.mag_max_norm_deviation,
                                             {0, 10}, "a field whose strength is off by more than this fraction is "
                                                      "disturbed; 0: off"};
const ConfigKey<double> kMagMaxInclinationDeviation{"estimator.mag.max_inclination_deviation",
                                                    kDefaults.mag_max_inclination_deviation_deg, {0, 180},
                                                    "a field whose inclination is off by more than this is disturbed "
                                                    "[deg]; 0: off"};
const ConfigKey<double> kMagMaxHeadingDeviation{"estimator.mag.max_heading_deviation",
                                                kDefaults.mag_max_heading_deviation_deg, {0, 180},
                                                "a field whose heading disagrees with the state's by more is disturbed "
                                                "[deg]"};
const ConfigKey<double> kMagMaxDisturbance{"estimator.mag.max_disturbance", kDefaults.mag_max_disturbance_s, {0, 3600},
                                           "a field disagreeing for longer than this is trusted again [s]"};

// Features and depth.
const ConfigKey<double> kFarThreshold{"estimator.features.far_threshold", kDefaults.far_threshold_m, {0.1, 1000},
                                      "features farther than this are far features [m]"};
const ConfigKey<double> kFarDepthSigmaScale{"estimator.features.far_depth_sigma_scale", kDefaults.far_depth_sigma_scale,
                                            {0, 1e6}, "a free far feature's weak inverse-depth prior: the depth sigma "
                                                      "times this (0: none)"};
const ConfigKey<std::string> kFarPolicy =
    enum_key("estimator.features.far_policy", "free", kFarPolicyNames, "far features' depth: estimated (free) or fixed");
const ConfigKey<double> kPixelSigma{"estimator.features.pixel_sigma", kDefaults.pixel_sigma_px, {1e-3, 100},
                                    "feature measurement sigma [px]"};
const ConfigKey<int> kMinVisual{"estimator.features.min_visual", kDefaults.min_visual_features, 0, 10000,
                                "below this many features with visual factors the frame is IMU-only"};
const ConfigKey<std::string> kAnchorBearing =
    enum_key("estimator.features.anchor_bearing", to_string(kDefaults.anchor_bearing), kAnchorBearingNames,
             "a landmark's bearing in its anchor frame: fixed or estimated");
const ConfigKey<std::string> kLeavingAnchor =
    enum_key("estimator.features.leaving_anchor", to_string(kDefaults.leaving_anchor), kLeavingAnchorNames,
             "a track whose anchor keyframe is marginalized: reuse, restart, reanchor or hand_over");
const ConfigKey<double> kDisparitySigma{"estimator.depth.disparity_sigma", kDefaults.disparity_sigma_px, {0, 100},
                                        "depth noise as a disparity sigma [px]; 0: the calibration's"};
const ConfigKey<double> kDepthBaseline{"estimator.depth.baseline", kDefaults.depth_baseline_m, {0, 10},
                                       "stereo baseline of the depth noise [m]; 0: the calibration's"};
const ConfigKey<std::string> kPointCovariance =
    enum_key("estimator.depth.point_covariance", "full", kDepth3dCovarianceNames,
             "covariance of the depth-augmented 3D factor's point: full or the paper's");

// Keyframes, loss, solver.
const ConfigKey<double> kKeyframeParallax{"estimator.keyframe.parallax", kDefaults.keyframe_parallax_px, {0, 1000},
                                          "mean parallax to the last keyframe that makes a keyframe [px]"};
const ConfigKey<int> kKeyframeMinTracked{"estimator.keyframe.min_tracked", kDefaults.keyframe_min_tracked, 0, 10000,
                                         "fewer common tracks than this make a keyframe"};
const ConfigKey<double> kKeyframeMaxInterval{"estimator.keyframe.max_interval", kDefaults.keyframe_max_interval_s,
                                             {0.01, 100}, "a keyframe at least this often [s]"};
const ConfigKey<std::string> kLoss =
    enum_key("estimator.loss.type", "cauchy", kLossNames, "robust loss of the visual factors");
const ConfigKey<double> kLossScale{"estimator.loss.scale", kDefaults.loss_scale, {1e-3, 1e3},
                                   "scale of the robust loss [sigma]"};
const ConfigKey<std::string> kLinearSolver =
    enum_key("estimator.solver.linear_solver", "dense_schur", kLinearSolverNames, "Ceres linear solver");
const ConfigKey<int> kMaxIterations{"estimator.solver.max_iterations", kDefaults.max_iterations, 1, 1000,
                                    "solver iterations per frame at most"};
const ConfigKey<double> kMaxSolverTime{"estimator.solver.max_time", kDefaults.max_solver_time_s, {0, 60},
                                       "solver time limit per frame [s]; 0: none (machine-independent results)"};
const ConfigKey<std::string> kNonKeyframes =
    enum_key("estimator.solver.non_keyframes", to_string(kDefaults.non_keyframe_solve), kNonKeyframeSolveNames,
             "a non-keyframe is solved with the window or alone against it (newest)");
const ConfigKey<std::string> kSchurOrdering =
    enum_key("estimator.solver.schur_ordering", to_string(kDefaults.schur_ordering), kSchurOrderingNames,
             "elimination ordering of the Schur solvers");
const ConfigKey<bool> kMarginalization{"estimator.marginalization", kDefaults.marginalization,
                                       "keep a marginalization prior of the states leaving the window"};
const ConfigKey<bool> kFirstEstimates{"estimator.first_estimates", kDefaults.first_estimates,
                                       "linearize the factors on blocks the prior holds at the prior's first estimates (FEJ)"};
const ConfigKey<bool> kResidualDiagnostics{"estimator.diagnostics.residuals", kDefaults.residual_diagnostics,
                                           "accumulate whitened residual statistics per factor type"};
const ConfigKey<std::string> kCovariance =
    enum_key("estimator.covariance", "schur", kCovarianceMethodNames, "how the newest state's covariance is computed");
const ConfigKey<std::string> kCovarianceWeights =
    enum_key("estimator.covariance_weights", "inliers", kCovarianceWeightsNames,
             "visual factor weights of the covariance: robust or inliers");
const ConfigKey<std::string> kPriorWeights =
    enum_key("estimator.prior_weights", "inliers", kCovarianceWeightsNames,
             "visual factor weights of the marginalization prior: robust or inliers");

// Initialization.
const ConfigKey<std::string> kInitMethod =
    enum_key("estimator.initialization.method", "still", kInitializationNames,
             "initialization: still start, hybrid PnP (hpnp) or 3D-2D PnP");
const ConfigKey<double> kStillDuration{"estimator.initialization.still_duration", kDefaults.still_duration_s,
                                       {0.05, 60}, "still: IMU data averaged for gravity [s]"};
const ConfigKey<double> kInitSigmaRollPitch{"estimator.initialization.sigma_roll_pitch",
                                            kDefaults.init_sigma_roll_pitch_rad, {1e-6, 1},
                                            "initial roll and pitch sigma [rad]"};
const ConfigKey<double> kInitSigmaVelocity{"estimator.initialization.sigma_velocity", kDefaults.init_sigma_velocity,
                                           {1e-6, 10}, "initial velocity sigma [m/s]"};
const ConfigKey<double> kInitSigmaGyroBias{"estimator.initialization.sigma_gyro_bias", kDefaults.init_sigma_gyro_bias,
                                           {1e-8, 1}, "initial gyro bias sigma [rad/s]"};
const ConfigKey<double> kInitSigmaAccelBias{"estimator.initialization.sigma_accel_bias", kDefaults.init_sigma_accel_bias,
                                            {1e-8, 10}, "initial accelerometer bias sigma [m/s^2]"};
const ConfigKey<bool> kStillGyroBias{"estimator.initialization.still_gyro_bias", kDefaults.still_gyro_bias,
                                     "still: the mean gyro over a camera-confirmed still window is the gyro bias"};
const ConfigKey<double> kStillMaxMotion{"estimator.initialization.still_max_motion_px", kDefaults.still_max_motion_px,
                                        {0, 100}, "still: tracks moving at most this (median) confirm the still window "
                                                  "[px]"};
const ConfigKey<double> kLostAfter{"estimator.lost_after", kDefaults.lost_after_s, {0, kInf},
                                   "IMU-only for longer than this: mode lost [s]"};

// Failure detection and restart.
const ConfigKey<bool> kFailureDetection{"estimator.failure.detection", kDefaults.failure_detection,
                                        "failure detection after every solve, with a restart"};
const ConfigKey<double> kMaxAccelBias{"estimator.failure.max_accel_bias", kFailure.max_accel_bias, {1e-3, kInf},
                                      "failure: accelerometer bias above this [m/s^2]"};
const ConfigKey<double> kMaxGyroBias{"estimator.failure.max_gyro_bias", kFailure.max_gyro_bias, {1e-4, kInf},
                                     "failure: gyro bias above this [rad/s]"};
const ConfigKey<double> kMaxPositionJump{"estimator.failure.max_position_jump", kFailure.max_position_jump_m,
                                         {1e-3, kInf}, "failure: position jump between estimates beyond the motion [m]"};
const ConfigKey<double> kMaxRotationJump{"estimator.failure.max_rotation_jump", kFailure.max_rotation_jump_rad,
                                         {1e-3, M_PI}, "failure: rotation between consecutive estimates [rad]"};
const ConfigKey<double> kMaxSpeed{"estimator.failure.max_speed", kFailure.max_speed_mps, {1e-2, kInf},
                                  "failure: speed above this [m/s]"};
const ConfigKey<double> kMinInlierFraction{"estimator.failure.min_inlier_fraction", kFailure.min_inlier_fraction, {0, 1},
                                           "failure: share of visual residuals inside the gate below this"};
const ConfigKey<double> kCollapseFrom{"estimator.failure.collapse_from", kFailure.collapse_from, {0, 1},
                                      "the inlier test applies after the last second's median share was at least "
                                      "this"};
const ConfigKey<int> kMinVisualResiduals{"estimator.failure.min_visual_residuals", kFailure.min_visual_residuals, 1,
                                         100000, "the inlier test needs at least this many visual residual blocks"};
const ConfigKey<double> kConfirmedInlierFraction{"estimator.failure.confirmed_inlier_fraction",
                                                 kDefaults.confirmed_inlier_fraction, {0, 1},
                                                 "a restart starts from an estimate vision confirmed with this inlier "
                                                 "share"};
const ConfigKey<double> kRestartMaxGap{"estimator.failure.restart_max_gap", kDefaults.restart_max_gap_s, {0, 60},
                                       "... found within this time before the failed frame [s]"};
const ConfigKey<double> kRestartAccelDensity{"estimator.failure.restart_accel_density", kDefaults.restart_accel_density,
                                             {0, 100}, "the walker's acceleration over the restart gap as white noise "
                                                       "[m/s^2/sqrt(s)]"};
const ConfigKey<double> kRestartSigmaVelocity{"estimator.failure.restart_sigma_velocity",
                                              kDefaults.restart_sigma_velocity, {0, 100},
                                              "uncertainty added to the restart estimate's velocity [m/s]"};

// Online calibration.
const ConfigKey<bool> kEstimateExtrinsic{"estimator.extrinsic.estimate", kDefaults.estimate_extrinsic,
                                         "estimate the camera-IMU extrinsic online"};
const ConfigKey<double> kExtrinsicSigmaRotation{"estimator.extrinsic.sigma_rotation",
                                                kDefaults.extrinsic_sigma_rotation_rad, {1e-6, 1},
                                                "prior sigma of the extrinsic rotation [rad]"};
const ConfigKey<double> kExtrinsicSigmaTranslation{"estimator.extrinsic.sigma_translation",
                                                   kDefaults.extrinsic_sigma_translation_m, {1e-6, 1},
                                                   "prior sigma of the extrinsic translation [m]"};
const ConfigKey<bool> kEstimateTimeOffset{"estimator.time_offset.estimate", kDefaults.estimate_time_offset,
                                          "estimate the camera-IMU time offset online"};
const ConfigKey<double> kTimeOffsetSigma{"estimator.time_offset.sigma", kDefaults.time_offset_sigma_s, {1e-6, 0.1},
                                         "prior sigma of the time offset [s]"};

void read_mag(const Config& c, EstimatorConfig& e) {
  const char* ref_key = "estimator.mag.reference_field";
  e.mag_reference_field_enu = get_vec3(c, kMagReference);
  // The factor needs a heading: a field without a horizontal part (or given in microtesla by
  // mistake, caught by the range above) cannot define one.
  const Vec3& m = e.mag_reference_field_enu;
  if (!(m.head<2>().norm() >= 1e-3 * m.norm()) || !(m.head<2>().norm() > 1e-9))
    throw ConfigError(c.origin(ref_key), ref_key,
                      "needs a horizontal component: [east, north, up] in tesla, e.g. [0, 20e-6, -45e-6]");
  e.mag_hard_iron = get_vec3(c, kMagHardIron);
  const char* soft_key = "estimator.mag.soft_iron";
  if (c.has(soft_key)) {
    const auto v = get(c, kMagSoftIron);
    for (int i = 0; i < 9; ++i) e.mag_soft_iron(i / 3, i % 3) = v[static_cast<std::size_t>(i)];
    const Mat3& A = e.mag_soft_iron;
    const Eigen::SelfAdjointEigenSolver<Mat3> eig(0.5 * (A + A.transpose()));
    const double lo = eig.eigenvalues().minCoeff(), hi = eig.eigenvalues().maxCoeff();
    if ((A - A.transpose()).norm() > 1e-3 * A.norm() || !(lo > 1e-3 * hi))
      throw ConfigError(c.origin(soft_key), soft_key,
                        "must be near symmetric positive definite (9 numbers row by row; eigenvalue ratio > 1e-3)");
  }
  e.mag_sigma = get(c, kMagSigma);
  e.mag_max_time_offset_s = get(c, kMagMaxTimeOffset);
  e.mag_max_norm_deviation = get(c, kMagMaxNormDeviation);
  e.mag_max_inclination_deviation_deg = get(c, kMagMaxInclinationDeviation);
  e.mag_max_heading_deviation_deg = get(c, kMagMaxHeadingDeviation);
  e.mag_max_disturbance_s = get(c, kMagMaxDisturbance);
}

}  // namespace

ConfigSchema estimator_config_schema() {
  ConfigSchema s;
  s.add(kWindowSize);
  s.add(kUseImu);
  s.add(kImuNoiseScale);
  s.add(kImuRandomWalkScale);
  s.add(kImuMaxSampleGap);
  s.add(kImuGapGyroDensity);
  s.add(kImuGapAccelDensity);
  s.add(kUseReprojection);
  s.add(kUseInverseDepth);
  s.add(kUseDepth3d);
  s.add(kUseGps);
  s.add(kUseMag);
  s.add(kUseZeroVelocity);
  s.add(kZeroVelocitySigma);
  s.add(kZeroVelocityMaxMotion);
  s.add(kZeroVelocityLookback);
  s.add(kZeroVelocityMaxSpeed);
  s.add(kUseDepth);
  s.add(kGpsMaxTimeOffset);
  s.add(kGpsHuber);
  s.add(kGpsCorrelationTime);
  s.add(kGpsMode);
  s.add(kGpsMultipathFraction);
  s.add(kGpsOutlierGate);
  s.add(kGpsMaxOutlier);
  s.add(kGpsRegistrationFixes);
  s.add(kMagReference);
  s.add(kMagHardIron);
  s.add(kMagSoftIron);
  s.add(kMagSigma);
  s.add(kMagMaxTimeOffset);
  s.add(kMagMaxNormDeviation);
  s.add(kMagMaxInclinationDeviation);
  s.add(kMagMaxHeadingDeviation);
  s.add(kMagMaxDisturbance);
  s.add(kFarThreshold);
  s.add(kFarDepthSigmaScale);
  s.add(kFarPolicy);
  s.add(kPixelSigma);
  s.add(kMinVisual);
  s.add(kAnchorBearing);
  s.add(kLeavingAnchor);
  s.add(kDisparitySigma);
  s.add(kDepthBaseline);
  s.add(kPointCovariance);
  s.add(kKeyframeParallax);
  s.add(kKeyframeMinTracked);
  s.add(kKeyframeMaxInterval);
  s.add(kLoss);
  s.add(kLossScale);
  s.add(kLinearSolver);
  s.add(kMaxIterations);
  s.add(kMaxSolverTime);
  s.add(kNonKeyframes);
  s.add(kSchurOrdering);
  s.add(kMarginalization);
  s.add(kFirstEstimates);
  s.add(kResidualDiagnostics);
  s.add(kCovariance);
  s.add(kCovarianceWeights);
  s.add(kPriorWeights);
  s.add(kInitMethod);
  s.add(kStillDuration);
  s.add(kInitSigmaRollPitch);
  s.add(kInitSigmaVelocity);
  s.add(kInitSigmaGyroBias);
  s.add(kInitSigmaAccelBias);
  s.add(kStillGyroBias);
  s.add(kStillMaxMotion);
  s.add(kLostAfter);
  s.add(kFailureDetection);
  s.add(kMaxAccelBias);
  s.add(kMaxGyroBias);
  s.add(kMaxPositionJump);
  s.add(kMaxRotationJump);
  s.add(kMaxSpeed);
  s.add(kMinInlierFraction);
  s.add(kCollapseFrom);
  s.add(kMinVisualResiduals);
  s.add(kConfirmedInlierFraction);
  s.add(kRestartMaxGap);
  s.add(kRestartAccelDensity);
  s.add(kRestartSigmaVelocity);
  s.add(kEstimateExtrinsic);
  s.add(kExtrinsicSigmaRotation);
  s.add(kExtrinsicSigmaTranslation);
  s.add(kEstimateTimeOffset);
  s.add(kTimeOffsetSigma);
  return s;
}

ConfigSchema config_schema() { return estimator_config_schema().add(frontend_config_schema()); }

EstimatorConfig read_estimator_config(const Config& c) {
  EstimatorConfig e;
  e.window_size = get(c, kWindowSize);

  e.use_imu = get(c, kUseImu);
  e.imu_noise_scale = get(c, kImuNoiseScale);
  e.imu_random_walk_scale = get(c, kImuRandomWalkScale);
  e.imu_max_sample_gap_s = get(c, kImuMaxSampleGap);
  e.imu_gap_gyro_density = get(c, kImuGapGyroDensity);
  e.imu_gap_accel_density = get(c, kImuGapAccelDensity);
  e.use_reprojection = get(c, kUseReprojection);
  e.use_inverse_depth = get(c, kUseInverseDepth);
  e.use_depth_3d = get(c, kUseDepth3d);
  e.use_gps = get(c, kUseGps);
  e.use_mag = get(c, kUseMag);
  e.use_zero_velocity = get(c, kUseZeroVelocity);
  e.zero_velocity_sigma_mps = get(c, kZeroVelocitySigma);
  e.zero_velocity_max_motion_px = get(c, kZeroVelocityMaxMotion);
  e.zero_velocity_lookback_s = get(c, kZeroVelocityLookback);
  e.zero_velocity_max_speed_mps = get(c, kZeroVelocityMaxSpeed);
  e.use_depth = get(c, kUseDepth);
  e.gps_max_time_offset_s = get(c, kGpsMaxTimeOffset);
  e.gps_huber_threshold = get(c, kGpsHuber);
  e.gps_correlation_time_s = get(c, kGpsCorrelationTime);
  e.gps_mode = get_enum(c, kGpsMode, kGpsModeNames);
  e.gps_multipath_fraction = get(c, kGpsMultipathFraction);
  e.gps_outlier_gate = get(c, kGpsOutlierGate);
  e.gps_max_outlier_s = get(c, kGpsMaxOutlier);
  e.gps_registration_fixes = get(c, kGpsRegistrationFixes);
  read_mag(c, e);

  e.far_threshold_m = get(c, kFarThreshold);
  e.far_depth_sigma_scale = get(c, kFarDepthSigmaScale);
  e.far_policy = get_enum(c, kFarPolicy, kFarPolicyNames);
  e.pixel_sigma_px = get(c, kPixelSigma);
  e.min_visual_features = get(c, kMinVisual);
  e.anchor_bearing = get_enum(c, kAnchorBearing, kAnchorBearingNames);
  e.leaving_anchor = get_enum(c, kLeavingAnchor, kLeavingAnchorNames);
  e.disparity_sigma_px = get(c, kDisparitySigma);
  e.depth_baseline_m = get(c, kDepthBaseline);
  e.depth_3d_covariance = get_enum(c, kPointCovariance, kDepth3dCovarianceNames);

  e.keyframe_parallax_px = get(c, kKeyframeParallax);
  e.keyframe_min_tracked = get(c, kKeyframeMinTracked);
  e.keyframe_max_interval_s = get(c, kKeyframeMaxInterval);

  e.loss = get_enum(c, kLoss, kLossNames);
  e.loss_scale = get(c, kLossScale);

  e.linear_solver = get_enum(c, kLinearSolver, kLinearSolverNames);
  e.max_iterations = get(c, kMaxIterations);
  e.max_solver_time_s = get(c, kMaxSolverTime);
  e.non_keyframe_solve = get_enum(c, kNonKeyframes, kNonKeyframeSolveNames);
  e.schur_ordering = get_enum(c, kSchurOrdering, kSchurOrderingNames);

  e.marginalization = get(c, kMarginalization);
  e.first_estimates = get(c, kFirstEstimates);
  e.residual_diagnostics = get(c, kResidualDiagnostics);
  e.covariance_method = get_enum(c, kCovariance, kCovarianceMethodNames);
  e.covariance_weights = get_enum(c, kCovarianceWeights, kCovarianceWeightsNames);
  e.prior_weights = get_enum(c, kPriorWeights, kCovarianceWeightsNames);

  e.init_method = get_enum(c, kInitMethod, kInitializationNames);
  e.still_duration_s = get(c, kStillDuration);
  e.init_sigma_roll_pitch_rad = get(c, kInitSigmaRollPitch);
  e.init_sigma_velocity = get(c, kInitSigmaVelocity);
  e.init_sigma_gyro_bias = get(c, kInitSigmaGyroBias);
  e.init_sigma_accel_bias = get(c, kInitSigmaAccelBias);
  e.still_gyro_bias = get(c, kStillGyroBias);
  e.still_max_motion_px = get(c, kStillMaxMotion);
  e.lost_after_s = get(c, kLostAfter);
  e.failure_detection = get(c, kFailureDetection);
  FailureThresholds& f = e.failure;
  f.max_accel_bias = get(c, kMaxAccelBias);
  f.max_gyro_bias = get(c, kMaxGyroBias);
  f.max_position_jump_m = get(c, kMaxPositionJump);
  f.max_rotation_jump_rad = get(c, kMaxRotationJump);
  f.max_speed_mps = get(c, kMaxSpeed);
  f.min_inlier_fraction = get(c, kMinInlierFraction);
  f.collapse_from = get(c, kCollapseFrom);
  f.min_visual_residuals = get(c, kMinVisualResiduals);
  e.confirmed_inlier_fraction = get(c, kConfirmedInlierFraction);
  e.restart_max_gap_s = get(c, kRestartMaxGap);
  e.restart_accel_density = get(c, kRestartAccelDensity);
  e.restart_sigma_velocity = get(c, kRestartSigmaVelocity);

  e.estimate_extrinsic = get(c, kEstimateExtrinsic);
  e.extrinsic_sigma_rotation_rad = get(c, kExtrinsicSigmaRotation);
  e.extrinsic_sigma_translation_m = get(c, kExtrinsicSigmaTranslation);
  e.estimate_time_offset = get(c, kEstimateTimeOffset);
  e.time_offset_sigma_s = get(c, kTimeOffsetSigma);
  return e;
}

Vec3 calibrated_mag_field(const EstimatorConfig& config, const Vec3& raw) {
  return config.mag_soft_iron.partialPivLu().solve(raw - config.mag_hard_iron);
}

// Each to_string keeps what it gave an out-of-range value before the tables: "?" where it was a
// switch with a "?" default, its default name where it was a switch with one, and the second name
// where it was a two-way ternary.
std::string to_string(LossKind kind) { return std::string(enum_name(kLossNames, kind, "?")); }
std::string to_string(LinearSolverKind kind) { return std::string(enum_name(kLinearSolverNames, kind, "?")); }
std::string to_string(InitializationMethod method) {
  return std::string(enum_name(kInitializationNames, method, "?"));
}
std::string to_string(GpsMode mode) { return std::string(enum_name(kGpsModeNames, mode, "decoupled")); }
std::string to_string(FarFeaturePolicy policy) { return std::string(enum_name(kFarPolicyNames, policy, "fixed")); }
std::string to_string(LeavingAnchorPolicy policy) {
  return std::string(enum_name(kLeavingAnchorNames, policy, "reuse"));
}
std::string to_string(AnchorBearing bearing) {
  return std::string(enum_name(kAnchorBearingNames, bearing, "estimated"));
}
std::string to_string(NonKeyframeSolve solve) {
  return std::string(enum_name(kNonKeyframeSolveNames, solve, "newest"));
}
std::string to_string(SchurOrdering ordering) { return std::string(enum_name(kSchurOrderingNames, ordering, "auto")); }
std::string to_string(Depth3dCovariance model) {
  return std::string(enum_name(kDepth3dCovarianceNames, model, "paper"));
}

}  // namespace navaid::estimation
