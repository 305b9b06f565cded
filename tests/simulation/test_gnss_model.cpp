#include "navaid/simulation/gnss_model.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <vector>

#include "navaid/core/errors.hpp"
#include "navaid/core/geodesy.hpp"

namespace navaid::simulation {
namespace {

const GeodeticOrigin kOrigin{48.137, 11.575, 560.0};

SE3 yaw_pose(double yaw, const Vec3& t) { return SE3(quat_from_rpy(0.0, 0.0, yaw), t); }

// Position error of a fix in ENU [m] with respect to the true ENU position.
Vec3 enu_error(const GnssModel& m, const GpsFix& f, const Vec3& truth_enu) {
  return m.enu_frame().to_enu(f.latitude_deg, f.longitude_deg, f.altitude_m + f.geoid_separation_m) - truth_enu;
}

// Draws n fixes at a fixed point every dt and returns their ENU errors.
std::vector<Vec3> errors(GnssModel& m, int n, Duration dt, double canyon = 0.0) {
  std::vector<Vec3> out;
  out.reserve(static_cast<std::size_t>(n));
  const SE3 T_ENU_W = yaw_pose(0.3, Vec3(5.0, -7.0, 1.0));
  const Vec3 p_W(12.0, 3.0, 1.5);
  for (int k = 0; k < n; ++k) {
    const auto fix = m.measure(k * dt, p_W, T_ENU_W, canyon);
    EXPECT_TRUE(fix.has_value());
    out.push_back(enu_error(m, *fix, T_ENU_W * p_W));
  }
  return out;
}

Vec3 sample_variance(const std::vector<Vec3>& e) {
  Vec3 mean = Vec3::Zero();
  for (const auto& v : e) mean += v;
  mean /= static_cast<double>(e.size());
  Vec3 var = Vec3::Zero();
  for (const auto& v : e) var += (v - mean).cwiseAbs2();
  return var / static_cast<double>(e.size() - 1);
}

TEST(GnssModel, NoiselessFixIsTheTruth) {
  GnssModelConfig c;
  c.noise = false;
  c.geoid_separation_m = 47.5;
  GnssModel m(c, kOrigin);
  const SE3 T_ENU_W = yaw_pose(0.7, Vec3(100.0, -50.0, 2.0));
  const Vec3 p_W(30.0, 40.0, 1.5);
  const auto fix = m.measure(seconds_to_ns(3.0), p_W, T_ENU_W);
  ASSERT_TRUE(fix);
  EXPECT_EQ(fix->t, seconds_to_ns(3.0));
  EXPECT_EQ(fix->mode, GpsFixMode::k3D);

  const LocalEnuFrame enu(kOrigin);  // independent frame at the same origin
  const Vec3 p_ENU = T_ENU_W * p_W;
  const Vec3 geo = enu.to_geodetic(p_ENU);
  EXPECT_NEAR(fix->latitude_deg, geo.x(), 1e-9);
  EXPECT_NEAR(fix->longitude_deg, geo.y(), 1e-9);
  EXPECT_NEAR(fix->altitude_m, geo.z() - 47.5, 1e-6);  // MSL = ellipsoidal - N
  EXPECT_DOUBLE_EQ(fix->geoid_separation_m, 47.5);
  ASSERT_TRUE(ellipsoidal_height_m(*fix));
  EXPECT_NEAR(*ellipsoidal_height_m(*fix), geo.z(), 1e-6);
  // Back to ENU: the round trip closes to well below a millimetre.
  EXPECT_LT((enu.to_enu(fix->latitude_deg, fix->longitude_deg, *ellipsoidal_height_m(*fix)) - p_ENU).norm(), 1e-6);

  // At the origin itself the fix is the origin.
  const auto at_origin = m.measure(seconds_to_ns(4.0), Vec3::Zero(), SE3::identity());
  ASSERT_TRUE(at_origin);
  EXPECT_NEAR(at_origin->latitude_deg, kOrigin.latitude_deg, 1e-9);
  EXPECT_NEAR(at_origin->longitude_deg, kOrigin.longitude_deg, 1e-9);
  EXPECT_NEAR(at_origin->altitude_m + at_origin->geoid_separation_m, kOrigin.height_m, 1e-6);
  EXPECT_EQ(m.multipath_bias_enu(), Vec3::Zero());
}

TEST(GnssModel, WhiteNoiseMatchesConfiguredSigma) {
  GnssModelConfig c;
  c.sigma_horizontal_m = 3.0;
  c.sigma_vertical_m = 5.0;
  c.multipath_sigma_horizontal_m = 0.0;
  c.multipath_sigma_vertical_m = 0.0;
  c.seed = 7;
  GnssModel m(c, kOrigin);
  const auto e = errors(m, 20000, kNanosecondsPerSecond);
  const Vec3 var = sample_variance(e);
  // Relative standard error of a sample sigma is 1/sqrt(2n) = 0.5%; allow 3%.
  EXPECT_NEAR(std::sqrt(var.x()), 3.0, 0.09);
  EXPECT_NEAR(std::sqrt(var.y()), 3.0, 0.09);
  EXPECT_NEAR(std::sqrt(var.z()), 5.0, 0.15);
  Vec3 mean = Vec3::Zero();
  for (const auto& v : e) mean += v;
  mean /= static_cast<double>(e.size());
  EXPECT_LT(std::abs(mean.x()), 0.1);  // 4.7 standard errors
  EXPECT_LT(std::abs(mean.z()), 0.17);
}

TEST(GnssModel, GaussMarkovStationaryVarianceAndAutocorrelation) {
  GnssModelConfig c;
  c.sigma_horizontal_m = 0.0;
  c.sigma_vertical_m = 0.0;
  c.multipath_sigma_horizontal_m = 2.0;
  c.multipath_sigma_vertical_m = 2.0;
  c.multipath_tau_s = 2.0;
  c.seed = 11;
  GnssModel m(c, kOrigin);
  const int n = 20000;
  const auto e = errors(m, n, kNanosecondsPerSecond);
  const double phi = std::exp(-1.0 / 2.0);
  // Pool the three independent axes.
  double var = 0.0, lag1 = 0.0;
  for (int axis = 0; axis < 3; ++axis) {
    for (int k = 0; k < n; ++k) var += e[static_cast<std::size_t>(k)][axis] * e[static_cast<std::size_t>(k)][axis];
    for (int k = 1; k < n; ++k)
      lag1 += e[static_cast<std::size_t>(k)][axis] * e[static_cast<std::size_t>(k - 1)][axis];
  }
  const double rho = lag1 / var;
  var /= 3.0 * n;
  // Effective sample size ~ 3 n (1 - phi) / (1 + phi) ~ 15000: variance within ~1.2% (1 SE).
  EXPECT_NEAR(var, 4.0, 4.0 * 0.06);
  // SE of the lag-1 estimate ~ sqrt((1 - phi^2) / 3n) ~ 0.0035.
  EXPECT_NEAR(rho, phi, 0.02);
  // The bias is what the fix carries.
  EXPECT_LT((e.back() - m.multipath_bias_enu()).norm(), 1e-6);
}

TEST(GnssModel, GaussMarkovFollowsElapsedTime) {
  GnssModelConfig c;
  c.multipath_tau_s = 5.0;
  c.seed = 2;
  GnssModel m(c, kOrigin);
  ASSERT_TRUE(m.measure(seconds_to_ns(1.0), Vec3::Zero(), SE3::identity()));
  const Vec3 b0 = m.multipath_bias_enu();
  EXPECT_GT(b0.norm(), 0.0);
  // No elapsed time: phi = 1, q = 0, the bias is unchanged.
  ASSERT_TRUE(m.measure(seconds_to_ns(1.0), Vec3::Zero(), SE3::identity()));
  EXPECT_EQ(m.multipath_bias_enu(), b0);
  // Any elapsed time moves it.
  ASSERT_TRUE(m.measure(seconds_to_ns(1.1), Vec3::Zero(), SE3::identity()));
  EXPECT_NE(m.multipath_bias_enu(), b0);
}

TEST(GnssModel, MultipathGrowsWithCanyonFactor) {
  GnssModelConfig c;
  c.sigma_horizontal_m = 0.0;
  c.sigma_vertical_m = 0.0;
  c.canyon_gain = 3.0;
  c.seed = 5;
  GnssModel open(c, kOrigin), canyon(c, kOrigin);
  EXPECT_TRUE(canyon.multipath_sigma_enu(1.0).isApprox(4.0 * open.multipath_sigma_enu(0.0)));
  EXPECT_TRUE(canyon.multipath_sigma_enu(0.5).isApprox(2.5 * open.multipath_sigma_enu(0.0)));
  const auto e_open = errors(open, 4000, kNanosecondsPerSecond, 0.0);
  const auto e_canyon = errors(canyon, 4000, kNanosecondsPerSecond, 1.0);
  // Same seed, same unit state: the canyon bias is exactly (1 + k) times the open-sky one.
  for (std::size_t k = 0; k < e_open.size(); k += 97) {
    EXPECT_LT((e_canyon[k] - 4.0 * e_open[k]).norm(), 1e-5) << k;
  }
  const Vec3 ratio = (sample_variance(e_canyon).cwiseQuotient(sample_variance(e_open))).cwiseSqrt();
  EXPECT_NEAR(ratio.x(), 4.0, 1e-6);
  // Reported uncertainty grows too.
  EXPECT_GT(canyon.reported_covariance_enu(1.0)(0, 0), open.reported_covariance_enu(0.0)(0, 0));
}

TEST(GnssModel, ReportedCovarianceAndHdopMatchInjectedNoise) {
  GnssModelConfig c;
  c.sigma_horizontal_m = 3.0;
  c.sigma_vertical_m = 5.0;
  c.multipath_sigma_horizontal_m = 1.5;
  c.multipath_sigma_vertical_m = 2.5;
  c.multipath_tau_s = 0.1;  // 1 s apart: phi = exp(-10), fixes nearly independent
  c.canyon_gain = 2.0;
  c.uere_m = 5.0;
  c.seed = 3;
  GnssModel m(c, kOrigin);
  const double f = 0.5;
  const auto e = errors(m, 20000, kNanosecondsPerSecond, f);
  const double mp_h = 1.5 * 2.0, mp_v = 2.5 * 2.0;  // sigma_mp (1 + k f)
  const Mat3 expected = Vec3(9.0 + mp_h * mp_h, 9.0 + mp_h * mp_h, 25.0 + mp_v * mp_v).asDiagonal();
  const Mat3 reported = m.reported_covariance_enu(f);
  EXPECT_TRUE(reported.isApprox(expected, 1e-12));
  const Vec3 var = sample_variance(e);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(var[i] / reported(i, i), 1.0, 0.06) << i;

  const auto fix = m.measure(seconds_to_ns(1e5), Vec3::Zero(), SE3::identity(), f);
  ASSERT_TRUE(fix);
  EXPECT_TRUE(fix->covariance_enu.isApprox(expected, 1e-12));
  // HDOP * UERE is the horizontal sigma (io's NMEA convention).
  EXPECT_NEAR(fix->hdop * c.uere_m, std::sqrt(expected(0, 0) + expected(1, 1)), 1e-12);
  EXPECT_EQ(fix->satellites, c.satellites);
  EXPECT_EQ(fix->quality, 1);
}

TEST(GnssModel, OutageIntervalsYieldNoFix) {
  GnssModelConfig c;
  c.outages = {{seconds_to_ns(10.0), seconds_to_ns(20.0)}, {seconds_to_ns(25.5), seconds_to_ns(26.5)}};
  GnssModel m(c, kOrigin);
  for (int k = 0; k <= 30; ++k) {
    const auto fix = m.measure(k * m.period(), Vec3::Zero(), SE3::identity());
    const bool outage = (k >= 10 && k < 20) || k == 26;
    EXPECT_EQ(fix.has_value(), !outage) << "t = " << k << " s";
  }
}

TEST(GnssModel, CanyonThresholdOutageAndNoFixReports) {
  GnssModelConfig c;
  c.outage_canyon_factor = 0.7;
  c.report_no_fix = true;
  c.noise = false;
  GnssModel m(c, kOrigin);
  const Vec3 p(3.0, 4.0, 0.0);
  const auto ok = m.measure(0, p, SE3::identity(), 0.69);
  ASSERT_TRUE(ok);
  EXPECT_EQ(ok->mode, GpsFixMode::k3D);
  const auto none = m.measure(kNanosecondsPerSecond, p, SE3::identity(), 0.7);
  ASSERT_TRUE(none);
  EXPECT_EQ(none->mode, GpsFixMode::kNoFix);
  EXPECT_EQ(none->quality, 0);
  EXPECT_FALSE(ellipsoidal_height_m(*none));
  EXPECT_DOUBLE_EQ(none->latitude_deg, ok->latitude_deg);  // last known position repeated
  EXPECT_DOUBLE_EQ(none->covariance_enu(0, 0), kNoFixVariance_m2);
  EXPECT_TRUE(m.in_outage(0, 1.0));
  EXPECT_FALSE(m.in_outage(0, 0.0));

  c.report_no_fix = false;
  GnssModel silent(c, kOrigin);
  EXPECT_FALSE(silent.measure(0, p, SE3::identity(), 0.9));
}

TEST(GnssModel, DeterministicBySeed) {
  GnssModelConfig c;
  c.seed = 42;
  GnssModel a(c, kOrigin), b(c, kOrigin);
  c.seed = 43;
  GnssModel other(c, kOrigin);
  bool differs = false;
  for (int k = 0; k < 50; ++k) {
    const Vec3 p(k * 1.0, 0.5 * k, 0.0);
    const auto fa = a.measure(k * a.period(), p, SE3::identity(), 0.3);
    const auto fb = b.measure(k * b.period(), p, SE3::identity(), 0.3);
    const auto fo = other.measure(k * other.period(), p, SE3::identity(), 0.3);
    ASSERT_TRUE(fa && fb && fo);
    EXPECT_EQ(fa->latitude_deg, fb->latitude_deg);
    EXPECT_EQ(fa->longitude_deg, fb->longitude_deg);
    EXPECT_EQ(fa->altitude_m, fb->altitude_m);
    differs = differs || fa->latitude_deg != fo->latitude_deg;
  }
  EXPECT_TRUE(differs);
}

TEST(GnssModel, RateAndCallerErrors) {
  GnssModelConfig c;
  c.rate_hz = 10.0;
  GnssModel m(c, kOrigin);
  EXPECT_EQ(m.period(), 100'000'000);
  EXPECT_THROW(m.measure(0, Vec3::Zero(), SE3::identity(), 1.5), std::invalid_argument);
  ASSERT_TRUE(m.measure(10, Vec3::Zero(), SE3::identity()));
  EXPECT_THROW(m.measure(5, Vec3::Zero(), SE3::identity()), std::invalid_argument);
}

TEST(GnssModel, BadConfigNamesTheKey) {
  struct Case {
    std::function<void(GnssModelConfig&)> mutate;
    std::string key;
  };
  const std::vector<Case> cases = {
      {[](GnssModelConfig& c) { c.rate_hz = 0.5; }, "rate_hz"},
      {[](GnssModelConfig& c) { c.rate_hz = 20.0; }, "rate_hz"},
      {[](GnssModelConfig& c) { c.sigma_horizontal_m = -1.0; }, "sigma_horizontal_m"},
      {[](GnssModelConfig& c) { c.sigma_vertical_m = std::nan(""); }, "sigma_vertical_m"},
      {[](GnssModelConfig& c) { c.multipath_tau_s = 0.0; }, "multipath_tau_s"},
      {[](GnssModelConfig& c) { c.multipath_sigma_horizontal_m = -0.1; }, "multipath_sigma_horizontal_m"},
      {[](GnssModelConfig& c) { c.multipath_sigma_vertical_m = INFINITY; }, "multipath_sigma_vertical_m"},
      {[](GnssModelConfig& c) { c.canyon_gain = -1.0; }, "canyon_gain"},
      {[](GnssModelConfig& c) { c.outages = {{0, 5}, {7, 7}}; }, "outages[1]"},
      {[](GnssModelConfig& c) { c.outage_canyon_factor = 1.2; }, "outage_canyon_factor"},
      {[](GnssModelConfig& c) { c.geoid_separation_m = 500.0; }, "geoid_separation_m"},
      {[](GnssModelConfig& c) { c.uere_m = 0.0; }, "uere_m"},
      {[](GnssModelConfig& c) { c.satellites = 2; }, "satellites"},
  };
  for (const auto& k : cases) {
    GnssModelConfig c;
    k.mutate(c);
    try {
      GnssModel m(c, kOrigin);
      ADD_FAILURE() << "no ConfigError for " << k.key;
    } catch (const ConfigError& e) {
      EXPECT_EQ(e.key(), k.key) << e.what();
      EXPECT_NE(std::string(e.what()).find(k.key), std::string::npos);
    }
  }
  EXPECT_NO_THROW(validate(GnssModelConfig{}));
}

}  // namespace
}  // namespace navaid::simulation
