#include "navaid/evaluation/chi_square.hpp"

#include <cmath>
#include <limits>
#include <string>

#include "navaid/core/errors.hpp"

namespace navaid::evaluation {
namespace {

constexpr double kEps = 1e-16;
constexpr int kMaxIterations = 100000;  // the series needs ~sqrt(a) log terms; generous for dof ~ 1e6

void require_gamma_args(double a, double x) {
  if (!(a > 0.0) || !std::isfinite(a) || !(x >= 0.0) || std::isnan(x))
    throw Error("incomplete gamma: needs a > 0 and x >= 0, got a=" + std::to_string(a) + " x=" + std::to_string(x));
}

// log(x^a e^-x / Gamma(a)), the common prefactor of both expansions.
double log_prefactor(double a, double x) { return a * std::log(x) - x - std::lgamma(a); }

// P(a, x) = x^a e^-x / Gamma(a) * sum_n x^n / (a (a+1) ... (a+n)), for x < a + 1.
double gamma_p_series(double a, double x) {
  double term = 1.0 / a, sum = term;
  for (int n = 1; n < kMaxIterations; ++n) {
    term *= x / (a + n);
    sum += term;
    if (std::abs(term) < std::abs(sum) * kEps) break;
  }
  return sum * std::exp(log_prefactor(a, x));
}

// Q(a, x) = x^a e^-x / Gamma(a) * 1/(x+1-a- 1(1-a)/(x+3-a- 2(2-a)/(x+5-a- ...))), for x >= a + 1,
// evaluated with the modified Lentz algorithm.
double gamma_q_continued_fraction(double a, double x) {
  constexpr double tiny = std::numeric_limits<double>::min() / kEps;
  double b = x + 1.0 - a;
  double c = 1.0 / tiny;
  double d = 1.0 / b;
  double f = d;
  for (int n = 1; n < kMaxIterations; ++n) {
    const double an = -n * (n - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::abs(c) < tiny) c = tiny;
    d = 1.0 / d;
    const double delta = d * c;
    f *= delta;
    if (std::abs(delta - 1.0) < kEps) break;
  }
  return f * std::exp(log_prefactor(a, x));
}

}  // namespace

double regularized_gamma_p(double a, double x) {
  require_gamma_args(a, x);
  if (x == 0.0) return 0.0;
  if (std::isinf(x)) return 1.0;
  return x < a + 1.0 ? gamma_p_series(a, x) : 1.0 - gamma_q_continued_fraction(a, x);
}

double regularized_gamma_q(double a, double x) {
  require_gamma_args(a, x);
  if (x == 0.0) return 1.0;
  if (std::isinf(x)) return 0.0;
  return x < a + 1.0 ? 1.0 - gamma_p_series(a, x) : gamma_q_continued_fraction(a, x);
}

double chi_square_cdf(double x, double dof) {
  if (!(dof > 0.0)) throw Error("chi-square: dof must be positive, got " + std::to_string(dof));
  if (x <= 0.0) return 0.0;
  return regularized_gamma_p(0.5 * dof, 0.5 * x);
}

double normal_quantile(double p) {
  if (!(p > 0.0 && p < 1.0)) throw Error("normal quantile: p must be in (0, 1), got " + std::to_string(p));
  // Acklam's rational approximations (relative error < 1.2e-9) for the central and tail regions.
  static const double a[] = {-3.969683028665376e+01, 2.209460984245205e+02, -2.759285104469687e+02,
                             1.383577518672690e+02,  -3.066479806614716e+01, 2.506628277459239e+00};
  static const double b[] = {-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
                             6.680131188771972e+01,  -1.328068155288572e+01};
  static const double c[] = {-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                             -2.549732539343734e+00, 4.374664141464968e+00,  2.938163982698783e+00};
  static const double d[] = {7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00,
                             3.754408661907416e+00};
  constexpr double p_low = 0.02425;
  double z;
  if (p < p_low) {
    const double q = std::sqrt(-2.0 * std::log(p));
    z = (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
        ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1.0);
  } else if (p <= 1.0 - p_low) {
    const double q = p - 0.5, r = q * q;
    z = (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
        (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1.0);
  } else {
    const double q = std::sqrt(-2.0 * std::log1p(-p));
    z = -(((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
        ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1.0);
  }
  // One Halley step on Phi(z) - p with the exact Phi from erfc.
  const double e = 0.5 * std::erfc(-z / std::sqrt(2.0)) - p;
  const double u = e * std::sqrt(2.0 * M_PI) * std::exp(0.5 * z * z);
  return z - u / (1.0 + 0.5 * z * u);
}

double chi_square_quantile(double p, double dof) {
  if (!(p > 0.0 && p < 1.0)) throw Error("chi-square quantile: p must be in (0, 1), got " + std::to_string(p));
  if (!(dof > 0.0) || !std::isfinite(dof)) throw Error("chi-square quantile: dof must be positive, got " + std::to_string(dof));
  // Wilson-Hilferty: (X/k)^(1/3) is nearly normal with mean 1 - 2/(9k) and variance 2/(9k).
  const double h = 2.0 / (9.0 * dof);
  double x = dof * std::pow(std::max(1.0 - h + normal_quantile(p) * std::sqrt(h), 1e-3), 3.0);
  // Newton on F(x) - p, kept inside a bracket that bisection shrinks whenever a step leaves it.
  double lo = 0.0, hi = std::numeric_limits<double>::infinity();
  const double a = 0.5 * dof;
  for (int it = 0; it < 200; ++it) {
    // Residual on the smaller tail so that both ends keep their relative precision.
    const double r = p < 0.5 ? chi_square_cdf(x, dof) - p : (1.0 - p) - regularized_gamma_q(a, 0.5 * x);
    if (r > 0.0) hi = x; else lo = x;
    if (r == 0.0) return x;
    const double log_pdf = (a - 1.0) * std::log(x) - 0.5 * x - a * std::log(2.0) - std::lgamma(a);
    const double pdf = std::exp(log_pdf);
    double next = pdf > 0.0 ? x - r / pdf : (std::isinf(hi) ? 2.0 * x : 0.5 * (lo + hi));
    if (!(next > lo && next < hi)) next = std::isinf(hi) ? 2.0 * std::max(x, lo) + 1.0 : 0.5 * (lo + hi);
    if (std::abs(next - x) <= 1e-14 * x) return next;
    x = next;
  }
  return x;
}

}  // namespace navaid::evaluation
