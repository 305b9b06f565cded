#pragma once
// Exact standard-normal draws by the ziggurat method (Marsaglia & Tsang, "The Ziggurat Method for
// Generating Random Variables", J. Stat. Software 5(8), 2000): 256 layers of equal area under
// exp(-x^2/2); ~99% of draws cost one 64-bit engine call and one comparison. The per-pixel image
// noise models need ~1e6 draws per frame, where std::normal_distribution (polar method: two
// uniforms, a log and a sqrt per pair) dominates the frame time.
#include <array>
#include <cstdint>
#include <random>

namespace navaid::simulation {

class GaussianSampler {
 public:
  static constexpr int kLayers = 256;

  /// One N(0, 1) draw. Each 64-bit engine output feeds two draws (32 bits each: layer, sign and a
  /// 23-bit position, a resolution of ~4e-7 sigma), so the sequence depends on the engine state
  /// and on the draws taken before from this sampler.
  double operator()(std::mt19937_64& rng) {
    const Tables& t = *tables_;
    for (;;) {
      std::uint32_t bits;
      if (has_spare_) {
        bits = spare_;
        has_spare_ = false;
      } else {
        const std::uint64_t b = rng();
        bits = static_cast<std::uint32_t>(b);
        spare_ = static_cast<std::uint32_t>(b >> 32);
        has_spare_ = true;
      }
      const int i = static_cast<int>(bits & 0xFFu);
      const double sign = (bits & 0x100u) ? -1.0 : 1.0;
      const double x = static_cast<double>(bits >> 9) * 0x1.0p-23 * t.x[i];
      if (x < t.x[i + 1]) return sign * x;  // inside the layer's core rectangle
      const double v = slow_path(rng, i, x);
      if (v >= 0.0) return sign * v;
    }
  }

 private:
  struct Tables {
    std::array<double, kLayers + 1> x;  ///< layer i spans [0, x[i]]; x[1] = r, x[kLayers] = 0
    std::array<double, kLayers + 1> f;  ///< exp(-x^2 / 2) at x[i] (f[0] = f(r): base layer top)
  };
  static const Tables& tables();
  /// Tail (layer 0) or wedge test; returns the accepted |x|, or -1 to draw again.
  static double slow_path(std::mt19937_64& rng, int layer, double x);

  const Tables* tables_ = &tables();
  std::uint32_t spare_ = 0;
  bool has_spare_ = false;
};

}  // namespace navaid::simulation
