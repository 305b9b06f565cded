#include "navaid/simulation/gnss_model.hpp"

#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "navaid/core/errors.hpp"
#include "navaid/core/random_draws.hpp"
#include "value_checks.hpp"

namespace navaid::simulation {

using detail::check_range;
using detail::format_number;

void validate(const GnssModelConfig& c, const std::string& source) {
  check_range(source, "rate_hz", c.rate_hz, 1.0, 10.0, "Hz");
  check_range(source, "sigma_horizontal_m", c.sigma_horizontal_m, 0.0, 1e3, "m");
  check_range(source, "sigma_vertical_m", c.sigma_vertical_m, 0.0, 1e3, "m");
  check_range(source, "multipath_tau_s", c.multipath_tau_s, 0.0, 1e6, "s", true);
  check_range(source, "multipath_sigma_horizontal_m", c.multipath_sigma_horizontal_m, 0.0, 1e3, "m");
  check_range(source, "multipath_sigma_vertical_m", c.multipath_sigma_vertical_m, 0.0, 1e3, "m");
  check_range(source, "canyon_gain", c.canyon_gain, 0.0, 100.0, "");
  for (std::size_t i = 0; i < c.outages.size(); ++i) {
    if (c.outages[i].start >= c.outages[i].end) {
      throw ConfigError(source, "outages[" + std::to_string(i) + "]",
                        "expected start < end, found [" + format_seconds(c.outages[i].start) + ", " +
                            format_seconds(c.outages[i].end) + ") s");
    }
  }
  if (c.outage_canyon_factor) {
    check_range(source, "outage_canyon_factor", *c.outage_canyon_factor, 0.0, 1.0, "");
  }
  check_range(source, "geoid_separation_m", c.geoid_separation_m, -150.0, 150.0, "m");
  if (!std::isfinite(c.uere_m) || c.uere_m <= 0.0 || c.uere_m > 1e3) {
    throw ConfigError(source, "uere_m", "expected a value in (0, 1e3] m, found " + format_number(c.uere_m));
  }
  if (c.satellites < 4 || c.satellites > 64) {
    throw ConfigError(source, "satellites", "expected an integer in [4, 64], found " + std::to_string(c.satellites));
  }
}

GnssModel::GnssModel(GnssModelConfig config, const GeodeticOrigin& origin)
    : config_((validate(config), std::move(config))),
      enu_(origin),
      rng_(config_.seed),
      last_lat_lon_deg_(origin.latitude_deg, origin.longitude_deg) {}

Duration GnssModel::period() const { return seconds_to_ns(1.0 / config_.rate_hz); }

Vec3 GnssModel::multipath_sigma_enu(double canyon_factor) const {
  const double scale = 1.0 + config_.canyon_gain * canyon_factor;
  return Vec3(config_.multipath_sigma_horizontal_m, config_.multipath_sigma_horizontal_m,
              config_.multipath_sigma_vertical_m) *
         scale;
}

Mat3 GnssModel::reported_covariance_enu(double canyon_factor) const {
  const Vec3 mp = multipath_sigma_enu(canyon_factor);
  const Vec3 white(config_.sigma_horizontal_m, config_.sigma_horizontal_m, config_.sigma_vertical_m);
  return (white.cwiseAbs2() + mp.cwiseAbs2()).asDiagonal();
}

bool GnssModel::in_outage(Timestamp t, double canyon_factor) const {
  if (config_.outage_canyon_factor && canyon_factor >= *config_.outage_canyon_factor) return true;
  for (const auto& o : config_.outages) {
    if (t >= o.start && t < o.end) return true;
  }
  return false;
}

std::optional<GpsFix> GnssModel::measure(Timestamp t, const Vec3& p_W_antenna, const SE3& T_ENU_W,
                                         double canyon_factor) {
  if (!(canyon_factor >= 0.0 && canyon_factor <= 1.0)) {
    throw std::invalid_argument("GnssModel::measure: canyon_factor must be in [0, 1], got " + format_number(canyon_factor));
  }
  if (last_t_ && t < *last_t_) {
    throw std::invalid_argument("GnssModel::measure: time went backwards (" + format_seconds(t) + " s after " +
                                format_seconds(*last_t_) + " s)");
  }

  // Propagate the unit Gauss-Markov state over the elapsed time, outages included, so the bias is
  // continuous in time whatever the caller's sampling.
  if (config_.noise) {
    if (!last_t_) {
      for (int i = 0; i < 3; ++i) unit_state_[i] = normal_(rng_);  // start in the stationary law
    } else {
      const double dt = ns_to_seconds(t - *last_t_);
      const double phi = std::exp(-dt / config_.multipath_tau_s);
      const double q = std::sqrt(1.0 - phi * phi);
      for (int i = 0; i < 3; ++i) unit_state_[i] = phi * unit_state_[i] + q * normal_(rng_);
    }
    bias_enu_ = multipath_sigma_enu(canyon_factor).cwiseProduct(unit_state_);
  }
  last_t_ = t;

  GpsFix fix;
  fix.t = t;
  if (in_outage(t, canyon_factor)) {
    if (!config_.report_no_fix) return std::nullopt;
    constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
    fix.mode = GpsFixMode::kNoFix;
    fix.quality = 0;
    fix.satellites = 0;
    // Receivers repeat the last position with a no-fix flag; io's recording writer requires a
    // valid latitude/longitude on every fix, so never NaN there.
    fix.latitude_deg = last_lat_lon_deg_.x();
    fix.longitude_deg = last_lat_lon_deg_.y();
    fix.altitude_m = fix.geoid_separation_m = kNaN;
    fix.hdop = kNaN;
    fix.covariance_enu = Mat3::Identity() * kNoFixVariance_m2;
    return fix;
  }

  Vec3 p_enu = T_ENU_W * p_W_antenna;
  if (config_.noise) {
    Vec3 white = draw_vector<3>([&] { return normal_(rng_); });
    white.x() *= config_.sigma_horizontal_m;
    white.y() *= config_.sigma_horizontal_m;
    white.z() *= config_.sigma_vertical_m;
    p_enu += white + bias_enu_;
  }
  const Vec3 geo = enu_.to_geodetic(p_enu);
  fix.latitude_deg = geo.x();
  fix.longitude_deg = geo.y();
  last_lat_lon_deg_ = Eigen::Vector2d(geo.x(), geo.y());
  fix.geoid_separation_m = config_.geoid_separation_m;
  fix.altitude_m = geo.z() - config_.geoid_separation_m;  // MSL = ellipsoidal - N
  fix.mode = GpsFixMode::k3D;
  fix.quality = 1;
  fix.satellites = config_.satellites;
  fix.covariance_enu = reported_covariance_enu(canyon_factor);
  fix.hdop = std::sqrt(fix.covariance_enu(0, 0) + fix.covariance_enu(1, 1)) / config_.uere_m;
  return fix;
}

}  // namespace navaid::simulation
