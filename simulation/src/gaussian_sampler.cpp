#include "navaid/simulation/gaussian_sampler.hpp"

#include <cmath>

#include "navaid/simulation/frame_rng.hpp"

namespace navaid::simulation {

namespace {

double density(double x) { return std::exp(-0.5 * x * x); }

// Start of the tail for 256 layers (Marsaglia & Tsang 2000): with it the recursion below closes,
// the top layer ending at x = 0 under f(0) = 1.
constexpr double kR = 3.6541528853610088;

}  // namespace

const GaussianSampler::Tables& GaussianSampler::tables() {
  static const Tables t = [] {
    Tables tb{};
    // Common layer area: the base rectangle under f(r) plus the tail beyond r.
    const double v = kR * density(kR) + std::sqrt(std::acos(-1.0) / 2.0) * std::erfc(kR / std::sqrt(2.0));
    tb.x[0] = v / density(kR);  // base layer: rectangle of area v whose part beyond r stands for the tail
    tb.f[0] = density(kR);
    tb.x[1] = kR;
    tb.f[1] = density(kR);
    for (int i = 1; i < kLayers - 1; ++i) {
      // Next boundary: the layer [f(x_i), f(x_{i+1})] x [0, x_i] has area v.
      const double fi = tb.f[i] + v / tb.x[i];
      tb.f[i + 1] = fi;
      tb.x[i + 1] = std::sqrt(-2.0 * std::log(fi));
    }
    tb.x[kLayers] = 0.0;
    tb.f[kLayers] = 1.0;
    return tb;
  }();
  return t;
}

double GaussianSampler::slow_path(std::mt19937_64& rng, int layer, double x) {
  const Tables& t = tables();
  if (layer == 0) {
    // Tail beyond r by Marsaglia's exponential rejection: r + e1 / r with e1, e2 ~ Exp(1) kept
    // when 2 e2 > (e1 / r)^2.
    for (;;) {
      const double a = -std::log1p(-uniform01(rng)) / kR;
      const double b = -std::log1p(-uniform01(rng));
      if (2.0 * b > a * a) return kR + a;
    }
  }
  // Wedge between the core rectangle and the curve: uniform height in the layer, kept under f.
  const double y = t.f[layer] + uniform01(rng) * (t.f[layer + 1] - t.f[layer]);
  return y < density(x) ? x : -1.0;
}

}  // namespace navaid::simulation
