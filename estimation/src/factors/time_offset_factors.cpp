#include "navaid/estimation/factors/time_offset_factors.hpp"

#include <cmath>
#include <string>

#include "navaid/core/errors.hpp"

namespace navaid::estimation {

namespace {

const TimedObservation& checked(const TimedObservation& o, const char* factor, const char* which) {
  if (!o.m.allFinite() || !o.velocity.allFinite() || !std::isfinite(o.td0_s))
    throw Error(std::string(factor) + ": the " + which + " observation (m, velocity, td0) must be finite");
  return o;
}

// d r / d td of the moved normalized measurements (d m / d td = -v).
template <int Rows>
Eigen::Matrix<double, Rows, 1> td_jacobian(const Eigen::Matrix<double, Rows, 2>& d_m_anchor,
                                           const Eigen::Matrix<double, Rows, 2>& d_m_target,
                                           const TimedObservation& anchor, const TimedObservation& target) {
  return -(d_m_anchor * anchor.velocity + d_m_target * target.velocity);
}

}  // namespace

ReprojectionTdFactor::ReprojectionTdFactor(const TimedObservation& anchor, const TimedObservation& target,
                                           double focal_px, double sigma_px)
    : plain_(anchor.m, target.m, focal_px, sigma_px),
      anchor_(checked(anchor, "ReprojectionTdFactor", "anchor")),
      target_(checked(target, "ReprojectionTdFactor", "target")) {}

bool ReprojectionTdFactor::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  const double td = parameters[4][0];
  const bool want_td = jacobians != nullptr && jacobians[4] != nullptr;
  Eigen::Matrix2d d_anchor, d_target;
  if (!plain_.evaluate_at(parameters, anchor_.at(td), target_.at(td), residuals, jacobians,
                          want_td ? &d_anchor : nullptr, want_td ? &d_target : nullptr))
    return false;
  if (want_td) Eigen::Map<Eigen::Vector2d>{jacobians[4]} = td_jacobian<2>(d_anchor, d_target, anchor_, target_);
  return true;
}

Depth3dTdFactor::Depth3dTdFactor(const TimedObservation& anchor, const TimedObservation& target, double depth_j_m,
                                 double depth_rate_mps, double focal_px, double sigma_lambda, double sigma_px,
                                 Depth3dCovariance model)
    : plain_(anchor.m, target.m, depth_j_m, focal_px, sigma_lambda, sigma_px, model),
      anchor_(checked(anchor, "Depth3dTdFactor", "anchor")),
      target_(checked(target, "Depth3dTdFactor", "target")),
      depth_m_(depth_j_m),
      depth_rate_mps_(depth_rate_mps) {
  if (!std::isfinite(depth_rate_mps))
    throw Error("Depth3dTdFactor: the depth rate must be finite, got " + std::to_string(depth_rate_mps));
}

bool Depth3dTdFactor::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  const double td = parameters[4][0];
  const double depth = depth_m_ - (td - target_.td0_s) * depth_rate_mps_;
  if (!(depth > 0.0)) return false;
  const bool want_td = jacobians != nullptr && jacobians[4] != nullptr;
  Eigen::Matrix<double, 3, 2> d_anchor, d_target;
  Eigen::Vector3d d_depth;
  if (!plain_.evaluate_at(parameters, anchor_.at(td), target_.at(td), depth, residuals, jacobians,
                          want_td ? &d_anchor : nullptr, want_td ? &d_target : nullptr, want_td ? &d_depth : nullptr))
    return false;
  if (want_td)
    Eigen::Map<Eigen::Vector3d>{jacobians[4]} = td_jacobian<3>(d_anchor, d_target, anchor_, target_) - d_depth * depth_rate_mps_;
  return true;
}

}  // namespace navaid::estimation
