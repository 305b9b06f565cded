// predict_state: an estimate carried forward through the IMU, mean and first-order covariance.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "navaid/core/errors.hpp"
#include "navaid/estimation/state_prediction.hpp"
#include "test_support.hpp"

namespace {

using namespace navaid;
using namespace navaid::estimation;

/// 200 Hz samples over [0, 1] s of a body turning about z at 0.3 rad/s and accelerating along x.
std::vector<ImuSample> turning_imu() {
  std::vector<ImuSample> imu;
  for (int k = 0; k <= 200; ++k) {
    ImuSample s;
    s.t = seconds_to_ns(0.005 * k);
    s.gyro = Vec3(0.02, -0.01, 0.3);
    s.accel = Vec3(0.4, 0.1, 9.81);
    s.has_gyro = true;
    imu.push_back(s);
  }
  return imu;
}

StateEstimate start_state() {
  StateEstimate e;
  e.t = seconds_to_ns(0.1);
  e.T_W_B = SE3(so3_exp(Vec3(0.05, -0.02, 0.7)), Vec3(1, 2, 0.5));
  e.v_W = Vec3(0.8, -0.3, 0.05);
  e.b_g = Vec3(0.001, -0.002, 0.0005);
  e.b_a = Vec3(0.02, -0.01, 0.03);
  e.mode = EstimatorMode::kRgbdVio;
  e.covariance = Mat15::Identity() * 1e-4;
  return e;
}

ImuNoise noise() { return ImuNoise::from(navaid::testing::euroc_imu_calibration()); }

/// [dtheta, dp, dv, db_g, db_a] of `b` against `a` in StateEstimate's parametrization.
Eigen::Matrix<double, 15, 1> difference(const StateEstimate& a, const StateEstimate& b) {
  Eigen::Matrix<double, 15, 1> d;
  d.segment<3>(0) = so3_log(a.T_W_B.q.conjugate() * b.T_W_B.q);
  d.segment<3>(3) = b.T_W_B.t - a.T_W_B.t;
  d.segment<3>(6) = b.v_W - a.v_W;
  d.segment<3>(9) = b.b_g - a.b_g;
  d.segment<3>(12) = b.b_a - a.b_a;
  return d;
}

TEST(StatePrediction, StandingStillStaysPut) {
  std::vector<ImuSample> imu = turning_imu();
  for (auto& s : imu) {
    s.gyro.setZero();
    s.accel = Vec3(0, 0, 9.81);  // gravity's reaction, level body
  }
  StateEstimate e;
  e.t = 0;
  e.T_W_B = SE3(Quat::Identity(), Vec3(3, 4, 1));
  const StateEstimate p = predict_state(e, seconds_to_ns(0.5), imu, noise());
  EXPECT_EQ(p.t, seconds_to_ns(0.5));
  EXPECT_NEAR((p.T_W_B.t - e.T_W_B.t).norm(), 0.0, 1e-9);
  EXPECT_NEAR(p.v_W.norm(), 0.0, 1e-9);
  EXPECT_GT(p.covariance(3, 3), e.covariance(3, 3));  // the position grows more uncertain
}

TEST(StatePrediction, TransitionMatchesNumericPerturbation) {
  const std::vector<ImuSample> imu = turning_imu();
  const StateEstimate e = start_state();
  const Timestamp t = seconds_to_ns(0.6);
  const ImuPreintegration pre = ImuPreintegration::between(imu, e.t, t, noise(), e.b_g, e.b_a);
  const Mat15 F = state_transition(pre, e);
  const StateEstimate base = predict_state(e, t, imu, noise());
  const double h = 1e-6;
  for (int i = 0; i < 15; ++i) {
    Eigen::Matrix<double, 15, 1> d = Eigen::Matrix<double, 15, 1>::Zero();
    d(i) = h;
    StateEstimate x = e;
    x.T_W_B.q = so3_boxplus(e.T_W_B.q, d.segment<3>(0));
    x.T_W_B.t += d.segment<3>(3);
    x.v_W += d.segment<3>(6);
    x.b_g += d.segment<3>(9);
    x.b_a += d.segment<3>(12);
    // The preintegration keeps its linearization biases: the bias columns are first order in both.
    const StateEstimate moved = predict_state(x, t, imu, noise());
    const Eigen::Matrix<double, 15, 1> numeric = difference(base, moved) / h;
    for (int r = 0; r < 15; ++r) EXPECT_NEAR(numeric(r), F(r, i), 1e-4) << "row " << r << " column " << i;
  }
}

TEST(StatePrediction, CovarianceIsPropagatedAndNoiseAdded) {
  const std::vector<ImuSample> imu = turning_imu();
  const StateEstimate e = start_state();
  const StateEstimate p = predict_state(e, seconds_to_ns(0.6), imu, noise());
  const ImuPreintegration pre = ImuPreintegration::between(imu, e.t, p.t, noise(), e.b_g, e.b_a);
  const Mat15 F = state_transition(pre, e);
  const Mat15 without_noise = F * e.covariance * F.transpose();
  const Mat15 added = p.covariance - without_noise;
  EXPECT_GT(added.trace(), 0.0);
  EXPECT_LT((added - added.transpose()).norm(), 1e-12);
  EXPECT_GT(p.covariance(4, 4), e.covariance(4, 4));  // velocity uncertainty moves into position
  EXPECT_EQ(p.mode, e.mode);
  EXPECT_EQ(p.b_g, e.b_g);
}

TEST(StatePrediction, AnUncoveredIntervalIsAnError) {
  const std::vector<ImuSample> imu = turning_imu();
  EXPECT_THROW(predict_state(start_state(), seconds_to_ns(2.0), imu, noise()), Error);
}

}  // namespace
