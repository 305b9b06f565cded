#include "navaid/estimation/imu_preintegration.hpp"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>

#include <cmath>
#include <utility>
#include <vector>

#include "navaid/core/errors.hpp"
#include "navaid/simulation/imu_model.hpp"
#include "navaid/simulation/walker_trajectory.hpp"
#include "test_support.hpp"

namespace navaid::estimation {
namespace {

using simulation::ImuModel;
using simulation::ImuModelOptions;
using simulation::KinematicState;
using simulation::WalkerTrajectory;

ImuModelOptions noiseless(const Vec3& b_g = Vec3::Zero(), const Vec3& b_a = Vec3::Zero()) {
  ImuModelOptions o;
  o.white_noise = false;
  o.bias_walk = false;
  o.initial_gyro_bias = b_g;
  o.initial_accel_bias = b_a;
  return o;
}

WalkerTrajectory test_walk() {
  return WalkerTrajectory({{0.0, 0.0}, {6.0, 0.0}, {6.0, 4.0}, {1.0, 7.0}});  // full gait + head scan
}

std::vector<ImuSample> stream(const WalkerTrajectory& traj, double rate_hz, double t0, double t1,
                              const ImuModelOptions& options) {
  ImuModel model(navaid::testing::euroc_imu_calibration(rate_hz), options);
  return simulation::simulate_imu_stream(traj, model, t0, t1).samples;
}

struct PredictionError {
  double position, velocity, rotation;
};

// Preintegrates [t_i, t_j] at bias (b_g, b_a) and compares the predicted state j with the truth.
PredictionError prediction_error(const WalkerTrajectory& traj, const std::vector<ImuSample>& samples, double t_i,
                                 double t_j, const Vec3& b_g = Vec3::Zero(), const Vec3& b_a = Vec3::Zero()) {
  const ImuPreintegration pre = ImuPreintegration::between(samples, seconds_to_ns(t_i), seconds_to_ns(t_j),
                                                           ImuNoise::from(navaid::testing::euroc_imu_calibration(200.0)), b_g, b_a);
  const KinematicState si = traj.state(t_i), sj = traj.state(t_j);
  SE3 T_j;
  Vec3 v_j;
  pre.predict(si.T_W_B, si.v_W, b_g, b_a, &T_j, &v_j);
  return {(T_j.t - sj.T_W_B.t).norm(), (v_j - sj.v_W).norm(), T_j.q.angularDistance(sj.T_W_B.q)};
}

TEST(ImuSamplesBetween, KeepsGridSamplesAndInterpolatesStraddlingEnds) {
  std::vector<ImuSample> s(5);
  for (int k = 0; k < 5; ++k) {
    s[k].t = 100 * k;
    s[k].gyro = Vec3(k, 2.0 * k, -k);
    s[k].accel = Vec3(10.0 + k, 0.0, 3.0 * k);
  }
  const std::vector<ImuSample> a = imu_samples_between(s, 150, 325);
  ASSERT_EQ(a.size(), 4u);  // 150 (interpolated), 200, 300, 325 (interpolated)
  EXPECT_EQ(a[0].t, 150);
  EXPECT_TRUE(a[0].gyro.isApprox(Vec3(1.5, 3.0, -1.5)));
  EXPECT_TRUE(a[0].accel.isApprox(Vec3(11.5, 0.0, 4.5)));
  EXPECT_EQ(a[1].t, 200);
  EXPECT_EQ(a[2].t, 300);
  EXPECT_EQ(a[3].t, 325);
  EXPECT_TRUE(a[3].gyro.isApprox(Vec3(3.25, 6.5, -3.25)));

  const std::vector<ImuSample> b = imu_samples_between(s, 100, 300);  // ends on the grid
  ASSERT_EQ(b.size(), 3u);
  EXPECT_EQ(b.front().gyro, s[1].gyro);
  EXPECT_EQ(b.back().accel, s[3].accel);

  const std::vector<ImuSample> c = imu_samples_between(s, 110, 190);  // both ends in one gap
  ASSERT_EQ(c.size(), 2u);
  EXPECT_TRUE(c[1].gyro.isApprox(Vec3(1.9, 3.8, -1.9)));

  EXPECT_THROW(imu_samples_between(s, 300, 300), Error);
  EXPECT_THROW(imu_samples_between(s, -1, 300), Error);   // not covered
  EXPECT_THROW(imu_samples_between(s, 100, 401), Error);
  std::vector<ImuSample> bad = s;
  bad[3].t = bad[2].t;
  EXPECT_THROW(imu_samples_between(bad, 0, 400), Error);  // not strictly increasing
  bad = s;
  bad[2].has_gyro = false;
  EXPECT_THROW(imu_samples_between(bad, 0, 400), Error);
}

TEST(ImuPreintegration, NoiselessWalkReproducesRelativeMotion) {
  const WalkerTrajectory traj = test_walk();
  const std::vector<ImuSample> samples = stream(traj, 400.0, 0.0, 9.0, noiseless());
  // Keyframe times off the IMU grid (interpolated ends); 1 s and 5 s windows while walking
  // (gait bob, sway and head scan). What remains is the O(h^2) mid-point error (measured at
  // 400 Hz: 2.4e-5 m, 1.3e-5 m/s, 5.6e-7 rad over 1 s; 7.4e-5 m, 2.2e-5 m/s, 1.9e-6 rad over 5 s).
  const PredictionError e1 = prediction_error(traj, samples, 2.0013, 3.0013);
  EXPECT_LT(e1.position, 5e-5);
  EXPECT_LT(e1.velocity, 3e-5);
  EXPECT_LT(e1.rotation, 1.5e-6);
  const PredictionError e5 = prediction_error(traj, samples, 1.5021, 6.5021);
  EXPECT_LT(e5.position, 1.5e-4);
  EXPECT_LT(e5.velocity, 5e-5);
  EXPECT_LT(e5.rotation, 4e-6);
}

TEST(ImuPreintegration, ConstantBiasesAreRemoved) {
  const WalkerTrajectory traj = test_walk();
  const Vec3 b_g(0.02, -0.015, 0.01), b_a(-0.2, 0.1, 0.3);
  const std::vector<ImuSample> samples = stream(traj, 400.0, 0.0, 5.0, noiseless(b_g, b_a));
  const PredictionError with = prediction_error(traj, samples, 1.2, 4.2, b_g, b_a);
  EXPECT_LT(with.position, 1e-4);
  EXPECT_LT(with.rotation, 5e-6);
  const PredictionError without = prediction_error(traj, samples, 1.2, 4.2);
  EXPECT_GT(without.position, 1.0);  // 0.3 m/s^2 over 3 s would be > 1 m
}

TEST(ImuPreintegration, MidPointErrorIsSecondOrderInTheStep) {
  const WalkerTrajectory traj = test_walk();
  const PredictionError coarse = prediction_error(traj, stream(traj, 100.0, 0.0, 6.0, noiseless()), 1.0, 5.0);
  const PredictionError fine = prediction_error(traj, stream(traj, 200.0, 0.0, 6.0, noiseless()), 1.0, 5.0);
  EXPECT_NEAR(coarse.position / fine.position, 4.0, 0.6);
  EXPECT_NEAR(coarse.rotation / fine.rotation, 4.0, 0.6);
}

// Preintegrated values at bias b versus the first-order correction from the linearization bias.
struct BiasCorrectionError {
  double theta, alpha, beta;        // |first order - reintegrated|
  double d_theta, d_alpha, d_beta;  // |reintegrated - uncorrected|, the change to explain
};

BiasCorrectionError bias_correction_error(const std::vector<ImuSample>& samples, const Vec3& dbg, const Vec3& dba) {
  const ImuNoise noise = ImuNoise::from(navaid::testing::euroc_imu_calibration(200.0));
  const Vec3 bg0(0.01, 0.0, -0.01), ba0(0.05, -0.05, 0.1);
  const Timestamp ti = samples.front().t, tj = samples.back().t;
  const ImuPreintegration lin = ImuPreintegration::between(samples, ti, tj, noise, bg0, ba0);
  const ImuPreintegration re = ImuPreintegration::between(samples, ti, tj, noise, bg0 + dbg, ba0 + dba);
  BiasCorrectionError e;
  e.theta = so3_boxminus(lin.corrected_delta_q(bg0 + dbg), re.delta_q()).norm();
  e.alpha = (lin.corrected_delta_p(bg0 + dbg, ba0 + dba) - re.delta_p()).norm();
  e.beta = (lin.corrected_delta_v(bg0 + dbg, ba0 + dba) - re.delta_v()).norm();
  e.d_theta = so3_boxminus(lin.delta_q(), re.delta_q()).norm();
  e.d_alpha = (lin.delta_p() - re.delta_p()).norm();
  e.d_beta = (lin.delta_v() - re.delta_v()).norm();
  return e;
}

TEST(ImuPreintegration, BiasJacobiansMatchReintegration) {
  const WalkerTrajectory traj = test_walk();
  const std::vector<ImuSample> samples = stream(traj, 200.0, 1.0, 3.0, noiseless());
  const Vec3 dbg(2e-3, -3e-3, 1e-3), dba(0.03, 0.02, -0.04);
  const BiasCorrectionError big = bias_correction_error(samples, dbg, dba);
  const BiasCorrectionError small = bias_correction_error(samples, 0.5 * dbg, 0.5 * dba);
  // The correction explains all but a second-order remainder of the change...
  EXPECT_LT(big.theta, 1e-3 * big.d_theta);
  EXPECT_LT(big.alpha, 1e-2 * big.d_alpha);
  EXPECT_LT(big.beta, 1e-2 * big.d_beta);
  // ...which shrinks by 4 when the bias step halves (a wrong Jacobian would leave a first-order
  // remainder that only halves).
  EXPECT_NEAR(big.alpha / small.alpha, 4.0, 0.3);
  EXPECT_NEAR(big.beta / small.beta, 4.0, 0.3);
  EXPECT_NEAR(big.theta / small.theta, 4.0, 0.3);
  // Each bias alone, so that a swapped or missing block cannot hide behind the other.
  for (const auto& [g, a] : {std::pair<Vec3, Vec3>{dbg, Vec3::Zero()}, std::pair<Vec3, Vec3>{Vec3::Zero(), dba}}) {
    const BiasCorrectionError e = bias_correction_error(samples, g, a);
    EXPECT_LT(e.alpha, 1e-2 * e.d_alpha);
    EXPECT_LT(e.beta, 1e-2 * e.d_beta);
  }
}

TEST(ImuPreintegration, RepropagateEqualsFreshIntegrationAndHonoursThresholds) {
  const WalkerTrajectory traj = test_walk();
  const std::vector<ImuSample> samples = stream(traj, 200.0, 0.0, 2.0, noiseless());
  const ImuNoise noise = ImuNoise::from(navaid::testing::euroc_imu_calibration(200.0));
  const Vec3 bg(0.01, 0.02, -0.01), ba(0.1, -0.2, 0.05);
  ImuPreintegration p = ImuPreintegration::between(samples, 0, seconds_to_ns(2.0), noise, Vec3::Zero(), Vec3::Zero());
  const ImuPreintegration fresh = ImuPreintegration::between(samples, 0, seconds_to_ns(2.0), noise, bg, ba);
  EXPECT_FALSE(p.repropagate_if_needed(Vec3(1e-4, 0, 0), Vec3(1e-3, 0, 0), 1e-3, 1e-2));
  EXPECT_TRUE(p.linearization_gyro_bias().isZero());
  EXPECT_TRUE(p.repropagate_if_needed(bg, ba, 1e-3, 1e-2));
  EXPECT_EQ(p.linearization_gyro_bias(), bg);
  EXPECT_EQ(p.delta_p(), fresh.delta_p());
  EXPECT_EQ(p.delta_v(), fresh.delta_v());
  EXPECT_EQ(p.delta_q().coeffs(), fresh.delta_q().coeffs());
  EXPECT_EQ(p.covariance(), fresh.covariance());
  EXPECT_EQ(p.jacobian(), fresh.jacobian());
  EXPECT_DOUBLE_EQ(p.duration_s(), 2.0);
}

TEST(ImuPreintegration, CovarianceClosedFormWithoutSpecificForceOrRotation) {
  // Free fall without rotation: the errors are plain sums of white noise, so with q = density^2
  // and T = N h: P_theta = q_g T, P_beta = q_a T, P_alpha = q_a T^3/3, P_alpha_beta = q_a T^2/2
  // (the continuous-time values: the mid-point sums plus the within-step spread q_a h^3/12).
  ImuNoise noise;
  noise.gyro_noise_density = 2e-4;
  noise.accel_noise_density = 3e-3;
  ImuPreintegration p(noise, Vec3::Zero(), Vec3::Zero());
  const int n = 250;
  const double h = 0.004, T = n * h;
  for (int k = 0; k <= n; ++k) {
    ImuSample s;
    s.t = Timestamp{k} * 4'000'000;
    p.add(s);
  }
  const double qg = noise.gyro_noise_density * noise.gyro_noise_density;
  const double qa = noise.accel_noise_density * noise.accel_noise_density;
  const Mat15& P = p.covariance();
  const Mat3 I = Mat3::Identity();
  auto near = [](const Mat3& a, const Mat3& b) { return (a - b).norm() <= 1e-12 * b.norm(); };
  EXPECT_TRUE(near(P.block<3, 3>(kTheta, kTheta), qg * T * I)) << P.topLeftCorner<3, 3>();
  EXPECT_TRUE(near(P.block<3, 3>(kBeta, kBeta), qa * T * I));
  EXPECT_TRUE(near(P.block<3, 3>(kAlpha, kAlpha), qa * (T * T * T / 3) * I));
  EXPECT_TRUE(near(P.block<3, 3>(kAlpha, kBeta), qa * T * T / 2 * I));
  EXPECT_TRUE((P.block<3, 3>(kTheta, kAlpha).isZero(1e-20)));
  EXPECT_TRUE((P.bottomRightCorner<6, 6>().isZero(0.0)));  // no bias walk configured
}

TEST(ImuPreintegration, CovarianceMatchesMonteCarloOverNoisyStreams) {
  // Residual of the preintegration at the true states for noisy streams (white noise and bias
  // walk from simulation::ImuModel), whitened with the propagated covariance: must be N(0, I15).
  const WalkerTrajectory traj = test_walk();
  const double rate = 200.0, t0 = 2.0, t1 = 3.0;
  const ImuCalibration calib = navaid::testing::euroc_imu_calibration(rate);
  const ImuNoise noise = ImuNoise::from(calib);
  const int steps = static_cast<int>((t1 - t0) * rate);
  std::vector<KinematicState> states;
  for (int k = 0; k <= steps; ++k) states.push_back(traj.state(t0 + k / rate));
  auto preintegrate = [&](ImuModel& model, Vec3* bg_end, Vec3* ba_end) {
    ImuPreintegration p(noise, model.gyro_bias(), model.accel_bias());
    for (int k = 0; k <= steps; ++k) p.add(model.measure(states[k], Timestamp{k} * 5'000'000));
    *bg_end = model.gyro_bias();
    *ba_end = model.accel_bias();
    return p;
  };
  Vec3 unused_g, unused_a;
  ImuModel clean(calib, noiseless());
  const ImuPreintegration ref = preintegrate(clean, &unused_g, &unused_a);  // removes discretization error
  const Mat15 L_inv = Eigen::LLT<Mat15>(ref.covariance()).matrixL().solve(Mat15::Identity());

  const int runs = 400;
  Mat15 S = Mat15::Zero();
  for (int r = 0; r < runs; ++r) {
    ImuModelOptions opt;
    opt.seed = 9000 + static_cast<std::uint64_t>(r);
    ImuModel model(calib, opt);  // starts at zero bias: the bias at t_i is the linearization bias
    Vec3 bg, ba;
    const ImuPreintegration p = preintegrate(model, &bg, &ba);
    Eigen::Matrix<double, 15, 1> e;
    e << so3_boxminus(ref.delta_q(), p.delta_q()), ref.delta_p() - p.delta_p(), ref.delta_v() - p.delta_v(), bg, ba;
    const Eigen::Matrix<double, 15, 1> w = L_inv * e;
    S += w * w.transpose();
  }
  S /= runs;
  // Sampling sd of a diagonal entry sqrt(2 / runs) = 0.071, of an off-diagonal 1 / sqrt(runs) = 0.05.
  for (int i = 0; i < 15; ++i) {
    EXPECT_NEAR(S(i, i), 1.0, 5.0 * std::sqrt(2.0 / runs)) << "diagonal " << i;
    for (int j = 0; j < i; ++j) EXPECT_NEAR(S(i, j), 0.0, 5.0 / std::sqrt(runs)) << "entry " << i << "," << j;
  }
  EXPECT_NEAR(S.trace() / 15.0, 1.0, 5.0 * std::sqrt(2.0 / (15.0 * runs)));
}

// Removes the samples in (t_from, t_to): a stalled driver or a dropped USB packet.
std::vector<ImuSample> with_gap(const std::vector<ImuSample>& samples, double t_from, double t_to) {
  std::vector<ImuSample> out;
  for (const ImuSample& s : samples) {
    if (s.t <= seconds_to_ns(t_from) || s.t >= seconds_to_ns(t_to)) out.push_back(s);
  }
  return out;
}

ImuNoise gap_noise() {
  ImuNoise n = ImuNoise::from(navaid::testing::euroc_imu_calibration(200.0));
  n.max_sample_gap_s = 0.05;
  return n;
}

bool positive_definite(const Mat15& P) { return Eigen::LLT<Mat15>(P).info() == Eigen::Success; }

TEST(ImuSamplesBetween, ReportsTheStreamIntervalOfEveryStep) {
  std::vector<ImuSample> s(4);
  const Timestamp t[] = {0, 100, 1000, 1100};  // a gap from 100 to 1000
  for (int k = 0; k < 4; ++k) s[k].t = t[k];
  std::vector<double> raw;
  const std::vector<ImuSample> a = imu_samples_between(s, 50, 1050, &raw);
  ASSERT_EQ(a.size(), 4u);
  ASSERT_EQ(raw.size(), 4u);
  EXPECT_EQ(raw[0], 0.0);
  EXPECT_DOUBLE_EQ(raw[1], 100e-9);
  EXPECT_DOUBLE_EQ(raw[2], 900e-9);
  EXPECT_DOUBLE_EQ(raw[3], 100e-9);
  imu_samples_between(s, 300, 400, &raw);  // both ends inside the gap
  ASSERT_EQ(raw.size(), 2u);
  EXPECT_DOUBLE_EQ(raw[1], 900e-9);
}

TEST(ImuPreintegration, GapKeepsCovariancePositiveDefiniteAndWide) {
  const WalkerTrajectory traj = test_walk();
  const std::vector<ImuSample> full = stream(traj, 200.0, 0.0, 6.0, noiseless());
  const std::vector<ImuSample> gappy = with_gap(full, 2.0, 3.0);
  const ImuNoise noise = gap_noise();
  // An interval across the gap, and a 33 ms one inside it (two interpolated samples only).
  for (const auto& [t_i, t_j] : {std::pair{1.5, 3.5}, std::pair{2.4, 2.433}}) {
    SCOPED_TRACE(t_i);
    const ImuPreintegration p =
        ImuPreintegration::between(gappy, seconds_to_ns(t_i), seconds_to_ns(t_j), noise, Vec3::Zero(), Vec3::Zero());
    EXPECT_TRUE(positive_definite(p.covariance()));
    const ImuPreintegration q =
        ImuPreintegration::between(full, seconds_to_ns(t_i), seconds_to_ns(t_j), noise, Vec3::Zero(), Vec3::Zero());
    // The gap's unmeasured motion widens velocity far beyond the sensor's own noise.
    const double gap_var = p.covariance().block(kBeta, kBeta, 3, 3).trace();
    EXPECT_GT(gap_var, 100 * q.covariance().block(kBeta, kBeta, 3, 3).trace());
  }
  // Without bridging, the interval inside the gap is one step: still positive definite (the
  // within-step spread of the force noise), but as narrow as the sensor's own noise.
  ImuNoise off = noise;
  off.max_sample_gap_s = 0;
  const ImuPreintegration single =
      ImuPreintegration::between(gappy, seconds_to_ns(2.4), seconds_to_ns(2.433), off, Vec3::Zero(), Vec3::Zero());
  EXPECT_TRUE(positive_definite(single.covariance()));
  EXPECT_LT(1e4 * single.covariance().block(kBeta, kBeta, 3, 3).trace(),
            ImuPreintegration::between(gappy, seconds_to_ns(2.4), seconds_to_ns(2.433), noise, Vec3::Zero(), Vec3::Zero())
                .covariance()
                .block(kBeta, kBeta, 3, 3)
                .trace());
}

TEST(ImuPreintegration, BridgingLeavesAnUnbrokenStreamUnchanged) {
  const WalkerTrajectory traj = test_walk();
  const std::vector<ImuSample> samples = stream(traj, 200.0, 0.0, 4.0, ImuModelOptions{});
  ImuNoise off = gap_noise();
  off.max_sample_gap_s = 0;
  const auto a = ImuPreintegration::between(samples, seconds_to_ns(0.7), seconds_to_ns(3.1), gap_noise(), Vec3::Zero(),
                                            Vec3::Zero());
  const auto b =
      ImuPreintegration::between(samples, seconds_to_ns(0.7), seconds_to_ns(3.1), off, Vec3::Zero(), Vec3::Zero());
  EXPECT_EQ(a.delta_p(), b.delta_p());
  EXPECT_EQ(a.delta_v(), b.delta_v());
  EXPECT_EQ(a.covariance(), b.covariance());
}

TEST(ImuPreintegration, BridgedGapStillPredictsASteadyWalk) {
  // Straight walk at constant speed with the gait removed: the bridge interpolates linearly, so
  // across a 0.5 s gap the prediction stays on the line (within the mid-point error).
  const WalkerTrajectory traj({{0.0, 0.0}, {20.0, 0.0}});
  const std::vector<ImuSample> gappy = with_gap(stream(traj, 200.0, 0.0, 8.0, noiseless()), 4.0, 4.5);
  const ImuPreintegration p =
      ImuPreintegration::between(gappy, seconds_to_ns(3.0), seconds_to_ns(5.5), gap_noise(), Vec3::Zero(), Vec3::Zero());
  const KinematicState si = traj.state(3.0), sj = traj.state(5.5);
  SE3 T_j;
  Vec3 v_j;
  p.predict(si.T_W_B, si.v_W, Vec3::Zero(), Vec3::Zero(), &T_j, &v_j);
  // The gait's bob and sway are not linear over 0.5 s: the error is bounded by the gap's size,
  // and well inside the widened covariance.
  const double sigma_p = std::sqrt(p.covariance().block(kAlpha, kAlpha, 3, 3).trace());
  EXPECT_LT((T_j.t - sj.T_W_B.t).norm(), sigma_p);
}

TEST(ImuPreintegration, RejectsBadInput) {
  ImuNoise bad;
  bad.gyro_noise_density = -1.0;
  EXPECT_THROW(ImuPreintegration(bad, Vec3::Zero(), Vec3::Zero()), ConfigError);
  bad = ImuNoise{};
  bad.max_sample_gap_s = 0.05;
  bad.gap_accel_density = 0;
  EXPECT_THROW(ImuPreintegration(bad, Vec3::Zero(), Vec3::Zero()), ConfigError);
  ImuPreintegration p(ImuNoise{}, Vec3::Zero(), Vec3::Zero());
  ImuSample s;
  s.t = 10;
  p.add(s);
  EXPECT_THROW(p.add(s), Error);  // same time
  s.t = 20;
  s.has_gyro = false;
  EXPECT_THROW(p.add(s), Error);
}

}  // namespace
}  // namespace navaid::estimation
