#include "navaid/estimation/factors/depth_3d_factor.hpp"

#include <cmath>
#include <string>

#include "anchored_point.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/estimation/factors/pose_parametrization.hpp"

namespace navaid::estimation {

namespace {
constexpr double kMinDepth = 1e-6;  // [m] in front of the camera

// [X, Y, 1/Z] of the measured point in the target camera.
Vec3 measured_point(const Eigen::Vector2d& m_target, double depth_m) {
  return Vec3(m_target.x() * depth_m, m_target.y() * depth_m, 1.0 / depth_m);
}
}  // namespace

Depth3dFactor::Depth3dFactor(const Eigen::Vector2d& m_anchor, const Eigen::Vector2d& m_target, double depth_j_m,
                             double focal_px, double sigma_lambda, double sigma_px, Depth3dCovariance model)
    : m_anchor_(m_anchor), m_target_(m_target), depth_m_(depth_j_m) {
  if (!(depth_j_m > 0.0) || !std::isfinite(depth_j_m)) {
    throw Error("Depth3dFactor: measured depth must be finite and > 0, got " + std::to_string(depth_j_m));
  }
  auto require = [](double v, const char* key) {
    if (!(v > 0.0) || !std::isfinite(v)) throw ConfigError("depth_3d_factor", key, "must be finite and > 0");
  };
  require(focal_px, "focal_px");
  require(sigma_lambda, "sigma_lambda");
  require(sigma_px, "sigma_px");
  measurement_ = measured_point(m_target, depth_j_m);
  const double sigma_n = sigma_px / focal_px;  // on the normalized plane
  const double Z = depth_j_m;
  const bool full = model == Depth3dCovariance::kFull;
  sqrt_information_ << 1.0 / (Z * sigma_n), 0.0, full ? m_target.x() * Z / sigma_n : 0.0,  //
      0.0, 1.0 / (Z * sigma_n), full ? m_target.y() * Z / sigma_n : 0.0,                   //
      0.0, 0.0, 1.0 / sigma_lambda;
}

bool Depth3dFactor::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  return evaluate_at(parameters, m_anchor_, m_target_, depth_m_, residuals, jacobians, nullptr, nullptr, nullptr);
}

bool Depth3dFactor::evaluate_at(double const* const* parameters, const Eigen::Vector2d& m_anchor,
                                const Eigen::Vector2d& m_target, double depth_j_m, double* residuals,
                                double** jacobians, Eigen::Matrix<double, 3, 2>* d_m_anchor,
                                Eigen::Matrix<double, 3, 2>* d_m_target, Eigen::Vector3d* d_depth) const {
  const bool want = jacobians != nullptr || d_m_anchor != nullptr;
  const detail::AnchoredPoint pt = detail::transfer_anchored_point(
      parameters[0], parameters[1], parameters[2], parameters[3][0], Vec3(m_anchor.x(), m_anchor.y(), 1.0), want,
      jacobians != nullptr && jacobians[2] != nullptr);
  const Vec3& P = pt.P_ct;
  if (!(P.z() > kMinDepth)) return false;
  const Vec3 predicted(P.x(), P.y(), 1.0 / P.z());
  Eigen::Map<Vec3>{residuals} = sqrt_information_ * (measured_point(m_target, depth_j_m) - predicted);
  if (d_m_target) {  // X = x_j Z, Y = y_j Z
    Eigen::Matrix<double, 3, 2> d_measured = Eigen::Matrix<double, 3, 2>::Zero();
    d_measured(0, 0) = depth_j_m;
    d_measured(1, 1) = depth_j_m;
    *d_m_target = sqrt_information_ * d_measured;
  }
  if (d_depth) *d_depth = sqrt_information_ * Vec3(m_target.x(), m_target.y(), -1.0 / (depth_j_m * depth_j_m));
  if (!want) return true;

  // d r / d P = -S d[X, Y, 1/Z] / dP
  const Mat3 d_point = sqrt_information_ * Vec3(-1.0, -1.0, 1.0 / (P.z() * P.z())).asDiagonal();
  if (d_m_anchor) *d_m_anchor = d_point * pt.d_m_anchor;
  if (!jacobians) return true;
  if (jacobians[0]) write_pose_jacobian<3>(d_point * pt.d_anchor, parameters[0], jacobians[0]);
  if (jacobians[1]) write_pose_jacobian<3>(d_point * pt.d_target, parameters[1], jacobians[1]);
  if (jacobians[2]) write_pose_jacobian<3>(d_point * pt.d_extrinsic, parameters[2], jacobians[2]);
  if (jacobians[3]) Eigen::Map<Vec3>{jacobians[3]} = d_point * pt.d_lambda;
  return true;
}

}  // namespace navaid::estimation
