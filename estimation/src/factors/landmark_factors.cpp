#include "navaid/estimation/factors/landmark_factors.hpp"

#include <cmath>
#include <string>

#include "navaid/core/errors.hpp"
#include "navaid/estimation/factors/inverse_depth_factor.hpp"

namespace navaid::estimation {

namespace {

void require_positive(double v, const char* factor, const char* key) {
  if (!(v > 0.0) || !std::isfinite(v)) throw ConfigError(factor, key, "must be finite and > 0");
}

const TimedObservation& checked(const TimedObservation& o, const char* factor) {
  if (!o.m.allFinite() || !o.velocity.allFinite() || !std::isfinite(o.td0_s))
    throw Error(std::string(factor) + ": the observation (m, velocity, td0) must be finite");
  return o;
}

// The plain factor's blocks with lambda = l[2], and its Jacobians, of which the landmark's
// [d/dx_a, d/dy_a, d/dlambda] (row-major Rows x 3) is assembled from d/dm_anchor and d/dlambda.
template <int Rows, typename Call>
bool evaluate_on_landmark(double const* const* parameters, double* residuals, double** jacobians, Call&& call) {
  const double* landmark = parameters[3];
  const double* blocks[4] = {parameters[0], parameters[1], parameters[2], landmark + 2};
  const Eigen::Vector2d m_anchor(landmark[0], landmark[1]);
  const bool want_landmark = jacobians != nullptr && jacobians[3] != nullptr;
  Eigen::Matrix<double, Rows, 1> d_lambda;
  Eigen::Matrix<double, Rows, 2> d_m_anchor;
  double* plain_jacobians[4] = {nullptr, nullptr, nullptr, nullptr};
  if (jacobians) {
    for (int i = 0; i < 3; ++i) plain_jacobians[i] = jacobians[i];
    if (want_landmark) plain_jacobians[3] = d_lambda.data();
  }
  if (!call(blocks, m_anchor, residuals, jacobians ? plain_jacobians : nullptr, want_landmark ? &d_m_anchor : nullptr))
    return false;
  if (want_landmark) {
    Eigen::Map<Eigen::Matrix<double, Rows, kLandmarkSize, Eigen::RowMajor>> J(jacobians[3]);
    J.template leftCols<2>() = d_m_anchor;
    J.col(2) = d_lambda;
  }
  return true;
}

}  // namespace

AnchorBearingTdFactor::AnchorBearingTdFactor(const TimedObservation& anchor, double focal_px, double sigma_px)
    : anchor_(checked(anchor, "AnchorBearingTdFactor")) {
  require_positive(focal_px, "anchor_bearing_factor", "focal_px");
  require_positive(sigma_px, "anchor_bearing_factor", "sigma_px");
  sqrt_information_ = focal_px / sigma_px;
}

bool AnchorBearingTdFactor::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  const double* l = parameters[0];
  const Eigen::Vector2d m = anchor_.at(parameters[1][0]);
  residuals[0] = sqrt_information_ * (l[0] - m.x());
  residuals[1] = sqrt_information_ * (l[1] - m.y());
  if (jacobians && jacobians[0]) {
    Eigen::Map<Eigen::Matrix<double, 2, kLandmarkSize, Eigen::RowMajor>> J(jacobians[0]);
    J << sqrt_information_, 0.0, 0.0, 0.0, sqrt_information_, 0.0;
  }
  if (jacobians && jacobians[1]) Eigen::Map<Eigen::Vector2d>{jacobians[1]} = sqrt_information_ * anchor_.velocity;
  return true;
}

LandmarkReprojectionTdFactor::LandmarkReprojectionTdFactor(const TimedObservation& target, double focal_px,
                                                           double sigma_px)
    : target_(checked(target, "LandmarkReprojectionTdFactor")),
      plain_(Eigen::Vector2d::Zero(), target.m, focal_px, sigma_px) {}

bool LandmarkReprojectionTdFactor::Evaluate(double const* const* parameters, double* residuals,
                                            double** jacobians) const {
  const double td = parameters[4][0];
  const bool want_td = jacobians != nullptr && jacobians[4] != nullptr;
  Eigen::Matrix2d d_m_target;
  if (!evaluate_on_landmark<2>(parameters, residuals, jacobians,
                               [&](const double* const* blocks, const Eigen::Vector2d& m_anchor, double* r, double** J,
                                   Eigen::Matrix<double, 2, 2>* d_m_anchor) {
                                 return plain_.evaluate_at(blocks, m_anchor, target_.at(td), r, J, d_m_anchor,
                                                           want_td ? &d_m_target : nullptr);
                               }))
    return false;
  if (want_td) Eigen::Map<Eigen::Vector2d>{jacobians[4]} = -d_m_target * target_.velocity;
  return true;
}

LandmarkDepth3dTdFactor::LandmarkDepth3dTdFactor(const TimedObservation& target, double depth_j_m,
                                                 double depth_rate_mps, double focal_px, double sigma_lambda,
                                                 double sigma_px, Depth3dCovariance model)
    : target_(checked(target, "LandmarkDepth3dTdFactor")),
      depth_m_(depth_j_m),
      depth_rate_mps_(depth_rate_mps),
      plain_(Eigen::Vector2d::Zero(), target.m, depth_j_m, focal_px, sigma_lambda, sigma_px, model) {
  if (!std::isfinite(depth_rate_mps))
    throw Error("LandmarkDepth3dTdFactor: the depth rate must be finite, got " + std::to_string(depth_rate_mps));
}

bool LandmarkDepth3dTdFactor::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  const double td = parameters[4][0];
  const double depth = depth_m_ - (td - target_.td0_s) * depth_rate_mps_;
  if (!(depth > 0.0)) return false;
  const bool want_td = jacobians != nullptr && jacobians[4] != nullptr;
  Eigen::Matrix<double, 3, 2> d_m_target;
  Eigen::Vector3d d_depth;
  if (!evaluate_on_landmark<3>(parameters, residuals, jacobians,
                               [&](const double* const* blocks, const Eigen::Vector2d& m_anchor, double* r, double** J,
                                   Eigen::Matrix<double, 3, 2>* d_m_anchor) {
                                 return plain_.evaluate_at(blocks, m_anchor, target_.at(td), depth, r, J, d_m_anchor,
                                                           want_td ? &d_m_target : nullptr,
                                                           want_td ? &d_depth : nullptr);
                               }))
    return false;
  if (want_td)
    Eigen::Map<Eigen::Vector3d>{jacobians[4]} = -d_m_target * target_.velocity - d_depth * depth_rate_mps_;
  return true;
}

AnchorBearingFactor::AnchorBearingFactor(const Eigen::Vector2d& m_anchor, double focal_px, double sigma_px)
    : m_anchor_(m_anchor) {
  if (!m_anchor.allFinite()) throw Error("AnchorBearingFactor: the anchor observation must be finite");
  require_positive(focal_px, "anchor_bearing_factor", "focal_px");
  require_positive(sigma_px, "anchor_bearing_factor", "sigma_px");
  sqrt_information_ = focal_px / sigma_px;
}

bool AnchorBearingFactor::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  const double* l = parameters[0];
  residuals[0] = sqrt_information_ * (l[0] - m_anchor_.x());
  residuals[1] = sqrt_information_ * (l[1] - m_anchor_.y());
  if (jacobians && jacobians[0]) {
    Eigen::Map<Eigen::Matrix<double, 2, kLandmarkSize, Eigen::RowMajor>> J(jacobians[0]);
    J << sqrt_information_, 0.0, 0.0, 0.0, sqrt_information_, 0.0;
  }
  return true;
}

AnchorInverseDepthFactor::AnchorInverseDepthFactor(double depth_m, double sigma_lambda) {
  if (!(depth_m > 0.0) || !std::isfinite(depth_m))
    throw Error("AnchorInverseDepthFactor: measured depth must be finite and > 0, got " + std::to_string(depth_m));
  require_positive(sigma_lambda, "anchor_inverse_depth_factor", "sigma_lambda");
  measured_inverse_depth_ = 1.0 / depth_m;
  sigma_lambda_ = sigma_lambda;
}

bool AnchorInverseDepthFactor::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  residuals[0] = (parameters[0][2] - measured_inverse_depth_) / sigma_lambda_;
  if (jacobians && jacobians[0]) {
    jacobians[0][0] = 0.0;
    jacobians[0][1] = 0.0;
    jacobians[0][2] = 1.0 / sigma_lambda_;
  }
  return true;
}

LandmarkReprojectionFactor::LandmarkReprojectionFactor(const Eigen::Vector2d& m_target, double focal_px,
                                                       double sigma_px)
    : m_target_(m_target), plain_(Eigen::Vector2d::Zero(), m_target, focal_px, sigma_px) {}

bool LandmarkReprojectionFactor::Evaluate(double const* const* parameters, double* residuals,
                                          double** jacobians) const {
  return evaluate_on_landmark<2>(
      parameters, residuals, jacobians,
      [&](const double* const* blocks, const Eigen::Vector2d& m_anchor, double* r, double** J,
          Eigen::Matrix<double, 2, 2>* d_m_anchor) {
        return plain_.evaluate_at(blocks, m_anchor, m_target_, r, J, d_m_anchor, nullptr);
      });
}

LandmarkDepth3dFactor::LandmarkDepth3dFactor(const Eigen::Vector2d& m_target, double depth_j_m, double focal_px,
                                             double sigma_lambda, double sigma_px, Depth3dCovariance model)
    : m_target_(m_target),
      depth_m_(depth_j_m),
      plain_(Eigen::Vector2d::Zero(), m_target, depth_j_m, focal_px, sigma_lambda, sigma_px, model) {}

bool LandmarkDepth3dFactor::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  return evaluate_on_landmark<3>(
      parameters, residuals, jacobians,
      [&](const double* const* blocks, const Eigen::Vector2d& m_anchor, double* r, double** J,
          Eigen::Matrix<double, 3, 2>* d_m_anchor) {
        return plain_.evaluate_at(blocks, m_anchor, m_target_, depth_m_, r, J, d_m_anchor, nullptr, nullptr);
      });
}

}  // namespace navaid::estimation
