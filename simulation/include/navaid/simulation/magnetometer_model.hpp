#pragma once
// Simulated 3-axis magnetometer in the body frame B (DESIGN.md §4 conventions, field in tesla):
//   m_B = A_soft * R_B_ENU * m_ENU + b_hard + n,   n ~ N(0, sigma^2 I),
//   R_B_ENU = (R_ENU_W R_W_B)^T from the orientations of T_ENU_W and T_W_B.
// A_soft (soft iron) must be invertible and near symmetric positive definite, as calibrated
// soft-iron matrices are; b_hard (hard iron) is a constant offset in B.
#include <cstdint>
#include <random>
#include <string>

#include "navaid/core/geometry.hpp"
#include "navaid/core/messages.hpp"
#include "navaid/core/time.hpp"

namespace navaid::simulation {

struct MagnetometerModelConfig {
  /// Earth field in ENU [T]. Default: a mid-northern-latitude field (roughly central Europe:
  /// 20 uT horizontal towards north, 45 uT pointing down, |m| ~ 49 uT, inclination ~ 66 deg),
  /// zero declination, i.e. magnetic north = true north. |m| must be in (0, 1e-3] T: the limit
  /// catches fields given in microtesla by mistake.
  Vec3 field_enu_t = Vec3(0.0, 20e-6, -45e-6);
  Vec3 hard_iron_t = Vec3::Zero();   ///< b_hard [T], |b| <= 1e-3 T
  Mat3 soft_iron = Mat3::Identity();  ///< A_soft, see validate() for the accepted matrices
  double sigma_t = 0.2e-6;           ///< white-noise sigma per axis [T], [0, 1e-4]
  bool noise = true;                 ///< false: m_B exactly as modelled
  std::uint64_t seed = 1;
};

/// Relative tolerance on soft-iron asymmetry: |A - A^T|_F <= tol |A|_F.
constexpr double kSoftIronSymmetryTolerance = 1e-3;
/// Smallest accepted ratio of the extreme eigenvalues of (A + A^T) / 2 (all must be positive).
constexpr double kSoftIronMinEigenvalueRatio = 1e-3;

/// Throws ConfigError(source, key, ...) naming the first bad key and its allowed range.
void validate(const MagnetometerModelConfig& config, const std::string& source = "magnetometer_model");

class MagnetometerModel {
 public:
  /// Validates the config (ConfigError).
  explicit MagnetometerModel(MagnetometerModelConfig config);

  /// One sample at time t for the body pose T_W_B in a world W placed in ENU by T_ENU_W.
  MagSample measure(Timestamp t, const SE3& T_ENU_W, const SE3& T_W_B);
  /// The noise-free model value A_soft R_B_ENU m_ENU + b_hard [T].
  Vec3 expected_field_B(const SE3& T_ENU_W, const SE3& T_W_B) const;
  const MagnetometerModelConfig& config() const { return config_; }

 private:
  MagnetometerModelConfig config_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};
};

}  // namespace navaid::simulation
