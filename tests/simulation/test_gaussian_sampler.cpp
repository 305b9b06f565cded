#include "navaid/simulation/gaussian_sampler.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace navaid::simulation {
namespace {

double normal_cdf(double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); }

TEST(GaussianSampler, MomentsOfAStandardNormal) {
  std::mt19937_64 rng(1);
  GaussianSampler g;
  const int n = 1000000;
  double s1 = 0, s2 = 0, s3 = 0, s4 = 0;
  for (int i = 0; i < n; ++i) {
    const double x = g(rng);
    s1 += x;
    s2 += x * x;
    s3 += x * x * x;
    s4 += x * x * x * x;
  }
  // Standard errors: mean 1/sqrt(n), E x^2 sqrt(2/n), E x^3 sqrt(15/n), E x^4 sqrt(96/n).
  const double rn = std::sqrt(static_cast<double>(n));
  EXPECT_NEAR(s1 / n, 0.0, 4.5 / rn);
  EXPECT_NEAR(s2 / n, 1.0, 4.5 * std::sqrt(2.0) / rn);
  EXPECT_NEAR(s3 / n, 0.0, 4.5 * std::sqrt(15.0) / rn);
  EXPECT_NEAR(s4 / n, 3.0, 4.5 * std::sqrt(96.0) / rn);
}

TEST(GaussianSampler, HistogramMatchesTheNormalCdfIncludingTheTail) {
  std::mt19937_64 rng(2);
  GaussianSampler g;
  const int n = 2000000;
  // Bins of width 0.25 on [-4, 4] plus the two tails beyond |x| = 4 (past the ziggurat's r = 3.65,
  // so the tail sampler is checked too); bins narrow enough to see a wrong wedge in any layer.
  constexpr int kBins = 32;
  std::vector<double> count(kBins + 2, 0.0);
  for (int i = 0; i < n; ++i) {
    const double x = g(rng);
    const int b = x < -4.0 ? 0 : x >= 4.0 ? kBins + 1 : 1 + static_cast<int>((x + 4.0) / 0.25);
    count[static_cast<std::size_t>(b)] += 1.0;
  }
  double chi2 = 0.0;
  for (int b = 0; b < kBins + 2; ++b) {
    const double lo = b == 0 ? -INFINITY : -4.0 + 0.25 * (b - 1);
    const double hi = b == kBins + 1 ? INFINITY : -4.0 + 0.25 * b;
    const double expected = n * (normal_cdf(hi) - normal_cdf(lo));
    chi2 += std::pow(count[static_cast<std::size_t>(b)] - expected, 2) / expected;
  }
  // 33 degrees of freedom: P(chi2 > 70) ~ 2e-4.
  EXPECT_LT(chi2, 70.0);
  // Tail beyond 4: expected 2 n * 3.17e-5 = 127 draws.
  const double tail = count.front() + count.back();
  const double expected_tail = n * 2.0 * normal_cdf(-4.0);
  EXPECT_NEAR(tail, expected_tail, 4.5 * std::sqrt(expected_tail));
}

TEST(GaussianSampler, DeterministicForAnEngineState) {
  std::mt19937_64 a(5), b(5);
  GaussianSampler ga, gb;
  for (int i = 0; i < 1000; ++i) ASSERT_EQ(ga(a), gb(b));
}

}  // namespace
}  // namespace navaid::simulation
