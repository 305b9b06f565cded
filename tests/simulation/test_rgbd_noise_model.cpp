#include "navaid/simulation/rgbd_noise_model.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "navaid/core/errors.hpp"
#include "test_support.hpp"

namespace navaid::simulation {
namespace {

// f b = 25 px m: sigma_z = 0.004 z^2 at sigma_d = 0.1 px.
RgbdNoiseConfig config() {
  RgbdNoiseConfig c;
  c.focal_px = 500.0;
  c.baseline_m = 0.05;
  c.disparity_sigma_px = 0.1;
  c.min_depth_m = 0.3;
  c.max_depth_m = 12.0;
  c.intensity_sigma = 3.0;
  return c;
}

// A fronto-parallel wall: constant depth z, constant intensity.
RenderedFrame wall(double z, int w = 320, int h = 240, std::uint8_t intensity = 100) {
  RenderedFrame f;
  f.depth = ImageF32(w, h, 1, static_cast<float>(z));
  f.intensity = ImageU8(w, h, 1, intensity);
  return f;
}

struct Moments {
  double mean = 0, var = 0;
  std::size_t n = 0;
};

Moments moments(const std::vector<double>& v) {
  Moments m;
  m.n = v.size();
  for (double x : v) m.mean += x;
  m.mean /= static_cast<double>(m.n);
  for (double x : v) m.var += (x - m.mean) * (x - m.mean);
  m.var /= static_cast<double>(m.n - 1);
  return m;
}

std::vector<double> valid_depths(const ImageF32& d) {
  std::vector<double> out;
  for (float z : d.pixels)
    if (z > 0.0f) out.push_back(z);
  return out;
}

// |k - n p| within 4.5 binomial standard deviations (two-sided miss probability ~7e-6).
void expect_binomial(std::size_t k, std::size_t n, double p, const std::string& what) {
  const double sd = std::sqrt(static_cast<double>(n) * p * (1.0 - p));
  EXPECT_NEAR(static_cast<double>(k), static_cast<double>(n) * p, 4.5 * sd) << what;
}

TEST(RgbdNoiseModel, DepthSigmaFollowsStereoLaw) {
  RgbdNoiseConfig c = config();
  EXPECT_NEAR(depth_sigma(1.0, c), 0.004, 1e-15);
  EXPECT_NEAR(depth_sigma(5.0, c), 0.1, 1e-15);
  EXPECT_NEAR(depth_bias(5.0, c), 0.1 * 0.1 / 5.0, 1e-15);
  c.disparity_quantization_px = 0.125;  // adds q^2/12 to the disparity variance
  EXPECT_NEAR(depth_sigma(1.0, c), std::sqrt(0.01 + 0.125 * 0.125 / 12.0) / 25.0, 1e-15);
  c.depth_noise = false;
  EXPECT_EQ(depth_sigma(5.0, c), 0.0);
  c.depth_noise = true;
  c.noise = false;
  EXPECT_EQ(depth_sigma(5.0, c), 0.0);
}

TEST(RgbdNoiseModel, DepthNoiseStdMatchesModelAtSeveralDepths) {
  const RgbdNoiseConfig c = config();
  for (double z : {1.0, 2.5, 4.0, 7.0}) {
    const auto noisy = apply_rgbd_noise(wall(z), c, 42, static_cast<std::uint64_t>(z * 10));
    const auto d = valid_depths(noisy.depth);
    ASSERT_EQ(d.size(), noisy.depth.pixels.size()) << "a flat wall has no holes, z = " << z;
    const Moments m = moments(d);
    const double s = depth_sigma(z, c) / z;
    // Documented second-order variance: sigma_z^2 (1 + 8 s^2). The sample variance over n
    // Gaussian-like draws has relative sd sqrt(2 / (n - 1)) (chi-square); allow 4.5 of them.
    const double expected_var = std::pow(depth_sigma(z, c), 2) * (1.0 + 8.0 * s * s);
    const double rel = 4.5 * std::sqrt(2.0 / static_cast<double>(m.n - 1));
    EXPECT_NEAR(m.var / expected_var, 1.0, rel) << "z = " << z;
  }
}

TEST(RgbdNoiseModel, DisparityIsUnbiasedAndDepthCarriesTheSecondOrderBias) {
  const RgbdNoiseConfig c = config();
  const double z = 4.0, fb = c.focal_px * c.baseline_m;
  const auto noisy = apply_rgbd_noise(wall(z, 640, 480), c, 7, 0);
  const auto d = valid_depths(noisy.depth);
  std::vector<double> disparity;
  for (double v : d) disparity.push_back(fb / v);
  const Moments mz = moments(d), md = moments(disparity);
  const double n = static_cast<double>(mz.n);
  // Disparity: unbiased; standard error sigma_d / sqrt(n).
  EXPECT_NEAR(md.mean, fb / z, 4.5 * c.disparity_sigma_px / std::sqrt(n));
  // Depth: E[z'] = z + sigma_z^2 / z (+ O(s^4) = 3e-6 m here), standard error sigma_z / sqrt(n).
  const double se = depth_sigma(z, c) / std::sqrt(n);
  EXPECT_NEAR(mz.mean, z + depth_bias(z, c), 4.5 * se);
  // The bias is real: ~9 standard errors here, so the unbiased claim would be rejected.
  EXPECT_GT(mz.mean - z, 4.5 * se);
}

TEST(RgbdNoiseModel, QuantizedDisparityLiesOnTheGridWithSheppardVariance) {
  RgbdNoiseConfig c = config();
  c.disparity_quantization_px = 0.125;
  const double z = 3.0, fb = c.focal_px * c.baseline_m;
  const auto noisy = apply_rgbd_noise(wall(z), c, 3, 1);
  std::vector<double> disparity;
  for (float v : noisy.depth.pixels) {
    ASSERT_GT(v, 0.0f);
    const double dq = fb / v / 0.125;
    ASSERT_NEAR(dq, std::round(dq), 1e-3);  // float depth: ~1e-7 relative
    disparity.push_back(fb / v);
  }
  const Moments m = moments(disparity);
  const double expected_var = 0.01 + 0.125 * 0.125 / 12.0;
  EXPECT_NEAR(m.var / expected_var, 1.0, 4.5 * std::sqrt(2.0 / static_cast<double>(m.n - 1)));
  EXPECT_NEAR(m.mean, fb / z, 4.5 * std::sqrt(expected_var / static_cast<double>(m.n)));
}

TEST(RgbdNoiseModel, RangeLimitsInvalidateOutsideDepths) {
  RgbdNoiseConfig c = config();
  c.max_depth_m = 10.0;
  // The limits apply to the measured depth: far enough out (20 m: the 10 m limit is 12.5 sigma_d
  // away in disparity) no draw comes back inside.
  for (bool noise : {true, false}) {
    c.noise = noise;
    for (double z : {0.2, noise ? 20.0 : 10.01}) {
      const auto noisy = apply_rgbd_noise(wall(z), c, 1, 0);
      for (float v : noisy.depth.pixels) ASSERT_EQ(v, 0.0f) << "z = " << z << " noise " << noise;
    }
  }
  // Near the far limit the noise pushes a fraction beyond it: those are 0, the rest stay inside.
  c.noise = true;
  const auto noisy = apply_rgbd_noise(wall(9.9), c, 1, 0);
  std::size_t zeros = 0;
  for (float v : noisy.depth.pixels) {
    if (v == 0.0f) {
      ++zeros;
    } else {
      EXPECT_GE(v, c.min_depth_m);
      EXPECT_LE(v, c.max_depth_m);
    }
  }
  // P(z' > 10) = P(n < -(d - fb/10) / sigma_d) with d = fb / 9.9.
  const double fb = 25.0, thr = (fb / 9.9 - fb / 10.0) / 0.1;
  const double p = 0.5 * std::erfc(thr / std::sqrt(2.0));
  expect_binomial(zeros, noisy.depth.pixels.size(), p, "beyond max_depth_m");
}

// Left half at 2 m, right half at 4 m: a vertical depth edge between columns w/2-1 and w/2.
RenderedFrame step(int w = 320, int h = 240) {
  RenderedFrame f = wall(2.0, w, h);
  for (int y = 0; y < h; ++y)
    for (int x = w / 2; x < w; ++x) f.depth.at(x, y) = 4.0f;
  return f;
}

TEST(RgbdNoiseModel, HolesAppearAtDepthEdgesOnly) {
  RgbdNoiseConfig c = config();
  c.edge_dropout_probability = 1.0;
  const RenderedFrame f = step();
  const int w = f.depth.width, h = f.depth.height;
  const auto noisy = apply_rgbd_noise(f, c, 5, 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const bool edge = x == w / 2 - 1 || x == w / 2;
      EXPECT_EQ(noisy.depth.at(x, y) == 0.0f, edge) << x << "," << y;
    }

  c.edge_dropout_probability = 0.4;
  std::size_t holes = 0, others = 0;
  const auto partial = apply_rgbd_noise(f, c, 5, 1);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const bool hole = partial.depth.at(x, y) == 0.0f;
      if (x == w / 2 - 1 || x == w / 2)
        holes += hole;
      else
        others += hole;
    }
  EXPECT_EQ(others, 0u);
  expect_binomial(holes, 2u * static_cast<std::size_t>(h), 0.4, "edge holes");
}

TEST(RgbdNoiseModel, SlantedPlaneBelowTheJumpThresholdKeepsAllPixels) {
  RgbdNoiseConfig c = config();
  c.edge_dropout_probability = 1.0;
  c.edge_relative_jump = 0.1;
  // Depth growing 1.5% per column: 3% across a 3x3 window, below the 10% threshold.
  RenderedFrame f = wall(1.0, 100, 50);
  for (int y = 0; y < 50; ++y)
    for (int x = 0; x < 100; ++x) f.depth.at(x, y) = static_cast<float>(0.5 * std::pow(1.03, x * 0.5));
  const auto noisy = apply_rgbd_noise(f, c, 9, 0);
  for (float v : noisy.depth.pixels) ASSERT_GT(v, 0.0f);
  // Invalid pixels (0) are not edges: a wall next to an unrendered region keeps its pixels.
  for (int y = 0; y < 50; ++y)
    for (int x = 0; x < 10; ++x) f.depth.at(x, y) = 0.0f;
  const auto with_gap = apply_rgbd_noise(f, c, 9, 0);
  for (int y = 0; y < 50; ++y)
    for (int x = 0; x < 100; ++x) EXPECT_EQ(with_gap.depth.at(x, y) == 0.0f, x < 10) << x << "," << y;
}

TEST(RgbdNoiseModel, FlyingPixelsLieBetweenForegroundAndBackground) {
  RgbdNoiseConfig c = config();
  c.edge_dropout_probability = 0.0;
  c.flying_pixel_probability = 1.0;
  c.depth_noise = false;
  const RenderedFrame f = step();
  const int w = f.depth.width;
  const auto noisy = apply_rgbd_noise(f, c, 11, 0);
  int strictly_between = 0;
  for (int y = 0; y < f.depth.height; ++y)
    for (int x = 0; x < w; ++x) {
      const float v = noisy.depth.at(x, y);
      if (x == w / 2 - 1 || x == w / 2) {
        EXPECT_GE(v, 2.0f);
        EXPECT_LE(v, 4.0f);
        strictly_between += v > 2.0f && v < 4.0f;
      } else {
        EXPECT_EQ(v, f.depth.at(x, y));
      }
    }
  EXPECT_EQ(strictly_between, 2 * f.depth.height);
}

TEST(RgbdNoiseModel, DropoutRateIsBinomial) {
  RgbdNoiseConfig c = config();
  c.dropout_probability = 0.07;
  const auto noisy = apply_rgbd_noise(wall(2.0), c, 13, 0);
  std::size_t zeros = 0;
  for (float v : noisy.depth.pixels) zeros += v == 0.0f;
  expect_binomial(zeros, noisy.depth.pixels.size(), 0.07, "dropout");
}

TEST(RgbdNoiseModel, IntensityNoiseVarianceIncludesShotNoiseAndRounding) {
  RgbdNoiseConfig c = config();
  for (double gain : {0.0, 0.5}) {
    c.intensity_shot_gain = gain;
    const auto noisy = apply_rgbd_noise(wall(2.0), c, 17, 0);
    std::vector<double> v(noisy.intensity.pixels.begin(), noisy.intensity.pixels.end());
    const Moments m = moments(v);
    // sigma_i^2 + g I, plus 1/12 from rounding to integers (Sheppard); far from the clamps.
    const double expected = 9.0 + gain * 100.0 + 1.0 / 12.0;
    EXPECT_NEAR(m.var / expected, 1.0, 4.5 * std::sqrt(2.0 / static_cast<double>(m.n - 1))) << "gain " << gain;
    EXPECT_NEAR(m.mean, 100.0, 4.5 * std::sqrt(expected / static_cast<double>(m.n)));
  }
  // Clamped at the ends of the range.
  const auto dark = apply_rgbd_noise(wall(2.0, 64, 64, 0), c, 17, 0);
  std::size_t zeros = 0;
  for (auto p : dark.intensity.pixels) zeros += p == 0;
  EXPECT_GT(zeros, dark.intensity.pixels.size() / 3);  // half the draws fall below 0
}

TEST(RgbdNoiseModel, DeterministicPerSeedAndFrameInAnyOrder) {
  RgbdNoiseConfig c = config();
  c.dropout_probability = 0.05;
  c.edge_dropout_probability = 0.5;
  const RenderedFrame f = step(120, 80);
  std::vector<NoisyRgbd> forward, backward(4);
  for (std::uint64_t k = 0; k < 4; ++k) forward.push_back(apply_rgbd_noise(f, c, 99, k));
  for (std::uint64_t k = 4; k-- > 0;) backward[k] = apply_rgbd_noise(f, c, 99, k);
  for (std::size_t k = 0; k < 4; ++k) {
    EXPECT_EQ(forward[k].depth, backward[k].depth) << k;
    EXPECT_EQ(forward[k].intensity, backward[k].intensity) << k;
  }
  EXPECT_FALSE(forward[0].depth == forward[1].depth);
  EXPECT_FALSE(forward[0].intensity == forward[1].intensity);
  const auto other_seed = apply_rgbd_noise(f, c, 100, 0);
  EXPECT_FALSE(other_seed.depth == forward[0].depth);
  EXPECT_FALSE(other_seed.intensity == forward[0].intensity);
  // Separate streams: switching the holes off leaves every pixel's disparity noise unchanged ...
  RgbdNoiseConfig no_holes = c;
  no_holes.dropout_probability = 0.0;
  no_holes.edge_dropout_probability = 0.0;
  const auto full = apply_rgbd_noise(f, no_holes, 99, 0);
  std::size_t compared = 0;
  for (std::size_t i = 0; i < full.depth.pixels.size(); ++i) {
    ASSERT_GT(full.depth.pixels[i], 0.0f);
    if (forward[0].depth.pixels[i] > 0.0f) {
      ASSERT_EQ(forward[0].depth.pixels[i], full.depth.pixels[i]) << i;
      ++compared;
    }
  }
  EXPECT_GT(compared, full.depth.pixels.size() * 9 / 10);
  EXPECT_LT(compared, full.depth.pixels.size());
  // ... and switching intensity noise off leaves the depth unchanged.
  c.intensity_noise = false;
  const auto no_intensity = apply_rgbd_noise(f, c, 99, 0);
  EXPECT_EQ(no_intensity.depth, forward[0].depth);
  EXPECT_EQ(no_intensity.intensity, f.intensity);
}

TEST(RgbdNoiseModel, ReusedBuffersGiveTheSameFrames) {
  const RgbdNoiseConfig c = config();
  NoisyRgbd out;
  apply_rgbd_noise(step(64, 48), c, 3, 0, out);
  apply_rgbd_noise(wall(2.0, 32, 24), c, 3, 1, out);  // smaller frame into the larger buffers
  const NoisyRgbd fresh = apply_rgbd_noise(wall(2.0, 32, 24), c, 3, 1);
  EXPECT_EQ(out.depth, fresh.depth);
  EXPECT_EQ(out.intensity, fresh.intensity);
}

TEST(RgbdNoiseModel, NoiseOffIsIdentityExceptRangeLimits) {
  RgbdNoiseConfig c = config();
  c.noise = false;
  c.dropout_probability = 0.5;
  c.edge_dropout_probability = 1.0;
  RenderedFrame f = step(64, 48);
  f.depth.at(3, 3) = 0.1f;   // below min
  f.depth.at(5, 5) = 20.0f;  // above max
  f.depth.at(7, 7) = 0.0f;   // invalid stays invalid
  for (std::size_t i = 0; i < f.intensity.pixels.size(); ++i) f.intensity.pixels[i] = static_cast<std::uint8_t>(i % 256);
  const auto out = apply_rgbd_noise(f, c, 1, 2);
  EXPECT_EQ(out.intensity, f.intensity);
  RenderedFrame expected = f;
  expected.depth.at(3, 3) = 0.0f;
  expected.depth.at(5, 5) = 0.0f;
  EXPECT_EQ(out.depth, expected.depth);
  // Images that were not rendered stay empty.
  RenderedFrame depth_only;
  depth_only.depth = f.depth;
  EXPECT_TRUE(apply_rgbd_noise(depth_only, config(), 1, 2).intensity.empty());
}

TEST(RgbdNoiseModel, ConfigFromCameraDepthSection) {
  CameraCalibration cam;
  cam.fx = 612.5;
  RgbdNoiseConfig c = rgbd_noise_config(cam);
  EXPECT_EQ(c.focal_px, 612.5);
  EXPECT_EQ(c.baseline_m, RgbdNoiseConfig{}.baseline_m);  // no depth section: defaults
  cam.depth_min_m = 0.2;
  cam.depth_max_m = 6.0;
  cam.depth_baseline_m = 0.095;
  cam.depth_disparity_sigma_px = 0.05;
  c = rgbd_noise_config(cam);
  EXPECT_EQ(c.min_depth_m, 0.2);
  EXPECT_EQ(c.max_depth_m, 6.0);
  EXPECT_EQ(c.baseline_m, 0.095);
  EXPECT_EQ(c.disparity_sigma_px, 0.05);
  EXPECT_NO_THROW(validate(c));
}

TEST(RgbdNoiseModel, BadConfigNamesTheKey) {
  const std::vector<std::pair<std::string, std::function<void(RgbdNoiseConfig&)>>> cases = {
      {"focal_px", [](RgbdNoiseConfig& c) { c.focal_px = 0.0; }},
      {"min_depth_m", [](RgbdNoiseConfig& c) { c.min_depth_m = -1.0; }},
      {"max_depth_m", [](RgbdNoiseConfig& c) { c.max_depth_m = c.min_depth_m; }},
      {"baseline_m", [](RgbdNoiseConfig& c) { c.baseline_m = 0.0; }},
      {"disparity_sigma_px", [](RgbdNoiseConfig& c) { c.disparity_sigma_px = std::nan(""); }},
      {"disparity_quantization_px", [](RgbdNoiseConfig& c) { c.disparity_quantization_px = -0.1; }},
      {"edge_relative_jump", [](RgbdNoiseConfig& c) { c.edge_relative_jump = 0.0; }},
      {"edge_dropout_probability", [](RgbdNoiseConfig& c) { c.edge_dropout_probability = 1.5; }},
      {"flying_pixel_probability", [](RgbdNoiseConfig& c) { c.flying_pixel_probability = -0.1; }},
      {"dropout_probability", [](RgbdNoiseConfig& c) { c.dropout_probability = 2.0; }},
      {"intensity_sigma", [](RgbdNoiseConfig& c) { c.intensity_sigma = -1.0; }},
      {"intensity_shot_gain", [](RgbdNoiseConfig& c) { c.intensity_shot_gain = INFINITY; }},
  };
  for (const auto& [key, edit] : cases) {
    RgbdNoiseConfig c = config();
    edit(c);
    const auto e = testing::expect_throw<ConfigError>([&] { apply_rgbd_noise(wall(1.0, 8, 8), c, 1, 0); }, key);
    ASSERT_TRUE(e);
    EXPECT_EQ(e->key(), key);
    EXPECT_EQ(e->file(), "rgbd_noise");
  }
  RenderedFrame bad = wall(1.0, 8, 8);
  bad.depth.at(2, 3) = -1.0f;
  const std::string msg = testing::error_message<std::invalid_argument>([&] { apply_rgbd_noise(bad, config(), 1, 0); });
  EXPECT_NE(msg.find("(2, 3)"), std::string::npos) << msg;
}

}  // namespace
}  // namespace navaid::simulation
