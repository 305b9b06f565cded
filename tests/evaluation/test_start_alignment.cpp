#include "navaid/evaluation/start_alignment.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "navaid/core/errors.hpp"
#include "navaid/core/random_draws.hpp"

namespace navaid::evaluation {
namespace {

// A walk around a circle at 1 m/s with a slow wobble in roll, 10 Hz, 60 s.
std::vector<io::StampedPose> circle() {
  std::vector<io::StampedPose> gt;
  for (int k = 0; k <= 600; ++k) {
    const double s = 0.1 * k, a = s / 10.0;
    gt.push_back({seconds_to_ns(s), SE3(quat_from_rpy(0.05 * std::sin(s), 0.0, a + M_PI / 2),
                                        Vec3(10.0 * std::cos(a), 10.0 * std::sin(a), 1.2))});
  }
  return gt;
}

TEST(StartAlignment, InterpolatesBetweenSamplesAndRefusesOutsideTheSpan) {
  const auto gt = circle();
  EXPECT_TRUE(interpolate_pose(gt, gt[7].t).is_approx(gt[7].T_W_B, 0.0));
  const SE3 mid = interpolate_pose(gt, (gt[7].t + gt[8].t) / 2);
  EXPECT_TRUE(mid.t.isApprox(0.5 * (gt[7].T_W_B.t + gt[8].T_W_B.t), 1e-12));
  EXPECT_NEAR(mid.q.angularDistance(gt[7].T_W_B.q), 0.5 * gt[8].T_W_B.q.angularDistance(gt[7].T_W_B.q), 1e-12);
  EXPECT_THROW(interpolate_pose(gt, gt.back().t + 1), Error);
  EXPECT_THROW(interpolate_pose(gt, gt.front().t - 1), Error);
}

// Estimates = ground truth seen from a world rotated by `yaw` and shifted by `t` (the estimator's
// W), with a given position/rotation covariance and errors drawn from it.
std::vector<StateEstimate> estimates_in_other_world(const std::vector<io::StampedPose>& gt, double yaw, const Vec3& t,
                                                    const Mat3& P_pos, const Mat3& P_rot, double error_scale,
                                                    std::uint64_t seed) {
  const SE3 T_est_gt(quat_from_rpy(0, 0, yaw), t);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n(0.0, 1.0);
  const Mat3 Lp = P_pos.llt().matrixL(), Lr = P_rot.llt().matrixL();
  std::vector<StateEstimate> est;
  for (std::size_t k = 0; k < gt.size(); k += 3) {
    StateEstimate s;
    s.t = gt[k].t;
    s.mode = k == 0 ? EstimatorMode::kInitializing : EstimatorMode::kRgbdVio;
    const SE3 truth = T_est_gt * gt[k].T_W_B;
    // The first real estimate is exact: it defines the frame.
    const double scale = k <= 3 ? 0.0 : error_scale;
    const Vec3 dp = scale * Lp * draw_vector<3>([&] { return n(rng); });
    const Vec3 dth = scale * Lr * draw_vector<3>([&] { return n(rng); });
    // truth = estimate (+) error, in the covariance's parametrization.
    s.T_W_B = SE3(Quat(truth.q * so3_exp(-dth)), Vec3(truth.t - dp));
    s.covariance.block<3, 3>(0, 0) = P_rot;
    s.covariance.block<3, 3>(3, 3) = P_pos;
    est.push_back(s);
  }
  return est;
}

TEST(StartAlignment, FirstStateFramePutsExactEstimatesOntoTheTruth) {
  const auto gt = circle();
  Mat3 P = Mat3::Zero();
  P.diagonal() << 1e-4, 4e-4, 9e-4;
  const auto est = estimates_in_other_world(gt, 0.8, Vec3(3.0, -2.0, 0.5), P, 1e-6 * Mat3::Identity(), 0.0, 1);
  const auto aligned = align_to_first_state(est, gt);
  ASSERT_EQ(aligned.size(), est.size() - 1);  // the initializing one is left out
  for (const auto& p : aligned) EXPECT_TRUE(p.T_W_B.is_approx(interpolate_pose(gt, p.t), 1e-9));
  // Position covariance rotated back by the yaw difference (-0.8 rad); rotation covariance unchanged.
  const Mat3 Rz = Eigen::AngleAxisd(-0.8, Vec3::UnitZ()).toRotationMatrix();
  EXPECT_TRUE(aligned[5].position_covariance.isApprox(Rz * P * Rz.transpose(), 1e-12));
  EXPECT_TRUE(aligned[5].rotation_covariance.isApprox(1e-6 * Mat3::Identity(), 1e-12));
}

TEST(StartAlignment, ATiltedBodyKeepsItsTiltErrorOutOfTheYaw) {
  // A body with x up (EuRoC's IMU: pitch near -70 deg), estimated with 0.7 deg of tilt error and
  // W turned 1 rad: the alignment turns W back by 1 rad and leaves the tilt error as it is (the
  // difference of Euler yaws would have put ~1.6 deg of it into yaw).
  const Quat q_gt = quat_from_rpy(0.2, -1.2, 2.0);
  const std::vector<io::StampedPose> gt{{0, SE3(q_gt, Vec3(1, 2, 3))}, {seconds_to_ns(1.0), SE3(q_gt, Vec3(1, 2, 3))}};
  const Quat tilt(Eigen::AngleAxisd(0.7 * M_PI / 180.0, Vec3(0.0, 1.0, 0.0)));
  StateEstimate first;
  first.t = seconds_to_ns(0.5);
  first.T_W_B = SE3(Quat(Eigen::AngleAxisd(-1.0, Vec3::UnitZ())) * tilt * q_gt, Vec3::Zero());
  const SE3 T = first_state_transform(first, gt);
  EXPECT_NEAR(yaw_of(T.q), 1.0, 2e-3);
  const double error_rad = (T.q * first.T_W_B.q).angularDistance(q_gt);
  EXPECT_NEAR(error_rad, 0.7 * M_PI / 180.0, 1e-4);
}

TEST(StartAlignment, NeesIsThreeWhenErrorsFollowTheCovarianceAndNotOtherwise) {
  const auto gt = circle();
  Mat3 P = Mat3::Zero();
  P << 4e-4, 1e-4, 0, 1e-4, 2e-4, 0, 0, 0, 1e-4;
  const Mat3 R = 1e-5 * Mat3::Identity();
  const auto consistent = first_state_nees(align_to_first_state(estimates_in_other_world(gt, -1.3, Vec3(1, 2, 3), P, R, 1.0, 7), gt), gt);
  EXPECT_TRUE(consistent.position_summary.consistent()) << consistent.position_summary.average;
  EXPECT_TRUE(consistent.orientation_summary.consistent()) << consistent.orientation_summary.average;
  // Errors twice as large as the covariance says: NEES ~ 12, far outside the bounds.
  const auto optimistic = first_state_nees(align_to_first_state(estimates_in_other_world(gt, -1.3, Vec3(1, 2, 3), P, R, 2.0, 7), gt), gt);
  EXPECT_GT(optimistic.position_summary.average, optimistic.position_summary.upper);
  EXPECT_GT(optimistic.orientation_summary.average, optimistic.orientation_summary.upper);
  EXPECT_THROW(first_state_nees({}, gt), Error);
}

}  // namespace
}  // namespace navaid::evaluation
