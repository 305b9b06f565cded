// The sliding-window estimator's absolute sensors on simulated feature-level walks: the
// magnetometer yaw factor (estimator.factors.mag) and the two GPS modes (estimator.gps.mode).
// The simulator's world frame is ENU at the recording's origin (T_ENU_W = identity), so ground
// truth poses are ENU poses and the simulated field is m_B = A R_B_ENU m_ENU + b (+ noise).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

#include "navaid/core/errors.hpp"
#include "navaid/core/geodesy.hpp"
#include "navaid/estimation/factors/magnetometer_yaw_factor.hpp"
#include "navaid/estimation/factors/pose_parametrization.hpp"
#include "navaid/estimation/sliding_window_estimator.hpp"
#include "navaid/io/event_stream.hpp"
#include "navaid/io/navaid_recording.hpp"
#include "navaid/simulation/simulator.hpp"
#include "estimator_fixtures.hpp"
#include "test_support.hpp"

namespace navaid::estimation {
namespace {

io::Recording simulate(const std::string& name, const std::vector<std::string>& overrides) {
  return testing::simulate_recording(name, overrides);
}

using SensorsRun = testing::EstimatorRun;

SensorsRun sensors_run(const io::Recording& rec, const std::vector<std::string>& overrides) {
  return testing::run_estimator(rec, overrides, /*flush=*/false);
}

using testing::groundtruth_at;

// Heading error of every estimate after the 4-DOF alignment fixed by the first estimate (the
// estimator's W has yaw 0 at the start): the yaw drift since the start [rad].
std::vector<double> yaw_drift(const std::vector<StateEstimate>& est, const std::vector<GroundTruthState>& gt) {
  std::vector<double> out;
  std::optional<Quat> align;
  for (const auto& s : est) {
    if (s.mode == EstimatorMode::kInitializing) continue;
    const Quat g = groundtruth_at(gt, s.t).q;
    if (!align) align = Quat(Eigen::AngleAxisd(yaw_of(g) - yaw_of(s.T_W_B.q), Vec3::UnitZ()));
    // World-frame rotation error; its yaw is the heading error.
    out.push_back(yaw_of(*align * s.T_W_B.q * g.conjugate()));
  }
  return out;
}

double rms(const std::vector<double>& v, std::size_t from = 0) {
  double sq = 0;
  for (std::size_t i = from; i < v.size(); ++i) sq += v[i] * v[i];
  return std::sqrt(sq / static_cast<double>(v.size() - from));
}

// A long walk with few features and no depth (VIO), where the heading drifts measurably.
const io::Recording& long_walk() {
  static const io::Recording rec =
      simulate("sws_long", {"scenario=lab-walk-1", "mount=hand", "simulation.mode=features", "duration=40", "seed=5",
                            "sensor.camera.rate=10", "features.max_per_frame=20", "features.pixel_sigma=2", "sensor.imu.gyro_random_walk=2e-4", "sensor.gps.enabled=false"});
  return rec;
}

// ---------------------------------------------------------------------------------------------
// Magnetometer.

TEST(SlidingWindowMag, FactorResidualIsZeroAtTheTrueState) {
  // Noise-free samples with hard and soft iron: calibrated with the same iron model, every sample
  // matches the true pose's heading exactly; with a wrong hard iron it does not.
  const std::string hard = "hard_iron=[3e-6, -2e-6, 5e-6]";
  const std::string soft = "soft_iron=[1.1, 0.05, 0, 0.05, 0.9, 0.02, 0, 0.02, 1.0]";
  std::vector<std::string> sim = {"scenario=lab-walk-1", "mount=hand", "simulation.mode=features", "duration=3",
                                  "sensor.camera.rate=5", "features.max_per_frame=5", "sensor.mag.noise=false"};
  sim.insert(sim.end(), {"sensor.mag." + hard, "sensor.mag." + soft});
  const io::Recording rec = simulate("sws_mag_exact", sim);
  ASSERT_GT(rec.mag.size(), 100u);
  const EstimatorConfig right =
      read_estimator_config(Config::parse("{}", "<test>", {"estimator.mag." + hard, "estimator.mag." + soft}));
  const EstimatorConfig wrong = read_estimator_config(Config::parse("{}", "<test>", {"estimator.mag." + soft}));
  const double sigma = magnetometer_yaw_sigma(right.mag_sigma, right.mag_reference_field_enu);
  const double identity_alignment[4] = {0, 0, 0, 0};
  double worst_right = 0, worst_wrong = 0;
  for (const auto& m : rec.mag) {
    double pose[kPoseSize];
    pose_to_block(groundtruth_at(rec.groundtruth, m.t), pose);
    const double* blocks[] = {pose, identity_alignment};
    double r = 0;
    MagnetometerYawFactor(calibrated_mag_field(right, m.field), right.mag_reference_field_enu, sigma)
        .Evaluate(blocks, &r, nullptr);
    worst_right = std::max(worst_right, std::abs(r * sigma));
    MagnetometerYawFactor(calibrated_mag_field(wrong, m.field), wrong.mag_reference_field_enu, sigma)
        .Evaluate(blocks, &r, nullptr);
    worst_wrong = std::max(worst_wrong, std::abs(r * sigma));
  }
  EXPECT_LT(worst_right, 1e-9) << "rad";
  EXPECT_GT(worst_wrong, 0.05) << "rad: the hard iron must matter";
}

TEST(SlidingWindowMag, CalibrationInvertsTheIronModel) {
  const EstimatorConfig c = read_estimator_config(Config::parse(
      "{}", "<test>", {"estimator.mag.hard_iron=[1e-6, 2e-6, 3e-6]", "estimator.mag.soft_iron=[2, 0, 0, 0, 1, 0, 0, 0, 4]"}));
  const Vec3 m = calibrated_mag_field(c, Vec3(3e-6, 5e-6, -5e-6));
  EXPECT_NEAR(m.x(), 1e-6, 1e-18);
  EXPECT_NEAR(m.y(), 3e-6, 1e-18);
  EXPECT_NEAR(m.z(), -2e-6, 1e-18);
}

TEST(SlidingWindowMag, BoundsTheYawDriftOfALongWalk) {
  const auto& rec = long_walk();
  const std::vector<std::string> vio = {"estimator.depth.enabled=false"};
  std::vector<std::string> with_mag = vio;
  with_mag.push_back("estimator.factors.mag=true");
  const SensorsRun off = sensors_run(rec, vio);
  const SensorsRun on = sensors_run(rec, with_mag);
  const auto d_off = yaw_drift(off.estimates, rec.groundtruth);
  const auto d_on = yaw_drift(on.estimates, rec.groundtruth);
  ASSERT_GT(d_off.size(), 200u);
  ASSERT_EQ(d_on.size(), d_off.size());
  // The second half of the walk, where the drift has built up.
  const double rms_off = rms(d_off, d_off.size() / 2), rms_on = rms(d_on, d_on.size() / 2);
  const double end_off = std::abs(d_off.back()), end_on = std::abs(d_on.back());
  EXPECT_LT(rms_on, 0.5 * rms_off) << "yaw drift rms " << rms_on << " rad with the factor, " << rms_off << " without";
  // The sample noise (0.2 uT on a 20 uT horizontal field) is 0.01 rad per sample.
  EXPECT_LT(rms_on, 0.02);
  RecordProperty("yaw_rms_mrad_without", static_cast<int>(std::lround(rms_off * 1e3)));
  RecordProperty("yaw_rms_mrad_with", static_cast<int>(std::lround(rms_on * 1e3)));
  RecordProperty("yaw_end_mrad_without", static_cast<int>(std::lround(end_off * 1e3)));
  RecordProperty("yaw_end_mrad_with", static_cast<int>(std::lround(end_on * 1e3)));
  std::printf("yaw drift (2nd half rms / end): without mag %.4f / %.4f rad, with mag %.4f / %.4f rad\n", rms_off,
              end_off, rms_on, end_on);
  // The yaw covariance of the newest state stays bounded with the factor; without, it grows.
  const double var_on = on.estimates.back().covariance(2, 2), var_off = off.estimates.back().covariance(2, 2);
  EXPECT_LT(var_on, var_off);
}

TEST(SlidingWindowMag, IsDeterministic) {
  const auto& rec = long_walk();
  const io::Recording shortened = [&] {
    io::Recording r = rec;
    const Timestamp end = r.imu.front().t + seconds_to_ns(8.0);
    auto cut = [&](auto& v) {
      v.erase(std::remove_if(v.begin(), v.end(), [&](const auto& x) { return x.t > end; }), v.end());
    };
    cut(r.imu), cut(r.features), cut(r.mag), cut(r.gps);
    return r;
  }();
  const SensorsRun a = sensors_run(shortened, {"estimator.factors.mag=true"});
  const SensorsRun b = sensors_run(shortened, {"estimator.factors.mag=true"});
  ASSERT_EQ(a.estimates.size(), b.estimates.size());
  for (std::size_t i = 0; i < a.estimates.size(); ++i) {
    EXPECT_EQ(a.estimates[i].T_W_B.q.coeffs(), b.estimates[i].T_W_B.q.coeffs());
    EXPECT_EQ(a.estimates[i].T_W_B.t, b.estimates[i].T_W_B.t);
  }
}

TEST(SlidingWindowMag, BadConfigNamesTheKey) {
  for (const auto& [set, key] : std::vector<std::pair<std::string, std::string>>{
           {"estimator.mag.reference_field=[0, 0, -45e-6]", "estimator.mag.reference_field"},
           {"estimator.mag.reference_field=[0, 20, -45]", "estimator.mag.reference_field"},  // microtesla
           {"estimator.mag.reference_field=[0, 20e-6]", "estimator.mag.reference_field"},
           {"estimator.mag.sigma=0", "estimator.mag.sigma"},
           {"estimator.mag.hard_iron=[0, 0, 1]", "estimator.mag.hard_iron"},
           {"estimator.mag.soft_iron=[1, 0, 0, 0, 1, 0, 0, 0, 0]", "estimator.mag.soft_iron"},
           {"estimator.mag.soft_iron=[1, 0.5, 0, 0, 1, 0, 0, 0, 1]", "estimator.mag.soft_iron"},
           {"estimator.mag.max_time_offset=-1", "estimator.mag.max_time_offset"},
           {"estimator.gps.mode=loose", "estimator.gps.mode"},
           {"estimator.gps.registration_fixes=-2", "estimator.gps.registration_fixes"}}) {
    const Config c = Config::parse("{}", "<test>", {set});
    const auto e = navaid::testing::expect_throw<ConfigError>([&] { read_estimator_config(c); }, set);
    if (e) {
      // A bad element of a sequence is named with its index, e.g. "estimator.mag.hard_iron[2]".
      EXPECT_EQ(e->key().rfind(key, 0), 0u) << e->what();
    }
  }
  const EstimatorConfig d = read_estimator_config(Config::parse("{}"));
  EXPECT_FALSE(d.use_mag);
  EXPECT_EQ(d.gps_mode, GpsMode::kJoint);
  EXPECT_EQ(d.gps_registration_fixes, 0);
}

// ---------------------------------------------------------------------------------------------
// GPS modes.

struct EnuErrors {
  double rmse_m = 0;
  std::size_t registered = 0;
};

EnuErrors enu_errors(const std::vector<StateEstimate>& est, const io::Recording& rec) {
  EnuErrors r;
  double sq = 0;
  for (const auto& s : est) {
    if (!s.T_ENU_W) continue;
    EXPECT_TRUE(s.T_ENU_W_covariance.has_value());
    if (s.T_ENU_W_covariance) {
      EXPECT_GT(Eigen::SelfAdjointEigenSolver<Mat4>(*s.T_ENU_W_covariance).eigenvalues().minCoeff(), 0.0);
    }
    sq += ((*s.T_ENU_W * s.T_W_B).t - groundtruth_at(rec.groundtruth, s.t).t).squaredNorm();
    ++r.registered;
  }
  if (r.registered) r.rmse_m = std::sqrt(sq / static_cast<double>(r.registered));
  return r;
}

TEST(SlidingWindowGps, JointAndDecoupledBothPutTheTrackIntoEnu) {
  // route1's first 120 s with GPS (sigma 3 m, urban multipath on; this seed's fixes are off by
  // 13 m RMS), at 5 Hz with 40 features to keep the three runs short.
  const io::Recording rec =
      simulate("sws_gps", {"scenario=route1", "mount=head", "simulation.mode=features", "duration=120", "seed=4",
                           "sensor.camera.rate=5", "features.max_per_frame=40"});
  ASSERT_TRUE(rec.origin.has_value());
  ASSERT_GT(rec.gps.size(), 100u);
  double fix_sq = 0;
  const LocalEnuFrame enu(*rec.origin);
  for (const auto& f : rec.gps) {
    const Vec3 z = enu.to_enu(f.latitude_deg, f.longitude_deg, f.altitude_m + f.geoid_separation_m);
    fix_sq += (z - (groundtruth_at(rec.groundtruth, f.t) * rec.calibration.gps_lever_arm_B)).squaredNorm();
  }
  const double fixes = std::sqrt(fix_sq / static_cast<double>(rec.gps.size()));

  const SensorsRun joint = sensors_run(rec, {"estimator.factors.gps=true"});
  const SensorsRun decoupled = sensors_run(rec, {"estimator.factors.gps=true", "estimator.gps.mode=decoupled"});
  const EnuErrors ej = enu_errors(joint.estimates, rec), ed = enu_errors(decoupled.estimates, rec);
  EXPECT_EQ(joint.stats.gps_registrations, 1u);
  // Decoupled re-registers at (nearly) every fix after the first registration.
  EXPECT_GT(decoupled.stats.gps_registrations, rec.gps.size() / 2);
  for (const EnuErrors* e : {&ej, &ed}) {
    EXPECT_GT(e->registered, joint.estimates.size() / 2) << "registered too late";
    EXPECT_LT(e->rmse_m, fixes) << "fused " << e->rmse_m << " m, fixes " << fixes << " m";
  }
  std::printf("route1 120 s ENU rmse: joint %.3f m, decoupled %.3f m, fixes %.3f m\n", ej.rmse_m, ed.rmse_m, fixes);
  RecordProperty("joint_enu_rmse_cm", static_cast<int>(std::lround(ej.rmse_m * 100)));
  RecordProperty("decoupled_enu_rmse_cm", static_cast<int>(std::lround(ed.rmse_m * 100)));
  RecordProperty("fix_rmse_cm", static_cast<int>(std::lround(fixes * 100)));

  // Decoupled: the VIO window holds no GPS, so the track in W is the one without GPS (on the
  // first 60 s: registered after 51 s).
  io::Recording head = rec;
  const Timestamp end = rec.imu.front().t + seconds_to_ns(60.0);
  auto cut = [&](auto& v) {
    v.erase(std::remove_if(v.begin(), v.end(), [&](const auto& x) { return x.t > end; }), v.end());
  };
  cut(head.imu), cut(head.features), cut(head.mag), cut(head.gps);
  const SensorsRun vio = sensors_run(head, {});
  const SensorsRun decoupled_head = sensors_run(head, {"estimator.factors.gps=true", "estimator.gps.mode=decoupled"});
  ASSERT_EQ(vio.estimates.size(), decoupled_head.estimates.size());
  for (std::size_t i = 0; i < vio.estimates.size(); ++i)
    ASSERT_EQ(vio.estimates[i].T_W_B.t, decoupled_head.estimates[i].T_W_B.t) << i;
  EXPECT_GT(decoupled_head.stats.gps_registrations, 0u);
}

}  // namespace
}  // namespace navaid::estimation
