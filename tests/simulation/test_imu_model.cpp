#include "navaid/simulation/imu_model.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "navaid/core/config.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/simulation/scenario.hpp"
#include "navaid/simulation/simulation_config.hpp"
#include "test_support.hpp"

namespace navaid::simulation {
namespace {

ImuModelOptions noiseless() {
  ImuModelOptions o;
  o.white_noise = false;
  o.bias_walk = false;
  return o;
}

WalkerTrajectory test_walk() {
  return WalkerTrajectory({{0.0, 0.0}, {6.0, 0.0}, {6.0, 4.0}, {1.0, 7.0}});  // full gait + head scan
}

struct NavState {
  Quat q;
  Vec3 v, p;
};

// Classical RK4 on (q, v, p) with q' = q (0, w) / 2, v' = R(q) f + g, p' = v; the IMU values at the
// step start, midpoint and end are consecutive samples (step = 2 sample periods).
NavState integrate(const NavState& x0, const std::vector<ImuSample>& s, std::size_t k_end) {
  struct Deriv {
    Eigen::Vector4d q;
    Vec3 v, p;
  };
  auto f = [](const Eigen::Vector4d& qc, const Vec3& v, const ImuSample& m) {
    const Quat q = Quat(qc).normalized();
    const Quat w(0.0, m.gyro.x(), m.gyro.y(), m.gyro.z());
    return Deriv{0.5 * (Quat(qc) * w).coeffs(), q * m.accel + kGravityW, v};
  };
  Eigen::Vector4d q = x0.q.coeffs();
  Vec3 v = x0.v, p = x0.p;
  for (std::size_t k = 0; k + 2 <= k_end; k += 2) {
    const double h = ns_to_seconds(s[k + 2].t - s[k].t);
    const Deriv k1 = f(q, v, s[k]);
    const Deriv k2 = f(q + 0.5 * h * k1.q, v + 0.5 * h * k1.v, s[k + 1]);
    const Deriv k3 = f(q + 0.5 * h * k2.q, v + 0.5 * h * k2.v, s[k + 1]);
    const Deriv k4 = f(q + h * k3.q, v + h * k3.v, s[k + 2]);
    p += h / 6.0 * (k1.p + 2.0 * k2.p + 2.0 * k3.p + k4.p);
    v += h / 6.0 * (k1.v + 2.0 * k2.v + 2.0 * k3.v + k4.v);
    q += h / 6.0 * (k1.q + 2.0 * k2.q + 2.0 * k3.q + k4.q);
    q.normalize();  // unit norm on every update (DESIGN.md §4)
  }
  return {Quat(q), v, p};
}

TEST(ImuModel, NoiselessImuIntegratesToGroundTruth) {
  const WalkerTrajectory traj = test_walk();
  ImuModel model(navaid::testing::euroc_imu_calibration(1000.0), noiseless());
  const SimulatedImuStream stream = simulate_imu_stream(traj, model, 0.5, 10.5, 123'000'000'000);
  ASSERT_EQ(stream.samples.size(), 10001u);
  ASSERT_EQ(stream.ground_truth.size(), stream.samples.size());
  EXPECT_EQ(stream.samples.front().t, 123'500'000'000);
  EXPECT_EQ(stream.samples.back().t, 133'500'000'000);

  const GroundTruthState& g0 = stream.ground_truth.front();
  const NavState x = integrate({g0.T_W_B.q, *g0.v_W, g0.T_W_B.t}, stream.samples, 10000);
  const GroundTruthState& g1 = stream.ground_truth[10000];
  // Issue acceptance is < 1 mm after 10 s; RK4 on the exact C^4 trajectory gives ~3e-9 m.
  EXPECT_LT((x.p - g1.T_W_B.t).norm(), 1e-6);
  EXPECT_LT((x.v - *g1.v_W).norm(), 1e-4);
  EXPECT_LT(x.q.angularDistance(g1.T_W_B.q), 1e-5);
  EXPECT_GT((g1.T_W_B.t - g0.T_W_B.t).norm(), 5.0);  // it really walked
}

TEST(ImuModel, LeverArmAndRotatedImuIntegrateToImuPose) {
  const WalkerTrajectory traj = test_walk();
  ImuCalibration calib = navaid::testing::euroc_imu_calibration(1000.0);
  calib.T_B_I = SE3(quat_from_rpy(0.1, -0.2, 0.7), Vec3(0.05, -0.08, 0.12));
  ImuModel model(calib, noiseless());
  const SimulatedImuStream stream = simulate_imu_stream(traj, model, 1.0, 6.0);
  const KinematicState b0 = traj.state(1.0);
  const SE3 T0 = b0.T_W_B * calib.T_B_I;
  const Vec3 v0 = b0.v_W + b0.T_W_B.q * b0.omega_B.cross(calib.T_B_I.t);
  const NavState x = integrate({T0.q, v0, T0.t}, stream.samples, 5000);
  const SE3 T1 = stream.ground_truth[5000].T_W_B * calib.T_B_I;
  EXPECT_LT((x.p - T1.t).norm(), 1e-3);
  EXPECT_LT(x.q.angularDistance(T1.q), 1e-5);
}

TEST(ImuModel, StaticLevelImuMeasuresMinusGravity) {
  ImuModel model(navaid::testing::euroc_imu_calibration(200.0), noiseless());
  const ImuSample s = model.measure(KinematicState{}, 0);
  EXPECT_LT((s.accel - Vec3(0, 0, 9.81)).norm(), 1e-12);
  EXPECT_LT(s.gyro.norm(), 1e-15);
}

TEST(ImuModel, AShockAddsItsForceInsideItsIntervalOnly) {
  ImuModelOptions opt = noiseless();
  opt.shocks.push_back({1'000'000'000, 1'050'000'000, Vec3(30, -5, 2)});
  ImuModel model(navaid::testing::euroc_imu_calibration(200.0), opt);
  const Vec3 rest(0, 0, 9.81);
  EXPECT_LT((model.measure(KinematicState{}, 999'999'999).accel - rest).norm(), 1e-12);
  EXPECT_LT((model.measure(KinematicState{}, 1'000'000'000).accel - rest - Vec3(30, -5, 2)).norm(), 1e-12);
  EXPECT_LT((model.measure(KinematicState{}, 1'049'999'999).accel - rest - Vec3(30, -5, 2)).norm(), 1e-12);
  const ImuSample after = model.measure(KinematicState{}, 1'050'000'000);
  EXPECT_LT((after.accel - rest).norm(), 1e-12);
  EXPECT_LT(after.gyro.norm(), 1e-15);  // the gyro is not touched
}

TEST(ImuModel, ShocksAreReadFromTheSimulationConfig) {
  const Scenario scenario = make_scenario("corridor");
  const SimulationConfig c = read_simulation_config(
      Config::parse("{}", "<test>", {"sensor.imu.shocks=[2.0, 0.05, 40, 0, 0, 5.5, 0.1, 0, 0, -30]"}), scenario);
  ASSERT_EQ(c.imu_options.shocks.size(), 2u);
  EXPECT_EQ(c.imu_options.shocks[0].begin, kSimulationEpoch + 2'000'000'000);
  EXPECT_EQ(c.imu_options.shocks[0].end, kSimulationEpoch + 2'050'000'000);
  EXPECT_EQ(c.imu_options.shocks[1].accel_I, Vec3(0, 0, -30));
  for (const char* bad : {"sensor.imu.shocks=[2.0, 0.05, 40, 0]", "sensor.imu.shocks=[2.0, 0, 40, 0, 0]"}) {
    const auto e = testing::expect_throw<ConfigError>(
        [&] { read_simulation_config(Config::parse("{}", "<test>", {bad}), scenario); }, bad);
    if (e) {
      EXPECT_EQ(e->key(), "sensor.imu.shocks");
    }
  }
}

TEST(ImuModel, ScaleAndMisalignmentMultiplyTheTrueSignals) {
  ImuModelOptions opt = noiseless();
  opt.accel_scale_misalignment << 1.01, 0.002, -0.001, 0.0, 0.99, 0.003, 0.001, -0.002, 1.02;
  opt.gyro_scale_misalignment << 0.98, 0.0, 0.004, 0.001, 1.03, 0.0, 0.0, 0.002, 1.0;
  ImuModel model(navaid::testing::euroc_imu_calibration(200.0), opt);
  KinematicState turning;
  turning.omega_B = Vec3(0.1, -0.2, 0.5);
  const ImuSample s = model.measure(turning, 0);
  EXPECT_LT((s.accel - opt.accel_scale_misalignment * Vec3(0, 0, 9.81)).norm(), 1e-12);
  EXPECT_LT((s.gyro - opt.gyro_scale_misalignment * turning.omega_B).norm(), 1e-15);
  ImuModelOptions bad = noiseless();
  bad.accel_scale_misalignment(0, 0) = 9.81;  // a unit mistake, not a scale error
  const auto e = testing::expect_throw<ConfigError>([&] { ImuModel(navaid::testing::euroc_imu_calibration(200.0), bad); });
  ASSERT_TRUE(e);
  EXPECT_EQ(e->key(), "accel_scale_misalignment");
}

TEST(ImuModel, WhiteNoiseStatisticsMatchDensity) {
  const ImuCalibration calib = navaid::testing::euroc_imu_calibration(200.0);
  ImuModelOptions opt;
  opt.seed = 7;
  opt.bias_walk = false;
  opt.initial_gyro_bias = Vec3(0.01, -0.02, 0.03);
  opt.initial_accel_bias = Vec3(-0.1, 0.2, 0.05);
  ImuModel model(calib, opt);
  const int n = 20000;
  Eigen::Matrix<double, 6, 1> sum = Eigen::Matrix<double, 6, 1>::Zero(), sum2 = sum;
  for (int k = 0; k < n; ++k) {
    const ImuSample s = model.measure(KinematicState{}, Timestamp{k} * 5'000'000);
    Eigen::Matrix<double, 6, 1> e;
    e << s.gyro - opt.initial_gyro_bias, s.accel - Vec3(0, 0, 9.81) - opt.initial_accel_bias;
    sum += e;
    sum2 += e.cwiseProduct(e);
  }
  const double sg = calib.gyro_noise_density * std::sqrt(calib.rate_hz);
  const double sa = calib.accel_noise_density * std::sqrt(calib.rate_hz);
  EXPECT_DOUBLE_EQ(model.gyro_noise_sigma(), sg);
  EXPECT_DOUBLE_EQ(model.accel_noise_sigma(), sa);
  for (int i = 0; i < 6; ++i) {
    const double sigma = i < 3 ? sg : sa;
    const double mean = sum(i) / n;
    const double sd = std::sqrt(sum2(i) / n - mean * mean);
    EXPECT_LT(std::abs(mean), 5.0 * sigma / std::sqrt(n)) << "axis " << i;
    EXPECT_NEAR(sd / sigma, 1.0, 0.03) << "axis " << i;  // sampling sd of sd ~ 1/sqrt(2n) = 0.5%
  }
  // Biases stay put without the random walk.
  EXPECT_EQ(model.gyro_bias(), opt.initial_gyro_bias);
  EXPECT_EQ(model.accel_bias(), opt.initial_accel_bias);
}

TEST(ImuModel, BiasRandomWalkVarianceGrowsAsRwSquaredTimesT) {
  const ImuCalibration calib = navaid::testing::euroc_imu_calibration(100.0);
  const int runs = 500, steps = 200;  // T = 2 s
  const double T = steps / calib.rate_hz;
  double g2 = 0.0, a2 = 0.0;
  for (int r = 0; r < runs; ++r) {
    ImuModelOptions opt;
    opt.seed = 1000 + static_cast<std::uint64_t>(r);
    opt.white_noise = false;
    ImuModel model(calib, opt);
    for (int k = 0; k <= steps; ++k) model.measure(KinematicState{}, Timestamp{k} * 10'000'000);
    g2 += model.gyro_bias().squaredNorm();
    a2 += model.accel_bias().squaredNorm();
  }
  // 1500 squared zero-mean gaussians: relative sd of the variance estimate sqrt(2/1500) = 3.7%.
  EXPECT_NEAR(g2 / (3 * runs) / (calib.gyro_random_walk * calib.gyro_random_walk * T), 1.0, 0.15);
  EXPECT_NEAR(a2 / (3 * runs) / (calib.accel_random_walk * calib.accel_random_walk * T), 1.0, 0.15);
}

TEST(ImuModel, SameSeedSameStreamDifferentSeedDifferent) {
  const WalkerTrajectory traj = test_walk();
  auto run = [&](std::uint64_t seed) {
    ImuModelOptions opt;
    opt.seed = seed;
    ImuModel model(navaid::testing::euroc_imu_calibration(200.0), opt);
    return simulate_imu_stream(traj, model, 0.0, 2.0);
  };
  const SimulatedImuStream a = run(42), b = run(42), c = run(43);
  ASSERT_EQ(a.samples.size(), 401u);
  bool any_diff = false;
  for (std::size_t k = 0; k < a.samples.size(); ++k) {
    EXPECT_EQ(a.samples[k].t, b.samples[k].t);
    EXPECT_EQ(a.samples[k].gyro, b.samples[k].gyro);
    EXPECT_EQ(a.samples[k].accel, b.samples[k].accel);
    EXPECT_EQ(*a.ground_truth[k].b_g, *b.ground_truth[k].b_g);
    any_diff = any_diff || a.samples[k].gyro != c.samples[k].gyro || a.samples[k].accel != c.samples[k].accel;
  }
  EXPECT_TRUE(any_diff);
  EXPECT_NE(*a.ground_truth.back().b_a, *c.ground_truth.back().b_a);
}

TEST(ImuModel, RejectsBadCalibrationAndBackwardTime) {
  EXPECT_THROW(ImuModel(navaid::testing::euroc_imu_calibration(0.0)), ConfigError);
  ImuCalibration c = navaid::testing::euroc_imu_calibration(100.0);
  c.accel_noise_density = -1.0;
  EXPECT_THROW(ImuModel{c}, ConfigError);
  ImuModel model(navaid::testing::euroc_imu_calibration(100.0));
  model.measure(KinematicState{}, 1000);
  EXPECT_THROW(model.measure(KinematicState{}, 999), std::invalid_argument);
}

}  // namespace
}  // namespace navaid::simulation
