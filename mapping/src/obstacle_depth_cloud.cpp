// Camera-frame points from a metric depth image, the obstacle pipeline's input for RGB-D frames.
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "navaid/core/camera.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/mapping/obstacle_pipeline.hpp"

namespace navaid::mapping {

std::vector<Eigen::Vector3f> camera_points_from_depth(const RgbdFrame& frame, const CameraCalibration& camera,
                                                      int stride) {
  if (stride < 1) throw Error(fmt::format("camera_points_from_depth: stride {} must be >= 1", stride));
  const ImageF32& depth = frame.depth;
  if (depth.empty())
    throw Error(fmt::format("camera_points_from_depth: frame {} has no depth pixels loaded (depth file '{}')",
                            frame.index, frame.depth_path));
  if (depth.width != camera.width || depth.height != camera.height || depth.channels != 1)
    throw Error(fmt::format("camera_points_from_depth: frame {} depth is {}x{}x{}, camera '{}' is {}x{}", frame.index,
                            depth.width, depth.height, depth.channels, camera.name, camera.width, camera.height));
  const auto model = make_camera_model(camera);
  const bool pinhole = camera.distortion == DistortionModel::kNone;
  const Eigen::Vector3f nan = Eigen::Vector3f::Constant(std::numeric_limits<float>::quiet_NaN());
  std::vector<Eigen::Vector3f> points;
  points.reserve(static_cast<std::size_t>((depth.width + stride - 1) / stride) *
                 static_cast<std::size_t>((depth.height + stride - 1) / stride));
  for (int y = 0; y < depth.height; y += stride) {
    for (int x = 0; x < depth.width; x += stride) {
      const float z = depth.at(x, y);
      if (!(z > 0.0f) || !std::isfinite(z)) {
        points.push_back(nan);
        continue;
      }
      if (pinhole) {  // the common case needs no Newton undistortion per pixel
        points.emplace_back(static_cast<float>((x - camera.cx) / camera.fx) * z,
                            static_cast<float>((y - camera.cy) / camera.fy) * z, z);
        continue;
      }
      const auto b = model->unproject(Eigen::Vector2d(x, y));
      points.push_back(b ? Eigen::Vector3f((*b * (z / b->z())).cast<float>()) : nan);
    }
  }
  return points;
}

}  // namespace navaid::mapping
