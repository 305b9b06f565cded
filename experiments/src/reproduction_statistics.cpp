#include "navaid/experiments/reproduction_statistics.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "navaid/core/errors.hpp"

namespace navaid::experiments {
namespace {

constexpr double kEps = 1e-16;
constexpr int kMaxTerms = 100000;

// 1/(1 + d1/(1 + d2/(1 + ...))) with d_2m+1 = -(a+m)(a+b+m)x / ((a+2m)(a+2m+1)) and
// d_2m = m(b-m)x / ((a+2m-1)(a+2m)); converges fast for x < (a+1)/(a+b+2).
double beta_continued_fraction(double a, double b, double x) {
  constexpr double tiny = std::numeric_limits<double>::min() / kEps;
  double f = tiny, c = f, d = 0.0;
  auto step = [&](double numerator) {
    d = 1.0 + numerator * d;
    if (std::abs(d) < tiny) d = tiny;
    c = 1.0 + numerator / c;
    if (std::abs(c) < tiny) c = tiny;
    d = 1.0 / d;
    const double delta = c * d;
    f *= delta;
    return std::abs(delta - 1.0) < 4.0 * std::numeric_limits<double>::epsilon();
  };
  step(1.0);  // the leading 1 / (1 + ...)
  for (int m = 0; m < kMaxTerms; ++m) {
    const double odd = -(a + m) * (a + b + m) * x / ((a + 2 * m) * (a + 2 * m + 1));
    if (step(odd)) break;
    const double mm = m + 1;
    const double even = mm * (b - mm) * x / ((a + 2 * mm - 1) * (a + 2 * mm));
    if (step(even)) break;
  }
  return f;
}

void require_level(double level) {
  if (!(level > 0.0 && level < 1.0)) throw Error(fmt::format("confidence level must be in (0, 1), got {}", level));
}

void require_finite(const std::vector<double>& v, const char* what) {
  for (std::size_t i = 0; i < v.size(); ++i)
    if (!std::isfinite(v[i])) throw Error(fmt::format("{}[{}] is not finite ({})", what, i, v[i]));
}

void require_pairs(const std::vector<double>& method, const std::vector<double>& baseline) {
  if (method.size() != baseline.size())
    throw Error(fmt::format("paired values differ in number: {} method vs {} baseline", method.size(), baseline.size()));
  if (method.empty()) throw Error("no pairs to compare");
  require_finite(method, "method");
  require_finite(baseline, "baseline");
  for (std::size_t i = 0; i < baseline.size(); ++i)
    if (!(baseline[i] > 0.0)) throw Error(fmt::format("baseline[{}] = {} must be > 0 for a relative change", i, baseline[i]));
}

}  // namespace

double regularized_beta(double a, double b, double x) {
  if (!(a > 0.0) || !(b > 0.0) || !std::isfinite(a) || !std::isfinite(b) || !(x >= 0.0 && x <= 1.0))
    throw Error(fmt::format("incomplete beta: needs a > 0, b > 0, 0 <= x <= 1, got a={} b={} x={}", a, b, x));
  if (x == 0.0 || x == 1.0) return x;
  const double log_front = std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) + a * std::log(x) + b * std::log1p(-x);
  // Use the symmetry I_x(a, b) = 1 - I_{1-x}(b, a) where the fraction converges slowly.
  if (x < (a + 1.0) / (a + b + 2.0)) return std::exp(log_front) * beta_continued_fraction(a, b, x) / a;
  return 1.0 - std::exp(log_front) * beta_continued_fraction(b, a, 1.0 - x) / b;
}

double student_t_cdf(double t, double dof) {
  if (!(dof > 0.0) || std::isnan(t)) throw Error(fmt::format("Student t: needs dof > 0, got dof={} t={}", dof, t));
  if (std::isinf(t)) return t > 0 ? 1.0 : 0.0;
  const double tail = 0.5 * regularized_beta(0.5 * dof, 0.5, dof / (dof + t * t));  // P(T > |t|)
  return t >= 0 ? 1.0 - tail : tail;
}

double student_t_quantile(double p, double dof) {
  if (!(p > 0.0 && p < 1.0) || !(dof > 0.0) || !std::isfinite(dof))
    throw Error(fmt::format("Student t quantile: needs 0 < p < 1 and dof > 0, got p={} dof={}", p, dof));
  if (p < 0.5) return -student_t_quantile(1.0 - p, dof);
  if (p == 0.5) return 0.0;
  double lo = 0.0, hi = 1.0;
  while (student_t_cdf(hi, dof) < p) {
    lo = hi;
    hi *= 2.0;
    if (!std::isfinite(hi)) throw Error(fmt::format("Student t quantile: p={} too close to 1 for dof={}", p, dof));
  }
  for (int i = 0; i < 200 && hi - lo > 1e-15 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (student_t_cdf(mid, dof) < p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

MeanInterval mean_interval(const std::vector<double>& values, double level) {
  require_level(level);
  if (values.empty()) throw Error("mean interval of an empty sample");
  require_finite(values, "values");
  MeanInterval r;
  r.n = values.size();
  for (double v : values) r.mean += v;
  r.mean /= static_cast<double>(r.n);
  if (r.n < 2) {
    r.low = r.high = std::numeric_limits<double>::quiet_NaN();
    return r;
  }
  double ss = 0.0;
  for (double v : values) ss += (v - r.mean) * (v - r.mean);
  r.std = std::sqrt(ss / static_cast<double>(r.n - 1));
  const double half = student_t_quantile(0.5 * (1.0 + level), static_cast<double>(r.n - 1)) * r.std /
                      std::sqrt(static_cast<double>(r.n));
  r.low = r.mean - half;
  r.high = r.mean + half;
  return r;
}

ProportionInterval wilson_interval(std::size_t k, std::size_t n, double level) {
  require_level(level);
  if (n == 0 || k > n) throw Error("a proportion needs 0 <= k <= n and n > 0");
  // The normal quantile as the t quantile's limit (a million degrees of freedom: equal to 1e-6).
  const double z = student_t_quantile(0.5 * (1.0 + level), 1e6);
  const double nn = static_cast<double>(n), p = static_cast<double>(k) / nn, z2 = z * z;
  const double centre = (p + z2 / (2 * nn)) / (1 + z2 / nn);
  const double half = z * std::sqrt(p * (1 - p) / nn + z2 / (4 * nn * nn)) / (1 + z2 / nn);
  // Exactly 0 and 1 at the ends (the formula leaves rounding residue there).
  return {n, k, p, k == 0 ? 0.0 : std::max(0.0, centre - half), k == n ? 1.0 : std::min(1.0, centre + half)};
}

RelativeChange relative_change_paired_t(const std::vector<double>& method, const std::vector<double>& baseline,
                                        double level) {
  require_level(level);
  require_pairs(method, baseline);
  std::vector<double> ratios(method.size());
  for (std::size_t i = 0; i < method.size(); ++i) ratios[i] = method[i] / baseline[i] - 1.0;
  const MeanInterval m = mean_interval(ratios, level);
  return {m.n, m.mean, m.low, m.high};
}

RelativeChange relative_change_bootstrap(const std::vector<double>& method, const std::vector<double>& baseline,
                                         double level, std::size_t resamples, std::uint64_t seed) {
  require_level(level);
  require_pairs(method, baseline);
  if (resamples < 100) throw Error(fmt::format("bootstrap needs at least 100 resamples, got {}", resamples));
  const std::size_t n = method.size();
  auto change = [&](const auto& index) {
    double sm = 0.0, sb = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      sm += method[index(i)];
      sb += baseline[index(i)];
    }
    return sm / sb - 1.0;
  };
  RelativeChange r;
  r.pairs = n;
  r.estimate = change([](std::size_t i) { return i; });
  if (n < 2) {
    r.low = r.high = std::numeric_limits<double>::quiet_NaN();
    return r;
  }
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<std::size_t> pick(0, n - 1);
  std::vector<std::size_t> draw(n);
  std::vector<double> changes(resamples);
  for (auto& c : changes) {
    for (auto& d : draw) d = pick(rng);
    c = change([&](std::size_t i) { return draw[i]; });
  }
  std::sort(changes.begin(), changes.end());
  // Percentiles by linear interpolation between order statistics.
  auto percentile = [&](double q) {
    const double pos = q * static_cast<double>(resamples - 1);
    const auto k = static_cast<std::size_t>(std::floor(pos));
    const double w = pos - static_cast<double>(k);
    return k + 1 < resamples ? (1.0 - w) * changes[k] + w * changes[k + 1] : changes[k];
  };
  r.low = percentile(0.5 * (1.0 - level));
  r.high = percentile(0.5 * (1.0 + level));
  return r;
}

WelchTest welch_t_test(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() < 2 || b.size() < 2) throw Error("Welch's t test needs at least two values in each sample");
  const MeanInterval ma = mean_interval(a), mb = mean_interval(b);
  const double va = ma.std * ma.std / a.size(), vb = mb.std * mb.std / b.size();
  WelchTest w;
  if (va + vb == 0) {
    w.p = ma.mean == mb.mean ? 1.0 : 0.0;
    w.t = ma.mean == mb.mean ? 0.0 : std::copysign(INFINITY, ma.mean - mb.mean);
    return w;
  }
  w.t = (ma.mean - mb.mean) / std::sqrt(va + vb);
  w.dof = (va + vb) * (va + vb) / (va * va / (a.size() - 1.0) + vb * vb / (b.size() - 1.0));
  w.p = 2.0 * (1.0 - student_t_cdf(std::abs(w.t), w.dof));
  return w;
}

}  // namespace navaid::experiments
