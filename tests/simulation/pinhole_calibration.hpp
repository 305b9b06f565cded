#pragma once
// A distortion-free pinhole camera of w x h pixels and focal length f, principal point at the
// image centre, for the renderer tests.
#include "navaid/core/calibration.hpp"

namespace navaid::simulation {

inline CameraCalibration pinhole(int w, int h, double f) {
  CameraCalibration c;
  c.width = w;
  c.height = h;
  c.fx = c.fy = f;
  c.cx = 0.5 * (w - 1);
  c.cy = 0.5 * (h - 1);
  return c;
}

}  // namespace navaid::simulation
