#pragma once
// Visual-inertial alignment (W-ROMA RGBD-VIO §V-A, after VINS-Mono's): the keyframe camera poses
// of a window SfM (in the reference camera frame l, metric when the SfM had depth) and the IMU
// preintegrated between consecutive keyframes give, in turn,
//
//  1. the gyro bias: least squares on the rotation residuals
//       J_k db_g = Log(gamma_k(b_g)^-1 R_l_Bk^T R_l_Bk+1),  J_k = d theta_k / d b_g,
//     Gauss-Newton on the preintegration's first-order bias correction, then the
//     preintegrations are integrated again at the estimate;
//  2. the velocity v_k of every keyframe and gravity g_l, both in frame l (and the scale s of the
//     SfM's translations when asked), linear least squares on, per pair k, k+1 (dt, R_k = R_l_Bk):
//       R_k^T (s c_k+1 - s c_k - v_k dt - g_l dt^2/2) = alpha_k + R_k^T (R_k+1 - R_k) t_B_C,
//       R_k^T (v_k+1 - v_k - g_l dt)                  = beta_k,
//     where c_k is camera k's position in l and t_B_C the camera's position in B (the body
//     position is s c_k - R_k t_B_C: the extrinsic is metric, the SfM maybe not). Unit weights,
//     as VINS-Mono: the visual poses, not the IMU noise, dominate the errors;
//  3. gravity refined on its sphere |g_l| = |core::kGravityW|: g_l = |g| g_hat + B w with B a
//     tangent basis of g_hat, the same system solved for (v, w, s), g_hat renormalized, repeated;
//  4. the rotation R_W_l that maps g_l onto kGravityW, with the yaw chosen so that the oldest
//     keyframe's body has yaw 0 and W's origin at that body (the still-start convention of the
//     sliding-window estimator).
//
// The accelerometer bias is not estimated (it is not separable from gravity over a short
// window); the preintegrations' linearization accel bias is kept (zero in practice).
#include <optional>
#include <string>
#include <vector>

#include "navaid/core/geometry.hpp"
#include "navaid/core/time.hpp"
#include "navaid/estimation/imu_preintegration.hpp"

namespace navaid::estimation {

struct VisualInertialAlignmentOptions {
  std::size_t min_keyframes = 4;      ///< >= 3; fewer fails (the linear system needs 3N+3 <= 6(N-1) and motion)
  double gravity_norm_tolerance = 0.1;  ///< relative |g_l| error allowed before refinement
  double max_gyro_bias = 0.1;         ///< [rad/s] a larger estimate is implausible: failure
  bool estimate_scale = false;        ///< true for an up-to-scale SfM (VIO without depth)
  double min_scale = 1e-3;            ///< an estimated scale below this fails
  int gyro_bias_iterations = 3;       ///< Gauss-Newton steps of step 1
  int gravity_refinement_iterations = 4;
};

/// Throws ConfigError naming the first bad option.
void validate(const VisualInertialAlignmentOptions& options, const std::string& source = "visual_inertial_alignment");

struct VisualInertialAlignment {
  bool success = false;
  std::string failure;  ///< why not, when !success

  Vec3 gyro_bias = Vec3::Zero();    ///< b_g [rad/s]
  Vec3 accel_bias = Vec3::Zero();   ///< the preintegrations' linearization accel bias, kept
  double gyro_rms_rad = 0;          ///< rms rotation residual after the gyro-bias fit
  double scale = 1;                 ///< metric / SfM units (1 unless estimated)
  Vec3 gravity_l_unrefined = Vec3::Zero();  ///< g in l from step 2
  Vec3 gravity_l = Vec3::Zero();            ///< refined, |g| = |kGravityW|
  std::vector<Vec3> velocities_l;           ///< v_k in frame l [m/s]

  /// Reference camera frame into the gravity-aligned W, for metric coordinates: an SfM point P_l
  /// is at T_W_l * (scale * P_l).
  SE3 T_W_l;
  std::vector<SE3> T_W_B;       ///< body pose of every keyframe in W (metric)
  std::vector<Vec3> v_W;        ///< body velocity of every keyframe in W
  /// Preintegrations between consecutive keyframes integrated again at gyro_bias.
  std::vector<ImuPreintegration> preintegrations;
};

/// Aligns keyframes k = 0..N-1 (time order) with camera poses T_l_C[k] (camera k into frame l;
/// l need not be one of them) to the IMU. `preintegrations[k]` runs from keyframe k to k+1 (N-1
/// of them) in the IMU clock; `times[k]` are the keyframes' IMU-clock times. Degenerate windows
/// (too few keyframes, gravity norm off, implausible bias or scale, singular system) return
/// success = false with a reason. Throws Error on inconsistent input: sizes that do not match,
/// preintegrations whose ends are not the keyframe times, non-finite poses; ConfigError on bad
/// options.
VisualInertialAlignment align_visual_inertial(const std::vector<Timestamp>& times, const std::vector<SE3>& T_l_C,
                                              const SE3& T_B_C,
                                              const std::vector<ImuPreintegration>& preintegrations,
                                              const VisualInertialAlignmentOptions& options = {});

}  // namespace navaid::estimation
