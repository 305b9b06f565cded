#pragma once
// Depth of a feature from the aligned depth image (depth along the optical axis, 0 = invalid):
// the median of the valid depths in a square patch around the pixel nearest to uv, refused when
// the patch holds too few valid depths, when they spread too much (a depth edge: foreground and
// background mixed, the median would be neither) or when the median is outside the sensor range.
#include <optional>

#include <Eigen/Core>

#include "navaid/core/image.hpp"

namespace navaid::estimation {

struct DepthPatchOptions {
  int patch_size = 3;                   ///< odd side of the square patch [px]
  int min_valid = 5;                    ///< valid pixels needed
  double max_relative_spread = 0.1;     ///< (max - min) / median limit
  double min_depth_m = 0.0;             ///< sensor range: medians outside are refused
  double max_depth_m = 1e9;
};

/// Median patch depth [m] at pixel uv (OpenCV convention: (0, 0) is the centre of the top-left
/// pixel), or nullopt (see above). Pixels outside the image count as invalid. The median of an
/// even count is the mean of the two middle values.
std::optional<double> associate_depth(const ImageF32& depth, const Eigen::Vector2d& uv, const DepthPatchOptions& options);

}  // namespace navaid::estimation
