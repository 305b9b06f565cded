// Chi-square CDF and quantiles against table values: the printed tables (Abramowitz & Stegun 26.4)
// give 3-4 decimals; these are the same points to 10 significant digits (scipy.stats.chi2.ppf).
#include <gtest/gtest.h>

#include <cmath>

#include "navaid/core/errors.hpp"
#include "navaid/evaluation/chi_square.hpp"

using navaid::Error;
using namespace navaid::evaluation;

TEST(ChiSquare, QuantilesMatchTables) {
  struct Row {
    double p, dof, x;
  };
  const Row rows[] = {
      {0.95, 1, 3.841458821},   {0.99, 1, 6.634896601},    {0.05, 1, 0.00393214},     {0.025, 3, 0.2157952826},
      {0.975, 3, 9.348403604},  {0.001, 3, 0.02429758582}, {0.999, 3, 16.26623620},   {0.95, 2, 5.991464547},
      {0.05, 10, 3.940299136},  {0.95, 10, 18.30703805},   {0.99, 30, 50.89218131},   {0.05, 100, 77.92946517},
      {0.95, 100, 124.3421134}, {0.025, 1000, 914.2571538}, {0.975, 1000, 1089.530913}, {0.025, 30000, 29521.80594},
      {0.975, 30000, 30481.98266},
  };
  for (const Row& r : rows) {
    EXPECT_NEAR(chi_square_quantile(r.p, r.dof), r.x, 2e-9 * r.x) << "p=" << r.p << " dof=" << r.dof;
    EXPECT_NEAR(chi_square_cdf(r.x, r.dof), r.p, 1e-9) << "p=" << r.p << " dof=" << r.dof;
  }
}

TEST(ChiSquare, ClosedFormsForTwoDegreesAndIncompleteGamma) {
  // chi2(2) is exponential with mean 2: F(x) = 1 - exp(-x / 2), quantile -2 log(1 - p).
  for (double p : {1e-8, 0.01, 0.3, 0.5, 0.9, 0.999999}) {
    EXPECT_NEAR(chi_square_quantile(p, 2), -2.0 * std::log1p(-p), 1e-12 * (1 - 2.0 * std::log1p(-p))) << p;
  }
  // P(1, x) = 1 - e^-x; P(1/2, x) = erf(sqrt(x)); P + Q = 1 on both sides of the a + 1 switch.
  for (double x : {0.1, 1.0, 2.5, 7.0, 30.0}) {
    EXPECT_NEAR(regularized_gamma_p(1.0, x), -std::expm1(-x), 1e-15);
    EXPECT_NEAR(regularized_gamma_p(0.5, x), std::erf(std::sqrt(x)), 1e-15);
    EXPECT_NEAR(regularized_gamma_q(0.5, x), std::erfc(std::sqrt(x)), 1e-14 * std::erfc(std::sqrt(x)) + 1e-300);
    EXPECT_NEAR(regularized_gamma_p(4.5, x) + regularized_gamma_q(4.5, x), 1.0, 1e-15);
  }
  EXPECT_EQ(chi_square_cdf(0.0, 3), 0.0);
  EXPECT_EQ(chi_square_cdf(-1.0, 3), 0.0);
}

TEST(ChiSquare, NormalQuantile) {
  EXPECT_NEAR(normal_quantile(0.975), 1.959963984540054, 1e-14);
  EXPECT_NEAR(normal_quantile(0.5), 0.0, 1e-15);
  EXPECT_NEAR(normal_quantile(1e-6), -4.753424308822899, 1e-12);
  EXPECT_NEAR(normal_quantile(0.999), -normal_quantile(0.001), 1e-13);
}

TEST(ChiSquare, BadArguments) {
  EXPECT_THROW(chi_square_quantile(0.0, 3), Error);
  EXPECT_THROW(chi_square_quantile(1.0, 3), Error);
  EXPECT_THROW(chi_square_quantile(0.5, 0), Error);
  EXPECT_THROW(chi_square_cdf(1.0, -2), Error);
  EXPECT_THROW(regularized_gamma_p(0.0, 1.0), Error);
  EXPECT_THROW(regularized_gamma_q(1.0, -1.0), Error);
  EXPECT_THROW(normal_quantile(std::nan("")), Error);
}
