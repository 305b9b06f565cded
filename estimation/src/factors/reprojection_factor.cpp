#include "navaid/estimation/factors/reprojection_factor.hpp"

#include <cmath>

#include "anchored_point.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/estimation/factors/pose_parametrization.hpp"

namespace navaid::estimation {

namespace {
constexpr double kMinDepth = 1e-6;  // [m] in front of the camera
}

ReprojectionFactor::ReprojectionFactor(const Eigen::Vector2d& m_anchor, const Eigen::Vector2d& m_target,
                                       double focal_px, double sigma_px)
    : m_anchor_(m_anchor), m_target_(m_target) {
  auto require = [](double v, const char* key) {
    if (!(v > 0.0) || !std::isfinite(v)) throw ConfigError("reprojection_factor", key, "must be finite and > 0");
  };
  require(focal_px, "focal_px");
  require(sigma_px, "sigma_px");
  sqrt_information_ = focal_px / sigma_px;
}

bool ReprojectionFactor::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  return evaluate_at(parameters, m_anchor_, m_target_, residuals, jacobians, nullptr, nullptr);
}

bool ReprojectionFactor::evaluate_at(double const* const* parameters, const Eigen::Vector2d& m_anchor,
                                     const Eigen::Vector2d& m_target, double* residuals, double** jacobians,
                                     Eigen::Matrix2d* d_m_anchor, Eigen::Matrix2d* d_m_target) const {
  const bool want = jacobians != nullptr || d_m_anchor != nullptr;
  const detail::AnchoredPoint pt = detail::transfer_anchored_point(
      parameters[0], parameters[1], parameters[2], parameters[3][0], Vec3(m_anchor.x(), m_anchor.y(), 1.0), want,
      jacobians != nullptr && jacobians[2] != nullptr);
  const Vec3& P = pt.P_ct;
  if (!(P.z() > kMinDepth)) return false;
  const double s = sqrt_information_;
  Eigen::Map<Eigen::Vector2d>{residuals} = s * (P.head<2>() / P.z() - m_target);
  if (d_m_target) *d_m_target = -s * Eigen::Matrix2d::Identity();
  if (!want) return true;

  Eigen::Matrix<double, 2, 3> d_proj;  // s * d(x/z, y/z) / dP
  const double iz = 1.0 / P.z();
  d_proj << iz, 0.0, -P.x() * iz * iz,  //
      0.0, iz, -P.y() * iz * iz;
  d_proj *= s;
  if (d_m_anchor) *d_m_anchor = d_proj * pt.d_m_anchor;
  if (!jacobians) return true;
  if (jacobians[0]) write_pose_jacobian<2>(d_proj * pt.d_anchor, parameters[0], jacobians[0]);
  if (jacobians[1]) write_pose_jacobian<2>(d_proj * pt.d_target, parameters[1], jacobians[1]);
  if (jacobians[2]) write_pose_jacobian<2>(d_proj * pt.d_extrinsic, parameters[2], jacobians[2]);
  if (jacobians[3]) Eigen::Map<Eigen::Vector2d>{jacobians[3]} = d_proj * pt.d_lambda;
  return true;
}

}  // namespace navaid::estimation
