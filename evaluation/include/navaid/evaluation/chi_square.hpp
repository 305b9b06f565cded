#pragma once
// Chi-square distribution without Boost: the regularized incomplete gamma function by its power
// series (x < a + 1) and its Legendre continued fraction (modified Lentz, otherwise), accurate to
// about 1e-14 relative; quantiles by safeguarded Newton iteration on the CDF, started from the
// Wilson-Hilferty cube-root normal approximation.
namespace navaid::evaluation {

/// P(a, x) = gamma(a, x) / Gamma(a), a > 0, x >= 0. Throws navaid::Error otherwise.
double regularized_gamma_p(double a, double x);
/// Q(a, x) = 1 - P(a, x), computed directly (no cancellation in the upper tail).
double regularized_gamma_q(double a, double x);

/// P(X <= x) for X ~ chi2(dof), dof > 0.
double chi_square_cdf(double x, double dof);
/// The x with chi_square_cdf(x, dof) = p, 0 < p < 1. Throws navaid::Error otherwise.
double chi_square_quantile(double p, double dof);

/// Standard normal quantile (Acklam's rational approximation refined by one Halley step, ~1e-15).
double normal_quantile(double p);

}  // namespace navaid::evaluation
