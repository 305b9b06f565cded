#pragma once
// Simulated GNSS receiver: true antenna position -> noisy GpsFix (DESIGN.md §4 conventions).
//
// Error model, per ENU axis, at fix time t_k:
//   p_meas = p_true + w_k + b_k,
//   w_k ~ N(0, diag(sigma_h^2, sigma_h^2, sigma_v^2))             (white receiver noise)
//   b_k = sigma_mp(f) .* u_k                                      (multipath bias)
//   u_k = phi u_{k-1} + sqrt(1 - phi^2) n_k,  phi = exp(-dt/tau)  (unit first-order Gauss-Markov,
//         discretized exactly for any dt, so uneven call times stay correct)
//   sigma_mp(f) = sigma_mp_open_sky (1 + canyon_gain f),  f = urban-canyon factor in [0, 1].
// For a constant f this is the textbook process x_k = phi x_{k-1} + q^(1/2) n_k with
// q = sigma_mp(f)^2 (1 - phi^2); keeping u at unit variance lets the bias scale at once when the
// walker enters a canyon instead of lagging by tau.
//
// Reported covariance_enu = diag(sigma_h^2 + sigma_mp,h(f)^2, same, sigma_v^2 + sigma_mp,v(f)^2):
// the white variance plus the multipath steady-state variance (the marginal error variance; the
// time correlation of the bias is not expressed in a per-fix covariance). HDOP is reported as
// sqrt(cov_EE + cov_NN) / uere_m, the same relation io's NMEA reader uses to turn HDOP back into
// a covariance (io::NmeaOptions::uere_autonomous_m = 5 m), so a recorded-and-replayed simulated
// fix keeps its covariance. With noise disabled the fix is exactly the truth but the reported
// covariance and HDOP stay those of the configured model, so estimators weigh it the same way.
//
// Geoid: GpsFix::altitude_m is MSL. GeographicLib's geoid models (EGM96/EGM2008) need data files
// that Debian's libgeographiclib package does not ship (/usr/share/GeographicLib is absent on the
// build machine), so the separation N is a configurable constant: altitude_m = h_ellipsoid - N
// and geoid_separation_m = N, which keeps ellipsoidal_height_m(fix) exact.
#include <cstdint>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "navaid/core/calibration.hpp"
#include "navaid/core/geodesy.hpp"
#include "navaid/core/geometry.hpp"
#include "navaid/core/messages.hpp"
#include "navaid/core/time.hpp"

namespace navaid::simulation {

/// A GNSS outage: no fix for start <= t < end.
struct GnssOutage {
  Timestamp start = 0;
  Timestamp end = 0;
};

/// Variance [m^2] on each ENU axis of a kNoFix fix: finite (recordings store it) but no information.
constexpr double kNoFixVariance_m2 = 1e12;

struct GnssModelConfig {
  double rate_hz = 1.0;              ///< fix rate, [1, 10] Hz; the caller samples every period()
  double sigma_horizontal_m = 3.0;   ///< white-noise sigma per horizontal axis (E, N) [m], >= 0
  double sigma_vertical_m = 5.0;     ///< white-noise sigma on U [m], >= 0
  double multipath_tau_s = 30.0;     ///< Gauss-Markov correlation time tau [s], > 0
  double multipath_sigma_horizontal_m = 1.5;  ///< open-sky steady-state sigma per E/N axis [m], >= 0
  double multipath_sigma_vertical_m = 2.5;    ///< open-sky steady-state sigma on U [m], >= 0
  double canyon_gain = 3.0;          ///< k in sigma_mp (1 + k f), >= 0 (f = 1: 4x the open-sky sigma)
  std::vector<GnssOutage> outages;   ///< [start, end) intervals without fix; start < end
  /// No fix while the canyon factor is >= this, in [0, 1]; unset: the factor never blocks fixes.
  std::optional<double> outage_canyon_factor;
  /// During an outage: false -> measure() returns nullopt; true -> a GpsFix with mode kNoFix,
  /// quality 0, 0 satellites, NaN altitude/geoid separation/HDOP, the last reported latitude and
  /// longitude (the origin before any fix) and covariance kNoFixVariance_m2 * I.
  bool report_no_fix = false;
  double geoid_separation_m = 0.0;   ///< constant N [m], |N| <= 150 (Earth's geoid spans ~ -107..+86 m)
  double uere_m = 5.0;               ///< user equivalent range error relating HDOP to sigma [m], > 0
  int satellites = 10;               ///< reported satellites used, [4, 64]
  bool noise = true;                 ///< false: fixes exactly at the truth
  std::uint64_t seed = 1;
};

/// Throws ConfigError(source, key, ...) naming the first bad key and its allowed range.
void validate(const GnssModelConfig& config, const std::string& source = "gnss_model");

class GnssModel {
 public:
  /// Validates the config (ConfigError) and sets the ENU origin of the scenario.
  GnssModel(GnssModelConfig config, const GeodeticOrigin& origin);

  /// One fix at time t for the true antenna position p_W_antenna. T_ENU_W maps W into the ENU
  /// frame at the origin (both z-up, so in practice a yaw and a translation). canyon_factor in
  /// [0, 1] (std::invalid_argument otherwise). Calls must have non-decreasing t
  /// (std::invalid_argument otherwise); the multipath bias evolves over the elapsed time, also
  /// through outages. Returns nullopt in an outage unless report_no_fix is set.
  std::optional<GpsFix> measure(Timestamp t, const Vec3& p_W_antenna, const SE3& T_ENU_W,
                                double canyon_factor = 0.0);

  /// True when t lies in a configured outage or canyon_factor reaches outage_canyon_factor.
  bool in_outage(Timestamp t, double canyon_factor) const;
  /// The covariance measure() reports for this canyon factor (see the file comment).
  Mat3 reported_covariance_enu(double canyon_factor) const;
  /// Steady-state multipath sigma per ENU axis for this canyon factor.
  Vec3 multipath_sigma_enu(double canyon_factor) const;
  /// Multipath bias [m, ENU] added to the last fix (zero before the first call / without noise).
  const Vec3& multipath_bias_enu() const { return bias_enu_; }
  /// Nominal time between fixes, 1 / rate_hz.
  Duration period() const;
  const GnssModelConfig& config() const { return config_; }
  const LocalEnuFrame& enu_frame() const { return enu_; }

 private:
  GnssModelConfig config_;
  LocalEnuFrame enu_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};
  std::optional<Timestamp> last_t_;
  Vec3 unit_state_ = Vec3::Zero();  ///< u_k, unit-variance Gauss-Markov state per axis
  Vec3 bias_enu_ = Vec3::Zero();
  Eigen::Vector2d last_lat_lon_deg_;  ///< repeated by kNoFix fixes
};

}  // namespace navaid::simulation
