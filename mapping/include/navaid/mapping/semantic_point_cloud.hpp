#pragma once
// eLabrador eq. (3) and (5): every (strided) pixel with a valid depth d becomes the camera-frame
// point Z = d, X = (u - cx) Z / fx, Y = (v - cy) Z / fy (for a distorted lens, the undistorted
// bearing scaled to Z = d), carrying the pixel's class and class probability, moved into the world
// by T_W_C = T_W_B * T_B_C of the frame's estimate.
#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "navaid/core/calibration.hpp"
#include "navaid/core/config.hpp"
#include "navaid/core/messages.hpp"
#include "navaid/mapping/semantic_fusion.hpp"

namespace navaid::mapping {

struct SemanticPointCloudConfig {
  int pixel_stride = 4;       ///< every n-th pixel in u and v (640x480 / 4 -> 19,200 points)
  double depth_min_m = 0.3;   ///< nearer depths are sensor artefacts
  double depth_max_m = 6.0;   ///< farther stereo depth is too noisy to map
  /// Classes whose points are dropped (sky has no surface; persons when configured, since they move).
  std::vector<SemanticClass> ignored_classes{SemanticClass::kSky};
  /// Class probability of a labelled pixel when the frame has no confidence image.
  double default_label_probability = 0.7;
};

/// Keys under mapping.cloud.*: pixel_stride, depth_min_m, depth_max_m, ignored_classes (list of
/// class names, e.g. [sky, person]), default_label_probability.
SemanticPointCloudConfig read_semantic_point_cloud_config(const Config& config);

struct SemanticPoint {
  Eigen::Vector3f p_W;
  SemanticObservation observation;  ///< kUnlabeled with probability 0 when the frame has no labels
};

struct SemanticPointCloud {
  Vec3 origin_W = Vec3::Zero();  ///< camera centre: where the rays start
  std::vector<SemanticPoint> points;
  bool labelled = false;         ///< the frame had a label image
  // Where the pixels went (sampled pixels = points + the four counts below).
  std::size_t invalid_depth = 0;   ///< depth 0, negative or not finite
  std::size_t out_of_range = 0;    ///< outside [depth_min_m, depth_max_m]
  std::size_t ignored_class = 0;   ///< class in ignored_classes
  std::size_t not_unprojected = 0;  ///< the lens model could not undistort the pixel
};

/// Back-projects a frame whose depth (and labels, confidence when present) are loaded. Throws
/// navaid::Error when the depth is missing or its size differs from the calibration, or when the
/// labels / confidence differ in size from the depth, or when a label id is not a class.
SemanticPointCloud make_semantic_point_cloud(const RgbdFrame& frame, const CameraCalibration& camera,
                                             const SE3& T_W_B, const SemanticPointCloudConfig& config);

}  // namespace navaid::mapping
