#pragma once
// Statistics of a reproduction: confidence intervals over Monte-Carlo seeds, and the relative
// change of one method against a baseline over paired runs (same recording, same seed, hence the
// same simulated data). Student's t distribution without Boost, like chi_square.hpp: the
// regularized incomplete beta function by its continued fraction (modified Lentz), quantiles by
// bisection on the CDF.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace navaid::experiments {

/// I_x(a, b), a > 0, b > 0, 0 <= x <= 1. Throws navaid::Error otherwise.
double regularized_beta(double a, double b, double x);

/// P(T <= t) for T ~ Student's t with `dof` > 0 degrees of freedom.
double student_t_cdf(double t, double dof);
/// The t with student_t_cdf(t, dof) = p, 0 < p < 1, dof > 0. Throws navaid::Error otherwise.
double student_t_quantile(double p, double dof);

/// Mean of n samples with the two-sided t interval mean ± t_{(1+level)/2, n-1} s / sqrt(n).
struct MeanInterval {
  std::size_t n = 0;
  double mean = 0;
  double std = 0;   ///< sample standard deviation (0 when n = 1)
  double low = 0;   ///< NaN when n = 1 (no spread to estimate)
  double high = 0;  ///< NaN when n = 1
};

/// Throws navaid::Error on an empty sample, a non-finite value or a level outside (0, 1).
MeanInterval mean_interval(const std::vector<double>& values, double level = 0.95);

/// A proportion k / n with Wilson's score interval (good at 0 % and 100 %, where the normal
/// approximation collapses to a point).
struct ProportionInterval {
  std::size_t n = 0, k = 0;
  double rate = 0, low = 0, high = 0;
};
/// Throws navaid::Error when n = 0, k > n or the level is outside (0, 1).
ProportionInterval wilson_interval(std::size_t k, std::size_t n, double level = 0.95);

/// A relative change of `method` against `baseline` (negative = method lower, i.e. better for an
/// error metric), as a fraction, with a two-sided confidence interval.
struct RelativeChange {
  std::size_t pairs = 0;
  double estimate = 0;
  double low = 0;   ///< NaN when there are too few pairs for an interval
  double high = 0;
};

/// Mean over pairs of method_i / baseline_i - 1 with the paired t interval. Throws navaid::Error
/// when the vectors differ in size, are empty, hold non-finite values or a baseline <= 0.
RelativeChange relative_change_paired_t(const std::vector<double>& method, const std::vector<double>& baseline,
                                        double level = 0.95);

/// The change of the means, sum(method) / sum(baseline) - 1 (how a paper's "reduces the mean
/// RMSE by x %" is computed), with a percentile bootstrap interval: `resamples` draws of the pairs
/// with replacement, deterministic for a given `seed`. Same errors as above, and resamples < 100.
RelativeChange relative_change_bootstrap(const std::vector<double>& method, const std::vector<double>& baseline,
                                         double level = 0.95, std::size_t resamples = 10000,
                                         std::uint64_t seed = 1);

/// Welch's two-sample t test of equal means (unequal variances): the statistic, the
/// Welch-Satterthwaite degrees of freedom and the two-sided p-value. p = 1 when both samples are
/// constant and equal, 0 when constant and different. Throws navaid::Error when a sample has fewer
/// than two values or a non-finite value.
struct WelchTest {
  double t = 0, dof = 0, p = 1;
};
WelchTest welch_t_test(const std::vector<double>& a, const std::vector<double>& b);

}  // namespace navaid::experiments
