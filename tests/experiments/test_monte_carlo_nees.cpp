// Monte-Carlo NEES (per-epoch ANEES over runs): hand-computed ANEES and chi-square bounds, seeded
// synthetic runs (consistent, fully correlated in time, over-confident), epoch matching across runs,
// bad input, and the run-folder reader it is fed from.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <random>

#include "navaid/core/errors.hpp"
#include "navaid/core/random_draws.hpp"
#include "navaid/evaluation/monte_carlo_nees.hpp"
#include "navaid/evaluation/nees.hpp"
#include "navaid/experiments/run_folder.hpp"
#include "navaid/evaluation/start_alignment.hpp"
#include "test_support.hpp"

using navaid::Error;
using navaid::IoError;
using navaid::Mat3;
using navaid::SE3;
using navaid::Timestamp;
using navaid::Vec3;
using navaid::testing::expect_throw;
using namespace navaid::evaluation;
using namespace navaid::experiments;

namespace {

using Matrix = std::vector<std::vector<double>>;

// NEES of N runs x K epochs: true errors ~ N(0, P_ik) with a random SPD P_ik, the estimator
// reporting `reported` * P_ik. With `frozen`, each run keeps its first error and covariance at every
// epoch (fully correlated in time).
Matrix gaussian_nees(std::size_t runs, std::size_t epochs, double reported, unsigned seed, bool frozen = false) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n01;
  const auto draw = [&] { return navaid::draw_vector<3>([&] { return n01(rng); }); };
  Matrix out(runs);
  for (auto& run : out) {
    double value = 0.0;
    for (std::size_t k = 0; k < epochs; ++k) {
      if (!frozen || k == 0) {
        Mat3 A;
        A << draw(), draw(), draw();
        const Mat3 P = 0.01 * (A * A.transpose() + 0.1 * Mat3::Identity());
        const Vec3 e = Mat3(P.llt().matrixL()) * draw();
        value = nees(e, reported * P);
      }
      run.push_back(value);
    }
  }
  return out;
}

NeesSeries series(const std::string& name, std::vector<Timestamp> t, double value) {
  NeesSeries s{name, std::move(t), {}, {}};
  for (std::size_t k = 0; k < s.t.size(); ++k) {
    s.position.push_back(value + static_cast<double>(k));
    s.orientation.push_back(2.0 * value);
  }
  return s;
}

}  // namespace

TEST(MonteCarloNees, BoundsMatchChiSquareTables) {
  // chi2(2) has the closed-form quantile -2 ln(1 - p): N = 2 runs of a 1-dof NEES.
  const NeesBounds b2 = average_nees_bounds(2.0, 2.0, 0.95);
  EXPECT_NEAR(b2.lower, -std::log(0.975), 1e-10);
  EXPECT_NEAR(b2.upper, -std::log(0.025), 1e-10);
  // 20 runs of a 3-dof NEES: chi2(60) 2.5 % / 97.5 % quantiles 40.482 / 83.298 (tables), / 20.
  const NeesBounds b60 = average_nees_bounds(60.0, 20.0, 0.95);
  EXPECT_NEAR(b60.lower, 40.482 / 20, 1e-4);
  EXPECT_NEAR(b60.upper, 83.298 / 20, 1e-4);
  EXPECT_DOUBLE_EQ(b60.dof, 60.0);
  EXPECT_TRUE(b60.contains(3.0));
  EXPECT_FALSE(b60.contains(1.9));
}

TEST(MonteCarloNees, HandComputedAnees) {
  // 2 runs, 1 dof: ANEES_k bounds [-ln 0.975, -ln 0.025] = [0.0253, 3.689].
  const Matrix v{{0.0, 2.0, 9.0}, {0.02, 4.0, 1.0}};
  const AneesStatistics s = anees_statistics(v, 1);
  ASSERT_EQ(s.anees.size(), 3u);
  EXPECT_DOUBLE_EQ(s.anees[0], 0.01);
  EXPECT_DOUBLE_EQ(s.anees[1], 3.0);
  EXPECT_DOUBLE_EQ(s.anees[2], 5.0);
  EXPECT_EQ(s.epochs_below, 1u);
  EXPECT_EQ(s.epochs_above, 1u);
  EXPECT_DOUBLE_EQ(s.fraction_inside, 1.0 / 3.0);
  EXPECT_NEAR(s.time_average, 8.01 / 3.0, 1e-12);
  EXPECT_NEAR(s.run_averages[0], 11.0 / 3.0, 1e-12);
  EXPECT_NEAR(s.run_averages[1], 5.02 / 3.0, 1e-12);
  EXPECT_NEAR(s.epoch_bounds.lower, -std::log(0.975), 1e-10);
  EXPECT_NEAR(s.epoch_bounds.upper, -std::log(0.025), 1e-10);
  // Time average: conservative = per-epoch bounds; independent epochs: chi2(N K d) = chi2(6), / 6.
  EXPECT_DOUBLE_EQ(s.conservative_bounds.lower, s.epoch_bounds.lower);
  EXPECT_DOUBLE_EQ(s.conservative_bounds.upper, s.epoch_bounds.upper);
  EXPECT_DOUBLE_EQ(s.independent_bounds.dof, 6.0);
  EXPECT_NEAR(s.independent_bounds.upper, 14.449375 / 6.0, 1e-5);  // chi2(6) 97.5 % quantile
  EXPECT_TRUE(s.consistent());
  // K_eff = 2 mean^2 / (d var), var over runs with N - 1: clamped to [1, K] = 1 here.
  const double m = 8.01 / 3.0, var = std::pow(11.0 / 3.0 - m, 2) + std::pow(5.02 / 3.0 - m, 2);
  EXPECT_DOUBLE_EQ(s.effective_epochs, std::clamp(2.0 * m * m / var, 1.0, 3.0));
}

TEST(MonteCarloNees, ConsistentRunsFallInsideAtTheExpectedRate) {
  const std::size_t K = 400;
  const AneesStatistics s = anees_statistics(gaussian_nees(20, K, 1.0, 11), 3);
  // Independent epochs: the count inside is Binomial(K, 0.95), sd 0.011 in the fraction.
  EXPECT_GT(s.fraction_inside, 0.90);
  EXPECT_LT(s.fraction_inside, 0.99);
  EXPECT_TRUE(s.consistent());
  // Epochs truly independent here: the time average passes even the narrow independent-epoch test
  // (at 99.99 %) and the effective epoch count is of the order of K (var estimated from 20 runs).
  EXPECT_TRUE(average_nees_bounds(20.0 * K * 3, 20.0 * K, 0.9999).contains(s.time_average));
  EXPECT_LT(s.independent_bounds.upper - s.independent_bounds.lower, 0.1 * (s.epoch_bounds.upper - s.epoch_bounds.lower));
  EXPECT_GT(s.effective_epochs, 0.3 * K);
}

TEST(MonteCarloNees, CorrelatedEpochsNeedTheConservativeBounds) {
  // Each run's error frozen over time: the time average is a mean of 20 chi2(3) samples.
  const std::size_t K = 300;
  const AneesStatistics s = anees_statistics(gaussian_nees(20, K, 1.0, 5, true), 3);
  EXPECT_TRUE(s.consistent());
  EXPECT_LT(s.effective_epochs, 3.0);  // ~1 when nothing averages out over time
  EXPECT_TRUE(s.effective_bounds.contains(s.time_average));
  EXPECT_FALSE(s.independent_bounds.contains(s.time_average));  // would wrongly reject
}

TEST(MonteCarloNees, OverConfidentRunsFallOutside) {
  // The estimator reports P / 4: every NEES is 4x too large.
  const AneesStatistics s = anees_statistics(gaussian_nees(20, 200, 0.25, 3), 3);
  EXPECT_FALSE(s.consistent());
  EXPECT_GT(s.time_average, s.conservative_bounds.upper);
  EXPECT_LT(s.fraction_inside, 0.05);
  EXPECT_GT(s.epochs_above, 190u);
  // And an under-confident one (4 P) falls below.
  const AneesStatistics u = anees_statistics(gaussian_nees(20, 200, 4.0, 3), 3);
  EXPECT_FALSE(u.consistent());
  EXPECT_LT(u.time_average, u.conservative_bounds.lower);
}

TEST(MonteCarloNees, RunsAreMatchedOnTheirSharedEpochs) {
  // Run b initializes two frames later and stops one frame earlier.
  const NeesSeries a = series("a", {10, 20, 30, 40, 50, 60}, 1.0);
  const NeesSeries b = series("b", {30, 40, 50}, 3.0);
  const MonteCarloNees m = monte_carlo_nees({a, b});
  EXPECT_EQ(m.t, (std::vector<Timestamp>{30, 40, 50}));
  EXPECT_EQ(m.dropped, (std::vector<std::size_t>{3, 0}));
  EXPECT_EQ(m.runs, (std::vector<std::string>{"a", "b"}));
  // a at 30 ns is its third value (1 + 2), b's first is 3: ANEES 3.
  EXPECT_DOUBLE_EQ(m.position.anees[0], 0.5 * (3.0 + 3.0));
  EXPECT_DOUBLE_EQ(m.position.anees[2], 0.5 * (5.0 + 5.0));
  EXPECT_DOUBLE_EQ(m.orientation.anees[1], 0.5 * (2.0 + 6.0));
  EXPECT_EQ(m.position.runs, 2u);
  EXPECT_EQ(m.orientation.epochs, 3u);
}

TEST(MonteCarloNees, SkipLeavesOutTheStartOfTheSharedSpan) {
  const NeesSeries a = series("a", {10, 20, 30, 40, 50, 60}, 1.0);
  const NeesSeries b = series("b", {30, 40, 50, 60}, 3.0);
  const MonteCarloNees m = monte_carlo_nees({a, b}, 0.95, 15);  // span starts at 30: keep 50, 60
  EXPECT_EQ(m.t, (std::vector<Timestamp>{50, 60}));
  EXPECT_EQ(m.dropped, (std::vector<std::size_t>{4, 2}));
  EXPECT_DOUBLE_EQ(m.position.anees[0], 0.5 * ((1.0 + 4) + (3.0 + 2)));  // a and b at 50 ns
  expect_throw<Error>([&] { monte_carlo_nees({a, b}, 0.95, 31); }, "skip past the end");
  expect_throw<Error>([&] { monte_carlo_nees({a, b}, 0.95, -1); }, "negative skip");
}

TEST(MonteCarloNees, RunsWithDifferentEpochsAreAnError) {
  const NeesSeries a = series("seed1", {1'000'000'000, 2'000'000'000, 3'000'000'000}, 1.0);
  const NeesSeries b = series("seed2", {1'000'000'000, 2'500'000'000, 3'000'000'000}, 1.0);
  const auto e = expect_throw<Error>([&] { monte_carlo_nees({a, b}); });
  ASSERT_TRUE(e);
  const std::string what = e->what();
  EXPECT_NE(what.find("do not share their epochs"), std::string::npos) << what;
  EXPECT_NE(what.find("2.000000000 s is in 'seed1' only"), std::string::npos) << what;
  // A frame missing in the middle of the shared span is the same error.
  const NeesSeries c = series("seed3", {1'000'000'000, 3'000'000'000}, 1.0);
  const auto missing = expect_throw<Error>([&] { monte_carlo_nees({a, c}); });
  ASSERT_TRUE(missing);
  EXPECT_NE(std::string(missing->what()).find("2.000000000 s is in 'seed1' only"), std::string::npos) << missing->what();
  // No overlap at all.
  const auto apart = expect_throw<Error>([&] { monte_carlo_nees({series("x", {1, 2}, 1.0), series("y", {3, 4}, 1.0)}); });
  ASSERT_TRUE(apart);
  EXPECT_NE(std::string(apart->what()).find("share no epoch"), std::string::npos);
}

TEST(MonteCarloNees, BadInputIsAnError) {
  const NeesSeries a = series("a", {1, 2, 3}, 1.0);
  expect_throw<Error>([&] { monte_carlo_nees({a}); }, "one run");
  expect_throw<Error>([&] { monte_carlo_nees({a, series("empty", {}, 1.0)}); }, "empty run");
  NeesSeries short_values = a;
  short_values.orientation.pop_back();
  expect_throw<Error>([&] { monte_carlo_nees({a, short_values}); }, "unequal lengths");
  expect_throw<Error>([&] { monte_carlo_nees({a, series("back", {1, 3, 2}, 1.0)}); }, "times not increasing");
  NeesSeries negative = a;
  negative.position[1] = -0.5;
  expect_throw<Error>([&] { monte_carlo_nees({a, negative}); }, "negative NEES");
  NeesSeries nan = a;
  nan.orientation[0] = std::nan("");
  expect_throw<Error>([&] { monte_carlo_nees({a, nan}); }, "NaN NEES");
  expect_throw<Error>([] { anees_statistics({{1.0, 2.0}, {1.0}}, 3); }, "ragged matrix");
  expect_throw<Error>([] { anees_statistics({{1.0}, {1.0}}, 0); }, "dof 0");
  expect_throw<Error>([] { anees_statistics({{1.0}, {1.0}}, 3, 1.0); }, "confidence 1");
  expect_throw<Error>([] { average_nees_bounds(0.0, 1.0, 0.95); }, "dof 0 bounds");
}

TEST(MonteCarloNees, SeriesAreThoseOfFirstStateNees) {
  std::vector<navaid::io::StampedPose> gt;
  std::vector<navaid::StateEstimate> estimates;
  for (int k = 0; k < 20; ++k) {
    const Timestamp t = 1'000'000'000LL + k * 100'000'000LL;
    const SE3 pose(navaid::quat_from_rpy(0.01 * k, -0.02, 0.1 * k), Vec3(0.3 * k, 0.1 * k * k, 1.0));
    gt.push_back({t, pose});
    navaid::StateEstimate s;
    s.t = t;
    // Offset by a yaw and a shift (the estimator's own world) and a small error growing over time.
    s.T_W_B = SE3(navaid::quat_from_rpy(0, 0, 0.7), Vec3(2, -1, 0)) * pose * SE3(navaid::quat_from_rpy(0.001 * k, 0, 0), Vec3(0.01 * k, 0, 0));
    s.covariance = navaid::Mat15::Identity() * 1e-3;
    s.mode = k < 3 ? navaid::EstimatorMode::kInitializing : navaid::EstimatorMode::kRgbdVio;
    estimates.push_back(s);
  }
  const NeesSeries s = first_state_nees_series("run", estimates, gt);
  const NeesEvaluation e = first_state_nees(align_to_first_state(estimates, gt), gt);
  EXPECT_EQ(s.name, "run");
  EXPECT_EQ(s.t, e.t);
  EXPECT_EQ(s.position, e.position);
  EXPECT_EQ(s.orientation, e.orientation);
  EXPECT_EQ(s.t.size(), 17u);  // the initializing frames are left out
  std::vector<navaid::StateEstimate> initializing(estimates.begin(), estimates.begin() + 3);
  expect_throw<Error>([&] { first_state_nees_series("init", initializing, gt); }, "only initializing frames");
}

TEST(RunFolder, ReadsEstimatesAsNavaidRunWritesThem) {
  navaid::testing::ScratchDir dir("run_folder");
  const std::string header =
      "t_ns,px,py,pz,qw,qx,qy,qz,vx,vy,vz,bgx,bgy,bgz,bax,bay,baz,mode,"
      "cov_pxx,cov_pxy,cov_pxz,cov_pyy,cov_pyz,cov_pzz,cov_rxx,cov_rxy,cov_rxz,cov_ryy,cov_ryz,cov_rzz,"
      "enu_yaw,enu_x,enu_y,enu_z\n";
  navaid::testing::write_text(
      dir / "estimates.csv",
      header +
          "100,1,2,3,1,0,0,0,0.5,0,0,0,0,0,0,0,0,initializing,1,0,0,1,0,1,1,0,0,1,0,1,,,,\n"
          "200,1.5,2,3,0.7071067811865476,0,0,0.7071067811865476,0,0,0,0.001,0,0,0,0.02,0,rgbd-vio,"
          "0.04,0.01,0.002,0.09,-0.02,0.01,1e-4,2e-5,0,3e-4,0,5e-4,0.1,1,2,3\n");
  const auto e = read_estimates_csv(dir / "estimates.csv");
  ASSERT_EQ(e.size(), 2u);
  EXPECT_EQ(e[0].mode, navaid::EstimatorMode::kInitializing);
  EXPECT_EQ(e[1].t, 200);
  EXPECT_EQ(e[1].mode, navaid::EstimatorMode::kRgbdVio);
  EXPECT_DOUBLE_EQ(e[1].T_W_B.t.x(), 1.5);
  EXPECT_NEAR(e[1].T_W_B.q.z(), std::sqrt(0.5), 1e-15);
  EXPECT_DOUBLE_EQ(e[1].b_a.y(), 0.02);
  const PoseWithCovariance p = pose_with_covariance(e[1]);
  EXPECT_DOUBLE_EQ(p.position_covariance(0, 1), 0.01);
  EXPECT_DOUBLE_EQ(p.position_covariance(2, 1), -0.02);
  EXPECT_DOUBLE_EQ(p.position_covariance(2, 2), 0.01);
  EXPECT_DOUBLE_EQ(p.rotation_covariance(1, 0), 2e-5);
  EXPECT_DOUBLE_EQ(p.rotation_covariance(2, 2), 5e-4);
  EXPECT_DOUBLE_EQ(e[1].covariance(0, 3), 0.0);

  navaid::testing::write_text(dir / "bad_mode.csv", header + "100,1,2,3,1,0,0,0,0,0,0,0,0,0,0,0,0,flying,1,0,0,1,0,1,1,0,0,1,0,1,,,,\n");
  const auto bad_mode = expect_throw<IoError>([&] { read_estimates_csv(dir / "bad_mode.csv"); });
  ASSERT_TRUE(bad_mode);
  EXPECT_EQ(bad_mode->line(), 2u);
  EXPECT_NE(std::string(bad_mode->what()).find("flying"), std::string::npos);
  navaid::testing::write_text(dir / "bad_header.csv", "t,x,y\n");
  expect_throw<IoError>([&] { read_estimates_csv(dir / "bad_header.csv"); }, "wrong header");
  navaid::testing::write_text(dir / "short.csv", header + "100,1,2,3\n");
  expect_throw<IoError>([&] { read_estimates_csv(dir / "short.csv"); }, "short row");
  expect_throw<IoError>([&] { read_estimates_csv(dir / "missing.csv"); }, "missing file");
}

TEST(RunFolder, RecordingComesFromSummaryJson) {
  navaid::testing::ScratchDir dir("run_summary");
  navaid::testing::write_text(dir / "summary.json", R"({"recording": "/data/rec-seed3", "frames": 10})");
  EXPECT_EQ(run_recording(dir.path()), std::filesystem::path("/data/rec-seed3"));
  navaid::testing::write_text(dir / "summary.json", R"({"frames": 10})");
  expect_throw<IoError>([&] { run_recording(dir.path()); }, "no recording key");
  navaid::testing::write_text(dir / "summary.json", "{not json");
  expect_throw<IoError>([&] { run_recording(dir.path()); }, "invalid JSON");
  expect_throw<IoError>([&] { run_recording(dir / "nowhere"); }, "no summary.json");
}
