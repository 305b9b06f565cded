#include "navaid/estimation/failure_detection.hpp"

#include <cmath>
#include <cstdio>

namespace navaid::estimation {

namespace {

std::string exceeds(const char* what, double value, double limit, const char* unit) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "%s %.3g %s > %.3g", what, value, unit, limit);
  return buf;
}

}  // namespace

std::optional<std::string> detect_estimator_failure(const StateEstimate& current, const StateEstimate* previous,
                                                    const VisualSupport& support, const FailureThresholds& limits) {
  const bool finite = current.T_W_B.t.allFinite() && current.T_W_B.q.coeffs().allFinite() && current.v_W.allFinite() &&
                      current.b_g.allFinite() && current.b_a.allFinite();
  if (!finite) return std::string("state not finite");
  if (current.b_a.norm() > limits.max_accel_bias)
    return exceeds("accelerometer bias", current.b_a.norm(), limits.max_accel_bias, "m/s^2");
  if (current.b_g.norm() > limits.max_gyro_bias)
    return exceeds("gyro bias", current.b_g.norm(), limits.max_gyro_bias, "rad/s");
  if (current.v_W.norm() > limits.max_speed_mps) return exceeds("speed", current.v_W.norm(), limits.max_speed_mps, "m/s");
  if (support.residuals >= static_cast<std::size_t>(limits.min_visual_residuals) &&
      support.inlier_fraction() < limits.min_inlier_fraction && support.recent_median >= limits.collapse_from)
  {
    char buf[160];
    std::snprintf(buf, sizeof buf, "visual inliers %zu of %zu (%.2f < %.2f, recent median %.2f)", support.inliers,
                  support.residuals, support.inlier_fraction(), limits.min_inlier_fraction, support.recent_median);
    return std::string(buf);
  }
  if (!previous) return std::nullopt;
  const double dt = ns_to_seconds(current.t - previous->t);
  const Vec3 predicted = previous->T_W_B.t + previous->v_W * dt;
  const double jump = (current.T_W_B.t - predicted).norm();
  if (jump > limits.max_position_jump_m) return exceeds("position jump", jump, limits.max_position_jump_m, "m");
  const double angle = Eigen::AngleAxisd(previous->T_W_B.q.conjugate() * current.T_W_B.q).angle();
  if (angle > limits.max_rotation_jump_rad)
    return exceeds("rotation jump", angle, limits.max_rotation_jump_rad, "rad");
  return std::nullopt;
}

}  // namespace navaid::estimation
