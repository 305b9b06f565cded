#pragma once
// How far the tracks two frames share moved in the image between them: the camera's own test of
// standing still (a turn and a step both move tracks; a still camera moves none, whatever the
// IMU's vibration says). Private to the sliding-window estimator.
#include <cstddef>
#include <deque>
#include <limits>
#include <optional>

#include "navaid/core/messages.hpp"

namespace navaid::estimation::sliding_window {

struct ImageMotion {
  std::size_t common = 0;                                       ///< tracks both frames observe
  double median_px = std::numeric_limits<double>::quiet_NaN();  ///< median |displacement| [px]
  /// |component-wise median displacement| [px]: the coherent shift a turn gives every track,
  /// known to ~1.25 sigma / sqrt(common) however noisy each track is.
  double shift_px = std::numeric_limits<double>::quiet_NaN();
  /// Stood still: no coherent shift beyond `max_px` and a median displacement within `max_px`
  /// plus what pixel noise of `pixel_sigma` alone gives (2 sigma, above noise's 1.66 sigma median).
  bool still(std::size_t min_common, double max_px, double pixel_sigma) const {
    return common >= min_common && shift_px <= max_px && median_px <= max_px + 2.0 * pixel_sigma;
  }
};

/// Both frames' features must have strictly increasing track ids (FeatureFrame's contract).
ImageMotion image_motion(const FeatureFrame& from, const FeatureFrame& to);

/// The motion from the oldest of `recent` within `span_s` before `frame` to `frame`; none when the
/// oldest such frame is less than half the span before it.
std::optional<ImageMotion> image_motion_over(const std::deque<FeatureFrame>& recent, const FeatureFrame& frame,
                                             double span_s);

}  // namespace navaid::estimation::sliding_window
