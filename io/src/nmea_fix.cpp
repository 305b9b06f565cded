// NMEA epochs -> GpsFix: fix values, quality and the ENU position covariance.
#include <cmath>
#include <limits>

#include "navaid/io/nmea.hpp"
#include "nmea_detail.hpp"

namespace navaid::io {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Receivers send 99.9/99.99 as "DOP unknown" (BT-451 and others).
std::optional<double> usable_dop(const std::optional<double>& dop) {
  if (dop && *dop > 0.0 && *dop < 99.0) return dop;
  return std::nullopt;
}

std::optional<double> usable_sd(const std::optional<double>& sd) {
  // 0 means the receiver does not estimate it: a zero variance would claim a perfect fix.
  if (sd && *sd > 0.0) return sd;
  return std::nullopt;
}

std::optional<double> epoch_hdop(const NmeaEpoch& e) {
  if (e.gga) {
    if (auto h = usable_dop(e.gga->hdop)) return h;
  }
  for (const auto& g : e.gsa) {
    if (auto h = usable_dop(g.hdop)) return h;
  }
  return std::nullopt;
}

std::optional<double> epoch_vdop(const NmeaEpoch& e) {
  for (const auto& g : e.gsa) {
    if (auto v = usable_dop(g.vdop)) return v;
  }
  return std::nullopt;
}

// GGA quality, or its equivalent from RMC's status and FAA mode when there is no GGA.
int epoch_quality(const NmeaEpoch& e) {
  if (e.gga && e.gga->quality) return *e.gga->quality;
  if (e.rmc) {
    const char mode = e.rmc->mode_indicator.value_or(' ');
    if (mode == 'R') return 4;
    if (mode == 'F') return 5;
    if (mode == 'D' || e.rmc->status == 'D') return 2;
  }
  return 1;
}

double uere_m(int quality, const NmeaOptions& o) {
  switch (quality) {
    case 2: return o.uere_differential_m;
    case 4: return o.uere_rtk_fixed_m;
    case 5: return o.uere_rtk_float_m;
    default: return o.uere_autonomous_m;
  }
}

bool has_altitude(const NmeaEpoch& e) {
  return e.mode == GpsFixMode::k3D && e.gga && e.gga->altitude_msl_m.has_value();
}

}  // namespace

Mat3 nmea_covariance_enu(const NmeaEpoch& e, const NmeaOptions& o) {
  Mat3 cov = Mat3::Zero();
  const double uere = uere_m(epoch_quality(e), o);
  const auto hdop = epoch_hdop(e);

  const std::optional<double> lat_sd = e.gst ? usable_sd(e.gst->latitude_sd_m) : std::nullopt;
  const std::optional<double> lon_sd = e.gst ? usable_sd(e.gst->longitude_sd_m) : std::nullopt;
  if (lat_sd && lon_sd) {
    cov(0, 0) = *lon_sd * *lon_sd;
    cov(1, 1) = *lat_sd * *lat_sd;
    // The error ellipse adds the east-north correlation, but only when it describes the same
    // error as the lat/lon deviations (a^2 + b^2 = lat^2 + lon^2): several receivers fill the
    // ellipse fields with unrelated values (skytraq, u-blox M9N captures).
    const auto a = e.gst->semi_major_sd_m, b = e.gst->semi_minor_sd_m, theta = e.gst->semi_major_orientation_rad;
    if (a && b && theta) {
      const double ellipse = *a * *a + *b * *b;
      const double axes = cov(0, 0) + cov(1, 1);
      if (ellipse > 0.0 && std::abs(ellipse - axes) <= 0.1 * axes) {
        const double s = std::sin(*theta), c = std::cos(*theta);
        // Semi-major axis along (east, north) = (sin, cos) of the azimuth.
        const double ee = *a * *a * s * s + *b * *b * c * c;
        const double nn = *a * *a * c * c + *b * *b * s * s;
        const double en = (*a * *a - *b * *b) * s * c;
        double rho = ee > 0.0 && nn > 0.0 ? en / std::sqrt(ee * nn) : 0.0;
        rho = std::max(-1.0, std::min(1.0, rho));
        cov(0, 1) = cov(1, 0) = rho * *lon_sd * *lat_sd;
      }
    }
  } else if (hdop) {
    // HDOP^2 = (q_EE + q_NN) / sigma^2: the horizontal variance splits evenly over east and north.
    const double horizontal = (*hdop * uere) * (*hdop * uere);
    cov(0, 0) = cov(1, 1) = horizontal / 2.0;
  } else {
    cov(0, 0) = cov(1, 1) = o.unknown_horizontal_sd_m * o.unknown_horizontal_sd_m;
  }

  const std::optional<double> alt_sd = e.gst ? usable_sd(e.gst->altitude_sd_m) : std::nullopt;
  const auto vdop = epoch_vdop(e);
  double vertical_sd = o.unknown_vertical_sd_m;
  if (has_altitude(e)) {
    if (alt_sd) {
      vertical_sd = *alt_sd;
    } else if (vdop) {
      vertical_sd = *vdop * uere;
    } else if (hdop) {
      vertical_sd = o.vdop_per_hdop * *hdop * uere;
    } else {
      vertical_sd = o.vdop_per_hdop * o.unknown_horizontal_sd_m;
    }
  }
  cov(2, 2) = vertical_sd * vertical_sd;
  return cov;
}

std::optional<GpsFix> to_gps_fix(const NmeaEpoch& e, const NmeaOptions& o) {
  if (!e.has_position() || !e.t || !e.latitude_deg || !e.longitude_deg) return std::nullopt;
  GpsFix fix;
  fix.t = *e.t;
  fix.latitude_deg = *e.latitude_deg;
  fix.longitude_deg = *e.longitude_deg;
  fix.altitude_m = has_altitude(e) ? *e.gga->altitude_msl_m : kNaN;
  fix.geoid_separation_m = e.gga && e.gga->geoid_separation_m ? *e.gga->geoid_separation_m : kNaN;
  fix.mode = e.mode;
  fix.quality = epoch_quality(e);
  if (e.gga && e.gga->satellites) {
    fix.satellites = *e.gga->satellites;
  } else if (!e.gsa.empty()) {
    int used = 0;
    for (const auto& g : e.gsa) used += static_cast<int>(g.satellites_used.size());
    fix.satellites = used;
  } else {
    fix.satellites = -1;
  }
  fix.hdop = epoch_hdop(e).value_or(kNaN);
  fix.covariance_enu = nmea_covariance_enu(e, o);
  return fix;
}

std::vector<GpsFix> nmea_fixes(const std::vector<NmeaEpoch>& epochs, const NmeaOptions& options,
                               const std::string& source, DataReport* report) {
  nmea_detail::Warnings warnings(source, report, 10);
  std::vector<GpsFix> fixes;
  fixes.reserve(epochs.size());
  for (const auto& e : epochs) {
    if (!e.has_position()) {
      if (report) report->warn(source, "epochs without a position fix (receiver reported no fix) skipped");
      continue;
    }
    auto fix = to_gps_fix(e, options);
    if (!fix) {
      if (report) report->warn(source, "epochs with a fix but no known date (no RMC/ZDA date in the stream) skipped");
      continue;
    }
    if (!fixes.empty() && fix->t <= fixes.back().t) {
      warnings.warn("time not increasing", e.first_line,
                    "fix time " + format_seconds(fix->t) + " s is not after the previous fix (" +
                        format_seconds(fixes.back().t) + " s); skipped");
      continue;
    }
    fixes.push_back(std::move(*fix));
  }
  return fixes;
}

}  // namespace navaid::io
