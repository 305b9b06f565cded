#pragma once
// Sensor noise of a stereo / structured-light RGB-D camera, applied to a noise-free RenderedFrame
// (docs/sensor-noise.md). Kept apart from rendering so that Monte-Carlo runs re-use one rendering.
//
// Depth, per pixel with clean depth z > 0 (0 = invalid stays 0):
//   d  = f b / z                              disparity [px], f = fx of the camera, b = baseline
//   d' = d + sigma_d n,  n ~ N(0, 1)          matching noise, in disparity (where it is white)
//   d' <- q round(d' / q)                     optional sub-pixel quantization step q (0 = off)
//   z' = f b / d'                              (d' <= 0: no match, pixel invalid)
// so to first order sigma_z = z^2 sigma_d / (f b) (depth_sigma()). z' is the reciprocal of a
// Gaussian and therefore biased at second order: E[z'] = z (1 + s^2 + 3 s^4 + ...), s = sigma_z / z,
// i.e. E[z'] ~ z + sigma_z^2 / z (depth_bias()), while the disparity f b / z' is unbiased.
// Its standard deviation is sigma_z (1 + 4 s^2) to second order. Quantization adds q^2 / 12 to the
// disparity variance (Sheppard), which depth_sigma() includes.
// Then, in this order:
//   - edge holes: a pixel whose clean 3x3 neighbourhood (valid pixels only) spans a relative jump
//     (z_max - z_min) / z_min > edge_relative_jump is invalidated with edge_dropout_probability
//     (stereo occlusion and matching failure at silhouettes); on both sides of the edge;
//   - flying pixels (off by default): a surviving edge pixel takes, with flying_pixel_probability,
//     a depth uniform between its neighbourhood's z_min and z_max before the disparity noise
//     (mixed foreground/background returns);
//   - range limits: measured depths outside [min_depth_m, max_depth_m] become 0;
//   - random dropout: any valid pixel becomes 0 with dropout_probability (independently; drawn
//     as geometric gaps between dropped pixels).
// Intensity: I' = clamp(round(I + sqrt(sigma_i^2 + g I) n), 0, 255): read noise sigma_i plus
// optional shot noise with gain g [grey levels per grey level]. Rounding adds 1/12 grey level^2.
//
// noise = false returns the clean depth with the range limits applied and the clean intensity.
// Every frame's draws come from engines seeded by (seed, frame_index) only (frame_rng.hpp), with
// separate streams for the disparity noise, the hole / dropout decisions and the intensity noise:
// switching holes, dropout or intensity noise on or off leaves the disparity noise of every pixel
// unchanged (and so on between the three streams). Normal draws: gaussian_sampler.hpp.
#include <cstdint>
#include <string>

#include "navaid/core/calibration.hpp"
#include "navaid/core/image.hpp"
#include "navaid/simulation/rgbd_renderer.hpp"

namespace navaid::simulation {

struct RgbdNoiseConfig {
  double focal_px = 0.0;             ///< f [px]: the camera's fx, > 0
  double min_depth_m = 0.3;          ///< measured depths below are reported as 0, >= 0
  double max_depth_m = 10.0;         ///< measured depths above are reported as 0, > min_depth_m
  double baseline_m = 0.05;          ///< b [m], > 0
  double disparity_sigma_px = 0.08;  ///< sigma_d [px], >= 0
  double disparity_quantization_px = 0.0;  ///< q [px], e.g. 1/8; 0 = continuous disparity
  double edge_relative_jump = 0.1;         ///< 3x3 relative depth jump that marks an edge, > 0
  double edge_dropout_probability = 0.5;   ///< P(edge pixel invalid), [0, 1]
  double flying_pixel_probability = 0.0;   ///< P(surviving edge pixel mixes fg/bg), [0, 1]
  double dropout_probability = 0.0;        ///< P(any valid pixel invalid), [0, 1]
  double intensity_sigma = 2.0;            ///< read noise sigma_i [grey levels], >= 0
  double intensity_shot_gain = 0.0;        ///< g: shot-noise variance g I [grey levels^2], >= 0
  bool depth_noise = true;      ///< disparity noise and quantization
  bool intensity_noise = true;  ///< read and shot noise
  bool noise = true;            ///< false: everything off except the range limits
};

/// Defaults with f = camera.fx and, where the camera's depth section sets them (non-zero), its
/// range, baseline and disparity sigma. Not validated: call validate() after any edits.
RgbdNoiseConfig rgbd_noise_config(const CameraCalibration& camera);

/// Throws ConfigError(source, key, ...) naming the first bad key and its allowed range.
void validate(const RgbdNoiseConfig& config, const std::string& source = "rgbd_noise");

/// First-order depth standard deviation [m] at depth z: z^2 sigma_d' / (f b), with
/// sigma_d'^2 = sigma_d^2 + q^2 / 12 (quantization), 0 when depth noise is off.
double depth_sigma(double z, const RgbdNoiseConfig& config);
/// Second-order mean error E[z'] - z ~ depth_sigma(z)^2 / z of the measured depth at z [m].
double depth_bias(double z, const RgbdNoiseConfig& config);

/// Noisy images; an image that was empty in the clean frame stays empty.
struct NoisyRgbd {
  ImageF32 depth;
  ImageU8 intensity;
};

/// Noisy depth and intensity of a clean frame, deterministic per (seed, frame_index). Validates the
/// config (ConfigError); throws std::invalid_argument when a clean depth is negative or not
/// finite. Labels are not touched (see label_confusion_model.hpp). Safe to call from several
/// threads (frames in parallel).
NoisyRgbd apply_rgbd_noise(const RenderedFrame& clean, const RgbdNoiseConfig& config, std::uint64_t seed,
                           std::uint64_t frame_index);
/// Same, reusing the buffers of `out`.
void apply_rgbd_noise(const RenderedFrame& clean, const RgbdNoiseConfig& config, std::uint64_t seed,
                      std::uint64_t frame_index, NoisyRgbd& out);

}  // namespace navaid::simulation
