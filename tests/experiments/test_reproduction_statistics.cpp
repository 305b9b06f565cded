// Student's t and the confidence intervals of a reproduction: quantiles against closed forms and
// high-precision values, intervals on hand-computed samples, the bootstrap's coverage by simulation.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "navaid/core/errors.hpp"
#include "navaid/experiments/reproduction_statistics.hpp"

using navaid::Error;
using namespace navaid::experiments;

TEST(ReproductionStatistics, IncompleteBetaClosedFormsAndReferenceValues) {
  for (double x : {0.0, 0.05, 0.3, 0.5, 0.77, 1.0}) {
    EXPECT_NEAR(regularized_beta(1.0, 1.0, x), x, 1e-15);
    EXPECT_NEAR(regularized_beta(3.0, 1.0, x), x * x * x, 1e-14);
    EXPECT_NEAR(regularized_beta(1.0, 4.0, x), 1.0 - std::pow(1.0 - x, 4.0), 1e-14);
  }
  EXPECT_NEAR(regularized_beta(6.5, 6.5, 0.5), 0.5, 1e-14);
  // scipy.stats.beta.cdf
  EXPECT_NEAR(regularized_beta(2.5, 7.0, 0.3), 0.6412224629717214, 1e-13);
  EXPECT_NEAR(regularized_beta(20.0, 25.0, 0.45), 0.5341355634470708, 1e-13);
  EXPECT_NEAR(regularized_beta(0.5, 0.5, 0.1), 0.20483276469913345, 1e-13);  // 2/pi asin(sqrt x)
}

TEST(ReproductionStatistics, StudentTQuantilesMatchClosedFormsAndTables) {
  for (double p : {0.6, 0.9, 0.975, 0.999}) {
    EXPECT_NEAR(student_t_quantile(p, 1.0), std::tan(M_PI * (p - 0.5)), 1e-10 * std::tan(M_PI * (p - 0.5)));  // Cauchy
    EXPECT_NEAR(student_t_quantile(p, 2.0), (2 * p - 1) / std::sqrt(2 * p * (1 - p)), 1e-11);
    EXPECT_NEAR(student_t_quantile(1.0 - p, 5.0), -student_t_quantile(p, 5.0), 1e-12);
  }
  struct Row {
    double p, dof, t;
  };
  // mpmath (30 digits) root of the regularized incomplete beta form; scipy's t.ppf is off by up to 1e-9.
  const Row rows[] = {{0.975, 4, 2.7764451051977935}, {0.975, 9, 2.262157162798205},  {0.975, 24, 2.0638985616280254},
                      {0.95, 10, 1.8124611228116759}, {0.995, 30, 2.749995653567225}, {0.975, 1000, 1.9623390808264081}};
  for (const Row& r : rows) {
    EXPECT_NEAR(student_t_quantile(r.p, r.dof), r.t, 1e-10 * r.t) << r.p << " " << r.dof;
    EXPECT_NEAR(student_t_cdf(r.t, r.dof), r.p, 1e-12) << r.p << " " << r.dof;
  }
  EXPECT_NEAR(student_t_cdf(-5.0, 3.0), 0.007696219036651148, 1e-14);
  EXPECT_NEAR(student_t_cdf(1.5, 7.5), 0.9127597147067679, 1e-13);
  EXPECT_EQ(student_t_quantile(0.5, 3.0), 0.0);
}

TEST(ReproductionStatistics, MeanIntervalOnAHandComputedSample) {
  // {1..5}: mean 3, s = sqrt(2.5), half width t(0.975, 4) s / sqrt(5).
  const MeanInterval m = mean_interval({1, 2, 3, 4, 5});
  EXPECT_EQ(m.n, 5u);
  EXPECT_DOUBLE_EQ(m.mean, 3.0);
  EXPECT_NEAR(m.std, std::sqrt(2.5), 1e-15);
  const double half = 2.7764451051977935 * std::sqrt(2.5) / std::sqrt(5.0);
  EXPECT_NEAR(m.low, 3.0 - half, 1e-10);
  EXPECT_NEAR(m.high, 3.0 + half, 1e-10);
  // A 90 % interval is narrower; one sample has no interval.
  const MeanInterval m90 = mean_interval({1, 2, 3, 4, 5}, 0.90);
  EXPECT_GT(m90.low, m.low);
  const MeanInterval one = mean_interval({0.25});
  EXPECT_EQ(one.mean, 0.25);
  EXPECT_TRUE(std::isnan(one.low) && std::isnan(one.high));
}

TEST(ReproductionStatistics, PairedTRelativeChangeByHand) {
  // Per-pair changes -0.5, -0.5, -0.25: mean -5/12, s = sqrt(1/48), half = t(0.975, 2) s / sqrt(3).
  const RelativeChange c = relative_change_paired_t({1, 2, 3}, {2, 4, 4});
  EXPECT_EQ(c.pairs, 3u);
  EXPECT_NEAR(c.estimate, -5.0 / 12.0, 1e-15);
  const double half = 4.302652729749464 * std::sqrt(1.0 / 48.0) / std::sqrt(3.0);
  EXPECT_NEAR(c.low, -5.0 / 12.0 - half, 1e-10);
  EXPECT_NEAR(c.high, -5.0 / 12.0 + half, 1e-10);
}

TEST(ReproductionStatistics, BootstrapChangeOfTheMeans) {
  // The estimate is the change of the sums, not the mean of the per-pair changes.
  const RelativeChange c = relative_change_bootstrap({1, 2, 3}, {2, 4, 4});
  EXPECT_NEAR(c.estimate, 6.0 / 10.0 - 1.0, 1e-15);
  EXPECT_LE(c.low, c.estimate);
  EXPECT_GE(c.high, c.estimate);
  // Every resample of pairs with one common ratio has that ratio: the interval collapses.
  const RelativeChange same = relative_change_bootstrap({0.7, 1.4, 2.1, 0.35}, {1, 2, 3, 0.5});
  EXPECT_NEAR(same.estimate, -0.3, 1e-15);
  EXPECT_NEAR(same.low, -0.3, 1e-12);
  EXPECT_NEAR(same.high, -0.3, 1e-12);
  // Deterministic by seed.
  const std::vector<double> a{0.9, 1.1, 0.5, 0.7, 1.3}, b{1.0, 1.5, 0.9, 0.8, 1.6};
  const RelativeChange r1 = relative_change_bootstrap(a, b, 0.95, 2000, 7), r2 = relative_change_bootstrap(a, b, 0.95, 2000, 7);
  EXPECT_EQ(r1.low, r2.low);
  EXPECT_EQ(r1.high, r2.high);
}

TEST(ReproductionStatistics, BootstrapIntervalCoversTheTrueChange) {
  // Pairs as in a study: per pair a baseline RMSE b ~ U(0.5, 1.5) and the method's RMSE
  // 0.75 b (1 + 0.2 n), n standard normal, so the change of the means is -25 %. Over 300 studies
  // of 25 pairs the 95 % interval must cover it in 0.90-0.99 of them: the percentile bootstrap
  // covers a little less than nominal at n = 25; 300 Bernoulli(0.95) trials stay within
  // 0.95 +- 3.3 sd (sd 1.3 %) with probability > 0.999.
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<double> base(0.5, 1.5);
  std::normal_distribution<double> noise(0.0, 0.2);
  int covered = 0;
  const int studies = 300;
  for (int s = 0; s < studies; ++s) {
    std::vector<double> m(25), b(25);
    for (int i = 0; i < 25; ++i) {
      b[i] = base(rng);
      m[i] = 0.75 * b[i] * (1.0 + noise(rng));
    }
    const RelativeChange c = relative_change_bootstrap(m, b, 0.95, 1000, static_cast<std::uint64_t>(s));
    covered += c.low <= -0.25 && -0.25 <= c.high;
  }
  EXPECT_GE(covered, static_cast<int>(0.90 * studies));
  EXPECT_LE(covered, static_cast<int>(0.99 * studies));
}

TEST(ReproductionStatistics, BadInputIsAnError) {
  EXPECT_THROW(regularized_beta(0.0, 1.0, 0.5), Error);
  EXPECT_THROW(regularized_beta(1.0, 1.0, 1.5), Error);
  EXPECT_THROW(student_t_quantile(1.0, 3.0), Error);
  EXPECT_THROW(student_t_quantile(0.5, 0.0), Error);
  EXPECT_THROW(student_t_cdf(NAN, 3.0), Error);
  EXPECT_THROW(mean_interval({}), Error);
  EXPECT_THROW(mean_interval({1.0, NAN}), Error);
  EXPECT_THROW(mean_interval({1.0, 2.0}, 1.0), Error);
  EXPECT_THROW(relative_change_paired_t({1.0}, {1.0, 2.0}), Error);
  EXPECT_THROW(relative_change_paired_t({}, {}), Error);
  EXPECT_THROW(relative_change_paired_t({1.0}, {0.0}), Error);
  EXPECT_THROW(relative_change_bootstrap({1.0, 2.0}, {1.0, INFINITY}), Error);
  EXPECT_THROW(relative_change_bootstrap({1.0, 2.0}, {1.0, 2.0}, 0.95, 50), Error);
}

TEST(ReproductionStatistics, WilsonIntervalsOfProportions) {
  // Closed forms: 0 of n gives [0, z^2 / (n + z^2)]; n of n the mirror image.
  const double z2 = 1.959963984540054 * 1.959963984540054;
  const ProportionInterval none = wilson_interval(0, 10);
  EXPECT_EQ(none.rate, 0.0);
  EXPECT_NEAR(none.low, 0.0, 1e-12);
  EXPECT_NEAR(none.high, z2 / (10 + z2), 1e-6);
  const ProportionInterval all = wilson_interval(10, 10);
  EXPECT_NEAR(all.low, 1.0 - none.high, 1e-9);
  EXPECT_NEAR(all.high, 1.0, 1e-12);
  // 8 of 10 (statsmodels proportion_confint(8, 10, method="wilson")).
  const ProportionInterval eight = wilson_interval(8, 10);
  EXPECT_NEAR(eight.low, 0.4901625, 1e-5);
  EXPECT_NEAR(eight.high, 0.9433178, 1e-5);
  EXPECT_THROW(wilson_interval(1, 0), Error);
  EXPECT_THROW(wilson_interval(11, 10), Error);
}

namespace {

// Welch's test against values computed by hand: a = {1, 2, 3, 4} (mean 2.5, var 5/3), b = {2, 4,
// 6, 8, 10} (mean 6, var 10): t = -3.5 / sqrt(5/12 + 2) = -2.2514, dof = (29/12)^2 /
// ((5/12)^2 / 3 + 2^2 / 4) = 5.5208; two-sided p (the t density integrated numerically) = 0.0691.
TEST(WelchTest, KnownAnswerAndDegenerateSamples) {
  using navaid::experiments::welch_t_test;
  const auto w = welch_t_test({1, 2, 3, 4}, {2, 4, 6, 8, 10});
  EXPECT_NEAR(w.t, -2.2514, 1e-4);
  EXPECT_NEAR(w.dof, 5.5208, 1e-4);
  EXPECT_NEAR(w.p, 0.0691, 5e-4);
  EXPECT_EQ(welch_t_test({1, 1}, {1, 1, 1}).p, 1.0);
  EXPECT_EQ(welch_t_test({1, 1}, {2, 2}).p, 0.0);
  EXPECT_THROW(welch_t_test({1}, {1, 2}), navaid::Error);
}

}  // namespace
