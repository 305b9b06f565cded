#include "navaid/simulation/magnetometer_model.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <sstream>
#include <utility>

#include "navaid/core/errors.hpp"
#include "value_checks.hpp"

namespace navaid::simulation {

using detail::check_range;
using detail::format_number;

namespace {

void check_vector(const std::string& source, const std::string& key, const Vec3& v, double max_norm_t) {
  if (!v.allFinite() || v.norm() > max_norm_t) {
    throw ConfigError(source, key,
                      "expected a finite vector with norm <= " + format_number(max_norm_t) + " T, found norm " + format_number(v.norm()));
  }
}

}  // namespace

void validate(const MagnetometerModelConfig& c, const std::string& source) {
  check_vector(source, "field_enu_t", c.field_enu_t, 1e-3);
  if (c.field_enu_t.norm() == 0.0) throw ConfigError(source, "field_enu_t", "expected a non-zero field");
  check_vector(source, "hard_iron_t", c.hard_iron_t, 1e-3);
  if (!std::isfinite(c.sigma_t) || c.sigma_t < 0.0 || c.sigma_t > 1e-4) {
    throw ConfigError(source, "sigma_t", "expected a value in [0, 1e-4] T, found " + format_number(c.sigma_t));
  }

  const Mat3& a = c.soft_iron;
  if (!a.allFinite()) throw ConfigError(source, "soft_iron", "expected finite entries");
  const double asymmetry = (a - a.transpose()).norm();
  if (asymmetry > kSoftIronSymmetryTolerance * a.norm()) {
    throw ConfigError(source, "soft_iron",
                      "expected a near-symmetric matrix (|A - A^T| <= " + format_number(kSoftIronSymmetryTolerance) +
                          " |A|), found |A - A^T| / |A| = " + format_number(a.norm() > 0 ? asymmetry / a.norm() : 0.0));
  }
  // Positive eigenvalues of the symmetric part imply x^T A x > 0, hence A invertible; the ratio
  // bound rejects numerically singular matrices too.
  const Eigen::SelfAdjointEigenSolver<Mat3> eig(0.5 * (a + a.transpose()), Eigen::EigenvaluesOnly);
  const Vec3 ev = eig.eigenvalues();  // ascending
  if (!(ev[0] > 0.0) || ev[0] < kSoftIronMinEigenvalueRatio * ev[2]) {
    throw ConfigError(source, "soft_iron",
                      "expected a positive definite, invertible matrix (eigenvalues > 0, min/max >= " +
                          format_number(kSoftIronMinEigenvalueRatio) + "), found eigenvalues " + format_number(ev[0]) + ", " +
                          format_number(ev[1]) + ", " + format_number(ev[2]));
  }
}

MagnetometerModel::MagnetometerModel(MagnetometerModelConfig config)
    : config_((validate(config), std::move(config))), rng_(config_.seed) {}

Vec3 MagnetometerModel::expected_field_B(const SE3& T_ENU_W, const SE3& T_W_B) const {
  const Quat q_ENU_B = T_ENU_W.q * T_W_B.q;
  return config_.soft_iron * (q_ENU_B.conjugate() * config_.field_enu_t) + config_.hard_iron_t;
}

MagSample MagnetometerModel::measure(Timestamp t, const SE3& T_ENU_W, const SE3& T_W_B) {
  MagSample s;
  s.t = t;
  s.field = expected_field_B(T_ENU_W, T_W_B);
  if (config_.noise) {
    for (int i = 0; i < 3; ++i) s.field[i] += config_.sigma_t * normal_(rng_);
  }
  return s;
}

}  // namespace navaid::simulation
