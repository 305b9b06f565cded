#pragma once
// What the estimator hands to mapping, planning and interaction.
#include <optional>
#include <string_view>

#include "navaid/core/geometry.hpp"
#include "navaid/core/time.hpp"

namespace navaid {

enum class EstimatorMode { kInitializing, kRgbdVio, kVio, kImuOnly, kLost };

std::string_view to_string(EstimatorMode mode);
/// Inverse of to_string; nullopt for unknown names.
std::optional<EstimatorMode> estimator_mode_from_string(std::string_view name);

using Mat15 = Eigen::Matrix<double, 15, 15>;
using Mat4 = Eigen::Matrix4d;

/// Estimate of the body B at time t.
///
/// Covariance parametrization (15 x 15, this order):
///   [0:3)   dtheta: rotation error on the right, R_W_B = R_hat * Exp(dtheta)   [rad]
///   [3:6)   dp:     position error in W, p = p_hat + dp                         [m]
///   [6:9)   dv:     velocity error in W                                         [m/s]
///   [9:12)  db_g:   gyro bias error                                             [rad/s]
///   [12:15) db_a:   accelerometer bias error                                    [m/s^2]
/// T_ENU_W is 4-DOF (gravity fixes roll and pitch): its covariance is over
///   [dyaw, dx, dy, dz] with T_ENU_W = T_hat with yaw + dyaw and translation + [dx dy dz].
struct StateEstimate {
  Timestamp t = 0;
  SE3 T_W_B;
  Vec3 v_W = Vec3::Zero();
  Vec3 b_g = Vec3::Zero();
  Vec3 b_a = Vec3::Zero();
  Mat15 covariance = Mat15::Identity();
  std::optional<SE3> T_ENU_W;
  std::optional<Mat4> T_ENU_W_covariance;
  EstimatorMode mode = EstimatorMode::kInitializing;
};

}  // namespace navaid
