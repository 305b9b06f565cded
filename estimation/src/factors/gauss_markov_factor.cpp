#include "navaid/estimation/factors/gauss_markov_factor.hpp"

#include <cmath>
#include <string>

#include <Eigen/Cholesky>

#include "navaid/core/errors.hpp"

namespace navaid::estimation {

Mat3 sqrt_information_of(const Mat3& covariance, const char* what) {
  if (!covariance.allFinite()) throw Error(std::string(what) + ": non-finite covariance");
  if (!covariance.isApprox(covariance.transpose(), 1e-9)) throw Error(std::string(what) + ": covariance not symmetric");
  const Eigen::LLT<Mat3> llt(covariance);
  if (llt.info() != Eigen::Success) throw Error(std::string(what) + ": covariance not positive definite");
  return llt.matrixL().solve(Mat3::Identity());
}

GaussMarkovFactor::GaussMarkovFactor(double dt_s, double tau_s, const Mat3& stationary_covariance) {
  if (!(dt_s >= 0) || !(tau_s > 0) || !std::isfinite(dt_s) || !std::isfinite(tau_s))
    throw Error("GaussMarkovFactor: needs dt >= 0 and tau > 0 (got dt " + std::to_string(dt_s) + " s, tau " +
                std::to_string(tau_s) + " s)");
  phi_ = std::exp(-dt_s / tau_s);
  if (!(phi_ < 1.0 - 1e-12)) throw Error("GaussMarkovFactor: dt / tau too small for a noisy step");
  sqrt_information_ = sqrt_information_of((1.0 - phi_ * phi_) * stationary_covariance, "GaussMarkovFactor");
}

bool GaussMarkovFactor::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  const Eigen::Map<const Vec3> previous(parameters[0]);
  const Eigen::Map<const Vec3> current(parameters[1]);
  Eigen::Map<Vec3>{residuals} = sqrt_information_ * (current - phi_ * previous);
  if (jacobians) {
    using J3 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;
    if (jacobians[0]) Eigen::Map<J3>{jacobians[0]} = -phi_ * sqrt_information_;
    if (jacobians[1]) Eigen::Map<J3>{jacobians[1]} = sqrt_information_;
  }
  return true;
}

}  // namespace navaid::estimation
