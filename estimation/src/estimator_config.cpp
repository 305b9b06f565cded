#include "navaid/estimation/estimator_config.hpp"

#include <limits>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include "navaid/core/enum_names.hpp"
#include "navaid/core/errors.hpp"

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
constexpr NameTable<LeavingAnchorPolicy, 3> kLeavingAnchorNames{{
    {LeavingAnchorPolicy::kReuse, "reuse"},
    {LeavingAnchorPolicy::kRestart, "restart"},
    {LeavingAnchorPolicy::kReanchor, "reanchor"},
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

/// An enum key: Config checks the name against the table's names (its error lists them), the
/// table gives the value.
template <class Enum, std::size_t N>
Enum get_enum(const Config& c, const char* key, const std::string& fallback, const NameTable<Enum, N>& table) {
  const std::string name = c.get_string(key, fallback, enum_names(table));
  if (const std::optional<Enum> value = enum_value(table, name)) return *value;
  throw Error("unreachable: Config::get_string validated '" + name + "'");
}

Vec3 get_vec3(const Config& c, const char* key, const Vec3& fallback, Range allowed) {
  if (!c.has(key)) return fallback;
  const auto v = c.get_doubles(key, 3, allowed);
  return Vec3(v[0], v[1], v[2]);
}

void read_mag(const Config& c, EstimatorConfig& e) {
  const char* ref_key = "estimator.mag.reference_field";
  e.mag_reference_field_enu = get_vec3(c, ref_key, e.mag_reference_field_enu, {-1e-3, 1e-3});
  // The factor needs a heading: a field without a horizontal part (or given in microtesla by
  // mistake, caught by the range above) cannot define one.
  const Vec3& m = e.mag_reference_field_enu;
  if (!(m.head<2>().norm() >= 1e-3 * m.norm()) || !(m.head<2>().norm() > 1e-9))
    throw ConfigError(c.origin(ref_key), ref_key,
                      "needs a horizontal component: [east, north, up] in tesla, e.g. [0, 20e-6, -45e-6]");
  e.mag_hard_iron = get_vec3(c, "estimator.mag.hard_iron", e.mag_hard_iron, {-1e-3, 1e-3});
  const char* soft_key = "estimator.mag.soft_iron";
  if (c.has(soft_key)) {
    const auto v = c.get_doubles(soft_key, 9, {-100, 100});
    for (int i = 0; i < 9; ++i) e.mag_soft_iron(i / 3, i % 3) = v[static_cast<std::size_t>(i)];
    const Mat3& A = e.mag_soft_iron;
    const Eigen::SelfAdjointEigenSolver<Mat3> eig(0.5 * (A + A.transpose()));
    const double lo = eig.eigenvalues().minCoeff(), hi = eig.eigenvalues().maxCoeff();
    if ((A - A.transpose()).norm() > 1e-3 * A.norm() || !(lo > 1e-3 * hi))
      throw ConfigError(c.origin(soft_key), soft_key,
                        "must be near symmetric positive definite (9 numbers row by row; eigenvalue ratio > 1e-3)");
  }
  e.mag_sigma = c.get_double("estimator.mag.sigma", e.mag_sigma, {1e-10, 1e-4});
  e.mag_max_time_offset_s = c.get_double("estimator.mag.max_time_offset", e.mag_max_time_offset_s, {0, 1});
  e.mag_max_norm_deviation = c.get_double("estimator.mag.max_norm_deviation", e.mag_max_norm_deviation, {0, 10});
  e.mag_max_inclination_deviation_deg =
      c.get_double("estimator.mag.max_inclination_deviation", e.mag_max_inclination_deviation_deg, {0, 180});
  e.mag_max_heading_deviation_deg =
      c.get_double("estimator.mag.max_heading_deviation", e.mag_max_heading_deviation_deg, {0, 180});
  e.mag_max_disturbance_s = c.get_double("estimator.mag.max_disturbance", e.mag_max_disturbance_s, {0, 3600});
}

}  // namespace

EstimatorConfig read_estimator_config(const Config& c) {
  EstimatorConfig e;
  e.window_size = static_cast<int>(c.get_int("estimator.window_size", e.window_size, 2, 100));

  e.use_imu = c.get_bool("estimator.factors.imu", e.use_imu);
  e.imu_noise_scale = c.get_double("estimator.imu.noise_scale", e.imu_noise_scale, {1e-3, 1e3});
  e.imu_random_walk_scale = c.get_double("estimator.imu.random_walk_scale", e.imu_random_walk_scale, {1e-3, 1e3});
  e.imu_max_sample_gap_s = c.get_double("estimator.imu.max_sample_gap", e.imu_max_sample_gap_s, {0, 10});
  e.imu_gap_gyro_density = c.get_double("estimator.imu.gap_gyro_density", e.imu_gap_gyro_density, {1e-4, 100});
  e.imu_gap_accel_density = c.get_double("estimator.imu.gap_accel_density", e.imu_gap_accel_density, {1e-3, 1000});
  e.use_reprojection = c.get_bool("estimator.factors.reprojection", e.use_reprojection);
  e.use_inverse_depth = c.get_bool("estimator.factors.inverse_depth", e.use_inverse_depth);
  e.use_depth_3d = c.get_bool("estimator.factors.depth_3d", e.use_depth_3d);
  e.use_gps = c.get_bool("estimator.factors.gps", e.use_gps);
  e.use_mag = c.get_bool("estimator.factors.mag", e.use_mag);
  e.use_zero_velocity = c.get_bool("estimator.factors.zero_velocity", e.use_zero_velocity);
  e.zero_velocity_sigma_mps = c.get_double("estimator.zero_velocity.sigma", e.zero_velocity_sigma_mps, {1e-6, 10});
  e.zero_velocity_max_motion_px =
      c.get_double("estimator.zero_velocity.max_motion_px", e.zero_velocity_max_motion_px, {0, 100});
  e.zero_velocity_lookback_s = c.get_double("estimator.zero_velocity.lookback", e.zero_velocity_lookback_s, {0.01, 10});
  e.zero_velocity_max_speed_mps =
      c.get_double("estimator.zero_velocity.max_speed", e.zero_velocity_max_speed_mps, {0, 10});
  e.use_depth = c.get_bool("estimator.depth.enabled", e.use_depth);
  e.gps_max_time_offset_s = c.get_double("estimator.gps.max_time_offset", e.gps_max_time_offset_s, {0, 1});
  e.gps_huber_threshold = c.get_double("estimator.gps.huber_threshold", e.gps_huber_threshold, {0.1, 100});
  e.gps_correlation_time_s = c.get_double("estimator.gps.correlation_time", e.gps_correlation_time_s, {0, 1e4});
  e.gps_mode = get_enum(c, "estimator.gps.mode", "joint", kGpsModeNames);
  e.gps_multipath_fraction = c.get_double("estimator.gps.multipath_fraction", e.gps_multipath_fraction, {0, 0.95});
  e.gps_outlier_gate = c.get_double("estimator.gps.outlier_gate", e.gps_outlier_gate, {0, 1e6});
  e.gps_max_outlier_s = c.get_double("estimator.gps.max_outlier", e.gps_max_outlier_s, {0, 1e4});
  e.gps_registration_fixes =
      static_cast<int>(c.get_int("estimator.gps.registration_fixes", e.gps_registration_fixes, 0, 1000000));
  read_mag(c, e);

  e.far_threshold_m = c.get_double("estimator.features.far_threshold", e.far_threshold_m, {0.1, 1000});
  e.far_depth_sigma_scale =
      c.get_double("estimator.features.far_depth_sigma_scale", e.far_depth_sigma_scale, {0, 1e6});
  e.far_policy = get_enum(c, "estimator.features.far_policy", "free", kFarPolicyNames);
  e.pixel_sigma_px = c.get_double("estimator.features.pixel_sigma", e.pixel_sigma_px, {1e-3, 100});
  e.min_visual_features =
      static_cast<int>(c.get_int("estimator.features.min_visual", e.min_visual_features, 0, 10000));
  e.anchor_bearing =
      get_enum(c, "estimator.features.anchor_bearing", to_string(e.anchor_bearing), kAnchorBearingNames);
  e.leaving_anchor =
      get_enum(c, "estimator.features.leaving_anchor", to_string(e.leaving_anchor), kLeavingAnchorNames);
  e.disparity_sigma_px = c.get_double("estimator.depth.disparity_sigma", e.disparity_sigma_px, {0, 100});
  e.depth_baseline_m = c.get_double("estimator.depth.baseline", e.depth_baseline_m, {0, 10});
  e.depth_3d_covariance = get_enum(c, "estimator.depth.point_covariance", "full", kDepth3dCovarianceNames);

  e.keyframe_parallax_px = c.get_double("estimator.keyframe.parallax", e.keyframe_parallax_px, {0, 1000});
  e.keyframe_min_tracked =
      static_cast<int>(c.get_int("estimator.keyframe.min_tracked", e.keyframe_min_tracked, 0, 10000));
  e.keyframe_max_interval_s =
      c.get_double("estimator.keyframe.max_interval", e.keyframe_max_interval_s, {0.01, 100});

  e.loss = get_enum(c, "estimator.loss.type", "cauchy", kLossNames);
  e.loss_scale = c.get_double("estimator.loss.scale", e.loss_scale, {1e-3, 1e3});

  e.linear_solver = get_enum(c, "estimator.solver.linear_solver", "dense_schur", kLinearSolverNames);
  e.max_iterations = static_cast<int>(c.get_int("estimator.solver.max_iterations", e.max_iterations, 1, 1000));
  e.max_solver_time_s = c.get_double("estimator.solver.max_time", e.max_solver_time_s, {0, 60});
  e.non_keyframe_solve =
      get_enum(c, "estimator.solver.non_keyframes", to_string(e.non_keyframe_solve), kNonKeyframeSolveNames);
  e.schur_ordering =
      get_enum(c, "estimator.solver.schur_ordering", to_string(e.schur_ordering), kSchurOrderingNames);

  e.marginalization = c.get_bool("estimator.marginalization", e.marginalization);
  e.residual_diagnostics = c.get_bool("estimator.diagnostics.residuals", e.residual_diagnostics);
  e.covariance_method = get_enum(c, "estimator.covariance", "schur", kCovarianceMethodNames);
  e.covariance_weights = get_enum(c, "estimator.covariance_weights", "inliers", kCovarianceWeightsNames);
  e.prior_weights = get_enum(c, "estimator.prior_weights", "inliers", kCovarianceWeightsNames);

  e.init_method = get_enum(c, "estimator.initialization.method", "still", kInitializationNames);
  e.still_duration_s = c.get_double("estimator.initialization.still_duration", e.still_duration_s, {0.05, 60});
  e.init_sigma_roll_pitch_rad =
      c.get_double("estimator.initialization.sigma_roll_pitch", e.init_sigma_roll_pitch_rad, {1e-6, 1});
  e.init_sigma_velocity = c.get_double("estimator.initialization.sigma_velocity", e.init_sigma_velocity, {1e-6, 10});
  e.init_sigma_gyro_bias =
      c.get_double("estimator.initialization.sigma_gyro_bias", e.init_sigma_gyro_bias, {1e-8, 1});
  e.init_sigma_accel_bias =
      c.get_double("estimator.initialization.sigma_accel_bias", e.init_sigma_accel_bias, {1e-8, 10});
  e.still_gyro_bias = c.get_bool("estimator.initialization.still_gyro_bias", e.still_gyro_bias);
  e.still_max_motion_px =
      c.get_double("estimator.initialization.still_max_motion_px", e.still_max_motion_px, {0, 100});
  e.lost_after_s = c.get_double("estimator.lost_after", e.lost_after_s, {0, kInf});
  e.failure_detection = c.get_bool("estimator.failure.detection", e.failure_detection);
  FailureThresholds& f = e.failure;
  f.max_accel_bias = c.get_double("estimator.failure.max_accel_bias", f.max_accel_bias, {1e-3, kInf});
  f.max_gyro_bias = c.get_double("estimator.failure.max_gyro_bias", f.max_gyro_bias, {1e-4, kInf});
  f.max_position_jump_m = c.get_double("estimator.failure.max_position_jump", f.max_position_jump_m, {1e-3, kInf});
  f.max_rotation_jump_rad =
      c.get_double("estimator.failure.max_rotation_jump", f.max_rotation_jump_rad, {1e-3, M_PI});
  f.max_speed_mps = c.get_double("estimator.failure.max_speed", f.max_speed_mps, {1e-2, kInf});
  f.min_inlier_fraction = c.get_double("estimator.failure.min_inlier_fraction", f.min_inlier_fraction, {0, 1});
  f.collapse_from = c.get_double("estimator.failure.collapse_from", f.collapse_from, {0, 1});
  f.min_visual_residuals = static_cast<int>(
      c.get_int("estimator.failure.min_visual_residuals", f.min_visual_residuals, 1, 100000));
  e.confirmed_inlier_fraction =
      c.get_double("estimator.failure.confirmed_inlier_fraction", e.confirmed_inlier_fraction, {0, 1});
  e.restart_max_gap_s = c.get_double("estimator.failure.restart_max_gap", e.restart_max_gap_s, {0, 60});
  e.restart_accel_density =
      c.get_double("estimator.failure.restart_accel_density", e.restart_accel_density, {0, 100});
  e.restart_sigma_velocity =
      c.get_double("estimator.failure.restart_sigma_velocity", e.restart_sigma_velocity, {0, 100});

  e.estimate_extrinsic = c.get_bool("estimator.extrinsic.estimate", e.estimate_extrinsic);
  e.extrinsic_sigma_rotation_rad =
      c.get_double("estimator.extrinsic.sigma_rotation", e.extrinsic_sigma_rotation_rad, {1e-6, 1});
  e.extrinsic_sigma_translation_m =
      c.get_double("estimator.extrinsic.sigma_translation", e.extrinsic_sigma_translation_m, {1e-6, 1});
  e.estimate_time_offset = c.get_bool("estimator.time_offset.estimate", e.estimate_time_offset);
  e.time_offset_sigma_s = c.get_double("estimator.time_offset.sigma", e.time_offset_sigma_s, {1e-6, 0.1});
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
