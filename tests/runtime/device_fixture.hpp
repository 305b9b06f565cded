#pragma once
// A small rendered world for the device's tests: a floor and a box ahead, a camera 0.8 m up on a
// body walking forward at 1 m/s, frames rendered with depth and labels in memory, estimates at the
// true poses with a small covariance (what the estimator would hand over when it tracks).
#include <vector>

#include "navaid/core/camera.hpp"
#include "navaid/core/messages.hpp"
#include "navaid/core/state_estimate.hpp"

namespace navaid::testing {

struct DeviceWalk {
  CameraCalibration camera;
  std::vector<RgbdFrame> frames;
  std::vector<StateEstimate> estimates;  ///< one per frame, same times
};

/// `frames` frames at 10 Hz from t = 1 s; 160 x 120 pixels.
DeviceWalk rendered_device_walk(int frames);

}  // namespace navaid::testing
