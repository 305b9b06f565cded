// NEES: hand-computed values, the chi-square consistency test on seeded samples (consistent,
// over- and under-confident covariances), and bad input.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <random>

#include "navaid/core/errors.hpp"
#include "navaid/core/random_draws.hpp"
#include "navaid/evaluation/nees.hpp"
#include "test_support.hpp"

using navaid::Error;
using navaid::Mat3;
using navaid::Quat;
using navaid::SE3;
using navaid::Vec3;
using namespace navaid::evaluation;

namespace {

const Mat3 kCovariance = (Mat3() << 0.04, 0.01, 0.0, 0.01, 0.09, -0.02, 0.0, -0.02, 0.01).finished();

// `n` estimates whose true errors are drawn from N(0, kCovariance), reporting kCovariance * reported.
struct Samples {
  std::vector<PoseWithCovariance> estimates;
  std::vector<SE3> truth;
};

Samples draw(std::size_t n, double reported, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n01;
  const Mat3 L = kCovariance.llt().matrixL();
  Samples s;
  for (std::size_t i = 0; i < n; ++i) {
    PoseWithCovariance e;
    e.T_W_B = SE3(navaid::quat_from_rpy(0.1 * i, 0.2, -0.3), Vec3(i, 2.0, 0.5));
    e.position_covariance = reported * kCovariance;
    e.rotation_covariance = reported * kCovariance * 0.01;
    const Vec3 dp = L * navaid::draw_vector<3>([&] { return n01(rng); });
    const Vec3 dtheta = 0.1 * (L * navaid::draw_vector<3>([&] { return n01(rng); }));
    s.truth.push_back(SE3(navaid::so3_boxplus(e.T_W_B.q, dtheta), e.T_W_B.t + dp));
    s.estimates.push_back(e);
  }
  return s;
}

}  // namespace

TEST(Nees, HandComputed) {
  EXPECT_DOUBLE_EQ(nees(Vec3(1, 2, 3), Vec3(1, 4, 9).asDiagonal().toDenseMatrix()), 3.0);
  const Mat3 P = (Mat3() << 2, 1, 0, 1, 2, 0, 0, 0, 1).finished();
  EXPECT_NEAR(nees(Vec3(1, 1, 0), P), 2.0 / 3.0, 1e-15);
}

TEST(Nees, OrientationErrorIsTheRightPerturbation) {
  PoseWithCovariance e;
  e.T_W_B = SE3(navaid::quat_from_rpy(0.5, -0.2, 1.0), Vec3::Zero());
  e.rotation_covariance = Vec3(1e-4, 4e-4, 9e-4).asDiagonal();
  const Vec3 dtheta(0.01, -0.02, 0.03);  // 1 sigma on each axis
  const SE3 truth(navaid::so3_boxplus(e.T_W_B.q, dtheta), Vec3(0.3, 0, 0));
  EXPECT_NEAR(orientation_nees({e}, {truth})[0], 3.0, 1e-9);
  EXPECT_NEAR(position_nees({e}, {truth})[0], 0.09, 1e-12);  // identity position covariance
}

TEST(Nees, FromStateEstimateBlocks) {
  navaid::StateEstimate s;
  s.covariance = navaid::Mat15::Zero();
  for (int i = 0; i < 15; ++i) s.covariance(i, i) = i + 1.0;
  const PoseWithCovariance p = pose_with_covariance(s);
  EXPECT_EQ(p.rotation_covariance.diagonal(), Vec3(1, 2, 3));
  EXPECT_EQ(p.position_covariance.diagonal(), Vec3(4, 5, 6));
}

TEST(Nees, ConsistentCovariancePassesAndWrongOnesFail) {
  // 2000 independent draws: a consistent estimator's ANEES lies within the 99.9 % bounds (the test
  // fails by chance with probability 1e-3 for a random seed; the seed is fixed), and about 95 % of
  // single values within the 95 % per-sample bounds (binomial sd 0.5 %, allowed 4 sd).
  const Samples ok = draw(2000, 1.0, 5);
  for (const auto& values : {position_nees(ok.estimates, ok.truth), orientation_nees(ok.estimates, ok.truth)}) {
    const NeesSummary s = summarize_nees(values, 3, 0.999);
    EXPECT_TRUE(s.consistent()) << s.average << " not in [" << s.lower << ", " << s.upper << "]";
    EXPECT_NEAR(summarize_nees(values, 3, 0.95).fraction_inside, 0.95, 4 * std::sqrt(0.95 * 0.05 / 2000));
  }
  // Reporting half the true covariance doubles the NEES (ANEES ~ 6); twice the covariance halves it.
  const Samples over = draw(2000, 0.5, 6), under = draw(2000, 2.0, 7);
  const NeesSummary s_over = summarize_nees(position_nees(over.estimates, over.truth), 3, 0.999);
  const NeesSummary s_under = summarize_nees(orientation_nees(under.estimates, under.truth), 3, 0.999);
  EXPECT_GT(s_over.average, s_over.upper);
  EXPECT_LT(s_under.average, s_under.lower);
}

TEST(Nees, EvaluationMatchesEstimatesToGroundTruthByTime) {
  // Estimates every third ground-truth pose, 4 ms late; the unmatched ground truth is ignored.
  const Samples s = draw(300, 1.0, 9);
  std::vector<PoseWithCovariance> estimates;
  std::vector<navaid::io::StampedPose> truth;
  for (std::size_t i = 0; i < s.truth.size(); ++i) {
    truth.push_back({static_cast<navaid::Timestamp>(i) * 10'000'000, s.truth[i]});
    if (i % 3 == 0) {
      estimates.push_back(s.estimates[i]);
      estimates.back().t = truth.back().t + 4'000'000;
    }
  }
  const NeesEvaluation e = evaluate_nees(estimates, truth);
  ASSERT_EQ(e.position.size(), 100u);
  for (std::size_t k = 0; k < e.position.size(); ++k) {
    EXPECT_EQ(e.t[k], estimates[k].t);
    EXPECT_DOUBLE_EQ(e.position[k], position_nees({s.estimates[3 * k]}, {s.truth[3 * k]})[0]);
  }
  EXPECT_EQ(e.orientation_summary.count, 100u);
  EXPECT_THROW(evaluate_nees(estimates, {}), Error);
}

TEST(Nees, SummaryBoundsAreChiSquareQuantiles) {
  // One value of dof 3: [chi2(0.025, 3), chi2(0.975, 3)]; ten values: chi2(., 30) / 10.
  const NeesSummary one = summarize_nees({3.0}, 3);
  EXPECT_NEAR(one.lower, 0.2157952826, 1e-9);
  EXPECT_NEAR(one.upper, 9.348403604, 1e-8);
  const NeesSummary ten = summarize_nees(std::vector<double>(10, 3.0), 3);
  EXPECT_NEAR(ten.lower, 1.679077, 1e-6);
  EXPECT_NEAR(ten.upper, 4.697924, 1e-6);
  EXPECT_DOUBLE_EQ(ten.average, 3.0);
  EXPECT_DOUBLE_EQ(ten.fraction_inside, 1.0);
  EXPECT_TRUE(ten.consistent());
}

TEST(Nees, BadInput) {
  using navaid::testing::error_message;
  EXPECT_NE(error_message<Error>([] { nees(Vec3::Ones(), -Mat3::Identity()); }).find("positive definite"), std::string::npos);
  EXPECT_NE(error_message<Error>([] { nees(Vec3::Ones(), (Mat3() << 1, 0.5, 0, 0, 1, 0, 0, 0, 1).finished()); }).find("symmetric"),
            std::string::npos);
  EXPECT_THROW(nees(Vec3(std::nan(""), 0, 0), Mat3::Identity()), Error);
  EXPECT_NE(error_message<Error>([] { position_nees({PoseWithCovariance{}}, {}); }).find("1 estimates but 0"), std::string::npos);
  EXPECT_THROW(summarize_nees({}, 3), Error);
  EXPECT_THROW(summarize_nees({-1.0}, 3), Error);
  EXPECT_THROW(summarize_nees({1.0}, 0), Error);
  EXPECT_THROW(summarize_nees({1.0}, 3, 1.0), Error);
}
