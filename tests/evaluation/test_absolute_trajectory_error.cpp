// Alignment and ATE: hand-computed cases, and trajectories whose ATE is known by construction.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string_view>
#include <utility>
#include <vector>

#include "navaid/core/errors.hpp"
#include "navaid/evaluation/absolute_trajectory_error.hpp"
#include "synthetic_trajectory.hpp"
#include "test_support.hpp"

using navaid::Error;
using navaid::Mat3;
using navaid::Quat;
using navaid::SE3;
using navaid::Vec3;
using navaid::io::StampedPose;
using namespace navaid::evaluation;

namespace {

std::vector<PosePair> pairs_of(const std::vector<StampedPose>& est, const std::vector<StampedPose>& gt) {
  std::vector<PosePair> pairs;
  for (std::size_t i = 0; i < est.size(); ++i) pairs.push_back({est[i].t, gt[i].t, est[i].T_W_B, gt[i].T_W_B});
  return pairs;
}

std::vector<PosePair> position_pairs(const std::vector<Vec3>& est, const std::vector<Vec3>& gt) {
  std::vector<PosePair> pairs;
  for (std::size_t i = 0; i < est.size(); ++i)
    pairs.push_back({static_cast<navaid::Timestamp>(i), static_cast<navaid::Timestamp>(i), SE3(Quat::Identity(), est[i]),
                     SE3(Quat::Identity(), gt[i])});
  return pairs;
}

// Errors with zero mean and zero correlation with the centred positions leave every alignment's
// rotation and translation unchanged, so the aligned error is exactly these vectors.
std::vector<Vec3> orthogonal_errors(const std::vector<StampedPose>& poses, double rms, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n01;
  const std::size_t n = poses.size();
  Eigen::MatrixXd A(n, 4), E(n, 3);
  for (std::size_t i = 0; i < n; ++i) {
    A.row(i) << 1.0, poses[i].T_W_B.t.transpose();
    E.row(i) << n01(rng), n01(rng), n01(rng);
  }
  const Eigen::MatrixXd residual = E - A * A.colPivHouseholderQr().solve(E);
  const double current = std::sqrt(residual.squaredNorm() / static_cast<double>(n));
  std::vector<Vec3> out;
  for (std::size_t i = 0; i < n; ++i) out.push_back(residual.row(i).transpose() * (rms / current));
  return out;
}

const SE3 kYawOnly(navaid::quat_from_rpy(0.0, 0.0, 2.3), Vec3(4.0, -7.0, 1.5));
const SE3 kGeneral(navaid::quat_from_rpy(0.4, -0.3, -1.9), Vec3(-2.0, 3.0, 0.5));

}  // namespace

TEST(Alignment, ModeNames) {
  // Every enumerator with its name; a dropped or misspelt table entry fails.
  const std::vector<std::pair<AlignmentMode, std::string_view>> modes{
      {AlignmentMode::kNone, "none"},
      {AlignmentMode::kPosYaw, "4dof"},
      {AlignmentMode::kSe3, "se3"},
      {AlignmentMode::kSim3, "sim3"},
      {AlignmentMode::kScale, "scale"},
  };
  for (const auto& [m, name] : modes) {
    EXPECT_EQ(to_string(m), name);
    EXPECT_EQ(alignment_mode_from_string(to_string(m)), m) << name;
  }
  EXPECT_EQ(alignment_mode_from_string("posyaw"), AlignmentMode::kPosYaw);
  EXPECT_EQ(to_string(AlignmentMode::kPosYaw), "4dof") << "posyaw is read, never written";
  EXPECT_FALSE(alignment_mode_from_string("SE3"));
  EXPECT_EQ(to_string(static_cast<AlignmentMode>(17)), "?");
}

TEST(Ate, HandComputedWithoutAlignment) {
  // Errors 0.3, 0.4 and 0: RMSE sqrt(0.25 / 3), mean 0.7 / 3, median 0.3, max 0.4.
  const auto pairs = position_pairs({{0, 0, 0.3}, {1, 0.4, 0}, {2, 0, 0}}, {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}});
  const AteResult r = compute_ate(pairs, {AlignmentMode::kNone, 0});
  EXPECT_NEAR(r.position.rmse, std::sqrt(0.25 / 3.0), 1e-15);
  EXPECT_NEAR(r.position.mean, 0.7 / 3.0, 1e-15);
  EXPECT_DOUBLE_EQ(r.position.median, 0.3);
  EXPECT_DOUBLE_EQ(r.position.max, 0.4);
  EXPECT_DOUBLE_EQ(r.position.min, 0.0);
  EXPECT_EQ(r.position.count, 3u);
  EXPECT_DOUBLE_EQ(r.rotation_deg.max, 0.0);
}

TEST(Ate, HandComputedSquareWithAlternatingHeight) {
  // A unit square whose estimate alternates +-0.1 m in height, then is turned by 90 deg and moved:
  // the +-0.1 pattern has zero mean and no correlation with x or y, so SE(3) and 4-DOF alignment
  // undo exactly the turn and the move, leaving 0.1 m everywhere.
  const std::vector<Vec3> gt{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  std::vector<Vec3> est;
  const Mat3 Rz90 = navaid::quat_from_rpy(0, 0, M_PI / 2).toRotationMatrix();
  for (std::size_t i = 0; i < gt.size(); ++i) est.push_back(Rz90 * (gt[i] + Vec3(0, 0, i % 2 ? -0.1 : 0.1)) + Vec3(5, -2, 1));
  for (auto mode : {AlignmentMode::kSe3, AlignmentMode::kPosYaw}) {
    const AteResult r = compute_ate(position_pairs(est, gt), {mode, 0});
    EXPECT_NEAR(r.position.rmse, 0.1, 1e-12) << to_string(mode);
    EXPECT_NEAR(r.position.min, 0.1, 1e-12) << to_string(mode);
    EXPECT_TRUE(r.transform.R.isApprox(Rz90.transpose(), 1e-12)) << to_string(mode);
    EXPECT_EQ(r.transform.scale, 1.0);
  }
}

TEST(Ate, HandComputedSim3RecoversScale) {
  // The estimate is the ground-truth square at half size, rotated: Sim(3) scale 2, ATE 0.
  const std::vector<Vec3> gt{{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}, {0, 0, 1}};
  std::vector<Vec3> est;
  const Mat3 R = navaid::quat_from_rpy(0.3, 0.2, 1.0).toRotationMatrix();
  for (const auto& p : gt) est.push_back(R * (0.5 * p) + Vec3(1, 2, 3));
  const AteResult r = compute_ate(position_pairs(est, gt), {AlignmentMode::kSim3, 0});
  EXPECT_NEAR(r.transform.scale, 2.0, 1e-12);
  EXPECT_LT(r.position.max, 1e-12);
  // SE(3) cannot shrink: it turns the copy back about the centroid mu = (0, 0, 0.2), leaving
  // |p - mu| / 2 at each point: sqrt(0.25 (4 * 2.04 + 0.64) / 5) = sqrt(0.44).
  const AteResult se3 = compute_ate(position_pairs(est, gt), {AlignmentMode::kSe3, 0});
  EXPECT_NEAR(se3.position.rmse, std::sqrt(0.44), 1e-12);
}

TEST(Ate, RigidlyMovedTrajectoryHasZeroErrorInEveryMatchingMode) {
  const auto gt = navaid::testing::synthetic_trajectory(120);
  // 4-DOF removes a yaw + translation, SE(3) any rigid motion, Sim(3) a scaled one too.
  for (auto [mode, T] : {std::pair{AlignmentMode::kPosYaw, kYawOnly}, std::pair{AlignmentMode::kSe3, kGeneral},
                         std::pair{AlignmentMode::kSim3, kGeneral}}) {
    auto est = navaid::testing::in_frame(gt, T);
    if (mode == AlignmentMode::kSim3)
      for (auto& p : est) p.T_W_B.t *= 0.37;
    const AteResult r = compute_ate(pairs_of(est, gt), {mode, 0});
    EXPECT_LT(r.position.max, 1e-9) << to_string(mode);
    EXPECT_LT(r.rotation_deg.max, 1e-7) << to_string(mode);
    EXPECT_NEAR(r.transform.scale, mode == AlignmentMode::kSim3 ? 1.0 / 0.37 : 1.0, 1e-9);
  }
  // 4-DOF cannot remove roll and pitch: a tilted copy keeps an error.
  const AteResult tilted = compute_ate(pairs_of(navaid::testing::in_frame(gt, kGeneral), gt), {AlignmentMode::kPosYaw, 0});
  EXPECT_GT(tilted.position.rmse, 0.1);
}

TEST(Ate, KnownErrorSurvivesAlignment) {
  const auto gt = navaid::testing::synthetic_trajectory(200);
  const double rms = 0.05;
  const auto e = orthogonal_errors(gt, rms, 11);
  double mean = 0.0;
  for (const auto& v : e) mean += v.norm() / static_cast<double>(e.size());
  auto noisy = gt;
  for (std::size_t i = 0; i < gt.size(); ++i) noisy[i].T_W_B.t += e[i];
  for (auto [mode, T] : {std::pair{AlignmentMode::kPosYaw, kYawOnly}, std::pair{AlignmentMode::kSe3, kGeneral},
                         std::pair{AlignmentMode::kNone, SE3()}}) {
    const AteResult r = compute_ate(pairs_of(navaid::testing::in_frame(noisy, T), gt), {mode, 0});
    EXPECT_NEAR(r.position.rmse, rms, 1e-10) << to_string(mode);
    EXPECT_NEAR(r.position.mean, mean, 1e-10) << to_string(mode);
    EXPECT_TRUE(r.transform.apply(T).is_approx(SE3(), 1e-9)) << to_string(mode);
  }
}

TEST(Ate, AlignOnFirstFrames) {
  // The estimate is exact for 30 poses, then drifts by 1 cm per pose along x.
  const auto gt = navaid::testing::synthetic_trajectory(100);
  auto est = navaid::testing::in_frame(gt, kGeneral);
  for (std::size_t i = 30; i < est.size(); ++i) est[i].T_W_B.t += kGeneral.q * Vec3(0.01 * (i - 29.0), 0, 0);
  const auto pairs = pairs_of(est, gt);
  for (std::size_t n : {1u, 30u}) {
    const AteResult r = compute_ate(pairs, {AlignmentMode::kSe3, n});
    EXPECT_EQ(r.align_frames, n);
    EXPECT_LT(r.position_errors[0], 1e-9);
    EXPECT_LT(r.position_errors[29], 1e-9);
    EXPECT_NEAR(r.position_errors[99], 0.70, 1e-9);
  }
  // One frame, 4-DOF: the yaw of the first pose's relative rotation.
  const AteResult yaw = compute_ate(pairs_of(navaid::testing::in_frame(gt, kYawOnly), gt), {AlignmentMode::kPosYaw, 1});
  EXPECT_LT(yaw.position.max, 1e-9);
  // Aligning on everything spreads the drift: the first poses are no longer exact.
  EXPECT_GT(compute_ate(pairs, {AlignmentMode::kSe3, 0}).position_errors[0], 1e-3);
}

TEST(Ate, UndeterminedAlignmentsAreErrors) {
  using navaid::testing::error_message;
  const auto line = position_pairs({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}, {{0, 0, 0}, {0, 1, 0}, {0, 2, 0}});
  EXPECT_NE(error_message<Error>([&] { compute_ate(line, {AlignmentMode::kSe3, 0}); }).find("collinear"), std::string::npos);
  EXPECT_NE(error_message<Error>([&] { compute_ate(line, {AlignmentMode::kSim3, 0}); }).find("collinear"), std::string::npos);
  // A line is enough for yaw.
  EXPECT_LT(compute_ate(line, {AlignmentMode::kPosYaw, 0}).position.max, 1e-12);
  const auto vertical = position_pairs({{0, 0, 0}, {0, 0, 1}}, {{1, 1, 0}, {1, 1, 1}});
  EXPECT_NE(error_message<Error>([&] { compute_ate(vertical, {AlignmentMode::kPosYaw, 0}); }).find("horizontal"),
            std::string::npos);
  EXPECT_NE(error_message<Error>([&] { compute_ate(line, {AlignmentMode::kSim3, 1}); }).find("at least 2"), std::string::npos);
  EXPECT_NE(error_message<Error>([&] { compute_ate(line, {AlignmentMode::kSe3, 4}); }).find("only 3"), std::string::npos);
  EXPECT_NE(error_message<Error>([&] { compute_ate({}, {}); }).find("no matched poses"), std::string::npos);
  EXPECT_NE(error_message<Error>([&] { align_positions({Vec3::Zero()}, {}, AlignmentMode::kSe3); }).find("1 estimated"),
            std::string::npos);
  const auto same = position_pairs({{1, 1, 1}, {1, 1, 1}, {1, 1, 1}}, {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  EXPECT_THROW(compute_ate(same, {AlignmentMode::kSim3, 0}), Error);
}

TEST(ErrorStatistics, MedianOfEvenCountAndPopulationStd) {
  const ErrorStatistics s = compute_statistics({4.0, 1.0, 3.0, 2.0});
  EXPECT_DOUBLE_EQ(s.median, 2.5);
  EXPECT_DOUBLE_EQ(s.mean, 2.5);
  EXPECT_DOUBLE_EQ(s.std, std::sqrt(1.25));
  EXPECT_DOUBLE_EQ(s.rmse, std::sqrt(7.5));
  EXPECT_THROW(compute_statistics({}), Error);
  EXPECT_THROW(compute_statistics({1.0, std::nan("")}), Error);
}
