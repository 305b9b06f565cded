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
  std::size_t common = 0;                                   ///< tracks both frames observe
  double median_px = std::numeric_limits<double>::quiet_NaN();  ///< median displacement [px]
};

/// Both frames' features must have strictly increasing track ids (FeatureFrame's contract).
ImageMotion image_motion(const FeatureFrame& from, const FeatureFrame& to);

/// The motion from the oldest of `recent` within `span_s` before `frame` to `frame`; none when the
/// oldest such frame is less than half the span before it.
std::optional<ImageMotion> image_motion_over(const std::deque<FeatureFrame>& recent, const FeatureFrame& frame,
                                             double span_s);

}  // namespace navaid::estimation::sliding_window
