#pragma once
// eLabrador's decoupled GPS-map registration (../shared/seeds/elabrador-wearable-outdoor-navigation.txt,
// §III-A.4, eq. 6-7): estimate the 4-DOF alignment T_ENU_W = [yaw, t_x, t_y, t_z] from pairs
// (GPS fix, VIO antenna position in W at the fix time), outside the factor graph.
//
//   eq. 6  fix -> metric ENU by the geodesic inverse problem (GeographicLib): from the origin,
//          p = s (sin a, cos a) with s the distance and a the azimuth (clockwise from north);
//          up = ellipsoidal height - origin height.
//   eq. 7  weighted SE(2) least squares  min sum_i w_i |R a_i + t - p_i|^2  in closed form
//          (weighted centroids, yaw = atan2(sum w (a x p), sum w (a . p))), t_z = weighted mean of
//          (up_i - a_z,i); then Gauss-Newton on the full objective
//          sum_i rho(|r_i|_Sigma_i),  r_i = Rz(yaw) a_i + t - p_i,  Sigma_i = GpsFix::covariance_enu
//          (the GpsPositionFactor's residual), which the closed form already minimizes when each
//          fix's horizontal covariance is isotropic and uncorrelated with its height.
//   robust rho: Huber (default) or Cauchy by iteratively reweighted least squares on the
//          Mahalanobis norm of each fix residual (multipath jumps).
//   covariance of [yaw, t_x, t_y(, t_z)] = inverse of the weighted normal equations at the solution
//          (or, for time-correlated fix errors, the sandwich form; see error_correlation_time_s).
//
// "Not yet": the yaw is only observable once the walker has moved. Before fitting, the fixes must
// be at least `min_fixes` and the weighted RMS horizontal distance of the W positions from their
// centroid at least `min_spread_m` (a single point or standing still is rejected; a straight line
// is fine: its direction fixes the yaw). After fitting, the yaw standard deviation must be at most
// `max_yaw_sigma_rad`. Otherwise the result's status says which test failed and registered() is
// false. Details and the paper differences: docs/estimator.md, "GPS registration".
#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "navaid/core/calibration.hpp"
#include "navaid/core/geometry.hpp"
#include "navaid/core/messages.hpp"

namespace navaid::estimation {

/// One GPS fix with the VIO position of the antenna in W at the fix time (p_W_B + R_W_B l_B).
struct GpsRegistrationPair {
  GpsFix fix;
  Vec3 antenna_W = Vec3::Zero();
};

/// How eq. 6 turns fixes into metres.
enum class GeodesicPath {
  kFromOrigin,  ///< one geodesic from the origin to each fix (azimuthal equidistant); default
  kChained,     ///< the paper's chain: p_i = p_{i-1} + geodesic from fix i-1 to fix i (input order)
};

enum class RobustLoss { kNone, kHuber, kCauchy };

struct GpsRegistrationOptions {
  GeodesicPath path = GeodesicPath::kFromOrigin;
  RobustLoss loss = RobustLoss::kHuber;
  /// Robust threshold k on the Mahalanobis norm of a fix residual [standard deviations], > 0.
  /// Huber weight min(1, k/e); Cauchy weight 1/(1 + (e/k)^2) (started from the Huber solution).
  double robust_threshold = 3.0;
  std::size_t min_fixes = 3;           ///< >= 2
  double min_spread_m = 5.0;           ///< weighted RMS horizontal distance from the centroid in W, > 0
  double max_yaw_sigma_rad = 0.17453292519943295;  ///< 10 deg, > 0
  int max_iterations = 50;             ///< reweighting iterations, >= 1
  bool estimate_height = true;         ///< false, or no fix with a height: [yaw, t_x, t_y] only, t_z = 0
  /// Correlation time tau [s] of the fix errors (multipath), >= 0. 0: independent fixes, covariance
  /// H^-1. > 0: errors of fixes i, j correlate as exp(-|t_i - t_j| / tau) (the whole per-fix
  /// covariance, which is conservative for its white part) and the covariance is the sandwich
  /// H^-1 B H^-1 of the same estimate; a per-fix covariance alone is optimistic by ~2 tau x rate.
  double error_correlation_time_s = 0.0;
};

/// Throws ConfigError(source, key, ...) naming the first bad option and its allowed range.
void validate(const GpsRegistrationOptions& options, const std::string& source = "gps_registration");

enum class GpsRegistrationStatus {
  kRegistered,           ///< alignment and covariance valid
  kTooFewFixes,          ///< fewer than min_fixes located fixes
  kInsufficientMotion,   ///< spread of the W positions below min_spread_m
  kYawTooUncertain,      ///< fitted, but the yaw sigma exceeds max_yaw_sigma_rad
};
const char* to_string(GpsRegistrationStatus status);

struct GpsRegistration {
  GpsRegistrationStatus status = GpsRegistrationStatus::kTooFewFixes;
  bool registered() const { return status == GpsRegistrationStatus::kRegistered; }

  /// [yaw, t_x, t_y, t_z] in the estimator's T_ENU_W block layout (t_z = 0 when not estimated).
  /// Filled also for kYawTooUncertain (for diagnostics); zero for the earlier statuses.
  Eigen::Vector4d alignment = Eigen::Vector4d::Zero();
  /// Covariance of [yaw, t_x, t_y, t_z] (4x4) when height_estimated, else of [yaw, t_x, t_y] (3x3);
  /// empty before a fit. Units rad^2, m^2.
  Eigen::MatrixXd covariance;
  bool height_estimated = false;

  double spread_m = 0;            ///< weighted RMS horizontal distance of the W positions from their centroid
  double yaw_sigma_rad = 0;       ///< sqrt(covariance(0, 0)); 0 before a fit
  std::size_t used_fixes = 0;     ///< located fixes (k2D / k3D)
  std::size_t skipped_no_fix = 0; ///< kNoFix fixes, ignored
  std::vector<double> weights;    ///< final robust weight per input pair (0 for skipped ones)
  int iterations = 0;             ///< reweighting iterations run
  double weighted_chi2 = 0;       ///< sum of weight * squared Mahalanobis norm at the solution

  /// T_ENU_W = (Rz(yaw), t).
  SE3 T_ENU_W() const;
};

/// Eq. 6: located fixes (k2D / k3D) to metres in the ENU frame at `origin`, in input order.
/// up = ellipsoidal_height_m(fix) - origin.height_m, NaN for fixes without a height.
/// Throws Error on a kNoFix fix, non-finite or out-of-range latitude/longitude or origin.
std::vector<Vec3> geodesic_enu(const std::vector<GpsFix>& fixes, const GeodeticOrigin& origin,
                               GeodesicPath path = GeodesicPath::kFromOrigin);

/// Estimates T_ENU_W from the pairs (any order for kFromOrigin; time order for kChained). kNoFix
/// fixes are skipped and counted. Throws Error on non-finite positions, a covariance that is not
/// symmetric positive definite or a bad latitude/longitude, ConfigError on bad options.
GpsRegistration register_gps_to_world(const std::vector<GpsRegistrationPair>& pairs, const GeodeticOrigin& origin,
                                      const GpsRegistrationOptions& options = {});

}  // namespace navaid::estimation
