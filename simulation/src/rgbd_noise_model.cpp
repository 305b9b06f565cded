#include "navaid/simulation/rgbd_noise_model.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "navaid/core/errors.hpp"
#include "value_checks.hpp"
#include "navaid/simulation/frame_rng.hpp"
#include "navaid/simulation/gaussian_sampler.hpp"

namespace navaid::simulation {

using detail::check_range;
using detail::format_number;

namespace {

// Effective disparity variance: matching noise plus the uniform rounding error of the quantizer.
double disparity_variance(const RgbdNoiseConfig& c) {
  if (!c.noise || !c.depth_noise) return 0.0;
  const double q = c.disparity_quantization_px;
  return c.disparity_sigma_px * c.disparity_sigma_px + q * q / 12.0;
}

// Min and max clean depth over rows y-1..y+1 of every column (clamped at the border): the first,
// separable half of the 3x3 neighbourhood extrema. Invalid pixels enter the minimum as +inf and
// the maximum as 0, so they never count.
void column_extrema(const ImageF32& depth, std::vector<float>& vmin, std::vector<float>& vmax) {
  const int w = depth.width, h = depth.height;
  constexpr float kInf = std::numeric_limits<float>::infinity();
  vmin.resize(depth.pixels.size());
  vmax.resize(depth.pixels.size());
  const float* z = depth.pixels.data();
  for (int y = 0; y < h; ++y) {
    const float* a = z + static_cast<std::size_t>(std::max(0, y - 1)) * w;
    const float* b = z + static_cast<std::size_t>(y) * w;
    const float* c = z + static_cast<std::size_t>(std::min(h - 1, y + 1)) * w;
    float* lo = vmin.data() + static_cast<std::size_t>(y) * w;
    float* hi = vmax.data() + static_cast<std::size_t>(y) * w;
    for (int x = 0; x < w; ++x) {
      lo[x] = std::min(a[x] > 0.0f ? a[x] : kInf, std::min(b[x] > 0.0f ? b[x] : kInf, c[x] > 0.0f ? c[x] : kInf));
      hi[x] = std::max(a[x], std::max(b[x], c[x]));
    }
  }
}

// Nearest integer (halves away from zero) without a libm call or a data-dependent branch: x86-64's
// baseline has no rounding instruction, and the fraction is random once per pixel.
double round_nearest(double v) {
  if (!(std::abs(v) < 0x1.0p52)) return v;  // already integral (or not finite)
  const double mag = static_cast<double>(static_cast<std::int64_t>(std::abs(v) + 0.5));
  return std::copysign(mag, v);
}

// Number of Bernoulli(p) failures before the next success, so that rare per-pixel events cost one
// draw per event instead of one per pixel.
std::uint64_t geometric_gap(std::mt19937_64& rng, double p) {
  if (p >= 1.0) return 0;
  const double u = 1.0 - uniform01(rng);  // (0, 1]
  const double g = std::floor(std::log(u) / std::log1p(-p));
  return g < 1e18 ? static_cast<std::uint64_t>(g) : std::numeric_limits<std::uint64_t>::max();
}

void check_clean_depth(const ImageF32& depth) {
  for (std::size_t i = 0; i < depth.pixels.size(); ++i) {
    const float z = depth.pixels[i];
    if (!(z >= 0.0f) || !std::isfinite(z)) {
      const int w = std::max(depth.width, 1);
      throw std::invalid_argument("apply_rgbd_noise: clean depth must be finite and >= 0, found " + format_number(z) +
                                  " at pixel (" + std::to_string(static_cast<int>(i) % w) + ", " +
                                  std::to_string(static_cast<int>(i) / w) + ")");
    }
  }
}

void noisy_depth(const ImageF32& clean, const RgbdNoiseConfig& c, std::uint64_t seed, std::uint64_t frame,
                 ImageF32& out) {
  check_clean_depth(clean);
  out.width = clean.width;
  out.height = clean.height;
  out.channels = 1;
  out.pixels.resize(clean.pixels.size());
  const double zlo = c.min_depth_m, zhi = c.max_depth_m;
  auto in_range = [&](double z) { return z >= zlo && z <= zhi; };

  if (!c.noise) {
    for (std::size_t i = 0; i < clean.pixels.size(); ++i) {
      const float z = clean.pixels[i];
      out.pixels[i] = in_range(z) ? z : 0.0f;
    }
    return;
  }

  const bool edges = c.edge_dropout_probability > 0.0 || c.flying_pixel_probability > 0.0;
  std::vector<float> vmin, vmax;
  if (edges) column_extrema(clean, vmin, vmax);
  const int w = clean.width;

  std::mt19937_64 noise_rng = frame_rng(seed, frame, FrameNoiseStream::kDepth);
  std::mt19937_64 hole_rng = frame_rng(seed, frame, FrameNoiseStream::kDepthDropout);
  GaussianSampler normal;
  const double fb = c.focal_px * c.baseline_m;
  const double q = c.disparity_quantization_px;
  const bool dropout = c.dropout_probability > 0.0;
  // Valid pixels left to pass before the next random dropout.
  std::uint64_t to_next_dropout = dropout ? geometric_gap(hole_rng, c.dropout_probability) : 0;

  for (std::size_t i = 0, x = 0; i < clean.pixels.size(); ++i, x = (x + 1 == static_cast<std::size_t>(w)) ? 0 : x + 1) {
    const double z = clean.pixels[i];
    if (z == 0.0) {
      out.pixels[i] = 0.0f;
      continue;
    }
    bool hole = false;
    double base = z;
    if (edges) {
      // 3x3 extrema over the valid pixels: row extrema of the column extrema.
      const std::size_t l = x > 0 ? i - 1 : i, r = x + 1 < static_cast<std::size_t>(w) ? i + 1 : i;
      const double zmin = std::min(vmin[l], std::min(vmin[i], vmin[r]));
      const double zmax = std::max(vmax[l], std::max(vmax[i], vmax[r]));
      if (zmax - zmin > c.edge_relative_jump * zmin) {
        if (c.edge_dropout_probability > 0.0) hole = uniform01(hole_rng) < c.edge_dropout_probability;
        if (!hole && c.flying_pixel_probability > 0.0 && uniform01(hole_rng) < c.flying_pixel_probability) {
          base = zmin + uniform01(hole_rng) * (zmax - zmin);
        }
      }
    }
    double measured = base;
    if (c.depth_noise) {
      // Drawn for every valid pixel, holes included, so the noise of a pixel does not depend on
      // the hole decisions.
      double d = fb / base + c.disparity_sigma_px * normal(noise_rng);
      if (q > 0.0) d = q * round_nearest(d / q);
      measured = d > 0.0 ? fb / d : 0.0;
    }
    if (dropout) {
      if (to_next_dropout == 0) {
        hole = true;
        to_next_dropout = geometric_gap(hole_rng, c.dropout_probability);
      } else {
        --to_next_dropout;
      }
    }
    out.pixels[i] = (!hole && in_range(measured)) ? static_cast<float>(measured) : 0.0f;
  }
}

void noisy_intensity(const ImageU8& clean, const RgbdNoiseConfig& c, std::uint64_t seed, std::uint64_t frame,
                     ImageU8& out) {
  out = clean;
  if (!c.noise || !c.intensity_noise) return;
  std::array<double, 256> sigma{};
  for (int v = 0; v < 256; ++v) sigma[v] = std::sqrt(c.intensity_sigma * c.intensity_sigma + c.intensity_shot_gain * v);
  std::mt19937_64 rng = frame_rng(seed, frame, FrameNoiseStream::kIntensity);
  GaussianSampler normal;
  for (auto& p : out.pixels) {
    const double v = std::clamp(p + sigma[p] * normal(rng), 0.0, 255.0);
    p = static_cast<std::uint8_t>(v + 0.5);
  }
}

}  // namespace

RgbdNoiseConfig rgbd_noise_config(const CameraCalibration& camera) {
  RgbdNoiseConfig c;
  c.focal_px = camera.fx;
  if (camera.depth_max_m > 0.0) {
    c.min_depth_m = camera.depth_min_m;
    c.max_depth_m = camera.depth_max_m;
  }
  if (camera.depth_baseline_m > 0.0) c.baseline_m = camera.depth_baseline_m;
  if (camera.depth_disparity_sigma_px > 0.0) c.disparity_sigma_px = camera.depth_disparity_sigma_px;
  return c;
}

void validate(const RgbdNoiseConfig& c, const std::string& source) {
  check_range(source, "focal_px", c.focal_px, 0.0, 1e5, "px", true);
  check_range(source, "min_depth_m", c.min_depth_m, 0.0, 1e3, "m");
  if (!std::isfinite(c.max_depth_m) || c.max_depth_m <= c.min_depth_m || c.max_depth_m > 1e4) {
    throw ConfigError(source, "max_depth_m",
                      "expected a value in (min_depth_m = " + format_number(c.min_depth_m) + ", 1e4] m, found " + format_number(c.max_depth_m));
  }
  check_range(source, "baseline_m", c.baseline_m, 0.0, 10.0, "m", true);
  check_range(source, "disparity_sigma_px", c.disparity_sigma_px, 0.0, 100.0, "px");
  check_range(source, "disparity_quantization_px", c.disparity_quantization_px, 0.0, 10.0, "px (0 = off)");
  check_range(source, "edge_relative_jump", c.edge_relative_jump, 0.0, 1e3, "", true);
  check_range(source, "edge_dropout_probability", c.edge_dropout_probability, 0.0, 1.0, "");
  check_range(source, "flying_pixel_probability", c.flying_pixel_probability, 0.0, 1.0, "");
  check_range(source, "dropout_probability", c.dropout_probability, 0.0, 1.0, "");
  check_range(source, "intensity_sigma", c.intensity_sigma, 0.0, 255.0, "grey levels");
  check_range(source, "intensity_shot_gain", c.intensity_shot_gain, 0.0, 255.0, "grey levels");
}

double depth_sigma(double z, const RgbdNoiseConfig& c) {
  return z * z * std::sqrt(disparity_variance(c)) / (c.focal_px * c.baseline_m);
}

double depth_bias(double z, const RgbdNoiseConfig& c) {
  const double s = depth_sigma(z, c);
  return s * s / z;
}

NoisyRgbd apply_rgbd_noise(const RenderedFrame& clean, const RgbdNoiseConfig& config, std::uint64_t seed,
                           std::uint64_t frame_index) {
  NoisyRgbd out;
  apply_rgbd_noise(clean, config, seed, frame_index, out);
  return out;
}

void apply_rgbd_noise(const RenderedFrame& clean, const RgbdNoiseConfig& config, std::uint64_t seed,
                      std::uint64_t frame_index, NoisyRgbd& out) {
  validate(config);
  noisy_depth(clean.depth, config, seed, frame_index, out.depth);
  noisy_intensity(clean.intensity, config, seed, frame_index, out.intensity);
}

}  // namespace navaid::simulation
